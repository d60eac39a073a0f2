"""A chunk's campaign flights handed back in bulk (worker -> coordinator): what Table 5 reads of
each flight (hil.runs.campaign.write_campaign) as one numpy record a flight in one array, the
flights' fault events and rows as one JSON text, flight 0's series as its arrays.

Before, each flight came back as a CampaignFlight of nested dicts (about 60 floats in 16 dicts,
its events, the per-flight improvements Table 5 does not read): one object graph a flight to
pickle on the worker and to rebuild on the coordinator.  A batch is three objects whatever its
flights, and unpack_flights gives back every value write_campaign reads bit for bit (floats as
float64, their NaN included; the events through JSON, whose floats round-trip exactly), so
Table 5 is the same byte for byte (tests/python/parallel/test_bulk.py).

Why not only the aggregates: campaign.csv, faults.log and summary.json's `runs` are per
flight, and Table 5's means and intervals are sums in flight order over the whole campaign
(metrics.campaign_table5): per-chunk partial sums would move their last digits.
"""
from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from hil.results import metrics
from hil.runs.campaign import CampaignFlight

#: the tables of a flight's symmetric modes (rowtables.mode_tables) that Table 5 reads
MODE_TABLES = ("table4", "table4_truth", "coverage")
MODES = ("prior", "posterior")
_SHAPE = (len(metrics.FILTERS), len(metrics.STATES))

#: one flight: its numbers (a table is FILTERS x STATES; NaN where a value is NaN)
RECORD = np.dtype([
    ("index", "<i8"), ("fault_start", "<f8"), ("missing_steps", "<i8"), ("unanswered_steps", "<i8"),
    ("table", "<f8", _SHAPE), ("table_truth", "<f8", _SHAPE),
    ("has_coverage", "?"), ("coverage", "<f8", _SHAPE),
    ("has_modes", "?"), ("modes", "<f8", (len(MODES), len(MODE_TABLES), *_SHAPE)),
    ("replay_worst", "<f8"),   # replay_check's max_abs_estimate_difference (with the modes)
])


@dataclass
class FlightBatch:
    """Campaign flights in bulk: `numbers` (RECORD, one a flight, in the order given), `text`
    (JSON: each flight's [events, rows, not_computed]), `series` (the flight of index 0's,
    when it is among them: cdrw_run0.csv)."""

    numbers: np.ndarray
    text: bytes
    series: dict[str, np.ndarray] | None = None

    def __len__(self) -> int:
        return len(self.numbers)

    @property
    def indices(self) -> list[int]:
        return [int(i) for i in self.numbers["index"]]


def _table_array(table: metrics.Table) -> np.ndarray:
    if list(table) != list(metrics.FILTERS) or any(list(row) != list(metrics.STATES) for row in table.values()):
        raise ValueError(f"a flight's table of {list(table)} x {[list(r) for r in table.values()]}, "
                        f"not {list(metrics.FILTERS)} x {list(metrics.STATES)}")
    return np.array([[table[f][s] for s in metrics.STATES] for f in metrics.FILTERS], dtype="<f8")


def _table(a: np.ndarray) -> metrics.Table:
    return {f: {s: float(a[i, j]) for j, s in enumerate(metrics.STATES)} for i, f in enumerate(metrics.FILTERS)}


def pack_flights(flights: Sequence[CampaignFlight]) -> FlightBatch:
    """The flights as one batch (ValueError when a table is not FILTERS x STATES in that
    order: it would not come back the same)."""
    numbers = np.zeros(len(flights), RECORD)
    text: list[list[Any]] = []
    series = None
    for r, fl in zip(numbers, flights):
        r["index"], r["fault_start"] = fl.index, fl.fault_start
        r["missing_steps"], r["unanswered_steps"] = fl.missing_steps, fl.unanswered_steps
        r["table"], r["table_truth"] = _table_array(fl.table), _table_array(fl.table_truth)
        r["has_coverage"] = bool(fl.coverage)
        if fl.coverage:
            r["coverage"] = _table_array(fl.coverage)
        r["has_modes"] = bool(fl.modes)
        if fl.modes:
            r["modes"] = [[_table_array(fl.modes[m][t]) for t in MODE_TABLES] for m in MODES]
            r["replay_worst"] = (fl.replay_check or {})["max_abs_estimate_difference"]
        text.append([fl.events, fl.rows, None if fl.modes else (fl.replay_check or {}).get("not_computed")])
        if fl.series is not None:
            series = fl.series
    return FlightBatch(numbers, json.dumps(text, allow_nan=True).encode(), series)


def unpack_flights(batch: FlightBatch) -> list[CampaignFlight]:
    """The batch's flights as write_campaign reads them: every value pack_flights took, the
    same to the last bit (a mode's tables are MODE_TABLES, replay_check its rows and either
    max_abs_estimate_difference or, without modes, not_computed when there was one)."""
    out = []
    for r, (events, rows, not_computed) in zip(batch.numbers, json.loads(batch.text)):
        modes = None
        check: dict[str, Any] = {"rows": rows}
        if r["has_modes"]:
            modes = {m: {t: _table(r["modes"][k, j]) for j, t in enumerate(MODE_TABLES)} for k, m in enumerate(MODES)}
            check["max_abs_estimate_difference"] = float(r["replay_worst"])
        elif not_computed is not None:
            check["not_computed"] = not_computed
        index = int(r["index"])
        out.append(CampaignFlight(index, float(r["fault_start"]), _table(r["table"]), _table(r["table_truth"]),
                                  int(r["missing_steps"]), int(r["unanswered_steps"]), events,
                                  batch.series if index == 0 else None,
                                  _table(r["coverage"]) if r["has_coverage"] else None, rows, modes, check))
    return out


__all__ = ["FlightBatch", "pack_flights", "unpack_flights"]
