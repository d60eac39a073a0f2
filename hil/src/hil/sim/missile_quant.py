"""Fig. 3 with a real quantiser: Monte Carlo of the sampled missile loop beside the
LSB^2/12 model of hil.sim.missile_cov (`hil study missile-rms --mc-loops N`).

Each of `loops` flights of `seconds` s runs the exact discrete plant (ZOH Phi, Gamma, Van Loan
gust noise) with the firmware's LQG design (estimator propagated with the applied command,
as in missile_cov) and, with *common random numbers*, four D/As: none (open loop, u = 0),
ideal, and each N-bit converter (hil.sim.missile.DAConverter's rounding: half away from
zero, codes clamped).  From each flight's sample covariance of (x_k, u_k) the continuous-time
average over the interval follows exactly (missile_cov.interval_mean_cov is linear in it), so
each flight gives RMS q and alpha_T; the ratios to the same flight's open loop and ideal D/A
are averaged over the flights with a 95 % normal interval (the flights are independent).
The first 2 s of each flight are dropped (the initial gust state is drawn stationary).
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from hil.io.paths import tool
from hil.sim import missile
from hil.sim.linalg import solve_continuous_lyapunov
from hil.sim.missile_cov import (DAC_SPAN, closed_loop_rms, firmware_design,
                                 interval_mean_cov, open_loop_rms)

BURN_IN = 2.0  # s


def _interval_map(T: float) -> np.ndarray:
    """(16, 3, 3): interval_mean_cov(S) - interval_mean_cov(0) for each unit S_ij."""
    base = interval_mean_cov(np.zeros((4, 4)), T)
    out = np.empty((16, 3, 3))
    for i in range(16):
        e = np.zeros(16)
        e[i] = 1.0
        out[i] = interval_mean_cov(e.reshape(4, 4), T) - base
    return out


def quantise(u: np.ndarray, bits: int) -> np.ndarray:
    """The firmware's N-bit D/A on an array of commands."""
    lsb = DAC_SPAN / float(1 << bits)
    code = np.sign(u) * np.floor(np.abs(u) / lsb + 0.5)
    return np.clip(code, -(1 << (bits - 1)), (1 << (bits - 1)) - 1) * lsb


def monte_carlo(design, bits: Sequence[int], loops: int, seconds: float,
                seed: int = 1) -> dict[str, np.ndarray]:
    """{variant: (loops, 2) RMS (q, alpha_T)} for 'open', 'ideal' and each word length."""
    T = design.T
    phi, gam = missile.zoh(missile.F, missile.G, T)
    gam = gam[:, 0]
    qd = missile.van_loan_noise(missile.F, missile.f, T)
    lw = missile.sqrt_factor(qd)
    lv = np.linalg.cholesky(design.R)
    p_ol = solve_continuous_lyapunov(missile.F, -np.outer(missile.f, missile.f))
    steps = int(round(seconds / T))
    skip = int(round(BURN_IN / T))
    rng = np.random.default_rng(seed)
    x0 = rng.standard_normal((loops, 3)) @ missile.sqrt_factor(p_ol).T
    variants: list[tuple[str, int | None]] = [("open", -1), ("ideal", None)] + \
        [(str(int(n)), int(n)) for n in bits]
    x = {v: x0.copy() for v, _ in variants}
    xb = {v: np.zeros((loops, 3)) for v, _ in variants}
    acc = {v: np.zeros((loops, 4, 4)) for v, _ in variants}
    for k in range(steps):
        w = rng.standard_normal((loops, 3)) @ lw.T
        v = rng.standard_normal((loops, 2)) @ lv.T
        for name, nb in variants:
            xs = x[name]
            if nb == -1:
                u = np.zeros(loops)
            else:
                y = xs @ design.H.T + v
                xh = xb[name] + (y - xb[name] @ design.H.T) @ design.L.T
                u = -(xh @ design.K)
                if nb is not None:
                    u = quantise(u, nb)
                xb[name] = xh @ design.Phi.T + np.outer(u, design.Gamma)
            if k >= skip:
                z = np.column_stack([xs, u])
                acc[name] += z[:, :, None] * z[:, None, :]
            x[name] = xs @ phi.T + np.outer(u, gam) + w
    n = steps - skip
    imap = _interval_map(T)
    base = interval_mean_cov(np.zeros((4, 4)), T)
    out = {}
    for name, _ in variants:
        s = acc[name] / n
        m = base[None] + np.einsum("ls,sij->lij", s.reshape(loops, 16), imap)
        out[name] = np.sqrt(np.column_stack([m[:, 0, 0], m[:, 1, 1]]))
    return out


