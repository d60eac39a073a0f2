"""Fault kinds (SPEC section 5): one frozen dataclass per kind, with start, duration and its
parameters.  A fault is active for start <= t < start + duration (duration may be inf).

Four levels:
* sensor -- changes a measured value before it is encoded (applied here, see inject.py);
* frame  -- changes what happens to CAN frames of one message (or all, frame = "*");
* bus    -- affects the bus as a whole;
* wire   -- the wire-time bus's own faults (error frames, a babbling controller, bus-off):
  canbus applies them, so they fly with `--bus wire` only (hil.rig.wirefaults).
Frame and bus faults are *specifications* here; the bus layer applies them to frames.
Their parameters are documented on each class so that layer knows exactly what is meant.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

if TYPE_CHECKING:  # hints only
    import numpy as np

from hil.scenario.schema import spec

#: tolerance on fault edges, so 50 Hz sample times (k * 0.02) land on the intended side
T_EPS = 1e-9


@dataclass(frozen=True, kw_only=True)
class Fault:
    """Common part: when the fault is active."""

    kind: ClassVar[str] = ""
    level: ClassVar[str] = ""

    start: float = spec(ge=0.0)                      # s, from the start of the run
    duration: float = spec(gt=0.0, allow_inf=True)   # s, > 0 (inf: until the end)

    @property
    def end(self) -> float:
        return self.start + self.duration

    def active(self, t: float) -> bool:
        return self.start - T_EPS <= t < self.end - T_EPS

    @property
    def target(self) -> str:
        """What the fault acts on (signal, frame or 'bus'), for logs."""
        return "bus"

    def params(self) -> dict[str, Any]:
        """Every field, in declaration order (what describe() prints)."""
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}

    def describe(self) -> str:
        """The command-line form, e.g. 'spike:signal=alpha,start=4,duration=0.1,magnitude=0.2'."""
        def fmt(v: Any) -> str:
            if isinstance(v, float):
                return "inf" if math.isinf(v) else f"{v:g}"
            return str(v).lower() if isinstance(v, bool) else str(v)
        body = ",".join(f"{k}={fmt(v)}" for k, v in self.params().items() if v is not None)
        return f"{self.kind}:{body}"


# ---------------------------------------------------------------------------------------------
# sensor level
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True, kw_only=True)
class SensorFault(Fault):
    level: ClassVar[str] = "sensor"
    signal: str = spec()   # cdrw: alpha, q, de; missile: q_g, n_a

    @property
    def target(self) -> str:
        return self.signal

    def apply(self, value: float, t: float, held: float, rng: np.random.Generator) -> float:
        """The faulty reading.  held = the reading delivered just before the fault began."""
        raise NotImplementedError


@dataclass(frozen=True, kw_only=True)
class Spike(SensorFault):
    """Short additive error: reading + magnitude (the paper's ~0.1 s sensor malfunction)."""

    kind: ClassVar[str] = "spike"
    magnitude: float = spec()

    def apply(self, value: float, t: float, held: float, rng: np.random.Generator) -> float:
        return value + self.magnitude


@dataclass(frozen=True, kw_only=True)
class Bias(Spike):
    """Constant offset: reading + magnitude, the spike's arithmetic under the name engineers
    use for a long one (e.g. a mis-rigged vane)."""

    kind: ClassVar[str] = "bias"


@dataclass(frozen=True, kw_only=True)
class Stuck(SensorFault):
    """The reading freezes: at `value` if given, else at the last reading before the fault."""

    kind: ClassVar[str] = "stuck"
    value: float | None = spec(None)

    def apply(self, value: float, t: float, held: float, rng: np.random.Generator) -> float:
        return held if self.value is None else self.value


@dataclass(frozen=True, kw_only=True)
class Dropout(SensorFault):
    """The sensor delivers nothing.  fill = "nan": no valid reading (the bus layer sends no
    value / marks it invalid, an offline consumer sees NaN); "zero": a dead sensor reading 0;
    "hold": the last reading is repeated (a stale value)."""

    kind: ClassVar[str] = "dropout"
    fill: str = spec("nan", choices=("nan", "zero", "hold"))

    def apply(self, value: float, t: float, held: float, rng: np.random.Generator) -> float:
        if self.fill == "zero":
            return 0.0
        if self.fill == "hold":
            return held
        return math.nan


@dataclass(frozen=True, kw_only=True)
class NoiseBurst(SensorFault):
    """Extra noise: uniform on [-magnitude, magnitude] or Gaussian with sigma = magnitude."""

    kind: ClassVar[str] = "noise_burst"
    magnitude: float = spec(gt=0.0)
    distribution: str = spec("uniform", choices=("uniform", "gaussian"))

    def apply(self, value: float, t: float, held: float, rng: np.random.Generator) -> float:
        if self.distribution == "gaussian":
            return value + float(rng.normal(0.0, self.magnitude))
        return value + float(rng.uniform(-self.magnitude, self.magnitude))


@dataclass(frozen=True, kw_only=True)
class Drift(SensorFault):
    """Growing offset: reading + rate * (t - start)  (units of the signal per second)."""

    kind: ClassVar[str] = "drift"
    rate: float = spec()

    def apply(self, value: float, t: float, held: float, rng: np.random.Generator) -> float:
        return value + self.rate * (t - self.start)


@dataclass(frozen=True, kw_only=True)
class Scale(SensorFault):
    """Gain error: reading * factor."""

    kind: ClassVar[str] = "scale"
    factor: float = spec()

    def apply(self, value: float, t: float, held: float, rng: np.random.Generator) -> float:
        return value * self.factor


# ---------------------------------------------------------------------------------------------
# frame level (applied by the bus layer; "frame" is a DBC message name or "*" for every
# frame the simulator sends for this aircraft)
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True, kw_only=True)
class FrameFault(Fault):
    level: ClassVar[str] = "frame"
    frame: str = spec("*")

    @property
    def target(self) -> str:
        return self.frame


