"""fcc in lockstep on vcan0, driven frame by frame (issue 6): outputs against the
firmware's own replay tools, the protocol's corner cases, run-time commands.

Run inside the bus environment:
    FCC_BUILD_DIR=$PWD/build scripts/with-vcan .venv/bin/python -m pytest -m vcan tests/python/fcc/test_fcc_lockstep.py
"""
from __future__ import annotations

import csv
import io
import json
import signal
import subprocess

import numpy as np
import pytest

from hil.bus.protocol import COMMAND_FLIGHT, COMMAND_GROUND, COMMAND_RESET, COMMAND_SHUTDOWN
from fcc_harness import (CDRW, MISSILE, Fcc, Sim, flight, missile_sensors, parse_summary)

pytestmark = pytest.mark.vcan

FILTER_PREFIX = {"azkf": "SID_AZKF", "zkf": "SID_ZKF", "kf": "SID_KF"}


@pytest.fixture
def run_fcc(bin_path, tmp_path):
    """run_fcc(*args) starts fcc on vcan0 and a simulator node; both are stopped at the end."""
    started: list[tuple[Fcc, Sim]] = []

    def _start(*args: str) -> tuple[Fcc, Sim]:
        sim = Sim()
        fcc = Fcc(bin_path("fcc"), ("--iface", "vcan0", *args), tmp_path).start()
        fcc.wait_ready()
        started.append((fcc, sim))
        sim.attach()                # fcc's trip from its heartbeat, then FLIGHT
        return fcc, sim

    yield _start
    for fcc, sim in started:
        fcc.kill()
        sim.close()


def shutdown(fcc: Fcc, sim: Sim) -> dict[str, dict[str, float]]:
    sim.control(command=COMMAND_GROUND)     # SHUTDOWN is refused in flight
    sim.control(command=COMMAND_SHUTDOWN)
    assert fcc.wait() == 0, fcc.stderr()
    return parse_summary(fcc.stderr())


# ---- identification ---------------------------------------------------------------

# flight() is not a CDRW flight (its elevator moves 4.6 deg for 0.09 rad/s of pitch rate):
# both sides get a prior of its scale instead of the CDRW wind-tunnel model, whose refits
# on it would hit the MLS's rho guard (a warning, which marks the step degraded).
FLIGHT_PRIOR = ("--prior", "0.97,0.02,-0.4,0.94,-0.004,-0.6")


# The identification options are parsed by the same code in both programs: the
# same options must give the same outputs (the second set: those fcc gained last).
@pytest.mark.parametrize("sid_args", [
    FLIGHT_PRIOR,
    (*FLIGHT_PRIOR, "--mls-intercept", "--no-arm-on-prior", "--max-fault", "3", "--window", "60"),
], ids=["paper", "intercept"])
def test_cdrw_outputs_match_sid_replay(run_fcc, bin_path, tmp_path, sid_args):
    fcc, sim = run_fcc("--apps", "cdrw", *sid_args)
    n = 150
    rows = []
    outputs = []
    for k in range(n):
        alpha, q, de = flight(k)
        rows.append((0.02 * k, alpha, q, de))
        frames, ack = sim.step_cdrw(k, alpha, q, de)
        assert ack.values["degraded"] == 0
        assert len(frames) == 12, sorted(frames)  # every output frame before the ACK
        outputs.append(frames)
    summary = shutdown(fcc, sim)
    assert summary["cdrw"]["steps"] == n and summary["cdrw"]["degraded"] == 0

    data = io.StringIO()
    w = csv.writer(data)
    w.writerow(["t", "alpha", "q", "de"])
    w.writerows(rows)
    replay = subprocess.run([str(bin_path("sid_replay")), "--filter", "all", *sid_args],
                            input=data.getvalue(),
                            capture_output=True, text=True, check=True)
    reference = list(csv.DictReader(io.StringIO(replay.stdout)))
    assert len(reference) == 3 * n
    for row in reference:
        k = round(float(row["t"]) / 0.02)
        p = FILTER_PREFIX[row["filter"]]
        st, bo, ma, mb = (outputs[k][f"{p}_{s}"] for s in ("STATE", "BOUNDS", "MODEL_A", "MODEL_B"))
        assert st["step"] == k & 0xFFF
        assert st["alpha_hat"] == pytest.approx(float(row["alpha_hat"]), abs=6e-6)
        assert st["q_hat"] == pytest.approx(float(row["q_hat"]), abs=6e-6)
        assert st["order"] == int(row["order"])
        for name in ("alpha_lo", "alpha_hi", "q_lo", "q_hi"):
            assert bo[name] == pytest.approx(float(row[name]), abs=6e-5)
        for name in ("a11", "a12", "a21", "a22"):
            assert ma[name] == pytest.approx(float(row[name]), abs=6e-5)
        for name in ("b1", "b2", "rho", "gain_norm"):
            assert mb[name] == pytest.approx(float(row[name]), abs=6e-5)


