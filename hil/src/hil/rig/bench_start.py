"""Start-up cost of `hil run cdrw` (scripts/bench.d/start runs this inside scripts/with-vcan):
the whole command's wall time minus its lockstep loop (run_info.json's lockstep_wall_s),
without plots and with plots (figures queued for the host by with-vcan; their drawing there is
timed by the bench script after the guest).  Budget (issue 14): at most 1.5 s beyond the loop
without plots, 5 s with.  Each run is a fresh interpreter, as a user starts it."""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from .bench import print_table
from .runs import AFTER_ENV

NO_PLOTS_BUDGET_S = 1.5
PLOTS_BUDGET_S = 5.0


def _timed(argv: list[str], env: dict[str, str] | None = None) -> float:
    t0 = time.perf_counter()
    r = subprocess.run(argv, capture_output=True, text=True, env=env)
    if r.returncode != 0:
        raise SystemExit(f"bench start: {' '.join(argv)} failed: {r.stderr.strip()[-300:]}")
    return time.perf_counter() - t0


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="hil.rig.bench_start")
    p.add_argument("--runs", type=int, default=3, help="runs of each kind (median)")
    p.add_argument("--keep", type=Path, help="leave the last run with plots here (for the host)")
    args = p.parse_args(argv)
    hil = [sys.executable, "-m", "hil.cli"]
    rows = []
    with tempfile.TemporaryDirectory(prefix="bench-start.") as tmp:
        # figures queued in a file of our own (not drawn, not handed to with-vcan)
        env = {**os.environ, AFTER_ENV: str(Path(tmp) / "after")}
        t_pass = statistics.median(_timed([sys.executable, "-c", "pass"]) for _ in range(args.runs))
        t_imp = statistics.median(_timed([sys.executable, "-c", "import hil.cli, hil.rig.runs"])
                                  for _ in range(args.runs))
        for label, extra, budget in (("no plots", ["--no-plots"], NO_PLOTS_BUDGET_S),
                                     ("plots (queued for the host)", [], PLOTS_BUDGET_S)):
            beyond, loops, totals = [], [], []
            for i in range(args.runs):
                out = args.keep if (args.keep and extra == [] and i == args.runs - 1) else Path(tmp) / f"r{i}"
                total = _timed([*hil, "run", "cdrw", "--quiet", *extra, "--out", str(out)], env)
                loop = json.loads((out / "run_info.json").read_text())["lockstep_wall_s"]
                totals.append(total)
                loops.append(loop)
                beyond.append(total - loop)
            med = statistics.median(beyond)
            rows.append((f"hil run cdrw, {label}: beyond the loop (median)", f"{med:.2f} s",
                         f"<= {budget:g} s", "ok" if med <= budget else "MISSED"))
            rows.append(("  whole command / lockstep loop (median)",
                         f"{statistics.median(totals):.2f} / {statistics.median(loops):.2f} s", "", ""))
        rows.append(("python -c pass", f"{t_pass:.2f} s", "", ""))
        rows.append(("python -c 'import hil.cli, hil.rig.runs'", f"{t_imp:.2f} s", "", ""))
    print_table("start-up, inside the guest", rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
