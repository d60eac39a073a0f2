"""`hil campaign|sweep ... --workers N | --scheduler ADDRESS`: Table 5 and Fig. 3 flown by
many rigs.

Everything a flight depends on is decided here, in the coordinator, exactly as in the
sequential commands: the campaign's fault times from its seed (hil.scenario.campaign),
the sweep's (T, N) points (hil.runs.sweep.sweep_points).  Each flight carries its own inputs and
the results are merged in flight order by the sequential commands' own writers, so the run
directory is the same for any number of workers.
"""
from __future__ import annotations

import time
from collections.abc import Sequence
from pathlib import Path

from hil.bus.secoc import Counters
from hil.io.output import write_json
from hil.parallel.bulk import unpack_flights
from hil.parallel.engine import Cluster, Flight
from hil.parallel.flights import (campaign_flights, fly_campaign_flights, fly_field_flight, fly_sweep_point,
                                  one_session_counters, salvage_campaign_flights)
from hil.results.report import firmware_summary
from hil.rig.config import RigConfig
from hil.rig.errors import RigError
from hil.rig.status import StatusCounters
from hil.runs.campaign import write_campaign
from hil.runs.field_campaign import finish_field_campaign, flights_of
from hil.runs.outcome import Outcome, finish
from hil.runs.sweep import sweep_points, write_sweep
from hil.scenario.campaign import campaign_fault_times
from hil.scenario.file import Scenario
from hil.scenario.schema import ScenarioError
from hil.scenario.vary import Draw, Vary

#: tasks per worker: with equal chunks the last round then leaves at most a quarter of a
#: round idle on any rig (40 chunks of 25 on 32 rigs left 38 % idle); more only pays more
#: session starts (recorder, fcc, its first heartbeat, shutdown: once per chunk)
TASKS_PER_WORKER = 4
#: tasks per rig of this machine (--workers: hil.parallel.local): two, the fewest with which a
#: rig flies a chunk while the last is evaluated; more only pay more session starts (0.31 s
#: each: 100 flights on 2 rigs, 4 chunks against 8, 5.95 against 6.58 s, median of 3, load 4)
LOCAL_TASKS_PER_RIG = 2
#: most flights one rig session flies in a row (the rig's answer timeout grows with the chunk;
#: a failed chunk keeps the flights it finished: hil.parallel.engine)
SESSION_FLIGHTS_MAX = 100


