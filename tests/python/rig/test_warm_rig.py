"""A warm rig (hil.cli.rig, hil.parallel.keeper/warm/forked): `hil rig up`, commands flown on it
with --rig from the host shell, `hil rig status`, `hil rig down`.

Host side, no vcan needed here: the rig boots its own guest (User-Mode Linux, or a vcanK of its
own on a kernel with vcan), so these tests run from the host shell, not inside
scripts/with-vcan.  Each rig's state lives in a directory of the test's ($HIL_RUNTIME_DIR).

* the requests' token, the forked command's cancellation, the state file's checks: no guest;
* a life cycle: up, up again, status, a run whose deterministic files equal a cold run's
  (scripts/with-vcan hil run), a second client refused (exit 8), a client interrupted (its
  command stops as an interrupted run does: 130) and one killed mid-command (its command
  cancelled, the next one flies), down with no process of the guest left;
* SIGTERM to the keeper and the idle timeout stop the rig as `hil rig down` does.

Bounded: three guests of about 4 s each, and a few 7 s flights.
"""
from __future__ import annotations

import contextlib
import fcntl
import json
import os
import pickle
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from hil.cli import usage
from hil.parallel import forked
from hil.parallel.files import write_request
from hil.parallel.server import Unauthentic, read_request
from hil.parallel.warm import LOCK, STATE, RigBusy, RigNotUp, pid_alive, read_state, state_dir

REPO = Path(__file__).resolve().parents[3]
HIL = str(Path(sys.executable).with_name("hil"))
UML = Path(os.environ.get("WITH_VCAN_UML_DIR") or REPO / ".uml")
needs_rig = pytest.mark.skipif(not (UML / "linux.uml").exists() and not Path("/sys/class/net/vcan0").exists(),
                               reason="needs User-Mode Linux (scripts/setup) or a kernel with vcan")
#: the files of a run directory that do not depend on the session (its key, trip, timing)
DETERMINISTIC = (".hil-run.json", "summary.json", "cdrw.csv", "faults.log")
#: a bound on what the tests wait for (not a synchronisation: each wait is for a condition)
WAIT_S = 120.0


def hil(*args: str, env: dict[str, str], **kw: object) -> subprocess.CompletedProcess[str]:
    return subprocess.run([HIL, *args], env=env, capture_output=True, text=True, timeout=600, cwd=REPO, **kw)


def wait_for(cond, what: str) -> None:
    deadline = time.monotonic() + WAIT_S
    while not cond():
        assert time.monotonic() < deadline, f"not within {WAIT_S:g} s: {what}"
        time.sleep(0.05)


def guest_processes(guest: int) -> list[int]:
    """The processes of the rig process `guest` (scripts/with-vcan) still there: its process
    group, and the User-Mode Linux kernel's processes, which with-vcan names umid=wv<its pid>."""
    pids = []
    for d in Path("/proc").glob("[0-9]*"):
        try:
            fields = (d / "stat").read_text().rsplit(")", 1)[1].split()
            cmdline = (d / "cmdline").read_bytes().split(b"\0")
        except OSError:
            continue
        if fields[0] != "Z" and (int(fields[2]) == guest or f"umid=wv{guest}".encode() in cmdline):
            pids.append(int(d.name))
    return pids


@pytest.fixture
def runtime(tmp_path, monkeypatch) -> dict[str, str]:
    d = tmp_path / "rt"
    monkeypatch.setenv("HIL_RUNTIME_DIR", str(d))
    return {**os.environ, "HIL_RUNTIME_DIR": str(d)}


# ---- no guest -----------------------------------------------------------------------------
def test_a_request_without_the_token_is_never_unpickled(tmp_path):
    req = tmp_path / "r.pkl"
    write_request(req, "secret", len, ("abc",))
    assert read_request(req, "secret") == (len, ("abc",))
    # a forged request: its pickle would run os.system if it were loaded
    req.write_bytes(b"guess\n" + pickle.dumps((os.system, ("touch " + str(tmp_path / "owned"),))))
    with pytest.raises(Unauthentic):
        read_request(req, "secret")
    assert not (tmp_path / "owned").exists()


def test_the_state_directory_is_the_users_own(runtime):
    d = state_dir()
    assert d.stat().st_mode & 0o777 == 0o700
    os.chmod(d, 0o755)
    assert state_dir().stat().st_mode & 0o777 == 0o700


def test_a_state_file_whose_keeper_is_gone_is_removed(runtime):
    d = state_dir()
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    (d / STATE).write_text(json.dumps({"pid": dead.pid, "dir": "/nonexistent", "token": "t", "target": "host",
                                       "iface": "vcan0", "started": 0.0, "idle_timeout": 1.0, "guest": dead.pid}))
    assert read_state(d) is None and not (d / STATE).exists()


