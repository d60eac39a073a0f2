"""Every fault kind: parses from the command line, validates with a clear error, applies."""
from __future__ import annotations

import math

import numpy as np
import pytest

from hil.scenario.faults import BUS_KINDS, FRAME_KINDS, KINDS, SENSOR_KINDS, WIRE_KINDS
from hil.sim.sensor_faults import FaultTimeline, SensorFaultInjector
from hil.scenario.schema import ScenarioError
from hil.scenario.sensor_options import SIGNALS
from hil.bus import load
from hil.scenario.file import parse_fault_spec, parse_flight_fault

T = np.round(np.arange(0.0, 2.0, 0.02), 10)
BASE = {"alpha": 0.2, "q": 0.05, "de": -0.04}

# one valid command line per kind, with its expected effect
SENSOR_CASES = {
    "spike": ("spike:signal=alpha,start=1.0,duration=0.1,magnitude=0.2", lambda v, t: v + 0.2),
    "bias": ("bias:signal=q,start=1.0,duration=0.1,magnitude=-0.5", lambda v, t: v - 0.5),
    "stuck": ("stuck:signal=alpha,start=1.0,duration=0.1", None),  # checked separately
    "dropout": ("dropout:signal=de,start=1.0,duration=0.1", lambda v, t: math.nan),
    "noise_burst": ("noise_burst:signal=q,start=1.0,duration=0.1,magnitude=0.3", None),
    "drift": ("drift:signal=alpha,start=1.0,duration=0.1,rate=2.0", lambda v, t: v + 2.0 * (t - 1.0)),
    "scale": ("scale:signal=q,start=1.0,duration=0.1,factor=1.5", lambda v, t: v * 1.5),
}
OTHER_CASES = {
    "loss": "loss:frame=CDRW_AOA,start=1,duration=0.5,probability=0.5",
    "delay": "delay:frame=CDRW_PITCH_RATE,start=1,duration=0.5,delay=0.03",
    "duplicate": "duplicate:start=1,duration=0.5,count=2",
    "replay": "replay:frame=CDRW_AOA,start=1,duration=0.5,age=0.2",
    "bad_crc": "bad_crc:frame=CDRW_AOA,start=1,duration=0.1",
    "counter_freeze": "counter_freeze:frame=CDRW_AOA,start=1,duration=0.1",
    "counter_jump": "counter_jump:frame=CDRW_AOA,start=1,duration=0.1,jump=3",
    "wrong_dlc": "wrong_dlc:frame=CDRW_AOA,start=1,duration=0.1,dlc=5",
    "out_of_range": "out_of_range:frame=CDRW_AOA,signal=alpha,start=1,duration=0.1,raw=2000000",
    "flood": "flood:start=1,duration=0.2,can_id=0x0,rate_hz=1000",
    "silence": "silence:start=1,duration=inf",
    "bus_load": "bus_load:start=1,duration=0.5,utilisation=0.3,id_lo=0x300,id_hi=0x30f",
}


def test_every_kind_has_a_case():
    assert set(SENSOR_CASES) == set(SENSOR_KINDS)
    assert set(OTHER_CASES) == set(FRAME_KINDS) | set(BUS_KINDS)
    # the wire kinds' cases: tests/python/scenario/test_wire_fault_kinds.py
    assert set(KINDS) == set(SENSOR_KINDS) | set(FRAME_KINDS) | set(BUS_KINDS) | set(WIRE_KINDS)


def _run(spec: str, signal: str) -> tuple[np.ndarray, np.ndarray, SensorFaultInjector]:
    fault = parse_fault_spec(spec, "cdrw")
    inj = SensorFaultInjector([fault], seed=1)
    out, flags = [], []
    for t in T:
        vals = dict(BASE, alpha=BASE["alpha"] + 0.01 * t)   # a moving signal for 'stuck'
        out.append(inj.apply(float(t), vals)[signal])
        flags.append(bool(inj.active))
    return np.array(out), np.array(flags), inj


@pytest.mark.parametrize("kind", sorted(SENSOR_CASES))
def test_sensor_fault_parses_and_applies_only_while_active(kind):
    spec, effect = SENSOR_CASES[kind]
    fault = parse_fault_spec(spec, "cdrw")
    assert fault.kind == kind and fault.level == "sensor"
    assert parse_fault_spec(fault.describe(), "cdrw") == fault          # describe() round-trips
    out, flags, inj = _run(spec, fault.signal)
    active = (T >= 1.0) & (T < 1.1 - 1e-9)
    assert np.array_equal(flags, active)
    assert np.count_nonzero(active) == 5                                 # 0.1 s at 50 Hz
    clean = np.array([dict(BASE, alpha=BASE["alpha"] + 0.01 * t)[fault.signal] for t in T])
    assert np.array_equal(out[~active], clean[~active])                  # untouched outside
    if effect is not None:
        expected = np.array([effect(v, t) for v, t in zip(clean[active], T[active])])
        assert np.allclose(out[active], expected, equal_nan=True)
    assert [e.action for e in inj.log] == ["start", "end"]
    assert inj.log[0].t == pytest.approx(1.0) and inj.log[1].t == pytest.approx(1.1)


