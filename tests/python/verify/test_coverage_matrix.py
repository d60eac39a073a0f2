"""`hil verify --coverage`: the lines each requirement's cases reach and the two DO-178C work
lists.  On the host: the merge logic on small synthetic llvm-cov exports (lcov form, as
llvm-cov-19 export -format=lcov writes them) and the refusals before anything flies; on the
bus: one case of seed2-autopilot against fcc's coverage build (scripts/test coverage's build-cov)."""
from __future__ import annotations

import html
import re
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from rig_helpers import cli

from hil.verify.coverage import matrix_of, parse_lcov, portable_name, ranges, summary, work_text

ROOT = Path(__file__).resolve().parents[3]
BUILD_COV = ROOT / "build-cov"


def lcov(*files: tuple[str, dict[int, int]]) -> str:
    """An lcov export as llvm-cov writes it: SF, FN/BRDA rows the parser skips, DA per line."""
    out = []
    for name, lines in files:
        out += [f"SF:{name}", "FN:3,f", "FNDA:1,f", "BRDA:5,0,0,1"]
        out += [f"DA:{n},{k}" for n, k in lines.items()]
        out += [f"LF:{len(lines)}", "end_of_record"]
    return "\n".join(out) + "\n"


LQG = "/src/firmware/lqg/fcc_lqg_ctrl.c"
BUS = "/src/firmware/bus/fcc_bus.c"
#: the same code in three exports: two cases and the unit tests
CASE_A = lcov((LQG, {10: 3, 11: 3, 12: 0, 20: 0, 21: 0}), (BUS, {5: 1, 6: 0}))
CASE_B = lcov((LQG, {10: 1, 11: 0, 12: 2, 20: 0, 21: 0}), (BUS, {5: 0, 6: 0}))
UNIT = lcov((LQG, {10: 1, 11: 1, 12: 1, 20: 1, 21: 0}), (BUS, {5: 1, 6: 0}), ("/src/tests/c/test_x.c", {1: 1}))


def test_only_the_hand_written_firmwares_c_files_count():
    assert portable_name("/w/firmware/lqg/fcc_lqg_ctrl.c") == "lqg/fcc_lqg_ctrl.c"
    assert portable_name("/w/firmware/bus/generated/fcc_bus_gen.c") is None      # generated: reported apart
    assert portable_name("/w/firmware/port/linux/fcc_main.c") is None            # the port, not the core
    assert portable_name("/w/firmware/linalg/fcc_mat.h") is None                 # as scripts/test coverage
    assert portable_name("/w/tests/c/test_lqg.c") is None
    assert parse_lcov(UNIT) == {"lqg/fcc_lqg_ctrl.c": {10: 1, 11: 1, 12: 1, 20: 1, 21: 0},
                                "bus/fcc_bus.c": {5: 1, 6: 0}}


def test_a_run_spans_blank_and_comment_lines_but_not_code_outside_it():
    code = frozenset({3, 4, 7, 9, 10, 15})
    assert ranges(frozenset({3, 4, 7, 10, 15}), code) == [(3, 7), (10, 15)]
    assert ranges(frozenset(), code) == []


def test_a_requirement_reaches_the_union_of_its_cases_lines_and_the_work_lists_follow():
    m = matrix_of([("s", ["R-1", "R-2"], parse_lcov(CASE_A)), ("s", ["R-2"], parse_lcov(CASE_B))], parse_lcov(UNIT))
    r1, r2 = m.rows
    assert (r1.requirement, r2.requirement) == ("R-1", "R-2")
    assert r1.lines["lqg/fcc_lqg_ctrl.c"] == {10, 11} and r2.lines["lqg/fcc_lqg_ctrl.c"] == {10, 11, 12}
    assert m.percent(r1, "lqg/fcc_lqg_ctrl.c") == pytest.approx(40.0)
    assert m.percent(r2, "lqg/fcc_lqg_ctrl.c") == pytest.approx(60.0)
    assert m.percent(r2, "bus/fcc_bus.c") == pytest.approx(50.0)
    assert m.total(r2.lines) == (4, 7)
    # line 20: the unit tests only; 21 and the bus's 6: nothing; the test's own file is not code
    assert m.unit_only() == {"lqg/fcc_lqg_ctrl.c": [(20, 20)]}
    assert work_text(m.unreached()) == ["bus/fcc_bus.c:6", "lqg/fcc_lqg_ctrl.c:21"]
    assert summary(m).endswith("(57.1 %) of the hand-written firmware; unit tests only: 1 lines; "
                               "reached by nothing: 2 lines")


