"""The wire-time bus in simulated time (hil.rig.simbus over libcanbus_sim.so) and the missile's
command acting at its end of frame (hil.rig.lockstep_wire, hil.sim.drivers), host only: every
expected time is computed here by hand from the frames' lengths (hil.bus.busload.frame_bits, an
implementation of ISO 11898-1's stuffing that shares no code with the C model)."""
from __future__ import annotations

import ctypes
import dataclasses

import numpy as np
import pytest
from hil.bus import SIM_NODES, FrameCodec
from hil.bus.dbc import load as load_dbc
from hil.bus.busload import frame_bits, worst_case_bits
from hil.bus.rawcan import CAN_FRAME, pack_frame
from hil.results.busstats import load_frames
from hil.rig.lockstep_wire import WireSteps
from hil.rig.errors import RigError
from hil.rig.simbus import _DONE, Load, SimBus, _Done
from hil.rig.wirefaults import SEED_STRIDE, canbus_args
from hil.scenario.faults import BusError, BusLoad, BusOff
from hil.scenario.file import load_default_scenario
from hil.sim import missile
from hil.sim.drivers import MissileDriver, StepIO
from hil.sim.missile_runs import MissileSimulation

IFS = 3
TICK = (0x020, bytes.fromhex("0011223344556677"))
GYRO = (0x040, bytes(8))
CMD = (0x030, bytes.fromhex("a5a5a5a5a5a5a5a5"))


def eof_after(start: float, frame: tuple[int, bytes], bitrate: int) -> float:
    """A frame starting at `start` ends its stuffed length less the interframe space later."""
    return start + (frame_bits(*frame) - IFS) / bitrate


def test_arbitration_and_exact_lengths_by_hand() -> None:
    bus = SimBus(500_000)
    # the simulator queues a gyro reading and a tick at 1 ms: the tick (0x020) wins
    assert bus.queue("sim", [pack_frame(*GYRO), pack_frame(*TICK)], 0.001) == 2
    # fcc's FIFO queues its command at 1.1 ms, while the tick is on the wire
    assert bus.queue("fcc", [pack_frame(*CMD)], 0.0011) == 1
    ended = bus.run(0.01)
    tick_eof = eof_after(0.001, TICK, 500_000)
    # at the next idle bus (tick's end + 3 bits) the command (0x030) beats the gyro (0x040)
    cmd_eof = eof_after(tick_eof + IFS / 500_000, CMD, 500_000)
    gyro_eof = eof_after(cmd_eof + IFS / 500_000, GYRO, 500_000)
    assert [(e.node, e.frame_id) for e in ended] == [("sim", 0x020), ("fcc", 0x030), ("sim", 0x040)]
    assert [e.t_eof for e in ended] == pytest.approx([tick_eof, cmd_eof, gyro_eof], abs=1e-12)
    assert frame_bits(*TICK) == 116 and frame_bits(*GYRO) == 127   # (hil.bus.busload's vectors)
    assert _DONE.size == ctypes.sizeof(_Done)   # the results are read as bytes
    stats = bus.stats()
    assert stats["frames"] == 3 and stats["lost"] == 0 and stats["time_base"] == "simulated"
    assert stats["ids"]["0x030"]["max_s"] == pytest.approx(cmd_eof - 0.0011, abs=1e-9)


def test_a_frame_whose_bits_the_run_does_not_determine_takes_its_worst_case() -> None:
    bus = SimBus(250_000, worst=[0x020])
    bus.queue("sim", [pack_frame(*TICK)], 0.0)
    (e,) = bus.run(1.0)
    assert e.t_eof == pytest.approx((worst_case_bits(8) - IFS) / 250_000, abs=1e-12)


def test_a_full_controller_queue_loses_the_rest() -> None:
    bus = SimBus(125_000)
    assert bus.queue("fcc", [pack_frame(*CMD)] * 70, 0.0) == 64   # CANBUS_QUEUE_LEN
    assert bus.stats()["lost"] == 6


def test_background_load_is_periodic_deterministic_and_analysed() -> None:
    load = Load(0.4, 0x300, 0x30F, 0.0, 1.0, seed=7)

    def fly() -> tuple[list[float], dict]:
        bus = SimBus(500_000, [load])
        ticks = []
        for k in range(50):   # a tick every 20 ms among the load
            bus.queue("sim", [pack_frame(*TICK)], k * 0.02)
            ticks += [e.t_eof for e in bus.run(k * 0.02 + 0.02)]
        return ticks, bus.stats()

    ticks, stats = fly()
    assert (ticks, stats) == fly()   # same seed, same times
    period = 16 * worst_case_bits(8) / 500_000 / 0.4   # 16 streams fill 40 % with C = 135 bits
    streams = stats["load_streams"]
    assert [s["id"] for s in streams] == list(range(0x300, 0x310))
    assert {s["period_ns"] for s in streams} == {round(period * 1e9)}
    carried = sum(v["n"] for k, v in stats["ids"].items() if int(k, 16) >= 0x300)
    assert 16 * int(1.0 / period) <= carried <= 16 * (int(1.0 / period) + 1)
    assert 0.3 < stats["load"] < 0.4   # below 0.4: stuffing on the actual bits is less than the worst case
    frames = load_frames(stats)
    assert [f.frame_id for f in frames] == list(range(0x300, 0x310)) and frames[0].sender == "LOAD"
    # the tick (0x020) waits at most for one load frame already on the wire
    assert max(t - k * 0.02 for k, t in enumerate(ticks)) <= (worst_case_bits(8) + 116 - IFS) / 500_000


