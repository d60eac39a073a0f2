"""What the commands that fly share: the scenario from the command line, the run's
configuration from the options, the staged run directory and the tables printed after it.
"""
from __future__ import annotations

import argparse
import logging
import shlex
import sys
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path

from hil.bus import load
from hil.bus.secoc import KeyFileError, read_key_file
from hil.cli.usage import EXIT_SYNC, PROG, UsageError
from hil.io.rundir import staged_run
from hil.rig.config import RigConfig
from hil.rig.wirefaults import canbus_faults, refusal
from hil.scenario.file import find_scenario, load_default_scenario, load_scenario, with_extra_faults
from hil.targets.device import ArgsRefused
from hil.targets.registry import device_class, target

_log = logging.getLogger(__name__)


@contextmanager
def reading(what: object) -> Iterator[None]:
    """A user's file too large or nested too deeply for its parser (the TOML and JSON parsers
    recurse per level of nesting: `x = [[[...]]]`): one line, a usage error (exit 2)."""
    try:
        yield
    except (RecursionError, MemoryError) as e:
        raise UsageError(f"{what}: too large or nested too deeply to read ({type(e).__name__})") from None


def scenario(aircraft: str, name_or_path: str | None, faults: Sequence[str], seed: int | None):
    """The scenario a command flies: a file, a shipped one by name, or the aircraft's default;
    with the command line's faults and seed."""
    frames = {m.name for m in load().messages}
    with reading(name_or_path or "the default scenario"):
        sc = (load_default_scenario(aircraft, frames) if name_or_path is None
              else load_scenario(find_scenario(name_or_path), frames))
    _log.info("scenario: %s (%s)", sc.name or aircraft, sc.source)
    if sc.aircraft != aircraft:
        raise UsageError(f"{sc.source}: a scenario for aircraft {sc.aircraft!r}, not {aircraft!r}")
    if faults:
        sc = with_extra_faults(sc, faults, frames)
        for f in sc.faults:
            if f.start >= sc.duration:
                raise UsageError(f"command line: fault {f.describe()!r}: field 'start': {f.start:g} s "
                                 f"is not before the end of the run ({sc.duration:g} s)")
    if seed is not None:
        sc = sc.replace(seed=seed)
    return sc


def bus_model(args: argparse.Namespace) -> str:
    """--bus (ideal where the command has none); wire: over SocketCAN.  Realtime: the rig makes
    the nodes' vxcan ends and canbus for the host fcc and the M4F image (behind slcan), and
    judges the real bus of an external device (hil.targets.registry: Target.wire); lockstep:
    the bus model runs in simulated time beside the host fcc (hil.rig.simbus)."""
    bus: str = getattr(args, "bus", "ideal")
    if bus != "wire":
        return bus
    if args.interface != "socketcan":
        raise UsageError("--bus wire: SocketCAN only (--interface socketcan)")
    if args.mode != "realtime" and args.target != "host":
        raise UsageError("--bus wire in lockstep: fcc on the host only (--target host), "
                         "or --mode realtime for the other targets")
    return bus


def refuse_wire_faults(scenarios: Sequence, args: argparse.Namespace) -> None:
    """A wire-level fault (canbus's) on another bus, or a bus model's fault on a real bus: one
    line, exit 2."""
    why = refusal(canbus_faults(scenarios), bus_model(args), target(args.target).wire == "real")
    if why:
        raise UsageError(why)


def rig_config(args: argparse.Namespace, stage: Path):
    try:
        extra = tuple(shlex.split(args.fcc_args))
    except ValueError as e:
        raise UsageError(f"--fcc-args: {e}") from None
    tgt = target(args.target)
    if args.fcc is not None and not tgt.runs_rig_firmware:
        raise UsageError(f"--fcc: the {tgt.name} target runs no firmware of the rig's")
    if args.fcc_args and not tgt.runs_rig_firmware:
        raise UsageError(f"--fcc-args: the {tgt.name} target is configured through SIM_CONTROL, "
                         "and by whoever started it")
    if tgt.socketcan_only and args.interface != "socketcan":
        raise UsageError(f"--target {tgt.name}: the image's serial line is routed to a SocketCAN "
                         "interface (slcand, can-gw): use --interface socketcan")
    if args.key_file is not None:
        try:
            read_key_file(args.key_file)
        except KeyFileError as e:
            raise UsageError(f"--key-file: {e}") from None
    device = device_class(args.target)
    try:
        device.check_args(args.fcc, extra, args.mode)
    except ArgsRefused as e:
        raise UsageError(f"--fcc-args: {e}") from None
    return RigConfig(out_dir=stage, iface=args.iface, mode=args.mode,
                     timeout=args.timeout or tgt.lockstep_timeout_s, fcc_args=extra,
                     progress=not args.quiet, rows=args.rows,
                     plots=not args.no_plots, log_format=args.log_format,
                     fcc_binary=device.firmware(args.fcc, not args.quiet),
                     target=args.target, interface=args.interface, bitrate=args.bitrate,
                     key_file=args.key_file, recorder=getattr(args, "recorder", "canrec"),
                     bus=bus_model(args))


def sync_status(outcomes: Sequence) -> int:
    """0, or EXIT_SYNC with one line on stderr when a realtime run's time synchronisation was
    attacked, refused or lost (its summary's `sync`, hil.results.sync), or fcc's outputs were
    forged, impersonated or disagree with the reference (`bus_trust`, hil.results.trust).  A
    sync loss fcc recovered from, with nothing forged, replayed or refused and the data age in
    bounds (`platform.sync_loss.tolerated`, hil.results.platform), is a warning line, not 7."""
    for outcome in outcomes:
        for key in ("sync", "bus_trust"):
            verdict = outcome.summary.get(key) or {}
            loss = (outcome.summary.get("platform") or {}).get("sync_loss") or {}
            if key == "sync" and verdict.get("verdict") == "lost" and loss.get("tolerated"):
                print(f"{PROG}: {loss['message']}", file=sys.stderr)
                continue
            if verdict.get("verdict", "ok") != "ok":
                why = f"; {loss['message']}" if key == "sync" and loss.get("message") else ""
                print(f"{PROG}: {verdict['message']}{why}", file=sys.stderr)
                return EXIT_SYNC
    return 0


def staged(args: argparse.Namespace, out: Path, runner) -> list:
    """runner(cfg) -> [Outcome, ...] in a staging directory, published to out when done
    (hil.io.rundir); the tables are printed once the results are in place."""

    with staged_run(out, args.command, force=args.force) as stage:
        outcomes = runner(rig_config(args, stage))
    for outcome in outcomes:
        for t in outcome.tables:
            print(t)
            print()
        where = out / outcome.out_dir.relative_to(stage)
        print(f"results in {where}/")
    return outcomes
