"""The DBC as the bus layer sees it: messages, E2E parameters, raw limits.

Everything that both codecs must agree on (the raw range of each signal, the
E2E data ID, the maximum counter delta, which signals are integers) is derived
here, once, from dbc/fcc_hil.dbc.  The C glue generator (hil.bus.cgen) and the
Python codec (hil.bus.codec) both call these functions.

Start-up: cantools (and the python-can it imports) costs more to import than a lockstep
flight takes in the UML guest, so the packaged DBC's specification is also kept digested in
``data/fcc_hil.spec.json`` (written by dbc/generate: ``python -m hil.bus.digest``).  ``load()``
uses it when the DBC's bytes are the ones it was made from (length and CRC-32 recorded in
it); any other DBC, or a DBC edited since, is parsed by cantools.  Frames are packed and
unpacked here (little-endian integer signals only, checked when parsing); the cantools
``Message`` of a message (``MessageSpec.message``: comments, cantools' own codec) is parsed
on first use.

Why this module is long: the one reading of the DBC -- messages, signals, their E2E and
SecOC attributes and, since issue 36, each frame's application (FccApp) -- kept together so that
the C generator, the Python codec and the digest cannot read the same file two ways.
"""
from __future__ import annotations

import json
import os
import zlib
from dataclasses import asdict, dataclass
from functools import cached_property, lru_cache
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple

from hil.bus.dbcfile import DbcError, DbcMissing, parse_dbc, read_dbc
from hil.bus.e2e import DEFAULT_MAX_DELTA_COUNTER
from hil.util.rounding import round_half_away

if TYPE_CHECKING:
    from cantools.database.can import Database, Message, Signal

#: the DBC shipped with the package (in the source tree a link to dbc/fcc_hil.dbc, the one
#: source; a wheel holds a copy, tests/python/cli/test_install.py checks it equals the source)
PACKAGED_DBC = Path(__file__).resolve().parents[1] / "data" / "fcc_hil.dbc"
#: the packaged DBC digested (dbc/generate writes it from dbc/fcc_hil.dbc)
PACKAGED_SPEC = PACKAGED_DBC.with_name("fcc_hil.spec.json")
SPEC_FORMAT = 4   # 2: the value tables (VAL_) of the signals; 3: FccApp of the messages; 4: FccDiagnostic
DEFAULT_DBC = PACKAGED_DBC
DBC_ENV = "FCC_HIL_DBC"
_dbc_override: Path | None = None
E2E_SIGNALS = ("crc", "counter")
#: the message attribute naming the application of fcc a frame belongs to (ENUM, "none" first)
APP_ATTRIBUTE = "FccApp"
#: the message attribute declaring a frame of fcc's that no part of the rig reads (ENUM no/yes)
DIAGNOSTIC_ATTRIBUTE = "FccDiagnostic"
#: the flight computer's node: the receiver of the applications' inputs
FCC_NODE = "FCC"


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
    #: the DBC's value table (VAL_) of the signal: (name, raw value) in the order of the values
    choices: tuple[tuple[str, int], ...] = ()

    @cached_property
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

    def scaled(self, raw: int) -> float | int:
        """The DBC's physical value of a raw one (raw * scale + offset, as cantools decodes)."""
        return raw if self.is_integer else raw * self.scale + self.offset

    def unpack(self, bits: int) -> int:
        """This signal's raw value in the frame's bytes read as one little-endian integer."""
        v = (bits >> self.start) & ((1 << self.length) - 1)
        return v - (1 << self.length) if self.signed and v >> (self.length - 1) else v

    def pack(self, raw: int) -> int:
        """raw in place in the frame's little-endian integer (raw must fit the signal)."""
        lo = -(1 << (self.length - 1)) if self.signed else 0
        if not lo <= raw < lo + (1 << self.length):
            raise ValueError(f"{self.name}: raw value {raw} does not fit {self.length} bits")
        return (raw & ((1 << self.length) - 1)) << self.start


