"""Seed 1's Tables 4 and 5 as bar charts, from summary.json's cdrw block: per state (α, q) and
filter the error integral against the fault-free measurement (the paper's measure, solid) and
against the true state (hatched); Table 5 with its 95 % intervals over the campaign's
flights; the paper's values beside the bars as markers when the run is the paper's scenario.
"""
from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from hil.plots.cdrw import COLORS, LABELS
from hil.plots.mpl import plt, save
from hil.results import metrics

WIDTH = 0.36


def table_bars(cd: Mapping[str, Any], out: Path) -> Path | None:
    """table4_bars.png (one flight) or table5_bars.png (a campaign)."""
    fig = table_figure(cd)
    if fig is None:
        return None
    return save(fig, out / ("table5_bars.png" if "table5" in cd else "table4_bars.png"))


def table_figure(cd: Mapping[str, Any]) -> plt.Figure | None:
    campaign = "table5" in cd
    key = "table5" if campaign else "table4"
    if key not in cd or f"{key}_truth" not in cd:
        return None
    names = [f for f in metrics.FILTERS if f in cd[key]]
    paper = (metrics.PAPER_TABLE5 if campaign else metrics.PAPER_TABLE4) if cd.get("paper_scenario") else None
    fig, axs = plt.subplots(1, 2, figsize=(10, 4))
    x = np.arange(len(names))
    for ax, state in zip(axs, metrics.STATES):
        for off, measure, hatch, label in ((-WIDTH / 2, key, None, "vs fault-free measurement"),
                                          (WIDTH / 2, f"{key}_truth", "//", "vs true state")):
            vals = [cd[measure][f][state] for f in names]
            err = _half_widths(cd.get(f"{measure}_ci"), names, state)
            ax.bar(x + off, vals, WIDTH, yerr=err, capsize=4 if err is not None else 0,
                   color=[COLORS[f] for f in names], alpha=0.85 if hatch is None else 0.35,
                   hatch=hatch, edgecolor="k", lw=0.6, label=label)
        if paper is not None:
            ax.plot(x - WIDTH / 2 - 0.08, [paper[f][state] for f in names], "D", color="k", ms=6,
                    label=f"paper ({'Table 5' if campaign else 'Table 4'})")
        ax.set_xticks(x, [LABELS[f] for f in names])
        ax.set_ylabel(f"∫|error| dt, {'α (rad·s)' if state == 'alpha' else 'q (rad)'}")
        ax.set_title("α" if state == "alpha" else "q", fontsize=10)
        ax.grid(axis="y", alpha=0.3)
    axs[0].legend(fontsize=7)
    rows = cd.get("rows")
    what = (f"Table 5 — mean error integral over {cd.get('runs_count')} flights, 95 % t-interval"
            if campaign else "Table 4 — error integral of one flight (no interval: one flight)")
    fig.suptitle(what + (f", {rows} rows" if rows else ""), fontsize=10)
    return fig


def _half_widths(ci: Mapping[str, Any] | None, names: list[str], state: str) -> list[float] | None:
    if not ci:
        return None
    return [float(ci[f][state].get("half_width") or 0.0) for f in names]
