"""`hil study bus --figure`: the missile's RMS q against background load, a line per bit rate,
one panel per sampling period and design (hil.runs.bus_study)."""
from __future__ import annotations

from pathlib import Path
from typing import Any

from hil.plots.mpl import plt, save


def bus_study_figure(study: dict[str, Any], out: Path, made_by: str | None = None) -> Path | None:
    pts = [p for p in study["points"] if p["rms_q"] is not None and not p["failed"]]
    periods = sorted({p["period"] for p in study["points"]})
    designs = ("plain", "delay-aware")
    fig, axs = plt.subplots(len(periods), 2, sharex=True, squeeze=False,
                            figsize=(10, 3.2 * len(periods)))
    for row, period in enumerate(periods):
        for col, design in enumerate(designs):
            ax = axs[row][col]
            for bitrate in sorted({p["bitrate"] for p in study["points"]}):
                got = sorted((p["load"], p["rms_q"]) for p in pts
                             if (p["period"], p["design"], p["bitrate"]) == (period, design, bitrate))
                if got:
                    ax.plot([100 * u for u, _ in got], [q for _, q in got], "o-", ms=4,
                            label=f"{bitrate / 1000:g} kbit/s")
            ax.set_title(f"T = {period:g} s, {design} LQG", fontsize=9)
            ax.set_ylabel("RMS q (rad/s)")
            ax.grid(alpha=0.3)
    for ax in axs[-1]:
        ax.set_xlabel("background load (% of the bus)")
    axs[0][0].legend(fontsize=7)
    fig.suptitle(f"Missile RMS q on the wire-time bus (lockstep, seed {study['seed']}, "
                 f"{study['duration']:g} s flights)", fontsize=10)
    return save(fig, out, made_by=made_by)