def test_a_command_split_inside_a_sub_step_is_exact() -> None:
    """MissilePlant.step_pieces against two plain sub-steps (no gust: the input part only)."""
    h_ns, a_ns = 2_500_000, 1_234_567
    one = missile.MissilePlant(1, gust_scale=0.0)
    two = missile.MissilePlant(1, gust_scale=0.0)
    one.step_pieces([(0, 0.1), (a_ns, -0.2)], h_ns)
    two.step(0.1, a_ns * 1e-9, 1)
    two.step(-0.2, (h_ns - a_ns) * 1e-9, 1)
    np.testing.assert_allclose(one.x, two.x, rtol=1e-12, atol=1e-15)


def _command(codec: FrameCodec, k: int, code: int) -> tuple[int, bytes]:
    return codec.encode("MSL_ELEV_CMD", {"step": k, "da_code": code, "da_bits": 8, "degraded": 0,
                                         "saturated": 0})


def test_the_missile_applies_its_command_at_its_end_of_frame() -> None:
    """One step by hand: the simulator's frames at t_0 = 0, fcc's answer when they have ended;
    the plant's period integrated with the command from its end of frame, computed here."""
    sc = load_default_scenario("missile")
    sc = sc.replace(lqg=dataclasses.replace(sc.lqg, period=0.05))
    bitrate = 250_000
    driver = MissileDriver(sc, FrameCodec(nodes=SIM_NODES))
    wire = WireSteps(SimBus(bitrate))
    fcc = FrameCodec(nodes="FCC")
    wire.reach(0.0)
    sent = [f.raw for f in driver.frames_for_step()] + [pack_frame(*TICK)]
    t_in = wire.inputs(sent, 0.0, 0.05)
    # by hand: the tick first (0x020), then the gyro (0x040), then the accelerometer (0x041)
    frames = sorted(((fid, data) for fid, data in (_unpack(r) for r in sent)), key=lambda f: f[0])
    t = 0.0
    for f in frames:
        t = eof_after(t, f, bitrate) + IFS / bitrate
    assert t_in == pytest.approx(t - IFS / bitrate, abs=1e-12)
    cmd = _command(fcc, 0, 37)
    io = StepIO(acked=True, frames=[cmd])
    wire.answer(io, [(pack_frame(*cmd), 1)], t_in)
    driver.end_step(io)
    wire.reach(0.05)
    cmd_eof = eof_after(t_in + IFS / bitrate, cmd, bitrate)   # the bus is idle 3 bits after t_in
    assert io.arrivals == [pytest.approx(cmd_eof, abs=1e-12)]
    driver.finish()
    # the same period flown by hand, the code switching at the command's end of frame
    ref = MissileSimulation(sc)
    ref.sample()
    trace = ref.advance_switched([(round(cmd_eof * 1e9), 37)])
    ns = ref.n_sub
    np.testing.assert_array_equal(driver.x_fine[: ns + 1], trace)
    assert driver.code[0] == 37 and driver.cmd_delay[0] == pytest.approx(cmd_eof)
    # and it is not the ideal bus's flight (the command from t_0)
    ideal = MissileSimulation(sc)
    ideal.sample()
    assert not np.array_equal(ideal.advance(37), trace)


def _unpack(raw: bytes) -> tuple[int, bytes]:
    fid, dlc, data = CAN_FRAME.unpack(raw)
    return fid, data[:dlc]


def test_a_bus_error_delays_the_step_by_the_retransmission_time() -> None:
    """bus_error on the gyro (canbus's --error, given to the model as the realtime process takes
    it): the corrupted frame leaves the bus idle (bit + 1 + 6 + 8 + 3) bits after its SOF,
    bit = its CRC delimiter (its length less 13: docs/bus-timing.md), and is sent again; every
    frame behind it (here the command, which fcc queues at the gyro's end) ends that much later."""
    args = canbus_args([BusError(start=0.0, duration=0.002, frame="MSL_RATE_GYRO", count=1)],
                       {"sim": "sim", "fcc": "fcc"}, load_dbc())
    gyro = (load_dbc().by_name("MSL_RATE_GYRO").frame_id, bytes(8))

    def step(faults: list[str]) -> tuple[float, dict]:
        bus = SimBus(500_000, faults=faults)
        bus.queue("sim", [pack_frame(*gyro)], 0.0)
        (g,) = bus.run(0.01)
        bus.queue("fcc", [pack_frame(*CMD)], g.t_eof)
        (c,) = bus.run(0.02)
        return c.t_eof, bus.stats()

    clean, _ = step([])
    hit, stats = step(args)
    bits = frame_bits(*gyro)
    assert hit - clean == pytest.approx((bits - 13 + 1 + 6 + 8 + 3) / 500_000, abs=1e-12)
    assert stats["error_frames"] == 1
    nodes = {n["iface"]: n for n in stats["nodes"]}
    assert (nodes["sim"]["tx_errors"], nodes["fcc"]["rx_errors"]) == (1, 1)


