"""Worst-case response times of a CAN bus's cyclic frames (Davis, Burns, Bril, Lukkien 2007;
FIFO-queued nodes by the derivation below).

"Controller Area Network (CAN) schedulability analysis: refuted, revisited and revised"
(Real-Time Systems 35) corrects Tindell's 1994 analysis; SPEC §8 states it as computed here.
For frame m with period T_m, queuing jitter J_m and frame time C_m, hp(m) the frames that win
arbitration over it and lp(m) those that lose:

    B_m  = max over lp(m) of C_k                                   (blocking; 0 if none)
    t_m  = B_m + sum over hp(m) + {m} of ceil((t_m + J_k)/T_k) C_k  (busy period, from C_m)
    Q_m  = ceil((t_m + J_m)/T_m)                                   (instances in it)
    w(q) = B_m + q C_m + sum over hp(m) of ceil((w(q) + J_k + tau_bit)/T_k) C_k   (q < Q_m)
    R_m  = max over q of J_m + w(q) - q T_m + C_m

C_m is the worst-case frame time (hil.bus.busload.worst_case_bits: every possible stuff bit,
with the interframe space), so the bound holds for any payload.  When the utilisation of
hp(m) + {m} reaches 1 the busy period has no end: R_m is unbounded (None).

A node's frames are priority-queued (its controller presents its highest-priority pending
frame to arbitration) unless the node is named FIFO-queued (`fifo`: a Linux SocketCAN node,
whose frames wait in one FIFO).  A FIFO's frames are bounded by a derivation of this module's
own, not Davis, Kollmann, Pollex and Slomka 2011's equations (the paper was not at hand; its
idea is the same: a FIFO's frames suffer the interference of the lowest priority among them).
With F the FIFO node's frames, L the lowest priority in F, hp(L) the other nodes' frames of
higher priority than L and lp(L) theirs of lower:

    B_L  = max over lp(L) of C_k                                      (0 if none)
    t_L  = B_L + sum over F + hp(L) of ceil((t_L + J_k)/T_k) C_k       (level-L busy period)
    n_k(x) = floor((x + J_k)/T_k) + 1      (instances of k queued in a window [0, x])
    w(x) = B_L + sum over F of n_k(x) C_k - C_m
                + sum over hp(L) of ceil((w(x) + J_k + tau_bit)/T_k) C_k
    R_m  = J_m + max over x in X of (w(x) + C_m - x),  X = {0} + {q T_k - J_k in (0, t_L): k in F}

Why it is safe: let m be queued at a and s <= a the start of the level-L busy period it is
in (the bus idle, or a frame of lp(L) winning an arbitration with F empty and no frame of
hp(L) pending: a FIFO offers its head at every arbitration, canbus_core.c `offered`, and a
priority-queued node its highest frame).  From s until m ends the bus carries at most one
frame of lp(L) (begun before s), the FIFO's frames queued in [s, a] (m waits behind all of
them, FIFO order; x = a - s; at most n_k(x) of each, m's own earlier ones included), and
frames of hp(L) queued before m's transmission begins (Davis 2007's term, with tau_bit).
Nothing else wins an arbitration while F holds a frame: its head's priority is at least L.
w(x) - x is largest where an n_k steps up, hence X; a lies in the busy period, x < t_L.  No
assumption that a FIFO frame ends within its period is needed.  It is pessimistic: every F
frame suffers hp(L), though a higher head of the FIFO would suffer less.

A FIFO's frame k seen by the other nodes' frames: it reaches the head of its FIFO up to
R_k - C_k after its nominal release, so the priority-queued analysis above takes it with
queuing jitter R_k - C_k (a frame below an unbounded FIFO frame is unbounded).  One FIFO
node at most (the rig has one, fcc; two would bound each other's jitter circularly).

The arithmetic is exact (fractions of a second): a response equal to a multiple of a period
must not round into one more interfering instance.
"""
from __future__ import annotations

import math
from collections.abc import Callable, Collection, Iterable, Mapping, Sequence
from dataclasses import dataclass, replace
from fractions import Fraction

from hil.bus.busload import worst_case_bits
from hil.bus.dbc import BusSpec, MessageSpec


