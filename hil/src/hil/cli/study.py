"""`hil study missile-rms`: Fig. 3 by covariance analysis (and a real quantiser's Monte
Carlo); `hil study cdrw`: seed 1's Table 5 with its controls (both offline, no bus); `hil study
bus`: the missile's RMS q over bit rate and background load on the wire-time bus in lockstep,
and Table 4 there (hil.runs.bus_study, on vcan0)."""
from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable

import tempfile
from pathlib import Path

from hil.cli.usage import UsageError
from hil.io.paths import tool
from hil.reference.cdrw_controls import cases, cdrw_study, format_cdrw_study
from hil.results.bus_study import format_grid, format_table4
from hil.results.fig3_grid import FIG3_PERIODS
from hil.runs import bus_study
from hil.sim.missile_cov import format_study, missile_rms_study
from hil.sim.missile_quant import format_quantiser, quantiser_study


def _cdrw_options(args: argparse.Namespace) -> str:
    return f"--runs {args.runs} --noise-seeds {args.noise_seeds}" + \
        (f" --cases {','.join(args.cases)}" if args.cases else "")


def _missile_options(args: argparse.Namespace) -> str:
    fmt = lambda v: ",".join(f"{x:g}" for x in v)  # noqa: E731
    return (f"--periods {fmt(args.periods)} --bits {fmt(args.bits)} --gyro-var "
            f"{args.gyro_var:g} --accel-var {args.accel_var:g}" +
            (f" --mc-loops {args.mc_loops} --mc-seconds {args.mc_seconds:g}" if args.mc_loops else ""))


def _made_by(args: argparse.Namespace) -> str:
    """The command that made the figure, from the options it used."""
    return f"hil study {args.study} {STUDIES[args.study][1](args)} --figure {args.figure}"


def _missile(args: argparse.Namespace) -> int:
    for n in args.bits:
        if not 2 <= n <= 16:
            raise UsageError(f"--bits: D/A word length must be 2 to 16, got {n}")
    for T in args.periods:
        if not 0.001 <= T <= 1.0:
            raise UsageError(f"--periods: lqg_design accepts 0.001 to 1 s, got {T:g}")
    if args.mc_loops < 0:
        raise UsageError(f"--mc-loops: expected 0 or more, got {args.mc_loops}")
    study = missile_rms_study(args.periods, args.bits, args.gyro_var, args.accel_var, tool("lqg_design"))
    if args.mc_loops:
        study["monte_carlo"] = quantiser_study(args.periods, args.bits, args.gyro_var,
                                               args.accel_var, args.mc_loops, args.mc_seconds)
    if args.figure:
        from hil.plots.missile import fig3_covariance
        args.figure.parent.mkdir(parents=True, exist_ok=True)
        fig3_covariance({"studies": [study]}, args.figure.parent, args.figure.name, _made_by(args))
    if args.json:
        print(json.dumps(study, allow_nan=False))
    else:
        print(format_study(study))
        if "monte_carlo" in study:
            print(format_quantiser(study["monte_carlo"]))
    return 0


def _cdrw(args: argparse.Namespace) -> int:
    if args.runs < 2 or args.noise_seeds < 2:
        raise UsageError("--runs and --noise-seeds: at least 2 (an interval needs two flights)")
    names = {c.name for c in cases()}
    bad = [c for c in (args.cases or []) if c not in names]
    if bad:
        raise UsageError(f"--cases: unknown {', '.join(bad)} (known: {', '.join(sorted(names))})")
    study = cdrw_study(tool("sid_replay"), args.runs, args.noise_seeds, args.cases,
                       progress=lambda n: print(f"study cdrw: {n}", file=sys.stderr, flush=True))
    if args.figure:
        from hil.plots.cdrw import controls_figure
        args.figure.parent.mkdir(parents=True, exist_ok=True)
        controls_figure(study, args.figure, _made_by(args))
    print(json.dumps(study, allow_nan=False) if args.json else format_cdrw_study(study))
    return 0


def _bus_options(args: argparse.Namespace) -> str:
    rate = lambda r: f"{r // 1_000_000}M" if r % 1_000_000 == 0 else f"{r // 1000}k"  # noqa: E731
    return (f"--periods {','.join(f'{t:g}' for t in args.periods)} --bitrates "
            f"{','.join(rate(r) for r in args.bitrates)} --loads {','.join(f'{u:g}' for u in args.loads)} "
            f"--load-ids {args.load_ids[0]:#05x}-{args.load_ids[1]:#05x} --duration {args.duration:g} "
            f"--seed {args.seed}" + (" --no-table4" if args.no_table4 else
                                     f" --table4 {rate(args.table4[0])},{args.table4[1]:g}"))


def _bus(args: argparse.Namespace) -> int:
    args.bitrates = args.bitrates or list(bus_study.BITRATES)
    args.loads = args.loads if args.loads is not None else list(bus_study.LOADS)
    args.load_ids = args.load_ids or bus_study.LOAD_IDS
    for t in args.periods:
        if not 0.005 <= t <= 1.0:
            raise UsageError(f"--periods: a missile scenario's period is 0.005 to 1 s, got {t:g}")
    say = lambda line: print(f"study bus: {line}", file=sys.stderr, flush=True)  # noqa: E731
    with tempfile.TemporaryDirectory(prefix="hil-study-bus-") as tmp:
        study: dict = {"seed": args.seed, "duration": args.duration, "load_ids": list(args.load_ids),
                       "points": bus_study.missile_grid(Path(tmp), args.bitrates, args.loads, args.periods,
                                                        args.seed, args.duration, args.load_ids, say)}
        if not args.no_table4:
            study["table4"] = bus_study.table4(Path(tmp), args.table4[0], args.table4[1], args.seed, args.load_ids)
    if args.figure:
        from hil.plots.bus_study import bus_study_figure
        args.figure.parent.mkdir(parents=True, exist_ok=True)
        bus_study_figure(study, args.figure, _made_by(args))
    if args.json:
        print(json.dumps(study, allow_nan=False))
    else:
        print(format_grid(study))
        if "table4" in study:
            print()
            print(format_table4(study["table4"]))
    return 1 if any(p["failed"] for p in study["points"]) else 0


#: each study by its name: (what it runs, the options that made it, for its figure)
STUDIES: dict[str, tuple[Callable[[argparse.Namespace], int], Callable[[argparse.Namespace], str]]] = {
    "cdrw": (_cdrw, _cdrw_options), "missile-rms": (_missile, _missile_options), "bus": (_bus, _bus_options)}


def run(args: argparse.Namespace) -> int:
    if args.periods is None:
        args.periods = list(bus_study.PERIODS if args.study == "bus" else FIG3_PERIODS)
    return STUDIES[args.study][0](args)
