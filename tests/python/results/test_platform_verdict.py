"""Realtime verdicts that know the platform (hil.results.platform, hil.rig.platform, issue 37):
a recovered sync loss with nothing forged, replayed or refused is a warning and exit 0, every
attack still exit 7; a deadline miss within what the platform's baseline shows is
platform-limited, beyond it the firmware's own.  Synthetic summaries, as hil.results.sync and
hil.runs.evaluate write them; the baseline from a real cyclictest where it is installed."""
from __future__ import annotations

import copy
import shutil
from collections import Counter
from pathlib import Path
from typing import Any

import pytest
from hil.cli.common import sync_status
from hil.cli.usage import EXIT_SYNC
from hil.results.platform import FIRMWARE, PLATFORM_LIMITED, platform_verdict
from hil.results.sync import REFUSALS
from hil.rig.platform import Baseline, facts, percentile, preempt_model
from hil.rig.timesync import SYNC_INTERVAL_S, UsablePairs
from hil.runs.outcome import Outcome

PERIOD_S = 0.1
#: 25 wake-ups at 10 ms take 0.25 s; a deadline, not a duration: a loaded machine may take longer
CYCLES_DEADLINE_S = 60.0
NO_REFUSALS = dict.fromkeys(REFUSALS, 0)


def summary(*, losses: int = 0, state: str = "LOCKED", verdict: str = "ok", refused: dict | None = None,
            overruns: int = 0, missing: int = 0, age_max: float = 2000.0, trust: str = "ok") -> dict[str, Any]:
    """A realtime missile run's summary.json, the parts the platform verdict reads."""
    message = {"ok": "", "lost": f"time sync lost: {losses} losses (fcc {state} at the end)",
               "attacked": "time sync attacked: 4 forged SYNC/FOLLOW_UP frames, 2 forged and 0 "
                           "replayed TSYNC_AUTH refused",
               "refused": "time master refused: 3 authenticated SYNC/FOLLOW_UP pairs implausible"}[verdict]
    return {"mode": "realtime", "firmware": {"overruns": overruns},
            "missile": {"runs": [{"commands_missing": missing}, {}]},
            "realtime": {"bus": {"data_age": {"n": 50, "p50": 900.0, "p99": age_max, "max": age_max}},
                         "fcc": {"latency_us missile": {"n": 50, "p50": 400, "p99": 900, "max": 1200}}},
            "sync": {"state": state, "losses": losses, "refused": refused or dict(NO_REFUSALS),
                     "master_unpaired_frames": 0, "verdict": verdict, "message": message},
            "bus_trust": {"verdict": trust, "message": "" if trust == "ok" else "fcc's outputs forged"}}


def info(max_us: int | None = 4000, no_echo: int = 0, late_steps: int = 0, gap_ms: float = 101.0,
         pair_gap_ms: float | None = None, slack_min_ms: float = 12.0) -> dict[str, Any]:
    """run_info.json's parts the verdict reads; the master's pair gap (from the SYNC of one
    usable pair to the next pair's last frame) is at least its longest SYNC gap."""
    base = ({"p50_us": 300, "p99_us": 2000, "max_us": max_us, "cycles": 50} if max_us is not None
            else {"error": "cyclictest not found: install rt-tests (scripts/setup does)"})
    return {"sim_late_steps": late_steps, "sim_handover_slack_ms": {"min": slack_min_ms},
            "time_master": {"syncs_without_echo": no_echo, "max_sync_gap_ms": gap_ms,
                            "max_pair_gap_ms": gap_ms if pair_gap_ms is None else pair_gap_ms},
            "platform": {"kernel": "7.2.7", "preempt": "none (voluntary or server)", "uml": True,
                         "baseline": base}}


def judged(s: dict[str, Any], i: dict[str, Any] | None = None) -> dict[str, Any]:
    s = copy.deepcopy(s)
    s["platform"] = platform_verdict(s, info() if i is None else i, PERIOD_S)
    return s


def exit_status(s: dict[str, Any], capsys: Any) -> tuple[int, str]:
    rc = sync_status([Outcome(Path("run"), s)])
    return rc, capsys.readouterr().err


