"""`hil campaign ... --workers N | --scheduler ADDRESS`: Table 5 flown by many rigs.

The fault times come from the campaign seed here, in the coordinator, exactly as in the
sequential campaign (hil.rig.runs.campaign_fault_times); each flight carries its own, so the
merged Table 5, campaign.csv and summary.json are the same for any number of workers.
"""
from __future__ import annotations

import functools
import time
from pathlib import Path

from ..faults import Scenario, ScenarioError
from ..rig.output import write_json
from ..rig.session import RigError
from ..rig.runs import Outcome, RigConfig, _finish, campaign_fault_times, write_campaign
from .engine import Cluster, Flight
from .flights import add_counters, fly_campaign_flight


def run_campaign_parallel(scenario: Scenario, runs: int, seed: int, cfg: RigConfig, *,
                          workers: int | None = None, scheduler: str | None = None) -> Outcome:
    """Table 5 over `runs` flights on a local cluster of `workers` rigs or on `scheduler`.
    Flights that failed twice are listed in summary.json (failed_runs) and left out of the
    means; the caller reports them."""
    if scenario.aircraft != "cdrw":
        raise ScenarioError(f"{scenario.source}: a campaign flies the CDRW (aircraft = \"cdrw\")")
    if runs < 1:
        raise ValueError(f"--runs must be >= 1, got {runs}")
    out = Path(cfg.out_dir)
    starts = campaign_fault_times(scenario, runs, seed)
    flights = [Flight(i, fly_campaign_flight, (scenario, i, float(t))) for i, t in enumerate(starts)]
    t0 = time.perf_counter()
    with Cluster(workers, scheduler) as cluster:
        res = cluster.run(flights, cfg, progress=cfg.progress, desc="hil campaign")
    done = [res.values[i] for i in sorted(res.values)]
    failed = [{"run": i, "fault_start": float(starts[i]), "error": res.failed[i]} for i in sorted(res.failed)]
    if not done:
        raise RigError(f"all {runs} flights failed twice; run 0: {res.failed[0]}")
    firmware = functools.reduce(add_counters, [d.firmware for d in done]) if done else {}
    summary = write_campaign(out, scenario, seed, runs, [d.flight for d in done], firmware, cfg.mode,
                             failed)
    write_json(out / "run_info.json", {"mode": cfg.mode, "wall_s": time.perf_counter() - t0,
                                       "parallel": res.info})
    return _finish(cfg, out, summary, None)
