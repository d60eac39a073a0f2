"""Runs side by side (`hil compare`): their time series overlaid on shared axes, each run's
fault windows shaded in its colour, and their headline numbers (hil.results.verdict) as
grouped bars.  The page that shows them: hil.plots.compare_page.

    compare_figures(runs, out) -> [written PNG paths]
"""
from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from hil.io.output import read_csv
from hil.plots.faults import shade, window_spans
from hil.plots.mpl import plt, save
from hil.results.faultwindows import flight_events, from_events
from hil.results.verdict import headline_metrics

DEG = 180.0 / np.pi
_STEPS = re.compile(r"^missile_T(?P<T>\d+\.\d+)_b(?P<b>\d+)\.csv$")
Series = dict[str, np.ndarray]


@dataclass
class Run:
    """One run directory to compare: its label (its directory's name, or its path when two
    runs share a name), its summary.json and its headline numbers."""

    label: str
    path: Path
    summary: dict[str, Any]
    metrics: dict[str, float] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.metrics = headline_metrics(self.summary)


def label_runs(paths: Sequence[Path], summaries: Sequence[dict[str, Any]]) -> list[Run]:
    names = [p.name or str(p) for p in paths]
    return [Run(n if names.count(n) == 1 else str(p), p, s) for n, p, s in zip(names, paths, summaries)]


def _colour(i: int) -> str:
    return f"C{i % 10}"


def compare_figures(runs: Sequence[Run], out: Path) -> list[Path]:
    written = [_cdrw_series(runs, out), _missile_series(runs, out), _metrics(runs, out)]
    return [p for p in written if p is not None]


#: the columns the overlays draw (a run without them, e.g. a trimmed copy, is left out)
CDRW_COLUMNS = {"t", "alpha_true", "q_true", "azkf_alpha_hat", "azkf_q_hat"}
MISSILE_COLUMNS = {"t", "q", "alpha_T", "q_hat", "alpha_T_hat", "u"}


def _cdrw_csv(run: Run) -> Series | None:
    for name in ("cdrw.csv", "cdrw_run0.csv"):
        if (run.path / name).is_file():
            s = read_csv(run.path / name)
            return s if set(s) >= CDRW_COLUMNS else None
    return None


def _cdrw_series(runs: Sequence[Run], out: Path) -> Path | None:
    """α and q (true dashed, the MLS-AZKF's estimate solid) and the AZKF's α error, per run."""
    data = [(i, r, s) for i, r in enumerate(runs) if (s := _cdrw_csv(r)) is not None]
    if not data:
        return None
    fig, axs = plt.subplots(3, 1, sharex=True, figsize=(9, 7.5))
    for i, run, s in data:
        c = _colour(i)
        t_end = float(s["t"][-1])
        for ax in axs:
            shade(ax, window_spans(from_events(flight_events(run.summary, "cdrw")), t_end),
                  f"{run.label}: fault", color=c, alpha=0.15)
        for ax, key in ((axs[0], "alpha"), (axs[1], "q")):
            ax.plot(s["t"], s[f"{key}_true"] * DEG, "--", color=c, lw=0.9, label=f"{run.label}: true")
            ax.plot(s["t"], s[f"azkf_{key}_hat"] * DEG, "-", color=c, lw=1.2, label=f"{run.label}: MLS-AZKF")
        axs[2].plot(s["t"], np.abs(s["azkf_alpha_hat"] - s["alpha_true"]) * DEG, color=c, lw=1.0,
                    label=run.label)
    axs[0].set_ylabel("α (deg)")
    axs[1].set_ylabel("q (deg/s)")
    axs[2].set_ylabel("|α̂ − α| AZKF (deg)")
    axs[2].set_xlabel("t (s)")
    for ax in axs:
        ax.grid(alpha=0.3)
    axs[0].legend(fontsize=7, ncol=2)
    fig.suptitle(f"CDRW: {len(data)} runs compared (dashed: true state; solid: MLS-AZKF estimate; "
                 "shaded: fault windows)", fontsize=10)
    return save(fig, out / "compare_cdrw.png", made_by=_made_by(runs))


