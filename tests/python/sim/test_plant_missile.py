"""Missile plant: exact discretisation, gust statistics, D/A, open loop and the LQG reference."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad_vec
from scipy.linalg import expm, solve_continuous_lyapunov

from hil.scenario.file import load_default_scenario, parse_fault_spec
from hil.sim import missile
from hil.sim.missile import DAConverter, MissilePlant, van_loan_noise, zoh
from hil.sim.missile_cov import closed_loop_rms, open_loop_rms
from hil.sim.missile_runs import COST_A, MissileSimulation, design_lqg, discrete_cost, simulate_missile
from hil.scenario.sensor_options import MissileSensorOptions
from hil.sim.sensors import MissileSensors


def test_model_matrices_are_the_papers():
    assert missile.F.tolist() == [[-1.2132, -177.0, 0.0], [1.0, -4.03, 0.00149], [0.0, 0.0, -2.0]]
    assert missile.G.tolist() == [-69.3, -0.2978, 0.0]
    assert missile.f.tolist() == [0.0, -0.0179, -24.0]
    assert missile.H.tolist() == [[1.0, 0.0, 0.0], [-26.74, -568.4, 0.0]]
    # the gust model: tau_w = 0.5 s and sigma_w^2 = 24^2 / (2 * 2) = 144
    assert missile.F[2, 2] == -1.0 / missile.TAU_W
    assert missile.f[2] ** 2 / (2.0 / missile.TAU_W) == pytest.approx(missile.SIGMA_W**2)


@pytest.mark.parametrize("h", [0.0125, 0.1])
def test_discretisation_against_quadrature(h):
    phi, gam = zoh(missile.F, missile.G, h)
    assert np.allclose(phi, expm(missile.F * h), rtol=1e-13, atol=1e-15)
    gq, _ = quad_vec(lambda s: expm(missile.F * s) @ missile.G, 0.0, h, epsabs=1e-14)
    assert np.allclose(gam[:, 0], gq, rtol=1e-9, atol=1e-14)
    qq, _ = quad_vec(lambda s: expm(missile.F * s) @ np.outer(missile.f, missile.f) @ expm(missile.F * s).T,
                     0.0, h, epsabs=1e-14)
    assert np.allclose(van_loan_noise(missile.F, missile.f, h), qq, rtol=1e-9, atol=1e-13)


def test_discrete_cost_against_quadrature():
    T = 0.1

    def integrand(s: float) -> np.ndarray:
        phi, gam = zoh(missile.F, missile.G, s)
        m = np.hstack([phi, gam])
        w = m.T @ COST_A @ m
        w[3, 3] += 1.0
        return w

    wq, _ = quad_vec(integrand, 0.0, T, epsabs=1e-14)
    q11, q12, q22 = discrete_cost(T)
    assert np.allclose(q11, wq[:3, :3], rtol=1e-9, atol=1e-14)
    assert np.allclose(q12, wq[:3, 3], rtol=1e-9, atol=1e-14)
    assert q22 == pytest.approx(wq[3, 3], rel=1e-10)


def test_open_loop_without_gust_is_the_analytic_propagation():
    T, n_sub = 0.1, 8
    plant = MissilePlant(seed=5, gust_scale=0.0, gust0=3.0)
    x0 = plant.state
    phi = expm(missile.F * T)
    for k in range(1, 31):
        plant.step(0.0, T, n_sub)
        assert np.allclose(plant.state, np.linalg.matrix_power(phi, k) @ x0, rtol=1e-11, atol=1e-13)
    # sub-steps are exact too: the trace is the flow at the sub-step times
    start = np.linalg.matrix_power(phi, 30) @ x0
    plant.step(0.05, T, n_sub)
    for j, xj in enumerate(plant.last_substeps):
        p_j, g_j = zoh(missile.F, missile.G, j * T / n_sub)
        assert np.allclose(xj, p_j @ start + g_j[:, 0] * 0.05, rtol=1e-11, atol=1e-13)


def test_open_loop_mean_with_gust_follows_expm():
    """Monte Carlo mean over 4000 gust realisations = e^{F t} x0 (within 4 standard errors)."""
    T, n = 0.1, 10
    plant = MissilePlant(seed=11, gust0=0.0, batch=4000)
    x0 = plant.state[0]
    for _ in range(n):
        plant.step(0.0, T, 8)
    mean = plant.state.mean(axis=0)
    se = plant.state.std(axis=0) / math.sqrt(4000)
    expected = expm(missile.F * T * n) @ x0
    assert np.all(np.abs(mean - expected) < 4.0 * se + 1e-12)
    # and the spread is the exact covariance int_0^t e^{Fs} f f^T e^{F^T s} ds
    cov = np.cov(plant.state.T)
    exact = van_loan_noise(missile.F, missile.f, T * n)
    assert np.allclose(np.diag(cov), np.diag(exact), rtol=0.1)


def test_gust_variance_tends_to_144():
    plant = MissilePlant(seed=3, gust0=0.0, batch=2000)
    for _ in range(60):                       # 6 s = 12 gust time constants
        plant.step(0.0, 0.1, 8)
    var = plant.state[:, 2].var()
    assert var == pytest.approx(144.0, rel=0.1)          # 2000 samples: se ~ 3 %
    # and the stationary q, alpha_T spread matches the continuous Lyapunov solution
    pc = solve_continuous_lyapunov(missile.F, -np.outer(missile.f, missile.f))
    assert pc[2, 2] == pytest.approx(144.0, rel=1e-12)
    assert plant.state[:, 1].var() == pytest.approx(pc[1, 1], rel=0.15)
    stationary = MissilePlant(seed=4, gust0="stationary", batch=4000)
    assert stationary.state[:, 2].var() == pytest.approx(144.0, rel=0.1)


def test_da_converter_is_exact():
    for bits in (6, 8, 12):
        dac = DAConverter(bits)
        assert dac.lsb == 0.8 / 2**bits
        assert (dac.code_min, dac.code_max) == (-(2 ** (bits - 1)), 2 ** (bits - 1) - 1)
        for code in (dac.code_min, -3, -1, 0, 1, 7, dac.code_max):
            assert dac.value(code) == code * dac.lsb              # exactly code x LSB
            assert dac.code(dac.value(code)) == code
        assert dac.code(1.0) == dac.code_max and dac.code(-1.0) == dac.code_min   # clamped
        assert dac.code(2.5 * dac.lsb) == 3 and dac.code(-2.5 * dac.lsb) == -3    # half away from 0
        assert dac.code(2.49 * dac.lsb) == 2
        with pytest.raises(ValueError, match="outside"):
            dac.value(dac.code_max + 1)
    with pytest.raises(ValueError, match="bits"):
        DAConverter(1)


def test_elevator_from_code_is_held_for_the_period():
    dac = DAConverter(6)
    a = MissilePlant(seed=1, gust_scale=0.0)
    b = MissilePlant(seed=1, gust_scale=0.0)
    a.step_code(-5, dac, 0.1, 8)
    b.step(-5 * 0.8 / 64, 0.1, 8)
    assert np.array_equal(a.state, b.state) and a.u == -0.0625
    with pytest.raises(ValueError, match="outside"):
        a.step_code(40, dac, 0.1)
    with pytest.raises(ValueError, match="elevator"):
        a.step(0.5, 0.1)


def test_sensors_noise_statistics():
    s = MissileSensors(seed=2, options=MissileSensorOptions(var_gyro=0.8, var_acc=0.8))
    x = np.array([0.1, 0.01, 5.0])
    y = np.array([[m["q_g"], m["n_a"]] for m in (s.measure(x) for _ in range(20000))])
    assert y.mean(axis=0) == pytest.approx(missile.H @ x, abs=0.05)
    assert y.var(axis=0) == pytest.approx([0.8, 0.8], rel=0.05)


def test_lqg_reference_design_is_sound():
    d = design_lqg(0.1)
    # the closed loop and the estimator are stable
    assert max(abs(np.linalg.eigvals(d.Phi - np.outer(d.Gamma, d.K)))) < 1.0
    assert max(abs(np.linalg.eigvals(d.Phi - d.Phi @ d.L @ missile.H))) < 1.0
    # the Riccati equations hold (cross-term LQR; a-priori Kalman)
    g = d.Gamma[:, None]
    res = (d.Phi.T @ d.P @ d.Phi - d.P + d.Q11
           - (d.Phi.T @ d.P @ g + d.Q12[:, None]) @ (d.Phi.T @ d.P @ g + d.Q12[:, None]).T
           / (d.Q22 + (g.T @ d.P @ g).item()))
    assert np.max(np.abs(res)) < 1e-9 * np.max(np.abs(d.P))
    m_next = d.Phi @ d.Z @ d.Phi.T + d.Qd
    assert np.allclose(m_next, d.M, rtol=1e-9, atol=1e-12)


def test_closed_loop_beats_open_loop_and_matches_covariance_analysis():
    sc = load_default_scenario("missile")
    long = sc.replace(duration=400.0, lqg=sc.lqg.__class__(period=0.1, bits=12))
    cl = simulate_missile(long)
    ol = simulate_missile(long, closed_loop=False)
    rq, ra = closed_loop_rms(design_lqg(0.1), 8)
    oq, oa = open_loop_rms()
    assert cl.rms_q == pytest.approx(rq, rel=0.05) and cl.rms_alpha == pytest.approx(ra, rel=0.05)
    assert ol.rms_q == pytest.approx(oq, rel=0.05) and ol.rms_alpha == pytest.approx(oa, rel=0.05)
    assert rq < oq and ra < oa
    # same seed, same gust: the open loop did not move the elevator
    assert np.all(ol.code == 0) and np.all(ol.u == 0.0)


def test_missile_run_records_codes_and_is_deterministic():
    sc = load_default_scenario("missile")
    r1, r2 = simulate_missile(sc), simulate_missile(sc)
    assert np.array_equal(r1.x_fine, r2.x_fine) and np.array_equal(r1.code, r2.code)
    assert r1.x[0].tolist() == [0.1, 0.0, 0.0]                 # seed 2's initial condition
    assert len(r1.t) == 100 and len(r1.t_fine) == 4001        # 10 s at T = 0.1, 2.5 ms sub-steps
    assert np.allclose(np.diff(r1.t_fine), missile.FINE_STEP, rtol=1e-9)
    assert np.array_equal(r1.u, r1.code * (0.8 / 256))
    assert np.any(r1.code != 0)
    r3 = simulate_missile(sc.replace(seed=2))
    assert not np.array_equal(r1.x_fine, r3.x_fine)


def test_missile_simulation_step_api_and_sensor_fault():
    sc = load_default_scenario("missile")
    sc = sc.replace(faults=(parse_fault_spec("bias:signal=q_g,start=1.0,duration=0.5,magnitude=2", "missile"),))
    sim = MissileSimulation(sc)
    while not sim.done:
        s = sim.sample()
        delta = s.meas["q_g"] - s.meas_faultfree["q_g"]
        assert delta == pytest.approx(2.0 if 1.0 <= s.t < 1.5 - 1e-9 else 0.0)
        assert s.fault_active == (1.0 <= s.t < 1.5 - 1e-9)
        sim.advance(0)
    with pytest.raises(RuntimeError):
        sim.sample()


def test_substeps_are_on_the_common_fine_base():
    assert missile.FINE_STEP == 0.0025
    for T, n in ((0.02, 8), (0.05, 20), (0.1, 40), (0.2, 80), (0.3, 120), (1.0, 400)):
        assert missile.substeps_for(T) == n and missile.common_time_base(T)
    # off the grid or too short: smallest n >= 8 with T / n <= 2.5 ms, documented as not shared
    for T, n in ((0.03, 12), (0.011, 8), (0.01, 8), (0.005, 8), (0.0333, 14)):
        assert missile.substeps_for(T) == n and T / n <= missile.FINE_STEP
    assert not missile.common_time_base(0.01) and not missile.common_time_base(0.0333)
    assert missile.substeps_for(0.1, 16) == 40 and missile.substeps_for(0.1, 50) == 50
    with pytest.raises(ValueError, match="period"):
        missile.substeps_for(0.0)


def _open_loop(T: float, seed: int = 2):
    sc = load_default_scenario("missile")
    sc = sc.replace(seed=seed, lqg=sc.lqg.__class__(period=T, bits=8, closed_loop=False))
    return simulate_missile(sc)


def test_same_seed_same_open_loop_gust_for_every_period():
    """Common random numbers: the open-loop true state at common times does not depend on T."""
    runs = {T: _open_loop(T) for T in (0.05, 0.1, 0.2)}
    ref = runs[0.2]
    for T, r in runs.items():
        assert r.t_fine[-1] == pytest.approx(10.0) and len(r.x_fine) == 4001
        assert np.array_equal(r.x_fine, ref.x_fine)                 # every 2.5 ms, bit for bit
        stride = round(0.2 / T)                                     # the samples at t = 0.2 k
        assert np.array_equal(r.x[::stride], ref.x)
        assert r.rms_q == ref.rms_q and r.rms_alpha == ref.rms_alpha
    assert not np.array_equal(_open_loop(0.1, seed=3).x_fine, ref.x_fine)


def test_advance_substeps_with_one_code_flies_like_advance():
    sc = load_default_scenario("missile")
    a, b = MissileSimulation(sc), MissileSimulation(sc)
    assert a.n_sub == 40 and a.common_time_base
    for code in (3, -7, 0, 12):
        a.sample()
        b.sample()
        ta = a.advance(code)
        tb = b.advance_substeps([code] * b.n_sub)
        assert ta.shape == (41, 3) and np.allclose(ta, tb, rtol=1e-13, atol=1e-15)
    with pytest.raises(ValueError, match="sub-steps"):
        b.sample()
        b.advance_substeps([0] * 8)