def test_a_recovered_sync_loss_without_attack_is_a_warning_with_its_numbers_exit_0(capsys) -> None:
    s = judged(summary(losses=1, verdict="lost"))
    loss = s["platform"]["sync_loss"]
    assert loss["tolerated"] and loss["losses"] == 1 and loss["data_age_max_us"] == 2000.0
    rc, err = exit_status(s, capsys)
    assert rc == 0
    assert err == ("hil: warning: time sync lost 1 time(s) and recovered (fcc LOCKED at the end): no "
                   "forged, replayed or refused frame, data age max 2000 us < 204000 us (fcc's freshness "
                   "bound 200000 us + the platform's stall); "
                   "firmware (cyclictest max 4000 us at fcc's priority, 0 SYNC(s) the master could "
                   "not stamp, fcc's longest wait for a usable pair 101 ms)\n")


@pytest.mark.parametrize("verdict, refused", [
    ("attacked", {**NO_REFUSALS, "unauthenticated": 4, "mac_failed": 2}),       # forged
    ("attacked", {**NO_REFUSALS, "freshness_failed": 3}),                       # replayed
    ("refused", {**NO_REFUSALS, "step_refused": 3}),                            # implausible
])
def test_a_sync_loss_with_a_forged_replayed_or_refused_frame_still_exits_7(verdict, refused, capsys) -> None:
    s = judged(summary(losses=1, verdict=verdict, refused=refused))
    assert not s["platform"]["sync_loss"]["tolerated"]
    rc, err = exit_status(s, capsys)
    assert rc == EXIT_SYNC and err.startswith(f"hil: {s['sync']['message']}")


@pytest.mark.parametrize("change", [
    {"state": "HOLDOVER"},          # not recovered at the end
    {"state": "FREE_RUN"},
    {"age_max": 250_000.0},         # on data fcc takes as stale, beyond the platform's stall
    {"trust": "forged"},            # fcc's outputs not authentic: nothing is excused
])
def test_a_loss_not_recovered_or_with_stale_data_or_forged_outputs_exits_7(change, capsys) -> None:
    s = judged(summary(losses=1, verdict="lost", **change))
    assert not s["platform"]["sync_loss"]["tolerated"]
    rc, err = exit_status(s, capsys)
    assert rc == EXIT_SYNC and err.startswith("hil: time sync lost: 1 losses")
    # the line says whose the loss is and why it is not a warning
    assert "; firmware (cyclictest max 4000 us at fcc's priority, 0 SYNC(s) the master could not " \
           "stamp, fcc's longest wait for a usable pair 101 ms); not tolerated: " in err


def test_a_loss_in_a_platform_stall_the_baseline_shows_is_tolerated(capsys) -> None:
    """As measured (a default realtime missile run at load 8-10): cyclictest woke 368 ms late,
    2 losses, fcc LOCKED at the end, one command on data 201 ms old (fcc's freshness bound 200
    ms): the stall explains the age, a warning, exit 0."""
    s = judged(summary(losses=2, verdict="lost", age_max=201_182.0), info(max_us=368_592))
    rc, err = exit_status(s, capsys)
    assert rc == 0 and s["platform"]["sync_loss"]["verdict"] == PLATFORM_LIMITED
    assert "data age max 201182 us < 568592 us (fcc's freshness bound 200000 us + the platform's stall)" in err


def test_the_rigs_own_stall_widens_the_bound_too(capsys) -> None:
    """As measured: the rig's master (an ordinary thread) went 324 ms without a SYNC while
    cyclictest at fcc's priority saw 119 ms; a command on data 324 ms old: the rig's stall
    (224 ms beyond the interval) explains it, a warning."""
    s = judged(summary(losses=1, verdict="lost", age_max=324_376.0), info(max_us=118_781, gap_ms=324.0))
    rc, err = exit_status(s, capsys)
    assert rc == 0 and s["platform"]["sync_loss"]["data_age_bound_us"] == pytest.approx(424_000)


def test_the_simulators_own_lateness_widens_the_bound_too(capsys) -> None:
    """As measured at load 12.6: the rig's simulator handed a step over 2836 ms late (60 of 100
    late), cyclictest 109 ms, the master's longest gap 283 ms; commands on data up to 1.1 s
    old, nothing forged: platform-limited, a warning."""
    s = judged(summary(losses=1, verdict="lost", age_max=1_101_745.0),
               info(max_us=108_667, gap_ms=283.0, slack_min_ms=-2835.962, late_steps=60))
    assert exit_status(s, capsys)[0] == 0
    assert s["platform"]["sync_loss"]["platform_stall_us"] == pytest.approx(2_835_962)


