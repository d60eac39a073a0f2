"""The lockstep rig on the wire-time bus, in simulated time (`hil run --mode lockstep --bus
wire`): when each frame of a step would have ended on a real bus (hil.rig.simbus, the C model of
firmware/tools/canbus), while the frames themselves still travel on vcan as in every lockstep
run (the protocol is unchanged; the model decides the times, so the run stays deterministic).

Per step k of an application, sampled at t_k:
  1. the model runs to t_k: every frame that ended before has its time (the missile driver
     integrates its last period only now, hil.sim.drivers.MissileDriver.finish);
  2. the simulator's frames of the step (sensors, tick, fault events) are queued at t_k on its
     node and the model runs until the last of them has ended, SIM_EVENT excepted (the lowest
     priority, no input fcc steps on): fcc's inputs are complete then, t_in;
  3. fcc's answer is queued on fcc's FIFO node at t_in + FCC_COMPUTE_S: the frames the rig
     reads back from bus.log after the flight (the CDRW's identification outputs), taken from
     a socket of their own once the ACK is in (fcc sends a step's outputs before its ACK:
     firmware/app/README.md), then every frame the runner read until the ACK, in the order fcc
     sent them.  Reading the outputs on their own socket after the ACK, rather than among the
     runner's frames, spares the runner a wake-up for each (measured: the CDRW's step on the
     wire 0.34 ms against the ideal bus's 0.11 ms with them read one by one).  Each frame of
     the answer the simulator acts on (a command, and its authenticator when secured) gets the
     end of frame of the frame that completed it as its arrival, once the model gets there.
The frames whose bits the run does not determine take their worst-case length (SPEC §8): the
authenticators (a MAC under the session's random key and trip) and FCC_ACK (it carries fcc's
measured execution time); with their actual bits two runs of one seed differed (measured: a
tick's authenticator 8 µs longer in one, every later time shifted).  fcc's heartbeat
(0x700-0x70F) is left out: in lockstep it is paced by the wall clock
(hil.rig.simtime.WALL_PACED), so it has no simulated time, and putting it on the model where it
happened to be read would make the times depend on the host's speed (measured: a heartbeat
ahead of a command in fcc's FIFO delayed it 2.5 ms at 500 kbit/s in one run, not in the next).
Frames a node's controller queue cannot take are lost (the model's statistics count them; such
a frame never arrives).  Applications sampled at the same instant (the CDRW and the missile
every 0.1 s) are one exchange (LockstepRunner.step_wire): all their frames are queued at t_k,
fcc has its inputs when the last has ended, and its answers (the CDRW's first) are queued then.

What it costs (issue 35: a step at most 1.5x the ideal bus's).  An exchange is one call of the
C library for step 2 (hil.rig.simbus.SimBus.steps, a PyDLL: the GIL kept) and one for step 3;
step 1 is a call of its own only while a frame the simulator acts on is on its way (the
missile's command), else the next exchange's call runs the bus to t_k.  No clock is read per
step (a system call, 8-30 us in the UML guest): the model's wall time is read on one exchange
in SAMPLE, the clock read's own cost taken off (run_info.json wire_model_s, an estimate).  A
flight of one open-loop application (the CDRW alone: nothing the simulator does depends on the
model's times) puts its exchanges to the model BATCH at a time in one call, the same calls in
the same order, so the same times; fcc's outputs are read from the side socket then, a
recvmmsg per 256 frames, each step's those before the ACK the runner accepted (the side socket
receives fcc's ACKs too, in the order the runner's socket does).  What remains is the kernel
handing each of fcc's outputs to one more socket, and taking it back (docs/bus-timing.md, "What
it costs", has the figures).
"""
from __future__ import annotations

import ctypes
import math
import socket
import time
from collections.abc import Collection, Sequence
from dataclasses import dataclass, field

from hil.bus.canif import open_error
from hil.bus.dbc import load as load_dbc
from hil.bus.mmsg import BatchReceiver
from hil.bus.protocol import SIM_EVENT_ID
from hil.bus.rawcan import CAN_FRAME, DATA_OFFSET, enlarge_receive_buffer, open_raw
from hil.rig.errors import RigError
from hil.rig.simbus import NS, SimBus, Step, loads, ns
from hil.rig.wirebus import NODES
from hil.rig.wirefaults import canbus_args
from hil.sim.drivers import AppDriver, StepIO

