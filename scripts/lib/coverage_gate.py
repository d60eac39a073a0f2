"""coverage_gate -- judge the unit tests' structural coverage of the firmware against its floor.

    python coverage_gate.py PORTABLE.json GENERATED.json [--sources FILE...] [--raise]

PORTABLE.json is `llvm-cov export` of the hand-written portable firmware (with its MC/DC records),
GENERATED.json `llvm-cov export -summary-only` of the generated bus code (scripts/test coverage
writes both); --sources names the hand-written files that must be measured (a file no unit test
links is missing from the export, not at 0 %).  Prints the figures per file, the generated code's
apart (reported, not gated), holds every MC/DC condition the tests leave uncovered against the
reviewed exclusions (tests/coverage/exclusions.toml; a source that only a test-only build links is
listed there as [[unmeasured]], with its reason), and compares the hand-written totals with
their floors (tests/coverage/floor.json).  The last line is always
`coverage: lines L % branches B % mcdc M %`.  Exit status 0: no figure below its floor, every
uncovered condition excluded; 1: a figure fell, a condition is neither covered nor excluded, an
exclusion is stale (its code changed, or its conditions are covered now), or a source is not
measured and not listed as unmeasured (or listed and measured now); 2: a missing or malformed
input.  With --raise the floors are set to today's figures (rounded down to 0.1 %) when they rose.
"""

from __future__ import annotations

import argparse
import json
import math
import re
import sys
import tomllib
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FLOOR = ROOT / "tests/coverage/floor.json"
EXCLUSIONS = ROOT / "tests/coverage/exclusions.toml"
MEASURES = ("lines", "branches", "mcdc")
EXCLUSION_KINDS = ("defensive", "hardware-only")
EXCLUSION_FIELDS = ("file", "line", "code", "conditions", "kind", "reason", "reviewed")
UNMEASURED_FIELDS = ("file", "reason", "reviewed")


class InputError(Exception):
    """A missing or malformed input file: exit status 2."""


@dataclass(frozen=True)
class Figure:
    covered: int
    count: int

    @property
    def percent(self) -> float:
        return 100.0 * self.covered / self.count if self.count else 100.0

    def __str__(self) -> str:
        return f"{self.percent:5.1f} % ({self.covered}/{self.count})"


@dataclass(frozen=True)
class Decision:
    """One MC/DC decision of a source file: where it begins, its conditions, those not covered
    (numbered C1..Cn as `llvm-cov show` prints them)."""
    file: str
    line: int
    column: int
    conditions: int
    uncovered: frozenset[int]


@dataclass(frozen=True)
class Export:
    files: dict[str, dict[str, Figure]]
    totals: dict[str, Figure]
    decisions: list[Decision]


def read_export(path: Path) -> Export:
    """Per-file and total figures of one llvm-cov export, and its MC/DC decisions when it has them."""
    try:
        data = json.loads(path.read_text())["data"][0]
        files = {name_of(f): figures(f["summary"]) for f in data["files"]}
        decisions = [d for f in data["files"] for d in decisions_of(f)]
        return Export(files, figures(data["totals"]), decisions)
    except (OSError, ValueError, KeyError, IndexError, TypeError) as e:
        raise InputError(f"{path}: not an llvm-cov export ({e})") from e


def name_of(file: dict) -> str:
    return str(Path(file["filename"]).resolve().relative_to(ROOT / "firmware"))


def decisions_of(file: dict) -> list[Decision]:
    """The file's decisions, one per place: a function compiled twice (the double and the float
    matrix kernels) has a record per copy, and a condition covered in either is covered (as
    llvm-cov's summary merges them)."""
    covered: dict[tuple[int, int], list[bool]] = {}
    for line, column, _end_line, _end_column, _expansion, _kind, conds in file.get("mcdc_records", []):
        seen = covered.setdefault((line, column), [False] * len(conds))
        covered[(line, column)] = [a or b for a, b in zip(seen, conds)]
    name = "firmware/" + name_of(file)
    return [Decision(name, line, column, len(conds), frozenset(i for i, c in enumerate(conds, 1) if not c))
            for (line, column), conds in sorted(covered.items())]


