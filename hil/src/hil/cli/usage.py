"""What every part of the CLI shares: the program's name, the usage error (one line, exit 2),
and the exit statuses: one table (EXIT_STATUS) that `hil --help` prints and the documentation's
command-line reference renders (scripts/lib/cli_reference.py), so the two cannot drift."""
from __future__ import annotations

import textwrap

# the statuses an error's class carries: hil.util.errors (the lowest room, so every room can raise)
from hil.util.errors import (EXIT_DIED, EXIT_FAILED, EXIT_REFUSED, EXIT_RIG_BUSY, EXIT_SOFTWARE,
                             EXIT_TIMEOUT, EXIT_USAGE, InputError)

PROG = "hil"

#: hil verify: a case could not run (no device, a time-out, a crash): never a pass
EXIT_VERIFY_ERROR = 6
#: a realtime run whose time synchronisation was attacked, refused or lost (summary.json `sync`)
EXIT_SYNC = 7
#: interrupted: 128 + the signal's number
EXIT_SIGINT, EXIT_SIGTERM, EXIT_SIGHUP = 130, 143, 129

#: (status, meaning) of every exit status of `hil`, in the order they are listed
EXIT_STATUS: tuple[tuple[int, str], ...] = (
    (0, "done; `hil verify`: every case passed or was inconclusive (a realtime timing requirement "
        "failed on a platform that did not keep its schedule: INCONCLUSIVE with its figures and a "
        "warning line, never counted as a pass)"),
    (EXIT_FAILED, "the run failed: interface missing or down, fcc failed to start (or refused its "
                  "options), another fcc already on the bus or a second fcc heard during the run, "
                  "fcc reported failed steps, the recorder missed frames, answered steps missing "
                  "from `bus.log`; `hil verify`: a case failed; `hil replay`: the first difference; "
                  "`hil bus wcrt`: a frame misses its deadline or has no bounded response time; "
                  "`hil run --bus wire`: a frame's response time above its bound, or the bus lost "
                  "frames; "
                  "`hil inject`: the rig did not answer within `--timeout`"),
    (EXIT_USAGE, "bad command line or scenario (not UTF-8, out-of-range field, a fault on a frame "
                 "the simulator does not send for that aircraft, nested too deeply), a flight too "
                 "long for the memory available, a foreign `--out`, a user's file `--force` would "
                 "overwrite, a file argument that is not a regular file (a FIFO, a device, a "
                 "directory) or too large, a DBC hil cannot use (`--dbc`, `$FCC_HIL_DBC`: empty, "
                 "binary, truncated, not parsed, a message or signal of hil's missing, two messages "
                 "on one identifier), `--workers` outside 1..64, `--workers` with "
                 "`--log-format asc|blf` or inside the vcan launcher's guest (`hil-vcan`; in a clone "
                 "`scripts/with-vcan`), a firmware program "
                 "or an extra of the package missing; `hil replay` of a run whose bus key is not "
                 "kept, whose bus log or `run_info.json` is malformed, or with no step to replay; "
                 "`--rig` with no warm rig up, or one up for another `--target`; `--bus wire` other than "
                 "realtime on the host target over SocketCAN: nothing is "
                 "started"),
    (EXIT_TIMEOUT, "fcc did not answer a lockstep step within `--timeout` (after resending the "
                   "tick at `--timeout`/2)"),
    (EXIT_DIED, "fcc died during the run, or the serial line to the Cortex-M4F image lost "
                "frames (`--target qemu-m4f`)"),
    (EXIT_VERIFY_ERROR, "`hil verify`: a case could not run (no device, a time-out, a crash): "
                        "never a pass; its report is kept in OUT.failed-TIME, not published"),
    (EXIT_SYNC, "`hil run`: the flight finished, every figure from authenticated frames, but "
                "the bus was attacked: realtime, its time synchronisation was attacked (forged or "
                "replayed `SYNC`/`FOLLOW_UP`/`TSYNC_AUTH` refused by fcc), refused (the "
                "authenticated master implausible against fcc's clock) or lost (a loss fcc "
                "recovered from with nothing forged, replayed or refused and the data age in "
                "bounds: a warning line, not 7); or frames forged "
                "on fcc's outputs were refused, fcc counted frames on its own identifiers, or "
                "fcc's rows disagree with sid_replay's beyond the bus's resolution; one line names "
                "it, summary.json's `sync` or `bus_trust` has the counters"),
    (EXIT_RIG_BUSY, "`--rig`: the warm rig is flying another client's command: nothing is started "
                    "(one command at a time; try again when it is done)"),
    (EXIT_REFUSED, "`hil inject`: refused, nothing injected: no realtime run flies into `--out` "
                   "(none, or a lockstep one), no key or not the run's key, or the rig refused "
                   "the request (replayed, a CDRW fault, after the end of the flight)"),
    (EXIT_SOFTWARE, "an internal error of hil (a bug): one line `hil: internal error: ...` "
                    "naming the file its traceback was written to (`$XDG_CACHE_HOME/hil/"
                    "crash-TIME.log`); please report it with that file"),
    (EXIT_SIGINT, "interrupted (Ctrl-C, SIGINT): fcc and the recorder stopped, the session key "
                  "file removed, partial results kept marked `FAILED`; while hil is still starting "
                  "(before it has started anything), the one line at once"),
    (EXIT_SIGTERM, "SIGTERM: as SIGINT"),
    (EXIT_SIGHUP, "SIGHUP: as SIGINT"),
)


def exit_status_help(width: int = 79) -> str:
    """The exit statuses as `hil --help` ends with them."""
    lines = textwrap.wrap("exit status (every failure is one line on stderr; a failed run's files "
                          "are kept in OUT.failed-TIME):", width)
    for status, meaning in EXIT_STATUS:
        lines += textwrap.wrap(meaning.replace("`", ""), width, initial_indent=f"  {status:<5}",
                               subsequent_indent=" " * 7)
    return "\n".join(lines)


class UsageError(InputError):
    """Bad command line or scenario: one line, exit 2."""