@dataclass(frozen=True)
class Frame:
    """One cyclic frame stream: what the analysis needs of it."""

    frame_id: int
    name: str
    sender: str
    period_s: Fraction
    deadline_s: Fraction
    length: int = 8             # data bytes
    extended: bool = False      # 29-bit identifier
    jitter_s: Fraction = Fraction(0)

    @property
    def priority(self) -> tuple[int, int, int]:
        """Arbitration order, smaller wins: the 11 base identifier bits first, then an 11-bit
        frame over a 29-bit one (its RTR bit is dominant where the other sends SRR recessive),
        then the 18 extension bits."""
        if self.extended:
            return self.frame_id >> 18, 1, self.frame_id & 0x3FFFF
        return self.frame_id, 0, 0


@dataclass(frozen=True)
class Response:
    """A frame's frame time and worst-case response time (None: unbounded)."""

    frame: Frame
    c_s: Fraction
    wcrt_s: Fraction | None
    #: the sender's queue: "prio" (priority-ordered mailboxes) or "fifo"
    queue: str = "prio"

    @property
    def deadline_met(self) -> bool:
        return self.wcrt_s is not None and self.wcrt_s <= self.frame.deadline_s


def frame_time(frame: Frame, bitrate: int) -> Fraction:
    """C: the worst-case frame time including the interframe space."""
    return Fraction(worst_case_bits(frame.length, frame.extended), bitrate)


def utilisation(frames: Iterable[Frame], bitrate: int) -> Fraction:
    return sum((frame_time(f, bitrate) / f.period_s for f in frames), Fraction(0))


def seconds(value: float | int) -> Fraction:
    """A time given in decimal (a DBC's milliseconds, a command line's seconds) as the exact
    decimal it was written as, not its nearest binary float."""
    return Fraction(repr(float(value)))


def is_cyclic(message: MessageSpec) -> bool:
    """A cycle time, and a send type (GenMsgSendType) that is cyclic or not given."""
    if message.cycle_ms <= 0:
        return False
    send_type = message.message.send_type
    return send_type is None or "cyclic" in send_type.lower()


def cyclic_frames(spec: BusSpec) -> list[Frame]:
    """The DBC's cyclic frames: period GenMsgCycleTime, sender BO_'s, deadline = period (the
    DBC states no other deadline)."""
    frames = []
    for m in spec.messages:
        if is_cyclic(m):
            period = seconds(m.cycle_ms) / 1000
            frames.append(Frame(m.frame_id, m.name, ",".join(m.senders), period, period, m.length,
                                m.message.is_extended_frame))
    return frames


def with_periods(frames: Sequence[Frame], periods_s: Mapping[str, Fraction]) -> list[Frame]:
    """The frames with some periods (by name) replaced; deadline = the new period."""
    return [replace(f, period_s=periods_s[f.name], deadline_s=periods_s[f.name])
            if f.name in periods_s else f for f in frames]


def with_jitter(frames: Sequence[Frame], jitter_s: Fraction) -> list[Frame]:
    return [replace(f, jitter_s=jitter_s) for f in frames]


def _fixed_point(start: Fraction, step: Callable[[Fraction], Fraction]) -> Fraction:
    """Iterate x = step(x) from start until it stops changing (it is monotone and bounded
    when the utilisation is below 1)."""
    x = start
    while True:
        nxt = step(x)
        if nxt == x:
            return x
        x = nxt


def _interference(window: Fraction, hp: Sequence[Frame], c: Mapping[str, Fraction],
                  extra: Fraction) -> Fraction:
    return sum((math.ceil((window + k.jitter_s + extra) / k.period_s) * c[k.name] for k in hp),
               Fraction(0))


def _response(m: Frame, hp: Sequence[Frame], blocking: Fraction, c: Mapping[str, Fraction],
              tau_bit: Fraction) -> Fraction:
    """R_m of a frame whose hp(m) + {m} load the bus below 1."""
    cm = c[m.name]
    busy = _fixed_point(cm, lambda t: blocking + _interference(t, [*hp, m], c, Fraction(0)))
    instances = math.ceil((busy + m.jitter_s) / m.period_s)
    worst = Fraction(0)
    for q in range(instances):
        before = blocking + q * cm  # the blocking and the q earlier instances of m

        def delay(w: Fraction, before: Fraction = before) -> Fraction:
            return before + _interference(w, hp, c, tau_bit)

        w = _fixed_point(before, delay)
        worst = max(worst, m.jitter_s + w - q * m.period_s + cm)
    return worst


