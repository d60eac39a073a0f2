"""Stationary RMS of the missile by covariance analysis (seed 2, Fig. 3), exactly.

Fig. 3 is a steady-state quantity: the RMS of q and alpha_T of the loop in gusts, against the
sampling period T.  It is computed here without simulation:

* the plant (true, continuous): dx/dt = F x + G u + f eta, sampled with its exact ZOH
  (Phi, Gamma) and Van Loan noise Q_d over T (hil.sim.missile);
* the autopilot (the design under test, e.g. the firmware's own from `lqg_design`):
  x_hat_k = x_bar_k + L (y_k - H x_bar_k),  u_k = -K x_hat_k + d_k,
  x_bar_{k+1} = Phi_d x_hat_k + Gamma_d u_k  -- it propagates with the applied command;
* y_k = H x_k + v_k, v_k ~ (0, R);  d_k: the D/A as white uniform noise of variance
  LSB^2/12, LSB = 0.8 / 2^N, added to the held command (None: an ideal D/A);
* z_k = [x_k, x_bar_k] is a linear system driven by white (w_k, v_k, d_k): its stationary
  covariance solves a discrete Lyapunov equation;
* inside the period x(t_k + s) = Phi(s) x_k + Gamma(s) u_k + w(s) with w(s) independent of
  (x_k, u_k), so the continuous-time average over the interval is

      (1/T) int_0^T E x x^T ds = (1/T) [ int_0^T e^{A s} S e^{A^T s} ds ]_xx + (1/T) int_0^T Q(s) ds

  with A = [[F, G], [0, 0]] on (x, u), S = Cov(x_k, u_k).  The first integral is one Van Loan
  block exponential; the second follows from dQ/ds = F Q + Q F^T + f f^T, Q(0) = 0:
  F X + X F^T = Q(T) - T f f^T for X = int_0^T Q(s) ds (F is Hurwitz).  No sub-step sums.

The open loop (u = 0) is stationary in continuous time: F P + P F^T + f f^T = 0.
"""
from __future__ import annotations

import json
import math
import subprocess
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol

import numpy as np

from hil.sim import missile
from hil.sim.linalg import expm, solve_continuous_lyapunov, solve_discrete_lyapunov

#: D/A full scale span (rad): LSB = DAC_SPAN / 2^N
DAC_SPAN = 2.0 * missile.U_MAX


class Design(Protocol):
    """What the covariance analysis needs of an LQG design (period T)."""

    # read-only members (properties), so that a frozen dataclass is a Design too
    @property
    def T(self) -> float: ...
    @property
    def Phi(self) -> np.ndarray: ...    # 3x3, the estimator's transition
    @property
    def Gamma(self) -> np.ndarray: ...  # (3,), the estimator's input
    @property
    def H(self) -> np.ndarray: ...      # 2x3
    @property
    def R(self) -> np.ndarray: ...      # 2x2, the sensor noise the loop really gets
    @property
    def K(self) -> np.ndarray: ...      # (3,), u = -K x_hat
    @property
    def L(self) -> np.ndarray: ...      # 3x2, update-form filter gain


@dataclass(frozen=True)
class FirmwareDesign:
    """The matrices of one `lqg_design` JSON document."""

    T: float
    Phi: np.ndarray
    Gamma: np.ndarray
    H: np.ndarray
    R: np.ndarray
    K: np.ndarray
    L: np.ndarray

    @classmethod
    def from_json(cls, doc: dict[str, Any]) -> FirmwareDesign:
        a = lambda k: np.asarray(doc[k], dtype=float)  # noqa: E731
        return cls(T=float(doc["T"]), Phi=a("Phi"), Gamma=a("Gamma").reshape(3),
                   H=a("H"), R=a("R"), K=a("K").reshape(3), L=a("L"))


def dac_lsb(bits: int) -> float:
    return DAC_SPAN / float(1 << int(bits))


def dac_variance(bits: int | None) -> float:
    """The uniform-noise model of an N-bit D/A: LSB^2 / 12 (0 for an ideal one)."""
    return 0.0 if bits is None else dac_lsb(bits) ** 2 / 12.0


def firmware_design(tool: Path, period: float, gyro_var: float, accel_var: float) -> FirmwareDesign:
    """Run the firmware's `lqg_design` (its own numerics) and read its JSON."""
    cmd = [str(tool), "--period", repr(float(period)), "--gyro-var", repr(float(gyro_var)),
           "--accel-var", repr(float(accel_var))]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    if r.returncode != 0:
        msg = (r.stderr.strip().splitlines() or ["no message"])[0]
        raise RuntimeError(f"lqg_design --period {period:g}: exit {r.returncode}: {msg}")
    return FirmwareDesign.from_json(json.loads(r.stdout))


def firmware_real(tool: Path) -> str:
    """"double" or "float": the precision `lqg_design` reports its matrices in."""
    r = subprocess.run([str(tool), "--period", "0.1"], capture_output=True, text=True, timeout=60)
    return str(json.loads(r.stdout)["real"]) if r.returncode == 0 else "unknown"


def _plant_xu_block(T: float) -> np.ndarray:
    """A = [[F, G], [0, 0]] on (x, u): e^{A s} = [[Phi(s), Gamma(s)], [0, 1]]."""
    a = np.zeros((4, 4))
    a[:3, :3] = missile.F
    a[:3, 3] = missile.G
    return a


