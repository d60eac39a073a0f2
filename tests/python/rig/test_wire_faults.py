"""Wire faults in a realtime flight over canbus (`hil run --bus wire`, hil.rig.wirefaults):
error frames on the simulator's gyro frames, and fcc's node forced bus-off.

What fcc sees is what a SocketCAN driver gives it: one CAN_ERR_PROT error frame per error on
the bus, and its own controller's warning / passive / bus-off / restarted reports; fcc counts
them (its `fcc summary: controller` line in fcc.log) and keeps flying.  The counts are the
model's: canbus's statistics (summary.json's `bus`) say how many error frames the bus carried
and each node's counters; fcc's line must agree with them exactly.
"""
from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import pytest

from hil.bus.busload import frame_bits
from hil.cli.usage import EXIT_FAILED, EXIT_SYNC
from hil.results.busstats import FAULTED, WITHIN, JITTER
from rig_helpers import MISSILE_4S, cli

pytestmark = pytest.mark.vcan

CONTROLLER = re.compile(r"^fcc summary: controller (.*)$", re.M)


def faulty_run(tmp: Path, capsys: Any, fault: str) -> tuple[int, str, dict, dict[str, str]]:
    """A 4 s realtime missile flight at 500 kbit/s with the fault: (exit status, stderr,
    summary, fcc's controller line as key=value)."""
    sc = tmp / "missile.toml"
    sc.write_text(MISSILE_4S)
    out = tmp / "run"
    rc, _, err = cli(capsys, "run", "missile", str(sc), "--mode", "realtime", "--bus", "wire",
                     "--bitrate", "500k", "--fault", fault, "--no-plots", "--quiet", "--out", str(out))
    kept = out if (out / "summary.json").exists() else next(tmp.glob("run.failed-*"))
    summary = json.loads((kept / "summary.json").read_text())
    line = CONTROLLER.search((kept / "fcc.log").read_text())
    assert line is not None, "fcc printed no controller line"
    return rc, err, summary, dict(kv.split("=", 1) for kv in line.group(1).split())


def test_error_frames_on_the_gyro_are_counted_by_fcc_which_keeps_flying(tmp_path, capsys):
    rc, err, s, ctrl = faulty_run(tmp_path, capsys,
                                  "bus_error:frame=MSL_RATE_GYRO,start=1,duration=1,every=2")
    bus = s["bus"]
    # 1 s of gyro frames at 20 Hz (20 starts in the window, 19-21 as the realtime sender's
    # lateness moves its edges' frames), every 2nd corrupted once and retransmitted
    n = bus["error_frames"]
    assert 9 <= n <= 11, bus
    sim, fcc = bus["nodes"]["sim"], bus["nodes"]["fcc"]
    # +8 an error, -1 a success: below the warning level (the sim's frames between two errors
    # bring it down by fewer than 8)
    assert sim["tx_errors"] == n and 8 <= sim["tec_max"] < 96 and sim["error_passive"] == 0
    assert fcc["rx_errors"] == n and fcc["rec_max"] == 1 and fcc["error_frames"] == n
    # fcc: one protocol error frame each, as many as the bus had, nothing worse
    assert ctrl["protocol_errors"] == str(n) and ctrl["state"] == "active", ctrl
    assert ctrl["bus_off"] == "0" and ctrl["rec_max"] == "1", ctrl
    assert s["firmware"]["bus"]["bus_errors"] >= n
    # every gyro frame arrived: retransmitted, later than the bound without errors at most
    assert bus["frames"]["MSL_RATE_GYRO"]["verdict"] in (WITHIN, JITTER, FAULTED)
    run = s["missile"]["runs"][0]
    assert run["commands_missing"] < run["steps"]
    assert rc in (0, EXIT_SYNC), err


