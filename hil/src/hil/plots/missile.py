"""Seed 2's figures: RMS of q and alpha_T against the period for each D/A word length and
the open loop (Fig. 3), and the time responses at each period (Figs. 4-6: 6, 8 and 12 bits
against the open loop)."""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from hil.plots.faults import flag_spans, name_windows, shade, window_spans
from hil.plots.mpl import plt, save
from hil.results.faultwindows import FaultWindow

Series = dict[str, np.ndarray]
BITS_COLORS = {6: "tab:red", 8: "tab:green", 12: "tab:blue"}


def _color(bits: int | None) -> str:
    if bits is None:
        return "k"
    return BITS_COLORS.get(bits, f"C{bits % 10}")


def fig3_rms(runs: Sequence[Mapping[str, Any]], out: Path) -> Path | None:
    """RMS vs T: one line per word length, open loop dashed (needs >= 1 period)."""
    if not runs:
        return None
    fig, axs = plt.subplots(1, 2, figsize=(10, 4))
    groups: dict[int | None, list[Mapping[str, Any]]] = {}
    for r in runs:
        groups.setdefault(r.get("bits"), []).append(r)
    for bits, rs in sorted(groups.items(), key=lambda kv: (kv[0] is None, kv[0] or 0)):
        rs = sorted(rs, key=lambda r: r["period"])
        T = [r["period"] for r in rs]
        label = "open loop" if bits is None else f"{bits}-bit D/A"
        style = "--" if bits is None else "o-"
        for ax, key in ((axs[0], "rms_q"), (axs[1], "rms_alpha")):
            ax.plot(T, [r[key] for r in rs], style, color=_color(bits), label=label, ms=4)
    # the stationary RMS by covariance analysis (no D/A quantisation), where the summary has it
    closed = sorted((r for r in runs if r.get("bits") is not None and r.get("stationary")),
                    key=lambda r: r["period"])
    seen: dict[float, Mapping[str, Any]] = {r["period"]: r for r in closed}
    if seen:
        T = sorted(seen)
        for ax, key in ((axs[0], "rms_q"), (axs[1], "rms_alpha")):
            ax.plot(T, [seen[t]["stationary"][key] for t in T], ":", color="0.4",
                    label="stationary, no quantisation")
    opened = [r for r in runs if r.get("bits") is None and r.get("stationary")]
    if opened:
        for ax, key in ((axs[0], "rms_q"), (axs[1], "rms_alpha")):
            ax.axhline(opened[0]["stationary"][key], color="0.6", lw=0.8, ls="-.",
                       label="open loop, stationary")
    axs[0].set_ylabel("RMS q (rad/s)")
    axs[1].set_ylabel("RMS α_T (rad)")
    for ax in axs:
        ax.set_xlabel("sampling period T (s)")
        ax.grid(alpha=0.3)
        ax.set_yscale("log")
    axs[0].legend(fontsize=8)
    fig.suptitle("Fig. 3 — missile: RMS of q and α_T vs the sampling period")
    return save(fig, out / "fig3_missile_rms.png")


def fig3_covariance(doc: Mapping[str, Any], out: Path,
                    name: str = "fig3_missile_rms_covariance.png",
                    made_by: str | None = None) -> Path | None:
    """Fig. 3 as the paper ran it (hil.results.figures): per gyro variance (rows) the stationary
    RMS of q and alpha_T (columns) by covariance analysis against T for each word length and
    an ideal D/A, the open-loop level, and the HIL Monte-Carlo points with 95 % intervals."""
    studies = doc.get("studies") or []
    if not studies:
        return None
    fig, axs = plt.subplots(len(studies), 2, figsize=(11, 3.8 * len(studies)), squeeze=False)
    for row, st in zip(axs, studies):
        ps = st["periods"]
        T = [p["period"] for p in ps]
        for ax, key, unit in ((row[0], "rms_q", "RMS q (rad/s)"), (row[1], "rms_alpha", "RMS α_T (rad)")):
            ax.plot(T, [p[key] for p in ps], "-", color="0.3", lw=2.2, alpha=0.5, label="ideal D/A")
            for n in sorted(ps[0]["dac"] if ps else {}, key=int):
                ax.plot(T, [p["dac"][n][key] for p in ps], "-", color=_color(int(n)), lw=1.1,
                        label=f"{n}-bit D/A (LSB²/12 noise)")
            ax.axhline(st["open_loop"][key], color="k", ls="--", lw=1.0, label="open loop")
            mc = st.get("monte_carlo")
            for n in sorted(mc["periods"][0]["dac"] if mc and mc["periods"] else {}, key=int):
                ax.plot([p["period"] for p in mc["periods"]],
                        [p["dac"][n][key] for p in mc["periods"]], "x", ms=7, mew=1.6,
                        color=_color(int(n)),
                        label=f"{n}-bit, real quantiser (Monte Carlo, {mc['loops']} × "
                        f"{mc['seconds']:g} s)")
            pts = [h for h in doc.get("hil", []) if h["gyro_var"] == st["gyro_var"]]
            for h in pts:
                lo, hi, v = h[f"{key}_lo"], h[f"{key}_hi"], h[key]
                ax.errorbar([h["period"]], [v], yerr=[[v - lo], [hi - v]], fmt="o", ms=5,
                            color=_color(int(h["bits"])), mec="k", capsize=3)
            if pts:
                ax.plot([], [], "o", color="0.5", mec="k",
                        label=f"HIL fcc, {pts[0]['seconds']:g} s flight, 95 % CI")
            ax.set_xlabel("sampling period T (s)")
            ax.set_ylabel(unit)
            ax.set_title(f"gyro variance {st['gyro_var']:g} rad²/s², accel {st['accel_var']:g}",
                         fontsize=9)
            ax.grid(alpha=0.3)
        row[1].legend(fontsize=7, loc="lower right")
    mc_note = any(st.get("monte_carlo") for st in studies)
    fig.suptitle("Fig. 3 — missile: stationary RMS vs the sampling period (lines: covariance "
                 "analysis, D/A as LSB²/12 noise" + ("; ×: real quantiser" if mc_note else "") + ")",
                 fontsize=10)
    return save(fig, out / name, made_by=made_by)


