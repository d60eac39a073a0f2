"""Campaigns over any scenario field: ``--vary KEY=V1,V2,...`` (the flights are the product of
every --vary's values) and ``--draw KEY=LAW:A,B`` (a value drawn for each flight from the
campaign's seed).  KEY names a field as a scenario file does: ``seed``, ``duration``, a section's
field (``lqg.period``, ``lqg.bits``, ``plant.q0``, ``sensors.noise_scale``, deeper tables too:
``plant.maneuver.pull_deg``) or a fault's (``faults[0].magnitude``).  Every value is checked by
the validator that reads scenario files (hil.scenario.schema), so a bad key or value is the
same one-line ScenarioError (exit 2) as in a file.
"""
from __future__ import annotations

import dataclasses
import itertools
import re
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from hil.scenario.file import Scenario, check_fault_start, scenario_from_dict
from hil.scenario.schema import ScenarioError, replace_fields

#: the scenario's tables a KEY may name, and its top-level fields a KEY may name
SECTIONS = ("plant", "sensors", "lqg")
TOP_LEVEL = ("duration", "seed")
#: the laws of --draw: uniform over [A, B) (a number), integers over A..B (both included)
LAWS = ("uniform", "integers")
_FAULT = re.compile(r"faults\[(\d+)\]\.(\w+)")
KEY_FORMS = "duration, seed, plant.*, sensors.*, lqg.*, faults[N].*"


@dataclass(frozen=True)
class Vary:
    """--vary KEY=V1,V2,...: the campaign flies every value (with every other --vary's)."""

    key: str
    values: tuple[Any, ...]


@dataclass(frozen=True)
class Draw:
    """--draw KEY=LAW:A,B: each flight's value drawn from the law over [A, B]."""

    key: str
    law: str
    low: float
    high: float

    def describe(self) -> str:
        return f"{self.law}:{self.low:g},{self.high:g}"


def _value(text: str) -> Any:
    """A command-line value as a scenario file would have it: a TOML value (8, 0.05, true,
    inf, "x"), else the bare text as a string ("stationary")."""
    try:
        return tomllib.loads(f"v = {text.strip()}")["v"]
    except tomllib.TOMLDecodeError:
        return text.strip()


def _key_and_body(text: str, option: str) -> tuple[str, str]:
    key, eq, body = text.partition("=")
    if not eq or not key.strip() or not body.strip():
        raise ScenarioError(f"{option} {text!r}: expected KEY=..., KEY one of {KEY_FORMS}")
    return key.strip(), body.strip()


def parse_vary(text: str) -> Vary:
    """--vary KEY=V1,V2,... (values not yet checked against a scenario: check())."""
    key, body = _key_and_body(text, "--vary")
    values = tuple(_value(v) for v in body.split(",") if v.strip())
    if not values:
        raise ScenarioError(f"--vary {text!r}: no value")
    if len(set(map(repr, values))) != len(values):
        raise ScenarioError(f"--vary {text!r}: a value given twice")
    return Vary(key, values)


def parse_draw(text: str) -> Draw:
    """--draw KEY=uniform:A,B or KEY=integers:A,B."""
    key, body = _key_and_body(text, "--draw")
    law, sep, bounds = body.partition(":")
    if not sep or law not in LAWS:
        raise ScenarioError(f"--draw {text!r}: expected KEY=LAW:A,B, LAW one of {', '.join(LAWS)}")
    parts = [_value(b) for b in bounds.split(",")]
    if len(parts) != 2 or not all(isinstance(p, (int, float)) and not isinstance(p, bool) for p in parts):
        raise ScenarioError(f"--draw {text!r}: expected two numbers A,B")
    low, high = float(parts[0]), float(parts[1])
    if not low < high or (law == "integers" and not (low.is_integer() and high.is_integer())):
        raise ScenarioError(f"--draw {text!r}: expected A < B" + (" (whole numbers)" if law == "integers" else ""))
    return Draw(key, law, low, high)


