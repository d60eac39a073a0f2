"""End-to-end protection of CAN frames (one specification with firmware/bus/fcc_e2e.h).

The specification is written down in dbc/README.md ("E2E"); in short:

* byte 0 of a protected frame is a CRC-8 SAE J1850 (poly 0x1D, init 0xFF,
  xorout 0xFF, not reflected; check value 0x4B over b"123456789") computed over
  the message's 16-bit data ID (low byte, then high byte) followed by bytes 1..7;
* the low nibble of byte 1 is a 4-bit alive counter, +1 modulo 16 per frame;
* the receiver classifies every frame as OK, REPEATED, OK_SOME_LOST,
  WRONG_SEQUENCE or ERROR, and every period without any frame as NO_NEW_DATA.
"""
from __future__ import annotations

import enum
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np

CRC8_POLY = 0x1D
CRC8_INIT = 0xFF
CRC8_XOROUT = 0xFF
COUNTER_MODULO = 16
DEFAULT_MAX_DELTA_COUNTER = 3
FRAME_LENGTH = 8


def _make_table() -> tuple[int, ...]:
    table = []
    for byte in range(256):
        crc = byte
        for _ in range(8):
            crc = ((crc << 1) ^ CRC8_POLY) & 0xFF if crc & 0x80 else (crc << 1) & 0xFF
        table.append(crc)
    return tuple(table)


_TABLE = _make_table()


def crc8_j1850(data: bytes | bytearray, crc: int = CRC8_INIT, final_xor: bool = True) -> int:
    """CRC-8 SAE J1850 of data.  crc8_j1850(b"123456789") == 0x4B."""
    for byte in data:
        crc = _TABLE[crc ^ byte]
    return crc ^ CRC8_XOROUT if final_xor else crc


def crc_seed(data_id: int) -> int:
    """The E2E CRC's state after the data ID (low, high): where every frame of that message
    starts (a receiver keeps it)."""
    if not 0 <= data_id <= 0xFFFF:
        raise ValueError(f"E2E data ID {data_id} is not a 16-bit value")
    return _TABLE[_TABLE[CRC8_INIT ^ (data_id & 0xFF)] ^ (data_id >> 8)]


def _crc_from(seed: int, p: bytes | bytearray) -> int:
    """The E2E CRC of 8-byte frame p from its data ID's seed: over bytes 1..7 (unrolled
    crc8_j1850: this runs for every frame the lockstep loop sends or checks)."""
    t = _TABLE
    return t[t[t[t[t[t[t[seed ^ p[1]] ^ p[2]] ^ p[3]] ^ p[4]] ^ p[5]] ^ p[6]] ^ p[7]] ^ CRC8_XOROUT


def frame_crc(data_id: int, payload: bytes | bytearray) -> int:
    """The E2E CRC of an 8-byte frame: over data ID (low, high) and bytes 1..7."""
    if len(payload) != FRAME_LENGTH:
        raise ValueError(f"E2E frames are {FRAME_LENGTH} bytes, not {len(payload)}")
    return _crc_from(crc_seed(data_id), payload)


def protect(data_id: int, payload: bytes | bytearray, counter: int) -> bytes:
    """Write counter into the low nibble of byte 1 and the CRC into byte 0."""
    if not 0 <= counter < COUNTER_MODULO:
        raise ValueError(f"alive counter {counter} is not in 0..15")
    frame = bytearray(payload)
    if len(frame) != FRAME_LENGTH:
        raise ValueError(f"E2E frames are {FRAME_LENGTH} bytes, not {len(frame)}")
    frame[1] = (frame[1] & 0xF0) | counter
    frame[0] = frame_crc(data_id, frame)
    return bytes(frame)


def protect_many(data_id: int, payloads: np.ndarray, counters: np.ndarray) -> np.ndarray:
    """protect() of many frames of one message at once: payloads (n, 8) uint8, counters (n,)
    -> the protected frames (n, 8) uint8 (the ticks of a lockstep flight, hil.rig.tickplan:
    held equal to protect() by the tests)."""
    import numpy as np  # here: the bus layer is imported without numpy where it needs none

    if payloads.ndim != 2 or payloads.shape[1] != FRAME_LENGTH or payloads.dtype != np.uint8:
        raise ValueError(f"E2E frames are {FRAME_LENGTH} bytes: expected an (n, 8) uint8 array")
    counters = np.asarray(counters)
    if counters.size and not (counters.min() >= 0 and counters.max() < COUNTER_MODULO):
        raise ValueError("alive counters must be in 0..15")
    table = np.array(_TABLE, dtype=np.uint8)
    frames = payloads.copy()
    frames[:, 1] = (frames[:, 1] & 0xF0) | counters.astype(np.uint8)
    crc = np.full(len(frames), crc_seed(data_id), np.uint8)
    for j in range(1, FRAME_LENGTH):
        crc = table[crc ^ frames[:, j]]
    frames[:, 0] = crc ^ CRC8_XOROUT
    return frames


