"""`hil campaign`: Table 5, the flight many times, faults at random times; or a campaign over
any scenario field (--vary, --draw, --keep-logs; hil.runs.field_campaign), either aircraft."""
from __future__ import annotations

import argparse

from hil.cli.common import refuse_wire_faults, scenario
from hil.cli.many import parallel_options, run_many
from hil.cli.usage import UsageError
from hil.runs.campaign import run_campaign
from hil.runs.field_campaign import flights_of, run_field_campaign
from hil.scenario.vary import parse_draw, parse_vary


def run(args: argparse.Namespace) -> int:
    if args.runs < 1:
        raise UsageError(f"--runs must be at least 1, got {args.runs}")
    sc = scenario(args.aircraft, args.scenario, args.fault, None)
    refuse_wire_faults([sc], args)
    if args.aircraft == "cdrw" and not (args.vary or args.draw or args.keep_logs):
        return run_many(args, run_campaign, "run_campaign_parallel", sc, args.runs, args.seed)
    varies = [parse_vary(v) for v in args.vary]
    draws = [parse_draw(d) for d in args.draw]
    if args.keep_logs and parallel_options(args) is not None:
        raise UsageError("--keep-logs: the rigs of --workers/--scheduler keep no bus log (each is read and "
                         "removed there); fly the campaign in this rig for the logs")
    flights_of(sc, args.runs, args.seed, varies, draws)   # every key and value checked first
    return run_many(args, run_field_campaign, "run_field_campaign_parallel", sc, args.runs, args.seed,
                    varies, draws, args.keep_logs)
