"""The Cortex-M4F unit-test run in one table: ctest's JUnit XML of scripts/test target-unit read
back, per program its cmocka test cases and its instruction count (the image's last line under
QEMU's -icount shift=0), then the last line `N passed, M failed` (test cases; a program that
died before cmocka's summary counts as one failed case). With --cases CSV, every test case's
instruction count (program,case,instructions) goes there.

    python tests/target/summary.py out/test-results/ctest-build-m4f-test.xml [--cases CSV]
"""

import argparse
import csv
import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

PASSED = re.compile(r"\[  PASSED  \] (\d+) test")
FAILED = re.compile(r"\[  FAILED  \] (\d+) test")
INSTRUCTIONS = re.compile(r"target: (\d+) instructions")
CASE_INSTRUCTIONS = re.compile(r"^\[(?: {7}OK |  FAILED  )\] (\S+)\ntarget: case (\d+) instructions$", re.M)


def main(path: Path, cases_csv: Path | None) -> int:
    passed = failed = 0
    cases: list[tuple[str, str, int]] = []
    print(f"{'program':<24} {'cases':>5} {'failed':>6} {'instructions':>13}")
    for case in ET.parse(path).getroot().iter("testcase"):
        out = "".join(node.text or "" for node in case.iter("system-out"))
        ok = case.get("status") == "run" and case.find("failure") is None
        # a program may run several groups (test_app_node: three), each with its summary
        good = sum(int(n) for n in PASSED.findall(out))
        bad = sum(int(n) for n in FAILED.findall(out)) or (0 if ok else 1)
        count = m.group(1) if (m := INSTRUCTIONS.search(out)) else "-"
        passed, failed = passed + good, failed + bad
        cases += [(case.get("name", "?"), m.group(1), int(m.group(2))) for m in CASE_INSTRUCTIONS.finditer(out)]
        print(f"{case.get('name', '?'):<24} {good + bad:>5} {bad:>6} {count:>13}")
    if cases_csv is not None:
        with cases_csv.open("w", newline="") as f:
            csv.writer(f).writerows([("program", "case", "instructions"), *cases])
    print(f"{passed} passed, {failed} failed")
    return 0 if failed == 0 and passed > 0 else 1


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("junit", type=Path)
    parser.add_argument("--cases", type=Path, help="write every test case's instruction count here (CSV)")
    args = parser.parse_args()
    sys.exit(main(args.junit, args.cases))
