"""`hil faults`: every fault kind, its fields, units, defaults, an example."""
from __future__ import annotations

import argparse

from hil.cli.usage import UsageError
from hil.scenario.catalog import catalog
from hil.scenario.faults import KINDS


def run(args: argparse.Namespace) -> int:
    unknown = [k for k in args.kinds if k not in KINDS]
    if unknown:
        raise UsageError(f"no fault kind {unknown[0]!r} (kinds: {', '.join(KINDS)})")
    print(catalog(args.kinds or None))
    return 0
