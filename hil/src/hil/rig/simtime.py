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
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from pathlib import Path

from hil.bus.busload import worst_case_bits
from hil.bus.candump import LogFrame, read_log
from hil.bus.dbc import load
from hil.bus.logio import RUN_FORMATS, write_candump, write_frames
from hil.bus.protocol import APP_MISSILE, COMMAND_RESET, SENSOR_APP, SIM_CONTROL_ID, SIM_TICK_ID

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
    for t, f in simulated_times(frames, periods, baudrate):
        # (not dataclasses.replace: 4x slower, and a log has thousands of frames)
        yield LogFrame(t, f.channel, f.frame_id, f.data, f.extended, f.remote, f.error, f.fd)


def simulated_times(frames: Iterable[LogFrame], periods: Mapping[int, float],
                    baudrate: int) -> Iterator[tuple[float, LogFrame]]:
    """(simulated time, frame) of each frame (periods: step period per app): simulated()
    without a new frame each (a candump log is written from these directly)."""
    period = dict(periods)
    offset = 0.0          # simulated time of the current flight's step 0
    t_step = 0.0
    bus_free = 0.0
    last_step: dict[int, int] = {}
    for f in frames:
        data = f.data
        plain = f.classic_data and len(data) == 8
        if plain and f.frame_id == SIM_CONTROL_ID and (data[1] >> 4) == COMMAND_RESET:
            offset = math.ceil(bus_free / FLIGHT_GRID_S - 1e-9) * FLIGHT_GRID_S
            t_step, last_step = offset, {}
            lqg_period = int.from_bytes(data[2:4], "little") * 1e-4
            if lqg_period > 0:
                period[APP_MISSILE] = lqg_period
        elif plain and f.frame_id == SIM_TICK_ID:
            app = (data[1] >> 4) & 0x3
            t_step = max(t_step, offset + int.from_bytes(data[2:6], "little") * period.get(app, 0.0))
            last_step[app] = int.from_bytes(data[2:6], "little")
        elif plain and f.frame_id in SENSOR_APP:
            app = SENSOR_APP[f.frame_id]
            low = int.from_bytes(data[2:4], "little")
            prev = last_step.get(app)
            k = low if prev is None else prev + ((low - prev + 0x8000) & 0xFFFF) - 0x8000
            t_step = max(t_step, offset + k * period.get(app, 0.0))
        t = max(t_step, bus_free)
        if not (plain and WALL_PACED[0] <= f.frame_id <= WALL_PACED[1]):
            bits = 0 if (f.fd or f.error) else worst_case_bits(0 if f.remote else len(data), f.extended)
            bus_free = t + bits / baudrate
        yield round(t, 6), f


def finish_bus_log(run_dir: Path, mode: str, periods: Mapping[int, float], fmt: str,
                   baudrate: int, frames: Sequence[LogFrame] | None = None) -> Path:
    """The run's bus log as users read it: lockstep -> bus.<fmt> in simulated time and the
    recorder's wall-clock log renamed bus_wall.log; realtime -> bus.<fmt> in wall-clock time.
    `frames`: the recorder's log already read (else it is read here).  Returns the path of
    bus.<fmt>."""
    if fmt not in RUN_FORMATS:
        raise ValueError(f"log format must be one of {', '.join(RUN_FORMATS)}, not {fmt!r}")
    raw = run_dir / "bus.log"
    out = run_dir / f"bus.{fmt}"
    if mode == "lockstep":
        wall = run_dir / WALL_LOG
        os.replace(raw, wall)
        recorded = iter(read_log(wall) if frames is None else frames)
        first = next(recorded, None)  # its simulated time is 0: the log starts at its wall time
        recorded = itertools.chain(() if first is None else (first,), recorded)
        tmp = out.with_name(f".{out.name}.tmp{out.suffix}")
        if fmt == "log":
            write_candump(tmp, simulated_times(recorded, periods, baudrate))
        else:
            write_frames(tmp, simulated(recorded, periods, baudrate), received=sent_by_fcc(),
                         start=None if first is None else first.timestamp)
        os.replace(tmp, out)
    elif fmt != "log":
        tmp = out.with_name(f".{out.name}.tmp{out.suffix}")
        write_frames(tmp, read_log(raw) if frames is None else frames, received=sent_by_fcc())
        os.replace(tmp, out)
        raw.unlink()
    return out


def sent_by_fcc() -> Callable[[LogFrame], bool]:
    """Whether a frame is one the rig received: the log is the rig's view (ASC/BLF Tx and
    Rx), fcc's frames Rx (the DBC's node FCC sends them), every other frame Tx (the simulator,
    its sensors, the time master, the faults it injects)."""
    ids = frozenset(m.frame_id for m in load().messages if FCC_NODE in m.senders)
    return lambda f: f.frame_id in ids and not f.extended
