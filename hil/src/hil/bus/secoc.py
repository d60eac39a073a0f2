"""SecOC-style authentication of CAN frames (one specification with firmware/bus/fcc_secoc.h).

The specification is in dbc/README.md ("Authentication"); in short:

* a secured frame (SIM_CONTROL, SIM_TICK) or group (fcc's heartbeat; fcc's outputs of one step:
  the 12 identification frames, the missile's command + estimate) is followed by its
  authenticator frame (the DBC's ``SecOC_Pdus`` / ``SecOC_DataID`` attributes);
* freshness value FV = trip << 32 | message counter (one counter per secured PDU, from 1);
  fcc draws the trip at start and publishes it in ``FCC_SEC_SESSION``;
* authenticator = FV mod 2**16 (little-endian) + the first 6 bytes of
  AES-128-CMAC(key, data ID (2 bytes big-endian) + secured bytes + FV (8 bytes big-endian));
* the receiver rebuilds FV as the smallest counter above the last accepted one with those
  low 16 bits; more than WINDOW ahead fails freshness, otherwise the MAC decides; it holds up
  to CANDIDATES secured frames and accepts the one the MAC verifies.

The MAC is cryptography's (OpenSSL), independent of the C code; a sender or receiver copies its
key's CMAC context per message (``KeyedCmac``): 0.7 us a MAC instead of 3 us.

Why this module is long: one specification with both its ends (senders, receivers, the
endpoint between them and fcc) and its key files; split, the specification would be spread.
"""
from __future__ import annotations

import enum
import itertools
import os
from collections import deque
from collections.abc import Iterable, Iterator
from dataclasses import asdict, dataclass, field
from pathlib import Path

from hil.bus.dbc import BusSpec
from hil.io.paths import DATA
from hil.util.bounded import UnfitFile, read_bounded
from hil.util.errors import HilError

KEY_BYTES = 16
MAC_BYTES = 6
FV_TRUNC_BITS = 16
WINDOW = 1024
CANDIDATES = 4
#: the documented test key (tests only; fcc warns when it is used)
TEST_KEY_FILE = DATA / "secoc_test.key"  # shipped in the package (a copy of tests/keys/)


class KeyFileError(HilError, ValueError):
    """A key file that cannot be used (one line for the user)."""


def load_cmac() -> None:
    """Import the CMAC (cryptography's library: 0.09 s in the UML guest, so the rig session
    imports it while it listens to the bus, hil.rig.session; else the first MAC does)."""
    from cryptography.hazmat.primitives import cmac as _cmac  # noqa: F401
    from cryptography.hazmat.primitives.ciphers import algorithms as _algorithms  # noqa: F401


class KeyedCmac:
    """AES-128-CMAC under one key: the context made once (AES key schedule, CMAC subkeys) and
    copied for each message (cryptography's ``CMAC.copy``), the MAC itself cryptography's."""

    def __init__(self, key: bytes) -> None:
        from cryptography.hazmat.primitives.ciphers import algorithms
        from cryptography.hazmat.primitives.cmac import CMAC
        self._keyed = CMAC(algorithms.AES(key))

    def digest(self, data: bytes) -> bytes:
        """The full 16-byte AES-128-CMAC of data."""
        c = self._keyed.copy()
        c.update(data)
        return c.finalize()

    def mac(self, data_id: int, pdu: bytes, fv: int) -> bytes:
        """The truncated MAC: first MAC_BYTES of the CMAC over data ID | pdu | FV."""
        return self.digest(data_id.to_bytes(2, "big") + pdu + fv.to_bytes(8, "big"))[:MAC_BYTES]


def cmac(key: bytes, data: bytes) -> bytes:
    """The full 16-byte AES-128-CMAC of data (one message: KeyedCmac for many)."""
    return KeyedCmac(key).digest(data)


def mac(key: bytes, data_id: int, pdu: bytes, fv: int) -> bytes:
    """The truncated MAC: first MAC_BYTES of the CMAC over data ID | pdu | FV."""
    return KeyedCmac(key).mac(data_id, bytes(pdu), fv)


def same_mac(a: bytes, b: bytes) -> bool:
    """a == b in a time that does not depend on where they differ (what hmac.compare_digest
    does; hmac would load OpenSSL's libcrypto beside cryptography's own, 50 ms in the guest)."""
    diff = len(a) ^ len(b)
    for x, y in zip(a, b):
        diff |= x ^ y
    return diff == 0


