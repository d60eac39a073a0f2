"""A chunk's campaign flights handed back in bulk (hil.parallel.bulk), without a rig: every value
Table 5 reads of a flight comes back bit for bit (NaN, signed zero, the last ulp), and
write_campaign writes the same files byte for byte from the flights and from their batch."""
from __future__ import annotations

import math
import pickle
from pathlib import Path

import numpy as np
import pytest

from hil.parallel.bulk import MODE_TABLES, MODES, pack_flights, unpack_flights
from hil.results import metrics
from hil.runs.campaign import CampaignFlight, write_campaign
from hil.scenario.file import load_default_scenario

FIRMWARE = {"steps": {"cdrw": 702, "missile": 0}}


def table(rng: np.random.Generator) -> metrics.Table:
    return {f: {s: float(rng.random()) / 7.0 for s in metrics.STATES} for f in metrics.FILTERS}


def flight(index: int, rng: np.random.Generator, *, refused: bool = False) -> CampaignFlight:
    """A flight as hil.runs.campaign.evaluate_flights makes it (random values, the modes'
    extras Table 5 does not read included)."""
    modes = {m: {"table4": table(rng), "table4_truth": table(rng), "coverage": table(rng),
                 "improvement_over_kf_pct": {"azkf": {"alpha": 1.0, "q": 2.0}}} for m in MODES}
    check = {"rows": "paper", "resolution": {"estimate": 1e-5, "bound": 1e-4},
             "max_abs_estimate_difference": float(rng.random()) * 1e-5, "max_abs_bound_difference": 4e-5,
             "fault_flag_mismatches": 0}
    if refused:
        modes, check = {}, {"rows": "paper", "not_computed": "sid_replay: shorter than the MLS window"}
    t = 0.37 + index / 3.0
    events = [{"t": t, "action": "start", "index": 0, "level": "sensor", "kind": "spike", "target": "alpha",
               "spec": f"spike:start={t},duration=0.1,signal=alpha,magnitude=0.15"},
              {"t": t + 0.1, "action": "end", "index": 0, "level": "sensor", "kind": "spike", "target": "alpha",
               "spec": f"spike:start={t},duration=0.1,signal=alpha,magnitude=0.15"}]
    series = {"t": np.arange(5) * 0.02, "alpha_true": rng.random(5)} if index == 0 else None
    return CampaignFlight(index, t, table(rng), table(rng), index % 2, 3 - index % 3, events, series,
                          table(rng), "paper", modes, check)


def as_read(fl: CampaignFlight) -> CampaignFlight:
    """A flight reduced to what Table 5 reads: a mode's MODE_TABLES, replay_check's rows and
    its largest estimate difference or why there is none."""
    keep = ("rows", "max_abs_estimate_difference", "not_computed")
    modes = {m: {t: fl.modes[m][t] for t in MODE_TABLES} for m in MODES} if fl.modes else None
    return CampaignFlight(fl.index, fl.fault_start, fl.table, fl.table_truth, fl.missing_steps,
                          fl.unanswered_steps, fl.events, fl.series, fl.coverage, fl.rows, modes,
                          {k: v for k, v in (fl.replay_check or {}).items() if k in keep})


def bits(x: object) -> object:
    """A value in a form equal only when equal to the last bit (floats as their hex, NaN and
    -0.0 too) and in the same key order (json's)."""
    if isinstance(x, CampaignFlight):
        return bits(vars(x))
    if isinstance(x, dict):
        return [(k, bits(v)) for k, v in x.items()]
    if isinstance(x, list):
        return [bits(v) for v in x]
    if isinstance(x, float):
        return x.hex()
    if isinstance(x, np.ndarray):
        return (x.dtype.str, x.tobytes())
    return (type(x).__name__, x)


def test_a_batch_gives_back_every_value_table5_reads_bit_for_bit():
    rng = np.random.default_rng(5)
    flights = [flight(i, rng, refused=i == 3) for i in range(6)]
    flights[1].table["kf"]["q"] = math.nan                # a flight whose KF lacked estimates
    flights[2].table_truth["azkf"]["alpha"] = -0.0
    flights[4].coverage = None
    flights[5].fault_start = math.nextafter(flights[5].fault_start, 9.0)
    batch = pack_flights(flights)
    assert len(batch) == 6 and batch.indices == list(range(6))
    back = unpack_flights(pickle.loads(pickle.dumps(batch, protocol=pickle.HIGHEST_PROTOCOL)))
    assert [bits(b) for b in back] == [bits(as_read(f)) for f in flights]
    assert math.isnan(back[1].table["kf"]["q"]) and math.copysign(1.0, back[2].table_truth["azkf"]["alpha"]) < 0
    assert back[0].series is not None and all(b.series is None for b in back[1:])


def test_a_batch_is_a_few_objects_whatever_its_flights():
    rng = np.random.default_rng(1)
    batch = pack_flights([flight(i, rng) for i in range(1, 101)])
    assert batch.series is None and batch.numbers.shape == (100,)
    assert len(pickle.dumps(batch, protocol=pickle.HIGHEST_PROTOCOL)) < 100 * 1500   # was ~2 kB a flight


def test_table5_from_batches_is_byte_identical(tmp_path: Path):
    """write_campaign from the flights and from two batches of them (as two chunks): the same
    campaign.csv, faults.log, cdrw_run0.csv and summary.json."""
    rng = np.random.default_rng(9)
    flights = [flight(i, rng) for i in range(7)]
    sc = load_default_scenario("cdrw")
    direct, bulk = tmp_path / "direct", tmp_path / "bulk"
    for d in (direct, bulk):
        d.mkdir()
    write_campaign(direct, sc, 3, 7, flights, FIRMWARE, "lockstep")
    chunks = [pack_flights(flights[4:]), pack_flights(flights[:4])]   # in any order
    write_campaign(bulk, sc, 3, 7, [fl for c in chunks for fl in unpack_flights(c)], FIRMWARE, "lockstep")
    for name in ("campaign.csv", "faults.log", "cdrw_run0.csv", "summary.json"):
        assert (bulk / name).read_bytes() == (direct / name).read_bytes(), name


def test_a_table_of_another_shape_is_refused():
    rng = np.random.default_rng(2)
    fl = flight(1, rng)
    fl.table = {"kf": fl.table["kf"], "azkf": fl.table["azkf"], "zkf": fl.table["zkf"]}
    with pytest.raises(ValueError, match="FILTERS|azkf"):
        pack_flights([fl])
