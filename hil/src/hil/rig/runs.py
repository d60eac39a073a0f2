"""What the CLI commands do: a flight, a campaign, a sweep, the demo -- each in one rig
session (one fcc process), written to one run directory.

run directory
    summary.json      deterministic results (the seed decides them; hil.rig.report)
    run_info.json     wall-clock times, fcc command line, step execution times
    bus.log           the whole bus, candump log format (candump -L / -l)
    fcc.log           fcc's stdout/stderr (event lines, final counter block); qemu-m4f: the
                      image's log UART; external: the command line the device should run
    qemu.log, bootcfg.bin   qemu-m4f: QEMU's own messages, the image's boot configuration
    faults.log        every injected fault's start and end, with its time
    cdrw.csv, missile_T0.100_b8.csv, missile_T0.100_b8_fine.csv, campaign.csv ...
    *.png             the papers' figures (hil.plots)
"""
from __future__ import annotations

import dataclasses
import math
import os
import platform
import shlex
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol

import numpy as np

from .. import metrics
from ..bus import FrameCodec, load
from ..bus.candump import LogFrame, read_log
from ..faults import Scenario, ScenarioError, with_fault_start
from ..plants.options import LqgOptions
from ..progress import bar as progress_bar
from .apps import AppDriver, CdrwDriver, MissileDriver, OracleFlag
from .budget import check_memory
from .buslog import iter_flights, split_flights
from .lockstep import LockstepRunner
from .output import write_csv, write_json
from .results import (CdrwRecord, CdrwResult, MissileResult, cdrw_record, cdrw_result,
                      missile_open_loop, missile_result)
from . import rowtables
from .report import firmware_summary, summary_tables
from .rundir import atomic_write_text
from .session import COMMAND_FLIGHT, COMMAND_GROUND, COMMAND_RESET, RigError, RigSession, StatusCounters
from .simtime import finish_bus_log
from .targets import TARGETS


MODES = ("lockstep", "realtime")
#: realtime: fcc's SCHED_FIFO priority (the simulator runs normally: in the UML guest a
#: SCHED_FIFO python starved the guest's timers and frame delivery, measured)
FCC_RT_PRIORITY = 50
#: the LQG periods fcc accepts (firmware/app/README.md)
FCC_PERIOD_RANGE = (0.02, 0.3)


@dataclass
class RigConfig:
    out_dir: Path
    iface: str = "vcan0"
    mode: str = "lockstep"
    timeout: float = 2.0
    fcc_args: tuple[str, ...] = ()
    rows: str = "paper"            # CDRW: which estimate fcc reports (fcc --rows)
    progress: bool = True
    plots: bool = True
    fcc_binary: Path | None = None
    log_format: str = "log"
    #: the device under test (hil.rig.targets) and python-can's bus of the simulator
    target: str = "host"
    interface: str = "socketcan"
    bitrate: int | None = None
    key_file: Path | None = None   # None: a random key for each session
    #: the bus recorder of a SocketCAN session (hil.rig.processes.RECORDERS)
    recorder: str = "canrec"

    def __post_init__(self) -> None:
        if self.mode not in MODES:
            raise ValueError(f"mode must be one of {', '.join(MODES)}, not {self.mode!r}")
        if self.target not in TARGETS:
            raise ValueError(f"target must be one of {', '.join(TARGETS)}, not {self.target!r}")


@dataclass
class Outcome:
    """What a command produced: the summary (as written) and the text tables to print."""

    out_dir: Path
    summary: dict[str, Any]
    tables: list[str] = field(default_factory=list)


# ---- session helpers ------------------------------------------------------------------------
def check_missile(sc: Scenario) -> None:
    lo, hi = FCC_PERIOD_RANGE
    assert sc.lqg is not None
    if not lo - 1e-12 <= sc.lqg.period <= hi + 1e-12:
        raise ScenarioError(f"{sc.source}: [lqg]: field 'period': fcc runs the LQG at "
                            f"{lo:g} to {hi:g} s, got {sc.lqg.period:g}")


