"""Missile runs without the bus: open loop, and closed loop with a pure-Python LQG reference.

The reference autopilot is designed here with scipy (a trusted solver, independent of the
firmware's Hamiltonian-eigenvector design), so the firmware's gains, estimates and D/A codes
can be cross-checked offline.  Conventions (the firmware must use the same to compare):

* sample k at t_k = k*T: readings y_k = H x(t_k) + v_k (then sensor faults);
* seed 2's filter:  x_hat_k = x_bar_k + L (y_k - H x_bar_k),  u_k = -K x_hat_k,
  code_k = D/A code of u_k, the plant gets code_k * LSB held over [t_k, t_k + T),
  x_bar_{k+1} = Phi x_hat_k + Gamma * (code_k * LSB)  (the command actually applied);
* x_bar_0 = 0 (nothing known before the first reading); a reading that is NaN (dropout)
  skips the update (x_hat_k = x_bar_k).
* with a known input delay d (0 <= d < T; ``design_lqg(..., delay=d)``) code_k acts from
  t_k + d: u_k = -K x_hat_k - K_u u_{k-1}, x_bar_{k+1} = Phi x_hat_k + Gamma0 u_k + Gamma1 u_{k-1}
  (the delayed-input ZOH discretisation and the LQR on [x; u_{k-1}], firmware/lqg/fcc_lqg.h).

Discrete design for period T (SPEC section 3): Phi, Gamma by ZOH, Q_d by Van Loan, and the
continuous cost turned into the discrete cost with cross term (Q11, Q12, Q22, as MATLAB's
lqrd) by Van Loan's block exponential of [[-Fa^T, Qa], [0, Fa]], Fa = [[F, G], [0, 0]].
"""
from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from hil.scenario.file import Scenario, load_default_scenario
from hil.scenario.plant_options import LqgOptions, MissilePlantOptions
from hil.scenario.sensor_options import MissileSensorOptions
from hil.sim import missile
from hil.sim.linalg import expm, solve_discrete_are
from hil.sim.missile import DAConverter, MissilePlant
from hil.sim.sensor_faults import FaultEvent, SensorFaultInjector
from hil.sim.sensors import MissileSensors

#: seed 2's cost weights: J = E int (x^T A x + u^T B u) dt
COST_A = np.diag([0.12, 11.0, 0.0])
COST_B = 1.0


@dataclass(frozen=True)
class LqgDesign:
    T: float
    Phi: np.ndarray     # 3x3
    Gamma: np.ndarray   # 3
    Qd: np.ndarray      # 3x3, process noise covariance per period
    Q11: np.ndarray     # 3x3  discrete cost (with cross term)
    Q12: np.ndarray     # 3
    Q22: float
    R: np.ndarray       # 2x2 measurement noise covariance
    K: np.ndarray       # 3, u = -K x_hat
    P: np.ndarray       # 3x3, control Riccati solution
    M: np.ndarray       # 3x3, steady a-priori error covariance (before the reading)
    L: np.ndarray       # 3x2, filter gain
    Z: np.ndarray       # 3x3, steady a-posteriori error covariance
    delay: float = 0.0  # d, s: the command acts from t_k + d
    Gamma1: np.ndarray = field(default_factory=lambda: np.zeros(3))  # delayed part of the input
    K_u: float = 0.0    # gain on u_{k-1}
    Pa: np.ndarray | None = None  # 4x4 augmented Riccati solution (d > 0)

    @property
    def H(self) -> np.ndarray:
        return missile.H


def discrete_cost(T: float, A: np.ndarray = COST_A, B: float = COST_B) -> tuple[np.ndarray, np.ndarray, float]:
    """(Q11, Q12, Q22) = int_0^T [Phi(s) Gamma(s)]^T blkdiag(A, B) [Phi(s) Gamma(s); 0 I] ds."""
    n = 3
    fa = np.zeros((n + 1, n + 1))
    fa[:n, :n] = missile.F
    fa[:n, n] = missile.G
    qa = np.zeros((n + 1, n + 1))
    qa[:n, :n] = A
    qa[n, n] = B
    blk = np.zeros((2 * (n + 1), 2 * (n + 1)))
    blk[: n + 1, : n + 1] = -fa.T
    blk[: n + 1, n + 1:] = qa
    blk[n + 1:, n + 1:] = fa
    e = expm(blk * T)
    w = e[n + 1:, n + 1:].T @ e[: n + 1, n + 1:]
    w = 0.5 * (w + w.T)
    return w[:n, :n], w[:n, n].copy(), float(w[n, n])