def test_data_older_than_the_platform_explains_is_not_tolerated(capsys) -> None:
    """Data older than fcc's freshness bound plus every stall measured: exit 7, and the line
    says whose the loss is and why it is not a warning."""
    s = judged(summary(losses=1, verdict="lost", age_max=1_003_456.0),
               info(max_us=14_678, gap_ms=350.0, pair_gap_ms=420.0))
    rc, err = exit_status(s, capsys)
    assert rc == EXIT_SYNC and s["platform"]["sync_loss"]["verdict"] == PLATFORM_LIMITED
    assert err == ("hil: time sync lost: 1 losses (fcc LOCKED at the end); platform-limited (cyclictest "
                   "max 14678 us at fcc's priority, 0 SYNC(s) the master could not stamp, fcc's longest "
                   "wait for a usable pair 420 ms); not tolerated: data age max 1003456 us beyond "
                   "450000 us (fcc's freshness bound 200000 us + the platform's stall)\n")


def test_the_data_age_bound_is_fccs_own_freshness_bound() -> None:
    """fcc bridges --stale-limit missing frames (default 1) with the last value: a command on
    data up to 1 + that many periods old is computed on data fcc takes as fresh."""
    s = summary(losses=1, verdict="lost", age_max=150_000.0)
    assert judged(s)["platform"]["sync_loss"]["tolerated"]
    strict = {**info(), "fcc_command": "fcc --mode realtime --stale-limit 0 --rt-priority 50"}
    got = judged(s, strict)["platform"]["sync_loss"]
    assert got["data_age_fresh_us"] == 100_000 and got["data_age_bound_us"] == 104_000
    assert not got["tolerated"]


def test_a_clean_run_is_ok_and_exits_0(capsys) -> None:
    s = judged(summary())
    assert s["platform"]["verdict"] == "ok" and s["platform"]["baseline"]["max_us"] == 4000
    assert s["platform"]["deadline_misses"]["verdict"] == "none"
    assert exit_status(s, capsys) == (0, "")


def test_a_deadline_miss_within_the_baselines_max_is_platform_limited() -> None:
    """The period is 100 ms, fcc's median step 0.4 ms: the slack is 99.6 ms.  A platform that
    itself woke a thread of fcc's priority 120 ms late explains an overrun; one whose worst
    was 4 ms does not (the firmware's own)."""
    s = summary(overruns=2)
    got = judged(s, info(max_us=120_000))["platform"]
    assert got["deadline_misses"]["verdict"] == PLATFORM_LIMITED and got["verdict"] == PLATFORM_LIMITED
    assert got["deadline_misses"]["slack_us"] == pytest.approx(99_600)
    assert judged(s, info(max_us=4000))["platform"]["verdict"] == FIRMWARE
    assert judged(s, info(max_us=None))["platform"]["verdict"] == FIRMWARE   # nothing measured: no excuse


def test_lost_commands_in_a_stall_of_the_rigs_own_threads_are_platform_limited() -> None:
    """The M4F image at host load 3-4 (2026-12-02): 17 commands missing, the simulator 9 steps
    late, cyclictest's worst 4.3 ms -- but the rig's time master went 1.05 s between SYNCs (a
    stall of 950 ms beyond its interval): the platform's.  The same misses with the rig's
    threads on time are the firmware's; so is an overrun in that stall (fcc's own computation,
    at a priority the rig's threads do not have); with no baseline measured, nothing is excused."""
    s = summary(missing=17)
    stalled = info(max_us=4262, late_steps=9, gap_ms=1050.0)
    got = judged(s, stalled)["platform"]["deadline_misses"]
    assert got["verdict"] == PLATFORM_LIMITED and got["rig_stall_us"] == pytest.approx(950_000)
    assert judged(s, info(max_us=4262, late_steps=9))["platform"]["deadline_misses"]["verdict"] == FIRMWARE
    assert judged(summary(missing=17, overruns=1), stalled)["platform"]["deadline_misses"]["verdict"] == FIRMWARE
    assert judged(s, info(max_us=None, late_steps=9, gap_ms=1050.0))["platform"]["verdict"] == FIRMWARE