def test_coverage_needs_a_coverage_build_and_the_host(tmp_path, capsys):
    plain = tmp_path / "fcc"
    plain.write_bytes(b"#!/bin/sh\nexit 0\n")
    plain.chmod(0o755)
    rc, out, err = cli(capsys, "verify", "seed2-autopilot", "--coverage", "--fcc", str(plain),
                       "--out", str(tmp_path / "r"))
    assert rc == 2 and "is not a coverage build" in err and len(err.strip().splitlines()) == 1, err
    assert not (tmp_path / "r").exists()
    rc, _, err = cli(capsys, "verify", "seed2-autopilot", "--coverage", "--target", "qemu-m4f",
                     "--out", str(tmp_path / "r"))
    assert rc == 2 and "--coverage needs --target host" in err


# ---- on the bus -----------------------------------------------------------------------------------
CODE_RANGE = re.compile(r"^(app|bus|core|crypto|linalg|lqg|sid|timesync)/(\w+\.c):(\d+)(?:-(\d+))?$")


def matrix_cell(page: str, requirement: str, file: str) -> float:
    """The % in the report's matrix for one requirement and one file."""
    section = page[page.index("Coverage per requirement"):]
    head = re.findall(r"<th>([^<]*)</th>", section.split("</tr>")[0])
    row = next(r for r in section.split("</tr>") if f"/ {requirement}</td>" in r)
    cells = re.findall(r"<td>([^<]*)</td>", row)
    return float(cells[head.index(html.escape(file))])


@pytest.mark.vcan
def test_a_suite_with_coverage_reports_the_matrix_and_real_work_lists(tmp_path):
    assert (BUILD_COV / "unit.profdata").is_file(), "scripts/test vcan runs scripts/test coverage first"
    p = subprocess.run([sys.executable, "-m", "hil.cli", "verify", "seed2-autopilot", "--case", "default-T0.1-8bit",
                        "--coverage", "--build-dir", str(BUILD_COV), "--no-plots", "--force",
                        "--out", str(tmp_path / "report"), "--junit", str(tmp_path / "j.xml")],
                       capture_output=True, text=True, timeout=900, cwd=ROOT, check=False)
    assert p.returncode == 0, p.stdout + p.stderr
    assert re.search(r"^coverage: the cases reach \d+/\d+ lines", p.stdout, re.MULTILINE), p.stdout
    page = (tmp_path / "report" / "index.html").read_text(encoding="utf-8")
    assert "<h2>Coverage per requirement</h2>" in page
    assert matrix_cell(page, "LQG-CL-1", "lqg/fcc_lqg_ctrl.c") > 20.0      # the LQG's control law ran
    assert matrix_cell(page, "LQG-CL-1", "sid/fcc_zkf.c") < 20.0           # the missile has no identifier
    props = {q.get("name"): q.get("value") for q in ET.parse(tmp_path / "j.xml").getroot().iter("property")}
    assert re.fullmatch(r"[1-9]\d*/\d+ lines", props["coverage LQG-CL-1"]), props
    for name in ("unit-only", "unreached"):
        listed = (tmp_path / "report" / "coverage" / f"{name}.txt").read_text().splitlines()
        assert listed and int(props[f"coverage {name} lines"]) >= len(listed)
        for entry in listed:
            m = CODE_RANGE.match(entry)
            assert m, entry
            length = len((ROOT / "firmware" / m[1] / m[2]).read_text().splitlines())
            assert 1 <= int(m[3]) <= int(m[4] or m[3]) <= length, entry
