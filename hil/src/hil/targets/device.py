"""The device under test of a run (`hil ... --target`), as the session sees it.

Every target is a `Device`: `poll()` says whether it has gone (exit status, or a negative
signal number), `describe_exit()` says why in one line, `stop()` ends what the rig started.
The session waits for the first FCC_STATUS of any target (the lockstep protocol's "listening"),
and checks its FCC_STATUS.mode against the run's mode.

A target also owns its bus security: which key file it uses (`bus_key_file`), the trip the rig
knows it by before it starts (`choose_trip`; None: trust on first use, from its first heartbeat
that verifies under the key) and what its command line gets of them (`key_args`).
"""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from hil.util.errors import InputError


class ArgsRefused(InputError, ValueError):
    """The device refuses the options the user adds to its command line (one line: why)."""


@dataclass(frozen=True)
class DeviceStart:
    """What starting a device needs: the run directory (fcc.log goes there), the firmware's
    options, the rig's interface, the firmware (None: the build's) and python-can's interface."""

    run_dir: Path
    fcc_args: list[str] = field(default_factory=list)
    iface: str = "vcan0"
    firmware: Path | None = None
    interface: str = "socketcan"

    @property
    def log_path(self) -> Path:
        return self.run_dir / "fcc.log"


class Device:
    """What the session needs to know about the device under test."""

    target = "host"
    #: how the device is named in one-line errors ("fcc did not answer step 5 ...")
    label = "fcc"
    #: the rig started it and ends it with SIM_CONTROL shutdown (external: neither)
    owned = True
    #: its LQG period and D/A bits come from its command line; else the rig sends them in
    #: the SIM_CONTROL reset that starts every flight
    configured_by_args = True
    #: seconds from start to its first FCC_STATUS
    startup_timeout = 10.0
    cmd: list[str] = []
    returncode: int | None = None

    @classmethod
    def start(cls, how: DeviceStart) -> Device:
        raise NotImplementedError

    @classmethod
    def check_args(cls, given: Path | None, extra: Sequence[str], mode: str) -> None:
        """ArgsRefused when the device would refuse these extra options (--fcc-args) at its
        start: checked before the session opens, so that nothing starts that cannot fly."""

    @classmethod
    def firmware(cls, given: Path | None, progress: bool) -> Path | None:
        """The firmware to start, made ready before the session opens (None: the build's,
        found when the device starts); the Cortex-M4F image is cross-built here."""
        return given

    @classmethod
    def bus_key_file(cls, requested: Path | None) -> Path | None:
        """The key file the session uses with this device (None: a fresh random key)."""
        return requested

    @classmethod
    def choose_trip(cls) -> int | None:
        """The device's trip, known before it starts (None: taken from its first heartbeat)."""
        return None

    @classmethod
    def key_args(cls, key_file: Path, trip: int | None) -> list[str]:
        """Options that hand the key and the trip to the device's command line."""
        return []

    def poll(self) -> int | None:
        return None

    def local_pids(self) -> tuple[int, ...]:
        """The processes of this machine that play the device (none for an external one)."""
        return ()

    def describe_exit(self) -> str:
        return "still running"

    def stop(self, grace: float = 2.0) -> int | None:
        return self.returncode
