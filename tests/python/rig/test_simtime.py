"""A lockstep run's bus.log in simulated time (hil.rig.simtime.finish_bus_log) is, byte for byte,
the log the frame-by-frame rule writes: the recorded lines with their timestamps replaced, each
frame at the time of its step or when the bus is free (worst-case bits, none for error and FD
frames, wall-paced heartbeats holding up nothing), error and FD frames left out.  The rule is
spelled out here once more, a frame at a time (`reference_times`), as it was before the log was
retimed from columns; the logs mix every kind of line, flights with new LQG periods and both
applications, and are cut into many blocks."""
from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from pathlib import Path

import pytest

from hil.bus import SIM_NODES, FrameCodec, load
from hil.bus.busload import worst_case_bits
from hil.bus.candump import LogFormatError, LogFrame, format_line, read_log
from hil.bus.logcolumns import read_blocks
from hil.bus.apps import SENSOR_APP
from hil.bus.protocol import APP_MISSILE, COMMAND_RESET, SIM_CONTROL_ID, SIM_TICK_ID
from hil.rig.simtime import FLIGHT_GRID_S, WALL_LOG, WALL_PACED, finish_bus_log, simulated

SPEC = load()
CODEC = FrameCodec(SPEC, SIM_NODES)
FCC = FrameCodec(SPEC, "FCC")


def reference_times(frames: Iterable[LogFrame], periods: Mapping[int, float], baudrate: int) -> list[float]:
    """The simulated time of each frame, one frame at a time (hil.rig.simtime's docstring)."""
    period, offset, t_step, bus_free, last_step = dict(periods), 0.0, 0.0, 0.0, {}
    out = []
    for f in frames:
        data = f.data
        plain = f.classic_data and len(data) == 8
        if plain and f.frame_id == SIM_CONTROL_ID and (data[1] >> 4) == COMMAND_RESET:
            offset = math.ceil(bus_free / FLIGHT_GRID_S - 1e-9) * FLIGHT_GRID_S
            t_step, last_step = offset, {}
            if int.from_bytes(data[2:4], "little") > 0:
                period[APP_MISSILE] = int.from_bytes(data[2:4], "little") * 1e-4
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
        out.append(round(t, 6))
    return out


def reference_log(wall: Path, periods: Mapping[int, float]) -> bytes:
    """bus.log as the frame-by-frame rule writes it."""
    frames = list(read_log(wall))
    lines = []
    for t, f in zip(reference_times(frames, periods, SPEC.baudrate), frames):
        if f.error or f.fd:
            continue
        if f.remote:
            lines.append(f"({t:.6f}) {f.channel} {f.frame_id:0{8 if f.extended else 3}X}#R")
        else:
            lines.append(format_line(t, f.channel, f.frame_id, f.data, f.extended))
    return "".join(line + "\n" for line in lines).encode("ascii")


def line(t: float, codec: FrameCodec, name: str, values: dict) -> str:
    return format_line(t, "vcan0", *codec.encode(name, values))


