"""fcc's outputs read back from the run's bus log (candump -L).

The recorder sees every frame in bus order.  A flight starts at a SIM_CONTROL reset (the
rig sends one before every flight); inside it, lockstep output frames belong to the last
SIM_TICK of their application (fcc answers a tick completely before the simulator sends
anything else), and their own step field (12 bits for the identification frames) is checked
against it.  In realtime mode there are no ticks: frames are kept in order with their
timestamps and their own step field.

Nothing the bus says is taken on trust: given the run's key (and fcc's trip), the frames are
read as the live link reads them (hil.bus.secoc, hil.bus.e2e): SIM_CONTROL, SIM_TICK and
MSL_ELEV_CMD count only once their authenticator verified under the key and the trip, and
SIM_CONTROL and SIM_TICK only when their E2E check passes.  A forged reset starts no flight, a
forged or replayed tick moves no step (``BusAuth``; ``FlightFrames.rejected`` counts them).
"""
from __future__ import annotations

from collections import defaultdict
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from hil.bus.candump import LogFrame, read_log
from hil.bus.dbc import BusSpec, SignalSpec, load
from hil.bus.e2e import E2EReceiver
from hil.bus.protocol import COMMAND_RESET, SENSOR_APP, SIM_CONTROL_ID, SIM_TICK_ID
from hil.bus.secoc import Endpoint
from hil.sim.drivers import FILTERS, SID_PARTS, SID_PREFIX

# the sensor frames of each application (hil.bus.protocol.SENSOR_APP): their bytes 2-3 are
# the low 16 bits of the step


@dataclass
class FlightFrames:
    """fcc's output frames of one flight (between two resets), by application and step."""

    index: int
    by_step: dict[int, dict[int, list[tuple[int, bytes]]]] = field(
        default_factory=lambda: defaultdict(lambda: defaultdict(list)))
    frames: int = 0


@dataclass(frozen=True)
class BusAuth:
    """The run's bus key and fcc's trip (None: the first heartbeat that verifies under the key
    fixes it, as on the live link): what a frame must verify under to count."""

    key: bytes
    trip: int | None = None


class _Gate:
    """The live link's checks on the recorded frames: what passes is what fcc acted on."""

    def __init__(self, auth: BusAuth) -> None:
        spec = load()
        self.endpoint = Endpoint(spec, auth.key, ())   # every authenticator is verified here
        if auth.trip is not None:
            self.endpoint.set_trip(auth.trip)
        self.e2e = {m.frame_id: E2EReceiver(m.data_id, m.max_delta_counter)
                    for m in (spec.by_name("SIM_CONTROL"), spec.by_name("SIM_TICK"))}
        self.rejected = 0

    def frames(self, fid: int, data: bytes) -> list[tuple[int, bytes]]:
        got = self.endpoint.receive(fid, data)
        out = []
        for i, d in got:
            rx = self.e2e.get(i)
            if rx is not None:
                if not rx.check(d).data_usable:
                    self.rejected += 1
                    continue
                if i == SIM_CONTROL_ID and (d[1] >> 4) == COMMAND_RESET:
                    self.e2e[SIM_TICK_ID].reset()   # fcc resynchronises on a reset
            out.append((i, d))
        return out


def app_of(frame_id: int) -> int | None:
    """Which application produced an output frame (None: not an output)."""
    if 0x110 <= frame_id <= 0x13F:
        return 0
    if frame_id in (0x030, 0x100):
        return 1
    return None


def split_flights(log: Path | Iterable[LogFrame], auth: BusAuth | None = None) -> list[FlightFrames]:
    """The flights of a bus log (segments that start with a SIM_CONTROL reset); `log` is its
    path or its frames already read; auth: only frames that verify under it count."""
    return list(iter_flights(log, auth))


def authentic_frames(frames: Iterable[LogFrame], auth: BusAuth) -> Iterator[LogFrame]:
    """The frames fcc acted on (what iter_flights reads with auth), as log frames: secured
    ones at their authenticator's place (its time), authenticators not at all."""
    gate = _Gate(auth)
    for f in frames:
        if f.error or f.remote or f.extended or f.fd:
            continue
        for fid, data in gate.frames(f.frame_id, f.data):
            yield LogFrame(f.timestamp, f.channel, fid, data)


