"""The papers' figures as PNG files, drawn from a run directory's CSV files and summary.json
(so `hil report DIR` redraws them without flying again).

    plot_run_dir(path, out=None, only=None) -> [written PNG paths]

cdrw.csv (or a campaign's cdrw_run0.csv) → Figs. 5-10 of seed 1; campaign.csv → each flight's
errors against its fault time; summary.json cdrw → Table 4 or 5 as bars (tables);
summary.json missile.runs → Fig. 3 of seed 2; missile_T*_fine.csv and missile_T*_b*.csv → the
time responses (Figs. 4-6) at each period, with the gyro reading, fcc's estimate and the fault
windows; realtime_timing.csv → the histograms of a realtime run's timing; summary.json bus (a
run on the wire-time bus or a real one) → each identifier's response times against its bound.  `only` picks
families of them (FAMILIES: `hil plot --figures`); comparisons of runs: hil.plots.compare.

The figures are independent: on a machine with several CPUs they are drawn by forked workers
(matplotlib imported once, before the fork), the same PNG bytes as one after the other.

Room 11: may import hil.util, hil.io, hil.bus, hil.scenario, hil.sim, hil.targets, hil.apps, hil.rig,
hil.results, hil.reference; matplotlib only when drawing (hil.plots.mpl).
"""
from __future__ import annotations

import json
import multiprocessing
import os
import re
import signal
from collections.abc import Callable, Iterable, Iterator
from functools import partial
from pathlib import Path

import numpy as np

from hil.io.output import read_csv
from hil.results import timing
from hil.results.faultwindows import flight_events, from_events

_FINE = re.compile(r"^missile_T(?P<T>\d+\.\d+)_(?P<b>open|b\d+)_fine\.csv$")


#: at most this many drawing processes
MAX_WORKERS = 4
Figure = Callable[[], "Path | None"]
#: the families of figures, by the name `hil plot --figures` takes
FAMILIES = {
    "cdrw": "paper 1's (MLS-AZKF) Figs. 5-10 from cdrw.csv (a campaign: its flight 0)",
    "campaign": "each campaign flight's error integrals against its fault time",
    "tables": "Table 4 (one flight) or Table 5 (a campaign, 95 % intervals) as bar charts",
    "fig3": "paper 2's (LQG) Fig. 3: RMS against the period",
    "missile": "the missile's time responses: measured, true and estimated q, fault windows",
    "timing": "a realtime run's timing histograms",
    "bus": "each identifier's response times against its worst-case bound (summary.json bus)",
}


def plot_run_dir(run_dir: Path, keep: Iterable[Path] = (), out: Path | None = None,
                 only: Iterable[str] | None = None) -> list[Path]:
    """Every figure the run directory has data for (only: these FAMILIES), drawn into out
    (default the run directory); the PNGs written, in order; files in `keep` (the user's)
    are not overwritten: their figures are not drawn."""
    from hil.plots import mpl
    figs = figures(Path(run_dir), out, only)
    mpl.KEEP = {Path(p).resolve() for p in keep}
    mpl.SOURCE = Path(run_dir) if out is not None else None
    try:
        return [p for p in draw(figs) if p is not None]
    finally:
        mpl.KEEP = set()
        mpl.SOURCE = None


def _call(fig: Figure) -> Path | None:
    return fig()


def _worker_signals() -> None:
    """A drawing worker ends quietly when the pool stops it (SIGTERM at the pool's exit):
    not through the handler it inherits from `hil` (hil.cli), which raises -- a traceback
    per idle worker on stderr."""
    for sig in (signal.SIGTERM, signal.SIGHUP):
        signal.signal(sig, signal.SIG_DFL)


def draw(figs: list[Figure]) -> list[Path | None]:
    """Each figure drawn (in forked workers when there are several CPUs), results in order."""
    workers = min(len(figs), os.cpu_count() or 1, MAX_WORKERS)
    if workers < 2:
        return [f() for f in figs]

    with multiprocessing.get_context("fork").Pool(workers, initializer=_worker_signals) as pool:
        return pool.map(_call, figs, chunksize=1)


