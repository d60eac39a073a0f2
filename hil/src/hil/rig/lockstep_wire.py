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
"""
from __future__ import annotations

import math
import socket
import sys
from collections import deque
from dataclasses import dataclass

from collections.abc import Collection, Sequence

from hil.bus.dbc import load as load_dbc
from hil.bus.protocol import SIM_EVENT_ID
from hil.bus.mmsg import BatchReceiver
from hil.bus.rawcan import CAN_FRAME, enlarge_receive_buffer, open_raw
from hil.rig.errors import RigError
from hil.bus.canif import open_error
from hil.rig.simbus import Ended, SimBus, loads, ns
from hil.rig.wirebus import NODES
from hil.rig.wirefaults import canbus_args
from hil.rig.simtime import WALL_PACED
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


#: SIM_EVENT's can_id as struct can_frame starts (an 11-bit identifier, no flags)
_EVENT = SIM_EVENT_ID.to_bytes(4, sys.byteorder)


def _wall_paced(raw: bytes) -> bool:
    return WALL_PACED[0] <= CAN_FRAME.unpack_from(raw)[0] <= WALL_PACED[1]


@dataclass(slots=True)
class _Receipt:
    """One frame of fcc's on the bus (the ordinal-th it queued at t_queued ns), and the frames
    of its answer that it completes."""

    t_queued: int
    ordinal: int
    io: StepIO
    first: int
    count: int


class WireSteps:
    """The simulated times of one flight's steps (see the module docstring)."""

    def __init__(self, bus: SimBus, side: socket.socket | None = None) -> None:
        self.bus = bus
        #: the socket of fcc's frames the runner does not read (None: there are none)
        self._side = side
        self._batch = BatchReceiver(side.fileno()) if side is not None and BatchReceiver.available() else None
        self._inflight: deque[_Receipt] = deque()
        # fcc's frames queued on the model at one time, ended: (time in ns, how many).  A FIFO
        # ends a time's frames in order, and a bus-off drops a suffix of them (its queue, then
        # what it queues while off): the k-th to end is the k-th queued then
        self._queued = (-1, 0)
        self._ended = (-1, 0)
        self._t = 0.0

    @classmethod
    def for_flight(cls, bitrate: int, drivers: Sequence[AppDriver], iface: str,
                   side_ids: Collection[int]) -> WireSteps:
        """The model of one flight; fcc's frames side_ids, which the runner does not read,
        from their own socket on iface."""
        wire = [f for d in drivers for f in d.scenario.faults if f.level == "wire"]
        bus = SimBus(bitrate, loads(drivers), sorted(UNDETERMINED),
                     canbus_args(wire, {n: n for n in NODES}, load_dbc()))
        if not side_ids:
            return cls(bus)
        try:
            side = open_raw(iface, side_ids)
        except OSError as e:
            raise RigError(f"--bus wire: {open_error(iface, e)}") from None
        enlarge_receive_buffer(side)
        return cls(bus, side)

    def close(self) -> dict:
        """The model's statistics once what was queued has gone (hil.rig.simbus.SimBus.stats);
        the side socket closed."""
        if self._side is not None:
            self._side.close()
            self._side = None
        return self.stats()

    def reach(self, t: float) -> None:
        """The model runs to t s."""
        self._t = max(self._t, t)
        self._arrived(self.bus.run(t))

    def stats(self) -> dict:
        """The model's statistics (hil.rig.simbus.SimBus.stats) once what was queued has gone."""
        self.reach(self._t + DRAIN_S)
        return self.bus.stats()

    def inputs(self, raws: list[bytes], t: float, horizon: float) -> float:
        """The simulator's frames of a step (or of the steps sampled at t) queued at t; when fcc
        has them all (at most at horizon, an overloaded bus)."""
        inputs: list[bytes] = []
        events: list[bytes] = []
        for r in raws:
            (events if r[:4] == _EVENT else inputs).append(r)
        n = self.bus.queue("sim", inputs, t)
        self.bus.queue("sim", events, t)
        ended = self.bus.run(horizon, "sim", t, n)
        self._arrived(ended)
        at = ns(t)
        mine = [e.t_eof for e in ended if e.node == "sim" and ns(e.t_queued) == at]
        return max(mine) if n and len(mine) >= n else (horizon if n else t)

    def answer(self, io: StepIO, received: list[tuple[bytes, int]], t_in: float) -> None:
        """fcc's frames of the step, each with how many frames of io.frames it completed (in
        order), queued at t_in + FCC_COMPUTE_S."""
        io.wire = True
        io.arrivals = [math.inf] * len(io.frames)
        received = [(raw, 0) for raw in self._drain()] + \
            [(raw, count) for raw, count in received if not _wall_paced(raw)]
        at = ns(t_in + FCC_COMPUTE_S)
        n = self.bus.queue("fcc", [raw for raw, _ in received], t_in + FCC_COMPUTE_S)
        base = self._queued[1] if self._queued[0] == at else 0
        first = 0
        for i, (_, count) in enumerate(received[:n]):
            if count:   # fcc's FIFO ends its frames in the order queued: the i-th from now
                self._inflight.append(_Receipt(at, base + i, io, first, count))
                first += count
        self._queued = (at, base + n)

    def _drain(self) -> list[bytes]:
        """What the side socket holds (nothing blocks: fcc sent it before its ACK), a
        recvmmsg at a time where there is one (a system call is 10-30 us in the UML guest)."""
        out: list[bytes] = []
        side, batch = self._side, self._batch
        while side is not None:
            if batch is not None:
                n = batch.receive(socket.MSG_DONTWAIT)
                if n <= 0:
                    break
                out += batch.frames(n)
                if n < batch.CAPACITY:
                    break
                continue
            try:
                out.append(side.recv(CAN_FRAME.size, socket.MSG_DONTWAIT))
            except (BlockingIOError, InterruptedError):
                break
        return out

    def _arrived(self, ended: list[Ended]) -> None:
        inflight = self._inflight
        for e in ended:
            if e.node != "fcc":
                continue
            at = ns(e.t_queued)
            k = self._ended[1] + 1 if self._ended[0] == at else 0
            self._ended = (at, k)
            # receipts before this frame whose frames never ended (a bus-off dropped them):
            # their frames never arrive (arrival inf)
            while inflight and (inflight[0].t_queued, inflight[0].ordinal) <= (at, k):
                r = inflight.popleft()
                if (r.t_queued, r.ordinal) == (at, k):
                    for i in range(r.first, r.first + r.count):
                        r.io.arrivals[i] = e.t_eof
