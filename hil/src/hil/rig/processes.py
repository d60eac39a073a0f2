"""The two programs a run starts beside the simulator: the firmware and the bus recorder.

``FccProcess`` starts ``fcc`` with the run's flags, its stdout and stderr going to
``fcc.log`` in the run directory (that file keeps the firmware's event lines and its final
counter block).  A ``BusRecorder`` records the whole bus in the candump log format into
``bus.log``: ``Candump`` (``candump -l``) or ``Canrec`` (firmware/tools/canrec, the same lines,
frames read in batches), chosen per session (``RECORDERS``).
Both are stopped politely (shutdown frame / SIGINT), then firmly; neither outlives the run,
not even a killed rig: every child runs in its own process group (a Ctrl-C on the terminal
reaches the rig, which stops them in order) with a parent-death signal (Linux
PR_SET_PDEATHSIG = SIGKILL), so ``kill -9`` of hil takes fcc, the recorder and cangen with it.
"""
from __future__ import annotations

import ctypes
import os
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

PR_SET_PDEATHSIG = 1


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
    if SETPRIV is not None and sys.platform.startswith("linux"):
        return subprocess.Popen([SETPRIV, "--pdeathsig", "KILL", "--", *cmd], process_group=0, **kw)
    return subprocess.Popen(list(cmd), process_group=0, preexec_fn=_die_with_parent(os.getpid()),
                            **kw)


class ProcessError(RuntimeError):
    """A program could not be started or stopped (one line)."""


def proc_stat(pid: int) -> list[bytes]:
    """The fields of /proc/PID/stat after the command name (state first; proc(5) numbers
    them from 3): the name, in parentheses, may itself hold spaces and parentheses."""
    with open(f"/proc/{pid}/stat", "rb") as fh:
        return fh.read().rsplit(b")", 1)[1].split()


def _last_line(path: Path) -> str:
    try:
        lines = [ln.strip() for ln in path.read_text(errors="replace").splitlines() if ln.strip()]
    except OSError:
        return ""
    return lines[-1] if lines else ""


class FccProcess:
    """The firmware under test, as a child process."""

    def __init__(self, binary: Path, args: Sequence[str], log_path: Path) -> None:
        self.cmd = [str(binary), *args]
        self.log_path = log_path
        self._log = open(log_path, "wb")  # noqa: SIM115 - closed in stop()
        try:
            self.proc = spawn(self.cmd, stdin=subprocess.DEVNULL, stdout=self._log,
                              stderr=subprocess.STDOUT)
        except OSError as e:
            self._log.close()
            raise ProcessError(f"cannot start {binary}: {e.strerror}") from None
        self.returncode: int | None = None

    @property
    def pid(self) -> int:
        return self.proc.pid

    def poll(self) -> int | None:
        """Exit status if the process has ended (negative: killed by that signal)."""
        if self.returncode is None:
            self.returncode = self.proc.poll()
        return self.returncode

    def describe_exit(self) -> str:
        """'exit status 3' / 'killed by SIGKILL', plus its last line of output."""
        rc = self.poll()
        if rc is None:
            what = "still running"
        elif rc < 0:
            try:
                what = f"killed by {signal.Signals(-rc).name}"
            except ValueError:
                what = f"killed by signal {-rc}"
        else:
            what = f"exit status {rc}"
        last = _last_line(self.log_path)
        return f"{what}" + (f"; its last words: {last}" if last else "")

    def wait(self, timeout: float) -> int | None:
        try:
            self.returncode = self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            return None
        return self.returncode

    def stop(self, grace: float = 2.0) -> int | None:
        """Wait up to grace seconds for a clean exit, then SIGTERM, then SIGKILL."""
        rc = self.wait(grace) if self.poll() is None else self.returncode
        for sig in (signal.SIGTERM, signal.SIGKILL):
            if rc is not None:
                break
            try:
                self.proc.send_signal(sig)
            except ProcessLookupError:
                pass
            rc = self.wait(2.0)
        if not self._log.closed:
            self._log.close()
        return rc