def test_bus_off_of_fcc_recovers_after_6_plus_128_x_11_bits() -> None:
    """bus_off of fcc: its frames corrupted until TEC > 255 (32 attempts), its queue dropped,
    back after the error flag (6 bits) and 128 x 11 recessive bits on an idle bus."""
    args = canbus_args([BusOff(start=0.001, node="fcc")], {"sim": "sim", "fcc": "fcc"}, load_dbc())
    bus = SimBus(250_000, faults=args)
    assert bus.queue("fcc", [pack_frame(*CMD)] * 3, 0.001) == 3
    assert bus.run(0.05) == []                       # all 32 attempts corrupted, then bus-off
    assert bus.pending("fcc") == 0
    assert bus.queue("fcc", [pack_frame(*CMD)], 0.05) == 1   # recovered: on the bus again
    (e,) = bus.run(0.06)
    assert e.node == "fcc"
    stats = bus.stats()
    fcc = {n["iface"]: n for n in stats["nodes"]}["fcc"]
    assert fcc["bus_off"] == 1 and fcc["tx_errors"] == 32 and fcc["bus_off_dropped"] == 3
    assert fcc["recovery_s"] == [pytest.approx((6 + 128 * 11) / 250_000, abs=1e-12)]
    assert stats["lost"] == 0 and stats["error_frames"] == 32


def test_the_model_refuses_a_bad_fault_option_in_one_line() -> None:
    with pytest.raises(RigError, match="nobody"):
        SimBus(500_000, faults=["--bus-off", "nobody"])


def test_bus_load_is_canbus_s_load_option() -> None:
    f = BusLoad(start=1.0, duration=2.0, utilisation=0.25, id_lo=0x300, id_hi=0x30F)
    assert canbus_args([f], {}, load_dbc(), seed=5) == [
        "--load", f"util=0.25,id=0x300-0x30F,seed={5 * SEED_STRIDE},from=1,to=3"]
    # the model takes the option: the same streams as the load it describes
    bus = SimBus(500_000, faults=canbus_args([f], {}, load_dbc(), seed=5))
    assert [s["id"] for s in bus.stats()["load_streams"]] == list(range(0x300, 0x310))


def _first_step(bitrate: int, faults: list[str]) -> tuple[MissileDriver, list[bytes]]:
    """The missile's first step through the lockstep rig's model (WireSteps), fcc's command
    queued when its inputs have ended."""
    sc = load_default_scenario("missile")
    sc = sc.replace(lqg=dataclasses.replace(sc.lqg, period=0.05))
    driver = MissileDriver(sc, FrameCodec(nodes=SIM_NODES))
    wire = WireSteps(SimBus(bitrate, faults=faults))
    wire.reach(0.0)
    sent = [f.raw for f in driver.frames_for_step()] + [pack_frame(*TICK)]
    t_in = wire.inputs(sent, 0.0, 0.05)
    cmd = _command(FrameCodec(nodes="FCC"), 0, 37)
    io = StepIO(acked=True, frames=[cmd])
    wire.answer(io, [(pack_frame(*cmd), 1)], t_in)
    driver.end_step(io)
    wire.reach(0.05)
    driver.finish()
    return driver, sent


def test_a_gyro_error_delays_the_missile_s_command_by_the_retransmission_time() -> None:
    """The lockstep path (WireSteps, the missile driver) with bus_error on MSL_RATE_GYRO, once:
    the command comes (bit + 1 + 6 + 8 + 3) bit times later than without, bit = the gyro's CRC
    delimiter, its length (hil.bus.busload.frame_bits of the bytes the simulator sent) less 13."""
    bitrate = 250_000
    error = canbus_args([BusError(start=0.0, duration=0.01, frame="MSL_RATE_GYRO", count=1)],
                        {"sim": "sim", "fcc": "fcc"}, load_dbc())
    clean, sent = _first_step(bitrate, [])
    hit, _ = _first_step(bitrate, error)
    gyro_id = load_dbc().by_name("MSL_RATE_GYRO").frame_id
    (gyro,) = [f for f in (_unpack(r) for r in sent) if f[0] == gyro_id]
    retransmission = (frame_bits(*gyro) - 13 + 1 + 6 + 8 + 3) / bitrate
    assert hit.cmd_delay[0] - clean.cmd_delay[0] == pytest.approx(retransmission, abs=1e-12)
