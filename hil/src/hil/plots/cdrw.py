"""Seed 1's figures from a CDRW time series (cdrw.csv): Figs. 5 to 10.

Angles are drawn in degrees and rates in deg/s, as the paper draws them; the series are in
rad and rad/s.  Every fault window of the flight (its events: sensor, frame and bus faults;
else the series' sensor-fault flag) is shaded in every figure.
"""
from __future__ import annotations

from collections.abc import Callable
from functools import partial
from pathlib import Path

import numpy as np

from hil.plots.faults import flag_spans, shade, window_spans
from hil.plots.mpl import plt, save
from hil.results.faultwindows import FaultWindow

Series = dict[str, np.ndarray]
DEG = 180.0 / np.pi
COLORS = {"azkf": "tab:red", "zkf": "tab:green", "kf": "tab:blue"}
LABELS = {"azkf": "MLS-AZKF", "zkf": "MLS-ZKF", "kf": "MLS-KF"}
STALL_DEG = 15.0


def shade_faults(ax, s: Series) -> None:
    """The flight's fault windows (all kinds, from its events) where the run has them, else
    the series' sensor-fault flag (a campaign's flight 0)."""
    windows = s.get(WINDOWS_KEY)
    if isinstance(windows, list):
        shade(ax, window_spans(windows, float(s["t"][-1])))
    else:
        shade(ax, flag_spans(s["t"], s.get("fault")), "sensor fault active")


#: the series key plot_run_dir sets to say which flight a figure shows (campaigns)
NOTE_KEY = "_figure_note"
#: the series key plot_run_dir sets to the flight's fault windows (hil.results.faultwindows)
WINDOWS_KEY = "_fault_windows"


def _note(s: Series) -> str:
    note = s.get(NOTE_KEY)
    return f"\n{note}" if isinstance(note, str) and note else ""


def _stall_times(s: Series) -> list[float]:
    a = s["alpha_true"] * DEG
    cross = np.flatnonzero(np.diff(np.sign(a - STALL_DEG)))
    return [float(s["t"][i]) for i in cross]


def fig5_alpha_q(s: Series, out: Path) -> Path | None:
    fig, axs = plt.subplots(2, 1, sharex=True, figsize=(8, 5.5))
    for ax, key, unit in ((axs[0], "alpha", "deg"), (axs[1], "q", "deg/s")):
        shade_faults(ax, s)
        ax.plot(s["t"], s[f"{key}_meas"] * DEG, ".", ms=2.5, color="0.35", label="measured")
        ax.plot(s["t"], s[f"{key}_true"] * DEG, "-", lw=1.2, color="k", label="true")
        ax.set_ylabel(f"{'α' if key == 'alpha' else 'q'} ({unit})")
        ax.grid(alpha=0.3)
    axs[0].axhline(STALL_DEG, ls=":", color="tab:red", lw=1, label="15°")
    axs[0].legend(loc="upper left", fontsize=8)
    axs[1].set_xlabel("t (s)")
    fig.suptitle("Fig. 5 — CDRW flight (simulated): α and q" + _note(s))
    return save(fig, out / "fig5_cdrw_alpha_q.png")


def fig6_model(s: Series, out: Path) -> Path | None:
    names = ("a11", "a12", "a21", "a22", "b1", "b2")
    fig, axs = plt.subplots(3, 2, sharex=True, figsize=(9, 7))
    for ax, n in zip(axs.flat, names):
        shade_faults(ax, s)
        for f in ("kf", "zkf", "azkf"):
            ax.plot(s["t"], s[f"{f}_{n}"], color=COLORS[f], lw=1, label=LABELS[f])
        ax.plot(s["t"], s[f"{n}_true"], "k--", lw=1, label="true (local linearisation)")
        ax.set_ylabel(n)
        ax.grid(alpha=0.3)
    # one legend for the figure, in its own strip under the title, clear of every curve
    fig.legend(*axs[0, 0].get_legend_handles_labels(), fontsize=7, ncol=5, loc="upper center",
               bbox_to_anchor=(0.5, 0.935 if _note(s) else 0.955), frameon=False)
    for ax in axs[-1]:
        ax.set_xlabel("t (s)")
    fig.suptitle("Fig. 6 — elements of A_k, B_k estimated by the MLS (h = 2.2 s)" + _note(s))
    return save(fig, out / "fig6_model_elements.png", rect=(0, 0, 1, 0.9 if _note(s) else 0.925))


