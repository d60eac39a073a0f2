"""scripts/bench.d/lqg's table: the firmware's seed-2 LQG design (the instruction counts that
callgrind measured, given as --ir PART=N; its wall time per design from lqg_design --repeat,
start-up subtracted) beside the same design in scipy and in python-control, timed here
(tests/gen_lqg_vectors.py's plant and weights: Van Loan expm x3, two Riccati equations, gains,
poles).

Like is compared with like: the firmware solves each Riccati equation twice (Hamiltonian, then
doubling as a cross-check) where scipy and python-control solve it once, so the speed-ups are
taken against the firmware's one-solver cost (the design less its doubling part, the time
scaled by the same instruction ratio); and the BLAS under numpy runs on the threads that
scripts/bench.d/lqg pins (one, printed), not on as many as it finds.

    python -m hil.bench.lqg --tool build/bin/lqg_design [--period 0.1] [--ir hamiltonian_design=N ...]
"""
from __future__ import annotations

import argparse
import importlib.util
import os
import subprocess
import time
import timeit
from collections.abc import Callable, Sequence
from pathlib import Path
from types import ModuleType
from typing import Any

import control
import numpy as np
import scipy
import scipy.linalg as sl

from hil.io.paths import source_tree

#: the instruction counts the table shows, by solver and part (scripts/bench.d/lqg measures them)
IR_PARTS = ("design", "c2d", "ham", "dbl", "total")


def reference_module(repo: Path | None = None) -> ModuleType:
    """tests/gen_lqg_vectors.py: the plant, the weights and the discretisation the firmware's
    test vectors come from."""
    repo = repo or source_tree()
    if repo is None:
        raise SystemExit("bench lqg: needs the source tree (tests/gen_lqg_vectors.py)")
    spec = importlib.util.spec_from_file_location("gen", repo / "tests" / "gen_lqg_vectors.py")
    assert spec is not None and spec.loader is not None
    gen = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen)
    return gen


def discretise(gen: ModuleType, period: float) -> tuple[np.ndarray, ...]:
    phi, gam = gen.zoh(gen.F, gen.G, period)
    qd = gen.noise(gen.F, gen.W_GUST @ gen.W_GUST.T, period)
    q11, q12, q22 = gen.cost(gen.F, gen.G, gen.WX, gen.WU, period)
    return phi, gam, qd, q11, q12, q22


def scipy_design(gen: ModuleType, period: float) -> tuple[np.ndarray, np.ndarray]:
    phi, gam, qd, q11, q12, q22 = discretise(gen, period)
    p = sl.solve_discrete_are(phi, gam, q11, q22, s=q12)
    k = np.linalg.solve(q22 + gam.T @ p @ gam, gam.T @ p @ phi + q12.T)
    m = sl.solve_discrete_are(phi.T, gen.H.T, qd, gen.R)
    gain = np.linalg.solve(gen.H @ m @ gen.H.T + gen.R, gen.H @ m).T
    return np.linalg.eigvals(phi - gam @ k), np.linalg.eigvals(phi - phi @ gain @ gen.H)


def control_design(gen: ModuleType, period: float) -> tuple[Any, Any]:
    phi, gam, qd, q11, q12, q22 = discretise(gen, period)
    _, _, cl = control.dlqr(phi, gam, q11, q22, q12)
    _, _, est = control.dlqe(phi, np.eye(3), gen.H, qd, gen.R)
    return cl, est


def per_call(fn: Callable[[], object], repeat: int = 7) -> float:
    """Seconds per call, the best of `repeat` timeit runs."""
    timer = timeit.Timer(fn)
    n, _ = timer.autorange()
    return min(timer.repeat(repeat=repeat, number=n)) / n


def c_per_design(tool: Path, period: float, reps: int = 2000) -> float:
    """Seconds per design of lqg_design --repeat, its start-up subtracted (best of 3)."""
    def run(n: int) -> float:
        t0 = time.perf_counter()
        subprocess.run([str(tool), "--period", str(period), "--repeat", str(n)], check=True,
                       stdout=subprocess.DEVNULL)
        return time.perf_counter() - t0
    best = min(run(reps + 1) - run(1) for _ in range(3))
    return max(best, 0.0) / reps


