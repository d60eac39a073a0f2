"""hil.results.rowtables.sid_options: the identification options of fcc's command line, read
without starting sid_replay when the rig wrote the command line alone; the replay's rows read
only in the columns the tables use."""
from __future__ import annotations

from pathlib import Path

import pytest

from hil.bus import load
from hil.scenario.file import load_default_scenario
from hil.results import rowtables
from hil.results.sidrows import read_rows
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


def test_the_replays_rows_are_read_column_for_column() -> None:
    """read_rows with `columns`: those columns only, each the same array as read in full."""
    text = ("t,filter,alpha_hat,q_hat,gain_norm\n"
            "0,paper/kf,0.1,0.25,1\n0,prior/kf,0.5,nan,2\n0.02,paper/kf,-0.3,1e-300,3\n")
    every = read_rows(text)
    some = read_rows(text, rowtables.ESTIMATES)
    assert list(every) == list(some) == ["paper/kf", "prior/kf"]
    assert list(some["paper/kf"]) == ["alpha_hat", "q_hat"]
    for f in some:
        for c in some[f]:
            assert some[f][c].tobytes() == every[f][c].tobytes()
    assert some["paper/kf"]["q_hat"].tolist() == [0.25, 1e-300]


def test_the_replays_rows_must_be_whole() -> None:
    """A row with other than the header's fields is refused (one line), not shifted into the
    next row's columns; no rows, no filters."""
    with pytest.raises(ValueError, match="rows of other than the header's 3 fields"):
        read_rows("t,filter,alpha_hat\n0,kf,0.1\n0.02,kf\n")
    assert read_rows("t,filter,alpha_hat\n") == {} and read_rows("") == {}
    assert read_rows("t,filter,alpha_hat\n0,kf,0.5")["kf"]["alpha_hat"].tolist() == [0.5]


@pytest.mark.parametrize("sig", ["alpha", "q", "de", "q_g", "n_a"])
def test_readings_as_fcc_decodes_them_value_by_value(sig: str) -> None:
    """The replay's input, a column at a time: the very floats to_raw then to_phys give one by
    one (ties, signed zeros, NaN and infinities included)."""
    import numpy as np
    from hil.sim.drivers import SIGNAL_FRAMES

    spec = load()
    frame, name = SIGNAL_FRAMES[sig]
    s = next(x for x in spec.by_name(frame).signals if x.name == name)
    rng = np.random.default_rng(26)
    v = np.concatenate([rng.normal(0, 1, 20000), rng.normal(0, 1e-6, 2000),
                        (np.arange(-500, 500) + 0.5) / s.inv_scale,
                        [0.0, -0.0, np.nan, np.inf, -np.inf, -1e-9, 1e300, -1e300, 0.49999999999999994 / s.inv_scale]])
    want = np.array([x if not np.isfinite(x) else float(s.to_phys(s.to_raw(float(x)))) for x in v])
    assert rowtables._received(spec, sig, v).tobytes() == want.tobytes()
