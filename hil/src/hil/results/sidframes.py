"""fcc's identification outputs of a flight as arrays (hil.results.buslog reads the frames):
each signal decoded over all of a step's frames at once, a step's two different frames refused.
"""
from __future__ import annotations

import functools

import numpy as np

from hil.bus.dbc import BusSpec, SignalSpec
from hil.results.buslog import FlightFrames
from hil.rig.errors import RigError
from hil.sim.drivers import FILTERS, SID_PARTS, SID_PREFIX


class DuplicateOutput(RigError):
    """Two different frames of fcc's for one lockstep step (exit 1): fcc sends a step's outputs
    once, so one of them is not fcc's, and the step has no single value to report."""


def _column(sig: SignalSpec, bits: np.ndarray) -> np.ndarray:
    """A signal's physical values from frames read as little-endian 64-bit integers: what
    float(sig.scaled(sig.unpack(bits))) gives frame by frame, the same float operations (a
    signal of at most 32 bits, as every identification signal: exact in int64 and float64)."""
    if sig.length > 32:
        raise ValueError(f"{sig.name}: a {sig.length}-bit signal is not decoded here")
    raw = ((bits >> np.uint64(sig.start)) & np.uint64((1 << sig.length) - 1)).astype(np.int64)
    if sig.signed:
        raw = np.where(raw >> (sig.length - 1) != 0, raw - (1 << sig.length), raw)
    return raw.astype(float) if sig.is_integer else raw * sig.scale + sig.offset


@functools.lru_cache(maxsize=4)
def _sid_layout(spec: BusSpec) -> tuple[tuple[str, ...],
                                        tuple[tuple[int, SignalSpec | None, tuple[tuple[SignalSpec, str], ...]], ...]]:
    """The identification outputs' array names ('<filter>_<signal>', in order) and, per frame
    id, its step signal (None: it has none) and its other signals with their arrays' names."""
    names: list[str] = []
    ids = []
    for flt in FILTERS:
        for part in SID_PARTS:
            msg = spec.by_name(f"{SID_PREFIX[flt]}_{part}")
            step = next((sig for sig in msg.signals if sig.name == "step"), None)
            names += [f"{flt}_{sig.name}" for sig in msg.signals if sig is not step or part != "STATE"]
            others = tuple((sig, f"{flt}_{sig.name}") for sig in msg.signals if sig is not step)
            ids.append((msg.frame_id, step, others))
    return tuple(names), tuple(ids)


def sid_arrays(spec: BusSpec, flight: FlightFrames, n_steps: int,
               check_step: bool = True) -> dict[str, np.ndarray]:
    """The identification outputs of steps 0..n-1 as arrays named '<filter>_<signal>'
    (NaN where a frame is missing or, lockstep, its step field does not match the tick).
    Lockstep (check_step): a second, different frame for a step is refused (DuplicateOutput);
    an exact copy is the same frame.  Realtime: fcc counts its own steps on its own clock and
    the step is the newest sample's, so two of fcc's authenticated steps may land on one
    sample: the field is not compared and the later frame is the step's."""
    names, layout = _sid_layout(spec)
    out = {name: np.full(n_steps, np.nan) for name in names}
    # each frame id's frames of steps 0..n-1, in the log's order: their steps and their bytes,
    # decoded a signal at a time over all of them (numpy) instead of a frame at a time
    all_steps, frames = flight.outputs(0)
    usable = (all_steps < n_steps) & (frames.length == 8)
    mismatched = 0
    for fid, step_sig, sigs in layout:
        which = usable & (frames.frame_id == fid)
        if not which.any():
            continue
        steps, bits = all_steps[which], frames.data[which].view("<u8").ravel()
        if step_sig is not None and check_step:
            ok = _column(step_sig, bits).astype(np.int64) == (steps & 0xFFF)
            mismatched += int(np.count_nonzero(~ok))
            steps, bits = steps[ok], bits[ok]
        if check_step:
            _refuse_duplicates(spec, fid, steps, bits)
        # realtime: a step's last frame (two of fcc's steps on one sample)
        last = len(steps) - 1 - np.unique(steps[::-1], return_index=True)[1]
        steps, bits = steps[last], bits[last]
        for sig, name in sigs:
            out[name][steps] = _column(sig, bits)
    out["_mismatched"] = np.array([mismatched])
    return out


def _refuse_duplicates(spec: BusSpec, fid: int, steps: np.ndarray, bits: np.ndarray) -> None:
    """DuplicateOutput when one step has two different frames of identifier fid."""
    order = np.lexsort((bits, steps))
    st, bt = steps[order], bits[order]
    clash = np.flatnonzero((st[1:] == st[:-1]) & (bt[1:] != bt[:-1]))
    if len(clash):
        i = int(clash[0])
        msg = spec.by_id(fid)
        raise DuplicateOutput(
            f"bus.log: two different {msg.name if msg else hex(fid)} frames for step {int(st[i])} "
            f"({int(bt[i]):016x}, {int(bt[i + 1]):016x}): one is not fcc's; the flight is not "
            f"evaluated")
