"""Runs of recorded frames checked in one call (hil.bus.runcheck): the (frame, authenticator)
pairs verify_run takes and the E2E frames check_run takes, and the receivers after them, are
those hold()/verify() and check() give one by one; each stops before the first they would
decide otherwise."""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from hil.bus.e2e import E2EReceiver, E2ESender, E2EStatus
from hil.bus.runcheck import check_run, verify_run
from hil.bus.secoc import KeyedCmac, Receiver, Sender, Verdict, authenticator
from hil.bus.secoc_batch import authenticators, truncated_macs

KEY, DATA_ID, TRIP = bytes(range(16)), 0x0211, 7


def pairs(n: int, first_counter: int = 0, trip: int = TRIP) -> list[tuple[bytes, bytes]]:
    tx = Sender(KEY, DATA_ID, trip, first_counter)
    pdus = [bytes([k & 0xFF, k >> 8, 1, 2, 3, 4, 5, 6]) for k in range(n)]
    return [(p, tx.protect(p)) for p in pdus]


def run_of(pairs: list[tuple[bytes, bytes]]) -> tuple[np.ndarray, np.ndarray]:
    """The pairs as verify_run takes them (a frame shorter than 8 bytes: none)."""
    pairs = pairs[: next((i for i, (p, a) in enumerate(pairs) if len(p) != 8 or len(a) != 8), len(pairs))]
    return tuple(np.frombuffer(b"".join(col), np.uint8).reshape(-1, 8) for col in zip(*pairs)) \
        if pairs else (np.zeros((0, 8), np.uint8), np.zeros((0, 8), np.uint8))


def state(rx: Receiver) -> tuple:
    return rx.counter, list(rx.held), dataclasses.astuple(rx.counters)


def one_by_one(rx: Receiver, run: list[tuple[bytes, bytes]]) -> int:
    """How many leading pairs verify pair by pair (rx advanced past them)."""
    for i, (pdu, auth) in enumerate(run):
        rx.hold(pdu)
        if rx.verify(auth) != (Verdict.VERIFIED, pdu):
            return i
    return len(run)


@pytest.mark.parametrize("trip", [TRIP, 0xFFFFFFFF])
@pytest.mark.parametrize("first_counter", [0, 0xFFF0, 0xFFFFFFF0])
def test_genuine_pairs_verify_as_one_by_one(first_counter, trip):
    run = pairs(40, first_counter, trip)
    a, b, c = (Receiver(KEY, DATA_ID, trip, counter=first_counter) for _ in range(3))
    n = verify_run(a, *run_of(run))
    assert n == one_by_one(b, run) == one_by_one(c, run[:n]) and state(a) == state(c)
    assert n == (15 if first_counter == 0xFFFFFFF0 else 40)   # the counter's end: no more


def forge(run, i, how):
    pdu, auth = run[i]
    if how == "mac":
        run[i] = (pdu, auth[:7] + bytes([auth[7] ^ 1]))
    elif how == "pdu":
        run[i] = (bytes([pdu[0] ^ 1]) + pdu[1:], auth)
    elif how == "replay":
        run[i] = run[i - 5]
    elif how == "skip":          # a pair lost: the next one carries a counter two ahead
        del run[i]
    elif how == "short":
        run[i] = (pdu[:7], auth)
    return run


@pytest.mark.parametrize("how", ["mac", "pdu", "replay", "skip", "short"])
def test_it_stops_before_the_first_pair_decided_otherwise(how):
    run = forge(pairs(30), 12, how)
    rx = Receiver(KEY, DATA_ID, TRIP)
    assert verify_run(rx, *run_of(run)) == 12
    ref = Receiver(KEY, DATA_ID, TRIP)
    assert one_by_one(ref, run[:12]) == 12 and state(rx) == state(ref)


def test_nothing_is_taken_while_a_frame_is_held():
    run = pairs(3)
    rx = Receiver(KEY, DATA_ID, TRIP)
    rx.hold(b"\x00" * 8)
    before = state(rx)
    assert verify_run(rx, *run_of(run)) == 0 and state(rx) == before


def e2e_frames(n: int, first: int = 0) -> list[bytes]:
    tx = E2ESender(0x0123, first)
    return [tx.protect(bytes([0, 0x10, k & 0xFF, k >> 8, 0, 0, 0, 0])) for k in range(n)]


def e2e_state(rx: E2EReceiver) -> tuple:
    return rx.synced, rx.last_counter, rx.frames_this_period, rx.last_status, dict(rx.counts), rx.lost_frames


def e2e_one_by_one(rx: E2EReceiver, frames: list[bytes]) -> int:
    for i, f in enumerate(frames):
        if rx.check(f) is not E2EStatus.OK:
            return i
    return len(frames)