def delayed_lqr(T: float, delay: float, A: np.ndarray = COST_A, B: float = COST_B
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray, float, np.ndarray]:
    """The LQR for an input delay 0 < d < T on z = [x; u_{k-1}]: Gamma0, Gamma1, K (3), K_u
    and the augmented Riccati solution (4x4), scipy's DARE on
    z+ = [[Phi, Gamma1], [0, 0]] z + [Gamma0; 1] u with the cost of both hold intervals,
    [z; u]^T (blkdiag(Q(d), 0) + S^T Q(T-d) S) [z; u], S = [[Phi(d), Gamma(d), 0], [0, 0, 1]]."""
    n = 3
    phi = missile.zoh(missile.F, missile.G, T)[0]
    phi_d, gam_d = missile.zoh(missile.F, missile.G, delay)
    phi_r, gam0 = missile.zoh(missile.F, missile.G, T - delay)
    gam1 = phi_r @ gam_d

    def block(tau: float) -> np.ndarray:
        q11, q12, q22 = discrete_cost(tau, A, B)
        return np.block([[q11, q12[:, None]], [q12[None, :], np.array([[q22]])]])

    s = np.zeros((n + 1, n + 2))
    s[:n, :n], s[:n, n:n + 1], s[n, n + 1] = phi_d, gam_d, 1.0
    qa = np.zeros((n + 2, n + 2))
    qa[:n + 1, :n + 1] = block(delay)
    qa += s.T @ block(T - delay) @ s
    qa = 0.5 * (qa + qa.T)
    a = np.zeros((n + 1, n + 1))
    a[:n, :n], a[:n, n:] = phi, gam1
    b = np.vstack([gam0, [[1.0]]])
    q11, q12, q22 = qa[:n + 1, :n + 1], qa[:n + 1, n + 1:], qa[n + 1:, n + 1:]
    pa = solve_discrete_are(a, b, q11, q22, s=q12)
    ka = np.linalg.solve(q22 + b.T @ pa @ b, b.T @ pa @ a + q12.T)[0]
    return gam0[:, 0], gam1[:, 0], ka[:n], float(ka[n]), pa


def design_lqg(T: float, sensors: MissileSensorOptions = MissileSensorOptions(),
               A: np.ndarray = COST_A, B: float = COST_B, delay: float = 0.0) -> LqgDesign:
    """Steady-state discrete LQG for period T (scipy's DARE solver); with delay > 0 the
    command acts from t_k + delay (delayed_lqr; the Kalman gain does not change)."""
    if not T > 0.0:
        raise ValueError(f"lqg: period must be > 0, got {T}")
    if not 0.0 <= delay < T:
        raise ValueError(f"lqg: the delay must be in [0, T), got {delay} for T = {T}")
    phi, gam = missile.zoh(missile.F, missile.G, T)
    gam = gam[:, 0]
    qd = missile.van_loan_noise(missile.F, missile.f, T)
    q11, q12, q22 = discrete_cost(T, A, B)
    g = gam[:, None]
    p = solve_discrete_are(phi, g, q11, np.array([[q22]]), s=q12[:, None])
    k = np.linalg.solve(np.array([[q22]]) + g.T @ p @ g, g.T @ p @ phi + q12[None, :])[0]
    r = np.diag([sensors.var_gyro, sensors.var_acc])   # the sensors' noise covariance
    h = missile.H
    m = solve_discrete_are(phi.T, h.T, qd, r)
    m = 0.5 * (m + m.T)
    lg = m @ h.T @ np.linalg.inv(h @ m @ h.T + r)
    z = (np.eye(3) - lg @ h) @ m
    if delay == 0.0:
        return LqgDesign(T=T, Phi=phi, Gamma=gam, Qd=qd, Q11=q11, Q12=q12, Q22=q22, R=r, K=k,
                         P=p, M=m, L=lg, Z=0.5 * (z + z.T))
    gam0, gam1, k, k_u, pa = delayed_lqr(T, delay, A, B)
    return LqgDesign(T=T, Phi=phi, Gamma=gam0, Qd=qd, Q11=q11, Q12=q12, Q22=q22, R=r, K=k,
                     P=pa[:3, :3], M=m, L=lg, Z=0.5 * (z + z.T), delay=delay, Gamma1=gam1,
                     K_u=k_u, Pa=pa)