def fig7_rho(s: Series, out: Path) -> Path | None:
    fig, ax = plt.subplots(figsize=(8, 4))
    shade_faults(ax, s)
    for f in ("kf", "zkf", "azkf"):
        ax.plot(s["t"], s[f"{f}_rho"], color=COLORS[f], lw=1, label=f"ρ(A_k), {LABELS[f]}")
    ax.plot(s["t"], s["rho_true"], "k--", lw=1.2, label="ρ(A) true, separation state held")
    ax.plot(s["t"], s["rho_static"], "k:", lw=1.2, label="ρ(A) quasi-steady (wind-tunnel-like)")
    for tc in _stall_times(s):
        ax.axvline(tc, color="tab:red", lw=0.8, ls=":")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("spectral radius")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    ax.set_title("Fig. 7 — ρ(A_k) estimated by the MLS vs the true model (red: α crosses 15°)"
                 + _note(s), fontsize=10)
    return save(fig, out / "fig7_spectral_radius.png")


def fig8_estimates(s: Series, out: Path) -> Path | None:
    fig, axs = plt.subplots(2, 1, sharex=True, figsize=(8, 6))
    for ax, key, unit in ((axs[0], "alpha", "deg"), (axs[1], "q", "deg/s")):
        shade_faults(ax, s)
        ax.plot(s["t"], s[f"{key}_meas"] * DEG, ".", ms=2.5, color="0.5", label="measured (with fault)")
        ax.plot(s["t"], s[f"{key}_ff"] * DEG, "-", lw=0.8, color="0.2", label="measured, fault-free")
        for f in ("kf", "zkf", "azkf"):
            ax.plot(s["t"], s[f"{f}_{key}_hat"] * DEG, color=COLORS[f], lw=1.1, label=LABELS[f])
        ax.set_ylabel(f"{'α' if key == 'alpha' else 'q'} ({unit})")
        ax.grid(alpha=0.3)
    axs[0].legend(fontsize=7, ncol=2)
    axs[1].set_xlabel("t (s)")
    fig.suptitle("Fig. 8 — estimates under the sensor fault: MLS-AZKF, MLS-ZKF, MLS-KF" + _note(s))
    return save(fig, out / "fig8_estimates_under_fault.png")


def fig9_gains(s: Series, out: Path) -> Path | None:
    fig, axs = plt.subplots(2, 1, sharex=True, figsize=(8, 5), height_ratios=(2, 1))
    ax = axs[0]
    shade_faults(ax, s)
    for f in ("kf", "zkf", "azkf"):
        ax.plot(s["t"], s[f"{f}_gain_norm"], color=COLORS[f], lw=1.1,
                label=("‖K_k‖₂, " if f == "kf" else "‖G_k‖₂, ") + LABELS[f])
    ax.set_ylabel("gain norm")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    shade_faults(axs[1], s)
    axs[1].step(s["t"], s["azkf_order"], where="post", color=COLORS["azkf"], lw=1, label="AZKF order q")
    axs[1].set_yscale("symlog")
    axs[1].set_ylabel("order")
    axs[1].set_xlabel("t (s)")
    # the fault flag on its own 0/1 axis (not on the symlog order axis)
    flag = axs[1].twinx()
    flag.step(s["t"], s["azkf_fault"], where="post", color="k", lw=0.8, ls=":",
              label="AZKF fault flag (right axis)")
    flag.set_ylim(-0.1, 1.6)
    flag.set_yticks([0, 1])
    flag.set_ylabel("fault flag")
    h1, l1 = axs[1].get_legend_handles_labels()
    h2, l2 = flag.get_legend_handles_labels()
    axs[1].legend(h1 + h2, l1 + l2, fontsize=7, loc="upper right")
    fig.suptitle("Fig. 9 — gains of MLS-AZKF and MLS-KF (and the order the AZKF uses)" + _note(s))
    return save(fig, out / "fig9_gain_norms.png")


