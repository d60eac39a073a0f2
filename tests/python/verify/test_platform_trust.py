"""Two things every case is judged on besides its expectations: its run's outputs were
authentic (summary.json's bus_trust: a case whose run has it not ok never passes), and, for a
realtime case's timing requirements, the platform it flew on (hil.verify.platform: a timing
failure on a platform that did not keep its schedule is inconclusive with cyclictest's figures,
never a silent pass and never a firmware failure)."""
from __future__ import annotations

import xml.etree.ElementTree as ET
from typing import Any

import pytest

from hil.verify import suite
from hil.verify.platform import INCONCLUSIVE, limited
from hil.verify.report import counts, junit, line, requirement_verdict
from hil.verify.runner import (EVERY_REQUIREMENT, FAIL, PASS, CaseResult, Check, against_platform, case_verdict,
                               trusted, trusted_flights)

FORGED = {"verdict": "forged", "message": "bus attacked or outputs untrustworthy: frames forged on fcc's outputs "
                                          "refused (MSL_ELEV_CMD_AUTH's group: 3 refused, 0 conflicting copies)",
          "own_id": 3, "forged": {"refused": {"MSL_ELEV_CMD_AUTH": 3}, "conflicts": {}}}


def shipped(name: str) -> suite.Suite:
    return suite.load(suite.shipped()[name])


def case(s: suite.Suite, case_id: str) -> suite.Case:
    return next(c for c in s.cases if c.id == case_id)


# ---- bus_trust ----------------------------------------------------------------------------------
def test_a_case_whose_outputs_were_forged_does_not_pass():
    s = shipped("fcc-node-conformance")
    c = case(s, "clean-cdrw")
    (bad,) = trusted(c, {"bus_trust": FORGED})
    assert bad.verdict == FAIL and bad.requirement == EVERY_REQUIREMENT and "bus_trust forged" in bad.measured
    checks = [Check("NODE-HB-1", "heartbeats >= 1", PASS, "heartbeats = 12"), bad]
    assert case_verdict(checks) == FAIL
    r = CaseResult(s.name, c, case_verdict(checks), checks)
    # every requirement the case verifies fails with it, none passes on untrusted figures
    assert {requirement_verdict(req, [r], s.name) for req in c.requirements} == {FAIL}
    assert "failed (every requirement): bus_trust.ok == 1" in line(r)


def test_a_run_without_bus_trust_is_not_taken_as_trusted():
    c = case(shipped("fcc-node-conformance"), "clean-cdrw")
    (missing,) = trusted(c, {})
    assert missing.verdict == FAIL and "summary.json has no bus_trust" in missing.measured
    (ok,) = trusted(c, {"bus_trust": {"verdict": "ok", "message": ""}})
    assert ok.verdict == PASS


def test_an_attack_on_fcc_outputs_states_its_bus_trust_itself():
    """forged-commands names bus_trust fields (its run's outputs are forged by design): the case
    judges them, no implicit check is added."""
    c = case(shipped("fcc-node-conformance"), "forged-commands")
    assert trusted(c, {"bus_trust": FORGED}) == []
    from hil.verify.fields import values
    run = {"summary": {"bus_trust": FORGED}}
    assert values(run, {"bus_trust.ok", "bus_trust.forged_frames", "bus_trust.own_id"}) == \
        {"bus_trust.ok": 0.0, "bus_trust.forged_frames": 3.0, "bus_trust.own_id": 3.0}


def test_a_case_of_many_flights_needs_every_flight_trusted():
    runs = [{"summary": {"bus_trust": {"verdict": "ok"}}}] * 4 + [{"summary": {"bus_trust": FORGED}}]
    (c,) = trusted_flights(runs)
    assert c.verdict == FAIL and c.measured.startswith("1 of 5 flights not ok; first: flight 4: bus_trust forged")
    (c,) = trusted_flights(runs[:4])
    assert c.verdict == PASS and c.measured == "bus_trust ok in all 4 flights"