def test_stuck_holds_the_last_reading_or_a_given_value():
    out, flags, _ = _run(SENSOR_CASES["stuck"][0], "alpha")
    before = out[np.flatnonzero(flags)[0] - 1]
    assert np.all(out[flags] == before)
    out2, flags2, _ = _run("stuck:signal=alpha,start=1,duration=0.1,value=0.7", "alpha")
    assert np.all(out2[flags2] == 0.7)


def test_noise_burst_is_bounded_random_and_reproducible():
    spec = SENSOR_CASES["noise_burst"][0]
    out1, flags, _ = _run(spec, "q")
    out2, _, _ = _run(spec, "q")
    d = out1[flags] - BASE["q"]
    assert np.all(np.abs(d) <= 0.3) and np.std(d) > 0.01
    assert np.array_equal(out1, out2)
    g, fg, _ = _run("noise_burst:signal=q,start=1,duration=0.1,magnitude=0.3,distribution=gaussian", "q")
    assert not np.array_equal(g[fg], out1[flags])


def test_dropout_fill_modes():
    z, fz, _ = _run("dropout:signal=q,start=1,duration=0.1,fill=zero", "q")
    assert np.all(z[fz] == 0.0)
    h, fh, _ = _run("dropout:signal=alpha,start=1,duration=0.1,fill=hold", "alpha")
    assert np.all(h[fh] == h[np.flatnonzero(fh)[0] - 1])


def test_two_faults_on_one_signal_apply_in_order():
    faults = [parse_fault_spec("scale:signal=q,start=0,duration=1,factor=2", "cdrw"),
              parse_fault_spec("bias:signal=q,start=0,duration=1,magnitude=1", "cdrw")]
    inj = SensorFaultInjector(faults, seed=0)
    assert inj.apply(0.0, {"q": 0.5})["q"] == 2.0


@pytest.mark.parametrize("kind", sorted(OTHER_CASES))
def test_frame_and_bus_faults_parse_and_time(kind):
    fault = parse_fault_spec(OTHER_CASES[kind], "cdrw", known_frames={"CDRW_AOA", "CDRW_PITCH_RATE"})
    assert fault.kind == kind and fault.level in ("frame", "bus")
    assert parse_fault_spec(fault.describe(), "cdrw") == fault
    assert not fault.active(0.98) and fault.active(1.0)
    tl = FaultTimeline([fault])
    for t in T:
        tl.update(float(t))
    assert tl.log[0].action == "start" and tl.log[0].t == pytest.approx(1.0)
    # frame/bus faults are not the injector's business
    inj = SensorFaultInjector([fault], seed=0)
    assert inj.apply(1.0, BASE) == BASE


def test_frame_fault_parameters():
    f = parse_fault_spec(OTHER_CASES["out_of_range"], "cdrw")
    assert (f.frame, f.signal, f.raw) == ("CDRW_AOA", "alpha", 2000000)
    assert parse_fault_spec("out_of_range:frame=CDRW_AOA,signal=alpha,start=1,duration=1", "cdrw").raw is None
    assert parse_fault_spec("loss:start=0,duration=1", "missile").frame == "*"
    flood = parse_fault_spec(OTHER_CASES["flood"], "missile")
    assert (flood.can_id, flood.rate_hz, flood.dlc) == (0, 1000.0, 8)
    assert math.isinf(parse_fault_spec(OTHER_CASES["silence"], "cdrw").duration)


@pytest.mark.parametrize("spec, message", [
    ("spik:signal=alpha,start=1,duration=0.1", "unknown fault kind 'spik'"),
    ("spike:signal=beta,start=1,duration=0.1,magnitude=1",
     "field 'signal': unknown signal 'beta' for aircraft cdrw (signals: alpha, q, de)"),
    ("spike:signal=alpha,start=1,duration=-0.1,magnitude=1", "(spike): field 'duration': must be > 0.0, got -0.1"),
    ("spike:signal=alpha,start=-1,duration=0.1,magnitude=1", "field 'start': must be >= 0.0, got -1.0"),
    ("spike:signal=alpha,start=four,duration=0.1,magnitude=1", "field 'start': expected a number, got string 'four'"),
    ("spike:signal=alpha,start=1,duration=0.1", "(spike): missing field 'magnitude'"),
    ("spike:signal=alpha,start=1,duration=0.1,magnitude=1,magnitud=2", "unknown field 'magnitud'"),
    ("spike:signal=alpha,start=1,duration=0.1,magnitude=nan", "field 'magnitude': expected a number"),
    ("spike:signal=alpha,start=inf,duration=0.1,magnitude=1", "field 'start': must be a finite number"),
    ("spike signal=alpha", "expected KIND:key=value"),
    ("spike:signal=alpha,start", "expected key=value, got 'start'"),
    ("spike:start=1,start=2", "field 'start' given twice"),
    ("wrong_dlc:start=1,duration=1,dlc=9", "(wrong_dlc): field 'dlc': must be <= 8, got 9"),
    ("counter_jump:start=1,duration=1,jump=1.5", "field 'jump': expected an integer, got number 1.5"),
    ("loss:start=1,duration=1,probability=0", "field 'probability': must be > 0.0, got 0.0"),
    ("dropout:signal=q,start=1,duration=1,fill=maybe", "field 'fill': must be one of nan, zero, hold, got 'maybe'"),
    ("loss:frame=NOPE,start=1,duration=1", "field 'frame': unknown frame 'NOPE'"),
    ("spike:signal=q_g,start=1,duration=1,magnitude=1", "unknown signal 'q_g' for aircraft cdrw"),
])
def test_bad_fault_specs_give_one_clear_line(spec, message):
    with pytest.raises(ScenarioError) as err:
        parse_fault_spec(spec, "cdrw", known_frames={"CDRW_AOA"})
    text = str(err.value)
    assert message in text
    assert text.startswith("command line: fault ")
    assert "\n" not in text


