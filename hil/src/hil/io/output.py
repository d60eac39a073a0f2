"""Writing and reading a run directory: CSV time series and JSON documents (each written
atomically: hil.io.rundir).

summary.json holds only what the seed determines (sorted keys, no wall-clock value), so two
lockstep runs with the same seed write byte-identical files; timings, host and command lines
go to run_info.json.
"""
from __future__ import annotations

import csv
import io
import json
import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from hil.io.rundir import atomic_write_text
from hil.util.bounded import read_bounded


def _cells(column: np.ndarray) -> list[str]:
    """A column's cells: integers as they are, everything else as floats at full precision
    (a column at a time: a cell at a time is 3x slower; repr(nan) is "nan", so a float
    column needs no test per cell)."""
    if column.dtype.kind in "iu":
        return [str(v) for v in column.tolist()]
    if column.dtype.kind == "f":
        return list(map(repr, column.tolist()))
    return ["nan" if math.isnan(x) else repr(x) for x in map(float, column.tolist())]


def write_csv(path: Path, columns: Mapping[str, np.ndarray]) -> Path:
    """Columns of equal length → CSV with a header (full float precision)."""
    names = list(columns)
    n = {len(np.asarray(c)) for c in columns.values()}
    if len(n) != 1:
        raise ValueError(f"{path.name}: columns of different lengths {sorted(n)}")
    arrays = [np.asarray(columns[k]) for k in names]
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerow(names)   # (a name may need quotes)
    # a number never needs quotes: the rows are joined directly (csv.writer: 5x slower)
    buf.writelines(",".join(row) + "\n" for row in zip(*(_cells(a) for a in arrays)))
    return atomic_write_text(path, buf.getvalue(), encoding="ascii")


def read_csv(path: Path) -> dict[str, np.ndarray]:
    """A CSV written by write_csv → {column: float array}."""
    with open(path, newline="", encoding="ascii") as fh:
        r = csv.reader(fh)
        try:
            head = next(r)
        except StopIteration:
            raise ValueError(f"{path}: empty CSV file") from None
        rows = [[float(c) for c in row] for row in r if row]
    data = np.array(rows, dtype=float).reshape(len(rows), len(head))
    return {name: data[:, i] for i, name in enumerate(head)}


def _plain(obj: Any) -> Any:
    if isinstance(obj, Mapping):
        return {str(k): _plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_plain(v) for v in obj]
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return [_plain(v) for v in obj.tolist()]
    if isinstance(obj, float) and not math.isfinite(obj):
        return None if math.isnan(obj) else ("inf" if obj > 0 else "-inf")
    return obj


def write_json(path: Path, doc: Mapping[str, Any]) -> Path:
    return atomic_write_text(path, json.dumps(_plain(doc), indent=2, sort_keys=True) + "\n")


#: summary.json and its kind: a few MB at most
JSON_MAX_BYTES = 256 << 20


def read_json(path: Path) -> dict[str, Any]:
    try:
        return json.loads(read_bounded(path, JSON_MAX_BYTES, "summary").decode("utf-8"))
    except OSError as e:
        raise ValueError(f"{path}: cannot read: {e.strerror}") from None
    except json.JSONDecodeError as e:
        raise ValueError(f"{path}: not valid JSON: {e}") from None