def interval_mean_cov(s_xu: np.ndarray, T: float) -> np.ndarray:
    """(1/T) int_0^T E x(t_k + s) x(t_k + s)^T ds given S = Cov(x_k, u_k) (4x4), the
    command held over the interval and the gust acting on top (3x3 result)."""
    a = _plant_xu_block(T)
    blk = np.zeros((8, 8))
    blk[:4, :4] = -a
    blk[:4, 4:] = s_xu
    blk[4:, 4:] = a.T
    e = expm(blk * T)
    hold = (e[4:, 4:].T @ e[:4, 4:])[:3, :3]           # int e^{As} S e^{A^T s} ds
    ff = np.outer(missile.f, missile.f)
    q_t = missile.van_loan_noise(missile.F, missile.f, T)
    gust = solve_continuous_lyapunov(missile.F, q_t - T * ff)   # int_0^T Q(s) ds
    m = (hold + gust) / T
    return 0.5 * (m + m.T)


def stationary_xu(design: Design, dac_var: float = 0.0) -> np.ndarray:
    """Stationary Cov(x_k, u_k) (4x4) at the sample instants of the closed loop."""
    T = design.T
    phi, gam = missile.zoh(missile.F, missile.G, T)
    gam = gam[:, 0]
    qd = missile.van_loan_noise(missile.F, missile.f, T)
    lh = design.L @ design.H
    ax = np.hstack([lh, np.eye(3) - lh])        # x_hat = ax z + L v
    k = design.K[None, :]
    # u = -K ax z - K L v + d
    cu_z = -k @ ax
    cu_v = -k @ design.L
    a_cl = np.zeros((6, 6))
    a_cl[:3, :3] = phi
    a_cl[:3] += np.outer(gam, cu_z[0])
    a_cl[3:] = design.Phi @ ax + np.outer(design.Gamma, cu_z[0])
    # noises n = (w (3), v (2), d (1))
    b = np.zeros((6, 6))
    b[:3, :3] = np.eye(3)
    b[:3, 3:5] = np.outer(gam, cu_v[0])
    b[:3, 5] = gam
    b[3:, 3:5] = design.Phi @ design.L + np.outer(design.Gamma, cu_v[0])
    b[3:, 5] = design.Gamma
    n = np.zeros((6, 6))
    n[:3, :3] = qd
    n[3:5, 3:5] = design.R
    n[5, 5] = dac_var
    if max(abs(np.linalg.eigvals(a_cl))) >= 1.0:
        raise RuntimeError(f"closed loop at T = {T:g} s is not stable")
    sz = solve_discrete_lyapunov(a_cl, b @ n @ b.T)
    # (x, u) = cz z + dn (v, d)
    cz = np.zeros((4, 6))
    cz[:3, :3] = np.eye(3)
    cz[3] = cu_z[0]
    dn = np.zeros((4, 3))
    dn[3, :2] = cu_v[0]
    dn[3, 2] = 1.0
    nvd = np.zeros((3, 3))
    nvd[:2, :2] = design.R
    nvd[2, 2] = dac_var
    s = cz @ sz @ cz.T + dn @ nvd @ dn.T
    return 0.5 * (s + s.T)


def closed_loop_rms(design: Design, bits: int | None = None) -> tuple[float, float]:
    """(RMS q, RMS alpha_T): the continuous-time average over the sampling interval of the
    stationary closed loop; bits=None: ideal D/A, else the LSB^2/12 noise model."""
    m = interval_mean_cov(stationary_xu(design, dac_variance(bits)), design.T)
    return math.sqrt(m[0, 0]), math.sqrt(m[1, 1])


def open_loop_rms() -> tuple[float, float]:
    """(RMS q, RMS alpha_T) of the airframe in gusts with the elevator at 0."""
    p = solve_continuous_lyapunov(missile.F, -np.outer(missile.f, missile.f))
    return math.sqrt(p[0, 0]), math.sqrt(p[1, 1])


def missile_rms_study(periods: Sequence[float], bits: Sequence[int], gyro_var: float,
                      accel_var: float, tool: Path) -> dict[str, Any]:
    """`hil study missile-rms --json`: the firmware's design at every period, the RMS with an
    ideal D/A and with each word length (shape documented in the README)."""
    oq, oa = open_loop_rms()
    out: dict[str, Any] = {"gyro_var": gyro_var, "accel_var": accel_var,
                           "open_loop": {"rms_q": oq, "rms_alpha": oa}, "periods": []}
    for T in periods:
        d = firmware_design(tool, T, gyro_var, accel_var)
        q, a = closed_loop_rms(d)
        entry: dict[str, Any] = {"period": float(T), "rms_q": q, "rms_alpha": a, "dac": {}}
        for n in bits:
            nq, na = closed_loop_rms(d, int(n))
            entry["dac"][str(int(n))] = {"rms_q": nq, "rms_alpha": na}
        out["periods"].append(entry)
    return out


def format_study(study: dict[str, Any]) -> str:
    """The study as a text table (RMS q in rad/s, alpha_T in rad)."""
    bits = list(study["periods"][0]["dac"]) if study["periods"] else []
    head = f"{'T (s)':>7} {'ideal q':>10} {'ideal a_T':>10}" + "".join(
        f" {n + ' bit q':>10} {n + ' bit a_T':>10}" for n in bits)
    ol = study["open_loop"]
    lines = [f"Missile stationary RMS (covariance analysis), gyro var {study['gyro_var']:g}, "
             f"accel var {study['accel_var']:g}; open loop: q {ol['rms_q']:.5f} rad/s, "
             f"alpha_T {ol['rms_alpha']:.6f} rad", head]
    for p in study["periods"]:
        row = f"{p['period']:>7.3f} {p['rms_q']:>10.5f} {p['rms_alpha']:>10.6f}"
        for n in bits:
            row += f" {p['dac'][n]['rms_q']:>10.5f} {p['dac'][n]['rms_alpha']:>10.6f}"
        lines.append(row)
    return "\n".join(lines)
