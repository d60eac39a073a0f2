"""The papers' figures as PNG files, drawn from a run directory's CSV files and summary.json
(so `hil report DIR` redraws them without flying again).

    plot_run_dir(path) -> [written PNG paths]

cdrw.csv (or a campaign's cdrw_run0.csv) → Figs. 5-10 of seed 1; campaign.csv → each flight's
errors against its fault time; summary.json missile.runs → Fig. 3 of seed 2;
missile_T*_fine.csv → the time responses (Figs. 4-6) at each period; realtime_timing.csv → the
histograms of a realtime run's timing.

The figures are independent: on a machine with several CPUs they are drawn by forked workers
(matplotlib imported once, before the fork), the same PNG bytes as one after the other.

Room 10: may import hil.util, hil.io, hil.bus, hil.scenario, hil.sim, hil.targets, hil.rig,
hil.results, hil.reference; matplotlib only when drawing (hil.plots.mpl).
"""
from __future__ import annotations

import json
import multiprocessing
import os
import re
from collections.abc import Callable, Iterable
from functools import partial
from pathlib import Path

import numpy as np

from hil.io.output import read_csv
from hil.results import timing

_FINE = re.compile(r"^missile_T(?P<T>\d+\.\d+)_(?P<b>open|b\d+)_fine\.csv$")


#: at most this many drawing processes
MAX_WORKERS = 4
Figure = Callable[[], "Path | None"]


def plot_run_dir(run_dir: Path, keep: Iterable[Path] = ()) -> list[Path]:
    """Every figure the run directory has data for, drawn; the PNGs written, in order; files
    in `keep` (the user's) are not overwritten: their figures are not drawn."""
    figs = figures(Path(run_dir))
    from hil.plots import mpl
    mpl.KEEP = {Path(p).resolve() for p in keep}
    try:
        return [p for p in draw(figs) if p is not None]
    finally:
        mpl.KEEP = set()


def _call(fig: Figure) -> Path | None:
    return fig()


def draw(figs: list[Figure]) -> list[Path | None]:
    """Each figure drawn (in forked workers when there are several CPUs), results in order."""
    workers = min(len(figs), os.cpu_count() or 1, MAX_WORKERS)
    if workers < 2:
        return [f() for f in figs]

    with multiprocessing.get_context("fork").Pool(workers) as pool:
        return pool.map(_call, figs, chunksize=1)


def figures(run_dir: Path) -> list[Figure]:
    """The figures of a run directory, not yet drawn (the data read, matplotlib imported)."""
    from hil.plots import cdrw, missile, realtime  # they import matplotlib: only when drawing

    written: list[Figure] = []
    for name in ("cdrw.csv", "cdrw_run0.csv"):
        if (run_dir / name).is_file():
            note = ""
            if name == "cdrw_run0.csv" and (run_dir / "campaign.csv").is_file():
                c = read_csv(run_dir / "campaign.csv")
                note = (f"campaign flight 0 of {len(c['run'])} (fault at "
                        f"{float(c['fault_start'][0]):.2f} s); the tables are over all flights")
            written += cdrw.all_figures(read_csv(run_dir / name), run_dir, note)
            break
    if (run_dir / "campaign.csv").is_file():
        written.append(partial(cdrw.campaign_figure, read_csv(run_dir / "campaign.csv"), run_dir))
    summary_path = run_dir / "summary.json"
    summary = json.loads(summary_path.read_text()) if summary_path.is_file() else {}
    if (run_dir / "fig3.json").is_file():
        written.append(partial(missile.fig3_covariance, json.loads((run_dir / "fig3.json").read_text()),
                               run_dir))
    if summary_path.is_file():
        runs = summary.get("missile", {}).get("runs", [])
        periods = {r["period"] for r in runs}
        if len(periods) > 1 and not summary.get("responses"):  # a 3 s response is no RMS
            written.append(partial(missile.fig3_rms, runs, run_dir))
    by_period: dict[float, dict[int | None, dict[str, np.ndarray]]] = {}
    for f in sorted(run_dir.glob("missile_T*_fine.csv")):
        m = _FINE.match(f.name)
        if m is None:
            continue
        bits = None if m["b"] == "open" else int(m["b"][1:])
        by_period.setdefault(float(m["T"]), {})[bits] = read_csv(f)
    responses = summary.get("responses") or {}
    subtitle = ("deterministic: q0 = 0.1 rad/s, α_T0 = 0, no gust, no sensor noise "
                "(the design keeps its nominal R)") if responses.get("deterministic") else ""
    for T, curves in sorted(by_period.items(), reverse=True):
        elevator: dict[int | None, dict[str, np.ndarray]] = {
            b: read_csv(run_dir / f"missile_T{T:.3f}_b{b}.csv") for b in curves
            if b is not None and (run_dir / f"missile_T{T:.3f}_b{b}.csv").is_file()}
        written.append(partial(missile.fig_time_response, T, curves, run_dir, elevator, subtitle,
                               bool(responses.get("deterministic"))))
    if (run_dir / timing.CSV_NAME).is_file():
        written.append(partial(realtime.fig_realtime_timing, timing.read_csv(run_dir / timing.CSV_NAME),
                               run_dir))
    return written


__all__ = ["draw", "figures", "plot_run_dir"]
