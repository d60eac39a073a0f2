"""The fault windows shaded in every time figure (CDRW Figs. 5-10, the missile's responses,
`hil compare`): from a series' per-step fault flag, or from the flight's fault events
(hil.results.faultwindows: every kind, sensor and frame), one grey span each."""
from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from hil.results.faultwindows import FaultWindow

#: the spans' colour (under every curve)
GREY = "0.85"
Span = tuple[float, float]


def flag_spans(t: np.ndarray, flag: np.ndarray | None) -> list[Span]:
    """[start, end) of each run of steps with the flag set; a step lasts until the next."""
    if flag is None or not np.any(flag > 0):
        return []
    dt = t[1] - t[0] if len(t) > 1 else 0.02
    on = np.flatnonzero(np.diff(np.concatenate([[0], (flag > 0).astype(int), [0]])))
    return [(float(t[a]), float(t[b - 1] + dt)) for a, b in zip(on[::2], on[1::2])]


def window_spans(windows: Sequence[FaultWindow], t_end: float) -> list[Span]:
    """The windows as spans; one still active at the end of the flight ends with it."""
    return [(w.start, t_end if w.end is None else w.end) for w in windows]


def shade(ax, spans: Sequence[Span], label: str = "fault active", color: str = GREY,
          alpha: float = 1.0) -> list:
    """One span per window, labelled once (the legend); the patches drawn."""
    return [ax.axvspan(a, b, color=color, alpha=alpha, zorder=0, lw=0, label=label if i == 0 else None)
            for i, (a, b) in enumerate(spans)]


def name_windows(ax, windows: Sequence[FaultWindow], t_end: float) -> None:
    """Each window's kind(target) written at its start, along the bottom of the axes (clear
    of a legend at the top)."""
    for w in windows:
        ax.annotate(f"{w.kind}({w.target})", (min(w.start, t_end), 0.0), xycoords=("data", "axes fraction"),
                    xytext=(2, 2), textcoords="offset points", va="bottom", fontsize=7, color="0.2")
