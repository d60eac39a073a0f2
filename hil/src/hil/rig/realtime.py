"""Realtime: the simulator and fcc each on their own clock, as on an aircraft, on one time base.

fcc runs with --mode realtime (no ticks).  The simulator is the bus's time master
(hil.rig.timesync: SYNC + FOLLOW_UP every 0.1 s, for the whole session) and fcc samples and
commands on the master's instants (firmware/timesync, firmware/app/fcc_node_rt.c).  The
simulator keeps absolute deadlines t0 + k*period per application (no drift: a late step does
not shift the next one), t0 on every period's grid of the master time; the first flight waits
(at most SYNC_WAIT_S) until fcc reports LOCKED in FCC_SYNC_STATUS.

At deadline k it sends step k's sensor frames (sampled before, see below).  The missile's
command acts at the actuation instant t_k + delay (from its arrival when it came later:
counted late).  As soon as period k's command and estimate are in, the period is integrated
and step k+1 sampled, so that at the next deadline only the sending is left; without them the
period is closed at the next deadline with the previous code held.  fcc numbers its missile
steps by the master's instants, so each command and estimate goes to the period of its step
field (one that comes before the simulator opened that period is kept for it, one for a
period already integrated is counted in sim_stale_frames); without that numbering (fcc not
synchronised) a frame goes to the period in progress by its arrival.  A late step is counted
and run at once; nothing waits for fcc.

Frame delays are quantised to the sender's period (a delayed frame goes out with the first
step whose time has reached its due time).  A babbling-node flood is a real second node:
``cangen`` on the interface, started and stopped at the fault's times.
"""
from __future__ import annotations

import shutil
import subprocess
import time
from collections.abc import Callable, Sequence

from ..faults import Flood
from .apps import AppDriver, StepIO
from .link import pack_frame
from .processes import spawn
from .session import RigError, RigSession
from .timesync import TimeMaster

