"""Vector ASC and BLF logs of a run (hil.bus.logio, hil.rig.simtime.finish_bus_log): the
measurement starts at the run's real wall-clock start, the frames keep their simulated times
as offsets from it, and each frame's direction is the rig's view (the frames it sent Tx, fcc's
Rx), as python-can's own readers and cantools read them."""
from __future__ import annotations

from datetime import datetime
from pathlib import Path

import can
import cantools
import pytest

from hil.bus import load
from hil.bus.candump import LogFrame, format_line
from hil.bus.logio import write_frames
from hil.rig.simtime import WALL_LOG, finish_bus_log, sent_by_fcc

SPEC = load()
#: 2026-11-26 14:03:07.25 UTC, the wall clock of the recorder's first frame
WALL_START = 1795701787.25
#: fcc's heartbeat, then the flight: SIM_CONTROL (the rig's), a sensor frame, fcc's ACK
IDS = (0x700, 0x010, 0x050, 0x028)
FCC_SENDS = {0x700, 0x028}


def _frames(t0: float, dt: float = 0.02) -> list[LogFrame]:
    frames = []
    for i, fid in enumerate(IDS):
        msg = SPEC.by_id(fid).message
        data = msg.encode({s.name: 0 for s in msg.signals}, strict=False, scaling=False)
        frames.append(LogFrame(round(t0 + i * dt, 6), "vcan0", fid, bytes(data)))
    return frames


def _asc_begin(path: Path) -> datetime:
    line = next(ln for ln in path.read_text().splitlines() if ln.startswith("Begin Triggerblock"))
    return datetime.strptime(line.split(" ", 2)[2], "%a %b %d %H:%M:%S.%f %Y")


@pytest.mark.parametrize("fmt", ["asc", "blf"])
def test_offsets_from_a_real_start_and_the_rigs_directions(tmp_path: Path, fmt: str) -> None:
    sim = _frames(0.0)
    path = tmp_path / f"bus.{fmt}"
    assert write_frames(path, sim, start=WALL_START, received=sent_by_fcc()) == len(sim)
    if fmt == "asc":
        assert _asc_begin(path) == datetime.fromtimestamp(WALL_START)
        start = datetime.fromtimestamp(WALL_START)
        assert path.read_text().splitlines()[0] == f"date {start:%a %b %d %H:%M:%S}.250 2026"
        back = list(can.ASCReader(str(path), relative_timestamp=False))
        offsets = [m.timestamp for m in can.ASCReader(str(path))]   # relative: the simulated times
        assert offsets == pytest.approx([f.timestamp for f in sim], abs=1e-9)
    else:
        reader = can.BLFReader(str(path))
        assert reader.start_timestamp == pytest.approx(WALL_START, abs=1e-6)
        assert reader.stop_timestamp == pytest.approx(WALL_START + sim[-1].timestamp, abs=1e-3)
        back = list(reader)
    assert [m.timestamp - WALL_START for m in back] == pytest.approx([f.timestamp for f in sim], abs=1e-6)
    assert [m.is_rx for m in back] == [f.frame_id in FCC_SENDS for f in sim]
    db = cantools.database.load_file(str(SPEC.path))
    assert [db.get_message_by_frame_id(m.arbitration_id).name for m in back] == \
        ["FCC_STATUS", "SIM_CONTROL", "CDRW_AOA", "FCC_ACK"]
    for m, f in zip(back, sim):
        assert bytes(m.data) == f.data
        db.decode_message(m.arbitration_id, m.data)


def test_a_listeners_log_is_all_rx_and_starts_at_its_first_frame(tmp_path: Path) -> None:
    wall = _frames(WALL_START + 0.5)
    write_frames(tmp_path / "bus.asc", wall)
    assert _asc_begin(tmp_path / "bus.asc") == datetime.fromtimestamp(WALL_START + 0.5)
    back = list(can.ASCReader(str(tmp_path / "bus.asc"), relative_timestamp=False))
    assert all(m.is_rx for m in back)
    assert [m.timestamp for m in back] == pytest.approx([f.timestamp for f in wall], abs=2e-3)


@pytest.mark.parametrize("fmt", ["asc", "blf"])
def test_a_lockstep_runs_log_starts_at_the_recorders_first_frame(tmp_path: Path, fmt: str) -> None:
    # the recorder's log in wall-clock time, as a lockstep run leaves it: bus.log -> bus_wall.log,
    # bus.<fmt> in simulated time from the wall clock of its first frame
    wall = _frames(WALL_START, dt=0.0007)
    (tmp_path / "bus.log").write_text("".join(format_line(f.timestamp, f.channel, f.frame_id, f.data) + "\n"
                                              for f in wall))
    out = finish_bus_log(tmp_path, "lockstep", {0: 0.02}, fmt, SPEC.baudrate)
    assert (tmp_path / WALL_LOG).is_file() and out == tmp_path / f"bus.{fmt}"
    back = list(can.LogReader(str(out))) if fmt == "blf" else \
        list(can.ASCReader(str(out), relative_timestamp=False))
    assert back[0].timestamp == pytest.approx(WALL_START, abs=1e-6)
    assert [m.is_rx for m in back] == [f.frame_id in FCC_SENDS for f in wall]

