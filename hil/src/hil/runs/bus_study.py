"""`hil study bus`: what the bus does to the loops, flown in lockstep on the wire-time bus in
simulated time (hil.rig.lockstep_wire: deterministic, the real fcc on vcan0).

The missile (seed 2) at each sampling period T, bit rate and background load (a `bus_load`
fault over the whole flight: periodic frames of another node, by default at identifiers
0x004-0x00F, above every frame of the DBC but the time synchronisation's: the traffic the loop
must wait for), twice:
  * plain: fcc's LQG designed for no delay (`[lqg] delay = 0`), each command acting when it
    comes off the wire;
  * delay-aware: the LQG designed for the delay the plain flight measured at that point (its
    largest command delay, t_k to the command's end of frame, rounded up to DELAY_STEP_S), the
    actuator time-triggered at t_k + d (a command later than that acts when it comes).
Each point's RMS q, its commands' delays, and the run's bus check (a judged frame above its
bound fails the point, reported as such).  And Table 4 (the CDRW's identification) on the ideal
bus and on the wire at one bit rate and load.
"""
from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from hil.rig.config import RigConfig
from hil.runs.run import run_flight
from hil.scenario.faults import BusLoad
from hil.scenario.file import Scenario, load_default_scenario
from hil.util.errors import HilError

#: the delay-aware design's delay is the measured one rounded up to this (s)
DELAY_STEP_S = 1e-4
#: the default background node's identifiers: above the loop's frames, below time sync
LOAD_IDS = (0x004, 0x00F)
BITRATES = (125_000, 250_000, 500_000, 1_000_000)
LOADS = (0.0, 0.2, 0.4, 0.6, 0.8)
PERIODS = (0.05, 0.1)


def missile_scenario(period: float, delay: float, load: float, seed: int, duration: float,
                     ids: tuple[int, int] = LOAD_IDS) -> Scenario:
    sc = load_default_scenario("missile")
    assert sc.lqg is not None
    return sc.replace(seed=seed, duration=duration, faults=with_load(sc, load, ids).faults,
                      lqg=dataclasses.replace(sc.lqg, period=period, delay=delay))


def with_load(sc: Scenario, load: float, ids: tuple[int, int]) -> Scenario:
    """The scenario with a background node over the whole flight (its own faults kept)."""
    if not load:
        return sc
    return sc.replace(faults=(*sc.faults, BusLoad(start=0.0, duration=math.inf, utilisation=load,
                                                  id_lo=ids[0], id_hi=ids[1])))


def _fly(out: Path, sc: Scenario, bitrate: int | None) -> tuple[dict[str, Any], str]:
    """(summary.json, '' or why the run failed) of one flight; a failed run's summary is read
    from its directory when it got that far."""
    cfg = RigConfig(out_dir=out, progress=False, plots=False, bus="wire" if bitrate else "ideal",
                    bitrate=bitrate)
    try:
        return run_flight([sc], cfg).summary, ""
    except HilError as e:
        path = out / "summary.json"
        return (json.loads(path.read_text()) if path.exists() else {}), str(e)


def design_delay(measured_s: float, period: float) -> float:
    """The delay-aware design's d: the measured delay rounded up to DELAY_STEP_S, below T."""
    d = math.ceil(measured_s / DELAY_STEP_S - 1e-9) * DELAY_STEP_S
    return round(min(d, period - DELAY_STEP_S), 9)


def _point(summary: dict[str, Any], failed: str) -> dict[str, Any]:
    run = (summary.get("missile") or {"runs": [{}]})["runs"][0]
    bus = summary.get("bus") or {}
    delays = run.get("command_delay_s") or {}
    return {"rms_q": run.get("rms_q"), "delay_s": run.get("delay"),
            "cmd_delay_p50_s": delays.get("p50"), "cmd_delay_max_s": delays.get("max"),
            "commands_late": run.get("commands_late"), "commands_missing": run.get("commands_missing"),
            "bus_load": bus.get("load"), "late_queued": bus.get("late_queued"), "failed": failed}


def missile_grid(root: Path, bitrates: Sequence[int], loads: Sequence[float], periods: Sequence[float],
                 seed: int, duration: float, ids: tuple[int, int] = LOAD_IDS,
                 progress: Callable[[str], None] | None = None) -> list[dict[str, Any]]:
    """Every point of the grid, plain then delay-aware (see the module docstring)."""
    points = []
    for period in periods:
        for bitrate in bitrates:
            for load in loads:
                tag = f"T{period:g}-{bitrate // 1000}k-U{load:g}"
                plain = _point(*_fly(root / f"{tag}-plain", missile_scenario(period, 0.0, load, seed, duration, ids),
                                     bitrate))
                measured = plain["cmd_delay_max_s"]
                if measured is None:   # no command came: nothing to design for
                    aware = {**plain, "rms_q": None, "failed": "no command came off the wire in the plain flight"}
                else:
                    d = design_delay(measured, period)
                    aware = _point(*_fly(root / f"{tag}-aware",
                                         missile_scenario(period, d, load, seed, duration, ids), bitrate))
                for design, p in (("plain", plain), ("delay-aware", aware)):
                    points.append({"period": period, "bitrate": bitrate, "load": load, "design": design, **p})
                if progress is not None:
                    progress(f"{tag}: RMS q plain {plain['rms_q']}, delay-aware {aware['rms_q']}")
    return points


def table4(root: Path, bitrate: int, load: float, seed: int, ids: tuple[int, int] = LOAD_IDS
           ) -> dict[str, Any]:
    """The CDRW's Table 4 (each filter's alpha and q error) on the ideal bus and on the wire at
    bitrate with load, and the wire run's bus check."""
    base = load_default_scenario("cdrw").replace(seed=seed)
    loaded = with_load(base, load, ids)
    out: dict[str, Any] = {"bitrate": bitrate, "load": load}
    for name, sc, rate in (("ideal", base, None), ("wire", loaded, bitrate)):
        summary, failed = _fly(root / f"cdrw-{name}", sc, rate)
        out[name] = {"table4": (summary.get("cdrw") or {}).get("table4"), "failed": failed}
        if rate:
            frames = (summary.get("bus") or {}).get("frames") or {}
            out[name]["bus_load"] = (summary.get("bus") or {}).get("load")
            out[name]["verdicts"] = {v: sum(1 for f in frames.values() if f["verdict"] == v)
                                     for v in sorted({f["verdict"] for f in frames.values()})}
            out[name]["ack_max_s"] = (frames.get("FCC_ACK") or {}).get("max_s")
    return out
