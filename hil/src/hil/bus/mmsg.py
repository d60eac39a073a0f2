"""Many CAN frames in one system call: sendmmsg(2) through ctypes on libc (the standard
library's socket has sendmsg but no sendmmsg).  In the User-Mode Linux guest a system call
costs ~5.7 us; the lockstep runner sends a step's frames (5 for a CDRW step) in one call
(hil.rig.link.CanLink.send_many)."""
from __future__ import annotations

import ctypes
from collections.abc import Callable

#: sizeof(struct can_frame): the frames handed over are packed ones (hil.rig.link.pack_frame)
FRAME_BYTES = 16


class _Iovec(ctypes.Structure):
    _fields_ = [("base", ctypes.c_void_p), ("len", ctypes.c_size_t)]


class _Msghdr(ctypes.Structure):
    _fields_ = [("name", ctypes.c_void_p), ("namelen", ctypes.c_uint32),
                ("iov", ctypes.POINTER(_Iovec)), ("iovlen", ctypes.c_size_t),
                ("control", ctypes.c_void_p), ("controllen", ctypes.c_size_t),
                ("flags", ctypes.c_int)]


class _Mmsghdr(ctypes.Structure):
    _fields_ = [("hdr", _Msghdr), ("len", ctypes.c_uint)]


def _libc_sendmmsg() -> Callable[..., int] | None:
    """libc's sendmmsg(2) through ctypes (None: not there, e.g. not Linux/glibc).  No
    argtypes: converting four arguments through them doubled the call's cost (the lockstep
    loop calls it once a step); the caller passes C-sized values (BatchSender.send)."""
    try:
        fn = ctypes.CDLL(None, use_errno=True).sendmmsg
    except (OSError, AttributeError):
        return None
    fn.restype = ctypes.c_int
    return fn


class BatchSender:
    """Up to CAPACITY packed struct can_frames in one sendmmsg(2): a step's frames in one system
    call instead of one send() each (the largest cost of the lockstep loop in the guest).  The
    buffers and message headers are made once; a batch is one copy into them and one call."""

    CAPACITY = 64
    _fn = _libc_sendmmsg()

    @classmethod
    def available(cls) -> bool:
        return cls._fn is not None

    def __init__(self, fd: int) -> None:
        self.fd = fd
        n = self.CAPACITY
        self.buf = ctypes.create_string_buffer(n * FRAME_BYTES)
        self.iov = (_Iovec * n)()
        self.msgs = (_Mmsghdr * n)()
        base = ctypes.addressof(self.buf)
        for i in range(n):
            self.iov[i].base = base + i * FRAME_BYTES
            self.iov[i].len = FRAME_BYTES
            self.msgs[i].hdr.iov = ctypes.pointer(self.iov[i])
            self.msgs[i].hdr.iovlen = 1
        self.addr = ctypes.addressof(self.msgs)
        self.size = ctypes.sizeof(_Mmsghdr)
        #: the buffer as bytes to assign to (a slice copy: no foreign call per batch)
        self._bytes = memoryview(self.buf).cast("B")
        #: each message header's address as a C pointer, made once (the argument of a send
        #: from that frame on: an int would be passed as a 32-bit C int without argtypes)
        self._from = [ctypes.c_void_p(self.addr + i * self.size) for i in range(n)]

    def load(self, raws: list[bytes]) -> int:
        """Copy up to CAPACITY frames in; how many."""
        n = min(len(raws), self.CAPACITY)
        blob = b"".join(raws[:n])
        if len(blob) != n * FRAME_BYTES:
            raise ValueError(f"frames to send must be packed struct can_frames of {FRAME_BYTES} bytes")
        self._bytes[:len(blob)] = blob
        return n

    def send(self, first: int, n: int) -> int:
        """sendmmsg of frames first..n-1 loaded; how many went (-errno on failure of the first)."""
        got = self._fn(self.fd, self._from[first], n - first, 0)  # type: ignore[misc]
        return got if got >= 0 else -ctypes.get_errno()
