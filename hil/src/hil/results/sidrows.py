"""The rows of the identification, as arrays: sid_replay's CSV output (read_rows) or the
numpy reference's rows (rows_to_arrays) -> {filter: {column: array}}.
"""
from __future__ import annotations

import csv
import io
from collections.abc import Collection, Iterable, Mapping

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


def read_rows(text: str, columns: Collection[str] | None = None) -> dict[str, dict[str, np.ndarray]]:
    """sid_replay output -> {filter: {column: array}} (numeric columns, or only `columns`),
    as rows_to_arrays gives it, but a filter's rows converted at once (a row at a time is 4x
    slower; the text to float conversion is most of the time, hence `columns`)."""
    reader = csv.reader(io.StringIO(text))
    header = next(reader, None)
    if header is None:
        return {}
    col = header.index("filter")
    keep = [i for i, h in enumerate(header) if i != col and (columns is None or h in columns)]
    rows: dict[str, list[list[str]]] = {}
    for row in reader:
        rows.setdefault(row[col], []).append([row[i] for i in keep])
    names = [header[i] for i in keep]
    return {f: dict(zip(names, np.array(r, dtype=float).T)) for f, r in rows.items()}
