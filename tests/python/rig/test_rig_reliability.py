"""What survives which failure, on vcan0 with the real fcc: the bus log when the interface
goes down mid-run, no process left behind when the rig is killed, a leftover fcc detected
before a run, and no garbage reported with exit status 0."""
from __future__ import annotations

import contextlib
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from hil.bus import load
from hil.bus.secoc import TEST_KEY_FILE
from hil.cli import main
from hil.rig import lockstep
from hil.rig.link import CanLink
from hil.rig.session import listening_ahead
from hil.io.rundir import FAILED

from conftest import build_dir

pytestmark = pytest.mark.vcan

HIL = [sys.executable, "-m", "hil.cli"]


def cli(capsys, *argv: str) -> tuple[int, str, str]:
    rc = main(list(argv))
    out, err = capsys.readouterr()
    return rc, out, err


def failed_dirs(parent: Path, name: str) -> list[Path]:
    return sorted(p for p in parent.iterdir() if p.name.startswith(f"{name}.failed-"))


def children(pid: int) -> list[int]:
    try:
        text = Path(f"/proc/{pid}/task/{pid}/children").read_text()
    except OSError:
        return []
    return [int(c) for c in text.split()]


def comm(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/comm").read_text().strip()
    except OSError:
        return ""


def gone(pid: int, timeout: float = 10.0) -> bool:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        state = ""
        try:
            state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
        except (OSError, IndexError):
            return True
        if state == "Z":  # a zombie of a process we did not start: dead
            return True
        time.sleep(0.05)
    return False


def test_interface_down_mid_run_keeps_the_bus_log(tmp_path, capsys, monkeypatch):
    real_step = lockstep.LockstepRunner.step

    def step(self, d):
        if self.steps == 20:
            subprocess.run(["ip", "link", "set", "vcan0", "down"], check=True)
        return real_step(self, d)

    monkeypatch.setattr(lockstep.LockstepRunner, "step", step)
    out = tmp_path / "run"
    try:
        rc, _, err = cli(capsys, "run", "cdrw", "--out", str(out), "--quiet", "--no-plots")
    finally:
        subprocess.run(["ip", "link", "set", "vcan0", "up"], check=True)
    assert rc == 1, err
    assert len([ln for ln in err.splitlines() if ln.strip()]) == 1 and "vcan0" in err
    assert not out.exists()
    (kept,) = failed_dirs(tmp_path, "run")
    assert str(kept) in err
    assert "failed" in (kept / FAILED).read_text()
    log = (kept / "bus.log").read_text().splitlines()
    # the 20 steps flown before the interface went down are in it: 3 sensor frames, a tick
    # and fcc's 12 outputs + ACK each
    assert sum(" 020#" in ln for ln in log) == 20  # SIM_TICK
    assert sum(" 110#" in ln for ln in log) == 20  # SID_AZKF_STATE
    assert (kept / "fcc.log").exists()


def test_killing_the_rig_leaves_no_process_behind(tmp_path):
    out = tmp_path / "run"
    scen = tmp_path / "long.toml"
    scen.write_text('aircraft = "cdrw"\nduration = 60.0\nseed = 1\n')
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    hil = subprocess.Popen([*HIL, "run", "cdrw", str(scen), "--out", str(out), "--no-plots",
                            "--quiet"], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    try:
        deadline = time.monotonic() + 60
        kids: list[int] = []
        while time.monotonic() < deadline:
            kids = children(hil.pid)
            if {"fcc", "canrec"} <= {comm(k) for k in kids}:
                break
            assert hil.poll() is None, hil.stderr.read().decode() if hil.stderr else ""
            time.sleep(0.05)
        assert {"fcc", "canrec"} <= {comm(k) for k in kids}, kids
        time.sleep(0.5)  # mid-flight
        hil.send_signal(signal.SIGKILL)
        hil.wait(10)
        for k in kids:
            assert gone(k), f"{comm(k)} (pid {k}) outlived the rig"
    finally:
        if hil.poll() is None:
            hil.kill()
            hil.wait()
    # a next run on the same bus works (nothing left commanding it)
    rc = subprocess.run([*HIL, "run", "cdrw", "--out", str(tmp_path / "next"), "--quiet",
                         "--no-plots"], env=env, capture_output=True, timeout=300)
    assert rc.returncode == 0, rc.stderr.decode()


def test_a_leftover_fcc_on_the_bus_is_detected(tmp_path, capsys):
    fcc = subprocess.Popen([str(build_dir() / "bin" / "fcc"), "--iface", "vcan0",
                            "--key-file", str(TEST_KEY_FILE)],
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        time.sleep(0.3)
        rc, _, err = cli(capsys, "run", "cdrw", "--out", str(tmp_path / "o"), "--quiet",
                         "--no-plots")
    finally:
        fcc.terminate()
        fcc.wait(10)
    assert rc == 1
    line = [ln for ln in err.splitlines() if ln.strip()]
    assert len(line) == 1 and "another fcc is already on vcan0" in line[0], err
    assert not (tmp_path / "o").exists()


def test_a_socket_opened_ahead_carries_its_listen_into_the_session(tmp_path, capsys):
    """A warm rig's command takes the socket the rig opened as the previous command ended
    (hil.rig.session.listening_ahead): an fcc heard meanwhile, even one gone since, fails the
    run before fcc starts, as one heard in the session's own listen does; with none heard, the
    run's results are a fresh socket's."""
    heartbeat = load().by_name("FCC_STATUS").frame_id
    with listening_ahead("vcan0"), CanLink("vcan0", [heartbeat]) as watch:
        fcc = subprocess.Popen([str(build_dir() / "bin" / "fcc"), "--iface", "vcan0",
                                "--key-file", str(TEST_KEY_FILE)],
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            assert watch.recv_wait(10.0) is not None, "the leftover fcc's heartbeat"
        finally:
            fcc.terminate()
            fcc.wait(10)
        rc, _, err = cli(capsys, "run", "cdrw", "--out", str(tmp_path / "o"), "--quiet", "--no-plots")
    assert rc == 1 and "another fcc is already on vcan0" in err, err
    assert not (tmp_path / "o").exists()
    runs = {}
    for name in ("ahead", "fresh"):
        with listening_ahead("vcan0") if name == "ahead" else contextlib.nullcontext():
            rc, _, err = cli(capsys, "run", "cdrw", "--out", str(tmp_path / name), "--quiet", "--no-plots")
        assert rc == 0, err
        runs[name] = [(tmp_path / name / f).read_bytes() for f in ("summary.json", "cdrw.csv", "faults.log")]
    assert runs["ahead"] == runs["fresh"]


def test_step_errors_fail_the_run(tmp_path, capsys):
    """--x0 1e308,1e308 made every identification step fail, and Table 4 printed 35.28 for
    every filter with exit status 0; fcc now refuses the option (`fcc --check-args`, before
    the rig starts: exit 2), and a run whose firmware reports step errors fails (exit 1)
    whatever caused them."""
    rc, out, err = cli(capsys, "run", "cdrw", "--out", str(tmp_path / "o"), "--quiet",
                       "--no-plots", "--fcc-args", "--x0 1e308,1e308")
    assert rc == 2 and "Table 4" not in out
    assert "--x0" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "o").exists()


def test_an_own_earlier_run_is_replaced_whole(tmp_path, capsys):
    out = tmp_path / "o"
    rc, _, err = cli(capsys, "sweep", "missile", "--periods", "0.1", "--bits", "8", "--out",
                     str(out), "--quiet", "--no-plots")
    assert rc == 0, err
    assert (out / "missile_T0.100_b8.csv").exists()
    rc, _, err = cli(capsys, "run", "cdrw", "--out", str(out), "--quiet", "--no-plots")
    assert rc == 0, err
    assert not (out / "missile_T0.100_b8.csv").exists()   # no stale file of the earlier run
    assert json.loads((out / "summary.json").read_text())["command"] == "run"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["o"]
