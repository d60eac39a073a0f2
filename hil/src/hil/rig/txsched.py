"""Time-triggered transmission of the simulator's frames: each frame leaves at its sampling
instant, however late the simulator itself is scheduled (it only has to hand the frame over
before the instant: the slack).

The simulator knows its plant one step ahead (y_k is computed once u_(k-1) is in), so it hands
step k's frames over before t_k to a small transmitter process of its own: it sleeps until
each frame's instant on CLOCK_MONOTONIC (the master time's clock) at SCHED_FIFO priority
where allowed, and sends the frame on a raw CAN socket then.  The frames of one step go out
GAP_S apart, in their order.  A frame handed over after its instant goes out at once: the
simulator counts such steps (late) with their slack, the transmitter each frame's send
lateness; nothing is hidden.

Why a process and not the kernel (measured in the UML guest, Linux 6.1): the broadcast
manager (can-bcm) sends a frame at once whenever a transmit timer is started (STARTTIMER
implies TX_ANNOUNCE), so it cannot send one frame at a later instant, and its cyclic timer
re-arms from the expiry's own reading (drifts); the ETF qdisc with SO_TXTIME dropped every
CAN frame (the CAN raw socket sets no transmit time there).

Protocol on the pipe: records of RECORD (instant in ns of CLOCK_MONOTONIC, struct
can_frame); at end of input the transmitter sends what is left at its times and prints one
JSON line of statistics.  With --send-log it also writes, at the end, when each frame was
handed to the socket (CLOCK_REALTIME ns, the clock of the recorder's SO_TIMESTAMP, and the
identifier; SEND_LOG_HEADER): on a real bus the frame's queue time at this node, from which
hil.results.busstats_real measures its response time.

    python -m hil.rig.txsched IFACE [--rt-priority N] [--send-log PATH]   (started by TimedSender;
                                 imports no more than it needs: it starts within the flight)
"""
from __future__ import annotations

import argparse
import heapq
import json
import os
import select
import socket
import struct
import subprocess
import sys
import time
from collections.abc import Sequence

from hil.util.errors import HilError
from hil.util.processes import spawn

#: struct can_frame (hil.rig.link's; not imported: the transmitter starts without the rig)
CAN_FRAME = struct.Struct("=IB3x8s")
RECORD = struct.Struct("=q16s")
#: spacing of one step's frames on the bus (their order is kept)
GAP_S = 20e-6
#: a frame sent this much after its instant counts as late in the transmitter's statistics
LATE_S = 0.0005
#: the send log in a run directory, its first line; then one line a frame sent, in order
SEND_LOG = "sim_sends.csv"
SEND_LOG_HEADER = "t_realtime_ns,can_id"


class TxError(HilError, RuntimeError):
    """The transmitter cannot be started or fed (one line)."""


def _pct(values: Sequence[float], p: float) -> float | None:
    s = sorted(values)
    return round(s[min(len(s) - 1, int(p * len(s)))], 3) if s else None


class TimedSender:
    """The simulator's side: starts the transmitter, hands frames over to it."""

    def __init__(self, iface: str, rt_priority: int = 0, ready_timeout: float = 30.0,
                 send_log: str | None = None) -> None:
        args = [sys.executable, "-m", "hil.rig.txsched", iface]
        if rt_priority:
            args += ["--rt-priority", str(rt_priority)]
        if send_log is not None:
            args += ["--send-log", send_log]
        self.proc = spawn(args, stdin=subprocess.PIPE, stdout=subprocess.PIPE)
        assert self.proc.stdin is not None and self.proc.stdout is not None
        self._fd = self.proc.stdin.fileno()
        self.stats: dict[str, object] = {}
        ready = select.select([self.proc.stdout], [], [], ready_timeout)[0]
        if not ready or self.proc.stdout.readline().strip() != b"ready":
            self.close(1.0)
            raise TxError(f"the frame transmitter on {iface} did not start (python -m hil.rig.txsched)")

    def send_at(self, frames: Sequence[tuple[int, bytes]], instant: float) -> None:
        """Hand one step's frames over, to leave from `instant` (CLOCK_MONOTONIC, s) on."""
        ns = int(round(instant * 1e9))
        gap = int(GAP_S * 1e9)
        recs = b"".join(RECORD.pack(ns + i * gap, CAN_FRAME.pack(fid, len(data), bytes(data)))
                        for i, (fid, data) in enumerate(frames))
        if recs:
            try:
                os.write(self._fd, recs)   # one write of < PIPE_BUF bytes: atomic
            except OSError as e:
                raise TxError(f"the frame transmitter is gone: {e.strerror}") from None

    def close(self, timeout: float = 5.0) -> dict[str, object]:
        """End of input: the transmitter sends what is left at its times; its statistics."""
        assert self.proc.stdin is not None and self.proc.stdout is not None
        if not self.proc.stdin.closed:
            self.proc.stdin.close()
        try:
            if select.select([self.proc.stdout], [], [], timeout)[0]:
                self.stats = json.loads(self.proc.stdout.readline())
            self.proc.wait(timeout)
        except (subprocess.TimeoutExpired, ValueError):
            self.proc.kill()
            self.proc.wait()
        self.proc.stdout.close()
        return self.stats


