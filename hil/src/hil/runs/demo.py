"""`hil demo`: both aircraft with their default scenarios in one fcc; then seed 2 as the paper
ran it: the deterministic responses of Figs. 4-6 and Fig. 3 by covariance analysis with HIL
Monte-Carlo points.
"""
from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from pathlib import Path

from hil.io.output import write_json
from hil.io.paths import tool
from hil.results import figures
from hil.results.fig3_grid import FIG3_PERIODS
from hil.rig.config import RigConfig
from hil.rig.session import RigSession
from hil.runs.outcome import Outcome, report_outcome
from hil.runs.run import run_flight
from hil.runs.sweep import run_sweep
from hil.scenario.file import load_default_scenario
from hil.sim.missile_cov import missile_rms_study


def run_fig3(cfg: RigConfig, seconds: float = 0.0, periods: Sequence[float] = (),
             bits: Sequence[int] = ()) -> Outcome:
    """Fig. 3 as the paper ran it: the covariance analysis at both gyro variances on the fine
    grid, and HIL Monte-Carlo points (one long flight per point in stationary gusts, fcc on
    the bus) with 95 % batch-means intervals; fig3.json + fig3_missile_rms_covariance.png."""

    seconds = seconds or figures.MC_SECONDS
    periods = tuple(periods) or figures.MC_PERIODS
    bits = tuple(bits) or figures.MC_BITS
    base = load_default_scenario("missile", {m.name for m in RigSession.dbc_frames()})
    out = cfg.out_dir
    studies, hil = [], []
    for var in figures.FIG3_GYRO_VARS:
        studies.append(missile_rms_study(FIG3_PERIODS, figures.FIG3_BITS, var,
                                         base.sensors.var_acc, tool("lqg_design")))  # type: ignore[union-attr]
        sub = out / f"mc_gyro_{var:g}"
        sub.mkdir(parents=True, exist_ok=True)
        sc = figures.stationary_scenario(base, var, seconds)
        o = run_sweep(sc, periods, bits, dataclasses.replace(cfg, out_dir=sub, plots=False))
        for r in o.summary["missile"]["runs"]:
            if r["bits"] is None:
                continue
            tag = f"T{r['period']:.3f}_b{r['bits']}"
            hil.append({"gyro_var": var, "period": r["period"], "bits": r["bits"], "seed": sc.seed,
                        **figures.batch_rms(sub / f"missile_{tag}_fine.csv", seconds)})
    doc = figures.fig3_document(studies, hil)
    figures.write_fig3(out, doc)
    summary = {"command": "fig3", "fig3": doc}
    write_json(out / "summary.json", summary)
    return report_outcome(cfg, out, summary)


def run_responses(cfg: RigConfig) -> Outcome:
    """Figs. 4-6: deterministic initial-condition responses through fcc (q0 = 0.1 rad/s, no
    gust, no sensor noise) at T = 0.2, 0.1, 0.05 s, open loop and 6, 8, 12 bits."""

    base = load_default_scenario("missile", {m.name for m in RigSession.dbc_frames()})
    sc = figures.response_scenario(base)
    o = run_sweep(sc, figures.RESPONSE_PERIODS, figures.RESPONSE_BITS,
                  dataclasses.replace(cfg, plots=False))
    rows = figures.dead_zone(cfg.out_dir, o.summary["missile"]["runs"])
    o.summary["responses"] = {"deterministic": True, "seconds": sc.duration, "dead_zone": rows}
    write_json(cfg.out_dir / "summary.json", o.summary)
    return report_outcome(cfg, cfg.out_dir, o.summary)


def _fresh(path: Path) -> Path:
    path.mkdir(parents=True, exist_ok=True)
    for pattern in ("*.csv", "*.png", "*.json", "*.log", "*.asc", "*.blf"):
        for f in path.glob(pattern):
            if f.is_file():
                f.unlink()
    return path


def run_demo(cfg: RigConfig) -> list[Outcome]:
    """The README's main job: both aircraft with their embedded default scenarios in one fcc
    (the CDRW with the paper's sensor fault at 4 s); then seed 2 as the paper ran it: the
    deterministic responses of Figs. 4-6 (out_dir/responses) and Fig. 3 by covariance
    analysis with HIL Monte-Carlo points (out_dir/fig3)."""

    frames = {m.name for m in RigSession.dbc_frames()}
    cdrw = load_default_scenario("cdrw", frames)
    msl = load_default_scenario("missile", frames)
    first = run_flight([cdrw, msl], cfg, command="demo")
    responses = run_responses(dataclasses.replace(cfg, out_dir=_fresh(cfg.out_dir / "responses")))
    fig3 = run_fig3(dataclasses.replace(cfg, out_dir=_fresh(cfg.out_dir / "fig3")))
    return [first, responses, fig3]