class Field(NamedTuple):
    """A signal as the codecs' inner loops use it (no method calls there)."""

    name: str
    start: int
    mask: int
    sign: int      # the sign bit of a signed signal, 0 for an unsigned one
    raw_min: int
    raw_max: int
    inv_scale: int  # 0 for an integer signal (its physical value is the raw one)

    @classmethod
    def of(cls, s: SignalSpec) -> Field:
        return cls(s.name, s.start, (1 << s.length) - 1, 1 << (s.length - 1) if s.signed else 0,
                   s.raw_min, s.raw_max, 0 if s.is_integer else s.inv_scale)


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
    secoc_data_id: int = 0               # authenticator frames: the SecOC data ID of the MAC
    secoc_pdus: tuple[str, ...] = ()     # authenticator frames: the frames it authenticates
    app: str = ""                        # FccApp: the application of fcc it belongs to, or ""
    diagnostic: bool = False             # FccDiagnostic: sent by fcc for people, read by no rig part
    dbc_path: Path | None = None         # where .message is parsed from

    @property
    def message(self) -> Message:
        """cantools' Message (parsed on first use: comments, cantools' codec)."""
        if self.dbc_path is None:
            raise ValueError(f"{self.name}: no DBC to parse")
        return parse_dbc(self.dbc_path).get_message_by_name(self.name)

    def signal(self, name: str) -> SignalSpec:
        """The signal of that name."""
        for sig in self.signals:
            if sig.name == name:
                return sig
        raise DbcMissing(f"{self.dbc_path or 'the DBC'}: {self.name} has no signal {name!r}")

    def encode_raw(self, raw: dict[str, int]) -> bytes:
        """Raw values of every signal -> the 8 bytes."""
        bits = 0
        for s in self.signals:
            bits |= s.pack(int(raw[s.name]))
        return bits.to_bytes(self.length, "little")

    def decode_raw(self, data: bytes) -> dict[str, int]:
        """The frame's bytes -> every signal's raw value."""
        return dict(zip([f.name for f in self.fields], self.raw_values(data, self.fields)))

    def raw_values(self, data: bytes, fields: tuple[Field, ...]) -> list[int]:
        """The raw values of these fields of the frame's bytes (SignalSpec.unpack of each,
        inlined: the lockstep loop decodes every tick and acknowledgement)."""
        if len(data) != self.length:
            raise ValueError(f"{self.name}: {len(data)} bytes, expected {self.length}")
        bits = int.from_bytes(data, "little")
        return [(v := (bits >> f.start) & f.mask) - ((v & f.sign) << 1) for f in fields]

    @cached_property
    def fields(self) -> tuple[Field, ...]:
        """Every signal's field."""
        return tuple(Field.of(s) for s in self.signals)

    @cached_property
    def data_fields(self) -> tuple[Field, ...]:
        """The data signals' fields."""
        return tuple(Field.of(s) for s in self.data_signals)

    def decode(self, data: bytes) -> dict[str, float | int]:
        """The frame's bytes -> every signal's physical value (as cantools' decode)."""
        raw = self.decode_raw(data)
        return {s.name: s.scaled(raw[s.name]) for s in self.signals}

    def encode(self, values: dict[str, int]) -> bytes:
        """Integer signals' values -> the 8 bytes (scaled signals go through the codec)."""
        for s in self.signals:
            if not s.is_integer:
                raise ValueError(f"{self.name}: {s.name} is scaled: encode through hil.bus.codec")
        return self.encode_raw(values)

    @property
    def is_authenticator(self) -> bool:
        return self.secoc_data_id != 0

    @property
    def protected(self) -> bool:
        return self.data_id != 0

    @cached_property
    def data_signals(self) -> tuple[SignalSpec, ...]:
        """The signals an application reads and writes (all but crc and counter)."""
        return tuple(s for s in self.signals if not (self.protected and s.name in E2E_SIGNALS))


def _attr(message: Message, name: str, default: int) -> int:
    attrs = message.dbc.attributes if message.dbc else {}
    return int(attrs[name].value) if name in attrs else default


def _str_attr(message: Message, name: str) -> str:
    attrs = message.dbc.attributes if message.dbc else {}
    return str(attrs[name].value) if name in attrs else ""