def grid(axes: Sequence[tuple[str, Sequence[Any]]]) -> list[dict[str, Any]]:
    """Every combination of the axes' values, the first axis outermost (the last varies
    fastest): [{key: value, ...}, ...].  No axis: one empty combination.  (`hil sweep`'s
    (T, N) points and a campaign's --vary are this product.)"""
    keys = [k for k, _ in axes]
    if len(set(keys)) != len(keys):
        raise ScenarioError(f"a key varied twice: {', '.join(keys)}")
    return [dict(zip(keys, combo)) for combo in itertools.product(*(v for _, v in axes))]


def draw_values(draws: Sequence[Draw], runs: int, seed: int) -> list[dict[str, Any]]:
    """Each run's drawn values: key i's own stream of the campaign seed, so that adding a
    --draw leaves the others' values as they were; the same for every --vary combination."""
    per_key = []
    for i, d in enumerate(draws):
        rng = np.random.default_rng([int(seed), 0x6472, i])  # "dr"
        if d.law == "uniform":
            per_key.append([float(x) for x in rng.uniform(d.low, d.high, size=runs)])
        else:
            per_key.append([int(x) for x in rng.integers(int(d.low), int(d.high), size=runs, endpoint=True)])
    return [{d.key: per_key[i][r] for i, d in enumerate(draws)} for r in range(runs)]


def _replace_path(obj: Any, path: Sequence[str], value: Any, where: str) -> Any:
    """obj with the field at `path` (nested tables) set to value, checked as a file's."""
    name, rest = path[0], path[1:]
    if not rest:
        return replace_fields(obj, {name: value}, where)
    inner = getattr(obj, name, None)
    if not dataclasses.is_dataclass(inner):
        raise ScenarioError(f"{where}: unknown table {name!r}")
    return dataclasses.replace(obj, **{name: _replace_path(inner, rest, value, f"{where}.{name}")})


def with_fields(sc: Scenario, values: Mapping[str, Any], where: str = "command line") -> Scenario:
    """The scenario with these fields set (KEY: see the module docstring), every value and the
    fields' relations (a period within the flight, faults starting before its end) checked."""
    changes: dict[str, Any] = {}
    faults = list(sc.faults)
    for key, value in values.items():
        at = f"{where}: {key}"
        fault = _FAULT.fullmatch(key)
        path = key.split(".")
        if fault is not None:
            i = int(fault.group(1))
            if i >= len(faults):
                raise ScenarioError(f"{at}: the scenario has {len(faults)} fault(s)")
            faults[i] = replace_fields(faults[i], {fault.group(2): value}, f"{at} (faults[{i}], {faults[i].kind})")
        elif len(path) == 1 and key in TOP_LEVEL:
            # checked by the loader itself, in a file of nothing else (its relations to the
            # sections, which this scenario's may not share with a default one: below)
            changes[key] = getattr(scenario_from_dict({"aircraft": "cdrw", key: value}, at), key)
        elif len(path) > 1 and path[0] in SECTIONS:
            section = changes.get(path[0], getattr(sc, path[0]))
            if section is None:
                raise ScenarioError(f"{at}: a {sc.aircraft} scenario has no [{path[0]}]")
            changes[path[0]] = _replace_path(section, path[1:], value, f"{at}: [{path[0]}]")
        else:
            raise ScenarioError(f"{at}: unknown field {key!r} (fields: {KEY_FORMS})")
    new = dataclasses.replace(sc, **changes).replace(faults=tuple(faults))
    if new.lqg is not None and new.lqg.period > new.duration:
        raise ScenarioError(f"{where}: [lqg]: field 'period': {new.lqg.period} s is longer "
                            f"than the duration {new.duration} s")
    for i, f in enumerate(new.faults):
        check_fault_start(f, new.duration, f"{where}: faults[{i}] ({f.kind})")
    return new


def check(sc: Scenario, varies: Sequence[Vary], draws: Sequence[Draw]) -> None:
    """Every --vary value and both ends of every --draw, each alone on the scenario (the
    combinations are checked as they are flown); a key both varied and drawn is refused."""
    grid([(v.key, v.values) for v in varies] + [(d.key, ()) for d in draws])  # no key twice
    for v in varies:
        for value in v.values:
            with_fields(sc, {v.key: value}, f"--vary {v.key}={value}")
    for d in draws:
        for end in (d.low, d.high):
            value = int(end) if d.law == "integers" else end
            with_fields(sc, {d.key: value}, f"--draw {d.key}={d.describe()}")
