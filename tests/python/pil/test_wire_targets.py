"""`--bus wire` with the other targets: the M4F image behind slcan on the wire-time bus (canbus,
its slcan line routed to fcc's vxcan end), and an external device on a real bus (no model: the
rig measures the simulator's frames' response times -- its send time to the recorder's stamp --
and judges them against the bound at the bus's bit rate).

There is no board here: vcan0 stands in for can0, with an fcc started by hand (the external
target's test mode, tests/python/targets/test_rig_targets.py).  On vcan a frame takes no time, so
every response time is the kernel's hand-over (microseconds): the test asserts the section is
computed, paired and judged, not a bus's timing.
"""
from __future__ import annotations

import json
import subprocess
from pathlib import Path
from typing import Any

import pytest

from hil.bus import load
from hil.bus.secoc import TEST_KEY_FILE
from hil.cli.usage import EXIT_SYNC
from hil.plots import busresponse
from hil.results.busstats import JITTER, WITHIN
from hil.results.busstats_real import DEVICE_WHY
from hil.targets import board as pil_qemu
from rig_helpers import cli

SPEC = load()
MISSILE_3S = '''aircraft = "missile"
duration = 3.0
seed = 3
[lqg]
period = 0.1
bits = 8
'''


def run(tmp: Path, capsys: Any, *extra: str) -> tuple[int, str, Path]:
    sc = tmp / "missile.toml"
    sc.write_text(MISSILE_3S)
    out = tmp / "run"
    rc, _, err = cli(capsys, "run", "missile", str(sc), "--mode", "realtime", "--bus", "wire",
                     "--quiet", "--out", str(out), *extra)
    kept = out if (out / "summary.json").exists() else next(tmp.glob("run.failed-*"))
    return rc, err, kept


def wcrt(capsys: Any, scenario: Path, bitrate: str) -> dict[str, float]:
    """`hil bus wcrt --json`'s bound of each frame."""
    rc, out, err = cli(capsys, "bus", "wcrt", "--bitrate", bitrate, "--json", "--scenario", str(scenario))
    assert rc == 0, err
    return {f["name"]: f["wcrt_s"] for f in json.loads(out)["frames"]}


def sync_only(rc: int, summary: dict) -> bool:
    """Exit 0, or 7 for a loaded host's time synchronisation alone (docs/bus-timing.md)."""
    sync = summary.get("sync") or {}
    return rc == 0 or (rc == EXIT_SYNC and sync.get("state") == "LOCKED")


@pytest.mark.vcan
def test_external_device_on_a_real_bus_is_measured_and_judged(tmp_path, capsys, bin_path):
    fcc = subprocess.Popen([str(bin_path("fcc")), "--iface", "vcan0", "--mode", "realtime", "--apps",
                            "missile", "--key-file", str(TEST_KEY_FILE)],
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        rc, err, kept = run(tmp_path, capsys, "--target", "external", "--key-file", str(TEST_KEY_FILE),
                            "--bitrate", "250000")
    finally:
        fcc.terminate()
        fcc.wait(10)
    s = json.loads((kept / "summary.json").read_text())
    assert sync_only(rc, s), err
    bus = s["bus"]
    assert bus["model"] == "real" and bus["bitrate"] == 250_000 and bus["utilisation"] > 0
    # the simulator's sensor frames: every one sent paired with its recording, judged
    bounds = wcrt(capsys, tmp_path / "missile.toml", "250k")
    sent = (kept / "sim_sends.csv").read_text().splitlines()
    assert sent[0] == "t_realtime_ns,can_id"
    for name in ("MSL_RATE_GYRO", "MSL_ACCELEROMETER"):
        f = bus["frames"][name]
        fid = SPEC.by_name(name).frame_id
        assert f["id"] == fid and f["n"] == sum(1 for ln in sent[1:] if int(ln.split(",")[1]) == fid) > 20
        assert f["queue"] == "prio" and f["verdict"] in (WITHIN, JITTER), f
        assert 0 <= f["p50_s"] <= f["p99_s"] <= f["max_s"]
        assert f["wcrt_s"] == pytest.approx(bounds[name])   # `hil bus wcrt`'s at 250k
    # the device's frames: counted, bounded, not measured, and said why
    cmd = bus["not_measured"]["MSL_ELEV_CMD"]
    assert cmd["n"] > 20 and cmd["wcrt_s"] > 0 and cmd["why"] == DEVICE_WHY
    assert not any(f["queue"] == "fifo" for f in bus["frames"].values())
    # the figure is drawn with the run's plots
    assert (kept / busresponse.NAME).is_file()


@pytest.mark.vcan
@pytest.mark.skipif(pil_qemu.available() is None, reason="qemu-system-arm is not installed")
def test_m4f_image_behind_slcan_on_the_wire_time_bus(tmp_path, capsys):
    """The image's frames reach canbus through slcan_bridge on fcc's vxcan end (a FIFO
    node); the simulator's are judged, and the image's against the FIFO bound (its command on the bus)."""
    rc, err, kept = run(tmp_path, capsys, "--target", "qemu-m4f", "--bitrate", "500k", "--no-plots")
    s = json.loads((kept / "summary.json").read_text())
    bus = s["bus"]
    assert bus["model"] == "wire" and bus["lost"] == 0, bus
    assert bus["frames"]["MSL_RATE_GYRO"]["verdict"] in (WITHIN, JITTER)
    cmd = bus["frames"]["MSL_ELEV_CMD"]
    assert cmd["queue"] == "fifo" and cmd["verdict"] in (WITHIN, JITTER) and cmd["n"] > 0, cmd
    info = json.loads((kept / "run_info.json").read_text())
    assert info["target"] == "qemu-m4f"
    run0 = s["missile"]["runs"][0]
    assert run0["commands_missing"] < run0["steps"]
    # 7: the time synchronisation alone (the image in realtime refuses the master's pairs on
    # the ideal bus too: the serial line's delay; docs/bus-timing.md)
    assert rc == 0 or (rc == EXIT_SYNC and s["sync"]["verdict"] in ("refused", "lost", "ok")), err
