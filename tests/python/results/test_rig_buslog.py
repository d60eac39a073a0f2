"""fcc's outputs read back from a bus log (hil.results.buslog), on logs written here: flights
split at SIM_CONTROL resets, outputs attributed to their tick (lockstep) or to the newest
sensor sample (realtime), step fields checked."""
from __future__ import annotations

import math

import numpy as np
import pytest

from hil.bus import SIM_NODES, FrameCodec, load
from hil.bus.candump import format_line, read_log
from hil.bus.logcolumns import LogBlock
from hil.bus.secoc import Endpoint
from hil.results.buslog import BusAuth, authentic_frames, sid_arrays, split_flights

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


KEY, TRIP = bytes(range(16)), 0x1234


def secured_flights(attack: str) -> list[tuple[int, bytes]]:
    """Two lockstep flights of 40 steps as the rig sends them (resets and ticks E2E-protected
    and authenticated), with one attack on the second flight's ticks."""
    codec = FrameCodec(SPEC, SIM_NODES)
    sec = Endpoint(SPEC, KEY, SIM_NODES)
    sec.set_trip(TRIP)
    frames: list[tuple[int, bytes]] = []
    sent: list[list[tuple[int, bytes]]] = []
    for flight in range(2):
        frames += sec.protect(*codec.encode("SIM_CONTROL", {"command": 2, "lqg_period": 0.0, "da_bits": 0}))
        for k in range(40):
            tick = sec.protect(*codec.encode("SIM_TICK", {"app": 0, "step": k}))
            sent.append(tick)
            if flight == 1 and k == 20:
                if attack == "forged":       # a tick of another step, its authenticator made up
                    frames += [(tick[0][0], tick[0][1][:2] + bytes([99]) + tick[0][1][3:]), tick[1]]
                    continue
                if attack == "replayed":     # the tick and authenticator of 10 steps before, again
                    frames += sent[-11]
                if attack == "bad_crc":      # a genuine authenticator over a frame with a bad CRC
                    data = bytes([tick[0][1][0] ^ 1]) + tick[0][1][1:]
                    frames += [(tick[0][0], data), sec.protect(tick[0][0], data)[1]]
                    continue
                if attack == "lost":         # a tick that never reached the bus
                    continue
            frames += tick
            frames += sid_frames(k, 0.01 * k + flight)
    return frames


@pytest.mark.parametrize("attack", ["none", "forged", "replayed", "bad_crc", "lost"])
def test_the_gate_takes_what_the_live_link_takes(tmp_path, monkeypatch, attack):
    """Read at once (runs of tick pairs verified together, in blocks), the frames that count
    are those the frame-by-frame gate passes (authentic_frames), and a forged, replayed or
    corrupted tick moves no step."""
    monkeypatch.setattr("hil.bus.logcolumns.BLOCK_BYTES", 2000)   # runs cut by blocks
    write_log(tmp_path / "bus.log", secured_flights(attack))
    auth = BusAuth(KEY, TRIP)
    flights = split_flights(tmp_path / "bus.log", auth)
    one_by_one = split_flights([LogBlock.of(list(authentic_frames(read_log(tmp_path / "bus.log"), auth)))])
    assert len(flights) == len(one_by_one) == 2
    for fl, ref in zip(flights, one_by_one):
        steps, frames = fl.outputs(0)
        ref_steps, ref_frames = ref.outputs(0)
        assert steps.tolist() == ref_steps.tolist() and frames.tuples() == ref_frames.tuples()
        assert fl.frames == ref.frames
    a = sid_arrays(SPEC, flights[1], 40)
    missing = [20] if attack in ("forged", "bad_crc", "lost") else []
    assert np.flatnonzero(np.isnan(a["azkf_alpha_hat"])).tolist() == missing
    assert a["_mismatched"][0] == 0
    assert np.allclose(np.delete(a["azkf_alpha_hat"], missing), np.delete(0.01 * np.arange(40) + 1, missing))


