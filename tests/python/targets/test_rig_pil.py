"""`--target qemu-m4f` on vcan0: the Cortex-M4F image under QEMU, its SLCAN line joined to vcan0
by slcan_bridge, flown by the rig exactly as the host fcc.

Short lockstep flights of both aircraft (bounded: ~1 min on a loaded machine), checked
against the same flights of the host float build (the image's real type); and a link loss --
the bridge killed, QEMU frozen -- is one rig error, never a hang.
"""
from __future__ import annotations

import json
import os
import signal
import subprocess
import time
from pathlib import Path

import numpy as np
import pytest

from hil.targets import board as pil_qemu
from hil.io.output import read_csv
from hil.targets.qemu_m4f import build_image
from hil.rig.config import RigConfig
from hil.rig.flight import fcc_args
from hil.rig.errors import FccDied, FccTimeout
from hil.rig.session import RigSession
from rig_helpers import CDRW_1S, MISSILE_2S, airborne, fly, scenario

pytestmark = [pytest.mark.vcan,
              pytest.mark.skipif(pil_qemu.available() is None, reason="qemu-system-arm is not installed")]

REPO = Path(__file__).resolve().parents[3]
#: TCG on a loaded 2-core machine inside User-Mode Linux: generous per-step timeout
TIMEOUT = 20.0


@pytest.fixture(scope="module")
def float_fcc() -> Path:
    """The host float build's fcc (FCC_REAL=float, the image's real type)."""
    build = Path(os.environ.get("FCC_FLOAT_BUILD_DIR", REPO / "build-float"))
    if not (build / "CMakeCache.txt").is_file():
        subprocess.run(["cmake", "-S", str(REPO), "-B", str(build), "-G", "Ninja", "-DFCC_REAL=float"],
                       check=True, capture_output=True)
    subprocess.run(["cmake", "--build", str(build), "--target", "fcc"], check=True, capture_output=True)
    return build / "bin" / "fcc"


@pytest.fixture(scope="module")
def image() -> Path:
    return build_image()


def test_pil_flights_match_the_host_float_build(tmp_path, float_fcc, image):
    """Both aircraft in one image, lockstep: the CDRW's estimates and the missile's D/A codes
    of the image equal the host float build's (same compiler semantics aside: see README)."""
    cdrw, msl = scenario(CDRW_1S), scenario(MISSILE_2S)
    t0 = time.monotonic()
    pil = fly(tmp_path / "pil", cdrw, msl, target="qemu-m4f", timeout=TIMEOUT, fcc_binary=image)
    wall_pil = time.monotonic() - t0
    host = fly(tmp_path / "host", cdrw, msl, fcc_binary=float_fcc)
    info = json.loads((tmp_path / "pil" / "run_info.json").read_text())
    assert info["target"] == "qemu-m4f" and info["fcc_exit"] == 0 and "-icount" in info["fcc_command"]
    assert wall_pil < 300
    s_pil, s_host = pil.summary, host.summary
    assert s_pil["firmware"]["steps"] == s_host["firmware"]["steps"] == {"cdrw": 51, "missile": 40}
    assert s_pil["cdrw"]["flight"]["missing_steps"] == 0
    for f, row in s_host["cdrw"]["table4"].items():
        for state, v in row.items():
            assert s_pil["cdrw"]["table4"][f][state] == pytest.approx(v, rel=1e-3, abs=1e-9)
    a, b = read_csv(tmp_path / "pil" / "missile_T0.050_b8.csv"), read_csv(tmp_path / "host" / "missile_T0.050_b8.csv")
    assert len(a["code"]) == 40 and np.mean(a["code"] == b["code"]) >= 0.975   # at most 1 of 40
    assert "fcc summary: cdrw steps=51" in (tmp_path / "pil" / "fcc.log").read_text()


def _session(tmp_path: Path, image: Path) -> RigSession:
    sc = scenario(CDRW_1S)
    cfg = RigConfig(out_dir=tmp_path, target="qemu-m4f", fcc_binary=image, mode="lockstep")
    return RigSession(tmp_path, fcc_args([sc], RigConfig(out_dir=tmp_path)), cfg)


def test_link_loss_bridge_killed(tmp_path, image):
    """The bridge gone mid-flight (the serial line's other end): one error naming it, at once."""
    sc = scenario(CDRW_1S)
    with pytest.raises(FccDied, match=r"the M4F image died during step 5 of app cdrw "
                                      r"\(serial link lost: slcan_bridge killed by SIGKILL\)"):
        with _session(tmp_path, image) as rig:
            runner, d = airborne(rig, sc, 5, timeout=TIMEOUT)
            os.kill(rig.fcc.bridge.pid, signal.SIGKILL)  # type: ignore[union-attr]
            rig.fcc.bridge.wait(10)                      # type: ignore[union-attr]
            runner.step(d)
    assert rig.fcc.qemu.poll() is not None             # type: ignore[union-attr]  # nothing left behind
    assert not rig.fcc.line_socket.exists()            # type: ignore[union-attr]


def test_link_loss_uart_stops(tmp_path, image):
    """QEMU frozen (the UART stops answering): the lockstep timeout, one line, no hang."""
    sc = scenario(CDRW_1S)
    with _session(tmp_path, image) as rig:
        runner, d = airborne(rig, sc, 3, timeout=3.0)
        os.kill(rig.fcc.qemu.pid, signal.SIGSTOP)       # type: ignore[union-attr]
        t0 = time.monotonic()
        with pytest.raises(FccTimeout, match="the M4F image did not answer step 3 of app cdrw within 3 s"):
            runner.step(d)
        assert time.monotonic() - t0 < 10
        os.kill(rig.fcc.qemu.pid, signal.SIGCONT)       # type: ignore[union-attr]
    assert rig.fcc.qemu.poll() is not None              # type: ignore[union-attr]


def test_lockstep_runs_qemu_and_the_bridge_batch(tmp_path, image):
    """In lockstep every thread of QEMU (main loop, vCPU, ...) and the bridge run SCHED_BATCH with the
    rig: a woken thread does not preempt the one running, so QEMU's main loop reads a frame's
    bytes ahead before its vCPU takes them (firmware/port/mps2_an386/README.md)."""
    with _session(tmp_path, image) as rig:
        qemu_threads = [int(t) for t in os.listdir(f"/proc/{rig.fcc.qemu.pid}/task")]  # type: ignore[union-attr]
        assert rig.batch_scheduled and len(qemu_threads) >= 2
        assert set(rig.fcc.local_pids()) == {*qemu_threads, rig.fcc.bridge.pid}     # type: ignore[union-attr]
        for tid in rig.fcc.local_pids():
            assert os.sched_getscheduler(tid) == os.SCHED_BATCH
