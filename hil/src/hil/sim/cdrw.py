"""CDRW nonlinear longitudinal short-period model with a flow-separation state.

State s = (alpha, q, X): angle of attack (rad), pitch rate (rad/s), separation point X
(1 attached, 0 separated).  Equations, constant speed V (short-period approximation: the
speed and flight-path angle change little in the few seconds of the manoeuvre, gamma ~ 0):

    alpha_dot = q - qbar*S/(m*V) * C_L(alpha, X, q, de) + g/V + d_alpha
    q_dot     = qbar*S*cbar/Jy * C_m(alpha, X, q, de) + d_q
    X_dot     = (X0(alpha - tau2*alpha_dot) - X) / tau1

with the coefficient model documented in cdrw_params.  d_alpha, d_q are optional
disturbance rates (turbulence) held constant over a step.  Integration is classical RK4 at a
fine sub-step (default 2 ms, 10 per 50 Hz frame) with the elevator held (zero-order hold: the
servo is refreshed at the 50 Hz frame rate).

"True" linearisation for the identification (the paper's discrete model x = [alpha, q],
x_{k+1} = A_k x_k + B_k de_k):

* ``A``/``B`` (what the flight arrays call A_true/B_true) come from the continuous Jacobian
  of the (alpha, q) rates with the separation state X *held at its current value*,
  discretised exactly for dt with the elevator held (A = e^{A_c dt}, B = int_0^dt e^{A_c s}
  ds B_c).  Over one 20 ms step X hardly moves (tau1 = 0.5 s = 25 steps), so this (with
  the affine term c below) is the local one-step map of the aircraft; a least-squares fit
  with an intercept over a window of steady flight recovers it (measured before the stall:
  A_21 -0.966 vs -0.923).  The slow X-coupling is, for the MLS, an unmodelled input spread
  over its 2.2 s window, so windows that span the stall mix dynamics.
  Because X lags alpha, this A keeps the "stalled" dynamics for a while after alpha is back
  under 15 deg: the hysteresis of the paper's Fig. 7.  (Measured on the default flight:
  letting X respond within the step, i.e. the Jacobian of the full 3-state flow, changes the
  (q, alpha) entry by up to ~0.07 near alpha*, because X0 is steep there, but rho by < 0.001.)
* ``A_euler``/``B_euler`` = I + dt A_c, dt B_c: the same Jacobian through the paper's own
  Euler formula (eq. 3).  It differs from the exact map by O(dt^2): ~0.1 (10 %) on the
  (q, alpha) entry here because dt*|M_alpha| ~ 1, though rho differs by < 0.5 %.
* ``A_static`` (exact discretisation) replaces X by its static value X0(alpha) before
  differentiating, so the slope dX0/dalpha enters: the quasi-steady, wind-tunnel-like
  linearisation the paper compared its MLS estimate with (Fig. 7, from [16]).  It has no
  memory, hence no hysteresis, and it is statically unstable (rho > 1) in the pitch-up band.
* ``J3`` is the full 3x3 continuous Jacobian of (alpha, q, X), for reference.
* ``c`` is the affine term of the local model in absolute coordinates,
  x_{k+1} ~ A x_k + B de_k + c.  The paper's model (eq. 3) has no such term, but a trimmed
  aircraft at alpha = 9 deg needs one (gravity, C_m0 and the trim elevator do not cancel
  A x* + B de*): c = (+0.016 rad, +0.071 rad/s) per step at trim.  A regression without an
  intercept absorbs it into A and B (measured: A_21 ~ -0.5 instead of -0.92 before the stall).
"""
from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from hil.scenario.cdrw_params import DEFAULT_PARAMS, G0, CdrwParams

#: frame period of the CDRW identification (seed 1: 50 Hz)
DT_FRAME = 0.02
#: default RK4 sub-step
DT_SUB = 0.002


@dataclass(frozen=True)
class CdrwTrim:
    """Steady level flight at the parameter file's trim alpha."""

    alpha: float   # rad
    X: float       # separation state, = X0(alpha)
    de: float      # rad, elevator that zeroes the pitching moment
    V: float       # m/s, speed at which lift equals weight
    qbar: float    # Pa