@pytest.mark.parametrize("how", ["none", "crc", "repeat", "skip", "back"])
@pytest.mark.parametrize("synced", [False, True])
def test_e2e_run_is_what_check_gives_frame_by_frame(how, synced):
    frames = e2e_frames(40, first=5)
    if how == "crc":
        frames[17] = bytes([frames[17][0] ^ 0x40]) + frames[17][1:]
    elif how == "repeat":
        frames[17] = frames[16]
    elif how == "skip":
        del frames[17]
    elif how == "back":
        frames[17] = frames[12]
    a, b, c = (E2EReceiver(0x0123) for _ in range(3))
    for rx in (a, b, c):
        if synced:
            rx.check(e2e_frames(5)[-1])   # counter 4: the run's first (5) is the next
    n = check_run(a, np.frombuffer(b"".join(frames), np.uint8).reshape(-1, 8))
    assert n == e2e_one_by_one(b, frames) == (40 if how == "none" else 17)
    assert e2e_one_by_one(c, frames[:n]) == n and e2e_state(a) == e2e_state(c)


def test_the_run_macs_are_cryptographys_cmac():
    """truncated_macs (the AES of cryptography, the CMAC's two blocks by hand) against
    cryptography's own CMAC (KeyedCmac), 2000 messages: keys, data IDs, frames and FVs drawn
    at random, FVs up to 2**64 - 1."""
    rng = np.random.default_rng(26)
    for _ in range(20):
        key = rng.bytes(16)
        data_id = int(rng.integers(0, 1 << 16))
        pdus = rng.integers(0, 256, (100, 8), dtype=np.uint8)
        fvs = rng.integers(0, 1 << 64, 100, dtype=np.uint64, endpoint=False)
        fvs[:3] = [0, (1 << 64) - 1, 0xFFFFFFFF]
        keyed = KeyedCmac(key)
        want = [keyed.mac(data_id, p.tobytes(), int(fv)) for p, fv in zip(pdus, fvs)]
        assert [m.tobytes() for m in truncated_macs(key, data_id, pdus, fvs)] == want


def test_a_run_of_authenticators_is_each_one_in_turn():
    """authenticators (the tick plan's) against authenticator frame by frame, the counter
    across 2**16 (its low 16 bits are the frame's first two bytes)."""
    rng = np.random.default_rng(27)
    key, pdus = rng.bytes(16), rng.integers(0, 256, (50, 8), dtype=np.uint8)
    got = authenticators(key, 0x123, pdus, 0xDEADBEEF, 0xFFE0)
    assert [a.tobytes() for a in got] == [authenticator(key, 0x123, p.tobytes(), 0xDEADBEEF, 0xFFE0 + i)
                                          for i, p in enumerate(pdus)]


def test_groups_verify_as_one_by_one() -> None:
    """Groups of 12 frames (fcc's identification outputs of a step) with their authenticator:
    verify_run takes the leading groups GroupReceiver.verify_group takes one by one, and stops
    at a group with one byte changed; the MACs are cryptography's CMAC over the 96 bytes."""
    from hil.bus.secoc import GroupReceiver
    from hil.bus.secoc_batch import group_macs
    ids = tuple(range(0x110, 0x11C))
    tx = Sender(KEY, DATA_ID, TRIP)
    rng = np.random.default_rng(34)
    groups = [rng.integers(0, 256, 96, dtype=np.uint8).tobytes() for _ in range(30)]
    auths = [tx.protect(g) for g in groups]
    bad = bytearray(groups[20])
    bad[50] ^= 1
    groups[20] = bytes(bad)
    fvs = (np.uint64(TRIP << 32) | np.arange(1, 31, dtype=np.uint64))
    assert all(group_macs(KEY, DATA_ID, np.frombuffer(g, np.uint8).reshape(1, 96), fvs[i: i + 1])[0].tobytes()
               == KeyedCmac(KEY).mac(DATA_ID, g, int(fvs[i])) for i, g in enumerate(groups[:3]))
    batch = GroupReceiver(KEY, DATA_ID, TRIP, pdu_ids=ids)
    n = verify_run(batch, np.frombuffer(b"".join(groups), np.uint8).reshape(30, 96),
                   np.frombuffer(b"".join(auths), np.uint8).reshape(30, 8))
    single = GroupReceiver(KEY, DATA_ID, TRIP, pdu_ids=ids)
    verdicts = []
    for g, a in zip(groups, auths):
        for j, i in enumerate(ids):
            single.hold_frame(i, g[8 * j: 8 * j + 8])
        verdicts.append(single.verify_group(a)[0])
    assert n == 20 == verdicts.index(Verdict.MAC_FAILED)
    assert batch.counter == 20 and batch.counters.verified == 20
