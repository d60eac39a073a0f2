"""The rig's errors: one line for the user each, with the exit status of `hil` on the class
(hil.util.errors: 1 the run failed, 3 fcc did not answer a lockstep step in time, 4 fcc died
during the run).  Light to import: the CLI maps every failure to its exit status with them.
"""
from __future__ import annotations

from hil.util.errors import EXIT_DIED, EXIT_FAILED, EXIT_TIMEOUT, HilError


class RigError(HilError, RuntimeError):
    """A run cannot go on (one line for the user; the bus log is kept)."""

    exit_status = EXIT_FAILED


class FccTimeout(RigError):
    exit_status = EXIT_TIMEOUT


class FccDied(RigError):
    exit_status = EXIT_DIED
