"""One identification loop (MLS closed with KF, ZKF or AZKF) and the replay of a
flight, with the row semantics of firmware/sid/fcc_sid.h and sid_replay
(SidConfig.rows, sid_replay --rows):

* "paper" (default): KF row k: posterior after y_k (step 0 updates x0, P0 without
  predicting), bounds +/- 3 sigma, order 0, fault 0.  ZKF / AZKF row k: x_k before
  y_k is used, the hull of <x_k, P_k>, the gain and order of step k.
* "posterior": every filter after y_k; ZKF/AZKF x_k|k = x_k + G'(y_k - x_k),
  G' = M (M + R)^-1 (M = P_bar P_bar^T), the hull of [(I - G') P_bar, -G' F], ||G'||.
* "prior": every filter before y_k; KF x-_k with +/- 3 sigma of P-_k, ||K_k||.
* In each mode the MLS learns from the states the rows report.
* Model columns: the model used in the step (c1, c2 too with the MLS
  intercept: columns(cfg)).  A transition is learnt by the
  MLS only when both its ends were corrected by a measurement (AZKF: and no
  fault flagged, when mls_hold_on_fault).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from hil.reference.kf import Kf
from hil.reference.mls import Mls, MlsConfig
from hil.reference.model import Model, spectral_radius
from hil.reference.zkf import Azkf, AzkfConfig, Zkf
from hil.reference.zonotope import hull

FILTERS = ("kf", "zkf", "azkf")
ROWS = ("paper", "prior", "posterior")
COLUMNS = ("t", "filter", "alpha_hat", "q_hat", "alpha_lo", "alpha_hi", "q_lo", "q_hi",
           "gain_norm", "order", "fault", "a11", "a12", "a21", "a22", "b1", "b2", "rho")
INTERCEPT_COLUMNS = ("c1", "c2")


def columns(intercept: bool = False) -> tuple[str, ...]:
    """sid_replay's header: the c1, c2 columns only with the MLS intercept."""
    return COLUMNS + (INTERCEPT_COLUMNS if intercept else ())


@dataclass
class SidConfig:
    """Paper values and the firmware's documented defaults."""

    x0: np.ndarray = field(default_factory=lambda: np.array([0.1571, 0.0204]))
    p0: np.ndarray = field(default_factory=lambda: 0.1 * np.eye(2))
    e: np.ndarray = field(default_factory=lambda: 0.004 * np.eye(2))
    f: np.ndarray = field(default_factory=lambda: 0.02 * np.eye(2))
    mls_enabled: bool = True
    mls_hold_on_fault: bool = True
    arm_on_prior: bool = True
    mls: MlsConfig = field(default_factory=MlsConfig)
    zkf_order: int = 1000
    azkf: AzkfConfig = field(default_factory=AzkfConfig)
    alpha_limit: float = 1.5707963
    q_limit: float = 10.0
    de_limit: float = 1.0
    rows: str = "paper"