def test_timeline_refuses_time_going_back():
    tl = FaultTimeline([parse_fault_spec("silence:start=1,duration=1", "cdrw")])
    tl.update(1.5)
    with pytest.raises(ValueError, match="backwards"):
        tl.update(1.0)


# ---- a fault of a flight of one or more aircraft: whose it is -----------------------------------
BOTH = {"cdrw": 7.0, "missile": 10.0}
ALL_FRAMES = {m.name for m in load().messages}


@pytest.mark.parametrize("spec, owner", [
    ("spike:signal=alpha,start=1,duration=0.1,magnitude=1", "cdrw"),
    ("bias:signal=q_g,start=1,duration=0.1,magnitude=1", "missile"),
    ("bad_crc:frame=CDRW_AOA,start=1,duration=0.5", "cdrw"),
    ("replay:frame=MSL_RATE_GYRO,start=3,duration=1,age=0.5", "missile"),
    ("out_of_range:frame=MSL_ACCELEROMETER,signal=n_a,start=1,duration=1", "missile"),
    ("drift:signal=q,start=6.9,duration=1,rate=1", "cdrw"),
])
def test_a_flight_fault_belongs_to_the_aircraft_its_signal_or_frame_names(spec, owner):
    aircraft, fault = parse_flight_fault(spec, BOTH, "s.toml: case[0] c", ALL_FRAMES)
    assert aircraft == owner and fault.describe().split(":")[0] == spec.split(":")[0]


def test_a_fault_of_any_run_belongs_to_the_one_aircraft_flown():
    for spec in ("loss:start=1,duration=1", "silence:start=1,duration=1",
                 "delay:frame=SIM_TICK,start=1,duration=1,delay=0.01"):
        assert parse_flight_fault(spec, {"missile": 10.0}, "w", ALL_FRAMES)[0] == "missile"


@pytest.mark.parametrize("spec, durations, message", [
    ("spike:signal=alpa,start=4,duration=0.1,magnitude=0.15", BOTH,
     "(spike): field 'signal': unknown signal 'alpa' for aircraft cdrw (signals: alpha, q, de); "
     f"unknown signal 'alpa' for aircraft missile (signals: {', '.join(SIGNALS['missile'])})"),
    ("spkie:signal=alpha,start=4,duration=0.1,magnitude=0.15", BOTH, "field 'kind': unknown fault kind 'spkie'"),
    ("spike:signal=alpha,start=9,duration=0.1,magnitude=0.15", BOTH,
     "(spike): field 'start': 9.0 s is not before the end of the run (7.0 s)"),
    ("bias:signal=q_g,start=1,duration=1,magnitude=1", {"cdrw": 7.0},
     "(bias): field 'signal': a missile fault, and the flight is cdrw (unknown signal 'q_g'"),
    ("loss:frame=MSL_RATE_GYRO,start=1,duration=1", {"cdrw": 7.0},
     "(loss): field 'frame': a missile fault, and the flight is cdrw (the simulator does not send"),
    ("loss:frame=NOPE,start=1,duration=1", BOTH, "(loss): field 'frame': unknown frame 'NOPE'"),
    ("loss:start=1,duration=1", BOTH, "(loss): acts in a cdrw and a missile run alike"),
    ("flood:start=1,duration=1", BOTH, "(flood): acts in a cdrw and a missile run alike"),
    ("spike:signal=alpha,start=1,duration=0,magnitude=1", BOTH, "(spike): field 'duration': must be > 0.0, got 0.0"),
])
def test_a_flight_fault_of_no_aircraft_or_of_either_is_refused(spec, durations, message):
    with pytest.raises(ScenarioError) as err:
        parse_flight_fault(spec, durations, "s.toml: case[0] c: faults[0]", ALL_FRAMES)
    text = str(err.value)
    assert text.startswith("s.toml: case[0] c: faults[0]") and message in text and "\n" not in text
