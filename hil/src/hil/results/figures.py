"""The demo's seed-2 figures as the paper ran them.

* Fig. 3: the stationary RMS by covariance analysis (hil.sim.missile_cov, the firmware's
  own design) on a fine grid of T, each word length and the open loop, with HIL Monte-Carlo
  points (fcc on the bus, long flights in stationary gusts, 95 % confidence intervals by
  batch means), at the printed gyro variance 0.8 and at 8e-5.  fig3.json keeps every number
  (`hil report` redraws from it).
* Figs. 4-6: deterministic initial-condition responses through fcc (q0 = 0.1 rad/s, no gust,
  no sensor noise, the design keeps its nominal R) at T = 0.2, 0.1, 0.05 s for the open loop
  and 6, 8, 12 bits; the D/A codes show the dead zone (responses.json).
"""
from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from hil.io.output import read_csv, write_json
from hil.results import metrics
from hil.scenario.file import Scenario
from hil.scenario.plant_options import MissilePlantOptions
from hil.scenario.sensor_options import MissileSensorOptions

#: Fig. 3's word lengths and gyro variances; the Monte-Carlo points
FIG3_BITS = (6, 8, 12)
FIG3_GYRO_VARS = (0.8, 8e-5)
MC_PERIODS = (0.2, 0.1, 0.05)
MC_BITS = (8,)
MC_SECONDS = 200.0
MC_BATCHES = 10
#: Figs. 4-6
RESPONSE_PERIODS = (0.2, 0.1, 0.05)
RESPONSE_BITS = (6, 8, 12)
RESPONSE_SECONDS = 3.0


def _missile(base: Scenario) -> tuple[MissilePlantOptions, MissileSensorOptions]:
    """base's plant and sensor options, which these figures need to be the missile's."""
    if not isinstance(base.plant, MissilePlantOptions) or not isinstance(base.sensors, MissileSensorOptions):
        raise ValueError(f"the missile's figures need a missile scenario, got aircraft {base.aircraft!r}")
    return base.plant, base.sensors


def stationary_scenario(base: Scenario, gyro_var: float, seconds: float) -> Scenario:
    """The missile in stationary gusts (no transient: q0 = 0, the gust drawn from its
    stationary law), for a Monte-Carlo RMS."""
    plant, sensors = _missile(base)
    return base.replace(duration=seconds,
                        plant=dataclasses.replace(plant, q0=0.0, alpha0=0.0, gust0="stationary"),
                        sensors=dataclasses.replace(sensors, var_gyro=gyro_var))


def response_scenario(base: Scenario, seconds: float = RESPONSE_SECONDS) -> Scenario:
    """Seed 2's Figs. 4-6: from q = 0.1 rad/s, alpha_T = 0, no gust, no sensor noise."""
    plant, sensors = _missile(base)
    return base.replace(duration=seconds,
                        plant=dataclasses.replace(plant, q0=0.1, alpha0=0.0, gust0=0.0, gust_scale=0.0),
                        sensors=dataclasses.replace(sensors, noise_scale=0.0))


def batch_rms(fine_csv: Path, seconds: float, batches: int = MC_BATCHES,
              level: float = 0.95) -> dict[str, float]:
    """RMS of q and alpha_T over [0, seconds] of a sub-step trace, with a confidence interval
    by batch means: the mean square of each of `batches` equal stretches, a Student-t
    interval of their mean, square-rooted (stretches of 20 s are ~40 gust time constants
    apart, i.e. nearly independent)."""
    d = read_csv(fine_csv)
    keep = d["t"] <= seconds + 1e-9
    t, q, a = d["t"][keep], d["q"][keep], d["alpha_T"][keep]
    edges = np.linspace(0.0, seconds, batches + 1)
    out: dict[str, float] = {"seconds": seconds, "batches": batches}
    for key, x in (("q", q), ("alpha", a)):
        ms = [float(np.mean(x[(t >= lo) & (t < hi)] ** 2)) for lo, hi in zip(edges[:-1], edges[1:])]
        mean, half, _ = metrics.t_interval(ms, level)
        out[f"rms_{key}"] = math.sqrt(mean)
        out[f"rms_{key}_lo"] = math.sqrt(max(mean - half, 0.0))
        out[f"rms_{key}_hi"] = math.sqrt(mean + half)
    return out


def fig3_document(studies: Sequence[dict[str, Any]], hil: Sequence[dict[str, Any]]) -> dict[str, Any]:
    """fig3.json: the covariance studies (hil study missile-rms --json, one per gyro variance)
    and the HIL points; the knee of each curve (knee())."""
    return {"studies": list(studies), "hil": list(hil),
            "knee": [knee(s) for s in studies]}