# ---- the platform -------------------------------------------------------------------------------
def realtime_summary(verdict: str = "ok", max_us: int | None = 900, slack_us: float = 49_000.0,
                     late_steps: int = 0, period: float = 0.05) -> dict[str, Any]:
    base = {"p50_us": 80, "p99_us": 400, "max_us": max_us, "cycles": 100} if max_us is not None \
        else {"error": "cyclictest not found"}
    return {"platform": {"verdict": verdict, "baseline": base,
                         "deadline_misses": {"slack_us": slack_us, "verdict": "none"}},
            "realtime": {"simulator": {"late_steps": late_steps}}, "missile": {"runs": [{"period": period}]}}


def test_the_platform_is_limited_only_with_its_evidence():
    assert limited(realtime_summary()) == ""                                 # it kept its schedule
    why = limited(realtime_summary("platform-limited"))
    assert why.startswith("platform-limited: the run's deadline misses or sync loss are the platform's")
    assert "p50 80 us, p99 400 us, max 900 us over 100 cycles" in why
    # a wake-up of a tenth of the period (5 ms at T = 0.05 s) or of the step's slack, whichever is less
    assert limited(realtime_summary(max_us=4_999)) == ""
    assert "worst wake-up reached 5000 us" in limited(realtime_summary(max_us=5_000))
    assert "worst wake-up reached 3000 us" in limited(realtime_summary(max_us=3_000, slack_us=3_000))
    assert "the rig's simulator sent 3 step(s) after their instant" in limited(realtime_summary(late_steps=3))
    rig_stall = realtime_summary()
    rig_stall["platform"]["sync_loss"] = {"platform_stall_us": 35_000.0}
    assert "a thread of the rig's stalled 35000 us" in limited(rig_stall)
    late_frame = realtime_summary()
    late_frame["realtime"]["simulator"]["transmitter"] = {"send_lateness_ms": {"max": 5.9}}
    assert "sent a sensor frame 5.9 ms after its instant, after fcc's latest release (3.5 ms)" in limited(late_frame)
    late_frame["realtime"]["simulator"]["transmitter"] = {"send_lateness_ms": {"max": 3.4}}
    assert limited(late_frame) == ""
    # the firmware's own misses, or no baseline (no cyclictest): nothing is excused
    assert limited(realtime_summary("firmware", max_us=90_000, late_steps=3)) == ""
    assert limited(realtime_summary("platform-limited", max_us=None, late_steps=3)) == ""


def judged(summary: dict[str, Any]) -> list[Check]:
    s = shipped("realtime-timing")
    checks = [Check("RT-LAT-1", "realtime.latency_p99_us < 0.5 * realtime.period_us", FAIL,
                    "realtime.latency_p99_us = 31000 < 25000"),
              Check("RT-DL-1", "overruns == 0", PASS, "overruns = 0")]
    return against_platform(checks, s.timing, summary)


def test_a_timing_failure_on_a_limited_platform_is_inconclusive_with_its_figures():
    checks = judged(realtime_summary(late_steps=2))
    assert [c.verdict for c in checks] == [INCONCLUSIVE, PASS]
    assert checks[0].measured.startswith("realtime.latency_p99_us = 31000 < 25000; platform-limited: ")
    assert "max 900 us over 100 cycles" in checks[0].measured
    assert case_verdict(checks) == INCONCLUSIVE
    # on a platform that kept its schedule, or with the firmware's own misses, it fails
    assert case_verdict(judged(realtime_summary())) == FAIL
    assert case_verdict(judged(realtime_summary("firmware", late_steps=2))) == FAIL
    # a requirement not marked timing is never excused (an attack refused, a counter)
    other = [Check("TS-SEC-1", "sync.verdict.attacked == 1", FAIL, "sync.verdict.attacked = 0")]
    assert against_platform(other, shipped("time-sync").timing, realtime_summary("platform-limited")) == other


