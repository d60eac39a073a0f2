"""`hil campaign`: Table 5, the same CDRW flight many times with the scenario's faults at
random times (hil.scenario.campaign), one fcc reset between flights; the flights' share of the
table (evaluate_flights) and the table from them in any order (write_campaign, also for the
flights flown on many rigs, hil.parallel).
"""
from __future__ import annotations

import time
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from hil.bus import load as load_spec
from hil.io.output import write_csv, write_json
from hil.results import metrics, rowtables
from hil.results.buslog import BusAuth, iter_flights
from hil.results.flight import CdrwRecord, CdrwResult, cdrw_record, cdrw_result, require_estimates
from hil.results.report import firmware_summary
from hil.rig.config import RigConfig
from hil.rig.errors import RigError
from hil.rig.flight import fcc_args, fly, open_session, require_log, run_info
from hil.runs.budget import check_memory
from hil.runs.outcome import Outcome, finish, step_periods, write_fault_log
from hil.scenario.campaign import campaign_fault_times
from hil.scenario.file import Scenario, is_paper_scenario, with_fault_start
from hil.scenario.schema import ScenarioError
from hil.sim.drivers import CdrwDriver
from hil.util.progress import bar as progress_bar


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


def table_columns(table: metrics.Table, table_truth: metrics.Table) -> dict[str, float]:
    """A CDRW flight's Table 4 as campaign.csv's columns: FILTER_STATE_meas and _truth."""
    return {f"{f}_{s}_{key}": t[f][s]
            for key, t in (("meas", table), ("truth", table_truth))
            for f in metrics.FILTERS for s in metrics.STATES}


def _flag_value(args: Sequence[str], flag: str) -> str | None:
    """The value of the last `flag VALUE` in a command line (None: not given)."""
    value = None
    for i, a in enumerate(args[:-1]):
        if a == flag:
            value = args[i + 1]
    return value


def start_campaign_flight(index: int, fault_start: float, res: CdrwResult,
                          fcc_arg_list: Sequence[str] = ()) -> Callable[[], CampaignFlight]:
    """One flight's share of Table 5, in two halves: the flight's replay (sid_replay) starts
    now; the function returned waits for it and gives the CampaignFlight.  fcc_arg_list
    (fcc's command line) says which rows fcc flew and with which identification options, for
    the symmetric tables."""
    require_estimates(res, f"campaign flight {index}", _flag_value(fcc_arg_list, "--mode") == "realtime")
    flown, sid_args = rowtables.sid_options(fcc_arg_list)
    replay = rowtables.Replay(load_spec(), res.series, sid_args)

    def finish() -> CampaignFlight:
        modes, check = rowtables.symmetric_tables(res.series, res.dt, flown, replay)
        return CampaignFlight(index, fault_start, res.table, res.table_truth, res.missing_steps,
                              res.unanswered_steps, res.events, res.series if index == 0 else None,
                              res.coverage, flown, modes, check)
    return finish


def evaluate_flights(results: Iterable[tuple[int, float, CdrwResult]],
                     fcc_arg_list: Sequence[str] = ()) -> Iterator[CampaignFlight]:
    """The CampaignFlight of each (index, fault start, result), a flight's replay running while
    the next result is made (read from the bus log: `results` is lazy) and its replay
    started, so that neither waits for the other."""
    pending = None
    for index, fault_start, res in results:
        started = start_campaign_flight(index, fault_start, res, fcc_arg_list)
        if pending is not None:
            yield pending()
        pending = started
    if pending is not None:
        yield pending()


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
                   failed: Sequence[dict[str, Any]] = (), uncounted: Sequence[int] = ()) -> dict[str, Any]:
    """Table 5 from the campaign's flights (in any order; merged by index): campaign.csv,
    cdrw_run0.csv, faults.log and summary.json.  `failed`: flights that gave no result
    (listed in the summary; Table 5 is then the mean over the others).  `uncounted`: flights
    in Table 5 whose share of fcc's counters is not in `firmware` (flown by a rig session that
    failed after them: fcc's last heartbeat, mid-flight, is lost; hil.parallel)."""
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
        for name, value in table_columns(fl.table, fl.table_truth).items():
            rows.setdefault(name, []).append(value)
        per_run.append({"run": fl.index, "fault_start": fl.fault_start, "error": fl.table,
                        "error_truth": fl.table_truth, "missing_steps": fl.missing_steps,
                        "unanswered_steps": fl.unanswered_steps})
    write_fault_log(out, [(f"flight {fl.index:3d}  ", fl.events) for fl in flights])
    write_csv(out / "campaign.csv", {k: np.asarray(v) for k, v in rows.items()})
    summary: dict[str, Any] = {
        "command": "campaign", "mode": mode, "seed": seed, "runs_count": runs,
        "scenario": scenario.name or scenario.source, "flight_seed": scenario.seed,
        "faults": [f.describe() for f in scenario.faults],
        "cdrw": {**metrics.campaign_table5(
            [fl.table for fl in flights], [fl.table_truth for fl in flights],
            coverage=[fl.coverage for fl in flights if fl.coverage] if all(fl.coverage for fl in flights) else None),
            **_campaign_modes(flights), "paper_scenario": is_paper_scenario(scenario),
            "runs": per_run},
        "firmware": firmware}
    if failed:
        summary["failed_runs"] = list(failed)
    if uncounted:
        summary["firmware_uncounted"] = sorted(uncounted)
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
                runner = fly(rig, [d], cfg, bar, runner)
                records.append(cdrw_record(d))   # the driver (every sample's model) is dropped
        rig.shutdown()
    require_log(rig)
    args = fcc_args([scenario], cfg)
    flights = list(evaluate_flights(
        ((i, float(starts[i]), cdrw_result(rig.spec, rec, fl)) for i, (rec, fl) in enumerate(zip(
            records, iter_flights(out / "bus.log", BusAuth(rig.security.key, rig.security.trip))))),
        args))
    if len(flights) != runs:
        raise RigError(f"bus.log: {len(flights)} flights recorded, expected {runs}")
    summary = write_campaign(out, scenario, seed, runs, flights,
                             firmware_summary(rig.status, rig.security.counters()), cfg.mode)
    write_json(out / "run_info.json", run_info(rig, cfg, runner, time.perf_counter() - t0))
    return finish(cfg, out, summary, step_periods([scenario]))
