"""A scenario's faults of the wire-time bus (hil.scenario.faults: bus_error, babbling_node,
bus_off, bus_load) as canbus's options (firmware/tools/canbus: --error, --babble, --bus-off,
--load; docs/bus-timing.md), for both time bases: the realtime canbus process takes them on its
command line, the lockstep rig's model (hil.rig.simbus) the same options through
canbus_sim_setup, so that one C builder (canbus_fault_opts.c) makes the faults of both.

Their times count from the flight's start: in lockstep the model's time 0; in realtime canbus
is given `--epoch FILE` and, once the flight knows its first instant, the rig writes that
instant there (CLOCK_MONOTONIC nanoseconds, what Python's time.monotonic() reads on Linux) and
signals canbus (SIGUSR2).
"""
from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence

from hil.bus.dbc import BusSpec
from hil.scenario.faults import BabblingNode, BusError, BusLoad, BusOff, Fault
from hil.scenario.file import Scenario

#: a background load's seed: the scenario's, mixed with the fault's place (hil.rig.simbus.loads)
SEED_STRIDE = 1_000_003


def _window(f: Fault) -> str:
    to = "" if math.isinf(f.end) else f",to={f.end:.9g}"
    return f"from={f.start:.9g}{to}"


def _ids(spec: BusSpec, frame: str) -> str:
    if frame == "*":
        return "0-0x1FFFFFFF"
    m = spec.by_name(frame)
    return f"0x{m.frame_id:X}"


def canbus_faults(scenarios: Sequence[Scenario]) -> tuple[Fault, ...]:
    """The faults canbus flies: the wire level's, and the background loads within the flight
    (a load that went on after it would keep the bus from draining: the rig waits for canbus
    to carry nothing more before it stops it)."""
    out: list[Fault] = []
    for sc in scenarios:
        for f in sc.faults:
            if isinstance(f, BusLoad) and f.start < sc.duration:
                out.append(dataclasses.replace(f, duration=min(f.end, sc.duration) - f.start))
            elif f.level == "wire":
                out.append(f)
    return tuple(out)


def canbus_args(faults: Sequence[Fault], ends: Mapping[str, str], spec: BusSpec, seed: int = 0) -> list[str]:
    """The options for these faults; `ends` is canbus's interface of each rig node; a load's
    phases and data from seed and its place in faults."""
    args: list[str] = []
    for i, f in enumerate(faults):
        if isinstance(f, BusError):
            fields = [f"id={_ids(spec, f.frame)}", _window(f), f"every={f.every}"]
            fields += [f"node={ends[f.node]}"] if f.node != "*" else []
            fields += [f"count={f.count}"] if f.count else []
            fields += [f"bit={f.bit}" if f.bit >= 0 else "bit=crc-delim", f"superposed={f.superposed}"]
            args += ["--error", ",".join(fields)]
        elif isinstance(f, BabblingNode):
            period = 0.0 if f.rate_hz == 0 else 1.0 / f.rate_hz
            args += ["--babble", f"id=0x{f.can_id:X},dlc={f.dlc},period={period:.9g},{_window(f)}"]
        elif isinstance(f, BusOff):
            args += ["--bus-off", f"{ends[f.node]}@{f.start:.9g}"]
        elif isinstance(f, BusLoad):
            args += ["--load", f"util={f.utilisation:.9g},id=0x{f.id_lo:X}-0x{f.id_hi:X},"
                     f"seed={(seed * SEED_STRIDE + i) & 0xFFFFFFFFFFFFFFFF},{_window(f)}"]
    return args


def refusal(faults: Sequence[Fault], bus: str, real_bus: bool = False) -> str:
    """Why a flight on `bus` cannot fly these faults ('' when it can): wire faults are canbus's,
    and on a real bus (an external device's: no model) the rig injects none of the bus model's
    faults (`faults`: canbus_faults' -- flying on without them would report a run that did not
    have them)."""
    wire = [f for f in faults if f.level == "wire"]
    if wire and bus != "wire":
        return (f"fault {wire[0].describe()!r}: a fault of the wire-time bus (canbus): "
                f"needs --bus wire (this run's bus: {bus})")
    if faults and bus == "wire" and real_bus:
        return (f"fault {faults[0].describe()!r}: a fault of the bus model; a real bus (this "
                f"target's) has no model to inject it into")
    return ""
