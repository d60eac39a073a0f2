"""sid_replay (firmware/tools/sid_replay) against the numpy reference.

Same flight, same configuration: every column of every row must agree with
hil.reference (the firmware's maths checked by an independent
implementation), bad input must give one line on stderr and a non-zero exit,
and the error table of the paper (Tables 4-5) is computed on a synthetic
flight with one spike fault.
"""
from __future__ import annotations

import subprocess
from pathlib import Path

import numpy as np
import pytest

from hil.reference import MlsConfig, Model, SidConfig, batch_fit, default_prior_affine
from hil.reference.flight import Flight, synthetic_flight
from hil.reference.metrics import error_table, format_table
from hil.results.sidrows import read_binary_rows, read_rows, rows_to_arrays
from hil.reference.sid import COLUMNS, columns, replay, replay_mls_only
from hil.reference.zkf import AzkfConfig, DetectorConfig

from conftest import build_dir


def _is_float_build() -> bool:
    cache = build_dir() / "CMakeCache.txt"
    return cache.exists() and "FCC_REAL:STRING=float" in cache.read_text()


FLOAT = _is_float_build()


@pytest.fixture(scope="module")
def tool(bin_path) -> Path:
    return bin_path("sid_replay")


@pytest.fixture(scope="module")
def flight() -> Flight:
    return synthetic_flight()


def run(tool: Path, stdin: str, *args: str, check: bool = True) -> subprocess.CompletedProcess:
    res = subprocess.run([str(tool), *args], input=stdin, capture_output=True, text=True,
                         timeout=60)
    if check:
        assert res.returncode == 0, res.stderr
    return res


def assert_rows_match(c: dict, r: dict, tol: float) -> None:
    assert c.keys() == r.keys()
    for name in c:
        for col, ref in r[name].items():
            np.testing.assert_allclose(c[name][col], ref, rtol=tol, atol=tol,
                                       err_msg=f"{name}.{col}")


def test_output_format(tool: Path, flight: Flight) -> None:
    out = run(tool, flight.csv()).stdout.splitlines()
    assert out[0] == ",".join(COLUMNS)
    assert len(out) == 1 + 3 * len(flight.t)
    assert [line.split(",")[1] for line in out[1:4]] == ["kf", "zkf", "azkf"]
    only = run(tool, flight.csv(), "--filter", "azkf").stdout.splitlines()
    assert len(only) == 1 + len(flight.t) and all(",azkf," in line for line in only[1:])
    # the affine term's columns only with the intercept
    icpt = run(tool, flight.csv(), "--mls-intercept", "--filter", "kf").stdout.splitlines()
    assert icpt[0] == ",".join(columns(True)) and icpt[0].endswith(",rho,c1,c2")
    assert all(len(line.split(",")) == len(columns(True)) for line in icpt[1:])