def test_the_rigs_statuses_are_the_tables():
    assert (RigBusy.exit_status, RigNotUp.exit_status) == (usage.EXIT_RIG_BUSY, usage.EXIT_USAGE)


def test_rig_option_with_no_rig_up_is_one_line(runtime):
    r = hil("run", "cdrw", "--rig", "--no-plots", env=runtime)
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr.strip().splitlines() == ["hil: --rig: no rig is up (start one with `hil rig up`)"]
    r = hil("rig", "status", env=runtime)
    assert r.returncode == 1 and r.stdout == "rig: down\n"
    r = hil("campaign", "cdrw", "--rig", "--workers", "2", env=runtime)
    assert r.returncode == 2 and r.stderr.startswith("hil: --rig flies in the warm rig's one guest")


def _sleeps(seconds: float) -> int:
    print("started", flush=True)
    time.sleep(seconds)
    return 5


def test_a_forked_command_runs_apart_and_a_cancelled_one_stops(tmp_path):
    """forked.command on this host: the child's status and output; cancelled (as the keeper
    does for a dead client) it gets SIGTERM: 128 + 15."""
    assert forked.command(str(tmp_path), "a", os.getpid(), _sleeps, (0.0,), str(tmp_path), {"X": "1"}) == 5
    out, _ = forked.io_paths(tmp_path, "a")
    assert out.read_text() == "started\n" and forked.runs(tmp_path) == 1 and forked.running(tmp_path) is None
    forked.cancel(tmp_path, "b")              # written before: the command stops at its first look
    assert forked.command(str(tmp_path), "b", os.getpid(), _sleeps, (60.0,), str(tmp_path), {}) == 128 + 15
    forked.cancel(tmp_path, "other")          # another request's cancellation is not this one's
    assert forked.command(str(tmp_path), "c", os.getpid(), _sleeps, (0.0,), str(tmp_path), {}) == 5
    assert forked.runs(tmp_path) == 3


def _stops_then_awaits(flag: str) -> int:
    """A command whose device stops, then waits (wait_for) for the loop to have entered the next
    spare's context: 7 when it did while the command still ran, 1 otherwise (the child's status
    for what it raised)."""
    forked.device_stopped()
    wait_for(Path(flag).exists, "the loop entering the next spare's context")
    return 7


def test_the_next_spares_context_is_entered_when_a_commands_device_stops(tmp_path):
    """A warm rig's next command listens for another fcc from the moment the previous one's
    fcc stopped (hil.rig.session.on_device_stopped -> forked.device_stopped): the loop enters
    the next spare's context (refill's `inherit`) then, while the command still runs; the
    context is left once that spare is forked."""
    flag, entered = tmp_path / "entered", []

    @contextlib.contextmanager
    def inherit() -> Iterator[None]:
        entered.append(True)
        flag.write_text("in\n")
        try:
            yield
        finally:
            flag.unlink()

    try:
        forked.refill(inherit)
        assert forked.command(str(tmp_path), "s", os.getpid(), _stops_then_awaits, (str(flag),),
                              str(tmp_path), {}) == 7
        assert flag.exists()          # entered for the next spare, not left yet
        forked.after_answer()         # the next spare forked inside it: left
        assert not flag.exists() and len(entered) >= 2
    finally:
        forked.refill(contextlib.nullcontext)


# ---- a rig ----------------------------------------------------------------------------------
@pytest.fixture
def rig(runtime) -> Iterator[dict[str, str]]:
    """A rig that is up; afterwards down, with none of its guest's processes left."""
    r = hil("rig", "up", "--idle-timeout", "600", env=runtime)
    assert r.returncode == 0, r.stderr
    state = read_state(state_dir())
    assert state is not None and r.stdout.startswith(f"rig up: pid {state.pid}, target host")
    try:
        yield runtime
    finally:
        hil("rig", "down", env=runtime)
        assert not guest_processes(state.guest)