#: a step that starts this late (s) counts as late
LATE_S = 0.002
#: the first deadline is at least this far after fly() is called
LEAD_S = 0.05
#: the first flight waits this long at most for fcc to lock to the time master
SYNC_WAIT_S = 3.0
SYNC_LOCKED = 2


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
        self.worst_late_s = 0.0
        self.lateness: list[float] = []
        self.steps = 0
        self.wall_s = 0.0
        self.rx_frames = 0
        self.lock_wait_s = 0.0
        self.stale_frames = 0
        self._prepared: dict[int, list] = {}

    def timing(self) -> dict[str, object]:
        lat = sorted(self.lateness)
        pct = (lambda p: 1e3 * lat[min(len(lat) - 1, int(p * len(lat)))]) if lat else (lambda p: None)
        tm = self.rig.time_master
        return {"realtime_wall_s": self.wall_s, "realtime_steps": self.steps,
                "sim_late_steps": self.late_steps, "sync_lock_wait_s": self.lock_wait_s,
                "sim_stale_frames": self.stale_frames,
                "time_master": tm.stats() if tm is not None else self.rig.time_master_stats,
                "sim_step_lateness_ms": {"p50": pct(0.5), "p99": pct(0.99), "max": pct(1.0)},
                "rx_frames": self.rx_frames}

    def fly(self, drivers: Sequence[AppDriver]) -> None:
        rig, link = self.rig, self.rig.link
        assert link is not None
        master = self._time_master()
        t_begin = time.perf_counter()
        t0 = master.aligned_start(LEAD_S, [d.period for d in drivers])
        # per driver: the StepIO of the period in progress (None before step 0)
        open_io: dict[int, StepIO | None] = {id(d): None for d in drivers}
        self._prepared = {}
        # fcc numbers its steps by the master's sampling instants: instant n0 + k is step k
        self._n0 = {id(d): int(round(master.master_us(t0) / (d.period * 1e6))) for d in drivers}
        self._open_k: dict[int, int] = {}
        self._ahead: dict[int, dict[int, list[tuple[tuple[int, bytes], float]]]] = {
            id(d): {} for d in drivers}
        ends = {id(d): d.n_steps for d in drivers}   # deadline index of the final integration
        idx = {id(d): 0 for d in drivers}            # next deadline index per driver
        babblers: dict[tuple[int, int], Babbler] = {}
        try:
            while True:
                pending = [d for d in drivers if idx[id(d)] <= ends[id(d)]]
                if not pending:
                    break
                d = min(pending, key=lambda d: (idx[id(d)] * d.period, d.app))
                j = idx[id(d)]
                deadline = t0 + j * d.period
                self._listen(deadline, drivers, open_io)
                now = time.monotonic()
                late = max(0.0, now - deadline)
                self.lateness.append(late)
                if late > LATE_S:
                    self.late_steps += 1
                io = open_io[id(d)]
                if io is not None:
                    self._close(d, io)
                    open_io[id(d)] = None
                if j < d.n_steps:
                    self._babble(d, j * d.period, babblers)
                    frames = self._prepared.pop(id(d), None)
                    for f in (frames if frames is not None else d.frames_for_step()):
                        link.send_raw(pack_frame(f.frame_id, f.data))
                    io = StepIO(acked=False, t0=deadline)
                    open_io[id(d)] = io
                    self._open_k[id(d)] = j
                    for got, at in self._ahead[id(d)].pop(j, []):  # fcc answered before we asked
                        io.frames.append(got)
                        io.arrivals.append(at)
                    if io.frames and self._close_early(d, io):
                        open_io[id(d)] = None
                idx[id(d)] = j + 1
                rig.check_alive(f"during realtime step {j} of app {d.name}")
        finally:
            for b in babblers.values():
                b.stop()
            self.wall_s += time.perf_counter() - t_begin

    def _step_of(self, d: AppDriver, frame_id: int, data: bytes) -> int | None:
        """The simulator's step a missile output belongs to, from its step field (fcc counts
        the master's sampling instants); None when it is not one within 4 steps of the open
        period (fcc not synchronised: the frame goes to the open period, by arrival)."""
        cur = self._open_k.get(id(d))
        if cur is None or len(data) != 8:
            return None
        if frame_id == 0x030:
            raw, mod = int.from_bytes(data[2:4], "little"), 1 << 16   # MSL_ELEV_CMD.step
        elif frame_id == 0x100:
            raw, mod = data[7], 1 << 8                                # MSL_STATE_EST.step
        else:
            return None
        diff = (raw - self._n0[id(d)] - cur) % mod
        diff = diff - mod if diff >= mod // 2 else diff
        return cur + diff if abs(diff) <= 4 else None

    def _close(self, d: AppDriver, io: StepIO) -> None:
        d.end_step(io)
        self.steps += 1
        if self.progress is not None:
            self.progress(1)

    def _close_early(self, d: AppDriver, io: StepIO) -> bool:
        """Integrate d's period as soon as everything that acts on it has arrived, and sample
        the next step's readings now, so that at the deadline only the sending is left (in the
        loaded UML guest the integration takes milliseconds; done at the deadline it delayed
        every sensor frame by as much)."""
        if not d.complete(io):
            return False
        self._close(d, io)
        if not d.done:
            self._prepared[id(d)] = d.frames_for_step()
        return True

    def _time_master(self) -> TimeMaster:
        """The session's time master, started (and fcc locked to it) on the first flight."""
        rig = self.rig
        if rig.time_master is None:
            assert rig.link is not None
            rig.time_master = TimeMaster(rig.iface, rig.codec)
            rig.time_master.start()
            end = time.monotonic() + SYNC_WAIT_S
            while time.monotonic() < end and self.sync_state() != SYNC_LOCKED:
                got = rig.link.recv_wait(0.05)
                if got is not None:
                    rig.note_frame(*got)
                rig.check_alive("while locking to the time master")
            self.lock_wait_s = SYNC_WAIT_S - max(0.0, end - time.monotonic())
        return rig.time_master

    def sync_state(self) -> int | None:
        """fcc's time-sync state as of its last FCC_SYNC_STATUS (None: none seen)."""
        v = self.rig.status.last.get("FCC_SYNC_STATUS")
        return None if v is None else int(v["state"])

    def _babble(self, d: AppDriver, t: float, babblers: dict[tuple[int, int], Babbler]) -> None:
        for i, f in enumerate(d.injector.faults):
            if not isinstance(f, Flood):
                continue
            key = (id(d), i)
            if f.active(t) and key not in babblers:
                babblers[key] = Babbler(self.rig.iface, f)
            elif not f.active(t) and key in babblers:
                babblers.pop(key).stop()

    def _listen(self, until: float, drivers: Sequence[AppDriver],
                open_io: dict[int, StepIO | None]) -> None:
        """Receive fcc's frames until the deadline; each goes to the period in progress of
        its application."""
        rig, link = self.rig, self.rig.link
        assert link is not None
        by_app = {d.app: d for d in drivers}
        while True:
            left = until - time.monotonic()
            if left <= 0:
                return
            if left < 0.001:  # poll() counts whole milliseconds: sleep the rest, never spin
                time.sleep(left)
                return
            got = link.recv_wait(min(left, 0.05))
            if got is None:
                continue
            self.rx_frames += 1
            frame_id, data = got
            if frame_id >= 0x700:
                rig.note_frame(frame_id, data)
                continue
            for fid, data_ in rig.accept(frame_id, data):  # authenticated frames only
                self._file(fid, data_, by_app, open_io)

    def _file(self, frame_id: int, data: bytes, by_app: dict[int, AppDriver],
              open_io: dict[int, StepIO | None]) -> None:
        """One of fcc's outputs into the period it belongs to (see the module doc)."""
        d = by_app.get(1 if frame_id in (0x030, 0x100) else 0)
        if d is None:
            return
        got = (frame_id, data)
        at = time.monotonic()
        k, cur = self._step_of(d, frame_id, data), self._open_k.get(id(d))
        if k is not None and cur is not None and k > cur:
            self._ahead[id(d)].setdefault(k, []).append((got, at))
            return
        if k is not None and cur is not None and k < cur:
            self.stale_frames += 1   # for a period already integrated
            return
        io = open_io.get(id(d))
        if io is None:
            return
        io.frames.append(got)
        io.arrivals.append(at)
        if self._close_early(d, io):
            open_io[id(d)] = None
