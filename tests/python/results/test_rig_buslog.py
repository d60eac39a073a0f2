"""fcc's outputs read back from a bus log (hil.results.buslog), on logs written here: flights
split at SIM_CONTROL resets, outputs attributed to their tick (lockstep) or to the newest
sensor sample (realtime), step fields checked."""
from __future__ import annotations

import math

import numpy as np
import pytest

from hil.bus import SIM_NODES, FrameCodec, load
from hil.bus.candump import LogFormatError, format_line, read_log
from hil.results.buslog import data_frames, sid_arrays, split_flights

SPEC = load()


def sid_frames(k: int, alpha: float, step_field: int | None = None) -> list[tuple[int, bytes]]:
    out = []
    for flt in ("AZKF", "ZKF", "KF"):
        st = SPEC.by_name(f"SID_{flt}_STATE")
        out.append((st.frame_id, st.message.encode(
            {"alpha_hat": alpha, "q_hat": -alpha, "order": 2, "fault": 0, "degraded": 0,
             "step": (k if step_field is None else step_field) & 0xFFF})))
        b = SPEC.by_name(f"SID_{flt}_MODEL_B")
        out.append((b.frame_id, b.message.encode({"b1": 0.01, "b2": -0.5, "rho": 0.9, "gain_norm": 0.3})))
    return out


def write_log(path, frames):
    path.write_text("".join(format_line(1000.0 + 0.001 * i, "vcan0", fid, data) + "\n"
                            for i, (fid, data) in enumerate(frames)))


def test_lockstep_flights_and_steps(tmp_path):
    codec = FrameCodec(SPEC, SIM_NODES)
    frames = [codec.encode("RIG_PING", {"seq": 1, "t_send_us": 0})]
    for flight in range(2):
        frames.append(codec.encode("SIM_CONTROL", {"command": 2, "lqg_period": 0.0, "da_bits": 0}))
        for k in range(3):
            frames.append(codec.encode("SIM_TICK", {"app": 0, "step": k}))
            frames += sid_frames(k, 0.1 * k + flight, step_field=(7 if (flight, k) == (1, 2) else None))
    write_log(tmp_path / "bus.log", frames)
    flights = split_flights(tmp_path / "bus.log")
    assert len(flights) == 2
    a = sid_arrays(SPEC, flights[0], 4)
    assert np.allclose(a["azkf_alpha_hat"][:3], [0.0, 0.1, 0.2]) and math.isnan(a["azkf_alpha_hat"][3])
    assert np.allclose(a["kf_q_hat"][:3], [0.0, -0.1, -0.2]) and np.allclose(a["zkf_rho"][:3], 0.9)
    b = sid_arrays(SPEC, flights[1], 3)
    assert np.allclose(b["kf_alpha_hat"][:2], [1.0, 1.1])
    assert math.isnan(b["kf_alpha_hat"][2])        # its step field says 7, not 2: not used
    assert b["_mismatched"][0] == 3


def test_realtime_outputs_follow_the_newest_sample(tmp_path):
    codec = FrameCodec(SPEC, SIM_NODES)
    frames = [codec.encode("SIM_CONTROL", {"command": 2, "lqg_period": 0.0, "da_bits": 0})]
    for k in range(3):
        frames.append(codec.encode("CDRW_AOA", {"step": k, "alpha": 0.1}))
        frames += sid_frames(500 + k, 0.2 * k)       # fcc's own step count differs
    write_log(tmp_path / "bus.log", frames)
    (fl,) = split_flights(tmp_path / "bus.log")
    a = sid_arrays(SPEC, fl, 3, check_step=False)
    assert np.allclose(a["azkf_alpha_hat"], [0.0, 0.2, 0.4])
    assert fl.frames == 18


def test_data_frames_reads_what_read_log_reads(tmp_path, monkeypatch):
    """The fast reader of the flights' frames gives candump.read_log's data frames, whatever
    the lines (other spacing, extended, remote, error and FD frames, blank lines), across
    its blocks, and refuses a malformed line with read_log's message (its line number)."""
    lines = ["(1000.000001) vcan0 110#0102030405060708", "", "  (1000.1) can1   7FF#  ",
             "(1000.2) vcan0 12345678#AABB", "(1000.3) vcan0 123#R", "(1000.4) vcan0 20000080#0000000000000000",
             "(1000.5) vcan0 123##1AABB", "(1000.6) vcan0 0A0#", "(1000.7) vcan0 1fe#abcdef\t",
             "(1000.8)\tvcan0 028#00"]
    log = tmp_path / "bus.log"
    log.write_text("\n".join(lines * 40))          # no newline at the end
    monkeypatch.setattr("hil.results.buslog._BLOCK_CHARS", 100)   # many blocks
    want = [(f.frame_id, f.data) for f in read_log(log) if not (f.error or f.remote or f.extended or f.fd)]
    assert list(data_frames(log)) == want and len(want) == 5 * 40
    log.write_text("\n".join(lines * 3 + ["(1000.9) vcan0 123#ABC"] + lines) + "\n")
    with pytest.raises(LogFormatError) as ref:
        list(read_log(log))
    with pytest.raises(LogFormatError) as bad:
        list(data_frames(log))
    assert str(bad.value) == str(ref.value) and str(ref.value).startswith("line 31:")
