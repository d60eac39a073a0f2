"""The identified model x_{k+1} = A x + B de (+ c) and its 2x2 facts (eq. 26, gain norm)."""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np


@dataclass
class Model:
    """A (2x2), B (2,) of the discrete short-period model (eq. 3) and the optional
    affine term c (2,): x_{k+1} = A x_k + B de_k + c.  c = 0 is the paper's model."""

    a: np.ndarray = field(default_factory=lambda: np.eye(2))
    b: np.ndarray = field(default_factory=lambda: np.zeros(2))
    c: np.ndarray = field(default_factory=lambda: np.zeros(2))

    @staticmethod
    def from_flat(v: np.ndarray | Sequence[float]) -> Model:
        """From (a11, a12, a21, a22, b1, b2[, c1, c2]), the order of the CSV columns."""
        v = np.asarray(v, dtype=float)
        c = v[6:8].copy() if len(v) >= 8 else np.zeros(2)
        return Model(v[:4].reshape(2, 2).copy(), v[4:6].copy(), c)

    def flat(self) -> np.ndarray:
        """(a11, a12, a21, a22, b1, b2): the paper's six parameters."""
        return np.concatenate([self.a.ravel(), self.b])

    def flat8(self) -> np.ndarray:
        """(a11, ..., b2, c1, c2)."""
        return np.concatenate([self.a.ravel(), self.b, self.c])

    def copy(self) -> Model:
        return Model(self.a.copy(), self.b.copy(), self.c.copy())

    def predict(self, x: np.ndarray, de: float) -> np.ndarray:
        return self.a @ x + self.b * de + self.c


# The CDRW's wind-tunnel model at trim (hil.sim.cdrw_prior.wind_tunnel_prior(): static
# separation X = X0(alpha), the paper's Euler form, dt = 0.02 s, alpha* = 9 deg,
# de* = -0.042105 rad).  The paper's regression has no constant term, so its prior is the
# affine model with the trim offset c0 absorbed into [A B] by the smallest change that makes
# the trim a fixed point (what a least-squares fit without intercept converges to at trim).
# tests/python/reference/test_sid_cdrw.py checks these digits against the plant.
PRIOR_PAPER = (0.989307, 0.018740, -0.540133, 0.873259, -0.039892, -2.015052)
PRIOR_AFFINE = (0.895757, 0.018740, -1.001991, 0.873259, -0.014816, -1.891251,
                0.015751, 0.077761)


def default_prior() -> Model:
    """Same prior as fcc_sid_default_prior (the paper's form, no intercept)."""
    return Model.from_flat(PRIOR_PAPER)


def default_prior_affine() -> Model:
    """Same prior as fcc_sid_default_prior_affine (for the optional intercept)."""
    return Model.from_flat(PRIOR_AFFINE)


def spectral_radius(a: np.ndarray) -> float:
    """rho(A) = max |lambda_i| (eq. 26), by numpy's eigen-solver."""
    return float(np.max(np.abs(np.linalg.eigvals(a))))


def norm2(m: np.ndarray) -> float:
    """Largest singular value."""
    return float(np.linalg.norm(m, 2))