def _ratio(a: np.ndarray, b: np.ndarray) -> dict[str, Any]:
    """Mean per-flight change of a over b in %, 95 % interval, for (q, alpha_T)."""
    r = 100.0 * (a / b - 1.0)
    mean = r.mean(axis=0)
    half = 1.96 * r.std(axis=0, ddof=1) / math.sqrt(len(r))
    return {"q": float(mean[0]), "alpha": float(mean[1]),
            "q_ci": [float(mean[0] - half[0]), float(mean[0] + half[0])],
            "alpha_ci": [float(mean[1] - half[1]), float(mean[1] + half[1])]}


def quantiser_study(periods: Sequence[float], bits: Sequence[int], gyro_var: float,
                    accel_var: float, loops: int, seconds: float, seed: int = 1) -> dict[str, Any]:
    """The Monte Carlo block of `hil study missile-rms --json` (shape: see the README)."""
    oq, oa = open_loop_rms()
    out: dict[str, Any] = {"loops": loops, "seconds": seconds, "seed": seed, "periods": []}
    for T in periods:
        d = firmware_design(tool("lqg_design"), T, gyro_var, accel_var)
        mc = monte_carlo(d, bits, loops, seconds, seed)
        iq, ia = closed_loop_rms(d)
        entry: dict[str, Any] = {"period": float(T), "ideal_vs_open": _ratio(mc["ideal"], mc["open"]),
                                 "dac": {}}
        for n in bits:
            mq, ma = closed_loop_rms(d, int(n))
            entry["dac"][str(int(n))] = {
                "rms_q": float(np.sqrt(np.mean(mc[str(n)][:, 0] ** 2))),
                "rms_alpha": float(np.sqrt(np.mean(mc[str(n)][:, 1] ** 2))),
                "vs_open": _ratio(mc[str(n)], mc["open"]),
                "vs_ideal": _ratio(mc[str(n)], mc["ideal"]),
                "model_vs_open": {"q": 100.0 * (mq / oq - 1.0), "alpha": 100.0 * (ma / oa - 1.0)},
                "model_vs_ideal": {"q": 100.0 * (mq / iq - 1.0), "alpha": 100.0 * (ma / ia - 1.0)}}
        out["periods"].append(entry)
    return out


def format_quantiser(mc: dict[str, Any]) -> str:
    lines = [f"Real quantiser, Monte Carlo ({mc['loops']} flights x {mc['seconds']:g} s, common "
             "random numbers): change over the open loop, % (95 % interval) | LSB^2/12 model",
             f"{'T (s)':>7} {'bits':>4} {'q':>24} {'alpha_T':>24}   {'model q':>8} {'model a_T':>9}"]
    for p in mc["periods"]:
        for n, d in p["dac"].items():
            v = d["vs_open"]
            cell = lambda k: f"{v[k]:+6.2f} [{v[k + '_ci'][0]:+6.2f},{v[k + '_ci'][1]:+6.2f}]"  # noqa: E731, B023 - used in this iteration only
            lines.append(f"{p['period']:>7.3f} {n:>4} {cell('q'):>24} {cell('alpha'):>24}   "
                         f"{d['model_vs_open']['q']:+8.2f} {d['model_vs_open']['alpha']:+9.2f}")
    return "\n".join(lines)