#: fcc's compute time between its last input and its first output in the model: 0, the
#: lockstep rig does not model it (fcc's measured execution, run_info.json fcc_exec_us, is
#: 0.1-0.4 ms in the UML guest, of the order of one frame at 500 kbit/s)
FCC_COMPUTE_S = 0.0
#: frames whose bits the run does not determine (module docstring): their worst-case length
UNDETERMINED = frozenset({m.frame_id for m in load_dbc().messages if m.is_authenticator}
                         | {load_dbc().by_name("FCC_ACK").frame_id})
#: after the flight the model runs on this long for the frames still queued (its statistics)
DRAIN_S = 1.0
#: an open-loop flight's exchanges go to the model this many at a time (fcc's outputs of that
#: many steps wait in the side socket: 14 frames a CDRW step, its 4 MB queue holds thousands)
BATCH = 64
#: the model's wall time is read on one exchange in this many (a clock read is a system call)
SAMPLE = 16

_ACK_ID = load_dbc().by_name("FCC_ACK").frame_id


class _SideReceiver(BatchReceiver):
    """A batch's worth of fcc's outputs in few system calls."""

    CAPACITY = 256


@dataclass(slots=True)
class _Receipt:
    """One frame of fcc's on the bus (the ordinal-th it queued at t_queued ns), and the frames
    of its answer that it completes."""

    t_queued: int
    ordinal: int
    io: StepIO
    first: int
    count: int


@dataclass(slots=True)
class _Exchange:
    """An open-loop flight's exchange waiting for the model: the simulator's frames at t (ns),
    and fcc's answer (the runner's frames, the ACK it accepted: None, no answer)."""

    t: int
    horizon: int
    inputs: list[bytes]
    io: StepIO | None = None
    received: list[tuple[bytes, int]] = field(default_factory=list)
    ack: bytes | None = None


