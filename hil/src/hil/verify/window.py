"""Windows around events, and what is measured in them: the windowed expectations.

    [case.expect]
    SID-BND-2 = [{ signal = "cdrw.azkf_alpha_lo <= cdrw.alpha_true <= cdrw.azkf_alpha_hi",
                   window = { event = "fault[0].end", offset_s = 0.0, length_s = 1.0 },
                   measure = "settling_time", band = [1, 1], expect = "value <= 0.1" }]

A window starts at an event plus offset_s and lasts length_s (default: to `until`, an event,
or to the end of the run).  An event is

    start, end                      the flight's start (t = 0) and its last sample
    fault[N].start, fault[N].end    the N-th fault the case flies (the embedded scenario's own
                                    first, unless default_faults = false, then the case's)
    fault[KIND].start / .end        the first fault of that kind (fault[spike].end)
    a condition over series         the first sample at which it holds
                                    ("bus.FCC_SYNC_STATUS.state == 2")

The measure reduces the signal's samples in the window (t_from <= t <= t_to) to one number,
`value` in the expectation, which may name result fields as well (``value < 0.5 * missile.rms_q``).
Everything is checked when the suite is loaded (WindowError: one line naming the field).
"""
from __future__ import annotations

import math
import re
from collections.abc import Callable, Collection, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from hil.scenario.faults import Fault
from hil.scenario.schema import ScenarioError, build, spec
from hil.util.errors import HilError
from hil.verify.expr import Expectation
from hil.verify.series import RunSeries, Series, SeriesError, Signal, signal

NEVER = math.inf
#: the name the measured value has in the expectation
VALUE = "value"
_FAULT_EVENT = re.compile(r"fault\[([A-Za-z0-9_]{1,32})\]\.(start|end)")


class WindowError(HilError, ValueError):
    """A windowed expectation that is not one (one line)."""


class NoWindow(Exception):
    """The window's event never came in this flight (the check fails, saying so)."""


# ---- measures --------------------------------------------------------------------------------
def _true(x: np.ndarray) -> np.ndarray:
    return (x != 0) & ~np.isnan(x)


def _time_to_true(t: np.ndarray, x: np.ndarray, t0: float) -> float:
    hit = np.flatnonzero(_true(x))
    return float(t[hit[0]] - t0) if hit.size else NEVER


def _steps_to_true(x: np.ndarray) -> float:
    hit = np.flatnonzero(_true(x))
    return float(hit[0]) if hit.size else NEVER


def _holds_steps(x: np.ndarray) -> float:
    """The longest run of consecutive samples that hold."""
    best = run = 0
    for held in _true(x):
        run = run + 1 if held else 0
        best = max(best, run)
    return float(best)


def _settling_time(t: np.ndarray, x: np.ndarray, t0: float, band: tuple[float, float]) -> float:
    """From the window's start until the signal enters the band and stays in it to the
    window's end (inf: outside at the end)."""
    outside = np.flatnonzero(~((x >= band[0]) & (x <= band[1])))
    if not outside.size:
        return 0.0
    last = outside[-1]
    return NEVER if last == len(x) - 1 else float(t[last + 1] - t0)


def _towards(x: np.ndarray, target: float | None) -> tuple[float, float]:
    """(start, target) of a response: the target given, else the window's last sample."""
    return float(x[0]), float(x[-1]) if target is None else target


def _overshoot(x: np.ndarray, target: float | None) -> float:
    """How far the signal goes past its target, as a fraction of the change (0.2: 20 %)."""
    start, goal = _towards(x, target)
    change = goal - start
    if change == 0:
        return NEVER if np.any(x != goal) else 0.0
    return max(0.0, float(np.nanmax((x - goal) * np.sign(change)))) / abs(change)


def _rise_time(t: np.ndarray, x: np.ndarray, target: float | None) -> float:
    """From 10 % to 90 % of the change towards the target (inf: never got there)."""
    start, goal = _towards(x, target)
    progress = (x - start) / (goal - start) if goal != start else np.zeros_like(x)
    ten, ninety = np.flatnonzero(progress >= 0.1), np.flatnonzero(progress >= 0.9)
    if goal == start or not ninety.size:
        return NEVER
    return float(t[ninety[0]] - t[ten[0]])


def _rms(x: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.square(x))))


@dataclass(frozen=True)
class Measure:
    doc: str
    #: (t, x, window start, check) -> the value; x is never empty
    of: Callable[[np.ndarray, np.ndarray, float, Check], float]
    #: the check's parameters it takes: band (required), target (optional)
    params: tuple[str, ...] = ()


