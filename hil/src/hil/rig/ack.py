"""fcc's acknowledgement of a lockstep step (FCC_ACK), read once a step by hil.rig.lockstep.

It must pass the codec's checks of every received frame (its length, its E2E class -- CRC and
alive counter -- and the DBC ranges of its fields, counted by the codec as
``FrameCodec.decode`` counts them) and be the acknowledgement of step k of application app;
then its ``degraded`` flag and ``exec_us`` are read.  The generic decode builds a dict of
every field and a ``Decoded`` for that: in the UML guest several microseconds of a ~0.25 ms
step.  Here the fields are read straight from the frame's little-endian integer (the DBC's
field table, ``MessageSpec.data_fields``) and the range check reduces to the expected app and
step being in range: the two other fields' ranges are their whole widths (checked when the
reader is made; a DBC where they are not is read through ``FrameCodec.decode``).  A frame
that is not the expected acknowledgement gets the codec's full range check, so that its
counters stay those of the generic decode.
"""
from __future__ import annotations

from hil.bus import FrameCodec
from hil.bus.dbc import Field

ACK = "FCC_ACK"


def whole_width(f: Field) -> bool:
    """An unsigned, unscaled field whose DBC range is every value its bits hold."""
    return f.sign == 0 and f.inv_scale == 0 and f.raw_min == 0 and f.raw_max == f.mask


class AckReader:
    """The acknowledgements one codec receives."""

    def __init__(self, codec: FrameCodec) -> None:
        self.codec = codec
        self.msg = codec.spec.by_name(ACK)
        self.frame_id = self.msg.frame_id
        fields = {f.name: f for f in self.msg.data_fields}
        app, step, degraded, exec_us = (fields[n] for n in ("app", "step", "degraded", "exec_us"))
        self._app, self._step = (app.start, app.mask), (step.start, step.mask)
        self._degraded, self._exec_us = (degraded.start, degraded.mask), (exec_us.start, exec_us.mask)
        self._app_range, self._step_range = (app.raw_min, app.raw_max), (step.raw_min, step.raw_max)
        self._direct = (ACK in codec.consumes and len(fields) == 4
                        and all(f.sign == 0 and f.inv_scale == 0 for f in fields.values())
                        and whole_width(degraded) and whole_width(exec_us))

    def read(self, data: bytes, app: int, k: int) -> tuple[bool, int] | None:
        """(degraded, exec_us) when data is the acknowledgement of step k of app that the codec
        passes; None otherwise (refused by the codec's checks, or another step's: a repeated
        ACK of an earlier tick)."""
        if not self._direct:
            dec = self.codec.decode(self.frame_id, data)
            v = dec.values
            if not dec.ok or v is None or int(v["app"]) != app or int(v["step"]) != k:
                return None
            return bool(v["degraded"]), int(v["exec_us"])
        if not self.codec.usable(self.msg, data):
            return None
        bits = int.from_bytes(data, "little")
        (a, a_mask), (s, s_mask) = self._app, self._step
        (a_min, a_max), (s_min, s_max) = self._app_range, self._step_range
        if (bits >> a) & a_mask != app or (bits >> s) & s_mask != k \
                or not (a_min <= app <= a_max and s_min <= k <= s_max):
            self.codec.in_range(self.msg, data)   # counted as the generic decode counts it
            return None
        (d, d_mask), (e, e_mask) = self._degraded, self._exec_us
        return bool((bits >> d) & d_mask), (bits >> e) & e_mask
