"""Frame-level and bus-level fault injection on the frames the simulator sends.

The sensor-level faults change a reading before it is encoded (hil.sim.sensor_faults does that, in the
plant's simulation); the faults here act on the encoded, E2E-protected frames, as a broken
transceiver, a bad harness or a rogue node would (SPEC section 5, hil.scenario.faults):

=================  =====================================================================
loss               the frame is not sent (probability p); the sensor's counter still
                   advanced, so the next frame is E2E OK_SOME_LOST
delay              the frame is held back `delay` s: it goes out with the first step whose
                   time has reached t + delay (lockstep: after the tick it belonged to)
duplicate          `count` identical copies follow the frame (E2E REPEATED)
replay             the frame sent `age` s earlier goes out instead (old counter and CRC:
                   E2E WRONG_SEQUENCE or REPEATED); before that much history, unchanged
bad_crc            byte 0 (the CRC) is inverted (probability p): E2E ERROR
counter_freeze     the alive counter stays at its value at the start, CRC recomputed:
                   E2E REPEATED every frame
counter_jump       `jump` added to the alive counter, CRC recomputed: one OK_SOME_LOST or
                   WRONG_SEQUENCE at the start and one at the end
wrong_dlc          the frame goes out with `dlc` bytes (cut, or padded with 0x00)
out_of_range       `signal` carries raw value `raw` (default: the largest the field holds),
                   CRC recomputed: the receiver's range check must reject it
flood              a babbling node: `rate_hz` frames/s of `dlc` bytes 0xFF on `can_id`
silence            nothing from the simulated nodes reaches the bus (lockstep: the tick,
                   which is the rig's clock and not a node, still goes out)
=================  =====================================================================

A frame fault with ``frame = "*"`` acts on every sensor frame of the flown aircraft; the
lockstep tick and SIM_CONTROL are only touched when named explicitly.  Random choices come
from a stream derived from the scenario seed, so a run is reproducible.  Each start and end
of a fault is logged with its time (``FaultTimeline``).
"""
from __future__ import annotations

import math
from collections import deque
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from hil.bus import FrameCodec
from hil.bus.batch import encode_many
from hil.bus.dbc import MessageSpec, SignalSpec
from hil.bus.e2e import counter_of, protect
from hil.bus.protocol import FAULT_KIND_CODES
from hil.bus.rawcan import pack_frame
from hil.scenario.faults import (
    BadCrc,
    CounterFreeze,
    CounterJump,
    Fault,
    Flood,
    FrameDelay,
    FrameDuplicate,
    FrameLoss,
    FrameReplay,
    OutOfRange,
    Silence,
    WrongDlc,
)
from hil.sim.sensor_faults import FaultEvent, FaultTimeline, random_stream

if TYPE_CHECKING:
    import numpy as np

#: one message of every step of a flight, for FrameInjector.outgoing_flight: its name, which
#: steps send it (bool, one per step) and the values of its data signals in those steps
Batch = tuple[str, "np.ndarray", Mapping[str, "np.ndarray"]]

#: SIM_EVENT.kind of each fault kind (0 = none): the DBC's value table (hil.bus.protocol)
KIND_CODES: dict[str, int] = FAULT_KIND_CODES
#: how much of each message's history is kept for replays
REPLAY_HISTORY = 4096
T_EPS = 1e-9


@dataclass(frozen=True)
class TxFrame:
    """One frame to put on the bus."""

    frame_id: int
    data: bytes            # len 8, or the wrong DLC
    name: str              # DBC message, or "flood"
    #: the frame as the socket sends it (struct can_frame), packed once: the CDRW's frames
    #: are made before its flight, so its lockstep loop only hands them over
    raw: bytes = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "raw", pack_frame(self.frame_id, self.data))


def set_raw(data: bytes, sig: SignalSpec, raw: int) -> bytes:
    """data with signal sig replaced by raw (little-endian field; wrapped to its width)."""
    word = int.from_bytes(data, "little")
    mask = ((1 << sig.length) - 1) << sig.start
    word = (word & ~mask) | ((raw & ((1 << sig.length) - 1)) << sig.start)
    return word.to_bytes(8, "little")


