"""Scenarios: which aircraft, how long, which seed, plant/sensor/LQG options and faults.

A scenario is a TOML file (or the embedded defaults, ``load_default_scenario("cdrw")``):

    aircraft = "cdrw"            # or "missile"
    duration = 7.0               # s
    seed = 1
    [plant]    ...               # CdrwPlantOptions / MissilePlantOptions (hil.scenario.plant_options)
    [sensors]  ...               # CdrwSensorOptions / MissileSensorOptions (hil.sim.sensors)
    [lqg]      ...               # missile only: period, bits, closed_loop
    [[faults]]
    kind = "spike"               # see hil.scenario.faults.KINDS
    signal = "alpha"
    start = 4.0
    duration = 0.1
    magnitude = 0.15

Faults can also come from the command line: ``spike:signal=alpha,start=4,duration=0.1,
magnitude=0.15`` (parse_fault_spec), or from a `hil verify` case flying one or both aircraft,
which gives each to the aircraft its signal or frame belongs to (parse_flight_fault).  Every
error is a ScenarioError with one line that names the file (or "command line"), the fault (its
index and kind) and the field.
"""
from __future__ import annotations

import dataclasses
import math
from collections.abc import Collection, Iterable, Mapping
from dataclasses import dataclass
from difflib import get_close_matches
from pathlib import Path
from typing import Any

from hil.bus import load
from hil.bus.apps import APP_NAMES, sensor_frames
from hil.io import paths
from hil.scenario.faults import KINDS, BusError, Fault, FrameFault, OutOfRange, SensorFault
from hil.scenario.plant_options import CdrwPlantOptions, LqgOptions, MissilePlantOptions
from hil.scenario.schema import ScenarioError, build, parse_toml
from hil.scenario.sensor_options import SIGNALS, CdrwSensorOptions, MissileSensorOptions
from hil.util.bounded import UnfitFile, read_bounded

#: a scenario file is a few kB; anything above this is not one (/dev/zero)
SCENARIO_MAX_BYTES = 1 << 20


#: the frames the simulator sends for each aircraft, i.e. what a frame fault can act on: its
#: sensor frames (hil.bus.apps), and the rig's lockstep tick and fault events
SENSOR_FRAMES = {app: sensor_frames(app) for app in APP_NAMES}
RIG_FRAMES = ("SIM_TICK", "SIM_EVENT")
#: each aircraft's scenario sections: its [plant] and [sensors] options, its [lqg] (None: none)
SECTIONS: dict[str, tuple[type[CdrwPlantOptions | MissilePlantOptions],
                          type[CdrwSensorOptions | MissileSensorOptions], type[LqgOptions] | None]] = {
    "cdrw": (CdrwPlantOptions, CdrwSensorOptions, None),
    "missile": (MissilePlantOptions, MissileSensorOptions, LqgOptions)}
DEFAULT_DURATION = {"cdrw": 7.0, "missile": 10.0}
#: the applications a scenario flies: the DBC's (hil.bus.apps) that have scenario sections
AIRCRAFT = tuple(app for app in APP_NAMES if app in SECTIONS)
TOP_LEVEL_KEYS = ("name", "description", "aircraft", "duration", "seed",
                  "plant", "sensors", "lqg", "faults")


@dataclass(frozen=True)
class Scenario:
    aircraft: str
    duration: float
    seed: int
    plant: CdrwPlantOptions | MissilePlantOptions
    sensors: CdrwSensorOptions | MissileSensorOptions
    lqg: LqgOptions | None = None
    faults: tuple[Fault, ...] = ()
    name: str = ""
    description: str = ""
    source: str = "<scenario>"

    def active_faults(self, t: float, level: str | None = None) -> tuple[Fault, ...]:
        """Faults active at time t, optionally only one level ('sensor', 'frame', 'bus')."""
        return tuple(f for f in self.faults if f.active(t) and (level is None or f.level == level))

    @property
    def sensor_faults(self) -> tuple[Fault, ...]:
        return tuple(f for f in self.faults if f.level == "sensor")

    @property
    def frame_faults(self) -> tuple[Fault, ...]:
        return tuple(f for f in self.faults if f.level == "frame")

    @property
    def bus_faults(self) -> tuple[Fault, ...]:
        return tuple(f for f in self.faults if f.level == "bus")

    @property
    def wire_faults(self) -> tuple[Fault, ...]:
        """canbus's (`--bus wire` only)."""
        return tuple(f for f in self.faults if f.level == "wire")

    @property
    def signals(self) -> tuple[str, ...]:
        return SIGNALS[self.aircraft]

    def replace(self, **changes: Any) -> Scenario:
        """A copy with some fields changed (seed, duration, faults ...), faults re-checked."""
        new = dataclasses.replace(self, **changes)
        if "faults" in changes:
            new = dataclasses.replace(new, faults=tuple(changes["faults"]))
            for i, f in enumerate(new.faults):
                _check_target(f, new.aircraft, None, f"{new.source}: faults[{i}] ({f.kind})")
        return new