def knee(study: dict[str, Any]) -> dict[str, Any]:
    """Where the benefit of closing the loop goes: for q and alpha_T (ideal D/A), the share
    of the benefit at the shortest period (open loop RMS - closed loop RMS) left at
    T = 0.1 and 0.2 s, and the period at which half of it is gone (linear interpolation)."""
    ps = study["periods"]
    T = np.array([p["period"] for p in ps])
    out: dict[str, Any] = {"gyro_var": study["gyro_var"]}
    for key in ("rms_q", "rms_alpha"):
        ol = study["open_loop"][key]
        benefit = np.array([ol - p[key] for p in ps])
        share = benefit / benefit[0]
        half = next((float(np.interp(0.5, [share[i + 1], share[i]], [T[i + 1], T[i]]))
                     for i in range(len(T) - 1) if share[i] >= 0.5 > share[i + 1]), None)
        out[key] = {"benefit_at_shortest": float(benefit[0]), "shortest_period": float(T[0]),
                    "share_left": {f"{t:g}": float(np.interp(t, T, share)) for t in (0.1, 0.2, 0.3)},
                    "half_gone_at": half}
    return out


def dead_zone(run_dir: Path, runs: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """For each closed-loop response: how many D/A codes were not 0, when the first one
    came, and the largest |code| (the dead-zone finding of Figs. 4-6)."""
    rows = []
    for r in runs:
        if r.get("bits") is None:
            continue
        tag = f"T{r['period']:.3f}_b{r['bits']}"
        d = read_csv(run_dir / f"missile_{tag}.csv")
        nz = np.flatnonzero(d["code"] != 0)
        rows.append({"period": r["period"], "bits": r["bits"], "steps": int(len(d["code"])),
                     "nonzero_codes": int(nz.size),
                     "first_nonzero_t": float(d["t"][nz[0]]) if nz.size else None,
                     "max_abs_code": int(np.max(np.abs(d["code"]))) if len(d["code"]) else 0,
                     "lsb": 0.8 / (1 << int(r["bits"])),
                     "rms_q": r["rms_q"], "rms_alpha": r["rms_alpha"]})
    return rows


def format_dead_zone(rows: Sequence[dict[str, Any]]) -> str:
    lines = ["Figs. 4-6: D/A codes of the deterministic responses (q0 = 0.1 rad/s, no gust, "
             "no sensor noise)",
             f"{'T (s)':>7} {'D/A':>6} {'LSB (rad)':>10} {'codes != 0':>11} {'first at (s)':>13} "
             f"{'max |code|':>11}"]
    for r in rows:
        first = "-" if r["first_nonzero_t"] is None else f"{r['first_nonzero_t']:.2f}"
        lines.append(f"{r['period']:>7.3f} {str(r['bits']) + ' bit':>6} {r['lsb']:>10.5f} "
                     f"{r['nonzero_codes']:>5d} / {r['steps']:<4d} {first:>13} {r['max_abs_code']:>11d}")
    return "\n".join(lines)


def format_fig3(doc: dict[str, Any]) -> str:
    lines = ["Fig. 3: HIL Monte-Carlo RMS (95 % batch-means interval) against the covariance "
             "analysis", f"{'gyro var':>9} {'T (s)':>6} {'D/A':>6} {'RMS q HIL':>24} {'cov.':>8} "
             f"{'RMS a_T HIL':>26} {'cov.':>9}"]
    by_var = {s["gyro_var"]: s for s in doc["studies"]}
    for h in doc["hil"]:
        st = by_var.get(h["gyro_var"])
        cov = next((p for p in st["periods"] if abs(p["period"] - h["period"]) < 1e-9), None) if st else None
        cq = cov["dac"].get(str(h["bits"]), cov)["rms_q"] if cov else math.nan
        ca = cov["dac"].get(str(h["bits"]), cov)["rms_alpha"] if cov else math.nan
        lines.append(f"{h['gyro_var']:>9g} {h['period']:>6.3f} {str(h['bits']) + ' bit':>6} "
                     f"{h['rms_q']:.5f} [{h['rms_q_lo']:.5f}, {h['rms_q_hi']:.5f}] {cq:>8.5f} "
                     f"{h['rms_alpha']:.6f} [{h['rms_alpha_lo']:.6f}, {h['rms_alpha_hi']:.6f}] {ca:>9.6f}")
    for k in doc.get("knee", []):
        for key, name in (("rms_q", "q"), ("rms_alpha", "alpha_T")):
            kk = k[key]
            left = ", ".join(f"{v * 100:.0f} % at {t} s" for t, v in kk["share_left"].items())
            half = "never (to 0.3 s)" if kk["half_gone_at"] is None else f"{kk['half_gone_at']:.3f} s"
            lines.append(f"gyro var {k['gyro_var']:g}, {name}: closed-loop benefit at "
                         f"{kk['shortest_period']:g} s = {kk['benefit_at_shortest']:.3g}; left: {left}; "
                         f"half gone at {half}")
    return "\n".join(lines)


def write_fig3(out: Path, doc: dict[str, Any]) -> Path:
    return write_json(out / "fig3.json", doc)


def read_fig3(run_dir: Path) -> dict[str, Any] | None:
    p = run_dir / "fig3.json"
    return json.loads(p.read_text()) if p.is_file() else None