def out_of_range_raw(sig: SignalSpec) -> int:
    """The largest raw value the field holds, if that is outside the DBC range, else the
    smallest; a field whose DBC range covers every raw value cannot be made out of range."""
    hi = (1 << (sig.length - 1)) - 1 if sig.signed else (1 << sig.length) - 1
    lo = -(1 << (sig.length - 1)) if sig.signed else 0
    if hi > sig.raw_max:
        return hi
    if lo < sig.raw_min:
        return lo
    raise ValueError(f"{sig.name}: its DBC range covers the whole {sig.length}-bit field")


class FrameInjector:
    """Encodes the simulator's messages (E2E through the bus codec) and applies the frame-
    and bus-level faults active at the step's time."""

    def __init__(self, codec: FrameCodec, faults: Sequence[Fault], seed: int,
                 star_frames: Iterable[str], flood_frames: bool = True) -> None:
        """flood_frames: the babbling node's frames are produced here, per step (lockstep);
        False in realtime, where a cangen process babbles on its own clock."""
        self.flood_frames = flood_frames
        self.codec = codec
        self.spec = codec.spec
        self.star = frozenset(star_frames)
        self.faults: tuple[Fault, ...] = ()
        #: the faults that name each message (the tick's are looked up every step)
        self._naming: dict[str, list[tuple[int, Fault]]] = {}
        #: the messages a replay fault may act on: only their history is kept
        self._replayed: frozenset[str] = frozenset()
        self.timeline = FaultTimeline(())
        for f in faults:   # (a wire fault is canbus's: here only its SIM_EVENT start and end)
            if f.level in ("frame", "bus", "wire"):
                self.add(f)
        self._seed = int(seed)
        self._rng_made: np.random.Generator | None = None
        self._frozen: dict[int, int] = {}                 # fault index -> frozen counter
        self._history: dict[str, deque[tuple[float, bytes]]] = {}
        self._delayed: list[tuple[float, int, TxFrame]] = []   # (due, order, frame)
        self._order = 0
        self._flood_sent: dict[int, int] = {}             # fault index -> frames so far
        self.counts = {"encoded": 0, "sent": 0, "dropped": 0, "flood": 0, "delayed": 0,
                       "duplicated": 0, "replayed": 0, "corrupted": 0}

    def add(self, f: Fault) -> None:
        """One more frame or bus fault, from the next update() on (the scenario's, or one
        injected during a flight)."""
        name = getattr(f, "frame", "*")
        if name != "*":
            self.spec.by_name(name)  # KeyError names an unknown frame
            self._naming.setdefault(name, []).append((len(self.faults), f))
        if isinstance(f, OutOfRange):
            msg = self.spec.by_name(f.frame) if f.frame != "*" else None
            if msg is None or f.signal not in {s.name for s in msg.data_signals}:
                raise ValueError(f"fault {f.describe()}: out_of_range needs frame = a DBC "
                                 f"message and signal = one of its data signals")
        if isinstance(f, FrameReplay):
            self._replayed |= self.star if f.frame == "*" else {f.frame}
        self.faults = (*self.faults, f)
        self.timeline.add(f)

    @property
    def _rng(self) -> np.random.Generator:
        """The stream of the faults' probabilities ("fr"), made at the first draw."""
        if self._rng_made is None:
            self._rng_made = random_stream(self._seed, 0x6672)
        return self._rng_made

    @property
    def log(self) -> list[FaultEvent]:
        return self.timeline.log

    def _targets(self, fault: Fault, name: str) -> bool:
        frame = getattr(fault, "frame", "*")
        return frame == name or (frame == "*" and name in self.star)

    def update(self, t: float) -> list[FaultEvent]:
        """Advance the fault timeline to t (call once per step, before outgoing())."""
        events = self.timeline.update(t)
        for ev in events:
            if ev.action == "start" and isinstance(ev.fault, CounterFreeze):
                self._frozen.pop(ev.index, None)
        return events

    def silenced(self) -> bool:
        return any(isinstance(f, Silence) for f in self.timeline.active)

    def outgoing(self, t: float, messages: Sequence[tuple[str, Mapping[str, float | int]]],
                 *, extras: bool = True) -> list[TxFrame]:
        """The frames that go on the bus at step time t for these messages (in order):
        with extras, first the delayed frames now due and the babbling node's frames since
        the last call; then the messages."""
        active = [(i, f) for i, f in enumerate(self.faults) if f.active(t)]
        out: list[TxFrame] = []
        silent = any(isinstance(f, Silence) for _, f in active)
        if extras:
            out.extend(self._due(t))
            if self.flood_frames:
                for i, f in enumerate(self.faults):
                    if isinstance(f, Flood) and f.start <= t + T_EPS:
                        out.extend(self._flood(i, f, t))
        for name, values in messages:
            out.extend(self._one(t, name, values, active))
        if silent:
            self.counts["dropped"] += len(out)
            return []
        self.counts["sent"] += len(out)
        return out

    def outgoing_flight(self, n_steps: int, batches: Iterable[Batch]) -> list[list[TxFrame]] | None:
        """Every step's frames of a flight whose messages are all known before it starts, made
        at once (hil.bus.batch): what outgoing(t_k, messages of step k) would give step by step,
        with the same counts and E2E counters.  None when the scenario has a frame or bus
        fault (they act on single frames, some with random draws: the caller goes step by
        step), the batches then not taken (a generator's columns are never made)."""
        if self.faults:
            return None
        steps: list[list[TxFrame]] = [[] for _ in range(n_steps)]
        for name, sends, columns in batches:
            frame_id, datas = encode_many(self.codec, name, columns, saturate=True)
            for k, data in zip(sends.nonzero()[0].tolist(), datas):
                steps[k].append(TxFrame(frame_id, data, name))
            self.counts["encoded"] += len(datas)
            self.counts["sent"] += len(datas)
        return steps

    def faulted(self, t: float, name: str) -> bool:
        """True when a frame fault names this message explicitly and is active at t."""
        return any(f.level == "frame" and f.active(t) for _, f in self._naming.get(name, ()))

    def names(self, name: str) -> bool:
        """True when some fault of the scenario names this message explicitly (at any time)."""
        return name in self._naming

    def infrastructure(self, t: float, name: str, values: Mapping[str, float | int]) -> list[TxFrame]:
        """A rig frame (SIM_TICK, SIM_CONTROL): only faults that name it act on it; silence,
        floods and '*' faults do not (the tick is the rig's clock, not a node)."""
        active = [(i, f) for i, f in self._naming.get(name, ()) if f.active(t)]
        out = self._one(t, name, values, active, can_delay=False)
        self.counts["sent"] += len(out)
        return out

    def sent_as_encoded(self, t: float, name: str, data: bytes) -> None:
        """Account for a rig frame that no fault names, encoded ahead of time (the lockstep's
        tick plan, hil.rig.tickplan), as infrastructure() would have."""
        self.counts["encoded"] += 1
        self.counts["sent"] += 1
        self._remember(t, name, data)

    def flush_delayed(self) -> list[TxFrame]:
        """Frames still held back at the end of a run (they arrive after it)."""
        out = [f for _, _, f in sorted(self._delayed)]
        self._delayed.clear()
        return out

    # -- internals
    def _due(self, t: float) -> list[TxFrame]:
        due = sorted(d for d in self._delayed if d[0] <= t + T_EPS)
        if due:
            self._delayed = [d for d in self._delayed if d[0] > t + T_EPS]
        return [f for _, _, f in due]

    def _flood(self, index: int, f: Flood, t: float) -> list[TxFrame]:
        """The babbler's frames sent since the last step: one every 1/rate s from the start,
        those before min(t, end) -- so the frames of the last interval go out with the first
        step after the end, and a fault of duration d gives ceil(rate * d) frames."""
        total = int(math.ceil(f.rate_hz * (min(t, f.end) - f.start) - 1e-6))
        n = total - self._flood_sent.get(index, 0)
        self._flood_sent[index] = total
        self.counts["flood"] += max(n, 0)
        frame = TxFrame(f.can_id, b"\xff" * f.dlc, "flood")
        return [frame] * max(n, 0)

    def _encode(self, t: float, name: str, values: Mapping[str, float | int]) -> TxFrame:
        frame_id, data = self.codec.encode(name, values, saturate=True)
        self.counts["encoded"] += 1
        self._remember(t, name, data)
        return TxFrame(frame_id, data, name)

    def _remember(self, t: float, name: str, data: bytes) -> None:
        """Keep what was sent of a message a replay fault may replay."""
        if name in self._replayed:
            hist = self._history.get(name)
            if hist is None:
                hist = self._history[name] = deque(maxlen=REPLAY_HISTORY)
            hist.append((t, data))

    def _one(self, t: float, name: str, values: Mapping[str, float | int],
             active: list[tuple[int, Fault]], can_delay: bool = True) -> list[TxFrame]:
        """One message with the active faults applied in their listed order.  can_delay
        False (the tick): a delayed frame is a lost one -- in lockstep nothing happens on
        the bus between two steps that could carry it late."""
        frame = self._encode(t, name, values)
        copies = 0
        for i, f in active:
            if f.level != "frame" or not self._targets(f, name):
                continue
            if isinstance(f, FrameLoss):
                if f.probability >= 1.0 or self._rng.random() < f.probability:
                    self.counts["dropped"] += 1
                    return []
            elif isinstance(f, FrameDelay):
                if not can_delay:
                    self.counts["dropped"] += 1
                    return []
                self._delayed.append((t + f.delay, self._order, frame))
                self._order += 1
                self.counts["delayed"] += 1
                return []
            elif isinstance(f, FrameReplay):
                old = self._replay(name, t - f.age)
                if old is not None:
                    frame = TxFrame(frame.frame_id, old, name)
                    self.counts["replayed"] += 1
            elif isinstance(f, FrameDuplicate):
                copies += f.count
                self.counts["duplicated"] += f.count
            else:
                frame = TxFrame(frame.frame_id, self._corrupt(i, f, self.spec.by_name(name), frame.data), name)
                self.counts["corrupted"] += 1
        # copies are taken after every other fault: a duplicate repeats what was sent
        return [frame] * (1 + copies)

    def _replay(self, name: str, t_old: float) -> bytes | None:
        best = None
        for t_sent, data in self._history.get(name, ()):
            if t_sent <= t_old + T_EPS:
                best = data
            else:
                break
        return best

    def _corrupt(self, index: int, f: Fault, msg: MessageSpec, data: bytes) -> bytes:
        if isinstance(f, BadCrc):
            if f.probability >= 1.0 or self._rng.random() < f.probability:
                return bytes((data[0] ^ 0xFF,)) + data[1:]
            return data
        if isinstance(f, WrongDlc):
            return data[:f.dlc] if f.dlc <= len(data) else data + bytes(f.dlc - len(data))
        if not msg.protected and isinstance(f, (CounterFreeze, CounterJump)):
            return data
        if isinstance(f, CounterFreeze):
            frozen = self._frozen.setdefault(index, counter_of(data))
            return protect(msg.data_id, data, frozen)
        if isinstance(f, CounterJump):
            return protect(msg.data_id, data, (counter_of(data) + f.jump) % 16)
        if isinstance(f, OutOfRange):
            sig = next(s for s in msg.data_signals if s.name == f.signal)
            raw = out_of_range_raw(sig) if f.raw is None else f.raw
            new = set_raw(data, sig, raw)
            return protect(msg.data_id, new, counter_of(data)) if msg.protected else new
        raise ValueError(f"fault kind {f.kind} is not a frame fault")
