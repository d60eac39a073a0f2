"""Worst-case response times of a CAN bus's cyclic frames (Davis, Burns, Bril, Lukkien 2007).

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

Every node is taken as priority-queued (its controller presents its highest-priority pending
frame to arbitration).  FIFO-queued nodes need Davis, Kollmann, Pollex and Slomka 2011's
extension, which is not implemented.

The arithmetic is exact (fractions of a second): a response equal to a multiple of a period
must not round into one more interfering instance.
"""
from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping, Sequence
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


def analyse(frames: Sequence[Frame], bitrate: int) -> list[Response]:
    """Each frame's worst-case response time on a bus of `bitrate` bit/s, highest priority
    first."""
    if bitrate <= 0:
        raise ValueError(f"bit rate must be positive, not {bitrate}")
    ordered = sorted(frames, key=lambda f: f.priority)
    for a, b in zip(ordered, ordered[1:]):
        if a.priority == b.priority:
            raise ValueError(f"{a.name} and {b.name} share identifier {a.frame_id:#x}")
    c = {f.name: frame_time(f, bitrate) for f in ordered}
    tau_bit = Fraction(1, bitrate)
    out = []
    for i, m in enumerate(ordered):
        hp, lp = ordered[:i], ordered[i + 1:]
        if utilisation([*hp, m], bitrate) >= 1:
            out.append(Response(m, c[m.name], None))
            continue
        blocking = max((c[k.name] for k in lp), default=Fraction(0))
        out.append(Response(m, c[m.name], _response(m, hp, blocking, c, tau_bit)))
    return out


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
