"""`hil study missile-rms`: Fig. 3 by covariance analysis (and a real quantiser's Monte
Carlo); `hil study cdrw`: seed 1's Table 5 with its controls (both offline, no bus)."""
from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable

from hil.cli.usage import UsageError
from hil.io.paths import tool
from hil.reference.cdrw_controls import cases, cdrw_study, format_cdrw_study
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


#: each study by its name: (what it runs, the options that made it, for its figure)
STUDIES: dict[str, tuple[Callable[[argparse.Namespace], int], Callable[[argparse.Namespace], str]]] = {
    "cdrw": (_cdrw, _cdrw_options), "missile-rms": (_missile, _missile_options)}


def run(args: argparse.Namespace) -> int:
    return STUDIES[args.study][0](args)
