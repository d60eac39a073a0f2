"""The two programs a run starts beside the simulator: the firmware and the bus recorder.

``FccProcess`` starts ``fcc`` with the run's flags, its stdout and stderr going to
``fcc.log`` in the run directory (that file keeps the firmware's event lines and its final
counter block).  ``Candump`` records the whole bus (``candump -l``, the ``-L`` log format) into ``bus.log``.
Both are stopped politely (shutdown frame / SIGINT), then firmly; neither outlives the run,
not even a killed rig: every child runs in its own process group (a Ctrl-C on the terminal
reaches the rig, which stops them in order) with a parent-death signal (Linux
PR_SET_PDEATHSIG = SIGKILL), so ``kill -9`` of hil takes fcc, candump and cangen with it.
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


def spawn(cmd: Sequence[str], **kw: Any) -> subprocess.Popen:
    """subprocess.Popen for a rig child: own process group, killed when the rig dies."""
    return subprocess.Popen(list(cmd), process_group=0, preexec_fn=_die_with_parent(os.getpid()),
                            **kw)


class ProcessError(RuntimeError):
    """A program could not be started or stopped (one line)."""


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


class Candump:
    """The whole bus, absolute timestamps, candump log format (the ``candump -L`` format).

    Run as ``candump -l`` in a private directory, then renamed to bus.log: the log file is
    block-buffered, whereas ``-L`` on stdout flushes once per frame -- a system call per frame
    that in the UML guest made the recorder the busiest process of a lockstep run.  The same
    format is written either way.  Because the recorder may lag behind the bus (frames queued
    in its socket), it is stopped only once it has gone back to waiting with an empty queue
    after an end marker was sent; the log is then checked to end with that marker.
    """

    #: socket receive buffer: a lagging recorder must not lose frames
    RCVBUF = 16 << 20

    def __init__(self, iface: str, log_path: Path) -> None:
        exe = shutil.which("candump")
        if exe is None:
            raise ProcessError("candump not found: install can-utils (scripts/setup does)")
        self.log_path = log_path
        self._dir = log_path.parent / f".candump-{os.getpid()}"
        self._dir.mkdir(parents=True, exist_ok=True)
        for old in self._dir.glob("candump-*.log"):
            old.unlink()
        self.proc = spawn([exe, "-l", "-r", str(self.RCVBUF), iface], cwd=self._dir,
                          stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                          stderr=subprocess.PIPE)

    def alive(self) -> bool:
        return self.proc.poll() is None

    def error(self) -> str:
        """candump's own complaint after it died."""
        try:
            err = self.proc.stderr.read().decode(errors="replace").strip() if self.proc.stderr else ""
        except (OSError, ValueError):
            err = ""
        return err.splitlines()[-1] if err else f"exit status {self.proc.returncode}"

    def _state(self) -> str:
        try:
            with open(f"/proc/{self.proc.pid}/stat", "rb") as fh:
                return fh.read().rsplit(b")", 1)[1].split()[0].decode()
        except (OSError, IndexError):
            return "?"

    def wait_idle(self, timeout: float, polls: int = 3, gap: float = 0.003) -> bool:
        """Until candump sleeps (in select(): its socket queue is empty) for `polls` looks in a
        row.  At start this means it listens; after a frame was sent, that it has read it."""
        deadline = time.monotonic() + timeout
        seen = 0
        while time.monotonic() < deadline and self.alive():
            seen = seen + 1 if self._state() == "S" else 0
            if seen >= polls:
                return True
            time.sleep(gap)
        return False

    def _file(self) -> Path | None:
        files = sorted(self._dir.glob("candump-*.log"))
        return files[-1] if files else None

    def stop(self, marker: bytes | None = None, timeout: float = 10.0) -> bool:
        """Stop recording and move the log to log_path.  marker: the log text of a frame just
        sent (e.g. b"7F0#FFFFFFFF00000000"); True when the log is known to end with it."""
        if marker is not None and self.alive():
            self.wait_idle(timeout)
        if self.alive():
            self.proc.send_signal(signal.SIGINT)   # candump leaves its loop and closes the file
            try:
                self.proc.wait(2.0)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        if self.proc.stderr:
            self.proc.stderr.close()
        f = self._file()
        if f is not None:
            os.replace(f, self.log_path)
        elif not self.log_path.exists():
            self.log_path.write_bytes(b"")
        try:
            self._dir.rmdir()
        except OSError:
            pass
        return marker is not None and f is not None and self._ends_with(marker)

    def _ends_with(self, marker: bytes, tail: int = 1 << 16) -> bool:
        """The marker is the last frame of the log -- or, when a device the rig does not stop
        (--target external) kept sending after it, among the last `tail` bytes."""
        try:
            with open(self.log_path, "rb") as fh:
                fh.seek(max(0, os.path.getsize(self.log_path) - tail))
                return any(ln.endswith(marker) for ln in fh.read().splitlines()[1:])
        except OSError:
            return False
