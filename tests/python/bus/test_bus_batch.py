"""Many frames of one message at once (hil.bus.batch.encode_many): the bytes, codec counters
and E2E alive counters of FrameCodec.encode called once per frame."""
from __future__ import annotations

import numpy as np
import pytest

from hil.bus import SIM_NODES, FrameCodec
from hil.bus.batch import encode_many
from hil.bus.codec import EncodeError


def _columns(codec: FrameCodec, name: str, n: int, rng: np.random.Generator) -> dict[str, np.ndarray]:
    """Values of every data signal: inside the DBC range, on it, beyond it (a little and by
    far), halves of the raw step (rounding ties) and zeros of both signs."""
    msg = codec.spec.by_name(name)
    cols: dict[str, np.ndarray] = {}
    for sig in msg.data_signals:
        lo, hi = sig.to_phys(sig.raw_min), sig.to_phys(sig.raw_max)
        if sig.is_integer:
            cols[sig.name] = rng.integers(sig.raw_min - 3, sig.raw_max + 4, n, dtype=np.int64)
            continue
        span = hi - lo
        v = rng.uniform(lo - 0.2 * span, hi + 0.2 * span, n)
        v[::7] = (rng.integers(-1000, 1000, v[::7].size) + 0.5) / sig.inv_scale   # ties
        v[1::11] = rng.choice([lo, hi, -0.0, 0.0, 1e300, -1e300], v[1::11].size)
        cols[sig.name] = v
    return cols


def _one_by_one(codec: FrameCodec, name: str, cols: dict[str, np.ndarray], saturate: bool) -> list[bytes]:
    n = len(next(iter(cols.values())))
    return [codec.encode(name, {k: v[i].item() for k, v in cols.items()}, saturate=saturate)[1]
            for i in range(n)]


@pytest.mark.parametrize("name", ["CDRW_AOA", "CDRW_PITCH_RATE", "CDRW_ELEVATOR", "MSL_RATE_GYRO",
                                  "MSL_ACCELEROMETER", "SIM_EVENT", "SIM_TICK"])
def test_the_frames_and_counters_of_encode_one_by_one(name: str) -> None:
    a, b = FrameCodec(nodes=SIM_NODES), FrameCodec(nodes=SIM_NODES)
    for codec in (a, b):   # the senders somewhere in their cycle
        codec.encode(name, {s.name: 0 for s in codec.spec.by_name(name).data_signals})
    cols = _columns(a, name, 300, np.random.default_rng(len(name)))
    expected = _one_by_one(a, name, cols, saturate=True)
    frame_id, got = encode_many(b, name, cols, saturate=True)
    assert frame_id == a.spec.by_name(name).frame_id
    assert got == expected
    assert a.counters == b.counters and a.counters.tx_saturated > 0
    assert {k: s.counter for k, s in a.senders.items()} == {k: s.counter for k, s in b.senders.items()}


def test_in_range_values_need_no_saturation() -> None:
    a, b = FrameCodec(nodes=SIM_NODES), FrameCodec(nodes=SIM_NODES)
    cols = {"step": np.arange(40), "alpha": np.linspace(-0.5, 0.5, 40)}
    assert encode_many(b, "CDRW_AOA", cols)[1] == _one_by_one(a, "CDRW_AOA", cols, saturate=False)
    assert b.counters.tx_saturated == 0


@pytest.mark.parametrize(("name", "cols"), [
    ("CDRW_AOA", {"step": np.arange(3), "alpha": np.array([0.1, 1e9, 0.2])}),        # out of range
    ("CDRW_AOA", {"step": np.arange(3), "alpha": np.array([0.1, np.nan, 0.2])}),     # not finite
    ("CDRW_AOA", {"step": np.array([0.0, 1.5, 2.0]), "alpha": np.zeros(3)}),          # not whole
    ("CDRW_AOA", {"step": np.arange(3)}),                                            # missing
    ("CDRW_AOA", {"step": np.arange(3), "alpha": np.zeros(3), "q": np.zeros(3)}),    # not its own
    ("CDRW_AOA", {"step": np.arange(3), "alpha": np.zeros(2)}),                      # short
    ("FCC_ACK", {"app": np.zeros(3)}),                                               # not sent by SIM
])
def test_what_encode_refuses_is_refused_and_counted(name: str, cols: dict[str, np.ndarray]) -> None:
    codec = FrameCodec(nodes=SIM_NODES)
    counters = {k: s.counter for k, s in codec.senders.items()}
    with pytest.raises(EncodeError):
        encode_many(codec, name, cols)
    assert codec.counters.tx_refused == 1
    assert {k: s.counter for k, s in codec.senders.items()} == counters   # nothing was sent
