"""Missile short-period plant in gusts (seed 2, SPEC section 3) and its N-bit D/A converter.

    x = [q, alpha_T, w_g]  (rad/s, rad, ft/s),  u = elevator (rad, |u| <= 0.4)
    dx/dt = F x + G u + f eta_g,   eta_g unit-intensity white noise (E eta(t)eta(s) = delta(t-s))
    y = H x + v,  H = [[1, 0, 0], [-26.74, -568.4, 0]]   (rate gyro, accelerometer)

The gust w_g is first-order Gauss-Markov with tau_w = 0.5 s and sigma_w = 12 ft/s:
dw/dt = -2 w - 24 eta  has the stationary variance 24^2 / (2*2) = 144 = sigma_w^2.

Integration is *exact* per sub-step h: the state moves with Phi_h = e^{F h}, the held input
with Gamma_h = int_0^h e^{F s} G ds, and the noise adds a zero-mean Gaussian sample with the
exact covariance Q_h = int_0^h e^{F s} f f^T e^{F^T s} ds (Van Loan 1978), drawn through a
square-root factor of Q_h.  The discretisation is therefore independent of the number of
sub-steps; sub-steps only give the intersample time response (seed 2 uses >= 8 per period).

Common random numbers: every sampling period T is integrated on ONE fine time base
FINE_STEP = 2.5 ms (T = 0.02 -> 8, 0.05 -> 20, 0.1 -> 40, 0.2 -> 80 sub-steps), and the plant
draws one gust noise vector per fine step from its own seeded stream.  So the same seed flies
the same gust for every T: in open loop the true state at the common fine times is identical
(bit for bit) whatever T is, and a sweep over T compares controllers, not gust realisations.
See substeps_for() for the periods that are not whole multiples of FINE_STEP.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from hil.sim.linalg import expm
from hil.util.rounding import round_half_away


def _frozen(a: list) -> np.ndarray:
    arr = np.array(a, dtype=float)
    arr.setflags(write=False)
    return arr


#: seed 2 / SPEC section 3 (Mach 1.2 at sea level)
F = _frozen([[-1.2132, -177.0, 0.0], [1.0, -4.03, 0.00149], [0.0, 0.0, -2.0]])
G = _frozen([-69.3, -0.2978, 0.0])
f = _frozen([0.0, -0.0179, -24.0])
H = _frozen([[1.0, 0.0, 0.0], [-26.74, -568.4, 0.0]])
#: elevator limit, rad (also the D/A full scale)
U_MAX = 0.4
#: gust model (for documentation and tests): tau_w, sigma_w
TAU_W = 0.5
SIGMA_W = 12.0
#: seed 2's initial condition
Q0 = 0.1
#: state names, in order
STATE_NAMES = ("q", "alpha_T", "w_g")
#: the common fine integration step, s (one gust noise draw per fine step)
FINE_STEP = 0.0025
#: seed 2: at least 8 sub-steps per sampling period
MIN_SUBSTEPS = 8


def substeps_for(period: float, min_substeps: int = MIN_SUBSTEPS) -> int:
    """Sub-steps per sampling period: period / FINE_STEP when that is a whole number
    >= min_substeps (the common time base: same seed, same gust for every period).

    Otherwise (period not a whole multiple of 2.5 ms, e.g. 0.03 s, or too short, e.g.
    0.01 s) it falls back to the smallest n >= min_substeps with period / n <= FINE_STEP:
    the integration stays exact and at least as fine, but the gust noise is then drawn on
    a different time base, so such a period does NOT share the gust realisation of the
    periods on the common base (common_time_base() tells which case applies).
    """
    if not (math.isfinite(period) and period > 0.0):
        raise ValueError(f"missile: period must be > 0, got {period}")
    if isinstance(min_substeps, bool) or not isinstance(min_substeps, int) or min_substeps < 1:
        raise ValueError(f"missile: min_substeps must be a positive integer, got {min_substeps!r}")
    r = period / FINE_STEP
    n = round(r)
    if abs(r - n) <= 1e-9 * max(1.0, r) and n >= min_substeps:
        return int(n)
    return max(min_substeps, math.ceil(r - 1e-9))


def common_time_base(period: float, min_substeps: int = MIN_SUBSTEPS) -> bool:
    """True when the period is integrated on the common FINE_STEP base (shared gust)."""
    return math.isclose(period / substeps_for(period, min_substeps), FINE_STEP, rel_tol=1e-9)


def zoh(Fm: np.ndarray, Gm: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray]:
    """(Phi, Gamma) of a zero-order-hold input over h: one expm of [[F, G], [0, 0]] h."""
    n = Fm.shape[0]
    g = np.asarray(Gm, dtype=float).reshape(n, -1)
    m = g.shape[1]
    blk = np.zeros((n + m, n + m))
    blk[:n, :n] = Fm
    blk[:n, n:] = g
    e = expm(blk * h)
    return e[:n, :n], e[:n, n:]


def van_loan_noise(Fm: np.ndarray, fm: np.ndarray, h: float, intensity: float = 1.0) -> np.ndarray:
    """Q_h = int_0^h e^{F s} f W f^T e^{F^T s} ds by Van Loan's block exponential.

    expm([[-F, f W f^T], [0, F^T]] h) = [[., C12], [0, C22]] with C22 = e^{F^T h};
    then Q_h = C22^T C12.
    """
    n = Fm.shape[0]
    ff = intensity * np.outer(fm, fm)
    blk = np.zeros((2 * n, 2 * n))
    blk[:n, :n] = -Fm
    blk[:n, n:] = ff
    blk[n:, n:] = Fm.T
    e = expm(blk * h)
    q = e[n:, n:].T @ e[:n, n:]
    return 0.5 * (q + q.T)


def sqrt_factor(q: np.ndarray) -> np.ndarray:
    """L with L L^T = q for a symmetric PSD q (eigen-factor: robust when q is near-singular)."""
    w, v = np.linalg.eigh(0.5 * (q + q.T))
    return v * np.sqrt(np.clip(w, 0.0, None))


@dataclass(frozen=True)
class DAConverter:
    """N-bit D/A over [-full_scale, +full_scale] (SPEC section 3).

    LSB = 2*full_scale / 2^N; code = clamp(round(u / LSB), -2^(N-1), 2^(N-1) - 1), rounding
    half away from zero as C's round() does (the firmware's quantiser); value = code * LSB.
    """

    bits: int
    full_scale: float = U_MAX

    def __post_init__(self) -> None:
        if isinstance(self.bits, bool) or not isinstance(self.bits, int) or not 2 <= self.bits <= 16:
            raise ValueError(f"D/A: bits must be an integer in 2..16, got {self.bits!r}")
        if not self.full_scale > 0.0:
            raise ValueError(f"D/A: full_scale must be > 0, got {self.full_scale}")

    @property
    def lsb(self) -> float:
        return 2.0 * self.full_scale / float(1 << self.bits)

    @property
    def code_min(self) -> int:
        return -(1 << (self.bits - 1))

    @property
    def code_max(self) -> int:
        return (1 << (self.bits - 1)) - 1

    def code(self, u: float) -> int:
        """Quantise a command (rad) to the converter code."""
        if not math.isfinite(u):
            raise ValueError(f"D/A: command is not finite ({u})")
        return min(max(round_half_away(u / self.lsb), self.code_min), self.code_max)

    def value(self, code: int) -> float:
        """The elevator the converter outputs for a code (rad): code * LSB."""
        if isinstance(code, bool) or not isinstance(code, (int, np.integer)):
            raise ValueError(f"D/A: code must be an integer, got {code!r}")
        if not self.code_min <= int(code) <= self.code_max:
            raise ValueError(f"D/A: code {code} outside {self.code_min}..{self.code_max} "
                             f"for {self.bits} bits")
        return int(code) * self.lsb

    def quantise(self, u: float) -> float:
        return self.value(self.code(u))


class _DiscreteCache:
    """Exact sub-step matrices, computed once per sub-step length."""

    def __init__(self) -> None:
        self._cache: dict[float, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}

    def get(self, h: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        key = round(h, 15)
        hit = self._cache.get(key)
        if hit is None:
            phi, gam = zoh(F, G, h)
            hit = (phi, gam[:, 0].copy(), sqrt_factor(van_loan_noise(F, f, h)))
            self._cache[key] = hit
        return hit


_CACHE = _DiscreteCache()


class _GammaSeries:
    """Gamma_tau = int_0^tau e^{F s} G ds of the held input for parts of a sub-step (a command
    that comes off the wire inside one), tau in whole nanoseconds (the bus model's unit), by its
    power series sum_k F^k G tau^(k+1) / (k+1)!: ||F|| tau <= 0.45 for tau <= FINE_STEP, so 24
    terms are exact to the last bit of a double, at a hundredth of an expm's cost (the
    commands' times differ from step to step: no cache would hit)."""

    TERMS = 24

    def __init__(self) -> None:
        terms = [np.asarray(G, dtype=float)]
        for k in range(1, self.TERMS):
            terms.append(F @ terms[-1] / (k + 1))
        self._m = np.array(terms)   # row k: F^k G / (k+1)!
        self._k = np.arange(1, self.TERMS + 1)
        self._whole: dict[int, np.ndarray] = {}

    def get(self, tau_ns: int) -> np.ndarray:
        hit = self._whole.get(tau_ns)   # a whole sub-step, or none of it: the same every step
        if hit is not None:
            return hit
        if not 0 <= tau_ns <= round(FINE_STEP * 1e9):
            raise ValueError(f"missile: a part of a sub-step of {tau_ns} ns")
        return (float(tau_ns) * 1e-9) ** self._k @ self._m

    def piece_inputs(self, pieces: list[tuple[int, float]], h_ns: int) -> list[tuple[np.ndarray, float]]:
        """[(Gamma_{h - a_i} - Gamma_{h - a_(i+1)}, u_i), ...] of a sub-step of h_ns split into
        pieces [(a_i, u_i), ...] (a_0 = 0): the input each piece adds; each Gamma once."""
        self.whole(h_ns)
        gammas = [self.get(h_ns - a) for a, _ in pieces] + [self._whole[0]]
        return [(gammas[i] - gammas[i + 1], u) for i, (_, u) in enumerate(pieces)]

    def whole(self, h_ns: int) -> None:
        """Keep Gamma of 0 and of a whole sub-step of h_ns (every split sub-step needs both)."""
        if h_ns not in self._whole:
            self._whole[h_ns] = (float(h_ns) * 1e-9) ** self._k @ self._m
            self._whole[0] = 0.0 ** self._k @ self._m


_GAMMA = _GammaSeries()


def discrete_substep(h: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(Phi, Gamma, noise factor) of one sub-step of length h, computed once and cached."""
    return _CACHE.get(h)


class MissilePlant:
    """The missile airframe with its gust; owns the true state and its own noise stream.

    ``batch=None`` simulates one airframe (state shape (3,)); ``batch=n`` simulates n
    independent realisations at once (state (n, 3)), for Monte Carlo checks.
    ``gust0`` is the initial gust in ft/s, or "stationary" to draw it from N(0, sigma_w^2).
    ``gust_scale`` multiplies the noise input f (0 gives the deterministic response).
    """

    def __init__(self, seed: int, *, q0: float = Q0, alpha0: float = 0.0,
                 gust0: float | str = 0.0, gust_scale: float = 1.0,
                 batch: int | None = None) -> None:
        if not gust_scale >= 0.0:
            raise ValueError(f"missile: gust_scale must be >= 0, got {gust_scale}")
        self._rng = np.random.default_rng([int(seed), 0x6D73])  # own stream: "ms"
        shape = (3,) if batch is None else (int(batch), 3)
        x = np.zeros(shape)
        x[..., 0] = q0
        x[..., 1] = alpha0
        if isinstance(gust0, str):
            if gust0 != "stationary":
                raise ValueError(f"missile: gust0 must be a number or 'stationary', got {gust0!r}")
            x[..., 2] = SIGMA_W * gust_scale * self._rng.standard_normal(shape[:-1])
        else:
            x[..., 2] = float(gust0)
        self.gust_scale = float(gust_scale)
        self.x = x
        self.t = 0.0
        self.u = 0.0
        #: states at the sub-step boundaries of the last step, shape (n_sub + 1, ..., 3)
        self.last_substeps = x[None, ...].copy()

    @property
    def state(self) -> np.ndarray:
        return self.x.copy()

    def measure_true(self) -> np.ndarray:
        """Noise-free outputs H x: (q, n_a)."""
        return self.x @ H.T

    def step(self, u: float, dt: float, n_sub: int | None = None) -> np.ndarray:
        """Hold the elevator u (rad) for dt seconds, exact over n_sub equal sub-steps
        (default: substeps_for(dt), the common 2.5 ms base), one noise draw per sub-step."""
        if not dt > 0.0:
            raise ValueError(f"missile: dt must be > 0, got {dt}")
        if n_sub is None:
            n_sub = substeps_for(dt)
        if isinstance(n_sub, bool) or not isinstance(n_sub, int) or n_sub < 1:
            raise ValueError(f"missile: n_sub must be a positive integer, got {n_sub!r}")
        self.step_substeps(np.full(n_sub, float(u)), dt / n_sub)
        return self.state

    def step_pieces(self, pieces: list[tuple[int, float]], h_ns: int) -> np.ndarray:
        """One sub-step of h_ns nanoseconds whose held elevator changes inside it: pieces
        [(start_ns, u), ...] from start 0, in order (step_substeps)."""
        self.step_substeps(np.array([pieces[-1][1]]), h_ns * 1e-9, {0: pieces})
        return self.state

    def step_substeps(self, u: np.ndarray, h: float,
                      splits: dict[int, list[tuple[int, float]]] | None = None) -> np.ndarray:
        """len(u) exact sub-steps of h seconds, sub-step j holding the elevator u[j] (rad), or,
        for j in splits, changing inside it (u[j] then the last piece's): splits[j] =
        [(start_ns, u), ...] from start 0, in order (h then a whole number of nanoseconds, the
        bus model's unit).  Such a sub-step moves x to Phi_h x + noise_j + sum_i
        (Gamma_{h - a_i} - Gamma_{h - a_(i+1)}) u_i (exact; its noise is the draw it has without
        the switch: the gust does not depend on when the command came).  One block noise draw
        for all the sub-steps: the generator fills in order, so the same numbers as one draw per
        sub-step (tests/python/sim).  Returns the states at the sub-step boundaries (also
        last_substeps), shape (len(u) + 1, ..., 3)."""
        splits = splits or {}
        for v in set(u.tolist()).union(v for p in splits.values() for _, v in p):
            if not (math.isfinite(v) and abs(v) <= U_MAX + 1e-12):
                raise ValueError(f"missile: elevator {v} outside +-{U_MAX} rad")
        n, x = len(u), self.x
        phi, gam, lq = _CACHE.get(h)
        z = self._rng.standard_normal((n,) + x.shape)
        w = self.gust_scale * (z @ lq.T) + u.reshape((n,) + (1,) * x.ndim) * gam
        steps = {j: _GAMMA.piece_inputs(p, round(h * 1e9)) for j, p in splits.items() if len(p) > 1}
        trace = np.empty((n + 1,) + x.shape)
        trace[0] = x
        phi_t, matmul, add = phi.T, np.matmul, np.add
        first = 0
        for split in sorted(steps) + [n]:
            # x_(i+1) = x_i Phi^T + w_i, each written where the trace keeps it (no temporaries)
            for row, w_i in zip(trace[first + 1: split + 1], w[first:split]):
                matmul(x, phi_t, out=row)
                add(row, w_i, out=row)
                x = row
            if split < n:   # its noise as a one-row product (BLAS: its last bit can differ
                # from the same row of the block's), the numbers since the wire model came
                x = trace[split + 1]
                matmul(trace[split], phi_t, out=x)
                x += self.gust_scale * (z[split:split + 1] @ lq.T)[0]
                for g, v in steps[split]:
                    x += g * v
            first = split + 1
        self.x = trace[n].copy()
        self.u = float(u[-1])
        self.t += n * h
        self.last_substeps = trace
        return trace

    def step_code(self, code: int, dac: DAConverter, dt: float, n_sub: int | None = None) -> np.ndarray:
        """Apply a D/A code from the command frame: elevator = code * LSB, held for dt."""
        return self.step(dac.value(code), dt, n_sub)
