"""The papers' figures of merit, from a run's time series.

Seed 1, Tables 4 and 5: for each filter the error integral

    e = integral |y_k - y_hat_k| dt  ~  sum_k |y_k - C x_hat_k| * dt      (per state, C = I)

where y_k is the *fault-free* measurement and x_hat_k the estimate computed with the fault
injected; also against the true state (which a simulator knows).  The improvement over the
KF is 100 * (1 - e_filter / e_KF) %.  Row k of each filter is the firmware's output of step k
(KF: posterior after y_k; ZKF/AZKF: x_k before y_k is used -- firmware/sid/fcc_sid.h), all
compared with y_k, over the whole flight, as the paper does.

Seed 2, Fig. 3: RMS of q and alpha_T over the run, from the sub-step trace (>= 8 points per
control period), as hil.plants.missile_runs does for its offline reference.
"""
from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np

FILTERS = ("azkf", "zkf", "kf")
STATES = ("alpha", "q")

#: the paper's numbers (seed 1, real CDRW flight data), for side-by-side printing
PAPER_TABLE4 = {"azkf": {"alpha": 0.1073, "q": 0.2554}, "zkf": {"alpha": 0.1089, "q": 0.2731},
                "kf": {"alpha": 0.1956, "q": 0.3045}}
PAPER_TABLE5 = {"azkf": {"alpha": 0.0895, "q": 0.0903}, "zkf": {"alpha": 0.0966, "q": 0.0976},
                "kf": {"alpha": 0.1686, "q": 0.1700}}

Table = dict[str, dict[str, float]]


def error_integral(target: np.ndarray, estimate: np.ndarray, dt: float) -> tuple[float, float, int]:
    """(sum |target - estimate| dt for alpha, for q, steps without an estimate).

    target and estimate are (N, 2); a step where fcc sent no estimate (NaN) is left out of
    the sum and counted, so that a gap never looks like a good estimate silently."""
    target = np.asarray(target, dtype=float)
    estimate = np.asarray(estimate, dtype=float)
    if target.shape != estimate.shape or target.ndim != 2 or target.shape[1] != 2:
        raise ValueError(f"error_integral: shapes {target.shape} and {estimate.shape}, want (N, 2)")
    err = np.abs(target - estimate)
    missing = int(np.count_nonzero(np.isnan(estimate).any(axis=1)))
    e = np.nansum(err, axis=0) * dt
    return float(e[0]), float(e[1]), missing


def error_table(target: np.ndarray, estimates: Mapping[str, np.ndarray], dt: float) -> tuple[Table, int]:
    """{filter: {"alpha": e, "q": e}} and the largest count of steps without an estimate."""
    table: Table = {}
    missing = 0
    for name in FILTERS:
        if name not in estimates:
            continue
        ea, eq, miss = error_integral(target, estimates[name], dt)
        table[name] = {"alpha": ea, "q": eq}
        missing = max(missing, miss)
    return table, missing


def improvements(table: Mapping[str, Mapping[str, float]], baseline: str = "kf") -> Table:
    """{filter: {state: % better than the baseline}} for every filter but the baseline."""
    base = table[baseline]
    out: Table = {}
    for name, row in table.items():
        if name == baseline:
            continue
        out[name] = {s: (100.0 * (1.0 - row[s] / base[s]) if base[s] > 0 else math.nan)
                     for s in STATES}
    return out


def mean_table(tables: Sequence[Mapping[str, Mapping[str, float]]]) -> Table:
    """Element-wise mean of several error tables (Table 5: 100 faults at random times)."""
    if not tables:
        raise ValueError("mean_table: no tables")
    return {f: {s: float(np.mean([t[f][s] for t in tables])) for s in STATES} for f in tables[0]}


def rms(x: np.ndarray) -> float:
    x = np.asarray(x, dtype=float)
    return float(np.sqrt(np.mean(x * x)))


def missile_rms(x_fine: np.ndarray) -> tuple[float, float]:
    """(RMS q, RMS alpha_T) of a sub-step state trace (columns q, alpha_T, w_g)."""
    return rms(x_fine[:, 0]), rms(x_fine[:, 1])


# ---- text tables -------------------------------------------------------------------------
def format_error_table(table: Mapping[str, Mapping[str, float]], title: str,
                       paper: Mapping[str, Mapping[str, float]] | None = None) -> str:
    """The paper's layout: rows alpha and q, columns AZKF, ZKF, KF, the improvement over the
    KF in parentheses; the paper's value below each row when given."""
    imp = improvements(table)
    names = [f for f in FILTERS if f in table]
    lines = [title, f"{'state':<8}" + "".join(f"{n.upper():>20}" for n in names)]
    for s in STATES:
        cells = []
        for n in names:
            v = table[n][s]
            cells.append(f"{v:.4f}" + (f" ({imp[n][s]:+.1f}%)" if n in imp else ""))
        lines.append(f"{s:<8}" + "".join(f"{c:>20}" for c in cells))
        if paper is not None:
            pimp = improvements(paper)
            pc = [f"{paper[n][s]:.4f}" + (f" ({pimp[n][s]:+.1f}%)" if n in pimp else "")
                  for n in names]
            lines.append(f"{'  paper':<8}" + "".join(f"{c:>20}" for c in pc))
    return "\n".join(lines)


def format_missile_table(runs: Sequence[Mapping[str, object]]) -> str:
    """RMS of q and alpha_T per (T, bits); open loop rows say 'open'."""
    lines = [f"{'T (s)':>7} {'D/A':>6} {'RMS q (rad/s)':>15} {'RMS alpha_T (rad)':>18}"
             f" {'ref RMS q':>10} {'codes = ref':>12}"]
    for r in sorted(runs, key=lambda r: (-float(r["period"]), r["bits"] is None, r["bits"] or 0)):  # type: ignore[arg-type]
        bits = "open" if r.get("bits") is None else f"{r['bits']} bit"
        ref = r.get("reference") or {}
        ref_q = f"{ref['rms_q']:.5f}" if isinstance(ref, Mapping) and "rms_q" in ref else "-"
        agree = (f"{100.0 * ref['code_agreement']:.1f} %" if isinstance(ref, Mapping)
                 and "code_agreement" in ref else "-")
        lines.append(f"{float(r['period']):>7.3f} {bits:>6} {float(r['rms_q']):>15.5f} "  # type: ignore[arg-type]
                     f"{float(r['rms_alpha']):>18.6f} {ref_q:>10} {agree:>12}")  # type: ignore[arg-type]
    return "\n".join(lines)
