"""Lockstep over the wire-time bus in simulated time (hil.rig.lockstep_wire), the real fcc on
vcan0: the same seed gives the same bytes; every frame of the default flights that the analysis
judges (a priority-queued sender) stays within its worst-case response time at 250k, 500k and
1M; the bus changes the missile's flight (its commands act at their end of frame)."""
from __future__ import annotations

import filecmp
from pathlib import Path

import pytest
from hil.results.busstats import ABOVE, WITHIN
from hil.scenario.file import load_default_scenario
from rig_helpers import MISSILE_2S, fly, scenario

pytestmark = pytest.mark.vcan

LOADED = "bus_load:start=0,duration=inf,utilisation=0.5"


def _judged(bus: dict) -> dict[str, dict]:
    return {n: f for n, f in bus["frames"].items() if f["queue"] == "prio" and f["wcrt_s"] is not None}


def test_same_seed_same_bytes(tmp_path: Path) -> None:
    sc = scenario(MISSILE_2S, LOADED)
    for run in ("a", "b"):
        fly(tmp_path / run, sc, bus="wire", bitrate=250_000)
    files = sorted(p.name for p in (tmp_path / "a").iterdir() if p.suffix in (".csv", ".json")
                   and p.name != "run_info.json")   # run_info.json: the wall clock's facts
    assert "summary.json" in files and any(f.endswith(".csv") for f in files)
    match, mismatch, errors = filecmp.cmpfiles(tmp_path / "a", tmp_path / "b", files, shallow=False)
    assert mismatch == [] and errors == [] and match == files


@pytest.mark.parametrize("bitrate", [250_000, 500_000, 1_000_000])
@pytest.mark.parametrize("aircraft", ["missile", "cdrw"])
def test_default_flights_stay_within_their_bounds(aircraft: str, bitrate: int, tmp_path: Path) -> None:
    o = fly(tmp_path, load_default_scenario(aircraft), bus="wire", bitrate=bitrate)
    bus = o.summary["bus"]
    assert bus["bitrate"] == bitrate and bus["time_base"] == "simulated" and bus["lost"] == 0
    judged = _judged(bus)
    sensors = {"missile": ("MSL_RATE_GYRO", "MSL_ACCELEROMETER"),
               "cdrw": ("CDRW_AOA", "CDRW_PITCH_RATE", "CDRW_ELEVATOR")}[aircraft]
    assert {"SIM_TICK", *sensors} <= set(judged)
    for name, f in judged.items():
        assert f["verdict"] == WITHIN and 0 < f["max_s"] <= f["wcrt_s"], (name, f)
    assert all(f["verdict"] != ABOVE for f in bus["frames"].values())
    # a frame alone on the wire ends at least its unstuffed length after it was queued
    assert bus["frames"]["SIM_TICK"]["p50_s"] >= (44 + 64) / bitrate


def test_the_wire_changes_the_missile_s_flight(tmp_path: Path) -> None:
    sc = scenario(MISSILE_2S)
    ideal = fly(tmp_path / "ideal", sc).summary["missile"]["runs"][0]
    slow = fly(tmp_path / "125k", sc, bus="wire", bitrate=125_000).summary
    run = slow["missile"]["runs"][0]
    assert run["commands_missing"] == 0 and run["rms_q"] != ideal["rms_q"]
    # every command came off the wire after its sample: its response, then fcc's inputs before it
    cmd = slow["bus"]["frames"]["MSL_ELEV_CMD"]
    assert cmd["n"] == 40 and cmd["p50_s"] >= (44 + 64) / 125_000
