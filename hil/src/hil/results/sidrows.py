"""The rows of the identification, as arrays: sid_replay's CSV output (read_rows), its
binary estimates (read_binary_rows) or the numpy reference's rows (rows_to_arrays)
-> {filter: {column: array}}.
"""
from __future__ import annotations

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
    as rows_to_arrays gives it, but a column at a time: the text is cut into its cells once,
    a column is every n-th cell (its numbers converted at once), a filter's rows picked out
    of it (a row at a time is 4x slower; the conversion is most of the time, hence `columns`)."""
    header, _, body = text.partition("\n")
    if not header:
        return {}
    names = header.split(",")
    n = len(names)
    col = names.index("filter")
    keep = [i for i, h in enumerate(names) if i != col and (columns is None or h in columns)]
    body = body[:-1] if body.endswith("\n") else body
    cells = body.replace("\n", ",").split(",") if body else []
    if len(cells) % n:
        raise ValueError(f"sid_replay output: rows of other than the header's {n} fields")
    filters = np.array(cells[col::n])
    rows = {f: np.flatnonzero(filters == f) for f in dict.fromkeys(cells[col::n])}
    values = {names[i]: np.array(cells[i::n], dtype=float) for i in keep}
    return {f: {name: v[r] for name, v in values.items()} for f, r in rows.items()}


#: sid_replay --estimates: the columns after t and the filter (the rig's tables and check read
#: them; --binary: the values of a row after t and the filter's code)
ESTIMATES = ("alpha_hat", "q_hat", "alpha_lo", "alpha_hi", "q_lo", "q_hi")
#: the filter codes' names: code = filter + 3 x row mode (modes only with --all-rows)
BINARY_FILTERS = ("kf", "zkf", "azkf")
#: the row modes (fcc_sid.h), in the order of the codes
ROW_MODES = ("paper", "prior", "posterior")


def read_binary_rows(data: bytes, all_rows: bool) -> dict[str, dict[str, np.ndarray]]:
    """sid_replay --estimates --binary output (rows of 9 native binary64 values: t, the
    filter's code, ESTIMATES, the fault flag) -> {filter: {column: array}} with the columns t,
    ESTIMATES and fault, as read_rows gives the text of --estimates (filter "MODE/FILTER"
    with --all-rows) and its fault: the same numbers, none formatted or parsed."""
    width = 2 + len(ESTIMATES) + 1
    if len(data) % (8 * width):
        raise ValueError(f"sid_replay --binary output: {len(data)} bytes, not rows of {width} values")
    rows = np.frombuffer(data, dtype=np.float64).reshape(-1, width)
    names = [f"{m}/{f}" for m in ROW_MODES for f in BINARY_FILTERS] if all_rows else list(BINARY_FILTERS)
    out: dict[str, dict[str, np.ndarray]] = {}
    codes = rows[:, 1]
    unique, first = np.unique(codes, return_index=True)
    for code in unique[np.argsort(first)].tolist():   # in the order they first appear
        if not (code.is_integer() and 0 <= code < len(names)):
            raise ValueError(f"sid_replay --binary output: a row of filter code {code!r}")
        picked = rows[codes == code]
        out[names[int(code)]] = {"t": picked[:, 0].copy(),
                                 **{c: picked[:, 2 + j].copy() for j, c in enumerate(ESTIMATES)},
                                 "fault": picked[:, -1].copy()}
    return out
