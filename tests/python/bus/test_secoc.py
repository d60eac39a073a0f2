"""SecOC-style authentication, Python side (hil.bus.secoc, MAC by `cryptography`): the NIST
SP 800-38B examples, the committed cross-check vectors are current, the README's hand-worked
authenticator, and the receiver's freshness window, replay refusal and held frames."""
from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

from hil.bus import load
from hil.bus.secoc import (CANDIDATES, WINDOW, KeyedCmac, KeyFileError, Receiver, Sender, Verdict,
                           authenticator, cmac, read_key_file, TEST_KEY_FILE, write_key_file)

REPO = Path(__file__).resolve().parents[3]
NIST_KEY = bytes.fromhex("2b7e151628aed2a6abf7158809cf4f3c")
NIST_MSG = bytes.fromhex("6bc1bee22e409f96e93d7e117393172aae2d8a571e03ac9c9eb76fac45af8e51"
                         "30c81c46a35ce411e5fbc1191a0a52eff69f2445df4f9b17ad2b417be66c3710")


@pytest.mark.parametrize("n, tag", [(0, "bb1d6929e95937287fa37d129b756746"),
                                    (16, "070a16b46b4d4144f79bdd9dd04a287c"),
                                    (40, "dfa66747de9ae63030ca32611497c827"),
                                    (64, "51f0bebf7e3b9d92fc49741779363cfe")])
def test_sp800_38b_examples(n: int, tag: str) -> None:
    assert cmac(NIST_KEY, NIST_MSG[:n]).hex() == tag


def test_vectors_are_current(tmp_path: Path) -> None:
    spec_ = importlib.util.spec_from_file_location("gen_crypto_vectors", REPO / "tests" / "gen_crypto_vectors.py")
    assert spec_ is not None and spec_.loader is not None
    gen = importlib.util.module_from_spec(spec_)
    spec_.loader.exec_module(gen)
    for path in gen.generate(tmp_path):
        committed = REPO / "tests" / "vectors" / "crypto" / path.name
        assert committed.read_text() == path.read_text(), \
            f"tests/vectors/crypto/{path.name} is stale: run tests/gen_crypto_vectors.py"


def test_readme_vector() -> None:
    auth = authenticator(bytes(range(16)), 0x2020, bytes.fromhex("9F00010000000000"), 1, 1)
    text = (REPO / "dbc" / "README.md").read_text()
    assert " ".join(f"{b:02X}" for b in auth) in text
    assert load().by_name("SIM_TICK_AUTH").secoc_data_id == 0x2020


def _pair(trip: int = 5) -> tuple[Sender, Receiver]:
    key = read_key_file(TEST_KEY_FILE)
    return Sender(key, 0x2020, trip), Receiver(key, 0x2020, trip)


def test_receiver_accepts_in_order_and_refuses_replays() -> None:
    tx, rx = _pair()
    sent = []
    for k in range(5):
        pdu = bytes([k] * 8)
        auth = tx.protect(pdu)
        sent.append((pdu, auth))
        rx.hold(pdu)
        assert rx.verify(auth) == (Verdict.VERIFIED, pdu)
    for pdu, auth in sent:  # the recording played back
        rx.hold(pdu)
        assert rx.verify(auth)[0] is Verdict.FRESHNESS_FAILED
    # the 5 replayed frames stay held until evicted: 4 fit, 1 dropped
    assert rx.counters.as_dict() == {"verified": 5, "mac_failed": 0, "freshness_failed": 5,
                                     "unpaired": 1}


def test_forgeries_do_not_displace_the_genuine_frame() -> None:
    tx, rx = _pair()
    pdu = bytes(range(8))
    auth = tx.protect(pdu)
    rx.hold(pdu)
    rx.hold(bytes(8))                                   # forged frame squeezed in
    bad = auth[:7] + bytes([auth[7] ^ 1])
    assert rx.verify(bad)[0] is Verdict.MAC_FAILED      # forged authenticator: nothing lost
    assert rx.verify(auth) == (Verdict.VERIFIED, pdu)
    other = Sender(tx.key, 0x2020, trip=6, counter=tx.counter)  # same key, another fcc session
    rx.hold(pdu)
    assert rx.verify(other.protect(pdu))[0] is Verdict.MAC_FAILED
    for _ in range(CANDIDATES + 1):                    # a flood evicts, and says so
        rx.hold(bytes(8))
    assert rx.counters.unpaired == 3