#: the variables that set the BLAS's thread count, by the libraries numpy may be built with
BLAS_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


def blas_threads() -> str:
    """How many threads numpy's BLAS was given, as the environment pinned it."""
    pinned = {v: os.environ[v] for v in BLAS_THREAD_VARIABLES if v in os.environ}
    if not pinned:
        return "not pinned (the BLAS takes every CPU it finds)"
    return ", ".join(f"{k}={v}" for k, v in pinned.items())


def one_solver(ir: dict[str, int], t_c: float) -> tuple[int, float]:
    """The firmware's design with one Riccati solver, as scipy and python-control run it: the
    Hamiltonian design less its doubling cross-check, in instructions and (scaled by the same
    ratio) in time."""
    h = "hamiltonian"
    n = ir[f"{h}_design"] - ir[f"{h}_dbl"]
    return n, t_c * n / ir[f"{h}_design"]


def table(period: float, ir: dict[str, int], t_c: float, t_scipy: float, t_ctl: float) -> None:
    h = "hamiltonian"
    n_one, t_one = one_solver(ir, t_c)
    rows = [
        ("fcc_lqg_design_delayed, full design (C, double)", ir[f"{h}_design"], t_c),
        ("  Van Loan discretisation (3 expm)", ir[f"{h}_c2d"], None),
        ("  Hamiltonian eigenvectors (LQR + KF)", ir[f"{h}_ham"], None),
        ("  doubling (LQR + KF)", ir[f"{h}_dbl"], None),
        ("  full design less the doubling cross-check", n_one, t_one),
        ("fcc_lqg_design_delayed, --solver doubling", ir["doubling_design"], None),
        ("whole lqg_design process (startup, JSON)", ir[f"{h}_total"], None),
        (f"scipy {scipy.__version__} (expm, solve_discrete_are)", None, t_scipy),
        (f"python-control {control.__version__} (dlqr, dlqe)", None, t_ctl),
    ]
    print(f"missile LQG design at T = {period} s; every design runs and cross-checks both Riccati solvers")
    print(f"numpy {np.__version__}, BLAS threads: {blas_threads()}")
    print(f"{'':44s} {'instructions':>14s} {'time/design':>12s}")
    for name, n, t in rows:
        ns = f"{n:,d}" if n is not None else "-"
        ts = f"{t * 1e6:9.1f} us" if t is not None else "-"
        print(f"{name:44s} {ns:>14s} {ts:>12s}")
    print(f"speed-up of the C design (one solver, as theirs) over scipy: {t_scipy / t_one:.0f}x, "
          f"over python-control: {t_ctl / t_one:.0f}x" if t_one > 0 else "C design too fast to time")


def count(text: str) -> tuple[str, int]:
    """--ir SOLVER_PART=N"""
    key, _, n = text.partition("=")
    if not n:
        raise argparse.ArgumentTypeError(f"expected SOLVER_PART=N, got {text!r}")
    return key, int(n)


def main(argv: Sequence[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m hil.bench.lqg", description=__doc__.splitlines()[0])
    p.add_argument("--tool", type=Path, required=True, help="lqg_design of a Release build")
    p.add_argument("--period", type=float, default=0.1, help="T of the design (default 0.1 s)")
    p.add_argument("--ir", type=count, action="append", default=[], metavar="SOLVER_PART=N",
                   help=f"callgrind's count, SOLVER hamiltonian|doubling, PART {'|'.join(IR_PARTS)}")
    a = p.parse_args(argv)
    gen = reference_module()
    t_c = c_per_design(a.tool, a.period)
    t_scipy = per_call(lambda: scipy_design(gen, a.period))
    t_ctl = per_call(lambda: control_design(gen, a.period))
    table(a.period, dict(a.ir), t_c, t_scipy, t_ctl)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