def fcc_args(scenarios: Sequence[Scenario], cfg: RigConfig, apps: Sequence[str] | None = None) -> list[str]:
    """fcc's command line for these scenarios (apps, LQG period/bits, noise variances)."""
    names = list(apps) if apps else [sc.aircraft for sc in scenarios]
    args = ["--mode", cfg.mode, "--apps", ",".join(dict.fromkeys(names))]
    for sc in scenarios:
        if sc.aircraft == "missile":
            assert sc.lqg is not None
            check_missile(sc)
            delay = sc.lqg.resolved_delay(cfg.mode == "realtime")
            args += ["--lqg-period", f"{sc.lqg.period:.6g}", "--lqg-bits", str(sc.lqg.bits),
                     "--lqg-delay", f"{delay:.6g}",
                     "--gyro-var", repr(sc.sensors.var_gyro),  # type: ignore[union-attr]
                     "--accel-var", repr(sc.sensors.var_acc)]  # type: ignore[union-attr]
    if cfg.rows != "paper":
        args += ["--rows", cfg.rows]
    if cfg.mode == "realtime" and cfg.target == "host":  # as on a flight computer (refused
        args += ["--rt-priority", str(FCC_RT_PRIORITY)]   # without privilege: one line); the
        # image has no scheduler to ask (firmware/target/README.md: not applicable)
    return args + list(cfg.fcc_args)


def open_session(out: Path, scenarios: Sequence[Scenario], cfg: RigConfig,
                 prepare: Callable[[RigSession], object] | None = None) -> RigSession:
    """The rig session of a command: its target, its bus, the device's configuration."""
    return RigSession(out, fcc_args(scenarios, cfg), iface=cfg.iface, fcc_binary=cfg.fcc_binary,
                      target=cfg.target, interface=cfg.interface, bitrate=cfg.bitrate,
                      mode=cfg.mode, answer_timeout=cfg.timeout, key_file=cfg.key_file,
                      recorder=cfg.recorder, prepare=prepare)


def lqg_request(rig: RigSession, scenarios: Sequence[Scenario]) -> tuple[float, int]:
    """(period, bits) for the first reset: a device not configured by its command line (the
    emulated image, an external device) gets the missile's design through SIM_CONTROL."""
    if rig.fcc is None or rig.fcc.configured_by_args:
        return 0.0, 0
    for sc in scenarios:
        if sc.aircraft == "missile":
            assert sc.lqg is not None
            return sc.lqg.period, sc.lqg.bits
    return 0.0, 0


def make_drivers(scenarios: Sequence[Scenario], codec: FrameCodec, cfg: RigConfig) -> list[AppDriver]:
    """The drivers of one flight (one fcc): they share the CDRW's fault truth (OracleFlag)."""
    rt = cfg.mode == "realtime"
    oracle = OracleFlag()
    return [(CdrwDriver if sc.aircraft == "cdrw" else MissileDriver)(sc, codec, rt, oracle)
            for sc in scenarios]


def _fly(rig: RigSession, drivers: Sequence[AppDriver], cfg: RigConfig, bar: Any,
         runner: Any = None, period: float = 0.0, bits: int = 0) -> Any:
    """One flight, fcc on the ground before and after it: SIM_CONTROL reset (and a new LQG
    design when period/bits are given; it is also the flight boundary in bus.log), FLIGHT,
    the steps, GROUND (fcc accepts resets and designs on the ground only)."""
    rig.control(COMMAND_RESET, period, bits)
    try:
        if cfg.mode == "lockstep":
            rig.control(COMMAND_FLIGHT)
            r = runner or LockstepRunner(rig, cfg.timeout, bar.update)
            r.fly(drivers)
            return r
        from .realtime import RealtimeRunner
        rt = runner or RealtimeRunner(rig, progress=bar.update)
        rt.fly(drivers)   # FLIGHT goes out just before the first sampling instant
        return rt
    finally:
        if rig.fcc is not None and rig.fcc.poll() is None and rig.link is not None:
            rig.control(COMMAND_GROUND)


def _require_log(rig: RigSession) -> None:
    if not rig.log_complete:
        why = rig.recorder_error or "the recorder did not catch up with the bus"
        raise RigError(f"bus.log: {why}; fcc's outputs are read from that log, so the run is "
                       f"not evaluated")


def _run_info(rig: RigSession, cfg: RigConfig, runner: Any, t_wall: float) -> dict[str, Any]:
    st = rig.status
    info: dict[str, Any] = {
        "mode": cfg.mode, "target": cfg.target, "interface": cfg.interface, "iface": cfg.iface,
        "bitrate": cfg.bitrate, "fcc_command": shlex.join(rig.fcc.cmd) if rig.fcc else "",
        "fcc_exit": rig.fcc_exit, "wall_s": t_wall, "host": platform.node(),
        # the kernel the bus ran on; inside scripts/with-vcan: "RELEASE MODE" of its UML guest
        "kernel": platform.release(), "uml": os.environ.get("WITH_VCAN_UML"),
        "python": platform.python_version(), "heartbeats": st.heartbeats,
        "worst_step_us": st.get("FCC_STATUS.worst_step_us"), "status_flags": st.last.get("FCC_STATUS", {}),
        "stale_now": st.get("FCC_E2E_FAULTS.stale_now"),
        "secured_frames_verified": rig.security.counters()["verified"],
        "link": {"tx_frames": rig.link_stats.get("tx_frames", 0), "rx_frames": rig.link_stats.get("rx_frames", 0),
                 "tx_retries": rig.link_stats.get("tx_retries", 0), "tx_dropped": rig.link_stats.get("tx_dropped", 0)},
    }
    if runner is not None:
        info.update(runner.timing())
    return info


