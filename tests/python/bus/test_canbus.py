"""canbus (firmware/tools/canbus): a CAN bus with wire time between vxcan endpoints.

On vxcan in the guest (scripts/with-vcan; the vcan-marked tests): frames that two nodes queue
while a third one's fifty frames hold the bus reach a fourth node in arbitration order -- with the
first node's queue priority-ordered, and as a FIFO (priority inversion) -- and the times the
receiver's kernel stamps on them are spaced by at least each frame's time on the wire at
125 kbit/s, less the largest delivery error canbus measured itself (why that tolerance: see
test_frames_reach_the_others_in_arbitration_order).  A node's CAN FD frame is counted as lost
(exit 3).  On the host: a bad command line is one line and exit 2, a missing interface exit 1.

    scripts/with-vcan .venv/bin/python -m pytest -m vcan -q -p no:cacheprovider tests/python/bus/test_canbus.py
"""
from __future__ import annotations

import itertools
import json
import select
import signal
import subprocess
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import can
import pytest
from hil.bus.busload import frame_bits

BITRATE = 125_000
BIT_S = 1.0 / BITRATE
BLOCKERS = 50  # frames of the blocking node: ~50 ms of bus at 125 kbit/s
STARTUP_S = 10.0


def _read_line(stream: Any, deadline: float, what: str) -> str:
    ready, _, _ = select.select([stream], [], [], max(0.0, deadline - time.monotonic()))
    line = stream.readline() if ready else ""
    assert line, f"canbus gave no {what} in time"
    return str(line)


