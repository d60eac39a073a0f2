"""slcan_bridge (firmware/tools/slcan_bridge) on vcan0, with this test as the line's other end
(where QEMU's UART0 would be): it opens the channel as slcand does, a frame on the bus becomes
its SLCAN line (with -z its kernel receive stamp appended), a frame line becomes a frame on the
bus, a full queue is one line and exit 3, the line closing ends it with its summary."""
from __future__ import annotations

import re
import select
import socket
import subprocess
import time
from collections.abc import Iterator
from pathlib import Path

import can
import pytest

pytestmark = pytest.mark.vcan
IFACE = "vcan0"
TIMEOUT = 10.0


@pytest.fixture
def bus() -> Iterator[can.BusABC]:
    with can.Bus(interface="socketcan", channel=IFACE, receive_own_messages=False) as b:
        yield b


def _start(bin_path, sock: Path, *args: str) -> subprocess.Popen[str]:
    proc = subprocess.Popen([str(bin_path("slcan_bridge")), "-i", IFACE, "-u", str(sock), *args],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert proc.stdout is not None
    assert proc.stdout.readline() == "slcan_bridge: ready\n"
    return proc


def _connect(proc: subprocess.Popen[str], sock: Path) -> socket.socket:
    line = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    line.connect(str(sock))
    assert proc.stdout is not None and proc.stdout.readline() == "slcan_bridge: connected\n"
    return line


def _read_until(line: socket.socket, want: bytes) -> bytes:
    got = b""
    deadline = time.monotonic() + TIMEOUT
    while not got.endswith(want):
        r, _, _ = select.select([line], [], [], max(0.0, deadline - time.monotonic()))
        assert r, f"no {want!r} from the bridge (got {got!r})"
        chunk = line.recv(4096)
        assert chunk, f"the bridge closed the line (got {got!r})"
        got += chunk
    return got


def test_frames_cross_both_ways_with_their_bus_time(tmp_path, bin_path, bus):
    sock = tmp_path / "uart0.sock"
    proc = _start(bin_path, sock, "-z")
    line = _connect(proc, sock)
    assert _read_until(line, b"O\r") == b"\r\r\rC\rS6\rZ2\rO\r"   # slcand -o -c -s6, and Z2
    line.sendall(b"\r\r\r\r\r")                                   # the image's answers: OK
    bus.send(can.Message(arbitration_id=0x040, data=b"\x01\x02\xAB", is_extended_id=False))
    got = _read_until(line, b"\r").decode()
    m = re.fullmatch(r"t0403(0102AB)([0-9A-F]{8})\r", got)
    assert m, got
    stamp_us = int(m[2], 16)
    now_us = time.clock_gettime_ns(time.CLOCK_MONOTONIC) // 1000 % 2**32
    assert 0 <= (now_us - stamp_us) % 2**32 < TIMEOUT * 1e6   # the frame's time on vcan0, passed
    line.sendall(b"t0302BEEF\r\a")                                # a frame, then an error answer
    rx = bus.recv(TIMEOUT)
    assert rx is not None and rx.arbitration_id == 0x030 and bytes(rx.data) == b"\xBE\xEF"
    line.close()                                                  # QEMU gone: the session is over
    assert proc.wait(TIMEOUT) == 0
    summary = proc.stderr.read() if proc.stderr else ""
    assert re.search(r"slcan_bridge: summary to_image=1 from_image=1 answers_ok=5 "
                     r"answers_error=1 lines_bad=0 ", summary), summary
    assert not sock.exists()


def test_a_full_queue_is_one_line_and_exit_3(tmp_path, bin_path, bus):
    """The line takes nothing (its reader never reads): the kernel's smallest socket buffer,
    then the queue of 2 frames, then a frame dropped -- said, never silent."""
    sock = tmp_path / "uart0.sock"
    proc = _start(bin_path, sock, "-n", "2", "-b", "1")
    line = _connect(proc, sock)
    for i in range(500):  # more than ~4.6 kB of 22-character lines
        if proc.poll() is not None:
            break
        bus.send(can.Message(arbitration_id=0x041, data=bytes([i & 0xFF] * 8), is_extended_id=False))
    assert proc.wait(TIMEOUT) == 3
    err = proc.stderr.read().splitlines() if proc.stderr else []
    assert err[0] == ("slcan_bridge: a frame dropped on its way to the image (the queue of 2 frames "
                      "toward the line was full: the line is slower than the bus)"), err
    assert err[1].startswith("slcan_bridge: summary ") and len(err) == 2, err
    line.close()


def test_an_existing_path_is_refused_and_kept(tmp_path, bin_path):
    sock = tmp_path / "uart0.sock"
    sock.write_text("a user's file")
    r = subprocess.run([str(bin_path("slcan_bridge")), "-i", IFACE, "-u", str(sock)],
                       capture_output=True, text=True, timeout=TIMEOUT)
    assert r.returncode == 1 and r.stdout == ""
    assert r.stderr.splitlines()[0] == f"slcan_bridge: {sock} exists (the bridge replaces nothing)"
    assert sock.read_text() == "a user's file"


def test_an_interface_that_is_not_there(tmp_path, bin_path):
    r = subprocess.run([str(bin_path("slcan_bridge")), "-i", "nocan9", "-u", str(tmp_path / "s")],
                       capture_output=True, text=True, timeout=TIMEOUT)
    assert r.returncode == 1
    assert r.stderr.splitlines()[0] == "slcan_bridge: cannot open CAN interface nocan9"