class LqgReference:
    """The reference autopilot: seed 2's steady-state filter and regulator, D/A in the loop."""

    def __init__(self, design: LqgDesign, dac: DAConverter) -> None:
        self.design = design
        self.dac = dac
        self.x_bar = np.zeros(3)
        self.x_hat = np.zeros(3)
        self.u_prev = 0.0  # u_{k-1} as applied (delay-aware design)

    def update(self, y: np.ndarray) -> int:
        """One period: take the readings (q_g, n_a), return the D/A code to apply."""
        d = self.design
        if np.all(np.isfinite(y)):
            self.x_hat = self.x_bar + d.L @ (y - missile.H @ self.x_bar)
        else:
            self.x_hat = self.x_bar.copy()
        code = self.dac.code(float(-d.K @ self.x_hat) - d.K_u * self.u_prev)
        u = self.dac.value(code)
        self.x_bar = d.Phi @ self.x_hat + d.Gamma * u + d.Gamma1 * self.u_prev
        self.u_prev = u
        return code


@dataclass(frozen=True)
class MissileSample:
    k: int
    t: float
    x: np.ndarray                      # true [q, alpha_T, w_g]
    meas: dict[str, float]             # readings with faults: q_g, n_a
    meas_faultfree: dict[str, float]
    fault_active: bool
    events: tuple[FaultEvent, ...]


