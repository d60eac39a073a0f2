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

fcc silent for `timeout` s → FccTimeout("fcc did not answer step k of app X within 2 s");
fcc gone → FccDied with its exit status.  A tick that a fault drops or corrupts on purpose is
not answered by a correct fcc: the runner then waits a short while only and moves on.
"""
from __future__ import annotations

import time
from collections.abc import Callable, Sequence

from .apps import APP_NAMES, AppDriver, StepIO
from .link import pack_frame
from .session import FccDied, FccTimeout, RigSession

DEFAULT_TIMEOUT_S = 2.0
#: how long to listen for an ACK that a faulted tick should not produce
UNANSWERED_TICK_WAIT_S = 0.1
#: check the clock every this many frames even when frames keep coming
CLOCK_EVERY = 32


class LockstepRunner:
    def __init__(self, session: RigSession, timeout: float = DEFAULT_TIMEOUT_S,
                 progress: Callable[[int], None] | None = None) -> None:
        if not timeout > 0:
            raise ValueError(f"lockstep timeout must be > 0, got {timeout}")
        self.rig = session
        self.timeout = timeout
        self.progress = progress
        self.ack_id = session.spec.by_name("FCC_ACK").frame_id
        self.exec_us: dict[int, list[int]] = {0: [], 1: []}
        self.unanswered_ticks = 0
        self.steps = 0
        self.wall_s = 0.0

    def fly(self, drivers: Sequence[AppDriver]) -> None:
        """Run every driver to its end, interleaved by step time."""
        t0 = time.perf_counter()
        try:
            while True:
                pending = [d for d in drivers if not d.done]
                if not pending:
                    break
                self.step(min(pending, key=lambda d: (d.t_next, d.app)))
        finally:
            self.wall_s += time.perf_counter() - t0
        link = self.rig.link
        assert link is not None
        for d in drivers:  # frames still held back by a delay fault arrive after the run
            for f in d.injector.flush_delayed():
                link.send_raw(pack_frame(f.frame_id, f.data))

    def step(self, d: AppDriver) -> StepIO:
        link = self.rig.link
        assert link is not None
        k, t = d.k, d.t_next
        frames = d.frames_for_step()
        frames += d.injector.infrastructure(t, "SIM_TICK", {"app": d.app, "step": k})
        answer_expected = not d.injector.faulted(t, "SIM_TICK")
        for f in frames:
            link.send_raw(pack_frame(f.frame_id, f.data))
        io = self._await_ack(d.app, k, answer_expected)
        d.end_step(io)
        self.steps += 1
        if self.progress is not None:
            self.progress(1)
        return io

    def _await_ack(self, app: int, k: int, expected: bool) -> StepIO:
        rig, link = self.rig, self.rig.link
        assert link is not None
        wait = self.timeout if expected else UNANSWERED_TICK_WAIT_S
        deadline = time.monotonic() + wait
        io = StepIO(acked=False)
        n = 0
        while True:
            got = link.recv()
            if got is None or n % CLOCK_EVERY == CLOCK_EVERY - 1:
                if got is None:
                    rig.check_alive(f"during step {k} of app {APP_NAMES[app]}")
                if time.monotonic() > deadline:
                    if expected:
                        raise FccTimeout(f"fcc did not answer step {k} of app {APP_NAMES[app]} "
                                         f"within {self.timeout:g} s; bus log kept in "
                                         f"{rig.run_dir / 'bus.log'}")
                    self.unanswered_ticks += 1
                    return io
                if got is None:
                    continue
            n += 1
            frame_id, data = got
            if frame_id == self.ack_id:
                dec = rig.codec.decode(frame_id, data)
                if dec.ok and dec.values is not None and int(dec.values["app"]) == app \
                        and int(dec.values["step"]) == k:
                    io.acked = True
                    io.degraded = bool(dec.values["degraded"])
                    self.exec_us[app].append(int(dec.values["exec_us"]))
                    return io
                continue  # a repeated ACK of an earlier tick
            if frame_id >= 0x700:
                rig.note_frame(frame_id, data)
                continue
            io.frames.append(got)


__all__ = ["DEFAULT_TIMEOUT_S", "FccDied", "FccTimeout", "LockstepRunner"]
