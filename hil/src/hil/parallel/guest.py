"""The host side of one worker's rig: a long-lived vcan bus with the flight server on it.

On a kernel with vcan the rig is the host itself with a vcan interface of its own (vcan1,
vcan2, ... whichever is free); otherwise it is a User-Mode Linux guest (scripts/with-vcan)
with its own vcan0.  Either way it runs hil.parallel.server, boots once (about 3 s for a
guest) and flies many flights; each flight has its own candump and fcc inside it.

A rig that dies or does not answer within the flight timeout is killed and booted again for
the next flight; the task fails with its cause (RigDown.cause: the rig process's exit status or
signal and its last lines), and the engine keeps what the task finished (hil.parallel.engine).
"""
from __future__ import annotations

import itertools
import os
import secrets
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from hil.io.paths import with_vcan
from hil.parallel.files import LEASE_S, await_answer, exit_cause, last_lines, write_request
from hil.rig.errors import RigError

BOOT_TIMEOUT_S = 120.0
#: the guest's own limit (with-vcan --timeout); the lease ends it much earlier when unused
GUEST_LIFETIME_S = 7 * 24 * 3600


class RigFailed(RigError):
    """A task failed in a rig; `cause` says why, for run_info (which process: "fcc" or
    "rig", its exit status or signal, its last lines)."""

    def __init__(self, message: str, cause: dict[str, Any] | None = None) -> None:
        super().__init__(message)
        self.cause = dict(cause or {})


class RigDown(RigFailed):
    """The rig died, hung or could not start: the flight it had is lost (and flown again).
    `cause`: the rig process's exit (exit_cause) and the last lines of its log."""

    def __init__(self, message: str, cause: dict[str, Any] | None = None) -> None:
        super().__init__(message, {"process": "rig", **(cause or {})})


def rig_root() -> Path:
    """Where rigs keep their request/answer files and flight directories: $HIL_RIG_DIR, or
    the temporary directory (a UML guest sees the host's whole file system)."""
    return Path(os.environ.get("HIL_RIG_DIR") or tempfile.gettempdir())


