"""`hil study missile-rms`: Fig. 3 by covariance analysis (no bus)."""
from __future__ import annotations

import argparse
import json

from hil.cli.usage import UsageError
from hil.io.paths import tool
from hil.sim.missile_cov import format_study, missile_rms_study


def run(args: argparse.Namespace) -> int:
    for n in args.bits:
        if not 2 <= n <= 16:
            raise UsageError(f"--bits: D/A word length must be 2 to 16, got {n}")
    for T in args.periods:
        if not 0.001 <= T <= 1.0:
            raise UsageError(f"--periods: lqg_design accepts 0.001 to 1 s, got {T:g}")
    study = missile_rms_study(args.periods, args.bits, args.gyro_var, args.accel_var, tool("lqg_design"))
    print(json.dumps(study, allow_nan=False) if args.json else format_study(study))
    return 0
