"""One flight in a rig session, the bus side of `hil run`: fcc's command line, the session,
the drivers stepping through the flight, and the facts the evaluation needs (Flown).

Nothing here imports numpy.  A lockstep CDRW flight inside scripts/with-vcan's guest has its
drivers computed and its results evaluated on the host (hil.offload), so the guest imports
only what talks to the bus; everywhere else both halves run in this process.  The evaluation
is hil.rig.runs.evaluate_flight either way.
"""
from __future__ import annotations

import platform
import shlex
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .. import offload
from ..bus import FrameCodec, load
from ..faults import Scenario, ScenarioError
from ..progress import bar as progress_bar
from .apps import AppDriver, CdrwDriver, MissileDriver, OracleFlag
from .budget import check_memory
from .lockstep import LockstepRunner
from .session import COMMAND_FLIGHT, COMMAND_GROUND, COMMAND_RESET, RigError, RigSession, StatusCounters
from .targets import TARGETS

MODES = ("lockstep", "realtime")
#: realtime: fcc's SCHED_FIFO priority (the simulator runs normally: in the UML guest a
#: SCHED_FIFO python starved the guest's timers and frame delivery, measured)
FCC_RT_PRIORITY = 50
#: the LQG periods fcc accepts (firmware/app/README.md)
FCC_PERIOD_RANGE = (0.02, 0.3)


@dataclass
class RigConfig:
    out_dir: Path
    iface: str = "vcan0"
    mode: str = "lockstep"
    timeout: float = 2.0
    fcc_args: tuple[str, ...] = ()
    rows: str = "paper"            # CDRW: which estimate fcc reports (fcc --rows)
    progress: bool = True
    plots: bool = True
    fcc_binary: Path | None = None
    log_format: str = "log"
    #: the device under test (hil.rig.targets) and python-can's bus of the simulator
    target: str = "host"
    interface: str = "socketcan"
    bitrate: int | None = None
    key_file: Path | None = None   # None: a random key for each session
    #: the bus recorder of a SocketCAN session (hil.rig.processes.RECORDERS)
    recorder: str = "candump"

    def __post_init__(self) -> None:
        if self.mode not in MODES:
            raise ValueError(f"mode must be one of {', '.join(MODES)}, not {self.mode!r}")
        if self.target not in TARGETS:
            raise ValueError(f"target must be one of {', '.join(TARGETS)}, not {self.target!r}")


@dataclass
class Outcome:
    """What a command produced: the summary (as written) and the text tables to print."""

    out_dir: Path
    summary: dict[str, Any]
    tables: list[str] = field(default_factory=list)


# ---- session helpers ------------------------------------------------------------------------
def check_missile(sc: Scenario) -> None:
    lo, hi = FCC_PERIOD_RANGE
    assert sc.lqg is not None
    if not lo - 1e-12 <= sc.lqg.period <= hi + 1e-12:
        raise ScenarioError(f"{sc.source}: [lqg]: field 'period': fcc runs the LQG at "
                            f"{lo:g} to {hi:g} s, got {sc.lqg.period:g}")


def fcc_args(scenarios: Sequence[Scenario], cfg: RigConfig, apps: Sequence[str] | None = None) -> list[str]:
    """fcc's command line for these scenarios (apps, LQG period/bits, noise variances)."""
    names = list(apps) if apps else [sc.aircraft for sc in scenarios]
    args = ["--mode", cfg.mode, "--apps", ",".join(dict.fromkeys(names))]
    for sc in scenarios:
        if sc.aircraft == "missile":
            assert sc.lqg is not None
            check_missile(sc)
            delay = sc.lqg.resolved_delay(cfg.mode == "realtime")
            args += ["--lqg-period", f"{sc.lqg.period:.6g}", "--lqg-bits", str(sc.lqg.bits),
                     "--lqg-delay", f"{delay:.6g}",
                     "--gyro-var", repr(sc.sensors.var_gyro),  # type: ignore[union-attr]
                     "--accel-var", repr(sc.sensors.var_acc)]  # type: ignore[union-attr]
    if cfg.rows != "paper":
        args += ["--rows", cfg.rows]
    if cfg.mode == "realtime" and cfg.target == "host":  # as on a flight computer (refused
        args += ["--rt-priority", str(FCC_RT_PRIORITY)]   # without privilege: one line); the
        # image has no scheduler to ask (firmware/target/README.md: not applicable)
    return args + list(cfg.fcc_args)


