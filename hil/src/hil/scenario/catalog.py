"""`hil faults`: every fault kind with its fields (type, unit, default, allowed range) and an
example, read from the fault classes themselves (hil.scenario.faults), so the list cannot drift
from what the scenario loader accepts."""
from __future__ import annotations

import dataclasses
import math
import typing
from typing import Any

from hil.bus.apps import BUS_APPS
from hil.bus.dbc import PACKAGED_DBC, load
from hil.scenario.faults import KINDS, Fault
from hil.scenario.sensor_options import SIGNALS

#: the unit of each field, by name (sensor values are in the signal's unit)
UNITS = {
    "start": "s", "duration": "s", "delay": "s", "age": "s", "magnitude": "signal unit",
    "value": "signal unit", "rate": "signal unit/s", "factor": "1", "probability": "0..1",
    "count": "frames", "jump": "counter steps", "dlc": "bytes", "raw": "raw DBC value",
    "can_id": "11-bit id", "rate_hz": "Hz", "signal": "", "frame": "DBC message",
    "fill": "", "distribution": "", "node": "rig node", "every": "frames",
    "bit": "bits from SOF", "superposed": "bits",
    "utilisation": "0..1 of the bus", "id_lo": "11-bit id",
    "id_hi": "11-bit id",
}
#: the unit of each sensor signal: its DBC signal's
SIGNAL_UNITS = {name: load(PACKAGED_DBC).by_name(frame).signal(sig).unit
                for app in BUS_APPS.values() for name, frame, sig in app.sensor_signals}

#: one command-line example per kind (tests parse every one)
EXAMPLES = {
    "spike": ("cdrw", "spike:signal=alpha,start=4,duration=0.1,magnitude=0.15"),
    "bias": ("cdrw", "bias:signal=alpha,start=2,duration=inf,magnitude=0.02"),
    "stuck": ("cdrw", "stuck:signal=q,start=3,duration=1"),
    "dropout": ("cdrw", "dropout:signal=de,start=3,duration=0.5,fill=hold"),
    "noise_burst": ("missile", "noise_burst:signal=q_g,start=2,duration=1,magnitude=0.5,distribution=gaussian"),
    "drift": ("cdrw", "drift:signal=alpha,start=1,duration=inf,rate=0.005"),
    "scale": ("missile", "scale:signal=n_a,start=3,duration=2,factor=1.5"),
    "loss": ("cdrw", "loss:frame=CDRW_AOA,start=2,duration=0.5,probability=0.3"),
    "delay": ("cdrw", "delay:frame=CDRW_PITCH_RATE,start=2,duration=1,delay=0.04"),
    "duplicate": ("cdrw", "duplicate:frame=CDRW_AOA,start=2,duration=0.5,count=2"),
    "replay": ("missile", "replay:frame=MSL_RATE_GYRO,start=3,duration=1,age=0.5"),
    "bad_crc": ("cdrw", "bad_crc:frame=CDRW_AOA,start=2,duration=0.5"),
    "counter_freeze": ("cdrw", "counter_freeze:frame=CDRW_ELEVATOR,start=2,duration=0.3"),
    "counter_jump": ("cdrw", "counter_jump:frame=CDRW_AOA,start=2,duration=0.5,jump=3"),
    "wrong_dlc": ("cdrw", "wrong_dlc:frame=CDRW_AOA,start=2,duration=0.2,dlc=6"),
    "out_of_range": ("cdrw", "out_of_range:frame=CDRW_AOA,signal=alpha,start=2,duration=0.2"),
    "flood": ("cdrw", "flood:start=2,duration=1,can_id=0x000,rate_hz=4000"),
    "silence": ("missile", "silence:start=3,duration=0.5"),
    "bus_error": ("missile", "bus_error:frame=MSL_RATE_GYRO,start=2,duration=1,every=2"),
    "babbling_node": ("missile", "babbling_node:can_id=0x005,start=2,duration=0.5"),
    "bus_off": ("missile", "bus_off:node=fcc,start=3"),
    "bus_load": ("missile", "bus_load:start=0,duration=inf,utilisation=0.5,id_lo=0x200,id_hi=0x6ff"),
}


def _type(hint: Any) -> str:
    args = [a for a in typing.get_args(hint) if a is not type(None)]
    base = args[0] if args else hint
    return {float: "number", int: "integer", str: "string", bool: "boolean"}.get(base, str(base))


def _range(meta: dict[str, Any]) -> str:
    parts = []
    for key, op in (("gt", ">"), ("ge", ">="), ("lt", "<"), ("le", "<=")):
        if meta.get(key) is not None:
            parts.append(f"{op} {meta[key]:g}")
    if meta.get("choices"):
        parts.append("one of " + " ".join(map(str, meta["choices"])))
    if meta.get("allow_inf"):
        parts.append("inf = to the end of the run")
    return ", ".join(parts)


def _default(f: dataclasses.Field) -> str:
    if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING:
        return "required"
    d = f.default
    if d is None:
        return "default: none"
    return f"default {d:g}" if isinstance(d, float) and math.isfinite(d) else f"default {d}"


def fields(cls: type[Fault]) -> list[tuple[str, str, str, str, str]]:
    """(name, type, unit, default, range) of each field of a fault kind."""
    hints = typing.get_type_hints(cls)
    out = []
    for f in dataclasses.fields(cls):
        meta = dict(f.metadata)
        rng = _range(meta)
        if f.name == "signal" and cls.level == "sensor":
            rng = "; ".join(f"{a}: {' '.join(f'{s} ({SIGNAL_UNITS[s]})' for s in sigs)}"
                            for a, sigs in SIGNALS.items())
        elif f.name == "frame":
            rng = ("a DBC message name, or * = every "
                   + ("frame on the bus" if cls.level == "wire" else "sensor frame of the aircraft"))
        out.append((f.name, _type(hints[f.name]), UNITS.get(f.name, ""), _default(f), rng))
    return out


def describe(kind: str) -> str:
    cls = KINDS[kind]
    doc = " ".join((cls.__doc__ or "").split())
    lines = [f"{kind}  [{cls.level}]  {doc}"]
    rows = fields(cls)
    w = max(len(r[0]) for r in rows)
    for name, typ, unit, default, rng in rows:
        lines.append(f"    {name:<{w}}  {typ:<7}  {unit:<13}  {default:<15}  {rng}".rstrip())
    aircraft, example = EXAMPLES[kind]
    lines.append(f"    example ({aircraft}): --fault {example}")
    return "\n".join(lines)


def catalog(kinds: list[str] | None = None) -> str:
    """The text `hil faults [KIND...]` prints."""
    head = ("Fault kinds (a scenario's [[faults]] table with kind = \"...\" and these fields, or "
            "--fault KIND:field=value,...).\nTimes in seconds from the start of the run; "
            "sensor values in the signal's unit.\n\n")
    return head + "\n\n".join(describe(k) for k in (kinds or list(KINDS)))
