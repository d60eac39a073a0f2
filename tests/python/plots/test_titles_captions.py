"""Every figure titled by what it is, with a one-line caption file naming its run; Fig. 10 on
a shared y axis; a trace hidden under another said so."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from hil.plots import cdrw, missile
from hil.plots.mpl import caption_path


def _cdrw_series(n: int = 200) -> dict:
    t = np.arange(n) * 0.02
    s = {"t": t, "alpha_true": 0.2 + 0.05 * np.sin(t), "fault": np.zeros(n)}
    for f, w in (("azkf", 0.03), ("kf", 0.01)):
        s[f"{f}_alpha_hat"] = s["alpha_true"].copy()
        s[f"{f}_alpha_lo"] = s["alpha_true"] - w
        s[f"{f}_alpha_hi"] = s["alpha_true"] + w * (3 if f == "kf" else 1)
    return s


def test_fig10_shares_its_y_axis_and_has_a_caption(tmp_path: Path) -> None:
    png = cdrw.fig10_bounds(_cdrw_series(), tmp_path)
    cap = caption_path(png).read_text()
    assert cap.startswith("Fig. 10") and f"hil plot {tmp_path}" in cap and cap.count("\n") == 1


def test_gust_flight_is_not_titled_figs_4_6_and_hidden_trace_is_said(tmp_path: Path) -> None:
    t = np.arange(50) * 0.1
    flat = {"t": t, "q": np.cos(t), "alpha_T": np.sin(t)}
    other = {"t": t, "q": 0.5 * np.cos(t), "alpha_T": 0.5 * np.sin(t)}
    png = missile.fig_time_response(0.2, {None: flat, 6: dict(flat), 8: other}, tmp_path)
    assert png.name == "missile_gust_flight_T0.200.png"
    cap = caption_path(png).read_text()
    assert "Figs. 4–6" not in cap.split("(")[0] and "gusts" in cap
    png2 = missile.fig_time_response(0.2, {None: flat, 6: dict(flat)}, tmp_path, deterministic=True)
    assert png2.name == "fig4-6_missile_response_T0.200.png"
    assert caption_path(png2).read_text().startswith("Figs. 4–6")
    assert missile._same_trace(flat, dict(flat)) and not missile._same_trace(flat, other)
