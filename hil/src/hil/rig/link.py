"""The simulator's CAN socket: on SocketCAN a raw CAN_RAW socket (hil.bus.rawcan), on any
other interface python-can's bus.

Why not ``bus.send(can.Message)`` / ``bus.recv()``: in the User-Mode Linux guest every system
call is slow, and python-can's receive path costs a ``select()`` plus a ``recvmsg()`` per
frame.  Here a receive is one blocking ``recvmmsg()`` bounded by ``SO_RCVTIMEO`` (a short
slice, so that the caller can notice a dead firmware or a deadline between slices) that takes
every frame already queued behind the first (fcc's answer to a step comes in one burst: one
system call instead of one per frame; the others are handed out from the link's read-ahead by
the next receives, whichever method), and a send is one ``send()`` of a pre-packed
``struct can_frame``, or one ``sendmmsg()`` of a step's frames.  The socket is opened with the standard
library (python-can alone costs about a second to import in the guest), with the settings
python-can's SocketCAN bus would give it (hil.bus.rawcan).

Any other python-can interface (``interface="pcan"``, ``"slcan"``, ``"kvaser"`` ...) goes through
python-can's own ``send()``/``recv()``; there the link is also the bus recorder (no candump
beside it: many adapters cannot be opened twice): every frame it sends and every frame it
receives goes to ``log_path`` in the candump ``-L`` format (``hil.bus.candump.format_line``),
in the order the rig saw them, and the receive filter is applied in Python after logging.
"""
from __future__ import annotations

import errno
import math
import select
import socket
import struct
import time
from collections import deque
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING, Any, TextIO

from hil.bus.candump import format_line
from hil.bus.canif import check_up, open_error
from hil.bus.mmsg import MSG_WAITFORONE, BatchReceiver, BatchSender
from hil.bus.rawcan import CAN_FRAME, RECEIVE_BUFFER_BYTES, enlarge_receive_buffer, open_raw, pack_frame
from hil.util.errors import HilError

if TYPE_CHECKING:
    import can

CAN_MTU = CAN_FRAME.size
CAN_EFF_FLAG = 0x80000000
CAN_RTR_FLAG = 0x40000000
CAN_ERR_FLAG = 0x20000000
#: receive slice: how often a blocked receive wakes up to check deadlines and the firmware
RECV_SLICE_S = 0.05
#: a full transmit queue (ENOBUFS) is retried this long before the frame counts as dropped
SEND_RETRY_S = 0.05

_TIMEVAL = struct.Struct("@ll")
#: SO_TIMESTAMPNS on Linux (the socket module does not always export it)
SO_TIMESTAMPNS = getattr(socket, "SO_TIMESTAMPNS", 35)
_TIMESPEC = struct.Struct("=qq")


class MonotonicStamps:
    """SocketCAN's receive stamps (CLOCK_REALTIME) on CLOCK_MONOTONIC, the rig's clock: the
    offset is the tightest of 5 bracketed readings (a preempted reading would shift every
    stamp), renewed every second."""

    def __init__(self) -> None:
        self._rt_minus_mono = 0.0
        self._at = -math.inf

    def monotonic(self, realtime: float) -> float:
        now = time.monotonic()
        if now - self._at > 1.0:
            best = math.inf
            for _ in range(5):
                m0 = time.monotonic()
                r = time.time()
                m1 = time.monotonic()
                if m1 - m0 < best:
                    best, self._rt_minus_mono = m1 - m0, r - 0.5 * (m0 + m1)
            self._at = now
        return realtime - self._rt_minus_mono

    def of(self, ancdata: list[tuple[int, int, bytes]]) -> float | None:
        """CLOCK_MONOTONIC of a recvmsg()'s SO_TIMESTAMPNS stamp (None: none there)."""
        for level, kind, data in ancdata:
            if level == socket.SOL_SOCKET and kind == SO_TIMESTAMPNS and len(data) >= _TIMESPEC.size:
                sec, nsec = _TIMESPEC.unpack_from(data)
                return self.monotonic(sec + nsec * 1e-9)
        return None


class LinkError(HilError, RuntimeError):
    """The interface cannot be opened or used (one line)."""


