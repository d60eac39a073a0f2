"""`hil replay`: a recorded lockstep run replayed into fcc, every firmware frame compared."""
from __future__ import annotations

import argparse
import shlex

from hil.cli.usage import UsageError
from hil.io.rundir import note_written
from hil.runs.replay import ReplayError, replay
from hil.targets.device import ArgsRefused
from hil.targets.registry import device_class


def run(args: argparse.Namespace) -> int:
    try:
        extra = shlex.split(args.fcc_args)
    except ValueError as e:
        raise UsageError(f"--fcc-args: {e}") from None
    try:  # as the flying commands do (hil.cli.common.rig_config): before anything starts
        device_class("host").check_args(args.fcc, extra, "lockstep")
    except ArgsRefused as e:
        raise UsageError(f"--fcc-args: {e}") from None
    if not args.dir.is_dir():
        raise UsageError(f"{args.dir}: not a run directory")
    out = args.out or args.dir / "replay"
    out.mkdir(parents=True, exist_ok=True)
    try:
        steps, diff = replay(args.dir, out, extra, args.iface, args.timeout)
    except ReplayError as e:
        raise UsageError(str(e)) from None
    finally:
        if out.resolve().is_relative_to(args.dir.resolve()):  # the run stays hil's own: a new
            note_written(args.dir, [f for f in out.rglob("*") if f.is_file()])
    if diff is not None:
        print(f"replay of {args.dir}: DIFFERENT after {steps} identical steps; {diff}")
        return 1
    print(f"replay of {args.dir}: identical ({steps} steps, every firmware frame)")
    return 0
