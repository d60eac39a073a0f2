"""A flight's results: time series (CSV columns) and figures of merit, per aircraft.

Everything here is computed from what the simulator knows (truth, readings) and what fcc put
on the bus -- nothing timing-dependent, so a lockstep run with the same seed gives the same
numbers.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hil.bus import dbc as dbc_spec
from hil.bus.apps import BUS_APPS
from hil.bus.dbc import BusSpec
from hil.results import metrics
from hil.results.buslog import FlightFrames
from hil.results.sidframes import sid_arrays
from hil.rig.errors import RigError
from hil.sim.drivers import FILTERS, CdrwDriver, MissileDriver
from hil.sim.missile_cov import closed_loop_rms, open_loop_rms
from hil.sim.missile_runs import design_lqg, rms_over, simulate_missile

Series = dict[str, np.ndarray]


@dataclass
class CdrwResult:
    scenario: str
    seed: int
    dt: float
    series: Series
    table: metrics.Table               # vs the fault-free measurement
    table_truth: metrics.Table         # vs the true state
    coverage: metrics.Table            # share of steps with the truth inside the bounds
    missing_steps: int                 # steps without an estimate from fcc
    unanswered_steps: int              # steps fcc did not acknowledge
    faults: list[str]
    events: list[dict[str, Any]]
    injected: dict[str, int]

    def summary(self) -> dict[str, Any]:
        return {"scenario": self.scenario, "seed": self.seed, "steps": len(self.series["t"]),
                "dt": self.dt, "error": self.table, "error_truth": self.table_truth,
                "improvement_over_kf_pct": metrics.improvements(self.table),
                "improvement_over_kf_truth_pct": metrics.improvements(self.table_truth),
                "coverage": self.coverage, "missing_steps": self.missing_steps,
                "unanswered_steps": self.unanswered_steps,
                "degraded_steps": int(np.sum(self.series["degraded"])),
                "faults": self.faults, "fault_events": self.events, "frames_injected": self.injected}


@dataclass
class MissileResult:
    scenario: str
    seed: int
    period: float
    bits: int | None
    closed_loop: bool
    series: Series
    fine: Series
    rms_q: float
    rms_alpha: float
    reference: dict[str, float] = field(default_factory=dict)
    stationary: dict[str, float] = field(default_factory=dict)
    commands_missing: int = 0
    commands_rejected: int = 0
    commands_late: int = 0      # realtime: arrived after the actuation instant t_k + delay
    delay: float = 0.0          # s: each command acts from t_k + delay (the LQG's design delay)
    unanswered_steps: int = 0
    faults: list[str] = field(default_factory=list)
    events: list[dict[str, Any]] = field(default_factory=list)
    injected: dict[str, int] = field(default_factory=dict)
    #: the wire-time bus in lockstep: t_k to when step k's command came off the wire (s)
    command_delay: dict[str, float] | None = None

    def run_entry(self) -> dict[str, Any]:
        """One element of summary.json's missile.runs."""
        entry: dict[str, Any] = {"period": self.period, "bits": self.bits,
                                 "closed_loop": self.closed_loop, "rms_q": self.rms_q,
                                 "rms_alpha": self.rms_alpha, "scenario": self.scenario,
                                 "seed": self.seed, "steps": len(self.series["t"]),
                                 "stationary": self.stationary}
        if self.closed_loop:
            entry.update({"reference": self.reference, "commands_missing": self.commands_missing,
                          "commands_rejected": self.commands_rejected,
                          "commands_late": self.commands_late, "delay": self.delay,
                          "unanswered_steps": self.unanswered_steps, "faults": self.faults,
                          "fault_events": self.events, "frames_injected": self.injected})
            if self.command_delay is not None:
                entry["command_delay_s"] = self.command_delay
        return entry

    @property
    def tag(self) -> str:
        """File-name tag: T0.100_b8, T0.100_open."""
        return f"T{self.period:.3f}_" + ("open" if self.bits is None else f"b{self.bits}")


def _events(driver: CdrwDriver | MissileDriver) -> list[dict[str, Any]]:
    return [ev.as_dict() for ev in sorted(driver.events, key=lambda e: (e.t, e.index))]


@dataclass
class CdrwRecord:
    """What the simulator knows of one CDRW flight, compact (a campaign keeps 100 of these
    while fcc's side waits in the bus log)."""

    scenario: str
    seed: int
    dt: float
    realtime: bool
    series: Series
    faults: list[str]
    events: list[dict[str, Any]]
    injected: dict[str, int]


