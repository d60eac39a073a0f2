"""SecOC-style authentication of CAN frames (one specification with firmware/bus/fcc_secoc.h).

The specification is in dbc/README.md ("Authentication"); in short:

* a secured frame (SIM_CONTROL, SIM_TICK, MSL_ELEV_CMD, or the heartbeat group) is followed
  by its authenticator frame (the DBC's ``SecOC_Pdus`` / ``SecOC_DataID`` attributes);
* freshness value FV = trip << 32 | message counter (one counter per secured PDU, from 1);
  fcc draws the trip at start and publishes it in ``FCC_SEC_SESSION``;
* authenticator = FV mod 2**16 (little-endian) + the first 6 bytes of
  AES-128-CMAC(key, data ID (2 bytes big-endian) + secured bytes + FV (8 bytes big-endian));
* the receiver rebuilds FV as the smallest counter above the last accepted one with those
  low 16 bits; more than WINDOW ahead fails freshness, otherwise the MAC decides; it holds up
  to CANDIDATES secured frames and accepts the one the MAC verifies.

The MAC is computed by the ``cryptography`` package (OpenSSL), independent of the C code.
"""
from __future__ import annotations

import enum
import secrets
from collections import deque
from dataclasses import dataclass, field
from pathlib import Path

from cryptography.hazmat.primitives.cmac import CMAC
from cryptography.hazmat.primitives.ciphers import algorithms

KEY_BYTES = 16
MAC_BYTES = 6
FV_TRUNC_BITS = 16
WINDOW = 1024
CANDIDATES = 4
#: the documented test key (tests only; fcc warns when it is used)
TEST_KEY_FILE = Path(__file__).resolve().parents[4] / "tests" / "keys" / "secoc_test.key"


class KeyFileError(ValueError):
    """A key file that cannot be used (one line for the user)."""


def cmac(key: bytes, data: bytes) -> bytes:
    """The full 16-byte AES-128-CMAC of data."""
    c = CMAC(algorithms.AES(key))
    c.update(data)
    return c.finalize()


def mac(key: bytes, data_id: int, pdu: bytes, fv: int) -> bytes:
    """The truncated MAC: first MAC_BYTES of the CMAC over data ID | pdu | FV."""
    return cmac(key, data_id.to_bytes(2, "big") + bytes(pdu) + fv.to_bytes(8, "big"))[:MAC_BYTES]


def authenticator(key: bytes, data_id: int, pdu: bytes, trip: int, counter: int) -> bytes:
    """The 8 bytes of the authenticator frame for pdu at message counter `counter`."""
    fv = (trip << 32) | counter
    return (counter & 0xFFFF).to_bytes(2, "little") + mac(key, data_id, pdu, fv)


def read_key_file(path: str | Path) -> bytes:
    """A key file: one line of 32 hex digits (lines starting with # are comments)."""
    try:
        text = Path(path).read_text(encoding="ascii")
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
    key = key if key is not None else secrets.token_bytes(KEY_BYTES)
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
        return {"verified": self.verified, "mac_failed": self.mac_failed,
                "freshness_failed": self.freshness_failed, "unpaired": self.unpaired}


@dataclass
class Sender:
    """The sending side of one secured PDU."""

    key: bytes
    data_id: int
    trip: int
    counter: int = 0

    def protect(self, pdu: bytes) -> bytes:
        self.counter += 1
        return authenticator(self.key, self.data_id, pdu, self.trip, self.counter)


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
        cand = self.fresh_counter(auth)
        if cand is None:
            self.counters.freshness_failed += 1
            return Verdict.FRESHNESS_FAILED, None
        if not self.held:
            self.counters.mac_failed += 1
            return Verdict.NO_PDU, None
        fv = (self.trip << 32) | cand
        for i, pdu in enumerate(self.held):
            if secrets.compare_digest(mac(self.key, self.data_id, pdu, fv), bytes(auth[2:8])):
                self.counters.unpaired += i
                for _ in range(i + 1):
                    self.held.popleft()
                self.counter = cand
                self.counters.verified += 1
                return Verdict.VERIFIED, pdu
        self.counters.mac_failed += 1
        return Verdict.MAC_FAILED, None
