"""Frame codec of one bus node: physical values <-> 8-byte frames, with E2E and checks.

The Python twin of firmware/bus/fcc_bus.c (same order of checks, same counters):
a received frame is 1) of a known identifier this node consumes, 2) 8 bytes long,
3) E2E-usable (protected messages), 4) inside the DBC range -- or rejected with
its own counter.  Encoding refuses NaN/Inf and out-of-range values (or clamps
finite ones with saturate=True) and E2E-protects with the message's own counter.
No I/O here: hil.bus.node puts this on python-can.
"""
from __future__ import annotations

import enum
import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field

from hil.bus import dbc
from hil.bus.e2e import E2EReceiver, E2ESender, E2EStatus
from hil.util.errors import HilError

Value = float | int


class Verdict(enum.IntEnum):
    """Why a received frame was not passed on; values equal fcc_bus_verdict_t."""

    PASS = 0
    UNKNOWN_ID = 1
    WRONG_DLC = 2
    E2E = 3
    OUT_OF_RANGE = 4


class EncodeError(HilError, ValueError):
    """A value cannot be encoded (not finite, out of range, missing, not ours)."""


@dataclass(slots=True)
class Decoded:
    """One received frame after the checks; values is None unless verdict is PASS."""

    frame_id: int
    name: str | None
    verdict: Verdict
    e2e: E2EStatus
    values: dict[str, Value] | None
    timestamp: float = 0.0
    data: bytes = b""       # the frame's bytes (BusNode fills it in)

    @property
    def ok(self) -> bool:
        return self.verdict is Verdict.PASS


@dataclass
class Counters:
    e2e: dict[E2EStatus, int] = field(default_factory=lambda: dict.fromkeys(E2EStatus, 0))
    unknown_id: int = 0
    wrong_dlc: int = 0
    out_of_range: int = 0
    tx_refused: int = 0
    tx_saturated: int = 0
    stale_now: int = 0


# ---- stateless helpers ---------------------------------------------------------

def _value_to_raw(sig: dbc.SignalSpec, value: Value, saturate: bool) -> tuple[int, bool]:
    if type(value) is float or type(value) is int:   # noqa: E721 - the usual case, no bool or numpy
        pass
    elif isinstance(value, bool):
        value = int(value)
    elif not isinstance(value, (int, float)):
        raise EncodeError(f"{sig.name}: {value!r} is not a number")
    if sig.is_integer:
        if isinstance(value, float) and not value.is_integer():   # NaN and Inf are not either
            raise EncodeError(f"{sig.name}: {value} is not " +
                              ("finite" if not math.isfinite(value) else "an integer"))
        raw = int(value)
    elif isinstance(value, float) and not math.isfinite(value):
        raise EncodeError(f"{sig.name}: {value} is not finite")
    else:
        raw = _scaled_raw(sig, float(value))
    if sig.raw_min <= raw <= sig.raw_max:
        return raw, False
    if not saturate:
        raise EncodeError(f"{sig.name}: {value} is outside the DBC range "
                          f"[{sig.to_phys(sig.raw_min)}, {sig.to_phys(sig.raw_max)}]")
    return (sig.raw_min if raw < sig.raw_min else sig.raw_max), True


def _scaled_raw(sig: dbc.SignalSpec, value: float) -> int:
    x = value * sig.inv_scale
    if not math.isfinite(x):  # overflow: certainly out of range
        return sig.raw_max + 1 if x > 0 else sig.raw_min - 1
    return dbc.round_half_away(x)


def pack(msg: dbc.MessageSpec, values: Mapping[str, Value], *,
         saturate: bool = False) -> tuple[bytes, bool]:
    """Physical values -> 8 bytes with crc = counter = 0; returns (bytes, clamped)."""
    bits = 0
    clamped = False
    for sig in msg.data_signals:
        if sig.name not in values:
            raise EncodeError(f"{msg.name}: signal {sig.name} missing")
        raw, c = _value_to_raw(sig, values[sig.name], saturate)
        bits |= sig.pack(raw)
        clamped |= c
    if len(values) != len(msg.data_signals):   # every data signal is there: others too
        unknown = set(values) - {s.name for s in msg.data_signals}
        raise EncodeError(f"{msg.name}: no signal(s) {sorted(unknown)}")
    return bits.to_bytes(msg.length, "little"), clamped


def decode_values(msg: dbc.MessageSpec, data: bytes) -> dict[str, Value] | None:
    """8 bytes -> physical values of the data signals; None when a raw value is out of range."""
    fields = msg.data_fields
    out: dict[str, Value] = {}
    for f, r in zip(fields, msg.raw_values(bytes(data), fields)):
        if not f.raw_min <= r <= f.raw_max:
            return None
        out[f.name] = r / f.inv_scale if f.inv_scale else r
    return out


# ---- one node --------------------------------------------------------------------

