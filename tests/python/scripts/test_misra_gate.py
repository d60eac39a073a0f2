"""scripts/lib/misra_gate.py's deviation check: a Required finding without a deviation record fails,
a Mandatory one always fails, records are written per rule and file and keep their reviewer."""

import importlib.util
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[3]
_spec = importlib.util.spec_from_file_location("misra_gate", REPO / "scripts/lib/misra_gate.py")
assert _spec is not None and _spec.loader is not None
gate = importlib.util.module_from_spec(_spec)
sys.modules["misra_gate"] = gate  # dataclasses look their module up there
_spec.loader.exec_module(gate)

PERMIT = "\n".join(f'{field} = "x"' for field in gate.PERMIT_FIELDS)


def deviations(tmp_path: Path, records: str) -> Path:
    path = tmp_path / "deviations.toml"
    path.write_text(f'[permits."10.4"]\n{PERMIT}\n\n[disapplied]\n"15.5" = "early returns"\n\n'
                    f"{gate.RECORDS_MARK}\n{records}")
    return path


def test_a_required_finding_needs_a_record(tmp_path: Path) -> None:
    dev = gate.read_deviations(deviations(tmp_path, '[records."10.4"]\n"a.c" = { findings = 2, reviewer = "R" }\n'))
    missing, over = gate.check_deviations({("10.4", "a.c"): 2, ("15.5", "a.c"): 9}, dev)
    assert (missing, over) == ([], [])
    missing, _ = gate.check_deviations({("10.4", "a.c"): 3, ("10.4", "b.c"): 1, ("17.7", "a.c"): 1}, dev)
    assert missing == ["rule 10.4 (Required) in a.c: 3 findings, 2 under deviation records",
                       "rule 10.4 (Required) in b.c: 1 findings, 0 under deviation records",
                       "rule 17.7 (Required) in a.c: 1 findings, 0 under deviation records and no permit for the rule"]
    _, over = gate.check_deviations({("10.4", "a.c"): 1}, dev)
    assert over == ["rule 10.4 in a.c: 2 recorded, 1 found"]


def test_a_mandatory_finding_admits_no_deviation(tmp_path: Path) -> None:
    dev = gate.read_deviations(deviations(tmp_path, ""))
    missing, _ = gate.check_deviations({("17.3", "a.c"): 1}, dev)
    assert missing == ["rule 17.3 (Mandatory) in a.c: 1 findings; a Mandatory rule admits no deviation"]


def test_records_are_rewritten_below_the_mark_keeping_reviewers(tmp_path: Path) -> None:
    path = deviations(tmp_path, '[records."10.4"]\n"a.c" = { findings = 5, reviewer = "R" }\n')
    gate.write_records(path, {("10.4", "a.c"): 3, ("10.4", "b.c"): 1, ("12.1", "a.c"): 7}, gate.read_deviations(path))
    dev = gate.read_deviations(path)
    assert dev.records == {("10.4", "a.c"): (3, "R"), ("10.4", "b.c"): (1, gate.PENDING)}
    assert dev.disapplied == {"15.5": "early returns"}


@pytest.mark.parametrize("records", ['[records."17.7"]\n"a.c" = { findings = 1, reviewer = "R" }\n',
                                     '[records."10.4"]\n"a.c" = { findings = 1 }\n'])
def test_a_record_without_permit_or_reviewer_is_refused(tmp_path: Path, records: str) -> None:
    with pytest.raises(gate.InputError):
        gate.read_deviations(deviations(tmp_path, records))
