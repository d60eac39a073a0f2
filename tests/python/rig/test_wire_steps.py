"""The lockstep rig's exchanges with the wire-time bus model (hil.rig.lockstep_wire.WireSteps),
host only: an open-loop flight's exchanges put to the model in batches, fcc's outputs read from
the side socket afterwards and split at the ACK the runner accepted, give the model the same
calls, so the same times and statistics, as one exchange at a time; the frames a step's ACK
does not close (another application's ACK, a repeated one) are not fcc's outputs of the step.
The side socket is a UDP socket on the loopback that receives each struct can_frame as one
datagram, as a CAN_RAW socket does (a Unix datagram pair queues only 10)."""
from __future__ import annotations

import math
import socket

import pytest
from hil.bus.protocol import SIM_EVENT_ID
from hil.bus.rawcan import enlarge_receive_buffer, pack_frame
from hil.rig.lockstep_wire import BATCH, WireSteps
from hil.rig.simbus import Load, SimBus
from hil.sim.drivers import StepIO

ACK_ID = 0x028
SIDS = [0x110 + i for i in range(13)]
READINGS = [0x050, 0x051, 0x052]
TICK = 0x020
PERIOD = 0.02
STEPS = 2 * BATCH + 21   # three batches, the last one short


def _side() -> tuple[socket.socket, socket.socket]:
    """(fcc's end, the side socket): datagrams from one to the other."""
    side = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    side.bind(("127.0.0.1", 0))
    enlarge_receive_buffer(side)
    fcc_end = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    fcc_end.connect(side.getsockname())
    return fcc_end, side


def _ack(app: int, k: int) -> bytes:
    return pack_frame(ACK_ID, bytes([app, 0]) + k.to_bytes(2, "little") + bytes(4))


def _sim_frames(k: int) -> list[bytes]:
    frames = [pack_frame(fid, bytes([k & 0xFF, i, 0x55, 0xAA])) for i, fid in enumerate(READINGS)]
    if k % 7 == 0:   # a fault event now and then: queued after the readings, not waited for
        frames.insert(0, pack_frame(SIM_EVENT_ID, bytes([k & 0xFF, 1])))
    return frames + [pack_frame(TICK, k.to_bytes(8, "little"))]


def _fly(deferred: bool) -> tuple[dict, list[StepIO], int]:
    """The exchanges of a made-up open-loop flight, fcc's outputs on the side socket as fcc
    sends them: its outputs, then its ACK; sometimes another application's ACK before them,
    a repeated ACK after, a step unanswered, a step with fewer outputs."""
    bus = SimBus(250_000, [Load(0.3, 0x200, 0x20F, 0.0, STEPS * PERIOD, 11)])
    fcc_end, side = _side()
    wire = WireSteps(bus, side, deferred)
    ios: list[StepIO] = []
    outputs = 0
    try:
        for k in range(STEPS):
            t = k * PERIOD
            wire.step_at(t)
            t_in = wire.inputs(_sim_frames(k), t, t + PERIOD)
            assert math.isnan(t_in) == deferred
            answered = k % 29 != 5
            if k % 11 == 3:
                fcc_end.send(_ack(2, k))            # the other application's: not this step's
            sids = SIDS[: 13 if k % 13 else 6] if answered else []
            for i, fid in enumerate(sids):
                fcc_end.send(pack_frame(fid, bytes([k & 0xFF, i, 0, 0xFF, 0, 0x0F, k >> 8, 1])))
            outputs += len(sids)
            io = StepIO(acked=answered, frames=[(0x030, bytes(8))] if answered else [])
            # the runner's frames: one the simulator acts on (it completes io.frames[0]), the ACK
            received = [(pack_frame(0x030, bytes(8)), 1), (_ack(1, k), 0)] if answered else []
            if answered:
                fcc_end.send(_ack(1, k))
                if k % 17 == 0:
                    fcc_end.send(_ack(1, k))        # a repeated tick's ACK again
            wire.answer(io, received, t_in)
            ios.append(io)
        wire.reach(STEPS * PERIOD)
        return wire.close(), ios, outputs
    finally:
        fcc_end.close()


def test_batches_give_the_times_of_one_exchange_at_a_time() -> None:
    one, ios_one, outputs = _fly(deferred=False)
    batched, ios_batched, _ = _fly(deferred=True)
    assert batched == one
    assert [io.arrivals for io in ios_batched] == [io.arrivals for io in ios_one]
    answered = [io for io in ios_one if io.acked]
    assert len(answered) < STEPS and all(len(io.arrivals) == 1 and math.isfinite(io.arrivals[0])
                                         for io in answered)
    # fcc sent its outputs, the frame the simulator acts on and one ACK a step answered: no
    # other application's ACK, no repeated one
    fcc = {n["iface"]: n for n in one["nodes"]}["fcc"]
    assert fcc["sent"] == outputs + 2 * len(answered) and one["lost"] == 0


def test_each_command_arrives_after_its_step_s_inputs() -> None:
    """The frame the simulator acts on ends after the step's inputs have (fcc answers then)
    and within its period on this bus (30 % load at 250 kbit/s)."""
    _, ios, _ = _fly(deferred=False)
    for k, io in enumerate(ios):
        if io.acked:
            assert k * PERIOD < io.arrivals[0] < (k + 1) * PERIOD, k


@pytest.mark.parametrize("deferred", [False, True])
def test_an_unanswered_step_queues_no_answer(deferred: bool) -> None:
    bus = SimBus(500_000)
    fcc_end, side = _side()
    wire = WireSteps(bus, side, deferred)
    try:
        wire.step_at(0.0)
        t_in = wire.inputs(_sim_frames(1), 0.0, PERIOD)
        wire.answer(StepIO(acked=False), [], t_in)
        stats = wire.close()
    finally:
        fcc_end.close()
    nodes = {n["iface"]: n for n in stats["nodes"]}
    assert nodes["fcc"]["sent"] == 0 and nodes["sim"]["sent"] == len(_sim_frames(1))
