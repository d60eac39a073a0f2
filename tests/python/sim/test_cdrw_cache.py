"""The cache of the CDRW's open-loop flight (hil.sim.cdrw_cache): a flight from the cache is
the computed one bit for bit (and so are the driver's frames); a corrupt, foreign, linked or
unprivate entry or directory is never trusted."""
from __future__ import annotations

import dataclasses
import os
from pathlib import Path

import numpy as np
import pytest

from hil.bus import FrameCodec, load
from hil.scenario.file import load_default_scenario, parse_fault_spec, with_fault_start
from hil.sim import cdrw_cache
from hil.sim.drivers import CdrwDriver


@pytest.fixture(scope="module")
def scenario():
    """The default flight with its fault, shortened (the spike at 4 s stays in)."""
    return load_default_scenario("cdrw").replace(duration=4.5)


@pytest.fixture(scope="module")
def computed(scenario):
    return cdrw_cache.compute(scenario)


@pytest.fixture
def cache(tmp_path, monkeypatch) -> Path:
    d = tmp_path / "cache"
    monkeypatch.setenv(cdrw_cache.CACHE_ENV, str(d))
    return d


def same(a, b) -> None:
    """Equal value, type and bits (arrays: dtype, shape, bytes; fault events: the scenario's
    own fault object)."""
    assert type(a) is type(b)
    if isinstance(a, np.ndarray):
        assert (a.dtype, a.shape, a.tobytes()) == (b.dtype, b.shape, b.tobytes())
    elif dataclasses.is_dataclass(a):
        for f in dataclasses.fields(a):
            if f.name == "fault":
                assert getattr(a, f.name) is getattr(b, f.name)
            else:
                same(getattr(a, f.name), getattr(b, f.name))
    elif isinstance(a, (list, tuple)):
        assert len(a) == len(b)
        for x, y in zip(a, b):
            same(x, y)
    elif isinstance(a, dict):
        assert list(a) == list(b)
        for k in a:
            same(a[k], b[k])
    else:
        assert a == b or (a != a and b != b)   # NaN: a dropped-out reading


def entries(d: Path) -> list[Path]:
    return sorted(d.glob(f"*{cdrw_cache.SUFFIX}"))


def test_a_cached_flight_is_the_computed_one_bit_for_bit(scenario, computed, cache) -> None:
    n = len(computed)
    same(cdrw_cache.open_loop(scenario, n), computed)      # computed and stored
    assert len(entries(cache)) == 1
    assert (cache.stat().st_mode & 0o777) == 0o700
    same(cdrw_cache.open_loop(scenario, n), computed)      # read back
    assert any(s.events for s in computed)


def test_the_driver_sends_the_same_frames_with_and_without_the_cache(scenario, cache, monkeypatch) -> None:
    def driver():
        d = CdrwDriver(scenario, FrameCodec(load()))
        return d.samples, d._events, d._frames, d._fault_active

    monkeypatch.setenv(cdrw_cache.CACHE_ENV, "off")
    off = driver()
    assert not cache.exists()
    monkeypatch.setenv(cdrw_cache.CACHE_ENV, str(cache))
    miss = driver()
    hit = driver()
    assert len(entries(cache)) == 1
    same(miss, off)
    same(hit, off)


def test_another_scenario_has_its_own_entry(scenario, computed, cache) -> None:
    other = scenario.replace(seed=scenario.seed + 1)
    a = cdrw_cache.open_loop(scenario, len(computed))
    b = cdrw_cache.open_loop(other, len(computed))
    assert len(entries(cache)) == 2
    assert a[10].meas != b[10].meas


def test_flights_that_differ_in_their_faults_share_one_entry(scenario, cache) -> None:
    # a Table 5 campaign: one seed, the fault moved in time (or gone); each flight is the one
    # CdrwSimulation computes with that fault, bit for bit
    flights = [with_fault_start(scenario, t) for t in (0.5, 2.0, 3.1)] + [scenario.replace(faults=())]
    for sc in flights:
        computed = cdrw_cache.compute(sc)
        same(cdrw_cache.open_loop(sc, len(computed)), computed)
    assert len(entries(cache)) == 1


