#!/usr/bin/env python3
"""Reference vectors for the seed-2 LQG design and the linear-algebra core.

Computes, with scipy (expm, solve_discrete_are with the cross term ``s=``)
and checked against python-control and numerical quadrature, everything
``lqg_design`` prints for T in PERIODS, plus a few hard linear-algebra cases,
and writes

* ``tests/vectors/lqg/lqg_reference.json`` -- for the Python tests;
* ``tests/vectors/lqg/lqg_vectors.h``      -- the design cases and a 4-state
  DARE as a C header (for tests/c/test_lqg.c), and
* ``tests/vectors/lqg/linalg_vectors.h``   -- the hard linear-algebra cases
  (for tests/c/test_linalg.c), both rendered from the JSON (so the C tests
  need no JSON parser).

Both files are generated, never edited: ``tests/python/fcc/test_lqg_design.py``
recomputes them and fails on drift.

    .venv/bin/python tests/gen_lqg_vectors.py [--out DIR]
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

import control
import numpy as np
import scipy
import scipy.integrate
import scipy.linalg as sl

PERIODS = (0.01, 0.02, 0.05, 0.1, 0.2, 0.3, 0.5)
#: (T, d): the delay-aware design (fcc --lqg-delay, lqg_design --delay): the rig's 2.5 ms
#: actuation instant at the three real-time periods, and half a period
DELAYED = ((0.1, 0.0025), (0.05, 0.0025), (0.02, 0.0025), (0.05, 0.025), (0.1, 0.09))
REPO = Path(__file__).resolve().parents[1]
OUT_DIR = REPO / "tests" / "vectors" / "lqg"
JSON_NAME = "lqg_reference.json"
HEADER_NAME = "lqg_vectors.h"
LINALG_HEADER_NAME = "linalg_vectors.h"

# SPEC section 3: the paper's missile, weights and sensor noise.
F = np.array([[-1.2132, -177.0, 0.0], [1.0, -4.03, 0.00149], [0.0, 0.0, -2.0]])
G = np.array([[-69.3], [-0.2978], [0.0]])
W_GUST = np.array([[0.0], [-0.0179], [-24.0]])
WX = np.diag([0.12, 11.0, 0.0])
WU = np.array([[1.0]])
H = np.array([[1.0, 0.0, 0.0], [-26.74, -568.4, 0.0]])
R = np.diag([0.8, 0.8])

Matrix = np.ndarray


def zoh(f: Matrix, g: Matrix, t: float) -> tuple[Matrix, Matrix]:
    """Phi, Gamma from expm([[F, G], [0, 0]] T)."""
    n, m = g.shape
    blk = np.zeros((n + m, n + m))
    blk[:n, :n], blk[:n, n:] = f, g
    e = sl.expm(blk * t)
    return e[:n, :n], e[:n, n:]


def noise(f: Matrix, qc: Matrix, t: float) -> Matrix:
    """Q_d = int e^{Fs} Qc e^{F^T s} ds by Van Loan: Phi E12 of expm([[-F, Qc], [0, F^T]] T)."""
    n = f.shape[0]
    blk = np.zeros((2 * n, 2 * n))
    blk[:n, :n], blk[:n, n:], blk[n:, n:] = -f, qc, f.T
    e = sl.expm(blk * t)
    qd = e[n:, n:].T @ e[:n, n:]
    return (qd + qd.T) / 2


def cost(f: Matrix, g: Matrix, wx: Matrix, wu: Matrix, t: float) -> tuple[Matrix, Matrix, Matrix]:
    """Q11, Q12, Q22 as MATLAB lqrd: E22^T E12 of expm([[-Fa^T, Wa], [0, Fa]] T)."""
    n, m = g.shape
    fa = np.zeros((n + m, n + m))
    fa[:n, :n], fa[:n, n:] = f, g
    wa = sl.block_diag(wx, wu)
    na = n + m
    blk = np.zeros((2 * na, 2 * na))
    blk[:na, :na], blk[:na, na:], blk[na:, na:] = -fa.T, wa, fa
    e = sl.expm(blk * t)
    w = e[na:, na:].T @ e[:na, na:]
    q11 = (w[:n, :n] + w[:n, :n].T) / 2
    q22 = (w[n:, n:] + w[n:, n:].T) / 2
    return q11, w[:n, n:], q22


def check_by_quadrature(t: float, phi: Matrix, gam: Matrix, qd: Matrix,
                        q11: Matrix, q12: Matrix, q22: Matrix) -> None:
    """Independent check of the Van Loan blocks (and of SPEC's transposes)."""
    def phi_s(s: float) -> Matrix:
        return sl.expm(F * s)

    def gam_s(s: float) -> Matrix:
        return zoh(F, G, s)[1] if s > 0 else np.zeros_like(G)

    def integrate(fun) -> Matrix:
        val, _ = scipy.integrate.quad_vec(fun, 0.0, t, epsabs=1e-14, epsrel=1e-12)
        return val

    qc = W_GUST @ W_GUST.T
    refs = {
        "Gamma": (gam, integrate(lambda s: phi_s(s) @ G)),
        "Qd": (qd, integrate(lambda s: phi_s(s) @ qc @ phi_s(s).T)),
        "Q11": (q11, integrate(lambda s: phi_s(s).T @ WX @ phi_s(s))),
        "Q12": (q12, integrate(lambda s: phi_s(s).T @ WX @ gam_s(s))),
        "Q22": (q22, integrate(lambda s: gam_s(s).T @ WX @ gam_s(s) + WU)),
        "Phi": (phi, sl.expm(F * t)),
    }
    for name, (vl, quad) in refs.items():
        err = np.abs(vl - quad).max() / np.abs(quad).max()
        if err > 1e-9:
            raise AssertionError(f"T={t}: Van Loan {name} differs from quadrature by {err:.2e}")


def sorted_poles(eigs: np.ndarray) -> list[list[float]]:
    """Decreasing modulus, then decreasing imaginary part (the firmware's order)."""
    order = sorted(eigs, key=lambda z: (-abs(z), -z.imag))
    return [[float(z.real), float(z.imag)] for z in order]


def design(t: float) -> dict[str, Any]:
    phi, gam = zoh(F, G, t)
    qd = noise(F, W_GUST @ W_GUST.T, t)
    q11, q12, q22 = cost(F, G, WX, WU, t)
    check_by_quadrature(t, phi, gam, qd, q11, q12, q22)

    p = sl.solve_discrete_are(phi, gam, q11, q22, s=q12)
    k = np.linalg.solve(q22 + gam.T @ p @ gam, gam.T @ p @ phi + q12.T)
    m = sl.solve_discrete_are(phi.T, H.T, qd, R)
    s = H @ m @ H.T + R
    l = np.linalg.solve(s, H @ m).T  # M H^T S^-1, the update-form gain
    p_post = m - l @ H @ m
    p_post = (p_post + p_post.T) / 2

    # python-control as a second opinion on both Riccati equations.
    k_ctl, _, _ = control.dlqr(phi, gam, q11, q22, q12)
    l_pred, m_ctl, _ = control.dlqe(phi, np.eye(3), H, qd, R)
    for name, a, b in (("K", k, k_ctl), ("M", m, m_ctl), ("Phi L", phi @ l, l_pred)):
        err = np.abs(np.asarray(a) - np.asarray(b)).max() / np.abs(b).max()
        if err > 1e-9:
            raise AssertionError(f"T={t}: scipy and python-control differ on {name}: {err:.2e}")

    return {
        "T": t,
        "Phi": phi.tolist(), "Gamma": gam.tolist(), "Qd": qd.tolist(),
        "Q11": q11.tolist(), "Q12": q12.tolist(), "Q22": q22.tolist(),
        "H": H.tolist(), "R": R.tolist(),
        "K": k.tolist(), "P": p.tolist(), "M": m.tolist(), "P_post": p_post.tolist(),
        "L": l.tolist(),
        "closed_loop_poles": sorted_poles(np.linalg.eigvals(phi - gam @ k)),
        "estimator_poles": sorted_poles(np.linalg.eigvals(phi - phi @ l @ H)),
    }


def delayed_design(t: float, delay: float) -> dict[str, Any]:
    """The LQR on [x; u_{k-1}] (hil.sim.missile_runs.delayed_lqr, scipy's DARE), checked
    against python-control's dlqr on the same augmented system, and Gamma0 + Gamma1 against
    Gamma (together they are the whole period's input)."""
    from hil.sim.missile_runs import delayed_lqr
    gam0, gam1, k, k_u, pa = delayed_lqr(t, delay)
    phi, gam = zoh(F, G, t)
    err = np.abs(gam0 + gam1 - gam[:, 0]).max() / np.abs(gam).max()
    if err > 1e-12:
        raise AssertionError(f"T={t}, d={delay}: Gamma0 + Gamma1 != Gamma ({err:.2e})")
    a = np.block([[phi, gam1[:, None]], [np.zeros((1, 4))]])
    b = np.vstack([gam0[:, None], [[1.0]]])
    # the augmented cost rebuilt here; python-control's K on it must equal scipy's
    from hil.sim.missile_runs import discrete_cost
    def block(tau: float) -> Matrix:
        q11, q12, q22 = discrete_cost(tau)
        return np.block([[q11, q12[:, None]], [q12[None, :], np.array([[q22]])]])
    phi_d, gam_d = zoh(F, G, delay)
    sm = np.zeros((4, 5))
    sm[:3, :3], sm[:3, 3:4], sm[3, 4] = phi_d, gam_d, 1.0
    qa = np.zeros((5, 5))
    qa[:4, :4] = block(delay)
    qa += sm.T @ block(t - delay) @ sm
    qa = (qa + qa.T) / 2
    k_ctl, _, _ = control.dlqr(a, b, qa[:4, :4], qa[4:, 4:], qa[:4, 4:])
    ka = np.concatenate([k, [k_u]])
    err = np.abs(ka - np.asarray(k_ctl)[0]).max() / np.abs(ka).max()
    if err > 1e-9:
        raise AssertionError(f"T={t}, d={delay}: scipy and python-control differ on K: {err:.2e}")
    return {"T": t, "delay": delay, "Gamma0": gam0.tolist(), "Gamma1": gam1.tolist(),
            "K": k.tolist(), "K_u": [k_u], "Pa": pa.tolist(),
            "Qa11": qa[:4, :4].tolist(), "Qa12": qa[:4, 4].tolist(), "Qa22": [float(qa[4, 4])],
            "closed_loop_poles": sorted_poles(np.linalg.eigvals(a - b @ ka[None, :]))[:3]}


def linalg_cases() -> dict[str, Any]:
    """Hard cases for the core, with scipy's answers."""
    rng = np.random.default_rng(20240611)
    skew = rng.standard_normal((8, 8))
    skew = 40.0 * (skew - skew.T) - 0.5 * np.eye(8)  # ||.||_1 ~ 300, rotation-like
    nonnormal = np.triu(rng.standard_normal((6, 6)), 1) * 30.0 - np.diag(np.arange(1.0, 7.0))
    plant_block = np.zeros((8, 8))
    plant_block[:4, :4] = -np.block([[F, G], [np.zeros((1, 4))]]).T
    plant_block[:4, 4:] = sl.block_diag(WX, WU)
    plant_block[4:, 4:] = np.block([[F, G], [np.zeros((1, 4))]])
    expm_cases = [("skew_8x8_norm300", skew), ("nonnormal_6x6", nonnormal),
                  ("lqrd_block_T1", plant_block * 1.0)]
    eig_cases = [("random_10x10", rng.standard_normal((10, 10))),
                 ("graded_8x8", rng.standard_normal((8, 8)) * np.logspace(-4, 4, 8)[None, :])]

    # A generic DARE beyond n = 3: 4 states (2 unstable), 2 inputs, cross term.
    a = rng.standard_normal((4, 4)) * 0.6 + np.diag([1.3, -1.1, 0.2, 0.4])
    b = rng.standard_normal((4, 2))
    c = rng.standard_normal((2, 4))
    q = c.T @ c + 0.01 * np.eye(4)
    r = np.array([[2.0, 0.3], [0.3, 1.0]])
    s = 0.05 * rng.standard_normal((4, 2))
    x = sl.solve_discrete_are(a, b, q, r, s=s)
    return {
        "expm": [{"name": nm, "A": m.tolist(), "expm": sl.expm(m).tolist()} for nm, m in expm_cases],
        "eig": [{"name": nm, "A": m.tolist(),
                 "eigenvalues": sorted_poles(np.linalg.eigvals(m))} for nm, m in eig_cases],
        "dare": {"A": a.tolist(), "B": b.tolist(), "Q": q.tolist(), "R": r.tolist(),
                 "S": s.tolist(), "X": x.tolist()},
    }


def reference() -> dict[str, Any]:
    return {
        "generator": "tests/gen_lqg_vectors.py",
        "versions": {"numpy": np.__version__, "scipy": scipy.__version__,
                     "control": control.__version__},
        "plant": {"F": F.tolist(), "G": G.tolist(), "f": W_GUST.tolist(), "A": WX.tolist(),
                  "B": WU.tolist(), "H": H.tolist(), "R": R.tolist()},
        "cases": [design(t) for t in PERIODS],
        "delayed": [delayed_design(t, d) for t, d in DELAYED],
        "linalg": linalg_cases(),
    }


# ---- C header rendering (from the JSON data only) ------------------------------

def _flat(m: Any) -> list[float]:
    return [float(v) for v in np.asarray(m, dtype=float).ravel()]


def _arr(vals: list[float]) -> str:
    return "{" + ", ".join(repr(v) for v in vals) + "}"


def _preamble(ref: dict[str, Any], guard: str) -> list[str]:
    return [
        "/* GENERATED by tests/gen_lqg_vectors.py from lqg_reference.json -- do not edit.",
        " * scipy %s, numpy %s, python-control %s. */" % (
            ref["versions"]["scipy"], ref["versions"]["numpy"], ref["versions"]["control"]),
        "#ifndef %s" % guard,
        "#define %s" % guard,
        "",
    ]


def render_header(ref: dict[str, Any]) -> str:
    """The design cases and the 4-state DARE (tests/c/test_lqg.c)."""
    lines = _preamble(ref, "LQG_VECTORS_H") + [
        "typedef struct {",
        "    double t;",
        "    double phi[9], gamma[3], qd[9], q11[9], q12[3], q22[1];",
        "    double k[3], p[9], m[9], p_post[9], l[6];",
        "    double cl_poles[6], est_poles[6]; /* (re, im) pairs, firmware order */",
        "} lqg_vector_t;",
        "",
        "static const lqg_vector_t lqg_vectors[] = {",
    ]
    keys = ("Phi", "Gamma", "Qd", "Q11", "Q12", "Q22", "K", "P", "M", "P_post", "L",
            "closed_loop_poles", "estimator_poles")
    for case in ref["cases"]:
        fields = ",\n     ".join(_arr(_flat(case[k])) for k in keys)
        lines.append("    {%r,\n     %s}," % (float(case["T"]), fields))
    lines += ["};", "#define LQG_VECTOR_COUNT %d" % len(ref["cases"]), ""]
    lines += ["/* The delay-aware design: the LQR on [x; u_{k-1}]. */", "typedef struct {",
              "    double t, delay;",
              "    double gamma0[3], gamma1[3], k[3], k_u[1], pa[16], qa11[16], qa12[4], qa22[1];",
              "    double cl_poles[6];", "} lqg_delayed_vector_t;", "",
              "static const lqg_delayed_vector_t lqg_delayed_vectors[] = {"]
    dkeys = ("Gamma0", "Gamma1", "K", "K_u", "Pa", "Qa11", "Qa12", "Qa22", "closed_loop_poles")
    for case in ref["delayed"]:
        fields = ",\n     ".join(_arr(_flat(case[k])) for k in dkeys)
        lines.append("    {%r, %r,\n     %s}," % (float(case["T"]), float(case["delay"]), fields))
    lines += ["};", "#define LQG_DELAYED_VECTOR_COUNT %d" % len(ref["delayed"]), ""]
    d = ref["linalg"]["dare"]
    lines += ["/* A 4-state, 2-input DARE with cross term (scipy solve_discrete_are). */"]
    for key, name in (("A", "a"), ("B", "b"), ("Q", "q"), ("R", "r"), ("S", "s"), ("X", "x")):
        vals = _flat(d[key])
        lines.append("static const double lqg_dare4_%s[%d] = %s;" % (name, len(vals), _arr(vals)))
    lines += ["", "#endif /* LQG_VECTORS_H */", ""]
    return "\n".join(lines)


def render_linalg_header(ref: dict[str, Any]) -> str:
    """expm and eigenvalue cases (tests/c/test_linalg.c)."""
    lines = _preamble(ref, "LINALG_VECTORS_H")
    lines += ["typedef struct {", "    const char *name;", "    int n;",
              "    double a[100], expm[100];", "} linalg_expm_vector_t;", "",
              "static const linalg_expm_vector_t linalg_expm_vectors[] = {"]
    for c in ref["linalg"]["expm"]:
        lines.append('    {"%s", %d,\n     %s,\n     %s},' % (
            c["name"], len(c["A"]), _arr(_flat(c["A"])), _arr(_flat(c["expm"]))))
    lines += ["};", "#define LINALG_EXPM_VECTOR_COUNT %d" % len(ref["linalg"]["expm"]), ""]
    lines += ["typedef struct {", "    const char *name;", "    int n;",
              "    double a[100], eig[20]; /* (re, im) pairs, firmware order */",
              "} linalg_eig_vector_t;", "", "static const linalg_eig_vector_t linalg_eig_vectors[] = {"]
    for c in ref["linalg"]["eig"]:
        lines.append('    {"%s", %d,\n     %s,\n     %s},' % (
            c["name"], len(c["A"]), _arr(_flat(c["A"])), _arr(_flat(c["eigenvalues"]))))
    lines += ["};", "#define LINALG_EIG_VECTOR_COUNT %d" % len(ref["linalg"]["eig"]), ""]
    lines += ["#endif /* LINALG_VECTORS_H */", ""]
    return "\n".join(lines)


def render_json(ref: dict[str, Any]) -> str:
    return json.dumps(ref, indent=1, sort_keys=False) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=OUT_DIR, help="output directory")
    args = parser.parse_args(argv)
    ref = reference()
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / JSON_NAME).write_text(render_json(ref))
    # The headers are rendered from the JSON as written, so they depend on nothing else.
    written = json.loads((args.out / JSON_NAME).read_text())
    (args.out / HEADER_NAME).write_text(render_header(written))
    (args.out / LINALG_HEADER_NAME).write_text(render_linalg_header(written))
    print(f"wrote {JSON_NAME}, {HEADER_NAME}, {LINALG_HEADER_NAME} in {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
