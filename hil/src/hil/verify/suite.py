"""Test suites: TOML files of requirements and test cases, validated before anything flies.

    [suite]
    name = "seed1-identification"
    title = "..."

    [[requirement]]
    id = "SID-DET-1"
    text = "The AZKF flags a 0.1 s sensor spike within 2 steps of its start."
    source = "Seed 1, Algorithm 1 (fault detection)"
    # timing = "schedule" or "sync": a realtime timing requirement, judged against the run's
    # platform: a failure the platform explains is inconclusive, not the firmware's (hil.verify.platform)

    [[case]]
    id = "spike-detected"
    aircraft = ["cdrw"]                       # cdrw, missile or both, flown in one fcc
    faults = ["spike:signal=alpha,start=4,duration=0.1,magnitude=0.15"]   # added to the scenario's
    default_faults = true                     # false: the scenario's own faults are left out
    seed = 1                                  # optional
    duration = 7.0                            # optional, s
    lqg = { period = 0.1, bits = 8 }          # optional, missile
    mode = "lockstep"                         # or "realtime"
    attack = "forged-control"                 # optional: hil.verify.attack.ATTACKS
    [case.expect]                             # per requirement: the case verifies these
    SID-DET-1 = ["detector.latency_steps <= 2", "detector.false_alarm_steps == 0"]
    NODE-RT-1 = ["overruns == 0"]
    SID-BND-2 = [{ signal = "cdrw.azkf_alpha_lo <= cdrw.alpha_true <= cdrw.azkf_alpha_hi",
                   window = { event = "fault[0].end", length_s = 1.0 }, measure = "settling_time",
                   band = [1, 1], expect = "value <= 0.1" }]   # hil.verify.window

A case with ``flights = N`` (2 to 1000) flies N flights, seeds seed, seed + 1, ...; each of its
expectations is then over all of them, with its confidence interval (hil.verify.statistical):
    SID-STAT-1 = [
      { share = "azkf.alpha.error_integral_truth < kf.alpha.error_integral_truth", expect = "lo >= 0.9" }]

Every value is checked when the suite is loaded, before anything flies, by the validator of
scenario files (hil.scenario.schema): a case's flight is each aircraft's embedded scenario with
the case's seed, duration, lqg and faults, built by hil.scenario.file as a scenario file is;
each fault goes to the aircraft its signal or frame belongs to (one of neither, or of both in
a case flying both, is refused).  An error is one line naming the file, the case and the field.
"""
from __future__ import annotations

import re
import tomllib
from collections.abc import Collection, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from hil.bus import load as load_dbc
from hil.apps.missile import check_missile
from hil.io import paths
from hil.runs.budget import check_memory
from hil.scenario.file import AIRCRAFT, Scenario, default_scenario_text, parse_flight_fault, scenario_from_dict
from hil.scenario.schema import ScenarioError, build, check_keys, field_names, parse_toml, spec
from hil.util.bounded import UnfitFile, read_bounded
from hil.util.errors import HilError
from hil.verify.attack import ATTACKS
from hil.verify.expr import Expectation, ExpressionError, parse
from hil.verify.fields import FIELDS
from hil.verify.platform import KINDS
from hil.verify.statistical import MAX_FLIGHTS, OverFlights, StatisticalError
from hil.verify.statistical import build as build_over_flights
from hil.verify.window import VALUE, Windowed, WindowError, check

MAX_SUITE_BYTES = 1 << 20
MODES = ("lockstep", "realtime")
#: a case's values that are its scenario's: checked as a scenario file's are (hil.scenario.file)
FLIGHT_KEYS = ("seed", "duration", "lqg")
#: what an id may be
ID = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]{0,63}")


class SuiteError(HilError, ValueError):
    """A suite that cannot be run as written (one line: file, item, field, what is wrong)."""


@dataclass(frozen=True, kw_only=True)
class _Head:
    """[suite]"""

    name: str = spec()
    title: str = spec("")