def test_oracle_fault_flag_drives_the_azkf_order(run_fcc):
    fcc, sim = run_fcc("--apps", "cdrw", "--detector", "oracle")
    k = 0
    for k in range(40):  # the detector is armed once the MLS has data
        sim.step_cdrw(k, *flight(k))
    sim.event(True, 40)
    frames, _ = sim.step_cdrw(40, *flight(40))
    assert frames["SID_AZKF_STATE"]["fault"] == 1
    assert frames["SID_AZKF_STATE"]["order"] == 1000  # q_fault: the low, KF-like gain
    assert frames["SID_KF_STATE"]["fault"] == 1       # shown on every row
    sim.event(False, 41)
    frames, _ = sim.step_cdrw(41, *flight(41))
    assert frames["SID_AZKF_STATE"]["fault"] == 0
    assert frames["SID_AZKF_STATE"]["order"] == 2
    assert shutdown(fcc, sim)["control"]["oracle_events"] == 2


# ---- autopilot ----------------------------------------------------------------------

def lqg_reference(lqg_design: str, period: float, bits: int):
    """The seed's runtime from lqg_design's matrices, in numpy: update, command, D/A, propagate."""
    d = json.loads(subprocess.run([lqg_design, "--period", str(period), "--bits", str(bits)],
                                  capture_output=True, text=True, check=True).stdout)
    phi, gamma, k_gain, l_gain, h = (np.array(d[x]) for x in ("Phi", "Gamma", "K", "L", "H"))
    lsb = 0.8 / 2 ** bits

    def step(x_pred: np.ndarray, y: np.ndarray | None) -> tuple[int, np.ndarray, np.ndarray]:
        x_hat = x_pred if y is None else x_pred + l_gain @ (y - h @ x_pred)
        u = float(np.clip(-(k_gain @ x_hat)[0], -0.4, 0.4))
        code = int(np.clip(np.sign(u) * np.floor(abs(u) / lsb + 0.5), -2 ** (bits - 1), 2 ** (bits - 1) - 1))
        return code, x_hat, phi @ x_hat + gamma[:, 0] * code * lsb

    return step


