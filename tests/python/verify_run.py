"""`hil verify` run as a user runs it, for the verify tests: its status, its output and the
verdict of each case as its table prints it."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def run_verify(*args: str, tmp: Path) -> tuple[int, str, dict[str, str]]:
    """hil verify ARGS into tmp/report (and tmp/j.xml): (status, stdout + stderr, {case: verdict})."""
    p = subprocess.run([sys.executable, "-m", "hil.cli", "verify", *args, "--force",
                        "--out", str(tmp / "report"), "--junit", str(tmp / "j.xml")],
                       capture_output=True, text=True, timeout=900, cwd=ROOT)
    verdicts = {}
    for ln in p.stdout.splitlines():
        parts = ln.split()
        if len(parts) >= 2 and parts[0] in ("PASS", "FAIL", "ERROR", "INCONCLUSIVE", "-") and "/" not in parts[1]:
            verdicts[parts[1]] = parts[0]
    return p.returncode, p.stdout + p.stderr, verdicts
