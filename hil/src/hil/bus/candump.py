"""candump -L log lines: "(1700000000.123456) vcan0 123#DEADBEEF".

Classic data frames (3-digit standard or 8-digit extended identifiers), remote
frames ("123#R"), error frames (identifier with CAN_ERR_FLAG 0x20000000) and
CAN FD frames ("123##1...", recognised and flagged, not decoded).
"""
from __future__ import annotations

import io
import re
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

from hil.util.bounded import open_regular
from hil.util.errors import InputError

CAN_ERR_FLAG = 0x20000000
CAN_EFF_MASK = 0x1FFFFFFF

_LINE = re.compile(
    r"^\((?P<ts>\d+(?:\.\d+)?)\)\s+(?P<chan>\S+)\s+"
    r"(?P<id>[0-9A-Fa-f]{3}|[0-9A-Fa-f]{8})"
    r"(?P<sep>##?)(?P<data>R\d?|[0-9A-Fa-f]*)\s*$")


#: a bus log larger than this is no run's (a minute of a loaded 500 kbit/s bus is ~20 MB)
LOG_MAX_BYTES = 4 << 30


def open_log(path: str | Path) -> BinaryIO:
    """A bus log to read: a regular file of at most LOG_MAX_BYTES (hil.util.bounded: a FIFO or
    a device is one line, not a hang)."""
    return open_regular(path, LOG_MAX_BYTES, "bus log")


class LogFormatError(InputError, ValueError):
    """A line that is not candump -L format."""


@dataclass(frozen=True)
class LogFrame:
    timestamp: float
    channel: str
    frame_id: int
    data: bytes
    extended: bool = False
    remote: bool = False
    error: bool = False
    fd: bool = False

    @property
    def classic_data(self) -> bool:
        """A classic data frame with a standard identifier: the only kind the rig's frames are
        (error, remote, extended and FD frames are someone else's)."""
        return not (self.error or self.remote or self.extended or self.fd)


def parse_line(line: str, lineno: int = 0) -> LogFrame:
    m = _LINE.match(line.strip())
    if m is None:
        raise LogFormatError(f"line {lineno}: not candump -L format: {line.strip()[:60]!r}")
    raw_id = int(m["id"], 16)
    extended = len(m["id"]) == 8
    error = extended and bool(raw_id & CAN_ERR_FLAG)
    fd = m["sep"] == "##"
    payload = m["data"]
    remote = payload.startswith("R")
    if fd:
        payload = payload[1:]  # the flags nibble
    if remote:
        data = b""
    else:
        if len(payload) % 2:
            raise LogFormatError(f"line {lineno}: odd number of hex digits in {m['data']!r}")
        data = bytes.fromhex(payload)
        if len(data) > (64 if fd else 8):
            raise LogFormatError(f"line {lineno}: {len(data)} data bytes")
    return LogFrame(float(m["ts"]), m["chan"], raw_id & CAN_EFF_MASK, data,
                    extended, remote, error, fd)


def read_log(path: str | Path) -> Iterator[LogFrame]:
    """Frames of a candump -L log; blank lines skipped, anything else malformed raises."""
    with io.TextIOWrapper(open_log(path), encoding="ascii", errors="replace") as f:
        for lineno, line in enumerate(f, 1):
            if line.strip():
                yield parse_line(line, lineno)


def format_line(timestamp: float, channel: str, frame_id: int, data: bytes,
                extended: bool = False) -> str:
    ident = f"{frame_id:08X}" if extended else f"{frame_id:03X}"
    return f"({timestamp:.6f}) {channel} {ident}#{bytes(data).hex().upper()}"
