"""`hil demo`: both aircraft, then seed 2's Figs. 4-6 and Fig. 3."""
from __future__ import annotations

import argparse

from hil.cli.common import staged
from hil.runs.demo import run_demo


def run(args: argparse.Namespace) -> int:
    staged(args, args.out, run_demo)
    return 0
