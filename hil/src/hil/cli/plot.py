"""`hil plot`: a run directory's figures redrawn from its CSV files and summary.json (all of
them, or the families --figures names), into the run directory or a new --out directory.

Also what `hil report` and `hil compare` share with it: a run directory read (one line and
exit 2 when it is not one) and its figures redrawn in place, its user's files kept.
"""
from __future__ import annotations

import argparse
import logging
import re
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from hil.cli.usage import UsageError
from hil.io.output import read_json
from hil.io.rundir import note_written, staged_run, users_files
from hil.plots import FAMILIES, plot_run_dir


#: the names of the figures hil draws (hil.plots)
_FIGURE = re.compile(r"(fig\d.*|campaign_errors|realtime_timing|missile_.*|table[45]_bars)\.png")
_log = logging.getLogger(__name__)


def not_a_summary(path: Path, e: Exception) -> UsageError:
    if isinstance(e, KeyError):
        return UsageError(f"{path}: not a hil summary: missing key {e.args[0]!r}")
    return UsageError(f"{path}: not a hil summary: {str(e).splitlines()[0] if str(e) else type(e).__name__}")


def read_run_dir(run_dir: Path) -> dict[str, Any]:
    """The summary.json of a run directory; a usage error when there is none to read."""
    if not run_dir.exists():
        raise UsageError(f"{run_dir}: no such run directory")
    path = run_dir / "summary.json"
    if not path.is_file():
        raise UsageError(f"{run_dir}: no summary.json (not a run directory)")
    try:
        summary = read_json(path)
    except ValueError as e:
        raise UsageError(str(e)) from None
    if not isinstance(summary, dict):
        raise UsageError(f"{path}: not a hil summary: expected a JSON object, got "
                         f"{type(summary).__name__ if summary is not None else 'null'}")
    return summary


def families(names: Iterable[str] | None) -> list[str] | None:
    """--figures checked against hil.plots.FAMILIES."""
    if names is None:
        return None
    unknown = [n for n in names if n not in FAMILIES]
    if unknown:
        raise UsageError(f"--figures {unknown[0]}: no such figures (choose from {', '.join(FAMILIES)})")
    return list(names)


def draw(run_dir: Path, out: Path | None = None, only: Iterable[str] | None = None) -> list[Path]:
    """The figures drawn from run_dir into out; in place (out None) the files that are not
    hil's (not in the run's manifest) are kept, not redrawn, and said so."""
    theirs = users_files(run_dir) if out is None else []
    try:
        written = plot_run_dir(run_dir, theirs, out, only)
    except (KeyError, TypeError, AttributeError, IndexError, ValueError) as e:
        raise not_a_summary(run_dir / "summary.json", e) from None
    if out is None:
        note_written(run_dir, written)
        drawn = {p.name for p in written}
        for p in theirs:
            if p.name not in drawn and _FIGURE.fullmatch(p.name):
                _log.warning("%s is not hil's (not in the run's manifest): kept, not redrawn", p.name)
    return written


def run(args: argparse.Namespace) -> int:
    read_run_dir(args.dir)
    only = families(args.figures)
    if args.out is None or args.out.resolve() == args.dir.resolve():
        written = _some(draw(args.dir, None, only), args.dir, only)
        where = args.dir
    else:
        with staged_run(args.out, "plot", force=args.force) as stage:
            written = _some(draw(args.dir, stage, only), args.dir, only)
        where = args.out
    print(f"plots: {', '.join(p.name for p in written)}")
    print(f"figures in {where}/")
    return 0


def _some(written: list[Path], run_dir: Path, only: list[str] | None) -> list[Path]:
    if not written:
        raise UsageError(f"{run_dir}: no figures to draw" + (f" of {', '.join(only)}" if only else ""))
    return written
