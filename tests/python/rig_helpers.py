"""Shared by the rig's bus tests: short scenarios and a quiet flight through the real fcc."""
from __future__ import annotations

from pathlib import Path
from typing import Any

from hil.bus import load
from hil.scenario.file import Scenario, loads_scenario, with_extra_faults
from hil.sim.drivers import CdrwDriver
from hil.rig.lockstep import LockstepRunner
from hil.runs.outcome import Outcome
from hil.rig.config import RigConfig
from hil.runs.run import run_flight
from hil.bus.protocol import COMMAND_FLIGHT, COMMAND_RESET
from hil.rig.session import RigSession

FRAMES = {m.name for m in load().messages}

CDRW_1S = '''aircraft = "cdrw"
duration = 1.0
seed = 3
'''

MISSILE_2S = '''aircraft = "missile"
duration = 2.0
seed = 3
[lqg]
period = 0.05
bits = 8
'''
MISSILE_4S = MISSILE_2S.replace("duration = 2.0", "duration = 4.0")


def scenario(text: str, *faults: str) -> Scenario:
    sc = loads_scenario(text, "<test>", FRAMES)
    return with_extra_faults(sc, faults, FRAMES) if faults else sc


def fly(out: Path, *scenarios: Scenario, **cfg: Any) -> Outcome:
    cfg.setdefault("progress", False)
    cfg.setdefault("plots", False)
    return run_flight(list(scenarios), RigConfig(out_dir=out, **cfg))


def airborne(rig: RigSession, sc: Scenario, steps: int, timeout: float) -> tuple[LockstepRunner, CdrwDriver]:
    """A CDRW flight flown by hand in an open session (for the tests that break the device in
    flight): RESET, FLIGHT (ticks run only in flight), `steps` lockstep steps; the runner and
    driver to go on with."""
    runner = LockstepRunner(rig, timeout=timeout)
    d = CdrwDriver(sc, rig.codec)
    rig.control(COMMAND_RESET)
    rig.control(COMMAND_FLIGHT)
    for _ in range(steps):
        runner.step(d)
    return runner, d


def cli(capsys: Any, *argv: str) -> tuple[int, str, str]:
    """`hil ARGV...` in this process: (exit status, stdout, stderr)."""
    from hil.cli import main

    rc = main(list(argv))
    out, err = capsys.readouterr()
    return rc, out, err