class MissileSimulation:
    """Plant + sensors + sensor faults of a missile scenario, one control period at a time:
    ``s = sample()`` (readings at t_k), then ``advance(code)`` (the D/A code from the command
    frame, held for one period).

    The plant is integrated on the common fine base (missile.FINE_STEP = 2.5 ms):
    ``n_sub = missile.substeps_for(period, plant.substeps)`` sub-steps per period, one gust
    noise draw each, so the same seed flies the same gust for every period (common random
    numbers; see missile.substeps_for for periods off the 2.5 ms grid).  ``[plant] substeps``
    is the minimum number of sub-steps per period.  Sensor noise is drawn per sample."""

    def __init__(self, scenario: Scenario) -> None:
        if scenario.aircraft != "missile" or scenario.lqg is None:
            raise ValueError(f"{scenario.source}: not a missile scenario (aircraft = {scenario.aircraft})")
        po: MissilePlantOptions = scenario.plant  # type: ignore[assignment]
        self.scenario = scenario
        self.lqg: LqgOptions = scenario.lqg
        self.period = self.lqg.period
        #: sub-steps per period on the common fine time base (>= [plant] substeps)
        self.n_sub = missile.substeps_for(self.period, po.substeps)
        #: False when the period is off the 2.5 ms grid (its gust is then not shared)
        self.common_time_base = missile.common_time_base(self.period, po.substeps)
        self.dac = DAConverter(self.lqg.bits)
        # the sub-step matrices now (scipy is imported on first use, seconds in the UML guest:
        # never inside a realtime flight's first step)
        missile.discrete_substep(self.period / self.n_sub)
        self.plant = MissilePlant(scenario.seed, q0=po.q0, alpha0=po.alpha0, gust0=po.gust0,
                                  gust_scale=po.gust_scale)
        self.sensors = MissileSensors(scenario.seed, scenario.sensors)  # type: ignore[arg-type]
        self.faults = SensorFaultInjector(scenario.sensor_faults, scenario.seed)
        #: control periods in the run
        # every period flies at least `duration` seconds (the RMS is taken over exactly
        # [0, duration]: a sweep compares the same seconds at every T)
        self.n_periods = max(1, int(math.ceil(scenario.duration / self.period - 1e-9)))
        self.k = 0
        self._sampled = False
        #: the code acting at the end of the last period (what a delayed command replaces)
        self.last_code = 0

    @property
    def done(self) -> bool:
        return self.k >= self.n_periods

    def delay_substeps(self, delay: float) -> int:
        """Whole sub-steps before a command delayed by `delay` s acts (rounded up)."""
        h = self.period / self.n_sub
        return min(self.n_sub, int(math.ceil(delay / h - 1e-9)))

    def advance_delayed(self, code: int, delay: float) -> np.ndarray:
        """advance(code) with the code acting from t_k + delay (the previous code before)."""
        m = self.delay_substeps(delay)
        if m == 0 or code == self.last_code:
            return self.advance(code)
        return self.advance_substeps([self.last_code] * m + [code] * (self.n_sub - m))

    def advance_switched(self, switches: list[tuple[int, int]]) -> np.ndarray:
        """advance() with the D/A code changing at given instants of the period: switches
        [(offset_ns from t_k, code), ...] in time order, each offset in [0, period); the code
        acting before the first is the last one applied.  A switch inside a sub-step splits it
        exactly (MissilePlant.step_substeps: the bus model says when a command came off the
        wire, to the nanosecond).  Without switches, or with every switch on a sub-step
        boundary, the same numbers as advance_substeps()."""
        n, h_ns, value = self.n_sub, round(self.period / self.n_sub * 1e9), self.dac.value
        u = np.full(n, value(self.last_code))   # at the end of each sub-step
        splits: dict[int, list[tuple[int, float]]] = {}
        code = self.last_code
        for at, code in switches:
            j, start = divmod(at, h_ns)
            if not 0 <= j < n:
                raise ValueError(f"missile: a switch at {at} ns outside the period")
            v = value(code)
            held = splits.get(j, [(0, float(u[j]))])
            splits[j] = [p for p in held if p[0] < start] + [(start, v)]
            u[j:] = v
        return self._advance(u, splits, code)

    def sample(self) -> MissileSample:
        if self.done:
            raise RuntimeError("missile: the run is over")
        if self._sampled:
            raise RuntimeError("missile: sample() twice without advance()")
        t = self.k * self.period
        clean = self.sensors.measure(self.plant.x)
        n_log = len(self.faults.log)
        faulty = self.faults.apply(t, clean)
        self._sampled = True
        return MissileSample(k=self.k, t=t, x=self.plant.state, meas=faulty,
                             meas_faultfree=clean, fault_active=bool(self.faults.active),
                             events=tuple(self.faults.log[n_log:]))

    def advance(self, code: int) -> np.ndarray:
        """Apply a D/A code (validated against the word length) for one period."""
        return self._advance(np.full(self.n_sub, self.dac.value(code)), {}, code)

    def advance_substeps(self, codes: list[int]) -> np.ndarray:
        """Like advance(), with one D/A code per sub-step (real-time rig: a command that
        arrives during the period acts from the next sub-step).  Same noise draws as
        advance() when every code is the same."""
        if len(codes) != self.n_sub:
            raise ValueError(f"missile: {len(codes)} codes for {self.n_sub} sub-steps")
        value = self.dac.value
        return self._advance(np.array([value(c) for c in codes]), {}, codes[-1])

    def _advance(self, u: np.ndarray, splits: dict[int, list[tuple[int, float]]], last: int
                 ) -> np.ndarray:
        """The period integrated (MissilePlant.step_substeps), `last` the code at its end."""
        if not self._sampled:
            raise RuntimeError("missile: advance() before sample()")
        trace = self.plant.step_substeps(u, self.period / self.n_sub, splits)
        self._sampled = False
        self.k += 1
        self.last_code = last
        return trace


