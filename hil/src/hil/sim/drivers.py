"""The two aircraft as the rig flies them against fcc, one step at a time.

A driver owns one scenario's simulation (plant, sensors, sensor faults) and its frame
injector (frame and bus faults).  Per step k at t_k = k*period:

    frames = driver.frames_for_step()    readings at t_k as frames, faults applied (fault
                                         starts/ends go out first as SIM_EVENT)
    ... the runner sends them, then SIM_TICK(app, k), waits for FCC_ACK(app, k) ...
    driver.end_step(io)                  fcc's answer; the plant moves to t_k+1

CDRW (seed 1): the simulator flies the pull-up open loop (its own elevator schedule), so the
whole flight (hil.sim.cdrw_cache: computed once per scenario and code) and every frame of it
are computed before the first tick (the hot loop only sends); fcc's outputs, the three
filters' estimates, are read back from the bus log.  Missile (seed 2): the
elevator is the D/A code of fcc's MSL_ELEV_CMD of step k, held over [t_k, t_k + T) with the
scenario's sub-steps; without a usable command of step k the previous code stays applied
(a real actuator holds its last input).
"""
from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from hil.bus import FrameCodec
from hil.bus.apps import BUS_APPS
from hil.bus.protocol import APP_CDRW, APP_MISSILE
from hil.scenario.faults import Fault, SensorFault
from hil.scenario.file import SENSOR_FRAMES, Scenario
from hil.sim.cdrw_cache import open_loop
from hil.sim.cdrw_flight import CdrwSimulation
from hil.sim.frame_faults import KIND_CODES, Batch, FrameInjector, TxFrame
from hil.sim.missile_runs import MissileSimulation
from hil.sim.sensor_faults import FaultEvent, SensorFaultInjector

if TYPE_CHECKING:
    from hil.sim.cdrw_flight import CdrwSample

#: which DBC message and signal carries each sensor signal (hil.bus.apps)
SIGNAL_FRAMES = {name: (frame, sig) for app in BUS_APPS.values() for name, frame, sig in app.sensor_signals}
CDRW_SENSOR_FRAMES = SENSOR_FRAMES["cdrw"]
MISSILE_SENSOR_FRAMES = SENSOR_FRAMES["missile"]
FILTERS = ("azkf", "zkf", "kf")
SID_PREFIX = {"azkf": "SID_AZKF", "zkf": "SID_ZKF", "kf": "SID_KF"}
SID_PARTS = ("STATE", "BOUNDS", "MODEL_A", "MODEL_B")

Message = tuple[str, dict[str, float | int]]


@dataclass(slots=True)
class StepIO:
    """What fcc answered to one step.  Realtime: no ACK; t0 is the wall time (monotonic) the
    period began and arrivals[i] the time frames[i] was received.  Lockstep on the wire-time
    bus (wire): arrivals[i] is the simulated time frames[i] came off the wire (hil.rig.simbus),
    inf until it has (filled in as the bus model runs on, after end_step)."""

    acked: bool
    degraded: bool = False
    frames: list[tuple[int, bytes]] = field(default_factory=list)
    t0: float | None = None
    arrivals: list[float] = field(default_factory=list)
    wire: bool = False


@dataclass
class OracleFlag:
    """The CDRW's sensor-fault truth as last told to fcc: every SIM_EVENT carries it
    (oracle_fault), so the drivers flying in one fcc share one."""

    value: bool = False


def _target_id(codec: FrameCodec, fault: object) -> int:
    if isinstance(fault, SensorFault):
        return codec.spec.by_name(SIGNAL_FRAMES[fault.signal][0]).frame_id
    frame = getattr(fault, "frame", None)
    if frame and frame != "*":
        return codec.spec.by_name(frame).frame_id
    return int(getattr(fault, "can_id", 0))


