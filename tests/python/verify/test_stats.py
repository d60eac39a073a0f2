"""The confidence intervals of requirements over many flights (hil.verify.stats), against
published values: Wilson and Clopper-Pearson for 95 of 100 (Brown, Cai & DasGupta 2001 give
the method; scipy's binomtest computes both), and the bootstrap's behaviour."""
from __future__ import annotations

import pytest
from scipy.stats import binomtest

from hil.verify.stats import bootstrap_percentile, clopper_pearson, wilson


@pytest.mark.parametrize("k, n", [(95, 100), (0, 10), (10, 10), (17, 20), (1, 3)])
def test_wilson_and_clopper_pearson_agree_with_scipys_binomtest(k, n) -> None:
    for ours, method in ((wilson(k, n), "wilson"), (clopper_pearson(k, n), "exact")):
        ref = binomtest(k, n).proportion_ci(0.95, method=method)
        assert ours.estimate == k / n
        assert ours.lo == pytest.approx(ref.low, abs=1e-9) and ours.hi == pytest.approx(ref.high, abs=1e-9)


def test_ninety_five_of_a_hundred_does_not_prove_ninety_five_percent() -> None:
    """The interval, not the share, decides: 95/100 has a lower bound near 0.89."""
    w = wilson(95, 100)
    assert 0.888 < w.lo < 0.889 and 0.978 < w.hi < 0.979
    assert clopper_pearson(100, 100).lo == pytest.approx(0.025 ** (1 / 100), rel=1e-9)   # (a/2)^(1/n): 0.9638
    assert w.describe("%", 100) == "95% (Wilson 95%: 88.82% to 97.85%)"


def test_a_bootstrap_interval_contains_the_sample_percentile_and_is_reproducible() -> None:
    x = [float(v) for v in range(1, 101)]
    a, b = bootstrap_percentile(x, 99), bootstrap_percentile(x, 99)
    assert a == b and a.lo <= a.estimate <= a.hi and a.hi <= 100.0 and a.lo >= 90.0
    assert bootstrap_percentile([5.0] * 20, 99).lo == bootstrap_percentile([5.0] * 20, 99).hi == 5.0
    with pytest.raises(ValueError):
        bootstrap_percentile([], 50)
    with pytest.raises(ValueError):
        wilson(3, 2)
