"""Each identifier's measured response times against its worst-case bound, from summary.json's
`bus` section only (hil.results.busstats: a `--bus wire` run over canbus, or an external
device's real bus), so any run that wrote the section -- realtime or lockstep -- draws it.

One row per frame, sorted by identifier: p50, p99 and max of its response times (queued at the
sender → end of frame, in ms, log scale) and its bound (`wcrt_s`, Davis et al. 2007 with zero
queuing jitter; `wcrt_jitter_s` where the run computed it, with the measured release jitter).
A frame above its bound is drawn red and marked ABOVE; every cyclic frame is judged (fcc's,
FIFO-queued, by hil.bus.wcrt's FIFO derivation); those the analysis does not bound (an event
frame; an unbounded one) are grey and say why; above the zero-jitter bound but within the one with the
run's measured release jitter, orange; on a real
bus the device's frames, whose queue time is not on the bus, have their bound only ("not
measured").  The
section holds percentiles, not samples: canbus reports a histogram's p50/p99/max per
identifier (firmware/tools/canbus, `ids`), not every response.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from hil.bus import load
from hil.plots.mpl import plt, save
from hil.results.busstats import ABOVE, JITTER, LATE, WITHIN

NAME = "bus_response_times.png"
#: the verdicts of hil.results.busstats that fail a run (drawn red), and that pass (blue; above
#: the J = 0 bound but within the one with the run's release jitter: orange)
_FAILING = (ABOVE, LATE)
_JUDGED_OK = (WITHIN, JITTER)


@dataclass(frozen=True)
class Row:
    """One frame of the figure."""

    frame_id: int | None
    name: str
    #: None: not measured (a real bus: the device's frames; their bound only)
    p50_s: float | None
    p99_s: float | None
    max_s: float | None
    wcrt_s: float | None
    wcrt_jitter_s: float | None
    verdict: str

    @property
    def label(self) -> str:
        return f"{self.frame_id:#05x} {self.name}" if self.frame_id is not None else self.name

    @property
    def mark(self) -> str:
        """What the row says beside it: ABOVE, its verdict when not judged, '' when within."""
        if self.verdict in _FAILING:
            return "ABOVE" + (" (canbus late)" if "late" in self.verdict else "")
        if self.verdict == _JUDGED_OK[0]:
            return ""
        if self.verdict == _JUDGED_OK[1]:
            return "within the bound with the jitter"
        if self.max_s is None:
            return "not measured" + ("" if self.wcrt_s is not None else ", no bound")
        return self.verdict


def rows(section: Mapping[str, Any]) -> list[Row]:
    """The section's frames, sorted by identifier (each entry's `id`; a summary without one: the
    DBC's, or the name when it is canbus's hexadecimal key; none of these, last)."""
    ids = {m.name: m.frame_id for m in load().messages}
    out = []
    for name, f in section["frames"].items():
        fid = f.get("id", ids.get(name, _hex(name)))
        out.append(Row(fid, name, f["p50_s"], f["p99_s"], f["max_s"], f.get("wcrt_s"),
                       f.get("wcrt_jitter_s"), f.get("verdict", "")))
    for name, f in (section.get("not_measured") or {}).items():   # a real bus's (busstats_real)
        out.append(Row(f.get("id", ids.get(name, _hex(name))), name, None, None, None, f.get("wcrt_s"),
                       None, "not measured"))
    return sorted(out, key=lambda r: (r.frame_id is None, r.frame_id or 0, r.name))


def _hex(name: str) -> int | None:
    try:
        return int(name, 16)
    except ValueError:
        return None


def figure(section: Mapping[str, Any]) -> plt.Figure:
    """The figure (not saved): one row per identifier, lowest identifier on top."""
    rs = rows(section)
    height = 1.5 + 0.32 * max(len(rs), 1)
    fig, ax = plt.subplots(figsize=(9.5, height))
    ms = 1e3
    for y, r in enumerate(rs):
        failing = r.verdict in _FAILING
        colour = ("tab:red" if failing else "tab:blue" if r.verdict == _JUDGED_OK[0]
                  else "tab:orange" if r.verdict == _JUDGED_OK[1] else "0.55")
        if r.p50_s is not None and r.p99_s is not None and r.max_s is not None:
            ax.plot([r.p50_s * ms, r.max_s * ms], [y, y], color=colour, lw=1, zorder=2)
            ax.plot(r.p50_s * ms, y, "o", color=colour, ms=4, zorder=3)
            ax.plot(r.p99_s * ms, y, "s", color=colour, ms=4, zorder=3)
            ax.plot(r.max_s * ms, y, "^", color=colour, ms=6 if failing else 5, zorder=3.5)
        if r.wcrt_s is not None:
            ax.plot([r.wcrt_s * ms] * 2, [y - 0.35, y + 0.35], color="black", lw=2, zorder=4)
        if r.wcrt_jitter_s is not None:
            ax.plot([r.wcrt_jitter_s * ms] * 2, [y - 0.35, y + 0.35], color="black", lw=1.2,
                    ls="--", zorder=4)
        if r.mark:
            ax.annotate(r.mark, (1.0, y), xycoords=("axes fraction", "data"), xytext=(4, 0),
                        textcoords="offset points", va="center", fontsize=7,
                        color="tab:red" if failing else colour if colour != "0.55" else "0.35",
                        fontweight="bold" if failing else None)
    ax.set_yticks(range(len(rs)), [r.label for r in rs], fontsize=7, family="monospace")
    ax.set_ylim(len(rs) - 0.5, -0.5)
    ax.set_xscale("log")
    ax.xaxis.set_major_formatter(plt.ScalarFormatter())
    ax.set_xlabel("response time, queued at the sender → end of frame (ms)")
    ax.grid(alpha=0.3, which="both", axis="x")
    for marker, label in (("o", "p50"), ("s", "p99"), ("^", "max")):
        ax.plot([], [], marker, color="0.3", label=label)
    ax.plot([], [], color="black", lw=2, label="bound (J = 0)")
    ax.plot([], [], color="black", lw=1.2, ls="--", label="bound with the release jitter")
    fig.legend(fontsize=7, loc="lower center", ncol=5, frameon=False)
    above = sum(r.verdict in _FAILING for r in rs)
    measured = sum(r.max_s is not None for r in rs)
    fig.suptitle(f"bus at {section['bitrate']} bit/s ({section.get('model', 'wire')}): response time "
                 f"per identifier against its worst-case bound; {above} of {measured} frames above")
    return fig


def fig_bus_response(section: Mapping[str, Any], out: Path) -> Path | None:
    fig = figure(section)
    return save(fig, out / NAME, rect=(0, 0.3 / fig.get_figheight(), 1, 1))  # room for the legend


__all__ = ["NAME", "Row", "fig_bus_response", "figure", "rows"]
