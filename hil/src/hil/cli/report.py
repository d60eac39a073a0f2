"""`hil report`: a run directory's tables again, its plots redrawn, its bus log analysed."""
from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

from hil.bus import load
from hil.bus.diag import analyse, render
from hil.bus.logio import read_frames, run_log
from hil.cli.usage import UsageError
from hil.io.output import read_json
from hil.io.rundir import note_written, users_files
from hil.plots import plot_run_dir
from hil.results.report import summary_tables
from hil.results.verdict import lines as verdict_lines


#: the names of the figures hil draws (hil.plots)
_FIGURE = re.compile(r"(fig\d.*|campaign_errors|realtime_timing)\.png")


def not_a_summary(path: Path, e: Exception) -> UsageError:
    if isinstance(e, KeyError):
        return UsageError(f"{path}: not a hil summary: missing key {e.args[0]!r}")
    return UsageError(f"{path}: not a hil summary: {str(e).splitlines()[0] if str(e) else type(e).__name__}")


def run(args: argparse.Namespace) -> int:
    summary_path = args.dir / "summary.json"
    if not summary_path.is_file():
        raise UsageError(f"{args.dir}: no summary.json (not a run directory)")
    try:
        summary = read_json(summary_path)
    except ValueError as e:
        raise UsageError(str(e)) from None
    if args.plots_only and args.no_plots:
        raise UsageError("--plots-only and --no-plots exclude each other")
    if not isinstance(summary, dict):
        raise UsageError(f"{summary_path}: not a hil summary: expected a JSON object, got "
                         f"{type(summary).__name__ if summary is not None else 'null'}")
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
        print(render(analyse(read_frames(log), load())))
    if not args.no_plots:
        try:
            theirs = users_files(args.dir)
            written = plot_run_dir(args.dir, theirs)
        except (KeyError, TypeError, AttributeError, IndexError) as e:
            raise not_a_summary(summary_path, e) from None
        note_written(args.dir, written)
        for p in theirs:
            if _FIGURE.fullmatch(p.name):
                print(f"hil report: {p.name} is not hil's (not in the run's manifest): kept, "
                      f"not redrawn", file=sys.stderr)
        names = [p.name for p in written]
        if names:
            print(f"plots: {', '.join(names)}")
    return 0
