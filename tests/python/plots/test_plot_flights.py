"""On the bus: a missile flight with a stuck gyro ends with its verdict line first; its figure
shades the fault's window (from the flight's events) over the gyro reading fcc received, the
true q and fcc's estimate; `hil plot` redraws it; `hil compare` overlays it with a clean
flight; run_info.json and the captions name only files that outlive the run."""
from __future__ import annotations

import json

import pytest

from hil.io.output import read_csv
from hil.plots import missile
from hil.plots.mpl import caption_path, plt
from hil.results.faultwindows import flight_events, from_events
from rig_helpers import cli

STUCK = "stuck:signal=q_g,start=3,duration=1"


@pytest.mark.vcan
def test_a_stuck_gyro_is_in_the_verdict_the_figure_and_the_comparison(tmp_path, capsys) -> None:
    a, b = tmp_path / "stuck", tmp_path / "clean"
    rc, out, err = cli(capsys, "run", "missile", "--fault", STUCK, "--out", str(a), "--quiet")
    assert rc == 0, err
    first = out.splitlines()[0]
    assert first.startswith("verdict n/a | missile missile_default, lockstep, random seed 1 | "
                            "faults stuck(q_g)@3-4s | T 0.1 s, 8-bit D/A: RMS q "), first
    # the gyro fcc received holds one value through the window; its estimate is in the series
    steps = read_csv(a / "missile_T0.100_b8.csv")
    held = steps["q_g"][(steps["t"] >= 3.0 - 1e-9) & (steps["t"] < 4.0 - 1e-9)]
    assert len(held) == 10 and len(set(held.tolist())) == 1 and not (steps["q_hat"] == 0).all()
    summary = json.loads((a / "summary.json").read_text())
    fig = missile.time_response(0.1, {8: read_csv(a / "missile_T0.100_b8_fine.csv")}, {8: steps},
                                faults=from_events(flight_events(summary, "missile")))
    try:
        spans = [(p.get_x(), p.get_x() + p.get_width()) for p in fig.axes[0].patches]
        assert spans == [pytest.approx((3.0, 4.0))]
    finally:
        plt.close(fig)
    # recorded paths outlive the run: the kept key and the published directory
    info = json.loads((a / "run_info.json").read_text())
    assert "--key-file session.key " in info["fcc_command"] and "partial" not in info["fcc_command"]
    png = a / "missile_gust_flight_T0.100.png"
    assert caption_path(png).read_text().rstrip().endswith(f"(redraw: hil plot {a})")
    png.unlink()
    rc, out, err = cli(capsys, "plot", str(a), "--figures", "missile")
    assert rc == 0 and out.splitlines()[0] == "plots: missile_gust_flight_T0.100.png", err
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    rc, _, err = cli(capsys, "run", "missile", "--out", str(b), "--quiet", "--no-plots")
    assert rc == 0, err
    rc, out, err = cli(capsys, "compare", str(a), str(b), "--out", str(tmp_path / "cmp"))
    assert rc == 0, err
    assert out.splitlines()[0] == "compare: compare_missile.png, compare_metrics.png, compare.html"
    page = (tmp_path / "cmp" / "compare.html").read_text()
    assert "faults stuck(q_g)@3-4s" in page and "no faults" in page
