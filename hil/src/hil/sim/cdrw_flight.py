"""The CDRW flight, step by step (for the lockstep runner) or whole (offline, no bus).

Sample k is taken at t_k = k*dt: the true state x(t_k), the readings (bounded noise, then
the scenario's sensor faults), the elevator de_k that is held over [t_k, t_k + dt) (servo
refreshed at the 50 Hz frame rate) and the true local linearisation at (x(t_k), de_k).
The plant then integrates to t_{k+1} with a bounded random disturbance v_k (process noise).

The fault-free readings use the *same* noise draws as the faulty ones (the faults are
applied on top), so the paper's error integral against the fault-free measurement is exact.
The faults draw from a stream of their own and the flight is open loop, so everything but
the faulty readings is the fault-free scenario's: with_sensor_faults() turns that flight into
any faulty one (a Table 5 campaign flies one clean flight with N fault start times).
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from hil.scenario.file import Scenario, load_default_scenario
from hil.scenario.plant_options import CdrwPlantOptions
from hil.sim.cdrw import CdrwLinearisation, CdrwPlant, CdrwTrim
from hil.sim.sensor_faults import FaultEvent, SensorFaultInjector
from hil.sim.sensors import CdrwSensors
from hil.sim.sid_csv import sid_csv


@dataclass(frozen=True)
class CdrwSample:
    k: int
    t: float
    alpha: float                     # true, rad
    q: float                         # true, rad/s
    X: float                         # true separation state
    de: float                        # elevator applied over [t, t + dt), rad
    meas: dict[str, float]           # readings with faults: alpha, q, de
    meas_faultfree: dict[str, float]
    fault_active: bool               # any sensor fault active at this sample
    events: tuple[FaultEvent, ...]   # fault starts/ends at this sample
    lin: CdrwLinearisation           # true local model (A, B, rho ...)


class CdrwSimulation:
    """Plant + sensors + sensor faults of one CDRW scenario; step() once per frame."""

    def __init__(self, scenario: Scenario) -> None:
        if scenario.aircraft != "cdrw":
            raise ValueError(f"{scenario.source}: not a CDRW scenario (aircraft = {scenario.aircraft})")
        opts: CdrwPlantOptions = scenario.plant  # type: ignore[assignment]
        self.scenario = scenario
        self.opts = opts
        self.dt = opts.dt
        self.plant = CdrwPlant(opts.params, substep=opts.substep, q0=opts.q0)
        self.sensors = CdrwSensors(scenario.seed, scenario.sensors)  # type: ignore[arg-type]
        self.faults = SensorFaultInjector(scenario.sensor_faults, scenario.seed)
        self._rng = np.random.default_rng([int(scenario.seed), 0x706E])  # own stream: "pn"
        #: samples in the run: t = 0, dt, ..., duration
        self.n_samples = int(round(scenario.duration / self.dt)) + 1
        self.k = 0

    @property
    def trim(self) -> CdrwTrim:
        return self.plant.trim

    @property
    def done(self) -> bool:
        return self.k >= self.n_samples

    def elevator(self, t: float) -> float:
        """Commanded elevator at time t: trim + the manoeuvre."""
        return self.plant.trim.de + self.opts.maneuver.offset(t)

    def step(self) -> CdrwSample:
        """Sample at t_k, then integrate the plant to t_{k+1}."""
        if self.done:
            raise RuntimeError("cdrw: the run is over")
        k, dt, p = self.k, self.dt, self.plant
        t = k * dt
        de = self.elevator(t)
        clean = self.sensors.measure(p.alpha, p.q, de)
        sample = _with_faults(self.faults, CdrwSample(
            k=k, t=t, alpha=p.alpha, q=p.q, X=p.X, de=de, meas=clean, meas_faultfree=clean,
            fault_active=False, events=(), lin=p.linearise(de, dt)))
        bound = self.opts.process_noise
        v_a = float(self._rng.uniform(-bound[0], bound[0])) if bound[0] > 0.0 else 0.0
        v_q = float(self._rng.uniform(-bound[1], bound[1])) if bound[1] > 0.0 else 0.0
        p.step(de, dt, d_alpha=v_a / dt, d_q=v_q / dt)
        self.k += 1
        return sample


def _with_faults(faults: SensorFaultInjector, clean: CdrwSample) -> CdrwSample:
    """The sample with the injector's faults applied to its fault-free readings (samples in
    order: the injector holds and logs across them).  A fault-free sample (its readings the
    very dict of its fault-free ones) that no fault changes or starts or ends at is itself
    that sample: a campaign's flights share most of their samples with the clean flight."""
    n_log = len(faults.log)
    faulty = faults.apply(clean.t, clean.meas_faultfree)
    if clean.meas is clean.meas_faultfree and not faults.active and len(faults.log) == n_log \
            and not clean.fault_active and not clean.events:
        return clean
    return dataclasses.replace(clean, meas=faulty, fault_active=bool(faults.active),
                               events=tuple(faults.log[n_log:]))