def figures(summary: dict[str, dict[str, int]]) -> dict[str, Figure]:
    return {m: Figure(summary[m]["covered"], summary[m]["count"]) for m in MEASURES}


def print_table(title: str, files: dict[str, dict[str, Figure]], totals: dict[str, Figure]) -> None:
    print(f"{title:32} {'lines':>22} {'branches':>22} {'mcdc':>22}")
    for name in sorted(files):
        print(f"{name:32} " + " ".join(f"{str(files[name][m]):>22}" for m in MEASURES))
    print(f"{'total':32} " + " ".join(f"{str(totals[m]):>22}" for m in MEASURES))


def read_exclusions(path: Path, table: str = "exclusion") -> list[dict]:
    """The [[table]] entries of the exclusions file (exclusion: conditions; unmeasured: sources)."""
    try:
        entries = tomllib.loads(path.read_text()).get(table, [])
    except (OSError, tomllib.TOMLDecodeError) as err:
        raise InputError(f"{path}: {err}") from err
    if not isinstance(entries, list) or not all(isinstance(e, dict) for e in entries):
        raise InputError(f"{path}: [[{table}]] is not a list of tables")
    return entries


def check_exclusions(entries: list[dict], decisions: list[Decision]) -> list[str]:
    """Every uncovered condition excluded, every exclusion still true: it names the code on its
    line, a decision begins there, and each condition it lists is still uncovered."""
    problems = []
    excused: set[tuple[str, int, int]] = set()
    kinds = dict.fromkeys(EXCLUSION_KINDS, 0)
    at: dict[tuple[str, int], list[Decision]] = {}
    for d in decisions:
        at.setdefault((d.file, d.line), []).append(d)
    for i, e in enumerate(entries, 1):
        missing = [f for f in EXCLUSION_FIELDS if f not in e]
        if missing:
            problems.append(f"exclusion {i}: missing {', '.join(missing)}")
            continue
        if e["kind"] not in kinds:
            problems.append(f"exclusion {i}: kind '{e['kind']}' is none of {', '.join(EXCLUSION_KINDS)}")
            continue
        kinds[e["kind"]] += 1
        place = f"{e['file']}:{e['line']}"
        source = ROOT / e["file"]
        lines = source.read_text().splitlines() if source.is_file() else []
        if not 0 < e["line"] <= len(lines) or e["code"] not in lines[e["line"] - 1]:
            problems.append(f"exclusion {i}: {place} no longer reads '{e['code']}': review it again")
            continue
        found = [d for d in at.get((e["file"], e["line"]), []) if e.get("column", d.column) == d.column]
        if len(found) != 1:
            problems.append(f"exclusion {i}: {place}: " + ("no MC/DC decision begins here: stale" if not found
                            else "more than one decision begins here: name its column"))
            continue
        for c in e["conditions"]:
            if c not in found[0].uncovered:
                problems.append(f"exclusion {i}: {place} C{c} is covered now (or no condition of its "
                                f"{found[0].conditions}): remove it from the entry")
            excused.add((e["file"], e["line"], c))
    uncovered = [(d, c) for d in decisions for c in sorted(d.uncovered)]
    neither = [(d, c) for d, c in uncovered if (d.file, d.line, c) not in excused]
    for d, c in neither:
        problems.append(f"{d.file}:{d.line}:{d.column} condition C{c} of {d.conditions} is neither "
                        "covered nor excluded: test it, or list it with its reason in tests/coverage/exclusions.toml")
    print(f"MC/DC conditions not covered: {len(uncovered)}, excluded by a reviewed entry "
          f"{len(uncovered) - len(neither)}, neither {len(neither)}; exclusions: {len(entries)} ("
          + ", ".join(f"{k} {n}" for k, n in kinds.items()) + ")")
    return problems