@dataclass(frozen=True, kw_only=True)
class FrameLoss(FrameFault):
    """Each frame is not sent, with this probability (1: all lost)."""

    kind: ClassVar[str] = "loss"
    probability: float = spec(1.0, gt=0.0, le=1.0)


@dataclass(frozen=True, kw_only=True)
class FrameDelay(FrameFault):
    """Each frame is sent `delay` seconds late (lockstep: after the tick it belongs to)."""

    kind: ClassVar[str] = "delay"
    delay: float = spec(gt=0.0)


@dataclass(frozen=True, kw_only=True)
class FrameDuplicate(FrameFault):
    """Each frame is sent `count` extra times, unchanged (same counter: E2E REPEATED)."""

    kind: ClassVar[str] = "duplicate"
    count: int = spec(1, ge=1, le=16)


@dataclass(frozen=True, kw_only=True)
class FrameReplay(FrameFault):
    """Instead of the current frame, the one sent `age` seconds earlier is sent again
    (old counter and CRC: a replay/stale-data attack; E2E WRONG-SEQUENCE or REPEATED)."""

    kind: ClassVar[str] = "replay"
    age: float = spec(gt=0.0)


@dataclass(frozen=True, kw_only=True)
class BadCrc(FrameFault):
    """The E2E CRC byte is corrupted, with this probability (E2E ERROR)."""

    kind: ClassVar[str] = "bad_crc"
    probability: float = spec(1.0, gt=0.0, le=1.0)


@dataclass(frozen=True, kw_only=True)
class CounterFreeze(FrameFault):
    """The alive counter stops at its value at the start (E2E REPEATED every frame)."""

    kind: ClassVar[str] = "counter_freeze"


@dataclass(frozen=True, kw_only=True)
class CounterJump(FrameFault):
    """`jump` is added (mod 16) to the alive counter while active: one jump at the start and
    one back at the end (E2E OK-SOME-LOST or WRONG-SEQUENCE, depending on the size)."""

    kind: ClassVar[str] = "counter_jump"
    jump: int = spec(5, ge=1, le=15)


@dataclass(frozen=True, kw_only=True)
class WrongDlc(FrameFault):
    """The frame is sent with this data length (bytes) instead of its DBC length."""

    kind: ClassVar[str] = "wrong_dlc"
    dlc: int = spec(4, ge=0, le=8)


@dataclass(frozen=True, kw_only=True)
class OutOfRange(FrameFault):
    """Signal `signal` (a DBC signal of the frame) carries raw value `raw`, outside its DBC
    range; without `raw`, the largest raw value the field can hold."""

    kind: ClassVar[str] = "out_of_range"
    signal: str = spec()
    raw: int | None = spec(None)


# ---------------------------------------------------------------------------------------------
# bus level
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True, kw_only=True)
class BusFault(Fault):
    level: ClassVar[str] = "bus"


@dataclass(frozen=True, kw_only=True)
class Flood(BusFault):
    """A babbling node sends frames with `can_id` (default 0: the highest priority) at
    `rate_hz`, `dlc` bytes of 0xFF each."""

    kind: ClassVar[str] = "flood"
    can_id: int = spec(0, ge=0, le=0x7FF)
    rate_hz: float = spec(2000.0, gt=0.0, le=20000.0)
    dlc: int = spec(8, ge=0, le=8)