@dataclass
class Flown:
    """A flight as the rig flew it, for its evaluation: the drivers after their last step,
    fcc's heartbeat counters, the rig's verification counters and run_info.json's facts (the
    runner's timing among them)."""

    drivers: list[AppDriver]
    status: StatusCounters
    security: dict[str, int]
    info: dict[str, Any]
    transmitter: dict[str, Any] = field(default_factory=dict)


class FlightWitness(Protocol):
    """Another node that takes part in a flight (hil.verify's attacker): the flight starts
    once it is ready, and it stops before the rig shuts fcc down (so that the recorder closes
    the log on the rig's own end marker)."""

    def wait_ready(self) -> None: ...

    def stop_now(self) -> None: ...


def run_flight(scenarios: Sequence[Scenario], cfg: RigConfig, command: str = "run",
               witness: FlightWitness | None = None) -> Outcome:
    """One flight of one or both aircraft (interleaved in one fcc when both), evaluated."""
    out = cfg.out_dir
    if len({sc.aircraft for sc in scenarios}) != len(scenarios):
        raise ValueError("one scenario per aircraft")
    check_memory(scenarios)
    t0 = time.perf_counter()
    # the drivers are computed while the session listens for another fcc on the bus
    with open_session(out, scenarios, cfg, lambda rig: make_drivers(scenarios, rig.codec, cfg)) as rig:
        drivers: list[AppDriver] = rig.prepared  # type: ignore[assignment]
        if witness is not None:
            witness.wait_ready()
        try:
            with progress_bar(sum(d.n_steps for d in drivers), cfg.progress, f"hil {command}") as bar:
                runner = _fly(rig, drivers, cfg, bar, None, *lqg_request(rig, scenarios))
        finally:
            if witness is not None:
                witness.stop_now()
        rig.shutdown()
    _require_log(rig)
    flown = Flown(drivers, rig.status, rig.security.counters(),
                  _run_info(rig, cfg, runner, time.perf_counter() - t0), rig.transmitter_stats)
    return evaluate_flight(scenarios, cfg, command, flown)


def count_babbled(log: Iterable[LogFrame], drivers: Sequence[AppDriver]) -> None:
    """Realtime floods come from cangen, on its own: its frames are counted in the bus log
    (frames_injected "flood" and "sent", as lockstep counts the frames it sends itself)."""
    from ..faults import Flood

    ids = {f.can_id for d in drivers for f in d.injector.faults if isinstance(f, Flood)}
    if not ids:
        return
    seen = dict.fromkeys(ids, 0)
    for fr in log:
        if fr.frame_id in seen:
            seen[fr.frame_id] += 1
    for d in drivers:
        mine = {f.can_id for f in d.injector.faults if isinstance(f, Flood)}
        n = sum(seen.pop(i, 0) for i in mine)
        d.injector.counts["flood"] += n
        d.injector.counts["sent"] += n


def _cdrw_block(res: CdrwResult, flown: str, replay: rowtables.Replay, paper: bool) -> dict[str, Any]:
    """summary.json's cdrw: Table 4 of the rows fcc flew (cdrw.rows), the bounds coverage,
    both symmetric tables (cdrw.tables: prior, posterior, from this flight's replay) and the
    replay's check."""
    tables, check = rowtables.symmetric_tables(res.series, res.dt, flown, replay)
    return {"table4": res.table, "table4_truth": res.table_truth, "rows": flown,
            "coverage": res.coverage, "tables": tables, "replay_check": check,
            "paper_scenario": paper,
            "improvement_over_kf_pct": metrics.improvements(res.table),
            "improvement_over_kf_truth_pct": metrics.improvements(res.table_truth),
            "flight": res.summary()}


def _write_cdrw(out: Path, res: CdrwResult, name: str = "cdrw.csv") -> None:
    write_csv(out / name, res.series)


def _write_missile(out: Path, res: MissileResult) -> None:
    write_csv(out / f"missile_{res.tag}.csv", res.series)
    write_csv(out / f"missile_{res.tag}_fine.csv", res.fine)


