"""The fault matrix: every fault class x both aircraft, lockstep, the real fcc on vcan0.

Each cell flies both aircraft interleaved through one fcc (CDRW 1 s = 51 steps of 20 ms;
missile 2 s = 40 steps of 50 ms), each with the same fault class over its steps 10-19,
then checks
  * the run completes (every step answered, the run evaluated: what `hil run` exits 0 on);
  * fcc's counters (its final heartbeat) are exactly what the injected faults imply: the
    E2E classes and the rejections, derived below from the frames the injector reports;
  * nothing is lost: bus.log ends with the rig's end marker, and holds every frame the
    simulator sent and one FCC_ACK per answered step.
The `expect` functions state the arithmetic: F = sensor frames per step of the aircraft,
N = steps under the fault (10), base = the fault-free E2E "ok" count.
"""
from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import pytest

from hil.bus.candump import read_log
from rig_helpers import CDRW_1S, MISSILE_2S, fly, scenario

pytestmark = pytest.mark.vcan

N = 10
AIRCRAFT = {
    #          scenario   steps F  fault window       a signal  a frame         its signal  2 steps
    "cdrw": (CDRW_1S, 51, 3, "start=0.2,duration=0.2", "alpha", "CDRW_AOA", "alpha", 0.04),
    "missile": (MISSILE_2S, 40, 2, "start=0.5,duration=0.5", "q_g", "MSL_RATE_GYRO", "q_g", 0.1),
}
SIM_IDS = {0x010, 0x011, 0x020, 0x021, 0x050, 0x051, 0x052, 0x040, 0x041, 0x710, 0x7F0}  # + authenticators
ACK_ID = 0x028


def base_ok(steps: int, f: int) -> int:
    """Fault-free E2E OK: every sensor frame, every tick, and the session's five authenticated
    SIM_CONTROL commands (reset, flight, ground at the end of the flight, ground + shutdown)."""
    return f * steps + steps + 5


#: kind -> (spec template, expected counters given (steps, F, injected counts));
#: counters not named must be 0.  {w}: the window, {sig}/{frame}/{fsig}: the aircraft's.
#: Every fault sends a SIM_EVENT at its start and its end (+2 OK), except where the
#: simulator is silenced at the start.
Expect = Callable[[int, int, dict], dict]
CASES: dict[str, tuple[str, Expect]] = {
    # sensor level: the frames are all there, the values change
    "spike": ("spike:signal={sig},{w},magnitude=0.05", lambda s, f, i: {"ok": base_ok(s, f) + 2}),
    "bias": ("bias:signal={sig},{w},magnitude=0.02", lambda s, f, i: {"ok": base_ok(s, f) + 2}),
    "stuck": ("stuck:signal={sig},{w}", lambda s, f, i: {"ok": base_ok(s, f) + 2}),
    "noise_burst": ("noise_burst:signal={sig},{w},magnitude=0.02",
                    lambda s, f, i: {"ok": base_ok(s, f) + 2}),
    "drift": ("drift:signal={sig},{w},rate=0.1", lambda s, f, i: {"ok": base_ok(s, f) + 2}),
    "scale": ("scale:signal={sig},{w},factor=1.5", lambda s, f, i: {"ok": base_ok(s, f) + 2}),
    # a dead sensor sends nothing (its counter does not move): N empty periods, no jump
    "dropout": ("dropout:signal={sig},{w}",
                lambda s, f, i: {"ok": base_ok(s, f) + 2 - N, "no_new_data": N}),
    # frame level, on every sensor frame of the aircraft (frame = *) unless one is needed
    "loss": ("loss:frame=*,{w}",   # N*F empty periods; each sensor's next frame jumps N+1
             lambda s, f, i: {"ok": base_ok(s, f) + 2 - N * f - f, "no_new_data": N * f,
                              "wrong_sequence": f}),
    "delay": ("delay:frame=*,{w},delay=0.01",  # late by < 1 step: in order, E2E OK, the
              lambda s, f, i: {"ok": base_ok(s, f) + 2, "no_new_data": f}),  # 1st period empty
    "duplicate": ("duplicate:frame=*,{w},count=2",
                  lambda s, f, i: {"ok": base_ok(s, f) + 2, "repeated": 2 * N * f}),
    "bad_crc": ("bad_crc:frame=*,{w}",  # N*F errors; the next good frame jumps N+1
                lambda s, f, i: {"ok": base_ok(s, f) + 2 - N * f - f, "error": N * f,
                                 "wrong_sequence": f}),
    "counter_freeze": ("counter_freeze:frame={frame},{w}",  # 1st frozen = its own counter
                       lambda s, f, i: {"ok": base_ok(s, f) + 2 - N, "repeated": N - 1,
                                        "wrong_sequence": 1}),
    # a replay: step k sends step k-2's frame, counter and CRC as they were (age = 2 steps).
    # Step 10 goes back 1 (delta 15: WRONG_SEQUENCE; the receiver takes the old counter as
    # its last), steps 11-19 then run on by 1 each (OK: a 4-bit alive counter cannot tell a
    # replay two steps old from fresh data), step 20's own frame skips 2 (OK_SOME_LOST)
    "replay": ("replay:frame={frame},{w},age={age}",
               lambda s, f, i: {"ok": base_ok(s, f) + 2 - 2, "wrong_sequence": 1, "ok_some_lost": 1}),
    "counter_jump": ("counter_jump:frame={frame},{w},jump=5",  # into and out of the jump
                     lambda s, f, i: {"ok": base_ok(s, f) + 2 - 2, "wrong_sequence": 2}),
    "wrong_dlc": ("wrong_dlc:frame={frame},{w},dlc=4",  # refused before E2E (so E2E sees
                  lambda s, f, i: {"ok": base_ok(s, f) + 2 - N - 1, "wrong_dlc": N,  # an empty
                                   "no_new_data": N, "wrong_sequence": 1}),  # period); a jump
    "out_of_range": ("out_of_range:frame={frame},signal={fsig},{w}",  # E2E OK, then refused
                     lambda s, f, i: {"ok": base_ok(s, f) + 2, "out_of_range": N}),
    # bus level
    "flood": ("flood:{w},rate_hz=2000,can_id=0x7FE",
              lambda s, f, i: {"ok": base_ok(s, f) + 2, "unknown_id": i["flood"]}),
    "silence": ("silence:{w}",  # the start event is silenced too; each sensor jumps after
                lambda s, f, i: {"ok": base_ok(s, f) + 1 - N * f - f, "no_new_data": N * f,
                                 "wrong_sequence": f}),
    # background load on the wire-time bus (flown with --bus wire): the times change, not
    # the frames fcc gets
    "bus_load": ("bus_load:{w},utilisation=0.3", lambda s, f, i: {"ok": base_ok(s, f) + 2}),
}
#: the kinds flown on the wire-time bus in simulated time (the others on the ideal bus)
WIRE_KINDS = {"bus_load"}
COUNTERS = ("ok", "repeated", "ok_some_lost", "wrong_sequence", "error", "no_new_data",
            "unknown_id", "wrong_dlc", "out_of_range")


