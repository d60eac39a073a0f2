"""`hil compare`: runs overlaid -- their time series on shared axes, their headline numbers
side by side with the differences from the first run -- as PNG files and one self-contained
page (compare.html), in a new --out directory (published as a run's: hil.io.rundir)."""
from __future__ import annotations

import argparse
import shlex
from pathlib import Path
from typing import Any

from hil.cli.plot import not_a_summary, read_run_dir
from hil.cli.usage import PROG, UsageError
from hil.io.rundir import staged_run
from hil.plots.compare import compare_figures, label_runs
from hil.plots.compare_page import write_page
from hil.results.verdict import headline_metrics
from hil.results.verdict import lines as verdict_lines

#: what a summary that is not hil's raises when read (a usage error: one line, exit 2)
_NOT_HILS = (KeyError, TypeError, AttributeError, IndexError, ValueError)


def _checked(run_dir: Path) -> dict[str, Any]:
    summary = read_run_dir(run_dir)
    try:
        headline_metrics(summary)
        verdict_lines(summary)
    except _NOT_HILS as e:
        raise not_a_summary(run_dir / "summary.json", e) from None
    return summary


def run(args: argparse.Namespace) -> int:
    if len(args.dirs) < 2:
        raise UsageError("compare: give two run directories or more")
    runs = label_runs(args.dirs, [_checked(d) for d in args.dirs])
    out = args.out.resolve()
    for d in args.dirs:
        if out == d.resolve() or out in d.resolve().parents:
            raise UsageError(f"--out {args.out}: holds the compared run {d}; the comparison goes elsewhere")
    command = shlex.join([PROG, "compare", *map(str, args.dirs), "--out", str(args.out)])
    with staged_run(args.out, "compare", force=args.force) as stage:
        try:
            pngs = compare_figures(runs, stage)
        except _NOT_HILS as e:
            raise UsageError(f"compare: a run's time series cannot be read: {e}") from None
        page = write_page(runs, pngs, stage, command)
    print(f"compare: {', '.join(p.name for p in pngs)}, {page.name}")
    print(f"comparison in {args.out}/")
    return 0
