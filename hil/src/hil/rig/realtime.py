"""Realtime: the simulator and fcc each on their own clock, as on an aircraft, on one time base.

fcc runs with --mode realtime (no ticks).  The simulator is the bus's time master
(hil.rig.timesync: SYNC + FOLLOW_UP every 0.1 s, for the whole session) and fcc samples and
commands on the master's instants (firmware/timesync, firmware/app/fcc_node_rt.c).  Step k of
an application is sampled at the instant t0 + k*period, t0 on every period's grid of the master
time; the first flight waits (at most SYNC_WAIT_S) until fcc reports LOCKED in FCC_SYNC_STATUS.

The sensors sample at the instant; the simulator is not the clock.  The plant is known one
step ahead: once period k-1 is closed, y_k is computed and step k's frames are handed over to
the time-triggered transmitter (hil.rig.txsched), which puts them on the bus at t_k whenever the
simulator itself runs.  A step handed over after its instant is counted (sim_late_steps) and
goes out at once; the hand-over slack (instant minus hand-over time) is reported.

The missile's command acts at the actuation instant t_k + delay, or from the time it was on
the bus (its kernel receive stamp) when that was later (counted late).  As soon as period k's
command and estimate are in, the period is integrated and step k+1 handed over; without them
the period is closed PREP_S before the next instant with the previous code held (a command
that comes after that is counted in sim_stale_frames).  fcc numbers its missile steps by the
master's instants, so each command and estimate goes to the period of its step field (one
that comes before the simulator opened that period is kept for it); without that numbering
(fcc not synchronised) a frame goes to the period in progress by its arrival.  The CDRW flies
open loop: its step k+1 is handed over half a period before its instant.

Frame delays are quantised to the sender's period (a delayed frame goes out with the first
step whose time has reached its due time).  A babbling-node flood is a real second node:
``cangen`` on the interface, started and stopped at the fault's times (when the step that
starts or ends it is handed over: up to one period early).

Every flight measures the platform beside it (hil.rig.platform: cyclictest at the flight's
shortest period and fcc's priority, for the flight's length): run_info.json's ``platform``.
"""
from __future__ import annotations

import shutil
import subprocess
import time
from collections.abc import Callable, Sequence

from hil.bus.protocol import COMMAND_FLIGHT, SYNC_HAS_TIME, SYNC_LOCKED
from hil.rig.errors import RigError
from hil.rig.config import FCC_RT_PRIORITY
from hil.rig.inject import apply_requests
from hil.rig.platform import Baseline, facts
from hil.rig.session import RigSession
from hil.rig.timesync import TimeMaster
from hil.rig.txsched import TimedSender
from hil.scenario.faults import Flood
from hil.sim.drivers import AppDriver, StepIO
from hil.util.processes import spawn

#: a closed-loop period without fcc's answer is closed this long (s, at most a quarter period)
#: before the next instant: the integration, the next sample and the hand-over take
#: milliseconds in the loaded UML guest
PREP_S = 0.004
#: the transmitter's SCHED_FIFO priority where allowed: above fcc's (hil.rig.flight.FCC_RT_PRIORITY),
#: so that a step of fcc's never delays a sample
TX_RT_PRIORITY = 51
#: the first sampling instant is at least this far after fly() is called
LEAD_S = 0.05
#: the first flight waits this long at most for fcc to lock to the time master
SYNC_WAIT_S = 3.0


class Babbler:
    """``cangen`` sending one identifier as fast as a flood fault says."""

    def __init__(self, iface: str, f: Flood) -> None:
        exe = shutil.which("cangen")
        if exe is None:
            raise RigError("cangen not found: install can-utils (scripts/setup does)")
        gap_ms = 1000.0 / f.rate_hz
        data = "FF" * f.dlc
        args = [exe, iface, "-g", f"{gap_ms:.3f}", "-I", f"{f.can_id:03X}", "-L", str(f.dlc)]
        if f.dlc:
            args += ["-D", data]
        self.proc = spawn(args, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                          stderr=subprocess.DEVNULL)

    def stop(self) -> None:
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(2.0)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()