MEASURES: dict[str, Measure] = {
    "max": Measure("largest sample", lambda t, x, t0, c: float(np.max(x))),
    "min": Measure("smallest sample", lambda t, x, t0, c: float(np.min(x))),
    "mean": Measure("mean of the samples", lambda t, x, t0, c: float(np.mean(x))),
    "rms": Measure("root mean square of the samples", lambda t, x, t0, c: _rms(x)),
    "peak": Measure("largest magnitude |x|", lambda t, x, t0, c: float(np.max(np.abs(x)))),
    "first": Measure("the first sample", lambda t, x, t0, c: float(x[0])),
    "last": Measure("the last sample", lambda t, x, t0, c: float(x[-1])),
    "samples": Measure("how many samples the window holds", lambda t, x, t0, c: float(len(x))),
    "true_steps": Measure("samples at which the signal holds (non-zero)",
                          lambda t, x, t0, c: float(np.count_nonzero(_true(x)))),
    "holds_steps": Measure("the longest run of consecutive samples at which it holds",
                           lambda t, x, t0, c: _holds_steps(x)),
    "steps_to_true": Measure("samples before the first at which it holds (inf: never)",
                             lambda t, x, t0, c: _steps_to_true(x)),
    "time_to_true": Measure("s from the window's start to the first sample at which it holds "
                            "(inf: never)", lambda t, x, t0, c: _time_to_true(t, x, t0)),
    "settling_time": Measure("s from the window's start until the signal is inside `band` "
                             "to the window's end (inf: outside at its end)",
                             lambda t, x, t0, c: _settling_time(t, x, t0, c.band_or_fail()), ("band",)),
    "overshoot": Measure("how far past `target` (default: the last sample) as a fraction of the "
                         "change from the first sample", lambda t, x, t0, c: _overshoot(x, c.target),
                         ("target",)),
    "rise_time": Measure("s from 10 % to 90 % of the change from the first sample to `target` "
                         "(default: the last sample; inf: never)",
                         lambda t, x, t0, c: _rise_time(t, x, c.target), ("target",)),
}


# ---- events and windows ----------------------------------------------------------------------
@dataclass(frozen=True)
class Event:
    """A time known when the suite is loaded (at), or the first sample of a condition (when)."""

    text: str
    at: float | None = None
    when: Signal | None = None

    def time(self, run: RunSeries, end: float) -> float:
        if self.at is not None:
            return end if math.isinf(self.at) else self.at
        assert self.when is not None
        s = run.of(self.when)
        hit = np.flatnonzero(_true(s.x))
        if not hit.size:
            raise NoWindow(f"event {self.text!r} never came")
        return float(s.t[hit[0]])


@dataclass(frozen=True, kw_only=True)
class _WindowFields:
    event: str = spec("start")
    offset_s: float = spec(0.0)
    length_s: float | None = spec(None, gt=0.0)
    until: str | None = spec(None)

    def __post_init__(self) -> None:
        if self.length_s is not None and self.until is not None:
            raise ValueError("field 'until': give length_s or until, not both")


@dataclass(frozen=True)
class Window:
    start: Event
    offset_s: float
    length_s: float | None
    until: Event | None

    def bounds(self, run: RunSeries, end: float) -> tuple[float, float]:
        """(t_from, t_to) in this flight, end: its last sample's time."""
        t0 = self.start.time(run, end) + self.offset_s
        if self.length_s is not None:
            return t0, t0 + self.length_s
        return t0, self.until.time(run, end) if self.until is not None else end

    def describe(self) -> str:
        text = self.start.text if not self.offset_s else f"{self.start.text} {self.offset_s:+g} s"
        if self.length_s is not None:
            return f"{text}, for {self.length_s:g} s"
        return f"{text} until {self.until.text if self.until else 'end'}"


def _fault_time(match: re.Match[str], faults: Sequence[Fault], where: str) -> float:
    which, edge = match.group(1), match.group(2)
    if which.isdigit():
        if int(which) >= len(faults):
            raise WindowError(f"{where}: {match.group(0)!r}: the case flies {len(faults)} fault"
                              f"{'s' if len(faults) != 1 else ''} (fault[0] ... fault[{len(faults) - 1}])")
        return _edge(faults[int(which)], edge)
    fault = next((f for f in faults if f.kind == which), None)
    if fault is None:
        kinds = sorted({f.kind for f in faults})
        raise WindowError(f"{where}: {match.group(0)!r}: the case flies no {which} fault "
                          f"(its faults: {', '.join(kinds) or 'none'})")
    return _edge(fault, edge)


def _edge(fault: Fault, edge: str) -> float:
    return fault.start if edge == "start" else fault.end


def event(text: str, faults: Sequence[Fault], aircraft: Collection[str], where: str) -> Event:
    """start, end, fault[N|KIND].start|end, or a condition over series (WindowError)."""
    if text in ("start", "end"):
        return Event(text, at=0.0 if text == "start" else math.inf)
    match = _FAULT_EVENT.fullmatch(text)
    if match:
        return Event(text, at=_fault_time(match, faults, where))
    try:
        return Event(text, when=signal(text, aircraft))
    except SeriesError as e:
        raise WindowError(f"{where}: not an event (start, end, fault[N].start, fault[KIND].end, ... "
                          f"or a condition over series): {e}") from None


