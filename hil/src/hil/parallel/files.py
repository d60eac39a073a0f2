"""The files between the host side of a worker's rig (hil.parallel.guest) and the loop inside
it (hil.parallel.server), in a directory both see:

    DIR/ready        written once the loop runs
    DIR/token        the rig's secret (owner-only), written by the host before the loop starts
    DIR/req/N.pkl    a request: the token's line, then pickled (function, args); taken and
                     removed by the loop, which answers one without the token with an error
                     and never unpickles it
    DIR/res/N.pkl    its answer: pickled ("ok", value, seconds) or ("error", exception, seconds)
    DIR/lease        touched by the host while it wants the rig; the loop ends when it has not
                     changed for LEASE_S (the host process was killed) or when DIR/stop appears

Files are written under a temporary name and renamed, so a reader never sees half of one.
Light to import (a warm rig's client imports it with every `hil` command): the token is made
by the host side (hil.parallel.guest) and checked by the loop.
Also here: what a failed rig leaves to say why (last_lines of a log, exit_cause of a process).
"""
from __future__ import annotations

import os
import pickle
import signal
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

LEASE_S = 20.0
POLL_S = 0.01
#: how many of a failed process's last lines a failure keeps, and how much of its log is read
LAST_LINES = 10
TAIL_BYTES = 8192


def write_atomic(path: Path, data: bytes) -> None:
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_bytes(data)
    os.replace(tmp, path)


def write_request(path: Path, token: str, fn: Any, args: tuple[Any, ...]) -> None:
    """A request for the loop: fn(*args), under the rig's token (the loop reads it:
    hil.parallel.server.read_request)."""
    write_atomic(path, token.encode() + b"\n" + pickle.dumps((fn, args), protocol=pickle.HIGHEST_PROTOCOL))


def await_answer(res: Path, check: Callable[[], None], poll_s: float = POLL_S) -> tuple[Any, float]:
    """The answer in `res` once the loop has written it: (fn's value, seconds it took in the
    rig), or what fn raised; check() is called at each poll (every poll_s) until then and
    raises when the rig is down or the wait is over."""
    while not res.exists():
        check()
        time.sleep(poll_s)
    status, value, seconds = pickle.loads(res.read_bytes())
    res.unlink()
    if status != "ok":
        raise value
    return value, seconds


def last_lines(path: Path, n: int = LAST_LINES) -> list[str]:
    """The last n non-blank lines of a log (its last TAIL_BYTES only; [] when unreadable)."""
    try:
        with open(path, "rb") as f:
            f.seek(max(0, f.seek(0, os.SEEK_END) - TAIL_BYTES))
            tail = f.read(TAIL_BYTES)
    except OSError:
        return []
    lines = [ln.strip() for ln in tail.decode(errors="replace").splitlines() if ln.strip()]
    return lines[-n:]


def exit_cause(returncode: int | None) -> dict[str, Any]:
    """A process's end as a failure records it: {"status": N} or {"signal": "SIGKILL"}
    (Popen's negative return code), {"status": None} while it runs."""
    if returncode is None or returncode >= 0:
        return {"status": returncode, "signal": None}
    try:
        name = signal.Signals(-returncode).name
    except ValueError:
        name = f"signal {-returncode}"
    return {"status": None, "signal": name}
