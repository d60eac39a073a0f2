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

import re
from collections import defaultdict
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from hil.bus.candump import LogFrame, parse_line
from hil.bus.dbc import BusSpec, SignalSpec, load
from hil.bus.e2e import E2EReceiver
from hil.bus.protocol import COMMAND_RESET, SENSOR_APP, SIM_CONTROL_ID, SIM_TICK_ID
from hil.bus.secoc import Endpoint
from hil.sim.drivers import FILTERS, SID_PARTS, SID_PREFIX

# the sensor frames of each application (hil.bus.protocol.SENSOR_APP): their bytes 2-3 are
# the low 16 bits of the step

#: a candump -L line of a classic data frame with a standard identifier, single spaces: nearly
#: every line of a rig's log, read by one regular-expression pass over a block of the text
#: (group 1 the identifier, 2 the data); any other line is group 3, for candump.parse_line
_PLAIN_LINE = re.compile(r"^\(\d+(?:\.\d+)?\) \S+ ([0-9A-Fa-f]{3})#((?:[0-9A-Fa-f]{2}){0,8})$|^(.*)$",
                         re.MULTILINE)
#: the text read per pass (whole lines): the log of a long campaign is never held at once
_BLOCK_CHARS = 1 << 20


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
        #: the frames these checks look at (secured, authenticators, E2E): all others pass as
        #: they are (the bulk of a log: fcc's identification outputs)
        self.checked = frozenset({*self.e2e, *self.endpoint.auth_ids,
                                  *(m.frame_id for m in spec.messages if self.endpoint.is_secured(m.frame_id))})

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
    return _OUTPUT_APP.get(frame_id)


#: the output frames of each application (0 CDRW, 1 missile)
_OUTPUT_APP = {**dict.fromkeys(range(0x110, 0x140), 0), 0x030: 1, 0x100: 1}


def split_flights(log: Path | Iterable[LogFrame], auth: BusAuth | None = None) -> list[FlightFrames]:
    """The flights of a bus log (segments that start with a SIM_CONTROL reset); `log` is its
    path or its frames already read; auth: only frames that verify under it count."""
    return list(iter_flights(log, auth))


def authentic_frames(frames: Iterable[LogFrame], auth: BusAuth) -> Iterator[LogFrame]:
    """The frames fcc acted on (what iter_flights reads with auth), as log frames: secured
    ones at their authenticator's place (its time), authenticators not at all."""
    gate = _Gate(auth)
    for f in frames:
        if not f.classic_data:
            continue
        for fid, data in gate.frames(f.frame_id, f.data):
            yield LogFrame(f.timestamp, f.channel, fid, data)


def data_frames(path: Path) -> Iterator[tuple[int, bytes]]:
    """(identifier, data) of the classic data frames of a candump -L log, in order: what
    candump.read_log gives without its frame objects (a LogFrame per line costs more than
    the rest of a flight's read-back), as strict (a malformed line raises LogFormatError)."""
    before = 0   # lines of the blocks before this one
    with open(path, encoding="ascii", errors="replace") as f:
        while block := f.read(_BLOCK_CHARS):
            block += f.readline()   # whole lines only
            for lineno, (ident, data, other) in enumerate(_PLAIN_LINE.findall(block), before + 1):
                if ident:
                    yield int(ident, 16), bytes.fromhex(data)
                elif other.strip():
                    fr = parse_line(other, lineno)
                    if fr.classic_data:
                        yield fr.frame_id, fr.data
            before += block.count("\n") + (not block.endswith("\n"))


def _authentic(log: Path | Iterable[LogFrame], gate: _Gate | None) -> Iterator[tuple[int, bytes]]:
    frames = data_frames(log) if isinstance(log, Path) else (
        (f.frame_id, f.data) for f in log if f.classic_data)
    if gate is None:
        yield from frames
        return
    checked = gate.checked
    for fid, data in frames:
        if fid in checked:
            yield from gate.frames(fid, data)
        else:
            yield fid, data


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
        app = _OUTPUT_APP.get(fid)
        if app is None:
            continue
        cur.frames += 1
        if app in tick:
            cur.by_step[app][tick[app]].append((fid, data))
    if cur is not None:
        yield cur


def _column(sig: SignalSpec, bits: np.ndarray) -> np.ndarray:
    """A signal's physical values from frames read as little-endian 64-bit integers: what
    float(sig.scaled(sig.unpack(bits))) gives frame by frame, the same float operations (a
    signal of at most 32 bits, as every identification signal: exact in int64 and float64)."""
    if sig.length > 32:
        raise ValueError(f"{sig.name}: a {sig.length}-bit signal is not decoded here")
    raw = ((bits >> np.uint64(sig.start)) & np.uint64((1 << sig.length) - 1)).astype(np.int64)
    if sig.signed:
        raw = np.where(raw >> (sig.length - 1) != 0, raw - (1 << sig.length), raw)
    return raw.astype(float) if sig.is_integer else raw * sig.scale + sig.offset


def sid_arrays(spec: BusSpec, flight: FlightFrames, n_steps: int,
               check_step: bool = True) -> dict[str, np.ndarray]:
    """The identification outputs of steps 0..n-1 as arrays named '<filter>_<signal>'
    (NaN where a frame is missing or, lockstep, its step field does not match the tick;
    realtime: fcc counts its own steps, so the field is not compared, the last frame wins)."""
    out: dict[str, np.ndarray] = {}
    # per frame id: its step signal (None: it has none) and (signal, its column) of the others
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
    # each frame id's frames of steps 0..n-1, in the log's order: their steps and their bytes,
    # decoded a signal at a time over all of them (numpy) instead of a frame at a time
    found: dict[int, tuple[list[int], list[bytes]]] = {fid: ([], []) for fid in ids}
    for k, frames in flight.by_step.get(0, {}).items():
        if k < n_steps:
            for fid, data in frames:
                if fid in found and len(data) == 8:
                    ks, datas = found[fid]
                    ks.append(k)
                    datas.append(data)
    mismatched = 0
    for fid, (ks, datas) in found.items():
        if not ks:
            continue
        steps = np.array(ks)
        bits = np.frombuffer(b"".join(datas), dtype="<u8")
        step_sig, cols = ids[fid]
        if step_sig is not None:
            ok = _column(step_sig, bits).astype(np.int64) == (steps & 0xFFF)
            mismatched += int(np.count_nonzero(~ok))
            steps, bits = steps[ok], bits[ok]
        # a step's last frame wins (a step field written twice, realtime)
        last = len(steps) - 1 - np.unique(steps[::-1], return_index=True)[1]
        steps, bits = steps[last], bits[last]
        for sig, col in cols:
            col[steps] = _column(sig, bits)
    out["_mismatched"] = np.array([mismatched])
    return out
