"""The wire-time bus in simulated time: firmware/tools/canbus's model (libcanbus_sim.so, the same
C core as the realtime `canbus` process) driven by the lockstep rig through ctypes.

"One model, two time bases" (issue 35): in realtime canbus moves the frames in wall time; in
lockstep the frames still travel on vcan as they always did (the protocol is unchanged), and
this model says when each would have ended on a real bus.  The nodes are those of
hil.rig.wirebus (the simulator's priority-ordered mailboxes, fcc's FIFO), plus a background
node per `bus_load` fault (firmware/tools/canbus/canbus_load.h) and the wire faults as canbus's
options (hil.rig.wirefaults: error frames, bus-off, babbling nodes, built by the realtime
process's own code; their fault confinement in the statistics, no SocketCAN error frame to fcc:
its frames travel on vcan).  Times are whole nanoseconds
of simulated time, so the same calls give the same times (deterministic).

    bus = SimBus(250_000, loads)
    bus.queue("sim", raws, t)          # the frames a node queued at t (s)
    for e in bus.run(t_until): ...     # each frame that ended by then: e.node, e.frame_id, e.t_eof
    done, ends = bus.steps(steps, raws, report=True)   # lockstep exchanges, one call for many
    stats = bus.stats()                # canbus's statistics line (hil.results.busstats)
"""
from __future__ import annotations

import ctypes
import json
import struct
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from typing import TYPE_CHECKING, NamedTuple

from hil.io.paths import tool
from hil.rig.errors import RigError
from hil.rig.wirebus import NODES
from hil.rig.wirefaults import SEED_STRIDE
from hil.scenario.faults import BusLoad
from hil.scenario.file import Scenario
from hil.util.errors import InputError

if TYPE_CHECKING:
    from hil.sim.drivers import AppDriver

#: the shared library (firmware/tools/canbus/canbus_sim.h), beside the tools in build/bin
LIBRARY = "libcanbus_sim.so"
NS = 1_000_000_000
#: background nodes a flight may have (canbus_sim.h CANBUS_SIM_LOADS_MAX)
LOADS_MAX = 4
#: frames returned by one call of canbus_sim_run (more: call again)
_BATCH = 128
#: a node's controller queue (canbus_core.h CANBUS_QUEUE_LEN): frames of fcc that may still
#: end from before an exchange, the one on the bus besides
QUEUE_LEN = 64
_EFF = 0x80000000
_POLICY = {"prio": 0, "fifo": 1}


class _Frame(ctypes.Structure):
    _fields_ = [("id", ctypes.c_uint32), ("ext", ctypes.c_bool), ("rtr", ctypes.c_bool),
                ("dlc", ctypes.c_uint8), ("data", ctypes.c_uint8 * 8)]


class _Done(ctypes.Structure):
    _fields_ = [("frame", _Frame), ("node", ctypes.c_uint32), ("bits", ctypes.c_uint32),
                ("t_queued", ctypes.c_uint64), ("t_sof", ctypes.c_uint64), ("t_eof", ctypes.c_uint64)]


class _Step(ctypes.Structure):
    """canbus_sim_step_t: one lockstep exchange (canbus_sim.h canbus_sim_steps)."""

    _fields_ = [("t", ctypes.c_uint64), ("horizon", ctypes.c_uint64), ("inputs_at", ctypes.c_uint32),
                ("inputs", ctypes.c_uint32), ("answer_at", ctypes.c_uint32), ("answer", ctypes.c_uint32),
                ("t_in", ctypes.c_uint64), ("queued", ctypes.c_uint32), ("answered", ctypes.c_uint32)]


class Step(NamedTuple):
    """An exchange for SimBus.steps, times in ns: the bus runs to t, the simulator's frames
    raws[inputs_at:inputs_at + inputs] are queued then (its events after the others, not
    waited for), and when they have ended (t_in; at most at the horizon) fcc's answer
    raws[answer_at:answer_at + answer]."""

    t: int
    horizon: int
    inputs_at: int
    inputs: int
    answer_at: int
    answer: int


