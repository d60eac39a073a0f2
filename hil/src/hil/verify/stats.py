"""Confidence intervals for requirements over many flights (issue 37, item 3).

* a share of flights (\"AZKF's α error below the KF's in >= 95 % of 100 flights\"): the
  observed k of n with its Wilson score interval and its exact Clopper-Pearson interval
  (binomial; Clopper-Pearson never undercovers, Wilson is closer to nominal on average);
* a percentile of a per-flight figure (\"p99 latency over 20 realtime flights\"): the sample
  percentile with a percentile-bootstrap interval (resampling the flights, a fixed seed: the
  same flights give the same interval).

A requirement over flights holds only when its whole interval is on the right side of the
bound: the verdict is about the device, not about this sample of flights.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy import stats as sstats

#: the bootstrap's resamples and its seed (reproducible intervals)
BOOTSTRAP_RESAMPLES = 2000
BOOTSTRAP_SEED = 37


@dataclass(frozen=True)
class Interval:
    estimate: float
    lo: float
    hi: float
    method: str
    level: float

    def describe(self, unit: str = "", scale: float = 1.0) -> str:
        lo, est, hi = (f"{x * scale:.4g}{unit}" for x in (self.lo, self.estimate, self.hi))
        return f"{est} ({self.method} {self.level:.0%}: {lo} to {hi})"


def _z(level: float) -> float:
    return float(sstats.norm.ppf(0.5 + level / 2))


def wilson(k: int, n: int, level: float = 0.95) -> Interval:
    """Wilson's score interval of a binomial proportion k/n."""
    if n <= 0 or not 0 <= k <= n:
        raise ValueError(f"a proportion needs 0 <= k <= n, n > 0 (got {k}/{n})")
    z = _z(level)
    p = k / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z / (1 + z * z / n) * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return Interval(p, max(0.0, centre - half), min(1.0, centre + half), "Wilson", level)


def clopper_pearson(k: int, n: int, level: float = 0.95) -> Interval:
    """The exact (Clopper-Pearson) interval of a binomial proportion k/n."""
    if n <= 0 or not 0 <= k <= n:
        raise ValueError(f"a proportion needs 0 <= k <= n, n > 0 (got {k}/{n})")
    a = 1 - level
    lo = 0.0 if k == 0 else float(sstats.beta.ppf(a / 2, k, n - k + 1))
    hi = 1.0 if k == n else float(sstats.beta.ppf(1 - a / 2, k + 1, n - k))
    return Interval(k / n, lo, hi, "Clopper-Pearson", level)


def bootstrap_percentile(samples: Sequence[float], q: float, level: float = 0.95,
                         resamples: int = BOOTSTRAP_RESAMPLES, seed: int = BOOTSTRAP_SEED) -> Interval:
    """The q-th percentile (0-100) of the samples and its percentile-bootstrap interval."""
    x = np.asarray(samples, dtype=float)
    if x.size == 0 or not np.all(np.isfinite(x)):
        raise ValueError("a percentile needs finite samples")
    rng = np.random.default_rng(seed)
    boot = np.percentile(x[rng.integers(0, x.size, size=(resamples, x.size))], q, axis=1)
    a = (1 - level) / 2
    return Interval(float(np.percentile(x, q)), float(np.quantile(boot, a)), float(np.quantile(boot, 1 - a)),
                    "bootstrap", level)