class _ModelColumns:
    """The true local model's columns of a flight (rho, rho_static, A, B by sample), from its
    samples' linearisations.  A campaign's flights share the clean flight's linearisations
    (hil.sim.cdrw_flight: the very objects, faults act on readings only), and their spectral
    radii were most of a record's cost: the last flight's columns are kept with its
    linearisations and given again (copies) when every sample's is the very same object."""

    def __init__(self) -> None:
        self._lins: list[Any] = []
        self._columns: Series = {}

    def get(self, lins: list[Any]) -> Series:
        if not (len(lins) == len(self._lins) and all(a is b for a, b in zip(lins, self._lins))):
            a = np.array([x.A for x in lins], dtype=float).reshape(-1, 4)
            b = np.array([x.B for x in lins], dtype=float).reshape(-1, 2)
            self._lins = lins
            self._columns = {"rho_true": np.array([x.rho for x in lins]),
                             "rho_static": np.array([x.rho_static for x in lins]),
                             **{f"{name}_true": a[:, i].copy() for i, name in enumerate(("a11", "a12", "a21", "a22"))},
                             "b1_true": b[:, 0].copy(), "b2_true": b[:, 1].copy()}
        return {k: v.copy() for k, v in self._columns.items()}


_model_columns = _ModelColumns()


def cdrw_record(driver: CdrwDriver) -> CdrwRecord:
    sm = driver.samples
    s: Series = {"t": np.array([x.t for x in sm])}
    s["alpha_true"] = np.array([x.alpha for x in sm])
    s["q_true"] = np.array([x.q for x in sm])
    s["X_true"] = np.array([x.X for x in sm])
    s["de"] = np.array([x.de for x in sm])
    for sig, col in (("alpha", "alpha_meas"), ("q", "q_meas"), ("de", "de_meas")):
        s[col] = np.array([x.meas[sig] for x in sm])
    s["alpha_ff"] = np.array([x.meas_faultfree["alpha"] for x in sm])
    s["q_ff"] = np.array([x.meas_faultfree["q"] for x in sm])
    s["fault"] = np.array([int(x.fault_active) for x in sm])
    s.update(_model_columns.get([x.lin for x in sm]))
    n = driver.n_steps
    acked = np.zeros(n, dtype=np.int8)
    degraded = np.zeros(n, dtype=np.int8)
    for k, io in enumerate(driver.steps):
        acked[k], degraded[k] = int(io.acked), int(io.degraded)
    s["acked"], s["degraded"] = acked, degraded
    return CdrwRecord(scenario=driver.scenario.name or driver.scenario.source,
                      seed=driver.scenario.seed, dt=driver.period, realtime=driver.realtime,
                      series=s, faults=[f.describe() for f in driver.scenario.faults],
                      events=_events(driver), injected=dict(driver.injector.counts))


def cdrw_result(spec: BusSpec, rec: CdrwRecord, flight: FlightFrames) -> CdrwResult:
    """The simulator's record of a flight joined with fcc's outputs from the bus log."""
    s = dict(rec.series)
    n = len(s["t"])
    s.update(sid_arrays(spec, flight, n, check_step=not rec.realtime))
    s.pop("_mismatched", None)
    y_ff = np.column_stack([s["alpha_ff"], s["q_ff"]])
    x_true = np.column_stack([s["alpha_true"], s["q_true"]])
    est = {f: np.column_stack([s[f"{f}_alpha_hat"], s[f"{f}_q_hat"]]) for f in FILTERS}
    table, missing = metrics.error_table(y_ff, est, rec.dt)
    table_truth, _ = metrics.error_table(x_true, est, rec.dt)
    bounds = {f: (np.column_stack([s[f"{f}_alpha_lo"], s[f"{f}_q_lo"]]),
                  np.column_stack([s[f"{f}_alpha_hi"], s[f"{f}_q_hi"]])) for f in FILTERS}
    return CdrwResult(scenario=rec.scenario, seed=rec.seed, dt=rec.dt, series=s, table=table,
                      table_truth=table_truth, coverage=metrics.coverage_table(x_true, bounds),
                      missing_steps=missing,
                      unanswered_steps=int(n - s["acked"].sum()), faults=rec.faults,
                      events=rec.events, injected=rec.injected)


def _as_received(y: np.ndarray) -> np.ndarray:
    """[q_g, n_a] at the resolution of their DBC signals: what fcc decodes (NaN stays NaN)."""
    spec = dbc_spec.load()
    sigs = [spec.by_name(frame).signal(name) for _, frame, name in BUS_APPS["missile"].sensor_signals]
    return np.array([v if not np.isfinite(v) else float(s.to_phys(s.to_raw(float(v))))
                     for s, v in zip(sigs, y)])