def spec_for(kind: str, aircraft: str) -> str:
    _, _, _, w, sig, frame, fsig, age = AIRCRAFT[aircraft]
    return CASES[kind][0].format(w=w, sig=sig, frame=frame, fsig=fsig, age=age)


def fly_cell(tmp_path: Path, kind: str) -> tuple[dict, dict[str, dict], dict]:
    """Both aircraft in one flight through one fcc (interleaved as in the demo), each with the
    fault: the counters add up, so each cell checks both aircraft with one session."""
    scs = [scenario(AIRCRAFT[a][0], spec_for(kind, a)) for a in sorted(AIRCRAFT)]
    o = fly(tmp_path, *scs, **({"bus": "wire"} if kind in WIRE_KINDS else {}))
    summary = o.summary
    fw = summary["firmware"]
    got = {**fw["e2e"], **fw["rejected"]}
    injected: dict[str, dict] = {}
    acked = 0
    for a in sorted(AIRCRAFT):
        steps = AIRCRAFT[a][1]
        blk = summary["cdrw"]["flight"] if a == "cdrw" else summary["missile"]["runs"][0]
        injected[a] = blk["frames_injected"]
        assert blk["steps"] - blk["unanswered_steps"] == steps and fw["steps"][a] == steps, a
        acked += steps
    # nothing lost: the whole bus is in bus.log, ending with the rig's end marker
    info = json.loads((tmp_path / "run_info.json").read_text())
    frames = list(read_log(tmp_path / "bus.log"))
    assert frames[-1].frame_id == 0x7F0 and frames[-1].data == bytes.fromhex("FFFFFFFF00000000")
    sim = sum(1 for fr in frames if fr.frame_id in SIM_IDS or fr.frame_id == 0x7FE)
    assert sim == info["link"]["tx_frames"], "a frame the simulator sent is missing in bus.log"
    acks = sum(1 for fr in frames if fr.frame_id == ACK_ID)
    assert acked <= acks <= acked + info.get("resent_ticks", 0)  # a resent tick: one more ACK
    return got, injected, info


def expected(kind: str, injected: dict[str, dict], resent_ticks: int = 0) -> dict[str, int]:
    """fcc's counters after a cell: each aircraft's CASES arithmetic, added up for one session
    (also docs/reliability.md's table: scripts/lib/doc_tables.py)."""
    want = dict.fromkeys(COUNTERS, 0)
    for a in sorted(AIRCRAFT):
        _, steps, f, *_ = AIRCRAFT[a]
        for c, v in CASES[kind][1](steps, f, injected[a]).items():
            want[c] += v
    want["ok"] -= 5          # one session's five SIM_CONTROL commands, not five per aircraft
    want["ok"] += resent_ticks  # a tick resent under load is one more OK
    if kind == "silence":
        # SIM_EVENT is one message with one alive counter for both aircraft: the CDRW's
        # end event is the first fcc sees (OK whatever its counter); the missile's silenced
        # start event took a counter, so its end event arrives OK_SOME_LOST
        want["ok"] -= 1
        want["ok_some_lost"] += 1
    return want


@pytest.mark.parametrize("kind", list(CASES))
def test_fault_class(tmp_path, kind):
    got, injected, info = fly_cell(tmp_path, kind)
    if kind == "replay":
        for a in sorted(AIRCRAFT):
            assert injected[a]["replayed"] == N, (a, injected[a])
    want = expected(kind, injected, info.get("resent_ticks", 0))
    print(f"MATRIX {kind} " + json.dumps({c: got[c] for c in COUNTERS}))  # README's table
    assert {c: got[c] for c in COUNTERS} == want, (kind, injected)
