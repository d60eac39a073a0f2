"""Requirements over many flights: a case with ``flights = N`` flies N flights (seeds seed,
seed + 1, ...) and judges each of its expectations over all of them, with its confidence
interval (hil.verify.stats):

    [[case]]
    id = "azkf-beats-kf"
    aircraft = ["cdrw"]
    flights = 100
    [case.expect]
    SID-STAT-1 = [
      { share = "azkf.alpha.error_integral_truth < kf.alpha.error_integral_truth", expect = "lo >= 0.9" }]
    RT-STAT-1 = [{ percentile = 99, of = "realtime.latency_p99_us", expect = "hi < 5000" }]

* ``share``: an expectation judged on every flight; ``value`` is the share of flights that
  hold it, ``lo`` and ``hi`` its interval (``method`` wilson, the default, or
  clopper-pearson);
* ``percentile`` (0-100) ``of`` a per-flight figure (an expression over fields): ``value``
  is that percentile over the flights, ``lo`` and ``hi`` its bootstrap interval;
* ``confidence``: the interval's level (default 0.95); ``expect``: over ``value``, ``lo``,
  ``hi`` (and ``n``, the flights).  Writing ``lo >= 0.95`` asks for the share demonstrated at
  that confidence; ``value >= 0.95`` for the share observed.
"""
from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from hil.util.errors import HilError
from hil.verify.expr import Expectation, evaluate, measured
from hil.verify.fields import values
from hil.verify.stats import Interval, bootstrap_percentile, clopper_pearson, wilson

#: the names an over-flights expectation's `expect` may use
NAMES = ("value", "lo", "hi", "n")
METHODS: dict[str, Callable[[int, int, float], Interval]] = {"wilson": wilson, "clopper-pearson": clopper_pearson}
KEYS = ("share", "percentile", "of", "expect", "confidence", "method")
#: flights a case may ask for
MAX_FLIGHTS = 1000


class StatisticalError(HilError, ValueError):
    """An over-flights expectation that cannot be judged as written (one line)."""


@dataclass(frozen=True)
class OverFlights:
    """One expectation over a case's flights: a share of flights (per-flight `per`, a
    comparison) or a percentile of a per-flight figure (`per`, a number), and `exp` over
    value/lo/hi/n."""

    kind: str                 # "share" or "percentile"
    per: Expectation
    exp: Expectation
    level: float = 0.95
    method: str = "wilson"
    q: float = 0.0

    @property
    def text(self) -> str:
        what = (f"share of flights with {self.per.text}" if self.kind == "share"
                else f"p{self.q:g} over flights of {self.per.text}")
        return f"{what}: {self.exp.text}"

    def interval(self, runs: Sequence[Mapping[str, Any]]) -> Interval:
        per = [evaluate(self.per.tree, values(run, self.per.fields)) for run in runs]
        if self.kind == "share":
            return METHODS[self.method](sum(bool(v) for v in per), len(per), self.level)
        return bootstrap_percentile([float(v) for v in per], self.q, self.level)

    def judge(self, runs: Sequence[Mapping[str, Any]]) -> tuple[bool, str]:
        """(holds, what was measured: the expectation's values and the interval in words)."""
        iv = self.interval(runs)
        vals = {"value": iv.estimate, "lo": iv.lo, "hi": iv.hi, "n": float(len(runs))}
        ok = bool(evaluate(self.exp.tree, vals))
        scale, unit = (100.0, "%") if self.kind == "share" else (1.0, "")
        return ok, f"{measured(self.exp, vals)}; {iv.describe(unit, scale)} over {len(runs)} flights"


def build(raw: Mapping[str, Any], where: str, parse: Callable[[str, str, tuple[str, ...]], Expectation]) -> OverFlights:
    """An over-flights expectation from its table; parse(where, text, extra names) checks an
    expression as the suite checks every expectation (fields documented and available)."""
    unknown = sorted(set(raw) - set(KEYS))
    if unknown:
        raise StatisticalError(f"{where}: unknown key(s) {', '.join(unknown)} (an expectation over flights "
                               f"has {', '.join(KEYS)})")
    if ("share" in raw) == ("percentile" in raw):
        raise StatisticalError(f"{where}: name one of 'share' (an expectation per flight) or 'percentile' "
                               f"(with 'of')")
    level = raw.get("confidence", 0.95)
    if not isinstance(level, (int, float)) or isinstance(level, bool) or not 0.5 <= level < 1:
        raise StatisticalError(f"{where}: field 'confidence': a level from 0.5 to below 1, got {level!r}")
    method = raw.get("method", "wilson")
    if method not in METHODS or ("percentile" in raw and "method" in raw):
        raise StatisticalError(f"{where}: field 'method': {' or '.join(METHODS)} (for a share; a percentile's "
                               f"interval is the bootstrap's), got {method!r}")
    if not isinstance(raw.get("expect"), str):
        raise StatisticalError(f"{where}: field 'expect': an expectation over {', '.join(NAMES)}")
    exp = parse(f"{where}: field 'expect'", raw["expect"], NAMES)
    if not exp.fields & {"value", "lo", "hi"} or exp.fields - set(NAMES):
        raise StatisticalError(f"{where}: field 'expect': {raw['expect']!r}: over value, lo, hi (and n) only")
    if "share" in raw:
        if not isinstance(raw["share"], str) or "of" in raw:
            raise StatisticalError(f"{where}: field 'share': an expectation judged on every flight (no 'of')")
        return OverFlights("share", parse(f"{where}: field 'share'", raw["share"], ()), exp, float(level), method)
    q = raw["percentile"]
    if not isinstance(q, (int, float)) or isinstance(q, bool) or not 0 <= q <= 100:
        raise StatisticalError(f"{where}: field 'percentile': 0 to 100, got {q!r}")
    if not isinstance(raw.get("of"), str):
        raise StatisticalError(f"{where}: field 'of': the per-flight figure (an expression over fields)")
    return OverFlights("percentile", parse(f"{where}: field 'of'", raw["of"], ()), exp, float(level), "", float(q))
