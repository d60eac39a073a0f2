"""The timing of a realtime run (realtime_timing.csv, hil.results.timing): histograms of the
step-start jitter (simulator's sensor frames and fcc's commands against the master's sampling
instants), the data age at use, and fcc's sync offset."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from hil.plots.mpl import plt, save

NAME = "realtime_timing.png"


def fig_realtime_timing(t: dict[str, np.ndarray], out: Path) -> Path | None:
    fig, ax = plt.subplots(1, 3, figsize=(13, 3.8))
    panels = (
        (ax[0], (("sim_jitter", "simulator: sensor frame - sampling instant"),
                 ("cmd_delay", "fcc: command - sampling instant")), "step start vs sampling instant (ms)"),
        (ax[1], (("data_age", "command - newest sensor frame"),), "data age at use (ms)"),
        (ax[2], (("sync_offset", "FCC_SYNC_STATUS.offset_us"),), "sync offset (us)"),
    )
    for a, series, xlabel in panels:
        for key, label in series:
            x = np.asarray(t.get(key, ()), dtype=float)
            if x.size == 0:
                continue
            scale = 1.0 if key == "sync_offset" else 1e-3
            p99 = np.percentile(np.abs(x), 99) * scale
            a.hist(x * scale, bins=60, alpha=0.6, label=f"{label} (n={x.size}, |p99| {p99:.3g})")
        a.set_xlabel(xlabel)
        a.set_ylabel("count")
        a.set_yscale("log")
        a.legend(fontsize=7)
        a.grid(alpha=0.3)
    fig.suptitle("realtime run: timing on the bus (candump stamps, master time from TSYNC)")
    return save(fig, out / NAME)
