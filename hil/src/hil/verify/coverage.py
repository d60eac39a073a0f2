"""Structural coverage per requirement (DO-178C Table A-7): which lines of the hand-written
firmware each requirement's cases reach, and the two work lists against the unit tests' coverage
-- lines reached by the unit tests only (each needs a requirement or a rationale) and lines
reached by nothing (dead-code candidates).

fcc built by clang 19 with source-based coverage (`scripts/test coverage` builds it in build-cov/)
writes its profile where $LLVM_PROFILE_FILE says: each case's run directory (profiles_to).  After
the suite, per case: llvm-profdata-19 merge, llvm-cov-19 export in lcov form (the per-line counts
as llvm-cov itself computes them from its regions); per requirement: the union of its cases'
lines.  The unit tests' lines come from build-cov/unit.profdata and its test binaries.
"""
from __future__ import annotations

import os
import shutil
import subprocess
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path, PurePath

from hil.util.errors import HilError

PROFDATA, COV = "llvm-profdata-19", "llvm-cov-19"
PROFILE_ENV = "LLVM_PROFILE_FILE"
#: the hand-written portable firmware (scripts/test: portable_sources), the matrix's columns
PORTABLE = ("app", "bus", "core", "crypto", "linalg", "lqg", "sid", "timesync")
#: a coverage build's binaries carry this section (the counters): fcc is one, or is not
COUNTERS = b"__llvm_prf_cnts"
#: llvm-cov on every case of a suite: a minute is ample on a loaded machine
TOOL_TIMEOUT_S = 120.0

#: file (relative to firmware/, e.g. lqg/fcc_lqg_ctrl.c) -> line -> execution count
Counts = dict[str, dict[int, int]]
#: file -> lines
Lines = dict[str, frozenset[int]]
#: file -> runs of lines (first, last), the form a work list is read in
WorkList = dict[str, list[tuple[int, int]]]


class CoverageError(HilError):
    """Coverage cannot be measured (one line: what is missing, and how to get it)."""


def llvm_tool(name: str) -> str:
    found = shutil.which(name)
    if found is None:
        raise CoverageError(f"{name} not found: --coverage needs LLVM 19's tools (scripts/setup installs them)")
    return found


def check_ready(fcc: Path, unit_dir: Path) -> None:
    """Everything --coverage needs, before anything flies."""
    for name in (PROFDATA, COV):
        llvm_tool(name)
    try:
        built = COUNTERS in fcc.read_bytes()
    except OSError as e:
        raise CoverageError(f"{fcc}: {e.strerror}") from None
    if not built:
        raise CoverageError(f"{fcc} is not a coverage build (scripts/test coverage builds one: --build-dir build-cov)")
    if not (unit_dir / "unit.profdata").is_file():
        raise CoverageError(f"no unit-test coverage in {unit_dir}: run scripts/test coverage first")


@contextmanager
def profiles_to(directory: Path) -> Iterator[None]:
    """Every coverage-built program started meanwhile writes its profile into directory (and
    none into the working directory, llvm's default)."""
    before = os.environ.get(PROFILE_ENV)
    os.environ[PROFILE_ENV] = str(directory / "fcc-%p.profraw")
    try:
        yield
    finally:
        if before is None:
            del os.environ[PROFILE_ENV]
        else:
            os.environ[PROFILE_ENV] = before


def portable_name(path: str) -> str | None:
    """firmware/lqg/fcc_lqg_ctrl.c -> lqg/fcc_lqg_ctrl.c; None outside the hand-written firmware."""
    parts = PurePath(path).parts
    for i in range(len(parts) - 2, 0, -1):
        if parts[i - 1] == "firmware" and parts[i] in PORTABLE and len(parts) == i + 2 and parts[-1].endswith(".c"):
            return f"{parts[i]}/{parts[i + 1]}"
    return None


def parse_lcov(text: str) -> Counts:
    """The per-line counts of an lcov export (SF:, DA:line,count), the hand-written firmware only."""
    counts: Counts = {}
    mine: dict[int, int] | None = None
    for row in text.splitlines():
        if row.startswith("SF:"):
            name = portable_name(row[3:])
            mine = counts.setdefault(name, {}) if name is not None else None
        elif row.startswith("DA:") and mine is not None:
            line, count = row[3:].split(",")[:2]
            mine[int(line)] = mine.get(int(line), 0) + int(count)
        elif row == "end_of_record":
            mine = None
    return counts