def test_missile_commands_match_the_lqg_design(run_fcc, bin_path):
    fcc, sim = run_fcc("--apps", "missile", "--lqg-period", "0.05", "--lqg-bits", "8")
    step = lqg_reference(str(bin_path("lqg_design")), 0.05, 8)
    x_pred = np.zeros(3)
    exact = 0
    n = 60
    for k in range(n):
        q_g, n_a = missile_sensors(k)
        frames, ack = sim.step_missile(k, q_g, n_a)
        assert list(frames) == ["MSL_ELEV_CMD", "MSL_STATE_EST"]
        cmd = frames["MSL_ELEV_CMD"]
        assert ack.values["degraded"] == 0 and cmd["degraded"] == 0
        assert cmd["step"] == k and cmd["da_bits"] == 8
        code, x_hat, x_pred = step(x_pred, np.array([q_g, n_a]))
        # one LSB of slack for a rounding tie met in a different order of operations
        assert abs(cmd["da_code"] - code) <= 1
        exact += cmd["da_code"] == code
        est = frames["MSL_STATE_EST"]
        assert est["q_hat"] == pytest.approx(x_hat[0], abs=2e-5)
        assert est["alpha_t_hat"] == pytest.approx(x_hat[1], abs=2e-5)
    assert exact >= n - 1
    summary = shutdown(fcc, sim)
    assert summary["missile"]["steps"] == n
    assert summary["latency_us missile"]["n"] == n  # every command timed from its sensor frames


def test_redesign_between_steps_and_rejected_requests(run_fcc):
    fcc, sim = run_fcc("--apps", "missile")
    for k in range(3):
        frames, _ = sim.step_missile(k, *missile_sensors(k))
        assert frames["MSL_ELEV_CMD"]["da_bits"] == 8
    sim.control(period=0.3, bits=2)   # in flight: refused, whatever the values
    frames, _ = sim.step_missile(3, *missile_sensors(3))
    assert frames["MSL_ELEV_CMD"]["da_bits"] == 8
    sim.control(COMMAND_GROUND)       # designs are accepted on the ground
    sim.control(period=0.1, bits=12)
    sim.control(COMMAND_FLIGHT)
    frames, _ = sim.step_missile(4, *missile_sensors(4))
    assert frames["MSL_ELEV_CMD"]["da_bits"] == 12
    sim.control(COMMAND_GROUND)
    sim.control(period=0.01)          # below 0.02 s: refused
    sim.control(bits=1)               # refused
    sim.control(COMMAND_FLIGHT)
    frames, _ = sim.step_missile(5, *missile_sensors(5))
    assert frames["MSL_ELEV_CMD"]["da_bits"] == 12
    sim.quiet(0.25)                   # two heartbeats at 10 Hz
    assert sim.status["FCC_STATUS"]["config_rejected"] == 1
    assert sim.status["FCC_SEC_COUNTS"]["mode_refused"] == 1
    summary = shutdown(fcc, sim)
    assert summary["lqg"]["period_s"] == pytest.approx(0.1)
    assert summary["lqg"]["bits"] == 12
    assert summary["control"]["configs_applied"] == 1
    assert summary["control"]["configs_rejected"] == 2
    assert "LQG design applied" in fcc.stderr() and "config rejected" in fcc.stderr()


# ---- the protocol ---------------------------------------------------------------------

def test_repeated_lost_and_behind_ticks(run_fcc):
    fcc, sim = run_fcc("--apps", "cdrw,missile")
    sim.step_missile(0, *missile_sensors(0))
    sim.tick(MISSILE, 0)                       # repeated: the ACK again, no second step
    frames, ack = sim.until_ack(MISSILE, 0)
    assert frames == [] and ack.values["step"] == 0
    sim.step_missile(3, *missile_sensors(3))   # steps 1 and 2 lost
    sim.tick(MISSILE, 2)                       # behind: ignored
    assert not any(d.name == "FCC_ACK" for d in sim.quiet(0.3))
    sim.step_cdrw(0, *flight(0))               # the other app is not blocked
    summary = shutdown(fcc, sim)
    assert summary["missile"]["steps"] == 2
    assert summary["missile"]["ticks_repeated"] == 1
    assert summary["missile"]["ticks_lost"] == 2
    assert summary["missile"]["ticks_behind"] == 1
    assert summary["cdrw"]["steps"] == 1


