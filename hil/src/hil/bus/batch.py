"""Many frames of one message encoded at once: the same bytes, counters and E2E alive
counters as FrameCodec.encode called once per frame, in order.

A CDRW flight's sensor frames are all known before its first tick (hil.sim.drivers): encoding
them a frame at a time (a dict of values, a range check and a CRC per frame in Python) was
most of the driver's construction in the rig's guest.  Here each signal's column is scaled,
rounded (half away from zero, as hil.util.rounding and the firmware do), checked and packed
with numpy, and the frames are E2E-protected by protect_many with the sender's next
counters.
"""
from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from hil.bus import dbc
from hil.bus.codec import EncodeError, FrameCodec
from hil.bus.e2e import COUNTER_MODULO, protect_many
from hil.util.rounding import round_half_away_many


def _raw_column(sig: dbc.SignalSpec, values: np.ndarray, saturate: bool) -> tuple[np.ndarray, np.ndarray]:
    """A signal's raw values (int64) and which of them were clamped to its DBC range, as
    hil.bus.codec._value_to_raw gives them one by one."""
    if values.dtype.kind in "iub":
        raw = values.astype(np.int64)
    else:
        x = np.asarray(values, dtype=np.float64)
        if not np.isfinite(x).all():
            raise EncodeError(f"{sig.name}: {x[~np.isfinite(x)][0]} is not finite")
        if sig.is_integer:
            if (x != np.floor(x)).any():
                raise EncodeError(f"{sig.name}: {x[x != np.floor(x)][0]} is not an integer")
            # beyond the field by more than one is clamped all the same (and stays an int64)
            raw = np.clip(x, sig.raw_min - 1, sig.raw_max + 1).astype(np.int64)
        else:
            # an overflow to +-inf or a value far outside the field becomes just outside it
            scaled = np.clip(x * sig.inv_scale, sig.raw_min - 1, sig.raw_max + 1)
            raw = round_half_away_many(scaled).astype(np.int64)
    clamped = (raw < sig.raw_min) | (raw > sig.raw_max)
    if clamped.any() and not saturate:
        v = values[clamped][0]
        raise EncodeError(f"{sig.name}: {v} is outside the DBC range "
                          f"[{sig.to_phys(sig.raw_min)}, {sig.to_phys(sig.raw_max)}]")
    return np.clip(raw, sig.raw_min, sig.raw_max), clamped


def pack_many(msg: dbc.MessageSpec, columns: Mapping[str, np.ndarray], n: int,
               saturate: bool) -> tuple[np.ndarray, int]:
    """hil.bus.codec.pack of n frames: (n, length) uint8 with crc = counter = 0, and how many
    frames had a value clamped."""
    for sig in msg.data_signals:
        if sig.name not in columns:
            raise EncodeError(f"{msg.name}: signal {sig.name} missing")
    if len(columns) != len(msg.data_signals):
        unknown = set(columns) - {s.name for s in msg.data_signals}
        raise EncodeError(f"{msg.name}: no signal(s) {sorted(unknown)}")
    words = np.zeros(n, np.uint64)
    clamped = np.zeros(n, bool)
    for sig in msg.data_signals:
        col = np.asarray(columns[sig.name])
        if col.shape != (n,):
            raise EncodeError(f"{msg.name}: signal {sig.name} has {col.shape} values, expected ({n},)")
        raw, c = _raw_column(sig, col, saturate)
        words |= (raw & ((1 << sig.length) - 1)).astype(np.uint64) << np.uint64(sig.start)
        clamped |= c
    frames = words.astype("<u8").view(np.uint8).reshape(n, 8)[:, :msg.length]
    return np.ascontiguousarray(frames), int(clamped.sum())


def encode_many(codec: FrameCodec, name: str, columns: Mapping[str, np.ndarray], *,
                saturate: bool = False) -> tuple[int, list[bytes]]:
    """(CAN ID, the frames) of n messages `name` whose data signals take the columns' values
    (one array of n values per signal): FrameCodec.encode of each in turn, its counters
    (tx_saturated, tx_refused) and the message's E2E sender advanced as n calls would."""
    n = len(next(iter(columns.values()))) if columns else 0
    try:
        if name not in codec.produces:
            raise EncodeError(f"this node does not send {name}")
        msg = codec.spec.by_name(name)
        frames, clamped = pack_many(msg, columns, n, saturate)
    except (EncodeError, KeyError):
        codec.counters.tx_refused += 1
        raise
    codec.counters.tx_saturated += clamped
    if msg.protected:
        sender = codec.senders[name]
        counters = (sender.counter + np.arange(n)) % COUNTER_MODULO
        frames = protect_many(msg.data_id, frames, counters)
        sender.counter = (sender.counter + n) % COUNTER_MODULO
    blob, width = frames.tobytes(), msg.length
    return msg.frame_id, [blob[i: i + width] for i in range(0, n * width, width)]
