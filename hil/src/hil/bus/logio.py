"""Bus logs in the formats engineers use: candump -L (.log, read and written here, no
python-can import), and every format python-can's LogReader / Logger know (.asc, .blf,
.trc, .csv, ...), by file suffix.

    read_frames(path)            -> iterator of candump.LogFrame, any format
    write_frames(path, frames)   the format the suffix names
    retimed(block, times)        a block of a candump -L log at new times (lines copied)
    run_log(run_dir)             the bus log of a run directory, whichever format it has
"""
from __future__ import annotations

import functools
import itertools
import math
import time
from collections.abc import Callable, Iterable, Iterator, Sequence
from datetime import datetime
from pathlib import Path
from typing import Any

import numpy as np

from hil.bus.candump import LogFrame, format_line, open_log, read_log
from hil.bus.logcolumns import LogBlock

#: hil run --log-format choices (file bus.<fmt> in the run directory)
RUN_FORMATS = ("log", "asc", "blf")
CANDUMP_SUFFIXES = (".log", ".candump")


def run_log(run_dir: Path) -> Path | None:
    """bus.log / bus.asc / bus.blf of a run directory (None: none there)."""
    for fmt in RUN_FORMATS:
        p = Path(run_dir) / f"bus.{fmt}"
        if p.is_file():
            return p
    return None


def read_frames(path: str | Path) -> Iterator[LogFrame]:
    """Frames of a log of any format python-can reads; candump -L is parsed here (fast,
    strict: a malformed line raises candump.LogFormatError)."""
    path = Path(path)
    if path.suffix.lower() in CANDUMP_SUFFIXES:
        yield from read_log(path)
        return
    import can  # only the other formats need python-can (slow to import)

    open_log(path).close()  # python-can opens it itself: a regular file, as read_log reads
    try:
        reader = can.LogReader(str(path))
    except ValueError as e:  # unknown suffix
        raise ValueError(f"{path}: {e}") from None
    chan_default = "can0"
    with reader:
        for m in reader:
            chan = m.channel if isinstance(m.channel, str) and m.channel else chan_default
            yield LogFrame(float(m.timestamp), chan, int(m.arbitration_id), bytes(m.data),
                           bool(m.is_extended_id), bool(m.is_remote_frame), bool(m.is_error_frame),
                           bool(m.is_fd))


def write_frames(path: str | Path, frames: Iterable[LogFrame], *, start: float | None = None,
                 received: Callable[[LogFrame], bool] | None = None) -> int:
    """Write frames in the format of the path's suffix; returns the count written.
    For ASC and BLF (candump keeps the times as they are, and has no direction):
    start: the wall-clock time (Unix s) of the frames' time 0, when their times are offsets
    from it (a lockstep run's simulated time); None: the times are wall-clock already.
    received(frame): whether the log's node received it (Rx) rather than sent it (Tx);
    None: every frame Rx (a listener's log)."""
    path = Path(path)
    if path.suffix.lower() in CANDUMP_SUFFIXES:
        return write_candump(path, frames)
    return _write_vector(path, frames, start, received)


def write_candump(path: str | Path, frames: Iterable[LogFrame]) -> int:
    """Write frames as a candump -L log; error and FD frames are left out. Returns the count
    written."""
    n = 0
    with open(path, "w", encoding="ascii") as f:
        for fr in frames:
            if fr.error or fr.fd:
                continue
            f.write(_candump_line(fr.timestamp, fr) + "\n")
            n += 1
    return n


def retimed(block: LogBlock, times: Sequence[float]) -> bytes:
    """A block of a candump -L log again, each frame at its new time, as write_candump writes
    it: a line of the block's common layout is copied but for its timestamp (format_line
    writes it so), any other frame is written from its fields.  A time is written to the
    microsecond ("%.6f": the same digits as of the time rounded to the microsecond)."""
    text, n = block.text, len(block)
    ends, tails = block.ends, block.tails
    if n and not block.odd and len(text) == n * (int(ends[0]) + 1) and b"%" not in text:
        # every line one width (the rig's logs): one format for the whole block
        rows = np.frombuffer(text, np.uint8).reshape(n, -1)[:, int(tails[0]):]
        fmt = np.empty((n, 5 + rows.shape[1]), np.uint8)
        fmt[:, :5] = np.frombuffer(b"(%.6f", np.uint8)
        fmt[:, 5:] = rows
        return fmt.tobytes() % tuple(times)
    out = []
    for i, t in enumerate(times):
        if tails[i] >= 0:
            out.append(b"(%.6f%s" % (t, text[tails[i]: ends[i] + 1]))
        elif not (block.odd[i].error or block.odd[i].fd):
            out.append(b"%s\n" % _candump_line(t, block.odd[i]).encode("ascii"))
    return b"".join(out)


def _candump_line(t: float, fr: LogFrame) -> str:
    if fr.remote:
        ident = f"{fr.frame_id:08X}" if fr.extended else f"{fr.frame_id:03X}"
        return f"({t:.6f}) {fr.channel} {ident}#R"
    return format_line(t, fr.channel, fr.frame_id, fr.data, fr.extended)


# ---- ASC and BLF (python-can's writers) -------------------------------------------------------
#: the first event of an ASC log whose frame times are offsets from a given start
ASC_OFFSETS_NOTE = "hil: frame times are simulated seconds after this start (a lockstep run)"


def _write_vector(path: Path, frames: Iterable[LogFrame], start: float | None,
                  received: Callable[[LogFrame], bool] | None) -> int:
    """ASC/BLF (or any python-can format) with a real measurement start: python-can takes it
    from the first frame, so a log in simulated time from 0 said 1 Jan 1970."""
    import can

    it = iter(frames)
    first = next(it, None)
    header = start if start is not None else (first.timestamp if first is not None else time.time())
    # both formats keep the start to the millisecond: offsets from a given start stay exact
    header = math.floor(header * 1000) / 1000
    origin = 0.0 if start is None else header
    writer: Any
    if path.suffix.lower() == ".asc":
        writer = _asc_writer_class()(path, header)
        if start is not None:  # the time origin, so that the offsets are written as they are
            writer.log_event(ASC_OFFSETS_NOTE, origin)
    else:
        writer = can.Logger(str(path))
        if isinstance(writer, can.BLFWriter):
            writer.start_timestamp = header
    n = 0
    with writer:
        for fr in itertools.chain(() if first is None else (first,), it):
            writer.on_message_received(can.Message(
                timestamp=origin + fr.timestamp, arbitration_id=fr.frame_id, data=fr.data,
                is_extended_id=fr.extended, is_remote_frame=fr.remote, is_error_frame=fr.error,
                is_fd=fr.fd, dlc=len(fr.data), channel=fr.channel, check=False,
                is_rx=received is None or received(fr)))
            n += 1
    return n


@functools.cache
def _asc_writer_class() -> type:
    """The class, made on first use: python-can is imported only for these formats."""
    import can

    class AscWriter(can.ASCWriter):
        """python-can's ASC writer with the measurement's start in the header's `date` line
        and `Begin Triggerblock` (python-can writes the time the file is written and the
        first frame's time). `_format_header_datetime` is python-can's own (4.5 and 4.6 have it);
        tests/python/bus/test_vector_logs.py reads the header back."""

        def __init__(self, path: Path, start: float) -> None:
            self._start = datetime.fromtimestamp(start)
            super().__init__(str(path))

        def _format_header_datetime(self, dt: datetime) -> str:
            return str(super()._format_header_datetime(self._start))

    return AscWriter
