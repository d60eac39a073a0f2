"""Every realtime run measures its platform beside the flight (hil.rig.platform, issue 37):
run_info.json's `platform` (the kernel, its preemption model, UML or native, the governor, the
isolated CPUs, the load) with cyclictest's baseline at the flight's period and fcc's priority,
its histogram in cyclictest's format in the run directory, and summary.json's `platform`
verdict (hil.results.platform).  What the figures are depends on the machine: only their
shape and consistency are checked here."""
from __future__ import annotations

import json
import shutil

import pytest
from rig_helpers import MISSILE_2S, cli

from hil.rig.config import FCC_RT_PRIORITY
from hil.rig.platform import HIST_NAME

pytestmark = [pytest.mark.vcan,
              pytest.mark.skipif(shutil.which("cyclictest") is None, reason="rt-tests not installed")]


def test_a_realtime_missile_run_measures_its_platform(tmp_path, capsys):
    sc = tmp_path / "missile_2s.toml"
    sc.write_text(MISSILE_2S)
    out = tmp_path / "run"
    rc, _, err = cli(capsys, "run", "missile", str(sc), "--mode", "realtime", "--no-plots", "--quiet",
                     "--out", str(out))
    s = json.loads((out / "summary.json").read_text())
    assert rc == (7 if s["sync"]["verdict"] != "ok" and not s["platform"]["sync_loss"]["tolerated"]
                  else 0), err
    p = json.loads((out / "run_info.json").read_text())["platform"]
    assert p["kernel"] and p["preempt"] and isinstance(p["uml"], bool) and len(p["load_average"]) == 3
    assert "cpu_governor" in p and "isolated_cpus" in p
    b = p["baseline"]
    assert "error" not in b, b
    # one wake-up per period of the 2 s flight at T = 0.05 s (the last may not come)
    assert b["interval_us"] == 50_000 and b["priority"] == FCC_RT_PRIORITY and 35 <= b["cycles"] <= 42
    assert 0 <= b["min_us"] <= b["p50_us"] <= b["p99_us"] <= b["max_us"]
    assert sum(b["histogram"].values()) + b["overflows"] == b["cycles"]
    hist = (out / HIST_NAME).read_text().splitlines()
    assert hist[0] == "# Histogram" and f"# Max Latencies: {b['max_us']:05d}" in hist
    assert {int(r.split()[0]): int(r.split()[1]) for r in hist if not r.startswith("#")} == \
        {int(k): v for k, v in b["histogram"].items()}
    v = s["platform"]
    assert v["verdict"] in ("ok", "platform-limited", "firmware")
    assert v["baseline"]["max_us"] == b["max_us"] and v["deadline_misses"]["overruns"] == s["firmware"]["overruns"]
    assert HIST_NAME in json.loads((out / ".hil-run.json").read_text())["files"]
