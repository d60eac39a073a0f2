"""What a command needs before it starts: the firmware's programs (found by hil.io.paths) and
the optional parts of the package (extras).  Checked after the parse and before anything flies,
so that a missing sid_replay is one line at the start, not a failure after the flight."""
from __future__ import annotations

import argparse
import importlib.util
import os
import sys

from hil.bus import dbc
from hil.bus.dbcfile import DbcError
from hil.cli.usage import UsageError
from hil.apps.registry import application
from hil.io import paths
from hil.rig.simbus import LIBRARY
from hil.targets.registry import target

#: the commands that start a rig (a recorder and a device under test)
FLYING = ("run", "campaign", "sweep", "demo", "verify", "replay")
#: extra -> the modules it brings (hil/pyproject.toml [project.optional-dependencies])
EXTRAS = {"parallel": ("dask", "distributed"), "live": ("rich",)}


def apply(args: argparse.Namespace) -> None:
    """The parsed command's paths in force (--build-dir, --dbc, --fcc) and each checked, then
    what it needs (check): UsageError, one line, for the first that fails."""
    build_dir = getattr(args, "build_dir", None)
    if build_dir is not None:
        if not build_dir.is_dir():
            raise UsageError(f"--build-dir {build_dir}: no such directory")
        os.environ[paths.BUILD_ENV] = str(build_dir.resolve())  # the run's workers look there too
    dbc_path = getattr(args, "dbc", None)
    if dbc_path is not None or os.environ.get(dbc.DBC_ENV):
        try:  # a DBC hil cannot use is one line now, before anything starts
            dbc.check_contract(dbc.load(dbc_path))  # None: $FCC_HIL_DBC's
        except DbcError as e:
            raise UsageError(f"{'--dbc' if dbc_path is not None else '$' + dbc.DBC_ENV}: {e}") from None
        if dbc_path is not None:
            dbc.set_default(dbc_path)
    fcc_path = getattr(args, "fcc", None)
    paths.set_fcc(fcc_path)  # also when None: no earlier main() call's --fcc stays in force
    if fcc_path is not None:
        try:
            paths.fcc_binary()  # a bad path is a usage error now, not a failed run later
        except paths.ToolNotFound as e:
            paths.set_fcc(None)
            raise UsageError(str(e)) from None
    check(args)


def programs(args: argparse.Namespace) -> list[str]:
    """The firmware programs the parsed command runs, in the order it runs them."""
    cmd = args.command
    if cmd == "verify" and (args.list or args.fields):
        return []
    names: list[str] = []
    if cmd in FLYING:
        tgt = target(getattr(args, "target", "host"))
        if tgt.program is not None and tgt.needs_program(args.fcc, paths.source_tree()):
            names.append(tgt.program)  # (the M4F image: in a clone hil.targets cross-builds it)
        if getattr(args, "interface", "socketcan") == "socketcan" and \
                getattr(args, "recorder", "canrec") == "canrec":
            names.append("canrec")
    aircraft = getattr(args, "aircraft", None)
    study = getattr(args, "study", None)
    if cmd in ("run", "campaign") and aircraft is not None:
        names += application(aircraft).programs   # what its evaluation runs (hil.apps)
    if cmd in ("demo", "verify") or study == "cdrw":
        names.append("sid_replay")
    if cmd == "demo" or study == "missile-rms":
        names.append("lqg_design")
    if study == "bus":   # it flies: fcc, its recorder, the bus model
        names += ["fcc", "canrec", LIBRARY]
    elif getattr(args, "bus", "ideal") == "wire" and getattr(args, "mode", "") == "lockstep":
        names.append(LIBRARY)
    return names


def extras(args: argparse.Namespace) -> list[str]:
    """The extras the parsed command imports."""
    wanted = []
    if getattr(args, "workers", None) or getattr(args, "scheduler", None):
        wanted.append("parallel")
    if args.command == "live" and (args.rich or sys.stdout.isatty()):
        wanted.append("live")
    return wanted


def check(args: argparse.Namespace) -> None:
    """UsageError (exit 2, one line) naming the first thing missing and how to provide it."""
    for extra in extras(args):
        missing = [m for m in EXTRAS[extra] if importlib.util.find_spec(m) is None]
        if missing:
            raise UsageError(f"{' and '.join(missing)} not installed: `pip install 'hil[{extra}]'` "
                             f"(needed by {_what(extra)})")
    try:
        paths.require(programs(args))
    except paths.ToolNotFound as e:
        raise UsageError(str(e)) from None


def _what(extra: str) -> str:
    return {"parallel": "--workers and --scheduler", "live": "hil live's dashboard"}[extra]
