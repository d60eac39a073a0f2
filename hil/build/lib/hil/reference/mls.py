"""Moving-window least squares of [A_k B_k] (eqs. 5-7, 27-30), as firmware/sid/fcc_mls.h.

The window holds the last h transitions x_j -> x_{j+1} with regressor
phi_j = [alpha_j, q_j, de_j].  Both rows of [A B] share N = sum phi phi^T.
Ridge toward the prior: (N + ridge I) Theta = sum phi z^T + ridge Theta0.
Optional intercept (not in the paper): x_{j+1} = A x_j + B de_j + c; the
regression is then solved on the data centred on their window means (c is not
regularised): (Nc + ridge I) Theta = sum (phi - mean)(z - mean)^T + ridge Theta0,
c = mean(z) - Theta^T mean(phi).
Guards: the equilibrated normal matrix's 1-norm condition number must not
exceed max_cond, rho(A) must not exceed max_rho (0 = off); otherwise the last
good model is kept.  The reference sums the window afresh at every solve.
"""
from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field

import numpy as np

from hil.reference.model import Model, default_prior, spectral_radius

DEFAULT_WINDOW = 110
DEFAULT_MIN_TRANSITIONS = 20
DEFAULT_RIDGE = 1e-3
DEFAULT_MAX_COND = 1e6
DEFAULT_MAX_RHO = 1.2

OK = "ok"
SINGULAR = "singular"
RANGE = "range"
NOT_FINITE = "not_finite"


@dataclass
class MlsConfig:
    window: int = DEFAULT_WINDOW
    min_transitions: int = DEFAULT_MIN_TRANSITIONS
    ridge: float = DEFAULT_RIDGE
    max_cond: float = DEFAULT_MAX_COND
    max_rho: float = DEFAULT_MAX_RHO
    prior: Model = field(default_factory=default_prior)
    intercept: bool = False


def _theta_from_model(m: Model) -> np.ndarray:
    """Theta (3x2): column i holds the coefficients of output row i."""
    return np.vstack([m.a.T, m.b[None, :]])


def _model_from_theta(th: np.ndarray, c: np.ndarray | None = None) -> Model:
    return Model(th[:2, :].T.copy(), th[2, :].copy(),
                 np.zeros(2) if c is None else np.asarray(c, dtype=float).copy())


def effective_prior(cfg: MlsConfig) -> Model:
    """The prior as the MLS reports it: without intercept its c is dropped."""
    m = cfg.prior.copy()
    if not cfg.intercept:
        m.c = np.zeros(2)
    return m


class Mls:
    """The estimator: push transitions, solve, read .model / .se / .rho."""

    def __init__(self, cfg: MlsConfig | None = None) -> None:
        self.cfg = cfg or MlsConfig()
        self.window: deque[np.ndarray] = deque(maxlen=self.cfg.window)
        self.model = effective_prior(self.cfg)
        self.se = np.full(6, -1.0)
        self.rho = spectral_radius(self.model.a)
        self.cond = 0.0
        self.is_prior = True

    @property
    def n_transitions(self) -> int:
        return len(self.window)

    def push(self, x: np.ndarray, de: float, x_next: np.ndarray) -> None:
        self.window.append(np.array([x[0], x[1], de, x_next[0], x_next[1]], dtype=float))

    def update(self, x: np.ndarray, de: float, x_next: np.ndarray) -> str:
        self.push(x, de, x_next)
        return self.solve()

    def solve(self) -> str:
        cfg = self.cfg
        if len(self.window) < cfg.min_transitions:
            self.model = effective_prior(cfg)
            self.se = np.full(6, -1.0)
            self.rho = spectral_radius(self.model.a)
            self.is_prior = True
            return OK
        data = np.asarray(self.window)
        phi, z = data[:, :3], data[:, 3:]
        if cfg.intercept:
            phi_mean, z_mean = phi.mean(axis=0), z.mean(axis=0)
            phi, z = phi - phi_mean, z - z_mean
        n = phi.T @ phi
        nr = n + cfg.ridge * np.eye(3)
        rhs = phi.T @ z + cfg.ridge * _theta_from_model(cfg.prior)
        if np.any(np.diag(nr) <= 0.0):
            return SINGULAR
        d = 1.0 / np.sqrt(np.diag(nr))
        s = d[:, None] * nr * d[None, :]
        try:
            np.linalg.cholesky(s)
        except np.linalg.LinAlgError:
            return SINGULAR
        cond = float(np.linalg.cond(s, 1))
        if not cond <= cfg.max_cond:
            return SINGULAR
        th = np.linalg.solve(nr, rhs)
        c = z_mean - th.T @ phi_mean if cfg.intercept else np.zeros(2)
        if not (np.all(np.isfinite(th)) and np.all(np.isfinite(c))):
            return NOT_FINITE
        model = _model_from_theta(th, c)
        rho = spectral_radius(model.a)
        if cfg.max_rho > 0.0 and rho > cfg.max_rho:
            return RANGE
        nr_inv_diag = np.diag(np.linalg.inv(nr))
        m = len(self.window)
        n_par = 4 if cfg.intercept else 3
        se = np.full(6, -1.0)
        if m > n_par:
            resid = z - phi @ th
            var = np.sum(resid**2, axis=0) / (m - n_par)
            for i in range(2):
                sd = np.sqrt(var[i] * nr_inv_diag)
                se[2 * i], se[2 * i + 1], se[4 + i] = sd[0], sd[1], sd[2]
        self.model, self.se, self.rho, self.cond, self.is_prior = model, se, rho, cond, False
        return OK


def batch_fit(x: np.ndarray, de: np.ndarray, x_next: np.ndarray, ridge: float = 0.0,
              prior: Model | None = None, intercept: bool = False) -> Model:
    """Independent batch least squares of eq. (30) by numpy's lstsq.

    The ridge toward the prior is written as three pseudo-observations
    sqrt(ridge) e_j -> sqrt(ridge) Theta0_j appended to the regression; the
    intercept, when asked for, is a column of ones that the ridge leaves free.
    """
    phi = np.column_stack([x[:, 0], x[:, 1], de])
    z = np.asarray(x_next, dtype=float)
    if intercept:
        phi = np.column_stack([phi, np.ones(len(phi))])
    if ridge > 0.0:
        prior = prior or default_prior()
        pseudo = np.sqrt(ridge) * np.eye(3)
        if intercept:
            pseudo = np.column_stack([pseudo, np.zeros(3)])
        phi = np.vstack([phi, pseudo])
        z = np.vstack([z, np.sqrt(ridge) * _theta_from_model(prior)])
    th, *_ = np.linalg.lstsq(phi, z, rcond=None)
    return _model_from_theta(th[:3], th[3] if intercept else None)