def flights_one_by_one(frames: list[tuple[int, bytes]]) -> list[tuple[int, dict]]:
    """The attribution frame by frame, as iter_flights did it before it read columns: each
    flight's output count and {app: {step: [frames in log order]}}."""
    from hil.bus.protocol import COMMAND_RESET, SENSOR_APP, SIM_CONTROL_ID, SIM_TICK_ID
    from hil.results.buslog import app_of

    flights: list[tuple[int, dict]] = []
    tick: dict[int, int] = {}
    ticked: set[int] = set()
    for fid, data in frames:
        if fid == SIM_CONTROL_ID and len(data) == 8 and (data[1] >> 4) == COMMAND_RESET:
            flights.append((0, {}))
            tick, ticked = {}, set()
            continue
        if not flights:
            continue
        if fid == SIM_TICK_ID and len(data) == 8:
            tick[(data[1] >> 4) & 0x3] = int.from_bytes(data[2:6], "little")
            ticked.add((data[1] >> 4) & 0x3)
            continue
        if fid in SENSOR_APP and len(data) == 8 and SENSOR_APP[fid] not in ticked:
            low, prev = int.from_bytes(data[2:4], "little"), tick.get(SENSOR_APP[fid], -1)
            tick[SENSOR_APP[fid]] = low if prev < 0 else prev + ((low - prev) & 0xFFFF)
            continue
        app = app_of(fid)
        if app is None:
            continue
        count, by_app = flights[-1]
        flights[-1] = (count + 1, by_app)
        if app in tick:
            by_app.setdefault(app, {}).setdefault(tick[app], []).append((fid, data))
    return flights


def test_steps_are_attributed_as_frame_by_frame(tmp_path, monkeypatch):
    """Random logs of resets, ticks of any application (some short), sensor samples before and
    after ticks, outputs of both applications and other frames, read in small blocks: every
    flight's outputs get the steps the frame-by-frame reading gives them."""
    from hil.bus.protocol import COMMAND_RESET, SENSOR_APP, SIM_CONTROL_ID, SIM_TICK_ID

    monkeypatch.setattr("hil.bus.logcolumns.BLOCK_BYTES", 700)
    rng = np.random.default_rng(26)
    sensors, outputs = sorted(SENSOR_APP), [*range(0x110, 0x140), 0x030, 0x100]
    for _ in range(30):
        frames: list[tuple[int, bytes]] = []
        for _ in range(300):
            kind, data = rng.integers(0, 9), bytearray(rng.integers(0, 256, 8, dtype=np.uint8).tobytes())
            if kind == 0:
                data[1] = (COMMAND_RESET << 4) | (data[1] & 0xF) if rng.random() < 0.7 else data[1]
                frames.append((SIM_CONTROL_ID, bytes(data)))
            elif kind in (1, 2):
                data[1] = (int(rng.integers(0, 4)) << 4) | (data[1] & 0xF)
                frames.append((SIM_TICK_ID, bytes(data[: 8 if rng.random() < 0.9 else 7])))
            elif kind in (3, 4):
                frames.append((int(rng.choice(sensors)), bytes(data[: 8 if rng.random() < 0.9 else 6])))
            elif kind in (5, 6, 7):
                frames.append((int(rng.choice(outputs)), bytes(data[: int(rng.integers(0, 9))])))
            else:
                frames.append((int(rng.integers(0, 0x800)), bytes(data)))
        write_log(tmp_path / "bus.log", frames)
        got = split_flights(tmp_path / "bus.log")
        want = flights_one_by_one(frames)
        assert len(got) == len(want)
        for fl, (count, by_app) in zip(got, want):
            assert fl.frames == count
            for app in (0, 1):
                steps, cols = fl.outputs(app)
                mine: dict[int, list] = {}
                for k, frame in zip(steps.tolist(), cols.tuples()):
                    mine.setdefault(k, []).append(frame)
                assert mine == by_app.get(app, {})
