"""The Cortex-M4F unit-test run in one table: ctest's JUnit XML of scripts/test target-unit read
back, per program its cmocka test cases and its instruction count (the image's last line under
QEMU's -icount shift=0), then the last line `N passed, M failed` (test cases; a program that
died before cmocka's summary counts as one failed case).

    python tests/target/summary.py out/test-results/ctest-build-m4f-test.xml
"""

import re
import sys
import xml.etree.ElementTree as ET

PASSED = re.compile(r"\[  PASSED  \] (\d+) test")
FAILED = re.compile(r"\[  FAILED  \] (\d+) test")
INSTRUCTIONS = re.compile(r"target: (\d+) instructions")


def main(path: str) -> int:
    passed = failed = 0
    print(f"{'program':<24} {'cases':>5} {'failed':>6} {'instructions':>13}")
    for case in ET.parse(path).getroot().iter("testcase"):
        out = "".join(node.text or "" for node in case.iter("system-out"))
        ok = case.get("status") == "run" and case.find("failure") is None
        good = int(m.group(1)) if (m := PASSED.search(out)) else 0
        bad = int(m.group(1)) if (m := FAILED.search(out)) else (0 if ok else 1)
        count = m.group(1) if (m := INSTRUCTIONS.search(out)) else "-"
        passed, failed = passed + good, failed + bad
        print(f"{case.get('name', '?'):<24} {good + bad:>5} {bad:>6} {count:>13}")
    print(f"{passed} passed, {failed} failed")
    return 0 if failed == 0 and passed > 0 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
