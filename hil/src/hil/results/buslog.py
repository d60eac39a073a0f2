"""fcc's outputs read back from the run's bus log (candump -L).

The recorder sees every frame in bus order.  A flight starts at a SIM_CONTROL reset (the
rig sends one before every flight); inside it, lockstep output frames belong to the last
SIM_TICK of their application (fcc answers a tick completely before the simulator sends
anything else), and their own step field (12 bits for the identification frames) is checked
against it.  In realtime mode there are no ticks: frames are kept in order with their
timestamps and their own step field.

Nothing the bus says is taken on trust: given the run's key (and fcc's trip), the frames are
read as the live link reads them (hil.bus.secoc, hil.bus.e2e): SIM_CONTROL, SIM_TICK and fcc's
outputs (the 12 identification frames of a step under SID_OUT_AUTH, the missile's command and
estimate under MSL_ELEV_CMD_AUTH) count only once their authenticator verified under the key
and the trip, and SIM_CONTROL and SIM_TICK only when their E2E check passes.  A forged reset
starts no flight, a forged or replayed tick moves no step, a forged estimate, bound or flag
reaches no table (``BusAuth``); what was refused on fcc's identifiers is counted
(``Forgeries``: the run reports it, hil.results.trust).  A second, different frame for a step
already seen is refused too (hil.results.sidframes): lockstep, fcc sends a step's outputs once.
"""
from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from hil.bus.candump import LogFrame
from hil.bus.dbc import load
from hil.bus.e2e import E2EReceiver
from hil.bus.logcolumns import FrameColumns, LogBlock, le_uint, per_identifier, read_columns
from hil.bus.apps import BUS_APPS, SENSOR_APP
from hil.bus.protocol import COMMAND_RESET, SIM_CONTROL_ID, SIM_TICK_ID
from hil.bus.runcheck import check_run, verify_run
from hil.bus.secoc import Endpoint, GroupReceiver, Receiver
from hil.results.trust import Forgeries

#: fcc's outputs of one step of each application (by SIM_TICK.app): the group each authenticator covers
OUTPUT_AUTH = {a.code: a.output_auth for a in BUS_APPS.values() if a.output_auth}
#: the output frames of each application (hil.bus.apps), by identifier
_OUTPUT_APP = {load().by_name(f).frame_id: a.code for a in BUS_APPS.values() for f in a.output_frames}


#: the application of each output frame, and of each sensor frame (hil.bus.protocol.SENSOR_APP:
#: their bytes 2-3 are the low 16 bits of the step), by identifier
_OUTPUT_OF, _SENSOR_OF = per_identifier(_OUTPUT_APP), per_identifier(SENSOR_APP)


@dataclass
class FlightFrames:
    """fcc's output frames of one flight (between two resets): per application, the frames
    that have a step (lockstep: their application's last tick; realtime: its newest sample)
    with that step, in log order; `frames` counts them all."""

    index: int
    frames: int = 0
    _parts: dict[int, list[tuple[np.ndarray, FrameColumns]]] = field(default_factory=dict, repr=False)

    def add(self, app: int, steps: np.ndarray, frames: FrameColumns) -> None:
        self._parts.setdefault(app, []).append((steps, frames))

    def outputs(self, app: int) -> tuple[np.ndarray, FrameColumns]:
        """An application's frames with a step: (their steps, the frames)."""
        parts = self._parts.get(app) or [(np.zeros(0, np.int64), FrameColumns.of([]))]
        if len(parts) > 1:
            parts[:] = [(np.concatenate([s for s, _ in parts]), FrameColumns.concat(f for _, f in parts))]
        return parts[0]


@dataclass(frozen=True)
class BusAuth:
    """The run's bus key and fcc's trip (None: the first heartbeat that verifies under the key
    fixes it, as on the live link): what a frame must verify under to count."""

    key: bytes
    trip: int | None = None


