"""hil's one exception hierarchy: every error hil reports to its user is a HilError, and the
class says the exit status of `hil` (exit_status), so that the command line maps an error to
its status by the class alone (hil.cli's _fail) and anything else that reaches it is a bug
(EXIT_SOFTWARE, the traceback in a log).  The statuses' meanings are hil.cli.usage's one
table (EXIT_STATUS); the numbers live here, the lowest room, so that every room can raise.

The classes keep the built-in base they had (ValueError, RuntimeError, ...) as a second base:
who catches a ValueError still catches a scenario error.
"""
from __future__ import annotations

from typing import ClassVar

#: the run failed (the default of every HilError)
EXIT_FAILED = 1
#: bad command line, scenario or input file: nothing is started
EXIT_USAGE = 2
#: fcc did not answer a lockstep step in time (hil.rig.errors.FccTimeout)
EXIT_TIMEOUT = 3
#: fcc died during the run (hil.rig.errors.FccDied)
EXIT_DIED = 4
#: --rig: the warm rig is flying another client's command (hil.parallel.warm.RigBusy)
EXIT_RIG_BUSY = 8
#: `hil inject`: the request refused (hil.rig.inject.InjectRefused)
EXIT_REFUSED = 9
#: a bug in hil: an exception that is no HilError (sysexits.h's EX_SOFTWARE)
EXIT_SOFTWARE = 70


class HilError(Exception):
    """An error hil reports in one line (its message) with the exit status of its class."""

    exit_status: ClassVar[int] = EXIT_FAILED


class InputError(HilError):
    """An input hil will not use (command line, scenario, file): exit 2, nothing started."""

    exit_status: ClassVar[int] = EXIT_USAGE
