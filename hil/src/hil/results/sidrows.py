"""The rows of the identification, as arrays: sid_replay's CSV output (read_rows) or the
numpy reference's rows (rows_to_arrays) -> {filter: {column: array}}.
"""
from __future__ import annotations

import csv
import io
from collections.abc import Iterable, Mapping

import numpy as np


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
