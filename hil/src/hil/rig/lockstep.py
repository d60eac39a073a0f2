"""Lockstep: the simulator publishes step k, fcc steps on the tick and answers, the simulator
waits for the answer before it integrates.  Deterministic, and faster than real time.

Per step k of an application (firmware/app/README.md, "Lockstep protocol"):
  1. the driver samples its sensors at t_k (fault starts/ends go out first as SIM_EVENT);
  2. the frames pass the frame/bus fault injector and go out, then SIM_TICK(app, k);
  3. the runner reads until FCC_ACK(app, k), keeping every output frame of the step;
     heartbeat frames update the firmware counters on the way;
  4. the driver consumes the outputs (missile: the elevator command) and integrates.
Several applications are interleaved by their step times (the CDRW at 50 Hz and the missile
at 1/T in one fcc process): the earliest t_k goes next, the CDRW first on a tie.

On the wire-time bus (`--bus wire`, a WireSteps given) the bus model says, in simulated time,
when each frame of the step ends on the wire (hil.rig.lockstep_wire); the frames still travel
on vcan as above.

A tick (or its answer) can be lost without any fault: a flood overflows a receive queue.
So when the answer has not come within half the timeout, the tick is sent again
with the next alive counter -- fcc runs a step once and answers a repeated tick with the
same ACK (firmware/app/README.md, "Repeated tick"); each resend is counted (run_info.json
"resent_ticks").  fcc silent for `timeout` s after all that → FccTimeout("fcc did not answer
step k of app X within 2 s");
fcc gone → FccDied with its exit status.  A tick that a fault drops or corrupts on purpose is
not answered by a correct fcc: the runner knows it (it mirrors fcc's E2E receiver of the
tick) and moves on without waiting; the next clean tick that fcc's E2E check
would refuse as a wrong sequence is followed by one more, which resynchronises it.
"""
from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterable, Sequence

from hil.rig.ack import AckReader
from hil.rig.errors import FccDied, FccTimeout
from hil.rig.link import pack_frame
from hil.rig.lockstep_wire import WireSteps
from hil.rig.simbus import ns
from hil.rig.session import RigSession
from hil.rig.simtime import WALL_PACED
from hil.rig.tickplan import TICK, TickPlan
from hil.sim.drivers import AppDriver, StepIO
from hil.sim.frame_faults import TxFrame
from hil.targets.registry import target

#: the host fcc's lockstep timeout (hil.targets.registry: each target's own)
DEFAULT_TIMEOUT_S = target("host").lockstep_timeout_s
#: check the clock every this many frames even when frames keep coming
CLOCK_EVERY = 32


