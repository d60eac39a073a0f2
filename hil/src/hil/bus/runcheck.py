"""A run of recorded frames checked in one call, as the live link's receivers check them one at
a time: the ticks of a lockstep flight (SecOC pair, then E2E) are half the frames a bus log's
reader checks, and a call per frame was most of reading the log.

Each function takes the leading frames that pass in the simplest way and advances the receiver
exactly as the frame-by-frame calls would; it stops before the first frame that does not, which
the caller hands to those calls (they decide and count it as they always do).

* verify_run: pairs (the secured frame, then its authenticator) of one PDU, Receiver.hold then
  Receiver.verify, while nothing else is held and each authenticator carries the next message
  counter (FV's low 16 bits one above the last accepted counter's) with a MAC that verifies
  (the MACs of the run computed together: truncated_macs, held equal to KeyedCmac by the
  tests).
* check_run: frames of one E2E-protected message, E2EReceiver.check, while each is OK: its CRC
  right and its alive counter one above the last (any, for the first after a reset).
"""
from __future__ import annotations

import numpy as np

from hil.bus.e2e import COUNTER_MODULO, FRAME_LENGTH, E2EReceiver, E2EStatus, protect_many
from hil.bus.secoc import FV_TRUNC_BITS, MAC_BYTES, Receiver

_COUNTER_MAX = 0xFFFFFFFF


def verify_run(rx: Receiver, pdus: np.ndarray, auths: np.ndarray) -> int:
    """How many of the leading pairs (pdus[i], auths[i]: (n, 8) uint8 each) verify one after
    the other from rx's state (module docstring); rx is advanced past them."""
    n = len(pdus)
    if rx.held or not n or pdus.shape != (n, 8) or auths.shape != (n, 8):
        return 0
    counters = rx.counter + 1 + np.arange(n, dtype=np.int64)
    fresh = ((auths[:, 0].astype(np.int64) | auths[:, 1].astype(np.int64) << 8)
             == counters & ((1 << FV_TRUNC_BITS) - 1)) & (counters <= _COUNTER_MAX)
    fvs = np.uint64(rx.trip << 32) | counters.astype(np.uint64)
    ok = fresh & (truncated_macs(rx.key, rx.data_id, pdus, fvs) == auths[:, 2:]).all(axis=1)
    n = int(np.argmin(ok)) if not ok.all() else n
    rx.counter += n
    rx.counters.verified += n
    return n


def truncated_macs(key: bytes, data_id: int, pdus: np.ndarray, fvs: np.ndarray) -> np.ndarray:
    """KeyedCmac(key).mac(data_id, pdus[i], fvs[i]) for every 8-byte pdu, at once: (n, 6)
    uint8.  AES-128-CMAC (NIST SP 800-38B) of the 18-byte message data ID | pdu | FV, two
    blocks: T = E(E(M1) xor (M2 | 80 00.. xor K2)), the subkey K2 = dbl(dbl(E(0))); the AES
    is cryptography's, every block of a run in one call."""
    from cryptography.hazmat.primitives.ciphers import Cipher, algorithms, modes
    aes = Cipher(algorithms.AES(key), modes.ECB()).encryptor()
    k2 = _dbl(_dbl(int.from_bytes(aes.update(bytes(16)), "big"))).to_bytes(16, "big")
    n = len(pdus)
    fv = fvs.astype(">u8").view(np.uint8).reshape(n, 8)
    m1 = np.empty((n, 16), np.uint8)
    m1[:, :2] = np.frombuffer(data_id.to_bytes(2, "big"), np.uint8)
    m1[:, 2:10] = pdus
    m1[:, 10:] = fv[:, :6]
    last = np.zeros((n, 16), np.uint8)
    last[:, :2] = fv[:, 6:]
    last[:, 2] = 0x80
    last ^= np.frombuffer(k2, np.uint8)
    x = np.frombuffer(aes.update(m1.tobytes()), np.uint8).reshape(n, 16) ^ last
    return np.frombuffer(aes.update(x.tobytes()), np.uint8).reshape(n, 16)[:, :MAC_BYTES]


def _dbl(block: int) -> int:
    """The CMAC subkey step: the 128-bit block shifted left, xor 0x87 when a bit fell out."""
    block <<= 1
    return (block ^ 0x87) & ((1 << 128) - 1) if block >> 128 else block


def check_run(rx: E2EReceiver, frames: np.ndarray) -> int:
    """How many of the leading frames ((n, 8) uint8) rx classifies OK one after the other
    (module docstring); rx is advanced past them."""
    if frames.ndim != 2 or frames.shape[1] != FRAME_LENGTH or not len(frames):
        return 0
    counters = frames[:, 1] & 0x0F
    first = int(counters[0]) if not rx.synced else (rx.last_counter + 1) % COUNTER_MODULO
    ok = ((protect_many(rx.data_id, frames, counters)[:, 0] == frames[:, 0])   # the CRC
          & (counters == (first + np.arange(len(frames))) % COUNTER_MODULO))
    n = int(np.argmin(ok)) if not ok.all() else len(frames)
    if n:
        rx.frames_this_period += n
        rx.counts[E2EStatus.OK] += n
        rx.last_status = E2EStatus.OK
        rx.synced, rx.last_counter = True, int(counters[n - 1])
    return n
