"""hil.results.rowtables.sid_options: the identification options of fcc's command line, read
without starting sid_replay when the rig wrote the command line alone."""
from __future__ import annotations

from pathlib import Path

import pytest

from hil.bus import load
from hil.scenario.file import load_default_scenario
from hil.results import rowtables
from hil.rig.config import RigConfig
from hil.rig.flight import fcc_args


def _written_options(mode: str, rows: str) -> set[str]:
    frames = {m.name for m in load().messages}
    scenarios = [load_default_scenario(a, frames) for a in ("cdrw", "missile")]
    args = fcc_args(scenarios, RigConfig(Path("unused"), mode=mode, rows=rows))
    return {a for a in args if a.startswith("--")}


@pytest.mark.parametrize("mode", ["lockstep", "realtime"])
def test_the_rigs_own_options_are_not_identification_options(mode: str) -> None:
    written = _written_options(mode, "prior")
    assert "--rows" in written and written - {"--rows"} <= rowtables.RIG_OPTIONS
    assert not rowtables.RIG_OPTIONS & rowtables._sid_option_names()   # sid_replay's own list


def test_the_rigs_command_line_needs_no_usage_text(monkeypatch: pytest.MonkeyPatch) -> None:
    def refuse() -> frozenset[str]:
        raise AssertionError("sid_replay --help was started")
    monkeypatch.setattr(rowtables, "_sid_option_names", refuse)
    assert rowtables.sid_options(["--mode", "lockstep", "--apps", "cdrw"]) == ("paper", [])
    assert rowtables.sid_options(["--mode", "lockstep", "--rows", "posterior"]) == ("posterior", [])


def test_a_users_options_are_sorted_by_sid_replays_usage() -> None:
    args = ["--mode", "lockstep", "--apps", "cdrw", "--window", "40", "--stale-limit", "3"]
    rows, sid = rowtables.sid_options(args)
    assert rows == "paper" and sid == ["--window", "40"]