@pytest.mark.parametrize("faults", [
    ("stuck:signal=q,start=1.02,duration=1", "dropout:signal=alpha,start=1.5,duration=0.3,fill=hold"),
    ("dropout:signal=de,start=0,duration=0.5,fill=nan", "stuck:signal=alpha,start=0.3,duration=0.1"),
    ("noise_burst:signal=q,start=2,duration=1,magnitude=0.5,distribution=gaussian",
     "drift:signal=alpha,start=3.9,duration=inf,rate=0.1"),
    ("scale:signal=q,start=4.49,duration=0.5,factor=2", "dropout:signal=q,start=3,duration=0.2,fill=zero"),
], ids=["held", "from-the-start", "random-and-to-the-end", "at-the-end"])
def test_every_sensor_fault_from_the_shared_flight_is_the_computed_one(scenario, cache, faults) -> None:
    """A flight's faulty readings made from the fault-free flight (only the samples around the
    faults computed again) are those CdrwSimulation steps: readings held from before a fault,
    random draws, faults from the first sample or to the last."""
    sc = scenario.replace(faults=tuple(parse_fault_spec(f, "cdrw") for f in faults))
    computed = cdrw_cache.compute(sc)
    same(cdrw_cache.open_loop(sc, len(computed)), computed)
    assert any(s.events for s in computed)


def _stored(scenario, computed, cache) -> Path:
    cdrw_cache.open_loop(scenario, len(computed))
    (entry,) = entries(cache)
    return entry


