"""Child processes of the rig: started in their own process group with a parent-death
signal (Linux PR_SET_PDEATHSIG = SIGKILL), so that ``kill -9`` of hil takes fcc, the recorder and
cangen with it; /proc/PID/stat; the last line a program wrote.
"""
from __future__ import annotations

import ctypes
import logging
import os
import shlex
import shutil
import signal
import subprocess
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from hil.util.errors import HilError

PR_SET_PDEATHSIG = 1
_log = logging.getLogger(__name__)


def _die_with_parent(parent: int) -> Callable[[], None] | None:
    """preexec_fn for a child that must not outlive this process (Linux; elsewhere None)."""
    if not sys.platform.startswith("linux"):
        return None
    libc = ctypes.CDLL(None, use_errno=True)

    def preexec() -> None:
        libc.prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
        if os.getppid() != parent:  # the parent died before prctl: nobody would kill us
            os._exit(1)
    return preexec


#: util-linux's setpriv sets the parent-death signal and execs the command
SETPRIV = shutil.which("setpriv")


def spawn(cmd: Sequence[str], **kw: Any) -> subprocess.Popen:
    """subprocess.Popen for a rig child: own process group, killed when the rig dies.

    Through `setpriv --pdeathsig KILL` where it exists: a preexec_fn makes Python fork
    instead of vfork, and in the UML guest forking the rig costs ~105 ms, vfork and the one
    exec more ~55 ms (measured, 5 starts each)."""
    _log.info("starting %s", shlex.join(map(str, cmd)))
    if SETPRIV is not None and sys.platform.startswith("linux"):
        return subprocess.Popen([SETPRIV, "--pdeathsig", "KILL", "--", *cmd], process_group=0, **kw)
    return subprocess.Popen(list(cmd), process_group=0, preexec_fn=_die_with_parent(os.getpid()),
                            **kw)


def run_as_batch(pids: Sequence[int], batch: bool = True) -> bool:
    """Put processes (0: this one) in the SCHED_BATCH policy, or back in SCHED_OTHER; False
    where the system refuses (or has no such policy).

    A batch process woken by a frame does not preempt the running one (Linux's wake-up
    preemption skips SCHED_BATCH).  In lockstep, with the simulator, fcc and the recorder all
    batch, each runs until it waits: the simulator's sendmmsg of a step's frames ends before fcc
    runs, and fcc reads the whole step at one wake-up instead of one per frame.  Nothing else
    changes: a batch process still gets its fair share of the CPU."""
    if not hasattr(os, "SCHED_BATCH"):
        return False
    policy = os.SCHED_BATCH if batch else os.SCHED_OTHER
    try:
        for pid in pids:
            os.sched_setscheduler(pid, policy, os.sched_param(0))
    except OSError:
        return False
    return True


class ProcessError(HilError, RuntimeError):
    """A program could not be started or stopped (one line)."""


def proc_stat(pid: int) -> list[bytes]:
    """The fields of /proc/PID/stat after the command name (state first; proc(5) numbers
    them from 3): the name, in parentheses, may itself hold spaces and parentheses."""
    with open(f"/proc/{pid}/stat", "rb") as fh:
        return fh.read().rsplit(b")", 1)[1].split()


def last_line(path: Path) -> str:
    """The last non-blank line of a program's output file ('' when there is none)."""
    try:
        lines = [ln.strip() for ln in path.read_text(errors="replace").splitlines() if ln.strip()]
    except OSError:
        return ""
    return lines[-1] if lines else ""
