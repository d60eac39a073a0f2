"""The Cortex-M4F image on QEMU's mps2-an386, and its SLCAN link on a pty.

    with Board(elf, run_dir) as board:           # boots; board.pty is /dev/pts/N
        link = board.link()                      # opens the pty, raw; "C", "S6", "O"
        link.send(0x020, data)                   # one SLCAN 't' line
        for frame_id, data in link.frames(timeout=5.0): ...

The command line is the one of firmware/port/mps2_an386/README.md (the interface with the
rig); `command()` builds it.  Board.exit_status() waits for QEMU to end (the
image exits through semihosting after SIM_CONTROL shutdown).
"""
from __future__ import annotations

import os
import re
import select
import shutil
import subprocess
import termios
import time
import tty
from collections.abc import Iterator
from pathlib import Path

from hil.targets import bootcfg
from hil.util.errors import HilError

QEMU = "qemu-system-arm"
MACHINE = "mps2-an386"
#: QEMU's "char device redirected to /dev/pts/N" line (the pty under the multiplexer "slcan")
PTY_LINE = re.compile(r"char device redirected to (/dev/pts/\d+) \(label slcan-base\)")
CR, BEL = 0x0D, 0x07


def available() -> str | None:
    """Path of qemu-system-arm, or None."""
    return shutil.which(QEMU)


def command(elf: Path, *, log: Path | None = None, bootcfg_file: Path | None = None,
            lockstep: bool = True, line_socket: Path | None = None) -> list[str]:
    """QEMU's command line: UART0 = SLCAN on a new pty (or, with line_socket, on that Unix
    socket, QEMU connecting as its client: slcan_bridge listens there), UART1 = the log file.
    The line goes through QEMU's multiplexer (mux=on) for its 32-byte buffer: without it QEMU
    reads the line one byte per main-loop round, each handed to the vCPU thread and back (the
    UART holds one byte); with it the main loop reads ahead while the image's receive
    interrupt takes the buffered bytes in one go.  -echr 256: no byte is the multiplexer's
    escape (Ctrl-A x would otherwise end QEMU).
    lockstep: -icount shift=0,sleep=on (1 instruction = 1 ns of virtual time);
    realtime: no -icount (virtual time = the host's clock)."""
    line = f"socket,id=slcan,path={line_socket},mux=on" if line_socket else "pty,id=slcan,mux=on"
    cmd = [QEMU, "-machine", MACHINE, "-cpu", "cortex-m4", "-display", "none", "-monitor", "none",
           "-nodefaults", "-nic", "none", "-kernel", str(elf),
           "-chardev", line, "-echr", "256", "-serial", "chardev:slcan",
           "-serial", f"file:{log}" if log is not None else "null",
           "-semihosting-config", "enable=on,target=native"]
    if lockstep:
        cmd += ["-icount", "shift=0,sleep=on"]
    if bootcfg_file is not None:
        cmd += ["-device", f"loader,file={bootcfg_file},addr={bootcfg.ADDRESS:#010x},force-raw=on"]
    return cmd


class SlcanError(HilError, RuntimeError):
    """The SLCAN link did not answer as the protocol says."""


