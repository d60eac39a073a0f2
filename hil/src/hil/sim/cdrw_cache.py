"""The CDRW's open-loop flight, cached per user: `hil run cdrw` computes the whole flight
(351 samples of RK4 and local linearisations in pure Python, ~0.2 s in the UML guest) before
fcc starts, and the flight depends on nothing but the scenario and this code.

    open_loop(scenario) -> [CdrwSample, ...]   from the cache, else computed (and stored)

Where: $HIL_CACHE if it names a directory, else $XDG_CACHE_HOME/hil/cdrw, else
~/.cache/hil/cdrw; HIL_CACHE=off computes every flight.  The directory is made owner-only
and used only while it is one (a real directory, the user's, no access for group or others).

An entry is the flight as JSON (floats by repr: they read back to the same bits), named by
the SHA-256 of the scenario (its repr: every field), of the source of the modules that
compute it and of the numpy and Python versions (their random streams and libm).  Its first
line is the SHA-256 of the rest.  An entry is used only when it is the user's own regular
file, its digest and key match, and every sample reads back with the expected shape;
anything else (a corrupt, truncated, foreign or older entry) is ignored and rebuilt.  Writes
are atomic (hil.io.rundir), so a concurrent run reads the old entry or the new one.
"""
from __future__ import annotations

import hashlib
import json
import os
import stat
import sys
from pathlib import Path
from typing import Any

import numpy as np

from hil.io.rundir import atomic_write
from hil.scenario import cdrw_params, faults, plant_options, sensor_options
from hil.scenario.file import Scenario
from hil.sim import cdrw, cdrw_flight, sensor_faults, sensors
from hil.sim.cdrw import CdrwLinearisation
from hil.sim.cdrw_flight import CdrwSample, CdrwSimulation
from hil.sim.sensor_faults import FaultEvent

CACHE_ENV = "HIL_CACHE"
#: an entry is one flight (~0.4 MB); larger is not one of ours
ENTRY_MAX_BYTES = 16 << 20
#: entries kept (the oldest go first): a campaign of new seeds does not fill the disk
MAX_ENTRIES = 64
#: the modules whose code decides the flight (and this one: the entry's format)
_CODE = (cdrw, cdrw_flight, sensors, sensor_faults, cdrw_params, plant_options, sensor_options,
         faults, sys.modules[__name__])
_LIN = ("A_c", "B_c", "A", "B", "A_euler", "B_euler", "A_static", "J3", "c")
_SHAPES = {"J3": (3, 3), "B_c": (2,), "B": (2,), "B_euler": (2,), "c": (2,)}


def cache_dir() -> Path | None:
    """The cache directory (None: caching is off)."""
    env = os.environ.get(CACHE_ENV, "")
    if env.lower() in ("off", "0", "no"):
        return None
    if env:
        return Path(env)
    xdg = os.environ.get("XDG_CACHE_HOME", "")
    base = Path(xdg) if xdg else Path.home() / ".cache"
    return base / "hil" / "cdrw"


def _usable_dir(d: Path) -> bool:
    """Make the directory (owner-only); usable only while it is the user's own and private."""
    try:
        d.mkdir(mode=0o700, parents=True, exist_ok=True)
        st = d.lstat()
    except OSError:
        return False
    return stat.S_ISDIR(st.st_mode) and st.st_uid == os.getuid() and not st.st_mode & 0o077


def entry_key(scenario: Scenario) -> str:
    h = hashlib.sha256()
    for mod in _CODE:
        h.update(Path(mod.__file__ or "").read_bytes())
    h.update(f"{np.__version__}\0{sys.version}\0{scenario!r}".encode())
    return h.hexdigest()


def _encode(key: str, samples: list[CdrwSample]) -> bytes:
    rows = [[s.k, s.t, s.alpha, s.q, s.X, s.de, s.meas, s.meas_faultfree, s.fault_active,
             [[e.t, e.action, e.index] for e in s.events],
             [getattr(s.lin, name).tolist() for name in _LIN], s.lin.dt] for s in samples]
    body = json.dumps({"key": key, "samples": rows}, separators=(",", ":")).encode()
    return hashlib.sha256(body).hexdigest().encode() + b"\n" + body


def _floats(d: Any) -> dict[str, float]:
    if not isinstance(d, dict):
        raise ValueError("not a reading")
    return {str(k): float(v) for k, v in d.items()}


def _array(name: str, value: Any) -> np.ndarray:
    a = np.array(value, dtype=float)
    if a.shape != _SHAPES.get(name, (2, 2)):
        raise ValueError(f"{name}: shape {a.shape}")
    return a


def _decode(data: bytes, key: str, scenario: Scenario, n: int) -> list[CdrwSample]:
    digest, _, body = data.partition(b"\n")
    if digest != hashlib.sha256(body).hexdigest().encode():
        raise ValueError("digest")
    doc = json.loads(body)
    if doc["key"] != key or len(doc["samples"]) != n:
        raise ValueError("another flight")
    fs = scenario.sensor_faults
    out = []
    for k, (k_, t, alpha, q, x, de, meas, ff, active, events, lin, dt) in enumerate(doc["samples"]):
        if k_ != k or not isinstance(active, bool):
            raise ValueError("sample")
        evs = tuple(FaultEvent(float(et), str(act), int(i), fs[int(i)]) for et, act, i in events)
        arrays = {name: _array(name, v) for name, v in zip(_LIN, lin, strict=True)}
        out.append(CdrwSample(k=k, t=float(t), alpha=float(alpha), q=float(q), X=float(x),
                              de=float(de), meas=_floats(meas), meas_faultfree=_floats(ff),
                              fault_active=active, events=evs,
                              lin=CdrwLinearisation(**arrays, dt=float(dt))))
    return out


def _read(path: Path) -> bytes | None:
    """The entry's bytes if it is the user's own regular file of a sane size (else None)."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW)
    except OSError:
        return None
    with os.fdopen(fd, "rb") as fh:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode) or st.st_uid != os.getuid() or st.st_size > ENTRY_MAX_BYTES:
            return None
        return fh.read(ENTRY_MAX_BYTES + 1)


def _prune(d: Path) -> None:
    """Keep the newest MAX_ENTRIES entries."""
    try:
        entries = sorted((p.stat().st_mtime, p) for p in d.glob("*.json"))
        for _, p in entries[:-MAX_ENTRIES]:
            p.unlink()
    except OSError:
        pass


def compute(scenario: Scenario) -> list[CdrwSample]:
    """Every sample of the scenario's open-loop flight, computed."""
    sim = CdrwSimulation(scenario)
    return [sim.step() for _ in range(sim.n_samples)]


def open_loop(scenario: Scenario, n_samples: int) -> list[CdrwSample]:
    """Every sample of the scenario's open-loop flight (n_samples of them), from the cache
    when it holds a valid entry, else computed and stored."""
    d = cache_dir()
    if d is None or not _usable_dir(d):
        return compute(scenario)
    key = entry_key(scenario)
    path = d / f"{key}.json"
    data = _read(path)
    if data is not None:
        try:
            return _decode(data, key, scenario, n_samples)
        except (ValueError, TypeError, KeyError, IndexError):
            pass   # not a valid entry: rebuilt below
    samples = compute(scenario)
    try:
        atomic_write(path, _encode(key, samples))
        _prune(d)
    except OSError:
        pass       # a full or read-only disk: the flight is computed next time too
    return samples