@pytest.mark.parametrize("args, cfg", [
    ((), SidConfig()),
    (("--fault-policy", "skip"), SidConfig(azkf=AzkfConfig(policy="skip"))),
    (("--detector", "oracle", "--zkf-order", "12", "--window", "60", "--ridge", "0.01"),
     SidConfig(zkf_order=12, mls=MlsConfig(window=60, ridge=0.01),
               azkf=AzkfConfig(det=DetectorConfig(mode="oracle")))),
    (("--q-normal", "6", "--q-fault", "40", "--margin", "3", "--clear", "5", "--hold", "2"),
     SidConfig(azkf=AzkfConfig(q_normal=6, q_fault=40,
                               det=DetectorConfig(margin=3.0, clear_count=5, hold_count=2)))),
    (("--x0", "0.1,0.05", "--p0", "0.05,0.2", "--e", "0.006", "--f", "0.03,0.001,0,0.025"),
     SidConfig(x0=np.array([0.1, 0.05]), p0=np.diag([0.05, 0.2]), e=0.006 * np.eye(2),
               f=np.array([[0.03, 0.001], [0.0, 0.025]]))),
    (("--mls-intercept",), SidConfig(mls=MlsConfig(intercept=True, prior=default_prior_affine()))),
    (("--mls-intercept", "--prior", "0.97,0.02,-0.4,0.94,-0.004,-0.6,0.001,-0.002", "--ridge",
      "0.01"),
     SidConfig(mls=MlsConfig(intercept=True, ridge=0.01, prior=Model.from_flat(
         [0.97, 0.02, -0.4, 0.94, -0.004, -0.6, 0.001, -0.002])))),
    (("--no-arm-on-prior", "--max-fault", "0", "--fault-policy", "skip", "--no-mls-hold"),
     SidConfig(arm_on_prior=False, mls_hold_on_fault=False, azkf=AzkfConfig(
         policy="skip", det=DetectorConfig(max_fault_steps=0)))),
    (("--max-fault", "3", "--margin", "1.2"),
     SidConfig(azkf=AzkfConfig(det=DetectorConfig(margin=1.2, max_fault_steps=3)))),
    (("--rows", "posterior"), SidConfig(rows="posterior")),
    (("--rows", "prior"), SidConfig(rows="prior")),
    (("--rows", "posterior", "--fault-policy", "skip", "--q-normal", "5"),
     SidConfig(rows="posterior", azkf=AzkfConfig(policy="skip", q_normal=5))),
    (("--rows", "prior", "--detector", "oracle", "--zkf-order", "12"),
     SidConfig(rows="prior", zkf_order=12, azkf=AzkfConfig(det=DetectorConfig(mode="oracle")))),
])
def test_matches_reference(tool: Path, flight: Flight, args: tuple, cfg: SidConfig) -> None:
    if FLOAT:
        cfg.mls.max_cond = 1e4  # the float build's documented default
    c = read_rows(run(tool, flight.csv(), *args).stdout)
    r = rows_to_arrays(replay(flight.t, flight.y, flight.de, flight.fault, cfg))
    assert_rows_match(c, r, 2e-3 if FLOAT else 1e-9)


def test_fixed_model_checks_each_filter_alone(tool: Path, flight: Flight) -> None:
    model = Model.from_flat([0.975, 0.019, -0.35, 0.95, -0.004, -0.55])
    args = ("--fixed-model", ",".join(f"{v:.17g}" for v in model.flat()))
    c = read_rows(run(tool, flight.csv(), *args).stdout)
    cfg = SidConfig(mls_enabled=False, mls=MlsConfig(prior=model))
    r = rows_to_arrays(replay(flight.t, flight.y, flight.de, flight.fault, cfg))
    assert_rows_match(c, r, 1e-4 if FLOAT else 1e-10)
    for name in c:
        assert np.all(c[name]["a21"] == c[name]["a21"][0])


def test_fixed_affine_model(tool: Path, flight: Flight) -> None:
    model = Model.from_flat([0.975, 0.019, -0.35, 0.95, -0.004, -0.55, 0.002, 0.05])
    args = ("--fixed-model", ",".join(f"{v:.17g}" for v in model.flat8()))
    c = read_rows(run(tool, flight.csv(), *args).stdout)
    cfg = SidConfig(mls_enabled=False, mls=MlsConfig(prior=model, intercept=True))
    r = rows_to_arrays(replay(flight.t, flight.y, flight.de, flight.fault, cfg))
    assert_rows_match(c, r, 1e-4 if FLOAT else 1e-10)
    np.testing.assert_allclose(c["kf"]["c2"], 0.05, rtol=1e-7)  # the model used, every step


def test_mls_only_intercept_recovers_an_affine_model(tool: Path, flight: Flight) -> None:
    """Exact states of x+ = A x + B de + c: A, B and c to 1e-9 (the paper's form cannot)."""
    a, b, c = flight.a[0], flight.b[0], np.array([0.016, 0.071])
    x = np.empty_like(flight.x)
    x[0] = flight.x[0]
    for k in range(len(x) - 1):
        x[k + 1] = a @ x[k] + b * flight.de[k] + c
    exact = Flight(flight.t, flight.de, x, x, x, flight.fault, flight.a, flight.b)
    out = read_rows(run(tool, exact.csv(), "--mls-only", "--ridge", "0",
                        "--mls-intercept").stdout)["mls"]
    fit = np.array([out[k][-1] for k in ("a11", "a12", "a21", "a22", "b1", "b2", "c1", "c2")])
    tol = 2e-3 if FLOAT else 1e-9
    np.testing.assert_allclose(fit, np.concatenate([a.ravel(), b, c]), atol=tol)
    paper = read_rows(run(tool, exact.csv(), "--mls-only", "--ridge", "0").stdout)["mls"]
    assert abs(paper["a21"][-1] - a[1, 0]) > 0.02


