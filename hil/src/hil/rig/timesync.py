"""The simulator as the bus's time master: TSYNC_SYNC + TSYNC_FOLLOW_UP (dbc/fcc_hil.dbc), in the
manner of CANopen SYNC / AUTOSAR CAN time synchronisation; fcc follows it (firmware/timesync).

Master time = microseconds of CLOCK_MONOTONIC since the master's epoch (when it was created):
the clock the realtime runner's deadlines are on, so step k of a flight that starts at master
time t0 is sampled at exactly t0 + k T in master time.  Every interval the master queues a SYNC
(sequence number, whole seconds), reads the frame's own loopback echo with its kernel receive
stamp -- the time the frame was on the bus (vcan echoes it at once, a real controller on
transmit completion) -- and sends the FOLLOW_UP with that precise time, then TSYNC_AUTH, the
SecOC authenticator of the pair (fcc uses a pair only once it verified: dbc/README.md,
firmware/app/README.md "Time synchronisation").  It runs in a thread for the whole realtime
session, so fcc stays locked between flights too.

On the wire-time bus (`hil run --bus wire`) the local echo comes when the frame is sent, not
when it has been on the bus: there the master reads its SYNC as another node received it, on
`echo_iface` (the recorder's end, to which canbus writes it with fcc's, at its end of frame), as
a real controller reports transmit completion.
"""
from __future__ import annotations

import math
import select
import socket
import struct
import threading
import time

from hil.bus import FrameCodec
from hil.bus.secoc import Sender
from hil.rig.link import CAN_FRAME, SO_TIMESTAMPNS, MonotonicStamps

#: sync period (s); fcc's loss-of-sync timeout is 3 intervals
SYNC_INTERVAL_S = 0.1
#: the SYNC goes out this far after each interval boundary (between the steps of every period
#: on the 2.5 ms grid: periods are multiples of 2.5 ms, this is 1.25 ms off it)
SYNC_PHASE_S = 0.00125
MASTER_ID = 1


class UsablePairs:
    """The longest time fcc waited for a pair it could use, as the master sees it: from the SYNC
    of one usable pair to the last frame of the next (SYNC, FOLLOW_UP and TSYNC_AUTH sent).  fcc
    holds a pair until its authenticator verifies, and drops a SYNC whose pair is not complete
    one interval after it (fcc_tsync_poll: missing_fup, then the late FOLLOW_UP an orphan_fup):
    such a pair is no use to it.  fcc loses the sync when this wait passes 3 intervals, whatever
    the gaps between SYNCs were -- a master stalled between a SYNC and its FOLLOW_UP
    (hil.results.platform judges the loss the platform's by it)."""

    def __init__(self, interval_s: float) -> None:
        self.interval_s = interval_s
        self.max_wait_s = 0.0
        self._last_sync: float | None = None   # CLOCK_MONOTONIC of the last usable pair's SYNC

    def complete(self, sync_tx: float, done: float) -> None:
        """A pair whose SYNC was on the bus at sync_tx and whose last frame went out at done."""
        if done - sync_tx > self.interval_s:
            return   # fcc dropped its SYNC before the pair was complete
        if self._last_sync is not None:
            self.max_wait_s = max(self.max_wait_s, done - self._last_sync)
        self._last_sync = sync_tx

    def longest(self, now: float | None = None) -> float:
        """The longest wait (s), including the one still open at `now` (None: only those over)."""
        if now is None or self._last_sync is None:
            return self.max_wait_s
        return max(self.max_wait_s, now - self._last_sync)