def fig_time_response(period: float, curves: Mapping[int | None, Series], out: Path,
                      steps: Mapping[int | None, Series] | None = None,
                      subtitle: str = "", deterministic: bool = False,
                      faults: Sequence[FaultWindow] | None = None) -> Path | None:
    """The time response at one period (time_response), written."""
    fig = time_response(period, curves, steps, subtitle, deterministic, faults)
    name = (f"fig4-6_missile_response_T{period:.3f}.png" if deterministic
            else f"missile_gust_flight_T{period:.3f}.png")
    return save(fig, out / name)


def time_response(period: float, curves: Mapping[int | None, Series],
                  steps: Mapping[int | None, Series] | None = None, subtitle: str = "",
                  deterministic: bool = False, faults: Sequence[FaultWindow] | None = None) -> plt.Figure:
    """q(t) and alpha_T(t) at one period for each word length, against the open loop.  With
    the per-step series (steps: missile_T*_b*.csv): on top, what the closed loop of the
    longest word saw -- the gyro reading as sent (faults in it), the true q and fcc's estimate
    q_hat (MSL_STATE_EST) -- and below, the applied elevator (D/A output, held).  Every panel
    shades the fault windows (faults: the flight's events; else the series' fault flag)."""
    sensed = max((b for b in steps or {} if b is not None and "q_hat" in (steps or {})[b]), default=None)
    n = 2 + (sensed is not None) + bool(steps)
    fig, axs = plt.subplots(n, 1, sharex=True, figsize=(9, 2.4 * n + 0.8))
    top = sensed is not None
    ax_q, ax_a = axs[int(top)], axs[int(top) + 1]
    order = sorted(curves, key=lambda b: (b is None, b or 0))
    for i, bits in enumerate(order):
        s = curves[bits]
        label = "open loop" if bits is None else f"{bits}-bit D/A"
        lw = 0.8 if bits is None else 1.1
        # a trace equal to one drawn before it hides under it: say so, and dash it
        same = [b for b in order[:i] if _same_trace(curves[b], s)]
        if same:
            label += " (= " + ", ".join("open loop" if b is None else f"{b}-bit" for b in same) \
                + ", drawn over it dashed)"
            lw = 1.6
        ls = "--" if same else "-"
        ax_q.plot(s["t"], s["q"], color=_color(bits), lw=lw, ls=ls, label=label)
        ax_a.plot(s["t"], s["alpha_T"], color=_color(bits), lw=lw, ls=ls, label=label)
        if steps and bits is not None and bits in steps:
            e = steps[bits]
            axs[-1].step(e["t"], e["u"], where="post", color=_color(bits), lw=lw, label=label)
    t_end = max(float(s["t"][-1]) for s in curves.values() if len(s["t"]))
    if sensed is not None:
        e = (steps or {})[sensed]
        _sensor_panel(axs[0], e, curves.get(sensed), sensed)
        ax_a.step(e["t"], e["alpha_T_hat"], where="post", color=_color(sensed), lw=0.9, ls=":",
                  label=f"fcc's estimate α̂_T ({sensed}-bit)")
        windows = list(faults or [])
        spans = window_spans(windows, t_end) if faults is not None else flag_spans(e["t"], e.get("fault"))
        for ax in axs:
            shade(ax, spans)
        name_windows(axs[0], windows, t_end)
        axs[0].legend(fontsize=7, ncol=4, loc="upper right")
    ax_q.set_ylabel("q (rad/s)")
    ax_a.set_ylabel("α_T (rad)")
    if steps:
        axs[-1].set_ylabel("elevator (rad)")
    axs[-1].set_xlabel("t (s)")
    for ax in axs:
        ax.grid(alpha=0.3)
    ax_q.legend(fontsize=7, ncol=4, loc="upper right")
    ax_a.legend(fontsize=7, ncol=2, loc="upper right")
    title = (f"Figs. 4–6 — missile time response at T = {period:g} s" if deterministic else
             f"Missile flight in gusts with sensor noise at T = {period:g} s (not the paper's "
             "Figs. 4–6, which are deterministic)")
    fig.suptitle(title + (f"\n{subtitle}" if subtitle else ""), fontsize=10)
    return fig


def _sensor_panel(ax, e: Series, fine: Series | None, bits: int) -> None:
    """The gyro reading fcc received, the true pitch rate and fcc's estimate of it."""
    ax.plot(e["t"], e["q_g"], ".", ms=3, color="0.4", label="gyro q_g as sent (noise, faults)")
    truth = fine if fine is not None else e
    ax.plot(truth["t"], truth["q"], "-", color="k", lw=1.1, label="true q")
    ax.step(e["t"], e["q_hat"], where="post", color="tab:orange", lw=1.3,
            label="fcc's estimate q̂ (MSL_STATE_EST)")
    ax.set_ylabel("q (rad/s)")
    ax.set_title(f"closed loop, {bits}-bit D/A: measured, true and estimated pitch rate", fontsize=9)


def _same_trace(a: Series, b: Series) -> bool:
    return (len(a["t"]) == len(b["t"]) and bool(np.allclose(a["q"], b["q"], rtol=0, atol=1e-12))
            and bool(np.allclose(a["alpha_T"], b["alpha_T"], rtol=0, atol=1e-12)))
