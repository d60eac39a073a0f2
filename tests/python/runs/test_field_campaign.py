"""`hil campaign AIRCRAFT --vary ... --keep-logs` on the real fcc (vcan): each flight's numbers
are those of the equivalent single `hil run`, byte for byte, and a kept flight replays."""
from __future__ import annotations

import json

import pytest

from hil.io.output import read_csv
from hil.runs.field_campaign import flight_numbers

from rig_helpers import CDRW_1S, MISSILE_2S, cli

pytestmark = pytest.mark.vcan

QUIET = ("--quiet", "--no-plots")


def test_a_2x2_vary_campaign_is_four_single_runs(tmp_path, capsys):
    base = tmp_path / "missile.toml"
    base.write_text('name = "m2"\n' + MISSILE_2S)   # (a run names its scenario: the same name)
    camp = tmp_path / "camp"
    rc, out, err = cli(capsys, "campaign", "missile", str(base), "--runs", "1", "--vary", "lqg.bits=6,8",
                       "--vary", "seed=3,4", "--keep-logs", "--out", str(camp), *QUIET)
    assert rc == 0, out + err
    summary = json.loads((camp / "summary.json").read_text())
    rows = read_csv(camp / "campaign.csv")
    combos = [c["values"] for c in summary["combinations"]]
    assert combos == [{"lqg.bits": b, "seed": s} for b in (6, 8) for s in (3, 4)]
    assert list(rows["lqg.bits"]) == [6, 6, 8, 8] and list(rows["seed"]) == [3, 4, 3, 4]
    for i, values in enumerate(combos):
        single_toml = tmp_path / f"single{i}.toml"
        single_toml.write_text('name = "m2"\n' + MISSILE_2S.replace("bits = 8", f"bits = {values['lqg.bits']}"))
        single = tmp_path / f"single{i}"
        rc, out, err = cli(capsys, "run", "missile", str(single_toml), "--seed", str(values["seed"]),
                           "--out", str(single), *QUIET)
        assert rc == 0, out + err
        want = json.loads((single / "summary.json").read_text())
        kept = json.loads((camp / summary["combinations"][i]["flights"][0]["dir"] / "summary.json").read_text())
        # deterministic: the simulator's and fcc's results byte for byte (not the session's key)
        assert json.dumps(kept["missile"]) == json.dumps(want["missile"])
        assert (camp / f"flights/{i:04d}/missile_T0.050_b{values['lqg.bits']}.csv").read_bytes() == \
            (single / f"missile_T0.050_b{values['lqg.bits']}.csv").read_bytes()
        numbers = flight_numbers(want)
        assert set(numbers) <= set(rows) and numbers["rms_q"] > 0
        assert {k: rows[k][i] for k in numbers} == numbers
        assert summary["combinations"][i]["mean"] == numbers
    rc, out, err = cli(capsys, "replay", str(camp / "flights" / "0002"))
    assert rc == 0 and "identical" in out, out + err


def test_a_cdrw_campaign_draws_moves_the_fault_and_keeps_no_log_unless_asked(tmp_path, capsys):
    base = tmp_path / "cdrw.toml"
    base.write_text(CDRW_1S.replace("duration = 1.0", "duration = 2.0") + '[[faults]]\nkind = "spike"\n'
                    'signal = "alpha"\nstart = 0.4\nduration = 0.1\nmagnitude = 0.1\n')
    camp = tmp_path / "camp"
    rc, out, err = cli(capsys, "campaign", "cdrw", str(base), "--runs", "2", "--seed", "5",
                       "--draw", "faults[0].magnitude=uniform:0.05,0.2", "--out", str(camp), *QUIET)
    assert rc == 0, out + err
    summary = json.loads((camp / "summary.json").read_text())
    flights = summary["combinations"][0]["flights"]
    assert len(flights) == 2 and flights[0]["fault_start"] != flights[1]["fault_start"]
    assert all(0.05 <= f["faults[0].magnitude"] < 0.2 and "dir" not in f for f in flights)
    assert not (camp / "flights").exists() and "kf_alpha_meas" in read_csv(camp / "campaign.csv")
    assert summary["bus_trust"]["verdict"] == "ok"


def test_table_5_s_flights_are_the_field_campaign_s(tmp_path, capsys):
    """`hil campaign cdrw` (one session, fcc reset between flights) and the same campaign flown
    as single runs (--keep-logs: a session each): the same fault times, Table 4 of every flight
    equal to the last bit."""
    base = tmp_path / "cdrw.toml"
    base.write_text(CDRW_1S.replace("duration = 1.0", "duration = 2.0") + '[[faults]]\nkind = "bias"\n'
                    'signal = "q"\nstart = 0.4\nduration = 0.3\nmagnitude = 0.05\n')
    for name, extra in (("t5", ()), ("single", ("--keep-logs",))):
        rc, out, err = cli(capsys, "campaign", "cdrw", str(base), "--runs", "2", "--seed", "7",
                           "--out", str(tmp_path / name), *QUIET, *extra)
        assert rc == 0, out + err
    table5 = json.loads((tmp_path / "t5" / "summary.json").read_text())["cdrw"]["runs"]
    single = json.loads((tmp_path / "single" / "summary.json").read_text())["combinations"][0]["flights"]
    assert [r["fault_start"] for r in table5] == [f["fault_start"] for f in single]
    for run, flight in zip(table5, single):
        assert {f"{f}_{s}_meas": v for f, row in run["error"].items() for s, v in row.items()} == \
            {k: v for k, v in flight.items() if k.endswith("_meas")}
