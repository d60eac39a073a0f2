"""The bus recorder a run starts beside the simulator: it records the whole bus in the
candump log format into ``bus.log``: ``Candump`` (``candump -l``) or ``Canrec``
(firmware/tools/canrec, the same lines, frames read in batches), chosen per session
(``RECORDERS``).  Stopped politely (SIGINT after the end marker), then firmly; it never outlives
the run (hil.util.processes.spawn).
"""
from __future__ import annotations

import os
import re
import shutil
import signal
import subprocess
import time
from pathlib import Path

from hil.io.paths import ToolNotFound, tool
from hil.util.processes import ProcessError, last_line, proc_stat, spawn


_TOTAL = re.compile(rb"DROPCOUNT: dropped \d+ CAN frames? on '[^']*' socket \(total drops (\d+)\)")


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
        said = last_line(self._err_path)
        if said.startswith("Enabling Logfile"):  # candump's start-up banner: not a reason
            said = ""
        rc = self.proc.returncode
        if said:
            return said
        if rc is not None and rc < 0:
            return f"killed by {signal.Signals(-rc).name}"
        return f"exit status {rc}"

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
        dropped = self._dropped(f) if f is not None else ""
        if dropped:
            lost = True
            self._error = dropped
        if f is not None:
            os.replace(f, self.log_path)
        elif not self.log_path.exists():
            self.log_path.write_bytes(b"")
        shutil.rmtree(self._dir, ignore_errors=True)
        return marker is not None and f is not None and not lost and self._ends_with(marker)

    def _dropped(self, f: Path) -> str:
        """The kernel's drop counter as the program logged it ('' when it lost nothing or
        cannot tell)."""
        return ""

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
        # -d: the kernel's drop counter (SO_RXQ_OVFL); candump writes a DROPCOUNT line into
        # its log with the first frame it receives after a loss (the end marker at the latest)
        return [exe, "-d", "-l", "-r", str(self.RCVBUF), iface]

    def _dropped(self, f: Path) -> str:
        total, tail = 0, b""
        with open(f, "rb") as fh:
            while chunk := fh.read(1 << 20):
                buf = tail + chunk
                if b"DROPCOUNT" in buf:
                    total = max(total, *(int(m) for m in _TOTAL.findall(buf)), 0)
                tail = buf[-128:]
        return (f"candump lost {total} frame(s) (the kernel's drop counter, SO_RXQ_OVFL): the "
                f"recorder did not keep up with the bus") if total else ""

    def _file(self) -> Path | None:
        files = sorted(self._dir.glob("candump-*.log"))
        return files[-1] if files else None


class Canrec(BusRecorder):
    """``canrec`` (firmware/tools/canrec): the same lines as candump -l, the frames taken from a
    packet socket's receive ring (or a batch per recvmmsg without CAP_NET_RAW), exit 3 when the
    kernel dropped a frame (every run's recorder)."""

    name = "canrec"
    #: the receive ring (-R, canrec's default): 6,500 frames, twice what the wait below gathers
    #: of the busiest bus the guest makes (a 20 kHz flood in lockstep); -r is the socket
    #: buffer where canrec may not have a ring (no CAP_NET_RAW)
    RING = 1 << 20
    LOST_EXIT = 3
    LOG_NAME = "canrec.log"

    def _executable(self) -> str:
        try:
            return str(tool("canrec"))
        except ToolNotFound as e:
            raise ProcessError(str(e)) from None

    #: after a read that emptied its queue, canrec lets frames gather this long (-w; the
    #: kernel's stamps, the same log): one wake-up per ~20 lockstep steps, not two a step
    GATHER_MS = 10

    def command(self, exe: str, iface: str) -> list[str]:
        return [exe, "-R", str(self.RING), "-r", str(self.RCVBUF), "-b", "256", "-w", str(self.GATHER_MS),
                "-o", self.LOG_NAME, iface]

    def _file(self) -> Path | None:
        f = self._dir / self.LOG_NAME
        return f if f.exists() else None


#: the recorders a SocketCAN session can use, by name (hil campaign --recorder)
RECORDERS: dict[str, type[BusRecorder]] = {"candump": Candump, "canrec": Canrec}
