"""`hil run`: one flight of one aircraft."""
from __future__ import annotations

import argparse
from pathlib import Path

from hil.cli.common import refuse_wire_faults, scenario, staged, sync_status
from hil.runs.run import run_flight


def run(args: argparse.Namespace) -> int:
    sc = scenario(args.aircraft, args.scenario, args.fault, args.seed)
    refuse_wire_faults([sc], args)
    out = Path(str(args.out).replace("<aircraft>", args.aircraft))
    return sync_status(staged(args, out, lambda cfg: [run_flight([sc], cfg)]))
