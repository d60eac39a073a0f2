"""Sensor models of both aircraft (noise only; faults are applied on top by hil.sim.sensor_faults).

CDRW (seed 1): alpha vane, pitch-rate gyro and elevator (elevon) position pick-off.  The
paper's filters assume *bounded* noise, |w| <= F with F = 0.02 I (a zonotope, not a
Gaussian), so the noise here is bounded and non-Gaussian: uniform (default) or triangular
on [-bound, +bound], or a normal truncated at +-bound (sigma = bound/2).  The default bounds
are exactly F's: 0.02 rad on alpha and 0.02 rad/s on q.  The elevator pick-off has a much
smaller bound (1 mrad ~ 0.06 deg, a servo potentiometer).

Missile (seed 2): rate gyro q_g = q + v_g and accelerometer n_a = -26.74 q - 568.4 alpha_T
+ v_a, white Gaussian with the paper's variances (0.8 rad^2/s^2 and 0.8 ft^2/s^4; the first
looks large but is what the paper prints, SPEC keeps it as the default).

Each sensor set draws from its own random stream, derived from the scenario seed, so the
noise realisation does not depend on anything else the simulator does (faults, control).
"""
from __future__ import annotations

import math

import numpy as np

from hil.scenario.sensor_options import CdrwSensorOptions, MissileSensorOptions
from hil.sim import missile


def bounded_noise(rng: np.random.Generator, distribution: str, bound: float) -> float:
    """One sample of zero-mean noise with |w| <= bound."""
    if bound == 0.0:
        return 0.0
    if distribution == "uniform":
        return float(rng.uniform(-bound, bound))
    if distribution == "triangular":
        return float(0.5 * bound * (rng.uniform(-1.0, 1.0) + rng.uniform(-1.0, 1.0)))
    if distribution == "truncated_normal":
        while True:  # rejection: ~1.05 draws per sample at +-2 sigma
            w = float(rng.normal(0.0, 0.5 * bound))
            if abs(w) <= bound:
                return w
    raise ValueError(f"unknown noise distribution {distribution!r}")


class CdrwSensors:
    """alpha, q and elevator measurements of the CDRW with bounded noise."""

    def __init__(self, seed: int, options: CdrwSensorOptions = CdrwSensorOptions()) -> None:
        self.options = options
        self._rng = np.random.default_rng([int(seed), 0x7365])  # own stream: "se"

    def measure(self, alpha: float, q: float, de: float) -> dict[str, float]:
        """One 50 Hz sample: {'alpha': rad, 'q': rad/s, 'de': rad}."""
        o = self.options
        w_a = bounded_noise(self._rng, o.distribution, o.bound[0])
        w_q = bounded_noise(self._rng, o.distribution, o.bound[1])
        w_d = bounded_noise(self._rng, o.distribution, o.de_bound)
        return {"alpha": alpha + w_a, "q": q + w_q, "de": de + w_d}


class MissileSensors:
    """Rate gyro and accelerometer of the missile with white Gaussian noise."""

    def __init__(self, seed: int, options: MissileSensorOptions = MissileSensorOptions()) -> None:
        self.options = options
        self._sd = (options.noise_scale * math.sqrt(options.var_gyro),
                    options.noise_scale * math.sqrt(options.var_acc))
        self._rng = np.random.default_rng([int(seed), 0x736D])  # own stream: "sm"

    def measure(self, x: np.ndarray) -> dict[str, float]:
        """One sample at the state x = [q, alpha_T, w_g]: {'q_g': rad/s, 'n_a': ft/s^2}."""
        y = missile.H @ np.asarray(x, dtype=float)
        v = self._rng.standard_normal(2)
        return {"q_g": float(y[0] + self._sd[0] * v[0]), "n_a": float(y[1] + self._sd[1] * v[1])}