def _missile_steps(run: Run) -> tuple[Series, Series | None] | None:
    """The closed loop's per-step series (the first period, the longest word) and its fine trace."""
    found = sorted((m for f in run.path.glob("missile_T*_b*.csv") if (m := _STEPS.match(f.name))),
                   key=lambda m: (-float(m["T"]), -int(m["b"])))
    if not found:
        return None
    m = found[0]
    fine = run.path / f"missile_T{m['T']}_b{m['b']}_fine.csv"
    steps = read_csv(run.path / m.group(0))
    if not set(steps) >= MISSILE_COLUMNS:
        return None
    return steps, (read_csv(fine) if fine.is_file() else None)


def _missile_series(runs: Sequence[Run], out: Path) -> Path | None:
    """q and α_T (true thin, fcc's estimate stepped) and the elevator, per run."""
    data = [(i, r, d) for i, r in enumerate(runs) if (d := _missile_steps(r)) is not None]
    if not data:
        return None
    fig, axs = plt.subplots(3, 1, sharex=True, figsize=(9, 7.5))
    for i, run, (steps, fine) in data:
        c = _colour(i)
        truth = fine if fine is not None else steps
        for ax in axs:
            shade(ax, window_spans(from_events(flight_events(run.summary, "missile")), float(truth["t"][-1])),
                  f"{run.label}: fault", color=c, alpha=0.15)
        for ax, key, est in ((axs[0], "q", "q_hat"), (axs[1], "alpha_T", "alpha_T_hat")):
            ax.plot(truth["t"], truth[key], "-", color=c, lw=0.8, alpha=0.8, label=f"{run.label}: true")
            ax.step(steps["t"], steps[est], where="post", color=c, lw=1.3, ls="--",
                    label=f"{run.label}: fcc's estimate")
        axs[2].step(steps["t"], steps["u"], where="post", color=c, lw=1.1, label=run.label)
    axs[0].set_ylabel("q (rad/s)")
    axs[1].set_ylabel("α_T (rad)")
    axs[2].set_ylabel("elevator (rad)")
    axs[2].set_xlabel("t (s)")
    for ax in axs:
        ax.grid(alpha=0.3)
    axs[0].legend(fontsize=7, ncol=2)
    fig.suptitle(f"Missile: {len(data)} runs compared (solid: true; dashed: fcc's estimate, "
                 "MSL_STATE_EST; shaded: fault windows)", fontsize=10)
    return save(fig, out / "compare_missile.png", made_by=_made_by(runs))


#: the groups of headline numbers drawn on one axis each (a shared unit): axis title, and how
#: a number's name starts or ends
GROUPS = (("error integral", ("Table",), ()), ("bounds coverage (%)", ("coverage",), ()),
          ("RMS q (rad/s)", (), ("RMS q",)), ("RMS α_T (rad)", (), ("RMS α_T",)))


def _metrics(runs: Sequence[Run], out: Path) -> Path | None:
    """Every headline number some run has, one bar per run, grouped by unit."""
    names = list(dict.fromkeys(k for r in runs for k in r.metrics))
    groups = [(title, [n for n in names if (head and n.startswith(head)) or (tail and n.endswith(tail))])
              for title, head, tail in GROUPS]
    groups = [(t, ns) for t, ns in groups if ns]
    if not groups:
        return None
    heights = [len(ns) * (0.1 * len(runs) + 0.12) + 0.7 for _, ns in groups]
    tall = sum(heights) + 0.8
    fig, axs = plt.subplots(len(groups), 1, figsize=(9, tall), height_ratios=heights, squeeze=False)
    width = 0.8 / len(runs)
    for ax, (title, ns) in zip(axs[:, 0], groups):
        y = np.arange(len(ns))[::-1]
        for i, run in enumerate(runs):
            vals = [run.metrics.get(n, np.nan) for n in ns]
            ax.barh(y + (len(runs) / 2 - i - 0.5) * width, vals, width, color=_colour(i), label=run.label)
        ax.set_yticks(y, ns, fontsize=7)
        ax.set_xlabel(title)
        ax.grid(axis="x", alpha=0.3)
    axs[0, 0].legend(fontsize=7)
    fig.suptitle("Headline numbers of each run (a missing bar: the run has no such number)", fontsize=10)
    return save(fig, out / "compare_metrics.png", rect=(0, 0, 1, 1 - 0.45 / tall), made_by=_made_by(runs))


def _made_by(runs: Sequence[Run]) -> str:
    return "hil compare " + " ".join(str(r.path) for r in runs)
