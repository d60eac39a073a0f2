"""What every part of the CLI shares: the program's name, the usage error (one line, exit 2)."""
from __future__ import annotations

PROG = "hil"
EXIT_USAGE = 2


class UsageError(Exception):
    """Bad command line or scenario: one line, exit 2."""
