"""The identified model x_{k+1} = A x_k + B de_k and its 2x2 facts (eq. 26, gain norm)."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class Model:
    """A (2x2) and B (2,) of the discrete short-period model (eq. 3)."""

    a: np.ndarray = field(default_factory=lambda: np.eye(2))
    b: np.ndarray = field(default_factory=lambda: np.zeros(2))

    @staticmethod
    def from_flat(v: "np.ndarray | list[float]") -> "Model":
        """From (a11, a12, a21, a22, b1, b2), the order of the CSV columns."""
        v = np.asarray(v, dtype=float)
        return Model(v[:4].reshape(2, 2).copy(), v[4:6].copy())

    def flat(self) -> np.ndarray:
        return np.concatenate([self.a.ravel(), self.b])

    def copy(self) -> "Model":
        return Model(self.a.copy(), self.b.copy())


def default_prior() -> Model:
    """Same representative prior as fcc_sid_default_prior (Euler, dt = 0.02 s)."""
    return Model(np.array([[0.97, 0.02], [-0.4, 0.94]]), np.array([-0.004, -0.6]))


def spectral_radius(a: np.ndarray) -> float:
    """rho(A) = max |lambda_i| (eq. 26), by numpy's eigen-solver."""
    return float(np.max(np.abs(np.linalg.eigvals(a))))


def norm2(m: np.ndarray) -> float:
    """Largest singular value."""
    return float(np.linalg.norm(m, 2))
