"""`hil`'s command line: the parser of every subcommand, their argument types and shared
options.  One module for all subcommands' arguments (where cantools puts each in its
subcommand's module): `hil --help` and the parse need none of the commands' code, so that a
command imports only what it runs (hil.cli.main imports the chosen one).
"""
from __future__ import annotations

import argparse
from collections.abc import Sequence
from pathlib import Path
from typing import NoReturn

import hil
from hil.cli import listing
from hil.cli.argtypes import (bitrate, bitrates, floats, id_range, ints, positive, rate_and_load,
                              seed, utilisations)
from hil.cli.bus.options import add_bus
from hil.cli.usage import PROG, UsageError, exit_status_help
from hil.targets.registry import TARGETS


class Parser(argparse.ArgumentParser):
    """argparse with one-line errors, and a command's positionals and options in any order:
    argparse alone fills the positionals it sees together at once, an optional one empty, so
    `hil run missile --quiet S.toml` left S.toml over ("unrecognized arguments"); a parser
    without subcommands (every command's own) parses intermixed: the options first, then the
    positionals wherever they stood."""

    _intermixing = False

    def error(self, message: str) -> NoReturn:  # one line, not argparse's usage block
        raise UsageError(f"{message} (see `{self.prog} --help`)")

    def parse_known_args(self, args: Sequence[str] | None = None,  # type: ignore[override]
                         namespace: argparse.Namespace | None = None) -> tuple[argparse.Namespace, list[str]]:
        if self._intermixing or self._subparsers is not None:  # the intermixed parse's own passes;
            return super().parse_known_args(args, namespace)  # subcommands: argparse's own parse
        self._intermixing = True
        try:
            return self.parse_known_intermixed_args(args, namespace)
        finally:
            self._intermixing = False


def version() -> str:
    """hil.__version__: looked up in the package's metadata when asked (--version only)."""
    return str(hil.__version__)


class VersionAction(argparse.Action):
    """--version, looked up only when asked (importlib.metadata costs 0.1 s in the UML guest)."""

    def __init__(self, option_strings: Sequence[str], dest: str = argparse.SUPPRESS, **kw: object) -> None:
        super().__init__(option_strings, dest, nargs=0, help="show the version and exit")

    def __call__(self, parser: argparse.ArgumentParser, *args: object) -> None:
        print(f"{parser.prog} {version()}")
        parser.exit()


def add_paths(p: argparse.ArgumentParser) -> None:
    """--dbc, --fcc and --build-dir: where the bus contract and the firmware are (installed use)."""
    p.add_argument("--dbc", type=Path, metavar="PATH",
                   help="the DBC (default $FCC_HIL_DBC, else the one shipped with hil)")
    p.add_argument("--fcc", type=Path, metavar="PATH",
                   help="the firmware binary (default $FCC_HIL_FCC, else $FCC_BUILD_DIR/bin/fcc, "
                        "else build/bin/fcc of the source tree, else fcc on $PATH); with "
                        "--target qemu-m4f: the ELF image (default $FCC_M4F_BUILD_DIR/bin/fcc_m4f.elf, "
                        "else cross-built into build-m4f of the source tree, else fcc_m4f.elf on $PATH)")
    add_build_dir(p)


def add_build_dir(p: argparse.ArgumentParser) -> None:
    p.add_argument("--build-dir", type=Path, metavar="DIR",
                   help="the firmware's CMake build directory: every program (fcc, sid_replay, canrec, "
                        "lqg_design) from DIR/bin (default $FCC_BUILD_DIR, else build/ of the source "
                        "tree, else $PATH)")


SCENARIO_HELP = ("scenario TOML, or a shipped scenario's name (hil run --list-scenarios); "
                 "default: the aircraft's default one")


class ListScenarios(argparse.Action):
    """--list-scenarios: the shipped scenarios, printed and exit (before the positionals are
    checked, as --version)."""

    def __init__(self, option_strings: Sequence[str], dest: str = argparse.SUPPRESS, **kw: object) -> None:
        super().__init__(option_strings, dest, nargs=0, help="list the shipped scenarios and exit")

    def __call__(self, parser: argparse.ArgumentParser, *args: object) -> None:
        print(listing.scenarios())
        parser.exit()


TARGET_CHOICES = tuple(TARGETS)


