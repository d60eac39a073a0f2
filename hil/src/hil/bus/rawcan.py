"""Raw SocketCAN sockets with the standard library only (python-can is slow to import, and
the lockstep link needs nothing of it on SocketCAN: hil.rig.link).

A socket from ``open_raw`` is what python-can's SocketCAN bus opens with the rig's settings:
CAN_RAW, bound to the interface, the kernel's receive filter on the given standard
identifiers (extended frames never match), its own frames not received and no error frames
(the kernel's defaults for a new CAN_RAW socket).
"""
from __future__ import annotations

import socket
import struct
from collections.abc import Iterable

CAN_EFF_FLAG = 0x80000000
#: struct can_frame: 32-bit id, 8-bit length, 3 pad bytes, 8 data bytes
CAN_FRAME = struct.Struct("=IB3x8s")
#: where a struct can_frame's data bytes start
DATA_OFFSET = 8
#: a standard identifier's filter mask: all 11 bits, and the extended-frame flag clear
STANDARD_MASK = 0x7FF | CAN_EFF_FLAG


def pack_frame(frame_id: int, data: bytes) -> bytes:
    """A raw struct can_frame for a classic frame of len(data) <= 8 bytes."""
    return CAN_FRAME.pack(frame_id, len(data), bytes(data))


def open_raw(channel: str, frame_ids: Iterable[int] | None = None) -> socket.socket:
    """A CAN_RAW socket on channel that receives these standard identifiers (None: every
    frame; an empty set: none).  OSError when the interface cannot be opened."""
    sock = socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)
    try:
        if frame_ids is not None:
            ids = sorted(set(frame_ids))
            filters = [v for i in ids for v in (i, STANDARD_MASK)]
            sock.setsockopt(socket.SOL_CAN_RAW, socket.CAN_RAW_FILTER,
                            struct.pack(f"={len(filters)}I", *filters))
        sock.bind((channel,))
    except OSError:
        sock.close()
        raise
    return sock


RECEIVE_BUFFER_BYTES = 4 << 20   # ~1 s of a full bus: a Python reader stalled by the guest loses nothing


def enlarge_receive_buffer(sock: socket.socket, nbytes: int = RECEIVE_BUFFER_BYTES) -> None:
    """Ask the kernel for an nbytes receive queue: SO_RCVBUFFORCE needs CAP_NET_ADMIN (root in
    the UML guest); without it SO_RCVBUF, which the kernel caps at net.core.rmem_max."""
    for opt in (getattr(socket, "SO_RCVBUFFORCE", 33), socket.SO_RCVBUF):
        try:
            sock.setsockopt(socket.SOL_SOCKET, opt, nbytes)
            return
        except OSError:
            continue
