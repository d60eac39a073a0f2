"""`hil campaign` and `hil sweep`: in this process's rig, or on many rigs with
--workers/--scheduler (hil.parallel.runs).
"""
from __future__ import annotations

import argparse
import os
import sys

from hil.cli.common import staged, sync_status
from hil.cli.usage import PROG, UsageError
from hil.io.paths import vcan_launcher
from hil.parallel import runs
from hil.targets.registry import target

#: more rigs than this is a typo (each is a UML guest with an fcc)
MAX_WORKERS = 64


def parallel_options(args: argparse.Namespace) -> dict[str, object] | None:
    """--workers/--scheduler as keyword arguments of the parallel runners (None: sequential)."""
    if args.workers is None and args.scheduler is None:
        return None
    if args.workers is not None and not 1 <= args.workers <= MAX_WORKERS:
        raise UsageError(f"--workers must be 1..{MAX_WORKERS}, got {args.workers}")
    if args.mode != "lockstep":
        raise UsageError("--workers/--scheduler fly lockstep flights only (realtime needs the machine to itself)")
    if not target(args.target).parallel or args.interface != "socketcan":
        raise UsageError("--workers/--scheduler fly the host fcc on rigs of their own (vcan), "
                         "not --target/--interface")
    if args.log_format != "log":
        raise UsageError(f"--log-format {args.log_format}: --workers/--scheduler keep no bus log (each "
                         "rig session's is read and removed); fly the sequential form for one: "
                         f"{vcan_launcher()} hil campaign|sweep ... --log-format {args.log_format}")
    if os.environ.get("WITH_VCAN_UML"):   # set by the vcan launcher inside its guest
        raise UsageError("--workers/--scheduler start each rig's own guest from the host shell and "
                         f"cannot inside {vcan_launcher()}'s guest: run the command without "
                         f"{vcan_launcher()}")
    return {"workers": args.workers, "scheduler": args.scheduler}


def run_many(args: argparse.Namespace, sequential, parallel: str, *inputs: object) -> int:
    """A campaign or sweep: sequential(*inputs, cfg) in this process's rig, or with
    --workers/--scheduler hil.parallel.runs.<parallel> on many rigs; flights that failed twice
    there are one line and exit 1 (the others' results are written); a flight's time
    synchronisation or fcc's outputs not trusted: cli.common.sync_status's exit status."""
    par = parallel_options(args)
    if par is None:
        return sync_status(staged(args, args.out, lambda cfg: [sequential(*inputs, cfg)]))
    (outcome,) = staged(args, args.out, lambda cfg: [getattr(runs, parallel)(*inputs, cfg, **par)])
    failed = outcome.summary.get("failed_runs") or []
    if not failed:
        return sync_status([outcome])
    print(f"{PROG}: {len(failed)} flight(s) failed twice and are left out of the results "
          f"(summary.json failed_runs); first: flight {failed[0]['run']}: {failed[0]['error']}",
          file=sys.stderr)
    return 1
