"""`hil sweep`: Fig. 3, the missile at several periods and D/A word lengths."""
from __future__ import annotations

import argparse

from hil.cli.common import scenario
from hil.cli.many import run_many
from hil.runs.sweep import run_sweep


def run(args: argparse.Namespace) -> int:
    sc = scenario("missile", args.scenario, args.fault, args.seed)
    return run_many(args, run_sweep, "run_sweep_parallel", sc, args.periods, args.bits)