class WireSteps:
    """The simulated times of one flight's steps (see the module docstring)."""

    def __init__(self, bus: SimBus, side: socket.socket | None = None, deferred: bool = False) -> None:
        """side: the socket of fcc's frames the runner does not read, and of its ACKs (None:
        there are none); deferred: no application acts on the model's times (an open-loop
        flight): the exchanges go to the model BATCH at a time."""
        self.bus = bus
        bus.roles("sim", "fcc", SIM_EVENT_ID, FCC_COMPUTE_S)
        self._side = side
        self._batch = _SideReceiver(side.fileno()) if side is not None and _SideReceiver.available() else None
        #: what the side socket gave, struct can_frames back to back, from _pos on not claimed
        self._blob = bytearray()
        self._pos = 0
        self._deferred = deferred
        self._waiting: list[_Exchange] = []
        self._inflight: list[_Receipt] = []
        # fcc's frames queued on the model at one time, ended: (time in ns, how many).  A FIFO
        # ends a time's frames in order, and a bus-off drops a suffix of them (its queue, then
        # what it queues while off): the k-th to end is the k-th queued then
        self._queued = (-1, 0)
        self._ended = (-1, 0)
        self._t = 0.0
        self._exchanges = 0
        #: the model's wall time: read on the sampled exchanges, and on every batch
        self._sampled_s = 0.0
        self._batches_s = 0.0
        #: what one clock read adds to a time measured (_start)
        self._read_s = min(-time.perf_counter() + time.perf_counter() for _ in range(5))

    @classmethod
    def for_flight(cls, bitrate: int, drivers: Sequence[AppDriver], iface: str,
                   side_ids: Collection[int]) -> WireSteps:
        """The model of one flight; fcc's frames side_ids, which the runner does not read,
        from their own socket on iface."""
        wire = [f for d in drivers for f in d.scenario.faults if f.level == "wire"]
        bus = SimBus(bitrate, loads(drivers), sorted(UNDETERMINED),
                     canbus_args(wire, {n: n for n in NODES}, load_dbc()))
        deferred = len(drivers) == 1 and not drivers[0].closed_loop
        if not side_ids:
            return cls(bus, deferred=deferred)
        try:
            side = open_raw(iface, {*side_ids, _ACK_ID})
        except OSError as e:
            raise RigError(f"--bus wire: {open_error(iface, e)}") from None
        enlarge_receive_buffer(side)
        return cls(bus, side, deferred)

    @property
    def model_s(self) -> float:
        """The model's wall time so far (the sampled exchanges' scaled: an estimate)."""
        return self._sampled_s * SAMPLE + self._batches_s

    def close(self) -> dict:
        """The model's statistics once what was queued has gone (hil.rig.simbus.SimBus.stats);
        the side socket closed."""
        stats = self.stats()
        if self._side is not None:
            self._side.close()
            self._side = None
        return stats

    def stats(self) -> dict:
        """The model's statistics (hil.rig.simbus.SimBus.stats) once what was queued has gone."""
        self.reach(self._t + DRAIN_S)
        return self.bus.stats()

    def reach(self, t: float) -> None:
        """The model runs to t s (an open-loop flight's waiting exchanges first)."""
        self._flush()
        self._t = max(self._t, t)
        at = ns(t)   # an exchange of no frames: the bus runs to t
        _, ends = self.bus.steps([Step(at, at, 0, 0, 0, 0)], (), self._reports(at))
        self._arrived([(tq, te / NS) for tq, te in ends])

    def step_at(self, t: float) -> None:
        """A step sampled at t s is next: the model runs to t when a frame of fcc that an
        application acts on may end before (the missile's command: its driver integrates the
        period up to t); otherwise the next exchange's call does it (the same times)."""
        if self._inflight:
            t0 = self._start()
            self.reach(t)
            self._took(t0)
        self._t = max(self._t, t)

    def inputs(self, raws: list[bytes], t: float, horizon: float) -> float:
        """The simulator's frames of a step (or of the steps sampled at t) queued at t; when fcc
        has them all (at most at horizon, an overloaded bus; nan for an open-loop flight's
        exchange, which the model takes later)."""
        self._exchanges += 1
        if self._deferred:
            self._waiting.append(_Exchange(ns(t), ns(horizon), raws))
            return math.nan
        t0 = self._start()
        at = ns(t)
        (done,), ends = self.bus.steps([Step(at, ns(horizon), 0, len(raws), 0, 0)], raws, self._reports(at))
        self._arrived([(tq, te / NS) for tq, te in ends])
        self._took(t0)
        return done.t_in / NS

    def answer(self, io: StepIO, received: list[tuple[bytes, int]], t_in: float) -> None:
        """fcc's frames of the step, each with how many frames of io.frames it completed (in
        order), queued at t_in + FCC_COMPUTE_S, after its outputs on the side socket."""
        t0 = self._start()
        io.wire = True
        io.arrivals = [math.inf] * len(io.frames)
        ack = received[-1][0] if io.acked and received else None
        if self._deferred:
            x = self._waiting[-1]
            x.io, x.received, x.ack = io, received, ack
        else:
            side = self._claim(ack)
            at = ns(t_in + FCC_COMPUTE_S)
            n = self.bus.queue("fcc", [side, *(raw for raw, _ in received)], at / NS)
            self._receipts(io, received, len(side) // CAN_FRAME.size, n, at)
        self._took(t0)
        if len(self._waiting) >= BATCH:
            self._flush()   # timed on its own

    def _start(self) -> float:
        """The clock now on a sampled exchange (0 on the others: no clock read), and what a
        clock read costs now (what it adds to the time measured: a system call in the guest,
        8-30 us as the machine is loaded)."""
        if self._exchanges % SAMPLE:
            return 0.0
        before = time.perf_counter()
        t0 = time.perf_counter()
        self._read_s = t0 - before
        return t0

    def _took(self, t0: float) -> None:
        """A sampled part of an exchange ends: its wall time, less the clock read's own."""
        if t0:
            self._sampled_s += max(0.0, time.perf_counter() - t0 - self._read_s)

    def _flush(self) -> None:
        """The waiting exchanges of an open-loop flight to the model, in one call."""
        if not self._waiting:
            return
        t0 = time.perf_counter()
        waiting, self._waiting = self._waiting, []
        raws: list[bytes] = []
        steps: list[Step] = []
        sides: list[int] = []
        at = 0   # frames so far
        for x in waiting:
            side = self._claim(x.ack)
            n_side = len(side) // CAN_FRAME.size
            inputs, answer = len(x.inputs), n_side + len(x.received)
            steps.append(Step(x.t, x.horizon, at, inputs, at + inputs, answer))
            sides.append(n_side)
            raws += x.inputs
            raws.append(side)
            raws += [raw for raw, _ in x.received]
            at += inputs + answer
        report = self._reports(waiting[0].t) or any(c for x in waiting for _, c in x.received)
        done, ends = self.bus.steps(steps, raws, report)
        for x, d, n_side in zip(waiting, done, sides):
            if x.io is not None:
                self._receipts(x.io, x.received, n_side, d.answered, d.t_in + ns(FCC_COMPUTE_S))
        self._arrived([(tq, te / NS) for tq, te in ends])
        self._batches_s += max(0.0, time.perf_counter() - t0 - self._read_s)

    def _receipts(self, io: StepIO, received: list[tuple[bytes, int]], skip: int, n: int, at: int) -> None:
        """The frames of io's answer to watch for: of the n queued at `at` ns (skip of fcc's
        outputs from the side socket first), the received ones that completed frames of io."""
        base = self._queued[1] if self._queued[0] == at else 0
        first = 0
        for i, (_, count) in enumerate(received[:max(0, n - skip)]):
            if count:   # fcc's FIFO ends its frames in the order queued: the i-th from now
                self._inflight.append(_Receipt(at, base + skip + i, io, first, count))
                first += count
        self._queued = (at, base + n)

    def _claim(self, ack: bytes | None) -> bytes:
        """fcc's outputs on the side socket (struct can_frames back to back) up to the ACK the
        runner accepted, ACKs left out (fcc sends a step's outputs before its ACK); none for a
        step not answered (fcc sends nothing then), and, should that ACK not be there, none
        (they go with the next).  Looked for as bytes: no object per frame."""
        if self._side is None or ack is None:
            return b""
        blob, head = self._blob, ack[:5]   # an ACK: its can_id and length
        pos = scan = self._pos
        chunks: list[bytes] = []
        while True:
            at = blob.find(head, scan)
            if at < 0:
                del blob[:pos]   # claimed: forget it
                scan, pos, self._pos = scan - pos, 0, 0
                if not self._drain():
                    return b""
                continue
            if (at - pos) % CAN_FRAME.size:   # inside a frame: not a frame's start
                scan = at + 1
                continue
            chunks.append(bytes(blob[pos:at]))
            pos = scan = at + CAN_FRAME.size
            if blob[at + DATA_OFFSET:pos] == ack[DATA_OFFSET:]:   # the ACK the runner accepted
                self._pos = pos
                return b"".join(chunks)   # bytes, as the runner's frames

    def _drain(self) -> bool:
        """What the side socket holds onto the blob (nothing blocks: fcc sent it before its
        ACK), a recvmmsg at a time where there is one; whether there was anything."""
        side, batch, blob = self._side, self._batch, self._blob
        got = False
        while side is not None:
            if batch is not None:
                n = batch.receive(socket.MSG_DONTWAIT)
                if n <= 0:
                    break
                blob += ctypes.string_at(batch.buf, n * CAN_FRAME.size)   # CAN_RAW: classic frames only
                got = True
                if n < batch.CAPACITY:
                    break
                continue
            try:
                blob += side.recv(CAN_FRAME.size, socket.MSG_DONTWAIT)
                got = True
            except (BlockingIOError, InterruptedError):
                break
        return got

    def _arrived(self, ended: list[tuple[int, float]]) -> None:
        """fcc's frames that ended, (queued at, ns; end of frame, s), in order: the receipts'
        frames arrive.  The calls that hand out none are those in which no frame can end that
        a receipt is or will be for (_reports)."""
        inflight = self._inflight
        for at, t_eof in ended:
            k = self._ended[1] + 1 if self._ended[0] == at else 0
            self._ended = (at, k)
            # receipts before this frame whose frames never ended (a bus-off dropped them):
            # their frames never arrive (arrival inf)
            while inflight and (inflight[0].t_queued, inflight[0].ordinal) <= (at, k):
                r = inflight.pop(0)
                if (r.t_queued, r.ordinal) == (at, k):
                    for i in range(r.first, r.first + r.count):
                        r.io.arrivals[i] = t_eof

    def _reports(self, t: int) -> bool:
        """Whether a run from here to past t ns must hand out fcc's frames that end: a receipt
        waits for one, or the last answer was queued at t or later (an answer queued at t, the
        next exchange's when its inputs are none, would count its frames after those)."""
        return bool(self._inflight) or self._queued[0] >= t
