"""The one-line verdict printed first after every run (and by `hil report`), from its
summary.json: what flew (aircraft, scenario, mode, random seed), its faults (kind(target)@
start-end), the headline numbers, and PASS or FAIL against the paper where the paper has a
number for what flew:

* CDRW, one flight of the paper's scenario: Table 4, where the MLS-AZKF's α error is the
  lowest of the three filters (0.1073 against 0.1089 and 0.1956); held when fcc's AZKF has
  the lowest α error both against the fault-free measurement (the paper's measure) and
  against the true state.  A campaign of the paper's scenario: the same of Table 5's means
  (0.0895 against 0.0966 and 0.1686).  Any other scenario: no paper number (n/a).
* Missile: the paper (seed 2) gives curves, no number for one flight: n/a.

    lines(summary) -> ["verdict PASS | cdrw cdrw_default, lockstep, random seed 1 | ..."]

The same headline numbers, as named values, for `hil compare` (headline_metrics).
"""
from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from hil.results import metrics
from hil.results.faultwindows import flight_events, from_events

Summary = Mapping[str, Any]
NAMES = {"azkf": "AZKF", "zkf": "ZKF", "kf": "KF"}


def lines(summary: Summary) -> list[str]:
    """One verdict line per aircraft that flew (one for `hil run`); none for a summary
    without a flight (e.g. a study's)."""
    out = []
    if isinstance(summary.get("cdrw"), Mapping):
        out.append(_cdrw_line(summary))
    runs = (summary.get("missile") or {}).get("runs") or []
    if any(r.get("bits") is not None for r in runs):
        out.append(_missile_line(summary, runs))
    return out


def _what_flew(summary: Summary, aircraft: str, scenario: object, seed: object, extra: str = "") -> str:
    return (f"{aircraft} {scenario or '?'}, {summary.get('mode', '?')}, random seed {seed}"
            + (f", {extra}" if extra else ""))


def _faults(summary: Summary, aircraft: str) -> str:
    events = flight_events(summary, aircraft)
    if events:
        return "faults " + " ".join(w.short() for w in from_events(events))
    moved = summary.get("faults") if summary.get("runs_count") else None  # a campaign's
    if moved:
        return "faults " + " ".join(_spec_short(s) for s in moved) + " at random times"
    return "no faults"


def _spec_short(spec: str) -> str:
    """'spike:start=4,duration=0.1,signal=alpha,...' -> 'spike(alpha, 0.1 s)'."""
    kind, _, body = spec.partition(":")
    fields = dict(kv.split("=", 1) for kv in body.split(",") if "=" in kv)
    target = fields.get("signal") or fields.get("frame") or "bus"
    return f"{kind}({target}, {fields.get('duration', '?')} s)"


def _trio(table: Mapping[str, Mapping[str, float]], state: str, fmt: str) -> str:
    return " ".join(f"{NAMES[f]} {format(table[f][state], fmt)}" for f in metrics.FILTERS if f in table)


def _lowest(table: Mapping[str, Mapping[str, float]], state: str) -> str:
    return min((f for f in metrics.FILTERS if f in table), key=lambda f: table[f][state])


def _cdrw_line(summary: Summary) -> str:
    cd = summary["cdrw"]
    campaign = "table5" in cd
    key = "table5" if campaign else "table4"
    flight = cd.get("flight") or {}
    flew = _what_flew(summary, "cdrw", flight.get("scenario") or summary.get("scenario"),
                      flight.get("seed", summary.get("seed")),
                      f"{cd.get('runs_count')} flights" if campaign else "")
    truth, meas = cd[f"{key}_truth"], cd[key]
    numbers = f"α error vs truth {_trio(truth, 'alpha', '.4f')}"
    if campaign and "table5_truth_ci" in cd:
        ci = cd["table5_truth_ci"]
        numbers = "α error vs truth (mean ± 95 %) " + " ".join(
            f"{NAMES[f]} {ci[f]['alpha']['mean']:.4f}±{_half(ci[f]['alpha'])}"
            for f in metrics.FILTERS if f in ci)
    if "coverage" in cd:
        numbers += "; α in bounds " + " ".join(
            f"{NAMES[f]} {100 * cd['coverage'][f]['alpha']:.1f}%" for f in metrics.FILTERS
            if f in cd["coverage"])
    paper = metrics.PAPER_TABLE5 if campaign else metrics.PAPER_TABLE4
    name = "Table 5" if campaign else "Table 4"
    if not cd.get("paper_scenario", False):
        word, claim = "n/a", f"no paper number: not the paper's scenario ({name} is of its fault)"
    else:
        lowest = {_lowest(meas, "alpha"), _lowest(truth, "alpha")}
        word = "PASS" if lowest == {"azkf"} else "FAIL"
        others = ", ".join(f"{paper[f]['alpha']:.4f}" for f in ("zkf", "kf"))
        claim = (f"paper {name}: AZKF's α error the lowest ({paper['azkf']['alpha']:.4f} vs {others}): "
                 + ("held" if word == "PASS" else
                    f"not held ({'/'.join(NAMES[f] for f in sorted(lowest - {'azkf'}))} lower)"))
    return " | ".join([f"verdict {word}", flew, _faults(summary, "cdrw"), numbers, claim]) + _sync(summary)


