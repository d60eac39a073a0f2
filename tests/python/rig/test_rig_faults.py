"""Each fault kind end to end: the simulator injects it on vcan0, the real fcc (lockstep)
sees it, and the effect shows in fcc's own counters (its heartbeat frames) or outputs.

Frame and bus faults act from 0.2 s for 0.2 s (10 steps of 20 ms) of a 1 s CDRW flight.
Sensor faults are compared with the same flight without the fault: fcc's estimates must be
identical before the fault starts and differ once it has.
"""
from __future__ import annotations

import numpy as np
import pytest

from hil.io.output import read_csv
from rig_helpers import CDRW_1S, MISSILE_2S, fly, scenario

pytestmark = pytest.mark.vcan

WINDOW = "start=0.2,duration=0.2"


def counters(outcome) -> tuple[dict, dict, dict]:
    fw = outcome.summary["firmware"]
    return fw["e2e"], fw["rejected"], outcome.summary["cdrw"]["flight"]


def test_no_fault_all_ok(tmp_path):
    o = fly(tmp_path, scenario(CDRW_1S))
    e2e, rej, fl = counters(o)
    assert o.summary["firmware"]["steps"]["cdrw"] == 51
    # sensors, ticks, and SIM_CONTROL: reset, flight, ground, ground + shutdown at the end
    assert e2e["ok"] == 3 * 51 + 51 + 5
    assert sum(v for k, v in e2e.items() if k != "ok") == 0 and sum(rej.values()) == 0
    assert fl["missing_steps"] == fl["unanswered_steps"] == fl["degraded_steps"] == 0


@pytest.mark.parametrize("spec, check", [
    (f"loss:frame=CDRW_AOA,{WINDOW}",
     lambda e, r, f: e["no_new_data"] == 10 and e["wrong_sequence"] == 1 and f["degraded_steps"] >= 10),
    # each frame one step late: the first step holds the last value, the next 9 are misaligned
    (f"delay:frame=CDRW_AOA,{WINDOW},delay=0.01",
     lambda e, r, f: e["no_new_data"] == 1 and f["degraded_steps"] == 9 and f["frames_injected"]["delayed"] == 10),
    (f"duplicate:frame=CDRW_AOA,{WINDOW},count=2", lambda e, r, f: e["repeated"] == 20),
    ("replay:frame=CDRW_AOA,start=0.4,duration=0.2,age=0.2",
     lambda e, r, f: e["wrong_sequence"] >= 1 and f["frames_injected"]["replayed"] == 10),
    (f"bad_crc:frame=*,{WINDOW}", lambda e, r, f: e["error"] == 30 and f["degraded_steps"] >= 10),
    (f"counter_freeze:frame=CDRW_PITCH_RATE,{WINDOW}",
     lambda e, r, f: e["repeated"] == 9 and e["wrong_sequence"] == 1),
    (f"counter_jump:frame=CDRW_PITCH_RATE,{WINDOW},jump=5", lambda e, r, f: e["wrong_sequence"] == 2),
    (f"wrong_dlc:frame=CDRW_ELEVATOR,{WINDOW},dlc=4", lambda e, r, f: r["wrong_dlc"] == 10),
    (f"out_of_range:frame=CDRW_AOA,signal=alpha,{WINDOW}", lambda e, r, f: r["out_of_range"] == 10),
    (f"flood:{WINDOW},rate_hz=2000,can_id=0x7FE", lambda e, r, f: r["unknown_id"] == 400),
    (f"silence:{WINDOW}", lambda e, r, f: e["no_new_data"] == 30 and f["degraded_steps"] >= 10),
])
def test_frame_and_bus_faults(tmp_path, spec, check):
    o = fly(tmp_path, scenario(CDRW_1S, spec))
    e2e, rej, fl = counters(o)
    assert check(e2e, rej, fl), (spec, e2e, rej, fl)
    # every step was still answered and estimated: fcc rides through on prediction
    assert fl["unanswered_steps"] == 0 and fl["missing_steps"] == 0
    assert [ev["action"] for ev in fl["fault_events"]] == ["start", "end"]
    assert [round(ev["t"], 3) for ev in fl["fault_events"]][0] == pytest.approx(0.2 if "replay" not in spec else 0.4)


def test_lost_ticks(tmp_path):
    """Ticks lost on purpose: those steps are not run; the next tick (E2E-resynchronised by
    the rig) is answered and the flight goes on."""
    o = fly(tmp_path, scenario(CDRW_1S, "loss:frame=SIM_TICK,start=0.2,duration=0.1"))
    _, _, fl = counters(o)
    assert fl["unanswered_steps"] == 5 and fl["missing_steps"] == 5
    assert o.summary["firmware"]["steps"]["cdrw"] == 46
    s = read_csv(tmp_path / "cdrw.csv")
    assert np.isnan(s["kf_alpha_hat"][10:15]).all() and not np.isnan(s["kf_alpha_hat"][15:]).any()
    assert "ticks_lost=5" in (tmp_path / "fcc.log").read_text()


