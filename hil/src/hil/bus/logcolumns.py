"""A candump -L log's frames as columns (numpy), a block of lines at a time: the (identifier,
data) of the frames hil.bus.candump.read_log gives, without an object or a regular-expression
match per line (a rig's log holds ~6300 lines a CDRW flight).

Nearly every line of a rig's log has one layout, "(SECONDS.MICROS) CHANNEL III#DD..DD": the
same widths and the same channel.  A block's lines of its most common length are checked
against the first of them character by character, all at once: a digit wherever that line
has a timestamp digit, an upper-case hex digit in the identifier and the data, every other
character (parentheses, point, spaces, channel, '#') the same.  A line that passes is one that
candump.parse_line reads as a classic data frame with that many bytes, and one that
candump.format_line writes back as it is after its timestamp (a retimed log copies it:
hil.rig.simtime); every other line (other widths or spacing, lower case, blank, extended,
remote, error, FD, malformed) is read by parse_line itself, so a malformed line is refused
with read_log's message and line number.
"""
from __future__ import annotations

import re
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hil.bus.candump import LogFrame, open_log, parse_line

#: most bytes of a classic frame
MAX_DATA = 8
#: the bytes read per block (whole lines): the log of a long campaign is never held at once
BLOCK_BYTES = 1 << 20
#: the layout a block's reference line must have to check the others against it: a
#: timestamp, a channel of printable ASCII (nothing a line's split could take for a space),
#: a 3-digit identifier and 1-8 data bytes; one space between fields
_LAYOUT = re.compile(rb"\((\d+)(?:\.(\d+))?\) [!-~]+ ([0-9A-F]{3})#((?:[0-9A-F]{2}){1,8})")
#: a byte's value as an upper-case hex digit (16: not one; a lower-case one is an odd line's)
_HEX = np.full(256, 16, np.uint8)
for _c in b"0123456789ABCDEF":
    _HEX[_c] = int(chr(_c), 16)


@dataclass(frozen=True)
class FrameColumns:
    """Classic data frames in log order: identifier, data (zero beyond its length), length."""

    frame_id: np.ndarray     # (n,) int64
    data: np.ndarray         # (n, 8) uint8
    length: np.ndarray       # (n,) int64

    def __len__(self) -> int:
        return len(self.frame_id)

    def take(self, which: np.ndarray | slice) -> FrameColumns:
        """The frames at these indices (where this mask is true, in this slice), in that order."""
        return FrameColumns(self.frame_id[which], self.data[which], self.length[which])

    def frame(self, i: int) -> tuple[int, bytes]:
        """Frame i as (identifier, data)."""
        return int(self.frame_id[i]), self.data[i, : self.length[i]].tobytes()

    def tuples(self) -> list[tuple[int, bytes]]:
        """Every frame as (identifier, data)."""
        return [self.frame(i) for i in range(len(self))]

    @staticmethod
    def of(frames: Iterable[tuple[int, bytes]]) -> FrameColumns:
        """Columns of (identifier, data) frames (data of at most 8 bytes)."""
        frames = list(frames)
        cols = FrameColumns(np.array([f for f, _ in frames], np.int64),
                            np.zeros((len(frames), MAX_DATA), np.uint8),
                            np.array([len(d) for _, d in frames], np.int64))
        for i, (_, d) in enumerate(frames):
            cols.data[i, : len(d)] = np.frombuffer(d, np.uint8)
        return cols

    @staticmethod
    def concat(parts: Iterable[FrameColumns]) -> FrameColumns:
        parts = list(parts)
        return FrameColumns(np.concatenate([p.frame_id for p in parts]),
                            np.concatenate([p.data for p in parts]),
                            np.concatenate([p.length for p in parts]))


def per_identifier(values: Mapping[int, int]) -> np.ndarray:
    """A value per standard identifier (-1: none; a candump line's 3 digits go up to 0xFFF),
    to look a column of identifiers up in at once."""
    table = np.full(0x1000, -1, np.int64)
    table[list(values)] = list(values.values())
    return table


def le_uint(data: np.ndarray, first: int, n: int) -> np.ndarray:
    """Bytes first..first+n-1 of each frame's data (rows of FrameColumns.data) as one
    little-endian whole number (int64)."""
    out = np.zeros(len(data), np.int64)
    for i in range(n):
        out |= data[:, first + i].astype(np.int64) << (8 * i)
    return out


@dataclass(frozen=True)
class LogBlock:
    """A block of a candump -L log: every frame in log order (blank lines left out), as
    columns; the frames not in the block's common layout also as parse_line reads them."""

    text: bytes              # the block's lines, each ended by "\n" ("\r\n" and "\r" made "\n")
    frames: FrameColumns     # identifier, data (a classic frame's, else zeros), data length
    ends: np.ndarray         # (n,) int64: where each frame's line ends in text (its "\n")
    tails: np.ndarray        # (n,) int64: where a common-layout line's ")" is in text, -1: odd
    odd: dict[int, LogFrame]  # the other frames by their index (other layouts, other kinds)

    def __len__(self) -> int:
        return len(self.frames)

    def classic(self) -> FrameColumns:
        """The classic data frames (all the frames of a rig's log, nearly always)."""
        other = [i for i, f in self.odd.items() if not f.classic_data]
        if not other:
            return self.frames
        keep = np.ones(len(self), bool)
        keep[other] = False
        return self.frames.take(keep)

    @staticmethod
    def of(frames: Sequence[LogFrame]) -> LogBlock:
        """The block of frames already read (no text: every frame odd)."""
        cols = FrameColumns.of((f.frame_id, f.data if f.classic_data else b"") for f in frames)
        cols.length[:] = [len(f.data) for f in frames]
        return LogBlock(b"", cols, np.full(len(frames), -1), np.full(len(frames), -1), dict(enumerate(frames)))


