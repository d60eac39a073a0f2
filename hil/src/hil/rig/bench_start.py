"""Start-up cost of `hil run cdrw` (scripts/bench.d/start): the whole command's wall time
minus its lockstep loop (run_info.json's lockstep_wall_s), without plots and with plots.

Two halves, because with-vcan draws a run's figures on the host after the guest exits:

    python -m hil.rig.bench_start guest --keep DIR     (inside scripts/with-vcan)
        fresh interpreters as a user starts them: `python -c pass`, the imports of `hil run`,
        `hil run cdrw --no-plots` and `hil run cdrw` (figures queued, not drawn), and for the
        ratio `hil run cdrw --no-plots` without with-vcan's hil.offload server (all in the
        guest), alternated round by round; the runs' times go to DIR/start.json, the last run
        with plots stays in DIR/run
    python -m hil.rig.bench_start host DIR             (on the host, after the guest)
        times `hil report --plots-only DIR/run` (the drawing with-vcan does after the guest)
        and prints the table against the budget of issue 14: at most 1.5 s beyond the loop
        without plots, 5 s with plots (beyond the loop in the guest + drawing on the host).

Where the time beyond the loop goes, from run_info.json's wall_s (the flight side: opening
the rig session to the recorder's stop): "session" is wall_s minus the loop (the recorder's and
fcc's start, the listen for another fcc, shutdown); "interpreter, imports, CLI, results, exit"
is the rest (Python's start, the imports, the scenario, the results -- computed on the host by
hil.offload when with-vcan runs its server, the guest waiting for them --, the run directory,
the exit).
"""
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

from ..offload import ENV as OFFLOAD_ENV
from .bench import print_table
from .runs import AFTER_ENV

NO_PLOTS_BUDGET_S = 1.5
PLOTS_BUDGET_S = 5.0
RESULTS = "start.json"


def _timed(argv: list[str], env: dict[str, str] | None = None) -> float:
    t0 = time.perf_counter()
    r = subprocess.run(argv, capture_output=True, text=True, env=env)
    if r.returncode != 0:
        raise SystemExit(f"bench start: {' '.join(argv)} failed: {r.stderr.strip()[-300:]}")
    return time.perf_counter() - t0


def guest(keep: Path, runs: int) -> dict[str, object]:
    """The measurements inside the guest (fresh interpreters), also written to keep/start.json."""
    hil = [sys.executable, "-m", "hil.cli"]
    res: dict[str, object] = {}
    with tempfile.TemporaryDirectory(prefix="bench-start.") as tmp:
        # figures queued in a file of our own (not drawn here, not handed to with-vcan)
        env = {**os.environ, AFTER_ENV: str(Path(tmp) / "after")}
        res["python_pass_s"] = [_timed([sys.executable, "-c", "pass"]) for _ in range(runs)]
        res["imports_s"] = [_timed([sys.executable, "-c", "import hil.cli, hil.rig.flight"])
                            for _ in range(runs)]
        # the server of hil.offload (with-vcan's) does the maths on the host; "guest_only" runs
        # without it, for the side-by-side ratio; the kinds alternate, round by round
        alone = {k: v for k, v in env.items() if k != OFFLOAD_ENV}
        kinds = (("no_plots", ["--no-plots"], env), ("plots", [], env), ("guest_only", ["--no-plots"], alone))
        rows: dict[str, list[dict[str, float]]] = {kind: [] for kind, _, _ in kinds}
        for i in range(runs):
            for kind, extra, kind_env in kinds:
                out = keep / "run" if (kind == "plots" and i == runs - 1) else Path(tmp) / f"{kind}{i}"
                total = _timed([*hil, "run", "cdrw", "--quiet", *extra, "--out", str(out)], kind_env)
                info = json.loads((out / "run_info.json").read_text())
                rows[kind].append({"total_s": total, "loop_s": info["lockstep_wall_s"], "wall_s": info["wall_s"]})
        res.update(rows)
        res["offloaded"] = OFFLOAD_ENV in env
    keep.mkdir(parents=True, exist_ok=True)
    (keep / RESULTS).write_text(json.dumps(res, indent=1))
    return res


def _med(rows: list[dict[str, float]], f) -> float:  # noqa: ANN001 - a row -> seconds
    return statistics.median(f(r) for r in rows)


def report(keep: Path) -> list[tuple[str, str, str, str]]:
    """Time the host's drawing of keep/run; the table rows (median of the runs)."""
    res = json.loads((keep / RESULTS).read_text())
    draw = _timed([sys.executable, "-m", "hil.cli", "report", "--plots-only", str(keep / "run")])
    rows = []
    for kind, label, budget, host in (("no_plots", "no plots", NO_PLOTS_BUDGET_S, 0.0),
                                      ("plots", "with plots", PLOTS_BUDGET_S, draw)):
        runs = res[kind]
        beyond = _med(runs, lambda r: r["total_s"] - r["loop_s"]) + host
        rows.append((f"hil run cdrw, {label}: beyond the loop", f"{beyond:.2f} s", f"<= {budget:g} s",
                     "ok" if beyond <= budget else "MISSED"))
        rows.append(("  whole command / lockstep loop",
                     f"{_med(runs, lambda r: r['total_s']):.2f} / {_med(runs, lambda r: r['loop_s']):.2f} s", "", ""))
        rows.append(("  interpreter, imports, CLI, results, exit",
                     f"{_med(runs, lambda r: r['total_s'] - r['wall_s']):.2f} s", "", ""))
        rows.append(("  session (wall_s - loop)",
                     f"{_med(runs, lambda r: r['wall_s'] - r['loop_s']):.2f} s", "", ""))
        if host:
            rows.append(("  figures drawn on the host after the guest", f"{draw:.2f} s", "", ""))
    if "guest_only" in res:
        alone = res["guest_only"]
        rows.append(("without the host's half (hil.offload): beyond the loop",
                     f"{_med(alone, lambda r: r['total_s'] - r['loop_s']):.2f} s", "", ""))
    rows.append(("the host's half (with-vcan's hil.offload server)",
                 "used" if res.get("offloaded") else "NOT RUNNING", "", ""))
    rows.append(("python -c pass (guest)", f"{statistics.median(res['python_pass_s']):.2f} s", "", ""))
    rows.append(("python -c 'import hil.cli, hil.rig.flight' (guest)",
                 f"{statistics.median(res['imports_s']):.2f} s", "", ""))
    return rows


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="hil.rig.bench_start")
    sub = p.add_subparsers(dest="half", required=True)
    g = sub.add_parser("guest", help="the runs, inside scripts/with-vcan")
    g.add_argument("--keep", type=Path, required=True, help="where the results and the last run go")
    g.add_argument("--runs", type=int, default=3, help="runs of each kind (median)")
    h = sub.add_parser("host", help="the drawing on the host and the table")
    h.add_argument("keep", type=Path)
    args = p.parse_args(argv)
    if args.half == "guest":
        guest(args.keep, args.runs)
        return 0
    print_table(f"start-up of hil run cdrw in the UML guest (median of "
                f"{len(json.loads((args.keep / RESULTS).read_text())['no_plots'])} runs)", report(args.keep))
    return 0


if __name__ == "__main__":
    sys.exit(main())
