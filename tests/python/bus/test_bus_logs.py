"""Bus logs: simulated time in a lockstep log (hil.rig.simtime), every python-can format in
and out (hil.bus.logio), and scripts/diag on them (periods a run used, strict JSON,
timestamps going backwards) -- on logs written here."""
from __future__ import annotations

import json
import math
import subprocess
from pathlib import Path

import pytest

from hil.bus import SIM_NODES, FrameCodec, diag, load
from hil.bus.candump import LogFrame
from hil.bus.logio import read_frames, write_frames
from hil.rig.simtime import FLIGHT_GRID_S, simulated

SPEC = load()
CODEC = FrameCodec(SPEC, SIM_NODES)


def frame(name: str, values: dict, t: float = 0.0) -> LogFrame:
    fid, data = CODEC.encode(name, values)
    return LogFrame(t, "vcan0", fid, data)


def missile_flight(period: float, steps: int, t0: float, lost: tuple[int, ...] = ()) -> list[LogFrame]:
    """A lockstep missile flight as the recorder saw it: squeezed wall-clock times."""
    out = [frame("SIM_CONTROL", {"command": 2, "lqg_period": period, "da_bits": 8}, t0)]
    for k in range(steps):
        t = t0 + 0.001 * (k + 1)
        gyro = frame("MSL_RATE_GYRO", {"q_g": 0.01, "step": k & 0xFFFF}, t)  # counter moves on
        if k not in lost:
            out.append(gyro)
        out.append(frame("SIM_TICK", {"app": 1, "step": k}, t))
    return out


def test_simulated_time_stamps_each_frame_with_its_step() -> None:
    wall = missile_flight(0.2, 5, 1000.0) + missile_flight(0.05, 4, 1000.1)
    sim = list(simulated(wall, {1: 0.1}, SPEC.baudrate))
    assert [f.data for f in sim] == [f.data for f in wall]            # same frames, same order
    ts = [f.timestamp for f in sim]
    assert ts == sorted(ts) and len(set(ts)) == len(ts)               # on the wire one by one
    gyro = [f.timestamp for f in sim if f.frame_id == 0x040]
    first = 0.0                                                       # nothing before it
    assert gyro[:5] == pytest.approx([first + 0.2 * k for k in range(5)], abs=1e-3)
    second = gyro[5]
    assert second == pytest.approx(math.ceil((gyro[4] + 1e-3) / FLIGHT_GRID_S) * FLIGHT_GRID_S, abs=1e-3)
    assert [g - second for g in gyro[5:]] == pytest.approx([0.0, 0.05, 0.1, 0.15], abs=1e-3)


def test_diag_uses_each_flights_own_period() -> None:
    """T = 0.2 s then 0.05 s with one frame lost: one NO_NEW_DATA, none against the DBC's 100 ms."""
    wall = missile_flight(0.2, 10, 1000.0) + missile_flight(0.05, 10, 1001.0, lost=(4,))
    rep = diag.analyse(simulated(wall, {1: 0.1}, SPEC.baudrate), SPEC)
    gyro = next(m for m in rep["messages"] if m["name"] == "MSL_RATE_GYRO")
    assert gyro["used_period_ms"] == [50.0, 200.0]
    assert gyro["e2e"]["NO_NEW_DATA"] == 1 and gyro["e2e"]["OK_SOME_LOST"] == 1
    assert gyro["count"] == 19


@pytest.mark.parametrize("suffix", [".log", ".asc", ".blf", ".trc"])
def test_formats_round_trip(tmp_path: Path, suffix: str) -> None:
    frames = list(simulated(missile_flight(0.1, 20, 5.0), {1: 0.1}, SPEC.baudrate))
    path = tmp_path / f"bus{suffix}"
    assert write_frames(path, frames) == len(frames)
    back = list(read_frames(path))
    assert [(f.frame_id, f.data) for f in back] == [(f.frame_id, f.data) for f in frames]
    assert [f.timestamp for f in back] == pytest.approx([f.timestamp for f in frames], abs=2e-5)


