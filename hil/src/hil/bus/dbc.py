"""The DBC as the bus layer sees it: messages, E2E parameters, raw limits.

Everything that both codecs must agree on (the raw range of each signal, the
E2E data ID, the maximum counter delta, which signals are integers) is derived
here, once, from dbc/fcc_hil.dbc.  The C glue generator (hil.bus.cgen) and the
Python codec (hil.bus.codec) both call these functions.
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import cantools
from cantools.database.can import Database, Message, Signal

from ..rounding import round_half_away
from .e2e import DEFAULT_MAX_DELTA_COUNTER

#: the DBC shipped with the package (in the source tree a link to dbc/fcc_hil.dbc, the one
#: source; a wheel holds a copy, tests/python/test_install.py checks it equals the source)
PACKAGED_DBC = Path(__file__).resolve().parents[1] / "data" / "fcc_hil.dbc"
DEFAULT_DBC = PACKAGED_DBC
DBC_ENV = "FCC_HIL_DBC"
_dbc_override: Path | None = None
E2E_SIGNALS = ("crc", "counter")


@dataclass(frozen=True)
class SignalSpec:
    """One signal: how raw and physical values relate, and the raw range allowed."""

    name: str
    start: int
    length: int
    signed: bool
    scale: float
    offset: float
    inv_scale: int          # raw = round(phys * inv_scale); 1 for integer signals
    raw_min: int            # the DBC minimum, in raw units
    raw_max: int            # the DBC maximum, in raw units
    unit: str

    @property
    def is_integer(self) -> bool:
        """True when the physical value is the raw integer itself."""
        return self.scale == 1 and self.offset == 0

    def to_raw(self, value: float) -> int:
        """Physical → raw, rounding like the C side (half away from zero)."""
        if self.is_integer:
            if isinstance(value, float) and not value.is_integer():
                raise ValueError(f"{self.name}: {value} is not an integer")
            return int(value)
        return round_half_away(value * self.inv_scale)

    def to_phys(self, raw: int) -> float | int:
        return raw if self.is_integer else raw / self.inv_scale


@dataclass(frozen=True)
class MessageSpec:
    name: str
    frame_id: int
    length: int
    cycle_ms: int           # 0 for event messages
    data_id: int            # 0: not E2E-protected
    max_delta_counter: int
    senders: tuple[str, ...]
    receivers: tuple[str, ...]
    signals: tuple[SignalSpec, ...]
    message: Message
    secoc_data_id: int = 0               # authenticator frames: the SecOC data ID of the MAC
    secoc_pdus: tuple[str, ...] = ()     # authenticator frames: the frames it authenticates

    @property
    def is_authenticator(self) -> bool:
        return self.secoc_data_id != 0

    @property
    def protected(self) -> bool:
        return self.data_id != 0

    @property
    def data_signals(self) -> tuple[SignalSpec, ...]:
        """The signals an application reads and writes (all but crc and counter)."""
        return tuple(s for s in self.signals if not (self.protected and s.name in E2E_SIGNALS))


def _attr(message: Message, name: str, default: int) -> int:
    attrs = message.dbc.attributes if message.dbc else {}
    return int(attrs[name].value) if name in attrs else default


def _str_attr(message: Message, name: str) -> str:
    attrs = message.dbc.attributes if message.dbc else {}
    return str(attrs[name].value) if name in attrs else ""


def _inv_scale(sig: Signal) -> int:
    if sig.scale == 1 and sig.offset == 0:
        return 1
    inv = 1.0 / sig.scale
    if sig.offset != 0 or abs(inv - round(inv)) > 1e-9 * inv:
        raise ValueError(f"{sig.name}: scale {sig.scale} must be 1/integer with offset 0")
    return int(round(inv))


def _signal_spec(sig: Signal) -> SignalSpec:
    if sig.byte_order != "little_endian" or sig.is_float or sig.is_multiplexer:
        raise ValueError(f"{sig.name}: only little-endian integer signals are supported")
    inv = _inv_scale(sig)
    lo_type = -(1 << (sig.length - 1)) if sig.is_signed else 0
    hi_type = (1 << (sig.length - 1)) - 1 if sig.is_signed else (1 << sig.length) - 1
    lo = lo_type if sig.minimum is None else max(lo_type, round_half_away(sig.minimum * inv))
    hi = hi_type if sig.maximum is None else min(hi_type, round_half_away(sig.maximum * inv))
    return SignalSpec(sig.name, sig.start, sig.length, sig.is_signed, sig.scale, sig.offset,
                      inv, lo, hi, sig.unit or "")


def _message_spec(msg: Message) -> MessageSpec:
    names = {s.name for s in msg.signals}
    data_id = _attr(msg, "E2E_DataID", 0)
    if data_id and not set(E2E_SIGNALS) <= names:
        raise ValueError(f"{msg.name}: E2E_DataID set but no crc/counter signals")
    receivers = sorted({r for s in msg.signals for r in s.receivers})
    return MessageSpec(
        name=msg.name, frame_id=msg.frame_id, length=msg.length,
        cycle_ms=int(msg.cycle_time or 0), data_id=data_id,
        max_delta_counter=_attr(msg, "E2E_MaxDeltaCounter", DEFAULT_MAX_DELTA_COUNTER),
        senders=tuple(msg.senders), receivers=tuple(receivers),
        signals=tuple(_signal_spec(s) for s in msg.signals), message=msg,
        secoc_data_id=_attr(msg, "SecOC_DataID", 0),
        secoc_pdus=tuple(_str_attr(msg, "SecOC_Pdus").split()))


class BusSpec:
    """The loaded DBC: messages sorted by identifier, nodes, bit rate."""

    def __init__(self, path: Path, db: Database, messages: tuple[MessageSpec, ...]) -> None:
        self.path = path
        self.db = db
        self.messages = messages
        self.nodes: tuple[str, ...] = tuple(n.name for n in db.nodes)
        bus = db.buses[0] if db.buses else None
        self.baudrate: int = int(bus.baudrate) if bus and bus.baudrate else 500_000
        self._by_id = {m.frame_id: m for m in messages}
        self._by_name = {m.name: m for m in messages}

    def by_id(self, frame_id: int) -> MessageSpec | None:
        return self._by_id.get(frame_id)

    def by_name(self, name: str) -> MessageSpec:
        try:
            return self._by_name[name]
        except KeyError:
            raise KeyError(f"no message {name!r} in {self.path.name}") from None


def set_default(path: Path | None) -> None:
    """The DBC given on the command line (--dbc): the default of every later load()."""
    global _dbc_override  # noqa: PLW0603 - one process-wide choice, made by the CLI
    _dbc_override = None if path is None else Path(path)


def default_path() -> Path:
    """--dbc, else $FCC_HIL_DBC, else the packaged DBC."""
    if _dbc_override is not None:
        return _dbc_override
    env = os.environ.get(DBC_ENV)
    return Path(env).expanduser() if env else PACKAGED_DBC


def load(path: str | Path | None = None) -> BusSpec:
    """Load and check the DBC (strict): every message 8 bytes, standard IDs.
    No path: the default (``default_path()``)."""
    return _load(Path(path) if path is not None else default_path())


@lru_cache(maxsize=8)
def _load(path: Path) -> BusSpec:
    if not path.is_file():
        raise FileNotFoundError(f"DBC file {path} does not exist")
    db = cantools.database.load_file(str(path), strict=True)
    messages = tuple(sorted((_message_spec(m) for m in db.messages), key=lambda m: m.frame_id))
    for m in messages:
        if m.length != 8 or m.message.is_extended_frame or m.frame_id > 0x7FF:
            raise ValueError(f"{m.name}: only 8-byte frames with 11-bit IDs are supported")
    names = {m.name for m in messages}
    for m in messages:
        if m.is_authenticator and (not m.secoc_pdus or not set(m.secoc_pdus) <= names):
            raise ValueError(f"{m.name}: SecOC_Pdus must name the frames it authenticates")
    return BusSpec(path, db, messages)
