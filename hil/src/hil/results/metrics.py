"""The papers' figures of merit, from a run's time series.

Seed 1, Tables 4 and 5: for each filter the error integral

    e = integral |y_k - y_hat_k| dt  ~  sum_k |y_k - C x_hat_k| * dt      (per state, C = I)

where y_k is the *fault-free* measurement and x_hat_k the estimate computed with the fault
injected; also against the true state (which a simulator knows).  The improvement over the
KF is 100 * (1 - e_filter / e_KF) %.  Row k of each filter is the firmware's output of step k
(KF: posterior after y_k; ZKF/AZKF: x_k before y_k is used -- firmware/sid/fcc_sid.h), all
compared with y_k, over the whole flight, as the paper does.

Seed 2, Fig. 3: hil.sim.missile_runs.rms_over (a run's RMS over [0, duration] of its
sub-step trace) and hil.sim.missile_cov (the stationary RMS, exactly).
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


def coverage_table(truth: np.ndarray, bounds: Mapping[str, tuple[np.ndarray, np.ndarray]]) -> Table:
    """{filter: {"alpha": share, "q": share}}: the share of steps at which the true state lies
    inside the filter's bounds (lo <= x <= hi; zonotope: the interval hull, which a correct
    model and bounded noise guarantee; KF: +-3 sigma).  Steps without bounds are left out."""
    truth = np.asarray(truth, dtype=float)
    out: Table = {}
    for name in FILTERS:
        if name not in bounds:
            continue
        lo, hi = (np.asarray(b, dtype=float) for b in bounds[name])
        ok = np.isfinite(lo) & np.isfinite(hi)
        inside = (lo <= truth) & (truth <= hi) & ok
        out[name] = {s: (float(inside[:, i].sum() / ok[:, i].sum()) if ok[:, i].any() else math.nan)
                     for i, s in enumerate(STATES)}
    return out


def format_coverage(cov: Mapping[str, Mapping[str, float]], title: str) -> str:
    """Bounds coverage as a small table (percent of steps)."""
    names = [f for f in FILTERS if f in cov]
    lines = [title, f"{'state':<8}" + "".join(f"{n.upper():>10}" for n in names)]
    for s in STATES:
        lines.append(f"{s:<8}" + "".join(f"{100 * cov[n][s]:>9.1f}%" for n in names))
    return "\n".join(lines)


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


#: how campaign_table5 states its interval (also written into summary.json)
CI_METHOD = ("two-sided Student-t interval of the mean over flights: "
             "mean +- t(1 - (1 - level)/2, n - 1) * s / sqrt(n), s the sample standard deviation "
             "(ddof = 1); the improvement's interval is the paired one of e_KF - e_filter per "
             "flight, scaled by 100 / mean(e_KF)")


def t_interval(samples: Sequence[float], level: float = 0.95) -> tuple[float, float, float]:
    """(mean, half width, sample standard deviation) of a Student-t interval of the mean.

    The half width is t(1 - (1 - level)/2, n - 1) * s / sqrt(n); NaN for fewer than 2 samples."""
    from scipy.special import stdtrit  # = scipy.stats.t.ppf, without importing scipy.stats (~1 s)

    x = np.asarray(samples, dtype=float)
    if x.ndim != 1 or x.size == 0:
        raise ValueError("t_interval: want a non-empty 1-D sample")
    if not 0.0 < level < 1.0:
        raise ValueError(f"t_interval: level must be in (0, 1), got {level}")
    mean = float(np.mean(x))
    if x.size < 2:
        return mean, math.nan, math.nan
    s = float(np.std(x, ddof=1))
    t = float(stdtrit(x.size - 1, 1.0 - (1.0 - level) / 2.0))
    return mean, t * s / math.sqrt(x.size), s


def _ci_cell(samples: Sequence[float], level: float) -> dict[str, float | None]:
    mean, half, s = t_interval(samples, level)
    fin = math.isfinite(half)
    return {"mean": mean, "half_width": half if fin else None, "std": s if fin else None,
            "lo": mean - half if fin else None, "hi": mean + half if fin else None}


#: a flight counts as a win only when the filter's error is below the KF's by more than this
#: share (equal filters, e.g. the unreduced ZKF and the KF, differ in the last digits only)
WIN_MARGIN = 1e-9


def _wins(e: float, e_kf: float) -> bool:
    return e < e_kf * (1.0 - WIN_MARGIN)


def campaign_table5(errors: Sequence[Mapping[str, Mapping[str, float]]],
                    errors_truth: Sequence[Mapping[str, Mapping[str, float]]],
                    level: float = 0.95,
                    coverage: Sequence[Mapping[str, Mapping[str, float]]] | None = None) -> dict[str, object]:
    """Table 5 of a campaign from its per-flight error integrals, with confidence intervals.

    errors[i] and errors_truth[i] are flight i's error tables ({filter: {"alpha": e, "q": e}},
    as error_table returns them; against the fault-free measurement and against the true
    state).  Returns (stable shape; keys may be added, none renamed)::

        {"runs_count": n, "ci_level": 0.95, "ci_method": CI_METHOD,
         "table5":       {filter: {state: mean}},          # as mean_table
         "table5_truth": {filter: {state: mean}},
         "table5_ci":       {filter: {state: {"mean", "half_width", "std", "lo", "hi"}}},
         "table5_truth_ci": {filter: {state: {...}}},
         "improvement_over_kf_pct":       {filter: {state: %}},   # of the means
         "improvement_over_kf_truth_pct": {filter: {state: %}},
         "improvement_over_kf_ci":       {filter: {state: {"mean", "half_width", "std", "lo", "hi"}}},
         "improvement_over_kf_truth_ci": {filter: {state: {...}}},
         "azkf_better_than_kf_runs":       {state: flights with e_AZKF < e_KF (1 - WIN_MARGIN)},
         "azkf_better_than_kf_truth_runs": {state: ...},
         "zkf_better_than_kf_runs":        {state: ...},
         "zkf_better_than_kf_truth_runs":  {state: ...},
         # only when per-flight coverage tables are given (coverage_table):
         "coverage":    {filter: {state: mean share of steps inside the bounds}},
         "coverage_ci": {filter: {state: {"mean", "half_width", "std", "lo", "hi"}}}}

    Every interval is the two-sided Student-t interval of the mean over the n flights
    (CI_METHOD): mean +- t(0.975, n-1) s/sqrt(n) at level 0.95.  The improvement's interval
    is the paired one: d_i = e_KF,i - e_filter,i, 100 * (mean(d) +- t s_d/sqrt(n)) / mean(e_KF)
    (mean(d)/mean(e_KF) is exactly the improvement of the means).  With one flight the
    half widths, standard deviations and bounds are None.  State keys are "alpha" and "q"."""
    if not errors or len(errors) != len(errors_truth):
        raise ValueError(f"campaign_table5: {len(errors)} and {len(errors_truth)} flights")
    out: dict[str, object] = {"runs_count": len(errors), "ci_level": level, "ci_method": CI_METHOD}
    for key, tabs in (("", errors), ("_truth", errors_truth)):
        names = [f for f in FILTERS if f in tabs[0]]
        mean = mean_table(tabs)
        out[f"table5{key}"] = mean
        out[f"table5{key}_ci"] = {f: {s: _ci_cell([t[f][s] for t in tabs], level) for s in STATES}
                                 for f in names}
        out[f"improvement_over_kf{key}_pct"] = improvements(mean)
        imp_ci: dict[str, dict[str, object]] = {}
        for f in names:
            if f == "kf":
                continue
            imp_ci[f] = {}
            for s in STATES:
                cell = _ci_cell([t["kf"][s] - t[f][s] for t in tabs], level)
                scale = 100.0 / mean["kf"][s] if mean["kf"][s] > 0 else math.nan
                imp_ci[f][s] = {k: (None if v is None else v * scale) for k, v in cell.items()}
            out[f"{f}_better_than_kf{key}_runs"] = {s: int(sum(_wins(t[f][s], t["kf"][s]) for t in tabs))
                                                   for s in STATES}
        out[f"improvement_over_kf{key}_ci"] = imp_ci
    if coverage:
        if len(coverage) != len(errors):
            raise ValueError(f"campaign_table5: {len(coverage)} coverage tables for {len(errors)} flights")
        out["coverage"] = mean_table(coverage)
        out["coverage_ci"] = {f: {s: _ci_cell([c[f][s] for c in coverage], level) for s in STATES}
                              for f in coverage[0]}
    return out


def format_table5(t5: Mapping[str, object], truth: bool = False,
                  paper: Mapping[str, Mapping[str, float]] | None = None, rows: str = "") -> str:
    """Table 5 (as campaign_table5 returns it) with its intervals: `mean +- half width` per
    filter and state, the improvement over the KF with its interval, then the win counts."""
    key = "_truth" if truth else ""
    mean: Mapping[str, Mapping[str, float]] = t5[f"table5{key}"]  # type: ignore[assignment]
    ci: Mapping[str, Mapping[str, Mapping[str, float | None]]] = t5[f"table5{key}_ci"]  # type: ignore[assignment]
    imp_ci: Mapping[str, Mapping[str, Mapping[str, float | None]]] = t5[f"improvement_over_kf{key}_ci"]  # type: ignore[assignment]
    n = t5["runs_count"]
    level = float(t5.get("ci_level", 0.95))  # type: ignore[arg-type]
    what = "|x_true - x_hat|" if truth else "|y_faultfree - y_hat|"
    names = [f for f in FILTERS if f in mean]
    lines = [f"CDRW Table 5 (mean over {n} flights, {100 * level:g} % t-interval"
             + (f", {rows} rows" if rows else "") + f"): integral {what} dt",
             f"{'state':<8}" + "".join(f"{x.upper():>30}" for x in names)]

    def pm(c: Mapping[str, float | None], fmt: str) -> str:
        h = c["half_width"]
        return format(float(c["mean"]), fmt) + ("" if h is None else " +- " + format(float(h), fmt.lstrip("+")))  # type: ignore[arg-type]

    for s in STATES:
        cells = [pm(ci[f][s], ".4f") for f in names]
        lines.append(f"{s:<8}" + "".join(f"{c:>30}" for c in cells))
        cells = [("" if f not in imp_ci else pm(imp_ci[f][s], "+.1f") + " %") for f in names]
        lines.append(f"{'  vs KF':<8}" + "".join(f"{c:>30}" for c in cells))
        if paper is not None:
            pimp = improvements(paper)
            pc = [f"{paper[f][s]:.4f}" + (f" ({pimp[f][s]:+.1f}%)" if f in pimp else "") for f in names]
            lines.append(f"{'  paper':<8}" + "".join(f"{c:>30}" for c in pc))
    for f in ("azkf", "zkf"):
        w = t5.get(f"{f}_better_than_kf{key}_runs")
        if isinstance(w, Mapping):
            lines.append(f"{f.upper()} better than KF in {w['alpha']} of {n} flights for alpha, "
                         f"{w['q']} of {n} for q")
    return "\n".join(lines)


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
