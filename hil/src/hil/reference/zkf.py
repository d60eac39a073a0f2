"""Zonotopic Kalman filter (eqs. 19-25), AZKF (Algorithm 1, SPEC erratum) and the
fault detector, as firmware/sid/fcc_zkf.h, fcc_azkf.h and fcc_fault.h (C = I)."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from hil.reference.model import Model, norm2
from hil.reference.zonotope import hull, reduce_order

ZONOTOPE, ORACLE, OFF = "zonotope", "oracle", "off"
POLICY_ORDER, POLICY_SKIP = "order", "skip"


class Zkf:
    """State set <x, P>; one combined predict-correct step of a given order."""

    def __init__(self, x0: np.ndarray, p0_gen: np.ndarray, e: np.ndarray, f: np.ndarray) -> None:
        self.x = np.array(x0, dtype=float)
        self.gen = np.array(p0_gen, dtype=float)
        self.e = np.asarray(e, dtype=float)
        self.f = np.asarray(f, dtype=float)
        self.r = self.f @ self.f.T
        self.gain = np.zeros((2, 2))
        #: the last step's posterior: x_k|k, hull radii of its set, ||G'_k||
        self.post_x = self.x.copy()
        self.post_hull = hull(self.gen)
        self.post_gain = 0.0

    def output_radius(self) -> np.ndarray:
        """Hull radius of <C x, [C P, F]>."""
        return hull(self.gen) + hull(self.f)

    def step(self, model: Model, de: float, y: np.ndarray | None, q: int) -> tuple[float, int]:
        """Returns (||G||, columns of P_bar)."""
        a = model.a
        pbar = reduce_order(self.gen, q)                               # (17-18)
        m = pbar @ pbar.T
        x_new = a @ self.x + model.b * de + model.c
        g = np.zeros((2, 2))
        self.post_x, self.post_hull, self.post_gain = self.x.copy(), hull(self.gen), 0.0
        if y is not None:
            g = a @ m @ np.linalg.inv(m + self.r)                      # (25)
            x_new = x_new + g @ (np.asarray(y) - self.x)               # (22)
            # the estimate after y_k: G' = M (M + R)^-1, G = A G'
            gp = m @ np.linalg.inv(m + self.r)
            self.post_x = self.x + gp @ (np.asarray(y) - self.x)
            self.post_hull = hull(np.hstack([(np.eye(2) - gp) @ pbar, -gp @ self.f]))
            self.post_gain = norm2(gp)
        cols = [(a - g) @ pbar, self.e]                                # (24)
        if y is not None:
            cols.append(-g @ self.f)
        self.gen = np.hstack(cols)
        self.x, self.gain = x_new, g
        return (norm2(g) if y is not None else 0.0), pbar.shape[1]


@dataclass
class DetectorConfig:
    mode: str = ZONOTOPE
    margin: float = 2.5
    raise_count: int = 1
    hold_count: int = 0
    clear_count: int = 3
    max_fault_steps: int = 10


class Detector:
    """Set-membership fault detector with raise / hold / clear counts."""

    def __init__(self, cfg: DetectorConfig | None = None) -> None:
        self.cfg = cfg or DetectorConfig()
        self.fault = False
        self.n_bad = 0
        self.n_good = 0
        self.hold_left = 0
        self.fault_steps = 0
        self.refractory_left = 0

    def step(self, innov: np.ndarray, radius: np.ndarray, oracle: bool) -> bool:
        cfg = self.cfg
        if cfg.mode == OFF:
            self.fault = False
            return False
        if cfg.mode == ORACLE:
            self.fault = bool(oracle)
            return self.fault
        bad = bool(np.any(~(np.abs(innov) <= cfg.margin * radius)))
        self.n_bad = self.n_bad + 1 if bad else 0
        self.n_good = 0 if bad else self.n_good + 1
        if not self.fault:
            if self.refractory_left > 0:
                self.refractory_left -= 1
            elif self.n_bad >= cfg.raise_count:
                self.fault, self.hold_left, self.n_good = True, cfg.hold_count, 0
                self.fault_steps = 1
            return self.fault
        if cfg.max_fault_steps > 0 and self.fault_steps >= cfg.max_fault_steps:
            self.fault, self.refractory_left, self.n_bad = False, cfg.max_fault_steps, 0
            return self.fault
        self.fault_steps += 1
        if self.hold_left > 0:
            self.hold_left -= 1
            self.n_good = 0
            return self.fault
        if self.n_good >= cfg.clear_count:
            self.fault, self.n_bad = False, 0
        return self.fault


@dataclass
class AzkfConfig:
    q_normal: int = 2
    q_fault: int = 1000
    policy: str = POLICY_ORDER
    det: DetectorConfig = field(default_factory=DetectorConfig)


class Azkf:
    """ZKF whose order (or update) follows the fault detector."""

    def __init__(self, cfg: AzkfConfig, x0: np.ndarray, p0_gen: np.ndarray, e: np.ndarray,
                 f: np.ndarray) -> None:
        self.cfg = cfg
        self.zkf = Zkf(x0, p0_gen, e, f)
        self.det = Detector(cfg.det)

    def step(self, model: Model, de: float, y: np.ndarray | None, oracle: bool,
             armed: bool = True) -> tuple[float, int, int, bool]:
        """Returns (||G||, order used, columns of P_bar, fault flag).

        armed False: no detection and no fault (model still the prior)."""
        if not armed:
            self.det.fault = False
        fault = self.det.fault
        if y is not None and armed:
            innov = np.asarray(y) - self.zkf.x
            fault = self.det.step(innov, self.zkf.output_radius(), oracle)
        skip = fault and self.cfg.policy == POLICY_SKIP
        q = self.cfg.q_fault if (fault and self.cfg.policy == POLICY_ORDER) else self.cfg.q_normal
        gnorm, ncols = self.zkf.step(model, de, None if skip else y, q)
        return gnorm, q, ncols, fault