def unmeasured(sources: list[Path], files: dict[str, dict[str, Figure]],
               allowed: Sequence[dict] = ()) -> list[str]:
    """The hand-written sources with code of their own that no unit test links: llvm-cov leaves
    them out, not at 0 %.  A source of #includes alone (fcc_mat64_*.c: the double flavour of a
    kernel) is measured as the file it includes.  A source listed as [[unmeasured]] (only a
    test-only build links it) may be missing; its entry is stale once it is measured, or gone."""
    names = {str(s.resolve().relative_to(ROOT / "firmware")) for s in sources if has_code(s)}
    problems, listed = [], set()
    for i, e in enumerate(allowed, 1):
        missing = [f for f in UNMEASURED_FIELDS if f not in e]
        name = str(e.get("file", "")).removeprefix("firmware/")
        if missing:
            problems.append(f"unmeasured {i}: missing {', '.join(missing)}")
        elif name not in names:
            problems.append(f"unmeasured {i}: firmware/{name} is no portable source with code: remove the entry")
        elif name in files:
            problems.append(f"unmeasured {i}: firmware/{name} is measured now: remove the entry")
        else:
            listed.add(name)
    problems += [f"firmware/{n} is not measured: no unit test links it"
                 for n in sorted(names - files.keys() - listed)]
    return problems


def has_code(source: Path) -> bool:
    text = re.sub(r"/\*.*?\*/|//[^\n]*", "", source.read_text(), flags=re.S)
    return any(line.strip() and not line.lstrip().startswith("#") for line in text.splitlines())


def read_floor(path: Path) -> dict[str, float]:
    try:
        floor = json.loads(path.read_text())
        return {m: float(floor[m]) for m in MEASURES}
    except (OSError, ValueError, KeyError, TypeError) as e:
        raise InputError(f"{path}: not a coverage floor ({e})") from e


def write_floor(path: Path, floor: dict[str, float]) -> None:
    about = ("Coverage floors of the hand-written portable firmware under the unit tests (percent): "
             "scripts/test coverage fails below them; raise them with "
             "`python scripts/lib/coverage_gate.py build-cov/portable.json build-cov/generated.json --raise`.")
    path.write_text(json.dumps({"_about": about, **floor}, indent=2) + "\n")


def compare(totals: dict[str, Figure], floor: dict[str, float]) -> tuple[list[str], dict[str, float]]:
    """The figures below their floor, and the floors today's figures allow (rounded down to 0.1 %)."""
    fell, allowed = [], {}
    for m in MEASURES:
        now = totals[m].percent
        allowed[m] = max(floor[m], math.floor(now * 10.0) / 10.0)
        if now < floor[m]:
            fell.append(f"{m} {now:.2f} % below its floor {floor[m]:.1f} %")
    return fell, allowed


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("portable", type=Path)
    parser.add_argument("generated", type=Path)
    parser.add_argument("--sources", type=Path, nargs="*", default=[], help="the files that must be measured")
    parser.add_argument("--raise", dest="raise_floor", action="store_true", help="write the risen floors")
    args = parser.parse_args()
    try:
        portable = read_export(args.portable)
        generated = read_export(args.generated)
        print_table("hand-written portable firmware", portable.files, portable.totals)
        print_table("generated (reported, not gated)", generated.files, generated.totals)
        # without --sources nothing is held to be measured (the floors' --raise alone)
        problems = (unmeasured(args.sources, portable.files, read_exclusions(EXCLUSIONS, "unmeasured"))
                    if args.sources else [])
        problems += check_exclusions(read_exclusions(EXCLUSIONS), portable.decisions)
        floor = read_floor(FLOOR)
    except InputError as e:
        print(f"coverage_gate: {e}", file=sys.stderr)
        return 2
    totals = portable.totals
    fell, allowed = compare(totals, floor)
    problems += fell
    rose = {m: v for m, v in allowed.items() if v > floor[m]}
    if rose and args.raise_floor and not fell:
        write_floor(FLOOR, allowed)
        print(f"floors raised in {FLOOR.relative_to(ROOT)}: " + ", ".join(f"{m} {v:.1f} %" for m, v in rose.items()))
    elif rose:
        raisable = ", ".join(f"{m} {floor[m]:.1f} -> {v:.1f} %" for m, v in rose.items())
        print(f"floors can be raised (--raise): {raisable}")
    for p in problems:
        print(f"coverage: {p}")
    print("coverage: " + " ".join(f"{m} {totals[m].percent:.1f} %" for m in MEASURES))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