class BusRecorder:
    """The whole bus into bus.log, absolute timestamps, in the candump log format (``candump
    -L``), by a recorder program; the subclasses say which program and how it is started.

    The program writes into a private directory next to bus.log (its file is block-buffered),
    which is renamed to bus.log when it stops.  Because the recorder may lag behind the bus
    (frames queued in its socket), it is stopped only once it has gone back to waiting with an
    empty queue after an end marker was sent; the log is then checked to end with that marker.
    Its own messages go to a file in that directory (a pipe nobody reads could fill and stop
    it); the last line is its error.
    """

    #: the program (on $PATH, or a built tool)
    name = "recorder"
    #: socket receive buffer: a lagging recorder must not lose frames
    RCVBUF = 16 << 20
    #: the exit status that says frames were lost (None: the program cannot tell)
    LOST_EXIT: int | None = None

    def __init__(self, iface: str, log_path: Path) -> None:
        self.iface = iface
        self.log_path = log_path
        self._dir = log_path.parent / f".{self.name}-{os.getpid()}"
        self._dir.mkdir(parents=True, exist_ok=True)
        for old in self._dir.iterdir():
            old.unlink()
        self._err_path = self._dir / "stderr"
        with open(self._err_path, "wb") as err:
            self.proc = spawn(self.command(self._executable(), iface), cwd=self._dir,
                              stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=err)
        #: after stop(): what the recorder said when it failed ("" when it exited 0)
        self._error: str | None = None

    def _executable(self) -> str:
        raise NotImplementedError

    def command(self, exe: str, iface: str) -> list[str]:
        """The command line, run in the private directory."""
        raise NotImplementedError

    def _file(self) -> Path | None:
        """The log the program wrote in the private directory."""
        raise NotImplementedError

    @property
    def label(self) -> str:
        return f"{self.name} on {self.iface}"

    @property
    def pid(self) -> int:
        return self.proc.pid

    def alive(self) -> bool:
        return self.proc.poll() is None

    def error(self) -> str:
        """The recorder's own complaint (its last line on stderr), or its exit status; after
        stop(), "" when it exited 0."""
        if self._error is not None:
            return self._error
        return _last_line(self._err_path) or f"exit status {self.proc.returncode}"

    def _state(self) -> str:
        try:
            return proc_stat(self.proc.pid)[0].decode()
        except (OSError, IndexError):
            return "?"

    def wait_idle(self, timeout: float, polls: int = 3, gap: float = 0.003) -> bool:
        """Until the recorder sleeps (waiting for frames: its socket queue is empty) for
        `polls` looks in a row.  At start this means it listens; after a frame was sent, that
        it has read it."""
        deadline = time.monotonic() + timeout
        seen = 0
        while time.monotonic() < deadline and self.alive():
            seen = seen + 1 if self._state() == "S" else 0
            if seen >= polls:
                return True
            time.sleep(gap)
        return False

    def stop(self, marker: bytes | None = None, timeout: float = 10.0) -> bool:
        """Stop recording and move the log to log_path.  marker: the log text of a frame just
        sent (e.g. b"7F0#FFFFFFFF00000000"); True when the log is known to end with it and the
        recorder lost no frame."""
        if marker is not None and self.alive():
            self.wait_idle(timeout)
        if self.alive():
            self.proc.send_signal(signal.SIGINT)   # it leaves its loop and closes the file
            try:
                self.proc.wait(2.0)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        self._error = self.error() if self.proc.returncode != 0 else ""
        lost = self.LOST_EXIT is not None and self.proc.returncode == self.LOST_EXIT
        f = self._file()
        if f is not None:
            os.replace(f, self.log_path)
        elif not self.log_path.exists():
            self.log_path.write_bytes(b"")
        shutil.rmtree(self._dir, ignore_errors=True)
        return marker is not None and f is not None and not lost and self._ends_with(marker)

    def _ends_with(self, marker: bytes, tail: int = 1 << 16) -> bool:
        """The marker is the last frame of the log -- or, when a device the rig does not stop
        (--target external) kept sending after it, among the last `tail` bytes."""
        try:
            with open(self.log_path, "rb") as fh:
                fh.seek(max(0, os.path.getsize(self.log_path) - tail))
                return any(ln.endswith(marker) for ln in fh.read().splitlines()[1:])
        except OSError:
            return False


class Candump(BusRecorder):
    """``candump -l``: the recorder users know (``hil run``, the demo).  Two system calls and a
    wake-up per frame.  (Not ``-L`` on stdout: that flushes once per frame -- in the UML guest
    a system call per frame more.)"""

    name = "candump"

    def _executable(self) -> str:
        exe = shutil.which("candump")
        if exe is None:
            raise ProcessError("candump not found: install can-utils (scripts/setup does)")
        return exe

    def command(self, exe: str, iface: str) -> list[str]:
        return [exe, "-l", "-r", str(self.RCVBUF), iface]

    def _file(self) -> Path | None:
        files = sorted(self._dir.glob("candump-*.log"))
        return files[-1] if files else None


class Canrec(BusRecorder):
    """``canrec`` (firmware/tools/canrec): the same lines as candump -l, a batch of frames per
    system call (recvmmsg), exit 3 when the kernel dropped a frame (the campaigns' recorder)."""

    name = "canrec"
    LOST_EXIT = 3
    LOG_NAME = "canrec.log"

    def _executable(self) -> str:
        from hil.io.paths import ToolNotFound, tool
        try:
            return str(tool("canrec"))
        except ToolNotFound as e:
            raise ProcessError(str(e)) from None

    def command(self, exe: str, iface: str) -> list[str]:
        return [exe, "-r", str(self.RCVBUF), "-o", self.LOG_NAME, iface]

    def _file(self) -> Path | None:
        f = self._dir / self.LOG_NAME
        return f if f.exists() else None


#: the recorders a SocketCAN session can use, by name (hil campaign --recorder)
RECORDERS: dict[str, type[BusRecorder]] = {"candump": Candump, "canrec": Canrec}
