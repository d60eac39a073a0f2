"""A run of one secured PDU's recorded pairs (the frame, then its authenticator) verified in one
call: what Receiver.hold(pdu) then Receiver.verify(auth) give pair by pair, for the pairs that
verify in the simplest way (the recorded ticks of a lockstep flight: half the frames a bus log's
reader has to check).

A pair is taken here only while nothing else is held and its authenticator carries the next
message counter (FV's low 16 bits one above the last accepted counter's) with a MAC that
verifies; the receiver then advances exactly as verify() advances it (counter, verified).
The run stops before the first pair that does not: the caller hands that one to hold/verify,
which decide (and count) it as they always do.
"""
from __future__ import annotations

from collections.abc import Sequence

from hil.bus.secoc import FV_TRUNC_BITS, Receiver

_COUNTER_MAX = 0xFFFFFFFF


def verify_run(rx: Receiver, pdus: Sequence[bytes], auths: Sequence[bytes]) -> int:
    """How many of the leading pairs (pdus[i], auths[i]) verify one after the other from rx's
    state (module docstring); rx is advanced past them."""
    if rx.held:
        return 0
    keyed, data_id, fv0, c0 = rx.keyed, rx.data_id, rx.trip << 32, rx.counter
    low = (1 << FV_TRUNC_BITS) - 1
    n = 0
    for pdu, auth in zip(pdus, auths):
        c = c0 + n + 1
        if (c > _COUNTER_MAX or len(pdu) != 8 or len(auth) != 8
                or int.from_bytes(auth[:2], "little") != c & low
                or keyed.mac(data_id, pdu, fv0 | c) != auth[2:]):
            break
        n += 1
    rx.counter += n
    rx.counters.verified += n
    return n
