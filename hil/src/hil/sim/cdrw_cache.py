"""The CDRW's open-loop flight, cached per user: `hil run cdrw` computes the whole flight
(351 samples of RK4 and local linearisations in pure Python, ~0.2 s in the UML guest) before
fcc starts, and the flight depends on nothing but the scenario and this code.

    open_loop(scenario, n) -> [CdrwSample] * n   from the cache, else computed (and stored)

Where: $FCC_HIL_CACHE if it names a directory, else $XDG_CACHE_HOME/hil/cdrw, else
~/.cache/hil/cdrw; FCC_HIL_CACHE=off computes every flight.  The directory is made owner-only
and used only while it is one (a real directory, the user's, no access for group or others).

What is stored is the fault-free flight (fault_free(scenario)): the faults change only the
readings (their random stream is their own, the flight open loop), applied on top per flight,
so the N flights of a campaign that differ in their fault's start share one entry; the last
entry used is kept in memory (a campaign's flights in one process skip even the decoding;
the entry's bytes are still read and compared, so a changed entry is never trusted).

An entry is named by the SHA-256 of the fault-free scenario (its repr: every field), of the
source of the modules that compute the flight and of the numpy and Python versions (their random
streams and libm).  Its first line is the SHA-256 of the rest, its second a JSON line (the
key again, the sample count, the readings' names, the fault events), then one row of
little-endian float64 per sample: the same bits read back, no float is printed or parsed.
An entry is used only when it is the user's own regular file (not a link), its digest, key,
count and size match; anything else (a corrupt, truncated, foreign or older entry) is
ignored and rebuilt.  Writes rename a complete file into place, so a concurrent run reads
the old entry or the new one.

What the cache promises: the flight it gives is the one the code would compute, against
accident -- a torn or truncated write, a corrupt disk, an entry of another scenario, another
version of this code, numpy or Python, another user's file, a link -- each of which is
rebuilt.  It promises nothing against someone who can write as the user: the digest is
unkeyed, so an entry rewritten with a matching digest is used without a word.  Such a person
can as well rewrite hil's own source, the key file or fcc; the cache is as trusted as the
user's home directory.  A keyed digest would not change that: its key would have to be kept
where the user's processes read it, so whoever can rewrite an entry can read the key and
digest the new entry with it (a key elsewhere -- a keyring, a token -- is more than a cache of
a computation is worth).  FCC_HIL_CACHE=off computes every flight (docs/security.md).
"""
from __future__ import annotations

import functools
import json
import math
import os
import stat
import sys
from pathlib import Path

import numpy as np
from cryptography.hazmat.primitives import hashes

from hil.io.paths import user_cache
from hil.io.rundir import unique_tag
from hil.scenario import cdrw_params, faults, plant_options, sensor_options
from hil.scenario.file import Scenario
from hil.sim import cdrw, cdrw_flight, sensor_faults, sensors
from hil.sim.cdrw import CdrwLinearisation
from hil.sim.cdrw_flight import CdrwSample, CdrwSimulation, fault_free, with_sensor_faults
from hil.sim.sensor_faults import FaultEvent

CACHE_ENV = "FCC_HIL_CACHE"
#: an entry's file: <key>.flight
SUFFIX = ".flight"
#: an entry is one flight (0.13 MB for the default one); larger is not one of ours
ENTRY_MAX_BYTES = 16 << 20
#: entries kept (the oldest go first): a campaign of new seeds does not fill the disk
MAX_ENTRIES = 64
#: the modules whose code decides the flight (and this one: the entry's format)
_CODE = (cdrw, cdrw_flight, sensors, sensor_faults, cdrw_params, plant_options, sensor_options,
         faults, sys.modules[__name__])
_LIN = ("A_c", "B_c", "A", "B", "A_euler", "B_euler", "A_static", "J3", "c")
_SHAPES = {"J3": (3, 3), "B_c": (2,), "B": (2,), "B_euler": (2,), "c": (2,)}
_SIZES = tuple(math.prod(_SHAPES.get(name, (2, 2))) for name in _LIN)


def cache_dir() -> Path | None:
    """The cache directory (None: caching is off, or there is no home directory)."""
    env = os.environ.get(CACHE_ENV, "")
    if env.lower() in ("off", "0", "no"):
        return None
    if env:
        return Path(env)
    base = user_cache()
    return None if base is None else base / "cdrw"


def _usable_dir(d: Path) -> bool:
    """Make the directory (owner-only); usable only while it is the user's own and private."""
    try:
        d.mkdir(mode=0o700, parents=True, exist_ok=True)
        st = d.lstat()
    except OSError:
        return False
    return stat.S_ISDIR(st.st_mode) and st.st_uid == os.getuid() and not st.st_mode & 0o077


def _sha256_hex(data: bytes) -> str:
    h = hashes.Hash(hashes.SHA256())
    h.update(data)
    return h.finalize().hex()


@functools.lru_cache(maxsize=1)
def _code_hash() -> hashes.Hash:
    """The digest's state after the source of the modules that compute the flight: read once
    per process, as the code that runs is the code imported (a campaign's flights would read
    and hash ten files each, system calls that cost in the rig's guest).  SHA-256 from
    cryptography, which the bus's authentication has loaded already (hashlib would load the
    system's OpenSSL besides it: 13 ms in the guest)."""
    h = hashes.Hash(hashes.SHA256())
    for mod in _CODE:
        h.update(Path(mod.__file__ or "").read_bytes())
    return h


def entry_key(scenario: Scenario) -> str:
    """The entry's name: what decides the fault-free flight (OSError: a module's source is
    unreadable)."""
    h = _code_hash().copy()
    h.update(f"{np.__version__}\0{sys.version}\0{fault_free(scenario)!r}".encode())
    return h.finalize().hex()


