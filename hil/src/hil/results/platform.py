"""A realtime run's timing faults, told apart: the platform's or the firmware's?

The platform's baseline (hil.rig.platform: cyclictest at the flight's period and fcc's
SCHED_FIFO priority, beside the flight) says how late this kernel, during this run, woke a
thread of fcc's priority that does nothing.  summary.json's ``platform`` judges against it:

* a deadline miss -- fcc's overruns (a step not finished within its period, its own count) and
  the loop's lost commands (not on the bus before the period closed) -- is **platform-limited**
  when the baseline's worst wake-up alone used up the step's slack (the period less fcc's
  median sensor-to-command time, its own clock); lost commands (no overrun) also when the rig's
  simulator (an ordinary process on the same platform) handed at least as many steps over late,
  or when a thread of the rig's own (its time master, its simulator: rig_stall_us) stalled for
  the step's slack -- the loop is the rig's and the node's together (measured: the M4F image
  under QEMU lost 17 commands and never printed its summary while the rig's threads stalled
  950 ms and cyclictest, at fcc's priority in the same guest, saw 4.3 ms).  An overrun is fcc's
  own computation: only a stall at its priority (cyclictest's) explains it.
  Otherwise it is the firmware's own.
* a sync loss (fcc went 3 sync intervals without a usable pair) is platform-limited when the
  baseline's worst wake-up reached a whole sync interval, the rig's master could not stamp a
  SYNC (its echo never came: the platform held the frame), or the master itself went 3
  intervals without a usable pair (a thread of the rig's, starved by the platform: from the SYNC
  of one pair fcc could use to the last frame of the next, hil.rig.timesync; measured, 1 s
  while cyclictest at fcc's priority saw 15 ms, and a master that stalled 176 ms between a SYNC
  and its FOLLOW_UP: 276 ms between SYNCs, but no usable pair for fcc in 333 ms, its loss), or
  that wait and the device's own link together did (a device behind a serial line -- the M4F
  image -- gets a pair up to its line's worst delay beyond the fastest delivery later than the
  bus carried it: measured, a master's 258 ms and a line's 145 ms); otherwise the firmware's own.
* a sync loss that fcc recovered from (LOCKED at the end) with no forged, replayed or refused
  frame (the sync verdict is "lost", nothing worse: hil.results.sync), fcc's outputs
  authentic (bus_trust ok) and the data age in bounds is **tolerated**: every command computed
  on a sensor frame fcc itself takes as fresh (less than 1 + --stale-limit periods old, fcc
  bridging that many missing frames with the last value), or older by no more than the
  platform's worst stall during the flight: the baseline's max, the time the rig's own
  master went beyond its interval without a SYNC (its longest gap less one interval, from the
  kernel's stamps of its frames), or the simulator's latest hand-over of a step (after its
  instant: the rig's threads run at an ordinary priority and starve longer than cyclictest's;
  measured at load 8-12: the master 324 ms against cyclictest's 119 ms, the simulator 2.8 s
  against 109 ms).  These are clocks the bus cannot move: a frame held back or replayed ages
  the data beyond them: `hil run` prints a warning with its
  numbers and does not exit 7 for it (hil.cli.common.sync_status).  Every attack still does.
"""
from __future__ import annotations

import shlex
from collections.abc import Mapping
from typing import Any

from hil.rig.timesync import SYNC_INTERVAL_S

#: fcc loses the sync after this many sync intervals without a usable pair (fcc_tsync.c's
#: loss_intervals)
LOSS_INTERVALS = 3

PLATFORM_LIMITED, FIRMWARE = "platform-limited", "firmware"
#: fcc's --stale-limit when its command line gives none (firmware/app/fcc_node.h)
DEFAULT_STALE_LIMIT = 1


def field_at(doc: Any, *path: str) -> Any:
    """doc[path[0]][path[1]]...; None where a key or a mapping is missing (run files of
    older versions or other targets lack sections)."""
    for key in path:
        if not isinstance(doc, Mapping):
            return None
        doc = doc.get(key)
    return doc


def rig_stall_us(info: Mapping[str, Any]) -> float:
    """The longest a thread of the rig's own fell behind its schedule (us): its time master's
    longest gap between SYNCs less one interval, its simulator's latest hand-over of a step."""
    gap_ms = field_at(info, "time_master", "max_sync_gap_ms")
    master = 0.0 if gap_ms is None else max(0.0, gap_ms * 1e3 - SYNC_INTERVAL_S * 1e6)
    slack_min = field_at(info, "sim_handover_slack_ms", "min")
    simulator = 0.0 if slack_min is None else max(0.0, -slack_min * 1e3)
    return max(master, simulator)


def deadline_misses(summary: Mapping[str, Any], info: Mapping[str, Any], baseline_max: int | None,
                    period_us: float | None) -> dict[str, Any]:
    """fcc's overruns and the loop's lost commands, and whose they are (module doc)."""
    overruns = int(field_at(summary, "firmware", "overruns") or 0)
    runs = field_at(summary, "missile", "runs") or [{}]
    missing = int(runs[0].get("commands_missing") or 0)
    late_steps = int(info.get("sim_late_steps") or 0)
    step_p50 = field_at(summary, "realtime", "fcc", "latency_us missile", "p50") or 0
    slack = None if period_us is None else period_us - step_p50
    rig_stall = rig_stall_us(info)
    if baseline_max is None or slack is None:   # nothing measured: no excuse
        stalled = rig_stalled = False
    else:
        stalled, rig_stalled = baseline_max >= slack, rig_stall >= slack
    out: dict[str, Any] = {"overruns": overruns, "commands_missing": missing, "sim_late_steps": late_steps,
                           "slack_us": slack, "rig_stall_us": rig_stall, "verdict": "none"}
    if overruns or missing:
        explained = stalled or (not overruns and (rig_stalled or late_steps >= missing))
        out["verdict"] = PLATFORM_LIMITED if explained else FIRMWARE
    return out


