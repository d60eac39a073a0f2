"""Bus logs in the formats engineers use: candump -L (.log, read and written here, no
python-can import), and every format python-can's LogReader / Logger know (.asc, .blf,
.trc, .csv, ...), by file suffix.

    read_frames(path)            -> iterator of candump.LogFrame, any format
    write_frames(path, frames)   the format the suffix names
    write_candump(path, timed)   candump -L of (timestamp, frame) pairs
    run_log(run_dir)             the bus log of a run directory, whichever format it has
"""
from __future__ import annotations

from collections.abc import Iterable, Iterator
from pathlib import Path

from hil.bus.candump import LogFrame, format_line, read_log

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


def write_frames(path: str | Path, frames: Iterable[LogFrame]) -> int:
    """Write frames in the format of the path's suffix; returns the count written."""
    path = Path(path)
    n = 0
    if path.suffix.lower() in CANDUMP_SUFFIXES:
        return write_candump(path, ((fr.timestamp, fr) for fr in frames))
    import can

    with can.Logger(str(path)) as w:
        for fr in frames:
            w.on_message_received(can.Message(
                timestamp=fr.timestamp, arbitration_id=fr.frame_id, data=fr.data,
                is_extended_id=fr.extended, is_remote_frame=fr.remote, is_error_frame=fr.error,
                is_fd=fr.fd, dlc=len(fr.data), channel=fr.channel, check=False))
            n += 1
    return n


def write_candump(path: str | Path, timed: Iterable[tuple[float, LogFrame]]) -> int:
    """Write (timestamp, frame) pairs as a candump -L log, each frame at the timestamp given
    with it (a retimed log needs no new frame objects); error and FD frames are left out.
    Returns the count written."""
    n = 0
    with open(path, "w", encoding="ascii") as f:
        for t, fr in timed:
            if fr.error or fr.fd:
                continue
            f.write(_candump_line(t, fr) + "\n")
            n += 1
    return n


def _candump_line(t: float, fr: LogFrame) -> str:
    if fr.remote:
        ident = f"{fr.frame_id:08X}" if fr.extended else f"{fr.frame_id:03X}"
        return f"({t:.6f}) {fr.channel} {ident}#R"
    return format_line(t, fr.channel, fr.frame_id, fr.data, fr.extended)
