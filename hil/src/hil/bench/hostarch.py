"""The portable host build beside an -DFCC_HOST_ARCH build (scripts/bench.d/hostarch):

    python -m hil.bench.hostarch PORTABLE_BUILD ARCH_BUILD [--rounds 5]

1. the same outputs: lqg_design at four designs and sid_replay on the synthetic flight, byte
   for byte (cmake/host-arch.cmake builds without FMA for that);
2. instructions per fcc step (callgrind on fcc_step_bench, frames in -> frames out) in each;
3. wall time per step of the same, the builds alternated `--rounds` times, medians and ratio,
   with the load average beside them (a shared machine moves the ratio).
"""
from __future__ import annotations

import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from hil.reference.flight import synthetic_flight

DESIGNS = (("--period", "0.1"), ("--period", "0.05", "--bits", "8"),
           ("--period", "0.2", "--delay", "0.05"), ("--period", "0.02"))
SID_ARGS = ((), ("--mls-intercept",))
STEPS = {"cdrw": 350, "missile": 3000}


def _load() -> str:
    return " ".join(f"{x:.1f}" for x in os.getloadavg())


def _out(cmd: list[str], stdin: str | None = None) -> str:
    return subprocess.run(cmd, input=stdin, capture_output=True, text=True, check=True).stdout


def same_outputs(a: Path, b: Path) -> list[str]:
    """The runs whose outputs differ between the bin directories a and b."""
    differ = [" ".join(("lqg_design", *d)) for d in DESIGNS
              if _out([str(a / "lqg_design"), *d]) != _out([str(b / "lqg_design"), *d])]
    csv = synthetic_flight().csv()
    differ += [" ".join(("sid_replay", *s)) for s in SID_ARGS
               if _out([str(a / "sid_replay"), *s], csv) != _out([str(b / "sid_replay"), *s], csv)]
    return differ


def instructions(bin_dir: Path, app: str) -> float:
    """Instructions per step of fcc_step_bench APP inside fcc_bench_measured_step (callgrind)."""
    with tempfile.TemporaryDirectory(prefix="bench-hostarch.") as tmp:
        cg = Path(tmp) / "cg.out"
        subprocess.run(["valgrind", "--tool=callgrind", "--toggle-collect=fcc_bench_measured_step",
                        f"--callgrind-out-file={cg}", str(bin_dir / "fcc_step_bench"), app,
                        str(STEPS[app])], capture_output=True, check=True)
        summary = re.search(r"^summary:\s*(\d+)", cg.read_text(), re.M)
    assert summary is not None, "callgrind wrote no summary"
    return int(summary.group(1)) / STEPS[app]


def wall_us(bin_dir: Path, app: str) -> float:
    line = _out([str(bin_dir / "fcc_step_bench"), app, str(STEPS[app])])
    return float(re.search(r"wall_us_per_step=([\d.]+)", line).group(1))  # type: ignore[union-attr]


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m hil.bench.hostarch", description=__doc__.splitlines()[0])
    p.add_argument("portable", type=Path, help="the portable build (its bin/ is used)")
    p.add_argument("arch", type=Path, help="the -DFCC_HOST_ARCH build")
    p.add_argument("--rounds", type=int, default=5)
    a = p.parse_args(argv)
    pb, ab = a.portable / "bin", a.arch / "bin"
    level = re.search(r"^FCC_HOST_ARCH:\w+=(.*)$", (a.arch / "CMakeCache.txt").read_text(), re.M)
    name = level.group(1) if level and level.group(1) else "?"
    print(f"host build: portable x86-64 ({a.portable}) beside -march={name} ({a.arch})")
    differ = same_outputs(pb, ab)
    print(f"1. outputs (lqg_design x{len(DESIGNS)}, sid_replay x{len(SID_ARGS)}): "
          + ("identical, byte for byte" if not differ else "DIFFER: " + "; ".join(differ)))
    print("2. instructions per fcc step (callgrind, fcc_step_bench, frames in -> out)")
    print(f"   {'app':<9}{'portable':>11}{name:>11}{'ratio':>8}")
    for app in STEPS:
        ip, ia = instructions(pb, app), instructions(ab, app)
        print(f"   {app:<9}{ip:>11.0f}{ia:>11.0f}{ia / ip:>8.3f}")
    print(f"3. wall time per fcc step [us], {a.rounds} rounds alternated, medians; load before {_load()}")
    print(f"   {'app':<9}{'portable':>11}{name:>11}{'ratio':>8}")
    for app in STEPS:
        wp: list[float] = []
        wa: list[float] = []
        for _ in range(a.rounds):
            wp.append(wall_us(pb, app))
            wa.append(wall_us(ab, app))
        mp, ma = statistics.median(wp), statistics.median(wa)
        print(f"   {app:<9}{mp:>11.2f}{ma:>11.2f}{ma / mp:>8.3f}")
    print(f"   load after {_load()}")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