class _Gate:
    """The live link's checks on the recorded frames: what passes is what fcc acted on.  A run
    of ticks, or of fcc's output groups (the 12 identification frames then SID_OUT_AUTH: most
    of a log), is verified in one call on the endpoint's receiver of their authenticator
    (columns: hil.bus.runcheck); any other frame one by one."""

    def __init__(self, auth: BusAuth) -> None:
        spec = load()
        self.endpoint = Endpoint(spec, auth.key, ())   # every authenticator is verified here
        if auth.trip is not None:
            self.endpoint.set_trip(auth.trip)
        tick_auth = next(m for m in spec.messages if m.secoc_pdus == ("SIM_TICK",))
        self.tick_auth_id = tick_auth.frame_id
        ticks = self.endpoint.receiver(self.tick_auth_id)
        assert isinstance(ticks, Receiver)
        self.ticks = ticks
        self.e2e = {m.frame_id: E2EReceiver(m.data_id, m.max_delta_counter)
                    for m in (spec.by_name("SIM_CONTROL"), spec.by_name("SIM_TICK"))}
        self.rejected = 0
        #: fcc's output groups: (members, authenticator id, its receiver), verified a run at once
        self.groups = [(ids, auth_id, r) for ids, auth_id, r in (
            (tuple(spec.by_name(p).frame_id for p in spec.by_name(name).secoc_pdus),
             spec.by_name(name).frame_id, self.endpoint.receiver(spec.by_name(name).frame_id))
            for name in OUTPUT_AUTH.values()) if isinstance(r, GroupReceiver)]
        #: the frames these checks look at (secured, authenticators, E2E): all others pass as
        #: they are
        self.checked = np.array(sorted({*self.e2e, *self.endpoint.auth_ids, *(
            m.frame_id for m in spec.messages if self.endpoint.is_secured(m.frame_id))}))

    def forgeries(self) -> Forgeries:
        """What was refused on fcc's output identifiers so far (Forgeries)."""
        out = Forgeries()
        for name in OUTPUT_AUTH.values():
            r = self.endpoint.receiver(load().by_name(name).frame_id)
            c = r.counters
            out.refused[name] = c.mac_failed + c.freshness_failed + c.unpaired
            out.conflicts[name] = r.conflicts if isinstance(r, GroupReceiver) else 0
        return out

    def frames(self, fid: int, data: bytes) -> list[tuple[int, bytes]]:
        """What one frame gives fcc to act on (nothing, or the frames its authenticator
        verified)."""
        return [(i, d) for i, d in self.endpoint.receive(fid, data) if self._e2e_ok(i, d)]

    def _e2e_ok(self, fid: int, data: bytes) -> bool:
        rx = self.e2e.get(fid)
        if rx is None:
            return True
        if not rx.check(data).data_usable:
            self.rejected += 1
            return False
        if fid == SIM_CONTROL_ID and (data[1] >> 4) == COMMAND_RESET:
            self.e2e[SIM_TICK_ID].reset()   # fcc resynchronises on a reset
        return True

    def columns(self, cols: FrameColumns) -> FrameColumns:
        """A block's frames fcc acted on: what frames() gives frame by frame, each in its
        authenticator's place; a run of ticks, or of an output group, that passes simply is
        taken at once."""
        at = np.flatnonzero(np.isin(cols.frame_id, self.checked))
        if not len(at):
            return cols
        keep = np.ones(len(cols), bool)
        keep[at] = False
        places, passed = [np.flatnonzero(keep)], [cols.take(keep)]   # where each frame goes
        if self.endpoint.trip is not None:   # (until it is known, every frame in bus order)
            for group in self.groups:        # each group's receiver sees its own frames only
                mine = np.isin(cols.frame_id[at], (*group[0], group[1]))
                self._group_frames(cols, at[mine], group, places, passed)
                at = at[~mine]
        ids, full = cols.frame_id[at].tolist(), (cols.length[at] == 8).tolist()
        runs = self._tick_pairs(ids, full)
        j = 0
        while j < len(at):
            n = runs[j]
            ticks = cols.data[at[j: j + 2 * n: 2]]
            n = verify_run(self.ticks, ticks, cols.data[at[j + 1: j + 2 * n: 2]])
            if n:
                usable = self._usable(ticks[:n])
                places.append(at[j + 1: j + 2 * n: 2][usable])
                passed.append(FrameColumns(np.full(len(usable), SIM_TICK_ID), ticks[usable], np.full(len(usable), 8)))
                j += 2 * n
                continue
            self._one(cols, int(at[j]), places, passed)
            j += 1
        return FrameColumns.concat(passed).take(np.argsort(np.concatenate(places), kind="stable"))

    def _one(self, cols: FrameColumns, i: int, places: list[np.ndarray], passed: list[FrameColumns]) -> None:
        """Row i as frames() decides it, in its place."""
        got = self.frames(*cols.frame(i))
        places.append(np.full(len(got), i))
        passed.append(FrameColumns.of(got))

    def _group_frames(self, cols: FrameColumns, at: np.ndarray,
                      group: tuple[tuple[int, ...], int, GroupReceiver],
                      places: list[np.ndarray], passed: list[FrameColumns]) -> None:
        """One output group's frames (cols' rows at, in bus order): runs of complete groups
        (the members in order, then their authenticator) that verify one after the other are
        taken at once, each group's frames at its authenticator's place; any other frame as
        frames() decides it."""
        members, auth_id, rx = group
        width = len(members) + 1
        runs = _pattern_runs(cols.frame_id[at], cols.length[at] == 8, (*members, auth_id))
        j = 0
        while j < len(at):
            n = int(runs[j]) if not rx.copies else 0   # (a copy held: GroupReceiver decides)
            rows = at[j: j + n * width].reshape(n, width)
            n = verify_run(rx, cols.data[rows[:, :-1]].reshape(n, 8 * len(members)), cols.data[rows[:, -1]])
            if n:
                places.append(np.repeat(rows[:n, -1], len(members)))
                passed.append(FrameColumns(np.tile(np.array(members, np.int64), n),
                                           cols.data[rows[:n, :-1]].reshape(-1, 8), np.full(n * len(members), 8)))
                j += n * width
                continue
            self._one(cols, int(at[j]), places, passed)
            j += 1

    def _tick_pairs(self, ids: list[int], full: list[bool]) -> list[int]:
        """For each checked frame, how many (tick, its authenticator) pairs of 8-byte frames
        follow one another from it on (none until fcc's trip is known)."""
        runs = [0] * (len(ids) + 2)
        if self.endpoint.trip is None:
            return runs
        for j in range(len(ids) - 2, -1, -1):
            if ids[j] == SIM_TICK_ID and ids[j + 1] == self.tick_auth_id and full[j] and full[j + 1]:
                runs[j] = 1 + runs[j + 2]
        return runs

    def _usable(self, ticks: np.ndarray) -> list[int]:
        """Which of these verified ticks pass E2E: runs of OK ones at once
        (hil.bus.runcheck.check_run), any other one as frames() checks it."""
        usable: list[int] = []
        i = 0
        while i < len(ticks):
            n = check_run(self.e2e[SIM_TICK_ID], ticks[i:])
            usable += range(i, i + n)
            i += n
            if i < len(ticks):
                if self._e2e_ok(SIM_TICK_ID, ticks[i].tobytes()):
                    usable.append(i)
                i += 1
        return usable


