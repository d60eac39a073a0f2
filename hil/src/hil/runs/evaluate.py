"""A flight's evaluation (hil.runs.run flies it): the CSVs, faults.log, summary.json,
run_info.json, the finished bus log and the tables, from its bus log and its drivers.
"""
from __future__ import annotations

import dataclasses
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from hil.apps.registry import application
from hil.bus import load
from hil.bus.logcolumns import LogBlock, read_blocks
from hil.bus.logio import read_frames
from hil.io.output import write_csv, write_json
from hil.results import metrics, rowtables, timing
from hil.results.buslog import split_flights
from hil.results.busstats import bus_section
from hil.results.busstats_real import read_sends, real_bus_section
from hil.results.flight import (
    CdrwResult,
    cdrw_record,
    cdrw_result,
    missile_open_loop,
    missile_result,
    require_estimates,
)
from hil.results.platform import platform_verdict
from hil.results.report import firmware_summary
from hil.results.sync import sync_summary
from hil.results.trust import Forgeries, bus_trust, faithful_replay
from hil.rig.config import RigConfig
from hil.rig.errors import RigError
from hil.rig.flight import Flown, fcc_args
from hil.rig.simtime import finish_bus_log
from hil.rig.txsched import SEND_LOG
from hil.runs.outcome import Outcome, report_outcome, step_periods, write_fault_log, write_missile
from hil.scenario.faults import Flood
from hil.scenario.file import Scenario, is_paper_scenario
from hil.sim.drivers import AppDriver, CdrwDriver, MissileDriver

def count_babbled(log: Iterable[LogBlock], drivers: Sequence[AppDriver]) -> None:
    """Realtime floods come from cangen, on its own: its frames are counted in the bus log
    (frames_injected "flood" and "sent", as lockstep counts the frames it sends itself)."""

    ids = {f.can_id for d in drivers for f in d.injector.faults if isinstance(f, Flood)}
    if not ids:
        return
    frame_ids = np.concatenate([b.frames.frame_id for b in log] or [np.zeros(0, np.int64)])
    seen = {i: int(np.count_nonzero(frame_ids == i)) for i in ids}
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


def evaluate_flight(scenarios: Sequence[Scenario], cfg: RigConfig, command: str, flown: Flown) -> Outcome:
    """A flight's results from its bus log and its drivers (run_flight): the
    CSVs, faults.log, summary.json, run_info.json, the finished bus log, the tables."""
    out = cfg.out_dir
    drivers = flown.drivers
    spec = load()
    log = list(read_blocks(out / "bus.log"))   # read once: the flights, then the finished log
    forgeries = Forgeries()   # what the reading refused on fcc's outputs (hil.results.trust)
    flights = split_flights(log, flown.auth, forgeries)
    if cfg.mode == "realtime":
        count_babbled(log, drivers)
    bus = _bus(out, cfg, flown, scenarios)   # before the log is finished (it may be converted)
    summary: dict[str, Any] = {"command": command, "mode": cfg.mode,
                               "firmware": firmware_summary(flown.status, flown.security)}
    fault_log = []
    cdrw: tuple[CdrwResult, str, rowtables.Replay, bool] | None = None
    for d in drivers:
        if isinstance(d, CdrwDriver):
            if not flights:
                raise RigError("bus.log: no authenticated flight start (SIM_CONTROL reset); the "
                               "run is not evaluated")
            res = cdrw_result(spec, cdrw_record(d), flights[0])
            require_estimates(res, f"hil {command}'s flight", cfg.mode == "realtime",
                              forgeries.describe())
            flown_rows, sid_args = rowtables.sid_options(fcc_args(scenarios, cfg))
            # sid_replay's symmetric tables run while the files are written
            cdrw = (res, flown_rows, rowtables.Replay(spec, res.series, sid_args),
                    is_paper_scenario(d.scenario))
            summary["cdrw"] = None   # its place in summary.json; filled in below
            _write_cdrw(out, res)
            fault_log.append(("cdrw     ", res.events))
        elif isinstance(d, MissileDriver):
            mres = missile_result(d)  # realtime too: the reference flies with the same delay
            assert d.scenario.lqg is not None, "a missile scenario has its [lqg]"
            ol = missile_open_loop(d.scenario.replace(lqg=dataclasses.replace(d.scenario.lqg, closed_loop=False)))
            write_missile(out, mres)
            write_missile(out, ol)
            summary["missile"] = {"runs": [mres.run_entry(), ol.run_entry()]}
            fault_log.append(("missile  ", mres.events))
        else:  # another application (hil.apps): its evaluation hook gives its summary block
            summary[d.name] = application(d.name).hook("evaluation")(d)
    write_fault_log(out, fault_log)
    info = dict(flown.info)
    missiles = [d for d in drivers if isinstance(d, MissileDriver)]
    if cfg.mode == "realtime" and missiles:
        info["realtime"] = summary["realtime"] = _realtime_timing(out, flown, missiles[0])
    if cfg.mode == "realtime":
        summary["sync"] = sync_summary(flown.status, flown.info.get("time_master"))
    finish_bus_log(out, cfg.mode, step_periods(scenarios), cfg.log_format, spec.baudrate, log)
    if cdrw is not None:
        summary["cdrw"] = _cdrw_block(*cdrw)
    summary["bus_trust"] = bus_trust(
        forgeries, flown.status, summary["cdrw"]["replay_check"] if cdrw is not None else None,
        faithful_replay(cfg.mode, cfg.target, int(np.sum(cdrw[0].series["degraded"])) if cdrw else 0))
    if bus is not None:
        summary["bus"] = bus
    if cfg.mode == "realtime":   # the timing faults, the platform's or the firmware's
        summary["platform"] = platform_verdict(summary, info, missiles[0].period if missiles else None)
    write_json(out / "summary.json", summary)
    write_json(out / "run_info.json", info)
    return report_outcome(cfg, out, summary)


def _bus(out: Path, cfg: RigConfig, flown: Flown, scenarios: Sequence[Scenario]) -> dict[str, Any] | None:
    """summary.json's bus section of a --bus wire run: canbus's model, or a real bus measured
    (an external device: hil.results.busstats_real); the bounds with the simulator's measured
    release lateness as queuing jitter."""
    late_s = max(0.0, (flown.transmitter.get("send_lateness_ms") or {}).get("max") or 0.0) * 1e-3
    if flown.bus:
        return bus_section(flown.bus, load(), scenarios, late_s)
    if cfg.bus != "wire":
        return None
    spec = load()
    try:
        sends = read_sends(out / SEND_LOG)
    except (OSError, ValueError, KeyError) as e:
        raise RigError(f"{SEND_LOG}: the simulator's send times are not readable ({e}); the real bus "
                       "is not judged") from None
    return real_bus_section(read_frames(out / "bus.log"), sends, spec, scenarios, cfg.bitrate or spec.baudrate,
                            late_s)


def _realtime_timing(out: Path, flown: Flown, d: MissileDriver) -> dict[str, Any]:
    """Offset, jitter and data age of a realtime missile flight (hil.results.timing), and the
    samples behind them in realtime_timing.csv (the histograms); the simulator's hand-over
    slack and its transmitter's send lateness."""
    t = timing.bus_timing(out / "bus.log", load(), d.period, flown.auth)
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
