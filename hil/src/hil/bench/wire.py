"""The wire-time bus's cost in lockstep (scripts/bench.d/wire runs this inside
scripts/with-vcan): the default CDRW and missile flights through vcan0 and the real fcc, each
on the ideal bus and on the wire-time bus in simulated time (hil.rig.lockstep_wire) one after
the other, alternating, so that both see the same machine.

Target (issue 35): a lockstep step with the wire model at most 1.5x the ideal bus's.  The
figure is the lockstep loop's wall time per step (run_info.json lockstep_wall_s /
lockstep_steps), median over the flights: everything the model costs is in it (an open-loop
flight's last exchanges go to the model before the loop ends).  The model's own share
(wire_model_s) beside it is an estimate: hil.rig.lockstep_wire reads the clock (a system call
in the guest) on one exchange in SAMPLE and on each batch of an open-loop flight, and takes the
clock read's own cost off; what the wire costs outside the model (the kernel handing fcc's
outputs to the side socket, the runner's bookkeeping) is in the step's figure only.
"""
from __future__ import annotations

import argparse
import json
import statistics
import sys
import tempfile
from pathlib import Path

from hil.bench.rig import print_table
from hil.rig.config import RigConfig
from hil.runs.run import run_flight
from hil.scenario.file import load_default_scenario

TARGET_RATIO = 1.5
BITRATE = 500_000


def _step_ms(out: Path, aircraft: str, bus: str) -> tuple[float, float]:
    """(lockstep wall ms per step, the wire model's ms per step) of one default flight."""
    run_flight([load_default_scenario(aircraft)],
               RigConfig(out_dir=out, progress=False, plots=False, bus=bus, bitrate=BITRATE))
    info = json.loads((out / "run_info.json").read_text())
    steps = info["lockstep_steps"]
    return 1e3 * info["lockstep_wall_s"] / steps, 1e3 * info.get("wire_model_s", 0.0) / steps


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="hil.bench.wire")
    p.add_argument("--flights", type=int, default=5, help="flights of each kind to time (median)")
    args = p.parse_args(argv)
    rows: list[tuple[str, str, str, str]] = []
    with tempfile.TemporaryDirectory(prefix="bench-wire.") as tmp:
        for aircraft in ("cdrw", "missile"):
            times: dict[str, list[tuple[float, float]]] = {"ideal": [], "wire": []}
            for i in range(args.flights):
                for bus in times:   # alternating: both buses see the same machine
                    times[bus].append(_step_ms(Path(tmp) / f"{aircraft}-{bus}-{i}", aircraft, bus))
            ideal = statistics.median(t for t, _ in times["ideal"])
            wire = statistics.median(t for t, _ in times["wire"])
            model = statistics.median(m for _, m in times["wire"])
            ratio = wire / ideal
            rows += [(f"default {aircraft} flight, lockstep step, ideal bus", f"{ideal:.3f} ms", "", ""),
                     (f"  wire-time bus at {BITRATE // 1000}k (simulated time)", f"{wire:.3f} ms", "", ""),
                     ("    of which the bus model", f"{model:.3f} ms", "", ""),
                     ("  wire / ideal (medians)", f"{ratio:.2f} x", f"<= {TARGET_RATIO} x",
                      "ok" if ratio <= TARGET_RATIO else "MISSED")]
    print_table(f"wire-time bus in lockstep ({args.flights} flights each, alternating)", rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