def _pattern_runs(ids: np.ndarray, full: np.ndarray, pattern: tuple[int, ...]) -> np.ndarray:
    """For each position of ids (8-byte frames where full), how many copies of pattern follow
    one another from it on."""
    size, n = len(pattern), len(ids)
    runs = np.zeros(n + size, np.int64)
    if n < size:
        return runs
    match = np.ones(n - size + 1, bool)
    for i, p in enumerate(pattern):
        match &= (ids[i: n - size + 1 + i] == p) & full[i: n - size + 1 + i]
    for j in np.flatnonzero(match)[::-1].tolist():
        runs[j] = 1 + runs[j + size]
    return runs


def app_of(frame_id: int) -> int | None:
    """Which application produced an output frame (None: not an output)."""
    return _OUTPUT_APP.get(frame_id)


def split_flights(log: Path | Iterable[LogBlock], auth: BusAuth | None = None,
                  forgeries: Forgeries | None = None) -> list[FlightFrames]:
    """The flights of a bus log (segments that start with a SIM_CONTROL reset); `log` is its
    path or its blocks already read (hil.bus.logcolumns.read_blocks); auth: only frames that
    verify under it count (forgeries: what was refused, as iter_flights)."""
    return list(iter_flights(log, auth, forgeries))


def authentic_frames(frames: Iterable[LogFrame], auth: BusAuth, own_time: bool = False) -> Iterator[LogFrame]:
    """The frames fcc acted on (what iter_flights reads with auth), as log frames: secured
    ones at their authenticator's place (its time; own_time: their own, the first copy's),
    authenticators not at all."""
    gate = _Gate(auth)
    first_seen: dict[tuple[int, bytes], float] = {}
    for f in frames:
        if not f.classic_data:
            continue
        if own_time and gate.endpoint.is_secured(f.frame_id):
            first_seen.setdefault((f.frame_id, bytes(f.data)), f.timestamp)
            if len(first_seen) > _FIRST_SEEN_MAX:   # forged copies never verify: bounded
                del first_seen[next(iter(first_seen))]
        for fid, data in gate.frames(f.frame_id, f.data):
            t = first_seen.pop((fid, data), f.timestamp) if own_time else f.timestamp
            yield LogFrame(t, f.channel, fid, data)


