"""`--target host` (the default): fcc, the Linux build, a child process of the rig on the
rig's interface; its stdout and stderr go to fcc.log in the run directory (the firmware's event
lines and its final counter block).  Stopped politely (the session's shutdown frame), then
firmly (SIGTERM, SIGKILL).

The rig starts it, so the rig chooses its trip (the high half of every freshness value) and
knows it from the start: a heartbeat recorded in another session, even under the same key,
never verifies (dbc/README.md, "Authentication").
"""
from __future__ import annotations

import os
import signal
import subprocess
from collections.abc import Sequence
from pathlib import Path

from hil.io.paths import tool
from hil.targets.device import ArgsRefused, Device, DeviceStart
from hil.util.processes import ProcessError, last_line, spawn

#: fcc --check-args parses and exits: a second is ample (on a loaded machine too)
CHECK_TIMEOUT_S = 30.0


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
        last = last_line(self.log_path)
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


class HostFcc(FccProcess, Device):
    """The Linux fcc, started by the rig on the rig's interface."""

    target = "host"

    def __init__(self, binary: Path, fcc_args: Sequence[str], iface: str, log_path: Path) -> None:
        FccProcess.__init__(self, binary, ["--iface", iface, *fcc_args], log_path)

    @classmethod
    def choose_trip(cls) -> int | None:
        return int.from_bytes(os.urandom(4), "little") or 1

    @classmethod
    def key_args(cls, key_file: Path, trip: int | None) -> list[str]:
        return ["--key-file", str(key_file), "--trip", str(trip)]

    def local_pids(self) -> tuple[int, ...]:
        return (self.pid,)

    @classmethod
    def check_args(cls, given: Path | None, extra: Sequence[str], mode: str) -> None:
        """fcc --check-args: its own option table judges them (exit 2 and its one line)."""
        if not extra:
            return
        fcc = given or tool("fcc")
        r = subprocess.run([str(fcc), "--check-args", "--mode", mode, *extra], capture_output=True,
                           text=True, stdin=subprocess.DEVNULL, timeout=CHECK_TIMEOUT_S)
        if r.returncode != 0:
            said = (r.stderr or r.stdout).strip().splitlines()
            why = said[-1].removeprefix("fcc: ") if said else f"exit status {r.returncode}"
            raise ArgsRefused(f"fcc refuses them: {why}")

    @classmethod
    def start(cls, how: DeviceStart) -> HostFcc:
        return cls(how.firmware or tool("fcc"), how.fcc_args, how.iface, how.log_path)