def test_faulty_frames_degrade_count_and_recover(run_fcc):
    fcc, sim = run_fcc("--apps", "cdrw", "--stale-limit", "1")
    node = sim.node
    k = 0

    def good() -> dict:
        nonlocal k
        frames, ack = sim.step_cdrw(k, *flight(k))
        k += 1
        return ack.values

    assert good()["degraded"] == 0
    # bad CRC on alpha
    fid, data = node.codec.encode("CDRW_AOA", {"step": k, "alpha": 0.1})
    node.send_raw(fid, bytes([data[0] ^ 0xFF]) + data[1:])
    sim.cdrw(k, *flight(k), skip=("CDRW_AOA",))
    sim.tick(CDRW, k)
    assert sim.until_ack(CDRW, k)[1].values["degraded"] == 1
    k += 1
    assert good()["degraded"] == 0
    # counter jump (WRONG_SEQUENCE) on q
    for _ in range(6):
        node.codec.encode("CDRW_PITCH_RATE", {"step": k, "q": 0.0})
    sim.step_cdrw(k, *flight(k))
    k += 1
    # wrong DLC on de, value out of range (valid CRC) on alpha, a burst of unknown ids
    fid, data = node.codec.encode("CDRW_ELEVATOR", {"step": k, "delta_e": 0.0})
    node.send_raw(fid, data[:5])
    raw = bytearray(node.codec.encode("CDRW_AOA", {"step": k, "alpha": 0.0})[1])
    raw[4:8] = (2_000_000).to_bytes(4, "little", signed=True)  # 2 rad > the vane's 1.5708
    from hil.bus.e2e import protect
    node.send_raw(0x050, protect(0x1050, bytes(raw), raw[1] & 0x0F))
    for i in range(300):
        node.send_raw(0x555 + (i % 7), bytes(8))
    sim.cdrw(k, *flight(k), skip=("CDRW_AOA", "CDRW_ELEVATOR"))
    sim.tick(CDRW, k)
    assert sim.until_ack(CDRW, k)[1].values["degraded"] == 1
    k += 1
    # one missing frame is bridged (stale limit 1), two are not
    _, ack = sim.step_cdrw(k, *flight(k), skip=("CDRW_PITCH_RATE",))
    assert ack.values["degraded"] == 0
    k += 1
    _, ack = sim.step_cdrw(k, *flight(k), skip=("CDRW_PITCH_RATE",))
    assert ack.values["degraded"] == 1
    k += 1
    # a frame of another step (misaligned)
    node.send("CDRW_AOA", {"step": k + 5, "alpha": 0.1})
    _, ack = sim.step_cdrw(k, *flight(k), skip=("CDRW_AOA",))
    assert ack.values["degraded"] == 1
    k += 1
    for _ in range(3):  # recovery on its own
        assert good()["degraded"] == 0
    sim.quiet(0.25)
    faults = sim.status["FCC_E2E_FAULTS"]
    assert faults["error"] == 1
    assert sim.status["FCC_E2E_COUNTS"]["wrong_sequence"] == 1
    rejects = sim.status["FCC_REJECT_COUNTS"]
    assert rejects["unknown_id"] == 300 and rejects["wrong_dlc"] == 1
    assert rejects["out_of_range"] == 1
    summary = shutdown(fcc, sim)
    assert summary["e2e"]["no_new_data"] == 3  # q twice, de once (its frame was too short)
    assert summary["cdrw"]["degraded"] == 5
    err = fcc.stderr()
    for line in ("E2E ERROR", "E2E WRONG_SEQUENCE", "wrong DLC", "value out of range",
                 "unknown CAN id", "sensor stale", "sensor recovered"):
        assert f"fcc: {line}" in err, line
    # rate limiting: 300 unknown frames, a handful of lines
    assert err.count("fcc: unknown CAN id") <= 3


