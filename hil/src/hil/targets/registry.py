"""The targets by name (`hil ... --target NAME`), each a `Target`: what the rest of hil asks of
a target (its lockstep timeout, whether it runs the rig's firmware, whose clock it steps on,
what it can do) is a property here, never a comparison of its name.

    host      fcc, the Linux build, as a child process of the rig (the default; hil.targets.host)
    qemu-m4f  the Cortex-M4F image under qemu-system-arm (hil.targets.qemu_m4f): its UART speaks
              SLCAN on a Unix socket, slcan_bridge joins that line to the rig's interface
    external  nothing: whatever answers on the bus (hil.targets.external)

A new target is a Device class (hil.targets.device) and one entry of TARGETS
(tests/python/targets/test_target_properties.py checks every target has every property).
"""
from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import TYPE_CHECKING

from hil.io import paths

if TYPE_CHECKING:
    from hil.targets.device import Device


@dataclass(frozen=True)
class Target:
    """A device under test: its Device class (imported when the target is used: a host run
    does not load the emulator's and the board's modules) and its properties."""

    name: str
    #: the module and the name of its Device class
    module: str
    device: str
    #: seconds a lockstep step may take to be answered (--timeout's default)
    lockstep_timeout_s: float
    #: the rig starts the firmware it builds (--fcc, --fcc-args apply); else the device is
    #: whoever answers on the bus, configured through SIM_CONTROL
    runs_rig_firmware: bool
    #: the firmware program the rig needs on this machine (None: none)
    program: str | None
    #: hil builds the program when it is missing in a clone (--fcc gives another)
    builds_program: bool
    #: a step's frames go out in one sendmmsg (the device takes a burst); else frame by frame
    batch_frames: bool
    #: only a SocketCAN interface reaches it (slcan_bridge's raw CAN socket)
    socketcan_only: bool
    #: realtime, it runs on this machine's scheduler: fcc asks for a realtime priority
    host_scheduler: bool
    #: its arithmetic is sid_replay's, so the lockstep cross-check's bound applies
    replay_exact: bool
    #: --workers/--scheduler can fly it on rigs of their own
    parallel: bool
    #: a warm rig (`hil rig up --target`) can keep it up
    warm_rig: bool
    #: what `--bus wire` means for it: "model" -- the rig puts canbus between the nodes' own
    #: vxcan ends (hil.rig.wirebus; the M4F image's slcan line is routed to its end); "real" --
    #: the bus it is on is a wire already (an external board on can0): no model, the rig
    #: records and judges the response times it can measure (hil.results.realbus)
    wire: str
    #: realtime: when its command acts after the sampling instant, where the scenario leaves
    #: that to the rig (its [lqg] delay "auto"; None: the rig's, a CAN node's 5 ms)
    actuation_delay_s: float | None = None

    def needs_program(self, fcc: object, source_tree: object) -> bool:
        """Whether its program must be found on this machine (with --fcc `fcc`, in the clone
        `source_tree`: None outside one)."""
        return self.program is not None and not (self.builds_program and (fcc or source_tree))

    def device_class(self) -> type[Device]:
        return getattr(importlib.import_module(self.module), self.device)


TARGETS: dict[str, Target] = {t.name: t for t in (
    Target("host", "hil.targets.host", "HostFcc", lockstep_timeout_s=2.0, runs_rig_firmware=True,
           program="fcc", builds_program=False, batch_frames=True, socketcan_only=False, host_scheduler=True,
           replay_exact=True, parallel=True, warm_rig=True, wire="model"),
    Target("qemu-m4f", "hil.targets.qemu_m4f", "QemuM4f", lockstep_timeout_s=30.0,
           runs_rig_firmware=True, program=paths.M4F_IMAGE, builds_program=True, batch_frames=True, socketcan_only=True,
           host_scheduler=False, replay_exact=False, parallel=False, warm_rig=True, wire="model",
           # its CAN is a serial line: QEMU's UART takes one byte per trip of its main loop (20-150
           # us in the UML guest, ~1.6 ms a 30-byte frame line), so a step's two sensor lines in and
           # its command line out put the command on the bus 8.4-9.5 ms after the sampling instant
           # (p50; p99 9.2-14.5 ms, max 15.2 ms: `hil verify realtime-timing time-sync --target
           # qemu-m4f`, idle 2-core host, 2026-12-02), past a CAN node's 5 ms
           actuation_delay_s=0.015),
    Target("external", "hil.targets.external", "ExternalDevice", lockstep_timeout_s=2.0,
           runs_rig_firmware=False, program=None, builds_program=False, batch_frames=False, socketcan_only=False,
           host_scheduler=False, replay_exact=False, parallel=False, warm_rig=False, wire="real"),
)}


def target(name: str) -> Target:
    """The target of a name (one line naming the choices when there is none)."""
    try:
        return TARGETS[name]
    except KeyError:
        raise ValueError(f"target must be one of {', '.join(TARGETS)}, not {name!r}") from None


def device_class(name: str) -> type[Device]:
    """The Device class of a target name."""
    return target(name).device_class()
