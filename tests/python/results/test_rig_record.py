"""The simulator's record of a CDRW flight (hil.results.flight.cdrw_record): a campaign's
flights reuse the true model's columns of the flight before when they share its
linearisations, and their records are the ones made from scratch, value for value."""
from __future__ import annotations

import pickle

from hil.bus import SIM_NODES, FrameCodec, load
from hil.results import flight
from hil.scenario.campaign import campaign_fault_times
from hil.scenario.file import load_default_scenario, with_fault_start
from hil.sim.drivers import CdrwDriver


def test_records_with_the_kept_model_columns_are_made_from_scratch(monkeypatch):
    spec = load()
    sc = load_default_scenario("cdrw", {m.name for m in spec.messages})
    codec = FrameCodec(spec, SIM_NODES)
    drivers = [CdrwDriver(with_fault_start(sc, float(t)), codec) for t in campaign_fault_times(sc, 4, 1)]
    kept = [flight.cdrw_record(d).series for d in drivers]
    # the flights share the clean flight's linearisations: the columns were given again
    assert all(a.lin is b.lin for a, b in zip(drivers[0].samples, drivers[3].samples))
    for d, series in zip(drivers, kept):
        monkeypatch.setattr(flight, "_model_columns", flight._ModelColumns())
        fresh = flight.cdrw_record(d).series
        assert list(series) == list(fresh)
        assert all(pickle.dumps(series[k]) == pickle.dumps(fresh[k]) for k in fresh)


def test_a_flight_of_other_linearisations_gets_its_own_columns(monkeypatch):
    spec = load()
    codec = FrameCodec(spec, SIM_NODES)
    sc = load_default_scenario("cdrw", {m.name for m in spec.messages})
    flight.cdrw_record(CdrwDriver(sc, codec))
    short = CdrwDriver(sc.replace(duration=sc.duration / 2), codec)
    got = flight.cdrw_record(short).series
    monkeypatch.setattr(flight, "_model_columns", flight._ModelColumns())
    fresh = flight.cdrw_record(short).series
    assert len(got["rho_true"]) == len(short.samples) < 351
    assert all(pickle.dumps(got[k]) == pickle.dumps(fresh[k]) for k in fresh)
