"""Flights inside one rig: a chunk of a campaign's CDRW flights, or a sweep's missile flight,
in a session of its own (candump, fcc, the simulator's socket; fcc reset between the
flights of a chunk as in the sequential campaign), so a result depends on nothing but its
inputs: not on which worker flies it, nor on what that worker flew before.

The rig leaves each finished flight's record in the chunk's directory as it finishes
(appended to records.pkl) and hands back only the session's summary (SessionDone); its worker
reads the records and the bus log there, evaluates the flights and hands them to the
coordinator in bulk (ChunkDone: hil.parallel.bulk).  A chunk whose rig fails part-way (fcc
died or hung, the guest died) keeps the flights it finished: salvage_campaign_flights
evaluates those whose frames are whole in the session's bus log; the engine flies the rest
again (hil.parallel.engine)."""
from __future__ import annotations

import dataclasses
import functools
import io
import os
import pickle
import shutil
import signal
import time
from collections.abc import Iterable, Iterator, Sequence
from pathlib import Path
from typing import Any

from hil.bus import load as load_spec
from hil.bus.secoc import read_key_file
from hil.parallel.bulk import FlightBatch, pack_flights
from hil.parallel.files import exit_cause, last_lines, write_atomic
from hil.parallel.guest import RigFailed, rig_root
from hil.results.buslog import BusAuth, FlightFrames, iter_flights
from hil.results.flight import CdrwRecord, CdrwResult, cdrw_record, cdrw_result, missile_result
from hil.results.report import firmware_summary
from hil.rig.config import RigConfig
from hil.rig.errors import RigError
from hil.rig.flight import fcc_args, fly, on_target, require_log
from hil.rig.session import KEPT_KEY, RigSession
from hil.runs.campaign import CampaignFlight, evaluate_flights
from hil.runs.run import run_flight
from hil.scenario.file import Scenario, with_fault_start
from hil.sim.drivers import CdrwDriver, MissileDriver
from hil.util.progress import bar as progress_bar

#: a test's deterministic rig failure (tests/python/parallel): "fcc N" kills fcc, "rig N" the
#: rig's own server process (its guest then ends; once its recorder has written the flights
#: before), before the last step of campaign flight N; once per $HIL_RIG_DIR (the first rig
#: to reach flight N claims the marker file there)
FAILURE_HOOK = "HIL_TEST_RIG_FAILURE"


@dataclasses.dataclass
class FlightDone:
    """What a rig sends back for one flight (a sweep point)."""

    flight: Any                  # MissileResult
    firmware: dict[str, Any]     # fcc's counters of this flight (flights_counters)


@dataclasses.dataclass
class SessionDone:
    """A chunk of campaign flights flown in one session, as the rig hands it to its worker:
    the flights (index, fault start), fcc's counters of these flights (flights_counters: the
    session's end left out), the session's directory, where the flights' records
    (records.pkl) and the bus log are read on the worker, and the key its frames verify
    under.  (The records stay in the file the rig wrote as it flew: sending them again in
    the answer cost the guest a second pickling and writing of about 80 kB a flight.)"""

    flights: list[tuple[int, float]]
    firmware: dict[str, Any]
    session_s: float             # the session's own start and end, paid once per chunk
    run_dir: Path
    auth: BusAuth


@dataclasses.dataclass
class ChunkDone:
    """A chunk's flights evaluated, as the worker hands them to the coordinator: what Table 5
    reads of each, in bulk (hil.parallel.bulk), and fcc's counters of these flights."""

    batch: FlightBatch
    firmware: dict[str, Any] | None  # None: a failed session's (fcc's last heartbeat is lost)
    session_s: float = 0.0


def worker_config(cfg: RigConfig) -> RigConfig:
    """A worker's session: the run's configuration with a random bus key of its own (the
    workers are never handed --key-file)."""
    return dataclasses.replace(cfg, key_file=None)


#: a session's finished flights' records, appended as they finish: (index, CdrwRecord) pickles
#: (one write each; a file per flight, written and renamed, cost twice as much in the guest)
RECORDS = "records.pkl"


