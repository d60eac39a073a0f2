"""`hil`: fly the CDRW and the missile against fcc on a CAN bus, and report.

    hil run cdrw|missile [SCENARIO.toml] [--fault SPEC]... [--out DIR] [--seed S]
                                         [--mode lockstep|realtime]
                                         [--target host|qemu-m4f|external] [--fcc PATH]
                                         [--interface NAME --channel CH --bitrate B]
    hil campaign cdrw [SCENARIO.toml] --runs 100 --seed S        (Table 5)
    hil sweep missile [SCENARIO.toml] --periods 0.2,0.1,0.05 --bits 6,8,12   (Fig. 3)
    hil report DIR                                              (tables + plots again)
    hil study missile-rms [--periods LIST] [--bits LIST] [--gyro-var V] [--json]
                                   (Fig. 3 by covariance analysis, no bus needed)
    hil demo [--out out/demo]        (both aircraft; Figs. 4-6 responses; Fig. 3 with HIL points)

Needs a CAN interface (vcan0; `scripts/with-vcan hil ...` provides one) and the built
firmware in $FCC_BUILD_DIR/bin (default <repo>/build/bin); --target qemu-m4f flies the
Cortex-M4F image under QEMU instead, --target external whatever answers on the bus.  Exit status: 0 done; 1 the run
failed (bus, firmware start-up, another fcc on the bus, failed firmware steps, fcc exit
status); 2 bad command line or scenario, or a foreign --out without --force; 3 fcc did not
answer a lockstep step in time; 4 fcc died during the run.  Failures are one line on stderr;
a failed run's bus log and partial results are kept in OUT.failed-TIME (hil.rig.rundir).
"""
from __future__ import annotations

import argparse
import dataclasses
import math
import os
import shlex
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import NoReturn

PROG = "hil"
#: Fig. 3's grid of sampling periods: 0.02 to 0.3 s every 10 ms (29 points)
FIG3_PERIODS = tuple(round(0.02 + 0.01 * i, 2) for i in range(29))
EXIT_USAGE = 2
#: hil verify: a case could not run (no device, a time-out, a crash): never a pass
EXIT_VERIFY_ERROR = 6