def session_chunks(runs: int, workers: int, per_worker: int | None = None) -> list[range]:
    """The campaign's flights in consecutive chunks, one rig session each: about `per_worker`
    (TASKS_PER_WORKER) per worker, at most SESSION_FLIGHTS_MAX flights each, sizes differing by
    at most one flight.  The results do not depend on the chunks (each flight's result and
    counters are its own, merged in flight order: hil.parallel.flights), so any number of
    workers writes the same summary.json."""
    if runs < 1 or workers < 1:
        raise ValueError(f"session_chunks: runs and workers must be >= 1, got {runs}, {workers}")
    per = TASKS_PER_WORKER if per_worker is None else per_worker
    n = min(runs, max(per * workers, -(-runs // SESSION_FLIGHTS_MAX)))
    bounds = [runs * k // n for k in range(n + 1)]
    return [range(a, b) for a, b in zip(bounds, bounds[1:])]


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
    t0 = time.perf_counter()
    with Cluster(workers, scheduler) as cluster:
        chunks = session_chunks(runs, max(1, len(cluster.workers())),
                                LOCAL_TASKS_PER_RIG if cluster.local is not None else TASKS_PER_WORKER)
        tasks = [Flight(c, fly_campaign_flights, (scenario, [(i, float(starts[i])) for i in chunk]),
                        count=len(chunk), post=campaign_flights, post_args=(scenario,), first=chunk.start,
                        salvage=salvage_campaign_flights)
                 for c, chunk in enumerate(chunks)]
        res = cluster.run(tasks, cfg, progress=cfg.progress, desc="hil campaign")
        cluster.close_soon()   # the rigs stop while Table 5 is written
        done = [d for c in sorted(res.values) for d in res.values[c]]
        failed = [{"run": i, "fault_start": float(starts[i]), "error": res.failed[i]} for i in sorted(res.failed)]
        if not done:
            raise RigError(f"all {runs} flights failed twice; flight 0: {res.failed[0]}")
        # fcc's counters of the sessions that ended (a failed session's are lost with its last
        # heartbeat: those flights are named in the summary, firmware_uncounted; zeros when none did)
        counted = [d for d in done if d.firmware is not None]
        firmware = (one_session_counters([d.firmware for d in counted]) if counted
                    else firmware_summary(StatusCounters(), Counters().as_dict()))
        uncounted = [i for d in done if d.firmware is None for i in d.batch.indices]
        # a session's start and end (recorder, fcc, its first heartbeat, shutdown): the cost of
        # a chunk beside its flights' (scripts/bench parallel models the chunking from it)
        res.info["session_s_per_task"] = sum(d.session_s for d in counted) / len(counted) if counted else None
        summary = write_campaign(out, scenario, seed, runs, [fl for d in done for fl in unpack_flights(d.batch)],
                                 firmware, cfg.mode, failed, uncounted)
    write_json(out / "run_info.json", {"mode": cfg.mode, "wall_s": time.perf_counter() - t0,
                                       "parallel": res.info})
    return finish(cfg, out, summary, None)


def run_sweep_parallel(scenario: Scenario, periods: Sequence[float], bits: Sequence[int],
                       cfg: RigConfig, *, workers: int | None = None,
                       scheduler: str | None = None) -> Outcome:
    """Fig. 3 with every (T, N) flown on its own rig session, on `workers` local rigs or on
    `scheduler`; the open loop is computed here.  A point that failed twice is reported
    (summary.json failed_runs) and missing from the table."""
    points = sweep_points(scenario, periods, bits)
    out = Path(cfg.out_dir)
    flights = [Flight(i, fly_sweep_point, (sc,), first=i) for i, sc in enumerate(points)]
    t0 = time.perf_counter()
    with Cluster(workers, scheduler) as cluster:
        res = cluster.run(flights, cfg, progress=cfg.progress, desc="hil sweep")
    done = [res.values[i][0] for i in sorted(res.values)]
    if not done:
        raise RigError(f"all {len(points)} sweep flights failed twice; first: {res.failed[0]}")
    firmware = one_session_counters([d.firmware for d in done])
    summary = write_sweep(out, scenario, periods, [d.flight for d in done], firmware, cfg.mode)
    if res.failed:
        summary["failed_runs"] = [{"run": i, "period": points[i].lqg.period, "bits": points[i].lqg.bits,  # type: ignore[union-attr]
                                   "error": res.failed[i]} for i in sorted(res.failed)]
        write_json(out / "summary.json", summary)
    write_json(out / "run_info.json", {"mode": cfg.mode, "wall_s": time.perf_counter() - t0,
                                       "parallel": res.info})
    return finish(cfg, out, summary, None)


def run_field_campaign_parallel(scenario: Scenario, runs: int, seed: int, varies: Sequence[Vary],
                                draws: Sequence[Draw], keep_logs: bool, cfg: RigConfig, *,
                                workers: int | None = None, scheduler: str | None = None) -> Outcome:
    """A campaign over scenario fields with every flight a task of its own (a single run in a
    rig session: a failed rig costs that flight only, flown again once), on `workers` local
    rigs or on `scheduler`; the results as the sequential command's (finish_field_campaign).
    The rigs keep no bus log (each is read and removed there): no --keep-logs."""
    if keep_logs:
        raise ValueError("--keep-logs: the rigs of --workers/--scheduler keep no bus log")
    out = Path(cfg.out_dir)
    plan = flights_of(scenario, runs, seed, varies, draws)
    t0 = time.perf_counter()
    with Cluster(workers, scheduler) as cluster:
        res = cluster.run([Flight(key["flight"], fly_field_flight, (sc,), first=key["flight"]) for key, sc in plan],
                          cfg, progress=cfg.progress, desc="hil campaign")
    failed = [{"run": i, "error": res.failed[i]} for i in sorted(res.failed)]
    outcome = finish_field_campaign(out, scenario, seed, runs, varies, draws, plan,
                                    {i: res.values[i][0] for i in res.values}, cfg.mode, failed)
    write_json(out / "run_info.json", {"mode": cfg.mode, "wall_s": time.perf_counter() - t0,
                                       "parallel": res.info})
    return outcome
