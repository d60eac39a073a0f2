"""Why a CAN interface cannot be opened, and what to do about it, in one line.

The kernel's own words ("[Errno 97] Address family not supported by protocol", "No such
device") name the symptom, not the cause: a kernel without CAN, an interface never created, an
interface down. ``open_error`` turns the OSError of a socket bind (raw, or python-can's) into
the line the user sees, with the command that fixes it.
"""
from __future__ import annotations

import errno
import os
from pathlib import Path

from hil.io.paths import vcan_launcher

IFF_UP = 0x1


def with_vcan_hint() -> str:
    launcher = vcan_launcher()
    return f"run it inside {launcher} ({launcher} CMD...: a kernel with vcan0)"


def _errno(e: BaseException) -> int | None:
    """The errno of e or of the OSError it wraps (python-can re-raises its own errors)."""
    seen: BaseException | None = e
    while seen is not None:
        if isinstance(seen, OSError) and seen.errno is not None:
            return seen.errno
        seen = seen.__cause__ or seen.__context__
    return None


def open_error(channel: str, e: BaseException) -> str:
    """'cannot open CAN interface CHANNEL: WHY; WHAT TO DO' for an error opening channel."""
    code = _errno(e)
    create = (f"sudo modprobe vcan && sudo ip link add dev {channel} type vcan "
              f"&& sudo ip link set {channel} up")
    if code == errno.EAFNOSUPPORT:
        why = f"the kernel has no CAN (AF_CAN not supported); {with_vcan_hint()}, or load it: {create}"
    elif code == errno.ENODEV:
        why = (f"there is no interface {channel!r}; create it: {create} "
               f"({vcan_launcher()} CMD... runs CMD where vcan0 exists)")
    elif code == errno.ENETDOWN:
        why = f"the interface is down; bring it up: sudo ip link set {channel} up"
    else:
        why = str(e).splitlines()[0] if str(e) else type(e).__name__
    return f"cannot open CAN interface {channel!r}: {why}"


def check_up(channel: str) -> None:
    """OSError(ENETDOWN) when channel exists and is down: a socket binds to a down interface,
    and only the first send or receive would say so."""
    try:
        flags = int((Path("/sys/class/net") / channel / "flags").read_text(encoding="ascii"), 16)
    except (OSError, ValueError):
        return  # not a network interface the kernel lists (or no sysfs): the bind decides
    if not flags & IFF_UP:
        raise OSError(errno.ENETDOWN, os.strerror(errno.ENETDOWN), channel)