def _enum_attr(message: Message, name: str) -> str:
    """An ENUM attribute's choice ("" when unset or its first choice, "none")."""
    attrs = message.dbc.attributes if message.dbc else {}
    if name not in attrs:
        return ""
    attr = attrs[name]
    value = attr.value
    if isinstance(value, int) and attr.definition.choices:
        value = attr.definition.choices[value]
    return "" if value == attr.definition.choices[0] else str(value)


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
    choices = tuple((str(name), int(value)) for value, name in sorted((sig.choices or {}).items()))
    return SignalSpec(sig.name, sig.start, sig.length, sig.is_signed, sig.scale, sig.offset,
                      inv, lo, hi, sig.unit or "", choices)


def _message_spec(msg: Message, path: Path) -> MessageSpec:
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
        signals=tuple(_signal_spec(s) for s in msg.signals),
        secoc_data_id=_attr(msg, "SecOC_DataID", 0),
        secoc_pdus=tuple(_str_attr(msg, "SecOC_Pdus").split()), app=_enum_attr(msg, APP_ATTRIBUTE),
        diagnostic=_enum_attr(msg, DIAGNOSTIC_ATTRIBUTE) == "yes",
        dbc_path=path)


class BusSpec:
    """The loaded DBC: messages sorted by identifier, nodes, bit rate, fcc's applications
    (the choices of the FccApp attribute but "none", in order: the application ids)."""

    def __init__(self, path: Path, messages: tuple[MessageSpec, ...], nodes: tuple[str, ...],
                 baudrate: int, apps: tuple[str, ...] = ()) -> None:
        self.path = path
        self.apps = apps
        self.messages = messages
        self.nodes = nodes
        self.baudrate = baudrate
        self._by_id = {m.frame_id: m for m in messages}
        self._by_name = {m.name: m for m in messages}

    def by_id(self, frame_id: int) -> MessageSpec | None:
        return self._by_id.get(frame_id)

    def app_inputs(self, app: str) -> tuple[MessageSpec, ...]:
        """The frames sent to fcc (node FCC) that belong to an application (FccApp), in
        identifier order: the application's input slots."""
        return tuple(m for m in self.messages if m.app == app and FCC_NODE in m.receivers
                     and FCC_NODE not in m.senders)

    def by_name(self, name: str) -> MessageSpec:
        try:
            return self._by_name[name]
        except KeyError:
            raise DbcMissing(f"{self.path}: no message {name!r} (hil needs it)") from None

    @property
    def db(self) -> Database:
        """cantools' Database of the DBC (parsed on first use)."""
        return parse_dbc(self.path)


def set_default(path: Path | None) -> None:
    """The DBC given on the command line (--dbc): the default of every later load(), also
    in the processes the rig starts (through the environment)."""
    global _dbc_override  # noqa: PLW0603 - one process-wide choice, made by the CLI
    _dbc_override = None if path is None else Path(path)
    if _dbc_override is not None:
        os.environ[DBC_ENV] = str(_dbc_override.resolve())


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
    data = read_dbc(path)
    try:
        return _from_spec_file(path, data=data) or _parsed(path)
    except DbcError:
        raise
    except ValueError as e:  # a check of the bus layer's: name the file
        raise DbcError(f"{path}: {e}") from None


def check_contract(spec: BusSpec) -> None:
    """A DBC other than the packaged one names every message and signal of the packaged one
    (hil's simulator and evaluation use them by name; identifiers and layouts may differ):
    DbcMissing names the first one it lacks, before anything flies rather than mid-flight."""
    ours = _load(PACKAGED_DBC)
    for m in ours.messages:
        theirs = spec._by_name.get(m.name)
        if theirs is None:
            raise DbcMissing(f"{spec.path}: no message {m.name!r} (hil's bus has it: {PACKAGED_DBC.name})")
        for sig in m.signals:
            theirs.signal(sig.name)


