"""The figure of each identifier's response times against its bound (hil.plots.busresponse),
drawn from summary.json's `bus` section alone: no guest, no canbus.

The section is hil.results.busstats's from canbus's statistics of a recorded run (the missile at
250 kbit/s of docs/bus-timing.md, "Measured": its per-identifier n, p50, p99, max); a copy with
the gyro's maximum raised above its bound must be drawn red and marked ABOVE; fcc's frames
(FIFO-queued) are judged like the others, against hil.bus.wcrt's FIFO bound."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from hil.bus import load
from hil.plots import busresponse
from hil.plots.mpl import caption_path, plt
from hil.results.busstats import ABOVE, WITHIN, bus_section
from hil.scenario.file import load_default_scenario
from rig_helpers import cli

SPEC = load()
#: the missile at 250 kbit/s (docs/bus-timing.md): name -> (n, p50, p99, max) in ms
MEASURED_250K = {
    "TSYNC_SYNC": (104, 0.48, 0.81, 0.88), "TSYNC_AUTH": (104, 0.66, 1.13, 1.15),
    "MSL_ELEV_CMD": (94, 0.48, 0.80, 0.80), "MSL_RATE_GYRO": (100, 0.47, 0.78, 1.03),
    "MSL_ACCELEROMETER": (100, 0.72, 2.42, 2.54), "MSL_STATE_EST": (94, 0.88, 2.98, 2.98),
    "MSL_ELEV_CMD_AUTH": (94, 1.51, 3.45, 3.45), "FCC_STATUS": (109, 0.48, 1.41, 3.00),
    "FCC_STATUS_AUTH": (109, 4.72, 6.09, 7.38)}


def section(**override: tuple[int, float, float, float]) -> dict:
    """The bus section of the recorded run (names in `override` with other figures)."""
    got = {**MEASURED_250K, **override}
    ids = {f"0x{SPEC.by_name(n).frame_id:03X}": {"n": v[0], "p50_s": v[1] * 1e-3, "p99_s": v[2] * 1e-3,
                                                  "max_s": v[3] * 1e-3} for n, v in got.items()}
    stats = {"bitrate": 250_000, "frames": sum(v[0] for v in got.values()), "lost": 0, "late_queued": 0,
             "load": 0.2, "cpu_s": 1.0, "wall_s": 10.0, "ids": ids,
             "delivery_error": {"n": 1, "p50_s": 2e-4, "p99_s": 1e-2, "max_s": 7e-2, "early": 0}}
    return bus_section(stats, SPEC, [load_default_scenario("missile")])


def marks(fig: plt.Figure) -> dict[str, str]:
    """Row label -> the text drawn beside it."""
    ax = fig.axes[0]
    labels = [t.get_text() for t in ax.get_yticklabels()]
    return {labels[round(t.xy[1])]: t.get_text() for t in ax.texts}


def test_the_figure_is_drawn_from_a_recorded_summary(tmp_path: Path, capsys) -> None:
    run = tmp_path / "run"
    run.mkdir()
    (run / "summary.json").write_text(json.dumps({"command": "run missile", "mode": "realtime",
                                                  "bus": section()}))
    rc, out, err = cli(capsys, "plot", str(run), "--figures", "bus")
    assert rc == 0 and out.splitlines()[0] == f"plots: {busresponse.NAME}", err
    png = run / busresponse.NAME
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "0 of 9 frames above" in caption_path(png).read_text()
    # frames sorted by identifier; fcc's (FIFO) and the simulator's within (nothing beside them)
    rows = busresponse.rows(section())
    assert [r.frame_id for r in rows] == sorted(SPEC.by_name(n).frame_id for n in MEASURED_250K)
    by_name = {r.name: r for r in rows}
    assert by_name["MSL_ELEV_CMD"].verdict == WITHIN and by_name["MSL_ELEV_CMD"].mark == ""
    assert by_name["FCC_STATUS_AUTH"].verdict == WITHIN and section()["frames"]["FCC_STATUS_AUTH"]["queue"] == "fifo"
    assert by_name["MSL_RATE_GYRO"].verdict == WITHIN and by_name["MSL_RATE_GYRO"].mark == ""


def test_a_frame_above_its_bound_is_drawn_red_and_marked() -> None:
    sec = section(MSL_RATE_GYRO=(100, 0.47, 0.78, 9.0))   # bound at 250k: 4.86 ms
    gyro = sec["frames"]["MSL_RATE_GYRO"]
    assert gyro["verdict"] == ABOVE and gyro["max_s"] > gyro["wcrt_s"]
    fig = busresponse.figure(sec)
    try:
        said = marks(fig)
        gyro_label = f"{SPEC.by_name('MSL_RATE_GYRO').frame_id:#05x} MSL_RATE_GYRO"
        assert said[gyro_label] == "ABOVE"
        assert said.get(f"{SPEC.by_name('MSL_ELEV_CMD').frame_id:#05x} MSL_ELEV_CMD", "") == ""
        assert "TSYNC_SYNC" not in " ".join(k for k, v in said.items() if v)
        # its max marker is red and to the right of its bound's bar
        row = [r.label for r in busresponse.rows(sec)].index(gyro_label)
        lines = [ln for ln in fig.axes[0].lines if list(ln.get_ydata()) == [row]]
        top = next(ln for ln in lines if ln.get_marker() == "^")
        assert top.get_color() == "tab:red" and top.get_xdata()[0] == pytest.approx(9.0)
        bound = next(ln for ln in fig.axes[0].lines if ln.get_linewidth() == 2 and len(ln.get_xdata()) == 2
                     and ln.get_ydata()[0] < row < ln.get_ydata()[1])
        assert bound.get_xdata()[0] < 9.0
        assert "1 of 9 frames above" in fig._suptitle.get_text()
    finally:
        plt.close(fig)


def test_a_fifo_frame_above_its_bound_is_marked_too() -> None:
    sec = section(FCC_STATUS_AUTH=(109, 4.72, 6.09, 60.0))   # fcc's FIFO bound at 250k: 19.98 ms
    auth = sec["frames"]["FCC_STATUS_AUTH"]
    assert auth["queue"] == "fifo" and auth["verdict"] == ABOVE and auth["wcrt_s"] < 0.06
    fig = busresponse.figure(sec)
    try:
        assert marks(fig)[f"{SPEC.by_name('FCC_STATUS_AUTH').frame_id:#05x} FCC_STATUS_AUTH"] == "ABOVE"
    finally:
        plt.close(fig)