def test_fcc_forced_bus_off_reports_it_and_its_restart(tmp_path, capsys):
    rc, err, s, ctrl = faulty_run(tmp_path, capsys, "bus_off:node=fcc,start=1")
    fcc = s["bus"]["nodes"]["fcc"]
    # 32 errors of its frame in a row: TEC 256, bus-off once, back after 128 x 11 recessive bits
    assert fcc["tx_errors"] == 32 and fcc["tec_max"] == 256 and fcc["bus_off"] == 1, fcc
    assert fcc["error_passive"] == 1
    assert len(fcc["recovery_s"]) == 1 and fcc["recovery_s"][0] >= 128 * 11 / 500_000
    # fcc saw it as its driver would say it: passive, bus-off, restarted, active again
    assert ctrl["bus_off"] == "1" and ctrl["restarts"] == "1" and ctrl["state"] == "active", ctrl
    assert ctrl["error_passive"] == "1" and ctrl["protocol_errors"] == "32", ctrl
    assert ctrl["tec_max"] == "255", ctrl   # data[6] holds at most 255
    # and flew on: the flight finished, most commands came
    run = s["missile"]["runs"][0]
    assert run["commands_missing"] < run["steps"] // 2
    assert rc in (0, EXIT_SYNC, EXIT_FAILED), err


def test_a_babbling_node_starves_the_frames_above_it_and_fails_no_bound(tmp_path, capsys):
    """Back to back at 0x005 for 0.5 s: it holds the bus but for the two time-sync frames
    (0x001, 0x002) of higher priority; the frames it delayed are said to be above their bound
    with bus faults, which does not fail the run."""
    rc, err, s, ctrl = faulty_run(tmp_path, capsys, "babbling_node:can_id=0x005,start=1,duration=0.5")
    bus = s["bus"]
    babbler = bus["nodes"]["babble0"]
    frame_s = frame_bits(0x005, b"\xff" * 8) / 500_000
    # at most what 0.5 s of wire holds, and most of it (the time-sync frames and the one frame
    # on the wire at its start are all that interrupt it)
    assert 0.9 * 0.5 / frame_s <= babbler["sent"] <= 0.5 / frame_s + 1, babbler
    assert bus["frames"]["MSL_RATE_GYRO"]["verdict"] == FAULTED
    assert bus["error_frames"] == 0 and ctrl["protocol_errors"] == "0"
    assert s["firmware"]["rejected"]["unknown_id"] >= babbler["sent"] * 0.9   # fcc saw them all
    assert rc in (0, EXIT_SYNC), err


def test_background_load_in_realtime_is_carried_and_analysed(tmp_path, capsys):
    """bus_load 0.5 in a realtime flight: canbus's --load node (the lockstep model's generator,
    firmware/tools/canbus/canbus_load.c) sends its periodic streams in wall time from the
    flight's start; the streams are in the analysis (the bound), and the judged frames stay
    within it (or within the bound with the realtime sender's jitter)."""
    rc, err, s, ctrl = faulty_run(tmp_path, capsys, "bus_load:start=0,duration=inf,utilisation=0.5")
    bus = s["bus"]
    load = bus["nodes"]["load"]
    # identifiers the DBC does not name: under canbus's key
    loads = {n: f for n, f in bus["frames"].items() if n.startswith("0x") and 0x200 <= int(n, 16) <= 0x6FF}
    assert len(loads) == 16 and all(f["wcrt_s"] is not None for f in loads.values())   # 16 streams
    # 16 streams at one period filling 50 % with the 135-bit worst case, over the flight (the
    # load's window is clipped to it: measured 7408 frames in 4 s, 4 s / 8.64 ms x 16 = 7407)
    period = 16 * 135 / 500_000 / 0.5
    assert 16 * int(4.0 / period) <= load["sent"] <= 16 * (int(4.0 / period) + 1), load
    assert 0.5 < bus["utilisation"] < 1.0 and bus["load"] > 0.3, bus
    judged = {n: f for n, f in bus["frames"].items() if f["queue"] == "prio" and f["wcrt_s"] is not None}
    assert {"MSL_RATE_GYRO", "MSL_ACCELEROMETER"} <= set(judged)
    assert all(f["verdict"] in (WITHIN, JITTER) for f in judged.values()), judged
    assert bus["lost"] == 0 and bus["error_frames"] == 0 and ctrl["protocol_errors"] == "0"
    assert rc in (0, EXIT_SYNC), err