def stale_limit(fcc_command: str | None) -> int:
    """fcc's --stale-limit (missing sensor frames bridged with the last value) from the command
    line run_info.json keeps."""
    try:
        args = shlex.split(fcc_command or "")
    except ValueError:
        args = []
    for flag, value in zip(args, args[1:]):
        if flag == "--stale-limit" and value.isdigit():
            return int(value)
    return DEFAULT_STALE_LIMIT


def sync_loss(summary: Mapping[str, Any], info: Mapping[str, Any], baseline_max: int | None,
              period_us: float | None) -> dict[str, Any]:
    """fcc's sync losses, whose they are, and whether the run tolerates them (module doc)."""
    sync = summary.get("sync") or {}
    losses = int(sync.get("losses") or 0)
    no_echo = int(field_at(info, "time_master", "syncs_without_echo") or 0)
    age = field_at(summary, "realtime", "bus", "data_age")
    age_max = age.get("max") if isinstance(age, Mapping) and age.get("n") else None
    gap_ms = field_at(info, "time_master", "max_sync_gap_ms")
    pair_gap_ms = field_at(info, "time_master", "max_pair_gap_ms")
    link_ms = float(field_at(summary, "realtime", "fcc", "link", "bus_delay_us_worst") or 0) / 1e3
    stall = max(float(baseline_max or 0), rig_stall_us(info))
    fresh = None if period_us is None else (1 + stale_limit(info.get("fcc_command"))) * period_us
    age_bound = None if fresh is None else fresh + stall
    out: dict[str, Any] = {"losses": losses, "state": sync.get("state"), "sync_verdict": sync.get("verdict"),
                           "master_syncs_without_echo": no_echo, "platform_stall_us": stall,
                           "data_age_max_us": age_max,
                           "data_age_fresh_us": fresh, "data_age_bound_us": age_bound, "verdict": "none",
                           "tolerated": False, "message": ""}
    if not losses:
        return out
    out["master_max_sync_gap_ms"] = gap_ms
    out["master_max_pair_gap_ms"] = pair_gap_ms
    out["link_delay_worst_ms"] = link_ms
    explained = (no_echo > 0
                 or (pair_gap_ms is not None and pair_gap_ms + link_ms >= LOSS_INTERVALS * SYNC_INTERVAL_S * 1e3)
                 or (baseline_max is not None and baseline_max >= SYNC_INTERVAL_S * 1e6))
    out["verdict"] = PLATFORM_LIMITED if explained else FIRMWARE
    age_ok = age_max is not None and age_bound is not None and age_max < age_bound
    not_tolerated = [why for bad, why in (
        (sync.get("verdict") != "lost", f"the sync was {sync.get('verdict')}"),
        (sync.get("state") != "LOCKED", f"fcc {sync.get('state')} at the end"),
        (field_at(summary, "bus_trust", "verdict") not in (None, "ok"), "fcc's outputs not authentic"),
        (not age_ok, "data age not measured" if age_max is None else
         f"data age max {age_max:.0f} us beyond {age_bound:.0f} us (fcc's freshness "
         f"bound {fresh:.0f} us + the platform's stall)"),
    ) if bad]
    out["tolerated"] = not not_tolerated
    base = (f"cyclictest max {baseline_max} us at fcc's priority" if baseline_max is not None
            else "no platform baseline")
    gap = "" if pair_gap_ms is None else f", fcc's longest wait for a usable pair {pair_gap_ms:.0f} ms"
    gap += f" + its link's worst delay {link_ms:.0f} ms" if link_ms else ""
    why = f"{out['verdict']} ({base}, {no_echo} SYNC(s) the master could not stamp{gap})"
    if out["tolerated"]:
        out["message"] = (f"warning: time sync lost {losses} time(s) and recovered (fcc LOCKED at "
                          f"the end): no forged, replayed or refused frame, data age max "
                          f"{age_max:.0f} us < {age_bound:.0f} us (fcc's freshness bound {fresh:.0f} us + the "
                          f"platform's stall); {why}")
    else:
        out["message"] = f"{why}; not tolerated: {', '.join(not_tolerated)}"
    return out


def platform_verdict(summary: Mapping[str, Any], info: Mapping[str, Any],
                     period_s: float | None) -> dict[str, Any]:
    """summary.json's `platform`: the baseline's percentiles, the deadline misses' and the sync
    losses' verdicts, and the run's (ok, platform-limited, firmware: the worst of them)."""
    base = field_at(info, "platform", "baseline") or {}
    baseline_max = base.get("max_us")
    period_us = None if period_s is None else period_s * 1e6
    parts = {"deadline_misses": deadline_misses(summary, info, baseline_max, period_us),
             "sync_loss": sync_loss(summary, info, baseline_max, period_us)}
    found = {p["verdict"] for p in parts.values()}
    verdict = FIRMWARE if FIRMWARE in found else PLATFORM_LIMITED if PLATFORM_LIMITED in found else "ok"
    return {"verdict": verdict,
            "baseline": {k: base.get(k) for k in ("p50_us", "p99_us", "max_us", "cycles")} if baseline_max is not None
            else {"error": base.get("error", "not measured")}, **parts}
