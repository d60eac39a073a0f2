"""The targets by name (`hil ... --target NAME`):

    host      fcc, the Linux build, as a child process of the rig (the default; hil.targets.host)
    qemu-m4f  the Cortex-M4F image under qemu-system-arm (hil.targets.qemu_m4f): its UART speaks
              SLCAN, slcand attaches that line as a CAN interface and the kernel CAN gateway
              routes it to and from the rig's interface
    external  nothing: whatever answers on the bus (hil.targets.external)
"""
from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from hil.targets.device import Device

#: each target's module and Device class, imported when the target is used (a host run does
#: not load the emulator's and the board's modules)
DEVICES: dict[str, tuple[str, str]] = {"host": ("hil.targets.host", "HostFcc"),
                                       "qemu-m4f": ("hil.targets.qemu_m4f", "QemuM4f"),
                                       "external": ("hil.targets.external", "ExternalDevice")}
TARGETS = tuple(DEVICES)


def device_class(target: str) -> type[Device]:
    """The Device class of a target name."""
    try:
        module, name = DEVICES[target]
    except KeyError:
        raise ValueError(f"target must be one of {', '.join(TARGETS)}, not {target!r}") from None
    return getattr(importlib.import_module(module), name)
