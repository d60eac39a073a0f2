"""The live decode of docs/bus.md (`candump -L -r 4194304 vcan0 | cantools decode ...`) loses no
frame while its reader is not reading yet (cantools starts in 3 s, a lockstep flight is over
sooner): with `-r 4194304` the socket's queue holds the whole flight; without it the kernel
drops frames (candump -d says so). The reader here reads only after the flight: the worst case,
whatever the machine's speed."""
from __future__ import annotations

import os
import select
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import REPO

pytestmark = pytest.mark.vcan
HIL = str(Path(sys.executable).with_name("hil"))
MARKER = "7F2#00"   # not in the DBC: the recorder's readiness, before the flight


def _listening_candump(*options: str) -> subprocess.Popen:
    dump = subprocess.Popen(["candump", "-L", "-d", *options, "vcan0"], stdout=subprocess.PIPE)
    for _ in range(100):  # until a frame sent now comes through: candump is bound
        subprocess.run(["cansend", "vcan0", MARKER], check=True)
        if select.select([dump.stdout], [], [], 0.1)[0]:
            break
    else:
        dump.kill()
        pytest.fail("candump did not start listening")
    return dump


def _flight_under(dump: subprocess.Popen, out: Path) -> tuple[list[str], int]:
    """Fly a lockstep CDRW flight while nobody reads candump's pipe; then read it all."""
    r = subprocess.run([HIL, "run", "cdrw", "--no-plots", "--quiet", "--out", str(out)],
                       capture_output=True, text=True, timeout=300, cwd=REPO)
    assert r.returncode == 0, r.stderr
    text = b""
    for _ in range(300):  # read what waited, until an end marker sent now comes after it
        subprocess.run(["cansend", "vcan0", MARKER], check=True)
        while select.select([dump.stdout], [], [], 0.2)[0]:
            text += os.read(dump.stdout.fileno(), 1 << 16)
        lines = text.decode("ascii").splitlines()
        if _frames(lines) and lines[-1].endswith(MARKER):
            break
    dump.terminate()
    dump.wait(timeout=10)
    with open(out / "bus_wall.log", encoding="ascii") as f:
        recorded = sum(1 for _ in f)
    return lines, recorded


def _frames(lines: list[str]) -> list[str]:
    return [ln for ln in lines if ln.startswith("(") and not ln.rstrip().endswith(MARKER)]


def test_the_documented_receive_queue_holds_a_lockstep_flight(tmp_path: Path) -> None:
    lines, recorded = _flight_under(_listening_candump("-r", "4194304"), tmp_path / "big")
    assert not [ln for ln in lines if "DROPCOUNT" in ln]
    assert len(_frames(lines)) == recorded


def test_the_default_receive_queue_does_not(tmp_path: Path) -> None:
    lines, recorded = _flight_under(_listening_candump(), tmp_path / "default")
    assert [ln for ln in lines if "DROPCOUNT" in ln]
    assert len(_frames(lines)) < recorded