def _parsed(path: Path) -> BusSpec:
    """The BusSpec of the DBC parsed by cantools, checked."""
    db = parse_dbc(path)
    messages = tuple(sorted((_message_spec(m, path) for m in db.messages), key=lambda m: m.frame_id))
    for m in messages:
        if m.length != 8 or m.message.is_extended_frame or m.frame_id > 0x7FF:
            raise ValueError(f"{m.name}: only 8-byte frames with 11-bit IDs are supported")
    names = {m.name for m in messages}
    for a, b in zip(messages, messages[1:]):
        if a.frame_id == b.frame_id:
            raise ValueError(f"{a.name} and {b.name} have the same identifier 0x{a.frame_id:03X}")
    for m in messages:
        if m.is_authenticator and (not m.secoc_pdus or not set(m.secoc_pdus) <= names):
            raise ValueError(f"{m.name}: SecOC_Pdus must name the frames it authenticates")
    bus = db.buses[0] if db.buses else None
    app_def = db.dbc.attribute_definitions.get(APP_ATTRIBUTE) if db.dbc else None
    apps = tuple(app_def.choices[1:]) if app_def is not None and app_def.choices else ()
    for m in messages:
        if m.app and m.app not in apps:
            raise ValueError(f"{m.name}: {APP_ATTRIBUTE} {m.app!r} is not an application")
    return BusSpec(path, messages, tuple(n.name for n in db.nodes),
                   int(bus.baudrate) if bus and bus.baudrate else 500_000, apps)


# ---- the digested specification (data/fcc_hil.spec.json) --------------------------------
def _fingerprint(data: bytes) -> str:
    """Which DBC a digest was made from: its length and CRC-32 (a check against editing the
    DBC and not running dbc/generate, not against tampering)."""
    return f"{len(data)}:{zlib.crc32(data):08x}"


def spec_document(spec: BusSpec) -> dict[str, Any]:
    """The JSON document of a loaded DBC's specification (the digest dbc/generate writes)."""
    return {"format": SPEC_FORMAT, "dbc": _fingerprint(read_dbc(spec.path)),
            "nodes": list(spec.nodes), "baudrate": spec.baudrate, "apps": list(spec.apps),
            "messages": [_message_document(m) for m in spec.messages]}


def _message_document(m: MessageSpec) -> dict[str, Any]:
    """A message of the digest: a signal's value table only where the DBC has one."""
    doc = {k: v for k, v in asdict(m).items() if k != "dbc_path"}
    doc["signals"] = [{k: v for k, v in sig.items() if k != "choices" or v} for sig in doc["signals"]]
    return doc


def _from_spec_file(path: Path, spec_file: Path | None = None,
                    data: bytes | None = None) -> BusSpec | None:
    """The BusSpec of path (its bytes: data) from the digest, when the digest was made from
    these bytes."""
    try:
        doc = json.loads((spec_file or PACKAGED_SPEC).read_text(encoding="utf-8"))
        dbc = read_dbc(path) if data is None else data
        if doc.get("format") != SPEC_FORMAT or doc.get("dbc") != _fingerprint(dbc):
            return None
        messages = tuple(MessageSpec(**{**m, "senders": tuple(m["senders"]),
                                        "receivers": tuple(m["receivers"]),
                                        "secoc_pdus": tuple(m["secoc_pdus"]),
                                        "signals": tuple(_signal_of(s) for s in m["signals"])},
                                     dbc_path=path)
                         for m in doc["messages"])
        return BusSpec(path, messages, tuple(doc["nodes"]), int(doc["baudrate"]),
                       tuple(doc["apps"]))
    except (OSError, ValueError, KeyError, TypeError):
        return None


def _signal_of(doc: dict[str, Any]) -> SignalSpec:
    """A SignalSpec from its JSON object (the value table's pairs come back as lists)."""
    return SignalSpec(**{**doc, "choices": tuple((str(n), int(v)) for n, v in doc.get("choices", ()))})


def write_spec_file(dbc_path: Path, out: Path) -> None:
    """Digest dbc_path (parsed by cantools) into out (JSON, deterministic bytes)."""
    spec = _parsed(Path(dbc_path))  # parsed, never copied from an older digest
    out.write_text(json.dumps(spec_document(spec), indent=1, sort_keys=True) + "\n", encoding="utf-8")

