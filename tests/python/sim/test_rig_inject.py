"""Frame- and bus-level fault injection (hil.sim.frame_faults), without a bus: what each fault does
to the frames, checked with the receiver side of the same E2E specification."""
from __future__ import annotations

import numpy as np
import pytest

from hil.bus import SIM_NODES, E2EReceiver, E2EStatus, FrameCodec, load
from hil.bus.codec import decode_values
from hil.scenario.file import parse_fault_spec
from hil.sim.frame_faults import FrameInjector, out_of_range_raw, set_raw

SPEC = load()
FRAMES = {m.name for m in SPEC.messages}
STAR = ("CDRW_AOA", "CDRW_PITCH_RATE", "CDRW_ELEVATOR")
DT = 0.02


def injector(*specs: str, seed: int = 1, flood_frames: bool = True) -> FrameInjector:
    faults = [parse_fault_spec(s, "cdrw", FRAMES) for s in specs]
    return FrameInjector(FrameCodec(SPEC, SIM_NODES), faults, seed, STAR, flood_frames)


def fly(inj: FrameInjector, n: int = 20) -> list[list]:
    """n steps of the three CDRW sensor frames; the frames that went out at each step."""
    out = []
    for k in range(n):
        t = k * DT
        inj.update(t)
        msgs = [("CDRW_AOA", {"step": k, "alpha": 0.1 + 0.001 * k}),
                ("CDRW_PITCH_RATE", {"step": k, "q": 0.01 * k}),
                ("CDRW_ELEVATOR", {"step": k, "delta_e": -0.05})]
        out.append(inj.outgoing(t, msgs))
    return out


def classes(steps: list[list], name: str) -> list[E2EStatus]:
    msg = SPEC.by_name(name)
    rx = E2EReceiver(msg.data_id, msg.max_delta_counter)
    return [rx.check(f.data) for frames in steps for f in frames if f.name == name]


def test_no_fault_every_frame_ok():
    steps = fly(injector())
    assert all(len(s) == 3 for s in steps)
    for name in STAR:
        assert classes(steps, name) == [E2EStatus.OK] * 20


def test_loss_then_some_lost():
    steps = fly(injector("loss:frame=CDRW_AOA,start=0.1,duration=0.04"))
    aoa = [f for s in steps for f in s if f.name == "CDRW_AOA"]
    assert len(aoa) == 18                       # steps 5 and 6 lost
    c = classes(steps, "CDRW_AOA")
    assert c.count(E2EStatus.OK_SOME_LOST) == 1 and c.count(E2EStatus.OK) == 17


def test_loss_probability_is_seeded():
    a = fly(injector("loss:frame=*,start=0,duration=1,probability=0.5", seed=7))
    b = fly(injector("loss:frame=*,start=0,duration=1,probability=0.5", seed=7))
    c = fly(injector("loss:frame=*,start=0,duration=1,probability=0.5", seed=8))
    n = [sum(len(s) for s in x) for x in (a, b, c)]
    assert n[0] == n[1] and 0 < n[0] < 60 and a != c


def test_delay_goes_out_with_a_later_step():
    inj = injector("delay:frame=CDRW_AOA,start=0.1,duration=0.02,delay=0.03")
    steps = fly(inj)
    assert [f.name for f in steps[5]] == ["CDRW_PITCH_RATE", "CDRW_ELEVATOR"]
    late = [f for f in steps[7] if f.name == "CDRW_AOA"]  # due at 0.13 -> step 7 (t = 0.14)
    assert len(late) == 2 and decode_values(SPEC.by_name("CDRW_AOA"), late[0].data)["step"] == 5
    assert inj.counts["delayed"] == 1


def test_duplicate_is_repeated():
    steps = fly(injector("duplicate:frame=CDRW_PITCH_RATE,start=0.1,duration=0.04,count=2"))
    c = classes(steps, "CDRW_PITCH_RATE")
    assert c.count(E2EStatus.REPEATED) == 4 and c.count(E2EStatus.OK) == 20


def test_replay_sends_an_old_frame():
    steps = fly(injector("replay:frame=CDRW_AOA,start=0.2,duration=0.02,age=0.1"))
    f = [x for x in steps[10] if x.name == "CDRW_AOA"][0]
    assert decode_values(SPEC.by_name("CDRW_AOA"), f.data)["step"] == 5
    assert E2EStatus.WRONG_SEQUENCE in classes(steps, "CDRW_AOA")


def test_bad_crc_is_error():
    steps = fly(injector("bad_crc:frame=*,start=0.1,duration=0.04"))
    for name in STAR:
        assert classes(steps, name).count(E2EStatus.ERROR) == 2


def test_counter_freeze_is_repeated():
    steps = fly(injector("counter_freeze:frame=CDRW_ELEVATOR,start=0.1,duration=0.1"))
    c = classes(steps, "CDRW_ELEVATOR")
    assert c.count(E2EStatus.REPEATED) == 4          # frozen at the first frame of the fault
    assert c.count(E2EStatus.WRONG_SEQUENCE) == 1    # the counter jumps back to its real value


def test_counter_jump_is_wrong_sequence_twice():
    steps = fly(injector("counter_jump:frame=CDRW_AOA,start=0.1,duration=0.1,jump=5"))
    assert classes(steps, "CDRW_AOA").count(E2EStatus.WRONG_SEQUENCE) == 2


