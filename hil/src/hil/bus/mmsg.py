"""Many CAN frames in one system call: sendmmsg(2) and recvmmsg(2) through ctypes on libc (the
standard library's socket has neither).  In the User-Mode Linux guest a system call costs
~6 us; the lockstep runner sends a step's frames (5 for a CDRW step) in one call
(hil.rig.link.CanLink.send_many) and takes fcc's answer (4 frames for a missile step) in one
(hil.rig.link.CanLink.recv)."""
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


#: recvmmsg(2): wait for the first message only (linux/socket.h), then take what is there
MSG_WAITFORONE = 0x10000


def _libc(name: str) -> Callable[..., int] | None:
    """libc's sendmmsg(2) or recvmmsg(2) through ctypes (None: not there, e.g. not
    Linux/glibc).  No argtypes: converting the arguments through them doubled the call's cost
    (the lockstep loop calls each once a step); the callers pass C-sized values."""
    try:
        fn = getattr(ctypes.CDLL(None, use_errno=True), name)
    except (OSError, AttributeError):
        return None
    fn.restype = ctypes.c_int
    return fn


class _Batch:
    """CAPACITY packed struct can_frames and their message headers, made once: a batch is one
    call and one copy in or out."""

    CAPACITY = 64
    _fn: Callable[..., int] | None = None

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


class BatchSender(_Batch):
    """Up to CAPACITY packed struct can_frames in one sendmmsg(2): a step's frames in one system
    call instead of one send() each (the largest cost of the lockstep loop in the guest)."""

    _fn = _libc("sendmmsg")

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


class BatchReceiver(_Batch):
    """Up to CAPACITY struct can_frames in one recvmmsg(2): fcc's answer to a step (its frames
    sent in one sendmmsg) in one system call instead of one recv() each."""

    _fn = _libc("recvmmsg")

    def receive(self, flags: int) -> int:
        """recvmmsg with flags (MSG_WAITFORONE: block for the first frame as long as the socket's
        SO_RCVTIMEO; MSG_DONTWAIT: none); how many frames came (-errno on failure)."""
        got = self._fn(self.fd, self._from[0], self.CAPACITY, flags, None)  # type: ignore[misc]
        return got if got >= 0 else -ctypes.get_errno()

    def frames(self, n: int) -> list[bytes]:
        """The n frames received, each a packed struct can_frame (a message of another size --
        none on a CAN_RAW socket without CAN FD -- is left out)."""
        return [self._bytes[i * FRAME_BYTES:(i + 1) * FRAME_BYTES].tobytes() for i in range(n)
                if self.msgs[i].len == FRAME_BYTES]
