"""The targets by name (`hil ... --target NAME`):

    host      fcc, the Linux build, as a child process of the rig (the default; hil.targets.host)
    qemu-m4f  the Cortex-M4F image under qemu-system-arm (hil.targets.qemu_m4f): its UART speaks
              SLCAN, slcand attaches that line as a CAN interface and the kernel CAN gateway
              routes it to and from the rig's interface
    external  nothing: whatever answers on the bus (hil.targets.external)
"""
from __future__ import annotations

from hil.targets.device import Device
from hil.targets.external import ExternalDevice
from hil.targets.host import HostFcc
from hil.targets.qemu_m4f import QemuM4f

DEVICES: dict[str, type[Device]] = {"host": HostFcc, "qemu-m4f": QemuM4f, "external": ExternalDevice}
TARGETS = tuple(DEVICES)


def device_class(target: str) -> type[Device]:
    """The Device class of a target name."""
    try:
        return DEVICES[target]
    except KeyError:
        raise ValueError(f"target must be one of {', '.join(TARGETS)}, not {target!r}") from None
