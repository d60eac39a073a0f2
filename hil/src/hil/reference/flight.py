"""A synthetic flight for the identification tests and the benchmark.

Not the CDRW (that nonlinear plant lives in hil.sim): a linear, slowly
time-varying short-period model in exactly the MLS's structure, so that the
truth A_k, B_k is known.  Shape like the paper's Fig. 5: alpha near 9 deg, a
pull-up that passes 15 deg near 3 s and comes back by ~5 s, with pitch
stability reduced while alpha is high; a small multisine on the elevator for
excitation; bounded uniform process and sensor noise; one sensor spike fault.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hil.sim.sid_csv import sid_csv

DT = 0.02


@dataclass
class Flight:
    t: np.ndarray         # (N,) s
    de: np.ndarray        # (N,) rad, applied at step k
    x: np.ndarray         # (N, 2) true state
    y_clean: np.ndarray   # (N, 2) measurement without the fault
    y: np.ndarray         # (N, 2) measurement with the fault
    fault: np.ndarray     # (N,) bool, True where the fault is injected
    a: np.ndarray         # (N, 2, 2) true A_k (x_{k+1} = A_k x_k + B_k de_k + v_k)
    b: np.ndarray         # (N, 2) true B_k

    def csv(self, with_fault_column: bool = True, faulty: bool = True) -> str:
        """The flight as sid_replay input (full precision)."""
        y = self.y if faulty else self.y_clean
        # as lists: sid_csv takes sequences of Python numbers (the same text)
        return sid_csv(self.t.tolist(), y[:, 0].tolist(), y[:, 1].tolist(), self.de.tolist(),
                       self.fault.tolist() if with_fault_column else None)


def _bump(t: np.ndarray, t0: float, t1: float, ramp: float) -> np.ndarray:
    """0 before t0, smooth rise to 1 over `ramp`, 1 until t1, smooth fall."""
    up = np.clip((t - t0) / ramp, 0.0, 1.0)
    down = np.clip((t1 - t) / ramp, 0.0, 1.0)
    s = np.minimum(up, down)
    return s * s * (3.0 - 2.0 * s)


def continuous_derivatives(t: np.ndarray) -> dict[str, np.ndarray]:
    """Time-varying short-period derivatives: stability reduced during the pull-up."""
    s = _bump(t, 2.4, 5.2, 0.8)
    return {"z_a": -1.5 + 0.3 * s, "m_a": -20.0 + 8.0 * s, "m_q": -3.0 + 1.2 * s,
            "z_de": np.full_like(t, -0.2), "m_de": np.full_like(t, -30.0)}


def synthetic_flight(seed: int = 1, duration: float = 7.0, fault_time: float = 4.0,
                     fault_duration: float = 0.1, spike: tuple[float, float] = (0.15, 0.6),
                     sensor_noise: tuple[float, float] = (0.01, 0.015),
                     process_noise: tuple[float, float] = (0.0005, 0.002)) -> Flight:
    rng = np.random.default_rng(seed)
    n = int(round(duration / DT)) + 1
    t = np.arange(n) * DT
    d = continuous_derivatives(t)
    a = np.empty((n, 2, 2))
    a[:, 0, 0] = 1.0 + DT * d["z_a"]
    a[:, 0, 1] = DT
    a[:, 1, 0] = DT * d["m_a"]
    a[:, 1, 1] = 1.0 + DT * d["m_q"]
    b = np.column_stack([DT * d["z_de"], DT * d["m_de"]])

    # Elevator: trim for alpha = 9 deg on the initial model, a pull-up, a multisine.
    ss_gain = np.linalg.solve(np.eye(2) - a[0], b[0])       # x_ss per rad of de
    de_trim = np.deg2rad(9.0) / ss_gain[0]
    pull = _bump(t, 1.5, 3.7, 0.9)
    dither = 0.012 * (np.sin(2 * np.pi * 0.7 * t) + 0.8 * np.sin(2 * np.pi * 1.9 * t + 1.0)
                      + 0.6 * np.sin(2 * np.pi * 3.3 * t + 2.0))
    de = de_trim * (1.0 + 0.6 * pull) + dither

    x = np.empty((n, 2))
    x[0] = ss_gain * de[0]
    lim = np.asarray(process_noise)
    for k in range(n - 1):
        v = rng.uniform(-lim, lim)
        x[k + 1] = a[k] @ x[k] + b[k] * de[k] + v
    w = rng.uniform(-np.asarray(sensor_noise), np.asarray(sensor_noise), size=(n, 2))
    y_clean = x + w
    fault = (t >= fault_time - 1e-9) & (t < fault_time + fault_duration - 1e-9)
    y = y_clean.copy()
    y[fault] += np.asarray(spike)
    return Flight(t, de, x, y_clean, y, fault, a, b)