def counter_of(payload: bytes | bytearray) -> int:
    return payload[1] & 0x0F


class E2EStatus(enum.IntEnum):
    """Receiver classification; values equal the C enum fcc_e2e_status_t."""

    OK = 0
    REPEATED = 1
    OK_SOME_LOST = 2
    WRONG_SEQUENCE = 3
    ERROR = 4
    NO_NEW_DATA = 5

    @property
    def data_usable(self) -> bool:
        """True for the classes whose data may be used (OK and OK_SOME_LOST)."""
        return self in _USABLE


#: the classes whose data may be used (a set of the members: checked for every frame received)
_USABLE = frozenset((E2EStatus.OK, E2EStatus.OK_SOME_LOST))


@dataclass
class E2ESender:
    """Sender state of one message: its data ID and the next alive counter."""

    data_id: int
    counter: int = 0

    def protect(self, payload: bytes | bytearray) -> bytes:
        frame = protect(self.data_id, payload, self.counter)
        self.counter = (self.counter + 1) % COUNTER_MODULO
        return frame


#: the classes as module names: reading a member off the enum class costs CPython 3.11 ten
#: times a global's lookup, and the receiver classifies every frame the lockstep loop checks
_OK, _REPEATED, _OK_SOME_LOST, _WRONG_SEQUENCE, _ERROR = (
    E2EStatus.OK, E2EStatus.REPEATED, E2EStatus.OK_SOME_LOST, E2EStatus.WRONG_SEQUENCE, E2EStatus.ERROR)


@dataclass
class E2EReceiver:
    """Receiver state machine of one message (see dbc/README.md, "E2E receiver")."""

    data_id: int
    max_delta_counter: int = DEFAULT_MAX_DELTA_COUNTER
    synced: bool = False
    last_counter: int = 0
    frames_this_period: int = 0
    last_status: E2EStatus = E2EStatus.NO_NEW_DATA
    stale: bool = False
    lost_frames: int = 0
    counts: dict[E2EStatus, int] = field(default_factory=lambda: dict.fromkeys(E2EStatus, 0))
    _seed: int = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not 1 <= self.max_delta_counter < COUNTER_MODULO - 1:
            raise ValueError(f"max delta counter {self.max_delta_counter} is not in 1..14")
        self._seed = crc_seed(self.data_id)

    def check(self, payload: bytes | bytearray) -> E2EStatus:
        """Classify one received 8-byte frame and update the state."""
        self.frames_this_period += 1
        status = self._classify(payload)
        self.counts[status] += 1
        self.last_status = status
        return status

    def _classify(self, payload: bytes | bytearray) -> E2EStatus:
        if len(payload) != FRAME_LENGTH or payload[0] != _crc_from(self._seed, payload):
            return _ERROR
        counter = counter_of(payload)
        if not self.synced:
            self.synced, self.last_counter = True, counter
            return _OK
        delta = (counter - self.last_counter) % COUNTER_MODULO
        if delta == 0:
            return _REPEATED
        self.last_counter = counter
        if delta == 1:
            return _OK
        if delta <= self.max_delta_counter:
            self.lost_frames += delta - 1
            return _OK_SOME_LOST
        return _WRONG_SEQUENCE

    def end_period(self) -> bool:
        """Close one receive period; True (and a NO_NEW_DATA count) if it had no frame."""
        self.stale = self.frames_this_period == 0
        if self.stale:
            self.counts[E2EStatus.NO_NEW_DATA] += 1
            self.last_status = E2EStatus.NO_NEW_DATA
        self.frames_this_period = 0
        return self.stale

    def reset(self) -> None:
        """Forget the counter history: the next valid frame is OK again."""
        self.synced = False
        self.frames_this_period = 0
