"""Applying faults in time: which are active, the log of every start/end, and the sensor-level
injection itself.

``FaultTimeline`` is level-agnostic (the bus layer uses it for frame and bus faults too):
call ``update(t)`` once per step with non-decreasing t; it returns the starts and ends that
happened at this step and keeps them all in ``log``.

``SensorFaultInjector.apply(t, values)`` returns the measurements with the active sensor
faults applied, in the order the faults are listed.  Its random numbers (noise bursts) come
from a stream of their own, so the fault-free noise realisation is never disturbed.
"""
from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

import numpy as np

from hil.scenario.faults import T_EPS, Fault, SensorFault


def random_stream(seed: int, stream: int) -> np.random.Generator:
    """numpy's generator of one named stream of a scenario seed."""
    return np.random.default_rng([int(seed), stream])


@dataclass(frozen=True)
class FaultEvent:
    """One line of the fault log."""

    t: float          # s, sample time at which the change was seen
    action: str       # "start" or "end"
    index: int        # position of the fault in its list
    fault: Fault

    def __str__(self) -> str:
        return f"t={self.t:.3f} s  {self.action:5s}  [{self.fault.level}] {self.fault.describe()}"

    def as_dict(self) -> dict:
        return {"t": self.t, "action": self.action, "index": self.index,
                "level": self.fault.level, "kind": self.fault.kind,
                "target": self.fault.target, "spec": self.fault.describe()}


class FaultTimeline:
    """Tracks the active set of a list of faults and logs every transition."""

    def __init__(self, faults: Iterable[Fault]) -> None:
        self.faults = tuple(faults)
        self._on = [False] * len(self.faults)
        self.log: list[FaultEvent] = []
        self._t = -math.inf

    def update(self, t: float) -> list[FaultEvent]:
        if t < self._t:
            raise ValueError(f"fault timeline: time went backwards ({t} < {self._t})")
        self._t = t
        events = []
        for i, fault in enumerate(self.faults):
            now = fault.active(t)
            if now != self._on[i]:
                self._on[i] = now
                events.append(FaultEvent(t, "start" if now else "end", i, fault))
        self.log.extend(events)
        return events

    def add(self, fault: Fault) -> None:
        """One more fault, from the next update() on (a fault injected during a flight)."""
        self.faults = (*self.faults, fault)
        self._on.append(False)

    @property
    def active(self) -> tuple[Fault, ...]:
        return tuple(f for f, on in zip(self.faults, self._on) if on)


class SensorFaultInjector:
    """Applies the sensor-level faults of a list (other levels are ignored) to measurements."""

    def __init__(self, faults: Iterable[Fault], seed: int) -> None:
        self.faults = tuple(f for f in faults if isinstance(f, SensorFault))
        self.timeline = FaultTimeline(self.faults)
        self._rng = random_stream(seed, 0x6661)  # own stream: "fa"
        self._held: dict[int, float] = {}       # fault index -> reading held at its start
        self._last: dict[str, float] = {}       # signal -> last delivered reading

    @property
    def log(self) -> list[FaultEvent]:
        return self.timeline.log

    def add(self, fault: SensorFault) -> None:
        """One more sensor fault, from the next apply() on."""
        self.faults = (*self.faults, fault)
        self.timeline.add(fault)

    @property
    def active(self) -> tuple[Fault, ...]:
        """Sensor faults active at the last apply()."""
        return self.timeline.active

    def window(self) -> tuple[float, float]:
        """[first start, last end) of the faults, in apply()'s time: before it no reading is
        changed and nothing is logged; from its end on, once the ends are logged, neither."""
        if not self.faults:
            return math.inf, math.inf
        return (min(f.start for f in self.faults) - T_EPS, max(f.end for f in self.faults) - T_EPS)

    def passed(self, values: Mapping[str, float]) -> None:
        """Readings delivered unchanged outside window() (what apply() would remember of them:
        the last good reading of each signal, held when a fault starts)."""
        for sig, v in values.items():
            if math.isfinite(v):
                self._last[sig] = v

    def apply(self, t: float, values: Mapping[str, float]) -> dict[str, float]:
        """The readings at time t with every active sensor fault applied."""
        for ev in self.timeline.update(t):
            if ev.action == "start":
                sig = ev.fault.target
                self._held[ev.index] = self._last.get(sig, values.get(sig, math.nan))
        out = dict(values)
        for i, fault in enumerate(self.faults):
            if fault.active(t) and fault.signal in out:
                out[fault.signal] = fault.apply(out[fault.signal], t, self._held[i], self._rng)
        for sig, v in out.items():
            if math.isfinite(v):  # a dropout (NaN) leaves the last good reading in place
                self._last[sig] = v
        return out