class FrameCodec:
    """Encoder/decoder state of one node (E2E counters and receivers, rejection counts)."""

    def __init__(self, spec: dbc.BusSpec | None = None,
                 nodes: str | Iterable[str] | None = None, *,
                 consumes: Iterable[str] | None = None,
                 produces: Iterable[str] | None = None) -> None:
        """nodes: the DBC node(s) this codec speaks for (None: every message both ways);
        consumes/produces override the message sets derived from them."""
        self.spec = spec or dbc.load()
        node_set = None if nodes is None else ({nodes} if isinstance(nodes, str) else set(nodes))
        for n in node_set or ():
            if n not in self.spec.nodes:
                raise ValueError(f"no node {n!r} in {self.spec.path.name}")
        names = [m.name for m in self.spec.messages]
        self.consumes = set(consumes) if consumes is not None else {
            m.name for m in self.spec.messages
            if node_set is None or node_set & set(m.receivers)}
        self.produces = set(produces) if produces is not None else {
            m.name for m in self.spec.messages
            if node_set is None or node_set & set(m.senders)}
        for n in self.consumes | self.produces:
            if n not in names:
                raise ValueError(f"no message {n!r} in {self.spec.path.name}")
        self.receivers = {m.name: E2EReceiver(m.data_id, m.max_delta_counter)
                          for m in self.spec.messages if m.protected}
        self.senders = {m.name: E2ESender(m.data_id) for m in self.spec.messages if m.protected}
        self.counters = Counters()

    # -- transmit
    def encode(self, name: str, values: Mapping[str, Value], *,
               saturate: bool = False) -> tuple[int, bytes]:
        """(CAN ID, protected 8 bytes) of a message this node produces."""
        try:
            if name not in self.produces:
                raise EncodeError(f"this node does not send {name}")
            msg = self.spec.by_name(name)
            data, clamped = pack(msg, values, saturate=saturate)
        except (EncodeError, KeyError):
            self.counters.tx_refused += 1
            raise
        if clamped:
            self.counters.tx_saturated += 1
        if msg.protected:
            data = self.senders[name].protect(data)
        return msg.frame_id, data

    # -- receive
    def decode(self, frame_id: int, data: bytes | bytearray, timestamp: float = 0.0, *,
               extended: bool = False) -> Decoded:
        """Check and decode one frame (extended, remote or FD frames: pass extended=True)."""
        msg = None if extended else self.spec.by_id(frame_id)
        if msg is None or msg.name not in self.consumes:
            self.counters.unknown_id += 1
            return Decoded(frame_id, msg.name if msg else None, Verdict.UNKNOWN_ID,
                           E2EStatus.OK, None, timestamp)
        if len(data) != msg.length:
            self.counters.wrong_dlc += 1
            return Decoded(frame_id, msg.name, Verdict.WRONG_DLC, E2EStatus.OK, None, timestamp)
        status = self._e2e(msg, data)
        if not status.data_usable:
            return Decoded(frame_id, msg.name, Verdict.E2E, status, None, timestamp)
        values = decode_values(msg, bytes(data))
        if values is None:
            self.counters.out_of_range += 1
            return Decoded(frame_id, msg.name, Verdict.OUT_OF_RANGE, status, None, timestamp)
        return Decoded(frame_id, msg.name, Verdict.PASS, status, values, timestamp)

    def usable(self, msg: dbc.MessageSpec, data: bytes) -> bool:
        """decode()'s checks of a frame of msg, a message this node consumes, short of the range
        check (in_range()), counted as decode() counts them: its length, then its E2E class.
        For a caller that reads a few fields itself (the lockstep loop's acknowledgement, once
        a step)."""
        if len(data) != msg.length:
            self.counters.wrong_dlc += 1
            return False
        return self._e2e(msg, data).data_usable

    def in_range(self, msg: dbc.MessageSpec, data: bytes) -> bool:
        """decode()'s range check of a frame that usable() passed, counted as decode() counts it."""
        if decode_values(msg, bytes(data)) is None:
            self.counters.out_of_range += 1
            return False
        return True

    def _e2e(self, msg: dbc.MessageSpec, data: bytes | bytearray) -> E2EStatus:
        """The E2E class of a received frame of msg (OK when it is not protected), counted."""
        if not msg.protected:
            return E2EStatus.OK
        status = self.receivers[msg.name].check(bytes(data))
        self.counters.e2e[status] += 1
        return status

    def end_period(self, name: str) -> bool:
        """Close a receive period of a consumed protected message; True if it had no frame."""
        rx = self.receivers.get(name)
        if rx is None or name not in self.consumes:
            return False
        stale = rx.end_period()
        if stale:
            self.counters.e2e[E2EStatus.NO_NEW_DATA] += 1
        self.counters.stale_now = sum(
            1 for n, r in self.receivers.items() if n in self.consumes and r.stale)
        return stale
