"""lqg_design (the firmware's own LQG design) against scipy / python-control.

The reference is tests/vectors/lqg/lqg_reference.json, produced by
tests/gen_lqg_vectors.py; the last test regenerates it and fails on drift.
"""
from __future__ import annotations

import importlib.util
import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[3]
VECTORS = REPO / "tests" / "vectors" / "lqg"
MATRIX_KEYS = ("Phi", "Gamma", "Qd", "Q11", "Q12", "Q22", "K", "P", "M", "P_post", "L")
SHAPES = {"Phi": (3, 3), "Gamma": (3, 1), "Qd": (3, 3), "Q11": (3, 3), "Q12": (3, 1),
          "Q22": (1, 1), "K": (1, 3), "P": (3, 3), "M": (3, 3), "P_post": (3, 3), "L": (3, 2)}
# The design computes in double in every build; a float build rounds the
# results to single precision (measured <= 3.1e-7 matrix-relative).
TOLERANCE = {"double": 1e-9, "float": 1e-5}


def _load_generator():
    spec = importlib.util.spec_from_file_location("gen_lqg_vectors", REPO / "tests" / "gen_lqg_vectors.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules["gen_lqg_vectors"] = module
    spec.loader.exec_module(module)
    return module


gen = _load_generator()
REFERENCE: dict[str, Any] = json.loads((VECTORS / gen.JSON_NAME).read_text())
CASES = {case["T"]: case for case in REFERENCE["cases"]}


def run_tool(tool: Path, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(tool), *args], capture_output=True, text=True, timeout=30)


def design(tool: Path, *args: str) -> dict[str, Any]:
    proc = run_tool(tool, *args)
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == ""
    return json.loads(proc.stdout)


def matrix_rel_err(actual: Any, expected: Any) -> float:
    """max |a - e| / max |e|: the comparison used everywhere for matrices."""
    a = np.asarray(actual, dtype=float)
    e = np.asarray(expected, dtype=float)
    assert a.shape == e.shape
    return float(np.abs(a - e).max() / np.abs(e).max())


def spectrum_err(actual: list[list[float]], expected: list[list[float]]) -> float:
    """Largest distance from an expected pole to the nearest unused computed one, relative."""
    left = [complex(re, im) for re, im in actual]
    scale = max(abs(complex(re, im)) for re, im in expected)
    worst = 0.0
    for re, im in expected:
        z = complex(re, im)
        j = min(range(len(left)), key=lambda i: abs(left[i] - z))
        worst = max(worst, abs(left.pop(j) - z) / scale)
    return worst


@pytest.fixture(scope="module")
def tool(bin_path) -> Path:
    return bin_path("lqg_design")


@pytest.fixture(scope="module")
def tol(tool: Path) -> float:
    return TOLERANCE[design(tool, "--period", "0.1")["real"]]


@pytest.mark.parametrize("solver", ["hamiltonian", "doubling"])
@pytest.mark.parametrize("period", sorted(CASES))
def test_design_matches_scipy(tool: Path, tol: float, period: float, solver: str) -> None:
    out = design(tool, "--period", repr(period), "--solver", solver)
    ref = CASES[period]
    assert out["solver"] == solver
    assert out["T"] == pytest.approx(period, rel=1e-7)
    for key in MATRIX_KEYS:
        assert np.asarray(out[key]).shape == SHAPES[key], key
        err = matrix_rel_err(out[key], ref[key])
        assert err <= tol, f"{key}: matrix-relative error {err:.2e} > {tol:.0e}"
    for key in ("closed_loop_poles", "estimator_poles"):
        err = spectrum_err(out[key], ref[key])
        assert err <= tol, f"{key}: relative error {err:.2e}"
    # The two Riccati methods ran and agree (both in double in every build).
    for eq in ("lqr", "kalman"):
        assert out["riccati"][eq]["solver_disagreement"] <= 1e-10
        assert out["riccati"][eq]["residual"] <= 1e-12
    # Stable closed loop and estimator.
    for key in ("closed_loop_poles", "estimator_poles"):
        assert max(abs(complex(re, im)) for re, im in out[key]) < 1.0


@pytest.mark.parametrize("case", REFERENCE["delayed"], ids=lambda c: f"T{c['T']}-d{c['delay']}")
def test_delayed_design_matches_scipy(tool: Path, tol: float, case: dict[str, Any]) -> None:
    """lqg_design --delay: Gamma0/Gamma1 and the LQR on [x; u_k-1] as scipy computes them."""
    out = design(tool, "--period", repr(case["T"]), "--delay", repr(case["delay"]))
    assert out["delay"] == pytest.approx(case["delay"], rel=1e-7)
    pairs = (("Gamma", "Gamma0"), ("Gamma1", "Gamma1"), ("K", "K"), ("Pa", "Pa"),
             ("Qa11", "Qa11"), ("Qa12", "Qa12"), ("Qa22", "Qa22"))
    for got, ref in pairs:
        err = matrix_rel_err(np.ravel(out[got]), np.ravel(case[ref]))
        assert err <= tol, f"{got}: matrix-relative error {err:.2e} > {tol:.0e}"
    assert out["K_u"] == pytest.approx(case["K_u"][0], rel=tol)
    assert spectrum_err(out["closed_loop_poles"], case["closed_loop_poles"]) <= tol
    # the filter is the undelayed one
    assert matrix_rel_err(out["L"], CASES[case["T"]]["L"]) <= tol


