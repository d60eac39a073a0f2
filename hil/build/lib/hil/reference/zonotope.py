"""Zonotopes <c, R> and the reduction operator of order q (eqs. 15-18).

Reduction, as firmware/sid/fcc_zonotope.h: if p <= q nothing happens;
otherwise rank the columns by decreasing squared 2-norm with a stable sort
(ties keep their original order), keep the first q - n and box the rest into
diag(|R_rest| 1).  The kept columns stay in their original relative order and
the n box columns come last (the set does not depend on the order).
"""
from __future__ import annotations

import numpy as np


def reduce_order(r: np.ndarray, q: int) -> np.ndarray:
    n, p = r.shape
    if q < n:
        raise ValueError(f"order {q} below the dimension {n}")
    if p <= q:
        return r.copy()
    norms = np.sum(r * r, axis=0)
    ranking = np.argsort(-norms, kind="stable")
    keep = np.sort(ranking[: q - n])
    boxed = np.sort(ranking[q - n:])
    box = np.diag(np.sum(np.abs(r[:, boxed]), axis=1))
    return np.hstack([r[:, keep], box])


def hull(r: np.ndarray) -> np.ndarray:
    """Interval hull radius sum_j |r_ij|."""
    return np.sum(np.abs(r), axis=1)


def size(r: np.ndarray) -> float:
    """J_R = sqrt(tr(R R^T)) (eq. 16)."""
    return float(np.sqrt(np.trace(r @ r.T)))


def contains(c: np.ndarray, r: np.ndarray, point: np.ndarray, tol: float = 1e-12) -> bool:
    """Exact membership in a 2-D zonotope: slabs normal to each generator and the axes."""
    d = np.asarray(point, dtype=float) - np.asarray(c, dtype=float)
    normals = np.vstack([np.column_stack([-r[1], r[0]]), np.eye(2)])
    for nv in normals:
        scale = np.sum(np.abs(nv))
        if scale == 0.0:
            continue
        if abs(nv @ d) > np.sum(np.abs(nv @ r)) + tol * scale:
            return False
    return True
