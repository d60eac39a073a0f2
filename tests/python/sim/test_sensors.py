"""CDRW sensors: bounded, non-Gaussian noise within SPEC's F = 0.02 I."""
from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from hil.scenario.file import load_default_scenario
from hil.sim.cdrw_flight import simulate_cdrw
from hil.scenario.sensor_options import NOISE_DISTRIBUTIONS, CdrwSensorOptions
from hil.sim.sensors import CdrwSensors, bounded_noise


@pytest.mark.parametrize("dist", NOISE_DISTRIBUTIONS)
def test_noise_is_bounded_zero_mean_and_not_gaussian(dist):
    rng = np.random.default_rng(7)
    w = np.array([bounded_noise(rng, dist, 0.02) for _ in range(20000)])
    assert np.max(np.abs(w)) <= 0.02
    assert abs(w.mean()) < 3 * w.std() / np.sqrt(w.size)
    assert w.std() > 0.004                     # not degenerate
    # a Gaussian of the same variance would exceed the bound; these have lighter tails
    assert stats.kurtosis(w) < -0.3
    near_bound = 0.7 if dist == "triangular" else 0.9   # the whole box is used
    assert np.max(np.abs(w)) > near_bound * 0.02


def test_uniform_default_matches_spec_F():
    o = CdrwSensorOptions()
    assert o.distribution == "uniform" and o.bound == (0.02, 0.02)
    s = CdrwSensors(seed=1)
    r = [s.measure(0.15, 0.01, -0.04) for _ in range(5000)]
    a = np.array([m["alpha"] for m in r]) - 0.15
    q = np.array([m["q"] for m in r]) - 0.01
    d = np.array([m["de"] for m in r]) + 0.04
    assert np.max(np.abs(a)) <= 0.02 and np.max(np.abs(q)) <= 0.02 and np.max(np.abs(d)) <= 0.001
    assert a.std() == pytest.approx(0.02 / np.sqrt(3), rel=0.05)      # uniform
    assert stats.kstest(a, stats.uniform(loc=-0.02, scale=0.04).cdf).pvalue > 0.01


def test_flight_noise_bounds_hold():
    f = simulate_cdrw(load_default_scenario("cdrw").replace(faults=()))
    assert np.max(np.abs(f.alpha_meas - f.alpha_true)) <= 0.02
    assert np.max(np.abs(f.q_meas - f.q_true)) <= 0.02
    assert np.max(np.abs(f.de - f.de_true)) <= 0.001


def test_bad_options_refused():
    with pytest.raises(ValueError, match="distribution"):
        CdrwSensorOptions(distribution="gauss")
    with pytest.raises(ValueError, match=">= 0"):
        CdrwSensorOptions(bound=(-0.1, 0.02))
