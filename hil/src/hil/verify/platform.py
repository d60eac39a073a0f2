"""A realtime case's timing requirements, judged against the platform it flew on.

A requirement marked ``timing`` in its suite is about deadlines, latencies, data age or the time
sync: what a platform that cannot keep its schedule breaks whatever the firmware does (a
User-Mode Linux guest on a shared host is not a realtime kernel).  When such a requirement fails
in a realtime run whose platform did not keep its schedule -- the evidence of summary.json's
``platform`` (hil.results.platform: cyclictest beside the flight at its period and fcc's
priority) -- the check is **inconclusive**, with that evidence, not a pass and not a firmware
failure.  Two kinds, each excused only by its own evidence:

``timing = "sync"`` (fcc locks on the master and holds it): only a sync loss hil.results.platform
judges the platform's (cyclictest's wake-up of a whole sync interval, a SYNC the master could not
stamp, the master's own starved thread leaving fcc 3 intervals without a usable pair), with no
pair refused as implausible (``step_refused``, ``rate_refused``: a refused master is the sync's
own failure, never a schedule's -- measured: the Cortex-M4F image over its serial link refuses
every pair on a clean bus, and no stall excuses that).

``timing = "schedule"`` (deadlines, latencies, data age, the residual), when

* the run's platform verdict is ``platform-limited`` (a deadline miss or sync loss the
  baseline or the rig's own starved threads explain),
* or cyclictest's worst wake-up at fcc's priority reached a tenth of the period (SCHEDULE_SHARE:
  the actuation instant, 5 ms at T = 0.05 s) or the step's slack (the period less fcc's median
  sensor-to-command time): a realtime schedule nothing running at that priority could keep
  (measured, 2 cores at load 1-4: a 48 ms wake-up at T = 0.05 s, and fcc's latency p99 55 ms
  in the same flight, every command still before the next sampling instant),
* or the platform's worst stall during the flight (hil.results.platform's: cyclictest's, or a
  thread of the rig's -- its time master's longest gap beyond the sync interval, its
  simulator's latest hand-over) reached that bound too (measured, 2 cores at load 1: the
  master's thread 35 ms late while cyclictest saw 3.7 ms),
* or the rig's transmitter (SCHED_FIFO) sent a sensor frame after fcc's latest release of the
  step (RELEASE_MS after its instant: docs/firmware.md, Realtime mode): fcc computes that step
  on the previous frame whatever it does (measured: a frame 5.9 ms late, data age 53 ms at
  T = 0.05 s),
* or the rig's simulator handed steps over after their instant (the rig, an ordinary process
  on the same platform, lost its own schedule: the case measured the platform).

Nothing excuses a failure when the platform's verdict is ``firmware`` (the baseline does not
explain the misses), when no baseline was measured (no cyclictest: no excuse), in a lockstep
case, or for a requirement not marked ``timing`` (an attack refused, a counter, a result).
`hil verify` counts an inconclusive case apart and exits 0 for it with a warning line (hil.cli.verify).
"""
from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from hil.results.platform import FIRMWARE, PLATFORM_LIMITED, field_at

INCONCLUSIVE = "inconclusive"
#: what a requirement's `timing` may say: the evidence that excuses its failure
KINDS = ("schedule", "sync")
#: a wake-up later than this share of the period: the platform did not keep a realtime schedule
SCHEDULE_SHARE = 0.1
#: fcc releases the autopilot's step at the latest this long after its sampling instant (ms):
#: a sensor frame sent later is used a step late (docs/firmware.md, Realtime mode)
RELEASE_MS = 3.5


def limited(summary: Mapping[str, Any], kind: str = "schedule") -> str:
    """Why this realtime run's platform did not keep its schedule as a requirement of this kind
    needs it, with its figures ('' : it did, or nothing shows it did not)."""
    verdict = field_at(summary, "platform", "verdict")
    base = field_at(summary, "platform", "baseline") or {}
    max_us = base.get("max_us")
    if verdict == FIRMWARE or max_us is None:
        return ""
    found = _sync_evidence(summary) if kind == "sync" else _schedule_evidence(summary, verdict, max_us)
    if not found:
        return ""
    return (f"platform-limited: {'; '.join(found)} (cyclictest at fcc's priority: p50 {base.get('p50_us')} us, "
            f"p99 {base.get('p99_us')} us, max {max_us} us over {base.get('cycles')} cycles)")


def _sync_evidence(summary: Mapping[str, Any]) -> list[str]:
    """A sync loss the platform explains, nothing refused as implausible."""
    loss = field_at(summary, "platform", "sync_loss") or {}
    refused = field_at(summary, "sync", "refused") or {}
    if loss.get("verdict") != PLATFORM_LIMITED or refused.get("step_refused") or refused.get("rate_refused"):
        return []
    return [f"fcc's sync loss(es) are the platform's: {loss.get('message') or 'hil.results.platform'}"]


def _schedule_evidence(summary: Mapping[str, Any], verdict: Any, max_us: float) -> list[str]:
    """What shows the platform did not keep the step's schedule (module doc)."""
    bound = _schedule_bound(summary)
    late = int(field_at(summary, "realtime", "simulator", "late_steps") or 0)
    stall = float(field_at(summary, "platform", "sync_loss", "platform_stall_us") or 0)
    tx_late_ms = float(field_at(summary, "realtime", "simulator", "transmitter", "send_lateness_ms", "max") or 0)
    return [why for shown, why in (
        (verdict == PLATFORM_LIMITED, "the run's deadline misses or sync loss are the platform's"),
        (bound is not None and max_us >= bound, f"cyclictest's worst wake-up reached {bound:.0f} us (a tenth "
                                                f"of the period, or the step's slack)"),
        (bound is not None and stall >= bound > max_us, f"a thread of the rig's stalled {stall:.0f} us (its "
                                                        f"time master's or simulator's: hil.results.platform)"),
        (tx_late_ms >= RELEASE_MS, f"the rig's transmitter sent a sensor frame {tx_late_ms:.1f} ms after its "
                                   f"instant, after fcc's latest release ({RELEASE_MS} ms)"),
        (late > 0, f"the rig's simulator sent {late} step(s) after their instant"),
    ) if shown]


def _schedule_bound(summary: Mapping[str, Any]) -> float | None:
    """The latest wake-up a realtime schedule at this period allows (us): the smaller of
    SCHEDULE_SHARE of the period and the step's slack (None: neither known)."""
    runs = field_at(summary, "missile", "runs") or [{}]
    period = runs[0].get("period") if isinstance(runs[0], Mapping) else None
    known = [b for b in (field_at(summary, "platform", "deadline_misses", "slack_us"),
                         None if period is None else round(SCHEDULE_SHARE * float(period) * 1e6)) if b is not None]
    return min(known) if known else None