def _run(cmd: Sequence[str]) -> str:
    try:
        r = subprocess.run(cmd, capture_output=True, text=True, stdin=subprocess.DEVNULL, timeout=TOOL_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        raise CoverageError(f"{Path(cmd[0]).name} did not finish in {TOOL_TIMEOUT_S:.0f} s") from None
    if r.returncode != 0:
        said = (r.stderr.strip().splitlines() or [f"exit status {r.returncode}"])[-1]
        raise CoverageError(f"{Path(cmd[0]).name}: {said}")
    return r.stdout


def export(profdata: Path, objects: Sequence[Path]) -> Counts:
    objs = [str(objects[0])] + [f"-object={o}" for o in objects[1:]]
    return parse_lcov(_run([llvm_tool(COV), "export", "-format=lcov", "-instr-profile", str(profdata), *objs]))


def case_counts(run_dir: Path, fcc: Path) -> Counts:
    """One case's lines: its fcc profiles (its flights' too) merged, exported."""
    raw = sorted(run_dir.rglob("*.profraw"))
    if not raw:
        raise CoverageError(f"{run_dir.name}: fcc wrote no profile (it did not exit, or is not a coverage build)")
    merged = run_dir / "fcc.profdata"
    _run([llvm_tool(PROFDATA), "merge", "-sparse", "-o", str(merged), *map(str, raw)])
    return export(merged, [fcc])


def unit_counts(unit_dir: Path) -> Counts:
    """The unit tests' lines (scripts/test coverage: unit.profdata and bin/test_*)."""
    tests = sorted((unit_dir / "bin").glob("test_*"))
    if not tests:
        raise CoverageError(f"no unit-test binaries in {unit_dir}/bin: run scripts/test coverage first")
    return export(unit_dir / "unit.profdata", tests)


def reached(counts: Sequence[Counts]) -> Lines:
    """The union of the lines executed at least once."""
    out: dict[str, set[int]] = {}
    for c in counts:
        for name, lines in c.items():
            out.setdefault(name, set()).update(n for n, k in lines.items() if k > 0)
    return {name: frozenset(lines) for name, lines in out.items()}


def ranges(lines: frozenset[int], code: frozenset[int]) -> list[tuple[int, int]]:
    """lines as runs over the file's code lines: a blank or comment line between two does not
    break a run, a line of code outside lines does."""
    runs: list[tuple[int, int]] = []
    start = prev = None
    for n in sorted(code):
        if n in lines:
            start, prev = (n if start is None else start), n
        elif start is not None and prev is not None:
            runs.append((start, prev))
            start = prev = None
    if start is not None and prev is not None:
        runs.append((start, prev))
    return runs


@dataclass(frozen=True)
class Row:
    suite: str
    requirement: str
    lines: Lines


@dataclass(frozen=True)
class Matrix:
    """Requirements x firmware files, and the two work lists."""

    #: the code: every line fcc's coverage mapping counts, per file
    code: Lines
    rows: tuple[Row, ...]
    unit: Lines

    @property
    def files(self) -> list[str]:
        return sorted(self.code)

    def percent(self, row: Row, name: str) -> float:
        code = self.code[name]
        return 100.0 * len(row.lines.get(name, frozenset()) & code) / len(code) if code else 0.0

    def total(self, lines: Lines) -> tuple[int, int]:
        """(lines reached, lines of code) over every file."""
        return (sum(len(lines.get(n, frozenset()) & c) for n, c in self.code.items()),
                sum(len(c) for c in self.code.values()))

    def by_verify(self) -> Lines:
        return {n: frozenset().union(*(r.lines.get(n, frozenset()) for r in self.rows)) for n in self.code}

    def unit_only(self) -> WorkList:
        """Lines the unit tests reach and no requirement's case does."""
        v = self.by_verify()
        return self._work(lambda n: (self.unit.get(n, frozenset()) & self.code[n]) - v.get(n, frozenset()))

    def unreached(self) -> WorkList:
        """Lines nothing reaches: dead-code candidates."""
        v = self.by_verify()
        return self._work(lambda n: self.code[n] - self.unit.get(n, frozenset()) - v.get(n, frozenset()))

    def _work(self, pick: Callable[[str], frozenset[int]]) -> WorkList:
        return {n: rs for n in self.files if (rs := ranges(pick(n), self.code[n]))}


def count_lines(work: WorkList, matrix: Matrix) -> int:
    """How many code lines a work list holds."""
    return sum(sum(1 for n in matrix.code[f] if a <= n <= b) for f, rs in work.items() for a, b in rs)


def summary(matrix: Matrix) -> str:
    """The one line after the traceability matrix."""
    got, of = matrix.total(matrix.by_verify())
    return (f"coverage: the cases reach {got}/{of} lines ({100.0 * got / of if of else 0.0:.1f} %) of the "
            f"hand-written firmware; unit tests only: {count_lines(matrix.unit_only(), matrix)} lines; "
            f"reached by nothing: {count_lines(matrix.unreached(), matrix)} lines")


def work_text(work: WorkList) -> list[str]:
    """`lqg/fcc_lqg_ctrl.c:120-131`, one range a line."""
    return [f"{f}:{a}" + (f"-{b}" if b != a else "") for f, rs in work.items() for a, b in rs]


def measure(cases: Sequence[tuple[str, Sequence[str], Path]], fcc: Path, unit_dir: Path) -> Matrix:
    """The matrix of the cases run (suite, requirements, run directory), against the unit tests."""
    return matrix_of([(suite, reqs, case_counts(run_dir, fcc)) for suite, reqs, run_dir in cases],
                     unit_counts(unit_dir))


def matrix_of(per_case: Sequence[tuple[str, Sequence[str], Counts]], unit: Counts) -> Matrix:
    """Per requirement (in the order the cases name them) the union of its cases' lines; the
    code: every line fcc's exports count."""
    code: dict[str, set[int]] = {}
    for _, _, counts in per_case:
        for name, lines in counts.items():
            code.setdefault(name, set()).update(lines)
    rows = [Row(suite, req, reached([c for s, reqs, c in per_case if s == suite and req in reqs]))
            for suite, req in dict.fromkeys((s, r) for s, reqs, _ in per_case for r in reqs)]
    return Matrix({n: frozenset(lines) for n, lines in code.items()}, tuple(rows), reached([unit]))
