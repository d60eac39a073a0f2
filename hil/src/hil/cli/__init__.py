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
    hil study cdrw [--runs N] [--noise-seeds N] [--json] [--figure PNG]
                                   (Table 5 with its controls, offline through sid_replay)
    hil study bus [--bitrates LIST] [--loads LIST] [--periods LIST] [--json] [--figure PNG]
                                   (the missile's RMS q over bit rate and load, lockstep on the
                                   wire-time bus; Table 4 there)
    hil demo [--out out/demo]        (both aircraft; Figs. 4-6 responses; Fig. 3 with HIL points)

Needs a CAN interface (vcan0; `hil-vcan hil ...` or, in the clone, `scripts/with-vcan hil ...`
provides one) and the firmware's programs, found as hil.io.paths says (--fcc, --build-dir,
$FCC_HIL_FCC, $FCC_BUILD_DIR, the source tree's build/, $PATH) and checked before anything
flies; --target qemu-m4f flies the Cortex-M4F image under QEMU instead, --target external
whatever answers on the bus.  Exit status: hil.cli.usage.EXIT_STATUS (printed by `hil --help`).
Failures are one line on stderr; a failed
run's bus log and partial results are kept in OUT.failed-TIME (hil.io.rundir).

The package: usage (the usage error), parser (every subcommand's arguments), common and many
(what the flying commands share), needs (the paths and programs a command needs, checked
before it starts), one module per subcommand with its run(args).  main() parses, then imports
only needs and the chosen subcommand's module -- neither for a command flown on a warm rig
(--rig: hil.cli.onrig), which the rig checks and runs.

Room 15, the top: may import every room; nothing imports it (the entry points are hil.cli:main
and hil.cli:entry).
"""
from __future__ import annotations

# first of all: a signal while the rest is imported ends hil at once, in one line (hil.util.startup)
from hil.util import startup
import argparse
import gc
import importlib
import os
import signal
import sys
import threading
from collections.abc import Sequence
from typing import NoReturn

from hil.cli import onrig
from hil.cli.parser import build
from hil.cli.usage import EXIT_FAILED, EXIT_SIGINT, EXIT_SOFTWARE, EXIT_USAGE, PROG, UsageError
from hil.io import crashlog, paths
from hil.util import log
from hil.util.errors import HilError

startup.started()  # from here on main()'s handlers, and Python's KeyboardInterrupt for SIGINT


def dispatch(args: argparse.Namespace) -> int:
    """The chosen subcommand, checked then run here: what it needs found (hil.cli.needs: the
    DBC, the firmware's programs), then its module in hil.cli (named as the subcommand); each
    imported now, so that a command loads only what it runs -- and one flown on a warm rig
    (--rig), neither: the rig's command checks and runs it; its run(args) gives the exit
    status."""
    importlib.import_module("hil.cli.needs").apply(args)
    return importlib.import_module(f"hil.cli.{args.command}").run(args)


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


class Terminated(KeyboardInterrupt):
    """SIGTERM or SIGHUP: handled as SIGINT is (the session stops fcc and the recorder and
    removes its key file, a run keeps its partial results marked FAILED), exit 128 + signal."""

    def __init__(self, signum: int) -> None:
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


def _terminate(signum: int, _frame: object) -> None:
    raise Terminated(signum)


def main(argv: Sequence[str] | None = None, parsed: argparse.Namespace | None = None) -> int:
    """`hil` with `argv` (default sys.argv), or the command line `parsed` already (a warm
    rig's command: hil.cli.rig)."""
    old: dict[signal.Signals, object] = {}
    if threading.current_thread() is threading.main_thread():
        for sig in (signal.SIGTERM, signal.SIGHUP):
            if signal.getsignal(sig) != signal.SIG_IGN:  # `nohup hil ...` goes on after a hangup
                old[sig] = signal.signal(sig, _terminate)
    build_env = os.environ.get(paths.BUILD_ENV)
    try:
        return _main(argv, parsed)
    finally:
        for sig, handler in old.items():
            signal.signal(sig, handler)  # type: ignore[arg-type]
        if build_env is None:  # --build-dir holds for this call only (tests call main() often)
            os.environ.pop(paths.BUILD_ENV, None)
        else:
            os.environ[paths.BUILD_ENV] = build_env


def _main(argv: Sequence[str] | None, parsed: argparse.Namespace | None) -> int:
    try:
        args = parsed or build().parse_args(_join_fcc_args(sys.argv[1:] if argv is None else argv))
        log.configure(args.verbose, args.debug)
        if onrig.wanted(args):   # --rig: the command runs on the warm rig (hil.cli.onrig)
            return onrig.on_rig(main, args)
        return dispatch(args)
    except KeyboardInterrupt as e:
        return _stopped(e)
    except BrokenPipeError:
        # the results are already in place when the tables are printed: not a failed run
        _quiet_stdout()
        return 0
    except UsageError as e:
        print(f"{PROG}: {e}", file=sys.stderr)
        return EXIT_USAGE
    except Exception as e:  # noqa: BLE001 - every failure is one line for the user
        return _fail(e)


def _stopped(e: KeyboardInterrupt) -> int:
    """SIGINT (Python's KeyboardInterrupt), SIGTERM or SIGHUP (Terminated): one line, 128 + the
    signal's number."""
    if isinstance(e, Terminated):
        print(f"{PROG}: terminated by {signal.Signals(e.signum).name}{_notes(e)}", file=sys.stderr)
        return 128 + e.signum
    print(f"{PROG}: interrupted{_notes(e)}", file=sys.stderr)
    return EXIT_SIGINT


def _notes(e: BaseException) -> str:
    """Where a failed run's partial results are (hil.io.rundir adds it as a note), to end
    the one line with."""
    notes = getattr(e, "__notes__", ())
    return f" ({'; '.join(notes)})" if notes else ""


def _os_message(e: OSError) -> str:
    """[Errno 28] No space left on device: 'x' -> "no space left on device: x" (one clear line)."""
    what = (e.strerror or type(e).__name__)
    what = what[0].lower() + what[1:]
    return f"{what}: {e.filename}" if e.filename else what


#: the environment's errors said as "what: file" (a subclass of a program's own says its own line)
_OS_ERRORS = (OSError, FileNotFoundError, PermissionError, IsADirectoryError, NotADirectoryError,
              FileExistsError)


def _fail(e: Exception) -> int:
    """One line and the exit status of the error's class (hil.util.errors); the environment's
    errors (a file, a socket, the memory) exit 1; anything else is a bug: exit 70, its traceback in a log."""
    msg = str(e).splitlines()[0] if str(e) else type(e).__name__
    if isinstance(e, HilError):
        code = e.exit_status
    elif isinstance(e, OSError):  # the environment (a file, a socket, the disk): the run failed
        msg = _os_message(e) if type(e) in _OS_ERRORS and e.errno is not None else msg
        code = EXIT_FAILED
    elif isinstance(e, (MemoryError, RecursionError)):  # what no reader of an input turned into its own
        msg = "out of memory (MemoryError)" if isinstance(e, MemoryError) else "nested too deeply (RecursionError)"
        code = EXIT_FAILED
    else:
        return _internal_error(e)
    print(f"{PROG}: {msg}{_notes(e)}", file=sys.stderr)
    return code


def _internal_error(e: BaseException) -> int:
    """A bug: one line naming the exception and the file its traceback is in, exit 70."""
    where = crashlog.write(e)
    said = f"{type(e).__name__}: {str(e).splitlines()[0]}" if str(e) else type(e).__name__
    kept = f"traceback in {where}" if where is not None else "no traceback file could be written"
    print(f"{PROG}: internal error: {said} ({kept}){_notes(e)}", file=sys.stderr)
    return EXIT_SOFTWARE


def entry() -> NoReturn:
    """The `hil` program (tests call main() instead)."""
    try:
        code = main()
    except KeyboardInterrupt as e:  # before main's try or after it (its handlers' moments)
        code = _stopped(e)
    # The interpreter's exit collects the objects still alive, all of which (the modules,
    # numpy's among them) live to the end: frozen, the collections skip them (0.03-0.05 s of
    # a `hil run` in the UML guest, measured)
    gc.freeze()
    sys.exit(code)