@needs_rig
def test_life_cycle(rig, tmp_path):
    env = rig
    state = read_state(state_dir())
    assert state is not None
    assert oct((state_dir() / STATE).stat().st_mode & 0o777) == "0o600"
    r = hil("rig", "up", env=env)
    assert r.returncode == 0 and r.stdout.startswith(f"rig already up: pid {state.pid}")
    r = hil("rig", "status", env=env)
    assert r.returncode == 0 and r.stdout.splitlines()[0].startswith(f"rig: up, pid {state.pid}, target host")
    assert "commands run: 0" in r.stdout and "client: none" in r.stdout

    # a run on the rig = a cold run in a guest of its own, file for file where deterministic
    warm, cold = tmp_path / "warm", tmp_path / "cold"
    r = hil("run", "cdrw", "--rig", "--no-plots", "--quiet", "--out", str(warm), env=env)
    assert r.returncode == 0, r.stderr
    assert f"results in {warm}/" in r.stdout and "CDRW Table 4" in r.stdout
    c = subprocess.run([str(REPO / "scripts" / "with-vcan"), HIL, "run", "cdrw", "--no-plots", "--quiet",
                        "--out", str(cold)], env=env, capture_output=True, text=True, timeout=600, cwd=REPO)
    assert c.returncode == 0, c.stderr
    assert r.stdout.replace(str(warm), "OUT") == c.stdout.replace(str(cold), "OUT")
    for name in DETERMINISTIC:
        assert (warm / name).read_bytes() == (cold / name).read_bytes(), name

    # the rig's usage errors are the command's own, one line
    r = hil("run", "cdrw", "--rig", "--target", "qemu-m4f", env=env)
    assert r.returncode == 2 and "the rig is up for --target host, not qemu-m4f" in r.stderr

    # a second client at a time is refused (this test holds the client lock)
    with open(state_dir() / LOCK, "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        r = hil("run", "cdrw", "--rig", "--no-plots", "--out", str(tmp_path / "second"), env=env)
    assert r.returncode == 8 and r.stdout == "" and len(r.stderr.strip().splitlines()) == 1
    assert "flying another client's command" in r.stderr and not (tmp_path / "second").exists()

    # Ctrl-C on a client: its command stops as an interrupted cold run does, with its status
    stopped = subprocess.Popen([HIL, "campaign", "cdrw", "--runs", "50", "--rig", "--no-plots", "--quiet",
                                "--out", str(tmp_path / "stopped")], env=env, cwd=REPO,
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    wait_for(lambda: (forked.running(state.root) or (0, ""))[0] == stopped.pid, "the campaign runs on the rig")
    wait_for(lambda: any(tmp_path.glob(".stopped.partial-*/*")), "the campaign writes its files")
    stopped.send_signal(signal.SIGINT)
    _, err = stopped.communicate(timeout=WAIT_S)
    assert stopped.returncode == usage.EXIT_SIGINT and err.startswith("hil: interrupted"), err
    assert not (tmp_path / "stopped").exists() and list(tmp_path.glob("stopped.failed-*"))

    # a client killed mid-command: its command is cancelled (partial results kept as a
    # cold run's interrupted ones are), and the next command flies
    doomed = subprocess.Popen([HIL, "campaign", "cdrw", "--runs", "50", "--rig", "--no-plots", "--quiet",
                               "--out", str(tmp_path / "doomed")], env=env, cwd=REPO,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wait_for(lambda: (forked.running(state.root) or (0, ""))[0] == doomed.pid, "the campaign runs on the rig")
    assert f"client: pid {doomed.pid}" in hil("rig", "status", env=env).stdout
    wait_for(lambda: any(tmp_path.glob(".doomed.partial-*/*")), "the campaign writes its files")
    doomed.kill()
    doomed.wait()
    wait_for(lambda: forked.running(state.root) is None, "the dead client's command stops")
    assert "its command" in (state_dir() / "keeper.log").read_text()
    assert not (tmp_path / "doomed").exists() and list(tmp_path.glob("doomed.failed-*"))
    r = hil("run", "cdrw", "--rig", "--no-plots", "--quiet", "--out", str(tmp_path / "after"), env=env)
    assert r.returncode == 0, r.stderr
    for name in DETERMINISTIC:
        assert (tmp_path / "after" / name).read_bytes() == (cold / name).read_bytes(), name
    assert "commands run: 4" in hil("rig", "status", env=env).stdout

    r = hil("rig", "down", env=env)
    assert r.returncode == 0 and r.stdout == f"rig: down (pid {state.pid} stopped)\n"
    assert not guest_processes(state.guest) and not (state_dir() / STATE).exists()
    assert hil("rig", "status", env=env).returncode == 1
    assert hil("rig", "down", env=env).stdout == "rig: down (none was up)\n"


@needs_rig
@pytest.mark.parametrize("how", ["SIGTERM", "idle"])
def test_the_rig_stops_by_itself_leaving_nothing(runtime, how):
    r = hil("rig", "up", "--idle-timeout", "1" if how == "idle" else "600", env=runtime)
    assert r.returncode == 0, r.stderr
    state = read_state(state_dir())
    assert state is not None
    if how == "SIGTERM":
        os.kill(state.pid, signal.SIGTERM)
    wait_for(lambda: not pid_alive(state.pid), "the keeper stops")
    assert read_state(state_dir()) is None and not guest_processes(state.guest)
    log = (state_dir() / "keeper.log").read_text()
    assert ("stopped by SIGTERM" if how == "SIGTERM" else "idle for 1 s") in log