def test_lost_commands_the_late_simulator_explains_are_platform_limited() -> None:
    s = summary(missing=3)
    assert judged(s, info(late_steps=3))["platform"]["deadline_misses"]["verdict"] == PLATFORM_LIMITED
    assert judged(s, info(late_steps=2))["platform"]["deadline_misses"]["verdict"] == FIRMWARE


def test_a_sync_loss_is_platform_limited_when_the_platform_held_a_sync_interval() -> None:
    s = summary(losses=1, verdict="lost")
    assert judged(s, info(no_echo=1))["platform"]["sync_loss"]["verdict"] == PLATFORM_LIMITED
    assert judged(s, info(max_us=100_000))["platform"]["sync_loss"]["verdict"] == PLATFORM_LIMITED
    assert judged(s, info(max_us=4000))["platform"]["sync_loss"]["verdict"] == FIRMWARE
    # as measured: the rig's master (an ordinary thread) starved for 1 s, cyclictest at fcc's
    # priority saw 15 ms
    assert judged(s, info(max_us=14_678, gap_ms=1004.0))["platform"]["sync_loss"]["verdict"] == PLATFORM_LIMITED
    assert judged(s, info(max_us=14_678, gap_ms=250.0))["platform"]["sync_loss"]["verdict"] == FIRMWARE


#: the incident of issue 37 (hil verify time-sync, case foreign-master, host load 9.5-14.6), from
#: the bus log: the rig's master sent SYNC 51 at 5.6057 s, SYNC 52 at 5.7383 s, stalled, sent 52's
#: FOLLOW_UP at 5.9147 s and its TSYNC_AUTH at 5.9383 s, and SYNC 53 276 ms after SYNC 52 (the
#: longest SYNC gap); pairs 51 and 53 complete 0.3 ms after their SYNC.  fcc dropped pair 52
#: (missing_fup=1 orphan_fup=1) and lost the sync; cyclictest's max was 83.6 ms.
INCIDENT_PAIRS = [(5.6057, 5.6060), (5.7383, 5.9383), (5.7383 + 0.276, 5.7383 + 0.2763)]
INCIDENT_CYCLICTEST_US = 83_600


def incident_info(pairs: list[tuple[float, float]]) -> dict[str, Any]:
    """run_info.json of the incident, the master's pair gap as hil.rig.timesync records it."""
    waits = UsablePairs(SYNC_INTERVAL_S)
    for sync_tx, done in pairs:
        waits.complete(sync_tx, done)
    return info(max_us=INCIDENT_CYCLICTEST_US, gap_ms=276.0, pair_gap_ms=round(waits.longest() * 1e3))


def test_a_sync_loss_of_a_master_stalled_between_sync_and_follow_up_is_the_platforms() -> None:
    """Every SYNC gap under 3 intervals, cyclictest under one: only the wait for a usable pair
    shows the master starved fcc of the sync (409 ms from SYNC 51 to pair 53 complete)."""
    loss = judged(summary(losses=1, verdict="lost"), incident_info(INCIDENT_PAIRS))["platform"]["sync_loss"]
    assert loss["master_max_sync_gap_ms"] == 276.0 and loss["master_max_pair_gap_ms"] == 409
    assert loss["verdict"] == PLATFORM_LIMITED and loss["tolerated"]
    assert "fcc's longest wait for a usable pair 409 ms" in loss["message"]
    # the same SYNCs with pair 52 complete in time: fcc had a pair every 276 ms at worst, a loss
    # is the firmware's own
    on_time = [INCIDENT_PAIRS[0], (5.7383, 5.7386), INCIDENT_PAIRS[2]]
    loss = judged(summary(losses=1, verdict="lost"), incident_info(on_time))["platform"]["sync_loss"]
    assert loss["master_max_pair_gap_ms"] == 276 and loss["verdict"] == FIRMWARE