def run_diag(repo: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([str(repo / "scripts" / "diag"), *args], capture_output=True, text=True,
                          timeout=120)


def test_diag_script_reads_blf_and_prints_strict_json(tmp_path: Path, repo: Path) -> None:
    frames = list(simulated(missile_flight(0.1, 30, 5.0), {1: 0.1}, SPEC.baudrate))
    write_frames(tmp_path / "bus.blf", frames)
    r = run_diag(repo, "--log", str(tmp_path / "bus.blf"), "--json")
    assert r.returncode == 0, r.stderr
    assert "NaN" not in r.stdout
    rep = json.loads(r.stdout, parse_constant=lambda c: pytest.fail(f"non-JSON constant {c}"))
    ctl = next(m for m in rep["messages"] if m["name"] == "SIM_CONTROL")
    assert ctl["rate_hz"] is None and ctl["jitter_std_ms"] is None      # one frame: no period
    gyro = next(m for m in rep["messages"] if m["name"] == "MSL_RATE_GYRO")
    assert gyro["rate_hz"] == pytest.approx(10.0, rel=1e-3)
    text = run_diag(repo, "--log", str(tmp_path / "bus.blf"))
    assert text.returncode == 0 and "MSL_RATE_GYRO" in text.stdout


def test_diag_counts_timestamps_going_backwards(tmp_path: Path, repo: Path) -> None:
    frames = list(simulated(missile_flight(0.1, 10, 5.0), {1: 0.1}, SPEC.baudrate))
    frames[6], frames[7] = frames[7], frames[6]
    write_frames(tmp_path / "bad.log", frames)
    r = run_diag(repo, "--log", str(tmp_path / "bad.log"))
    assert r.returncode == 1
    assert "timestamps going backwards: 1" in r.stdout
    (line,) = r.stderr.strip().splitlines()
    assert line.startswith("diag: ") and "1 timestamps go backwards (first at frame 8:" in line


def test_diag_unreadable_log_is_one_line(tmp_path: Path, repo: Path) -> None:
    (tmp_path / "x.blf").write_bytes(b"not a blf file at all" * 10)
    (tmp_path / "x.xyz").write_text("hello\n")
    for name in ("x.blf", "x.xyz"):
        r = run_diag(repo, "--log", str(tmp_path / name))
        assert r.returncode == 2 and r.stdout == ""
        (line,) = r.stderr.strip().splitlines()
        assert line.startswith(f"diag: {tmp_path / name}: cannot read")


def test_tick_streams_per_application_and_heartbeats_do_not_hold_up_steps() -> None:
    """The demo's interleaving: CDRW ticks at 50 Hz and missile ticks at 10 Hz on one SIM_TICK
    identifier are two streams; a burst of heartbeats in a slow step keeps the steps on time."""
    fcc = FrameCodec(SPEC, "FCC")
    wall = [frame("SIM_CONTROL", {"command": 2, "lqg_period": 0.0, "da_bits": 0}, 1.0)]
    for k in range(50):
        if k == 3:   # fcc's heartbeat, 40 frames in one step (a slow wall-clock step)
            wall += [LogFrame(1.0, "vcan0", *fcc.encode("FCC_BUS_COUNTS", {
                "bus_errors": 0, "rx_overflows": 0, "tx_dropped": 0, "tx_retries": 0})) for _ in range(40)]
        wall.append(frame("SIM_TICK", {"app": 0, "step": k}, 1.0 + 1e-3 * k))
        if k % 5 == 0:
            wall.append(frame("SIM_TICK", {"app": 1, "step": k // 5}, 1.0 + 1e-3 * k))
    rep = diag.analyse(simulated(wall, {0: 0.02, 1: 0.1}, SPEC.baudrate), SPEC)
    ticks = {m["name"]: m for m in rep["messages"] if m["name"].startswith("SIM_TICK")}
    assert set(ticks) == {"SIM_TICK[cdrw]", "SIM_TICK[missile]"}
    assert ticks["SIM_TICK[cdrw]"]["used_period_ms"] == [20.0]
    assert ticks["SIM_TICK[missile]"]["used_period_ms"] == [100.0]
    assert ticks["SIM_TICK[cdrw]"]["jitter_max_ms"] < 1.0        # not pushed by the heartbeats
    assert all(m["e2e"]["NO_NEW_DATA"] == 0 for m in ticks.values())
