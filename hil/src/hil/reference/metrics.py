"""Evaluation of Tables 4-5: integral of |y - y_hat| dt per state, per filter."""
from __future__ import annotations

import csv
import io

import numpy as np

from hil.reference.flight import DT


def read_rows(text: str) -> dict[str, dict[str, np.ndarray]]:
    """sid_replay output -> {filter: {column: array}} (numeric columns)."""
    out: dict[str, dict[str, list[float]]] = {}
    for row in csv.DictReader(io.StringIO(text)):
        cols = out.setdefault(row["filter"], {})
        for key, val in row.items():
            if key != "filter":
                cols.setdefault(key, []).append(float(val))
    return {f: {k: np.asarray(v) for k, v in cols.items()} for f, cols in out.items()}


def rows_to_arrays(rows: list[dict]) -> dict[str, dict[str, np.ndarray]]:
    """Reference replay rows -> the same layout as read_rows."""
    out: dict[str, dict[str, list[float]]] = {}
    for row in rows:
        cols = out.setdefault(row["filter"], {})
        for key, val in row.items():
            if key != "filter":
                cols.setdefault(key, []).append(float(val))
    return {f: {k: np.asarray(v) for k, v in cols.items()} for f, cols in out.items()}


def integral_error(target: np.ndarray, est: dict[str, np.ndarray], dt: float = DT) -> np.ndarray:
    """sum_k |target_k - C x_hat_k| dt for (alpha, q); target is (N, 2)."""
    y_hat = np.column_stack([est["alpha_hat"], est["q_hat"]])
    return np.sum(np.abs(target - y_hat), axis=0) * dt


def error_table(y_clean: np.ndarray, x_true: np.ndarray | None,
                results: dict[str, dict[str, np.ndarray]]) -> dict[str, dict[str, np.ndarray]]:
    """{filter: {'meas': [e_alpha, e_q], 'truth': [...]}}."""
    table = {}
    for name, est in results.items():
        entry = {"meas": integral_error(y_clean, est)}
        if x_true is not None:
            entry["truth"] = integral_error(x_true, est)
        table[name] = entry
    return table


def format_table(table: dict[str, dict[str, np.ndarray]], baseline: str = "kf") -> str:
    """Text table in the paper's layout, improvement vs the KF in parentheses."""
    lines = []
    for key, title in (("meas", "vs fault-free measurement"), ("truth", "vs true state")):
        if not all(key in v for v in table.values()):
            continue
        lines.append(f"integral |e| dt, {title}")
        lines.append(f"{'state':<6}" + "".join(f"{name.upper():>20}" for name in table))
        for i, state in enumerate(("alpha", "q")):
            base = table[baseline][key][i] if baseline in table else None
            cells = []
            for name in table:
                v = table[name][key][i]
                gain = "" if base is None or name == baseline else f" ({100 * (1 - v / base):+.1f}%)"
                cells.append(f"{v:.4f}{gain}")
            lines.append(f"{state:<6}" + "".join(f"{c:>20}" for c in cells))
    return "\n".join(lines)
