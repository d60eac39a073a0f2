"""`hil study bus`'s tables: the missile's RMS q over bit rate and background load, plain and
delay-aware (hil.runs.bus_study), and Table 4 on the ideal bus and on the loaded wire."""
from __future__ import annotations

from typing import Any

FILTERS = (("azkf", "MLS-AZKF"), ("zkf", "MLS-ZKF"), ("kf", "MLS-KF"))


def _rate(bitrate: int) -> str:
    return f"{bitrate // 1_000_000}M" if bitrate % 1_000_000 == 0 else f"{bitrate // 1000}k"


def _num(v: float | None, fmt: str) -> str:
    return "-" if v is None else format(v, fmt)


def _ms(v: float | None) -> str:
    return _num(None if v is None else 1e3 * v, ".2f")


def format_grid(study: dict[str, Any]) -> str:
    """Per period: RMS q plain / delay-aware, rows the load, columns the bit rate; then the
    plain flights' largest command delay (the delay-aware design's d, rounded up)."""
    pts = study["points"]
    rates = sorted({p["bitrate"] for p in pts})
    loads = sorted({p["load"] for p in pts})
    at = {(p["period"], p["bitrate"], p["load"], p["design"]): p for p in pts}
    lines = [f"Missile on the wire-time bus, lockstep (simulated time), seed {study['seed']}, "
             f"{study['duration']:g} s a flight; background load: bus_load on "
             f"{study['load_ids'][0]:#05x}-{study['load_ids'][1]:#05x}"]
    for period in sorted({p["period"] for p in pts}):
        lines.append(f"T = {period:g} s: RMS q (rad/s), plain / delay-aware LQG")
        lines.append("  load " + "".join(f"{_rate(r):>19}" for r in rates))
        for load in loads:
            cells = []
            for r in rates:
                plain, aware = at[(period, r, load, "plain")], at[(period, r, load, "delay-aware")]
                cell = "/".join("fail" if p["failed"] else _num(p["rms_q"], ".4f") for p in (plain, aware))
                cells.append(f"{cell:>19}")
            lines.append(f"  {100 * load:3.0f} %" + "".join(cells))
        lines.append(f"T = {period:g} s: largest command delay of the plain flight (ms)")
        lines.append("  load " + "".join(f"{_rate(r):>19}" for r in rates))
        for load in loads:
            cells = [f"{_ms(at[(period, r, load, 'plain')]['cmd_delay_max_s']):>19}" for r in rates]
            lines.append(f"  {100 * load:3.0f} %" + "".join(cells))
    failed = [p for p in pts if p["failed"]]
    for p in failed:
        lines.append(f"failed: T {p['period']:g}, {_rate(p['bitrate'])}, load {p['load']:g}, "
                     f"{p['design']}: {p['failed']}")
    return "\n".join(lines)


def format_table4(t4: dict[str, Any]) -> str:
    """Table 4 (alpha and q error of each filter) on the ideal bus and on the loaded wire."""
    head = (f"Table 4 (CDRW, one fault), ideal bus vs wire at {_rate(t4['bitrate'])} with "
            f"{100 * t4['load']:.0f} % background load")
    lines = [head, f"  {'filter':<10}{'alpha ideal':>13}{'alpha wire':>13}{'q ideal':>11}{'q wire':>11}"]
    ideal, wire = t4["ideal"]["table4"] or {}, t4["wire"]["table4"] or {}
    for key, label in FILTERS:
        i, w = ideal.get(key) or {}, wire.get(key) or {}
        lines.append(f"  {label:<10}{_num(i.get('alpha'), '.4f'):>13}{_num(w.get('alpha'), '.4f'):>13}"
                     f"{_num(i.get('q'), '.4f'):>11}{_num(w.get('q'), '.4f'):>11}")
    wire_info = t4["wire"]
    if wire_info.get("failed"):
        lines.append(f"  the wire run failed: {wire_info['failed']}")
    else:
        lines.append(f"  wire: bus load {_num(wire_info.get('bus_load'), '.3f')}, frames by verdict "
                     f"{wire_info.get('verdicts')}, FCC_ACK at most "
                     f"{_ms(wire_info.get('ack_max_s'))} ms"
                     " after its queueing")
    return "\n".join(lines)