def _write_fault_log(out: Path, flights: Sequence[tuple[str, Sequence[dict[str, Any]]]]) -> None:
    """faults.log: every fault start and end, with its time, one line each."""
    lines = []
    for label, events in flights:
        for ev in events:
            lines.append(f"{label}t={ev['t']:8.3f} s  {ev['action']:5s}  [{ev['level']}] {ev['spec']}")
    atomic_write_text(out / "faults.log", "\n".join(lines) + ("\n" if lines else ""))


def step_periods(scenarios: Sequence[Scenario]) -> dict[int, float]:
    """Each application's step period (s) in these scenarios (0 CDRW, 1 missile)."""
    periods: dict[int, float] = {}
    for sc in scenarios:
        if sc.aircraft == "cdrw":
            periods[0] = float(sc.plant.dt)  # type: ignore[union-attr]
        else:
            assert sc.lqg is not None
            periods[1] = float(sc.lqg.period)
    return periods


def _finish(cfg: RigConfig, out: Path, summary: dict[str, Any], periods: dict[int, float] | None,
            log: Sequence[LogFrame] | None = None) -> Outcome:
    """The bus log finished (`log`: its frames when already read) and the report."""
    if periods is not None:   # None: no bus log in `out` (flights on several rigs, hil.parallel)
        finish_bus_log(out, cfg.mode, periods, cfg.log_format, load().baudrate, log)
    return _report(cfg, out, summary)


def _report(cfg: RigConfig, out: Path, summary: dict[str, Any]) -> Outcome:
    """The summary's tables and, unless off, the figures of the run directory."""
    tables = summary_tables(summary)
    if cfg.plots:
        from ..plots import plot_run_dir
        names = [p.name for p in plot_run_dir(out)]
        if names:
            tables.append(f"plots: {', '.join(names)}")
    return Outcome(out, summary, tables)


# ---- commands --------------------------------------------------------------------------------
def evaluate_flight(scenarios: Sequence[Scenario], cfg: RigConfig, command: str, flown: Flown) -> Outcome:
    """A flight's results from its bus log and its drivers (hil.rig.flight.run_flight): the
    CSVs, faults.log, summary.json, run_info.json, the finished bus log, the tables."""
    out = cfg.out_dir
    drivers = flown.drivers
    spec = load()
    log = list(read_log(out / "bus.log"))   # read once: the flights, then the finished log
    flights = split_flights(log)
    if cfg.mode == "realtime":
        count_babbled(log, drivers)
    summary: dict[str, Any] = {"command": command, "mode": cfg.mode,
                               "firmware": firmware_summary(flown.status, flown.security)}
    fault_log = []
    cdrw: tuple[CdrwResult, str, rowtables.Replay, bool] | None = None
    for d in drivers:
        if isinstance(d, CdrwDriver):
            res = cdrw_result(spec, cdrw_record(d), flights[0])
            flown_rows, sid_args = rowtables.sid_options(fcc_args(scenarios, cfg))
            # sid_replay's symmetric tables run while the files are written
            cdrw = (res, flown_rows, rowtables.Replay(spec, res.series, sid_args),
                    is_paper_scenario(d.scenario))
            summary["cdrw"] = None   # its place in summary.json; filled in below
            _write_cdrw(out, res)
            fault_log.append(("cdrw     ", res.events))
        else:
            assert isinstance(d, MissileDriver)
            mres = missile_result(d)  # realtime too: the reference flies with the same delay
            ol = missile_open_loop(d.scenario.replace(lqg=dataclasses.replace(d.scenario.lqg, closed_loop=False)))
            _write_missile(out, mres)
            _write_missile(out, ol)
            summary["missile"] = {"runs": [mres.run_entry(), ol.run_entry()]}
            fault_log.append(("missile  ", mres.events))
    _write_fault_log(out, fault_log)
    info = dict(flown.info)
    missiles = [d for d in drivers if isinstance(d, MissileDriver)]
    if cfg.mode == "realtime" and missiles:
        info["realtime"] = summary["realtime"] = _realtime_timing(out, flown, missiles[0])
    finish_bus_log(out, cfg.mode, step_periods(scenarios), cfg.log_format, spec.baudrate, log)
    if cdrw is not None:
        summary["cdrw"] = _cdrw_block(*cdrw)
    write_json(out / "summary.json", summary)
    write_json(out / "run_info.json", info)
    return _report(cfg, out, summary)


