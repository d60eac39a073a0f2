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


def test_fcc_bus_off_in_simulated_time(tmp_path: Path) -> None:
    """bus_off of fcc at 1 s in lockstep: the model's fault confinement (the realtime canbus
    process's fault builder) in summary.json's bus section; on the idle bus of the step's end
    fcc is back after its error flag and 128 x 11 recessive bits, (6 + 1408) bit times exactly;
    the commands the bus-off dropped never arrive, and the flight flies on.  fcc itself gets no
    SocketCAN error frame in lockstep (its frames travel on vcan)."""
    o = fly(tmp_path, scenario(MISSILE_2S, "bus_off:node=fcc,start=1"), bus="wire", bitrate=500_000)
    bus = o.summary["bus"]
    fcc = bus["nodes"]["fcc"]
    assert fcc["tx_errors"] == 32 and fcc["tec_max"] == 256 and fcc["bus_off"] == 1, fcc
    assert fcc["recovery_s"] == [pytest.approx((6 + 128 * 11) / 500_000, abs=1e-12)]
    assert fcc["error_frames"] == 0 and bus["error_frames"] == 32
    # the step at 1 s: its answer dropped with fcc's queue (32 attempts of its first frame take
    # 32 x ~0.1 ms, well before the next step); fcc answered every step, one command never came
    run = o.summary["missile"]["runs"][0]
    assert run["unanswered_steps"] == 0 and run["command_delay_s"]["n"] == run["steps"] - 1
    assert bus["frames"]["MSL_ELEV_CMD"]["n"] == run["steps"] - 1


def test_a_gyro_error_frame_in_simulated_time(tmp_path: Path) -> None:
    """bus_error on MSL_RATE_GYRO once at 1 s: one error frame, the simulator's TEC +8 and
    every other node's REC +1; the same seed gives the same bytes (the exact delay it adds is
    tests/python/bus/test_simbus.py's, on the same path by hand)."""
    sc = scenario(MISSILE_2S, "bus_error:frame=MSL_RATE_GYRO,start=1,duration=0.05,count=1")
    for run in ("a", "b"):
        o = fly(tmp_path / run, sc, bus="wire", bitrate=500_000)
    bus = o.summary["bus"]
    assert bus["error_frames"] == 1
    nodes = bus["nodes"]
    assert nodes["sim"]["tx_errors"] == 1 and nodes["sim"]["tec_max"] == 8
    assert nodes["fcc"]["rx_errors"] == 1 and nodes["recorder"]["rx_errors"] == 1
    assert o.summary["missile"]["runs"][0]["commands_missing"] == 0
    files = sorted(p.name for p in (tmp_path / "a").iterdir() if p.suffix in (".csv", ".json")
                   and p.name != "run_info.json")
    match, mismatch, errors = filecmp.cmpfiles(tmp_path / "a", tmp_path / "b", files, shallow=False)
    assert "summary.json" in match and mismatch == [] and errors == [] and match == files