def test_delay_out_of_range_is_refused(tool: Path) -> None:
    proc = run_tool(tool, "--period", "0.05", "--delay", "0.05")
    assert proc.returncode != 0 and proc.stdout == ""
    assert proc.stderr.startswith("lqg_design: design failed") and len(proc.stderr.splitlines()) == 1


def test_gains_follow_noise_variances(tool: Path, tol: float) -> None:
    """Non-default sensor noise: the filter gain still matches scipy."""
    import scipy.linalg as sl

    period, gyro, accel = 0.05, 0.02, 3.5
    out = design(tool, "--period", str(period), "--gyro-var", str(gyro), "--accel-var", str(accel))
    phi, _ = gen.zoh(gen.F, gen.G, period)
    qd = gen.noise(gen.F, gen.W_GUST @ gen.W_GUST.T, period)
    r = np.diag([gyro, accel])
    m = sl.solve_discrete_are(phi.T, gen.H.T, qd, r)
    l_ref = np.linalg.solve(gen.H @ m @ gen.H.T + r, gen.H @ m).T
    assert matrix_rel_err(out["M"], m) <= tol
    assert matrix_rel_err(out["L"], l_ref) <= tol
    assert out["R"] == [[pytest.approx(gyro), 0.0], [0.0, pytest.approx(accel)]]
    # The regulator does not depend on the sensors.
    assert matrix_rel_err(out["K"], CASES[period]["K"]) <= tol


@pytest.mark.parametrize("bits", [2, 6, 8, 12, 16])
def test_dac_description(tool: Path, bits: int) -> None:
    out = design(tool, "--period", "0.1", "--bits", str(bits))
    assert out["bits"] == bits
    assert out["lsb"] == pytest.approx(0.8 / 2**bits, rel=1e-7)
    assert out["code_min"] == -(2 ** (bits - 1))
    assert out["code_max"] == 2 ** (bits - 1) - 1


def test_help(tool: Path) -> None:
    proc = run_tool(tool, "--help")
    assert proc.returncode == 0
    assert proc.stdout.startswith("usage: lqg_design --period T")
    assert proc.stderr == ""


@pytest.mark.parametrize(
    "args",
    [
        [],
        ["--period"],
        ["--period", "0"],
        ["--period", "-0.1"],
        ["--period", "1e9"],
        ["--period", "nan"],
        ["--period", "inf"],
        ["--period", "0.1s"],
        ["--period", "0.1", "--bits", "1"],
        ["--period", "0.1", "--bits", "17"],
        ["--period", "0.1", "--bits", "8.5"],
        ["--period", "0.1", "--gyro-var", "-0.8"],
        ["--period", "0.1", "--accel-var", "0"],
        ["--period", "0.1", "--accel-var", "nan"],
        ["--period", "0.1", "--solver", "qz"],
        ["--period", "0.1", "--frobnicate"],
        ["--period", "0.1", "stray"],
    ],
)
def test_bad_input_is_one_line_and_nonzero(tool: Path, args: list[str]) -> None:
    proc = run_tool(tool, *args)
    assert proc.returncode != 0
    assert proc.stdout == ""
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("lqg_design: "), proc.stderr


def test_a_write_error_fails(tool: Path) -> None:
    """A full disk is not a design: `lqg_design ... >/dev/full` exits non-zero, one line."""
    with open("/dev/full", "w") as full:
        proc = subprocess.run([str(tool), "--period", "0.1"], stdout=full, stderr=subprocess.PIPE,
                              text=True, check=False)
    assert proc.returncode == 1
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("lqg_design: cannot write"), proc.stderr


def test_reference_vectors_are_up_to_date(tmp_path: Path) -> None:
    """Regenerate with scipy; the committed JSON must match and the committed C
    headers must be exactly what the generator renders from that JSON."""
    assert gen.main(["--out", str(tmp_path)]) == 0
    fresh = json.loads((tmp_path / gen.JSON_NAME).read_text())
    committed = REFERENCE

    def walk(a: Any, b: Any, where: str) -> None:
        if isinstance(a, dict):
            assert set(a) == set(b), where
            for k in a:
                if k != "versions":
                    walk(a[k], b[k], f"{where}.{k}")
        elif isinstance(a, list) and a and isinstance(a[0], (list, float, int)):
            err = matrix_rel_err(a, b) if np.abs(np.asarray(b, dtype=float)).max() > 0 else 0.0
            assert err <= 1e-12, f"{where} drifted by {err:.2e}: rerun tests/gen_lqg_vectors.py"
        elif isinstance(a, list):
            assert len(a) == len(b), where
            for i, (x, y) in enumerate(zip(a, b)):
                walk(x, y, f"{where}[{i}]")
        else:
            assert a == b, where

    walk(fresh, committed, "reference")
    assert (VECTORS / gen.HEADER_NAME).read_text() == gen.render_header(committed), \
        "lqg_vectors.h was edited or is stale: rerun tests/gen_lqg_vectors.py"
    assert (VECTORS / gen.LINALG_HEADER_NAME).read_text() == gen.render_linalg_header(committed), \
        "linalg_vectors.h was edited or is stale: rerun tests/gen_lqg_vectors.py"