@contextmanager
def vxcan_bus(canbus: Path, policies: list[str]) -> Iterator[tuple[subprocess.Popen[str], list[can.BusABC]]]:
    """canbus with one vxcan pair a node (cbN: the node's end, cbNb: canbus's), and a
    python-can socket on each node's end."""
    names = [f"cb{i}" for i in range(len(policies))]
    sockets: list[can.BusABC] = []
    proc = None
    try:
        for name in names:
            subprocess.run(["ip", "link", "add", name, "type", "vxcan", "peer", "name", f"{name}b"],
                           check=True)
            for end in (name, f"{name}b"):
                subprocess.run(["ip", "link", "set", end, "up"], check=True)
        sockets = [can.Bus(interface="socketcan", channel=name) for name in names]
        proc = subprocess.Popen([str(canbus), "--bitrate", str(BITRATE),
                                 *(a for n, p in zip(names, policies) for a in ("--node", f"{n}b:{p}"))],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        assert proc.stderr is not None
        ready = _read_line(proc.stderr, time.monotonic() + STARTUP_S, "ready line")
        assert ready.startswith("canbus: ready:"), ready
        yield proc, sockets
    finally:
        if proc is not None and proc.poll() is None:
            proc.kill()
            proc.wait()
        for s in sockets:
            s.shutdown()
        for name in names:
            subprocess.run(["ip", "link", "del", name], check=False)


def stop(proc: subprocess.Popen[str]) -> tuple[int, dict[str, Any], str]:
    """SIGTERM: canbus's exit status, its last JSON line, its stderr."""
    proc.send_signal(signal.SIGTERM)
    out, err = proc.communicate(timeout=10)
    return proc.returncode, json.loads(out.strip().splitlines()[-1]), err


def receive(sock: can.BusABC, n: int) -> list[can.Message]:
    got: list[can.Message] = []
    while len(got) < n:
        msg = sock.recv(timeout=5.0)
        assert msg is not None, f"{len(got)} of {n} frames arrived"
        got.append(msg)
    assert sock.recv(timeout=0.05) is None, "more frames than were sent"
    return got


def frame_id(msg: can.Message) -> int:
    return int(msg.arbitration_id)


def wire_s(msg: can.Message) -> float:
    return frame_bits(msg.arbitration_id, bytes(msg.data), extended=msg.is_extended_id) * BIT_S


# node 0 (A) queues 0x200, 0x080 and a 29-bit frame with the base 0x010; node 1 (B) 0x100 and
# the 11-bit 0x010, which beats A's 29-bit one; node 2 holds the bus with 0x001s meanwhile.
A_FRAMES = [(0x200, False), (0x080, False), (0x010 << 18 | 1, True)]
B_FRAMES = [(0x100, False), (0x010, False)]
ORDER = {"prio": [0x010, 0x010 << 18 | 1, 0x080, 0x100, 0x200],
         # A's FIFO offers 0x200 first: B's two frames pass it, its own 0x080 waits behind it
         "fifo": [0x010, 0x100, 0x200, 0x080, 0x010 << 18 | 1]}


@pytest.mark.vcan
@pytest.mark.parametrize("policy", ["prio", "fifo"])
def test_frames_reach_the_others_in_arbitration_order(bin_path: Callable[[str], Path],
                                                      policy: str) -> None:
    with vxcan_bus(bin_path("canbus"), [policy, "prio", "prio", "prio"]) as (proc, (a, b, blocker, rx)):
        t_first = time.time()
        for k in range(BLOCKERS):
            blocker.send(can.Message(arbitration_id=0x001, is_extended_id=False, data=bytes([k] * 8)))
        for fid, ext in A_FRAMES:
            a.send(can.Message(arbitration_id=fid, is_extended_id=ext, data=b"\xA5" * 8))
        for fid, ext in B_FRAMES:
            b.send(can.Message(arbitration_id=fid, is_extended_id=ext, data=b"\x5A" * 4))
        sent_by = time.time()
        got = receive(rx, BLOCKERS + 5)
        # This order proves that A's and B's frames were all queued before the blocker's last
        # frame ended: A sent 0x200 first and B 0x100 before 0x010, so on an idle bus 0x200 would
        # lead.  Only a stall of this process longer than the blocker's frames (~50 ms) between
        # its first and last send would make it differ: a failure, not a false pass.
        assert [frame_id(m) for m in got] == [0x001] * BLOCKERS + ORDER[policy], (
            f"sending took {sent_by - t_first:.3f} s")
        assert [bytes(m.data) for m in got[:BLOCKERS]] == [bytes([k] * 8) for k in range(BLOCKERS)]
        # every node gets every frame but its own, in the same order
        assert [frame_id(m) for m in receive(a, BLOCKERS + 2)] == [
            f for f in [0x001] * BLOCKERS + ORDER[policy] if f in (0x100, 0x010, 0x001)]
        assert [frame_id(m) for m in receive(blocker, 5)] == ORDER[policy]
        proc.send_signal(signal.SIGUSR1)  # statistics while running: one JSON line
        assert proc.stdout is not None
        running = json.loads(_read_line(proc.stdout, time.monotonic() + 5.0, "statistics"))
        assert running["frames"] == BLOCKERS + 5 and proc.poll() is None
        status, stats, err = stop(proc)
    assert status == 0, err
    assert err == "", err  # (the ready line was read above)
    assert (stats["bitrate"], stats["frames"], stats["lost"], stats["pending"]) == (BITRATE, BLOCKERS + 5, 0, 0)
    assert [(n["policy"], n["sent"], n["received"]) for n in stats["nodes"]] == [
        (policy, 3, BLOCKERS + 2), ("prio", 2, BLOCKERS + 3), ("prio", BLOCKERS, 5),
        ("prio", 0, BLOCKERS + 5)]
    assert stats["ids"]["0x001"]["n"] == BLOCKERS
    assert stats["ids"]["0x00400001"]["n"] == 1
    # the model's response times (queued -> end of frame) hold at least the frame itself
    assert stats["ids"]["0x200"]["max_s"] >= wire_s(got[-1 if policy == "prio" else -3]) - 3 * BIT_S
    max_err = stats["delivery_error"]["max_s"]
    # Spacing.  In the model frame k+1 cannot end earlier than its wire time after frame k's
    # end (it starts after k's interframe space).  canbus delivers no frame before its end of
    # frame (an absolute sleep on CLOCK_MONOTONIC never returns early) and at most max_err after
    # it (measured after its last write returned, so later than the receiver's kernel stamp).
    # So the receiver's stamps are spaced by at least wire(k+1) - max_err; 2 us for the
    # realtime clock against the monotonic one the model runs on.
    tol = max_err + 2e-6
    for prev, msg in itertools.pairwise(got):
        assert msg.timestamp - prev.timestamp >= wire_s(msg) - tol, (hex(frame_id(msg)), tol)
    span = got[-1].timestamp - got[0].timestamp
    assert span >= sum(wire_s(m) for m in got[1:]) - tol, (span, tol)


@pytest.mark.vcan
def test_a_can_fd_frame_is_lost_and_said(bin_path: Callable[[str], Path]) -> None:
    with vxcan_bus(bin_path("canbus"), ["prio", "prio"]) as (proc, (a, b)):
        fd = can.Bus(interface="socketcan", channel="cb0", fd=True)
        try:
            fd.send(can.Message(arbitration_id=0x123, is_fd=True, data=bytes(12)))
        finally:
            fd.shutdown()
        a.send(can.Message(arbitration_id=0x124, is_extended_id=False, data=b"\x01"))
        assert [frame_id(m) for m in receive(b, 1)] == [0x124]
        status, stats, err = stop(proc)
    assert status == 3
    assert stats["lost"] == 1 and stats["nodes"][0]["lost"] == 1 and stats["frames"] == 1
    assert err.splitlines()[-1] == 'canbus: 1 frame lost in all (see "lost" per node)'


@pytest.mark.parametrize("args, words", [
    (["--node", "cb0b"], "a bus needs at least 2 nodes, 1 given"),
    (["--bitrate", "300000", "--node", "x", "--node", "y"], "not a whole number of nanoseconds"),
    (["--node", "x:lifo", "--node", "y"], "'lifo' is not prio or fifo"),
    (["--node", "x", "--node", "x"], "x is given twice"),
])
def test_a_bad_command_line_is_one_line_and_exit_2(bin_path: Callable[[str], Path],
                                                   args: list[str], words: str) -> None:
    r = subprocess.run([str(bin_path("canbus")), *args], capture_output=True, text=True, timeout=10,
                       check=False)
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr.count("\n") == 1 and r.stderr.startswith("canbus: ") and words in r.stderr


def test_a_missing_interface_is_one_line_and_exit_1(bin_path: Callable[[str], Path]) -> None:
    r = subprocess.run([str(bin_path("canbus")), "--node", "nosuchcan0", "--node", "nosuchcan1"],
                       capture_output=True, text=True, timeout=10, check=False)
    assert r.returncode == 1 and r.stdout == ""
    assert r.stderr == "canbus: no CAN interface nosuchcan0: No such device\n"
