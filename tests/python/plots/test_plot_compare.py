"""`hil plot` and `hil compare` on a recorded run directory (hil verify's fixture: a real
lockstep flight of both aircraft), their errors (one line, exit 2), the missile figure's
shaded fault windows and its measured / true / estimated pitch rate, and compare.html in
headless Chromium."""
from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from browser import PNG_MAGIC, screenshot
from hil.io.rundir import MANIFEST
from hil.plots import cdrw, missile
from hil.plots.mpl import caption_path, plt
from hil.results.faultwindows import FaultWindow
from rig_helpers import cli

RECORDED = Path(__file__).resolve().parents[2] / "vectors" / "verify"


def _png(path: Path) -> bytes:
    data = path.read_bytes()
    assert data[:8] == PNG_MAGIC and len(data) > 5_000, path
    return data


def test_plot_redraws_the_table_bars_into_out_and_the_caption_names_the_run(tmp_path, capsys) -> None:
    rc, out, err = cli(capsys, "plot", str(RECORDED), "--figures", "tables", "--out", str(tmp_path / "figs"))
    assert rc == 0, err
    png = tmp_path / "figs" / "table4_bars.png"
    _png(png)
    assert f"(redraw: hil plot {RECORDED})" in caption_path(png).read_text()
    assert "table4_bars.png" in json.loads((tmp_path / "figs" / MANIFEST).read_text())["files"]
    assert out.splitlines() == ["plots: table4_bars.png", f"figures in {tmp_path / 'figs'}/"]


@pytest.mark.parametrize("argv, message", [
    (["plot", "NOPE"], "NOPE: no such run directory"),
    (["plot", "EMPTY"], "EMPTY: no summary.json (not a run directory)"),
    (["plot", "RUN", "--figures", "fig99"], "--figures fig99: no such figures (choose from cdrw, campaign"),
    (["plot", "RUN", "--figures", "timing", "--out", "OUT"], "RUN: no figures to draw of timing"),
    (["compare", "RUN"], "compare: give two run directories or more"),
    (["compare", "RUN", "NOPE", "--out", "OUT"], "NOPE: no such run directory"),
    (["compare", "RUN", "RUN", "--out", "RUN"], "--out RUN: holds the compared run RUN; the comparison goes elsewhere"),
])
def test_errors_are_one_line_and_exit_2(tmp_path, capsys, argv, message) -> None:
    (tmp_path / "EMPTY").mkdir()
    names = {"NOPE": tmp_path / "missing", "EMPTY": tmp_path / "EMPTY", "RUN": RECORDED, "OUT": tmp_path / "out"}
    argv = [str(names.get(a, a)) for a in argv]
    message = message.replace("NOPE", str(names["NOPE"])).replace("EMPTY", str(names["EMPTY"])) \
        .replace("RUN", str(RECORDED))
    rc, out, err = cli(capsys, *argv)
    assert rc == 2 and out == ""
    assert err.count("\n") == 1 and err.startswith(f"hil: {message}"), err
    assert not (tmp_path / "out").exists()   # nothing published


def test_compare_writes_its_figures_and_a_page_chromium_renders(tmp_path, capsys) -> None:
    other = tmp_path / "again"
    shutil.copytree(RECORDED, other)
    s = json.loads((other / "summary.json").read_text())
    s["missile"]["runs"][0]["rms_q"] *= 1.5   # a second run whose closed loop did worse
    (other / "summary.json").write_text(json.dumps(s))
    rc, out, err = cli(capsys, "compare", str(RECORDED), str(other), "--out", str(tmp_path / "cmp"))
    assert rc == 0, err
    _png(tmp_path / "cmp" / "compare_metrics.png")
    page = tmp_path / "cmp" / "compare.html"
    text = page.read_text()
    assert text.count("verdict PASS | cdrw cdrw_default") == 2 and "data:image/png;base64," in text
    q = s["missile"]["runs"][0]["rms_q"]
    assert f"<td class='n'>{q / 1.5:.4g}</td>" in text and f"<td class='n'>{q:.4g}</td>" in text
    assert f"+{q - q / 1.5:.4g} (+50.0 %)" in text and "<td class='n'>0</td>" in text
    shot = screenshot(page, tmp_path / "shot.png")
    assert shot[:8] == PNG_MAGIC and len(shot) > 10_000   # a page was drawn, not a blank


def test_the_missile_figure_shades_each_fault_window_and_shows_gyro_truth_and_estimate() -> None:
    t = np.arange(100) * 0.1
    fine = {"t": np.arange(400) * 0.025, "q": np.zeros(400), "alpha_T": np.zeros(400)}
    steps = {"t": t, "q": np.zeros(100), "q_g": np.where((t >= 3) & (t < 4), 0.5, 0.1), "q_hat": np.zeros(100),
             "alpha_T_hat": np.zeros(100), "u": np.zeros(100), "fault": np.zeros(100)}
    windows = [FaultWindow("stuck", "q_g", 3.0, 4.0), FaultWindow("bad_crc", "MSL_ACCELEROMETER", 6.0, None)]
    fig = missile.time_response(0.1, {8: fine, None: fine}, {8: steps}, faults=windows)
    try:
        top = fig.axes[0]
        spans = sorted((round(p.get_x(), 6), round(p.get_x() + p.get_width(), 6)) for p in top.patches)
        assert spans == [(3.0, 4.0), (6.0, 9.975)]   # the open one to the end of the flight
        assert all(len(ax.patches) == 2 for ax in fig.axes)   # in every panel
        labels = top.get_legend_handles_labels()[1]
        assert labels == ["gyro q_g as sent (noise, faults)", "true q", "fcc's estimate q̂ (MSL_STATE_EST)",
                          "fault active"]
        assert [a.get_text() for a in top.texts] == ["stuck(q_g)", "bad_crc(MSL_ACCELEROMETER)"]
    finally:
        plt.close(fig)
    # no events: the series' own fault flag
    steps["fault"] = ((t >= 3) & (t < 4)).astype(int)
    fig = missile.time_response(0.1, {8: fine}, {8: steps})
    try:
        assert [(round(p.get_x(), 6), round(p.get_x() + p.get_width(), 6)) for p in fig.axes[0].patches] == [(3.0, 4.0)]
    finally:
        plt.close(fig)


def test_cdrw_figures_shade_every_faults_window_else_the_sensor_fault_flag() -> None:
    t = np.arange(100) * 0.02
    s = {"t": t, "fault": ((t >= 1.0) & (t < 1.2)).astype(int)}
    windows = [FaultWindow("flood", "bus", 0.4, 0.6), FaultWindow("replay", "CDRW_AOA", 1.5, None)]
    fig, (a, b) = plt.subplots(2, 1)
    try:
        cdrw.shade_faults(a, {**s, cdrw.WINDOWS_KEY: windows})
        cdrw.shade_faults(b, s)
        assert [(round(p.get_x(), 6), round(p.get_x() + p.get_width(), 6)) for p in a.patches] == \
            [(0.4, 0.6), (1.5, 1.98)]
        assert [(round(p.get_x(), 6), round(p.get_x() + p.get_width(), 6)) for p in b.patches] == [(1.0, 1.2)]
    finally:
        plt.close(fig)
