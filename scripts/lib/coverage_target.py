"""coverage_target -- the unit tests' line coverage of the firmware on the Cortex-M4F, and where it
differs from the host's.

    python coverage_target.py BUILD_M4F_COV BUILD_COV [--out DIR]

BUILD_M4F_COV is the test images' build with -DFCC_TARGET_COVERAGE=ON (the portable firmware
compiled by GCC with --coverage -fprofile-info-section; each image writes its .gcda files over
semihosting when it exits, tests/target/target_startup.c).  Runs every test image under QEMU as
`scripts/test target-unit` does, keeps each program's .gcda apart, merges them with
arm-none-eabi-gcov-tool and reads the merged counts with arm-none-eabi-gcov's JSON.  BUILD_COV is
`scripts/test coverage`'s clang build (its unit.profdata and test programs): its per-line counts
are the host's.  Prints per hand-written file the target's line coverage and the lines the two
builds disagree on (a line both compilers count as code, run on one and never on the other),
writes that list to DIR/host-target-lines.csv (default out/coverage-target/).  Exit status 0: every
image passed and the coverage was read; 1: an image failed or wrote no coverage; 2: a missing or
malformed input.
"""

from __future__ import annotations

import argparse
import csv
import gzip
import json
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PORTABLE = ("app", "bus", "core", "crypto", "linalg", "lqg", "sid", "timesync")
QEMU = ["qemu-system-arm", "-machine", "mps2-an386", "-cpu", "cortex-m4", "-nographic", "-monitor", "none",
        "-semihosting-config", "enable=on,target=native", "-icount", "shift=0", "-kernel"]


class InputError(Exception):
    """A missing or malformed input: exit status 2."""


@dataclass(frozen=True)
class Disagreement:
    file: str
    line: int
    host: int
    target: int


def run_images(build: Path, profiles: Path) -> list[str]:
    """Each image under QEMU, its .gcda files moved to profiles/<image>; the images that failed."""
    images = sorted(build.glob("bin/test_*.elf"))
    if not images:
        raise InputError(f"{build}: no test images (bin/test_*.elf)")
    failed = []
    for image in images:
        for stale in build.rglob("*.gcda"):
            stale.unlink()
        run = subprocess.run([*QEMU, str(image)], cwd=ROOT, capture_output=True, text=True, timeout=600)
        written = list(build.rglob("*.gcda"))
        if run.returncode != 0 or not written:
            failed.append(f"{image.stem}: exit status {run.returncode}, {len(written)} .gcda files")
        for gcda in written:
            dest = profiles / image.stem / gcda.relative_to(build)
            dest.parent.mkdir(parents=True, exist_ok=True)
            shutil.move(gcda, dest)
    return failed


def merge(profiles: Path, build: Path) -> None:
    """All images' counts summed into the build directory, next to the .gcno files."""
    merged = profiles / "_merged"
    runs = [d for d in sorted(profiles.iterdir()) if d.is_dir() and d != merged]
    shutil.copytree(runs[0], merged)
    for d in runs[1:]:
        subprocess.run(["arm-none-eabi-gcov-tool", "merge", str(d), str(merged), "-o", str(merged)],
                       check=True, capture_output=True)
        for gcda in d.rglob("*.gcda"):  # gcov-tool merges the objects both have; the others join
            dest = merged / gcda.relative_to(d)
            if not dest.exists():
                dest.parent.mkdir(parents=True, exist_ok=True)
                shutil.copy(gcda, dest)
    shutil.copytree(merged, build, dirs_exist_ok=True)


def target_lines(build: Path) -> dict[str, dict[int, int]]:
    """Per hand-written file (relative to firmware/), gcov's count of each line it counts as code."""
    lines: dict[str, dict[int, int]] = {}
    for gcda in sorted(build.rglob("*.gcda")):
        out = subprocess.run(["arm-none-eabi-gcov", "--json-format", "--stdout", "--object-directory",
                              str(gcda.parent), str(gcda)], cwd=build, capture_output=True, check=True)
        for doc in out.stdout.decode().splitlines():
            for f in json.loads(doc)["files"]:
                name = portable_name(f["file"])
                if name is not None:
                    per = lines.setdefault(name, {})
                    for ln in f["lines"]:
                        per[ln["line_number"]] = per.get(ln["line_number"], 0) + ln["count"]
    return lines