def read_columns(path: str | Path) -> Iterator[FrameColumns]:
    """The classic data frames of a candump -L log, a block of lines at a time; as strict as
    candump.read_log (blank lines skipped, a malformed line raises LogFormatError)."""
    for block in read_blocks(path):
        yield block.classic()


def read_blocks(path: str | Path) -> Iterator[LogBlock]:
    """Every frame of a candump -L log, a block of lines at a time; as strict as
    candump.read_log (blank lines skipped, a malformed line raises LogFormatError)."""
    before = 0   # lines of the blocks before this one
    with open_log(path) as f:
        while block := f.read(BLOCK_BYTES):
            block += f.readline()   # whole lines only
            # read_log's universal newlines: "\r\n" and "\r" end a line too
            if b"\r" in block:
                block = block.replace(b"\r\n", b"\n").replace(b"\r", b"\n")
            if not block.endswith(b"\n"):
                block += b"\n"
            parsed, n = _block(block, before)
            before += n
            yield parsed


def _block(block: bytes, before: int) -> tuple[LogBlock, int]:
    """A block's frames and its number of lines (numbered from before + 1)."""
    buf = np.frombuffer(block, np.uint8)
    ends = np.flatnonzero(buf == ord("\n"))
    starts = np.concatenate(([0], ends[:-1] + 1))
    plain, paren, cols = _plain_lines(buf, starts, ends - starts)
    if len(plain) == len(ends):   # every line (the rig's logs)
        return LogBlock(block, cols, ends, starts + paren, {}), len(ends)
    others = np.ones(len(ends), bool)
    others[plain] = False
    at: list[int] = []
    frames: list[LogFrame] = []
    for i in np.flatnonzero(others).tolist():
        text = block[starts[i]: ends[i]].decode("ascii", "replace")
        if text.strip():
            at.append(i)
            frames.append(parse_line(text, before + i + 1))
    lines = np.concatenate((plain, np.array(at, np.int64)))
    order = np.argsort(lines, kind="stable")
    odd = LogBlock.of(frames)
    tails = np.concatenate((starts[plain] + paren, odd.tails))[order]
    places = np.flatnonzero(order >= len(plain)).tolist()   # the odd frames' in log order
    return LogBlock(block, FrameColumns.concat([cols, odd.frames]).take(order), ends[lines[order]], tails,
                    {p: frames[order[p] - len(plain)] for p in places}), len(ends)


def _plain_lines(buf: np.ndarray, starts: np.ndarray, lens: np.ndarray) -> tuple[np.ndarray, int, FrameColumns]:
    """Which lines have the block's common layout (module docstring), where their ")" is, and
    their frames."""
    none = (np.zeros(0, np.int64), 0, FrameColumns.of([]))
    if not len(lens):
        return none
    width = int(np.bincount(lens).argmax())
    same = np.flatnonzero(lens == width)
    ref = buf[starts[same[0]]: starts[same[0]] + width].tobytes()
    m = _LAYOUT.fullmatch(ref)
    if m is None:
        return none
    if len(same) == len(lens) and len(buf) == len(lens) * (width + 1):   # a view of the block
        rows = buf.reshape(-1, width + 1)[:, :width]
    else:
        rows = buf[starts[same][:, None] + np.arange(width)]
    digits = np.r_[m.start(1): m.end(1), m.start(2): m.end(2)] if m.group(2) else np.r_[m.start(1): m.end(1)]
    hexes = np.r_[m.start(3): m.end(3), m.start(4): m.end(4)]
    fixed = np.ones(width, bool)   # (not np.setdiff1d: its first call imports numpy.ma, 35 ms)
    fixed[digits] = fixed[hexes] = False
    nib = _HEX[rows[:, hexes]]
    ok = ((rows[:, fixed] == np.frombuffer(ref, np.uint8)[fixed]).all(axis=1)
          & ((rows[:, digits] - np.uint8(ord("0"))) < 10).all(axis=1)   # (below '0' wraps high)
          & (nib < 16).all(axis=1))
    if not ok.all():
        same, nib = same[ok], nib[ok]
    n_bytes = (nib.shape[1] - 3) // 2
    data = np.zeros((len(same), MAX_DATA), np.uint8)
    data[:, :n_bytes] = nib[:, 3::2] << 4 | nib[:, 4::2]
    return same, ref.index(b")"), FrameColumns(nib[:, 0].astype(np.int64) << 8 | nib[:, 1] << 4 | nib[:, 2], data,
                              np.full(len(same), n_bytes, np.int64))
