"""The time master's record of fcc's wait for a usable pair (hil.rig.timesync.UsablePairs,
run_info.json's time_master.max_pair_gap_ms, issue 37): what hil.results.platform judges a sync
loss by.  fcc holds a SYNC until its pair's authenticator verifies and drops it one interval
after it was on the bus (fcc_tsync_poll), so a pair completed later is no use to it, and the
wait runs from the last usable pair's SYNC.  Synthetic bus times, host-only."""
from __future__ import annotations

import pytest

from hil.rig.timesync import SYNC_INTERVAL_S, UsablePairs


def waits(pairs: list[tuple[float, float]]) -> UsablePairs:
    w = UsablePairs(SYNC_INTERVAL_S)
    for sync_tx, done in pairs:
        w.complete(sync_tx, done)
    return w


def test_the_wait_runs_from_one_usable_sync_to_the_next_pair_complete() -> None:
    w = waits([(1.0, 1.001), (1.1, 1.102), (1.2, 1.2005)])
    assert w.longest() == pytest.approx(0.102)


def test_a_pair_completed_more_than_an_interval_after_its_sync_is_no_use_to_fcc() -> None:
    """The master stalled between SYNC 2 and its FOLLOW_UP: SYNCs 130 and 270 ms apart, but fcc
    had no usable pair from SYNC 1 until pair 3 was complete, 401 ms (its loss after 300)."""
    w = waits([(1.0, 1.0003), (1.13, 1.33), (1.4, 1.401)])
    assert w.longest() == pytest.approx(0.401)
    # completed within one interval of its SYNC: fcc uses it
    assert waits([(1.0, 1.0003), (1.13, 1.229), (1.4, 1.401)]).longest() == pytest.approx(0.271)


def test_a_wait_not_over_counts_up_to_now_and_nothing_before_the_first_usable_pair() -> None:
    w = waits([(5.0, 5.3), (5.4, 5.4002)])   # the first pair late: no wait from before it
    assert w.longest() == 0.0
    assert w.longest(now=5.75) == pytest.approx(0.35)   # the master silent since SYNC 5.4
    assert w.longest() == 0.0                          # an open wait is not kept
    assert UsablePairs(SYNC_INTERVAL_S).longest(now=9.0) == 0.0
