"""The simulator's time-triggered transmitter (hil.rig.txsched) on vcan0: every frame handed over
goes on the bus, not before its instant, a step's frames in their order; a hand-over after its
instant goes out at once.  No bound on lateness here (the machine may be loaded): the
transmitter counts it, and scripts/bench realtime reports it."""
from __future__ import annotations

import socket
import time

import pytest

from hil.rig.link import SO_TIMESTAMPNS, MonotonicStamps
from hil.rig.txsched import GAP_S, TimedSender

pytestmark = pytest.mark.vcan


def test_frames_leave_at_their_instants_in_order():
    rx = socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)
    rx.setsockopt(socket.SOL_SOCKET, SO_TIMESTAMPNS, 1)
    rx.settimeout(10.0)
    rx.bind(("vcan0",))
    stamps = MonotonicStamps()
    tx = TimedSender("vcan0")
    sent: list[tuple[float, int, bytes]] = []
    try:
        # two frames per hand-over, the hand-overs 4 gaps apart by construction: their frames
        # cannot interleave however fast or slow this loop runs
        first = time.monotonic() + 0.01
        for k in range(20):
            instant = first + k * 4 * GAP_S
            frames = [(0x040, bytes([k, 1])), (0x041, bytes([k, 2]))]
            tx.send_at(frames, instant)
            sent += [(instant + i * GAP_S, fid, data) for i, (fid, data) in enumerate(frames)]
        tx.send_at([(0x042, b"\x07")], time.monotonic() - 1.0)   # handed over too late
        sent.append((-1.0, 0x042, b"\x07"))
        got = []
        for _ in sent:
            raw, anc, _, _ = rx.recvmsg(16, socket.CMSG_SPACE(16))
            at = stamps.of(anc)
            assert at is not None
            got.append((at, int.from_bytes(raw[:4], "little"), raw[8:8 + raw[4]]))
    finally:
        stats = tx.close()
        rx.close()
    late_one = [g for g in got if g[1] == 0x042]
    on_time = [g for g in got if g[1] != 0x042]
    assert len(late_one) == 1 and [(f, d) for _, f, d in on_time] == [(f, d) for _, f, d in sent[:-1]]
    for (at, _, _), (instant, _, _) in zip(on_time, sent):
        assert at >= instant - 200e-6   # never early (stamp conversion: a few microseconds)
    assert stats["frames"] == len(sent) and stats["lost"] == 0
    assert stats["send_lateness_ms"]["max"] >= 1000.0   # the late hand-over, counted