def test_window() -> None:
    tx, rx = _pair()
    tx.counter = WINDOW - 1
    rx.hold(b"\x01" * 8)
    assert rx.verify(tx.protect(b"\x01" * 8))[0] is Verdict.VERIFIED
    tx.counter += WINDOW
    rx.hold(b"\x01" * 8)
    assert rx.verify(tx.protect(b"\x01" * 8))[0] is Verdict.FRESHNESS_FAILED


def test_key_files(tmp_path: Path) -> None:
    assert read_key_file(TEST_KEY_FILE) == bytes(range(16))
    k = write_key_file(tmp_path / "k")
    assert read_key_file(tmp_path / "k") == k and (tmp_path / "k").stat().st_mode & 0o077 == 0
    (tmp_path / "bad").write_text("00112233\n")
    with pytest.raises(KeyFileError, match="32 hex digits"):
        read_key_file(tmp_path / "bad")
    with pytest.raises(KeyFileError, match="cannot read"):
        read_key_file(tmp_path / "missing")


def test_a_keyed_cmac_carries_nothing_from_one_message_to_the_next() -> None:
    """KeyedCmac copies its keyed context per message: any order of messages gives each one
    the MAC a fresh CMAC gives it (the NIST SP 800-38B examples)."""
    keyed = KeyedCmac(NIST_KEY)
    for n in (64, 0, 40, 16, 40, 64):
        assert keyed.digest(NIST_MSG[:n]) == cmac(NIST_KEY, NIST_MSG[:n])
    assert keyed.digest(NIST_MSG[:16]).hex() == "070a16b46b4d4144f79bdd9dd04a287c"


def test_a_group_survives_forged_copies_forged_authenticators_and_a_lost_one() -> None:
    """fcc's output group (12 frames, one authenticator): a forged copy of a member beside
    fcc's (before or after it), a forged authenticator before fcc's, and a group whose
    authenticator never came: every genuine group after them verifies, the forged copies
    counted as conflicts and unpaired."""
    from hil.bus.secoc import GroupReceiver, Sender, Verdict
    key, data_id, trip = bytes(range(16)), 0x2134, 9
    ids = tuple(range(0x110, 0x11C))
    tx, rx = Sender(key, data_id, trip), GroupReceiver(key, data_id, trip, pdu_ids=ids)

    def group(k: int) -> list[tuple[int, bytes]]:
        return [(i, bytes([k, j]) + bytes(6)) for j, i in enumerate(ids)]

    def send(frames: list[tuple[int, bytes]]) -> bytes:
        return tx.protect(b"".join(d for _, d in frames))

    forged = (0x110, b"\x66" * 8)
    results = []
    for k in range(8):
        g, auth = group(k), send(group(k))
        frames: list[tuple[int, bytes]] = list(g)
        if k == 1:
            frames.insert(3, forged)                     # a forged copy after fcc's 0x110
        if k == 2:
            frames.insert(0, forged)                     # ... and before it
        for fid, data in frames:
            rx.hold_frame(fid, data)
        if k == 3:
            assert rx.verify_group(bytes(2) + b"\x01" * 6)[0] is Verdict.FRESHNESS_FAILED
            assert rx.verify_group(auth[:2] + b"\x01" * 6)[0] is Verdict.MAC_FAILED
        if k == 5:
            continue                                     # its authenticator lost
        verdict, got = rx.verify_group(auth)
        results.append(verdict)
        assert got == g, k
    assert results == [Verdict.VERIFIED] * 7
    assert rx.conflicts == 2 + 12                        # the forgeries; group 5's copies beside 6's
    assert rx.counters.unpaired == 2 + 12


def test_a_groups_candidates_depart_from_the_newest_copies_fewest_first() -> None:
    """The concatenations a group's authenticator is tried on, in their order: all newest, then
    one older copy (member by member, newest of the older first), then two, ...; members
    held once never depart (a group of 12 single copies: one candidate)."""
    from hil.bus.secoc import _combinations
    a, b, c = [b"a1", b"a0"], [b"b0"], [b"c2", b"c1", b"c0"]   # each member's copies, newest first
    assert list(_combinations([a, b, c])) == [
        b"a1b0c2",                          # all newest
        b"a0b0c2", b"a1b0c1", b"a1b0c0",    # one older copy
        b"a0b0c1", b"a0b0c0"]               # two
    assert list(_combinations([[bytes([k])] for k in range(12)])) == [bytes(range(12))]