class TimeMaster:
    """Publishes the master time on one interface until stop()."""

    def __init__(self, iface: str, codec: FrameCodec, *, auth: Sender | None = None,
                 master_id: int = MASTER_ID, interval_s: float = SYNC_INTERVAL_S,
                 echo_iface: str | None = None) -> None:
        """auth: the sender of TSYNC_AUTH (the session's key and fcc's trip,
        Endpoint.group_sender); None sends no authenticator (fcc then follows nothing);
        echo_iface: where the SYNC is read back as the bus delivered it (None: its own echo)."""
        self.codec = codec
        self.auth = auth
        self._auth_id = codec.spec.by_name("TSYNC_AUTH").frame_id
        self.master_id = master_id
        self.interval_s = interval_s
        self.epoch = time.monotonic()
        self._sync = codec.spec.by_name("TSYNC_SYNC")
        self.sock = socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)
        self.sock.setsockopt(socket.SOL_CAN_RAW, socket.CAN_RAW_RECV_OWN_MSGS, 1)
        self.sock.setsockopt(socket.SOL_CAN_RAW, socket.CAN_RAW_FILTER,
                             struct.pack("=II", self._sync.frame_id, 0x7FF))
        self.sock.setsockopt(socket.SOL_SOCKET, SO_TIMESTAMPNS, 1)
        self.sock.bind((iface,))
        self._echo_sock = self._sync_reader(echo_iface) if echo_iface is not None else None
        self._echo_timeout_s = 0.05 if echo_iface is None else 0.9 * interval_s
        self._stamps = MonotonicStamps()
        self.seq = 0
        self.sent = 0
        self.no_echo = 0
        #: SYNC / FOLLOW_UP frames sent that no TSYNC_AUTH covers (fcc drops each one,
        #: counted in FCC_SYNC_REFUSALS.unauthenticated: the rig tells them from forgeries)
        self.unpaired_frames = 0
        #: the longest time between two SYNCs on the bus (s): how long the platform starved the
        #: master's thread (less one interval), the rig's own stall (hil.results.platform)
        self.max_gap_s = 0.0
        self._last_tx: float | None = None
        self.pairs = UsablePairs(interval_s)
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None

    def _sync_reader(self, iface: str) -> socket.socket:
        sock = socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)
        sock.setsockopt(socket.SOL_CAN_RAW, socket.CAN_RAW_FILTER, struct.pack("=II", self._sync.frame_id, 0x7FF))
        sock.setsockopt(socket.SOL_SOCKET, SO_TIMESTAMPNS, 1)
        sock.bind((iface,))
        return sock

    # -- time base
    def master_us(self, mono: float | None = None) -> int:
        """Master time (us) of a CLOCK_MONOTONIC reading (now by default)."""
        return int(round(((time.monotonic() if mono is None else mono) - self.epoch) * 1e6))

    def published(self, master_us: int) -> int:
        """The master time put into a SYNC / FOLLOW_UP for the true master time master_us: the
        same (a test's faulty master overrides it)."""
        return master_us

    def monotonic(self, master_us: int) -> float:
        return self.epoch + master_us * 1e-6

    def aligned_start(self, lead_s: float, periods_s: list[float]) -> float:
        """CLOCK_MONOTONIC of the first master instant at least lead_s ahead on which every
        period's grid starts (a multiple of the periods' least common multiple)."""
        grid = math.lcm(*(max(1, int(round(p * 1e6))) for p in periods_s))
        first = -(-(self.master_us() + int(lead_s * 1e6)) // grid) * grid
        return self.monotonic(first)

    # -- one sync
    def _echo_stamp(self, sent: bytes, timeout_s: float) -> float | None:
        """CLOCK_MONOTONIC at which our own SYNC `sent` was on the bus (its echo's kernel
        stamp).  Echoes of earlier frames (one whose echo was never read) are skipped: the
        bytes must be the ones just sent (sequence number and E2E counter in them)."""
        sock = self._echo_sock or self.sock
        end = time.monotonic() + timeout_s
        while (left := end - time.monotonic()) > 0:
            if not select.select([sock], [], [], left)[0]:
                return None
            raw, anc, flags, _ = sock.recvmsg(CAN_FRAME.size, socket.CMSG_SPACE(16))
            ours = flags & socket.MSG_CONFIRM or sock is self._echo_sock  # (it hears no other node)
            if not ours or raw != sent:
                continue  # another node's SYNC (a second master), or an old echo
            return self._stamps.of(anc)
        return None

    def send_sync(self) -> bool:
        """One SYNC and its FOLLOW_UP; False when the echo did not come (no FOLLOW_UP)."""
        seq = self.seq
        self.seq = (self.seq + 1) & 0xFF
        sec = max(0, self.published(self.master_us())) // 1_000_000
        fid, sync = self.codec.encode("TSYNC_SYNC", {
            "master": self.master_id, "seq": seq, "interval_ms": int(round(self.interval_s * 1e3)),
            "sec": sec})
        raw = CAN_FRAME.pack(fid, len(sync), bytes(sync))
        self.sock.send(raw)
        self.sent += 1
        self.unpaired_frames += 1   # until its FOLLOW_UP and authenticator are out
        tx = self._echo_stamp(raw, self._echo_timeout_s)
        if tx is None:
            self.no_echo += 1
            return False
        if self._last_tx is not None:
            self.max_gap_s = max(self.max_gap_s, tx - self._last_tx)
        self._last_tx = tx
        m = self.published(self.master_us(tx))
        carry = m // 1_000_000 - sec
        if carry not in (0, 1):
            self.no_echo += 1
            return False
        fid, fup = self.codec.encode("TSYNC_FOLLOW_UP", {
            "master": self.master_id, "seq": seq, "sec_carry": carry,
            "ns": (m % 1_000_000) * 1000})
        self.sock.send(CAN_FRAME.pack(fid, len(fup), bytes(fup)))
        self.unpaired_frames += 1
        if self.auth is not None:
            tag = self.auth.protect(bytes(sync) + bytes(fup))
            self.sock.send(CAN_FRAME.pack(self._auth_id, len(tag), tag))
            self.unpaired_frames -= 2
            self.pairs.complete(tx, time.monotonic())
        return True

    # -- the thread
    def start(self) -> None:
        if self._thread is None:
            self._thread = threading.Thread(target=self._run, name="time-master", daemon=True)
            self._thread.start()

    def _run(self) -> None:
        interval_us = int(round(self.interval_s * 1e6))
        phase_us = int(round(SYNC_PHASE_S * 1e6))
        while not self._stop.is_set():
            nxt = (self.master_us() // interval_us + 1) * interval_us + phase_us
            if self._stop.wait(max(0.0, self.monotonic(nxt) - time.monotonic())):
                break
            try:
                self.send_sync()
            except OSError:
                self.no_echo += 1  # interface gone: fcc will go to holdover and count it

    def stop(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(2.0)
            self._thread = None
        self.sock.close()
        if self._echo_sock is not None:
            self._echo_sock.close()

    def stats(self) -> dict[str, int]:
        """run_info.json's `time_master`; while the master runs, its pair gap includes the wait
        since its last usable pair (a stall not yet over is fcc's wait too)."""
        pair_gap = self.pairs.longest(time.monotonic() if self._thread is not None else None)
        return {"syncs_sent": self.sent, "syncs_without_echo": self.no_echo,
                "unpaired_frames": self.unpaired_frames, "max_sync_gap_ms": int(round(self.max_gap_s * 1e3)),
                "max_pair_gap_ms": int(round(pair_gap * 1e3))}
