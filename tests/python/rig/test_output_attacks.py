"""Forged outputs (issue 34): a keyless node on vcan0 rewrites fcc's identification outputs --
its estimates (SID_AZKF_STATE α̂), its bounds (SID_AZKF_BOUNDS), its fault flags (the fault bit
of every filter's STATE frame) -- during a lockstep CDRW flight through the real fcc.  Every
table is the clean flight's (fcc's outputs count only under SID_OUT_AUTH), and the run says
what happened: the reading refused the forged copies, fcc counted every frame on its own
identifiers (FCC_E2E_FAULTS.own_id), the verdict is not "ok" (`hil run`: exit 7, one line).

The forger knows the DBC and everything said on the bus but the key: at every step, once fcc
has answered (its frames and their authenticator are on the bus), it sends its own version of
the step's frame; the next step's genuine frame then arrives beside it.  Placed by step count,
never by wall-clock time.
"""
from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest

from hil.bus import load
from hil.bus.secoc import TEST_KEY_FILE
from hil.rig.link import pack_frame
from hil.rig.lockstep import LockstepRunner
from rig_helpers import CDRW_1S, cli, fly, scenario

pytestmark = pytest.mark.vcan
SPEC = load()

State = dict[str, float]


def state(k: int, alpha: float, fault: int) -> State:
    return {"alpha_hat": alpha, "q_hat": 0.0, "order": 2, "fault": fault, "degraded": 0,
            "step": k & 0xFFF}


#: what the forger sends at step k: [(frame name, signal values)]
FORGERIES: dict[str, Callable[[int], list[tuple[str, State]]]] = {
    "estimate": lambda k: [("SID_AZKF_STATE", state(k, 0.354, 0))],
    "bounds": lambda k: [("SID_AZKF_BOUNDS", {"alpha_lo": 3.0, "alpha_hi": 3.1, "q_lo": 3.0, "q_hi": 3.1})],
    "fault flag": lambda k: [(f"SID_{f}_STATE", state(k, 0.1, 1)) for f in ("AZKF", "ZKF", "KF")],
}


def cdrw_flight(out: Path, monkeypatch: pytest.MonkeyPatch, forge: str | None = None) -> dict:
    """A lockstep CDRW flight; forge: after each step fcc answered, the forger's frames."""
    step = LockstepRunner.step

    def attacked(runner: LockstepRunner, d):  # type: ignore[no-untyped-def]
        k = d.k
        got = step(runner, d)
        if forge is not None:
            link = runner.rig.link
            assert link is not None
            for name, values in FORGERIES[forge](k):
                msg = SPEC.by_name(name)
                link.send_raw(pack_frame(msg.frame_id, msg.message.encode(values)))
        return got

    monkeypatch.setattr(LockstepRunner, "step", attacked)
    try:
        return dict(fly(out, scenario(CDRW_1S), key_file=TEST_KEY_FILE, timeout=10.0).summary)
    finally:
        monkeypatch.undo()


@pytest.fixture(scope="module")
def clean(tmp_path_factory) -> dict:
    with pytest.MonkeyPatch.context() as mp:
        return cdrw_flight(tmp_path_factory.mktemp("clean"), mp)


def test_the_clean_flight_is_trusted(clean):
    t = clean["bus_trust"]
    assert t["verdict"] == "ok" and t["message"] == "" and t["own_id"] == 0
    assert t["forged"] == {"refused": {"SID_OUT_AUTH": 0, "MSL_ELEV_CMD_AUTH": 0},
                           "conflicts": {"SID_OUT_AUTH": 0, "MSL_ELEV_CMD_AUTH": 0}}
    assert clean["firmware"]["rejected"]["own_id"] == 0


@pytest.mark.parametrize("forge", list(FORGERIES))
def test_forged_outputs_change_no_table_and_are_named(clean, tmp_path, monkeypatch, forge):
    s = cdrw_flight(tmp_path / "run", monkeypatch, forge)
    cd, ref = s["cdrw"], clean["cdrw"]
    assert cd["table4"] == ref["table4"] and cd["table4_truth"] == ref["table4_truth"]
    assert cd["coverage"] == ref["coverage"]
    assert cd["flight"]["missing_steps"] == ref["flight"]["missing_steps"] == 0
    assert s["firmware"]["steps"] == clean["firmware"]["steps"]
    per_step, steps = len(FORGERIES[forge](0)), cd["flight"]["steps"]
    assert steps == 51   # CDRW_1S: 1 s at 50 Hz, both ends
    t = s["bus_trust"]
    # fcc saw every forged frame on its own identifiers; the reading refused every copy that
    # met fcc's next frame (the last step's forgery meets none: held, never used)
    assert t["own_id"] == s["firmware"]["rejected"]["own_id"] == per_step * steps
    assert t["forged"]["conflicts"] == {"SID_OUT_AUTH": per_step * (steps - 1), "MSL_ELEV_CMD_AUTH": 0}
    assert t["forged"]["refused"] == {"SID_OUT_AUTH": per_step * (steps - 1), "MSL_ELEV_CMD_AUTH": 0}
    assert t["verdict"] == "forged"
    assert t["message"].startswith("bus attacked or outputs untrustworthy: frames forged on fcc's "
                                   "outputs refused (SID_OUT_AUTH's group: ")
    assert f"fcc counted {per_step * steps} frames on its own identifiers" in t["message"]


def test_hil_run_exits_7_naming_the_forgery(tmp_path, monkeypatch, capsys):
    """`hil run cdrw` under the same forger: exit 7 and one line, the results in --out."""
    step = LockstepRunner.step

    def attacked(runner: LockstepRunner, d):  # type: ignore[no-untyped-def]
        k = d.k
        got = step(runner, d)
        link = runner.rig.link
        assert link is not None
        for name, values in FORGERIES["estimate"](k):
            msg = SPEC.by_name(name)
            link.send_raw(pack_frame(msg.frame_id, msg.message.encode(values)))
        return got

    monkeypatch.setattr(LockstepRunner, "step", attacked)
    sc = tmp_path / "short.toml"
    sc.write_text(CDRW_1S)
    code, _, err = cli(capsys, "run", "cdrw", str(sc), "--no-plots", "--quiet",
                       "--key-file", str(TEST_KEY_FILE), "--out", str(tmp_path / "out"))
    assert code == 7
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("hil: bus attacked or outputs untrustworthy: "
                                                   "frames forged on fcc's outputs refused"), err
    assert (tmp_path / "out" / "summary.json").is_file()