class CanLink:
    """One CAN socket on an interface: raw SocketCAN, or python-can's bus of another interface."""

    #: python-can interfaces driven through the raw socket (the others: python-can's send/recv)
    RAW_INTERFACES = frozenset({"socketcan"})

    @classmethod
    def is_raw(cls, interface: str) -> bool:
        """Raw SocketCAN (recorded by candump), or python-can's path (recorded by the link)."""
        return interface in cls.RAW_INTERFACES

    def __init__(self, channel: str, frame_ids: Iterable[int] | None = None,
                 rcvbuf: int = RECEIVE_BUFFER_BYTES, *, interface: str = "socketcan",
                 bitrate: int | None = None, log_path: Path | None = None) -> None:
        """frame_ids: the identifiers to receive (kernel filters); None: every frame.
        interface/bitrate: python-can's; log_path: record the bus (not with socketcan)."""
        self.channel = channel
        self.interface = interface
        self.tx_frames = 0
        self.tx_retries = 0
        self.tx_dropped = 0
        self.rx_frames = 0
        if not self.is_raw(interface):
            self._open_generic(frame_ids, bitrate, log_path)
            return
        if log_path is not None:
            raise ValueError("on SocketCAN the recorder is candump, not the link")
        try:
            check_up(channel)
            self.sock: socket.socket = open_raw(channel, frame_ids)
        except OSError as e:
            raise LinkError(open_error(channel, e)) from None
        self._generic = False
        self.writer: TextIO | None = None
        self.bus: can.BusABC | None = None
        enlarge_receive_buffer(self.sock, rcvbuf)
        self._slice = -1.0
        self.set_slice(RECV_SLICE_S)
        self._poll = select.poll()
        self._poll.register(self.sock, select.POLLIN)
        self._stamps: MonotonicStamps | None = None
        self._batch = BatchSender(self.sock.fileno()) if BatchSender.available() else None
        self._batch_rx = BatchReceiver(self.sock.fileno()) if BatchReceiver.available() else None
        #: frames a recvmmsg took behind the one it handed out: the next receives' first
        self._ahead: deque[tuple[int, bytes]] = deque()

    def _open_generic(self, frame_ids: Iterable[int] | None, bitrate: int | None,
                      log_path: Path | None) -> None:
        import can  # only the other interfaces need python-can (slow to import)
        kwargs: dict[str, Any] = {} if bitrate is None else {"bitrate": bitrate}
        try:
            self.bus = can.Bus(interface=self.interface, channel=self.channel,
                               receive_own_messages=False, **kwargs)
        except (OSError, ValueError, ImportError, can.CanError) as e:
            raise LinkError(f"cannot open CAN interface {self.interface}:{self.channel}: "
                            f"{str(e).splitlines()[0] if str(e) else type(e).__name__}") from None
        self._generic = True
        self._wanted = None if frame_ids is None else frozenset(frame_ids)
        self._slice = RECV_SLICE_S
        self.writer = None if log_path is None else open(log_path, "w", encoding="ascii")  # noqa: SIM115
        self._t0 = time.time() - time.monotonic()

    def _log(self, msg: can.Message) -> None:
        """One log line, stamped with the rig's clock (adapters' own clocks have other epochs)."""
        if self.writer is not None:
            self.writer.write(format_line(self._t0 + time.monotonic(), self.channel,
                                          msg.arbitration_id, bytes(msg.data),
                                          msg.is_extended_id) + "\n")

    def _send_generic(self, frame_id: int, data: bytes) -> bool:
        import can
        if self.bus is None:
            raise LinkError(f"{self.channel}: cannot send: the link is closed")
        msg = can.Message(arbitration_id=frame_id, data=data, is_extended_id=frame_id > 0x7FF,
                          channel=self.channel)
        try:
            self.bus.send(msg, timeout=SEND_RETRY_S)
        except can.CanOperationError:
            self.tx_dropped += 1
            return False
        except can.CanError as e:
            raise LinkError(f"{self.channel}: cannot send: {e}") from None
        self.tx_frames += 1
        self._log(msg)
        return True

    def _recv_generic(self, timeout: float) -> tuple[int, bytes] | None:
        """The next wanted frame within timeout s (every frame received is logged)."""
        import can
        if self.bus is None:
            raise LinkError(f"{self.channel}: cannot receive: the link is closed")
        deadline = time.monotonic() + timeout
        while True:
            try:
                msg = self.bus.recv(max(0.0, deadline - time.monotonic()))
            except can.CanError as e:
                raise LinkError(f"{self.channel}: cannot receive: {e}") from None
            if msg is None:
                return None
            if msg.is_error_frame or msg.is_remote_frame:
                continue
            self.rx_frames += 1
            self._log(msg)
            if self._wanted is None or msg.arbitration_id in self._wanted:
                return msg.arbitration_id, bytes(msg.data)
            if time.monotonic() >= deadline:
                return None

    def set_slice(self, seconds: float) -> None:
        """Longest time one recv() blocks (SO_RCVTIMEO)."""
        if self._generic:
            self._slice = seconds
        elif seconds != self._slice:
            sec = int(seconds)
            self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVTIMEO,
                                 _TIMEVAL.pack(sec, int((seconds - sec) * 1e6)))
            self._slice = seconds

    @property
    def slice_s(self) -> float:
        """Longest time one recv() blocks."""
        return self._slice

    # -- transmit
    def send_raw(self, raw: bytes) -> bool:
        """Send one packed struct can_frame; False when the queue stayed full (counted)."""
        if self._generic:
            can_id, dlc, data = CAN_FRAME.unpack(raw)
            return self._send_generic(can_id & 0x1FFFFFFF, data[:dlc])
        deadline: float | None = None   # set at the first full queue: retries for SEND_RETRY_S
        while True:
            try:
                self.sock.send(raw)
                self.tx_frames += 1
                return True
            except OSError as e:
                if e.errno not in (errno.ENOBUFS, errno.EAGAIN):
                    raise LinkError(f"{self.channel}: cannot send: {e.strerror}") from None
            now = time.monotonic()
            if deadline is None:
                deadline = now + SEND_RETRY_S
            elif now >= deadline:
                self.tx_dropped += 1
                return False
            self.tx_retries += 1
            time.sleep(0.0005)

    def send_many(self, raws: list[bytes]) -> int:
        """Send packed struct can_frames in their order, in as few sendmmsg(2) calls as the
        queue allows (a full queue is retried as in send_raw); how many were dropped."""
        batch = None if self._generic else self._batch
        if batch is None or len(raws) == 1:
            return sum(not self.send_raw(r) for r in raws)
        dropped = 0
        while raws:
            n = batch.load(raws)
            i, deadline = 0, None
            while i < n:
                got = batch.send(i, n)
                if got > 0:
                    i += got
                    self.tx_frames += got
                    deadline = None
                    continue
                if -got not in (errno.ENOBUFS, errno.EAGAIN):
                    raise LinkError(f"{self.channel}: cannot send: {errno.errorcode.get(-got, -got)}")
                now = time.monotonic()
                if deadline is None:
                    deadline = now + SEND_RETRY_S
                elif now >= deadline:   # this frame is lost (counted); the next ones are tried
                    self.tx_dropped += 1
                    dropped += 1
                    i += 1
                    deadline = None
                    continue
                self.tx_retries += 1
                time.sleep(0.0005)
            raws = raws[n:]
        return dropped

    def send(self, frame_id: int, data: bytes) -> bool:
        return self.send_raw(pack_frame(frame_id, data))

    # -- receive
    @staticmethod
    def _frame(raw: bytes) -> tuple[int, bytes]:
        can_id, dlc, data = CAN_FRAME.unpack(raw)
        return can_id & 0x1FFFFFFF if can_id & CAN_EFF_FLAG else can_id & 0x7FF, data[:dlc]

    def _recv_once(self, flags: int = 0) -> tuple[int, bytes] | None:
        """The frame read ahead, else one receive: the frame (id, data), or None when nothing
        was there (or in time).  Blocking (flags 0) with recvmmsg: every frame queued behind
        the first comes in the same call and is read ahead."""
        if self._ahead:
            return self._ahead.popleft()
        batch = self._batch_rx
        if batch is not None and flags == 0:
            got = batch.receive(MSG_WAITFORONE)
            if got < 0:
                if -got in (errno.EAGAIN, errno.EINTR):
                    return None
                raise LinkError(f"{self.channel}: cannot receive: {errno.errorcode.get(-got, -got)}")
            frames = [self._frame(raw) for raw in batch.frames(got)]
            self.rx_frames += len(frames)
            self._ahead.extend(frames[1:])
            return frames[0] if frames else None
        try:
            raw = self.sock.recv(CAN_MTU, flags)
        except (BlockingIOError, TimeoutError, InterruptedError):
            return None
        except OSError as e:
            if e.errno in (errno.EAGAIN, errno.EINTR):
                return None
            raise LinkError(f"{self.channel}: cannot receive: {e.strerror}") from None
        self.rx_frames += 1
        return self._frame(raw)

    def recv(self) -> tuple[int, bytes] | None:
        """The next frame (id, data), or None when nothing came within one slice."""
        if self._generic:
            return self._recv_generic(self._slice)
        return self._recv_once()

    def recv_wait(self, timeout: float) -> tuple[int, bytes] | None:
        """The next frame within timeout seconds, to the millisecond (poll(); SO_RCVTIMEO is
        rounded up to the kernel tick, 10-20 ms in the UML guest, too coarse for pacing)."""
        if self._generic:
            return self._recv_generic(timeout)
        if not self._ahead and not self._poll.poll(max(0, int(timeout * 1000.0 + 0.5))):
            return None
        return self._recv_once(socket.MSG_DONTWAIT)

    def recv_stamped(self, timeout: float) -> tuple[int, bytes, float] | None:
        """Like recv_wait, with the time the frame was on the bus: its kernel receive stamp
        on CLOCK_MONOTONIC (python-can's interfaces, and a frame read ahead by recv(): when it
        is handed out)."""
        if self._generic:
            got = self._recv_generic(timeout)
            return None if got is None else (*got, time.monotonic())
        if self._ahead:
            return (*self._ahead.popleft(), time.monotonic())
        if not self._poll.poll(max(0, int(timeout * 1000.0 + 0.5))):
            return None
        if self._stamps is None:
            self.sock.setsockopt(socket.SOL_SOCKET, SO_TIMESTAMPNS, 1)  # python-can's own too
            self._stamps = MonotonicStamps()
        try:
            raw, anc, _, _ = self.sock.recvmsg(CAN_MTU, socket.CMSG_SPACE(_TIMESPEC.size),
                                               socket.MSG_DONTWAIT)
        except (BlockingIOError, InterruptedError):
            return None
        except OSError as e:
            raise LinkError(f"{self.channel}: cannot receive: {e.strerror}") from None
        at = self._stamps.of(anc)
        self.rx_frames += 1
        return (*self._frame(raw), time.monotonic() if at is None else at)

    def drain(self) -> list[tuple[int, bytes]]:
        """Every frame already queued, without waiting."""
        out = []
        if self._generic:
            while (got := self._recv_generic(0.0)) is not None:
                out.append(got)
            return out
        while (got := self._recv_once(socket.MSG_DONTWAIT)) is not None:
            out.append(got)
        return out

    def close(self) -> None:
        if self.writer is not None:
            self.writer.close()
            self.writer = None
        try:
            if self.bus is None:
                self.sock.close()
            else:
                self.bus.shutdown()
        except Exception:  # noqa: BLE001 - closing twice or after the interface vanished
            pass

    def __enter__(self) -> CanLink:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class LinkRecorder:
    """The bus recorder of a non-SocketCAN bus: the link's own log (see the module text), with
    the interface of ``processes.Candump`` that the session uses."""

    def __init__(self, link: CanLink) -> None:
        if link.writer is None:
            raise ValueError("the link was opened without a log")
        self.link = link

    def alive(self) -> bool:
        return True

    def stop(self, marker: bytes | None = None, timeout: float = 10.0) -> bool:
        """The log holds every frame the link saw, the marker (sent just before) last."""
        if self.link.writer is not None:
            self.link.writer.close()
            self.link.writer = None
        return marker is not None
