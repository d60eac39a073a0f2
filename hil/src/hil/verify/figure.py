"""A windowed check's evidence figure: the signal around its window, the window shaded, the
band (settling_time) or target, and the measured value marked -- beside the check in the
report (hil.verify.report)."""
from __future__ import annotations

import ast
import math
from pathlib import Path
from typing import Any

import numpy as np

from hil.verify.expr import Expectation, dotted
from hil.verify.window import VALUE, Check, Measured

#: how much of the signal is drawn either side of the window (a fraction of its length)
MARGIN = 0.5
#: measures whose value is a time after the window's start (marked by a vertical line)
TIMES = ("settling_time", "time_to_true", "rise_time")
#: measures whose value is a level of the signal (a horizontal line)
LEVELS = ("max", "min", "mean", "rms", "peak", "first", "last")


def limit(exp: Expectation) -> float | None:
    """The constant `value` is compared with (`value <= 0.1`, `2 > value`), if that is all."""
    tree = exp.tree
    if not (isinstance(tree, ast.Compare) and len(tree.comparators) == 1):
        return None
    sides = (tree.left, tree.comparators[0])
    names = [dotted(s) for s in sides]
    consts = [s.value for s in sides if isinstance(s, ast.Constant) and isinstance(s.value, (int, float))]
    return float(consts[0]) if VALUE in names and len(consts) == 1 else None


def draw(check: Check, got: Measured, verdict: str, title: str, path: Path, made_by: str,
         bound: float | None = None) -> Path | None:
    """The figure of one check, written to path (hil.plots.mpl.save: the PNG and its caption);
    bound: the limit of its expectation, drawn as the measured value is."""
    from hil.plots.mpl import plt, save   # matplotlib only when drawing

    span = max(got.t_to - got.t_from, 1e-3)
    t, x = got.series.t, got.series.x
    near = (t >= got.t_from - MARGIN * span) & (t <= got.t_to + MARGIN * span)
    fig, ax = plt.subplots(figsize=(6.4, 2.8))
    ax.step(t[near], x[near], where="post", lw=1.0, color="#1f4e9c", label=check.signal.text[:60])
    ax.axvspan(got.t_from, got.t_to, color="#f0c040", alpha=0.3, label=f"window: {check.window.describe()}")
    if check.band is not None:
        ax.axhspan(*check.band, color="#40a040", alpha=0.2, label=f"band [{check.band[0]:g}, {check.band[1]:g}]")
        for edge in check.band:   # (a band of one value has no area)
            ax.axhline(edge, color="#40a040", lw=0.8, ls="--")
    if check.target is not None:
        ax.axhline(check.target, color="#40a040", ls="--", lw=1.0, label=f"target {check.target:g}")
    _mark(ax, check, got.value, got.t_from, f"{check.measure} = {got.value:.4g}", "-")
    if bound is not None:
        _mark(ax, check, bound, got.t_from, f"limit {bound:g}", "--")
    ax.set_xlabel("t (s from the flight's start)")
    ax.set_title(f"{verdict.upper()}  {title}"[:90], fontsize=9)
    ax.legend(fontsize=7, loc="best")
    ax.grid(alpha=0.3)
    return save(fig, path, made_by=made_by)


def _mark(ax: Any, check: Check, value: float, t_from: float, label: str, style: str) -> None:
    """A value of the measure: a time as a vertical line, a level as a horizontal one, a count
    in the legend only."""
    colour = "#c03030" if style == "-" else "#802080"
    if check.measure in TIMES and math.isfinite(value):
        ax.axvline(t_from + value, color=colour, lw=1.2, ls=style, label=label)
    elif check.measure in LEVELS and np.isfinite(value):
        ax.axhline(value, color=colour, lw=1.0, ls=style, label=label)
    else:
        ax.plot([], [], " ", label=label)