def test_mls_only_recovers_the_model(tool: Path, flight: Flight) -> None:
    """Exact states of a constant linear model, no noise: A, B to 1e-9."""
    a, b = flight.a[0], flight.b[0]
    x = np.empty_like(flight.x)
    x[0] = flight.x[0]
    for k in range(len(x) - 1):
        x[k + 1] = a @ x[k] + b * flight.de[k]
    exact = Flight(flight.t, flight.de, x, x, x, flight.fault, flight.a, flight.b)
    out = read_rows(run(tool, exact.csv(), "--mls-only", "--ridge", "0").stdout)["mls"]
    fit = np.column_stack([out[c] for c in ("a11", "a12", "a21", "a22", "b1", "b2")])
    tol = 1e-3 if FLOAT else 1e-9
    np.testing.assert_allclose(fit[-1], np.concatenate([a.ravel(), b]), atol=tol)
    np.testing.assert_allclose(out["alpha_hat"], x[:, 0], rtol=1e-6 if FLOAT else 0)


def test_mls_only_equals_batch_least_squares(tool: Path, flight: Flight) -> None:
    """On noisy states (the truth of a time-varying model): the window's lstsq."""
    h = 80
    out = read_rows(run(tool, flight.csv(), "--mls-only", "--window", str(h)).stdout)["mls"]
    ref = rows_to_arrays(replay_mls_only(flight.t, flight.y, flight.de, MlsConfig(window=h)))
    tol = 5e-3 if FLOAT else 1e-9
    for col in ("a11", "a12", "a21", "a22", "b1", "b2", "rho"):
        np.testing.assert_allclose(out[col], ref["mls"][col], atol=tol, err_msg=col)
    y, de = flight.y, flight.de
    k = len(y) - 1
    batch = batch_fit(y[k - h:k], de[k - h:k], y[k - h + 1:k + 1], MlsConfig().ridge,
                      MlsConfig().prior)
    np.testing.assert_allclose([out[c][-1] for c in ("a11", "a12", "a21", "a22", "b1", "b2")],
                               batch.flat(), atol=tol)


def test_same_input_same_output(tool: Path, flight: Flight) -> None:
    first = run(tool, flight.csv()).stdout
    assert run(tool, flight.csv()).stdout == first


@pytest.mark.parametrize("extra", [(), ("--filter", "azkf")])
def test_all_rows_is_each_row_mode_in_one_run(tool: Path, flight: Flight, extra: tuple) -> None:
    """--all-rows (one process instead of three: the rig's symmetric tables) prints exactly the
    rows of --rows paper, prior and posterior, each filter named MODE/FILTER."""
    every = read_rows(run(tool, flight.csv(), "--all-rows", *extra).stdout)
    names = ("azkf",) if extra else ("kf", "zkf", "azkf")
    assert sorted(every) == sorted(f"{m}/{f}" for m in ("paper", "prior", "posterior") for f in names)
    for mode in ("paper", "prior", "posterior"):
        alone = read_rows(run(tool, flight.csv(), "--rows", mode, *extra).stdout)
        for f in names:
            for col, values in alone[f].items():
                np.testing.assert_array_equal(every[f"{mode}/{f}"][col], values, err_msg=f"{mode}/{f}.{col}")


def test_estimates_are_the_first_columns_of_every_row(tool: Path, flight: Flight) -> None:
    """--estimates (what the rig reads: less to print and to parse) prints each row's t,
    filter and six estimate columns, the same text as the full row's first eight fields."""
    full = run(tool, flight.csv(), "--all-rows").stdout.splitlines()
    short = run(tool, flight.csv(), "--all-rows", "--estimates").stdout.splitlines()
    assert short[0] == "t,filter,alpha_hat,q_hat,alpha_lo,alpha_hi,q_lo,q_hi"
    assert short == [",".join(row.split(",")[:8]) for row in full]