def figures(run_dir: Path, out: Path | None = None, only: Iterable[str] | None = None) -> list[Figure]:
    """The figures of a run directory (only: these FAMILIES), to be written into out (default
    the run directory), not yet drawn (the data read, matplotlib imported)."""
    out = run_dir if out is None else out
    wanted = set(FAMILIES if only is None else only)
    return [f for family, f in _families(run_dir, out) if family in wanted]


def _families(run_dir: Path, out: Path) -> Iterator[tuple[str, Figure]]:
    from hil.plots import busresponse, cdrw, missile, realtime, tables  # matplotlib: only when drawing

    summary_path = run_dir / "summary.json"
    summary = json.loads(summary_path.read_text()) if summary_path.is_file() else {}
    for name in ("cdrw.csv", "cdrw_run0.csv"):
        if (run_dir / name).is_file():
            note = ""
            if name == "cdrw_run0.csv" and (run_dir / "campaign.csv").is_file():
                c = read_csv(run_dir / "campaign.csv")
                note = (f"campaign flight 0 of {len(c['run'])} (fault at "
                        f"{float(c['fault_start'][0]):.2f} s); the tables are over all flights")
            # the flight's fault windows (a campaign's flight 0 has no events: its fault flag)
            events = flight_events(summary, "cdrw") if name == "cdrw.csv" else []
            windows = from_events(events) if events else None
            for f in cdrw.all_figures(read_csv(run_dir / name), out, note, windows):
                yield "cdrw", f
            break
    if (run_dir / "campaign.csv").is_file():
        yield "campaign", partial(cdrw.campaign_figure, read_csv(run_dir / "campaign.csv"), out)
    if isinstance(summary.get("cdrw"), dict):
        yield "tables", partial(tables.table_bars, summary["cdrw"], out)
    if (run_dir / "fig3.json").is_file():
        yield "fig3", partial(missile.fig3_covariance, json.loads((run_dir / "fig3.json").read_text()), out)
    if summary_path.is_file():
        runs = summary.get("missile", {}).get("runs", [])
        periods = {r["period"] for r in runs}
        if len(periods) > 1 and not summary.get("responses"):  # a 3 s response is no RMS
            yield "fig3", partial(missile.fig3_rms, runs, out)
    by_period: dict[float, dict[int | None, dict[str, np.ndarray]]] = {}
    for fine in sorted(run_dir.glob("missile_T*_fine.csv")):
        m = _FINE.match(fine.name)
        if m is None:
            continue
        bits = None if m["b"] == "open" else int(m["b"][1:])
        by_period.setdefault(float(m["T"]), {})[bits] = read_csv(fine)
    responses = summary.get("responses") or {}
    subtitle = ("deterministic: q0 = 0.1 rad/s, α_T0 = 0, no gust, no sensor noise "
                "(the design keeps its nominal R)") if responses.get("deterministic") else ""
    # the flight's fault windows, from its events (a summary without them: the series' flag)
    windows = from_events(flight_events(summary, "missile")) if summary.get("missile") else None
    for T, curves in sorted(by_period.items(), reverse=True):
        steps: dict[int | None, dict[str, np.ndarray]] = {
            b: read_csv(run_dir / f"missile_T{T:.3f}_b{b}.csv") for b in curves
            if b is not None and (run_dir / f"missile_T{T:.3f}_b{b}.csv").is_file()}
        yield "missile", partial(missile.fig_time_response, T, curves, out, steps, subtitle,
                                 bool(responses.get("deterministic")), windows)
    if (run_dir / timing.CSV_NAME).is_file():
        yield "timing", partial(realtime.fig_realtime_timing, timing.read_csv(run_dir / timing.CSV_NAME), out)
    if isinstance(summary.get("bus"), dict) and summary["bus"].get("frames"):
        yield "bus", partial(busresponse.fig_bus_response, summary["bus"], out)


__all__ = ["FAMILIES", "draw", "figures", "plot_run_dir"]
