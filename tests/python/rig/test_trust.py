"""Nothing the bus says is taken on trust (issue items 2-7): forged and replayed frames change
no table, on the bus (vcan) and in the evaluation of a recorded log.  Every attack is placed
by step count, never by wall-clock time."""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from hil.bus.secoc import TEST_KEY_FILE
from hil.rig.link import pack_frame
from hil.rig.lockstep import LockstepRunner
from hil.rig.session import RigSession
from rig_helpers import CDRW_1S, fly, scenario

#: `cansend vcan0 010#0020000000000000`: a SIM_CONTROL reset, no authenticator, no valid E2E
FORGED_RESET = (0x010, bytes.fromhex("0020000000000000"))
SIM_TICK_ID = 0x020


def cdrw_flight(out: Path, monkeypatch: pytest.MonkeyPatch, forge_at: int | None = None,
                replay_lag: int | None = None) -> dict:
    """A lockstep CDRW flight; forge_at: the forged reset goes on the bus before that step's
    tick; replay_lag: right after each tick, the tick (and its authenticator) of that many
    steps before is sent once more (between the tick and fcc's answer on the bus)."""
    sent_ticks: list[list[tuple[int, bytes]]] = []
    step, secure = LockstepRunner.step, RigSession.secure

    def capture(rig: RigSession, frame_id: int, data: bytes) -> list[tuple[int, bytes]]:
        got = secure(rig, frame_id, data)
        if frame_id == SIM_TICK_ID and replay_lag is not None:
            sent_ticks.append(got)
            if len(sent_ticks) > replay_lag:
                return got + sent_ticks[-1 - replay_lag]
        return got

    def attacked(runner: LockstepRunner, d):  # type: ignore[no-untyped-def]
        link = runner.rig.link
        assert link is not None
        if forge_at is not None and d.k == forge_at:
            link.send_raw(pack_frame(*FORGED_RESET))
        return step(runner, d)

    monkeypatch.setattr(LockstepRunner, "step", attacked)
    monkeypatch.setattr(RigSession, "secure", capture)
    try:
        return dict(fly(out, scenario(CDRW_1S), key_file=TEST_KEY_FILE, timeout=10.0).summary)
    finally:
        monkeypatch.undo()


@pytest.fixture(scope="module")
def clean(tmp_path_factory) -> dict:
    with pytest.MonkeyPatch.context() as mp:
        return cdrw_flight(tmp_path_factory.mktemp("clean"), mp)


@pytest.mark.vcan
def test_a_forged_reset_changes_no_table(clean, tmp_path, monkeypatch):
    s = cdrw_flight(tmp_path / "run", monkeypatch, forge_at=50)
    assert s["cdrw"]["table4"] == clean["cdrw"]["table4"]
    assert s["cdrw"]["flight"]["missing_steps"] == clean["cdrw"]["flight"]["missing_steps"] == 0
    assert s["cdrw"]["coverage"] == clean["cdrw"]["coverage"]


@pytest.mark.vcan
def test_ticks_replayed_ten_steps_late_change_no_table(clean, tmp_path, monkeypatch):
    s = cdrw_flight(tmp_path / "run", monkeypatch, replay_lag=10)
    assert s["cdrw"]["table4"] == clean["cdrw"]["table4"]
    assert s["cdrw"]["flight"]["missing_steps"] == 0
    assert s["firmware"]["steps"] == clean["firmware"]["steps"]


@pytest.mark.vcan
def test_a_second_fcc_on_the_bus_fails_the_run_before_any_result(tmp_path, monkeypatch, capsys):
    """A second rig's fcc (the same key, its own trip) comes up after the leftover listen:
    its first heartbeat that reaches the run fails it (exit 1, one line), no result published."""
    from fcc_harness import Fcc
    from hil.cli import main
    from hil.io.paths import build_dir

    second = Fcc(build_dir() / "bin" / "fcc", ["--iface", "vcan0"], tmp_path)
    control, shutdown = RigSession.control, RigSession.shutdown

    def control_with_second(rig: RigSession, *a, **kw):  # type: ignore[no-untyped-def]
        if second.proc is None:
            second.start().wait_ready()
        return control(rig, *a, **kw)

    def shutdown_after_its_heartbeat(rig: RigSession, *a, **kw):  # type: ignore[no-untyped-def]
        for _ in range(200):   # at 10 Hz its heartbeat comes: until it is seen (raises)
            got = rig.link.recv_wait(0.1)  # type: ignore[union-attr]
            if got is not None:
                rig.note_frame(*got)
        return shutdown(rig, *a, **kw)

    monkeypatch.setattr(RigSession, "control", control_with_second)
    monkeypatch.setattr(RigSession, "shutdown", shutdown_after_its_heartbeat)
    try:
        (tmp_path / "cdrw.toml").write_text(CDRW_1S)
        rc = main(["run", "cdrw", str(tmp_path / "cdrw.toml"), "--key-file", str(TEST_KEY_FILE),
                   "--out", str(tmp_path / "o"), "--quiet", "--no-plots"])
    finally:
        if second.proc is not None:
            second.proc.terminate()
            second.proc.wait(10)
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    assert rc == 1
    assert len(err) == 1 and "a second fcc is on vcan0" in err[0], err
    assert not (tmp_path / "o").exists()