class Done(NamedTuple):
    """What the model made of a Step: t_in (ns), the simulator's inputs queued (its events not
    counted), the answer's frames queued."""

    t_in: int
    queued: int
    answered: int


class _LoadCfg(ctypes.Structure):
    _fields_ = [("id_lo", ctypes.c_uint32), ("id_hi", ctypes.c_uint32), ("ppm", ctypes.c_uint32),
                ("start_ns", ctypes.c_uint64), ("end_ns", ctypes.c_uint64), ("seed", ctypes.c_uint64)]


@dataclass(frozen=True)
class Load:
    """A background node: `utilisation` of the bus (worst-case frame times) by periodic 8-byte
    frames on identifiers spread over [id_lo, id_hi], released in [start, end) s."""

    utilisation: float
    id_lo: int
    id_hi: int
    start: float
    end: float
    seed: int


class Ended(NamedTuple):
    """A frame of the rig's nodes that ended on the bus."""

    node: str
    frame_id: int
    t_queued: float
    t_eof: float


#: canbus_done_t as bytes: frame (id, ext, rtr, dlc, data, padding), node, bits, t_queued,
#: t_sof, t_eof (read with struct: one call a batch, not ctypes field by field); _ENDED the
#: fields the rig uses, id, ext, node, t_queued, t_eof
_DONE = struct.Struct("<I??B8sxIIQQQ")
_ENDED = struct.Struct("<I?11xI4xQ8xQ")
#: canbus_sim_step_t as bytes; _EOF: canbus_done_t's t_queued and t_eof
_STEP = struct.Struct("<QQIIIIQII")
#: sizeof (struct can_frame) (canbus_sim.h CANBUS_SIM_RAW_LEN)
_RAW = 16
_EOF = struct.Struct("<24xQ8xQ")


def _library() -> ctypes.CDLL:
    lib = ctypes.PyDLL(str(tool(LIBRARY)))   # short calls: the GIL kept, not released and taken back
    lib.canbus_sim_size.restype = ctypes.c_size_t
    lib.canbus_sim_setup.argtypes = [ctypes.c_void_p, ctypes.c_uint32, ctypes.c_uint32,
                                     ctypes.POINTER(ctypes.c_int), ctypes.POINTER(ctypes.c_char_p),
                                     ctypes.POINTER(_LoadCfg), ctypes.c_uint32,
                                     ctypes.POINTER(ctypes.c_char_p), ctypes.c_uint32, ctypes.c_char_p,
                                     ctypes.c_size_t]
    lib.canbus_sim_queue_raw.argtypes = [ctypes.c_void_p, ctypes.c_uint32, ctypes.c_char_p,
                                         ctypes.c_uint32, ctypes.c_uint64]
    lib.canbus_sim_queue_raw.restype = ctypes.c_uint32
    lib.canbus_sim_worst.argtypes = [ctypes.c_void_p, ctypes.POINTER(ctypes.c_uint32), ctypes.c_uint32]
    lib.canbus_sim_run.argtypes = [ctypes.c_void_p, ctypes.c_uint64, ctypes.POINTER(_Done), ctypes.c_uint32,
                                   ctypes.c_uint32, ctypes.c_uint64, ctypes.c_uint32,
                                   ctypes.POINTER(ctypes.c_uint32)]
    lib.canbus_sim_run.restype = ctypes.c_uint32
    lib.canbus_sim_roles.argtypes = [ctypes.c_void_p, ctypes.c_uint32, ctypes.c_uint32, ctypes.c_uint32,
                                     ctypes.c_uint64]
    lib.canbus_sim_steps.argtypes = [ctypes.c_void_p, ctypes.POINTER(_Step), ctypes.c_uint32, ctypes.c_char_p,
                                     ctypes.c_uint32, ctypes.POINTER(_Done), ctypes.c_uint32,
                                     ctypes.POINTER(ctypes.c_uint32)]
    lib.canbus_sim_pending.argtypes = [ctypes.c_void_p, ctypes.c_uint32]
    lib.canbus_sim_pending.restype = ctypes.c_uint32
    lib.canbus_sim_json.argtypes = [ctypes.c_void_p, ctypes.c_char_p]
    return lib


