"""`hil run`: one flight of one aircraft, or both interleaved in one fcc (the demo's first
part), evaluated from its bus log and its drivers (hil.runs.evaluate).

The simulator and the evaluation (numpy: 0.2 s of a start in the UML guest) are imported
while the session listens to the bus for another fcc, a wait otherwise: this module, and
what it imports at load, do not need them.
"""
from __future__ import annotations

import time
from collections.abc import Sequence
from typing import TYPE_CHECKING, Protocol

from hil.results.busstats import bus_failure
from hil.rig.config import RigConfig
from hil.rig.errors import RigError
from hil.rig.flight import Flown, fly, lqg_request, make_drivers, open_session, require_log, run_info
from hil.rig.session import RigSession
from hil.rig.simbus import check_bus_load
from hil.runs.budget import check_memory
from hil.scenario.file import Scenario
from hil.util.progress import bar as progress_bar

if TYPE_CHECKING:
    from hil.runs.outcome import Outcome
    from hil.sim.drivers import AppDriver


class FlightWitness(Protocol):
    """Another node that takes part in a flight (hil.verify's attacker): the flight starts
    once it is ready, and it stops before the rig shuts fcc down (so that the recorder closes
    the log on the rig's own end marker)."""

    def wait_ready(self) -> None: ...

    def stop_now(self) -> None: ...


def run_flight(scenarios: Sequence[Scenario], cfg: RigConfig, command: str = "run",
               witness: FlightWitness | None = None) -> Outcome:
    """One flight of one or both aircraft (interleaved in one fcc when both), evaluated."""
    out = cfg.out_dir
    if len({sc.aircraft for sc in scenarios}) != len(scenarios):
        raise ValueError("one scenario per aircraft")
    check_memory(scenarios)
    check_bus_load(scenarios, cfg.mode, cfg.bus)
    t0 = time.perf_counter()
    with open_session(out, scenarios, cfg, lambda rig: prepare(scenarios, rig, cfg)) as rig:
        drivers: list[AppDriver] = rig.prepared  # type: ignore[assignment]
        if witness is not None:
            witness.wait_ready()
        try:
            with progress_bar(sum(d.n_steps for d in drivers), cfg.progress, f"hil {command}") as bar:
                runner = fly(rig, drivers, cfg, bar, None, *lqg_request(rig, scenarios))
        finally:
            if witness is not None:
                witness.stop_now()
        rig.shutdown()
    require_log(rig)
    if rig.bus_error:
        raise RigError(rig.bus_error)
    from hil.results.buslog import BusAuth  # (both imported by prepare)
    from hil.runs.evaluate import evaluate_flight
    flown = Flown(drivers, rig.status, rig.security.counters(),
                  run_info(rig, cfg, runner, time.perf_counter() - t0), rig.transmitter_stats,
                  BusAuth(rig.security.key, rig.security.trip), rig.bus_stats)
    outcome = evaluate_flight(scenarios, cfg, command, flown)
    if "bus" in outcome.summary:  # measured above its bound: the model or the analysis is wrong
        why = bus_failure(outcome.summary["bus"])
        if why:
            raise RigError(f"{why}; the results are in the failed run's summary.json")
    return outcome


def prepare(scenarios: Sequence[Scenario], rig: RigSession, cfg: RigConfig) -> list[AppDriver]:
    """The work for the time the session listens to the bus before fcc starts: the drivers
    (their precomputation) and the import of the evaluation (numpy among it)."""
    import hil.runs.evaluate  # noqa: F401
    return make_drivers(scenarios, rig.codec, cfg)
