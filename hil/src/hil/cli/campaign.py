"""`hil campaign`: Table 5, the flight many times, faults at random times."""
from __future__ import annotations

import argparse

from hil.cli.common import scenario
from hil.cli.many import run_many
from hil.cli.usage import UsageError
from hil.runs.campaign import run_campaign


def run(args: argparse.Namespace) -> int:
    if args.runs < 1:
        raise UsageError(f"--runs must be at least 1, got {args.runs}")
    sc = scenario("cdrw", args.scenario, args.fault, None)
    return run_many(args, run_campaign, "run_campaign_parallel", sc, args.runs, args.seed)
