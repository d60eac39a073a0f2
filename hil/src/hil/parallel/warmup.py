"""A warm rig's loop made ready for its commands, once, before the first: what every command
would otherwise do again at its start, done in the loop, whose forked children inherit it
(hil.parallel.forked).

* the commands' modules imported (the list is the CLI's: hil.cli.rig.PRELOAD);
* the CDRW's fault-free flight of the default scenario decoded from the flight cache
  (hil.sim.cdrw_cache keeps the last entry used in memory: a child's `hil run cdrw` skips
  decoding it, and still reads and compares the entry's bytes, so a changed entry is never
  trusted);
* the first command's child forked (hil.parallel.forked.refill: and each next one's after an
  answer), with its session's socket on the rig's bus opened by the loop as soon as the
  previous command's fcc has stopped (hil.rig.session.listening_ahead, on_device_stopped): the
  listen for another fcc before fcc starts (0.25 s) runs while the previous command evaluates
  and the rig waits for the next one; and whose memory is made its
  own while it waits (hil.parallel.prefault: the copy-on-write faults of a fork are slow in
  the guest).
"""
from __future__ import annotations

import importlib
import sys
from collections.abc import Sequence
from functools import partial

from hil.bus import load as load_spec
from hil.parallel import forked
from hil.parallel.prefault import populate
from hil.rig.session import listening_ahead, on_device_stopped
from hil.scenario.file import load_default_scenario
from hil.sim.cdrw_cache import open_loop
from hil.sim.cdrw_flight import CdrwSimulation


def warm_up(modules: Sequence[str], iface: str) -> int:
    """Import `modules`, decode the default CDRW flight, fork the first command's child (each
    listening on the rig's bus `iface`): how many modules are loaded."""
    for name in modules:
        importlib.import_module(name)
    scenario = load_default_scenario("cdrw", {m.name for m in load_spec().messages})
    open_loop(scenario, CdrwSimulation(scenario).n_samples)
    on_device_stopped(forked.device_stopped)
    forked.refill(partial(listening_ahead, iface), populate)
    return len(sys.modules)
