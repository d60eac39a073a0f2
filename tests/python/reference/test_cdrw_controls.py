"""`hil study cdrw`: the Table 5 controls' machinery on small sizes, and the robust
inequalities the docs rest on (the AZKF's advantage survives without a fault, vanishes with
the true model; the posterior rows raise it; a small ZKF order turns the ZKF's loss round)."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from hil.reference import cdrw_controls as cc


@pytest.fixture(scope="module")
def study(bin_path) -> dict:
    names = ["paper", "no_fault", "true_model", "rows_posterior", "zkf_order_2", "noise_seeds"]
    return cc.cdrw_study(bin_path("sid_replay"), runs=3, noise_seeds=3, only=names)


def test_structure(study: dict) -> None:
    assert study["runs"] == 3 and study["noise_seeds"] == 3
    assert list(study["cases"]) == ["paper", "no_fault", "true_model", "rows_posterior",
                                    "zkf_order_2", "noise_seeds"]
    for name, c in study["cases"].items():
        a = c["azkf_vs_kf"]
        for key in ("alpha", "q"):
            lo, hi = a[f"{key}_ci"]
            assert lo <= a[key] + 1e-9 and a[key] <= hi + 1e-9, (name, key)
    assert study["cases"]["no_fault"]["n"] == 1
    assert "zkf_vs_kf" not in study["cases"]["true_model"]   # KF and AZKF only
    json.dumps(study, allow_nan=False)


def test_robust_inequalities(study: dict) -> None:
    c = study["cases"]
    assert c["no_fault"]["azkf_vs_kf"]["alpha"] > 30.0          # not about the fault
    assert c["true_model"]["azkf_vs_kf"]["alpha"] < 0.0         # the MLS bias is what it fixes
    assert c["true_model"]["azkf_vs_kf"]["q"] < 0.0
    assert c["rows_posterior"]["azkf_vs_kf"]["alpha"] > c["paper"]["azkf_vs_kf"]["alpha"]
    assert c["paper"]["zkf_vs_kf"]["alpha"] < 0.0 < c["zkf_order_2"]["zkf_vs_kf"]["alpha"]


def test_paper_table5_alpha_q_ratios() -> None:
    p = cc.paper_table5()
    for n in ("kf", "zkf", "azkf"):
        assert abs(p["table5"][n]["alpha_over_q"] - 1.0) < 0.011
        assert p["table4"][n]["alpha_over_q"] < 0.7


def test_bootstrap_interval_contains_the_estimate() -> None:
    rng = np.random.default_rng(3)
    base = 1.0 + 0.1 * rng.random((20, 2))
    e = 0.5 * base * (1.0 + 0.05 * rng.standard_normal((20, 2)))
    lo, hi = cc.bootstrap(e, base)
    v = cc.improvement(e, base)
    assert np.all(lo <= v) and np.all(v <= hi) and np.all(hi - lo < 10.0)


def test_cli_json_and_figure(tmp_path: Path, capsys) -> None:
    from hil.cli import main
    png = tmp_path / "controls.png"
    assert main(["study", "cdrw", "--runs", "2", "--noise-seeds", "2", "--cases", "paper,no_fault",
                 "--json", "--figure", str(png)]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert set(doc["cases"]) == {"paper", "no_fault"}
    assert png.is_file()
    cap = (tmp_path / "controls.caption.txt").read_text()
    assert cap.startswith("Table 5 with its controls") and "hil study cdrw" in cap
    assert cap.count("\n") == 1
    assert main(["study", "cdrw", "--cases", "nonsense"]) == 2