@dataclass(frozen=True)
class MissileRun:
    period: float
    bits: int | None                  # None: open loop
    closed_loop: bool
    t: np.ndarray                     # (n,) sample times
    x: np.ndarray                     # (n, 3) true state at the samples
    y: np.ndarray                     # (n, 2) readings with faults
    y_faultfree: np.ndarray
    code: np.ndarray                  # (n,) D/A codes applied (0 in open loop)
    u: np.ndarray                     # (n,) elevator applied, rad
    x_hat: np.ndarray                 # (n, 3) reference estimate (zeros in open loop)
    t_fine: np.ndarray                # (n*n_sub + 1,) sub-step times
    x_fine: np.ndarray                # (n*n_sub + 1, 3)
    design: LqgDesign | None
    events: tuple[FaultEvent, ...] = field(default=())
    duration: float = math.inf        # the RMS covers [0, duration] of the sub-step trace

    @property
    def rms_q(self) -> float:
        """RMS pitch rate over [0, duration] (time average of the sub-step trace)."""
        return rms_over(self.t_fine, self.x_fine, self.duration)[0]

    @property
    def rms_alpha(self) -> float:
        return rms_over(self.t_fine, self.x_fine, self.duration)[1]


def rms_over(t_fine: np.ndarray, x_fine: np.ndarray, duration: float) -> tuple[float, float]:
    """(RMS q, RMS alpha_T) of the sub-step trace over [0, duration]."""
    keep = np.asarray(t_fine) <= duration + 1e-9
    x = np.asarray(x_fine)[keep]
    return float(np.sqrt(np.mean(x[:, 0] ** 2))), float(np.sqrt(np.mean(x[:, 1] ** 2)))


def simulate_missile(scenario: Scenario | None = None, *, closed_loop: bool | None = None,
                     received: Callable[[np.ndarray], np.ndarray] | None = None,
                     delay: float = 0.0) -> MissileRun:
    """Fly a missile scenario offline; closed loop with the scipy LQG reference unless the
    scenario (or the closed_loop argument) says open loop (elevator code 0 throughout).
    received maps a measurement [q_g, n_a] to what the autopilot gets (e.g. the bus's
    resolution), so that the reference sees the same numbers as the firmware: a command
    that lands near a half-LSB tie of the D/A otherwise rounds the other way.  delay: each
    command acts from t_k + delay and the reference is designed for it."""
    sc = scenario if scenario is not None else load_default_scenario("missile")
    sim = MissileSimulation(sc)
    cl = sim.lqg.closed_loop if closed_loop is None else closed_loop
    design = design_lqg(sim.period, sc.sensors, delay=delay) if cl else None  # type: ignore[arg-type]
    ctrl = LqgReference(design, sim.dac) if design is not None else None
    n, ns = sim.n_periods, sim.n_sub
    t = np.empty(n)
    x = np.empty((n, 3))
    y = np.empty((n, 2))
    y0 = np.empty((n, 2))
    code = np.zeros(n, dtype=np.int64)
    xh = np.zeros((n, 3))
    x_fine = np.empty((n * ns + 1, 3))
    for k in range(n):
        s = sim.sample()
        t[k], x[k] = s.t, s.x
        y[k] = (s.meas["q_g"], s.meas["n_a"])
        y0[k] = (s.meas_faultfree["q_g"], s.meas_faultfree["n_a"])
        if ctrl is not None:
            code[k] = ctrl.update(y[k] if received is None else received(y[k]))
            xh[k] = ctrl.x_hat
        trace = sim.advance_delayed(int(code[k]), delay)
        x_fine[k * ns: (k + 1) * ns + 1] = trace
    t_fine = np.arange(n * ns + 1) * (sim.period / ns)
    return MissileRun(period=sim.period, bits=sim.lqg.bits if cl else None, closed_loop=cl, t=t,
                      x=x, y=y, y_faultfree=y0, code=code, u=code * sim.dac.lsb if cl else np.zeros(n),
                      x_hat=xh, t_fine=t_fine, x_fine=x_fine, design=design,
                      events=tuple(sim.faults.log), duration=sc.duration)