def test_a_sync_loss_a_slow_link_explains_with_the_masters_wait_is_the_platforms() -> None:
    """The M4F image's incident (hil verify time-sync --target qemu-m4f, replayed-master, idle
    host, 2026-12-02): the master's longest wait for a usable pair 258 ms and its serial line
    held a frame up to 145 ms beyond its fastest delivery -- the pair reached the image more than
    3 intervals after the last: the platform's.  Without the link's delay, or on a device with no
    link (the host fcc), 258 ms is the firmware's loss."""
    def loss_with(link: dict[str, int] | None) -> dict[str, Any]:
        s = summary(losses=1, verdict="lost")
        if link is not None:
            s["realtime"]["fcc"]["link"] = link
        return judged(s, info(max_us=3023, gap_ms=258.0, pair_gap_ms=258.0))["platform"]["sync_loss"]
    loss = loss_with({"bus_delay_us_worst": 144_895, "line_us_mean": 4242})
    assert loss["verdict"] == PLATFORM_LIMITED and loss["link_delay_worst_ms"] == pytest.approx(144.895)
    assert "fcc's longest wait for a usable pair 258 ms + its link's worst delay 145 ms" in loss["message"]
    assert loss_with({"bus_delay_us_worst": 30_000})["verdict"] == FIRMWARE
    assert loss_with(None)["verdict"] == FIRMWARE


@pytest.mark.parametrize("verdict, refused", [
    ("attacked", {**NO_REFUSALS, "unauthenticated": 4, "mac_failed": 2}),       # forged
    ("attacked", {**NO_REFUSALS, "freshness_failed": 3}),                       # replayed
    ("refused", {**NO_REFUSALS, "step_refused": 3}),                            # implausible
])
def test_an_attack_during_a_master_stall_still_exits_7(verdict, refused, capsys) -> None:
    """The master's stall makes the loss the platform's, never the attack: exit 7 all the same."""
    s = judged(summary(losses=1, verdict=verdict, refused=refused), incident_info(INCIDENT_PAIRS))
    loss = s["platform"]["sync_loss"]
    assert loss["verdict"] == PLATFORM_LIMITED and not loss["tolerated"]
    rc, err = exit_status(s, capsys)
    assert rc == EXIT_SYNC and err.startswith(f"hil: {s['sync']['message']}")


def test_preempt_model_from_the_kernels_build_string() -> None:
    assert preempt_model("#1 SMP PREEMPT_RT Tue Jan 2", None) == "PREEMPT_RT"
    assert preempt_model("#1 SMP PREEMPT_DYNAMIC @0", "0") == "PREEMPT_DYNAMIC"
    assert preempt_model("#1 SMP PREEMPT Fri", None) == "PREEMPT"
    assert preempt_model("#1 SMP Fri Sep 25", "1") == "PREEMPT_RT"
    assert preempt_model("#1 Fri Sep 25 16:07:24 UTC 2026", None) == "none (voluntary or server)"
    f = facts()
    assert f["kernel"] and f["preempt"] and isinstance(f["uml"], bool) and len(f["load_average"]) == 3


def test_percentiles_of_a_histogram_with_overflows() -> None:
    h = Counter({10: 50, 20: 48, 30: 1})
    assert percentile(h, 1, 900, 0.5) == 10 and percentile(h, 1, 900, 0.99) == 30
    assert percentile(h, 1, 900, 1.0) == 900        # the overflow: at the measured maximum
    assert percentile(Counter(), 0, 0, 0.5) is None


@pytest.mark.skipif(shutil.which("cyclictest") is None, reason="rt-tests not installed")
def test_the_baseline_is_cyclictests_measurement_in_its_histogram_format(tmp_path) -> None:
    b = Baseline(0.01, 50)
    for _ in range(2):   # two flights of a session add up: 25 wake-ups each, counted, not timed
        b.start(loops=25)
        assert b.wait(CYCLES_DEADLINE_S), f"cyclictest had not made 25 wake-ups in {CYCLES_DEADLINE_S} s"
    got = b.summary()
    if "error" in got and not got.get("cycles"):
        pytest.skip(f"cyclictest cannot run here: {got['error']}")
    assert got["interval_us"] == 10_000 and got["priority"] == 50 and got["cycles"] == 50
    assert got["min_us"] <= got["p50_us"] <= got["p99_us"] <= got["max_us"]
    assert sum(got["histogram"].values()) + got["overflows"] == got["cycles"]
    lines = b.write_hist(tmp_path).read_text().splitlines()   # type: ignore[union-attr]
    assert lines[0] == "# Histogram"
    rows = [ln.split() for ln in lines if not ln.startswith("#")]
    assert {int(us): int(n) for us, n in rows} == {int(k): v for k, v in got["histogram"].items()}
    assert f"# Max Latencies: {got['max_us']:05d}" in lines
    assert f"# Total: {got['cycles'] - got['overflows']:09d}" in lines
