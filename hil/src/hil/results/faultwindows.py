"""When each fault of a flight was active, from the start and end events its summary keeps
(summary.json: cdrw.flight.fault_events, missile.runs[i].fault_events; faults.log says the
same in text): for the verdict line (hil.results.verdict) and the shaded spans of the figures
(hil.plots).
"""
from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class FaultWindow:
    """One fault's active time: kind, what it acts on (signal, frame or bus), [start, end) in
    s; end None: still active when the flight ended."""

    kind: str
    target: str
    start: float
    end: float | None

    def short(self) -> str:
        """kind(target)@start-end, e.g. stuck(q_g)@3-4s (end '…' when it lasted to the end)."""
        end = "…" if self.end is None else f"{self.end:g}"
        return f"{self.kind}({self.target})@{self.start:g}-{end}s"


def from_events(events: Iterable[Mapping[str, Any]]) -> list[FaultWindow]:
    """The windows of a flight's fault events ({"action": "start"|"end", "index", "kind",
    "target", "t"}), by start time; a start without its end lasted to the end of the flight."""
    started: dict[object, Mapping[str, Any]] = {}
    out: list[FaultWindow] = []
    for ev in events:
        key = ev.get("index", ev.get("spec"))
        if ev.get("action") == "start":
            started[key] = ev
        elif ev.get("action") == "end" and key in started:
            s = started.pop(key)
            out.append(FaultWindow(str(s.get("kind")), str(s.get("target")), float(s["t"]), float(ev["t"])))
    out += [FaultWindow(str(s.get("kind")), str(s.get("target")), float(s["t"]), None)
            for s in started.values()]
    return sorted(out, key=lambda w: (w.start, w.kind, w.target))


def flight_events(summary: Mapping[str, Any], aircraft: str) -> list[Mapping[str, Any]]:
    """The fault events a summary keeps for one aircraft's flight (the closed-loop run of a
    missile flight; [] when there is none, e.g. a campaign, whose faults move)."""
    if aircraft == "cdrw":
        return list(((summary.get("cdrw") or {}).get("flight") or {}).get("fault_events") or [])
    runs = (summary.get("missile") or {}).get("runs") or []
    closed = [r for r in runs if r.get("bits") is not None]
    return list((closed[0] if closed else {}).get("fault_events") or [])