def open_session(out: Path, scenarios: Sequence[Scenario], cfg: RigConfig,
                 prepare: Callable[[RigSession], object] | None = None) -> RigSession:
    """The rig session of a command: its target, its bus, the device's configuration."""
    return RigSession(out, fcc_args(scenarios, cfg), iface=cfg.iface, fcc_binary=cfg.fcc_binary,
                      target=cfg.target, interface=cfg.interface, bitrate=cfg.bitrate,
                      mode=cfg.mode, answer_timeout=cfg.timeout, key_file=cfg.key_file,
                      recorder=cfg.recorder, prepare=prepare)


def lqg_request(rig: RigSession, scenarios: Sequence[Scenario]) -> tuple[float, int]:
    """(period, bits) for the first reset: a device not configured by its command line (the
    emulated image, an external device) gets the missile's design through SIM_CONTROL."""
    if rig.fcc is None or rig.fcc.configured_by_args:
        return 0.0, 0
    for sc in scenarios:
        if sc.aircraft == "missile":
            assert sc.lqg is not None
            return sc.lqg.period, sc.lqg.bits
    return 0.0, 0


def make_drivers(scenarios: Sequence[Scenario], codec: FrameCodec, cfg: RigConfig) -> list[AppDriver]:
    """The drivers of one flight (one fcc): they share the CDRW's fault truth (OracleFlag)."""
    rt = cfg.mode == "realtime"
    oracle = OracleFlag()
    return [(CdrwDriver if sc.aircraft == "cdrw" else MissileDriver)(sc, codec, rt, oracle)
            for sc in scenarios]


def _fly(rig: RigSession, drivers: Sequence[AppDriver], cfg: RigConfig, bar: Any,
         runner: Any = None, period: float = 0.0, bits: int = 0) -> Any:
    """One flight, fcc on the ground before and after it: SIM_CONTROL reset (and a new LQG
    design when period/bits are given; it is also the flight boundary in bus.log), FLIGHT,
    the steps, GROUND (fcc accepts resets and designs on the ground only)."""
    rig.control(COMMAND_RESET, period, bits)
    try:
        if cfg.mode == "lockstep":
            rig.control(COMMAND_FLIGHT)
            r = runner or LockstepRunner(rig, cfg.timeout, bar.update)
            r.fly(drivers)
            return r
        from .realtime import RealtimeRunner
        rt = runner or RealtimeRunner(rig, progress=bar.update)
        rt.fly(drivers)   # FLIGHT goes out just before the first sampling instant
        return rt
    finally:
        if rig.fcc is not None and rig.fcc.poll() is None and rig.link is not None:
            rig.control(COMMAND_GROUND)


def _require_log(rig: RigSession) -> None:
    if not rig.log_complete:
        why = rig.recorder_error or "the recorder did not catch up with the bus"
        raise RigError(f"bus.log: {why}; fcc's outputs are read from that log, so the run is "
                       f"not evaluated")