@pytest.mark.parametrize("extra", [("--all-rows",), ("--filter", "zkf")])
def test_binary_estimates_are_the_text_ones_to_the_bit(tool: Path, flight: Flight, extra: tuple) -> None:
    """--binary (what the rig reads: nothing formatted or parsed) gives, row for row, the
    numbers --estimates prints, exactly, under the same filter names, and each row's fault flag
    (which the cross-check compares too)."""
    text = read_rows(run(tool, flight.csv(), "--estimates", *extra).stdout)
    raw = subprocess.run([str(tool), "--estimates", "--binary", *extra], input=flight.csv().encode(),
                         capture_output=True, timeout=60, check=True).stdout
    binary = read_binary_rows(raw, all_rows="--all-rows" in extra)
    assert binary.keys() == text.keys()
    for name, cols in text.items():
        assert binary[name].keys() == {*cols.keys(), "fault"}
        assert set(np.unique(binary[name]["fault"])) <= {0.0, 1.0}
        for col, values in cols.items():
            np.testing.assert_array_equal(binary[name][col], values, err_msg=f"{name}.{col}")


def test_binary_output_of_another_shape_is_refused() -> None:
    with pytest.raises(ValueError, match="not rows of 9 values"):
        read_binary_rows(b"\0" * 64, all_rows=True)
    with pytest.raises(ValueError, match="filter code 9.0"):
        read_binary_rows(np.array([0.0, 9.0, 1, 2, 3, 4, 5, 6, 0]).tobytes(), all_rows=True)


def test_no_nan_anywhere(tool: Path, flight: Flight) -> None:
    for policy in ("order", "skip"):
        out = read_rows(run(tool, flight.csv(), "--fault-policy", policy).stdout)
        for cols in out.values():
            for v in cols.values():
                assert np.all(np.isfinite(v))


def test_error_table_one_fault(tool: Path, flight: Flight, capsys) -> None:
    """Table 4 of the paper on a synthetic flight: one 0.1 s spike at 4 s."""
    res = read_rows(run(tool, flight.csv()).stdout)
    table = error_table(flight.y_clean, flight.x, res)
    with capsys.disabled():
        print("\n" + format_table(table))
    # The adaptive filter follows the sensor in normal flight (high gain)
    # and rejects the spike: better than the KF against the truth.
    for i in range(2):
        assert table["azkf"]["truth"][i] < table["kf"]["truth"][i]
        assert table["azkf"]["meas"][i] < table["kf"]["meas"][i]
    # Every faulty sample is flagged by the default detector.
    assert np.all(res["azkf"]["fault"][flight.fault] == 1)


BAD_INPUTS = {
    "nan": "t,alpha,q,de\n0,0.1,0,0\n0.02,nan,0,0\n",
    "inf": "t,alpha,q,de\n0,0.1,0,0\n0.02,0.1,inf,0\n",
    "absurd alpha": "t,alpha,q,de\n0,0.1,0,0\n0.02,5.0,0,0\n",
    "absurd elevator": "t,alpha,q,de\n0,0.1,0,0\n0.02,0.1,0,3\n",
    "not a number": "t,alpha,q,de\n0,0.1,0,0\n0.02,0.1,zero,0\n",
    "missing column": "t,alpha,de\n0,0.1,0\n",
    "duplicate column": "t,alpha,q,de,q\n0,0.1,0,0,0\n",
    "field count": "t,alpha,q,de\n0,0.1,0,0\n0.02,0.1,0\n",
    "time goes back": "t,alpha,q,de\n0,0.1,0,0\n0.04,0.1,0,0\n0.02,0.1,0,0\n",
    "time repeats": "t,alpha,q,de\n0,0.1,0,0\n0,0.1,0,0\n",
    "bad fault flag": "t,alpha,q,de,fault\n0,0.1,0,0,2\n",
    "empty file": "",
    "header only": "t,alpha,q,de\n",
    "NUL-led line": "t,alpha,q,de\n0,0.1,0,0\n\x000.02,0.1,0,0\n0.04,0.1,0,0\n",
    "NUL inside a line": "t,alpha,q,de\n0,0.1,0,0\n0.02,0.1\x00,0,0\n",
}


