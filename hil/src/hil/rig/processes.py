"""The two programs a run starts beside the simulator: the firmware and the bus recorder.

``FccProcess`` starts ``fcc`` with the run's flags, its stdout and stderr going to
``fcc.log`` in the run directory (that file keeps the firmware's event lines and its final
counter block).  ``Candump`` records the whole bus with ``candump -L`` into ``bus.log``.
Both are stopped politely (shutdown frame / SIGINT), then firmly; neither outlives the run.
"""
from __future__ import annotations

import os
import shutil
import signal
import subprocess
import time
from collections.abc import Sequence
from pathlib import Path


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
            self.proc = subprocess.Popen(self.cmd, stdin=subprocess.DEVNULL, stdout=self._log,
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
    """``candump -L IFACE > bus.log``: the whole bus, absolute timestamps."""

    def __init__(self, iface: str, log_path: Path) -> None:
        exe = shutil.which("candump")
        if exe is None:
            raise ProcessError("candump not found: install can-utils (scripts/setup does)")
        self.log_path = log_path
        self._out = open(log_path, "wb")  # noqa: SIM115 - closed in stop()
        # -r: a large receive buffer, so that a burst (flood fault) is not lost by the recorder
        self.proc = subprocess.Popen([exe, "-L", "-r", str(4 << 20), iface],
                                     stdin=subprocess.DEVNULL, stdout=self._out,
                                     stderr=subprocess.PIPE)

    def size(self) -> int:
        try:
            return os.path.getsize(self.log_path)
        except OSError:
            return 0

    def alive(self) -> bool:
        return self.proc.poll() is None

    def error(self) -> str:
        """candump's own complaint after it died."""
        try:
            err = self.proc.stderr.read().decode(errors="replace").strip() if self.proc.stderr else ""
        except (OSError, ValueError):
            err = ""
        return err.splitlines()[-1] if err else f"exit status {self.proc.returncode}"

    def contains_tail(self, needle: bytes, tail: int = 4096) -> bool:
        """True when needle is in the last `tail` bytes written (candump flushes each line)."""
        try:
            with open(self.log_path, "rb") as fh:
                fh.seek(max(0, self.size() - tail))
                return needle in fh.read()
        except OSError:
            return False

    def stop(self, marker: bytes | None = None, timeout: float = 10.0) -> bool:
        """Stop recording.  marker: the log line text of a frame just sent (e.g. b"7F0#FF...");
        candump may lag behind the bus by many frames in its socket queue, so it is stopped
        only once that line is in the file (or after timeout).  True when the log is known
        to be complete."""
        complete = marker is None
        if marker is not None and self.proc.poll() is None:
            deadline = time.monotonic() + timeout
            while time.monotonic() < deadline and self.proc.poll() is None:
                if self.contains_tail(marker):
                    complete = True
                    break
                time.sleep(0.005)
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
            try:
                self.proc.wait(2.0)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        if self.proc.stderr:
            self.proc.stderr.close()
        self._out.close()
        return complete
