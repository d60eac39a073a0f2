"""One flight against the device under test, in a rig session: fcc's command line for the
flight's scenarios (fcc_args), the session (open_session), the drivers (make_drivers), the
flight itself with fcc on the ground before and after it (fly), and run_info.json's facts.

The simulator (numpy) is imported by make_drivers and fly, not with this module: `hil run`
opens its session first and imports it while the session listens to the bus.
"""
from __future__ import annotations

import os
import platform
import shlex
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from hil.apps.registry import application
from hil.bus import FrameCodec
from hil.bus.protocol import COMMAND_FLIGHT, COMMAND_GROUND, COMMAND_RESET
from hil.rig.config import FCC_RT_PRIORITY, RigConfig
from hil.rig.errors import RigError
from hil.rig.session import KEPT_KEY, RigSession
from hil.rig.status import StatusCounters
from hil.rig.wirefaults import canbus_faults, refusal
from hil.scenario.file import Scenario
from hil.targets.registry import target

if TYPE_CHECKING:
    from hil.sim.drivers import AppDriver



def on_target(sc: Scenario, cfg: RigConfig) -> Scenario:
    """The scenario as this run's device flies it: in realtime, an actuation delay left to the
    rig ("auto") is the device's own where it has one (the emulated image's serial link:
    hil.targets.registry); RigError if that delay does not fit in the scenario's period."""
    delay = target(cfg.target).actuation_delay_s
    if cfg.mode != "realtime" or delay is None or sc.lqg is None or sc.lqg.delay != "auto":
        return sc
    try:
        return replace(sc, lqg=replace(sc.lqg, delay=delay))
    except ValueError:
        raise RigError(f"--target {cfg.target} acts {delay * 1e3:g} ms after its sampling instant in "
                       f"realtime: a period of {sc.lqg.period:g} s is too short for it") from None


def fcc_args(scenarios: Sequence[Scenario], cfg: RigConfig, apps: Sequence[str] | None = None) -> list[str]:
    """fcc's command line for these scenarios (apps, LQG period/bits and delay, noise variances)."""
    names = list(apps) if apps else [sc.aircraft for sc in scenarios]
    args = ["--mode", cfg.mode, "--apps", ",".join(dict.fromkeys(names))]
    for sc in scenarios:
        args += application(sc.aircraft).fcc_args(on_target(sc, cfg), cfg.mode == "realtime")
    if cfg.rows != "paper":
        args += ["--rows", cfg.rows]
    if cfg.mode == "realtime" and target(cfg.target).host_scheduler:  # as on a flight computer (refused
        args += ["--rt-priority", str(FCC_RT_PRIORITY)]   # without privilege: one line); the
        # image has no scheduler to ask (firmware/port/mps2_an386/README.md: not applicable)
    return args + list(cfg.fcc_args)


def open_session(out: Path, scenarios: Sequence[Scenario], cfg: RigConfig,
                 prepare: Callable[[RigSession], object] | None = None) -> RigSession:
    """The rig session of a command: its target, its bus, the device's configuration (and the
    wire-time bus's faults: refused on another bus, hil.rig.wirefaults)."""
    faults = canbus_faults(scenarios)
    why = refusal(faults, cfg.bus, target(cfg.target).wire == "real")
    if why:
        raise RigError(why)
    rig = RigSession(out, fcc_args(scenarios, cfg), cfg, prepare=prepare)
    rig.wire_faults = faults
    rig.wire_seed = scenarios[0].seed if scenarios else 0
    return rig


def lqg_request(rig: RigSession, scenarios: Sequence[Scenario]) -> tuple[float, int]:
    """(period, bits) for the first reset: a device not configured by its command line (the
    emulated image, an external device) gets the first design an application asks for (the
    missile's) through SIM_CONTROL."""
    if rig.fcc is None or rig.fcc.configured_by_args:
        return 0.0, 0
    for sc in scenarios:
        design = application(sc.aircraft).design_request(sc)
        if design is not None:
            return design
    return 0.0, 0


def make_drivers(scenarios: Sequence[Scenario], codec: FrameCodec, cfg: RigConfig) -> list[AppDriver]:
    """The drivers of one flight (one fcc): they share the CDRW's fault truth (OracleFlag)."""
    from hil.sim.drivers import OracleFlag  # numpy: see the docstring
    rt = cfg.mode == "realtime"
    oracle = OracleFlag()
    return [application(sc.aircraft).driver(on_target(sc, cfg), codec, rt, oracle) for sc in scenarios]


