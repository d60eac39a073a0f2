"""The lockstep's tick plan (hil.rig.tickplan) against the step-by-step path: the same bytes
on the bus for every tick, the senders left in the same state, and no planned tick once
something else moved them (no vcan: the frames are compared, not sent)."""
from __future__ import annotations

import pytest

from hil.bus import SIM_NODES, FrameCodec, load
from hil.bus.rawcan import pack_frame
from hil.bus.secoc import TEST_KEY_FILE, Endpoint, read_key_file
from hil.rig.tickplan import TICK, TickPlan

SPEC = load()
TRIP = 0x5EED1234


def rig_side() -> tuple[FrameCodec, Endpoint]:
    security = Endpoint(SPEC, read_key_file(TEST_KEY_FILE), SIM_NODES)
    security.set_trip(TRIP)
    return FrameCodec(SPEC, SIM_NODES), security


def step_by_step(codec: FrameCodec, security: Endpoint, app: int, k: int) -> tuple[bytes, list[bytes]]:
    """The tick as the lockstep loop made it before the plan: encoded, protected, authenticated."""
    frame_id, data = codec.encode(TICK, {"app": app, "step": k}, saturate=True)
    return data, [pack_frame(fid, d) for fid, d in security.protect(frame_id, data)]


@pytest.mark.parametrize("app, first, e2e0, sec0", [(0, 0, 0, 0), (1, 5, 11, 70000), (0, 300, 15, 65535)])
def test_planned_ticks_are_the_step_by_step_ones(app: int, first: int, e2e0: int, sec0: int) -> None:
    planned_codec, planned_sec = rig_side()
    codec, sec = rig_side()
    for c, s in ((planned_codec, planned_sec), (codec, sec)):
        c.senders[TICK].counter = e2e0
        s.sender(SPEC.by_name(TICK).frame_id).counter = sec0
    plan = TickPlan(planned_codec, planned_sec, app, first, first + 40)
    for k in range(first, first + 40):
        tick = plan.take(k)
        assert tick is not None
        data, wire = step_by_step(codec, sec, app, k)
        assert tick.data == data and list(tick.wire) == wire
        tick_id = SPEC.by_name(TICK).frame_id
        assert planned_codec.senders[TICK].counter == codec.senders[TICK].counter
        assert planned_sec.sender(tick_id).counter == sec.sender(tick_id).counter
    assert plan.take(first + 40) is None   # beyond the plan


def test_no_planned_tick_once_another_tick_went_out() -> None:
    codec, security = rig_side()
    plan = TickPlan(codec, security, 0, 0, 10)
    assert plan.take(0) is not None
    step_by_step(codec, security, 0, 1)   # a resent or resynchronising tick
    assert plan.take(1) is None
    assert plan.take(0) is None           # a step taken is not handed out twice
    codec2, security2 = rig_side()
    plan2 = TickPlan(codec2, security2, 0, 0, 10)
    security2.set_trip(TRIP + 1)          # another trip: other authenticators
    assert plan2.take(0) is None


def test_the_plan_stops_before_a_step_the_field_cannot_carry() -> None:
    codec, security = rig_side()
    top = SPEC.by_name(TICK).signal("step").raw_max
    plan = TickPlan(codec, security, 0, top - 2, top + 5)
    assert len(plan.ticks) == 3
    assert all(plan.take(k) is not None for k in (top - 2, top - 1, top))
    assert plan.take(top + 1) is None