class RealtimeRunner:
    def __init__(self, session: RigSession, progress: Callable[[int], None] | None = None) -> None:
        self.rig = session
        self.progress = progress
        self.late_steps = 0
        self.slack_ms: list[float] = []
        self.steps = 0
        self.wall_s = 0.0
        self.rx_frames = 0
        self.lock_wait_s = 0.0
        self.stale_frames = 0
        self._open: dict[int, StepIO | None] = {}
        self._next: dict[int, int] = {}
        self._by_step = False
        self.platform: dict[str, object] = {}
        self.baseline: Baseline | None = None

    def timing(self) -> dict[str, object]:
        """run_info.json's realtime facts; the platform's histogram written beside it."""
        if self.baseline is not None:
            self.baseline.write_hist(self.rig.run_dir)
        s = sorted(self.slack_ms)
        pct = (lambda p: round(s[min(len(s) - 1, int(p * len(s)))], 3)) if s else (lambda p: None)
        tm = self.rig.time_master
        return {"realtime_wall_s": self.wall_s, "realtime_steps": self.steps,
                "sim_late_steps": self.late_steps, "sync_lock_wait_s": self.lock_wait_s,
                "sim_stale_frames": self.stale_frames,
                "time_master": tm.stats() if tm is not None else self.rig.time_master_stats,
                "sim_handover_slack_ms": {"min": pct(0.0), "p1": pct(0.01), "p50": pct(0.5)},
                "transmitter": self.rig.transmitter_stats, "rx_frames": self.rx_frames,
                "platform": {**self.platform,
                             "baseline": self.baseline.summary() if self.baseline else None}}

    def fly(self, drivers: Sequence[AppDriver]) -> None:
        rig = self.rig
        assert rig.link is not None
        master = self.prepare()
        assert rig.transmitter is not None
        self._sender = rig.transmitter
        self._measure_platform(drivers)
        t_begin = time.perf_counter()
        try:
            self._t0 = master.aligned_start(LEAD_S, [d.period for d in drivers])
            if rig.wire is not None:   # the wire faults' times count from the first instant
                rig.wire.start_faults(self._t0)
            # fcc numbers its steps by the master's sampling instants: instant n0 + k is step k
            self._n0 = {id(d): int(round(master.master_us(self._t0) / (d.period * 1e6)))
                        for d in drivers}
            self._open_k: dict[int, int] = {}
            self._ahead: dict[int, dict[int, list[tuple[tuple[int, bytes], float]]]] = {
                id(d): {} for d in drivers}
            self._open = {id(d): None for d in drivers}
            self._next = {id(d): 0 for d in drivers}
            self._babblers: dict[tuple[int, int], Babbler] = {}
            self._by_step = self.sync_state() in SYNC_HAS_TIME
            # FLIGHT (fcc locked on the ground, prepare()) half the shortest period before the
            # first instant: fcc's first step is the flight's step 0, as in lockstep
            self._sender.send_at(rig.message_frames("SIM_CONTROL", {
                "command": COMMAND_FLIGHT, "lqg_period": 0.0, "da_bits": 0}),
                self._t0 - min(d.period for d in drivers) / 2)
            for d in drivers:
                self._hand_over(d)
            if rig.inject is not None:   # `hil inject` may send from now on
                rig.inject.flying(drivers)
            next_poll = 0.0
            while True:
                due = [(self._cutoff(d), d) for d in drivers if self._open[id(d)] is not None]
                if not due:
                    break
                self._listen(min(c for c, _ in due), drivers)
                now = time.monotonic()
                for d in drivers:   # (periods closed while listening are not the same ones)
                    io = self._open[id(d)]
                    if io is not None and now >= self._cutoff(d):   # without all of fcc's answer
                        self._close(d, io)
                        self._hand_over(d)
                rig.check_alive("during a realtime flight")
                if rig.inject is not None and now >= next_poll:   # once per step at most
                    next_poll = now + min(d.period for d in drivers)
                    apply_requests(rig.inject, drivers, self._next)
        finally:
            for b in self._babblers.values():
                b.stop()
            self.wall_s += time.perf_counter() - t_begin
            if self.baseline is not None:   # (read after the flight: timing())
                self.baseline.stop()

    def _measure_platform(self, drivers: Sequence[AppDriver]) -> None:
        """The platform's facts (at the first flight) and its baseline beside this flight, at
        the shortest period and fcc's priority (hil.rig.platform)."""
        if self.baseline is None:
            self.platform = facts()
            self.baseline = Baseline(min(d.period for d in drivers), FCC_RT_PRIORITY)
        self.baseline.start()

    def _instant(self, d: AppDriver, j: int) -> float:
        return self._t0 + j * d.period

    def _cutoff(self, d: AppDriver) -> float:
        """When the period in progress is closed at the latest: before the next instant by
        the time the next step needs to be handed over (closed loop), by half a period for
        an open-loop aircraft (its frames do not depend on fcc)."""
        lead = min(PREP_S, d.period / 4) if d.closed_loop else d.period / 2
        return self._instant(d, self._next[id(d)]) - lead

    def _hand_over(self, d: AppDriver) -> None:
        """Step j's readings to the transmitter, to leave at instant j; its period opens."""
        j = self._next[id(d)]
        self._open[id(d)] = None
        if j >= d.n_steps:
            return
        instant = self._instant(d, j)
        self._babble(d, j * d.period)
        frames = d.frames_for_step()
        slack = instant - time.monotonic()
        self._sender.send_at([(f.frame_id, f.data) for f in frames], instant)
        self.slack_ms.append(1e3 * slack)
        if slack <= 0.0:
            self.late_steps += 1
        io = StepIO(acked=False, t0=instant)
        self._open[id(d)] = io
        self._open_k[id(d)] = j
        self._next[id(d)] = j + 1
        for got, at in self._ahead[id(d)].pop(j, []):  # fcc answered before we opened it
            io.frames.append(got)
            io.arrivals.append(at)
        if io.frames:
            self._close_early(d, io)

    def _step_of(self, d: AppDriver, frame_id: int, data: bytes) -> int | None:
        """The simulator's step a missile output belongs to, from its step field: fcc counts
        the master's sampling instants when it has the master's time (when the flight
        began); otherwise None (the frame goes to the period in progress, by arrival).  An
        output from a step long past is that step's, never the open period's: applied to the
        open period, a backlog after a stall of the simulator acted as a delay of several
        periods for the rest of the flight (measured: the loop diverged)."""
        cur = self._open_k.get(id(d))
        if cur is None or len(data) != 8 or not self._by_step:
            return None
        if frame_id == 0x030:
            raw, mod = int.from_bytes(data[2:4], "little"), 1 << 16   # MSL_ELEV_CMD.step
        elif frame_id == 0x100:
            raw, mod = data[7], 1 << 8                                # MSL_STATE_EST.step
        else:
            return None
        diff = (raw - self._n0[id(d)] - cur) % mod
        return cur + (diff - mod if diff >= mod // 2 else diff)

    def _close(self, d: AppDriver, io: StepIO) -> None:
        self._open[id(d)] = None
        d.end_step(io)
        self.steps += 1
        if self.progress is not None:
            self.progress(1)

    def _close_early(self, d: AppDriver, io: StepIO) -> None:
        """Integrate d's period as soon as everything that acts on it has arrived and hand
        the next step over at once: the more slack before its instant, the better."""
        if d.complete(io):
            self._close(d, io)
            self._hand_over(d)

    def prepare(self) -> TimeMaster:
        """The session's realtime infrastructure, started by the first flight while fcc is
        still on the ground: the time master (fcc locked to it, at most SYNC_WAIT_S) and the
        time-triggered transmitter."""
        rig = self.rig
        if rig.time_master is None:
            assert rig.link is not None
            rig.time_master = TimeMaster(rig.iface, rig.codec,
                                         auth=rig.security.group_sender("TSYNC_AUTH"),
                                         echo_iface=rig.bus_echo_iface)
            rig.time_master.start()
            t = time.monotonic()
            rig.transmitter = TimedSender(rig.iface, rt_priority=TX_RT_PRIORITY,
                                          send_log=None if rig.send_log is None else str(rig.send_log))
            end = t + SYNC_WAIT_S
            status = rig.spec.by_name("FCC_SYNC_STATUS")
            state = self.sync_state()
            while time.monotonic() < end and state != SYNC_LOCKED:
                got = rig.link.recv_wait(0.05)
                if got is not None:
                    n = len(rig.status_frames)
                    rig.note_frame(*got)   # authenticated heartbeat frames are appended
                    for fid, data in rig.status_frames[n:]:   # only this one decoded
                        if fid == status.frame_id:
                            state = int(status.decode(data)["state"])
                rig.check_alive("while locking to the time master")
            self.lock_wait_s = time.monotonic() - t
        return rig.time_master

    def sync_state(self) -> int | None:
        """fcc's time-sync state as of its last FCC_SYNC_STATUS (None: none seen)."""
        v = self.rig.status.last.get("FCC_SYNC_STATUS")
        return None if v is None else int(v["state"])

    def _babble(self, d: AppDriver, t: float) -> None:
        babblers = self._babblers
        for i, f in enumerate(d.injector.faults):
            if not isinstance(f, Flood):
                continue
            key = (id(d), i)
            if f.active(t) and key not in babblers:
                babblers[key] = Babbler(self.rig.iface, f)
            elif not f.active(t) and key in babblers:
                babblers.pop(key).stop()

    def _listen(self, until: float, drivers: Sequence[AppDriver]) -> None:
        """Receive fcc's frames until `until` and all that is queued; each goes to the period
        it belongs to, at the time it was on the bus (its kernel receive stamp)."""
        rig, link = self.rig, self.rig.link
        assert link is not None
        by_app = {d.app: d for d in drivers}
        while True:   # what is queued is read even after `until`: a late simulator must
            left = until - time.monotonic()   # not take a command on time for a missing one
            got = link.recv_stamped(min(max(left, 0.0), 0.05))
            if got is None:
                if left <= 0:
                    return
                continue
            self.rx_frames += 1
            frame_id, data, at = got
            if frame_id >= 0x700:
                rig.note_frame(frame_id, data)
                continue
            for fid, data_ in rig.accept(frame_id, data):  # authenticated frames only
                self._file(fid, data_, at, by_app)

    def _file(self, frame_id: int, data: bytes, at: float, by_app: dict[int, AppDriver]) -> None:
        """One of fcc's outputs into the period it belongs to (see the module doc)."""
        d = by_app.get(1 if frame_id in (0x030, 0x100) else 0)
        if d is None:
            return
        got = (frame_id, data)
        k, cur = self._step_of(d, frame_id, data), self._open_k.get(id(d))
        if k is not None and cur is not None and k > cur:
            self._ahead[id(d)].setdefault(k, []).append((got, at))
            return
        if k is not None and cur is not None and k < cur:
            self.stale_frames += 1   # for a period already integrated
            return
        io = self._open.get(id(d))
        if io is None:
            return
        io.frames.append(got)
        io.arrivals.append(at)
        self._close_early(d, io)
