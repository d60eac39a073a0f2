"""Seed 2's figures: RMS of q and alpha_T against the period for each D/A word length and
the open loop (Fig. 3), and the time responses at each period (Figs. 4-6: 6, 8 and 12 bits
against the open loop)."""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ._mpl import plt, save

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


def fig_time_response(period: float, curves: Mapping[int | None, Series], out: Path) -> Path:
    """q(t) and alpha_T(t) at one period for each word length, against the open loop."""
    fig, axs = plt.subplots(2, 1, sharex=True, figsize=(8, 5.5))
    for bits in sorted(curves, key=lambda b: (b is None, b or 0)):
        s = curves[bits]
        label = "open loop" if bits is None else f"{bits}-bit D/A"
        lw = 0.8 if bits is None else 1.1
        axs[0].plot(s["t"], s["q"], color=_color(bits), lw=lw, label=label)
        axs[1].plot(s["t"], s["alpha_T"], color=_color(bits), lw=lw, label=label)
    axs[0].set_ylabel("q (rad/s)")
    axs[1].set_ylabel("α_T (rad)")
    axs[1].set_xlabel("t (s)")
    for ax in axs:
        ax.grid(alpha=0.3)
    axs[0].legend(fontsize=8, ncol=4)
    fig.suptitle(f"Figs. 4–6 — missile time response at T = {period:g} s")
    return save(fig, out / f"fig4-6_missile_response_T{period:.3f}.png")
