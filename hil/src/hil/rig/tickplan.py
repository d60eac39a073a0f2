"""A lockstep flight's ticks, made before they are sent.

The tick of step k is SIM_TICK(app, k) with the next E2E alive counter (hil.bus.e2e) and the
next SecOC message counter (hil.bus.secoc): as long as no other tick goes out in between,
every tick of the flight is known when it starts.  A plan makes them in one pass, with the
encoder, E2E protection and authenticator of the step-by-step path, so that the lockstep loop
hands each step's bytes over instead of encoding, protecting and authenticating a tick per step
(most of the simulator's Python per step).

A planned tick is used only while both senders are where the plan expects them; the loop
advances them as sending it through the step-by-step path would.  A resent tick, one that
resynchronises fcc's receiver, or another application's tick moves them on: the plan is made
again from there (hil.rig.lockstep).  A fault that names SIM_TICK acts on single ticks: such a
flight has no plan.  Nor has a step number that the tick's field cannot carry (the encoder
would clamp it): the plan stops before it.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from hil.bus import FrameCodec
from hil.bus.batch import pack_many
from hil.bus.e2e import COUNTER_MODULO, protect_many
from hil.bus.rawcan import CAN_FRAME, DATA_OFFSET, pack_frame
from hil.bus.secoc import Endpoint
from hil.bus.secoc_batch import authenticators

TICK = "SIM_TICK"


class PlannedTick(NamedTuple):
    """One tick: its E2E-protected bytes, and what the socket sends (the tick and its
    authenticator as struct can_frames)."""

    data: bytes
    wire: tuple[bytes, bytes]


class TickPlan:
    """The ticks of steps first, first + 1, ... of one application, from the senders' state
    when the plan is made."""

    def __init__(self, codec: FrameCodec, security: Endpoint, app: int, first: int, end: int) -> None:
        msg = codec.spec.by_name(TICK)
        self._e2e = codec.senders[TICK]
        self._sec = security.sender(msg.frame_id)
        self.first = first
        self._e2e0, self._sec0, self._trip = self._e2e.counter, self._sec.counter, self._sec.trip
        step = msg.signal("step")
        end = min(end, step.raw_max + 1)   # beyond, the encoder would clamp the step number
        ks = np.arange(first, max(first, end), dtype=np.int64)
        payloads, _ = pack_many(msg, {"app": np.full(len(ks), app), "step": ks}, len(ks), saturate=False)
        counters = (self._e2e0 + np.arange(len(ks))) % COUNTER_MODULO
        frames = protect_many(msg.data_id, payloads, counters)
        blob = frames.tobytes()
        datas = [blob[i: i + 8] for i in range(0, len(blob), 8)]
        auths = authenticators(self._sec.key, self._sec.data_id, frames, self._trip, self._sec0 + 1)
        # each step's two struct can_frames side by side: the frames' headers, then their data
        wire = np.empty((len(datas), 2 * CAN_FRAME.size), np.uint8)
        for col, frame_id, data in ((0, msg.frame_id, frames),
                                    (CAN_FRAME.size, security.auth_id(msg.frame_id),
                                     auths)):
            wire[:, col: col + CAN_FRAME.size] = np.frombuffer(pack_frame(frame_id, bytes(8)), np.uint8)
            wire[:, col + DATA_OFFSET: col + CAN_FRAME.size] = data
        w, n = wire.tobytes(), CAN_FRAME.size
        self.ticks = [PlannedTick(d, (w[2 * n * i: 2 * n * i + n], w[2 * n * i + n: 2 * n * (i + 1)]))
                      for i, d in enumerate(datas)]

    def take(self, k: int) -> PlannedTick | None:
        """The tick of step k, its senders advanced past it; None when the plan does not
        have it or the senders are not where the plan expects them."""
        i = k - self.first
        e2e, sec = self._e2e, self._sec
        if not 0 <= i < len(self.ticks) or e2e.counter != (self._e2e0 + i) % COUNTER_MODULO \
                or sec.counter != self._sec0 + i or sec.trip != self._trip:
            return None
        e2e.counter = (e2e.counter + 1) % COUNTER_MODULO
        sec.counter += 1
        return self.ticks[i]
