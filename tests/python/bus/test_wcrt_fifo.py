"""hil.bus.wcrt's FIFO-queued node (the module's own derivation, stated in its docstring):
an example computed by hand here (two nodes, one a FIFO of three frames; each step in the
comments), what the priority-queued frames see of a FIFO's, the refusals, and the DBC with
the rig's FIFO node, fcc."""
from __future__ import annotations

from fractions import Fraction

import pytest

from hil.bus import dbc
from hil.bus.wcrt import Frame, analyse, cyclic_frames, seconds

MS = Fraction(1, 1000)
#: 135 bits (8 bytes, 11-bit identifier, worst-case stuffing, interframe space) in 1 ms
BITRATE_1MS = 135_000


def frame(frame_id: int, period_ms: float, sender: str, jitter_ms: float = 0) -> Frame:
    period = seconds(period_ms) * MS
    return Frame(frame_id, f"F{frame_id:x}", sender, period, period, jitter_s=seconds(jitter_ms) * MS)


#: node P (priority-queued): A 0x1 (T 4 ms) and D 0x5 (T 40 ms); node F (a FIFO): 0x2 (T 5 ms,
#: J 4.5 ms: two can be queued 0.5 ms apart), 0x3 (T 10 ms), 0x4 (T 20 ms); C = 1 ms each
EXAMPLE = [frame(1, 4, "P"), frame(5, 40, "P"), frame(2, 5, "F", 4.5), frame(3, 10, "F"), frame(4, 20, "F")]


def wcrt_ms(frames: list[Frame], fifo: tuple[str, ...]) -> dict[str, Fraction | None]:
    return {r.frame.name: None if r.wcrt_s is None else r.wcrt_s / MS
            for r in analyse(frames, BITRATE_1MS, fifo)}


def test_a_fifo_of_three_frames_by_hand() -> None:
    # F's lowest priority L = 0x4; hp(L) = {A}; lp(L) = {D}: B_L = 1.
    # t_L = 1 + ceil(t/4) + ceil((t + 4.5)/5) + ceil(t/10) + ceil(t/20), from 1 + 4 = 5:
    #   5 -> 1+2+2+1+1 = 7 -> 1+2+3+1+1 = 8 -> 8.
    # X = {0} + {5q - 4.5 < 8} = {0, 0.5, 5.5} (10 and 20 are not below 8).
    # n_0x2(x) = floor((x + 4.5)/5) + 1 = 1, 2, 3; n_0x3 = n_0x4 = 1;
    # ahead(x) = B + sum n_k C_k - C_m = 3, 4, 5.
    # w = ahead + ceil((w + tau)/4): 3 -> 4 -> 5 -> 5; 4 -> 6 -> 6; 5 -> 7 -> 7.
    # R(x) = J_m + w + 1 - x: 0x3, 0x4 (J 0): 6, 6.5, 2.5 -> 6.5 (not x = 0's: a burst of 0x2);
    #   0x2 (J 4.5): 4.5 + 6.5 = 11.
    # A: Davis 2007, B = 1: R = 2.
    # D sees the FIFO's frames with jitter R - C: 10, 5.5, 5.5.
    #   t = ceil(t/4) + ceil((t+10)/5) + ceil((t+5.5)/10) + ceil((t+5.5)/20) + ceil(t/40):
    #   1 -> 1+3+1+1+1 = 7 -> 2+4+2+1+1 = 10 -> 3+4+2+1+1 = 11 -> 3+5+2+1+1 = 12 -> 12; Q = 1;
    #   w = ceil((w+tau)/4) + ceil((w+10+tau)/5) + ceil((w+5.5+tau)/10) + ceil((w+5.5+tau)/20):
    #   0 -> 1+3+1+1 = 6 -> 2+4+2+1 = 9 -> 3+4+2+1 = 10 -> 3+5+2+1 = 11 -> 11; R = 12.
    assert wcrt_ms(EXAMPLE, ("F",)) == {"F1": 2, "F2": 11, "F3": Fraction(13, 2), "F4": Fraction(13, 2),
                                        "F5": 12}
    assert {r.frame.name: r.queue for r in analyse(EXAMPLE, BITRATE_1MS, ("F",))} == {
        "F1": "prio", "F2": "fifo", "F3": "fifo", "F4": "fifo", "F5": "prio"}


def test_the_same_frames_priority_queued() -> None:
    # Davis 2007 for all: 0x2 (J 4.5) over 0x3: B = 1, w = 1 + ceil((w + tau)/4) + ceil((w + 4.5 +
    # tau)/5) -> 1 -> 1+1+2 = 4 -> 1+2+2 = 5 -> 1+2+2 = 5: R = 5 + 1 = 6 < 6.5 (the FIFO's).
    got = wcrt_ms(EXAMPLE, ())
    assert got["F3"] == 6 and got["F3"] < wcrt_ms(EXAMPLE, ("F",))["F3"]


def test_a_fifo_alone_and_unbounded() -> None:
    # one frame alone in its FIFO: its own frame time
    assert wcrt_ms([frame(1, 10, "F")], ("F",)) == {"F1": 1}
    # F + hp(L) at utilisation 1: the FIFO's frames and those below them have no bound
    rs = wcrt_ms([frame(1, 2, "P"), frame(2, 4, "F"), frame(3, 4, "F"), frame(9, 100, "P")], ("F",))
    assert rs == {"F1": 2, "F2": None, "F3": None, "F9": None}


def test_one_fifo_node_at_most() -> None:
    with pytest.raises(ValueError, match="one FIFO-queued node at most"):
        analyse([frame(1, 10, "A"), frame(2, 10, "B")], BITRATE_1MS, ("A", "B"))


@pytest.mark.parametrize(("bitrate", "fifo_met", "unbounded"), [
    (125_000, 0, 32), (250_000, 27, 0), (500_000, 27, 0), (1_000_000, 27, 0)])
def test_the_dbc_with_fcc_a_fifo(bitrate: int, fifo_met: int, unbounded: int) -> None:
    frames = cyclic_frames(dbc.load())
    rs = analyse(frames, bitrate, ("FCC",))
    fifo = [r for r in rs if r.queue == "fifo"]
    assert len(fifo) == sum(f.sender == "FCC" for f in frames) == 27
    assert sum(r.deadline_met for r in fifo) == fifo_met
    assert sum(r.wcrt_s is None for r in rs) == unbounded
    plain = {r.frame.name: r.wcrt_s for r in analyse(frames, bitrate)}
    for r in rs:   # a FIFO never helps: no bound below the all-priority one
        if r.wcrt_s is not None:
            assert plain[r.frame.name] is not None and r.wcrt_s >= plain[r.frame.name]
