"""The scenario library (hil/src/hil/scenarios/*.toml) and `hil faults`: every scenario loads
and validates against the DBC, is documented (name, description, a header that says how to
fly it), and the fault catalogue covers every kind with units and a working example."""
from __future__ import annotations

import dataclasses
import importlib.resources
from pathlib import Path

import pytest

from hil.bus import load
from hil.cli import main
from hil.scenario.faults import KINDS
from hil.scenario.file import find_scenario, load_scenario, parse_fault_spec
from hil.scenario.catalog import EXAMPLES, UNITS

FRAMES = {m.name for m in load().messages}
LIBRARY = sorted(Path(str(importlib.resources.files("hil") / "scenarios")).glob("*.toml"))


def test_library_is_big_enough():
    names = {p.stem for p in LIBRARY}
    assert len(names) >= 6
    assert {"cdrw_default", "missile_default", "cdrw_multi_fault", "cdrw_slow_degradation",
            "cdrw_bus_attack", "missile_realtime_stress", "missile_word_length"} <= names


@pytest.mark.parametrize("path", LIBRARY, ids=lambda p: p.stem)
def test_scenario_loads_and_is_documented(path: Path):
    sc = load_scenario(path, FRAMES)
    assert sc.name == path.stem and sc.description
    assert sc.aircraft == path.stem.split("_")[0]
    header = [ln for ln in path.read_text().splitlines() if ln.startswith("#")]
    assert len(header) >= 3, "explain the scenario in a comment header"
    if path.stem not in ("cdrw_default", "missile_default"):
        assert any("hil run" in ln or "hil sweep" in ln for ln in header), "say how to fly it"
        assert any(ln.split("#", 1)[1].split()[-1:] == [path.stem] or f" {path.stem} " in ln
                   for ln in header), "fly it by its name (hil run --list-scenarios)"
    assert find_scenario(path.stem) == path                  # shipped: found by its name
    for f in sc.faults:
        assert f.start < sc.duration


def test_several_faults_and_levels():
    by = {p.stem: load_scenario(p, FRAMES) for p in LIBRARY}
    assert len(by["cdrw_multi_fault"].faults) >= 3
    assert {f.level for f in by["cdrw_bus_attack"].faults} == {"bus", "frame"}
    assert all(f.duration == float("inf") for f in by["cdrw_slow_degradation"].faults)
    assert by["missile_realtime_stress"].lqg.period == 0.02


def test_every_kind_has_units_and_a_working_example():
    for kind, cls in KINDS.items():
        for f in dataclasses.fields(cls):
            assert f.name in UNITS, f"{kind}.{f.name}: no unit in hil.scenario.catalog.UNITS"
        aircraft, example = EXAMPLES[kind]
        fault = parse_fault_spec(example, aircraft, FRAMES)
        assert fault.kind == kind


def test_hil_faults_lists_every_kind(capsys):
    assert main(["faults"]) == 0
    out = capsys.readouterr().out
    for kind in KINDS:
        assert f"\n{kind}  [" in out
    assert "rate      number   signal unit/s  required" in out       # drift needs a rate
    assert main(["faults", "flood"]) == 0
    one = capsys.readouterr().out
    assert "rate_hz" in one and "default 2000" in one and "spike" not in one
    assert main(["faults", "nope"]) == 2
    assert "no fault kind 'nope'" in capsys.readouterr().err