class SlcanLink:
    """The host end of the image's SLCAN line (what slcand does, in Python)."""

    def __init__(self, pty: str) -> None:
        self.fd = os.open(pty, os.O_RDWR | os.O_NOCTTY | os.O_NONBLOCK)
        tty.setraw(self.fd, termios.TCSANOW)
        self._buf = bytearray()
        self.answers: list[bytes] = []   # non-frame lines: b"" for CR, b"\a" for BEL, b"V0110", ...

    def close(self) -> None:
        os.close(self.fd)

    def write(self, text: bytes) -> None:
        view = memoryview(text)
        while view:
            _, w, _ = select.select([], [self.fd], [], 5.0)
            if not w:
                raise SlcanError("the SLCAN pty does not take bytes")
            n = os.write(self.fd, view)
            view = view[n:]

    def send(self, frame_id: int, data: bytes) -> None:
        self.write(b"t%03X%d%s\r" % (frame_id, len(data), data.hex().upper().encode()))

    def _lines(self, timeout: float) -> Iterator[bytes]:
        deadline = time.monotonic() + timeout
        while True:
            for i, b in enumerate(self._buf):
                if b in (CR, BEL):
                    line = bytes(self._buf[:i + 1])
                    del self._buf[:i + 1]
                    yield line
                    break
            else:
                left = deadline - time.monotonic()
                if left <= 0:
                    return
                r, _, _ = select.select([self.fd], [], [], min(left, 0.5))
                if r:
                    try:
                        self._buf += os.read(self.fd, 65536)
                    except BlockingIOError:
                        pass

    def frames(self, timeout: float) -> Iterator[tuple[int, bytes]]:
        """Frames the image sends, until timeout seconds have passed; other lines
        (answers to commands) go to self.answers."""
        for line in self._lines(timeout):
            text = line[:-1]
            if line[-1] == CR and text[:1] == b"t" and len(text) >= 5:
                dlc = int(text[4:5], 16)
                yield int(text[1:4], 16), bytes.fromhex(text[5:5 + 2 * dlc].decode())
            else:
                self.answers.append(text if line[-1] == CR else b"\a")

    def command(self, text: bytes, timeout: float = 10.0) -> bytes:
        """Sends one command line and returns its answer (b"" = CR, b"\\a" = BEL);
        frames that arrive meanwhile are dropped."""
        self.answers.clear()
        self.write(text + b"\r")
        deadline = time.monotonic() + timeout
        while not self.answers:
            left = deadline - time.monotonic()
            if left <= 0:
                raise SlcanError(f"no answer to {text!r} within {timeout} s")
            for _ in self.frames(min(left, 0.2)):
                pass
        return self.answers.pop(0)

    def open(self, timeout: float = 10.0) -> None:
        """slcand -o -c -s6: close, 500 kbit/s, open; the image answers CR to each."""
        self.write(b"\r\r\r")
        for cmd in (b"C", b"S6", b"O"):
            answer = self.command(cmd, timeout)
            if answer != b"":
                raise SlcanError(f"SLCAN {cmd.decode()} answered {answer!r}")


class Board:
    """One QEMU process running the image; stdout gives the pty, stderr goes to a file."""

    def __init__(self, elf: Path, run_dir: Path, *, config: bootcfg.BootConfig | None = None,
                 lockstep: bool = True) -> None:
        self.run_dir = run_dir
        self.log_path = run_dir / "m4f.log"
        cfg_file = config.write(run_dir / "bootcfg.bin") if config is not None else None
        self.cmd = command(elf, log=self.log_path, bootcfg_file=cfg_file, lockstep=lockstep)
        self.proc: subprocess.Popen[bytes] | None = None
        self.pty = ""
        self._link: SlcanLink | None = None

    def __enter__(self) -> Board:
        self._err = open(self.run_dir / "qemu.stderr", "wb")  # noqa: SIM115 -- closed in __exit__
        self.proc = subprocess.Popen(self.cmd, stdout=subprocess.PIPE, stderr=self._err)
        assert self.proc.stdout is not None
        line = self.proc.stdout.readline().decode(errors="replace")  # QEMU's first stdout line
        m = PTY_LINE.search(line)
        if m is None:
            self.__exit__()
            raise SlcanError(f"QEMU did not give a pty: {line.strip()!r} "
                            f"({(self.run_dir / 'qemu.stderr').read_text(errors='replace').strip()})")
        self.pty = m.group(1)
        return self

    def link(self) -> SlcanLink:
        if self._link is None:
            self._link = SlcanLink(self.pty)
            self._link.open()
        return self._link

    def log(self) -> str:
        return self.log_path.read_text(errors="replace") if self.log_path.exists() else ""

    def exit_status(self, timeout: float) -> int:
        assert self.proc is not None
        return self.proc.wait(timeout=timeout)

    def __exit__(self, *exc: object) -> None:
        if self._link is not None:
            self._link.close()
            self._link = None
        if self.proc is not None and self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        if self.proc is not None and self.proc.stdout is not None:
            self.proc.stdout.close()
        if hasattr(self, "_err"):
            self._err.close()