def _run_info(rig: RigSession, cfg: RigConfig, runner: Any, t_wall: float) -> dict[str, Any]:
    st = rig.status
    info: dict[str, Any] = {
        "mode": cfg.mode, "target": cfg.target, "interface": cfg.interface, "iface": cfg.iface,
        "bitrate": cfg.bitrate, "fcc_command": shlex.join(rig.fcc.cmd) if rig.fcc else "",
        "fcc_exit": rig.fcc_exit, "wall_s": t_wall, "host": platform.node(),
        "python": platform.python_version(), "heartbeats": st.heartbeats,
        "worst_step_us": st.get("FCC_STATUS.worst_step_us"), "status_flags": st.last.get("FCC_STATUS", {}),
        "stale_now": st.get("FCC_E2E_FAULTS.stale_now"),
        "secured_frames_verified": rig.security.counters()["verified"],
        "link": {"tx_frames": rig.link_stats.get("tx_frames", 0), "rx_frames": rig.link_stats.get("rx_frames", 0),
                 "tx_retries": rig.link_stats.get("tx_retries", 0), "tx_dropped": rig.link_stats.get("tx_dropped", 0)},
    }
    if runner is not None:
        info.update(runner.timing())
    return info


@dataclass
class Flown:
    """A flight as the rig flew it, for its evaluation (which may run on the other side of
    hil.offload): the drivers after their last step, fcc's heartbeat counters, the rig's
    verification counters and run_info.json's facts (the runner's timing among them)."""

    drivers: list[AppDriver]
    status: StatusCounters
    security: dict[str, int]
    info: dict[str, Any]
    transmitter: dict[str, Any] = field(default_factory=dict)
    #: offload.keep's key of the host's drivers (with their samples), None: drivers are those
    kept: int | None = None


def drivers_for_guest(scenarios: Sequence[Scenario], cfg: RigConfig) -> tuple[int, list[AppDriver]]:
    """On the host (hil.offload): the flight's drivers, kept here with their samples for the
    evaluation; the guest gets them pickled, without the samples (AppDriver.__getstate__)."""
    drivers = make_drivers(scenarios, FrameCodec(load()), cfg)
    return offload.keep(drivers), drivers


def offloaded(scenarios: Sequence[Scenario], cfg: RigConfig) -> bool:
    """Leave this flight's maths to the host: a lockstep CDRW flight (open loop: nothing the
    simulator sends depends on fcc) with a server of hil.offload ready."""
    return cfg.mode == "lockstep" and all(sc.aircraft == "cdrw" for sc in scenarios) \
        and offload.server_dir() is not None


def run_flight(scenarios: Sequence[Scenario], cfg: RigConfig, command: str = "run") -> Outcome:
    """One flight of one or both aircraft (interleaved in one fcc when both), evaluated
    (hil.rig.runs.evaluate_flight) here or on the host."""
    out = cfg.out_dir
    if len({sc.aircraft for sc in scenarios}) != len(scenarios):
        raise ValueError("one scenario per aircraft")
    check_memory(scenarios)
    t0 = time.perf_counter()
    # the host computes the flight while the guest starts its recorder
    remote = offload.submit("hil.rig.flight:drivers_for_guest", scenarios, cfg) \
        if offloaded(scenarios, cfg) else None
    kept = None

    def prepare(rig: RigSession) -> list[AppDriver]:
        nonlocal kept
        if remote is None:
            return make_drivers(scenarios, rig.codec, cfg)
        kept, drivers = remote.result()
        for d in drivers:
            d.attach(rig.codec)
        return drivers

    with open_session(out, scenarios, cfg, prepare) as rig:
        drivers: list[AppDriver] = rig.prepared  # type: ignore[assignment]
        with progress_bar(sum(d.n_steps for d in drivers), cfg.progress, f"hil {command}") as bar:
            runner = _fly(rig, drivers, cfg, bar, None, *lqg_request(rig, scenarios))
        rig.shutdown()
    _require_log(rig)
    flown = Flown(drivers, rig.status, rig.security.counters(),
                  _run_info(rig, cfg, runner, time.perf_counter() - t0), rig.transmitter_stats, kept)
    if remote is not None:
        return offload.call("hil.rig.runs:evaluate_flight", scenarios, cfg, command, flown)
    from .runs import evaluate_flight
    return evaluate_flight(scenarios, cfg, command, flown)
