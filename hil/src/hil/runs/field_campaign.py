"""`hil campaign AIRCRAFT --vary KEY=V1,V2,... --draw KEY=LAW:A,B --keep-logs`: a campaign over
any scenario field, for either aircraft (hil.scenario.vary).

Every flight is a `hil run` of its own scenario (hil.runs.run.run_flight, in
flights/NNNN/ of the run directory): the product of the --vary values, `runs` flights of each,
each run's --draw values and, when the scenario has faults, their random start (Table 5's rule,
hil.scenario.campaign) the same in every combination (common random numbers: the
combinations differ only by what is varied).  A flight's numbers are those of the single run
of its scenario; --keep-logs keeps its whole run directory (bus log, bus key, run_info.json:
what `hil replay` needs), otherwise it is removed once its numbers are taken.

run directory
    campaign.csv     a row per flight: flight, combination, run, each varied and drawn key
                     (a text value: nan, see summary.json), fault_start, the flight's numbers
    summary.json     command, aircraft, seed, vary, draw, combinations (values, flights, means)
    run_info.json    mode, wall_s (and with --workers/--scheduler: the cluster's, hil.parallel)
    flights/NNNN/    --keep-logs: each flight's run directory (`hil replay` replays it)
"""
from __future__ import annotations

import dataclasses
import math
import shutil
import time
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from hil.io.output import write_csv, write_json
from hil.rig.config import RigConfig
from hil.rig.errors import RigError
from hil.runs.campaign import table_columns
from hil.runs.outcome import Outcome
from hil.runs.run import run_flight
from hil.scenario.campaign import campaign_fault_times
from hil.scenario.file import Scenario, with_fault_start
from hil.scenario.vary import Draw, Vary, check, draw_values, grid, with_fields
from hil.util.progress import bar as progress_bar

#: a missile flight's numbers: its closed-loop entry's (summary.json missile.runs)
MISSILE_NUMBERS = ("rms_q", "rms_alpha", "commands_missing", "commands_rejected", "commands_late",
                   "unanswered_steps")
#: a flight's verdicts (hil.results.sync, hil.results.trust): the campaign's is its worst
VERDICTS = ("sync", "bus_trust")


def flight_numbers(summary: dict[str, Any]) -> dict[str, float]:
    """The numbers of a flight's summary.json that a campaign compares."""
    if summary.get("cdrw"):
        cd = summary["cdrw"]
        return table_columns(cd["table4"], cd["table4_truth"])
    runs = summary["missile"]["runs"]
    entry = next((r for r in runs if r["closed_loop"]), runs[0])
    return {k: float(entry[k]) for k in MISSILE_NUMBERS if k in entry}


def flights_of(scenario: Scenario, runs: int, seed: int, varies: Sequence[Vary],
               draws: Sequence[Draw]) -> list[tuple[dict[str, Any], Scenario]]:
    """Every flight of the campaign, in order (combination outer, run inner): its key (the
    combination's index and values, the run, its draws, its fault start) and its scenario."""
    if runs < 1:
        raise ValueError(f"--runs must be >= 1, got {runs}")
    check(scenario, varies, draws)
    drawn = draw_values(draws, runs, seed)
    flights: list[tuple[dict[str, Any], Scenario]] = []
    for c, values in enumerate(grid([(v.key, v.values) for v in varies])):
        base = with_fields(scenario, values, "--vary " + " ".join(f"{k}={v}" for k, v in values.items()))
        starts = campaign_fault_times(base, runs, seed) if base.faults else None
        for r in range(runs):
            where = f"flight {len(flights)}"
            sc = with_fields(base, drawn[r], where)
            key: dict[str, Any] = {"flight": len(flights), "combination": c, "run": r, **values, **drawn[r]}
            if starts is not None:
                key["fault_start"] = float(starts[r])
                sc = with_fault_start(sc, float(starts[r]))
            flights.append((key, sc))
    return flights


def _cell(value: Any) -> float:
    return float(value) if isinstance(value, (int, float)) else math.nan


def _worst_verdicts(summaries: Sequence[dict[str, Any]]) -> dict[str, Any]:
    """Per kind, the first flight's verdict that is not ok, else the first flight's
    (cli.common.sync_status reads them)."""
    worst: dict[str, Any] = {}
    for key in VERDICTS:
        given = [s[key] for s in summaries if s.get(key)]
        if given:
            worst[key] = next((v for v in given if v.get("verdict", "ok") != "ok"), given[0])
    return worst