def add_common(p: argparse.ArgumentParser, out_default: str) -> None:
    add_paths(p)
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
    p.add_argument("--bitrate", type=bitrate, metavar="BIT/S",
                   help="bitrate for interfaces that set it when opened (python-can's bitrate; a "
                   "SocketCAN interface's is set with `ip link`; the bus's is 500000)")
    p.add_argument("--mode", choices=("lockstep", "realtime"), default="lockstep",
                   help="lockstep (deterministic, default) or realtime (both sides on their clocks)")
    p.add_argument("--timeout", type=positive, metavar="S",
                   help="lockstep: seconds to wait for fcc's answer to a step; external: for "
                   "the device's heartbeat at the start (default: the target's, "
                   + ", ".join(f"{n} {t.lockstep_timeout_s:g}" for n, t in TARGETS.items()) + ")")
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


def add_parallel(p: argparse.ArgumentParser) -> None:
    g = p.add_mutually_exclusive_group()
    g.add_argument("--workers", type=int, metavar="N",
                   help="fly on N rigs at once from the host shell (each its own UML guest or vcanK, "
                        "fcc and recorder; Dask)")
    g.add_argument("--scheduler", metavar="ADDRESS",
                   help="fly on a running Dask cluster, e.g. tcp://host:8786 (README: Clusters)")


def add_rig(p: argparse.ArgumentParser) -> None:
    p.add_argument("--rig", action="store_true",
                   help="fly on the warm rig `hil rig up` started (no guest to boot; docs/rig.md)")


def add_rig_commands(sub: argparse._SubParsersAction[Parser]) -> None:
    rg = sub.add_parser("rig", help="a warm rig: a guest with its bus kept up for `--rig` commands")
    rsub = rg.add_subparsers(dest="rig_command", required=True, parser_class=Parser, metavar="ACTION")
    u = rsub.add_parser("up", help="start the rig and return once it is ready")
    u.add_argument("--target", choices=[n for n, t in TARGETS.items() if t.warm_rig], default="host",
                   help="the device under test the rig's commands fly (default host)")
    u.add_argument("--idle-timeout", type=positive, default=1800.0, metavar="S",
                   help="stop after S seconds without a command (default 1800)")
    rsub.add_parser("status", help="up or down, target, uptime, commands run, client (exit 1: down)")
    rsub.add_parser("down", help="stop the rig and its guest")


def add_logging(p: argparse.ArgumentParser, default: object) -> None:
    """-v/--verbose and --debug (hil.util.log): hil's options, taken before the command or
    after it (a command's own default SUPPRESS leaves hil's value in place)."""
    p.add_argument("-v", "--verbose", action="count", default=0 if default is None else default,
                   help="say what hil finds and does (the scenario, the programs, fcc's command line)")
    p.add_argument("--debug", action="store_true", default=False if default is None else default,
                   help="also the debug records, with their times and modules")


def _commands(p: argparse.ArgumentParser) -> list[argparse.ArgumentParser]:
    """Every (sub)command's parser under p."""
    found = []
    for action in p._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sp in dict.fromkeys(action.choices.values()):
                found += [sp, *_commands(sp)]
    return found