def is_paper_scenario(sc: Scenario) -> bool:
    """The paper's default CDRW scenario (the embedded one, its seed, its fault): only then
    are the paper's numbers printed beside ours."""
    from ..faults import load_default_scenario
    try:
        ref = load_default_scenario("cdrw", {m.name for m in RigSession.dbc_frames()})
    except Exception:  # noqa: BLE001 - no default, no paper rows
        return False
    return sc.aircraft == "cdrw" and sc.seed == ref.seed and sc.duration == ref.duration \
        and sc.plant == ref.plant and sc.sensors == ref.sensors \
        and [f.describe() for f in sc.faults] == [f.describe() for f in ref.faults]


def _realtime_timing(out: Path, flown: Flown, d: MissileDriver) -> dict[str, Any]:
    """Offset, jitter and data age of a realtime missile flight (hil.rig.timing), and the
    samples behind them in realtime_timing.csv (the histograms); the simulator's hand-over
    slack and its transmitter's send lateness."""
    from . import timing
    t = timing.bus_timing(out / "bus.log", load(), d.period)
    timing.write_csv(out / timing.CSV_NAME, t)
    log = out / "fcc.log"
    rep = timing.summarise(t, log.read_text(errors="replace") if log.is_file() else "")
    st = flown.status
    rep["sync_status"] = {k.split(".", 1)[1]: v for k, v in st.values.items()
                          if k.startswith("FCC_SYNC_STATUS.")}
    rep["delay_s"] = d.delay
    rep["commands_late"] = d.cmd_late
    t = flown.info   # (run_info.json's facts hold the runner's timing)
    rep["simulator"] = {"late_steps": t["sim_late_steps"], "steps": t["realtime_steps"],
                        "handover_slack_ms": t["sim_handover_slack_ms"],
                        "stale_frames": t["sim_stale_frames"], "transmitter": flown.transmitter}
    return rep


def campaign_fault_times(scenario: Scenario, runs: int, seed: int,
                         margin: float = 0.5) -> np.ndarray:
    """Table 5: when the scenario's faults (moved together) start in each flight -- uniform
    over the flight, `margin` s clear of both ends, on the 50 Hz sample grid."""
    if not scenario.faults:
        raise ScenarioError(f"{scenario.source}: a campaign needs a scenario with a fault")
    ends = [f.end for f in scenario.faults]
    span = (max(ends) if all(math.isfinite(e) for e in ends) else 0.0) - min(f.start for f in scenario.faults)
    hi = scenario.duration - margin - max(span, 0.0)
    if hi <= margin:
        raise ScenarioError(f"{scenario.source}: the flight is too short for faults at random times")
    rng = np.random.default_rng([int(seed), 0x6361])  # own stream: "ca"
    return np.round(rng.uniform(margin, hi, size=runs) / 0.02) * 0.02


@dataclass
class CampaignFlight:
    """One campaign flight as Table 5 needs it (small: it crosses processes and machines when
    the flights are flown in parallel, hil.parallel)."""

    index: int
    fault_start: float
    table: metrics.Table
    table_truth: metrics.Table
    missing_steps: int
    unanswered_steps: int
    events: list[dict[str, Any]]
    series: dict[str, np.ndarray] | None = None   # flight 0 only: cdrw_run0.csv
    coverage: metrics.Table | None = None           # bounds coverage of fcc's rows
    rows: str = "paper"                             # the rows fcc flew
    modes: dict[str, Any] | None = None             # rowtables.symmetric_tables: prior, posterior
    replay_check: dict[str, Any] | None = None


def _flag_value(args: Sequence[str], flag: str) -> str | None:
    """The value of the last `flag VALUE` in a command line (None: not given)."""
    value = None
    for i, a in enumerate(args[:-1]):
        if a == flag:
            value = args[i + 1]
    return value


def campaign_flight(index: int, fault_start: float, res: CdrwResult,
                    fcc_arg_list: Sequence[str] = ()) -> CampaignFlight:
    """One flight's share of Table 5; fcc_arg_list (fcc's command line) says which rows fcc
    flew and with which identification options, for the symmetric tables."""
    from ..bus import load as load_spec
    lost = res.missing_steps - res.unanswered_steps
    if lost > 0 and _flag_value(fcc_arg_list, "--mode") != "realtime":
        # in lockstep every answered step has its estimates on the bus: a gap is the
        # recorder's, and Table 5 would average the flight over the steps that are left
        raise RigError(f"bus.log: campaign flight {index} lacks fcc's estimates of {lost} answered "
                       f"steps (the recorder lost frames); the flight is not evaluated")
    flown, sid_args = rowtables.sid_options(fcc_arg_list)
    modes, check = rowtables.symmetric_tables(res.series, res.dt, flown,
                                              rowtables.Replay(load_spec(), res.series, sid_args))
    return CampaignFlight(index, fault_start, res.table, res.table_truth, res.missing_steps,
                          res.unanswered_steps, res.events, res.series if index == 0 else None,
                          res.coverage, flown, modes, check)