def fault_free(scenario: Scenario) -> Scenario:
    """The scenario without its faults: the flight every one of its fault variants shares."""
    return scenario.replace(faults=())


def with_sensor_faults(scenario: Scenario, clean: list[CdrwSample]) -> list[CdrwSample]:
    """The scenario's flight from its fault-free one (fault_free(scenario)'s samples), the
    same bits as CdrwSimulation(scenario) steps them."""
    faults = SensorFaultInjector(scenario.sensor_faults, scenario.seed)
    first, last = faults.window()
    out: list[CdrwSample] = []
    for s in clean:
        if s.t < first or (s.t >= last and out and out[-1].t >= last):
            # no fault acts before the first start, nor after the sample that logged the ends:
            # the fault-free sample itself (a 0.1 s spike touches 6 of a flight's 351)
            faults.passed(s.meas_faultfree)
            out.append(s)
        else:
            out.append(_with_faults(faults, s))
    return out


@dataclass(frozen=True)
class CdrwFlight:
    """A whole offline flight; every array has one entry per sample."""

    t: np.ndarray
    alpha_true: np.ndarray
    q_true: np.ndarray
    X_true: np.ndarray
    de_true: np.ndarray               # elevator applied
    alpha_meas: np.ndarray            # readings with the scenario's faults
    q_meas: np.ndarray
    de: np.ndarray                    # elevator reading with faults (what SID regresses on)
    fault_flag: np.ndarray            # 1 where a sensor fault is active
    alpha_meas_faultfree: np.ndarray  # same noise, no fault
    q_meas_faultfree: np.ndarray
    de_faultfree: np.ndarray
    A_true: np.ndarray                # (N, 2, 2) discrete Euler, X held (see plants.cdrw)
    B_true: np.ndarray                # (N, 2)
    c_true: np.ndarray                # (N, 2) affine term the paper's model omits
    rho_true: np.ndarray              # rho(A_true)
    rho_static: np.ndarray            # rho of the quasi-steady (wind-tunnel-like) A
    C_L: np.ndarray
    C_m: np.ndarray
    trim: CdrwTrim
    dt: float
    events: tuple[FaultEvent, ...] = field(default=())


def simulate_cdrw(scenario: Scenario | None = None) -> CdrwFlight:
    """Fly a CDRW scenario offline (default: the embedded cdrw_default.toml)."""
    sc = scenario if scenario is not None else load_default_scenario("cdrw")
    sim = CdrwSimulation(sc)
    n = sim.n_samples
    cols = {name: np.empty(n) for name in (
        "t", "alpha_true", "q_true", "X_true", "de_true", "alpha_meas", "q_meas", "de",
        "alpha_meas_faultfree", "q_meas_faultfree", "de_faultfree", "rho_true", "rho_static",
        "C_L", "C_m")}
    flag = np.zeros(n, dtype=np.int8)
    a_true = np.empty((n, 2, 2))
    b_true = np.empty((n, 2))
    c_true = np.empty((n, 2))
    for i in range(n):
        s = sim.step()
        c_l, c_m = sim.plant.coefficients_at(s.alpha, s.q, s.X, s.de)
        row = (s.t, s.alpha, s.q, s.X, s.de, s.meas["alpha"], s.meas["q"], s.meas["de"],
               s.meas_faultfree["alpha"], s.meas_faultfree["q"], s.meas_faultfree["de"],
               s.lin.rho, s.lin.rho_static, c_l, c_m)
        for arr, v in zip(cols.values(), row):
            arr[i] = v
        flag[i] = 1 if s.fault_active else 0
        a_true[i] = s.lin.A
        b_true[i] = s.lin.B
        c_true[i] = s.lin.c
    return CdrwFlight(**cols, fault_flag=flag, A_true=a_true, B_true=b_true, c_true=c_true, trim=sim.trim,
                      dt=sim.dt, events=tuple(sim.faults.log))


def write_sid_csv(path: str | Path, flight: CdrwFlight) -> Path:
    """The faulty readings as CSV for the C tool sid_replay (hil.sim.sid_csv), with the fault flag."""
    p = Path(path)
    p.write_text(sid_csv(flight.t, flight.alpha_meas, flight.q_meas, flight.de,
                         flight.fault_flag), encoding="ascii")
    return p
