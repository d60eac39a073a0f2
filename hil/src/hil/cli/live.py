"""`hil live`: a dashboard of the bus while a run flies."""
from __future__ import annotations

import argparse
import logging

from hil.bus import load
from hil.bus.canif import check_up, open_error
from hil.rig import live


def run(args: argparse.Namespace) -> int:
    logging.getLogger("can").addHandler(logging.NullHandler())  # its errors: our one line below
    try:
        check_up(args.iface)
        live.run(args.iface, args.seconds, load(), force_rich=args.rich)
    except OSError as e:
        raise RuntimeError(open_error(args.iface, e)) from None
    return 0