def host_lines(build_cov: Path) -> dict[str, dict[int, int]]:
    """The clang build's count of each line (llvm-cov's lcov export of the unit tests' profile)."""
    objects = sorted(build_cov.glob("bin/test_*"))
    profile = build_cov / "unit.profdata"
    if not objects or not profile.is_file():
        raise InputError(f"{build_cov}: no unit.profdata or test programs (run scripts/test coverage)")
    cmd = ["llvm-cov-19", "export", "-format=lcov", "-instr-profile", str(profile), str(objects[0]),
           *(f"-object={o}" for o in objects[1:])]
    text = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    lines: dict[str, dict[int, int]] = {}
    per: dict[int, int] = {}
    for row in text.splitlines():
        if row.startswith("SF:"):
            name = portable_name(row[3:])
            per = lines.setdefault(name, {}) if name is not None else {}
        elif row.startswith("DA:"):
            number, count = row[3:].split(",")[:2]
            per[int(number)] = per.get(int(number), 0) + int(count)
    return lines


def portable_name(path: str) -> str | None:
    """firmware/DIR/F.c relative to firmware/ when DIR is portable (not generated code), else None."""
    try:
        rel = Path(path).resolve().relative_to(ROOT / "firmware")
    except ValueError:
        return None
    return str(rel) if rel.parts[0] in PORTABLE and len(rel.parts) == 2 and rel.suffix == ".c" else None


def compare(host: dict[str, dict[int, int]], target: dict[str, dict[int, int]]) -> list[Disagreement]:
    """The lines both count as code, run on one build and never on the other."""
    out = []
    for name in sorted(host.keys() & target.keys()):
        for line in sorted(host[name].keys() & target[name].keys()):
            h, t = host[name][line], target[name][line]
            if (h > 0) != (t > 0):
                out.append(Disagreement(name, line, h, t))
    return out


def report(target: dict[str, dict[int, int]], diffs: list[Disagreement], out: Path) -> None:
    print(f"{'target (gcov, Cortex-M4F)':32} {'lines':>20} {'host only':>10} {'target only':>12}")
    total = [0, 0]
    for name in sorted(target):
        counts = target[name]
        run = sum(1 for c in counts.values() if c > 0)
        total[0] += run
        total[1] += len(counts)
        host_only = sum(1 for d in diffs if d.file == name and d.target == 0)
        target_only = sum(1 for d in diffs if d.file == name and d.host == 0)
        pct = 100.0 * run / len(counts) if counts else 100.0
        print(f"{name:32} {f'{pct:5.1f} % ({run}/{len(counts)})':>20} {host_only:>10} {target_only:>12}")
    out.mkdir(parents=True, exist_ok=True)
    with (out / "host-target-lines.csv").open("w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["file", "line", "host_count", "target_count", "source"])
        for d in diffs:
            source = (ROOT / "firmware" / d.file).read_text().splitlines()[d.line - 1].strip()
            writer.writerow([d.file, d.line, d.host, d.target, source])
    pct = 100.0 * total[0] / total[1] if total[1] else 100.0
    print(f"coverage-target: lines {pct:.1f} % ({total[0]}/{total[1]}); host and target disagree on "
          f"{len(diffs)} lines ({sum(1 for d in diffs if d.target == 0)} run on the host only): "
          f"{out / 'host-target-lines.csv'}")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build", type=Path)
    parser.add_argument("build_cov", type=Path)
    parser.add_argument("--out", type=Path, default=ROOT / "out/coverage-target")
    args = parser.parse_args()
    build = args.build.resolve()
    try:
        with tempfile.TemporaryDirectory() as tmp:
            failed = run_images(build, Path(tmp))
            merge(Path(tmp), build)
        target = target_lines(build)
        host = host_lines(args.build_cov)
    except (InputError, OSError, subprocess.CalledProcessError, ValueError, KeyError, gzip.BadGzipFile) as e:
        print(f"coverage_target: {e}", file=sys.stderr)
        return 2
    report(target, compare(host, target), args.out)
    for name in sorted(host.keys() - target.keys()):
        print(f"coverage-target: {name} is measured on the host only (no image writes its counts)")
    for f in failed:
        print(f"coverage-target: {f}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
