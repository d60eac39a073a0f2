"""`hil sweep`: Fig. 3's flights, the missile at every (T, N), one fcc redesigning on
SIM_CONTROL between flights, plus the open loop at every T.
"""
from __future__ import annotations

import math
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from hil.io.output import write_json
from hil.results.flight import MissileResult, missile_open_loop, missile_result
from hil.results.report import firmware_summary
from hil.rig.config import RigConfig
from hil.apps.missile import check_missile
from hil.rig.flight import fly, on_target, open_session, run_info
from hil.runs.budget import check_memory
from hil.runs.outcome import Outcome, finish, step_periods, write_fault_log, write_missile
from hil.scenario.file import Scenario
from hil.scenario.plant_options import LqgOptions
from hil.scenario.schema import ScenarioError
from hil.scenario.vary import grid
from hil.sim.drivers import MissileDriver
from hil.util.progress import bar as progress_bar


def sweep_points(scenario: Scenario, periods: Sequence[float], bits: Sequence[int]) -> list[Scenario]:
    """The closed-loop flights of a sweep, in order: every (T, N), T outer."""
    if scenario.aircraft != "missile":
        raise ScenarioError(f"{scenario.source}: a sweep flies the missile (aircraft = \"missile\")")
    if not periods or not bits:
        raise ValueError("a sweep needs at least one period and one word length")
    points = []
    for point in grid([("period", periods), ("bits", bits)]):   # (as a campaign's --vary)
        sc = scenario.replace(lqg=LqgOptions(period=float(point["period"]), bits=int(point["bits"]),
                                             closed_loop=True))
        check_missile(sc)
        if sc.lqg.period > sc.duration:  # type: ignore[union-attr]
            raise ScenarioError(f"{scenario.source}: period {point['period']} s is longer than the flight")
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
        write_missile(out, res)
        runs_out.append(res.run_entry())
        fault_log.append((f"{res.tag:12s}", res.events))
    write_fault_log(out, fault_log)
    for T in periods:
        sc = scenario.replace(lqg=LqgOptions(period=float(T), bits=base_lqg.bits, closed_loop=False))
        ol = missile_open_loop(sc)
        write_missile(out, ol)
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
                d = MissileDriver(on_target(sc, cfg), rig.codec, cfg.mode == "realtime")
                runner = fly(rig, [d], cfg, bar, runner, sc.lqg.period, sc.lqg.bits)
                mdrivers.append(d)
        rig.shutdown()
    results = [missile_result(d, reference=cfg.mode == "lockstep") for d in mdrivers]
    summary = write_sweep(out, scenario, periods, results,
                          firmware_summary(rig.status, rig.security.counters()), cfg.mode)
    write_json(out / "run_info.json", run_info(rig, cfg, runner, time.perf_counter() - t0))
    return finish(cfg, out, summary, step_periods([first]))
