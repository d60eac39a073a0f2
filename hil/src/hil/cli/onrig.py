"""`--rig`: a command (`hil run|verify|campaign`) flown on the warm rig `hil rig up` started
(hil.cli.rig): parsed here, checked and run there (hil.parallel.warm).  Imported by every `hil`
command's start (hil.cli.main asks it whether to fly on the rig): light.
"""
from __future__ import annotations

import argparse
import os
from collections.abc import Callable

from hil.cli.usage import UsageError
from hil.parallel import forked
from hil.parallel.warm import fly, read_state, state_dir


def wanted(args: argparse.Namespace) -> bool:
    """--rig given, and not already inside the rig (where the command itself runs)."""
    return bool(getattr(args, "rig", False)) and not os.environ.get(forked.IN_RIG)


def on_rig(main: Callable[..., int], args: argparse.Namespace) -> int:
    """main(parsed=args) run by the warm rig (the command line parsed here, not again
    there); its exit status."""
    if getattr(args, "workers", None) or getattr(args, "scheduler", None):
        raise UsageError("--rig flies in the warm rig's one guest: not with --workers/--scheduler "
                         "(each of their workers keeps a rig of its own)")
    state = read_state(state_dir())
    if state is not None and args.iface == "vcan0":   # the default bus: the rig's own (a vcanK of
        args.iface = state.iface                      # its own on a kernel with vcan)
    return fly(main, (None, args), args.target)