def _authentic(log: Path | Iterable[LogFrame], gate: _Gate | None) -> Iterator[tuple[int, bytes]]:
    for f in read_log(log) if isinstance(log, Path) else log:
        if f.error or f.remote or f.extended or f.fd:
            continue
        if gate is None:
            yield f.frame_id, f.data
        else:
            yield from gate.frames(f.frame_id, f.data)


def iter_flights(log: Path | Iterable[LogFrame], auth: BusAuth | None = None) -> Iterator[FlightFrames]:
    """The flights of a bus log one by one (a campaign's log holds 100 of them); auth: only
    authenticated, E2E-valid commands and ticks count (without it, every frame does)."""
    n = 0
    cur: FlightFrames | None = None
    tick: dict[int, int] = {}
    ticked: set[int] = set()
    gate = _Gate(auth) if auth is not None else None
    for fid, data in _authentic(log, gate):
        if fid == SIM_CONTROL_ID and len(data) == 8 and (data[1] >> 4) == COMMAND_RESET:
            if cur is not None:
                yield cur
            cur = FlightFrames(n)
            n += 1
            tick, ticked = {}, set()
            continue
        if cur is None:
            continue
        if fid == SIM_TICK_ID and len(data) == 8:
            tick[(data[1] >> 4) & 0x3] = int.from_bytes(data[2:6], "little")
            ticked.add((data[1] >> 4) & 0x3)
            continue
        if fid in SENSOR_APP and len(data) == 8 and SENSOR_APP[fid] not in ticked:
            # realtime (no ticks): outputs belong to the newest sample sent before them
            sensor_app = SENSOR_APP[fid]
            low = int.from_bytes(data[2:4], "little")
            prev = tick.get(sensor_app, -1)
            tick[sensor_app] = low if prev < 0 else prev + ((low - prev) & 0xFFFF)
            continue
        app = app_of(fid)
        if app is None:
            continue
        cur.frames += 1
        if app in tick:
            cur.by_step[app][tick[app]].append((fid, data))
    if cur is not None:
        yield cur


def sid_arrays(spec: BusSpec, flight: FlightFrames, n_steps: int,
               check_step: bool = True) -> dict[str, np.ndarray]:
    """The identification outputs of steps 0..n-1 as arrays named '<filter>_<signal>'
    (NaN where a frame is missing or, lockstep, its step field does not match the tick;
    realtime: fcc counts its own steps, so the field is not compared, the last frame wins)."""
    out: dict[str, np.ndarray] = {}
    # per frame id: its step signal (None: it has none) and (signal, its column) of the others;
    # the frames are decoded signal by signal (SignalSpec) straight into their columns
    ids: dict[int, tuple[SignalSpec | None, list[tuple[SignalSpec, np.ndarray]]]] = {}
    for flt in FILTERS:
        for part in SID_PARTS:
            msg = spec.by_name(f"{SID_PREFIX[flt]}_{part}")
            step_sig, cols = None, []
            for sig in msg.signals:
                if sig.name == "step":
                    step_sig = sig
                    if part == "STATE":
                        continue
                col = out[f"{flt}_{sig.name}"] = np.full(n_steps, np.nan)
                if sig.name != "step":
                    cols.append((sig, col))
            ids[msg.frame_id] = (step_sig if check_step else None, cols)
    steps = flight.by_step.get(0, {})
    mismatched = 0
    for k in range(n_steps):
        frames = steps.get(k)
        if not frames:
            continue
        for fid, data in frames:
            if fid not in ids or len(data) != 8:
                continue
            step_sig, cols = ids[fid]
            bits = int.from_bytes(data, "little")
            if step_sig is not None and int(step_sig.scaled(step_sig.unpack(bits))) != (k & 0xFFF):
                mismatched += 1
                continue
            for sig, col in cols:
                col[k] = float(sig.scaled(sig.unpack(bits)))
    out["_mismatched"] = np.array([mismatched])
    return out
