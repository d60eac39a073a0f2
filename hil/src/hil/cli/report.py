"""`hil report`: a run directory's tables again, its plots redrawn, its bus log analysed."""
from __future__ import annotations

import argparse

from hil.bus import load
from hil.bus.diag import analyse, render
from hil.bus.logio import read_frames, run_log
from hil.cli.usage import UsageError
from hil.cli.plot import draw, not_a_summary, read_run_dir
from hil.results.report import summary_tables
from hil.results.verdict import lines as verdict_lines


def run(args: argparse.Namespace) -> int:
    summary_path = args.dir / "summary.json"
    summary = read_run_dir(args.dir)
    if args.plots_only and args.no_plots:
        raise UsageError("--plots-only and --no-plots exclude each other")
    try:
        tables = [] if args.plots_only else [*verdict_lines(summary), *summary_tables(summary)]
    except (KeyError, TypeError, AttributeError, ValueError, IndexError) as e:
        raise not_a_summary(summary_path, e) from None
    for t in tables:
        print(t)
        print()
    if args.bus:
        log = run_log(args.dir)
        if log is None:
            raise UsageError(f"{args.dir}: no bus log (bus.log, bus.asc or bus.blf)")
        try:
            print(render(analyse(read_frames(log), load())))
        except (ValueError, OSError) as e:  # a malformed log (a line not candump's, not a file)
            raise UsageError(f"{log}: not a bus log hil can read: {str(e).splitlines()[0]}") from None
    if not args.no_plots:
        names = [p.name for p in draw(args.dir)]
        if names:
            print(f"plots: {', '.join(names)}")
    return 0
