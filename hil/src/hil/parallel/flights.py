"""Flights inside one rig: a chunk of a campaign's CDRW flights, or a sweep's missile flight,
in a session of its own (candump, fcc, the simulator's socket; fcc reset between the
flights of a chunk as in the sequential campaign), so a result depends on nothing but its
inputs: not on which worker flies it, nor on what that worker flew before."""
from __future__ import annotations

import dataclasses
import functools
import shutil
import time
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

from hil.bus import load as load_spec
from hil.results.buslog import BusAuth, iter_flights
from hil.results.flight import CdrwResult, cdrw_record, cdrw_result, missile_result
from hil.results.report import firmware_summary
from hil.rig.config import RigConfig
from hil.rig.errors import RigError
from hil.rig.flight import fcc_args, fly, require_log
from hil.rig.session import RigSession
from hil.runs.campaign import CampaignFlight, evaluate_flights
from hil.scenario.file import Scenario, with_fault_start
from hil.sim.drivers import CdrwDriver, MissileDriver
from hil.util.progress import bar as progress_bar


@dataclasses.dataclass
class FlightDone:
    """What a rig sends back for one flight (a sweep point)."""

    flight: Any                  # MissileResult
    firmware: dict[str, Any]     # fcc's counters of this flight (flights_counters)


@dataclasses.dataclass
class SessionDone:
    """A chunk of campaign flights flown in one session: each flight (index, fault start,
    and what is known of it: the simulator's CdrwRecord from the rig, its CampaignFlight
    after campaign_flights), fcc's counters of these flights (flights_counters: the
    session's end left out), and, from the rig, the session's directory with its bus.log and
    the key its frames verify under (fcc's outputs are read from it on the worker)."""

    flights: list[tuple[int, float, Any]]
    firmware: dict[str, Any]
    session_s: float = 0.0       # the session's own start and end, paid once per chunk
    run_dir: Path | None = None  # the rig's session directory (bus.log), until evaluated
    auth: BusAuth | None = None


def worker_config(cfg: RigConfig) -> RigConfig:
    """A worker's session: the run's configuration with a random bus key of its own (the
    workers are never handed --key-file)."""
    return dataclasses.replace(cfg, key_file=None)


def fly_campaign_flights(scenario: Scenario, flights: Sequence[tuple[int, float]],
                         cfg: RigConfig) -> SessionDone:
    """Campaign flights (index, fault start) one after the other in one fresh session in
    cfg.out_dir, fcc reset between them as in the sequential campaign (so each result
    depends only on its inputs).  Returns the simulator's records and the session's
    directory: fcc's outputs are read from its bus.log off the rig (campaign_flights, on the
    worker: the guest's one CPU is the rig's scarcest, and reading a log there costs about
    twice the host's); the directory stays until then (and when the session fails)."""
    out = Path(cfg.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    records = []
    t0 = time.perf_counter()
    with RigSession(out, fcc_args([scenario], cfg), worker_config(cfg)) as rig:
        flying = time.perf_counter()
        runner = None
        for _, fault_start in flights:
            d = CdrwDriver(with_fault_start(scenario, fault_start), rig.codec, cfg.mode == "realtime")
            with progress_bar(d.n_steps, False, "") as bar:
                runner = fly(rig, [d], cfg, bar, runner)
            records.append(cdrw_record(d))
        flying = time.perf_counter() - flying
        rig.shutdown()
    session_s = time.perf_counter() - t0 - flying
    require_log(rig)
    return SessionDone([(i, t, rec) for (i, t), rec in zip(flights, records)],
                       flights_counters(firmware_summary(rig.status, rig.security.counters())),
                       session_s, out, BusAuth(rig.security.key, rig.security.trip))


def campaign_flights(done: SessionDone, scenario: Scenario, cfg: RigConfig) -> SessionDone:
    """A session's flights as Table 5 needs them (CampaignFlight): fcc's outputs read from
    the session's bus.log (one pass, a flight at a time) and joined with the simulator's
    records, then the symmetric tables (one `sid_replay --all-rows` per flight, running
    while the next flight is read: hil.runs.campaign.evaluate_flights); on the worker, where
    starting a process is cheap, not inside the rig's guest.  The session's directory is
    removed once its flights are evaluated."""
    assert done.run_dir is not None
    log = done.run_dir / "bus.log"
    spec = load_spec()
    args = fcc_args([scenario], cfg)
    recorded = 0

    def results() -> Iterator[tuple[int, float, CdrwResult]]:
        nonlocal recorded
        for fl in iter_flights(log, done.auth):
            if recorded < len(done.flights):
                i, t, rec = done.flights[recorded]
                yield i, t, cdrw_result(spec, rec, fl)
            recorded += 1

    evaluated = [(fl.index, fl.fault_start, fl) for fl in evaluate_flights(results(), args)]
    if recorded != len(done.flights):
        raise RigError(f"{log}: {recorded} flights recorded, expected {len(done.flights)}")
    shutil.rmtree(done.run_dir, ignore_errors=True)
    return SessionDone(evaluated, done.firmware, done.session_s)


def fly_sweep_point(scenario: Scenario, cfg: RigConfig) -> FlightDone:
    """One closed-loop missile flight of a sweep (the scenario carries its T and word length),
    fcc designing for it on the flight's SIM_CONTROL reset as in the sequential sweep."""
    out = Path(cfg.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    lqg = scenario.lqg
    assert lqg is not None
    with RigSession(out, fcc_args([scenario], cfg), worker_config(cfg)) as rig:
        d = MissileDriver(scenario, rig.codec, cfg.mode == "realtime")
        with progress_bar(0, False, "") as bar:
            fly(rig, [d], cfg, bar, None, lqg.period, lqg.bits)
        rig.shutdown()
    done = FlightDone(missile_result(d, reference=cfg.mode == "lockstep"),
                      flights_counters(firmware_summary(rig.status, rig.security.counters())))
    shutil.rmtree(out, ignore_errors=True)
    return done


#: what fcc counts once per session after its flights: the shutdown's GROUND and SHUTDOWN
#: (SIM_CONTROL frames, FCC_E2E_COUNTS.ok; hil.rig.session.RigSession.shutdown).  Nothing
#: before the first flight is counted, so a session's counters less these are its flights'.
SESSION_END = {"e2e": {"ok": 2}}


def add_counters(a: dict[str, Any], b: dict[str, Any], sign: int = 1) -> dict[str, Any]:
    """fcc's counters a + sign * b (nested dicts of whole numbers; b may hold fewer keys)."""
    return {k: add_counters(v, b.get(k, {}), sign) if isinstance(v, dict) else v + sign * b.get(k, 0)
            for k, v in a.items()}


def flights_counters(session: dict[str, Any]) -> dict[str, Any]:
    """A session's counters (firmware_summary) less its end: its flights' own share."""
    return add_counters(session, SESSION_END, -1)


def one_session_counters(shares: Sequence[dict[str, Any]]) -> dict[str, Any]:
    """The flights' shares (flights_counters, in flight order) as one session flying them all
    would count them, as the sequential command does: the same for any chunking of the
    flights into sessions (whole numbers: the order of the sums does not matter)."""
    total = functools.reduce(add_counters, shares)
    return add_counters(total, SESSION_END)


__all__ = ["CampaignFlight", "FlightDone", "SessionDone", "add_counters", "campaign_flights",
           "flights_counters", "fly_campaign_flights", "fly_sweep_point", "one_session_counters"]
