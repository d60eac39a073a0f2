"""`hil live`: a dashboard of the bus while a run flies."""
from __future__ import annotations

import argparse

from hil.bus import load
from hil.rig import live


def run(args: argparse.Namespace) -> int:
    try:
        live.run(args.iface, args.seconds, load(), force_rich=args.rich)
    except OSError as e:
        raise RuntimeError(f"cannot watch CAN interface {args.iface!r}: {e}") from None
    return 0
