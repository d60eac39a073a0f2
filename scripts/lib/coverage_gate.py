"""coverage_gate -- judge the unit tests' structural coverage of the firmware against its floor.

    python coverage_gate.py PORTABLE.json GENERATED.json [--raise]

PORTABLE.json and GENERATED.json are `llvm-cov export -summary-only` of the hand-written portable
firmware and of the generated bus code (scripts/test coverage writes both).  Prints the figures
per file, the generated code's apart (reported, not gated), checks the reviewed exclusions
(tests/coverage/exclusions.toml: each still names the code it excuses), and compares the
hand-written totals with their floors (tests/coverage/floor.json).  The last line is always
`coverage: lines L % branches B % mcdc M %`.  Exit status 0: no figure below its floor;
1: a figure fell, or an exclusion no longer matches its code; 2: a missing or malformed input.
With --raise the floors are set to today's figures (rounded down to 0.1 %) when they rose.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import tomllib
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FLOOR = ROOT / "tests/coverage/floor.json"
EXCLUSIONS = ROOT / "tests/coverage/exclusions.toml"
MEASURES = ("lines", "branches", "mcdc")
EXCLUSION_KINDS = ("defensive", "hardware-only", "unmeasurable")
EXCLUSION_FIELDS = ("file", "line", "code", "kind", "reason", "reviewed")


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


def read_summary(path: Path) -> tuple[dict[str, dict[str, Figure]], dict[str, Figure]]:
    """Per-file and total figures of one llvm-cov export."""
    try:
        data = json.loads(path.read_text())["data"][0]
        files = {
            str(Path(f["filename"]).resolve().relative_to(ROOT / "firmware")): figures(f["summary"])
            for f in data["files"]
        }
        return files, figures(data["totals"])
    except (OSError, ValueError, KeyError, IndexError) as e:
        raise InputError(f"{path}: not an llvm-cov export summary ({e})") from e


def figures(summary: dict[str, dict[str, int]]) -> dict[str, Figure]:
    return {m: Figure(summary[m]["covered"], summary[m]["count"]) for m in MEASURES}


def print_table(title: str, files: dict[str, dict[str, Figure]], totals: dict[str, Figure]) -> None:
    print(f"{title:32} {'lines':>22} {'branches':>22} {'mcdc':>22}")
    for name in sorted(files):
        print(f"{name:32} " + " ".join(f"{str(files[name][m]):>22}" for m in MEASURES))
    print(f"{'total':32} " + " ".join(f"{str(totals[m]):>22}" for m in MEASURES))


def check_exclusions(path: Path) -> list[str]:
    """Problems of the reviewed exclusions: an entry that no longer names its code is stale."""
    try:
        entries = tomllib.loads(path.read_text()).get("exclusion", [])
    except (OSError, tomllib.TOMLDecodeError) as err:
        raise InputError(f"{path}: {err}") from err
    problems = []
    kinds = dict.fromkeys(EXCLUSION_KINDS, 0)
    for i, e in enumerate(entries, 1):
        missing = [f for f in EXCLUSION_FIELDS if f not in e]
        if missing:
            problems.append(f"exclusion {i}: missing {', '.join(missing)}")
            continue
        if e["kind"] not in kinds:
            problems.append(f"exclusion {i}: kind '{e['kind']}' is none of {', '.join(EXCLUSION_KINDS)}")
            continue
        kinds[e["kind"]] += 1
        source = ROOT / e["file"]
        lines = source.read_text().splitlines() if source.is_file() else []
        if not 0 < e["line"] <= len(lines) or e["code"] not in lines[e["line"] - 1]:
            problems.append(f"exclusion {i}: {e['file']}:{e['line']} no longer reads '{e['code']}': review it again")
    print(f"exclusions (reviewed, not subtracted from the figures): {len(entries)} ("
          + ", ".join(f"{k} {n}" for k, n in kinds.items()) + ")")
    return problems


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
    parser.add_argument("--raise", dest="raise_floor", action="store_true", help="write the risen floors")
    args = parser.parse_args()
    try:
        files, totals = read_summary(args.portable)
        gen_files, gen_totals = read_summary(args.generated)
        print_table("hand-written portable firmware", files, totals)
        print_table("generated (reported, not gated)", gen_files, gen_totals)
        problems = check_exclusions(EXCLUSIONS)
        floor = read_floor(FLOOR)
    except InputError as e:
        print(f"coverage_gate: {e}", file=sys.stderr)
        return 2
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
