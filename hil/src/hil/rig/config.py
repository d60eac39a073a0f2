"""The run's configuration: what `hil run/campaign/sweep/demo` were told, beyond the scenario
(interface, mode, device under test, bus key, recorder, outputs).  One object, handed to the
session and to every flight of the run.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from hil.targets.registry import TARGETS

MODES = ("lockstep", "realtime")
#: the bus between the nodes: ideal (one vcan interface, frames take no time) or wire
#: (hil.rig.wirebus: canbus, arbitration and wire time at `bitrate`)
BUSES = ("ideal", "wire")
#: realtime: fcc's SCHED_FIFO priority (the simulator runs normally: in the UML guest a
#: SCHED_FIFO python starved the guest's timers and frame delivery, measured); the platform's
#: baseline measures at the same priority (hil.rig.platform)
FCC_RT_PRIORITY = 50


@dataclass
class RigConfig:
    out_dir: Path
    iface: str = "vcan0"
    mode: str = "lockstep"
    timeout: float = 2.0
    fcc_args: tuple[str, ...] = ()
    rows: str = "paper"            # CDRW: which estimate fcc reports (fcc --rows)
    progress: bool = True
    plots: bool = True
    fcc_binary: Path | None = None
    log_format: str = "log"
    #: the device under test (hil.targets.registry) and python-can's bus of the simulator
    target: str = "host"
    interface: str = "socketcan"
    bitrate: int | None = None
    key_file: Path | None = None   # None: a random key for each session
    #: the bus recorder of a SocketCAN session (hil.rig.recorder.RECORDERS)
    recorder: str = "canrec"
    bus: str = "ideal"

    def __post_init__(self) -> None:
        if self.mode not in MODES:
            raise ValueError(f"mode must be one of {', '.join(MODES)}, not {self.mode!r}")
        if self.bus not in BUSES:
            raise ValueError(f"bus must be one of {', '.join(BUSES)}, not {self.bus!r}")
        if self.target not in TARGETS:
            raise ValueError(f"target must be one of {', '.join(TARGETS)}, not {self.target!r}")
