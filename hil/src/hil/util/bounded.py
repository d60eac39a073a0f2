"""Reads of the files a user names (key file, scenario, suite, DBC, summaries, bus logs): regular
files only, opened without blocking, never more than a limit.  A FIFO would block the open and
the read until someone writes, /dev/zero never ends, a directory or a device is no file of
any kind hil reads: each is one clear line (UnfitFile), never a hang or an exhausted memory.

    read_bounded(path, limit, what)   -> the bytes (at most limit)
    open_regular(path, limit, what)   -> a binary file object, for what is read as a stream
"""
from __future__ import annotations

import os
import stat
from pathlib import Path
from typing import BinaryIO

from hil.util.errors import InputError

#: what a file that is not a regular one is, in the user's words
_KINDS = ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))


class UnfitFile(InputError, ValueError):
    """A file hil will not read: not a regular file, or larger than its kind can be (one line
    for the user)."""


class TooLarge(UnfitFile):
    """A file larger than its kind can be."""


class NotRegularFile(UnfitFile):
    """A FIFO, a device, a socket or a directory where a file was expected."""


def _check(path: str | Path, st: os.stat_result, limit: int, what: str) -> None:
    if not stat.S_ISREG(st.st_mode):
        kind = next((name for test, name in _KINDS if test(st.st_mode)), "not a regular file")
        raise NotRegularFile(f"{path}: {kind}, not a {what} (only a regular file is read)")
    if st.st_size > limit:
        raise TooLarge(f"{path}: larger than a {what} can be ({limit} bytes at most)")


def open_regular(path: str | Path, limit: int, what: str) -> BinaryIO:
    """The regular file at path, open for reading; UnfitFile when it is anything else or its size
    is over limit (OSError as open raises).  Looked at before it is opened (no device is opened,
    no FIFO waited for), opened non-blocking and looked at again (what was opened is what was
    looked at).  The caller reads at most limit + 1 bytes (a file may grow)."""
    _check(path, os.stat(path), limit, what)
    fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_NOCTTY | os.O_CLOEXEC)
    try:
        _check(path, os.fstat(fd), limit, what)
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


def read_bounded(path: str | Path, limit: int, what: str) -> bytes:
    """At most `limit` bytes of the regular file at path; UnfitFile when it has more or is not
    a regular file (OSError as open raises)."""
    with open_regular(path, limit, what) as fh:
        data = fh.read(limit + 1)
    if len(data) > limit:
        raise TooLarge(f"{path}: larger than a {what} can be ({limit} bytes at most)")
    return data