class LockstepRunner:
    def __init__(self, session: RigSession, timeout: float = DEFAULT_TIMEOUT_S,
                 progress: Callable[[int], None] | None = None, wire: WireSteps | None = None) -> None:
        if not timeout > 0:
            raise ValueError(f"lockstep timeout must be > 0, got {timeout}")
        self.rig = session
        self.timeout = timeout
        self.progress = progress
        self.ack = AckReader(session.codec)
        #: fcc's execution time of each application's steps, by SIM_TICK.app
        self.exec_us: dict[int, list[int]] = {}
        #: the name of each application flown, by SIM_TICK.app (its driver's)
        self.app_names: dict[int, str] = {}
        self.unanswered_ticks = 0
        self.resent_ticks = 0
        self.steps = 0
        self.wall_s = 0.0
        #: a step's frames in one sendmmsg to the host fcc and the M4F image (its slcan line
        #: queues a burst: hil.targets.qemu_m4f.LINE_QUEUE); frame by frame to an external device
        self.batch = target(getattr(session, "target", "host")).batch_frames
        #: the frames the rig authenticates (the tick): the others go out as they were packed
        self._secured = session.security.secured_ids
        #: the flight's ticks made ahead (one application flying, no fault naming the tick)
        self._plan: TickPlan | None = None
        #: the wire-time bus in simulated time (None: the ideal bus)
        self.wire = wire

    def _send(self, raws: list[bytes]) -> None:
        link = self.rig.link
        assert link is not None
        if self.batch:
            link.send_many(raws)
        else:
            for raw in raws:
                link.send_raw(raw)

    def timing(self) -> dict[str, object]:
        """Wall-clock facts of the flights (run_info.json, never summary.json)."""
        def stats(v: list[int]) -> dict[str, float]:
            if not v:
                return {}
            a = sorted(v)
            return {"n": len(a), "p50": a[len(a) // 2], "p99": a[min(len(a) - 1, int(0.99 * len(a)))],
                    "max": a[-1]}
        return {"lockstep_wall_s": self.wall_s, "lockstep_steps": self.steps,
                **({"wire_model_s": self.wire.model_s} if self.wire is not None else {}),
                "wall_ms_per_step": 1e3 * self.wall_s / self.steps if self.steps else None,
                "fcc_exec_us": {self.app_names[a]: stats(v) for a, v in sorted(self.exec_us.items()) if v},
                "unanswered_ticks": self.unanswered_ticks, "resent_ticks": self.resent_ticks}

    def fly(self, drivers: Sequence[AppDriver]) -> None:
        """Run every driver to its end, interleaved by step time."""
        t0 = time.perf_counter()
        try:
            pending = [d for d in drivers if not d.done]
            self._plan_for(pending)
            while pending:
                first = min(pending, key=lambda d: (d.t_next, d.app)) if len(pending) > 1 else pending[0]
                if self.wire is None:
                    self.step(first)
                elif len(pending) == 1:
                    self.step_wire(pending)
                else:   # the applications sampled at that instant together, the CDRW first
                    self.step_wire(sorted((d for d in pending if ns(d.t_next) == ns(first.t_next)),
                                          key=lambda d: d.app))
                pending = [d for d in pending if not d.done]
            if self.wire is not None:   # the last periods' commands come off the wire
                self.wire.reach(max(d.n_steps * d.period for d in drivers))
                for d in drivers:
                    d.finish()
        finally:
            self._plan = None
            self.wall_s += time.perf_counter() - t0
        link = self.rig.link
        assert link is not None
        for d in drivers:  # frames still held back by a delay fault arrive after the run
            for f in d.injector.flush_delayed():
                link.send_raw(f.raw)

    def _wire(self, frames: Iterable[TxFrame]) -> list[bytes]:
        """The frames as the socket sends them, each one the rig authenticates followed by its
        authenticator."""
        secured, secure = self._secured, self.rig.secure
        out: list[bytes] = []
        for f in frames:
            out.append(f.raw)
            if f.frame_id in secured:   # secure() gives the frame itself, then its authenticator
                out += [pack_frame(fid, data) for fid, data in secure(f.frame_id, f.data)[1:]]
        return out

    def _plan_for(self, pending: Sequence[AppDriver]) -> None:
        """Plan the ticks of a flight of one application that no fault of the tick touches
        (two applications' ticks share the counters: step by step)."""
        self._plan = None
        if len(pending) == 1 and not pending[0].injector.names(TICK) and self.rig.security.trip is not None:
            d = pending[0]
            self._plan = TickPlan(d.injector.codec, self.rig.security, d.app, d.k, d.n_steps)

    def step(self, d: AppDriver) -> StepIO:
        if self.wire is not None:
            return self.step_wire([d])[0]
        k, t = d.k, d.t_next
        raws, answer_expected = self._outgoing(d)
        self._send(raws)
        io = self._await_ack(d.app, k, answer_expected, lambda: self._resend_tick(d, k, t))
        self._end(d, io)
        return io

    def step_wire(self, group: Sequence[AppDriver]) -> list[StepIO]:
        """The steps of the applications sampled at one instant, on the wire-time bus: their
        frames are queued on the model together, fcc has its inputs when the last of them has
        ended (hil.rig.lockstep_wire), and its answers, one application after the other, are
        queued then.  No clock read here (a system call in the guest): the model times itself."""
        wire = self.wire
        assert wire is not None
        t = group[0].t_next
        wire.step_at(t)
        out = [(d, d.k, *self._outgoing(d)) for d in group]
        t_in = wire.inputs([r for _, _, raws, _ in out for r in raws], t, t + min(d.period for d in group))
        ios = []
        for d, k, raws, answer_expected in out:
            self._send(raws)
            received: list[tuple[bytes, int]] = []
            io = self._await_ack(d.app, k, answer_expected,
                                 lambda d=d, k=k: self._resend_tick(d, k, t), received)  # type: ignore[misc]
            wire.answer(io, received, t_in)
            self._end(d, io)
            ios.append(io)
        return ios

    def _outgoing(self, d: AppDriver) -> tuple[list[bytes], bool]:
        """Step k's frames as the socket sends them (readings, fault events, the tick), and
        whether fcc will answer."""
        k, t = d.k, d.t_next
        self.app_names[d.app] = d.name
        frames = d.frames_for_step()
        ticks, answer_expected = self._tick(d, k, t)
        if not answer_expected and not d.injector.faulted(t, TICK):
            # a clean tick that fcc's E2E check will refuse (wrong sequence after ticks lost
            # on purpose): one more tick, with the next counter, resynchronises it
            more, answer_expected = self._tick(d, k, t)
            ticks += more
        return self._wire(frames) + ticks, answer_expected

    def _end(self, d: AppDriver, io: StepIO) -> None:
        d.end_step(io)
        self.steps += 1
        if self.progress is not None:
            self.progress(1)

    def _tick(self, d: AppDriver, k: int, t: float) -> tuple[list[bytes], bool]:
        """The tick of step k as the socket sends it (a fault may make it none or several
        frames) with the next counters, and whether fcc will act on it: the mirror of fcc's
        E2E receiver is updated by every tick frame."""
        plan = self._plan
        if plan is not None:
            planned = plan.take(k)
            if planned is None:   # a tick went out that the plan did not have: plan again
                plan = self._plan = TickPlan(d.injector.codec, self.rig.security, d.app, k, d.n_steps)
                planned = plan.take(k)
            if planned is not None:
                d.injector.sent_as_encoded(t, TICK, planned.data)
                # fcc's first checks (length, range, app and step) pass by construction
                return list(planned.wire), self.rig.tick_rx.check(planned.data).data_usable
        frames = d.injector.infrastructure(t, TICK, {"app": d.app, "step": k})
        expected = any([self.rig.fcc_accepts_tick(f.data, d.app, k) for f in frames])  # noqa: C419 - each tick updates the mirror of fcc's E2E state: no short cut
        return self._wire(frames), expected

    def _resend_tick(self, d: AppDriver, k: int, t: float) -> None:
        """The tick of step k once more, with the next alive counter."""
        self._send(self._tick(d, k, t)[0])
        self.resent_ticks += 1

    def _await_ack(self, app: int, k: int, expected: bool,
                   resend: Callable[[], None] | None = None,
                   received: list[tuple[bytes, int]] | None = None) -> StepIO:
        """fcc's answer to step k; received (the wire-time bus): every frame read, in order, with
        how many frames of the answer it completed, fcc's heartbeat left out (paced by the wall
        clock: hil.rig.lockstep_wire)."""
        rig, link, ack = self.rig, self.rig.link, self.ack
        assert link is not None
        io = StepIO(acked=False)
        if not expected:  # fcc will not act on this tick: nothing to wait for
            self.unanswered_ticks += 1
            return io
        # No clock read while the answer comes at once (the usual step): the deadlines start
        # at the first check, dated back by what may have passed unseen before it (one
        # receive slice, or the frames read since the step began).
        deadline = next_resend = math.inf
        n = 0
        while True:
            got = link.recv()
            if got is None or n % CLOCK_EVERY == CLOCK_EVERY - 1:
                if got is None:
                    rig.check_alive(f"during step {k} of app {self.app_names[app]}")
                now = time.monotonic()
                if deadline == math.inf:
                    start = now - link.slice_s if got is None else now
                    deadline = start + self.timeout
                    next_resend = start + self.timeout / 2
                if resend is not None and now >= next_resend and now < deadline:
                    resend()
                    next_resend = now + self.timeout / 2
                if now > deadline:
                    raise FccTimeout(f"{rig.fcc.label if rig.fcc else 'fcc'} did not answer step {k} "
                                     f"of app {self.app_names[app]} "
                                     f"within {self.timeout:g} s")
                if got is None:
                    continue
            n += 1
            frame_id, data = got
            if received is not None and not WALL_PACED[0] <= frame_id <= WALL_PACED[1]:
                received.append((pack_frame(frame_id, data), 0))
            if frame_id >= 0x700:
                rig.note_frame(frame_id, data)
                continue
            if frame_id == ack.frame_id:
                got_ack = ack.read(data, app, k)
                if got_ack is not None:
                    io.acked = True
                    io.degraded, exec_us = got_ack
                    self.exec_us.setdefault(app, []).append(exec_us)
                    return io
                continue  # a repeated ACK of an earlier tick (or one the codec refused)
            accepted = rig.accept(frame_id, data)
            io.frames.extend(accepted)
            if received is not None and accepted:
                received[-1] = (received[-1][0], len(accepted))


__all__ = ["DEFAULT_TIMEOUT_S", "FccDied", "FccTimeout", "LockstepRunner", "WireSteps"]