class AppDriver:
    """Common part: step bookkeeping, SIM_EVENT frames for fault starts and ends."""

    app: int = -1
    name: str = ""
    #: the simulation depends on fcc's outputs (realtime hands its next step over only after)
    closed_loop: bool = False

    def __init__(self, scenario: Scenario, codec: FrameCodec, period: float, n_steps: int,
                 star_frames: tuple[str, ...], realtime: bool = False,
                 oracle: OracleFlag | None = None) -> None:
        self.oracle = oracle if oracle is not None else OracleFlag()
        self.scenario = scenario
        self.codec = codec
        self.period = period
        self.n_steps = n_steps
        self.k = 0
        self.realtime = realtime
        self.injector = FrameInjector(codec, scenario.faults, scenario.seed, star_frames,
                                      flood_frames=not realtime)
        self.events: list[FaultEvent] = []
        self._fault_index = {id(f): i for i, f in enumerate(scenario.faults)}

    @property
    def done(self) -> bool:
        return self.k >= self.n_steps

    @property
    def t_next(self) -> float:
        return self.k * self.period

    def _event_messages(self, k: int, events: list[FaultEvent], oracle: bool) -> list[Message]:
        out: list[Message] = []
        for ev in events:
            self.events.append(ev)
            out.append(("SIM_EVENT", {
                "active": 1 if ev.action == "start" else 0, "oracle_fault": int(oracle),
                "fault_id": self._fault_index.get(id(ev.fault), 255) & 0xFF,
                "kind": KIND_CODES.get(ev.fault.kind, 0), "target_id": _target_id(self.codec, ev.fault),
                "step": k & 0xFFFF}))
        return out

    def inject(self, fault: Fault) -> None:
        """A fault added during the flight (`hil inject`; its start not before the next step
        to be made): in the scenario's list, so it is logged, evaluated and drawn as one of
        its own."""
        self.scenario = self.scenario.replace(faults=(*self.scenario.faults, fault))
        self._fault_index[id(fault)] = len(self.scenario.faults) - 1
        if isinstance(fault, SensorFault):
            self._sensor_faults().add(fault)
        else:
            self.injector.add(fault)

    def _sensor_faults(self) -> SensorFaultInjector:
        raise ValueError(f"the {self.name}'s readings are made before its flight")

    def frames_for_step(self) -> list[TxFrame]:
        raise NotImplementedError

    def end_step(self, io: StepIO) -> None:
        raise NotImplementedError

    def complete(self, io: StepIO) -> bool:
        """Realtime: everything fcc sends for this period has arrived (end_step may run before
        the deadline).  False: wait for the deadline."""
        return False

    def finish(self) -> None:
        """The flight is over: what end_step left for later is done (the lockstep rig on the
        wire-time bus calls it once the bus model has passed the last period's end)."""


# ---------------------------------------------------------------------------------------------
class CdrwDriver(AppDriver):
    """The CDRW pull-up (open loop) and fcc's three identification loops."""

    app = APP_CDRW
    name = "cdrw"

    def __init__(self, scenario: Scenario, codec: FrameCodec, realtime: bool = False,
                 oracle: OracleFlag | None = None) -> None:
        self.sim = CdrwSimulation(scenario)
        super().__init__(scenario, codec, self.sim.dt, self.sim.n_samples, CDRW_SENSOR_FRAMES,
                         realtime, oracle)
        self.samples: list[CdrwSample] = []
        self.steps: list[StepIO] = []
        self._frames: list[list[TxFrame]] = []
        self._events: list[list[Message]] = []
        self._fault_active: list[bool] = []
        # open loop: the flight does not depend on fcc (so it can come from the cache), and
        # its sensor frames are made at once unless a frame fault acts on single ones
        samples = open_loop(scenario, self.n_steps)
        planned = self.injector.outgoing_flight(len(samples), self._batches(samples))
        for k, s in enumerate(samples):
            self.samples.append(s)
            self._fault_active.append(bool(s.fault_active))
            events = list(s.events) + self.injector.update(s.t)
            # SIM_EVENT is encoded when sent: its alive counter is shared with the other app
            self._events.append(self._event_messages(s.k, events, s.fault_active))
            self._frames.append(planned[k] if planned is not None else
                                self.injector.outgoing(s.t, self._messages(s)))

    @staticmethod
    def _batches(samples: list[CdrwSample]) -> Iterator[Batch]:
        """_messages of every sample, a column per signal: the readings that are finite (made
        as outgoing_flight takes them: not at all when a frame fault sends step by step)."""
        steps = np.array([s.k for s in samples], dtype=np.int64) & 0xFFFF
        for sig, frame, field_name in BUS_APPS["cdrw"].sensor_signals:
            v = np.array([s.meas[sig] for s in samples], dtype=np.float64)
            sends = np.isfinite(v)
            yield frame, sends, {"step": steps[sends], field_name: v[sends]}

    def _messages(self, s: CdrwSample) -> list[Message]:
        msgs: list[Message] = []
        step = s.k & 0xFFFF
        for sig, frame, field_name in BUS_APPS[self.name].sensor_signals:  # the DBC's
            v = s.meas[sig]
            if math.isfinite(v):  # a dropped-out sensor sends nothing
                msgs.append((frame, {"step": step, field_name: v}))
        return msgs

    def frames_for_step(self) -> list[TxFrame]:
        k = self.k
        self.oracle.value = self._fault_active[k]
        if not self._events[k]:
            return self._frames[k]
        return self.injector.outgoing(k * self.period, self._events[k], extras=False) + self._frames[k]

    def end_step(self, io: StepIO) -> None:
        self.steps.append(io)
        self.k += 1


