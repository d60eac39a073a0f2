"""A warm rig's command, inside its guest: `hil run|verify|campaign ... --rig` run by a child
forked from the rig's loop (hil.parallel.server), whose modules are imported already, so the
command pays neither the guest's boot nor Python's imports -- and, a process of its own,
leaves nothing in the loop that the next command could see.

The child works in the client's directory with the client's environment (the guest's own
WITH_VCAN_UML kept: the command knows it flies in a guest); its stdout and stderr go to
files the client copies to its own as they grow.  While it runs, DIR/running names the
client's pid and the request; the rig's keeper (hil.parallel.keeper) writes that name to
DIR/cancel when the client died (the child then gets SIGTERM), and the client itself with the
signal it got (SIGINT, SIGTERM, SIGHUP) when it is interrupted: the child ends as an
interrupted `hil` run does (fcc and the recorder stopped, the partial results kept marked
FAILED, 128 + the signal).  DIR/runs counts the commands run.

Imported by the client (a small module: its requests name these functions) and by the loop;
hil.parallel.warmup readies the loop before its first command.
"""
from __future__ import annotations

import os
import pickle
import select
import signal
import socket
import sys
import time
from collections.abc import Callable
from contextlib import AbstractContextManager, ExitStack, nullcontext
from pathlib import Path
from typing import Any

from hil.parallel.files import write_atomic

RUNNING, CANCEL, RUNS = "running", "cancel", "runs"
#: set in the child: the command runs in the rig (its --rig is already served)
IN_RIG = "HIL_IN_RIG"
#: what the child keeps of the guest's environment
GUEST_ENV = ("WITH_VCAN_UML", "PYTHONUNBUFFERED")
#: how often a running command's cancellation is looked for
CANCEL_POLL_S = 0.1
#: after SIGTERM, how long the child has to stop its session before SIGKILL
STOP_GRACE_S = 30.0


def io_paths(root: Path, name: str) -> tuple[Path, Path]:
    """Where the child of request `name` writes its stdout and stderr."""
    return root / "io" / f"{name}.out", root / "io" / f"{name}.err"


def _child(fn: Callable[..., int], args: tuple[Any, ...], cwd: str, env: dict[str, str],
           out: Path, err: Path) -> int:
    """In the forked child: fn(*args) as a command runs, its output flushed: its exit status
    (whatever it raised: the child never returns into the loop)."""
    code = 1
    try:
        keep = {k: os.environ[k] for k in GUEST_ENV if k in os.environ}
        os.environ.clear()
        os.environ.update({**env, **keep, IN_RIG: "1"})
        os.chdir(cwd)
        for fd, path, name in ((1, out, "stdout"), (2, err, "stderr")):
            f = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
            os.dup2(f, fd)
            os.close(f)
            setattr(sys, name, open(fd, "w", encoding="utf-8", errors="backslashreplace",  # noqa: SIM115
                                    closefd=False, buffering=1))
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        code = fn(*args)
    except SystemExit as e:
        code = e.code if isinstance(e.code, int) else 1
    except BaseException as e:  # noqa: BLE001 - the child never returns into the loop
        print(f"hil: {type(e).__name__}: {e}", file=sys.stderr)
    finally:
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except Exception:  # noqa: BLE001, S110 - a closed stream: nothing more to say
                pass
    return code if isinstance(code, int) else 1


def _wait(pid: int, said: socket.socket, root: Path, name: str) -> int:
    """The child's exit status, as it says it (`said`: the loop answers while the child's
    exit frees its memory, 10-15 ms in the guest) or as it ends (128 + signal when killed);
    SIGTERM to it when the request is cancelled, SIGKILL when it has not stopped STOP_GRACE_S
    later.  Woken by either, looking for a cancellation every CANCEL_POLL_S meanwhile."""
    cancelled, term_at, heard = root / CANCEL, None, b""
    pidfd = os.pidfd_open(pid)
    watched: list[Any] = [pidfd, said]
    try:
        while True:
            if said in select.select(watched, [], [], CANCEL_POLL_S)[0]:
                got = said.recv(64)
                if not got:
                    watched.remove(said)   # it ended without saying: its end says it
                *lines, heard = (heard + got).split(b"\n")
                for line in lines:
                    if line == STOPPED:    # (device_stopped)
                        _enter_inherit()
                        continue
                    _exiting.append(pid)   # (reaped by a later refill once it has ended)
                    return int(line)
            done, waited = os.waitpid(pid, os.WNOHANG)
            if done:
                return os.waitstatus_to_exitcode(waited) if os.WIFEXITED(waited) else 128 + os.WTERMSIG(waited)
            sig = _cancelled(cancelled, name) if term_at is None else None
            if sig is not None:
                os.kill(pid, sig)
                term_at = time.monotonic()
            elif term_at is not None and time.monotonic() - term_at > STOP_GRACE_S:
                os.kill(pid, signal.SIGKILL)
    finally:
        os.close(pidfd)


def cancel(root: Path, name: str, sig: int = signal.SIGTERM) -> None:
    """Stop request `name`'s command with `sig` (it is run to its end when it has ended)."""
    write_atomic(root / CANCEL, f"{name} {int(sig)}\n".encode())


def _cancelled(path: Path, name: str) -> int | None:
    """The signal request `name` is cancelled with, or None."""
    try:
        what, sig = path.read_text().split()
        return int(sig) if what == name else None
    except (OSError, ValueError):
        return None


