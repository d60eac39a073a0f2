"""Simulated time in a lockstep run's bus log.

A lockstep run goes as fast as fcc answers, so the recorder's wall-clock timestamps are
squeezed (the 50 Hz tick shows as 400 Hz, the bus load above 100 %).  After the run the log
is rewritten: every frame gets the simulated time of the step it belongs to, and inside a
step the frames follow each other at the bus's bit rate (frame i starts when frame i-1 has
left the wire, its length with worst-case bit stuffing).  The step of a frame: a sensor frame
carries its step (bytes 2-3), SIM_TICK(app, k) names it, every other frame belongs to the
step in progress (fcc's heartbeat, paced by the wall clock, is stamped with the step it fell
in without delaying the frames after it).  Flights start at a SIM_CONTROL reset, on the next 0.1 s after the
frames before it (the start-up's heartbeats, the previous flight); a SIM_CONTROL with a
new LQG period changes the missile's step period.  The wall-clock log is kept beside it.
"""
from __future__ import annotations

import itertools
import math
import os
from collections.abc import Callable, Iterable, Iterator, Mapping
from pathlib import Path

import numpy as np

from hil.bus.busload import worst_case_bits
from hil.bus.candump import LogFrame, read_log
from hil.bus.dbc import load
from hil.bus.logcolumns import MAX_DATA, LogBlock, le_uint, per_identifier, read_blocks
from hil.bus.logio import RUN_FORMATS, retimed, write_frames
from hil.bus.apps import SENSOR_APP
from hil.bus.protocol import APP_MISSILE, COMMAND_RESET, SIM_CONTROL_ID, SIM_TICK_ID

#: the recorder's own log of a lockstep run (wall-clock timestamps)
WALL_LOG = "bus_wall.log"
#: fcc's heartbeat frames: paced by the wall clock, so a slow lockstep step gathers many of
#: them; they get the time of the step they fell in but do not hold up the steps' frames
WALL_PACED = (0x700, 0x70F)
#: the DBC's node of the device under test
FCC_NODE = "FCC"
#: flights start on this grid (s)
FLIGHT_GRID_S = 0.1


def simulated(frames: Iterable[LogFrame], periods: Mapping[int, float],
              baudrate: int) -> Iterator[LogFrame]:
    """The frames again, timestamped in simulated time (periods: step period per app)."""
    clock = SimClock(periods, baudrate)
    it = iter(frames)
    while chunk := list(itertools.islice(it, CHUNK_FRAMES)):
        for t, f in zip(clock.times(LogBlock.of(chunk)), chunk):
            # (not dataclasses.replace: 4x slower, and a log has thousands of frames)
            yield LogFrame(round(t, 6), f.channel, f.frame_id, f.data, f.extended, f.remote, f.error, f.fd)


#: frames given as objects are timed this many at a time (simulated)
CHUNK_FRAMES = 4096
#: the frames' kinds for the clock (SimClock.times: as numbers): any other, a reset, a tick, a
#: sensor sample
_OTHER, _RESET, _TICK, _SENSOR = range(4)
#: worst-case bits on the wire by [extended, data bytes]
_BITS = np.array([[worst_case_bits(n, ext) for n in range(MAX_DATA + 1)] for ext in (False, True)])
#: the application of each sensor frame by identifier (-1: not a sensor frame)
_SENSOR_OF = per_identifier(SENSOR_APP)