# ---------------------------------------------------------------------------------------------
class MissileDriver(AppDriver):
    """The missile in gusts; the elevator comes from fcc's command frame (closed loop)."""

    app = APP_MISSILE
    name = "missile"
    closed_loop = True

    def __init__(self, scenario: Scenario, codec: FrameCodec, realtime: bool = False,
                 oracle: OracleFlag | None = None) -> None:
        self.sim = MissileSimulation(scenario)
        super().__init__(scenario, codec, self.sim.period, self.sim.n_periods, MISSILE_SENSOR_FRAMES,
                         realtime, oracle)
        self.bits = self.sim.dac.bits
        self._cmd = codec.spec.by_name("MSL_ELEV_CMD")
        self._est = codec.spec.by_name("MSL_STATE_EST")
        n, ns = self.n_steps, self.sim.n_sub
        self.t = np.arange(n) * self.period
        self.x = np.empty((n, 3))
        self.y = np.full((n, 2), np.nan)
        self.y_ff = np.empty((n, 2))
        self.fault = np.zeros(n, dtype=np.int8)
        self.code = np.zeros(n, dtype=np.int64)
        self.cmd_ok = np.zeros(n, dtype=np.int8)       # a usable command of step k arrived
        self.acked = np.zeros(n, dtype=np.int8)
        self.degraded = np.zeros(n, dtype=np.int8)
        self.saturated = np.zeros(n, dtype=np.int8)
        self.x_hat = np.full((n, 3), np.nan)
        self.x_fine = np.empty((n * ns + 1, 3))
        self.cmd_missing = 0
        self.cmd_bad = 0
        self.cmd_late = 0
        #: the wire-time bus: each step's command delay, from t_k to when it came off the wire
        self.cmd_delay = np.full(n, np.nan)
        #: the wire-time bus: the step whose period is integrated once the bus model has passed
        #: its end, and the commands not applied yet: (their StepIO, frame index, code, step)
        self._open: int | None = None
        self._waiting: list[tuple[StepIO, int, int, int]] = []
        #: each command acts from t_k + delay (time-triggered actuator; fcc --lqg-delay)
        assert scenario.lqg is not None
        self.delay = scenario.lqg.resolved_delay(realtime)

    def _sensor_faults(self) -> SensorFaultInjector:
        return self.sim.faults

    def frames_for_step(self) -> list[TxFrame]:
        self.finish()
        k = self.k
        s = self.sim.sample()
        self.x[k] = s.x
        self.y[k] = (s.meas["q_g"], s.meas["n_a"])
        self.y_ff[k] = (s.meas_faultfree["q_g"], s.meas_faultfree["n_a"])
        self.fault[k] = int(s.fault_active)
        events = list(s.events) + self.injector.update(s.t)
        msgs = self._event_messages(k, events, self.oracle.value)
        step = k & 0xFFFF
        for sig, frame, field_name in BUS_APPS[self.name].sensor_signals:  # the DBC's
            v = s.meas[sig]
            if math.isfinite(v):
                msgs.append((frame, {"step": step, field_name: v}))
        return self.injector.outgoing(s.t, msgs)

    def complete(self, io: StepIO) -> bool:
        """The command and the estimate of this period are in: the command acts from the
        actuation instant (or from its arrival when it came later), nothing else can change
        the period's integration."""
        ids = {fid for fid, _ in io.frames}
        return io.t0 is not None and self._cmd.frame_id in ids and self._est.frame_id in ids

    def _commands(self, k: int, io: StepIO) -> list[tuple[int, int]]:
        """The usable D/A codes among fcc's frames (E2E-checked by the simulator's codec), with
        their index in io.frames; lockstep: only the command of step k."""
        codes: list[tuple[int, int]] = []
        dac = self.sim.dac
        for i, (frame_id, data) in enumerate(io.frames):
            if frame_id == self._est.frame_id and len(data) == 8:
                v = self._est.decode(data)
                if self.realtime or (int(v["step"]) & 0xFF) == (k & 0xFF):
                    self.x_hat[k] = (v["q_hat"], v["alpha_t_hat"], v["w_g_hat"])
                continue
            if frame_id != self._cmd.frame_id:
                continue
            d = self.codec.decode(frame_id, data)
            ok = d.ok and d.values is not None and int(d.values["da_bits"]) == self.bits \
                and dac.code_min <= int(d.values["da_code"]) <= dac.code_max \
                and (self.realtime or int(d.values["step"]) == (k & 0xFFFF))
            if not ok or d.values is None:
                self.cmd_bad += 1
                continue
            codes.append((i, int(d.values["da_code"])))
            self.degraded[k] = int(d.values["degraded"])
            self.saturated[k] = int(d.values["saturated"])
        return codes

    def end_step(self, io: StepIO) -> None:
        k = self.k
        self.acked[k] = int(io.acked)
        indexed = self._commands(k, io)
        self.cmd_ok[k] = int(bool(indexed))
        if not indexed:
            self.cmd_missing += 1
        if io.wire:  # integrated when the bus model has passed the period's end (finish)
            self._waiting += [(io, i, code, k) for i, code in indexed]
            self._open = k
            self.k += 1
            return
        codes = [(io.arrivals[i] if io.arrivals else 0.0, c) for i, c in indexed]
        ns = self.sim.n_sub
        last = self.sim.last_code
        if io.t0 is None:  # lockstep: the command of step k, from t_k + delay to the next one
            code = codes[-1][1] if codes else last
            trace = self.sim.advance_delayed(code, self.delay)
        else:  # realtime: each command acts at the actuation instant t_k + delay, or from
            # the first sub-step after it arrived when it came later (counted as late)
            h = self.period / ns
            m = self.sim.delay_substeps(self.delay)
            self.cmd_late += sum(1 for a, _ in codes if a > io.t0 + m * h)
            per_sub, code, i = [], last, 0
            for j in range(ns):
                while j >= m and i < len(codes) and codes[i][0] <= io.t0 + j * h:
                    code = codes[i][1]
                    i += 1
                per_sub.append(code)
            code = codes[-1][1] if codes else code
            trace = self.sim.advance_substeps(per_sub)
        self.code[k] = code
        self.x_fine[k * ns: (k + 1) * ns + 1] = trace
        self.k += 1

    def finish(self) -> None:
        """The wire-time bus: the open period [t_k, t_k + T) integrated, each command acting
        from the later of its actuation instant t_j + delay and the simulated time it came off
        the wire (the bus model has run past t_k + T: every arrival before it is known).  A
        command that comes in a later period acts there; one after the actuation instant
        (delay > 0) or after its own period (delay 0) counts as late."""
        k = self._open
        if k is None:
            return
        self._open = None
        t0, end = k * self.period, (k + 1) * self.period
        acts: list[tuple[float, int]] = []
        waiting: list[tuple[StepIO, int, int, int]] = []
        for io, i, code, j in self._waiting:
            arrival = io.arrivals[i]
            act = max(arrival, j * self.period + self.delay)
            if act >= end:
                waiting.append((io, i, code, j))
                continue
            self.cmd_delay[j] = arrival - j * self.period
            late = arrival > j * self.period + self.delay if self.delay > 0 else arrival >= (j + 1) * self.period
            self.cmd_late += int(late)
            acts.append((act, code))
        self._waiting = waiting
        acts.sort(key=lambda a: a[0])
        ns = self.sim.n_sub
        trace = self.sim.advance_switched([(round((a - t0) * 1e9), c) for a, c in acts])
        self.code[k] = self.sim.last_code
        self.x_fine[k * ns: (k + 1) * ns + 1] = trace
