"""summary.json's `bus` section as the text table a run prints at its end and `hil report`
prints again: each frame's response times and bound in milliseconds and its verdict, sorted by
identifier (hil.results.busstats, hil.results.busstats_real; the figure: hil.plots.busresponse).
"""
from __future__ import annotations

from collections.abc import Mapping
from typing import Any

_HEAD = f"{'id':>6}  {'name':<20} {'queue':<5} {'n':>5} {'p50':>8} {'p99':>8} {'max':>8} {'bound':>8}  verdict"


def _ms(v: float | None) -> str:
    return "none" if v is None else f"{v * 1e3:.3f}"


def format_bus(section: Mapping[str, Any]) -> str:
    """The table; a real bus's frames not measured too, each reason said once below it."""
    model = section.get("model", "wire")
    what = "canbus's model" if model == "wire" else "a real bus"
    lines = [f"Bus at {section['bitrate']} bit/s ({what}, utilisation {section.get('utilisation', 0):.3f}): "
             "response time, queued at the sender -> end of frame (ms); bound: Davis 2007, J = 0", _HEAD]
    for name, f in sorted(section["frames"].items(), key=lambda kv: kv[1].get("id", 0)):
        bound = _ms(f["wcrt_s"]) if f.get("wcrt_jitter_s") is None else \
            f"{_ms(f['wcrt_s'])} ({_ms(f['wcrt_jitter_s'])} with J = {section.get('jitter_s', 0):.3f} s)"
        lines.append(f"{_id(f)}  {name:<20} {f.get('queue', ''):<5} {f['n']:>5} "
                     f"{_ms(f['p50_s']):>8} {_ms(f['p99_s']):>8} {_ms(f['max_s']):>8} {bound:>8}  {f['verdict']}")
    reasons: list[str] = []
    for name, f in sorted((section.get("not_measured") or {}).items(), key=lambda kv: kv[1]["id"]):
        if f["why"] not in reasons:
            reasons.append(f["why"])
        lines.append(f"{_id(f)}  {name:<20} {'':<5} {f['n']:>5} {'':>8} {'':>8} {'':>8} "
                     f"{_ms(f['wcrt_s']):>8}  not measured [{reasons.index(f['why']) + 1}]")
    lines += [f"[{i}] {why}" for i, why in enumerate(reasons, 1)]
    return "\n".join(lines)


def _id(f: Mapping[str, Any]) -> str:
    text = f"0x{f['id']:03X}" if "id" in f else ""
    return f"{text:>6}"


__all__ = ["format_bus"]


def format_wire_faults(section: Mapping[str, Any]) -> str:
    """One line a node of what the bus's faults did ('' on a bus without any)."""
    nodes = section.get("nodes") or {}
    hit = {name: n for name, n in nodes.items() if n["tx_errors"] or n["rx_errors"] or n["bus_off"]}
    babblers = {name: n for name, n in nodes.items() if name.startswith("babble")}
    if not section.get("error_frames") and not hit and not babblers:
        return ""
    lines = [f"wire faults: {section['error_frames']} error frames on the bus"
             + "".join(f"; {name} sent {n['sent']} frames" for name, n in babblers.items())]
    for name, n in hit.items():
        rec = ", ".join(f"{r * 1e3:.3f}" for r in n["recovery_s"])
        lines.append(f"  {name}: TEC max {n['tec_max']} REC max {n['rec_max']}, errors tx "
                     f"{n['tx_errors']} rx {n['rx_errors']}, error frames to it {n['error_frames']}, "
                     f"error-passive {n['error_passive']}, bus-off {n['bus_off']}"
                     + (f" (recovered after {rec} ms; {n['bus_off_dropped']} frames dropped)"
                        if n["bus_off"] else ""))
    return "\n".join(lines)