def fly(rig: RigSession, drivers: Sequence[AppDriver], cfg: RigConfig, bar: Any,
         runner: Any = None, period: float = 0.0, bits: int = 0) -> Any:
    """One flight, fcc on the ground before and after it: SIM_CONTROL reset (and a new LQG
    design when period/bits are given; it is also the flight boundary in bus.log), FLIGHT,
    the steps, GROUND (fcc accepts resets and designs on the ground only)."""
    rig.control(COMMAND_RESET, period, bits)
    try:
        if cfg.mode == "lockstep":
            from hil.rig.lockstep import LockstepRunner, WireSteps  # numpy: see the docstring
            rig.control(COMMAND_FLIGHT)
            r = runner or LockstepRunner(rig, cfg.timeout, bar.update)
            # the frames the runner does not read: an open-loop application's outputs (the CDRW's)
            side = rig.model_only_ids if any(not d.closed_loop for d in drivers) else frozenset()
            r.wire = WireSteps.for_flight(rig.bitrate or rig.spec.baudrate, drivers, rig.iface,
                                          side) if cfg.bus == "wire" else None
            try:
                r.fly(drivers)
            finally:
                if r.wire is not None:
                    rig.bus_stats = r.wire.close()
            return r
        from hil.rig.realtime import RealtimeRunner
        rt = runner or RealtimeRunner(rig, progress=bar.update)
        rt.fly(drivers)   # FLIGHT goes out just before the first sampling instant
        return rt
    finally:
        if rig.fcc is not None and rig.fcc.poll() is None and rig.link is not None:
            rig.control(COMMAND_GROUND)


def disk_full(path: Path) -> bool:
    try:
        st = os.statvfs(path)
    except OSError:
        return False
    return st.f_bavail * st.f_frsize < (1 << 20)


def require_log(rig: RigSession) -> None:
    if not rig.log_complete:
        why = rig.recorder_error or "the recorder did not catch up with the bus"
        if disk_full(rig.run_dir):   # the recorder could not write: not a slow recorder
            why = f"no space left on the device of {rig.run_dir}"
        raise RigError(f"bus.log: {why}; fcc's outputs are read from that log, so the run is "
                       f"not evaluated")


def lasting_command(cmd: Sequence[str], run_dir: Path, cfg: RigConfig) -> str:
    """fcc's command line as run_info.json keeps it, naming only files that outlive the run:
    the session's own key (a temporary file) as its copy kept in the run directory
    (KEPT_KEY), the files written into the run directory (bootcfg.bin, a log) relative to it
    (the run is written in a staging directory, renamed when done: hil.io.rundir)."""
    inside = f"{Path(run_dir).resolve()}{os.sep}", f"{run_dir}{os.sep}"
    out: list[str] = []
    for i, arg in enumerate(cmd):
        if i > 0 and cmd[i - 1] == "--key-file" and cfg.key_file is None:
            arg = KEPT_KEY
        for prefix in inside:
            arg = arg.replace(prefix, "")
        out.append(arg)
    return shlex.join(out)


def run_info(rig: RigSession, cfg: RigConfig, runner: Any, t_wall: float) -> dict[str, Any]:
    st = rig.status
    info: dict[str, Any] = {
        "mode": cfg.mode, "target": cfg.target, "interface": cfg.interface, "iface": cfg.iface,
        "bitrate": cfg.bitrate, "fcc_command": lasting_command(rig.fcc.cmd, rig.run_dir, cfg) if rig.fcc else "",
        # the bus key: a --key-file's path (hil replay reads it), else the session's own key
        # kept in the run directory (hil.rig.session.KEPT_KEY)
        "key_file": str(Path(cfg.key_file).resolve()) if cfg.key_file else None,
        "fcc_exit": rig.fcc_exit, "wall_s": t_wall, "host": platform.node(),
        # the kernel the bus ran on; inside scripts/with-vcan: "RELEASE MODE" of its UML guest
        "kernel": platform.release(), "uml": os.environ.get("WITH_VCAN_UML"),
        "python": platform.python_version(), "heartbeats": st.heartbeats,
        "worst_step_us": st.get("FCC_STATUS.worst_step_us"), "status_flags": st.last.get("FCC_STATUS", {}),
        "stale_now": st.get("FCC_E2E_FAULTS.stale_now"),
        "secured_frames_verified": rig.security.counters()["verified"],
        "batch_scheduled": rig.batch_scheduled,
        "link": {"tx_frames": rig.link_stats.get("tx_frames", 0), "rx_frames": rig.link_stats.get("rx_frames", 0),
                 "tx_retries": rig.link_stats.get("tx_retries", 0), "tx_dropped": rig.link_stats.get("tx_dropped", 0)},
    }
    if runner is not None:
        info.update(runner.timing())
    return info


@dataclass
class Flown:
    """A flight as the rig flew it, for its evaluation: the drivers after their last step,
    fcc's heartbeat counters, the rig's verification counters and run_info.json's facts (the
    runner's timing among them)."""

    drivers: list[AppDriver]
    status: StatusCounters
    security: dict[str, int]
    info: dict[str, Any]
    transmitter: dict[str, Any] = field(default_factory=dict)
    #: the run's key and fcc's trip (hil.results.buslog.BusAuth): only frames that verify
    #: under it count in the evaluation (None: every frame counts)
    auth: Any = None
    #: --bus wire: canbus's statistics (hil.rig.wirebus; {} on the ideal bus)
    bus: dict[str, Any] = field(default_factory=dict)
