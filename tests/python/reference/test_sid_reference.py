"""The numpy reference of seed 1 (hil.reference) against independent solvers.

The reference is what the firmware is compared with, so it is itself checked
here against numpy's lstsq and scipy's discrete Riccati solver, and the
reduction operator against a brute-force check of its properties.
"""
from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import solve_discrete_are

from hil.reference import Kf, Mls, MlsConfig, Model, Zkf, batch_fit, contains, reduce_order
from hil.reference.flight import synthetic_flight
from hil.reference.model import norm2, spectral_radius
from hil.reference.zkf import Detector, DetectorConfig

A = np.array([[0.96, 0.02], [-0.45, 0.93]])
B = np.array([-0.004, -0.55])


def _simulate(n: int, noise: float, seed: int = 3) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    x = np.zeros((n + 1, 2))
    x[0] = [0.15, 0.02]
    de = -0.1 + 0.03 * np.sin(0.3 * np.arange(n)) + 0.02 * rng.standard_normal(n)
    for k in range(n):
        x[k + 1] = A @ x[k] + B * de[k] + noise * rng.uniform(-1, 1, 2)
    return x, de


def test_mls_recovers_noise_free_model() -> None:
    x, de = _simulate(200, 0.0)
    mls = Mls(MlsConfig(ridge=0.0))
    for k in range(200):
        mls.update(x[k], de[k], x[k + 1])
    np.testing.assert_allclose(mls.model.a, A, atol=1e-9)
    np.testing.assert_allclose(mls.model.b, B, atol=1e-9)


@pytest.mark.parametrize("ridge", [0.0, 1e-4, 0.05])
def test_mls_equals_batch_least_squares(ridge: float) -> None:
    x, de = _simulate(300, 0.003)
    h = 110
    mls = Mls(MlsConfig(window=h, ridge=ridge))
    for k in range(300):
        mls.update(x[k], de[k], x[k + 1])
        if k >= 20:
            lo = max(0, k + 1 - h)
            ref = batch_fit(x[lo:k + 1], de[lo:k + 1], x[lo + 1:k + 2], ridge, mls.cfg.prior)
            np.testing.assert_allclose(mls.model.flat(), ref.flat(), rtol=0, atol=1e-10)


def test_mls_standard_errors_match_ols_covariance() -> None:
    x, de = _simulate(150, 0.004)
    mls = Mls(MlsConfig(window=100, ridge=0.0))
    for k in range(150):
        mls.update(x[k], de[k], x[k + 1])
    phi = np.column_stack([x[50:150], de[50:150]])
    z = x[51:151]
    th, *_ = np.linalg.lstsq(phi, z, rcond=None)
    resid = z - phi @ th
    cov = np.linalg.inv(phi.T @ phi)
    for i in range(2):
        sd = np.sqrt(np.sum(resid[:, i] ** 2) / (100 - 3) * np.diag(cov))
        np.testing.assert_allclose([mls.se[2 * i], mls.se[2 * i + 1], mls.se[4 + i]], sd,
                                   rtol=1e-9)


def test_mls_guard_keeps_last_model() -> None:
    mls = Mls(MlsConfig(window=20, min_transitions=10, ridge=0.0))
    for _ in range(20):
        mls.update(np.array([0.1, 0.2]), 0.0, np.array([0.1, 0.2]))
    assert mls.solve() == "singular"
    assert mls.is_prior and np.array_equal(mls.model.a, mls.cfg.prior.a)


def _vertices(r: np.ndarray) -> np.ndarray:
    """Every generator sum R s, s in {-1, 1}^p (2 x 2^p)."""
    p = r.shape[1]
    bits = (np.arange(1 << p)[None, :] >> np.arange(p)[:, None]) & 1
    return r @ (2.0 * bits - 1.0)


def _inside(red: np.ndarray, pts: np.ndarray, tol: float = 1e-12) -> bool:
    """Exact 2-D zonotope membership of many points (slabs normal to each generator)."""
    normals = np.vstack([np.column_stack([-red[1], red[0]]), np.eye(2)])
    support = np.sum(np.abs(normals @ red), axis=1)
    return bool(np.all(np.abs(normals @ pts) <= support[:, None] + tol))


def test_reduction_properties_brute_force() -> None:
    rng = np.random.default_rng(5)
    for _ in range(30):
        p = int(rng.integers(3, 11))
        r = rng.uniform(-1, 1, (2, p))
        pts = _vertices(r)
        for q in range(2, p + 2):
            red = reduce_order(r, q)
            assert red.shape[1] == min(p, q)
            if q >= p:
                assert np.array_equal(red, r)
            assert _inside(red, pts)
            assert contains(np.zeros(2), red, pts[:, 0])
    # and a point just outside a box is outside
    assert not _inside(np.eye(2), np.array([[1.001], [0.0]]))


def test_reduction_ties_are_stable() -> None:
    r = np.array([[1.0, 0.0, 1.0, 0.0, 0.1], [0.0, 1.0, 0.0, 1.0, 0.0]])
    np.testing.assert_array_equal(reduce_order(r, 4), [[1, 0, 1.1, 0], [0, 1, 0, 1]])


def test_kf_converges_to_the_riccati_solution() -> None:
    """P- of the KF tends to the DARE solution (scipy) for a constant model."""
    e, f = 0.004 * np.eye(2), 0.02 * np.eye(2)
    kf = Kf(np.array([0.15, 0.0]), 0.1 * np.eye(2), e, f)
    model = Model(A, B)
    for _ in range(400):
        kf.step(model, -0.1, np.array([0.15, 0.0]))
    p_pred = A @ kf.p @ A.T + e @ e.T
    dare = solve_discrete_are(A.T, np.eye(2), e @ e.T, f @ f.T)
    np.testing.assert_allclose(p_pred, dare, rtol=1e-9)