# ---------------------------------------------------------------------------------------------
# faults
# ---------------------------------------------------------------------------------------------
def _target_problem(fault: Fault, aircraft: str,
                    known_frames: Collection[str] | None) -> tuple[str, str] | None:
    """(field, why) when the fault cannot act in a run of this aircraft, else None."""
    if isinstance(fault, SensorFault) and fault.signal not in SIGNALS[aircraft]:
        return "signal", (f"unknown signal {fault.signal!r} for aircraft {aircraft} "
                          f"(signals: {', '.join(SIGNALS[aircraft])})")
    if isinstance(fault, BusError) and fault.frame != "*":  # any frame on the wire: the DBC's
        names = known_frames if known_frames is not None else [m.name for m in load().messages]
        return None if fault.frame in names else ("frame", f"unknown frame {fault.frame!r} (a DBC message or *)")
    if not isinstance(fault, FrameFault) or fault.frame == "*":
        if isinstance(fault, OutOfRange):
            return "frame", "out_of_range needs one frame, not '*'"
        return None
    sent = SENSOR_FRAMES[aircraft] + RIG_FRAMES
    if known_frames is not None and fault.frame not in known_frames:
        return "frame", (f"unknown frame {fault.frame!r} "
                         f"(frames: *, {', '.join(sorted(known_frames))})")
    if fault.frame not in sent:  # a DBC frame, but nobody the rig plays sends it
        return "frame", (f"the simulator does not send {fault.frame} in a {aircraft} run "
                         f"(frames: *, {', '.join(sent)})")
    if isinstance(fault, OutOfRange):  # the DBC names the frame's signals
        signals = [sig.name for sig in load().by_name(fault.frame).data_signals]
        if fault.signal not in signals:
            return "signal", (f"{fault.frame} has no signal {fault.signal!r} "
                              f"(signals: {', '.join(signals)})")
    return None


def _check_target(fault: Fault, aircraft: str, known_frames: Collection[str] | None,
                  where: str) -> None:
    problem = _target_problem(fault, aircraft, known_frames)
    if problem is not None:
        raise ScenarioError(f"{where}: field {problem[0]!r}: {problem[1]}")


def check_fault_start(fault: Fault, duration: float, where: str) -> None:
    """A fault that starts at or after the end of the run would never fly: refused."""
    if fault.start >= duration:
        raise ScenarioError(f"{where}: field 'start': {fault.start} s is not before the end "
                            f"of the run ({duration} s)")


def _kinds_hint(kind: object) -> str:
    """The kind a misspelling was meant to be, or every kind when none is close."""
    close = get_close_matches(kind, list(KINDS), n=1) if isinstance(kind, str) else []
    return f"did you mean {close[0]!r}? `hil faults` lists them" if close else f"kinds: {', '.join(KINDS)}"


def _build_fault(table: Mapping[str, Any], where: str) -> tuple[Fault, str]:
    """The fault of a table (kind and every parameter checked, not yet its target) and
    `where` with its kind, for the errors that follow."""
    if not isinstance(table, Mapping):
        raise ScenarioError(f"{where}: expected a table, got {type(table).__name__}")
    kind = table.get("kind")
    if kind is None:
        raise ScenarioError(f"{where}: missing field 'kind' (kinds: {', '.join(KINDS)})")
    if not isinstance(kind, str) or kind not in KINDS:
        raise ScenarioError(f"{where}: field 'kind': unknown fault kind {kind!r} ({_kinds_hint(kind)})")
    where = f"{where} ({kind})"
    fields = {k: v for k, v in table.items() if k != "kind"}
    return build(KINDS[kind], fields, where), where


def fault_from_table(table: Mapping[str, Any], aircraft: str, where: str,
                     known_frames: Collection[str] | None = None) -> Fault:
    """One fault from a TOML table / parsed fields; `where` names it in errors."""
    fault, where = _build_fault(table, where)
    _check_target(fault, aircraft, known_frames, where)
    return fault


def _scalar(text: str) -> Any:
    """A command-line value: integer (0x.. too), number (inf allowed), true/false, else string."""
    low = text.strip().lower()
    if low in ("true", "false"):
        return low == "true"
    for conv in (lambda s: int(s, 0), float):
        try:
            v = conv(text)
        except ValueError:
            continue
        if isinstance(v, float) and math.isnan(v):
            return text
        return v
    return text.strip()


