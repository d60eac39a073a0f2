"""The wire-level fault kinds (bus_error, babbling_node, bus_off): parsed and validated like the
others, refused on a bus other than the wire-time one (one line, exit 2), ignored by the
simulator, and turned into canbus's options (hil.rig.wirefaults) -- which canbus accepts."""
from __future__ import annotations

import math
import subprocess
from pathlib import Path

import pytest

from hil.bus import load
from hil.io.paths import ToolNotFound, tool
from hil.rig.wirefaults import canbus_args, refusal
from hil.scenario.faults import WIRE_KINDS, BabblingNode, BusError, BusOff
from hil.scenario.file import parse_fault_spec
from hil.scenario.schema import ScenarioError

CASES = {
    "bus_error": "bus_error:frame=MSL_RATE_GYRO,node=sim,start=1,duration=2,every=3,count=10,bit=20,superposed=6",
    "babbling_node": "babbling_node:can_id=0x10,rate_hz=2000,start=0.5,duration=1",
    "bus_off": "bus_off:node=fcc,start=3",
}
ENDS = {"sim": "w1sb", "recorder": "w1rb", "fcc": "w1fb"}


def test_every_wire_kind_has_a_case():
    assert set(CASES) == set(WIRE_KINDS)


@pytest.mark.parametrize("kind", sorted(CASES))
def test_a_wire_fault_parses_round_trips_and_is_canbus_s(kind):
    fault = parse_fault_spec(CASES[kind], "missile", known_frames={m.name for m in load().messages})
    assert fault.kind == kind and fault.level == "wire"
    assert parse_fault_spec(fault.describe(), "missile") == fault


def test_canbus_options_of_each_kind():
    spec = load()
    err = parse_fault_spec(CASES["bus_error"], "missile")
    bab = parse_fault_spec(CASES["babbling_node"], "missile")
    off = parse_fault_spec(CASES["bus_off"], "missile")
    assert isinstance(err, BusError) and isinstance(bab, BabblingNode) and isinstance(off, BusOff)
    assert math.isinf(off.duration)
    gyro = spec.by_name("MSL_RATE_GYRO").frame_id
    assert canbus_args([err, bab, off], ENDS, spec) == [
        "--error", f"id=0x{gyro:X},from=1,to=3,every=3,node=w1sb,count=10,bit=20,superposed=6",
        "--babble", "id=0x10,dlc=8,period=0.0005,from=0.5,to=1.5",
        "--bus-off", "w1fb@3"]
    # every frame, forever, at the CRC delimiter; back to back
    every = parse_fault_spec("bus_error:start=0,duration=inf", "missile")
    b2b = parse_fault_spec("babbling_node:start=0,duration=inf", "missile")
    assert canbus_args([every, b2b], ENDS, spec) == [
        "--error", "id=0-0x1FFFFFFF,from=0,every=1,bit=crc-delim,superposed=0",
        "--babble", "id=0x0,dlc=8,period=0,from=0"]


@pytest.mark.parametrize("text, why", [
    ("bus_error:frame=NOPE,start=1,duration=1", "unknown frame 'NOPE'"),
    ("bus_error:start=1,duration=1,bit=43", "bit"),
    ("bus_error:start=1,duration=1,superposed=7", "superposed"),
    ("bus_error:start=1,duration=1,every=0", "every"),
    ("bus_error:start=1,duration=1,node=recorder", "node"),
    ("babbling_node:start=1,duration=1,can_id=0x800", "can_id"),
    ("babbling_node:start=1,duration=1,rate_hz=-1", "rate_hz"),
    ("bus_off:start=1,node=recorder", "node"),
])
def test_bad_wire_faults_are_refused_with_their_field(text, why):
    with pytest.raises(ScenarioError, match=why):
        parse_fault_spec(text, "missile")


def test_refused_on_the_ideal_bus_in_one_line():
    fault = parse_fault_spec(CASES["bus_off"], "missile")
    assert refusal([fault], "wire") == ""
    why = refusal([fault], "ideal")
    assert "needs --bus wire" in why and "bus_off" in why and "\n" not in why


def test_hil_run_refuses_a_wire_fault_on_the_ideal_bus_exit_2(tmp_path: Path):
    hil = Path(".venv/bin/hil")
    if not hil.exists():
        pytest.skip("no .venv/bin/hil (scripts/setup)")
    r = subprocess.run([str(hil), "run", "missile", "--fault", "bus_error:start=1,duration=1",
                        "--out", str(tmp_path / "out")], capture_output=True, text=True, check=False)
    assert r.returncode == 2
    assert r.stderr.strip().splitlines() == [
        "hil: fault 'bus_error:start=1,duration=1,frame=*,node=*,every=1,count=0,bit=-1,"
        "superposed=0': a fault of the wire-time bus (canbus): needs --bus wire (this run's bus: ideal)"]
    assert not (tmp_path / "out").exists()


def test_canbus_accepts_what_the_rig_gives_it_and_refuses_a_bad_schedule():
    """canbus parses the options before it opens anything: --help after them is 0, a bad one
    is one line and exit 2."""
    try:
        exe = str(tool("canbus"))
    except ToolNotFound:
        pytest.skip("canbus not built")
    spec = load()
    faults = [parse_fault_spec(t, "missile") for t in CASES.values()]
    nodes = [a for end in ENDS.values() for a in ("--node", end)]
    ok = subprocess.run([exe, *nodes, *canbus_args(faults, ENDS, spec), "--help"],
                        capture_output=True, text=True, check=False)
    assert ok.returncode == 0, ok.stderr
    bad = subprocess.run([exe, *nodes, "--error", "id=0x100,node=nobody"], capture_output=True,
                         text=True, check=False)
    assert bad.returncode == 2
    assert bad.stderr.splitlines() == ["canbus: --error: nobody is not a --node"]