def test_zkf_without_reduction_matches_the_riccati_solution() -> None:
    e, f = 0.004 * np.eye(2), 0.02 * np.eye(2)
    zkf = Zkf(np.array([0.15, 0.0]), np.sqrt(0.1) * np.eye(2), e, f)
    model = Model(A, B)
    for _ in range(150):
        zkf.step(model, -0.1, np.array([0.15, 0.0]), 1000)
    dare = solve_discrete_are(A.T, np.eye(2), e @ e.T, f @ f.T)
    np.testing.assert_allclose(zkf.gen @ zkf.gen.T, dare, rtol=1e-9)


def test_detector_counts() -> None:
    det = Detector(DetectorConfig(margin=1.0, raise_count=1, hold_count=0, clear_count=2,
                                  max_fault_steps=0))
    r = np.array([0.1, 0.1])
    assert det.step(np.array([0.2, 0.0]), r, False)
    assert det.step(np.array([0.0, 0.0]), r, False)
    assert not det.step(np.array([0.0, 0.0]), r, False)


def test_model_helpers() -> None:
    assert spectral_radius(np.array([[0.9, 0.1], [-0.1, 0.9]])) == pytest.approx(np.sqrt(0.82))
    assert norm2(np.array([[3.0, 0.0], [4.0, 5.0]])) == pytest.approx(np.sqrt(45.0))


def test_synthetic_flight_shape() -> None:
    f = synthetic_flight()
    assert len(f.t) == 351 and f.fault.sum() == 5
    alpha_deg = np.rad2deg(f.x[:, 0])
    assert 6 < alpha_deg[0] < 11 and alpha_deg.max() > 15
    # The truth obeys its own model exactly up to the bounded process noise.
    resid = f.x[1:] - np.einsum("kij,kj->ki", f.a[:-1], f.x[:-1]) - f.b[:-1] * f.de[:-1, None]
    assert np.all(np.abs(resid) <= np.array([0.0005, 0.002]) + 1e-15)


# ---- the optional intercept (x+ = A x + B de + c) ---------------------------------------
C_AFFINE = np.array([0.016, 0.071])


def _simulate_affine(n: int, noise: float, seed: int = 4) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    x = np.zeros((n + 1, 2))
    x[0] = [0.15, 0.0]
    de = -0.04 + 0.01 * np.sin(0.3 * np.arange(n)) + 0.005 * rng.standard_normal(n)
    for k in range(n):
        x[k + 1] = A @ x[k] + B * de[k] + C_AFFINE + noise * rng.uniform(-1, 1, 2)
    return x, de


def test_mls_intercept_recovers_an_affine_model() -> None:
    x, de = _simulate_affine(200, 0.0)
    mls = Mls(MlsConfig(ridge=0.0, intercept=True))
    for k in range(200):
        mls.update(x[k], de[k], x[k + 1])
    np.testing.assert_allclose(mls.model.a, A, atol=1e-9)
    np.testing.assert_allclose(mls.model.b, B, atol=1e-9)
    np.testing.assert_allclose(mls.model.c, C_AFFINE, atol=1e-10)
    # The paper's regression on the same data has no c: A and B absorb it.
    paper = Mls(MlsConfig(ridge=0.0))
    for k in range(200):
        paper.update(x[k], de[k], x[k + 1])
    assert np.all(paper.model.c == 0.0)
    assert np.max(np.abs(paper.model.flat() - np.concatenate([A.ravel(), B]))) > 0.05


@pytest.mark.parametrize("ridge", [0.0, 1e-3, 0.05])
def test_mls_intercept_equals_lstsq_with_a_column_of_ones(ridge: float) -> None:
    """Centred solve (the MLS) = lstsq with a free intercept column (batch_fit)."""
    x, de = _simulate_affine(250, 0.003)
    h = 90
    mls = Mls(MlsConfig(window=h, ridge=ridge, intercept=True))
    for k in range(250):
        mls.update(x[k], de[k], x[k + 1])
        if k >= 30:
            lo = max(0, k + 1 - h)
            ref = batch_fit(x[lo:k + 1], de[lo:k + 1], x[lo + 1:k + 2], ridge, mls.cfg.prior,
                            intercept=True)
            np.testing.assert_allclose(mls.model.flat8(), ref.flat8(), rtol=0, atol=1e-9)


def test_prior_affine_term_is_used_only_with_the_intercept() -> None:
    prior = Model(A, B, np.array([0.5, -0.25]))
    assert np.all(Mls(MlsConfig(prior=prior)).model.c == 0.0)
    np.testing.assert_array_equal(Mls(MlsConfig(prior=prior, intercept=True)).model.c,
                                  prior.c)


def test_filters_predict_with_the_affine_term() -> None:
    model = Model(A, B, C_AFFINE)
    kf = Kf(np.array([0.15, 0.0]), 0.1 * np.eye(2), 0.004 * np.eye(2), 0.02 * np.eye(2))
    kf.step(model, 0.0, np.array([0.15, 0.0]))
    x = kf.x.copy()
    kf.step(model, -0.04, None)
    np.testing.assert_allclose(kf.x, A @ x + B * -0.04 + C_AFFINE, atol=1e-15)
    zkf = Zkf(np.array([0.15, 0.0]), np.sqrt(0.1) * np.eye(2), 0.004 * np.eye(2),
              0.02 * np.eye(2))
    zkf.step(model, -0.04, None, 1000)
    np.testing.assert_allclose(zkf.x, A @ np.array([0.15, 0.0]) + B * -0.04 + C_AFFINE,
                               atol=1e-15)
