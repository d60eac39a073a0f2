"""fcc's system calls per lockstep step, counted by strace(1) during real flights on vcan0.

Under User-Mode Linux a system call costs about as much as a step's arithmetic, so how many
fcc makes per step is behaviour, not speed: a count, the same on any machine.  A step is the
wait (poll), one receive of the step's frames (recvmmsg), one send of its answer (sendmmsg),
and the step's clock reads.  Under strace every clock read is a real clock_gettime (the
time-stamp counter's anchor, fcc_hostclock.h, ages past its 5 ms between the slowed steps), so
the clock's share counted here is its worst case: the node's two reads around the step, and
the command's send stamp on a missile step -- no further read in the loop (fcc_main.c).
Heartbeats are turned off (--status-rate 0): they come by the wall clock, which strace slows.
"""
from __future__ import annotations

import collections
import re
import shutil
from pathlib import Path

import pytest

from hil.scenario.file import load_default_scenario
from rig_helpers import fly

pytestmark = [pytest.mark.vcan,
              pytest.mark.skipif(shutil.which("strace") is None, reason="strace is not installed")]

#: the default flights' steps
STEPS = {"cdrw": 351, "missile": 100}
#: the step's own calls: the wait, one receive, one send
IO_PER_STEP = 3
#: the clock reads of a step at worst (strace): CDRW two, missile three (its command's send stamp)
CLOCK_PER_STEP = {"cdrw": 2, "missile": 3}
#: set-up, the control frames before the first tick, and the ends, spread over the steps
SLACK_PER_STEP = 0.2

_CALL = re.compile(r"^([a-z_0-9]+)\(")


def traced_fcc(bin_path, tmp_path: Path) -> tuple[Path, Path]:
    """A firmware path that runs the real fcc under strace; (the path, its trace).  Both in
    SCHED_BATCH from the start, as the rig puts fcc (hil.util.processes.run_as_batch: it
    reaches strace, fcc's parent, only once fcc runs)."""
    trace = tmp_path / "fcc.strace"
    wrapper = tmp_path / "fcc-under-strace"
    wrapper.write_text(f'#!/bin/sh\nexec chrt --batch 0 strace -o "{trace}" "{bin_path("fcc")}" "$@"\n')
    wrapper.chmod(0o755)
    return wrapper, trace


def calls_in_flight(trace: Path) -> collections.Counter[str]:
    """The calls from the first receive to the last send: the lockstep flight (the start-up and
    the exit left out)."""
    calls = [m.group(1) for line in trace.read_text().splitlines() if (m := _CALL.match(line))]
    first = calls.index("recvmmsg")
    last = len(calls) - 1 - calls[::-1].index("sendmmsg")
    return collections.Counter(calls[first:last + 1])


@pytest.mark.parametrize("app", ["cdrw", "missile"])
def test_fcc_makes_at_most_its_steps_system_calls(app, bin_path, tmp_path):
    fcc, trace = traced_fcc(bin_path, tmp_path)
    outcome = fly(tmp_path / "run", load_default_scenario(app), fcc_binary=fcc,
                  fcc_args=("--status-rate", "0"), timeout=30.0)
    steps = outcome.summary["firmware"]["steps"][app]
    assert steps == STEPS[app]   # every tick answered: the default flight, whole
    calls = calls_in_flight(trace)
    io = sum(n for name, n in calls.items() if name != "clock_gettime")
    # the kinds a step makes, and no other (no re-arming of the timer, no socket option, no
    # read of the timer, no second receive of an empty queue)
    assert set(calls) <= {"poll", "recvmmsg", "sendmmsg", "clock_gettime", "write"}, calls
    assert io <= (IO_PER_STEP + SLACK_PER_STEP) * steps, calls
    assert calls["clock_gettime"] <= (CLOCK_PER_STEP[app] + SLACK_PER_STEP) * steps, calls
    # fcc's own count of its clock reads (its exit summary) says the same: these reads, whether
    # the counter served them or clock_gettime did
    m = re.search(r"^fcc summary: clock reads=(\d+) real=(\d+) counter=(yes|no)$",
                  (outcome.out_dir / "fcc.log").read_text(), re.MULTILINE)
    assert m is not None
    reads, real = int(m.group(1)), int(m.group(2))
    assert real <= reads <= (CLOCK_PER_STEP[app] + SLACK_PER_STEP) * steps
