"""The flights of a case of many flights (``flights = N``, hil.verify.statistical): flown one
after the other on this shell's bus, or spread on `--workers` rigs (hil.parallel: one task per
flight, each flight in a worker's rig as `hil campaign --workers` flies a campaign's).

Each flight is flight i of the case (its scenarios with seed + i) in run_dir/flight-III, read
as a case's run is (hil.verify.fields.read_run).  On the workers a flight's directory stays
in the rig (removed there); what the judging reads comes back -- summary.json, run_info.json
and the detector's per-step figures -- and its summary.json and run_info.json are written to
run_dir/flight-III as the sequential form leaves them.

What is used of hil.parallel (its public API): engine.Cluster (a local cluster of N rigs or
a scheduler's), engine.Flight (one task: a function flown in a rig), Cluster.run's Results
(values by task, the flights that failed twice), flights.worker_config (a worker's session
keys).
"""
from __future__ import annotations

import dataclasses
import json
import shutil
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from hil.io.output import write_json
from hil.parallel.engine import Cluster, Flight
from hil.parallel.flights import worker_config
from hil.rig.config import RigConfig
from hil.rig.errors import RigError
from hil.runs.run import run_flight
from hil.scenario.file import Scenario
from hil.verify.fields import read_run


def flight_dir(run_dir: Path, i: int) -> Path:
    return run_dir / f"flight-{i:03d}"


def seeded(flights: Sequence[Scenario], i: int) -> tuple[Scenario, ...]:
    """Flight i of a case: its scenarios with seed + i."""
    return tuple(sc.replace(seed=sc.seed + i) for sc in flights)


def fly_one(flights: Sequence[Scenario], cfg: RigConfig) -> dict[str, Any]:
    """One flight in cfg.out_dir, read as a case's run is."""
    out = Path(cfg.out_dir)
    outcome = run_flight(list(flights), cfg, "verify")
    info = json.loads((out / "run_info.json").read_text(encoding="utf-8"))
    return read_run(out, outcome.summary, info, None)


def fly_on_worker(flights: Sequence[Scenario], cfg: RigConfig) -> dict[str, Any]:
    """The task: one flight in a worker's rig (its own bus key, no figures), its directory
    removed once read."""
    run = fly_one(flights, dataclasses.replace(worker_config(cfg), plots=False))
    shutil.rmtree(cfg.out_dir, ignore_errors=True)
    return run


def fly_flights(flights: Sequence[Scenario], n: int, cfg: RigConfig, run_dir: Path,
                parallel: Mapping[str, Any] | None = None) -> list[dict[str, Any]]:
    """The n flights of a case, in order; on the workers (parallel: Cluster's keyword
    arguments, hil.cli.many.parallel_options) a flight that failed twice is a RigError naming
    it (a statistic over the flights that happened to succeed would not be the case's)."""
    if parallel is None:
        return [fly_one(seeded(flights, i), dataclasses.replace(cfg, out_dir=flight_dir(run_dir, i)))
                for i in range(n)]
    tasks = [Flight(i, fly_on_worker, (seeded(flights, i),), first=i) for i in range(n)]
    with Cluster(**parallel) as cluster:
        res = cluster.run(tasks, cfg, progress=cfg.progress, desc="hil verify")
    if res.failed:
        first = min(res.failed)
        raise RigError(f"{len(res.failed)} of {n} flights failed twice on the workers; flight {first}: "
                       f"{res.failed[first]}")
    runs = [res.values[i][0] for i in range(n)]
    for i, run in enumerate(runs):
        flight_dir(run_dir, i).mkdir(parents=True, exist_ok=True)
        write_json(flight_dir(run_dir, i) / "summary.json", run["summary"])
        write_json(flight_dir(run_dir, i) / "run_info.json", run["info"])
    write_json(run_dir / "run_info.json", {"flights": n, "parallel": res.info})
    return runs
