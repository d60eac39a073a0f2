"""The one-line verdict (hil.results.verdict) of a recorded run directory's summary: what flew,
its faults, the headline numbers, PASS/FAIL against the paper's Table 4 only where the paper
has a number; and the fault windows it and the figures take from the flight's events."""
from __future__ import annotations

import json
from pathlib import Path

from hil.results import verdict
from hil.results.faultwindows import FaultWindow, from_events

#: a recorded run of both aircraft (hil verify's fixture): cdrw_default and missile_default
RECORDED = Path(__file__).resolve().parents[2] / "vectors" / "verify"


def recorded() -> dict:
    return json.loads((RECORDED / "summary.json").read_text())


def test_a_cdrw_runs_line_says_what_flew_its_faults_numbers_and_the_papers_table4() -> None:
    cdrw, missile = verdict.lines(recorded())
    parts = cdrw.split(" | ")
    assert parts[0] == "verdict PASS"
    assert parts[1] == "cdrw cdrw_default, lockstep, random seed 1"
    assert parts[2] == "faults spike(alpha)@4-4.1s spike(q)@4-4.1s"
    # Table 4 against the true state and the bounds coverage, as summary.json has them
    assert parts[3] == ("α error vs truth AZKF 0.0569 ZKF 0.1437 KF 0.1192; "
                        "α in bounds AZKF 97.7% ZKF 77.8% KF 67.8%")
    assert parts[4] == "paper Table 4: AZKF's α error the lowest (0.1073 vs 0.1089, 0.1956): held"
    assert "\n" not in cdrw


def test_a_missile_runs_line_has_its_rms_word_length_period_and_no_paper_number() -> None:
    line = verdict.lines(recorded())[1]
    assert line.startswith("verdict n/a | missile missile_default, lockstep, random seed 1 | no faults | ")
    assert ("T 0.1 s, 8-bit D/A: RMS q 0.0721 rad/s, α_T 0.00529 rad (open loop 0.0821, 0.00551); "
            "D/A codes = reference 100.0%") in line
    assert line.endswith("no paper number for one flight (paper 2's Fig. 3 is a curve)")


def test_fail_when_another_filter_has_the_lowest_alpha_error() -> None:
    s = recorded()
    s["cdrw"]["table4"]["kf"]["alpha"] = 0.01   # the KF best against the measurement
    line = verdict.lines(s)[0]
    assert line.startswith("verdict FAIL") and line.endswith(": not held (KF lower)")


def test_no_verdict_against_the_paper_outside_its_scenario() -> None:
    s = recorded()
    s["cdrw"]["paper_scenario"] = False
    line = verdict.lines(s)[0]
    assert line.startswith("verdict n/a") and "not the paper's scenario" in line
    assert "PASS" not in line and "FAIL" not in line


def test_a_campaign_names_its_moved_faults_and_table5() -> None:
    s = recorded()
    cd = s["cdrw"]
    cd["table5"], cd["table5_truth"] = cd.pop("table4"), cd.pop("table4_truth")
    cd["runs_count"] = 3
    cd["table5_truth_ci"] = {f: {st: {"mean": v, "half_width": 0.001} for st, v in row.items()}
                             for f, row in cd["table5_truth"].items()}
    del cd["flight"]
    s.update(runs_count=3, scenario="cdrw_default", seed=1,
             faults=["spike:start=4,duration=0.1,signal=alpha,magnitude=0.15"])
    line = verdict.lines(s)[0]
    assert "cdrw cdrw_default, lockstep, random seed 1, 3 flights" in line
    assert "faults spike(alpha, 0.1 s) at random times" in line
    assert "AZKF 0.0569±0.0010" in line and "paper Table 5" in line and "(0.0895 vs 0.0966, 0.1686)" in line


def test_fault_windows_pair_starts_and_ends_and_a_fault_may_last_to_the_end() -> None:
    events = [{"action": "start", "index": 1, "kind": "stuck", "target": "q_g", "t": 3.0},
              {"action": "start", "index": 0, "kind": "bad_crc", "target": "MSL_ACCELEROMETER", "t": 6.0},
              {"action": "end", "index": 1, "kind": "stuck", "target": "q_g", "t": 4.0}]
    assert from_events(events) == [FaultWindow("stuck", "q_g", 3.0, 4.0),
                                   FaultWindow("bad_crc", "MSL_ACCELEROMETER", 6.0, None)]
    assert [w.short() for w in from_events(events)] == ["stuck(q_g)@3-4s", "bad_crc(MSL_ACCELEROMETER)@6-…s"]


def test_headline_metrics_are_the_numbers_the_verdict_judges() -> None:
    m = verdict.headline_metrics(recorded())
    assert m["Table 4 alpha AZKF vs truth"] == recorded()["cdrw"]["table4_truth"]["azkf"]["alpha"]
    assert round(m["coverage alpha KF (%)"], 1) == 67.8
    assert round(m["missile T 0.1 s 8-bit RMS q"], 4) == 0.0721
    assert "missile T 0.1 s open loop RMS α_T" in m
    assert not verdict.lines({"command": "study"})
