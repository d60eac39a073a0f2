"""A campaign over scenario fields (`hil campaign ... --vary`) on rigs of their own
(--workers, from the host shell): every flight a task, the results byte for byte those of
the sequential campaign in one guest."""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from hil.cli import main

REPO = Path(__file__).resolve().parents[3]
UML = Path(os.environ.get("WITH_VCAN_UML_DIR") or REPO / ".uml")
needs_rig = pytest.mark.skipif(not (UML / "linux.uml").exists() and not Path("/sys/class/net/vcan0").exists(),
                               reason="needs User-Mode Linux (scripts/setup) or a kernel with vcan")
MISSILE = 'name = "m2"\naircraft = "missile"\nduration = 2.0\nseed = 3\n[lqg]\nperiod = 0.05\nbits = 8\n'


@needs_rig
def test_a_vary_campaign_on_workers_equals_the_sequential_one(tmp_path):
    (tmp_path / "m.toml").write_text(MISSILE)
    argv = ["campaign", "missile", str(tmp_path / "m.toml"), "--runs", "1", "--vary", "lqg.bits=6,8",
            "--vary", "seed=3,4", "--quiet", "--no-plots"]
    r = subprocess.run([str(REPO / "scripts" / "with-vcan"), sys.executable, "-m", "hil.cli", *argv,
                        "--out", str(tmp_path / "seq")], cwd=REPO, capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    assert main([*argv, "--out", str(tmp_path / "par"), "--workers", "2"]) == 0
    assert (tmp_path / "seq" / "campaign.csv").read_bytes() == (tmp_path / "par" / "campaign.csv").read_bytes()
    seq = json.loads((tmp_path / "seq" / "summary.json").read_text())
    assert seq == json.loads((tmp_path / "par" / "summary.json").read_text())
    assert [c["values"] for c in seq["combinations"]] == [{"lqg.bits": b, "seed": s} for b in (6, 8) for s in (3, 4)]
