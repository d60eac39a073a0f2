"""`hil run`: one flight of one aircraft."""
from __future__ import annotations

import argparse
from pathlib import Path

from hil.cli.common import scenario, staged
from hil.runs.run import run_flight


def run(args: argparse.Namespace) -> int:
    sc = scenario(args.aircraft, args.scenario, args.fault, args.seed)
    out = Path(str(args.out).replace("<aircraft>", args.aircraft))
    staged(args, out, lambda cfg: [run_flight([sc], cfg)])
    return 0