def _encode(key: str, samples: list[CdrwSample]) -> bytes | None:
    """The entry: its digest line, a JSON line (key, reading names, fault events), then one
    row of float64 per sample, bit for bit (None: readings that change names, not stored)."""
    names = list(samples[0].meas) if samples else []
    if any(list(s.meas) != names or list(s.meas_faultfree) != names for s in samples):
        return None
    rows = [[s.t, s.alpha, s.q, s.X, s.de, *s.meas.values(), *s.meas_faultfree.values(),
             float(s.fault_active), s.lin.dt,
             *(v for name in _LIN for v in getattr(s.lin, name).ravel().tolist())] for s in samples]
    events = [[s.k, e.t, e.action, e.index] for s in samples for e in s.events]
    head = json.dumps({"key": key, "n": len(samples), "readings": names, "events": events})
    body = head.encode() + b"\n" + np.array(rows, dtype="<f8").tobytes()
    return _sha256_hex(body).encode() + b"\n" + body


def _decode(data: bytes, key: str, scenario: Scenario, n: int) -> list[CdrwSample]:
    digest, _, body = data.partition(b"\n")
    if digest != _sha256_hex(body).encode():
        raise ValueError("digest")
    head_line, _, block = body.partition(b"\n")
    head = json.loads(head_line)
    names = [str(x) for x in head["readings"]]
    width = 7 + 2 * len(names) + sum(_SIZES)
    if head["key"] != key or head["n"] != n or len(block) != n * width * 8:
        raise ValueError("another flight")
    table = np.frombuffer(block, dtype="<f8").reshape(n, width)
    fs = scenario.sensor_faults
    events: dict[int, list[FaultEvent]] = {}
    for k, t, action, i in head["events"]:
        if action not in ("start", "end") or type(k) is not int or type(i) is not int \
                or not (0 <= k < n and 0 <= i < len(fs)):
            raise ValueError("event")
        events.setdefault(k, []).append(FaultEvent(float(t), action, i, fs[i]))
    m = len(names)
    # readings the same bits as the fault-free ones are one dict, as the flight made them
    # (hil.sim.cdrw_flight._with_faults keeps such a sample where no fault acts)
    bits = table.view("<u8")
    same = (bits[:, 5:5 + m] == bits[:, 5 + m:5 + 2 * m]).all(axis=1).tolist()
    out = []
    for k, row in enumerate(table.tolist()):
        ff = dict(zip(names, row[5 + m:5 + 2 * m]))
        meas = ff if same[k] else dict(zip(names, row[5:5 + m]))
        lin, at = {}, 7 + 2 * m
        for name, size in zip(_LIN, _SIZES):
            lin[name] = np.array(row[at:at + size]).reshape(_SHAPES.get(name, (2, 2)))
            at += size
        out.append(CdrwSample(k=k, t=row[0], alpha=row[1], q=row[2], X=row[3], de=row[4],
                              meas=meas, meas_faultfree=ff,
                              fault_active=row[5 + 2 * m] != 0.0,
                              events=tuple(events.get(k, ())),
                              lin=CdrwLinearisation(**lin, dt=row[6 + 2 * m])))
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
        entries = sorted((p.stat().st_mtime, p) for p in d.glob(f"*{SUFFIX}"))
        for _, p in entries[:-MAX_ENTRIES]:
            p.unlink()
    except OSError:
        pass


def compute(scenario: Scenario) -> list[CdrwSample]:
    """Every sample of the scenario's open-loop flight, computed."""
    sim = CdrwSimulation(scenario)
    return [sim.step() for _ in range(sim.n_samples)]


def open_loop(scenario: Scenario, n_samples: int) -> list[CdrwSample]:
    """Every sample of the scenario's open-loop flight (n_samples of them): its fault-free
    flight (cached) with the scenario's sensor faults applied."""
    return with_sensor_faults(scenario, _clean_flight(fault_free(scenario), n_samples))


#: the last entry used in this process, its bytes -> its samples (one slot: a campaign's flights
#: share one entry; a changed file is a different key, so it is decoded and checked again)
_decoded: dict[bytes, list[CdrwSample]] = {}


def _remember(data: bytes, samples: list[CdrwSample]) -> None:
    _decoded.clear()
    _decoded[data] = samples


def _clean_flight(scenario: Scenario, n_samples: int) -> list[CdrwSample]:
    """The fault-free flight, from the cache when it holds a valid entry (decoded once while
    the entry's bytes stay the same), else computed and stored."""
    d = cache_dir()
    if d is None or not _usable_dir(d):
        return compute(scenario)
    try:
        key = entry_key(scenario)
    except OSError:   # the code is not in files (a frozen interpreter): nothing to key on
        return compute(scenario)
    path = d / f"{key}{SUFFIX}"
    data = _read(path)
    if data is not None and data in _decoded:
        return _decoded[data]
    if data is not None:
        try:
            samples = _decode(data, key, scenario, n_samples)
            _remember(data, samples)
            return samples
        except (ValueError, TypeError, KeyError, IndexError):
            pass   # not a valid entry: rebuilt below
    samples = compute(scenario)
    entry = _encode(key, samples)
    if entry is not None:
        _store(path, entry)
        _prune(d)
        _remember(entry, samples)
    return samples


def _store(path: Path, entry: bytes) -> None:
    """Write the entry beside its place, then rename it there (a reader sees the old entry or
    the new one).  Not synced: an entry a crash tears fails its digest and is rebuilt."""
    tmp = path.with_name(f".{path.name}.{unique_tag()}")
    try:
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o600)
        with os.fdopen(fd, "wb") as fh:
            fh.write(entry)
        os.replace(tmp, path)
    except OSError:
        tmp.unlink(missing_ok=True)   # a full or read-only disk: computed next time too
