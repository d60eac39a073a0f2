"""What every part of the CLI shares: the program's name, the usage error (one line, exit 2)."""
from __future__ import annotations

PROG = "hil"
EXIT_USAGE = 2
#: hil verify: a case could not run (no device, a time-out, a crash): never a pass
EXIT_VERIFY_ERROR = 6
#: a realtime run whose time synchronisation was attacked, refused or lost (summary.json `sync`)
EXIT_SYNC = 7


class UsageError(Exception):
    """Bad command line or scenario: one line, exit 2."""