def build() -> argparse.ArgumentParser:
    p = Parser(prog=PROG, description="Hardware-in-the-loop rig: fly the CDRW UAV and the missile "
                "against the fcc firmware on a CAN bus, inject faults, report the papers' tables.",
               epilog=exit_status_help(), formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--version", action=VersionAction)
    add_logging(p, None)
    sub = p.add_subparsers(dest="command", required=True, parser_class=Parser, metavar="COMMAND")

    r = sub.add_parser("run", help="one flight of one aircraft")
    r.add_argument("aircraft", choices=("cdrw", "missile"))
    r.add_argument("scenario", nargs="?", help=SCENARIO_HELP)
    r.add_argument("--fault", action="append", default=[], metavar="SPEC",
                   help="extra fault, e.g. spike:signal=alpha,start=4,duration=0.1,magnitude=0.2")
    r.add_argument("--seed", type=seed, help="the random seed (noise, gusts): overrides the scenario's")
    r.add_argument("--list-scenarios", action=ListScenarios)
    add_common(r, "out/run-<aircraft>")
    add_rig(r)
    r.add_argument("--bus", choices=("ideal", "wire"), default="ideal",
                   help="ideal (the nodes share --iface, frames take no time; default) or wire "
                        "(arbitration and wire time at --bitrate, default the DBC's Baudrate; "
                        "realtime: each node on its own vxcan end of canbus, --target external: no "
                        "model, the real bus's response times measured; lockstep: the same model in "
                        "simulated time; docs/bus-timing.md)")

    c = sub.add_parser("campaign", help="Table 5: faults at random times; or scenario fields varied (--vary)")
    c.add_argument("aircraft", choices=("cdrw", "missile"))
    c.add_argument("scenario", nargs="?", help=SCENARIO_HELP)
    c.add_argument("--runs", type=int, default=100, help="flights (default 100; with --vary: of each)")
    c.add_argument("--seed", type=seed, default=1, help="random seed of the fault times and draws (default 1)")
    c.add_argument("--vary", action="append", default=[], metavar="KEY=V1,V2,...", help="fly every value "
                   "of a scenario field (repeatable: the product), KEY as in a scenario file: duration, "
                   "seed, plant.*, sensors.*, lqg.*, faults[N].*; e.g. lqg.period=0.1,0.05")
    c.add_argument("--draw", action="append", default=[], metavar="KEY=LAW:A,B", help="a scenario field "
                   "drawn for each flight from --seed: uniform:A,B or integers:A,B (A..B)")
    c.add_argument("--keep-logs", action="store_true", help="keep each flight's run directory in "
                   "OUT/flights/NNNN/ (bus log, bus key: `hil replay` replays it)")
    c.add_argument("--fault", action="append", default=[], metavar="SPEC",
                   help="extra fault (moved in time with the scenario's)")
    c.add_argument("--recorder", choices=("canrec", "candump"), default="canrec",
                   help="the bus recorder of a SocketCAN rig: canrec (default; firmware/tools/canrec: "
                        "candump's log lines, frames read in batches: less CPU per flight in the UML "
                        "guest; every run records with it) or candump (can-utils)")
    add_parallel(c)
    add_common(c, "out/campaign-cdrw")
    add_rig(c)

    s = sub.add_parser("sweep", help="Fig. 3: the missile at several periods and D/A word lengths")
    s.add_argument("aircraft", choices=("missile",))
    s.add_argument("scenario", nargs="?", help=SCENARIO_HELP)
    s.add_argument("--periods", type=floats, default=[0.2, 0.1, 0.05], metavar="T,T,...",
                   help="sampling periods in s (default 0.2,0.1,0.05)")
    s.add_argument("--bits", type=ints, default=[6, 8, 12], metavar="N,N,...",
                   help="D/A word lengths (default 6,8,12)")
    s.add_argument("--seed", type=seed, help="the random seed (noise, gusts): overrides the scenario's")
    s.add_argument("--fault", action="append", default=[], metavar="SPEC", help="extra fault")
    add_parallel(s)
    add_common(s, "out/sweep-missile")

    rep = sub.add_parser("report", help="print a run directory's tables and redraw its plots")
    rep.add_argument("dir", type=Path)
    rep.add_argument("--no-plots", action="store_true", help="only print the tables")
    rep.add_argument("--plots-only", action="store_true", help="only draw the figures (no tables)")
    rep.add_argument("--bus", action="store_true", help="also analyse the bus log (rates, E2E, load)")
    rep.add_argument("--dbc", type=Path, metavar="PATH",
                     help="the DBC (default $FCC_HIL_DBC, else the one shipped with hil)")

    pl = sub.add_parser("plot", help="redraw a run directory's figures from its CSV files and summary.json")
    pl.add_argument("dir", type=Path, metavar="RUN_DIR")
    pl.add_argument("--figures", type=lambda t: [x for x in t.split(",") if x], metavar="NAME,...",
                    help="only these (default all): cdrw (Figs. 5-10), campaign, tables (Table 4/5 "
                    "bars), fig3, missile (time responses), timing (a realtime run's), bus (each "
                    "identifier's response times against its bound: a --bus wire run)")
    pl.add_argument("--out", type=Path, metavar="DIR", help="into DIR, a new directory (default RUN_DIR)")
    pl.add_argument("--force", action="store_true", help="write into an --out that holds other files (kept)")

    cm = sub.add_parser("compare", help="runs overlaid: time series on shared axes, tables side by "
                        "side with their differences; PNG files and compare.html")
    cm.add_argument("dirs", nargs="+", type=Path, metavar="RUN_DIR", help="two runs or more")
    cm.add_argument("--out", type=Path, default=Path("out/compare"), metavar="DIR",
                    help="where the comparison goes (default out/compare)")
    cm.add_argument("--force", action="store_true", help="write into an --out that holds other files (kept)")

    st = sub.add_parser("study", help="studies: missile-rms = Fig. 3 by covariance analysis and a "
                        "quantiser Monte Carlo; cdrw = Table 5 with its controls (both offline, no "
                        "bus); bus = the missile's RMS q over bit rate and background load on the "
                        "wire-time bus in lockstep, and Table 4 there (on vcan0, docs/bus-timing.md)")
    st.add_argument("study", choices=("missile-rms", "cdrw", "bus"))
    st.add_argument("--runs", type=int, default=12, metavar="N",
                    help="cdrw: fault start times per case (default 12; the campaign draws them)")
    st.add_argument("--noise-seeds", type=int, default=10, metavar="N",
                    help="cdrw: noise seeds 1..N for the seed-spread case (default 10)")
    st.add_argument("--cases", type=lambda t: [x for x in t.split(",") if x], default=None,
                    metavar="NAME,...", help="cdrw: only these cases (default all)")
    st.add_argument("--figure", type=Path, default=None, metavar="PNG",
                    help="cdrw / missile-rms: also draw the study's figure into PNG")
    st.add_argument("--mc-loops", type=int, default=0, metavar="N",
                    help="missile-rms: also a Monte Carlo with a real quantiser, N loops per "
                    "point (default 0: covariance model only)")
    st.add_argument("--mc-seconds", type=positive, default=50.0, metavar="S",
                    help="missile-rms: length of each Monte Carlo flight (default 50 s)")
    st.add_argument("--periods", type=floats, default=None, metavar="T,T,...",
                    help="sampling periods in s (default missile-rms 0.02,0.03,...,0.3; bus 0.05,0.1)")
    st.add_argument("--bitrates", type=bitrates, default=None, metavar="R,R,...",
                    help="bus: bit rates (default 125k,250k,500k,1M)")
    st.add_argument("--loads", type=utilisations, default=None, metavar="U,U,...",
                    help="bus: background loads, shares of the bus (default 0,0.2,0.4,0.6,0.8)")
    st.add_argument("--load-ids", type=id_range, default=None, metavar="LO-HI",
                    help="bus: the background node's identifiers (default 0x004-0x00f: above the "
                    "loop's frames)")
    st.add_argument("--duration", type=positive, default=10.0, metavar="S",
                    help="bus: seconds a flight (default 10, the default missile's)")
    st.add_argument("--seed", type=seed, default=1, metavar="N", help="bus: the flights' seed (default 1)")
    st.add_argument("--table4", type=rate_and_load, default=(250_000, 0.5), metavar="RATE,LOAD",
                    help="bus: Table 4 on the ideal bus and on the wire at RATE with LOAD (default 250k,0.5)")
    st.add_argument("--no-table4", action="store_true", help="bus: no Table 4 flights")
    st.add_argument("--bits", type=ints, default=[6, 8, 12], metavar="N,N,...",
                    help="D/A word lengths (default 6,8,12)")
    st.add_argument("--gyro-var", type=positive, default=0.8, metavar="V",
                    help="rate-gyro noise variance, rad^2/s^2 (default 0.8, as printed)")
    st.add_argument("--accel-var", type=positive, default=0.8, metavar="V",
                    help="accelerometer noise variance, ft^2/s^4 (default 0.8)")
    st.add_argument("--json", action="store_true", help="print the result as one JSON object")
    add_build_dir(st)

    lv = sub.add_parser("live", help="dashboard of the bus while a run flies (alpha, q, estimates, "
                        "fault flags, E2E counters)")
    lv.add_argument("--iface", default="vcan0", help="CAN interface (default vcan0)")
    lv.add_argument("--seconds", type=positive, default=10.0, metavar="S", help="how long (default 10)")
    lv.add_argument("--rich", action="store_true",
                    help="redraw in place even when stdout is not a terminal (e.g. inside scripts/with-vcan)")
    lv.add_argument("--dbc", type=Path, metavar="PATH",
                    help="the DBC (default $FCC_HIL_DBC, else the one shipped with hil)")
    lv.add_argument("--plot", action="store_true",
                    help="also a chart of --signals in the browser, streaming (served on 127.0.0.1)")
    lv.add_argument("--signals", default="MSL_RATE_GYRO.q_g,MSL_STATE_EST.q_hat,CDRW_AOA.alpha,"
                    "SID_AZKF_STATE.alpha_hat", metavar="MSG.SIG,...",
                    help="the chart's signals, MESSAGE.signal or a signal only one message has "
                    "(default: the missile's q_g and q_hat, the CDRW's alpha and the AZKF's estimate)")
    lv.add_argument("--port", type=int, default=8765, metavar="N",
                    help="the chart's port on 127.0.0.1 (default 8765; 0: any free one)")
    g = lv.add_mutually_exclusive_group()
    g.add_argument("--log", type=Path, metavar="BUS.LOG",
                   help="chart a recorded bus log (candump -L, ASC, BLF) instead of the bus")
    g.add_argument("--follow", type=Path, metavar="OUT",
                   help="chart the bus log of the run flying into --out OUT as it is recorded (e.g. "
                   "the chart on the host, the run inside scripts/with-vcan)")

    ij = sub.add_parser("inject", help="a fault into a realtime flight while it flies (as --fault; "
                        "without start: from the next step)")
    ij.add_argument("fault", metavar="FAULT", help="e.g. stuck:signal=q_g,duration=1 (see `hil faults`)")
    ij.add_argument("--out", type=Path, metavar="DIR",
                    help="the run's --out (default: the one run flying under out/)")
    ij.add_argument("--key-file", type=Path, metavar="PATH",
                    help="the run's --key-file (default: its session.key)")
    ij.add_argument("--timeout", type=positive, default=10.0, metavar="S",
                    help="seconds to wait for the rig's answer (default 10)")

    add_bus(sub, Parser)

    fl = sub.add_parser("faults", help="every fault kind: fields, units, defaults, an example")
    fl.add_argument("kinds", nargs="*", metavar="KIND", help="only these kinds")

    rp = sub.add_parser("replay", help="replay a recorded lockstep run into fcc; compare every "
                        "firmware frame (exit 0 identical, 1 the first difference)")
    rp.add_argument("dir", type=Path, metavar="RUN_DIR")
    rp.add_argument("--out", type=Path, metavar="DIR", help="where fcc.log goes (default RUN_DIR/replay)")
    rp.add_argument("--iface", default="vcan0", help="CAN interface (default vcan0)")
    rp.add_argument("--timeout", type=positive, default=2.0, metavar="S",
                    help="seconds to wait for fcc's answer to a step (default 2)")
    rp.add_argument("--fcc-args", default="", metavar="ARGS",
                    help="fcc options added to the recorded ones, e.g. \"--ridge 0.01\"")
    add_paths(rp)

    d = sub.add_parser("demo", help="both aircraft with the default scenarios, then paper 2's (LQG) Figs. 4-6 "
                       "(deterministic responses) and Fig. 3 (covariance analysis + HIL points)")
    add_common(d, "out/demo")

    v = sub.add_parser("verify", help="requirement-based test suites against the device under test: "
                       "a verdict per case and requirement, JUnit XML, an HTML report",
                       epilog="exit status: 0 every case passed, or was inconclusive (a realtime timing "
                       "requirement failed on a platform that did not keep its schedule: INCONCLUSIVE and a "
                       "warning line, JUnit <skipped>); 1 a case failed, or the CAN interface "
                       "cannot be opened (nothing flew); 2 bad command line or suite, or --coverage without its "
                       "tools or build (nothing flew); 6 a case could not run (error: no device, time-out, crash; "
                       "the report is not published), or --coverage could not measure it")
    v.add_argument("suites", nargs="*", metavar="SUITE",
                   help="a shipped suite's name (hil verify --list) or a suite TOML file")
    v.add_argument("--case", action="append", default=[], metavar="ID", help="only these cases (repeatable)")
    v.add_argument("--junit", type=Path, metavar="FILE", help="write JUnit XML here")
    v.add_argument("--report", type=Path, metavar="DIR",
                   help="the report's directory (index.html, one run directory per case; default: --out)")
    v.add_argument("--list", action="store_true", help="list the shipped suites and exit")
    v.add_argument("--fields", action="store_true", help="list the result fields expectations may name and exit")
    v.add_argument("--coverage", action="store_true", help="fcc's coverage build (scripts/test coverage, then "
                   "--build-dir build-cov): the lines each requirement reaches, the two work lists, in the report")
    add_common(v, "out/verify")
    add_parallel(v)   # the flights of cases of `flights = N` (hil.verify.flights)
    add_rig(v)
    add_rig_commands(sub)
    for command in _commands(p):
        add_logging(command, argparse.SUPPRESS)
    return p