def analyse(frames: Sequence[Frame], bitrate: int, fifo: Collection[str] = ()) -> list[Response]:
    """Each frame's worst-case response time on a bus of `bitrate` bit/s, highest priority
    first; the frames of a sender in `fifo` (at most one node) wait in a FIFO."""
    if bitrate <= 0:
        raise ValueError(f"bit rate must be positive, not {bitrate}")
    ordered = sorted(frames, key=lambda f: f.priority)
    for a, b in zip(ordered, ordered[1:]):
        if a.priority == b.priority:
            raise ValueError(f"{a.name} and {b.name} share identifier {a.frame_id:#x}")
    senders = {f.sender for f in ordered if f.sender in fifo}
    if len(senders) > 1:
        raise ValueError(f"one FIFO-queued node at most, not {len(senders)} ({', '.join(sorted(senders))})")
    c = {f.name: frame_time(f, bitrate) for f in ordered}
    tau_bit = Fraction(1, bitrate)
    group = [f for f in ordered if f.sender in senders]
    fifo_r = {m.name: fifo_response(m, ordered, group, c, tau_bit) for m in group}
    seen = [_as_seen(f, fifo_r, c) for f in ordered]
    out = []
    for i, m in enumerate(ordered):
        if m.name in fifo_r:
            out.append(Response(m, c[m.name], fifo_r[m.name], "fifo"))
            continue
        hp, lp = seen[:i], ordered[i + 1:]
        if utilisation([*ordered[:i], m], bitrate) >= 1 or any(k is None for k in hp):
            out.append(Response(m, c[m.name], None))
            continue
        blocking = max((c[k.name] for k in lp), default=Fraction(0))
        out.append(Response(m, c[m.name], _response(m, [k for k in hp if k is not None], blocking, c, tau_bit)))
    return out


def _as_seen(f: Frame, fifo_r: Mapping[str, Fraction | None], c: Mapping[str, Fraction]) -> Frame | None:
    """What a priority-queued frame sees of f: a FIFO's frame released up to R_f - C_f late
    (None: unbounded), any other as it is."""
    if f.name not in fifo_r:
        return f
    r = fifo_r[f.name]
    return None if r is None else replace(f, jitter_s=max(f.jitter_s, r - c[f.name]))


def fifo_response(m: Frame, ordered: Sequence[Frame], group: Sequence[Frame], c: Mapping[str, Fraction],
                  tau_bit: Fraction) -> Fraction | None:
    """R_m of frame m of the FIFO `group` (the module's derivation), `ordered` every frame in
    priority order; None when F + hp(L) load the bus to 1 or more."""
    lowest = max(f.priority for f in group)
    members = {f.name for f in group}
    hp = [f for f in ordered if f.name not in members and f.priority < lowest]
    lp = [f for f in ordered if f.name not in members and f.priority > lowest]
    level = [*group, *hp]
    if sum((c[f.name] / f.period_s for f in level), Fraction(0)) >= 1:
        return None
    blocking = max((c[k.name] for k in lp), default=Fraction(0))
    busy = _fixed_point(blocking + sum((c[f.name] for f in level), Fraction(0)),
                        lambda t: blocking + _interference(t, level, c, Fraction(0)))
    starts = {Fraction(0)} | {x for k in group for q in range(1, math.ceil((busy + k.jitter_s) / k.period_s) + 1)
                              if 0 < (x := q * k.period_s - k.jitter_s) < busy}
    worst = Fraction(0)
    for x in sorted(starts):
        ahead = blocking - c[m.name] + sum(((math.floor((x + k.jitter_s) / k.period_s) + 1) * c[k.name]
                                            for k in group), Fraction(0))

        def delay(w: Fraction, ahead: Fraction = ahead) -> Fraction:
            return ahead + _interference(w, hp, c, tau_bit)

        worst = max(worst, m.jitter_s + _fixed_point(ahead, delay) + c[m.name] - x)
    return worst


#: the frames an application sends once per step, by name (as hil.bus.busload.default_rates
#: groups them), and the lockstep frames that run once per step of every application
APPLICATION_FRAMES = {"missile": ("MSL_",), "cdrw": ("CDRW_", "SID_")}
LOCKSTEP_FRAMES = ("SIM_TICK", "SIM_TICK_AUTH", "FCC_ACK")


def application_periods(frames: Iterable[Frame], aircraft: str, period_s: Fraction) -> dict[str, Fraction]:
    """The periods a flight of `aircraft` stepping every `period_s` gives: its own frames at
    its period, the lockstep frames at the shorter of theirs and its.  The other
    application's frames keep the DBC's periods (the bound then holds for both flying)."""
    prefixes = APPLICATION_FRAMES[aircraft]
    periods = {}
    for f in frames:
        if f.name.startswith(prefixes):
            periods[f.name] = period_s
        elif f.name in LOCKSTEP_FRAMES:
            periods[f.name] = min(f.period_s, period_s)
    return periods
