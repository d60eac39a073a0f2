"""Realtime: the simulator and fcc each on their own clock, as on an aircraft.

fcc runs with --mode realtime (its own CLOCK_MONOTONIC deadlines, no ticks).  The simulator
keeps absolute deadlines t0 + k*period per application (no drift: a late step does not
shift the next one).  At deadline k it finishes period k-1 (missile: integrates it with the
commands that arrived during it, each from the first sub-step after its arrival, the last
one held when none came) and then samples and sends step k.  Between deadlines it receives
fcc's frames.  A late step is counted and run at once; nothing waits for fcc.

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

#: a step that starts this late (s) counts as late
LATE_S = 0.002
#: the first deadline is this far after fly() is called
LEAD_S = 0.05


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

    def timing(self) -> dict[str, object]:
        lat = sorted(self.lateness)
        pct = (lambda p: 1e3 * lat[min(len(lat) - 1, int(p * len(lat)))]) if lat else (lambda p: None)
        return {"realtime_wall_s": self.wall_s, "realtime_steps": self.steps,
                "sim_late_steps": self.late_steps,
                "sim_step_lateness_ms": {"p50": pct(0.5), "p99": pct(0.99), "max": pct(1.0)},
                "rx_frames": self.rx_frames}

    def fly(self, drivers: Sequence[AppDriver]) -> None:
        rig, link = self.rig, self.rig.link
        assert link is not None
        t_begin = time.perf_counter()
        t0 = time.monotonic() + LEAD_S
        # per driver: the StepIO of the period in progress (None before step 0)
        open_io: dict[int, StepIO | None] = {id(d): None for d in drivers}
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
                    d.end_step(io)
                    self.steps += 1
                    if self.progress is not None:
                        self.progress(1)
                    open_io[id(d)] = None
                if j < d.n_steps:
                    self._babble(d, j * d.period, babblers)
                    for f in d.frames_for_step():
                        link.send_raw(pack_frame(f.frame_id, f.data))
                    open_io[id(d)] = StepIO(acked=False, t0=deadline)
                idx[id(d)] = j + 1
                rig.check_alive(f"during realtime step {j} of app {d.name}")
        finally:
            for b in babblers.values():
                b.stop()
            self.wall_s += time.perf_counter() - t_begin

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
            got = link.recv_wait(min(left, 0.05))
            if got is None:
                continue
            self.rx_frames += 1
            frame_id, data = got
            if frame_id >= 0x700:
                rig.note_frame(frame_id, data)
                continue
            for fid, d_ in rig.accept(frame_id, data):
                app = 1 if fid in (0x030, 0x100) else 0
                d = by_app.get(app)
                io = open_io.get(id(d)) if d is not None else None
                if io is not None:
                    io.frames.append((fid, d_))
                    io.arrivals.append(time.monotonic())