def _spec_table(text: str, where: str) -> dict[str, Any]:
    """'kind:key=value,key=value,...' as a fault table."""
    kind, sep, body = text.partition(":")
    if not sep:
        raise ScenarioError(f"{where}: expected KIND:key=value,... (kinds: {', '.join(KINDS)})")
    table: dict[str, Any] = {"kind": kind.strip()}
    for item in filter(None, (s.strip() for s in body.split(","))):
        key, eq, value = item.partition("=")
        if not eq or not key.strip():
            raise ScenarioError(f"{where}: expected key=value, got {item!r}")
        if key.strip() in table:
            raise ScenarioError(f"{where}: field {key.strip()!r} given twice")
        table[key.strip()] = _scalar(value)
    return table


def parse_fault_spec(text: str, aircraft: str, known_frames: Collection[str] | None = None,
                     source: str = "command line") -> Fault:
    """Parse 'kind:key=value,key=value,...' (the form Fault.describe() prints)."""
    where = f"{source}: fault {text!r}"
    return fault_from_table(_spec_table(text, where), aircraft, where, known_frames)


def parse_flight_fault(text: str, durations: Mapping[str, float], where: str,
                       known_frames: Collection[str] | None = None) -> tuple[str, Fault]:
    """A fault spec of a flight of one or more aircraft (durations: each one's, s): the
    aircraft it belongs to, decided by its kind and target (signal, frame), and the fault.
    Refused: a fault that acts in none of them (a misspelt signal, another aircraft's frame),
    one that could act in several (frame '*', the rig's frames, a bus fault: name one
    aircraft's frame, or fly it in a case of its own) and one that starts after the end."""
    fault, where = _build_fault(_spec_table(text, where), where)
    problems = {a: _target_problem(fault, a, known_frames) for a in durations}
    owners = [a for a, problem in problems.items() if problem is None]
    if not owners:   # (every aircraft has a problem: the first one's field, each one's why)
        found = [problem for problem in problems.values() if problem is not None]
        whys = "; ".join(dict.fromkeys(why for _, why in found))
        others = [a for a in AIRCRAFT if a not in durations and _target_problem(fault, a, known_frames) is None]
        if others:
            whys = f"a {others[0]} fault, and the flight is {' and '.join(durations)} ({whys})"
        raise ScenarioError(f"{where}: field {found[0][0]!r}: {whys}")
    if len(owners) > 1:
        raise ScenarioError(f"{where}: acts in a {' and a '.join(owners)} run alike: which one "
                            "is meant? name one aircraft's frame, or fly it in a case of its own")
    check_fault_start(fault, durations[owners[0]], where)
    return owners[0], fault


# ---------------------------------------------------------------------------------------------
# scenarios
# ---------------------------------------------------------------------------------------------
def scenario_from_dict(data: Mapping[str, Any], source: str = "<scenario>",
                       known_frames: Collection[str] | None = None) -> Scenario:
    """Validate a parsed TOML document and build the Scenario."""

    for key in data:
        if key not in TOP_LEVEL_KEYS:
            raise ScenarioError(f"{source}: unknown key {key!r} (allowed: {', '.join(TOP_LEVEL_KEYS)})")
    aircraft = data.get("aircraft")
    if aircraft is None:
        raise ScenarioError(f"{source}: missing key 'aircraft' (one of: {', '.join(AIRCRAFT)})")
    if aircraft not in AIRCRAFT:
        raise ScenarioError(f"{source}: key 'aircraft': must be one of {', '.join(AIRCRAFT)}, "
                            f"got {aircraft!r}")
    head = build(_Head, {k: data[k] for k in ("name", "description", "duration", "seed") if k in data},
                 source)
    duration = DEFAULT_DURATION[aircraft] if head.duration is None else head.duration
    plant_options, sensor_options, lqg_options = SECTIONS[aircraft]
    if lqg_options is None and "lqg" in data:
        with_lqg = " or ".join(f'"{a}"' for a, (_, _, lqg_of) in SECTIONS.items() if lqg_of)
        raise ScenarioError(f"{source}: section [lqg] is only for aircraft = {with_lqg}")
    plant = build(plant_options, _table(data, "plant", source), f"{source}: [plant]")
    sensors = build(sensor_options, _table(data, "sensors", source), f"{source}: [sensors]")
    lqg = None
    if lqg_options is not None:
        lqg = build(lqg_options, _table(data, "lqg", source), f"{source}: [lqg]")
        if lqg.period > duration:
            raise ScenarioError(f"{source}: [lqg]: field 'period': {lqg.period} s is longer "
                                f"than the duration {duration} s")
    raw_faults = data.get("faults", [])
    if not isinstance(raw_faults, list):
        raise ScenarioError(f"{source}: key 'faults': expected an array of tables ([[faults]])")
    faults = tuple(fault_from_table(t, aircraft, f"{source}: faults[{i}]", known_frames)
                   for i, t in enumerate(raw_faults))
    for i, f in enumerate(faults):
        check_fault_start(f, duration, f"{source}: faults[{i}] ({f.kind})")
    return Scenario(aircraft=aircraft, duration=duration, seed=head.seed, plant=plant,
                    sensors=sensors, lqg=lqg, faults=faults, name=head.name,
                    description=head.description, source=source)


