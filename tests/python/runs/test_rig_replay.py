"""`hil replay`: a recorded lockstep flight replayed into a fresh fcc is identical frame for
frame on the same firmware, and the first difference (step, message, signal, both values) is
reported, exit status 1, when the firmware's behaviour changes."""
from __future__ import annotations

import re

import pytest

from hil.io import rundir

from rig_helpers import CDRW_1S, MISSILE_2S, cli, fly, scenario

pytestmark = pytest.mark.vcan


def test_replay_identical_then_different(tmp_path, capsys):
    # both aircraft in one fcc, a frame fault and a dropped tick on the way
    fly(tmp_path / "rec", scenario(CDRW_1S, "loss:frame=CDRW_AOA,start=0.3,duration=0.1"),
        scenario(MISSILE_2S, "loss:frame=SIM_TICK,start=1.0,duration=0.1"))
    rc, out, err = cli(capsys, "replay", str(tmp_path / "rec"))
    assert rc == 0, out + err
    steps = int(re.search(r"identical \((\d+) steps", out)[1])
    assert steps >= 51 + 38
    # a changed filter parameter: the first differing step, message, signal and values
    rc, out, err = cli(capsys, "replay", str(tmp_path / "rec"), "--fcc-args", "--ridge 0.05")
    assert rc == 1, out + err
    m = re.search(r"DIFFERENT after (\d+) identical steps; first difference at step (\d+) of app cdrw: "
                  r"(SID_\w+)\.(\w+): recorded (\S+), replayed (\S+)$", out.strip())
    assert m, out
    assert float(m[5]) != float(m[6])
    # a changed autopilot: the elevator command differs
    rc, out, _ = cli(capsys, "replay", str(tmp_path / "rec"), "--fcc-args", "--lqg-bits 6")
    assert rc == 1 and "MSL_" in out


def test_a_replayed_run_stays_hils_own(tmp_path, capsys):
    """replay writes RUN_DIR/replay/fcc.log; the run directory stays hil's own, so a new run may
    replace it (README's order: run, replay, run again with a fault)."""
    run = tmp_path / "run"
    assert cli(capsys, "run", "cdrw", "--quiet", "--no-plots", "--out", str(run))[0] == 0
    assert cli(capsys, "replay", str(run))[0] == 0
    assert (run / "replay" / "fcc.log").is_file() and rundir.is_own_run(run)
    rc, _, err = cli(capsys, "run", "cdrw", "--quiet", "--no-plots", "--out", str(run))
    assert rc == 0, err


def test_replay_refuses_what_it_cannot_replay(tmp_path, capsys):
    rc, _, err = cli(capsys, "replay", str(tmp_path / "nothing"))
    assert rc == 2 and "not a run directory" in err
    fly(tmp_path / "rt", scenario(CDRW_1S), mode="realtime")
    rc, _, err = cli(capsys, "replay", str(tmp_path / "rt"))
    assert rc == 2 and "only lockstep runs replay" in err and err.count("\n") == 1