def run_field_campaign(scenario: Scenario, runs: int, seed: int, varies: Sequence[Vary],
                       draws: Sequence[Draw], keep_logs: bool, cfg: RigConfig) -> Outcome:
    """The campaign's flights in this process's rig, each a single run (flights/NNNN/), and
    its tables."""
    out = Path(cfg.out_dir)
    plan = flights_of(scenario, runs, seed, varies, draws)
    t0 = time.perf_counter()
    summaries = {}
    with progress_bar(len(plan), cfg.progress, "hil campaign", unit="flight") as bar:
        for key, sc in plan:   # (one bar of flights, not one of steps per flight)
            where = out / "flights" / f"{key['flight']:04d}"
            flight_cfg = dataclasses.replace(cfg, out_dir=where, plots=False, progress=False)
            summaries[key["flight"]] = run_flight([sc], flight_cfg).summary
            if keep_logs:
                key["dir"] = str(where.relative_to(out))
            else:
                shutil.rmtree(where)
            bar.update(1)
    if not keep_logs and (out / "flights").is_dir():
        (out / "flights").rmdir()
    outcome = finish_field_campaign(out, scenario, seed, runs, varies, draws, plan, summaries, cfg.mode)
    write_json(out / "run_info.json", {"mode": cfg.mode, "wall_s": time.perf_counter() - t0})
    return outcome


def finish_field_campaign(out: Path, scenario: Scenario, seed: int, runs: int, varies: Sequence[Vary],
                          draws: Sequence[Draw], plan: Sequence[tuple[dict[str, Any], Scenario]],
                          summaries: Mapping[int, dict[str, Any]], mode: str,
                          failed: Sequence[dict[str, Any]] = ()) -> Outcome:
    """campaign.csv and summary.json from the flights' single-run summaries (by flight; those
    that failed are listed in `failed`: summary.json failed_runs), and the table to print."""
    done = [key for key, _ in plan if key["flight"] in summaries]
    if not done:
        raise RigError(f"{out}: no campaign flight gave a result")
    rows = [{**key, **flight_numbers(summaries[key["flight"]])} for key in done]
    summary = write_field_campaign(out, scenario, seed, runs, varies, draws, done, rows, mode)
    summary.update(_worst_verdicts([summaries[key["flight"]] for key in done]))
    if failed:
        summary["failed_runs"] = list(failed)
    write_json(out / "summary.json", summary)
    return Outcome(out, summary, [format_combinations(summary)])


def write_field_campaign(out: Path, scenario: Scenario, seed: int, runs: int, varies: Sequence[Vary],
                         draws: Sequence[Draw], keys: Sequence[dict[str, Any]],
                         rows: Sequence[dict[str, Any]], mode: str) -> dict[str, Any]:
    """campaign.csv (a row per flight) and the summary (its combinations with their means)."""
    names = list(dict.fromkeys(k for row in rows for k in row if k != "dir"))
    write_csv(out / "campaign.csv", {n: np.asarray([_cell(row.get(n)) for row in rows]) if n not in
                                     ("flight", "combination", "run") else np.asarray([row[n] for row in rows])
                                     for n in names})
    numbers = [n for n in rows[0] if n not in keys[0]]
    combinations = []
    for c, values in enumerate(grid([(v.key, v.values) for v in varies])):
        mine = [(key, row) for key, row in zip(keys, rows) if key["combination"] == c]
        combinations.append({
            "combination": c, "values": values,
            "flights": [{**key, **{n: row[n] for n in numbers}} for key, row in mine],
            "mean": {n: float(np.mean([row[n] for _, row in mine])) for n in numbers} if mine else {}})
    return {"command": "campaign", "aircraft": scenario.aircraft, "mode": mode, "seed": seed,
            "runs_count": runs, "scenario": scenario.name or scenario.source,
            "flight_seed": scenario.seed, "faults": [f.describe() for f in scenario.faults],
            "vary": {v.key: list(v.values) for v in varies},
            "draw": {d.key: d.describe() for d in draws},
            "combinations": combinations}


def format_combinations(summary: dict[str, Any]) -> str:
    """The campaign's table: each combination's values and the mean of its flights' numbers."""
    combos = summary["combinations"]
    keys = list(summary["vary"])
    numbers = list(next(c["mean"] for c in combos if c["mean"]))[:6]
    head = ["#", *keys, *numbers]
    body = [[str(c["combination"]), *(str(c["values"][k]) for k in keys),
             *(f"{c['mean'][n]:.6g}" if c["mean"] else "failed" for n in numbers)] for c in combos]
    widths = [max(len(r[i]) for r in [head, *body]) for i in range(len(head))]
    lines = ["  ".join(cell.rjust(w) for cell, w in zip(r, widths)) for r in [head, *body]]
    return "\n".join([f"Campaign: {summary['aircraft']}, {summary['runs_count']} flight(s) per "
                      "combination; the mean of each combination's flights", *lines])