def _campaign_modes(flights: Sequence[CampaignFlight]) -> dict[str, Any]:
    """cdrw.rows, cdrw.tables (Table 5 with intervals in prior and posterior rows) and
    cdrw.replay_check of a campaign, from its flights' symmetric tables."""
    flown = flights[0].rows
    missing = next((fl.replay_check for fl in flights if not fl.modes), None)
    if missing is not None:
        return {"rows": flown, "tables": {},
                "replay_check": {"rows": flown, "not_computed": (missing or {}).get(
                    "not_computed", "no symmetric tables for some flights")}}
    tables = {m: metrics.campaign_table5([fl.modes[m]["table4"] for fl in flights],  # type: ignore[index]
                                         [fl.modes[m]["table4_truth"] for fl in flights],  # type: ignore[index]
                                         coverage=[fl.modes[m]["coverage"] for fl in flights])  # type: ignore[index]
              for m in rowtables.SYMMETRIC}
    worst = max(fl.replay_check["max_abs_estimate_difference"] for fl in flights)  # type: ignore[index]
    return {"rows": flown, "tables": tables,
            "replay_check": {"rows": flown, "max_abs_estimate_difference": worst}}


def write_campaign(out: Path, scenario: Scenario, seed: int, runs: int,
                   flights: Sequence[CampaignFlight], firmware: dict[str, Any], mode: str,
                   failed: Sequence[dict[str, Any]] = ()) -> dict[str, Any]:
    """Table 5 from the campaign's flights (in any order; merged by index): campaign.csv,
    cdrw_run0.csv, faults.log and summary.json.  `failed`: flights that gave no result
    (listed in the summary; Table 5 is then the mean over the others)."""
    flights = sorted(flights, key=lambda f: f.index)
    if not flights:
        raise RigError(f"{out}: no campaign flight gave a result")
    rows: dict[str, list[float]] = {"run": [], "fault_start": []}
    per_run = []
    for fl in flights:
        if fl.series is not None:
            write_csv(out / "cdrw_run0.csv", fl.series)
        rows["run"].append(fl.index)
        rows["fault_start"].append(fl.fault_start)
        for key, table in (("meas", fl.table), ("truth", fl.table_truth)):
            for f in metrics.FILTERS:
                for s in metrics.STATES:
                    rows.setdefault(f"{f}_{s}_{key}", []).append(table[f][s])
        per_run.append({"run": fl.index, "fault_start": fl.fault_start, "error": fl.table,
                        "error_truth": fl.table_truth, "missing_steps": fl.missing_steps,
                        "unanswered_steps": fl.unanswered_steps})
    _write_fault_log(out, [(f"flight {fl.index:3d}  ", fl.events) for fl in flights])
    write_csv(out / "campaign.csv", {k: np.asarray(v) for k, v in rows.items()})
    summary: dict[str, Any] = {
        "command": "campaign", "mode": mode, "seed": seed, "runs_count": runs,
        "scenario": scenario.name or scenario.source, "flight_seed": scenario.seed,
        "faults": [f.describe() for f in scenario.faults],
        "cdrw": {**metrics.campaign_table5(
            [fl.table for fl in flights], [fl.table_truth for fl in flights],
            coverage=[fl.coverage for fl in flights] if all(fl.coverage for fl in flights) else None),
            **_campaign_modes(flights), "paper_scenario": is_paper_scenario(scenario),
            "runs": per_run},
        "firmware": firmware}
    if failed:
        summary["failed_runs"] = list(failed)
    write_json(out / "summary.json", summary)
    return summary