#: a child forked ahead of its command, waiting for it on a socket: (its pid, the loop's end;
#: the command comes on it, and the child's exit status goes back).  Forking the loop costs
#: about 0.1 s in the guest (its page tables copied by the UML kernel): paid while the loop is
#: idle, after an answer (the loop calls after_answer), not while a client waits.
_spare: tuple[int, socket.socket] | None = None
_keep_spare = False
#: what the loop forks each spare inside of, and what each spare does while it waits (refill's)
_inherit: Callable[[], AbstractContextManager[object]] = nullcontext
_ready: Callable[[int], object] | None = None
#: children that said their status and are ending
_exiting: list[int] = []
#: in the loop: the context the next spare is forked inside of, entered already (_enter_inherit)
_entered: ExitStack | None = None
#: in a command's child: its socket to the loop (device_stopped, its exit status)
_to_loop: socket.socket | None = None
STOPPED = b"stopped"


def device_stopped() -> None:
    """In a command's child: its device under test has stopped (hil.rig.session says so: a
    warm rig hooks this there, hil.parallel.warmup).  The loop enters the next spare's context
    now (a warm rig's: the next command's listen for another fcc starts), not once the command
    has evaluated its flight; each stop enters it afresh (a campaign's next session starts fcc
    again)."""
    if _to_loop is not None:
        try:
            _to_loop.sendall(STOPPED + b"\n")
        except OSError:   # the loop is gone (the rig stops): nobody to tell
            pass


def _enter_inherit() -> None:
    """In the loop: the next spare's context (refill's `inherit`) entered now, anew."""
    global _entered  # noqa: PLW0603 - the loop's one context for its next spare
    if _entered is not None:
        _entered.close()
    _entered = ExitStack()
    _entered.enter_context(_inherit())


def refill(inherit: Callable[[], AbstractContextManager[object]] | None = None,
           ready: Callable[[int], object] | None = None) -> None:
    """Fork the next command's child now, unless there is one (and keep one from now on).
    Once given, `inherit` makes the context each spare is forked inside of (what it opens, the
    spare inherits and the loop lets go of after the fork), and `ready(fd)` is what each spare
    does while it waits for its command, which comes on fd (a warm rig's: its command's socket
    on the bus, its memory made its own: hil.parallel.warmup)."""
    global _spare, _keep_spare, _inherit, _ready, _entered, _to_loop  # noqa: PLW0603 - the loop's one spare child
    _keep_spare = True
    _inherit, _ready = inherit or _inherit, ready or _ready
    _exiting[:] = [pid for pid in _exiting if os.waitpid(pid, os.WNOHANG) == (0, 0)]   # the ended reaped
    if _spare is not None:
        return
    for stream in (sys.stdout, sys.stderr):
        stream.flush()
    ours, theirs = socket.socketpair()
    if _entered is None:
        _enter_inherit()
    assert _entered is not None
    entered, _entered = _entered, None
    with entered:
        pid = os.fork()
        if pid == 0:             # (never back into the loop, whatever happens)
            code = 1
            try:
                ours.close()
                _get_ready(theirs.fileno())
                job = _received(theirs)
                _to_loop = theirs
                code = _child(*pickle.loads(job)) if job else 0   # 0: the loop ended first
                if job:
                    theirs.sendall(b"%d\n" % code)
            finally:
                os._exit(code)
    theirs.close()
    _spare = pid, ours


def _received(sock: socket.socket) -> bytes:
    """Everything sent on sock until the sender's end of sending."""
    parts = []
    while part := sock.recv(1 << 16):
        parts.append(part)
    return b"".join(parts)


def _get_ready(fd: int) -> None:
    """In a spare: ready(fd), or why it failed said (the command does without it)."""
    if _ready is None:
        return
    try:
        _ready(fd)
    except Exception as e:  # noqa: BLE001 - what it readies, the command does itself
        print(f"hil.parallel.forked: a spare not readied ({type(e).__name__}: {e})", file=sys.stderr, flush=True)


def after_answer() -> None:
    """The loop has answered a request: the next command's child forked, if one is kept."""
    if _keep_spare:
        refill()


def _start(job: tuple[Any, ...]) -> tuple[int, socket.socket]:
    """The child that runs `job` (_child's arguments): the spare, else a new one (its pid,
    the socket its status comes on)."""
    global _spare  # noqa: PLW0603 - the loop's one spare child
    refill()
    assert _spare is not None
    pid, sock = _spare
    _spare = None
    try:
        sock.sendall(pickle.dumps(job, protocol=pickle.HIGHEST_PROTOCOL))
        sock.shutdown(socket.SHUT_WR)
    except (BrokenPipeError, ConnectionResetError):  # the spare died: a new one
        sock.close()
        os.waitpid(pid, 0)
        return _start(job)
    return pid, sock


def command(root: str, name: str, client_pid: int, fn: Callable[..., int], args: tuple[Any, ...],
            cwd: str, env: dict[str, str]) -> int:
    """fn(*args) in a forked child (above), as request `name` of the client `client_pid`:
    its exit status."""
    d = Path(root)
    (d / "io").mkdir(exist_ok=True)
    write_atomic(d / RUNNING, f"{client_pid} {name}\n".encode())
    try:
        pid, said = _start((fn, args, cwd, env, *io_paths(d, name)))
        with said:
            return _wait(pid, said, d, name)
    finally:
        (d / RUNNING).unlink(missing_ok=True)
        write_atomic(d / RUNS, f"{runs(d) + 1}\n".encode())


def runs(root: Path) -> int:
    """How many commands the rig in `root` has run."""
    try:
        return int((root / RUNS).read_text())
    except (OSError, ValueError):
        return 0


def running(root: Path) -> tuple[int, str] | None:
    """(client pid, request) of the command running in the rig, or None."""
    try:
        pid, name = (root / RUNNING).read_text().split()
        return int(pid), name
    except (OSError, ValueError):
        return None
