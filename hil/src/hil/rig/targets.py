"""The device under test of a run (`hil ... --target`): what the rig starts, and how it stops it.

    host      fcc, the Linux build, as a child process of the rig (the default)
    qemu-m4f  the Cortex-M4F image under qemu-system-arm (hil.rig.qemu): its UART speaks SLCAN,
              slcand attaches that line as a CAN interface and the kernel CAN gateway routes
              it to and from the rig's interface
    external  nothing: the device under test is whatever answers on the bus -- a board behind
              a CAN adapter, or an fcc started by hand.  It is configured through SIM_CONTROL
              (LQG period and D/A bits); everything else is its own (start it like the command
              line the rig prints with --target host, see run_info.json "fcc_command").

Every target is a `Device`: `poll()` says whether it has gone (exit status, or a negative
signal number), `describe_exit()` says why in one line, `stop()` ends what the rig started.
The session waits for the first FCC_STATUS of any target (the lockstep protocol's "listening"),
and checks its FCC_STATUS.mode against the run's mode.
"""
from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from hil.io.paths import tool
from hil.rig.processes import FccProcess

TARGETS = ("host", "qemu-m4f", "external")


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

    def poll(self) -> int | None:
        return None

    def describe_exit(self) -> str:
        return "still running"

    def stop(self, grace: float = 2.0) -> int | None:
        return self.returncode


class HostFcc(FccProcess, Device):
    """The Linux fcc, started by the rig on the rig's interface."""

    target = "host"

    def __init__(self, binary: Path, fcc_args: Sequence[str], iface: str, log_path: Path) -> None:
        FccProcess.__init__(self, binary, ["--iface", iface, *fcc_args], log_path)


class ExternalDevice(Device):
    """A device the rig neither starts nor stops: it only has to answer on the bus."""

    target = "external"
    owned = False
    configured_by_args = False

    def __init__(self, iface: str, fcc_args: Sequence[str], log_path: Path) -> None:
        self.label = f"the device under test on {iface}"
        # what a hand-started fcc would be given (noise variances are not on SIM_CONTROL)
        self.cmd = ["fcc", "--iface", iface, *fcc_args]
        log_path.write_text("external target: the rig started no firmware; the device should run "
                            f"like\n  {' '.join(self.cmd)}\n", encoding="utf-8")


def start_device(target: str, run_dir: Path, fcc_args: Sequence[str], iface: str, *,
                 firmware: Path | None = None, interface: str = "socketcan") -> Device:
    """Start the device under test of `target` (fcc.log in run_dir keeps its output)."""
    log = run_dir / "fcc.log"
    if target == "host":
        return HostFcc(firmware or tool("fcc"), fcc_args, iface, log)
    if target == "external":
        return ExternalDevice(iface, fcc_args, log)
    if target == "qemu-m4f":
        from hil.rig.qemu import QemuM4f
        return QemuM4f(run_dir, fcc_args, iface, log, image=firmware, interface=interface)
    raise ValueError(f"target must be one of {', '.join(TARGETS)}, not {target!r}")
