"""Host double, host float and Cortex-M4F float compared value by value (tests/target/numeric_probe.c).

Runs build/bin/numeric_probe, build-float/bin/numeric_probe and build-m4f-test/bin/numeric_probe.elf
(under QEMU) and prints, per group of values, the largest difference between the host float build
and the target, and between the host double build and the target, each absolute and relative to
the group's largest magnitude: a markdown table (docs/certification.md shows it).

    python tests/target/compare_numeric.py
"""

import subprocess
import sys
from collections import defaultdict

QEMU = ["qemu-system-arm", "-machine", "mps2-an386", "-cpu", "cortex-m4", "-nographic", "-monitor", "none",
        "-semihosting-config", "enable=on,target=native", "-kernel"]
Values = dict[str, dict[int, float]]


def run(command: list[str]) -> Values:
    try:
        done = subprocess.run(command, capture_output=True, text=True, check=False)
    except OSError as e:
        sys.exit(f"compare_numeric: cannot run {command[0]}: {e.strerror} (build it: docs/certification.md)")
    if done.returncode != 0:
        sys.exit(f"compare_numeric: {' '.join(command)} failed (status {done.returncode}): {done.stderr.strip()}")
    values: Values = defaultdict(dict)
    for line in done.stdout.splitlines():
        fields = line.split()
        if len(fields) == 3 and not line.startswith("target:"):
            values[fields[0]][int(fields[1])] = float(fields[2])
    return values


def largest_difference(a: dict[int, float], b: dict[int, float]) -> tuple[float, float]:
    """Largest |a - b| and the same over the largest |b| of the group."""
    if a.keys() != b.keys():
        sys.exit("compare_numeric: the builds printed different values")
    diff = max(abs(a[i] - b[i]) for i in b)
    scale = max(abs(v) for v in b.values())
    return diff, diff / scale if scale > 0 else diff


def main() -> int:
    double = run(["build/bin/numeric_probe"])
    single = run(["build-float/bin/numeric_probe"])
    target = run(QEMU + ["build-m4f-test/bin/numeric_probe.elf"])
    print("| values | n | host float − target: abs | rel | host double − target: abs | rel |")
    print("|---|---|---|---|---|---|")
    for group in target:
        f_abs, f_rel = largest_difference(single[group], target[group])
        d_abs, d_rel = largest_difference(double[group], target[group])
        print(f"| `{group}` | {len(target[group])} | {f_abs:.3g} | {f_rel:.3g} | {d_abs:.3g} | {d_rel:.3g} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