def run_campaign(scenario: Scenario, runs: int, seed: int, cfg: RigConfig) -> Outcome:
    """Table 5: the same flight `runs` times, the scenario's faults at random times, one fcc
    process reset between flights."""
    if scenario.aircraft != "cdrw":
        raise ScenarioError(f"{scenario.source}: a campaign flies the CDRW (aircraft = \"cdrw\")")
    if runs < 1:
        raise ValueError(f"--runs must be >= 1, got {runs}")
    check_memory([scenario], flights=runs)
    out = cfg.out_dir
    starts = campaign_fault_times(scenario, runs, seed)
    t0 = time.perf_counter()
    records: list[CdrwRecord] = []
    with open_session(out, [scenario], cfg) as rig:
        n = int(round(scenario.duration / scenario.plant.dt)) + 1  # type: ignore[union-attr]
        runner = None
        with progress_bar(runs * n, cfg.progress, "hil campaign") as bar:
            for t_fault in starts:
                d = CdrwDriver(with_fault_start(scenario, float(t_fault)), rig.codec, cfg.mode == "realtime")
                runner = _fly(rig, [d], cfg, bar, runner)
                records.append(cdrw_record(d))   # the driver (every sample's model) is dropped
        rig.shutdown()
    _require_log(rig)
    args = fcc_args([scenario], cfg)
    flights = [campaign_flight(i, float(starts[i]), cdrw_result(rig.spec, rec, fl), args)
               for i, (rec, fl) in enumerate(zip(records, iter_flights(out / "bus.log")))]
    if len(flights) != runs:
        raise RigError(f"bus.log: {len(flights)} flights recorded, expected {runs}")
    summary = write_campaign(out, scenario, seed, runs, flights, firmware_summary(rig.status, rig.security.counters()), cfg.mode)
    write_json(out / "run_info.json", _run_info(rig, cfg, runner, time.perf_counter() - t0))
    return _finish(cfg, out, summary, step_periods([scenario]))


def sweep_points(scenario: Scenario, periods: Sequence[float], bits: Sequence[int]) -> list[Scenario]:
    """The closed-loop flights of a sweep, in order: every (T, N), T outer."""
    if scenario.aircraft != "missile":
        raise ScenarioError(f"{scenario.source}: a sweep flies the missile (aircraft = \"missile\")")
    if not periods or not bits:
        raise ValueError("a sweep needs at least one period and one word length")
    points = []
    for T in periods:
        for n in bits:
            lqg = LqgOptions(period=float(T), bits=int(n), closed_loop=True)
            sc = scenario.replace(lqg=lqg)
            check_missile(sc)
            if sc.lqg.period > sc.duration:  # type: ignore[union-attr]
                raise ScenarioError(f"{scenario.source}: period {T} s is longer than the flight")
            points.append(sc)
    for n in bits:
        if not 2 <= int(n) <= 16:
            raise ScenarioError(f"--bits: D/A word length must be 2 to 16, got {n}")
    return points


def write_sweep(out: Path, scenario: Scenario, periods: Sequence[float], results: Sequence[MissileResult],
                firmware: dict[str, Any], mode: str) -> dict[str, Any]:
    """Fig. 3 from the sweep's closed-loop flights (in sweep_points order) and the open loop
    at every T: the missile CSVs, faults.log and summary.json."""
    base_lqg = scenario.lqg
    assert base_lqg is not None
    runs_out: list[dict[str, Any]] = []
    fault_log = []
    for res in results:
        _write_missile(out, res)
        runs_out.append(res.run_entry())
        fault_log.append((f"{res.tag:12s}", res.events))
    _write_fault_log(out, fault_log)
    for T in periods:
        sc = scenario.replace(lqg=LqgOptions(period=float(T), bits=base_lqg.bits, closed_loop=False))
        ol = missile_open_loop(sc)
        _write_missile(out, ol)
        runs_out.append(ol.run_entry())
    summary = {"command": "sweep", "mode": mode, "scenario": scenario.name or scenario.source,
               "seed": scenario.seed, "missile": {"runs": runs_out}, "firmware": firmware}
    write_json(out / "summary.json", summary)
    return summary


def run_sweep(scenario: Scenario, periods: Sequence[float], bits: Sequence[int],
              cfg: RigConfig) -> Outcome:
    """Fig. 3: the missile at every (T, N), one fcc process redesigning on SIM_CONTROL
    between flights; plus the open loop at every T."""
    points = sweep_points(scenario, periods, bits)
    check_memory(points)
    out = cfg.out_dir
    t0 = time.perf_counter()
    first = points[0]
    mdrivers: list[MissileDriver] = []
    with open_session(out, [first], cfg) as rig:
        total = 0
        for sc in points:  # as MissileSimulation: every period flies the whole duration
            total += max(1, int(math.ceil(sc.duration / sc.lqg.period - 1e-9)))  # type: ignore[union-attr]
        runner = None
        with progress_bar(total, cfg.progress, "hil sweep") as bar:
            for sc in points:
                assert sc.lqg is not None
                d = MissileDriver(sc, rig.codec, cfg.mode == "realtime")
                runner = _fly(rig, [d], cfg, bar, runner, sc.lqg.period, sc.lqg.bits)
                mdrivers.append(d)
        rig.shutdown()
    results = [missile_result(d, reference=cfg.mode == "lockstep") for d in mdrivers]
    summary = write_sweep(out, scenario, periods, results, firmware_summary(rig.status, rig.security.counters()), cfg.mode)
    write_json(out / "run_info.json", _run_info(rig, cfg, runner, time.perf_counter() - t0))
    return _finish(cfg, out, summary, step_periods([first]))