@pytest.fixture(scope="module")
def baseline(tmp_path_factory):
    out = tmp_path_factory.mktemp("baseline")
    fly(out, scenario(CDRW_1S))
    return read_csv(out / "cdrw.csv")


@pytest.mark.parametrize("spec", [
    "spike:signal=alpha,start=0.4,duration=0.1,magnitude=0.15",
    "bias:signal=q,start=0.4,duration=0.3,magnitude=0.1",
    "stuck:signal=alpha,start=0.4,duration=0.3",
    "dropout:signal=alpha,start=0.4,duration=0.2",
    "noise_burst:signal=q,start=0.4,duration=0.2,magnitude=0.2",
    "drift:signal=alpha,start=0.4,duration=0.4,rate=0.5",
    "scale:signal=q,start=0.4,duration=0.3,factor=3.0",
    "spike:signal=de,start=0.4,duration=0.1,magnitude=0.1",
])
def test_sensor_faults_change_the_estimates_from_their_start(tmp_path, baseline, spec):
    o = fly(tmp_path, scenario(CDRW_1S, spec))
    s = read_csv(tmp_path / "cdrw.csv")
    k0 = 20                                                   # t = 0.4 s
    assert s["fault"][k0] == 1 and s["fault"][k0 - 1] == 0
    for f in ("azkf", "zkf", "kf"):
        before = np.array_equal(s[f"{f}_alpha_hat"][:k0], baseline[f"{f}_alpha_hat"][:k0])
        assert before, f"{f}: estimates differ before the fault ({spec})"
        after = s[f"{f}_alpha_hat"][k0:], s[f"{f}_q_hat"][k0:]
        ref = baseline[f"{f}_alpha_hat"][k0:], baseline[f"{f}_q_hat"][k0:]
        assert not (np.array_equal(after[0], ref[0]) and np.array_equal(after[1], ref[1])), f
    if spec.startswith("dropout"):        # a sensor that delivers nothing sends no frame
        assert o.summary["firmware"]["e2e"]["no_new_data"] == 10


def test_oracle_detector_follows_sim_event(tmp_path):
    """SIM_EVENT carries the simulator's truth; fcc --detector oracle flags exactly the
    faulty samples and switches the AZKF to its fault order there."""
    fly(tmp_path, scenario(CDRW_1S, "spike:signal=alpha,start=0.4,duration=0.1,magnitude=0.15"),
        fcc_args=("--detector", "oracle"))
    s = read_csv(tmp_path / "cdrw.csv")
    assert np.flatnonzero(s["fault"]).tolist() == [20, 21, 22, 23, 24]
    assert np.array_equal(s["azkf_fault"], s["fault"])
    assert set(s["azkf_order"][20:25]) == {1000.0} and s["azkf_order"][19] == s["azkf_order"][25] == 2.0


def test_missile_gyro_loss_degrades_commands(tmp_path):
    o = fly(tmp_path, scenario(MISSILE_2S, "loss:frame=MSL_RATE_GYRO,start=0.5,duration=0.5"))
    run = o.summary["missile"]["runs"][0]
    assert o.summary["firmware"]["e2e"]["no_new_data"] == 10
    s = read_csv(tmp_path / "missile_T0.050_b8.csv")
    assert s["degraded"][10:20].sum() >= 9 and s["degraded"][:10].sum() == 0
    assert run["commands_missing"] == 0 and run["unanswered_steps"] == 0


def test_missile_sensor_bias_changes_the_commands(tmp_path):
    base = fly(tmp_path / "a", scenario(MISSILE_2S)).summary["missile"]["runs"][0]
    o = fly(tmp_path / "b", scenario(MISSILE_2S, "bias:signal=q_g,start=1.0,duration=0.5,magnitude=2.0"))
    a = read_csv(tmp_path / "a" / "missile_T0.050_b8.csv")
    b = read_csv(tmp_path / "b" / "missile_T0.050_b8.csv")
    assert np.array_equal(a["code"][:20], b["code"][:20])
    assert not np.array_equal(a["code"][20:], b["code"][20:])
    assert base["reference"]["code_agreement"] > 0.95
    assert o.summary["missile"]["runs"][0]["faults"] == ["bias:start=1,duration=0.5,signal=q_g,magnitude=2"]
