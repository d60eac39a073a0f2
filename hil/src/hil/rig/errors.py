"""The rig's errors: one line for the user each, with the exit status of `hil` (1 the run
failed, 3 fcc did not answer a lockstep step in time, 4 fcc died during the run).  Light to
import: the CLI maps every failure to its exit status with them.
"""
from __future__ import annotations


class RigError(RuntimeError):
    """A run cannot go on (one line for the user; the bus log is kept)."""

    exit_code = 1


class FccTimeout(RigError):
    exit_code = 3


class FccDied(RigError):
    exit_code = 4
