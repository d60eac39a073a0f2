"""A bus node on python-can: a FrameCodec, one python-can Bus and one Notifier.

    with BusNode("vcan0", SIM_NODES) as node:
        node.send("SIM_TICK", {"app": 0, "step": k})
        ack = node.wait_for("FCC_ACK", timeout=1.0, match=lambda d: d.values["step"] == k)

Received frames are checked by the codec in the Notifier's thread and queued
(every verdict, so the caller sees rejections too), or handed to on_frame.
send() retries a full transmit queue (ENOBUFS) for a bounded time and counts
a frame it gives up on; send_raw() bypasses the codec for fault injection.
"""
from __future__ import annotations

import queue
import socket
import threading
import time
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass

import can

from hil.bus import dbc
from hil.bus.codec import Decoded, FrameCodec, Value
from hil.bus.rawcan import enlarge_receive_buffer

SEND_RETRY_S = 0.05      # give a full transmit queue this long before dropping
SEND_RETRY_SLEEP_S = 0.0005


@dataclass
class PortCounters:
    rx_frames: int = 0
    tx_frames: int = 0
    bus_errors: int = 0
    tx_retries: int = 0
    tx_dropped: int = 0


class _Listener(can.Listener):
    def __init__(self, node: BusNode) -> None:
        self._node = node

    def on_message_received(self, msg: can.Message) -> None:
        self._node._on_can_message(msg)

    def on_error(self, exc: Exception) -> None:
        self._node.errors.append(exc)


class BusNode:
    def __init__(self, channel: str = "vcan0", nodes: str | Iterable[str] | None = None, *,
                 interface: str = "socketcan", spec: dbc.BusSpec | None = None,
                 filters: bool = True, receive_own_messages: bool = False,
                 on_frame: Callable[[Decoded], None] | None = None) -> None:
        self.codec = FrameCodec(spec, nodes)
        self.port = PortCounters()
        self.errors: list[Exception] = []
        self._lock = threading.Lock()
        self._queue: queue.Queue[Decoded] = queue.Queue()
        self._on_frame = on_frame
        can_filters = None
        if filters and nodes is not None:
            can_filters = [{"can_id": self.codec.spec.by_name(n).frame_id, "can_mask": 0x7FF,
                            "extended": False} for n in sorted(self.codec.consumes)]
        self.bus = can.Bus(interface=interface, channel=channel, can_filters=can_filters,
                           receive_own_messages=receive_own_messages)
        raw = getattr(self.bus, "socket", None)
        if isinstance(raw, socket.socket):
            enlarge_receive_buffer(raw)
        self.notifier = can.Notifier(self.bus, [_Listener(self)], timeout=0.1)

    # -- receive side (Notifier thread)
    def _on_can_message(self, msg: can.Message) -> None:
        if msg.is_error_frame:
            self.port.bus_errors += 1
            return
        self.port.rx_frames += 1
        foreign = msg.is_extended_id or msg.is_remote_frame or msg.is_fd
        with self._lock:
            decoded = self.codec.decode(msg.arbitration_id, bytes(msg.data), msg.timestamp,
                                        extended=foreign)
        decoded.data = bytes(msg.data)
        if self._on_frame is not None:
            self._on_frame(decoded)
        else:
            self._queue.put(decoded)

    def recv(self, timeout: float | None = None) -> Decoded | None:
        """Next received frame (any verdict), or None after timeout seconds."""
        try:
            return self._queue.get(timeout=timeout)
        except queue.Empty:
            return None

    def wait_for(self, name: str, timeout: float,
                 match: Callable[[Decoded], bool] | None = None) -> Decoded | None:
        """First good frame of message name (satisfying match) within timeout; others dropped."""
        deadline = time.monotonic() + timeout
        while (left := deadline - time.monotonic()) > 0:
            d = self.recv(left)
            if d is not None and d.ok and d.name == name and (match is None or match(d)):
                return d
        return None

    def end_period(self, name: str) -> bool:
        with self._lock:
            return self.codec.end_period(name)

    # -- transmit side
    def encode(self, name: str, values: Mapping[str, Value], *,
               saturate: bool = False) -> tuple[int, bytes]:
        """Encode (E2E-protected, next alive counter) without sending."""
        with self._lock:
            return self.codec.encode(name, values, saturate=saturate)

    def send(self, name: str, values: Mapping[str, Value], *, saturate: bool = False) -> bool:
        """Encode (E2E-protected) and send; False if the frame was dropped after retries."""
        frame_id, data = self.encode(name, values, saturate=saturate)
        return self.send_raw(frame_id, data)

    def send_raw(self, frame_id: int, data: bytes, *, extended: bool = False) -> bool:
        """Send bytes as they are (fault injection: bad CRC, wrong DLC, ...)."""
        msg = can.Message(arbitration_id=frame_id, data=data, is_extended_id=extended)
        deadline = time.monotonic() + SEND_RETRY_S
        while True:
            try:
                self.bus.send(msg)
                self.port.tx_frames += 1
                return True
            except can.CanOperationError:
                if time.monotonic() >= deadline:
                    self.port.tx_dropped += 1
                    return False
                self.port.tx_retries += 1
                time.sleep(SEND_RETRY_SLEEP_S)

    # -- life cycle
    def close(self) -> None:
        self.notifier.stop()
        self.bus.shutdown()

    def __enter__(self) -> BusNode:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