@pytest.mark.vcan
@pytest.mark.parametrize("sig, status", [(signal.SIGTERM, 143), (signal.SIGHUP, 129)])
def test_sigterm_and_sighup_are_handled_as_sigint(sig, status, tmp_path):
    """Sent once the session's key file exists and the run's staging directory holds the
    recorder's files (the run is under way): a documented status, one line, the partial results
    visible and marked FAILED, no key file, no hidden staging directory left."""
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    env = {**os.environ, "TMPDIR": str(tmp)}
    hil = subprocess.Popen([sys.executable, "-m", "hil.cli", "run", "cdrw", "--out",
                            str(tmp_path / "o"), "--quiet", "--no-plots"], env=env,
                           stderr=subprocess.PIPE, stdout=subprocess.DEVNULL)
    try:
        for _ in range(6000):   # until the run is under way (files, not a time)
            stages = list(tmp_path.glob(".o.partial-*"))
            if list(tmp.glob("hil-key-*")) and stages and any(stages[0].rglob("*")) and \
                    (stages[0] / "fcc.log").exists():
                break
            assert hil.poll() is None, hil.stderr.read().decode()  # type: ignore[union-attr]
            time.sleep(0.01)
        hil.send_signal(sig)
        _, err = hil.communicate(timeout=60)
    finally:
        if hil.poll() is None:
            hil.kill()
    lines = [ln for ln in err.decode().splitlines() if ln.strip()]
    assert hil.returncode == status, lines
    assert len(lines) == 1 and f"terminated by {signal.Signals(sig).name}" in lines[0], lines
    failed = list(tmp_path.glob("o.failed-*"))
    assert len(failed) == 1 and (failed[0] / "FAILED").is_file()
    assert not list(tmp_path.glob(".o.partial-*")) and not (tmp_path / "o").exists()
    assert not list(tmp.glob("hil-key-*"))


@pytest.mark.vcan
@pytest.mark.parametrize("recorder, words", [("candump", r"candump lost \d+ frame\(s\)"),
                                             ("canrec", r"canrec: vcan0: \d+ frames lost")])
def test_frames_the_recorder_loses_fail_the_run(tmp_path, monkeypatch, recorder, words):
    """The recorder (candump -d, canrec) stopped (SIGSTOP) at step 50 with a small socket buffer
    (canrec: a one-page ring) while 2000 frames go on the bus, then continued: the kernel's drop
    counter fails the run, not a table over the steps that are left."""
    from hil.rig.errors import RigError
    from hil.rig.recorder import BusRecorder, Canrec

    monkeypatch.setattr(BusRecorder, "RCVBUF", 1)   # the smallest queue the kernel allows
    monkeypatch.setattr(Canrec, "RING", 4096)       # and the smallest ring
    step = LockstepRunner.step

    def flooded(runner: LockstepRunner, d):  # type: ignore[no-untyped-def]
        if d.k == 50:
            rec = runner.rig.bus_recorder
            os.kill(rec.pid, signal.SIGSTOP)  # type: ignore[union-attr]
            try:
                for i in range(2000):
                    runner.rig.link.send(0x555, i.to_bytes(8, "little"))  # type: ignore[union-attr]
            finally:
                os.kill(rec.pid, signal.SIGCONT)  # type: ignore[union-attr]
        return step(runner, d)

    monkeypatch.setattr(LockstepRunner, "step", flooded)
    with pytest.raises(RigError, match=words):
        fly(tmp_path / "o", scenario(CDRW_1S), key_file=TEST_KEY_FILE, timeout=10.0,
            recorder=recorder)
    assert not (tmp_path / "o" / "summary.json").exists()


@pytest.mark.vcan
def test_replay_sends_only_the_recordings_authenticated_frames(tmp_path, monkeypatch, capsys):
    """A run with a forged reset replays identical (the forged frame is not re-authenticated
    and sent to the fresh fcc); without the run's key, replay refuses in one line (exit 2)."""
    from hil.cli import main
    cdrw_flight(tmp_path / "rec", monkeypatch, forge_at=50)
    assert (tmp_path / "rec" / "session.key").is_file() is False  # --key-file: not copied
    rc = main(["replay", str(tmp_path / "rec")])
    out, err = capsys.readouterr()
    assert rc == 0 and "identical" in out, out + err
    info = json.loads((tmp_path / "rec" / "run_info.json").read_text())
    info["key_file"] = None
    (tmp_path / "rec" / "run_info.json").write_text(json.dumps(info))
    rc = main(["replay", str(tmp_path / "rec")])
    err = capsys.readouterr().err
    assert rc == 2 and "bus key is not kept" in err and err.count("\n") == 1