def lockstep_log(t0: float = 1795701787.25) -> list[str]:
    """Both applications' flights as the recorder writes them (squeezed wall-clock times):
    heartbeats, a CDRW flight at 50 Hz with a missile flight at T = 0.2 s interleaved, then a
    missile flight whose reset carries T = 0.05 s; sensor steps past 16 bits."""
    t = iter(t0 + 1e-4 * i for i in range(100000))
    gyro = {"q_g": 0.01, "step": 0}
    heartbeat = {"bus_errors": 0, "rx_overflows": 0, "tx_dropped": 0, "tx_retries": 0}
    out = [line(next(t), FCC, "FCC_BUS_COUNTS", heartbeat) for _ in range(3)]
    out.append(line(next(t), CODEC, "SIM_CONTROL", {"command": 2, "lqg_period": 0.2, "da_bits": 8}))
    for k in range(60):
        out.append(line(next(t), CODEC, "CDRW_AOA", {"step": k, "alpha": 0.1}))
        out.append(line(next(t), CODEC, "SIM_TICK", {"app": 0, "step": k}))
        if k % 10 == 0:
            out.append(line(next(t), CODEC, "MSL_RATE_GYRO", {**gyro, "step": k // 10}))
            out.append(line(next(t), CODEC, "SIM_TICK", {"app": 1, "step": k // 10}))
        if k == 7:   # a slow wall-clock step: fcc's heartbeats
            out += [line(next(t), FCC, "FCC_BUS_COUNTS", heartbeat) for _ in range(12)]
    out.append(line(next(t), CODEC, "SIM_CONTROL", {"command": 2, "lqg_period": 0.05, "da_bits": 8}))
    for k in range(65530, 65545):   # the sensor's 16-bit step wraps
        out.append(line(next(t), CODEC, "MSL_RATE_GYRO", {**gyro, "step": k & 0xFFFF}))
        out.append(line(next(t), CODEC, "SIM_TICK", {"app": 1, "step": k}))
    return out


#: every other kind of line candump.read_log reads: extended (one with bits above the 29),
#: remote, error, FD, other spacing, lower case, blank, another channel (one with a '%'), no
#: fraction, no data, the largest 3-digit identifier
ODD = ["(1795701787.900000) vcan0 12345678#0102", "(1795701787.900001) vcan0 123#R",
       "(1795701787.900002) vcan0 700#R8", "(1795701787.900003) vcan0 20000004#0000000000000000",
       "(1795701787.900004) vcan0 110##1" + "00" * 12, "  (1795701787.9) vcan0   028#0102030405060708  ",
       "", "(1795701787.900005) can1 133#0102", "(1795701787.900006) vcan0 9ABCDEF0#11",
       "(1795701787.900007) vcan0 1FFFFFFF#R", "(1795701787.900008) vcan0 010##0",
       "(1795701787) vcan0 701#", "(1795701787.900009) vcan0 05a#31050700486502ab",
       "(1795701787.900010) v%can0 050#3105070048650200", "(1795701787.900011) vcan0 12345678#R",
       "(1795701787.900012) vcan0 FFF#0102030405060708"]


def with_odd_lines(lines: list[str]) -> list[str]:
    out = list(lines)
    for k, odd in enumerate(ODD):
        out.insert(5 + 17 * k, odd)
    return out


def finished(tmp_path: Path, lines: list[str], periods: Mapping[int, float],
             newline: str = "\n") -> tuple[bytes, bytes]:
    """(bus.log as finish_bus_log writes it, as the reference writes it)."""
    (tmp_path / "bus.log").write_bytes((newline.join(lines) + newline).encode("latin-1"))
    out = finish_bus_log(tmp_path, "lockstep", periods, "log", SPEC.baudrate)
    return out.read_bytes(), reference_log(tmp_path / WALL_LOG, periods)


@pytest.mark.parametrize("odd", [False, True])
@pytest.mark.parametrize("block_bytes", [1 << 20, 700])
@pytest.mark.parametrize("channel", ["vcan0", "v%an0"])
def test_the_simulated_log_is_the_frame_by_frame_rules(tmp_path, monkeypatch, odd, block_bytes, channel):
    monkeypatch.setattr("hil.bus.logcolumns.BLOCK_BYTES", block_bytes)   # state carried over blocks
    lines = [ln.replace("vcan0", channel) for ln in (with_odd_lines(lockstep_log()) if odd else lockstep_log())]
    got, want = finished(tmp_path, lines, {0: 0.02, 1: 0.1})
    assert got == want
    assert got.count(b"\n") == len(lines) - (4 if odd else 0)   # blank, error and FD lines left out
    times = [float(ln[1: ln.index(b")")]) for ln in got.splitlines()]
    assert times == sorted(times) and times[0] == 0.0


def test_carriage_returns_end_lines_as_read_log_reads_them(tmp_path):
    got, want = finished(tmp_path, with_odd_lines(lockstep_log()), {0: 0.02, 1: 0.1}, "\r\n")
    assert got == want and b"\r" not in got


def test_each_new_lqg_period_and_each_step(tmp_path):
    """The missile flight after the second reset steps at 0.05 s from the next 0.1 s grid
    point; before it at 0.2 s (the first reset's), the CDRW at 0.02 s."""
    got, _ = finished(tmp_path, lockstep_log(), {0: 0.02, 1: 0.1})
    frames = list(read_log(tmp_path / "bus.log"))
    ticks = [(f.timestamp, f.data[1] >> 4 & 3, int.from_bytes(f.data[2:6], "little"))
             for f in frames if f.frame_id == SIM_TICK_ID]
    first = [(t, k) for t, app, k in ticks if app == 1 and k < 65530]
    assert first == [(pytest.approx(0.2 * k, abs=2e-3), k) for k in range(6)]
    cdrw = [(t, k) for t, app, k in ticks if app == 0]
    assert cdrw == [(pytest.approx(0.02 * k, abs=2e-3), k) for k in range(60)]
    second = [(t, k) for t, app, k in ticks if app == 1 and k >= 65530]
    start = math.ceil(cdrw[-1][0] / FLIGHT_GRID_S) * FLIGHT_GRID_S
    assert [t for t, _ in second] == pytest.approx([start + 0.05 * k for _, k in second], abs=2e-3)


def test_the_objects_path_gives_the_same_times(tmp_path):
    """simulated() (ASC and BLF) times frames already read as finish_bus_log times the lines."""
    lines = with_odd_lines(lockstep_log())
    (tmp_path / "wall.log").write_text("\n".join(lines) + "\n", encoding="latin-1")
    frames = list(read_log(tmp_path / "wall.log"))
    assert [f.timestamp for f in simulated(frames, {0: 0.02, 1: 0.1}, SPEC.baudrate)] == \
        reference_times(frames, {0: 0.02, 1: 0.1}, SPEC.baudrate)


def test_a_malformed_line_is_refused_as_read_log_refuses_it(tmp_path):
    lines = lockstep_log()
    lines.insert(40, "(1795701787.5) vcan0 110#073E0081FF02A0G0")
    (tmp_path / "bus.log").write_text("\n".join(lines) + "\n")
    with pytest.raises(LogFormatError) as exc:
        finish_bus_log(tmp_path, "lockstep", {0: 0.02}, "log", SPEC.baudrate)
    with pytest.raises(LogFormatError) as want:
        list(read_log(tmp_path / WALL_LOG))
    assert str(exc.value) == str(want.value) and str(exc.value).startswith("line 41:")
    assert sorted(p.name for p in tmp_path.iterdir()) == [WALL_LOG]   # no half-written bus.log


def test_an_empty_log(tmp_path):
    got, want = finished(tmp_path, [], {0: 0.02})
    assert got == want == b""


def test_blocks_already_read_give_the_same_log(tmp_path, monkeypatch):
    """evaluate_flight's way: the recorder's log read once (read_blocks), retimed from that."""
    monkeypatch.setattr("hil.bus.logcolumns.BLOCK_BYTES", 700)
    lines = with_odd_lines(lockstep_log())
    (tmp_path / "bus.log").write_text("\n".join(lines) + "\n", encoding="latin-1")
    blocks = list(read_blocks(tmp_path / "bus.log"))
    out = finish_bus_log(tmp_path, "lockstep", {0: 0.02, 1: 0.1}, "log", SPEC.baudrate, blocks)
    assert len(blocks) > 10 and out.read_bytes() == reference_log(tmp_path / WALL_LOG, {0: 0.02, 1: 0.1})