def fig10_bounds(s: Series, out: Path) -> Path | None:
    """The two filters' alpha bounds on one shared y axis, and a panel of the half-widths
    (the hull of the AZKF against the KF's 3 sigma) with their medians."""
    fig, axs = plt.subplots(3, 1, sharex=True, figsize=(8, 8))
    for ax, f in zip(axs[:2], ("azkf", "kf")):
        shade_faults(ax, s)
        ax.fill_between(s["t"], s[f"{f}_alpha_lo"] * DEG, s[f"{f}_alpha_hi"] * DEG,
                        color=COLORS[f], alpha=0.25, lw=0,
                        label="interval hull of the zonotope" if f != "kf" else "±3σ")
        ax.plot(s["t"], s[f"{f}_alpha_hat"] * DEG, color=COLORS[f], lw=1, label=f"α̂, {LABELS[f]}")
        ax.plot(s["t"], s["alpha_true"] * DEG, "k--", lw=0.8, label="α true")
        ax.set_ylabel("α (deg)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    lo = min(float(np.nanmin(s[f"{f}_alpha_lo"])) for f in ("azkf", "kf")) * DEG
    hi = max(float(np.nanmax(s[f"{f}_alpha_hi"])) for f in ("azkf", "kf")) * DEG
    pad = 0.05 * (hi - lo)
    for ax in axs[:2]:
        ax.set_ylim(lo - pad, hi + pad)  # the same y range in both panels
    ax = axs[2]
    shade_faults(ax, s)
    meds = []
    for f in ("azkf", "kf"):
        half = (s[f"{f}_alpha_hi"] - s[f"{f}_alpha_lo"]) / 2 * DEG
        med = float(np.nanmedian(half))
        meds.append(med)
        ax.plot(s["t"], half, color=COLORS[f], lw=1,
                label=f"{LABELS[f]} {'hull' if f != 'kf' else '3σ'} half-width, median {med:.2f}°")
    ax.set_ylim(0.0, 3.0 * max(meds))  # the initial transient (P0) is clipped
    ax.set_ylabel("half-width (deg)")
    ax.set_xlabel("t (s)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.suptitle("Fig. 10 — bounds of the α estimate: MLS-AZKF vs MLS-KF (shared y axis)" + _note(s))
    return save(fig, out / "fig10_bounds.png")


def all_figures(s: Series, out: Path, note: str = "",
                windows: list[FaultWindow] | None = None) -> list[Callable[[], Path | None]]:
    """Figs. 5-10, to draw (hil.plots.draw); note (e.g. which campaign flight) goes under
    every title; windows (the flight's faults) are shaded, else the series' fault flag."""
    s = {**s, NOTE_KEY: note} if note else s  # type: ignore[dict-item]
    if windows is not None:
        s = {**s, WINDOWS_KEY: windows}  # type: ignore[dict-item]
    return [partial(f, s, out) for f in (fig5_alpha_q, fig6_model, fig7_rho, fig8_estimates,
                                         fig9_gains, fig10_bounds)]


def campaign_figure(c: Series, out: Path) -> Path | None:
    """Table 5's raw material: each flight's error integrals against its fault time."""
    fig, axs = plt.subplots(1, 2, figsize=(10, 4))
    for ax, st, unit in ((axs[0], "alpha", "rad·s"), (axs[1], "q", "rad")):
        for f in ("kf", "zkf", "azkf"):
            ax.plot(c["fault_start"], c[f"{f}_{st}_meas"], "o", ms=3, color=COLORS[f], label=LABELS[f])
        ax.set_xlabel("fault start (s)")
        ax.set_ylabel(f"∫|y − ŷ| dt, {st} ({unit})")
        ax.grid(alpha=0.3)
    axs[0].legend(fontsize=7)
    fig.suptitle(f"Campaign — error integral of each of {len(c['run'])} flights (Table 5 = their means)"
                 "\nagainst the fault-free measurement; Figs. 5-10 of this directory show flight 0")
    return save(fig, out / "campaign_errors.png")


def controls_figure(study: dict, out: Path, made_by: str | None = None) -> Path | None:
    """`hil study cdrw --figure`: AZKF (and ZKF) improvement over the KF per control, with
    the 95 % intervals, beside the paper's Table 5 (dashed)."""
    cases = list(study["cases"].items())
    fig, axs = plt.subplots(1, 2, sharey=True, figsize=(10, 0.38 * len(cases) + 1.8))
    y = np.arange(len(cases))[::-1]
    for ax, key in zip(axs, ("alpha", "q")):
        for off, filt, color in ((0.15, "azkf", COLORS["azkf"]), (-0.15, "zkf", COLORS["zkf"])):
            for yi, (_, c) in zip(y, cases):
                d = c.get(f"{filt}_vs_kf")
                if not d:
                    continue
                lo, hi = d[f"{key}_ci"]
                ax.errorbar(d[key], yi + off, xerr=[[d[key] - lo], [hi - d[key]]], fmt="o",
                            ms=4, color=color, capsize=2,
                            label=f"{LABELS[filt]} vs MLS-KF" if yi == y[0] else None)
            ax.axvline(study["paper"]["table5"][filt][key], ls="--", lw=1, color=color,
                       label=f"paper Table 5, {LABELS[filt]}")
        ax.axvline(0.0, color="k", lw=0.8)
        ax.set_xlabel(f"improvement over MLS-KF on {'α' if key == 'alpha' else 'q'} (%)")
        ax.grid(alpha=0.3)
    axs[0].set_yticks(y, [name for name, _ in cases])
    axs[1].legend(loc="lower right", fontsize=7)
    fig.suptitle(f"Table 5 with its controls (simulated CDRW, sid_replay): mean over "
                 f"{study['runs']} fault times / {study['noise_seeds']} noise seeds, 95 % intervals",
                 fontsize=10)
    return save(fig, out, made_by=made_by)