@pytest.mark.parametrize("damage", ["flipped bit", "truncated", "not json", "empty"])
def test_a_corrupt_entry_is_rebuilt(scenario, computed, cache, damage) -> None:
    entry = _stored(scenario, computed, cache)
    data = entry.read_bytes()
    i = len(data) - 1000                    # a bit of a sample's floats
    bad = {"flipped bit": data[:i] + bytes([data[i] ^ 1]) + data[i + 1:],
           "truncated": data[: len(data) // 2], "not json": b"x\n{", "empty": b""}[damage]
    entry.write_bytes(bad)
    same(cdrw_cache.open_loop(scenario, len(computed)), computed)
    assert entry.read_bytes() == data        # rebuilt


def test_an_entry_of_another_flight_under_this_name_is_not_used(scenario, computed, cache) -> None:
    entry = _stored(scenario, computed, cache)
    other = scenario.replace(seed=scenario.seed + 1)
    # a well-formed entry (its digest matches) of another scenario, renamed to this one's key
    entry.write_bytes(cdrw_cache._encode(cdrw_cache.entry_key(other), cdrw_cache.compute(other)))
    same(cdrw_cache.open_loop(scenario, len(computed)), computed)
    # the right key with the wrong number of samples is refused too
    entry.write_bytes(cdrw_cache._encode(cdrw_cache.entry_key(scenario), computed[:-1]))
    same(cdrw_cache.open_loop(scenario, len(computed)), computed)
    # a well-formed entry whose fault event names a fault the scenario does not have
    doctored = computed[:40] + [dataclasses.replace(computed[40], events=(dataclasses.replace(
        computed[200].events[0], index=7),))] + computed[41:]
    entry.write_bytes(cdrw_cache._encode(cdrw_cache.entry_key(scenario), doctored))
    same(cdrw_cache.open_loop(scenario, len(computed)), computed)


def test_a_linked_entry_is_not_followed(scenario, computed, cache, tmp_path) -> None:
    entry = _stored(scenario, computed, cache)
    elsewhere = tmp_path / "elsewhere.json"
    os.replace(entry, elsewhere)
    entry.symlink_to(elsewhere)
    elsewhere.write_bytes(b"x\n{")   # were it followed, this would be read (and refused)
    same(cdrw_cache.open_loop(scenario, len(computed)), computed)
    assert not entry.is_symlink()    # replaced by a regular entry
    assert elsewhere.read_bytes() == b"x\n{"


def test_a_directory_others_can_write_is_not_used(scenario, computed, cache) -> None:
    cache.mkdir(mode=0o700)
    cache.chmod(0o777)
    same(cdrw_cache.open_loop(scenario, len(computed)), computed)
    assert entries(cache) == []
    assert (cache.stat().st_mode & 0o777) == 0o777   # the user's directory is left as it is


def test_off_computes_and_stores_nothing(scenario, computed, tmp_path, monkeypatch) -> None:
    monkeypatch.setenv(cdrw_cache.CACHE_ENV, "off")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    same(cdrw_cache.open_loop(scenario, len(computed)), computed)
    assert list(tmp_path.iterdir()) == []


def test_the_default_place_is_the_users_cache(monkeypatch, tmp_path) -> None:
    monkeypatch.delenv(cdrw_cache.CACHE_ENV, raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert cdrw_cache.cache_dir() == tmp_path / "hil" / "cdrw"
    monkeypatch.delenv("XDG_CACHE_HOME")
    assert cdrw_cache.cache_dir() == Path.home() / ".cache" / "hil" / "cdrw"
    monkeypatch.setenv("XDG_CACHE_HOME", "relative/dir")       # not absolute: ignored
    assert cdrw_cache.cache_dir() == Path.home() / ".cache" / "hil" / "cdrw"
    monkeypatch.delenv("HOME")                                   # no home: no cache
    monkeypatch.setattr(os.path, "expanduser", lambda p: p)
    assert cdrw_cache.cache_dir() is None


def test_old_entries_go_first(scenario, cache, monkeypatch) -> None:
    monkeypatch.setattr(cdrw_cache, "MAX_ENTRIES", 2)
    short = scenario.replace(duration=0.1)
    for seed in (1, 2, 3):
        cdrw_cache.open_loop(short.replace(seed=seed), 6)
        entry = cache / f"{cdrw_cache.entry_key(short.replace(seed=seed))}{cdrw_cache.SUFFIX}"
        os.utime(entry, (1000 + seed, 1000 + seed))   # apart, whatever the clock's grain
    kept = entries(cache)
    assert len(kept) == 2
    assert cache / f"{cdrw_cache.entry_key(short.replace(seed=1))}{cdrw_cache.SUFFIX}" not in kept


def test_a_faulty_flight_shares_the_clean_samples_where_no_fault_acts(scenario, computed, cache) -> None:
    # a campaign's flights keep one clean flight in memory, not one copy each
    clean = cdrw_cache.open_loop(scenario.replace(faults=()), len(computed))
    faulty = cdrw_cache.open_loop(scenario, len(computed))
    same(faulty, computed)
    shared = [a is b for a, b in zip(faulty, clean)]
    touched = [s.fault_active or bool(s.events) for s in faulty]
    assert shared == [not t for t in touched] and any(touched)


def test_what_the_cache_does_not_promise_an_entry_its_owner_rewrote_is_used(scenario, computed, cache) -> None:
    """The limit the module's docstring and docs/security.md state: the digest is unkeyed, so
    an entry rewritten by someone who writes as the user, digest and all, is the flight the run
    gets.  (Were it ever keyed, this test and those two texts change together.)"""
    entry = _stored(scenario, computed, cache)
    clean = cdrw_cache.compute(cdrw_cache.fault_free(scenario))      # what an entry holds
    doctored = [dataclasses.replace(s, alpha=s.alpha + 1.0) for s in clean]
    entry.write_bytes(cdrw_cache._encode(cdrw_cache.entry_key(scenario), doctored))
    got = cdrw_cache.open_loop(scenario, len(computed))
    assert [s.alpha for s in got] == [s.alpha + 1.0 for s in computed]
