"""A scenario's wire-level faults (hil.scenario.faults: bus_error, babbling_node, bus_off) as
canbus's options (firmware/tools/canbus: --error, --babble, --bus-off; docs/bus-timing.md).

Their times count from the flight's start: canbus is given `--epoch FILE` and, once the
realtime flight knows its first instant, the rig writes that instant there (CLOCK_MONOTONIC
nanoseconds, what Python's time.monotonic() reads on Linux) and signals canbus (SIGUSR2).
"""
from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

from hil.bus.dbc import BusSpec
from hil.scenario.faults import BabblingNode, BusError, BusOff, Fault


def _window(f: Fault) -> str:
    to = "" if math.isinf(f.end) else f",to={f.end:.9g}"
    return f"from={f.start:.9g}{to}"


def _ids(spec: BusSpec, frame: str) -> str:
    if frame == "*":
        return "0-0x1FFFFFFF"
    m = spec.by_name(frame)
    return f"0x{m.frame_id:X}"


def canbus_args(faults: Sequence[Fault], ends: Mapping[str, str], spec: BusSpec) -> list[str]:
    """The options for these faults; `ends` is canbus's interface of each rig node."""
    args: list[str] = []
    for f in faults:
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
    return args


def refusal(faults: Sequence[Fault], bus: str) -> str:
    """Why a flight on `bus` cannot fly these faults ('' when it can): wire faults are canbus's."""
    wire = [f for f in faults if f.level == "wire"]
    if wire and bus != "wire":
        return (f"fault {wire[0].describe()!r}: a fault of the wire-time bus (canbus): "
                f"needs --bus wire (this run's bus: {bus})")
    return ""