def test_wrong_dlc_cuts_the_frame():
    steps = fly(injector("wrong_dlc:frame=CDRW_AOA,start=0.1,duration=0.02,dlc=3"))
    f = [x for x in steps[5] if x.name == "CDRW_AOA"][0]
    assert len(f.data) == 3
    steps = fly(injector("wrong_dlc:frame=CDRW_AOA,start=0.1,duration=0.02,dlc=8"))
    assert all(len(f.data) == 8 for s in steps for f in s)


def test_out_of_range_keeps_a_valid_crc():
    steps = fly(injector("out_of_range:frame=CDRW_AOA,signal=alpha,start=0.1,duration=0.02"))
    f = [x for x in steps[5] if x.name == "CDRW_AOA"][0]
    assert classes(steps, "CDRW_AOA") == [E2EStatus.OK] * 20   # E2E is fine...
    assert decode_values(SPEC.by_name("CDRW_AOA"), f.data) is None  # ...the range check is not


def test_out_of_range_needs_a_signal_of_the_frame():
    with pytest.raises(ValueError, match="out_of_range"):
        injector("out_of_range:frame=CDRW_AOA,signal=q,start=0.1,duration=0.02")


def test_set_raw_and_out_of_range_raw():
    sig = next(s for s in SPEC.by_name("CDRW_AOA").signals if s.name == "alpha")
    data = set_raw(bytes(8), sig, -5)
    assert int.from_bytes(data[4:8], "little", signed=True) == -5
    assert out_of_range_raw(sig) == (1 << 31) - 1


def test_flood_counts_rate_times_duration():
    inj = injector("flood:start=0.1,duration=0.1,rate_hz=1000,can_id=0x7FE,dlc=2")
    steps = fly(inj)
    flood = [f for s in steps for f in s if f.name == "flood"]
    assert len(flood) == 100 and all(f.frame_id == 0x7FE and f.data == b"\xff\xff" for f in flood)
    inj = injector("flood:start=0.1,duration=0.1,rate_hz=1000", flood_frames=False)
    assert not [f for s in fly(inj) for f in s if f.name == "flood"]


def test_silence_drops_everything_but_counters_run_on():
    steps = fly(injector("silence:start=0.1,duration=0.04"))
    assert steps[5] == [] and steps[6] == []
    assert classes(steps, "CDRW_AOA").count(E2EStatus.OK_SOME_LOST) == 1


def test_tick_only_when_named():
    inj = injector("loss:frame=*,start=0,duration=1", "bad_crc:frame=SIM_TICK,start=0.1,duration=0.02")
    inj.update(0.0)
    assert len(inj.infrastructure(0.0, "SIM_TICK", {"app": 0, "step": 0})) == 1
    assert inj.faulted(0.1, "SIM_TICK") and not inj.faulted(0.0, "SIM_TICK")
    tick = inj.infrastructure(0.1, "SIM_TICK", {"app": 0, "step": 5})[0]
    rx = E2EReceiver(SPEC.by_name("SIM_TICK").data_id)
    assert rx.check(tick.data) is E2EStatus.ERROR


def test_delay_of_the_tick_is_a_loss():
    inj = injector("delay:frame=SIM_TICK,start=0,duration=1,delay=0.01")
    assert inj.infrastructure(0.0, "SIM_TICK", {"app": 0, "step": 0}) == []
    assert inj.flush_delayed() == []


def test_fault_timeline_logs_start_and_end():
    inj = injector("bad_crc:frame=*,start=0.1,duration=0.04")
    fly(inj)
    assert [(e.action, round(e.t, 3)) for e in inj.log] == [("start", 0.1), ("end", 0.14)]


def _batches(n: int, dropped: set[int]) -> list:
    """The three sensor messages of fly() for n steps, the AoA reading dropped at some."""
    k = np.arange(n)
    aoa = np.array([i not in dropped for i in range(n)])
    return [("CDRW_AOA", aoa, {"step": k[aoa], "alpha": (0.1 + 0.001 * k)[aoa]}),
            ("CDRW_PITCH_RATE", np.ones(n, bool), {"step": k, "q": 0.01 * k}),
            ("CDRW_ELEVATOR", np.ones(n, bool), {"step": k, "delta_e": np.full(n, -0.05)})]


def test_a_flight_without_frame_faults_is_made_at_once_as_step_by_step():
    dropped = {3, 4, 17}
    a, b = injector(), injector()
    for inj in (a, b):   # the senders somewhere in their cycle, as in a session's later flight
        inj.outgoing(0.0, [("CDRW_AOA", {"step": 0, "alpha": 0.0})])
    steps = []
    for k in range(20):
        a.update(k * DT)
        msgs = [m for m in (("CDRW_AOA", {"step": k, "alpha": 0.1 + 0.001 * k}),
                            ("CDRW_PITCH_RATE", {"step": k, "q": 0.01 * k}),
                            ("CDRW_ELEVATOR", {"step": k, "delta_e": -0.05}))
                if not (m[0] == "CDRW_AOA" and k in dropped)]
        steps.append(a.outgoing(k * DT, msgs))
    planned = b.outgoing_flight(20, _batches(20, dropped))
    assert planned == steps and [f.raw for s in planned for f in s] == [f.raw for s in steps for f in s]
    assert a.counts == b.counts
    assert {n: s.counter for n, s in a.codec.senders.items()} == {n: s.counter for n, s in b.codec.senders.items()}


def test_a_flight_with_a_frame_fault_goes_step_by_step():
    inj = injector("loss:frame=CDRW_AOA,start=0.1,duration=0.04")
    assert inj.outgoing_flight(20, _batches(20, set())) is None
    assert inj.counts["encoded"] == 0 and all(s.counter == 0 for s in inj.codec.senders.values())
