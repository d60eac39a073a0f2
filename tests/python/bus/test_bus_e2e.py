"""E2E in Python: the CRC's published values, the hand-worked frames, the receiver by hand.

The same cases are in tests/c/test_e2e.c; tests/vectors/bus/e2e_seq.txt is replayed
by both (test_bus_vectors.py here).
"""
from __future__ import annotations

import numpy as np
import pytest

from hil.bus.e2e import (E2EReceiver, E2ESender, E2EStatus, crc8_j1850, frame_crc, protect,
                         protect_many)


def _crc_bitwise(data: bytes) -> int:
    """Independent bit-by-bit CRC-8 SAE J1850 (no table)."""
    crc = 0xFF
    for byte in data:
        crc ^= byte
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1D) & 0xFF if crc & 0x80 else (crc << 1) & 0xFF
    return crc ^ 0xFF


@pytest.mark.parametrize("hex_data, crc", [
    ("313233343536373839", 0x4B),  # the check value: ASCII "123456789"
    # the AUTOSAR CRC library's published SAE J1850 table
    ("00000000", 0x59), ("F20183", 0x37), ("0FAA0055", 0x79), ("00FF5511", 0xB8),
    ("332255AABBCCDDEEFF", 0xCB), ("926B55", 0x8C), ("FFFFFFFF", 0x74),
])
def test_crc_published_values(hex_data: str, crc: int) -> None:
    data = bytes.fromhex(hex_data)
    assert crc8_j1850(data) == crc
    assert _crc_bitwise(data) == crc


def test_crc_table_equals_bitwise() -> None:
    for n in range(256):
        data = bytes([n, 255 - n, n ^ 0x5A])
        assert crc8_j1850(data) == _crc_bitwise(data)


def test_hand_worked_frames() -> None:
    # dbc/README.md: SIM_TICK (0x1020), app 0, step 1, counter 0
    assert _crc_bitwise(bytes.fromhex("201000010000000000")) == 0x9F
    assert protect(0x1020, bytes.fromhex("0000010000000000"), 0) == bytes.fromhex("9F00010000000000")
    # CDRW_AOA (0x1050), step 7, alpha raw 157000, counter 5
    assert protect(0x1050, bytes.fromhex("0000070048650200"), 5) == bytes.fromhex("3105070048650200")


def test_protect_keeps_data_nibble_and_checks_arguments() -> None:
    f = protect(0x1234, bytes([0, 0xA7, 1, 2, 3, 4, 5, 6]), 0x0C)
    assert f[1] == 0xAC and f[0] == frame_crc(0x1234, f)
    assert frame_crc(0x1234, f) != frame_crc(0x3412, f)  # byte order of the data ID matters
    with pytest.raises(ValueError):
        protect(0x1234, bytes(8), 16)
    with pytest.raises(ValueError):
        protect(0x1234, bytes(7), 0)
    with pytest.raises(ValueError):
        frame_crc(0x10000, bytes(8))


def test_protect_many_equals_protect() -> None:
    """The vectorised protection of a lockstep flight's ticks (hil.rig.tickplan) gives what
    protect() gives frame by frame: random payloads, every counter, several data IDs."""
    rng = np.random.default_rng(7)
    payloads = rng.integers(0, 256, (500, 8), dtype=np.uint8)
    before = payloads.copy()
    counters = np.arange(500) % 16
    for data_id in (0x0000, 0x1020, 0x1050, 0xFFFF):
        got = protect_many(data_id, payloads, counters)
        assert [bytes(r) for r in got] == [protect(data_id, bytes(p), int(c))
                                           for p, c in zip(payloads, counters)]
    assert (payloads == before).all()   # the payloads handed over are not changed
    with pytest.raises(ValueError):
        protect_many(0x10000, payloads, counters)
    with pytest.raises(ValueError):
        protect_many(0x1020, payloads, counters + 1)   # 16 is not a counter
    with pytest.raises(ValueError):
        protect_many(0x1020, payloads[:, :7], counters)


def _frame(counter: int, data_id: int = 0x1050) -> bytes:
    return protect(data_id, bytes([0, 0, 0x42, 0, 0, 0, 0, 0]), counter)


def test_receiver_by_hand() -> None:
    rx = E2EReceiver(0x1050)
    S = E2EStatus
    seq = [(14, S.OK), (14, S.REPEATED), (15, S.OK), (0, S.OK), (2, S.OK_SOME_LOST),
           (5, S.OK_SOME_LOST), (9, S.WRONG_SEQUENCE), (10, S.OK), (8, S.WRONG_SEQUENCE),
           (9, S.OK)]
    for counter, expected in seq:
        assert rx.check(_frame(counter)) is expected, counter
    assert rx.lost_frames == 3
    bad = bytearray(_frame(10))
    bad[0] ^= 1
    assert rx.check(bytes(bad)) is S.ERROR
    bad = bytearray(_frame(10))
    bad[7] ^= 0x80
    assert rx.check(bytes(bad)) is S.ERROR
    assert rx.check(_frame(10)[:7]) is S.ERROR
    assert rx.check(_frame(10)) is S.OK  # the errors did not move the counter
    assert rx.check(_frame(11, data_id=0x1051)) is S.ERROR
    assert rx.counts == {S.OK: 6, S.REPEATED: 1, S.OK_SOME_LOST: 2, S.WRONG_SEQUENCE: 2,
                         S.ERROR: 4, S.NO_NEW_DATA: 0}
    assert [s.data_usable for s in S] == [True, False, True, False, False, False]


def test_no_new_data_and_resync() -> None:
    rx = E2EReceiver(0x1050, max_delta_counter=2)
    assert rx.end_period() and rx.stale
    assert rx.check(_frame(3)) is E2EStatus.OK
    assert not rx.end_period()
    assert rx.end_period()
    assert rx.counts[E2EStatus.NO_NEW_DATA] == 2
    bad = bytearray(_frame(4))
    bad[0] ^= 0xFF
    assert rx.check(bytes(bad)) is E2EStatus.ERROR
    assert not rx.end_period()  # a rejected frame is still a frame
    assert rx.check(_frame(6)) is E2EStatus.WRONG_SEQUENCE  # delta 3 > 2
    rx.reset()
    assert rx.check(_frame(0)) is E2EStatus.OK


def test_sender_counts_modulo_16() -> None:
    tx, rx = E2ESender(0x1050), E2EReceiver(0x1050)
    for i in range(40):
        f = tx.protect(bytes([0, 0, i, 0, 0, 0, 0, 0]))
        assert f[1] & 0x0F == i % 16
        assert rx.check(f) is E2EStatus.OK
    with pytest.raises(ValueError):
        E2EReceiver(0x1050, max_delta_counter=15)