#: secured frames remembered with their own time until their authenticator (authentic_frames)
_FIRST_SEEN_MAX = 4096


def _authentic(log: Path | Iterable[LogBlock], gate: _Gate | None) -> Iterator[FrameColumns]:
    """The classic data frames of a log (its path: a block at a time) that pass the gate."""
    blocks = read_columns(log) if isinstance(log, Path) else (b.classic() for b in log)
    for cols in blocks:
        yield cols if gate is None else gate.columns(cols)


class _Flights:
    """Flights cut from the frames fcc acted on, a block at a time (iter_flights)."""

    def __init__(self) -> None:
        self.n = 0
        self.cur: FlightFrames | None = None
        self.tick: dict[int, int] = {}     # application -> the step its outputs belong to
        self.ticked: set[int] = set()      # applications with a tick in this flight

    def feed(self, cols: FrameColumns) -> Iterator[FlightFrames]:
        """The flights that end in this block (at a reset), the frames of the current one
        kept."""
        resets = np.flatnonzero((cols.frame_id == SIM_CONTROL_ID) & (cols.length == 8)
                                & ((cols.data[:, 1] >> 4) == COMMAND_RESET))
        start = 0
        for r in resets.tolist():
            self._segment(cols.take(slice(start, r)))
            if self.cur is not None:
                yield self.cur
            self.cur = FlightFrames(self.n)
            self.n += 1
            self.tick, self.ticked = {}, set()
            start = r + 1
        self._segment(cols.take(slice(start, len(cols))))

    def _segment(self, seg: FrameColumns) -> None:
        """Frames of the current flight without a reset: each output frame gets its
        application's step: its last tick's (lockstep), or, before the flight's first tick of
        that application, the newest sensor sample's (realtime)."""
        if self.cur is None or not len(seg):
            return
        fid, data, full = seg.frame_id, seg.data, seg.length == 8
        out_app = _OUTPUT_OF[fid]
        self.cur.frames += int(np.count_nonzero(out_app >= 0))
        tick_app = np.where((fid == SIM_TICK_ID) & full, (data[:, 1] >> 4) & 0x3, -1)
        for app in (0, 1):
            ticks = np.flatnonzero(tick_app == app)
            events, values = ticks, le_uint(data[ticks], 2, 4)
            if app not in self.ticked:
                samples = np.flatnonzero(full & (_SENSOR_OF[fid] == app))
                samples = samples[samples < ticks[0]] if len(ticks) else samples
                if len(samples):
                    events = np.concatenate((samples, events))
                    values = np.concatenate((self._unwrap(app, le_uint(data[samples], 2, 2)), values))
            outs = np.flatnonzero(out_app == app)
            # the step of each output: the newest event's before it, or the one carried in
            chain = np.concatenate(([self.tick.get(app, -1)], values))
            steps = chain[np.searchsorted(events, outs)]
            known = steps >= 0
            if known.any():
                self.cur.add(app, steps[known], seg.take(outs[known]))
            if len(values):
                self.tick[app] = int(values[-1])
            if len(ticks):
                self.ticked.add(app)

    def _unwrap(self, app: int, low: np.ndarray) -> np.ndarray:
        """Steps from the low 16 bits of successive samples: each the smallest step at or above
        the previous one with those bits (the first's: its bits, or above the carried step)."""
        prev = self.tick.get(app, -1)
        first = int(low[0]) if prev < 0 else prev + ((int(low[0]) - prev) & 0xFFFF)
        return first + np.concatenate(([0], np.cumsum(np.diff(low) & 0xFFFF)))


def iter_flights(log: Path | Iterable[LogBlock], auth: BusAuth | None = None,
                 forgeries: Forgeries | None = None) -> Iterator[FlightFrames]:
    """The flights of a bus log one by one (a campaign's log holds 100 of them); auth: only
    authenticated, E2E-valid commands, ticks and outputs count (without it, every frame does);
    forgeries (with auth): filled in, once the log is read, with what was refused on fcc's
    output identifiers."""
    flights = _Flights()
    gate = _Gate(auth) if auth is not None else None
    for cols in _authentic(log, gate):
        yield from flights.feed(cols)
    if flights.cur is not None:
        yield flights.cur
    if gate is not None and forgeries is not None:
        got = gate.forgeries()
        forgeries.refused, forgeries.conflicts = got.refused, got.conflicts