def new_token(root: Path) -> str:
    """A fresh secret for the rig in `root`, written to root/token readable by its owner only
    (the loop runs only requests that carry it: hil.parallel.server)."""
    token = secrets.token_hex(16)
    fd = os.open(root / "token", os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
    with os.fdopen(fd, "w") as f:
        f.write(token + "\n")
    return token


def _native_iface() -> str | None:
    """A vcan interface of our own on the host kernel, or None (no CAN here: use a guest)."""
    if shutil.which("ip") is None:
        return None
    subprocess.run(["modprobe", "vcan"], capture_output=True)
    for k in range(1, 100):
        name = f"vcan{k}"
        r = subprocess.run(["ip", "link", "add", "dev", name, "type", "vcan"], capture_output=True, text=True)
        if r.returncode == 0:
            up = subprocess.run(["ip", "link", "set", name, "txqueuelen", "1000", "up"], capture_output=True)
            if up.returncode == 0:
                return name
            subprocess.run(["ip", "link", "delete", name], capture_output=True)
            return None
        if "exists" not in r.stderr:
            return None
    return None


class GuestRig:
    """One rig, started on first use; call() runs a function in it and returns its value."""

    def __init__(self, root: Path | None = None, flight_timeout: float = 120.0,
                 boot_timeout: float = BOOT_TIMEOUT_S, name: str = "") -> None:
        # name: which of this process's rigs (hil.parallel.local drives several)
        self.base = Path(root or rig_root()) / f"hil-rig-{os.getpid()}{name}"
        self.flight_timeout = flight_timeout
        self.boot_timeout = boot_timeout
        self.dir: Path | None = None
        self.iface = "vcan0"
        self.native = False
        self.proc: subprocess.Popen[bytes] | None = None
        self.token = ""
        self.boots = 0
        self._seq = itertools.count()
        self._lock = threading.Lock()
        self._keeper: threading.Thread | None = None

    # -- life cycle
    def start(self) -> None:
        self.boots += 1
        d = self.base / f"boot{self.boots}"
        shutil.rmtree(d, ignore_errors=True)
        (d / "req").mkdir(parents=True)
        (d / "res").mkdir()
        (d / "lease").touch()
        self.token = new_token(d)
        self.dir = d
        server = [sys.executable, "-m", "hil.parallel.server", str(d)]
        iface = _native_iface()
        self.native = iface is not None
        if iface is not None:
            self.iface, cmd = iface, server
        else:
            self.iface = "vcan0"
            cmd = [*with_vcan(), "--uml", "--timeout", str(GUEST_LIFETIME_S), *server]
        log = open(d / "rig.log", "wb")  # noqa: SIM115 - the child owns it
        try:
            self.proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT,
                                         start_new_session=True)
        finally:
            log.close()
        if self._keeper is None:
            self._keeper = threading.Thread(target=self._renew, name="hil-rig-lease", daemon=True)
            self._keeper.start()
        deadline = time.monotonic() + self.boot_timeout
        while not (d / "ready").exists():
            if self.proc.poll() is not None:
                raise RigDown(f"the rig did not start ({self._last_words()})", self._cause())
            if time.monotonic() > deadline:
                self.kill()
                raise RigDown(f"the rig did not start within {self.boot_timeout:g} s", self._cause())
            time.sleep(0.05)

    def _renew(self) -> None:
        """Touch the lease while this process lives (a killed worker's rig stops by itself)."""
        while True:
            d = self.dir
            if d is not None and self.alive():
                try:
                    (d / "lease").touch()
                except OSError:
                    pass
            time.sleep(min(2.0, LEASE_S / 5))

    def alive(self) -> bool:
        return self.proc is not None and self.proc.poll() is None

    def _last_words(self) -> str:
        lines = last_lines(self.dir / "rig.log", 1) if self.dir is not None else []
        return lines[-1] if lines else f"exit status {self.proc.returncode if self.proc else '?'}"

    def _cause(self) -> dict[str, Any]:
        """Why the rig is down: its process's exit and the last lines of its log (the guest's
        console: the server's and the kernel's last words)."""
        rc = self.proc.poll() if self.proc is not None else None
        return {**exit_cause(rc), "last_lines": last_lines(self.dir / "rig.log") if self.dir is not None else []}

    def kill(self) -> None:
        """Stop the rig at once (the guest and everything in it)."""
        if self.proc is not None and self.proc.poll() is None:
            try:
                os.killpg(self.proc.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            self.proc.wait()
        self._release_iface()

    def stop(self, timeout: float = 30.0) -> None:
        """Ask the server to end (the guest then powers off); kill it if it does not."""
        if self.proc is not None and self.proc.poll() is None and self.dir is not None:
            (self.dir / "stop").touch()
            try:
                self.proc.wait(timeout)
            except subprocess.TimeoutExpired:
                pass
        self.kill()
        if self.dir is not None:
            shutil.rmtree(self.dir, ignore_errors=True)
        for d in (self.base / "flights", self.base):   # kept where a failed flight left files
            try:
                d.rmdir()
            except OSError:
                pass

    def _release_iface(self) -> None:
        if self.native:
            subprocess.run(["ip", "link", "delete", self.iface], capture_output=True)
            self.native = False

    # -- work
    def call(self, fn: Callable[..., Any], *args: Any) -> tuple[Any, float]:
        """fn(*args) inside the rig: (its value, seconds it took there).  Raises what fn
        raised, or RigDown when the rig died or did not answer within the flight timeout."""
        with self._lock:
            if not self.alive():
                self.start()
            assert self.dir is not None and self.proc is not None
            name = f"{next(self._seq):09d}.pkl"
            write_request(self.dir / "req" / name, self.token, fn, args)
            deadline = time.monotonic() + self.flight_timeout
            return await_answer(self.dir / "res" / name, lambda: self._check(deadline))

    def _check(self, deadline: float) -> None:
        """RigDown when the rig died, or did not answer by `deadline` (then it is killed)."""
        assert self.proc is not None
        if self.proc.poll() is not None:
            raise RigDown(f"the rig stopped during a flight ({self._last_words()})", self._cause())
        if time.monotonic() > deadline:
            self.kill()
            raise RigDown(f"the rig did not answer within {self.flight_timeout:g} s; killed",
                          {**self._cause(), "timeout_s": self.flight_timeout})

    def work_dir(self, name: str) -> Path:
        """A directory for one flight's files (kept there when the flight fails)."""
        return self.base / "flights" / name