def _check_id(value: str) -> None:
    """A case's id names its run directory (cases/ID), a requirement's the report's anchors."""
    if not ID.fullmatch(value):
        raise ValueError(f"field 'id': letters, digits and . _ - (not first), got {value!r}")


@dataclass(frozen=True)
class Requirement:
    id: str
    text: str
    source: str
    #: a realtime timing requirement, judged against the run's platform: "schedule" or "sync",
    #: the evidence that excuses its failure (hil.verify.platform); "" : not a timing requirement
    timing: str = ""

    def __post_init__(self) -> None:
        _check_id(self.id)
        if self.timing and self.timing not in KINDS:
            raise ValueError(f"field 'timing': {' or '.join(map(repr, KINDS))}, got {self.timing!r}")


@dataclass(frozen=True, kw_only=True)
class _CaseFields:
    """A [[case]]'s own fields (besides FLIGHT_KEYS and expect)."""

    id: str = spec()
    title: str = spec("")
    aircraft: tuple[str, ...] = spec(choices=AIRCRAFT)
    faults: tuple[str, ...] = spec(default_factory=tuple)
    default_faults: bool = spec(True)
    mode: str = spec("lockstep", choices=MODES)
    attack: str | None = spec(None, choices=tuple(ATTACKS))
    flights: int = spec(1, ge=1, le=MAX_FLIGHTS)

    def __post_init__(self) -> None:
        _check_id(self.id)
        if self.flights > 1 and self.attack is not None:
            raise ValueError("field 'flights': a case with an attack flies one flight")
        if not self.aircraft or len(set(self.aircraft)) != len(self.aircraft):
            raise ValueError(f"field 'aircraft': name {' and/or '.join(AIRCRAFT)}, once each")


CASE_KEYS = (*field_names(_CaseFields), *FLIGHT_KEYS, "expect")


@dataclass(frozen=True)
class Case:
    id: str
    title: str
    aircraft: tuple[str, ...]
    #: (requirement id, expectation), in the suite's order
    expect: tuple[tuple[str, Expectation | Windowed | OverFlights], ...]
    #: what flies: each aircraft's scenario, its faults among them, checked when loaded
    flights: tuple[Scenario, ...]
    mode: str = "lockstep"
    attack: str | None = None
    #: flights flown (seed, seed + 1, ...): more than one, every expectation is over them all
    n_flights: int = 1

    @property
    def requirements(self) -> tuple[str, ...]:
        return tuple(dict.fromkeys(req for req, _ in self.expect))


@dataclass(frozen=True)
class Suite:
    name: str
    title: str
    path: Path
    requirements: tuple[Requirement, ...]
    cases: tuple[Case, ...]

    @property
    def timing(self) -> dict[str, str]:
        """The timing requirements and their kinds (hil.verify.platform)."""
        return {r.id: r.timing for r in self.requirements if r.timing}


def shipped() -> dict[str, Path]:
    """The suites that come with hil, by name."""
    return paths.shipped(paths.SUITES)


def find(name_or_path: str) -> Path:
    """A shipped suite's name, or a path to a suite file (hil.io.paths.find_shipped)."""
    try:
        return paths.find_shipped(name_or_path, paths.SUITES, "suite")
    except paths.NotShipped as e:
        raise SuiteError(str(e)) from None


def _flights(case: _CaseFields, raw: Mapping[str, Any], where: str,
             frames: Collection[str]) -> tuple[Scenario, ...]:
    """Each aircraft's embedded scenario with the case's seed, duration, lqg and faults, checked
    by the scenario files' validator (the same messages) and as the rig checks a flight.  A
    fault goes to the aircraft its kind and target say; one of neither is refused."""
    scenarios = {}
    for aircraft in case.aircraft:
        data = tomllib.loads(default_scenario_text(aircraft))
        data.update({k: raw[k] for k in ("seed", "duration") if k in raw})
        if "lqg" in raw and (aircraft == "missile" or "missile" not in case.aircraft):
            lqg = raw["lqg"]   # (a cdrw-only case's lqg: refused by the validator, as in a file)
            data["lqg"] = {**data.get("lqg", {}), **lqg} if isinstance(lqg, Mapping) else lqg
        if not case.default_faults:
            data["faults"] = []
        scenarios[aircraft] = scenario_from_dict(data, where, frames)
    durations = {a: sc.duration for a, sc in scenarios.items()}
    for i, text in enumerate(case.faults):
        shown = repr(text) if len(text) <= 80 else f"{text[:80]!r}..."
        aircraft, fault = parse_flight_fault(text, durations, f"{where}: faults[{i}] {shown}", frames)
        scenarios[aircraft] = scenarios[aircraft].replace(faults=scenarios[aircraft].faults + (fault,))
    for sc in scenarios.values():
        if sc.aircraft == "missile":
            check_missile(sc)
    check_memory(list(scenarios.values()))
    return tuple(scenarios.values())


