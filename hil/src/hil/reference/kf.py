"""Kalman filter of MLS-KF (eqs. 10-14, C = I), as firmware/sid/fcc_kf.h."""
from __future__ import annotations

import numpy as np

from hil.reference.model import Model, norm2


class Kf:
    """x, p: posterior.  The first step updates the prior without predicting."""

    def __init__(self, x0: np.ndarray, p0: np.ndarray, e: np.ndarray, f: np.ndarray) -> None:
        self.x = np.array(x0, dtype=float)
        self.p = np.array(p0, dtype=float)
        self.q = e @ e.T
        self.r = f @ f.T
        self.started = False
        self.gain = np.zeros((2, 2))
        self.prior_x, self.prior_p = self.x.copy(), self.p.copy()   # before the last y_k

    def step(self, model: Model, de_prev: float, y: np.ndarray | None) -> float:
        """Predict (unless first) and update with y (None: no measurement).  Returns ||K||."""
        x, p = self.x, self.p
        if self.started:
            x = model.a @ x + model.b * de_prev + model.c           # (10)
            p = model.a @ p @ model.a.T + self.q                      # (11)
        k = np.zeros((2, 2))
        self.prior_x, self.prior_p = x.copy(), p.copy()
        if y is not None:
            k = p @ np.linalg.inv(p + self.r)                         # (12)
            x = x + k @ (np.asarray(y) - x)                           # (13)
            p = (np.eye(2) - k) @ p                                   # (14)
            p = 0.5 * (p + p.T)
        self.x, self.p, self.gain, self.started = x, p, k, True
        return norm2(k) if y is not None else 0.0

    def bounds(self, prior: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """+- 3 sigma of the posterior (prior: of the last step's prediction)."""
        x, p = (self.prior_x, self.prior_p) if prior else (self.x, self.p)
        s = 3.0 * np.sqrt(np.diag(p))
        return x - s, x + s
