"""SecOC's MACs of many frames at once (hil.bus.secoc does one frame at a time): a lockstep
flight's tick authenticators made before it (hil.rig.tickplan), a bus log's ticks verified a run
at a time (hil.bus.runcheck).  The same bytes as hil.bus.secoc.authenticator, frame by frame
(tests/python/bus/test_runcheck.py holds them equal, and the MACs to cryptography's CMAC)."""
from __future__ import annotations

import numpy as np

from hil.bus.secoc import MAC_BYTES


def authenticators(key: bytes, data_id: int, pdus: np.ndarray, trip: int, first: int) -> np.ndarray:
    """authenticator(key, data_id, pdus[i], trip, first + i) of n pdus of 8 bytes each, or of
    one group of frames each ((n, 8 m) uint8: the group's frames concatenated) at once: (n, 8)
    uint8."""
    counters = first + np.arange(len(pdus), dtype=np.int64)
    out = np.empty((len(pdus), 8), np.uint8)
    out[:, 0], out[:, 1] = counters & 0xFF, counters >> 8 & 0xFF
    fvs = np.uint64(trip << 32) | counters.astype(np.uint64)
    out[:, 2:] = truncated_macs(key, data_id, pdus, fvs) if pdus.shape[1] == 8 \
        else group_macs(key, data_id, pdus, fvs)
    return out


def group_macs(key: bytes, data_id: int, pdus: np.ndarray, fvs: np.ndarray) -> np.ndarray:
    """KeyedCmac(key).mac(data_id, pdus[i], fvs[i]) for pdus of any equal length ((n, L) uint8),
    at once: (n, 6) uint8.  AES-128-CMAC (NIST SP 800-38B) block by block over all n messages
    (one AES call per block of the message): the last block xor K1 when it is complete, else
    padded with 80 00.. and xor K2."""
    from cryptography.hazmat.primitives.ciphers import Cipher, algorithms, modes
    aes = Cipher(algorithms.AES(key), modes.ECB()).encryptor()
    k1 = _dbl(int.from_bytes(aes.update(bytes(16)), "big"))
    n, length = len(pdus), 2 + pdus.shape[1] + 8
    blocks = -(-length // 16)
    msg = np.zeros((n, 16 * blocks), np.uint8)
    msg[:, :2] = np.frombuffer(data_id.to_bytes(2, "big"), np.uint8)
    msg[:, 2: 2 + pdus.shape[1]] = pdus
    msg[:, length - 8: length] = fvs.astype(">u8").view(np.uint8).reshape(n, 8)
    last = k1 if length % 16 == 0 else _dbl(k1)
    if length % 16:
        msg[:, length] = 0x80
    msg[:, -16:] ^= np.frombuffer(last.to_bytes(16, "big"), np.uint8)
    x = np.zeros((n, 16), np.uint8)
    for b in range(blocks):
        x = np.frombuffer(aes.update((x ^ msg[:, 16 * b: 16 * b + 16]).tobytes()), np.uint8).reshape(n, 16)
    return x[:, :MAC_BYTES]


def truncated_macs(key: bytes, data_id: int, pdus: np.ndarray, fvs: np.ndarray) -> np.ndarray:
    """KeyedCmac(key).mac(data_id, pdus[i], fvs[i]) for every 8-byte pdu, at once: (n, 6)
    uint8.  AES-128-CMAC (NIST SP 800-38B) of the 18-byte message data ID | pdu | FV, two
    blocks: T = E(E(M1) xor (M2 | 80 00.. xor K2)), the subkey K2 = dbl(dbl(E(0))); the AES
    is cryptography's, every block in one call (KeyedCmac's context is per message)."""
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