class SimClock:
    """Simulated time of a log's frames (module docstring), a block of them at a time; the
    flight's start, its step and the bus's state carried from one block to the next."""

    def __init__(self, periods: Mapping[int, float], baudrate: int) -> None:
        self.period = dict(periods)
        self.baudrate = baudrate
        self.offset = 0.0          # simulated time of the current flight's step 0
        self.t_step = 0.0
        self.bus_free = 0.0
        self.last_step: dict[int, int] = {}

    def times(self, block: LogBlock) -> list[float]:
        """Each frame's simulated time (s; a log shows it to the microsecond)."""
        kind, app, value, cost = self._columns(block)
        period, last_step = self.period, self.last_step
        offset, t_step, bus_free = self.offset, self.t_step, self.bus_free
        out = []
        reset, tick = _RESET, _TICK
        for k, a, v, c in zip(kind, app, value, cost):
            if k:   # (most frames are none of these: fcc's outputs)
                if k == reset:
                    offset = math.ceil(bus_free / FLIGHT_GRID_S - 1e-9) * FLIGHT_GRID_S
                    t_step, last_step = offset, {}
                    if v > 0:   # a new LQG period (1e-4 s)
                        period[APP_MISSILE] = v * 1e-4
                elif k == tick:
                    t_step = max(t_step, offset + v * period.get(a, 0.0))
                    last_step[a] = v
                else:   # a sensor sample: its step from its low 16 bits, next to the app's last tick
                    prev = last_step.get(a)
                    v = v if prev is None else prev + ((v - prev + 0x8000) & 0xFFFF) - 0x8000
                    t_step = max(t_step, offset + v * period.get(a, 0.0))
            t = bus_free if bus_free > t_step else t_step   # max(t_step, bus_free)
            if c is not None:
                bus_free = t + c
            out.append(t)
        self.offset, self.t_step, self.bus_free, self.last_step = offset, t_step, bus_free, last_step
        return out

    def _columns(self, block: LogBlock) -> tuple[list[int], list[int], list[int], list[float | None]]:
        """Each frame's kind, application (tick, sensor), value (a reset's LQG period, a tick's
        step, a sample's low step bits) and time on the wire (s; None: wall-paced)."""
        cols = block.frames
        fid, data = cols.frame_id, cols.data.astype(np.int64)
        extended, silent, remote = (np.zeros(len(cols), bool) for _ in range(3))
        for i, f in block.odd.items():
            extended[i], silent[i], remote[i] = f.extended, f.error or f.fd, f.remote
        plain = (cols.length == 8) & ~(extended | silent | remote)   # a classic 8-byte frame
        sensor_app = _SENSOR_OF[np.where(plain, fid, 0)]
        kind = np.select([plain & (fid == SIM_CONTROL_ID) & ((data[:, 1] >> 4) == COMMAND_RESET),
                          plain & (fid == SIM_TICK_ID), plain & (sensor_app >= 0)],
                         [_RESET, _TICK, _SENSOR], _OTHER)
        app = np.where(kind == _TICK, (data[:, 1] >> 4) & 0x3, sensor_app)
        value = np.where(kind == _TICK, le_uint(data, 2, 4), le_uint(data, 2, 2))
        bits = np.where(silent, 0, _BITS[extended.astype(int), np.where(remote | silent, 0, cols.length)])
        paced = plain & (fid >= WALL_PACED[0]) & (fid <= WALL_PACED[1])
        cost: list[float | None] = (bits / self.baudrate).tolist()
        for i in np.flatnonzero(paced).tolist():
            cost[i] = None
        return kind.tolist(), app.tolist(), value.tolist(), cost


def finish_bus_log(run_dir: Path, mode: str, periods: Mapping[int, float], fmt: str,
                   baudrate: int, blocks: Iterable[LogBlock] | None = None) -> Path:
    """The run's bus log as users read it: lockstep -> bus.<fmt> in simulated time and the
    recorder's wall-clock log renamed bus_wall.log; realtime -> bus.<fmt> in wall-clock time.
    `blocks`: the recorder's log already read (read_blocks; a bus.log is retimed from them,
    else it is read here).  Returns the path of bus.<fmt> (a log that cannot be read raises:
    no half-written one)."""
    if fmt not in RUN_FORMATS:
        raise ValueError(f"log format must be one of {', '.join(RUN_FORMATS)}, not {fmt!r}")
    raw = run_dir / "bus.log"
    out = run_dir / f"bus.{fmt}"
    if mode != "lockstep" and fmt == "log":   # the recorder's log is the run's as it is
        return out
    tmp = out.with_name(f".{out.name}.tmp{out.suffix}")
    try:
        if mode == "lockstep":
            wall = run_dir / WALL_LOG
            os.replace(raw, wall)
            _write_simulated(wall, tmp, periods, baudrate, blocks)
        else:
            write_frames(tmp, read_log(raw), received=sent_by_fcc())
        os.replace(tmp, out)
    finally:
        tmp.unlink(missing_ok=True)
    if mode != "lockstep":
        raw.unlink()
    return out


def _write_simulated(wall: Path, path: Path, periods: Mapping[int, float], baudrate: int,
                     blocks: Iterable[LogBlock] | None) -> None:
    """A lockstep run's log in simulated time, in the format of the path's suffix."""
    if path.suffix == ".log":   # each line as recorded but for its time
        clock = SimClock(periods, baudrate)
        with open(path, "wb") as f:
            for block in read_blocks(wall) if blocks is None else blocks:
                f.write(retimed(block, clock.times(block)))
        return
    recorded = read_log(wall)
    first = next(recorded, None)  # its simulated time is 0: the log starts at its wall time
    write_frames(path, simulated(itertools.chain(() if first is None else (first,), recorded), periods, baudrate),
                 received=sent_by_fcc(), start=None if first is None else first.timestamp)


def sent_by_fcc() -> Callable[[LogFrame], bool]:
    """Whether a frame is one the rig received: the log is the rig's view (ASC/BLF Tx and
    Rx), fcc's frames Rx (the DBC's node FCC sends them), every other frame Tx (the simulator,
    its sensors, the time master, the faults it injects)."""
    ids = frozenset(m.frame_id for m in load().messages if FCC_NODE in m.senders)
    return lambda f: f.frame_id in ids and not f.extended