def missile_result(driver: MissileDriver, reference: bool = True) -> MissileResult:
    d = driver
    s: Series = {"t": d.t.copy(), "q": d.x[:, 0], "alpha_T": d.x[:, 1], "w_g": d.x[:, 2],
                 "q_g": d.y[:, 0], "n_a": d.y[:, 1], "q_g_ff": d.y_ff[:, 0], "n_a_ff": d.y_ff[:, 1],
                 "fault": d.fault, "code": d.code, "u": d.code * d.sim.dac.lsb, "cmd_ok": d.cmd_ok,
                 "degraded": d.degraded, "saturated": d.saturated, "q_hat": d.x_hat[:, 0],
                 "alpha_T_hat": d.x_hat[:, 1], "w_g_hat": d.x_hat[:, 2]}
    ns = d.sim.n_sub
    fine: Series = {"t": np.arange(len(d.x_fine)) * (d.period / ns), "q": d.x_fine[:, 0],
                    "alpha_T": d.x_fine[:, 1], "w_g": d.x_fine[:, 2]}
    rq, ra = rms_over(fine["t"], d.x_fine, d.scenario.duration)
    ref: dict[str, float] = {}
    if reference:
        # the scipy LQG of hil.sim.missile_runs on the same plant, gust and noise draws,
        # fed the measurements as fcc decodes them from the bus
        r = simulate_missile(d.scenario, closed_loop=True, received=_as_received, delay=d.delay)
        same = r.code[: d.n_steps] == d.code
        mismatch = np.flatnonzero(~same)
        ref = {"rms_q": r.rms_q, "rms_alpha": r.rms_alpha, "code_agreement": float(np.mean(same)),
               "first_code_mismatch_step": int(mismatch[0]) if mismatch.size else -1}
    # stationary RMS of this loop (covariance analysis, D/A as LSB^2/12 noise)
    sq, sa = closed_loop_rms(design_lqg(d.period, d.scenario.sensors), d.bits)  # type: ignore[arg-type]
    return MissileResult(scenario=d.scenario.name or d.scenario.source, seed=d.scenario.seed,
                         period=d.period, bits=d.bits, closed_loop=True, series=s, fine=fine,
                         rms_q=rq, rms_alpha=ra, reference=ref,
                         stationary={"rms_q": sq, "rms_alpha": sa}, commands_missing=d.cmd_missing,
                         commands_rejected=d.cmd_bad, commands_late=d.cmd_late, delay=d.delay,
                         unanswered_steps=int(d.n_steps - d.acked.sum()),
                         faults=[f.describe() for f in d.scenario.faults], events=_events(d),
                         injected=dict(d.injector.counts), command_delay=_delays(d.cmd_delay))


def _delays(delay: np.ndarray) -> dict[str, float] | None:
    """p50 and max of the commands' delays (None: no command came off a modelled wire)."""
    got = delay[np.isfinite(delay)]
    if not got.size:
        return None
    return {"n": int(got.size), "p50": float(np.median(got)), "max": float(got.max())}


def missile_open_loop(scenario: Any) -> MissileResult:
    """The same airframe, gust and sensors with the elevator at 0 (no fcc involved)."""
    r = simulate_missile(scenario, closed_loop=False)
    s: Series = {"t": r.t, "q": r.x[:, 0], "alpha_T": r.x[:, 1], "w_g": r.x[:, 2],
                 "q_g": r.y[:, 0], "n_a": r.y[:, 1], "code": r.code, "u": r.u}
    fine: Series = {"t": r.t_fine, "q": r.x_fine[:, 0], "alpha_T": r.x_fine[:, 1],
                    "w_g": r.x_fine[:, 2]}
    sq, sa = open_loop_rms()
    return MissileResult(scenario=scenario.name or scenario.source, seed=scenario.seed,
                         period=r.period, bits=None, closed_loop=False, series=s, fine=fine,
                         rms_q=r.rms_q, rms_alpha=r.rms_alpha, stationary={"rms_q": sq, "rms_alpha": sa})


def require_estimates(res: CdrwResult, what: str, realtime: bool, forged: str = "") -> None:
    """A lockstep flight with answered steps whose authenticated estimates are not in bus.log is
    refused (RigError, exit 1): every answered step has its estimates on the bus, so a gap is
    the recorder's, or forged frames displaced fcc's (forged: what the reading refused on fcc's
    outputs, hil.results.buslog.Forgeries.describe), and a table would average the flight over
    the steps that are left."""
    lost = res.missing_steps - res.unanswered_steps
    if lost > 0 and not realtime:
        why = f"forged frames displaced them: {forged}" if forged else "the recorder lost frames"
        raise RigError(f"bus.log: {what} lacks fcc's estimates of {lost} answered steps ({why}); "
                       f"the flight is not evaluated")