def ns(t: float) -> int:
    """Seconds of simulated time as the model's whole nanoseconds."""
    return round(t * NS)


class SimBus:
    """One flight's bus model (see the module docstring)."""

    def __init__(self, bitrate: int, loads: Sequence[Load] = (), worst: Sequence[int] = (),
                 faults: Sequence[str] = ()) -> None:
        """worst: the 11-bit identifiers whose frames take their worst-case length (SPEC §8),
        not their actual bits' (bits the run does not determine, e.g. a random key's MAC);
        faults: canbus's fault options (hil.rig.wirefaults.canbus_args, nodes named as in
        NODES), their times from 0."""
        self.bitrate = bitrate
        self._lib = _library()
        self._sim = ctypes.create_string_buffer(self._lib.canbus_sim_size())
        self.names = tuple(NODES)
        self._index = {name: i for i, name in enumerate(self.names)}
        self._names_c = (ctypes.c_char_p * len(self.names))(*(n.encode() for n in self.names))
        policy = (ctypes.c_int * len(self.names))(*(_POLICY[NODES[n]] for n in self.names))
        cfgs = (_LoadCfg * len(loads))(*(
            _LoadCfg(load.id_lo, load.id_hi, max(1, round(load.utilisation * 1e6)), ns(load.start),
                     ns(load.end) if load.end != float("inf") else 2**63, load.seed & 0xFFFFFFFFFFFFFFFF)
            for load in loads))
        opts = (ctypes.c_char_p * len(faults))(*(a.encode() for a in faults))
        err = ctypes.create_string_buffer(256)
        st = self._lib.canbus_sim_setup(self._sim, bitrate, len(self.names), policy, self._names_c, cfgs,
                                        len(loads), opts, len(faults) // 2, err, len(err))
        if st != 0:
            why = err.value.decode(errors="replace") or (
                f"status {st}: 1e9 must be a whole multiple of the bit rate, at most {LOADS_MAX} loads")
            raise RigError(f"--bus wire: the bus model refused {bitrate} bit/s with {len(loads)} background "
                           f"load(s) and faults {' '.join(faults) or 'none'}: {why}")
        ids = (ctypes.c_uint32 * len(worst))(*worst)
        if self._lib.canbus_sim_worst(self._sim, ids, len(worst)) != 0:
            raise RigError(f"--bus wire: {len(worst)} identifiers at their worst-case length: too many")
        self._out = (_Done * _BATCH)()
        self._reported = ctypes.c_uint32(0)

    def roles(self, sim: str, fcc: str, last_id: int, compute: float) -> None:
        """The nodes of steps(): the simulator's (its frames of 11-bit identifier last_id go
        after its others, not waited for) and fcc's, which answers compute s after its inputs."""
        if self._lib.canbus_sim_roles(self._sim, self._index[sim], self._index[fcc], last_id, ns(compute)) != 0:
            raise RigError(f"--bus wire: the bus model has no node {sim!r} or {fcc!r}")

    def queue(self, node: str, raws: Sequence[bytes], t: float) -> int:
        """SocketCAN frames (struct can_frames, back to back in any grouping) a node queues at
        t s; how many fit its queue (the others are lost: the statistics count them)."""
        blob = b"".join(raws)
        if not blob:
            return 0
        return int(self._lib.canbus_sim_queue_raw(self._sim, self._index[node], blob, len(blob) // _RAW, ns(t)))

    def steps(self, steps: Sequence[Step], raws: Sequence[bytes],
              report: bool) -> tuple[list[Done], list[tuple[int, int]]]:
        """Lockstep exchanges in one call (roles() first), their frames in raws (struct
        can_frames, back to back in any grouping): what the model made of each, and, when
        report, the frames of fcc that ended meanwhile, (t_queued, t_eof) in ns, in order."""
        buf = bytearray(b"".join([_STEP.pack(*s, 0, 0, 0) for s in steps]))
        blob = b"".join(raws)
        # every frame of fcc that can end: those queued before (QUEUE_LEN and the one on the
        # bus at most) and the answers
        cap = (QUEUE_LEN + 1 + sum(s.answer for s in steps)) if report else 0
        out = (self._out if cap <= _BATCH else (_Done * cap)()) if report else None
        st = self._lib.canbus_sim_steps(self._sim, (_Step * len(steps)).from_buffer(buf), len(steps), blob,
                                        len(blob) // _RAW, out, cap, ctypes.byref(self._reported))
        if st != 0:
            raise RigError(f"--bus wire: the bus model refused {len(steps)} lockstep exchange(s) (status {st})")
        done = [Done(*d[6:]) for d in _STEP.iter_unpack(buf)]
        if out is None:
            return done, []
        return done, list(_EOF.iter_unpack(ctypes.string_at(out, self._reported.value * _EOF.size)))

    def run(self, t: float, node: str = "", tq: float = 0.0, count: int = 0) -> list[Ended]:
        """The bus up to t s: the rig's frames that ended by then, in order.  With count > 0,
        up to the end of the count-th frame of node queued at tq s, if that comes first."""
        out, lib, sim, until, names = self._out, self._lib, self._sim, ns(t), self.names
        seen = ctypes.c_uint32(0)
        index, at = self._index.get(node, 0), ns(tq)
        ended: list[Ended] = []
        while True:
            n = lib.canbus_sim_run(sim, until, out, _BATCH, index, at, count, ctypes.byref(seen))
            raw = ctypes.string_at(out, n * _ENDED.size)
            ended += [Ended(names[node], fid | (_EFF if ext else 0), tq / NS, te / NS)
                      for fid, ext, node, tq, te in _ENDED.iter_unpack(raw)]
            if n < _BATCH or (count and seen.value >= count):
                return ended

    def pending(self, node: str) -> int:
        """Frames of node waiting or on the bus."""
        return int(self._lib.canbus_sim_pending(self._sim, self._index[node]))

    def stats(self) -> dict:
        """canbus's statistics line (firmware/tools/canbus/canbus_stats.h: the load's streams
        "load_streams": [{"id", "period_ns"}] and the load frames its full queue dropped,
        "load_dropped", among them)."""
        with tempfile.TemporaryDirectory(prefix="hil-simbus-") as tmp:
            path = Path(tmp) / "stats.json"
            if self._lib.canbus_sim_json(self._sim, str(path).encode()) != 0:
                raise RigError(f"--bus wire: the bus model could not write its statistics to {path}")
            stats = json.loads(path.read_text())
        stats["time_base"] = "simulated"
        return stats


def check_bus_load(scenarios: Sequence[Scenario], mode: str, bus: str) -> None:
    """A bus_load fault needs the wire-time bus (the model in simulated time, or the realtime
    canbus process's --load): InputError (exit 2) otherwise (the ideal bus has no time to
    fill); two of them active at once may not share identifiers; at most LOADS_MAX of them."""
    seen: list[BusLoad] = []
    for sc in scenarios:
        for f in sc.faults:
            if not isinstance(f, BusLoad):
                continue
            if bus != "wire":
                raise InputError(f"fault {f.describe()!r}: background load needs the wire-time bus "
                                 f"(--bus wire; this run's: {bus}, --mode {mode})")
            for g in seen:  # two nodes sending one identifier at once: an error on a real bus
                if f.id_lo <= g.id_hi and g.id_lo <= f.id_hi and f.start < g.end and g.start < f.end:
                    raise InputError(f"faults {g.describe()!r} and {f.describe()!r}: two background "
                                     f"nodes with identifiers in common at the same time")
            seen.append(f)
    if len(seen) > LOADS_MAX:
        raise InputError(f"{len(seen)} bus_load faults in one flight: the bus model takes at most {LOADS_MAX}")


def loads(drivers: Sequence[AppDriver]) -> list[Load]:
    """The flight's background nodes: each bus_load fault, over its window within the flight,
    its frames from the scenario's seed and the fault's place in the list."""
    return [Load(f.utilisation, f.id_lo, f.id_hi, f.start, min(f.end, d.n_steps * d.period),
                 d.scenario.seed * SEED_STRIDE + i)
            for d in drivers for i, f in enumerate(d.scenario.faults) if isinstance(f, BusLoad)]
