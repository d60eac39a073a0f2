"""The M4F image's serial line in the rig (`--target qemu-m4f`, vcan): a step's frames go out
in one burst and wait in slcan_bridge's queue while the UART takes one byte at a time; a frame
that queue drops is never lost silently -- the run ends with one line naming it.  In realtime
the bridge stamps each line with the frame's time on vcan0 and the image's time sync uses it.
"""
from __future__ import annotations

import json
import os
import re
import signal

import can
from pathlib import Path

import pytest
from rig_helpers import CDRW_1S, MISSILE_2S, airborne, fly, scenario

from hil.rig.config import RigConfig
from hil.rig.errors import FccDied
from hil.rig.flight import fcc_args
from hil.rig.session import RigSession
from hil.targets import board, qemu_m4f
from hil.targets.qemu_m4f import build_image

pytestmark = [pytest.mark.vcan,
              pytest.mark.skipif(board.available() is None, reason="qemu-system-arm is not installed")]

TIMEOUT = 20.0  # TCG in the UML guest on a loaded 2-core machine


@pytest.fixture(scope="module")
def image() -> Path:
    return build_image()


def test_a_burst_per_step_reaches_the_image_whole(tmp_path, image):
    """The rig batches each step's frames (one sendmmsg) to the image: the line queues them,
    every step is answered at once (no resent tick) and the image's ring never overflows."""
    fly(tmp_path, scenario(CDRW_1S), target="qemu-m4f", timeout=TIMEOUT, fcc_binary=image)
    info = json.loads((tmp_path / "run_info.json").read_text())
    assert info["fcc_exit"] == 0 and info["resent_ticks"] == 0
    log = (tmp_path / "fcc.log").read_text()
    assert "fcc summary: cdrw steps=51 " in log and " rx_overflows=0 " in log, log


def test_a_frame_the_line_drops_ends_the_run(tmp_path, image, monkeypatch):
    """A line queue of one frame behind the kernel's smallest socket buffer (~4.6 kB), QEMU frozen
    (it takes no byte), a burst on the bus: the bridge drops a frame, and the run ends with one
    line saying so (the kernel slcan's default queue of 10 dropped ticks this way, silently,
    behind the heartbeat or an attacker's frames)."""
    monkeypatch.setattr(qemu_m4f, "LINE_QUEUE", 1)
    monkeypatch.setattr(qemu_m4f, "LINE_BUFFER", 1)
    sc = scenario(CDRW_1S)
    cfg = RigConfig(out_dir=tmp_path, target="qemu-m4f", fcc_binary=image, mode="lockstep")
    with pytest.raises(FccDied, match=r"serial link lost: a frame dropped on its way to the image "
                                      r"\(the queue of 1 frames toward the line was full"):
        with RigSession(tmp_path, fcc_args([sc], RigConfig(out_dir=tmp_path)), cfg) as rig:
            runner, d = airborne(rig, sc, 3, timeout=TIMEOUT)
            qemu = rig.fcc.qemu  # type: ignore[union-attr]
            os.kill(qemu.pid, signal.SIGSTOP)
            try:
                with can.Bus(interface="socketcan", channel=cfg.iface) as bus:
                    for i in range(500):  # more than ~4.6 kB of 22-character lines
                        bus.send(can.Message(arbitration_id=0x7F0, data=[i & 0xFF], is_extended_id=False))
                assert rig.fcc.bridge.wait(TIMEOUT) == qemu_m4f.BRIDGE_LOST  # type: ignore[union-attr]
            finally:
                os.kill(qemu.pid, signal.SIGCONT)
            runner.step(d)


def test_realtime_lines_carry_their_bus_time(tmp_path, image):
    """In realtime every frame line to the image carries the frame's time on vcan0 (SLCAN Z2, the
    bridge's kernel receive stamp), the image takes none of them as malformed and stamps the frames
    with it, and its time sync follows the master on those stamps; in lockstep (virtual time: the
    instruction count) the lines carry none."""
    fly(tmp_path, scenario(MISSILE_2S), target="qemu-m4f", timeout=TIMEOUT, fcc_binary=image,
        mode="realtime")
    log = (tmp_path / "fcc.log").read_text()
    bridge = (tmp_path / "slcan_bridge.log").read_text()
    stamped = re.search(r"fcc summary: rx_timing .* bus_stamped=(\d+) ", log)
    assert stamped and int(stamped[1]) > 0, log
    assert re.search(r"fcc summary: slcan lines=\d+ .*", log), log
    assert "answers_error=0 " in bridge and "lines_bad=0 " in bridge, bridge
    samples = re.search(r"fcc summary: sync state=\d+ .*samples=(\d+) ", log)
    assert samples and int(samples[1]) > 0, log


def test_lockstep_lines_carry_no_stamp(tmp_path, image):
    fly(tmp_path, scenario(CDRW_1S), target="qemu-m4f", timeout=TIMEOUT, fcc_binary=image)
    assert " bus_stamped=0 " in (tmp_path / "fcc.log").read_text()


def test_realtime_line_runs_at_fccs_priority(tmp_path, image):
    """In realtime QEMU's main loop (it moves the line's bytes into the UART) runs at fcc's
    SCHED_FIFO priority and its other threads (the vCPU) just below, as the host fcc runs;
    lockstep leaves them to the rig's SCHED_BATCH (test above: the bursts)."""
    sc = scenario(CDRW_1S)
    cfg = RigConfig(out_dir=tmp_path, target="qemu-m4f", fcc_binary=image, mode="realtime")
    with RigSession(tmp_path, fcc_args([sc], cfg), cfg) as rig:
        qemu = rig.fcc.qemu  # type: ignore[union-attr]
        threads = {int(t.name): (os.sched_getscheduler(int(t.name)),
                                 os.sched_getparam(int(t.name)).sched_priority)
                   for t in Path(f"/proc/{qemu.pid}/task").iterdir()}
    main = threads.pop(qemu.pid)
    assert main == (os.SCHED_FIFO, qemu_m4f.LINE_RT_PRIORITY), (main, threads)
    # the vCPU (and QEMU's helper threads) below it; a thread the main loop starts later inherits
    assert threads and all(policy == os.SCHED_FIFO for policy, _ in threads.values()), threads
    assert (os.SCHED_FIFO, qemu_m4f.LINE_RT_PRIORITY - 1) in threads.values(), threads
