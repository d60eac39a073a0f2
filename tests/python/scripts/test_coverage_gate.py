"""scripts/lib/coverage_gate.py's hold on the uncovered MC/DC conditions: each is covered or excluded
by a reviewed entry, an entry goes stale when its code moves or its condition is covered, a source no
unit test links is reported (unless listed as linked by a test-only build alone, an entry that goes
stale once the source is measured), and a function compiled twice counts a condition covered in either."""

import importlib.util
import sys
from pathlib import Path
from typing import Any

import pytest

REPO = Path(__file__).resolve().parents[3]
_spec = importlib.util.spec_from_file_location("coverage_gate", REPO / "scripts/lib/coverage_gate.py")
assert _spec is not None and _spec.loader is not None
gate = importlib.util.module_from_spec(_spec)
sys.modules["coverage_gate"] = gate  # dataclasses look their module up there
_spec.loader.exec_module(gate)

CODE = "    if (a == NULL || b == NULL || n == 0u) {"


@pytest.fixture
def root(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    (tmp_path / "firmware").mkdir()
    (tmp_path / "firmware/x.c").write_text("int f(void);\n" + CODE + "\n")
    monkeypatch.setattr(gate, "ROOT", tmp_path)
    return tmp_path


def entry(conditions: list[int], line: int = 2, code: str = "a == NULL || b == NULL") -> dict:
    return {"file": "firmware/x.c", "line": line, "code": code, "conditions": conditions,
            "kind": "defensive", "reason": "r", "reviewed": "d"}


def decision(uncovered: set[int]) -> Any:
    return gate.Decision("firmware/x.c", 2, 9, 3, frozenset(uncovered))


def test_every_uncovered_condition_is_excluded_or_reported(root: Path) -> None:
    assert gate.check_exclusions([entry([1, 2])], [decision({1, 2})]) == []
    problems = gate.check_exclusions([entry([1])], [decision({1, 3})])
    assert problems == ["firmware/x.c:2:9 condition C3 of 3 is neither covered nor excluded: test it, "
                        "or list it with its reason in tests/coverage/exclusions.toml"]


def test_an_exclusion_goes_stale(root: Path) -> None:
    covered_now = gate.check_exclusions([entry([1, 2])], [decision({1})])
    assert covered_now == ["exclusion 1: firmware/x.c:2 C2 is covered now (or no condition of its 3): "
                           "remove it from the entry"]
    moved = gate.check_exclusions([entry([1], line=1)], [decision({1})])
    assert moved[0] == "exclusion 1: firmware/x.c:1 no longer reads 'a == NULL || b == NULL': review it again"
    gone = gate.check_exclusions([entry([1])], [])
    assert gone == ["exclusion 1: firmware/x.c:2: no MC/DC decision begins here: stale"]
    incomplete = {k: v for k, v in entry([1]).items() if k != "conditions"}
    assert gate.check_exclusions([incomplete], [decision(set())]) == ["exclusion 1: missing conditions"]


def test_a_condition_covered_in_either_copy_is_covered(root: Path) -> None:
    record = [2, 9, 2, 40, 0, 5]
    export = {"filename": str(root / "firmware/x.c"),
              "mcdc_records": [record + [[True, False, False]], record + [[False, True, False]]]}
    assert gate.decisions_of(export) == [decision({3})]


def test_a_source_no_test_links_is_not_measured(root: Path) -> None:
    (root / "firmware/flavour.c").write_text("/* the double flavour */\n#define F64 1\n#include \"x.c\"\n")
    sources = [root / "firmware/x.c", root / "firmware/flavour.c"]
    assert gate.unmeasured(sources, {}) == ["firmware/x.c is not measured: no unit test links it"]
    assert gate.unmeasured(sources, {"x.c": {}}) == []


def test_a_source_only_a_test_build_links_is_listed_with_its_reason(root: Path) -> None:
    sources = [root / "firmware/x.c"]
    listed = [{"file": "firmware/x.c", "reason": "test-only application", "reviewed": "d"}]
    assert gate.unmeasured(sources, {}, listed) == []
    assert gate.unmeasured(sources, {"x.c": {}}, listed) == [
        "unmeasured 1: firmware/x.c is measured now: remove the entry"]
    gone = [{**listed[0], "file": "firmware/y.c"}]
    assert gate.unmeasured(sources, {}, gone) == [
        "unmeasured 1: firmware/y.c is no portable source with code: remove the entry",
        "firmware/x.c is not measured: no unit test links it"]
    assert gate.unmeasured(sources, {}, [{"file": "firmware/x.c"}]) == [
        "unmeasured 1: missing reason, reviewed", "firmware/x.c is not measured: no unit test links it"]