@dataclass(frozen=True)
class CdrwLinearisation:
    """Local linear models at one point of the flight (see the module docstring)."""

    A_c: np.ndarray       # 2x2 continuous, X held
    B_c: np.ndarray       # 2,   continuous, X held
    A: np.ndarray         # 2x2 discrete, exact (e^{A_c dt}): the true A_k
    B: np.ndarray         # 2,   discrete, exact (elevator held): the true B_k
    A_euler: np.ndarray   # 2x2 I + dt*A_c (the paper's eq. 3)
    B_euler: np.ndarray   # 2,   dt*B_c
    A_static: np.ndarray  # 2x2 discrete, exact, with X = X0(alpha) (quasi-steady)
    J3: np.ndarray        # 3x3 continuous Jacobian of (alpha, q, X)
    c: np.ndarray         # 2, affine term: x_{k+1} ~ A x_k + B de_k + c (see below)
    dt: float

    @property
    def rho(self) -> float:
        """Spectral radius of the true discrete A."""
        return spectral_radius(self.A)

    @property
    def rho_static(self) -> float:
        return spectral_radius(self.A_static)


def spectral_radius(a: np.ndarray) -> float:
    """max |lambda_i| (seed 1, eq. 26); closed form for 2x2 (the hot path)."""
    if a.shape == (2, 2):
        half_tr = 0.5 * (a[0, 0] + a[1, 1])
        det = a[0, 0] * a[1, 1] - a[0, 1] * a[1, 0]
        disc = half_tr * half_tr - det
        if disc >= 0.0:
            r = math.sqrt(disc)
            return float(max(abs(half_tr + r), abs(half_tr - r)))
        return float(math.sqrt(det))  # complex pair: |lambda|^2 = det
    return float(np.max(np.abs(np.linalg.eigvals(a))))


def expm_phi1(a_c: np.ndarray, dt: float, terms: int = 18) -> tuple[np.ndarray, np.ndarray]:
    """(e^{A dt}, int_0^dt e^{A s} ds) of a small matrix by their Taylor series.

    Reference implementation (and fallback): for the 2x2 Jacobians here ||A dt|| ~ 1, so 18
    terms leave a truncation error < 1e-13 and no cancellation problem.
    """
    n = a_c.shape[0]
    term = np.eye(n) * dt            # (A dt)^k dt / (k+1)!, k = 0
    phi1 = term.copy()
    ad = a_c * dt
    for k in range(1, terms):
        term = term @ ad / (k + 1)
        phi1 += term
    return np.eye(n) + a_c @ phi1, phi1


