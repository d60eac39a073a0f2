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
from hil.bus.secoc import Endpoint, Sender
from hil.results.buslog import BusAuth, authentic_frames, split_flights
from hil.results.sidframes import DuplicateOutput, sid_arrays
from hil.results.trust import Forgeries

SPEC = load()
SID_AUTH = SPEC.by_name("SID_OUT_AUTH")


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


def all_sid_frames(k: int, alpha: float, fault: int = 0) -> list[tuple[int, bytes]]:
    """The 12 identification frames of step k, in fcc's order (SID_OUT_AUTH's group)."""
    values = {"STATE": {"alpha_hat": alpha, "q_hat": -alpha, "order": 2, "fault": fault,
                        "degraded": 0, "step": k & 0xFFF},
              "BOUNDS": {"alpha_lo": alpha - 0.01, "alpha_hi": alpha + 0.01, "q_lo": -0.5, "q_hi": 0.5},
              "MODEL_A": {"a11": 0.9, "a12": 0.02, "a21": -0.4, "a22": 0.95},
              "MODEL_B": {"b1": 0.01, "b2": -0.5, "rho": 0.9, "gain_norm": 0.3}}
    out = []
    for flt in ("AZKF", "ZKF", "KF"):
        for part, v in values.items():
            m = SPEC.by_name(f"SID_{flt}_{part}")
            out.append((m.frame_id, m.message.encode(v)))
    return out


def fcc_outputs(sender: Sender, k: int, alpha: float) -> list[tuple[int, bytes]]:
    """fcc's outputs of CDRW step k as it sends them: the 12 frames, then SID_OUT_AUTH."""
    frames = all_sid_frames(k, alpha)
    return frames + [(SID_AUTH.frame_id, sender.protect(b"".join(d for _, d in frames)))]


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
    fcc = Sender(KEY, SID_AUTH.secoc_data_id, TRIP)
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
            frames += fcc_outputs(fcc, k, 0.01 * k + flight)
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
    from hil.bus.apps import SENSOR_APP
    from hil.bus.protocol import COMMAND_RESET, SIM_CONTROL_ID, SIM_TICK_ID
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
    from hil.bus.apps import SENSOR_APP
    from hil.bus.protocol import COMMAND_RESET, SIM_CONTROL_ID, SIM_TICK_ID

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


def forged_state(k: int, alpha: float, fault: int = 0) -> tuple[int, bytes]:
    """A keyless node's SID_AZKF_STATE for step k: α̂ and the fault flag its own."""
    return all_sid_frames(k, alpha, fault)[0]


@pytest.mark.parametrize("where", ["before the authenticator", "after the authenticator"])
def test_forged_outputs_reach_no_table_and_are_counted(tmp_path, where):
    """A keyless node re-sends SID_AZKF_STATE with α̂ moved and the fault bit set at every step,
    squeezed before fcc's authenticator or right after it: every estimate is fcc's, and each
    forged copy is counted (refused, and a conflicting second copy of the frame)."""
    codec = FrameCodec(SPEC, SIM_NODES)
    sec = Endpoint(SPEC, KEY, SIM_NODES)
    sec.set_trip(TRIP)
    fcc = Sender(KEY, SID_AUTH.secoc_data_id, TRIP)
    frames = sec.protect(*codec.encode("SIM_CONTROL", {"command": 2, "lqg_period": 0.0, "da_bits": 0}))
    for k in range(30):
        frames += sec.protect(*codec.encode("SIM_TICK", {"app": 0, "step": k}))
        out = fcc_outputs(fcc, k, 0.01 * k)
        forged = forged_state(k, 0.3, fault=1)
        frames += out[:-1] + [forged, out[-1]] if where.startswith("before") else out + [forged]
    write_log(tmp_path / "bus.log", frames)
    forgeries = Forgeries()
    (fl,) = split_flights(tmp_path / "bus.log", BusAuth(KEY, TRIP), forgeries)
    a = sid_arrays(SPEC, fl, 30)
    assert np.allclose(a["azkf_alpha_hat"], 0.01 * np.arange(30))
    assert np.allclose(a["azkf_alpha_hi"], 0.01 * np.arange(30) + 0.01)
    assert not a["azkf_fault"].any() and not a["kf_fault"].any()
    # before: each step's forged copy conflicts with fcc's and is not used; after: it is held
    # into the next step, where fcc's own frame conflicts with it (the last one never resolves)
    assert forgeries.conflicts["SID_OUT_AUTH"] == (30 if where.startswith("before") else 29)
    assert forgeries.refused["SID_OUT_AUTH"] == (30 if where.startswith("before") else 29)
    assert forgeries.refused["MSL_ELEV_CMD_AUTH"] == 0
    assert "SID_OUT_AUTH's group: " in forgeries.describe()


def test_a_second_different_frame_for_a_step_is_refused(tmp_path):
    """Read without the key, a lockstep step with two different SID_AZKF_STATE frames has no
    value to report: the flight is refused (one line naming the frame and the step); an exact
    copy of fcc's frame is the same frame."""
    codec = FrameCodec(SPEC, SIM_NODES)
    frames = [codec.encode("SIM_CONTROL", {"command": 2, "lqg_period": 0.0, "da_bits": 0})]
    for k in range(5):
        frames.append(codec.encode("SIM_TICK", {"app": 0, "step": k}))
        frames += all_sid_frames(k, 0.1)
        frames.append(all_sid_frames(k, 0.1)[0])            # an exact repeat: the same frame
    write_log(tmp_path / "bus.log", frames)
    (fl,) = split_flights(tmp_path / "bus.log")
    assert np.allclose(sid_arrays(SPEC, fl, 5)["azkf_alpha_hat"], 0.1)
    frames.append(forged_state(4, 0.1, fault=1))            # the fault bit set: different
    write_log(tmp_path / "bus.log", frames)
    (fl,) = split_flights(tmp_path / "bus.log")
    with pytest.raises(DuplicateOutput, match=r"two different SID_AZKF_STATE frames for step 4"):
        sid_arrays(SPEC, fl, 5)