def authenticator(key: bytes | KeyedCmac, data_id: int, pdu: bytes, trip: int, counter: int) -> bytes:
    """The 8 bytes of the authenticator frame for pdu at message counter `counter`."""
    keyed = key if isinstance(key, KeyedCmac) else KeyedCmac(key)
    return (counter & 0xFFFF).to_bytes(2, "little") + keyed.mac(data_id, bytes(pdu), (trip << 32) | counter)


def read_key_file(path: str | Path) -> bytes:
    """A key file: one line of 32 hex digits (lines starting with # are comments)."""
    try:
        text = read_bounded(path, 4096, "key file").decode("ascii")
    except UnfitFile as exc:
        raise KeyFileError(str(exc)) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise KeyFileError(f"cannot read key file {path}: {exc}") from None
    lines = [ln.strip() for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    try:
        key = bytes.fromhex(lines[0]) if len(lines) == 1 else b""
    except ValueError:
        key = b""
    if len(key) != KEY_BYTES:
        raise KeyFileError(f"key file {path}: expected one line of {2 * KEY_BYTES} hex digits")
    return key


def write_key_file(path: Path, key: bytes | None = None) -> bytes:
    """Write a new random (or the given) key, readable by the owner only."""
    key = key if key is not None else os.urandom(KEY_BYTES)
    path.touch(mode=0o600, exist_ok=True)
    path.chmod(0o600)
    path.write_text("# AES-128 key of one rig session (SecOC-style bus authentication)\n"
                    f"{key.hex()}\n", encoding="ascii")
    return key


class Verdict(enum.Enum):
    VERIFIED = "verified"
    FRESHNESS_FAILED = "freshness_failed"
    MAC_FAILED = "mac_failed"
    NO_PDU = "no_pdu"


@dataclass
class Counters:
    verified: int = 0
    mac_failed: int = 0
    freshness_failed: int = 0
    unpaired: int = 0

    def as_dict(self) -> dict[str, int]:
        return asdict(self)


@dataclass
class Sender:
    """The sending side of one secured PDU."""

    key: bytes
    data_id: int
    trip: int
    counter: int = 0
    keyed: KeyedCmac = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        self.keyed = KeyedCmac(self.key)

    def protect(self, pdu: bytes) -> bytes:
        self.counter += 1
        return authenticator(self.keyed, self.data_id, pdu, self.trip, self.counter)


@dataclass
class Receiver:
    """The receiving side of one secured PDU (a single frame, or a group of frames whose
    latest copies are concatenated in DBC order)."""

    key: bytes
    data_id: int
    trip: int
    counters: Counters = field(default_factory=Counters)
    counter: int = 0
    held: deque[bytes] = field(default_factory=lambda: deque())
    keyed: KeyedCmac = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        self.keyed = KeyedCmac(self.key)

    def hold(self, data: bytes) -> None:
        if len(self.held) == CANDIDATES:
            self.held.popleft()
            self.counters.unpaired += 1
        self.held.append(bytes(data))

    def fresh_counter(self, auth: bytes) -> int | None:
        trunc = int.from_bytes(auth[:2], "little")
        cand = (self.counter & ~0xFFFF) | trunc
        if cand <= self.counter:
            cand += 1 << FV_TRUNC_BITS
        return cand if cand - self.counter <= WINDOW and cand <= 0xFFFFFFFF else None

    def verify(self, auth: bytes) -> tuple[Verdict, bytes | None]:
        verdict, i, pdu = self.verify_among(auth, self.held)
        for _ in range(i + 1 if verdict is Verdict.VERIFIED else 0):
            self.held.popleft()
        self.counters.unpaired += i
        return verdict, pdu

    def verify_among(self, auth: bytes, candidates: Iterable[bytes]) -> tuple[Verdict, int, bytes | None]:
        """(verdict, index, pdu) of the first of `candidates` (none: NO_PDU) the authenticator verifies,
        tried only until one does (a group's made as tried); the counter advanced, the verdict counted."""
        cand = self.fresh_counter(auth)
        if cand is None:
            self.counters.freshness_failed += 1
            return Verdict.FRESHNESS_FAILED, 0, None
        fv, tag, verdict = (self.trip << 32) | cand, bytes(auth[2:8]), Verdict.NO_PDU
        for i, pdu in enumerate(candidates):
            if same_mac(self.keyed.mac(self.data_id, pdu, fv), tag):
                self.counter = cand
                self.counters.verified += 1
                return Verdict.VERIFIED, i, pdu
            verdict = Verdict.MAC_FAILED
        self.counters.mac_failed += 1
        return verdict, 0, None


GROUP_TRIES = 256   # combinations of the copies held a group's authenticator is tried on


def _combinations(choices: list[list[bytes]]) -> Iterator[bytes]:
    """The concatenations of one copy per member (choices: each member's, newest first), the fewest
    departures from the newest copies first: all newest, then one older copy, ... (members held once stay)."""
    olders = [w for w, c in enumerate(choices) if len(c) > 1]
    for d in range(len(olders) + 1):
        for where in itertools.combinations(olders, d):
            for older in itertools.product(*(range(1, len(choices[w])) for w in where)):
                pick = dict(zip(where, older))
                yield b"".join(c[pick.get(i, 0)] for i, c in enumerate(choices))


@dataclass
class GroupReceiver(Receiver):
    """A secured PDU of several frames (fcc's heartbeat, its outputs of a step): each member's
    different copies since the last verified authenticator held (CANDIDATES, the oldest
    dropped) and tried newest first (_combinations); a failed authenticator discards nothing.
    A second, different copy is another node's (``conflicts``); an unused one is unpaired."""

    pdu_ids: tuple[int, ...] = ()
    copies: dict[int, list[bytes]] = field(default_factory=dict)
    #: different second copies of a member before its authenticator (forged frames)
    conflicts: int = 0

    def hold_frame(self, frame_id: int, data: bytes) -> None:
        got = self.copies.setdefault(frame_id, [])
        if bytes(data) in got:
            return
        self.conflicts += bool(got)
        if len(got) == CANDIDATES:
            got.pop(0)
            self.counters.unpaired += 1
        got.append(bytes(data))

    def verify_group(self, auth: bytes) -> tuple[Verdict, list[tuple[int, bytes]]]:
        if any(i not in self.copies for i in self.pdu_ids):
            self.counters.mac_failed += 1
            return Verdict.NO_PDU, []
        choices = [self.copies[i][::-1] for i in self.pdu_ids]
        verdict, _, pdu = self.verify_among(auth, itertools.islice(_combinations(choices), GROUP_TRIES))
        if verdict is not Verdict.VERIFIED or pdu is None:
            return verdict, []
        self.counters.unpaired += sum(len(c) for c in self.copies.values()) - len(self.pdu_ids)
        self.copies = {}
        return verdict, [(i, pdu[8 * j: 8 * j + 8]) for j, i in enumerate(self.pdu_ids)]


class Endpoint:
    """The simulator's end of the authentication with one fcc process: an authenticator for
    every secured frame it sends, and verification of every secured frame fcc sends.

    The trip is fcc's (FCC_SEC_SESSION); until it is known (``trip is None``) the first
    heartbeat that verifies with the trip it carries fixes it for the session."""

    def __init__(self, spec: object, key: bytes, own_node_names: tuple[str, ...]) -> None:
        assert isinstance(spec, BusSpec)
        self.spec = spec
        self.key = key
        self.trip: int | None = None
        self._send: dict[int, tuple[int, int]] = {}   # secured frame id -> (auth id, data id)
        self._send_groups: dict[str, int] = {}         # authenticator name -> data id (groups)
        self._senders: dict[int, Sender] = {}
        self._rx_single: dict[int, int] = {}              # secured id / auth id -> auth id
        self._receivers: dict[int, Receiver] = {}         # by auth id
        self._group_of: dict[int, int] = {}               # member id -> auth id
        self.session_id = spec.by_name("FCC_SEC_SESSION").frame_id
        for m in spec.messages:
            if not m.is_authenticator:
                continue
            pdus = tuple(spec.by_name(p).frame_id for p in m.secoc_pdus)
            ours = any(s in own_node_names for s in m.senders)
            if ours and len(pdus) > 1:   # the time master's SYNC + FOLLOW_UP
                self._send_groups[m.name] = m.secoc_data_id
            elif ours:
                self._send[pdus[0]] = (m.frame_id, m.secoc_data_id)
            elif len(pdus) == 1:
                self._rx_single[pdus[0]] = m.frame_id
                self._receivers[m.frame_id] = Receiver(key, m.secoc_data_id, 0)
            else:
                for p in pdus:
                    self._group_of[p] = m.frame_id
                self._receivers[m.frame_id] = GroupReceiver(key, m.secoc_data_id, 0, pdu_ids=pdus)

    @property
    def auth_ids(self) -> tuple[int, ...]:
        """Identifiers of the authenticators fcc sends (for the receive filter)."""
        return tuple(self._receivers)

    @property
    def secured_ids(self) -> frozenset[int]:
        """Identifiers of the frames of ours that protect() follows with an authenticator."""
        return frozenset(self._send)

    def counters(self) -> dict[str, int]:
        total = Counters()
        for r in self._receivers.values():
            for k, v in r.counters.as_dict().items():
                setattr(total, k, getattr(total, k) + v)
        return total.as_dict()

    def set_trip(self, trip: int) -> None:
        self.trip = trip
        for r in self._receivers.values():
            r.trip = trip
        for s in self._senders.values():
            s.trip = trip

    # -- sending
    def protect(self, frame_id: int, data: bytes) -> list[tuple[int, bytes]]:
        """The frame, followed by its authenticator when it is a secured 8-byte frame."""
        out = [(frame_id, bytes(data))]
        if frame_id in self._send and len(data) == 8:
            out.append((self.auth_id(frame_id), self.sender(frame_id).protect(bytes(data))))
        return out

    def sender(self, frame_id: int) -> Sender:
        """The sending side of a secured frame of ours (its message counter), made at its
        first use; its authenticator frame's identifier is ``auth_id(frame_id)``."""
        if self.trip is None:
            raise RuntimeError("SecOC: fcc's trip is not known yet (no verified heartbeat)")
        s = self._senders.get(frame_id)
        if s is None:
            s = self._senders[frame_id] = Sender(self.key, self._send[frame_id][1], self.trip)
        return s

    def auth_id(self, frame_id: int) -> int:
        """The identifier of the authenticator that follows a secured frame of ours."""
        return self._send[frame_id][0]

    def group_sender(self, auth_name: str) -> Sender:
        """The sending side of a secured group of ours (TSYNC_AUTH over the time master's
        SYNC + FOLLOW_UP): its own counter, for the one thread that sends it."""
        if self.trip is None:
            raise RuntimeError("SecOC: fcc's trip is not known yet (no verified heartbeat)")
        return Sender(self.key, self._send_groups[auth_name], self.trip)

    # -- receiving
    def receiver(self, auth_id: int) -> Receiver | GroupReceiver:
        """The receiving side of the authenticator auth_id (a reader that checks a run of its
        frames at once advances it: hil.bus.runcheck)."""
        return self._receivers[auth_id]

    def is_secured(self, frame_id: int) -> bool:
        """A frame fcc sends that counts only once its authenticator verified."""
        return frame_id in self._rx_single or frame_id in self._group_of

    def receive(self, frame_id: int, data: bytes) -> list[tuple[int, bytes]]:
        """What to act on: unsecured frames as they are, secured frames only once their
        authenticator verified (then the secured frame(s), not the authenticator)."""
        if frame_id in self._rx_single:
            if len(data) == 8:
                self._receivers[self._rx_single[frame_id]].hold(data)
            return []
        if frame_id in self._group_of:
            group = self._receivers[self._group_of[frame_id]]
            assert isinstance(group, GroupReceiver)
            if len(data) == 8:
                group.hold_frame(frame_id, data)
            return []
        r = self._receivers.get(frame_id)
        if r is None:
            return [(frame_id, bytes(data))]
        if len(data) != 8:
            r.counters.mac_failed += 1
            return []
        if isinstance(r, GroupReceiver):
            if self.trip is None:   # the first heartbeat: try the trip it carries
                session = r.copies.get(self.session_id)
                if not session:
                    r.copies = {}
                    return []
                r.trip = int.from_bytes(session[-1][:4], "little")
            verdict, frames = r.verify_group(data)
            if verdict is Verdict.VERIFIED and self.trip is None:
                self.set_trip(r.trip)
            elif verdict is not Verdict.VERIFIED and self.trip is None:
                r.trip = 0
            return frames
        if self.trip is None:
            r.counters.mac_failed += 1
            return []
        verdict, pdu = r.verify(data)
        pdu_id = next(p for p, a in self._rx_single.items() if a == frame_id)
        return [(pdu_id, pdu)] if verdict is Verdict.VERIFIED and pdu is not None else []