class UsageError(Exception):
    """Bad command line or scenario: one line, exit 2."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> NoReturn:  # one line, not argparse's usage block
        raise UsageError(f"{message} (see `{self.prog} --help`)")


def _floats(text: str) -> list[float]:
    try:
        vals = [float(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected numbers separated by commas, got {text!r}") from None
    if not vals or not all(math.isfinite(v) and v > 0 for v in vals):
        raise argparse.ArgumentTypeError(f"expected positive numbers separated by commas, got {text!r}")
    return vals


def _ints(text: str) -> list[int]:
    try:
        vals = [int(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected whole numbers separated by commas, got {text!r}") from None
    if not vals:
        raise argparse.ArgumentTypeError("expected at least one number")
    return vals


def _seed(text: str) -> int:
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 0, got {text!r}") from None
    if v < 0:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 0, got {text!r}")
    return v


def _positive(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not (math.isfinite(v) and v > 0):
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text!r}")
    return v


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version
    try:
        return version("hil")
    except PackageNotFoundError:
        return "unknown (not installed)"


class _VersionAction(argparse.Action):
    """--version, looked up only when asked (importlib.metadata costs 0.1 s in the UML guest)."""

    def __init__(self, option_strings: Sequence[str], dest: str = argparse.SUPPRESS, **kw: object) -> None:
        super().__init__(option_strings, dest, nargs=0, help="show the version and exit")

    def __call__(self, parser: argparse.ArgumentParser, *args: object) -> None:
        print(f"{parser.prog} {_version()}")
        parser.exit()


def _add_paths(p: argparse.ArgumentParser) -> None:
    """--dbc and --fcc: where the bus contract and the firmware are (installed use)."""
    p.add_argument("--dbc", type=Path, metavar="PATH",
                   help="the DBC (default $FCC_HIL_DBC, else the one shipped with hil)")
    p.add_argument("--fcc", type=Path, metavar="PATH",
                   help="the firmware binary (default $FCC_HIL_FCC, else $FCC_BUILD_DIR/bin/fcc, "
                        "else build/bin/fcc of the source tree, else fcc on $PATH); with "
                        "--target qemu-m4f: the ELF image (default: cross-built into build-m4f)")


TARGET_CHOICES = ("host", "qemu-m4f", "external")
#: lockstep answer timeout by target (--timeout)
DEFAULT_TIMEOUT_S = {"host": 2.0, "qemu-m4f": 30.0, "external": 2.0}


def _bitrate(text: str) -> int:
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected bits per second, e.g. 500000, got {text!r}") from None
    if not 10_000 <= v <= 1_000_000:
        raise argparse.ArgumentTypeError(f"expected 10000 to 1000000 bit/s, got {v}")
    return v


def _add_common(p: argparse.ArgumentParser, out_default: str) -> None:
    _add_paths(p)
    p.add_argument("--out", type=Path, default=Path(out_default), metavar="DIR",
                   help=f"run directory (default {out_default}); written when the run is done")
    p.add_argument("--force", action="store_true",
                   help="write into an --out that holds other files (they are kept)")
    p.add_argument("--target", choices=TARGET_CHOICES, default="host",
                   help="device under test: host (fcc, the Linux build; default), qemu-m4f (the "
                   "Cortex-M4F image under QEMU, SLCAN over its UART) or external (start no "
                   "firmware: whatever answers on the bus, e.g. a board on can0)")
    p.add_argument("--interface", default="socketcan", metavar="NAME",
                   help="python-can interface of the simulator's bus (default socketcan; e.g. "
                   "pcan, kvaser, slcan; the bus is then recorded by the rig itself, not candump)")
    p.add_argument("--channel", "--iface", dest="iface", default="vcan0", metavar="CHANNEL",
                   help="python-can channel: the CAN interface (default vcan0; e.g. can0)")
    p.add_argument("--bitrate", type=_bitrate, metavar="BIT/S",
                   help="bitrate for interfaces that set it when opened (python-can's bitrate; a "
                   "SocketCAN interface's is set with `ip link`; the bus's is 500000)")
    p.add_argument("--mode", choices=("lockstep", "realtime"), default="lockstep",
                   help="lockstep (deterministic, default) or realtime (both sides on their clocks)")
    p.add_argument("--timeout", type=_positive, metavar="S",
                   help="lockstep: seconds to wait for fcc's answer to a step; external: for "
                   "the device's heartbeat at the start (default 2; qemu-m4f: 30, emulation "
                   "on a loaded machine)")
    p.add_argument("--fcc-args", default="", metavar="ARGS",
                   help="extra fcc options, one string, e.g. \"--detector oracle\"")
    p.add_argument("--rows", choices=("paper", "prior", "posterior"), default="paper",
                   help="CDRW: the estimate fcc reports per step: paper (KF after y_k, ZKF/AZKF "
                   "before, default), prior (all before y_k) or posterior (all after); the "
                   "summary has Table 4/5 both ways in any case")
    p.add_argument("--key-file", type=Path, metavar="PATH",
                   help="AES-128 key of the bus authentication, shared with fcc (one line of 32 hex "
                        "digits); default: a random key for each session")
    p.add_argument("--no-plots", action="store_true", help="do not draw the PNG figures")
    p.add_argument("--log-format", choices=("log", "asc", "blf"), default="log",
                   help="bus log format: candump -L (bus.log, default), Vector ASC or BLF (python-can); "
                        "lockstep: simulated timestamps, the recorder's wall-clock log in bus_wall.log")
    p.add_argument("--quiet", action="store_true", help="no progress bar")


def _add_parallel(p: argparse.ArgumentParser) -> None:
    g = p.add_mutually_exclusive_group()
    g.add_argument("--workers", type=int, metavar="N",
                   help="fly on N rigs at once from the host shell (each its own UML guest or vcanK, "
                        "fcc and recorder; Dask)")
    g.add_argument("--scheduler", metavar="ADDRESS",
                   help="fly on a running Dask cluster, e.g. tcp://host:8786 (README: Clusters)")


def _parallel(args: argparse.Namespace) -> dict[str, object] | None:
    """--workers/--scheduler as keyword arguments of the parallel runners (None: sequential)."""
    if args.workers is None and args.scheduler is None:
        return None
    if args.workers is not None and args.workers < 1:
        raise UsageError(f"--workers must be at least 1, got {args.workers}")
    if args.mode != "lockstep":
        raise UsageError("--workers/--scheduler fly lockstep flights only (realtime needs the machine to itself)")
    if args.target != "host" or args.interface != "socketcan":
        raise UsageError("--workers/--scheduler fly the host fcc on rigs of their own (vcan), "
                         "not --target/--interface")
    return {"workers": args.workers, "scheduler": args.scheduler}


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog=PROG, description="Hardware-in-the-loop rig: fly the CDRW UAV and the missile "
                "against the fcc firmware on a CAN bus, inject faults, report the papers' tables.")
    p.add_argument("--version", action=_VersionAction)
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser, metavar="COMMAND")

    r = sub.add_parser("run", help="one flight of one aircraft")
    r.add_argument("aircraft", choices=("cdrw", "missile"))
    r.add_argument("scenario", nargs="?", type=Path, help="scenario TOML (default: the embedded one)")
    r.add_argument("--fault", action="append", default=[], metavar="SPEC",
                   help="extra fault, e.g. spike:signal=alpha,start=4,duration=0.1,magnitude=0.2")
    r.add_argument("--seed", type=_seed, help="override the scenario's seed")
    _add_common(r, "out/run-<aircraft>")

    c = sub.add_parser("campaign", help="Table 5: the flight many times, faults at random times")
    c.add_argument("aircraft", choices=("cdrw",))
    c.add_argument("scenario", nargs="?", type=Path, help="scenario TOML (default: the embedded one)")
    c.add_argument("--runs", type=int, default=100, help="flights (default 100)")
    c.add_argument("--seed", type=_seed, default=1, help="seed of the fault times (default 1)")
    c.add_argument("--fault", action="append", default=[], metavar="SPEC",
                   help="extra fault (moved in time with the scenario's)")
    c.add_argument("--recorder", choices=("canrec", "candump"), default="canrec",
                   help="the bus recorder of a SocketCAN rig: canrec (default; firmware/tools/canrec: "
                        "candump's log lines, frames read in batches: less CPU per flight in the UML "
                        "guest; every run records with it) or candump (can-utils)")
    _add_parallel(c)
    _add_common(c, "out/campaign-cdrw")

    s = sub.add_parser("sweep", help="Fig. 3: the missile at several periods and D/A word lengths")
    s.add_argument("aircraft", choices=("missile",))
    s.add_argument("scenario", nargs="?", type=Path, help="scenario TOML (default: the embedded one)")
    s.add_argument("--periods", type=_floats, default=[0.2, 0.1, 0.05], metavar="T,T,...",
                   help="sampling periods in s (default 0.2,0.1,0.05)")
    s.add_argument("--bits", type=_ints, default=[6, 8, 12], metavar="N,N,...",
                   help="D/A word lengths (default 6,8,12)")
    s.add_argument("--seed", type=_seed, help="override the scenario's seed")
    s.add_argument("--fault", action="append", default=[], metavar="SPEC", help="extra fault")
    _add_parallel(s)
    _add_common(s, "out/sweep-missile")

    rep = sub.add_parser("report", help="print a run directory's tables and redraw its plots")
    rep.add_argument("dir", type=Path)
    rep.add_argument("--no-plots", action="store_true", help="only print the tables")
    rep.add_argument("--plots-only", action="store_true", help="only draw the figures (no tables)")
    rep.add_argument("--bus", action="store_true", help="also analyse the bus log (rates, E2E, load)")
    rep.add_argument("--dbc", type=Path, metavar="PATH",
                     help="the DBC (default $FCC_HIL_DBC, else the one shipped with hil)")

    st = sub.add_parser("study", help="offline studies (no bus): missile-rms = Fig. 3 by covariance analysis")
    st.add_argument("study", choices=("missile-rms",))
    st.add_argument("--periods", type=_floats, default=list(FIG3_PERIODS), metavar="T,T,...",
                    help="sampling periods in s (default 0.02,0.03,...,0.3)")
    st.add_argument("--bits", type=_ints, default=[6, 8, 12], metavar="N,N,...",
                    help="D/A word lengths (default 6,8,12)")
    st.add_argument("--gyro-var", type=_positive, default=0.8, metavar="V",
                    help="rate-gyro noise variance, rad^2/s^2 (default 0.8, as printed)")
    st.add_argument("--accel-var", type=_positive, default=0.8, metavar="V",
                    help="accelerometer noise variance, ft^2/s^4 (default 0.8)")
    st.add_argument("--json", action="store_true", help="print the result as one JSON object")

    lv = sub.add_parser("live", help="dashboard of the bus while a run flies (alpha, q, estimates, "
                        "fault flags, E2E counters)")
    lv.add_argument("--iface", default="vcan0", help="CAN interface (default vcan0)")
    lv.add_argument("--seconds", type=_positive, default=10.0, metavar="S", help="how long (default 10)")
    lv.add_argument("--rich", action="store_true",
                    help="redraw in place even when stdout is not a terminal (e.g. inside scripts/with-vcan)")
    lv.add_argument("--dbc", type=Path, metavar="PATH",
                    help="the DBC (default $FCC_HIL_DBC, else the one shipped with hil)")

    fl = sub.add_parser("faults", help="every fault kind: fields, units, defaults, an example")
    fl.add_argument("kinds", nargs="*", metavar="KIND", help="only these kinds")

    rp = sub.add_parser("replay", help="replay a recorded lockstep run into fcc; compare every "
                        "firmware frame (exit 0 identical, 1 the first difference)")
    rp.add_argument("dir", type=Path, metavar="RUN_DIR")
    rp.add_argument("--out", type=Path, metavar="DIR", help="where fcc.log goes (default RUN_DIR/replay)")
    rp.add_argument("--iface", default="vcan0", help="CAN interface (default vcan0)")
    rp.add_argument("--timeout", type=_positive, default=2.0, metavar="S",
                    help="seconds to wait for fcc's answer to a step (default 2)")
    rp.add_argument("--fcc-args", default="", metavar="ARGS",
                    help="fcc options added to the recorded ones, e.g. \"--ridge 0.01\"")
    _add_paths(rp)

    d = sub.add_parser("demo", help="both aircraft with the default scenarios, then seed 2's Figs. 4-6 "
                       "(deterministic responses) and Fig. 3 (covariance analysis + HIL points)")
    _add_common(d, "out/demo")

    v = sub.add_parser("verify", help="requirement-based test suites against the device under test: "
                       "a verdict per case and requirement, JUnit XML, an HTML report",
                       epilog="exit status: 0 every case passed; 1 a case failed; 2 bad command line or "
                       "suite (nothing flew); 6 a case could not run (error: no device, time-out, crash)")
    v.add_argument("suites", nargs="*", metavar="SUITE",
                   help="a shipped suite's name (hil verify --list) or a suite TOML file")
    v.add_argument("--case", action="append", default=[], metavar="ID", help="only these cases (repeatable)")
    v.add_argument("--junit", type=Path, metavar="FILE", help="write JUnit XML here")
    v.add_argument("--report", type=Path, metavar="DIR",
                   help="the report's directory (index.html, one run directory per case; default: --out)")
    v.add_argument("--list", action="store_true", help="list the shipped suites and exit")
    v.add_argument("--fields", action="store_true", help="list the result fields expectations may name and exit")
    _add_common(v, "out/verify")
    return p


# ---- helpers -------------------------------------------------------------------------------
def _scenario(aircraft: str, path: Path | None, faults: Sequence[str], seed: int | None):
    from .bus import load
    from .faults import load_default_scenario, load_scenario, with_extra_faults

    frames = {m.name for m in load().messages}
    sc = load_scenario(path, frames) if path is not None else load_default_scenario(aircraft, frames)
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


def _config(args: argparse.Namespace, stage: Path):
    from .rig.runs import RigConfig

    try:
        extra = tuple(shlex.split(args.fcc_args))
    except ValueError as e:
        raise UsageError(f"--fcc-args: {e}") from None
    if args.fcc is not None and args.target == "external":
        raise UsageError("--fcc: the external target runs no firmware of the rig's")
    if args.fcc_args and args.target == "external":
        raise UsageError("--fcc-args: the external target is configured through SIM_CONTROL, "
                         "and by whoever started it")
    if args.target == "qemu-m4f" and args.interface != "socketcan":
        raise UsageError("--target qemu-m4f: the image's serial line is routed to a SocketCAN "
                         "interface (slcand, can-gw): use --interface socketcan")
    if args.key_file is not None:
        from .bus.secoc import KeyFileError, read_key_file
        try:
            read_key_file(args.key_file)
        except KeyFileError as e:
            raise UsageError(f"--key-file: {e}") from None
    return RigConfig(out_dir=stage, iface=args.iface, mode=args.mode,
                     timeout=args.timeout or DEFAULT_TIMEOUT_S[args.target], fcc_args=extra,
                     progress=not args.quiet, rows=args.rows,
                     plots=not args.no_plots, log_format=args.log_format, fcc_binary=args.fcc,
                     target=args.target, interface=args.interface, bitrate=args.bitrate,
                     key_file=args.key_file, recorder=getattr(args, "recorder", "canrec"))


def _staged(args: argparse.Namespace, out: Path, runner) -> list:
    """runner(cfg) -> [Outcome, ...] in a staging directory, published to out when done
    (hil.rig.rundir); the tables are printed once the results are in place."""
    from .rig.rundir import staged_run

    with staged_run(out, args.command, force=args.force) as stage:
        outcomes = runner(_config(args, stage))
    for outcome in outcomes:
        for t in outcome.tables:
            print(t)
            print()
        where = out / outcome.out_dir.relative_to(stage)
        print(f"results in {where}/")
    return outcomes


# ---- commands -------------------------------------------------------------------------------
def cmd_run(args: argparse.Namespace) -> int:
    from .rig.runs import run_flight

    sc = _scenario(args.aircraft, args.scenario, args.fault, args.seed)
    out = Path(str(args.out).replace("<aircraft>", args.aircraft))
    _staged(args, out, lambda cfg: [run_flight([sc], cfg)])
    return 0


def _run_many(args: argparse.Namespace, sequential, parallel: str, *inputs: object) -> int:
    """A campaign or sweep: sequential(*inputs, cfg) in this process's rig, or with
    --workers/--scheduler hil.parallel.runs.<parallel> on many rigs; flights that failed twice
    there are one line and exit 1 (the others' results are written)."""
    par = _parallel(args)
    if par is None:
        _staged(args, args.out, lambda cfg: [sequential(*inputs, cfg)])
        return 0
    from .parallel import runs
    (outcome,) = _staged(args, args.out, lambda cfg: [getattr(runs, parallel)(*inputs, cfg, **par)])
    failed = outcome.summary.get("failed_runs") or []
    if not failed:
        return 0
    print(f"{PROG}: {len(failed)} flight(s) failed twice and are left out of the results "
          f"(summary.json failed_runs); first: flight {failed[0]['run']}: {failed[0]['error']}",
          file=sys.stderr)
    return 1


def cmd_campaign(args: argparse.Namespace) -> int:
    from .rig.runs import run_campaign

    if args.runs < 1:
        raise UsageError(f"--runs must be at least 1, got {args.runs}")
    sc = _scenario("cdrw", args.scenario, args.fault, None)
    return _run_many(args, run_campaign, "run_campaign_parallel", sc, args.runs, args.seed)


def cmd_sweep(args: argparse.Namespace) -> int:
    from .rig.runs import run_sweep

    sc = _scenario("missile", args.scenario, args.fault, args.seed)
    return _run_many(args, run_sweep, "run_sweep_parallel", sc, args.periods, args.bits)


def _not_a_summary(path: Path, e: Exception) -> UsageError:
    if isinstance(e, KeyError):
        return UsageError(f"{path}: not a hil summary: missing key {e.args[0]!r}")
    return UsageError(f"{path}: not a hil summary: {str(e).splitlines()[0] if str(e) else type(e).__name__}")


def cmd_report(args: argparse.Namespace) -> int:
    from .rig.output import read_json
    from .rig.report import summary_tables

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
        tables = [] if args.plots_only else summary_tables(summary)
    except (KeyError, TypeError, AttributeError, ValueError, IndexError) as e:
        raise _not_a_summary(summary_path, e) from None
    for t in tables:
        print(t)
        print()
    if args.bus:
        from .bus import load
        from .bus.diag import analyse, render
        from .bus.logio import read_frames, run_log
        log = run_log(args.dir)
        if log is None:
            raise UsageError(f"{args.dir}: no bus log (bus.log, bus.asc or bus.blf)")
        print(render(analyse(read_frames(log), load())))
    if not args.no_plots:
        from .plots import plot_run_dir
        try:
            written = plot_run_dir(args.dir)
        except (KeyError, TypeError, AttributeError, IndexError) as e:
            raise _not_a_summary(summary_path, e) from None
        from .rig.rundir import note_written
        note_written(args.dir, written)
        names = [p.name for p in written]
        if names:
            print(f"plots: {', '.join(names)}")
    return 0


def cmd_study(args: argparse.Namespace) -> int:
    import json

    from .plants.missile_cov import format_study, missile_rms_study
    from .rig.paths import tool

    for n in args.bits:
        if not 2 <= n <= 16:
            raise UsageError(f"--bits: D/A word length must be 2 to 16, got {n}")
    for T in args.periods:
        if not 0.001 <= T <= 1.0:
            raise UsageError(f"--periods: lqg_design accepts 0.001 to 1 s, got {T:g}")
    study = missile_rms_study(args.periods, args.bits, args.gyro_var, args.accel_var, tool("lqg_design"))
    print(json.dumps(study, allow_nan=False) if args.json else format_study(study))
    return 0


def cmd_live(args: argparse.Namespace) -> int:
    from .bus import load
    from .live import run

    try:
        run(args.iface, args.seconds, load(), force_rich=args.rich)
    except OSError as e:
        raise RuntimeError(f"cannot watch CAN interface {args.iface!r}: {e}") from None
    return 0


def cmd_faults(args: argparse.Namespace) -> int:
    from .faults import KINDS
    from .faults.catalog import catalog

    unknown = [k for k in args.kinds if k not in KINDS]
    if unknown:
        raise UsageError(f"no fault kind {unknown[0]!r} (kinds: {', '.join(KINDS)})")
    print(catalog(args.kinds or None))
    return 0


def cmd_replay(args: argparse.Namespace) -> int:
    from .rig.replay import ReplayError, replay

    try:
        extra = shlex.split(args.fcc_args)
    except ValueError as e:
        raise UsageError(f"--fcc-args: {e}") from None
    if not args.dir.is_dir():
        raise UsageError(f"{args.dir}: not a run directory")
    out = args.out or args.dir / "replay"
    out.mkdir(parents=True, exist_ok=True)
    try:
        steps, diff = replay(args.dir, out, extra, args.iface, args.timeout)
    except ReplayError as e:
        raise UsageError(str(e)) from None
    finally:
        if out.resolve().is_relative_to(args.dir.resolve()):  # the run stays hil's own: a new
            from .rig.rundir import note_written              # run may replace it
            note_written(args.dir, [f for f in out.rglob("*") if f.is_file()])
    if diff is not None:
        print(f"replay of {args.dir}: DIFFERENT after {steps} identical steps; {diff}")
        return 1
    print(f"replay of {args.dir}: identical ({steps} steps, every firmware frame)")
    return 0


def cmd_demo(args: argparse.Namespace) -> int:
    from .rig.runs import run_demo

    _staged(args, args.out, run_demo)
    return 0


def cmd_verify(args: argparse.Namespace) -> int:
    from .rig.rundir import staged_run
    from .verify import fields, report, runner, suite

    if args.fields:
        print(fields.describe())
        return 0
    if args.list:
        for name, path in suite.shipped().items():
            s = suite.load(path)
            print(f"{name:<24} {len(s.cases):3d} cases  {len(s.requirements):3d} requirements  {s.title}")
        return 0
    if not args.suites:
        raise UsageError("verify: name at least one suite (hil verify --list shows the shipped ones)")
    try:
        suites = [suite.load(suite.find(name)) for name in args.suites]
    except suite.SuiteError as e:
        raise UsageError(f"verify: {e}") from None
    if args.case:
        known = {c.id for s in suites for c in s.cases}
        unknown = sorted(set(args.case) - known)
        if unknown:
            raise UsageError(f"verify: --case {', '.join(unknown)}: no such case in {', '.join(args.suites)}")
        suites = [dataclasses.replace(s, cases=tuple(c for c in s.cases if c.id in args.case)) for s in suites]
        suites = [s for s in suites if s.cases]
    out = args.report or args.out
    device = [f"--target={args.target}"] + ([f"--fcc-args={args.fcc_args}"] if args.fcc_args else []) \
        + ([f"--key-file={args.key_file}"] if args.key_file else [])
    command = shlex.join(["hil", "verify", *args.suites, *device])
    with staged_run(out, "verify", force=args.force) as stage:
        base = _config(args, stage)
        base = dataclasses.replace(base, progress=False)
        results = runner.run_suites(suites, base, stage, lambda s, c: runner.refly_command(s, c, device),
                                    lambda r: print(report.line(r), flush=True))
        report.html_report(results, suites, stage, args.target, command)
    if args.junit is not None:
        report.junit(results, suites, args.junit, args.target)
    n = report.counts(results)
    print()
    print(report.traceability(results, suites))
    print()
    print(f"verify: {n[runner.PASS]} passed, {n[runner.FAIL]} failed, {n[runner.ERROR]} errors "
          f"(report: {out / 'index.html'})")
    return EXIT_VERIFY_ERROR if n[runner.ERROR] else 1 if n[runner.FAIL] else 0


COMMANDS = {"run": cmd_run, "campaign": cmd_campaign, "sweep": cmd_sweep, "report": cmd_report,
            "study": cmd_study, "replay": cmd_replay, "faults": cmd_faults, "live": cmd_live,
            "demo": cmd_demo, "verify": cmd_verify}


def _apply_paths(args: argparse.Namespace) -> None:
    dbc_path = getattr(args, "dbc", None)
    if dbc_path is not None:
        if not dbc_path.is_file():
            raise UsageError(f"--dbc {dbc_path}: no such file")
        from .bus import dbc
        dbc.set_default(dbc_path)
    fcc_path = getattr(args, "fcc", None)
    from .rig import paths
    paths.set_fcc(fcc_path)  # also when None: no earlier main() call's --fcc stays in force
    if fcc_path is not None:
        try:
            paths.fcc_binary()  # a bad path is a usage error now, not a failed run later
        except paths.ToolNotFound as e:
            paths.set_fcc(None)
            raise UsageError(str(e)) from None


def _join_fcc_args(argv: Sequence[str]) -> list[str]:
    """`--fcc-args "--mls-intercept"`: argparse takes a value that starts with '--' for an
    option of its own; joined as --fcc-args=VALUE it is the value it is meant to be."""
    out: list[str] = []
    it = iter(argv)
    for a in it:
        if a == "--fcc-args":
            val = next(it, None)
            out.append(a if val is None else f"{a}={val}")
        else:
            out.append(a)
    return out


def _quiet_stdout() -> None:
    """The reader of our stdout has gone (`hil ... | head`): print nothing more, quietly."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError):
        pass


def main(argv: Sequence[str] | None = None) -> int:
    try:
        args = _parser().parse_args(_join_fcc_args(sys.argv[1:] if argv is None else argv))
        _apply_paths(args)
        return COMMANDS[args.command](args)
    except BrokenPipeError:
        # the results are already in place when the tables are printed: not a failed run
        _quiet_stdout()
        return 0
    except UsageError as e:
        print(f"{PROG}: {e}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt as e:
        print(f"{PROG}: interrupted{_notes(e)}", file=sys.stderr)
        return 130
    except Exception as e:  # noqa: BLE001 - every failure is one line for the user
        return _fail(e)


def _notes(e: BaseException) -> str:
    """Where a failed run's partial results are (hil.rig.rundir adds it as a note), to end
    the one line with."""
    notes = getattr(e, "__notes__", ())
    return f" ({'; '.join(notes)})" if notes else ""


def _fail(e: Exception) -> int:
    from .faults import ScenarioError
    from .rig.paths import ToolNotFound
    from .rig.rundir import OutDirRefused
    from .rig.session import RigError

    msg = str(e).splitlines()[0] if str(e) else type(e).__name__
    if isinstance(e, (ScenarioError, OutDirRefused)):
        code = EXIT_USAGE
    elif isinstance(e, RigError):
        code = e.exit_code
    elif isinstance(e, (ToolNotFound, OSError, ValueError, RuntimeError)):
        code = 1
    else:
        raise e
    print(f"{PROG}: {msg}{_notes(e)}", file=sys.stderr)
    return code


def entry() -> NoReturn:
    """The `hil` program (tests call main() instead)."""
    sys.exit(main())


if __name__ == "__main__":
    entry()