def test_reset_flies_the_same_flight_again(run_fcc):
    fcc, sim = run_fcc("--apps", "cdrw")
    first = [sim.step_cdrw(k, *flight(k))[0]["SID_AZKF_STATE"] for k in range(30)]
    sim.control(command=COMMAND_GROUND)
    sim.control(command=COMMAND_RESET)
    sim.close()
    # a new simulator process: its alive counters restart at 0; its freshness counters go on
    # (the freshness state belongs to the session with this fcc, not to a process)
    sim2 = Sim(endpoint=sim.sec)
    sim2.control(command=COMMAND_FLIGHT)
    try:
        again = [sim2.step_cdrw(k, *flight(k))[0]["SID_AZKF_STATE"] for k in range(30)]
        assert again == first
        summary = shutdown(fcc, sim2)
    finally:
        sim2.close()
    assert summary["cdrw"]["steps"] == 60            # counters kept across the reset
    assert summary["control"]["resets"] == 1
    assert summary["e2e"]["wrong_sequence"] == 0      # receivers resynchronised


def test_garbage_at_full_rate(run_fcc, bin_path):
    import can
    fcc, sim = run_fcc()
    rng = np.random.default_rng(7)
    flood = can.Bus(interface="socketcan", channel="vcan0")
    consumed = [0x040, 0x041, 0x050, 0x051, 0x052, 0x7F0]
    try:
        for k in range(40):
            for _ in range(60):  # 60 garbage frames per step, as fast as the socket takes them
                fid = int(rng.choice(consumed)) if rng.random() < 0.5 else int(rng.integers(0x080, 0x7FF))
                if fid in (0x100, 0x110, 0x111, 0x112, 0x113, 0x120, 0x121, 0x122, 0x123,
                           0x130, 0x131, 0x132, 0x133, 0x700, 0x701, 0x702, 0x703, 0x704,
                           0x705, 0x706, 0x707, 0x708, 0x709, 0x710, 0x7F1):
                    fid = 0x555
                dlc = int(rng.integers(0, 9))
                msg = can.Message(arbitration_id=fid, data=rng.integers(0, 256, dlc, dtype=np.uint8)
                                  .tobytes(), is_extended_id=False)
                try:
                    flood.send(msg)
                except can.CanOperationError:
                    pass
            frames, _ = sim.step_cdrw(k, *flight(k))
            for name, values in frames.items():
                assert all(np.isfinite(v) for v in values.values()), name
            frames, _ = sim.step_missile(k, *missile_sensors(k))
            code = frames["MSL_ELEV_CMD"]["da_code"]
            assert -128 <= code <= 127
    finally:
        flood.shutdown()
    summary = shutdown(fcc, sim)
    assert summary["cdrw"]["steps"] == 40 and summary["missile"]["steps"] == 40
    assert summary["rejected"]["unknown_id"] > 500
    assert summary["e2e"]["error"] + summary["rejected"]["wrong_dlc"] > 100


def test_sigterm_flushes_the_status_and_prints_counters(run_fcc):
    fcc, sim = run_fcc("--status-rate", "0")
    sim.step_cdrw(0, *flight(0))
    sim.quiet(0.1)
    sim.status.clear()
    fcc.stop(signal.SIGTERM)
    assert fcc.proc.returncode == 0
    sim.quiet(0.3)
    assert sim.status["FCC_STATUS"]["cdrw_steps"] == 1   # the last heartbeat reached the bus
    assert set(sim.status) == {"FCC_STATUS", "FCC_E2E_COUNTS", "FCC_E2E_FAULTS",
                               "FCC_REJECT_COUNTS", "FCC_BUS_COUNTS", "FCC_SEC_COUNTS",
                               "FCC_SEC_SESSION", "FCC_SYNC_STATUS", "FCC_SYNC_REFUSALS"}
    summary = parse_summary(fcc.stderr())
    assert "stopping (SIGTERM)" in fcc.stderr()
    # SIM_CONTROL(FLIGHT), 3 sensor frames, 1 tick
    assert summary["cdrw"]["steps"] == 1 and summary["e2e"]["ok"] == 5
