"""The papers' figures of merit (hil.results.metrics) and the run-directory files (hil.io.output),
checked against hand-computed values."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from hil.results import metrics
from hil.io.output import read_csv, write_csv, write_json


def test_error_integral_by_hand():
    target = np.array([[0.1, 1.0], [0.2, 2.0], [0.3, 3.0]])
    est = np.array([[0.1, 1.5], [0.1, 2.0], [0.5, 2.0]])
    ea, eq, missing = metrics.error_integral(target, est, 0.02)
    assert ea == pytest.approx((0.0 + 0.1 + 0.2) * 0.02)
    assert eq == pytest.approx((0.5 + 0.0 + 1.0) * 0.02)
    assert missing == 0


def test_error_integral_counts_missing_estimates():
    target = np.zeros((4, 2))
    est = np.array([[1.0, 1.0], [np.nan, np.nan], [1.0, 1.0], [np.nan, 2.0]])
    ea, eq, missing = metrics.error_integral(target, est, 0.5)
    assert (ea, eq, missing) == (1.0, 2.0, 2)


def test_error_integral_shape_check():
    with pytest.raises(ValueError, match="shapes"):
        metrics.error_integral(np.zeros((3, 2)), np.zeros((2, 2)), 0.02)


def test_improvements_match_the_paper_table4():
    imp = metrics.improvements(metrics.PAPER_TABLE4)
    # the paper prints 45.14 %, 16.12 %, 44.33 %, 10.31 %
    assert imp["azkf"]["alpha"] == pytest.approx(45.14, abs=0.01)
    assert imp["azkf"]["q"] == pytest.approx(16.12, abs=0.01)
    assert imp["zkf"]["alpha"] == pytest.approx(44.33, abs=0.01)
    assert imp["zkf"]["q"] == pytest.approx(10.31, abs=0.01)
    assert "kf" not in imp


def test_mean_table():
    a = {f: {"alpha": 1.0, "q": 2.0} for f in metrics.FILTERS}
    b = {f: {"alpha": 3.0, "q": 6.0} for f in metrics.FILTERS}
    assert metrics.mean_table([a, b])["zkf"] == {"alpha": 2.0, "q": 4.0}
    with pytest.raises(ValueError):
        metrics.mean_table([])


def test_missile_rms_over_the_flight_seconds():
    from hil.sim.missile_runs import rms_over
    t = np.linspace(0.0, 1.2, 961)
    x = np.column_stack([np.sin(2 * np.pi * 5 * t), np.where(t <= 1.0, 0.5, 9.0), t])
    rq, ra = rms_over(t, x, 1.0)          # the 0.2 s past the flight's duration do not count
    assert rq == pytest.approx(1 / math.sqrt(2), rel=1e-2)
    assert ra == pytest.approx(0.5)


def test_tables_render():
    text = metrics.format_error_table(metrics.PAPER_TABLE5, "T5", metrics.PAPER_TABLE5)
    assert "0.0895 (+46.9%)" in text and "AZKF" in text and "paper" in text
    runs = [{"period": 0.1, "bits": 8, "rms_q": 0.07, "rms_alpha": 0.005,
             "reference": {"rms_q": 0.07, "code_agreement": 1.0}},
            {"period": 0.1, "bits": None, "rms_q": 0.08, "rms_alpha": 0.006}]
    text = metrics.format_missile_table(runs)
    assert "8 bit" in text and "open" in text and "100.0 %" in text


def test_csv_round_trip(tmp_path):
    cols = {"t": np.array([0.0, 0.02]), "k": np.array([0, 1]), "x": np.array([np.nan, 1 / 3])}
    write_csv(tmp_path / "a.csv", cols)
    back = read_csv(tmp_path / "a.csv")
    assert back["t"].tolist() == [0.0, 0.02] and back["k"].tolist() == [0.0, 1.0]
    assert math.isnan(back["x"][0]) and back["x"][1] == 1 / 3   # full precision
    with pytest.raises(ValueError, match="different lengths"):
        write_csv(tmp_path / "b.csv", {"a": np.zeros(2), "b": np.zeros(3)})


def test_csv_cells_are_exact_text(tmp_path):
    """Every float at full precision (signed zero, either NaN, infinities, a float32 as the
    double it is), integers and booleans as such; only a header name that needs quotes gets them."""
    cols = {"x,y": np.array([1 / 3, -0.0, np.nan, -np.nan, np.inf, -np.inf]),
            "k": np.array([0, -1, 2, 3, 4, 5], dtype=np.int8),
            "f32": np.full(6, 0.1, dtype=np.float32),
            "ok": np.array([True, False, True, False, True, False])}
    write_csv(tmp_path / "c.csv", cols)
    assert (tmp_path / "c.csv").read_text().splitlines() == [
        '"x,y",k,f32,ok',
        "0.3333333333333333,0,0.10000000149011612,1.0", "-0.0,-1,0.10000000149011612,0.0",
        "nan,2,0.10000000149011612,1.0", "nan,3,0.10000000149011612,0.0",
        "inf,4,0.10000000149011612,1.0", "-inf,5,0.10000000149011612,0.0"]


def test_json_is_sorted_and_plain(tmp_path):
    write_json(tmp_path / "s.json", {"b": np.float64(1.5), "a": [np.int64(2), float("nan")]})
    text = (tmp_path / "s.json").read_text()
    assert text.index('"a"') < text.index('"b"')
    assert json.loads(text) == {"a": [2, None], "b": 1.5}


def _flight(azkf_a, zkf_a, kf_a, q_scale=2.0):
    return {"azkf": {"alpha": azkf_a, "q": q_scale * azkf_a}, "zkf": {"alpha": zkf_a, "q": q_scale * zkf_a},
            "kf": {"alpha": kf_a, "q": q_scale * kf_a}}


def test_campaign_table5_intervals_by_hand():
    # three flights; t(0.975, 2) = 4.302652729749464 (tables of the Student-t distribution)
    errs = [_flight(1.0, 2.0, 3.0), _flight(2.0, 2.5, 1.5), _flight(3.0, 2.0, 5.0)]
    t5 = metrics.campaign_table5(errs, errs)
    assert t5["runs_count"] == 3 and t5["ci_level"] == 0.95 and "Student-t" in t5["ci_method"]
    c = t5["table5_ci"]["azkf"]["alpha"]
    s = math.sqrt(((1 - 2) ** 2 + 0 + (3 - 2) ** 2) / 2)       # 1.0
    h = 4.302652729749464 * s / math.sqrt(3)
    assert c["mean"] == pytest.approx(2.0) and c["std"] == pytest.approx(s)
    # (scipy < 1.17 computes the quantile 1.2e-11 away from the table: hil allows scipy >= 1.14)
    assert c["half_width"] == pytest.approx(h, rel=1e-10)
    assert (c["lo"], c["hi"]) == (pytest.approx(2.0 - h), pytest.approx(2.0 + h))
    assert t5["table5"]["kf"]["q"] == pytest.approx(2 * (3.0 + 1.5 + 5.0) / 3)
    # paired improvement: d = kf - azkf = (2, -0.5, 2), mean 7/6, scaled by 100 / mean(kf)
    d = np.array([2.0, -0.5, 2.0])
    ic = t5["improvement_over_kf_ci"]["azkf"]["alpha"]
    assert ic["mean"] == pytest.approx(100 * d.mean() / (9.5 / 3))
    assert ic["mean"] == pytest.approx(t5["improvement_over_kf_pct"]["azkf"]["alpha"])
    assert ic["half_width"] == pytest.approx(100 * 4.302652729749464 * d.std(ddof=1) / math.sqrt(3) / (9.5 / 3))
    assert t5["azkf_better_than_kf_runs"] == {"alpha": 2, "q": 2}
    assert t5["zkf_better_than_kf_runs"] == {"alpha": 2, "q": 2}
    assert t5["azkf_better_than_kf_truth_runs"] == {"alpha": 2, "q": 2}
    text = metrics.format_table5(t5)
    assert "2.0000 +- " + f"{h:.4f}" in text and "AZKF better than KF in 2 of 3 flights" in text
    json.dumps(t5, allow_nan=False)                               # plain JSON


def test_campaign_table5_one_flight_has_no_interval():
    t5 = metrics.campaign_table5([_flight(1.0, 2.0, 3.0)], [_flight(1.0, 2.0, 3.0)])
    c = t5["table5_ci"]["kf"]["q"]
    assert c["mean"] == 6.0 and c["half_width"] is None and c["lo"] is None
    assert "+-" not in metrics.format_table5(t5).splitlines()[2]
    with pytest.raises(ValueError):
        metrics.campaign_table5([], [])


def test_coverage_table_by_hand():
    truth = np.array([[0.0, 1.0], [0.5, 1.0], [1.0, 1.0], [2.0, 1.0]])
    lo = np.array([[-1.0, 0.0], [0.0, 0.0], [np.nan, np.nan], [0.0, 1.5]])
    hi = np.array([[1.0, 2.0], [0.4, 2.0], [np.nan, np.nan], [3.0, 2.0]])
    cov = metrics.coverage_table(truth, {"kf": (lo, hi)})
    assert cov == {"kf": {"alpha": pytest.approx(2 / 3), "q": pytest.approx(2 / 3)}}
    assert "66.7%" in metrics.format_coverage(cov, "t")


def test_campaign_table5_with_coverage():
    errs = [_flight(1.0, 2.0, 3.0), _flight(2.0, 2.5, 1.5)]
    cov = [{f: {"alpha": 1.0, "q": 0.5} for f in metrics.FILTERS},
           {f: {"alpha": 0.8, "q": 0.7} for f in metrics.FILTERS}]
    t5 = metrics.campaign_table5(errs, errs, coverage=cov)
    assert t5["coverage"]["kf"] == {"alpha": pytest.approx(0.9), "q": pytest.approx(0.6)}
    assert t5["coverage_ci"]["azkf"]["q"]["mean"] == pytest.approx(0.6)