@pytest.mark.parametrize("name", sorted(BAD_INPUTS))
def test_bad_input_one_line_and_failure(tool: Path, name: str) -> None:
    res = run(tool, BAD_INPUTS[name], "--filter", "kf", "--fixed-model", "1,0,0,1,0,0",
              check=False)
    assert res.returncode != 0
    assert res.stdout == ""
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("sid_replay: "), res.stderr


@pytest.mark.parametrize("args", [
    ("--zkf-order", "100000"), ("--q-fault", "1001"), ("--q-normal", "1"),
    ("--window", "100"),                     # longer than the 60-row flight
    ("--window", "5000"),                    # above the compile-time bound
    ("--detector", "oracle"),                # no fault column
    ("--filter", "ekf"), ("--fault-policy", "drop"), ("--margin", "x"), ("--x0", "1"),
    ("--fixed-model", "1,2,3"), ("--p0", "1,2,3"), ("--frobnicate",), ("--ridge",),
    ("--f", "0"),                            # R = 0 is not invertible
    ("--margin", "-1"),
    ("--prior", "1,0,0,1,0,0,0"),            # 7 values: neither 6 nor 8
    ("--max-fault", "-2"), ("--max-fault", "x"), ("--all-rows", "--mls-only"),
    ("--estimates", "--mls-only"), ("--binary",),   # --binary writes --estimates' rows only
    ("--x0", "1e308,1e308"), ("--x0", "0,11"),   # beyond what the sensors can read
    ("--prior", "1e300,0,0,1,0,0"), ("--p0", "1e300"), ("--e", "1e30,1"),
])
def test_bad_options_one_line_and_failure(tool: Path, flight: Flight, args: tuple) -> None:
    short = "\n".join(flight.csv(with_fault_column=False).splitlines()[:61]) + "\n"
    res = run(tool, short, *args, check=False)
    assert res.returncode != 0
    assert res.stdout == ""
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("sid_replay: "), res.stderr


def test_reads_a_file_and_ignores_unknown_columns(tool: Path, flight: Flight, tmp_path) -> None:
    lines = flight.csv().splitlines()
    extra = [lines[0] + ",alpha_true"] + [f"{line},0.123" for line in lines[1:]]
    path = tmp_path / "flight.csv"
    path.write_text("\r\n".join(extra) + "\r\n")
    assert run(tool, "", str(path)).stdout == run(tool, flight.csv()).stdout
    res = run(tool, "", str(tmp_path / "missing.csv"), check=False)
    assert res.returncode != 0 and len(res.stderr.strip().splitlines()) == 1


@pytest.mark.parametrize("rows", ["posterior", "prior"])
def test_unreduced_zkf_is_the_kf(tool: Path, flight: Flight, rows: str) -> None:
    """Eqs. 21-25 without reduction (order >= generator count) with Q = E E^T, R = F F^T and
    the ZKF started from chol(P0) are the KF, read at the same moment (before or after y_k),
    on the same model.  240 steps keep the 4 new generators per step under the order 1000.
    (With the MLS on they part after the MLS starts fitting: the ZKF's combined step
    predicts x_k+1 in step k with the model of step k, the KF predicts it in step k+1 with
    a model that has also learnt the transition ending at x_k.)"""
    n = 240
    csv = "\n".join(flight.csv().splitlines()[: n + 1]) + "\n"
    model = "0.989307,0.018740,-0.540133,0.873259,-0.039892,-2.015052"
    c = read_rows(run(tool, csv, "--rows", rows, "--zkf-order", "1000", "--fixed-model", model).stdout)
    tol = 1e-5 if FLOAT else 1e-12
    assert len(c["kf"]["alpha_hat"]) == n
    # prior rows: the ZKF's gain column is its predictor gain G_k = A K_k, the KF's is K_k
    for col in ("alpha_hat", "q_hat") + (("gain_norm",) if rows == "posterior" else ()):
        np.testing.assert_allclose(c["zkf"][col], c["kf"][col], rtol=0, atol=tol, err_msg=col)