class _FailureHook:
    """The rig's step counter (LockstepRunner's progress): kills fcc or the rig before the last
    step of the flight FAILURE_HOOK names, once (tests only; without the variable it only
    counts).  The rig is killed once its recorder's file holds the flights before (the
    recorder lags the bus; salvage_campaign_flights keeps only what it wrote): one flight in
    the air, as fcc's death always is."""

    def __init__(self, rig: RigSession, out: Path) -> None:
        self.rig, self.out = rig, out
        what, _, at = os.environ.get(FAILURE_HOOK, "").partition(" ")
        self.what, self.at = what, int(at) if at.isdigit() else -1
        self.steps, self.kill_at, self.before = 0, -1, 0

    def arm(self, index: int, n_steps: int, before: int) -> None:
        if index != self.at:
            return
        try:   # one failure per campaign: the first rig there claims it
            os.close(os.open(rig_root() / f"hil-test-failure-{self.at}", os.O_CREAT | os.O_EXCL))
        except FileExistsError:
            return
        self.kill_at, self.before = self.steps + n_steps - 1, before

    def _recorded(self) -> int:
        """How many whole flights the recorder's file holds (as salvage_campaign_flights reads it)."""
        log = _cut_log(self.out)
        if log is None:
            return 0
        flights = iter_flights(log, BusAuth(self.rig.security.key, self.rig.security.trip))
        return sum(1 for _ in _whole_flights(flights, whole=False))

    def update(self, n: int) -> None:
        self.steps += n
        if self.steps != self.kill_at:
            return
        assert self.rig.fcc is not None
        if self.what == "fcc":
            pids = self.rig.fcc.local_pids()
        else:
            deadline = time.monotonic() + 60.0     # a bound, not the condition
            while self._recorded() < self.before and time.monotonic() < deadline:
                time.sleep(0.01)
            pids = (os.getpid(),)
        for pid in pids:
            os.kill(pid, signal.SIGKILL)


def _failed(e: Exception, rig: RigSession | None, out: Path) -> RigFailed:
    """A failed session's exception, with why for the engine: how fcc ended (as it died, or,
    when it hung or the session failed otherwise, as the session's end stopped it) and its
    last lines."""
    fcc = rig.fcc if rig is not None else None
    rc = fcc.poll() if fcc is not None else None
    msg = str(e).splitlines()[0] if str(e) else ""
    return RigFailed(f"{type(e).__name__}: {msg}", {"process": "fcc", **exit_cause(rc),
                                                   "last_lines": last_lines(out / "fcc.log")})


