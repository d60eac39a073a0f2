"""Test suites: TOML files of requirements and test cases, validated before anything flies.

    [suite]
    name = "seed1-identification"
    title = "..."

    [[requirement]]
    id = "SID-DET-1"
    text = "The AZKF flags a 0.1 s sensor spike within 2 steps of its start."
    source = "Seed 1, Algorithm 1 (fault detection)"

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
"""
from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from hil.util.bounded import UnfitFile, read_bounded
from hil.verify.attack import ATTACKS
from hil.verify.expr import Expectation, ExpressionError, parse
from hil.verify.fields import FIELDS

SUITES_DIR = Path(__file__).resolve().parent.parent / "suites"
MAX_SUITE_BYTES = 1 << 20
AIRCRAFT = ("cdrw", "missile")
MODES = ("lockstep", "realtime")
CASE_KEYS = {"id", "title", "aircraft", "faults", "default_faults", "seed", "duration",
             "lqg", "mode", "attack", "expect"}


class SuiteError(ValueError):
    """A suite that cannot be run as written (one line: file, item, what is wrong)."""


@dataclass(frozen=True)
class Requirement:
    id: str
    text: str
    source: str


@dataclass(frozen=True)
class Case:
    id: str
    title: str
    aircraft: tuple[str, ...]
    #: (requirement id, expectation), in the suite's order
    expect: tuple[tuple[str, Expectation], ...]
    faults: tuple[str, ...] = ()
    default_faults: bool = True
    seed: int | None = None
    duration: float | None = None
    lqg: dict[str, Any] = field(default_factory=dict)
    mode: str = "lockstep"
    attack: str | None = None

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


def shipped() -> dict[str, Path]:
    """The suites that come with hil, by name."""
    return {p.stem: p for p in sorted(SUITES_DIR.glob("*.toml"))}


def find(name_or_path: str) -> Path:
    """A shipped suite's name, or a path to a suite file."""
    p = Path(name_or_path)
    if p.suffix == ".toml" or p.exists():
        return p
    known = shipped()
    if name_or_path not in known:
        raise SuiteError(f"no suite named {name_or_path!r} (shipped: {', '.join(known)}; or give a .toml path)")
    return known[name_or_path]


def _str_list(where: str, v: Any, key: str) -> tuple[str, ...]:
    if not isinstance(v, list) or not all(isinstance(s, str) for s in v):
        raise SuiteError(f"{where}: {key!r} must be a list of strings")
    return tuple(v)


def _case(where: str, raw: dict[str, Any], req_ids: set[str]) -> Case:
    unknown = set(raw) - CASE_KEYS
    if unknown:
        raise SuiteError(f"{where}: unknown key(s) {', '.join(sorted(unknown))}")
    for key in ("id", "aircraft", "expect"):
        if key not in raw:
            raise SuiteError(f"{where}: {key!r} is required")
    if not isinstance(raw["expect"], dict) or not raw["expect"]:
        raise SuiteError(f"{where}: 'expect' must be a table: requirement id = [expectations]; "
                         "a case without an expectation proves nothing")
    missing = [r for r in raw["expect"] if r not in req_ids]
    if missing:
        raise SuiteError(f"{where}: expect: requirement(s) {', '.join(missing)} not declared in the suite")
    aircraft = _str_list(where, raw["aircraft"], "aircraft")
    if not aircraft or set(aircraft) - set(AIRCRAFT) or len(set(aircraft)) != len(aircraft):
        raise SuiteError(f"{where}: 'aircraft' must name cdrw and/or missile once each")
    mode = raw.get("mode", "lockstep")
    if mode not in MODES:
        raise SuiteError(f"{where}: 'mode' must be one of {', '.join(MODES)}")
    attack = raw.get("attack")
    if attack is not None and attack not in ATTACKS:
        raise SuiteError(f"{where}: unknown attack {attack!r} (known: {', '.join(ATTACKS)})")
    sources = {"node", *aircraft} | ({"attack"} if attack else set())
    expect = []
    for req, texts in raw["expect"].items():
        texts = _str_list(f"{where}: expect.{req}", texts, "expect")
        if not texts:
            raise SuiteError(f"{where}: expect.{req} is empty")
        expect += [(req, _expectation(where, text, sources)) for text in texts]
    lqg = raw.get("lqg", {})
    if not isinstance(lqg, dict) or set(lqg) - {"period", "bits", "closed_loop"}:
        raise SuiteError(f"{where}: 'lqg' takes period, bits, closed_loop")
    return Case(id=str(raw["id"]), title=str(raw.get("title", "")), aircraft=aircraft,
                expect=tuple(expect), faults=_str_list(where, raw.get("faults", []), "faults"),
                default_faults=bool(raw.get("default_faults", True)), seed=raw.get("seed"),
                duration=raw.get("duration"), lqg=dict(lqg), mode=mode, attack=attack)


def _expectation(where: str, text: str, sources: set[str]) -> Expectation:
    """One expectation, parsed, every field documented and available in this case."""
    try:
        exp = parse(text)
    except ExpressionError as e:
        raise SuiteError(f"{where}: expect: {e}") from None
    for name in sorted(exp.fields):
        if name not in FIELDS:
            raise SuiteError(f"{where}: expect {text!r}: unknown field {name!r} (hil verify --fields)")
        if FIELDS[name].source not in sources:
            raise SuiteError(f"{where}: expect {text!r}: field {name!r} needs a {FIELDS[name].source} "
                             f"flight, this case has {', '.join(sorted(sources))}")
    return exp


def load(path: Path) -> Suite:
    """Parse and validate a suite file (bounded read: a suite is a small text file)."""
    try:
        data = read_bounded(path, MAX_SUITE_BYTES, "suite")
    except UnfitFile as e:
        raise SuiteError(str(e)) from None
    except OSError as e:
        raise SuiteError(f"{path}: {e.strerror}") from None
    try:
        raw = tomllib.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, tomllib.TOMLDecodeError) as e:
        raise SuiteError(f"{path}: not a TOML suite: {e}") from None
    head = raw.get("suite", {})
    if "name" not in head:
        raise SuiteError(f"{path}: [suite] needs a name")
    reqs = []
    for i, r in enumerate(raw.get("requirement", [])):
        if not {"id", "text", "source"} <= set(r):
            raise SuiteError(f"{path}: requirement[{i}]: id, text and source are required")
        reqs.append(Requirement(str(r["id"]), str(r["text"]), str(r["source"])))
    ids = [r.id for r in reqs]
    if len(set(ids)) != len(ids):
        raise SuiteError(f"{path}: requirement ids repeat")
    cases = tuple(_case(f"{path}: case[{i}] {c.get('id', '')!s}".rstrip(), c, set(ids))
                  for i, c in enumerate(raw.get("case", [])))
    if not cases:
        raise SuiteError(f"{path}: no [[case]]")
    if len({c.id for c in cases}) != len(cases):
        raise SuiteError(f"{path}: case ids repeat")
    untested = [r.id for r in reqs if not any(r.id in c.requirements for c in cases)]
    if untested:
        raise SuiteError(f"{path}: requirement(s) {', '.join(untested)} verified by no case")
    return Suite(str(head["name"]), str(head.get("title", "")), path, tuple(reqs), cases)
