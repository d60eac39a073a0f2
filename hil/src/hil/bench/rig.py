"""Rig speed (scripts/bench.d/rig runs this inside scripts/with-vcan): the default 7 s CDRW
flight in lockstep through vcan0 and the real fcc, and the 100-flight campaign.

Targets (issue 7): the flight in <= 1.4 s of wall time (>= 5x real time), the campaign in
< 5 minutes.  "Flight" is the lockstep loop (every tick answered, 351 steps); the set-up
around it (flight pre-computation, candump and fcc start, shutdown, reading the bus log,
summary) is reported beside it, as is the wall time of the whole `hil run cdrw` command.
"""
from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from hil.rig.config import RigConfig
from hil.runs.campaign import run_campaign
from hil.runs.run import run_flight
from hil.scenario.file import load_default_scenario

FLIGHT_TARGET_S = 1.4
CAMPAIGN_TARGET_S = 300.0


def _flight(out: Path) -> tuple[float, float, float]:
    """(lockstep loop wall s, whole run_flight wall s, fcc exec p50 us) of one default flight."""
    t0 = time.perf_counter()
    run_flight([load_default_scenario("cdrw")], RigConfig(out_dir=out, progress=False, plots=False))
    total = time.perf_counter() - t0
    info = json.loads((out / "run_info.json").read_text())
    return info["lockstep_wall_s"], total, info["fcc_exec_us"]["cdrw"]["p50"]


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="hil.bench.rig")
    p.add_argument("--flights", type=int, default=5, help="default flights to time (median)")
    p.add_argument("--campaign-runs", type=int, default=100)
    args = p.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="bench-rig.") as tmp:
        root = Path(tmp)
        loops, totals, execs = [], [], []
        for i in range(args.flights):
            lw, tw, ex = _flight(root / f"f{i}")
            loops.append(lw)
            totals.append(tw)
            execs.append(ex)
        t0 = time.perf_counter()
        r = subprocess.run([sys.executable, "-m", "hil.cli", "run", "cdrw", "--quiet", "--no-plots",
                            "--out", str(root / "cli")], capture_output=True, text=True)
        cli_s = time.perf_counter() - t0
        if r.returncode != 0:
            print(r.stderr, file=sys.stderr)
            return 1
        t0 = time.perf_counter()
        run_campaign(load_default_scenario("cdrw"), args.campaign_runs, 1,
                     RigConfig(out_dir=root / "campaign", progress=False, plots=False))
        camp = time.perf_counter() - t0
        cinfo = json.loads((root / "campaign" / "run_info.json").read_text())
    med = statistics.median(loops)
    steps = 351
    rows = [
        ("default CDRW flight, lockstep loop (median)", f"{med:.3f} s", f"<= {FLIGHT_TARGET_S} s",
         "ok" if med <= FLIGHT_TARGET_S else "MISSED"),
        ("  min / max over runs", f"{min(loops):.3f} / {max(loops):.3f} s", "", ""),
        ("  per step (tick -> 12 outputs -> ACK)", f"{1e3 * med / steps:.2f} ms", "", ""),
        ("  real-time factor (7 s simulated)", f"{7.0 / med:.1f} x", ">= 5 x", ""),
        ("  fcc step execution p50 (its ACK)", f"{statistics.median(execs):.0f} us", "", ""),
        ("  whole run_flight (set-up, log, summary)", f"{statistics.median(totals):.3f} s", "", ""),
        ("  `hil run cdrw` command (interpreter start)", f"{cli_s:.2f} s", "", ""),
        (f"campaign, {args.campaign_runs} flights, one fcc", f"{camp:.1f} s", f"< {CAMPAIGN_TARGET_S:.0f} s",
         "ok" if camp < CAMPAIGN_TARGET_S else "MISSED"),
        ("  lockstep loops only", f"{cinfo['lockstep_wall_s']:.1f} s", "", ""),
        # a campaign's flights share one session (fcc, recorder): the step of a warm session,
        # beside the fresh session's of each default flight above
        ("  per step, one session's flights", f"{1e3 * cinfo['lockstep_wall_s'] / (args.campaign_runs * steps):.2f} ms",
         "", ""),
    ]
    print_table("rig (lockstep through vcan0 and fcc)", rows)
    return 0


def print_table(title: str, rows: list[tuple[str, str, str, str]]) -> None:
    """A bench part's table: (what, measured, target, ok/MISSED) rows under a title."""
    w = max(len(r[0]) for r in rows)
    print(f"{title:<{w}}  {'measured':>16}  {'target':>10}")
    for name, val, target, verdict in rows:
        print(f"{name:<{w}}  {val:>16}  {target:>10}  {verdict}")


if __name__ == "__main__":
    sys.exit(main())