class SidLoop:
    """MLS-KF, MLS-ZKF or MLS-AZKF."""

    def __init__(self, kind: str, cfg: SidConfig | None = None) -> None:
        if kind not in FILTERS:
            raise ValueError(f"unknown filter {kind!r}")
        if (cfg or SidConfig()).rows not in ROWS:
            raise ValueError(f"unknown rows {(cfg or SidConfig()).rows!r}")
        self.kind = kind
        self.cfg = cfg or SidConfig()
        self.mls = Mls(self.cfg.mls)
        c = self.cfg
        if kind == "kf":
            self.filt: Kf | Zkf | Azkf = Kf(c.x0, c.p0, c.e, c.f)
        else:
            gen0 = np.linalg.cholesky(c.p0)
            self.filt = (Zkf(c.x0, gen0, c.e, c.f) if kind == "zkf"
                         else Azkf(c.azkf, c.x0, gen0, c.e, c.f))
        self.prev_x: np.ndarray | None = None
        self.prev_de = 0.0
        self.prev_informed = False
        self.cur_informed = False

    def _model(self) -> Model:
        return self.mls.model  # without MLS: the (effective) prior, never refitted

    def _learn(self, from_ok: bool, x: np.ndarray | None, de: float, x_next: np.ndarray,
               to_ok: bool) -> None:
        if self.cfg.mls_enabled and from_ok and to_ok:
            if x is None:  # from_ok says there is a previous estimate
                raise RuntimeError("SidLoop: learning from a step that has no state estimate")
            self.mls.update(x, de, x_next)

    def step(self, y: np.ndarray, de: float, oracle: bool = False, valid: bool = True) -> dict:
        c = self.cfg
        y = np.asarray(y, dtype=float)
        use_y = (valid and bool(np.all(np.isfinite(y))) and abs(y[0]) <= c.alpha_limit
                 and abs(y[1]) <= c.q_limit)
        model = self._model().copy()
        row = {"a11": model.a[0, 0], "a12": model.a[0, 1], "a21": model.a[1, 0],
               "a22": model.a[1, 1], "b1": model.b[0], "b2": model.b[1],
               "rho": spectral_radius(model.a), "order": 0, "fault": 0}
        if c.mls.intercept:
            row.update(c1=model.c[0], c2=model.c[1])
        if isinstance(self.filt, Kf):  # kind == "kf"
            kf = self.filt
            row["gain_norm"] = kf.step(model, self.prev_de, y if use_y else None)
            prior = c.rows == "prior"
            lo, hi = kf.bounds(prior)
            xh = kf.prior_x if prior else kf.x
            informed = (self.prev_x is not None and self.cur_informed) if prior else use_y
            self._learn(self.prev_x is not None and self.prev_informed, self.prev_x, self.prev_de,
                        xh, informed)
            self.prev_x, self.prev_de, self.prev_informed = xh.copy(), de, informed
            self.cur_informed = use_y
        else:
            zkf = self.filt.zkf if isinstance(self.filt, Azkf) else self.filt
            xh = zkf.x.copy()
            h = hull(zkf.gen)
            lo, hi = xh - h, xh + h
            if isinstance(self.filt, Azkf):  # kind == "azkf"
                armed = not c.mls_enabled or c.arm_on_prior or not self.mls.is_prior
                gnorm, q, _, fault = self.filt.step(model, de, y if use_y else None, oracle, armed)
                skipped = fault and c.azkf.policy == "skip"
            else:
                q, fault, skipped = c.zkf_order, False, False
                gnorm, _ = zkf.step(model, de, y if use_y else None, q)
            row.update(gain_norm=gnorm, order=q, fault=int(fault))
            informed = use_y and not skipped and not (fault and c.mls_hold_on_fault)
            if c.rows != "posterior":
                self._learn(self.cur_informed, xh, de, zkf.x, informed)
                self.cur_informed = informed
            else:
                xh = zkf.post_x.copy()
                lo, hi = xh - zkf.post_hull, xh + zkf.post_hull
                row["gain_norm"] = zkf.post_gain
                self._learn(self.prev_x is not None and self.prev_informed, self.prev_x,
                            self.prev_de, xh, informed)
                self.prev_x, self.prev_de, self.prev_informed = xh.copy(), de, informed
        row.update(alpha_hat=xh[0], q_hat=xh[1], alpha_lo=lo[0], alpha_hi=hi[0], q_lo=lo[1],
                   q_hi=hi[1])
        return row


def replay(t: np.ndarray, y: np.ndarray, de: np.ndarray, fault: np.ndarray | None = None,
           cfg: SidConfig | None = None, filters: tuple[str, ...] = FILTERS) -> list[dict]:
    """Rows in sid_replay's order: for each step, one row per filter."""
    loops = [SidLoop(kind, cfg) for kind in filters]
    rows = []
    for k in range(len(t)):
        oracle = bool(fault[k]) if fault is not None else False
        for kind, loop in zip(filters, loops):
            row = loop.step(y[k], float(de[k]), oracle)
            row.update(t=float(t[k]), filter=kind)
            rows.append(row)
    return rows


def replay_mls_only(t: np.ndarray, x: np.ndarray, de: np.ndarray,
                    cfg: MlsConfig | None = None) -> list[dict]:
    """sid_replay --mls-only: row k holds the fit over transitions ending at x_k."""
    mls = Mls(cfg)
    rows = []
    for k in range(len(t)):
        if k > 0:
            mls.update(x[k - 1], float(de[k - 1]), x[k])
        m = mls.model
        rows.append({"t": float(t[k]), "filter": "mls", "alpha_hat": x[k, 0], "q_hat": x[k, 1],
                     "alpha_lo": x[k, 0], "alpha_hi": x[k, 0], "q_lo": x[k, 1], "q_hi": x[k, 1],
                     "gain_norm": 0.0, "order": 0, "fault": 0, "a11": m.a[0, 0],
                     "a12": m.a[0, 1], "a21": m.a[1, 0], "a22": m.a[1, 1], "b1": m.b[0],
                     "b2": m.b[1], "rho": mls.rho})
        if mls.cfg.intercept:
            rows[-1].update(c1=m.c[0], c2=m.c[1])
    return rows