@dataclass(frozen=True, kw_only=True)
class Silence(BusFault):
    """The simulator sends nothing at all (its node is off the bus)."""

    kind: ClassVar[str] = "silence"


@dataclass(frozen=True, kw_only=True)
class BusLoad(BusFault):
    """Background traffic from another node on the wire-time bus (--bus wire, lockstep or
    realtime): periodic 8-byte frames on identifiers spread evenly over [id_lo, id_hi] (at most
    16 of them), filling `utilisation` of the bus with their worst-case frame times; phases and
    data from the scenario's seed in lockstep, from the fault's place in realtime
    (firmware/tools/canbus/canbus_load.h)."""

    kind: ClassVar[str] = "bus_load"
    utilisation: float = spec(0.5, gt=0.0, le=1.0)
    id_lo: int = spec(0x200, ge=0, le=0x7FF)
    id_hi: int = spec(0x6FF, ge=0, le=0x7FF)

    def __post_init__(self) -> None:
        if self.id_lo > self.id_hi:
            raise ValueError(f"field 'id_lo': {self.id_lo:#x} above id_hi {self.id_hi:#x}")


# ---------------------------------------------------------------------------------------------
# wire level (canbus's: docs/bus-timing.md "Faults"; times from the flight's start)
# ---------------------------------------------------------------------------------------------
#: the rig's nodes that send on the wire (the recorder only listens)
WIRE_SENDERS = ("sim", "fcc")


@dataclass(frozen=True, kw_only=True)
class WireFault(Fault):
    level: ClassVar[str] = "wire"


@dataclass(frozen=True, kw_only=True)
class BusError(WireFault):
    """Error frames: each frame of `frame` (a DBC message, '*' every frame) sent by `node`
    (sim, fcc, '*' either) that starts while active, every `every`-th of them and at most
    `count` (0: no limit), is disturbed at bit `bit` from its SOF (-1: its CRC delimiter);
    error flag, `superposed` more flag bits, delimiter and interframe space follow, and its
    sender retransmits it (TEC +8, the others' REC +1)."""

    kind: ClassVar[str] = "bus_error"
    frame: str = spec("*")
    node: str = spec("*", choices=("*", *WIRE_SENDERS))
    every: int = spec(1, ge=1, le=1_000_000)
    count: int = spec(0, ge=0, le=1_000_000_000)
    bit: int = spec(-1, ge=-1, le=42)
    superposed: int = spec(0, ge=0, le=6)

    @property
    def target(self) -> str:
        return self.frame


@dataclass(frozen=True, kw_only=True)
class BabblingNode(WireFault):
    """A controller of its own on the wire sends `can_id` (`dlc` bytes 0xFF) `rate_hz` times a
    second, or back to back (rate_hz = 0): it wins every arbitration against higher
    identifiers (lower priority) and starves them."""

    kind: ClassVar[str] = "babbling_node"
    can_id: int = spec(0, ge=0, le=0x7FF)
    rate_hz: float = spec(0.0, ge=0.0, le=1e6)
    dlc: int = spec(8, ge=0, le=8)


@dataclass(frozen=True, kw_only=True)
class BusOff(WireFault):
    """`node`'s frames are disturbed from `start` until its TEC exceeds 255 (the 32nd error in
    a row): bus-off, its queue dropped as SocketCAN drops it; it recovers after 128 x 11
    recessive bits."""

    kind: ClassVar[str] = "bus_off"
    duration: float = spec(math.inf, gt=0.0, allow_inf=True)
    node: str = spec("fcc", choices=WIRE_SENDERS)

    @property
    def target(self) -> str:
        return self.node


#: every fault kind, by name
KINDS: dict[str, type[Fault]] = {
    c.kind: c for c in (Spike, Bias, Stuck, Dropout, NoiseBurst, Drift, Scale,
                        FrameLoss, FrameDelay, FrameDuplicate, FrameReplay, BadCrc,
                        CounterFreeze, CounterJump, WrongDlc, OutOfRange, Flood, Silence,
                        BusError, BabblingNode, BusOff, BusLoad)
}
SENSOR_KINDS = tuple(k for k, c in KINDS.items() if c.level == "sensor")
FRAME_KINDS = tuple(k for k, c in KINDS.items() if c.level == "frame")
BUS_KINDS = tuple(k for k, c in KINDS.items() if c.level == "bus")
WIRE_KINDS = tuple(k for k, c in KINDS.items() if c.level == "wire")