# ---- a windowed check --------------------------------------------------------------------------
@dataclass(frozen=True, kw_only=True)
class _CheckFields:
    signal: str = spec()
    measure: str = spec(choices=tuple(MEASURES))
    expect: str = spec()
    band: tuple[float, ...] = spec(default_factory=tuple)   # (): none
    target: float | None = spec(None)

    def __post_init__(self) -> None:
        takes = MEASURES[self.measure].params
        for name, given in (("band", bool(self.band)), ("target", self.target is not None)):
            if given and name not in takes:
                raise ValueError(f"field {name!r}: measure {self.measure!r} takes no {name}")
        if "band" in takes and not self.band:
            raise ValueError(f"missing field 'band' (measure {self.measure!r}: band = [low, high])")
        if self.band and (len(self.band) != 2 or self.band[0] > self.band[1]):
            raise ValueError(f"field 'band': [low, high] with low <= high, got {list(self.band)}")


@dataclass(frozen=True)
class Check:
    """A windowed check: the signal, the window, the measure and its parameters; the
    expectation over `value` (and result fields) is the suite's (hil.verify.expr)."""

    signal: Signal
    window: Window
    measure: str
    band: tuple[float, float] | None = None
    target: float | None = None

    def band_or_fail(self) -> tuple[float, float]:
        assert self.band is not None   # (checked at load: settling_time has one)
        return self.band

    def describe(self) -> str:
        extra = f", band [{self.band[0]:g}, {self.band[1]:g}]" if self.band else ""
        extra += f", target {self.target:g}" if self.target is not None else ""
        return f"{self.measure} of {self.signal.text} in [{self.window.describe()}]{extra}"


def check(raw: Mapping[str, Any], faults: Sequence[Fault], aircraft: Collection[str], duration: float,
          where: str) -> tuple[Check, str]:
    """A windowed expectation's table, checked: the check and its expectation's text
    (WindowError: one line naming the field)."""
    table = dict(raw)
    window_raw = table.pop("window", {})
    try:
        own = build(_CheckFields, table, where)
        if not isinstance(window_raw, Mapping):
            raise WindowError(f"{where}: field 'window': expected a table, got {window_raw!r}")
        w = build(_WindowFields, window_raw, f"{where}: window")
    except ScenarioError as e:
        raise WindowError(str(e)) from None
    try:
        sig = signal(own.signal, aircraft)
    except SeriesError as e:
        raise WindowError(f"{where}: field 'signal': {e}") from None
    start = event(w.event, faults, aircraft, f"{where}: window: field 'event'")
    until = event(w.until, faults, aircraft, f"{where}: window: field 'until'") if w.until else None
    if start.at is not None and not math.isinf(start.at) and not 0 <= start.at + w.offset_s < duration:
        raise WindowError(f"{where}: window: starts at {start.at + w.offset_s:g} s, outside the "
                          f"flight (0 to {duration:g} s)")
    if start.at is not None and math.isinf(start.at) and w.offset_s >= 0:
        raise WindowError(f"{where}: window: event 'end' needs offset_s < 0 (the last -offset_s "
                          "seconds of the flight)")
    band = (own.band[0], own.band[1]) if own.band else None
    return Check(sig, Window(start, w.offset_s, w.length_s, until), own.measure, band, own.target), own.expect


@dataclass(frozen=True)
class Measured:
    """A check's value and its evidence: the window, and the signal around it."""

    value: float
    t_from: float
    t_to: float
    series: Series


def measure(c: Check, run: RunSeries) -> Measured:
    """The check's value in this flight (NoWindow: its event never came, or the window holds
    no sample; SeriesError: the run has not got the signal)."""
    s = run.of(c.signal)
    if not s.t.size:
        raise NoWindow(f"no sample of {c.signal.text}")
    t_from, t_to = c.window.bounds(run, float(s.t[-1]))
    inside = (s.t >= t_from - 1e-9) & (s.t <= t_to + 1e-9)
    if not inside.any():
        raise NoWindow(f"no sample of {c.signal.text} in [{t_from:g}, {t_to:g}] s")
    value = MEASURES[c.measure].of(s.t[inside], s.x[inside], t_from, c)
    return Measured(value, t_from, t_to, s)


@dataclass(frozen=True)
class Windowed:
    """A windowed expectation of a case: the check, and the expectation over its value."""

    check: Check
    exp: Expectation

    @property
    def text(self) -> str:
        return f"{self.exp.text}, value = {self.check.describe()}"