def fly_campaign_flights(scenario: Scenario, flights: Sequence[tuple[int, float]],
                         cfg: RigConfig) -> SessionDone:
    """Campaign flights (index, fault start) one after the other in one fresh session in
    cfg.out_dir, fcc reset between them as in the sequential campaign (so each result
    depends only on its inputs).  Each finished flight's record is left in the session's
    directory as it finishes (records.pkl); the directory stays, and the flights are
    evaluated off the rig from it (campaign_flights, on the worker: the guest's one CPU is
    the rig's scarcest, and reading a log there costs about twice the host's).  When the
    session fails (RigFailed, with its cause), the worker keeps the flights it finished
    (salvage_campaign_flights); a failure after the flights (fcc's shutdown, the log's end)
    keeps none."""
    out = Path(cfg.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    flown = 0
    t0 = time.perf_counter()
    rig = None
    flying = 0.0
    try:
        with RigSession(out, fcc_args([scenario], cfg), worker_config(cfg)) as rig, \
                open(out / RECORDS, "wb", buffering=0) as kept:
            flying = time.perf_counter()
            runner = None
            steps = _FailureHook(rig, out)
            for i, fault_start in flights:
                d = CdrwDriver(with_fault_start(scenario, fault_start), rig.codec, cfg.mode == "realtime")
                steps.arm(i, d.n_steps, flown)
                runner = fly(rig, [d], cfg, steps, runner)
                kept.write(pickle.dumps((i, cdrw_record(d)), protocol=pickle.HIGHEST_PROTOCOL))
                flown += 1
            flying = time.perf_counter() - flying
            rig.shutdown()
        require_log(rig)
    except Exception as e:  # noqa: BLE001 - every failure goes back with its cause
        if flown == len(flights) or rig is None or not rig.log_complete:
            (out / RECORDS).unlink(missing_ok=True)   # failed after the flights, or the log misses frames
        raise _failed(e, rig, out) from None
    session_s = time.perf_counter() - t0 - flying
    return SessionDone(list(flights), flights_counters(firmware_summary(rig.status, rig.security.counters())),
                       session_s, out, BusAuth(rig.security.key, rig.security.trip))


def _whole_flights(flights: Iterable[FlightFrames], whole: bool) -> Iterator[FlightFrames]:
    """A bus log's flights; of a log cut off where its rig died (whole=False), only those a
    later flight's start follows (the last one's frames may end anywhere)."""
    if whole:
        yield from flights
        return
    held = None
    for fl in flights:
        if held is not None:
            yield held
        held = fl


def _evaluate(log: Path | Iterable[Any], auth: BusAuth | None, flown: Sequence[tuple[int, float, CdrwRecord]],
              scenario: Scenario, cfg: RigConfig, whole: bool = True) -> tuple[list[CampaignFlight], int]:
    """fcc's outputs of the flights `flown` read from the session's bus log (one pass, a
    flight at a time) and joined with the simulator's records, then the symmetric tables (one
    `sid_replay --all-rows` per flight, running while the next flight is read:
    hil.runs.campaign.evaluate_flights).  (The CampaignFlights, flights in the log.)"""
    spec = load_spec()
    recorded = 0

    def results() -> Iterator[tuple[int, float, CdrwResult]]:
        nonlocal recorded
        for fl in _whole_flights(iter_flights(log, auth), whole):
            if recorded < len(flown):
                i, t, rec = flown[recorded]
                yield i, t, cdrw_result(spec, rec, fl)
            recorded += 1

    return list(evaluate_flights(results(), fcc_args([scenario], cfg))), recorded


def campaign_flights(done: SessionDone, scenario: Scenario, cfg: RigConfig) -> ChunkDone:
    """A session's flights as Table 5 needs them, read and evaluated (_evaluate) on the
    worker, where starting a process is cheap, not inside the rig's guest, and handed back
    in bulk (hil.parallel.bulk).  The session's directory is removed once its flights are
    evaluated."""
    records = _finished_records(done.run_dir, done.flights)
    if len(records) != len(done.flights):
        raise RigError(f"{done.run_dir / RECORDS}: {len(records)} flights' records, expected {len(done.flights)}")
    log = done.run_dir / "bus.log"
    evaluated, recorded = _evaluate(log, done.auth, records, scenario, cfg)
    if recorded != len(done.flights):
        raise RigError(f"{log}: {recorded} flights recorded, expected {len(done.flights)}")
    shutil.rmtree(done.run_dir, ignore_errors=True)
    return ChunkDone(pack_flights(evaluated), done.firmware, done.session_s)


def _cut_log(out: Path) -> Path | None:
    """The bus log a failed session left: bus.log when the session closed (after its end
    marker: whole), else the recorder's own file cut where its rig died (hil.rig.recorder's
    private directory; written in blocks), up to its last whole line, as bus.cut.log."""
    cut = sorted(out.glob(".canrec-*/canrec.log")) + sorted(out.glob(".candump-*/candump-*.log"))
    if not cut:
        return None
    data = cut[-1].read_bytes()
    path = out / "bus.cut.log"
    write_atomic(path, data[:data.rfind(b"\n") + 1])
    return path


def _finished_records(out: Path, flights: Sequence[tuple[int, float]]) -> list[tuple[int, float, CdrwRecord]]:
    """The records a session left in records.pkl, of `flights` in order, up to the first
    missing or cut off where its rig died (a pickle without its end does not load)."""
    try:
        stream = io.BytesIO((out / RECORDS).read_bytes())
    except OSError:
        return []
    records = []
    for i, t in flights:
        try:
            j, rec = pickle.load(stream)
        except Exception:  # noqa: BLE001 - EOFError, UnpicklingError, ...: the end of what was written
            break
        if j != i:
            break
        records.append((i, t, rec))
    return records


def _reported_failed_step(fcc_log: Path) -> bool:
    """Did fcc report a failed step (its event line, as it happened: a killed fcc writes no
    exit summary)?  fcc's event lines are rate-limited: its log stays small (read up to 16 MiB)."""
    try:
        with open(fcc_log, "rb") as f:
            return b"step error" in f.read(1 << 24)
    except OSError:
        return False


@dataclasses.dataclass
class Salvaged:
    """What a failed session finished: `value` (its kept flights evaluated, a ChunkDone;
    None when none), `kept` flights, of `flown` that it finished (the others were cut off)."""

    value: ChunkDone | None
    kept: int
    flown: int


def salvage_campaign_flights(out: Path, scenario: Scenario, flights: Sequence[tuple[int, float]],
                             cfg: RigConfig) -> Salvaged:
    """The flights a failed session finished, from what it left in its directory `out`: their
    records (records.pkl, in flight order; one cut off where the rig died is not one), and
    fcc's outputs from the session's log under its key (session.key).  A flight is kept when
    its record is there and its frames are whole in the log: every one with a record when the
    session closed (bus.log: fcc died or hung, the recorder stopped after its end marker),
    else all but the log's last (the guest died: its recorder's file ends with the last batch
    it read, and the recorder lags the bus, by more than a flight under load: the flights it
    had not read are flown again too).  None is kept when fcc
    reported a failed step.  fcc's counters of these flights are lost (firmware None): its
    last heartbeat came mid-flight."""
    records = _finished_records(out, flights)
    key = out / KEPT_KEY
    if not records or not key.exists() or _reported_failed_step(out / "fcc.log"):
        return Salvaged(None, 0, len(records))
    whole = (out / "bus.log").exists()
    log = out / "bus.log" if whole else _cut_log(out)
    kept: list[CampaignFlight] = []
    if log is not None:
        try:
            kept, _ = _evaluate(log, BusAuth(read_key_file(key)), records, scenario, cfg, whole)
        finally:
            (out / "bus.cut.log").unlink(missing_ok=True)
    value = ChunkDone(pack_flights(kept), None) if kept else None
    return Salvaged(value, len(kept), len(records))


def fly_sweep_point(scenario: Scenario, cfg: RigConfig) -> FlightDone:
    """One closed-loop missile flight of a sweep (the scenario carries its T and word length),
    fcc designing for it on the flight's SIM_CONTROL reset as in the sequential sweep."""
    out = Path(cfg.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    lqg = scenario.lqg
    assert lqg is not None
    rig = None
    try:
        with RigSession(out, fcc_args([scenario], cfg), worker_config(cfg)) as rig:
            d = MissileDriver(on_target(scenario, cfg), rig.codec, cfg.mode == "realtime")
            with progress_bar(0, False, "") as bar:
                fly(rig, [d], cfg, bar, None, lqg.period, lqg.bits)
            rig.shutdown()
    except Exception as e:  # noqa: BLE001 - the failure goes back with its cause
        raise _failed(e, rig, out) from None
    done = FlightDone(missile_result(d, reference=cfg.mode == "lockstep"),
                      flights_counters(firmware_summary(rig.status, rig.security.counters())))
    shutil.rmtree(out, ignore_errors=True)
    return done


def fly_field_flight(scenario: Scenario, cfg: RigConfig) -> dict[str, Any]:
    """One flight of a campaign over scenario fields (hil.runs.field_campaign): the single run
    of its scenario in the rig's directory, its summary back (the directory is removed)."""
    out = Path(cfg.out_dir)
    try:
        summary = run_flight([scenario], dataclasses.replace(worker_config(cfg), plots=False)).summary
    except Exception as e:  # noqa: BLE001 - the failure goes back with its cause
        raise _failed(e, None, out) from None
    shutil.rmtree(out, ignore_errors=True)
    return summary


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


__all__ = ["ChunkDone", "FlightDone", "Salvaged", "SessionDone", "add_counters", "campaign_flights",
           "flights_counters", "fly_campaign_flights", "fly_sweep_point", "one_session_counters",
           "salvage_campaign_flights"]