@dataclass(frozen=True, kw_only=True)
class _Head:
    name: str = ""
    description: str = ""
    duration: float | None = dataclasses.field(default=None, metadata={"gt": 0.0})
    seed: int = dataclasses.field(default=1, metadata={"ge": 0})


def _table(data: Mapping[str, Any], key: str, source: str) -> Mapping[str, Any]:
    t = data.get(key, {})
    if not isinstance(t, Mapping):
        raise ScenarioError(f"{source}: key {key!r}: expected a table ([{key}])")
    return t


def find_scenario(name_or_path: str) -> Path:
    """A shipped scenario's name (its file's stem: `hil run --list-scenarios`), or a path to a
    scenario file; found as a suite is (hil.io.paths.find_shipped: a path always wins)."""
    try:
        return paths.find_shipped(name_or_path, paths.SCENARIOS, "scenario")
    except paths.NotShipped as e:
        raise ScenarioError(str(e)) from None


def load_scenario(path: str | Path, known_frames: Collection[str] | None = None) -> Scenario:
    """Read and validate a scenario file."""
    p = Path(path)
    try:
        text = read_bounded(p, SCENARIO_MAX_BYTES, "scenario file").decode("utf-8")
    except UnfitFile as e:
        raise ScenarioError(str(e)) from None
    except OSError as e:
        raise ScenarioError(f"{p}: cannot read scenario: {e.strerror or e}") from None
    except UnicodeDecodeError as e:
        raise ScenarioError(f"{p}: not UTF-8 text (byte {e.start}: {e.reason})") from None
    return loads_scenario(text, str(p), known_frames)


def loads_scenario(text: str, source: str = "<scenario>",
                   known_frames: Collection[str] | None = None) -> Scenario:
    return scenario_from_dict(parse_toml(text, source), source, known_frames)


def default_scenario_text(aircraft: str) -> str:
    """The embedded default scenario file of an aircraft, as text."""
    if aircraft not in AIRCRAFT:
        raise ScenarioError(f"no default scenario for aircraft {aircraft!r} (one of: {', '.join(AIRCRAFT)})")
    return (paths.SCENARIOS / f"{aircraft}_default.toml").read_text(encoding="utf-8")


def load_default_scenario(aircraft: str, known_frames: Collection[str] | None = None) -> Scenario:
    """The embedded default scenario (no file path needed)."""
    return loads_scenario(default_scenario_text(aircraft), f"<embedded {aircraft}_default.toml>",
                          known_frames)


def with_fault_start(scenario: Scenario, start: float) -> Scenario:
    """Move all faults in time so that the earliest starts at `start` (Table 5 campaigns)."""
    if not scenario.faults:
        return scenario
    if not (math.isfinite(start) and start >= 0.0):
        raise ScenarioError(f"{scenario.source}: fault start must be >= 0, got {start}")
    shift = start - min(f.start for f in scenario.faults)
    return scenario.replace(faults=tuple(dataclasses.replace(f, start=f.start + shift)
                                         for f in scenario.faults))


def with_extra_faults(scenario: Scenario, specs: Iterable[str],
                      known_frames: Collection[str] | None = None) -> Scenario:
    """Add command-line faults (parse_fault_spec strings) to a scenario."""
    extra = tuple(parse_fault_spec(s, scenario.aircraft, known_frames) for s in specs)
    return scenario.replace(faults=scenario.faults + extra)


def is_paper_scenario(sc: Scenario) -> bool:
    """The paper's default CDRW scenario (the embedded one, its seed, its fault): only then
    are the paper's numbers printed beside ours."""
    try:
        ref = load_default_scenario("cdrw", {m.name for m in load().messages})
    except Exception:  # noqa: BLE001 - no default, no paper rows
        return False
    return sc.aircraft == "cdrw" and sc.seed == ref.seed and sc.duration == ref.duration \
        and sc.plant == ref.plant and sc.sensors == ref.sensors \
        and [f.describe() for f in sc.faults] == [f.describe() for f in ref.faults]
