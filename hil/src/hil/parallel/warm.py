"""A warm rig from the host shell: where it is (its state file) and a command flown on it.

`hil rig up` starts the rig's keeper (hil.parallel.keeper: a guest with the flight loop of
hil.parallel.server, its modules imported); the keeper writes the state file once the rig is
ready.  The state lives in a directory of its own user's, readable by nobody else
($HIL_RUNTIME_DIR, else $XDG_RUNTIME_DIR/hil, else ~/.cache/hil; 0700), as rig.json (0600):
the keeper's pid, the rig's directory (its requests and answers, hil.parallel.files), the
token every request carries, the target, the interface, when it started and its idle timeout.

A client (`hil run|verify|campaign ... --rig`) holds DIR/client.lock for its command (a second
client is refused: RigBusy; the lock goes with the client's process, however it ends) and
asks the rig to run the command (hil.parallel.forked), copying its output as it grows.
"""
from __future__ import annotations

import codecs
import dataclasses
import fcntl
import json
import os
import signal
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from hil.parallel import forked
from hil.parallel.files import await_answer, write_request
from hil.rig.errors import RigError
from hil.util.errors import EXIT_RIG_BUSY, EXIT_USAGE

STATE = "rig.json"
LOCK = "client.lock"
#: how long a client waits for its cancelled command to stop (its session's own stop)
CANCEL_WAIT_S = forked.STOP_GRACE_S + 10.0
#: how often a client looks for its command's answer and output (on the host, while a user
#: waits: a fifth of the loop's poll, hil.parallel.files.POLL_S, which runs in the guest)
CLIENT_POLL_S = 0.002


class RigNotUp(RigError):
    """No rig is up (`hil rig up` starts one)."""

    exit_status = EXIT_USAGE


class RigBusy(RigError):
    """The rig serves another client."""

    exit_status = EXIT_RIG_BUSY


def state_dir() -> Path:
    """This user's directory of rig state, made owner-only; refused when another user owns it."""
    given = os.environ.get("HIL_RUNTIME_DIR")
    xdg = os.environ.get("XDG_RUNTIME_DIR")
    d = Path(given) if given else Path(xdg) / "hil" if xdg else Path.home() / ".cache" / "hil"
    d.mkdir(parents=True, exist_ok=True, mode=0o700)
    st = d.stat()
    if st.st_uid != os.getuid():
        raise RigError(f"{d}: owned by another user (uid {st.st_uid}): not a rig state directory of ours")
    if st.st_mode & 0o077:
        os.chmod(d, 0o700)
    return d


@dataclasses.dataclass(frozen=True)
class State:
    """A rig that is up, as its keeper wrote rig.json."""

    pid: int
    dir: str
    token: str
    target: str
    iface: str
    started: float
    idle_timeout: float
    guest: int          # the rig process (its process group: the guest and everything in it)

    @property
    def root(self) -> Path:
        return Path(self.dir)

    def alive(self) -> bool:
        return pid_alive(self.pid)

    def write(self, path: Path) -> None:
        tmp = path.with_name(f".{path.name}.tmp")
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
        with os.fdopen(fd, "w") as f:
            json.dump(dataclasses.asdict(self), f)
        os.replace(tmp, path)


def pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def read_state(d: Path) -> State | None:
    """The rig that is up (None: none; a state file whose keeper is gone is removed)."""
    try:
        state = State(**json.loads((d / STATE).read_text()))
    except (OSError, ValueError, TypeError):
        return None
    if not state.alive():
        (d / STATE).unlink(missing_ok=True)
        return None
    return state


def client_attached(state: State) -> int | None:
    """The pid of the client whose command the rig runs, or None."""
    now = forked.running(state.root)
    return now[0] if now is not None and pid_alive(now[0]) else None


class _Copier:
    """The command's stdout and stderr copied to ours (sys.stdout, sys.stderr) as they grow."""

    def __init__(self, paths: tuple[Path, Path]) -> None:
        self.files = list(zip(paths, ("stdout", "stderr")))
        self.pos = [0, 0]
        self.decoders = [codecs.getincrementaldecoder("utf-8")("replace") for _ in paths]

    def __call__(self) -> None:
        for k, (path, stream) in enumerate(self.files):
            try:
                with open(path, "rb") as f:
                    f.seek(self.pos[k])
                    data = f.read()
            except OSError:
                continue
            if data:
                self.pos[k] += len(data)
                sink = getattr(sys, stream)
                sink.write(self.decoders[k].decode(data))
                sink.flush()


def fly(fn: Callable[..., int], args: tuple[Any, ...], target: str) -> int:
    """fn(*args) on the rig that is up, as a command run there (hil.parallel.forked): its exit
    status.  RigNotUp, RigBusy, or RigError when the rig is for another target or stops."""
    d = state_dir()
    state = read_state(d)
    if state is None:
        raise RigNotUp("--rig: no rig is up (start one with `hil rig up`)")
    if target != state.target:
        raise RigNotUp(f"--rig: the rig is up for --target {state.target}, not {target} "
                       f"(`hil rig down`, then `hil rig up --target {target}`)")
    with open(d / LOCK, "a") as lock:
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise RigBusy(f"--rig: the rig (pid {state.pid}) is flying another client's command; "
                          "try again when it is done") from None
        return _command(state, fn, args)


def _command(state: State, fn: Callable[..., int], args: tuple[Any, ...]) -> int:
    root = state.root
    name = f"{time.time_ns():020d}-{os.getpid()}"
    copy = _Copier(forked.io_paths(root, name))

    def check() -> None:
        copy()
        if not state.alive():
            raise RigError(f"the rig (pid {state.pid}) stopped during the command")

    write_request(root / "req" / f"{name}.pkl", state.token, forked.command,
                  (str(root), name, os.getpid(), fn, args, os.getcwd(), dict(os.environ)))
    res = root / "res" / f"{name}.pkl"
    try:
        try:
            status, _ = await_answer(res, check, CLIENT_POLL_S)
        except KeyboardInterrupt as e:   # (and hil.cli's Terminated): the command stops as an interrupted run does
            forked.cancel(root, name, getattr(e, "signum", signal.SIGINT))
            deadline = time.monotonic() + CANCEL_WAIT_S

            def check_cancelled() -> None:
                check()
                if time.monotonic() > deadline:
                    raise RigError(f"the rig did not stop the command within {CANCEL_WAIT_S:g} s")

            status, _ = await_answer(res, check_cancelled, CLIENT_POLL_S)
        copy()
        return int(status)
    finally:
        for p in forked.io_paths(root, name):
            p.unlink(missing_ok=True)