def expm_phi1_2x2(a_c: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Closed form of expm_phi1 for 2x2 (the per-frame hot path).

    With s = tr(A)/2 and N = A - s I, N^2 = delta I (delta = s^2 - det A), so
    e^{A dt} = e^{s dt} (cosh(m) I + sinh(m)/sqrt(delta) N), m = sqrt(delta) dt (cos/sin
    when delta < 0); then int_0^dt e^{A s} ds = A^{-1} (e^{A dt} - I) when A is well
    invertible, else the series.
    """
    a, b, c, d = float(a_c[0, 0]), float(a_c[0, 1]), float(a_c[1, 0]), float(a_c[1, 1])
    s = 0.5 * (a + d)
    det = a * d - b * c
    delta = s * s - det
    m2 = delta * dt * dt
    if abs(m2) < 1e-8:
        ch, shd = 1.0 + 0.5 * m2, dt * (1.0 + m2 / 6.0)          # series of cosh, sinh/x
    elif delta > 0.0:
        r = math.sqrt(delta)
        ch, shd = math.cosh(r * dt), math.sinh(r * dt) / r
    else:
        r = math.sqrt(-delta)
        ch, shd = math.cos(r * dt), math.sin(r * dt) / r
    e = math.exp(s * dt)
    ed = np.array([[e * (ch + shd * (a - s)), e * shd * b],
                   [e * shd * c, e * (ch + shd * (d - s))]])
    if abs(det) * dt * dt < 1e-6:
        return ed, expm_phi1(a_c, dt)[1]
    inv = np.array([[d, -b], [-c, a]]) / det
    return ed, inv @ (ed - np.eye(2))


def separation_x0(p: CdrwParams, alpha_eff: float) -> float:
    """Static separation point X0 for an effective angle of attack."""
    return 0.5 * (1.0 - math.tanh(p.a1 * (alpha_eff - p.alpha_star)))


def lift_coefficient(p: CdrwParams, alpha: float, X: float, q_hat: float, de: float) -> float:
    return (p.C_L0 + p.C_La * alpha * (X + (1.0 - X) * p.eta_L)
            + p.C_Lq * q_hat + p.C_Lde * de)


def moment_coefficient(p: CdrwParams, alpha: float, X: float, q_hat: float, de: float) -> float:
    return (p.C_m0 + p.C_ma * alpha * (X + (1.0 - X) * p.eta_m) + p.dCm_sep * (1.0 - X)
            + p.C_mq * q_hat * (X + (1.0 - X) * p.eta_q) + p.C_mde * de)


def cdrw_trim(p: CdrwParams = DEFAULT_PARAMS) -> CdrwTrim:
    """Trim at p.alpha_trim: C_m = 0 gives the elevator, lift = weight gives the speed."""
    alpha = p.alpha_trim
    X = separation_x0(p, alpha)
    if p.C_mde == 0.0:
        raise ValueError("cdrw: C_mde = 0, the elevator cannot trim the aircraft")
    de = -moment_coefficient(p, alpha, X, 0.0, 0.0) / p.C_mde
    c_l = lift_coefficient(p, alpha, X, 0.0, de)
    if c_l <= 0.0:
        raise ValueError(f"cdrw: no positive lift at the trim alpha (C_L = {c_l:.4f})")
    qbar = p.weight / (p.S * c_l)
    V = math.sqrt(2.0 * qbar / p.rho_air)
    return CdrwTrim(alpha=alpha, X=X, de=de, V=V, qbar=qbar)


class CdrwPlant:
    """The nonlinear CDRW short-period plant; owns its true state (alpha, q, X)."""

    def __init__(self, params: CdrwParams = DEFAULT_PARAMS, *, substep: float = DT_SUB,
                 q0: float = 0.0) -> None:
        if not substep > 0.0:
            raise ValueError(f"cdrw: substep must be > 0, got {substep}")
        self.p = params
        self.trim = cdrw_trim(params)
        self.V = self.trim.V
        self.substep = substep
        # Dimensional groups, computed once (the hot path is pure-float arithmetic).
        qbar = self.trim.qbar
        self._kz = qbar * params.S / (params.mass * self.V)        # 1/s per unit C_L
        self._km = qbar * params.S * params.cbar / params.Jy       # 1/s^2 per unit C_m
        self._g_v = G0 / self.V                                     # gamma ~ 0
        self._qh = params.cbar / (2.0 * self.V)                     # q -> q_hat
        self.alpha = self.trim.alpha
        self.q = q0
        self.X = self.trim.X
        self.t = 0.0

    # ---- model --------------------------------------------------------------------------
    @property
    def state(self) -> np.ndarray:
        """True state [alpha, q, X]."""
        return np.array([self.alpha, self.q, self.X])

    def set_state(self, alpha: float, q: float, X: float) -> None:
        self.alpha, self.q, self.X = float(alpha), float(q), float(X)

    def rates(self, alpha: float, q: float, X: float, de: float,
              d_alpha: float = 0.0, d_q: float = 0.0) -> tuple[float, float, float]:
        """(alpha_dot, q_dot, X_dot) of the nonlinear model."""
        p = self.p
        q_hat = q * self._qh
        alpha_dot = (q - self._kz * lift_coefficient(p, alpha, X, q_hat, de)
                     + self._g_v + d_alpha)
        q_dot = self._km * moment_coefficient(p, alpha, X, q_hat, de) + d_q
        x_dot = (separation_x0(p, alpha - p.tau2 * alpha_dot) - X) / p.tau1
        return alpha_dot, q_dot, x_dot

    def static_rates(self, alpha: float, q: float, de: float) -> tuple[float, float]:
        """(alpha_dot, q_dot) with X at its static value X0(alpha) (wind-tunnel view)."""
        a_dot, q_dot, _ = self.rates(alpha, q, separation_x0(self.p, alpha), de)
        return a_dot, q_dot

    # ---- integration --------------------------------------------------------------------
    def step(self, de: float, dt: float = DT_FRAME, d_alpha: float = 0.0,
             d_q: float = 0.0, *, hold_separation: bool = False) -> np.ndarray:
        """Advance dt seconds with the elevator and the disturbance held; returns the state.

        hold_separation=True freezes X (analysis only: the flow whose Jacobian is A_true).
        """
        if not dt > 0.0:
            raise ValueError(f"cdrw: dt must be > 0, got {dt}")
        n = max(1, math.ceil(dt / self.substep - 1e-9))
        h = dt / n
        a, q, x = self.alpha, self.q, self.X
        f: Callable[..., tuple[float, float, float]] = self.rates
        if hold_separation:
            def held(a_: float, q_: float, x_: float, de_: float, da: float, dq: float) -> tuple[float, float, float]:
                r = self.rates(a_, q_, x_, de_, da, dq)
                return r[0], r[1], 0.0
            f = held
        for _ in range(n):
            k1 = f(a, q, x, de, d_alpha, d_q)
            k2 = f(a + 0.5 * h * k1[0], q + 0.5 * h * k1[1], x + 0.5 * h * k1[2], de, d_alpha, d_q)
            k3 = f(a + 0.5 * h * k2[0], q + 0.5 * h * k2[1], x + 0.5 * h * k2[2], de, d_alpha, d_q)
            k4 = f(a + h * k3[0], q + h * k3[1], x + h * k3[2], de, d_alpha, d_q)
            a += h / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0])
            q += h / 6.0 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1])
            x += h / 6.0 * (k1[2] + 2.0 * k2[2] + 2.0 * k3[2] + k4[2])
        if not (math.isfinite(a) and math.isfinite(q) and math.isfinite(x)):
            raise FloatingPointError(f"cdrw: state diverged at t = {self.t:.3f} s")
        self.alpha, self.q, self.X = a, q, x
        self.t += dt
        return self.state

    # ---- coefficients of the current state (for hysteresis plots and tests) ---------------
    def coefficients(self, de: float) -> tuple[float, float]:
        """(C_L, C_m) at the current true state."""
        return self.coefficients_at(self.alpha, self.q, self.X, de)

    def coefficients_at(self, alpha: float, q: float, X: float, de: float) -> tuple[float, float]:
        """(C_L, C_m) at a given state."""
        q_hat = q * self._qh
        return (lift_coefficient(self.p, alpha, X, q_hat, de),
                moment_coefficient(self.p, alpha, X, q_hat, de))

    # ---- linearisation ------------------------------------------------------------------
    def linearise(self, de: float, dt: float = DT_FRAME, eps: float = 1e-6) -> CdrwLinearisation:
        """True local linearisation at the current state (central differences, see docstring)."""
        s0 = (self.alpha, self.q, self.X)
        j3 = np.empty((3, 3))
        for j in range(3):
            sp, sm = list(s0), list(s0)
            sp[j] += eps
            sm[j] -= eps
            fp = self.rates(sp[0], sp[1], sp[2], de)
            fm = self.rates(sm[0], sm[1], sm[2], de)
            j3[:, j] = [(fp[i] - fm[i]) / (2.0 * eps) for i in range(3)]
        fp = self.rates(*s0, de + eps)
        fm = self.rates(*s0, de - eps)
        b_c = np.array([(fp[0] - fm[0]) / (2.0 * eps), (fp[1] - fm[1]) / (2.0 * eps)])
        a_c = j3[:2, :2].copy()
        a_s = np.empty((2, 2))
        for j in range(2):
            sp, sm = [self.alpha, self.q], [self.alpha, self.q]
            sp[j] += eps
            sm[j] -= eps
            fp2 = self.static_rates(sp[0], sp[1], de)
            fm2 = self.static_rates(sm[0], sm[1], de)
            a_s[:, j] = [(fp2[i] - fm2[i]) / (2.0 * eps) for i in range(2)]
        eye = np.eye(2)
        a_d, phi1 = expm_phi1_2x2(a_c, dt)
        a_sd, _ = expm_phi1_2x2(a_s, dt)
        f0 = self.rates(*s0, de)
        x0 = np.array(s0[:2])
        c_c = np.array(f0[:2]) - a_c @ x0 - b_c * de
        return CdrwLinearisation(A_c=a_c, B_c=b_c, A=a_d, B=phi1 @ b_c,
                                 A_euler=eye + dt * a_c, B_euler=dt * b_c,
                                 A_static=a_sd, J3=j3, c=phi1 @ c_c, dt=dt)