def _half(cell: Mapping[str, Any]) -> str:
    h = cell.get("half_width")
    return "?" if h is None else f"{h:.4f}"


def _sync(summary: Summary) -> str:
    sync = summary.get("sync")
    if isinstance(sync, Mapping) and sync.get("verdict", "ok") != "ok":
        return f" | time sync {sync.get('verdict')}"
    return ""


def _missile_line(summary: Summary, runs: Sequence[Mapping[str, Any]]) -> str:
    closed = [r for r in runs if r.get("bits") is not None]
    first = closed[0]
    flew = _what_flew(summary, "missile", first.get("scenario"), first.get("seed"))
    if len(closed) == 1:
        opened = next((r for r in runs if r.get("bits") is None and r["period"] == first["period"]), None)
        numbers = (f"T {first['period']:g} s, {first['bits']}-bit D/A: RMS q {first['rms_q']:.4f} rad/s, "
                   f"α_T {first['rms_alpha']:.5f} rad")
        if opened is not None:
            numbers += f" (open loop {opened['rms_q']:.4f}, {opened['rms_alpha']:.5f})"
        ref = first.get("reference") or {}
        if "code_agreement" in ref:
            numbers += f"; D/A codes = reference {100 * ref['code_agreement']:.1f}%"
    else:
        T = sorted({r["period"] for r in closed})
        bits = sorted({r["bits"] for r in closed})
        q = [r["rms_q"] for r in closed]
        a = [r["rms_alpha"] for r in closed]
        numbers = (f"{len(closed)} closed-loop runs, T {'/'.join(f'{t:g}' for t in T)} s, "
                   f"{'/'.join(map(str, bits))}-bit D/A: RMS q {min(q):.4f}-{max(q):.4f} rad/s, "
                   f"α_T {min(a):.5f}-{max(a):.5f} rad")
    claim = "no paper number for one flight (paper 2's Fig. 3 is a curve)"
    return " | ".join(["verdict n/a", flew, _faults(summary, "missile"), numbers, claim]) + _sync(summary)


def headline_metrics(summary: Summary) -> dict[str, float]:
    """The numbers a run is judged by, named (for `hil compare`): CDRW Table 4 (or Table 5's
    means) against the fault-free measurement and the true state, the bounds coverage; the
    missile's RMS per period and word length."""
    out: dict[str, float] = {}
    cd = summary.get("cdrw")
    if isinstance(cd, Mapping):
        key = "table5" if "table5" in cd else "table4"
        name = "Table 5" if key == "table5" else "Table 4"
        for measure, label in ((key, "vs measurement"), (f"{key}_truth", "vs truth")):
            for s in metrics.STATES:
                for f in metrics.FILTERS:
                    if f in cd.get(measure, {}):
                        out[f"{name} {s} {NAMES[f]} {label}"] = float(cd[measure][f][s])
        for s in metrics.STATES:
            for f in metrics.FILTERS:
                if f in cd.get("coverage", {}):
                    out[f"coverage {s} {NAMES[f]} (%)"] = 100.0 * float(cd["coverage"][f][s])
    for r in (summary.get("missile") or {}).get("runs") or []:
        da = "open loop" if r.get("bits") is None else f"{r['bits']}-bit"
        out[f"missile T {r['period']:g} s {da} RMS q"] = float(r["rms_q"])
        out[f"missile T {r['period']:g} s {da} RMS α_T"] = float(r["rms_alpha"])
    return {k: v for k, v in out.items() if math.isfinite(v)}
