"""`hil study bus` on a reduced grid, the real fcc on vcan0 in lockstep over the wire-time bus:
its table and figure, and the trends the physics guarantees (a slower bus or more traffic of
higher priority never brings a command sooner; Table 4 of the open-loop CDRW does not depend on
when fcc's outputs come off the wire)."""
from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from rig_helpers import cli

pytestmark = pytest.mark.vcan


def test_a_small_bus_study(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    args = ("study", "bus", "--bitrates", "125k,1M", "--loads", "0,0.6", "--periods", "0.1",
            "--duration", "2", "--table4", "250k,0.5")
    rc, out, err = cli(capsys, *args, "--json")
    assert rc == 0, err
    study = json.loads(out)
    pts = study["points"]
    assert len(pts) == 2 * 2 * 1 * 2 and not any(p["failed"] for p in pts)
    assert all(math.isfinite(p["rms_q"]) and p["commands_missing"] == 0 for p in pts)
    at = {(p["bitrate"], p["load"], p["design"]): p for p in pts}
    for load in (0.0, 0.6):   # an eighth of the bit time: every command sooner
        assert at[(1_000_000, load, "plain")]["cmd_delay_max_s"] < at[(125_000, load, "plain")]["cmd_delay_max_s"]
    for rate in (125_000, 1_000_000):   # higher-priority traffic: no command sooner
        assert at[(rate, 0.6, "plain")]["cmd_delay_p50_s"] >= at[(rate, 0.0, "plain")]["cmd_delay_p50_s"]
        # the delay-aware LQG is designed for the plain flight's largest delay (rounded up)
        aware = at[(rate, 0.6, "delay-aware")]
        assert at[(rate, 0.6, "plain")]["cmd_delay_max_s"] <= aware["delay_s"] < 0.1
    t4 = study["table4"]
    assert t4["ideal"]["table4"] == t4["wire"]["table4"] and not t4["wire"]["failed"]
    # the table and the figure
    fig = tmp_path / "bus.png"
    rc, out, err = cli(capsys, *args, "--figure", str(fig))
    assert rc == 0, err
    assert "T = 0.1 s: RMS q (rad/s), plain / delay-aware LQG" in out and "Table 4 (CDRW" in out
    assert fig.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