def test_an_inconclusive_case_is_counted_apart_and_skipped_in_junit(tmp_path):
    s = shipped("realtime-timing")
    c = case(s, "T0.05")
    checks = judged(realtime_summary(late_steps=2))
    r = CaseResult(s.name, c, case_verdict(checks), checks, seconds=6.0)
    assert counts([r]) == {PASS: 0, FAIL: 0, INCONCLUSIVE: 1, "error": 0}
    assert requirement_verdict("RT-LAT-1", [r], s.name) == INCONCLUSIVE
    assert requirement_verdict("RT-DL-1", [r], s.name) == PASS
    text = line(r)
    assert text.startswith("INCONCLUSIVE  realtime-timing/T0.05") and "inconclusive RT-LAT-1: " in text
    junit([r], [s], tmp_path / "j.xml", "host")
    (ts,) = ET.parse(tmp_path / "j.xml").getroot().findall("testsuite")
    assert (ts.get("failures"), ts.get("skipped")) == ("0", "1")
    assert ts.find("testcase/skipped").get("message").startswith("inconclusive: RT-LAT-1: ")


def sync_summary(loss_verdict: str, step_refused: int = 0) -> dict[str, Any]:
    out = realtime_summary(late_steps=5)      # the schedule slipped too: it does not excuse a sync failure
    out["platform"]["sync_loss"] = {"verdict": loss_verdict, "message": "platform-limited (cyclictest max "
                                                                        "122481 us at fcc's priority, ...)"}
    out["sync"] = {"refused": {"step_refused": step_refused, "rate_refused": 0}}
    return out


def test_a_sync_requirement_is_excused_only_by_a_sync_loss_the_platform_explains():
    why = limited(sync_summary("platform-limited"), "sync")
    assert why.startswith("platform-limited: fcc's sync loss(es) are the platform's: platform-limited (cyclictest")
    assert limited(sync_summary("firmware"), "sync") == ""
    assert limited(sync_summary("none"), "sync") == ""        # no loss: a refusal, a slow lock
    # a master refused as implausible is the sync's own failure (the M4F image over its serial
    # link refuses every pair on a clean bus): never excused, whatever the platform did
    assert limited(sync_summary("platform-limited", step_refused=78), "sync") == ""
    hold = [Check("TS-HOLD-1", "sync.verdict.ok == 1", FAIL, "sync.verdict.ok = 0")]
    assert [c.verdict for c in against_platform(hold, shipped("time-sync").timing,
                                                sync_summary("none"))] == [FAIL]
    assert [c.verdict for c in against_platform(hold, shipped("time-sync").timing,
                                                sync_summary("platform-limited"))] == [INCONCLUSIVE]


def test_a_bad_timing_kind_is_refused_at_load(tmp_path):
    text = suite.shipped()["time-sync"].read_text().replace('timing = "sync"', 'timing = "always"', 1)
    p = tmp_path / "s.toml"
    p.write_text(text)
    with pytest.raises(suite.SuiteError, match=r"requirement\[0\]: field 'timing': 'schedule' or 'sync', got 'always'"):
        suite.load(p)


def test_every_realtime_timing_requirement_is_judged_against_the_platform_and_no_security_one():
    assert shipped("realtime-timing").timing == {"RT-RIG-1": "schedule", "RT-LAT-1": "schedule", "RT-DL-1": "schedule",
                                                 "RT-DL-2": "schedule", "RT-AGE-1": "schedule", "RT-SYNC-1": "sync"}
    ts = shipped("time-sync")
    assert ts.timing == {"TS-LOCK-1": "sync", "TS-HOLD-1": "sync", "TS-HOLD-2": "sync"}
    assert not {"TS-SEC-1", "TS-SEC-2"} & set(ts.timing)


def test_a_timing_figure_the_target_does_not_report_fails_its_check_not_the_run():
    """The Cortex-M4F image's summary has no own-clock latency (realtime.fcc is {}): inf, which
    no bound holds -- a failed check, not a case that could not run (it was: a KeyError)."""
    from hil.verify.fields import NEVER, values
    run = {"summary": {"realtime": {"fcc": {}, "bus": {"data_age": {"p99": None, "n": 0}}}}}
    assert values(run, {"realtime.latency_p99_us", "realtime.data_age_p99_us"}) == \
        {"realtime.latency_p99_us": NEVER, "realtime.data_age_p99_us": NEVER}