def run_fig3(cfg: RigConfig, seconds: float = 0.0, periods: Sequence[float] = (),
             bits: Sequence[int] = ()) -> Outcome:
    """Fig. 3 as the paper ran it: the covariance analysis at both gyro variances on the fine
    grid, and HIL Monte-Carlo points (one long flight per point in stationary gusts, fcc on
    the bus) with 95 % batch-means intervals; fig3.json + fig3_missile_rms_covariance.png."""
    from ..faults import load_default_scenario
    from ..plants.missile_cov import missile_rms_study
    from . import figures
    from .paths import tool

    seconds = seconds or figures.MC_SECONDS
    periods = tuple(periods) or figures.MC_PERIODS
    bits = tuple(bits) or figures.MC_BITS
    base = load_default_scenario("missile", {m.name for m in RigSession.dbc_frames()})
    out = cfg.out_dir
    studies, hil = [], []
    for var in figures.FIG3_GYRO_VARS:
        studies.append(missile_rms_study(figures.FIG3_PERIODS, figures.FIG3_BITS, var,
                                         base.sensors.var_acc, tool("lqg_design")))  # type: ignore[union-attr]
        sub = out / f"mc_gyro_{var:g}"
        sub.mkdir(parents=True, exist_ok=True)
        sc = figures.stationary_scenario(base, var, seconds)
        o = run_sweep(sc, periods, bits, dataclasses.replace(cfg, out_dir=sub, plots=False))
        for r in o.summary["missile"]["runs"]:
            if r["bits"] is None:
                continue
            tag = f"T{r['period']:.3f}_b{r['bits']}"
            hil.append({"gyro_var": var, "period": r["period"], "bits": r["bits"], "seed": sc.seed,
                        **figures.batch_rms(sub / f"missile_{tag}_fine.csv", seconds)})
    doc = figures.fig3_document(studies, hil)
    figures.write_fig3(out, doc)
    summary = {"command": "fig3", "fig3": doc}
    write_json(out / "summary.json", summary)
    return _report(cfg, out, summary)


def run_responses(cfg: RigConfig) -> Outcome:
    """Figs. 4-6: deterministic initial-condition responses through fcc (q0 = 0.1 rad/s, no
    gust, no sensor noise) at T = 0.2, 0.1, 0.05 s, open loop and 6, 8, 12 bits."""
    from ..faults import load_default_scenario
    from . import figures

    base = load_default_scenario("missile", {m.name for m in RigSession.dbc_frames()})
    sc = figures.response_scenario(base)
    o = run_sweep(sc, figures.RESPONSE_PERIODS, figures.RESPONSE_BITS,
                  dataclasses.replace(cfg, plots=False))
    rows = figures.dead_zone(cfg.out_dir, o.summary["missile"]["runs"])
    o.summary["responses"] = {"deterministic": True, "seconds": sc.duration, "dead_zone": rows}
    write_json(cfg.out_dir / "summary.json", o.summary)
    return _report(cfg, cfg.out_dir, o.summary)


def _fresh(path: Path) -> Path:
    path.mkdir(parents=True, exist_ok=True)
    for pattern in ("*.csv", "*.png", "*.json", "*.log", "*.asc", "*.blf"):
        for f in path.glob(pattern):
            if f.is_file():
                f.unlink()
    return path


def run_demo(cfg: RigConfig) -> list[Outcome]:
    """The README's main job: both aircraft with their embedded default scenarios in one fcc
    (the CDRW with the paper's sensor fault at 4 s); then seed 2 as the paper ran it: the
    deterministic responses of Figs. 4-6 (out_dir/responses) and Fig. 3 by covariance
    analysis with HIL Monte-Carlo points (out_dir/fig3)."""
    from ..faults import load_default_scenario

    frames = {m.name for m in RigSession.dbc_frames()}
    cdrw = load_default_scenario("cdrw", frames)
    msl = load_default_scenario("missile", frames)
    first = run_flight([cdrw, msl], cfg, command="demo")
    responses = run_responses(dataclasses.replace(cfg, out_dir=_fresh(cfg.out_dir / "responses")))
    fig3 = run_fig3(dataclasses.replace(cfg, out_dir=_fresh(cfg.out_dir / "fig3")))
    return [first, responses, fig3]