def serve(fd: int, sock: socket.socket, sends: list[tuple[int, int]] | None = None) -> dict[str, object]:
    """Send every record read from fd at its instant; statistics at end of input; each frame's
    (CLOCK_REALTIME ns as it is handed to the socket, identifier) appended to `sends`."""
    heap: list[tuple[int, int, bytes]] = []
    buf, seq, eof = b"", 0, False
    late_ms: list[float] = []
    while not eof or heap:
        wait = None if not heap else max(0, heap[0][0] - time.monotonic_ns()) * 1e-9
        if eof:
            time.sleep(wait or 0.0)
        elif select.select([fd], [], [], wait)[0]:
            data = os.read(fd, 1 << 16)
            eof = not data
            buf += data
            n = len(buf) // RECORD.size * RECORD.size
            for ns, frame in RECORD.iter_unpack(buf[:n]):
                heapq.heappush(heap, (ns, seq, frame))
                seq += 1
            buf = buf[n:]
        while heap and heap[0][0] <= time.monotonic_ns():
            ns, _, frame = heapq.heappop(heap)
            queued = time.time_ns()
            try:
                sock.send(frame)
            except OSError:
                time.sleep(0.0005)   # a full queue: once more, then it is lost (counted)
                queued = time.time_ns()
                try:
                    sock.send(frame)
                except OSError:
                    late_ms.append(float("inf"))
                    continue
            late_ms.append((time.monotonic_ns() - ns) * 1e-6)
            if sends is not None:
                sends.append((queued, CAN_FRAME.unpack_from(frame)[0]))
    lost = sum(1 for v in late_ms if v == float("inf"))
    sent = [v for v in late_ms if v != float("inf")]
    return {"frames": len(sent), "lost": lost, "late": sum(1 for v in sent if v > LATE_S * 1e3),
            "send_lateness_ms": {"p50": _pct(sent, 0.5), "p99": _pct(sent, 0.99),
                                 "max": _pct(sent, 1.0)}}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("iface")
    ap.add_argument("--rt-priority", type=int, default=0)
    ap.add_argument("--send-log", help="write each frame's send time (CLOCK_REALTIME ns) and identifier here")
    a = ap.parse_args(argv)
    try:
        sock = socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)
        sock.setsockopt(socket.SOL_CAN_RAW, socket.CAN_RAW_FILTER, b"")  # sends only
        sock.bind((a.iface,))
    except OSError as e:
        print(f"txsched: cannot open CAN interface {a.iface!r}: {e.strerror}", file=sys.stderr)
        return 1
    rt = False
    if a.rt_priority:
        try:
            os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(a.rt_priority))
            rt = True
        except OSError:
            pass   # without the privilege: normal priority (reported)
    print("ready", flush=True)
    sends: list[tuple[int, int]] | None = [] if a.send_log else None
    stats = serve(sys.stdin.fileno(), sock, sends)
    stats["sched_fifo"] = rt
    if a.send_log and sends is not None:
        with open(a.send_log, "w", encoding="ascii") as f:
            f.write(SEND_LOG_HEADER + "\n" + "".join(f"{t},{i}\n" for t, i in sends))
    print(json.dumps(stats), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
