"""`--target external`: nothing is started.  The device under test is whatever answers on the
bus -- a board behind a CAN adapter, or an fcc started by hand.  It is configured through
SIM_CONTROL (LQG period and D/A bits); everything else is its own (start it like the command
line the rig prints with --target host, see run_info.json "fcc_command").  Its trip is taken
from its first heartbeat that verifies under the key (trust on first use; a replayed old
heartbeat then is a denial, never a spoof).
"""
from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from hil.targets.device import Device, DeviceStart


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

    @classmethod
    def start(cls, how: DeviceStart) -> ExternalDevice:
        return cls(how.iface, how.fcc_args, how.log_path)