def _expect(where: str, raw: Any, req_ids: set[str], sources: set[str],
            flights: tuple[Scenario, ...], n_flights: int = 1
            ) -> tuple[tuple[str, Expectation | Windowed | OverFlights], ...]:
    if not isinstance(raw, Mapping) or not raw:
        raise SuiteError(f"{where}: field 'expect': a table, requirement id = [expectations]; "
                         "a case without an expectation proves nothing")
    missing = [r for r in raw if r not in req_ids]
    if missing:
        raise SuiteError(f"{where}: field 'expect': requirement(s) {', '.join(missing)} not declared "
                         "in the suite")
    expect: list[tuple[str, Expectation | Windowed | OverFlights]] = []
    for req, items in raw.items():
        if not isinstance(items, list) or not items or \
                not all(isinstance(t, (str, Mapping)) for t in items):
            raise SuiteError(f"{where}: field 'expect.{req}': expected an array of expectations "
                             "(strings, or tables of a windowed check)")
        for i, item in enumerate(items):
            at = f"{where}: field 'expect.{req}'"
            over = isinstance(item, Mapping) and ("share" in item or "percentile" in item)
            if over != (n_flights > 1):
                raise SuiteError(f"{at}[{i}]: " + (
                    "an expectation over flights ('share', 'percentile') needs a case of flights >= 2"
                    if over else f"a case of {n_flights} flights judges expectations over them: "
                                 "'share' or 'percentile' tables (hil.verify.statistical)"))
            if over:
                expect.append((req, _over_flights(f"{at}[{i}]", item, sources)))
            else:
                expect.append((req, _expectation(at, item, sources) if isinstance(item, str)
                               else _windowed(f"{at}[{i}]", item, sources, flights)))
    return tuple(expect)


def _over_flights(where: str, raw: Mapping[str, Any], sources: set[str]) -> OverFlights:
    try:
        return build_over_flights(raw, where, lambda at, text, extra: _expectation(at, text, sources, extra))
    except StatisticalError as e:
        raise SuiteError(str(e)) from None


def _windowed(where: str, raw: Mapping[str, Any], sources: set[str], flights: tuple[Scenario, ...]) -> Windowed:
    """A windowed check (hil.verify.window) and its expectation over `value`."""
    faults = [f for sc in flights for f in sc.faults]
    try:
        c, text = check(raw, faults, [sc.aircraft for sc in flights], min(sc.duration for sc in flights), where)
    except WindowError as e:
        raise SuiteError(str(e)) from None
    exp = _expectation(f"{where}: field 'expect'", text, sources, {VALUE})
    if VALUE not in exp.fields:
        raise SuiteError(f"{where}: field 'expect': {text!r} does not name {VALUE!r}, the measured value")
    return Windowed(c, exp)


def _expectation(where: str, text: str, sources: set[str], extra: Collection[str] = ()) -> Expectation:
    """One expectation, parsed, every field documented and available in this case (or one of
    the extra names)."""
    try:
        exp = parse(text)
    except ExpressionError as e:
        raise SuiteError(f"{where}: {e}") from None
    for name in sorted(exp.fields - set(extra)):
        if name not in FIELDS:
            raise SuiteError(f"{where}: {text!r}: unknown field {name!r} (hil verify --fields)")
        if FIELDS[name].source not in sources:
            raise SuiteError(f"{where}: {text!r}: field {name!r} needs a {FIELDS[name].source} "
                             f"flight, this case has {', '.join(sorted(sources))}")
    return exp


