"""Evaluation of Tables 4-5: integral of |y - y_hat| dt per state, per filter."""
from __future__ import annotations

import csv
import io
from collections.abc import Iterable, Mapping

import numpy as np

from hil import metrics
from hil.reference.flight import DT


def rows_to_arrays(rows: Iterable[Mapping[str, object]]) -> dict[str, dict[str, np.ndarray]]:
    """Replay rows (the reference's, or sid_replay's CSV rows) -> {filter: {column: array}}."""
    out: dict[str, dict[str, list[float]]] = {}
    for row in rows:
        cols = out.setdefault(str(row["filter"]), {})
        for key, val in row.items():
            if key != "filter":
                cols.setdefault(key, []).append(float(val))  # type: ignore[arg-type]
    return {f: {k: np.asarray(v) for k, v in cols.items()} for f, cols in out.items()}


def read_rows(text: str) -> dict[str, dict[str, np.ndarray]]:
    """sid_replay output -> {filter: {column: array}} (numeric columns), as rows_to_arrays
    gives it, but a filter's rows converted at once (a row at a time is 4x slower)."""
    reader = csv.reader(io.StringIO(text))
    header = next(reader, None)
    if header is None:
        return {}
    col = header.index("filter")
    names = [h for i, h in enumerate(header) if i != col]
    rows: dict[str, list[list[str]]] = {}
    for row in reader:
        rows.setdefault(row[col], []).append(row[:col] + row[col + 1:])
    return {f: dict(zip(names, np.array(r, dtype=float).T)) for f, r in rows.items()}


def _estimate(est: Mapping[str, np.ndarray]) -> np.ndarray:
    return np.column_stack([est["alpha_hat"], est["q_hat"]])


def error_table(y_clean: np.ndarray, x_true: np.ndarray | None,
                results: dict[str, dict[str, np.ndarray]]) -> dict[str, dict[str, np.ndarray]]:
    """{filter: {'meas': [e_alpha, e_q], 'truth': [...]}}: hil.metrics' error integral."""
    table = {}
    for name, est in results.items():
        targets = {"meas": y_clean} if x_true is None else {"meas": y_clean, "truth": x_true}
        table[name] = {key: np.array(metrics.error_integral(target, _estimate(est), DT)[:2])
                       for key, target in targets.items()}
    return table


def format_table(table: dict[str, dict[str, np.ndarray]]) -> str:
    """Text tables in the paper's layout (hil.metrics), improvement vs the KF in parentheses."""
    parts = []
    for key, title in (("meas", "vs fault-free measurement"), ("truth", "vs true state")):
        if all(key in v for v in table.values()):
            rows = {name: dict(zip(metrics.STATES, (float(e) for e in v[key])))
                    for name, v in table.items()}
            parts.append(metrics.format_error_table(rows, f"integral |e| dt, {title}"))
    return "\n".join(parts)
