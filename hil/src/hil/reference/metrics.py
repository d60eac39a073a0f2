"""Evaluation of Tables 4-5: integral of |y - y_hat| dt per state, per filter."""
from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from hil.reference.flight import DT
from hil.results import metrics


def _estimate(est: Mapping[str, np.ndarray]) -> np.ndarray:
    return np.column_stack([est["alpha_hat"], est["q_hat"]])


def error_table(y_clean: np.ndarray, x_true: np.ndarray | None,
                results: dict[str, dict[str, np.ndarray]]) -> dict[str, dict[str, np.ndarray]]:
    """{filter: {'meas': [e_alpha, e_q], 'truth': [...]}}: hil.results.metrics' error integral."""
    table = {}
    for name, est in results.items():
        targets = {"meas": y_clean} if x_true is None else {"meas": y_clean, "truth": x_true}
        table[name] = {key: np.array(metrics.error_integral(target, _estimate(est), DT)[:2])
                       for key, target in targets.items()}
    return table


def format_table(table: dict[str, dict[str, np.ndarray]]) -> str:
    """Text tables in the paper's layout (hil.results.metrics), improvement vs the KF in parentheses."""
    parts = []
    for key, title in (("meas", "vs fault-free measurement"), ("truth", "vs true state")):
        if all(key in v for v in table.values()):
            rows = {name: dict(zip(metrics.STATES, (float(e) for e in v[key])))
                    for name, v in table.items()}
            parts.append(metrics.format_error_table(rows, f"integral |e| dt, {title}"))
    return "\n".join(parts)