def _realtime(case: _CaseFields) -> set[str]:
    """A realtime flight's sources: its sync, and its timing if it flies the missile."""
    if case.mode != "realtime":
        return set()
    return {"sync", "realtime"} if "missile" in case.aircraft else {"sync"}


def _case(where: str, raw: Mapping[str, Any], req_ids: set[str], frames: Collection[str]) -> Case:
    check_keys(raw, CASE_KEYS, where)
    own = build(_CaseFields, {k: v for k, v in raw.items() if k in field_names(_CaseFields)}, where)
    flights = _flights(own, raw, where, frames)
    if "expect" not in raw:
        raise SuiteError(f"{where}: missing field 'expect'")
    sources = {"node", *own.aircraft} | ({"attack"} if own.attack else set()) | _realtime(own)
    return Case(id=own.id, title=own.title, aircraft=own.aircraft,
                expect=_expect(where, raw["expect"], req_ids, sources, flights, own.flights), flights=flights,
                mode=own.mode, attack=own.attack, n_flights=own.flights)


def _tables(raw: Mapping[str, Any], key: str, where: str) -> list[Mapping[str, Any]]:
    """The [[key]] array of tables."""
    items = raw.get(key, [])
    if not isinstance(items, list) or not all(isinstance(t, Mapping) for t in items):
        raise SuiteError(f"{where}: key {key!r}: expected an array of tables ([[{key}]])")
    return items


def _read(path: Path) -> dict[str, Any]:
    """The suite file's TOML (bounded read: a suite is a small text file)."""
    try:
        data = read_bounded(path, MAX_SUITE_BYTES, "suite")
    except UnfitFile as e:
        raise SuiteError(str(e)) from None
    except OSError as e:
        raise SuiteError(f"{path}: {e.strerror or e}") from None
    try:
        return parse_toml(data.decode("utf-8"), str(path))
    except UnicodeDecodeError as e:
        raise SuiteError(f"{path}: not UTF-8 text (byte {e.start}: {e.reason})") from None
    except ScenarioError as e:
        raise SuiteError(str(e)) from None


def load(path: Path) -> Suite:
    """Parse and validate a suite file: every value, every case's flight, every expectation,
    before anything flies (SuiteError: one line naming the file, the case and the field)."""
    raw = _read(path)
    try:
        return _suite(path, raw)
    except ScenarioError as e:
        raise SuiteError(str(e)) from None


def _suite(path: Path, raw: Mapping[str, Any]) -> Suite:
    check_keys(raw, ("suite", "requirement", "case"), str(path))
    head_table = raw.get("suite", {})
    if not isinstance(head_table, Mapping):
        raise SuiteError(f"{path}: key 'suite': expected a table ([suite])")
    head = build(_Head, head_table, f"{path}: [suite]")
    reqs = tuple(build(Requirement, r, f"{path}: requirement[{i}]")
                 for i, r in enumerate(_tables(raw, "requirement", str(path))))
    ids = [r.id for r in reqs]
    if len(set(ids)) != len(ids):
        raise SuiteError(f"{path}: requirement ids repeat")
    frames = {m.name for m in load_dbc().messages}
    cases = tuple(_case(f"{path}: case[{i}] {c.get('id', '')!s}".rstrip(), c, set(ids), frames)
                  for i, c in enumerate(_tables(raw, "case", str(path))))
    if not cases:
        raise SuiteError(f"{path}: no [[case]]")
    if len({c.id for c in cases}) != len(cases):
        raise SuiteError(f"{path}: case ids repeat")
    untested = [r.id for r in reqs if not any(r.id in c.requirements for c in cases)]
    if untested:
        raise SuiteError(f"{path}: requirement(s) {', '.join(untested)} verified by no case")
    return Suite(head.name, head.title, path, reqs, cases)
