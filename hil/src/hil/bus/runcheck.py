"""A run of recorded frames checked in one call, as the live link's receivers check them one at
a time: the ticks of a lockstep flight (SecOC pair, then E2E) are half the frames a bus log's
reader checks, and a call per frame was most of reading the log.

Each function takes the leading frames that pass in the simplest way and advances the receiver
exactly as the frame-by-frame calls would; it stops before the first frame that does not, which
the caller hands to those calls (they decide and count it as they always do).

* verify_run: pairs (the secured frame, or a group's frames, then its authenticator) of one
  PDU, Receiver.hold then Receiver.verify (GroupReceiver.hold_frame then verify_group), while
  nothing else is held and each authenticator carries the next message counter (FV's low 16
  bits one above the last accepted counter's) with a MAC that verifies (the run's
  authenticators made together: hil.bus.secoc_batch.authenticators).
* check_run: frames of one E2E-protected message, E2EReceiver.check, while each is OK: its CRC
  right and its alive counter one above the last (any, for the first after a reset).
"""
from __future__ import annotations

import numpy as np

from hil.bus.e2e import COUNTER_MODULO, FRAME_LENGTH, E2EReceiver, E2EStatus, protect_many
from hil.bus.secoc import Receiver
from hil.bus.secoc_batch import authenticators

_COUNTER_MAX = 0xFFFFFFFF


def verify_run(rx: Receiver, pdus: np.ndarray, auths: np.ndarray) -> int:
    """How many of the leading pairs (pdus[i], auths[i]: (n, 8) uint8 each; a group's pdus
    (n, 8 m): its m frames concatenated, GroupReceiver.verify_group's) verify one after the
    other from rx's state (module docstring); rx is advanced past them."""
    n = len(pdus)
    if rx.held or not n or pdus.ndim != 2 or pdus.shape[1] % 8 or auths.shape != (n, 8):
        return 0
    # each the authenticator the sender makes at the next counter: its low bits, then the MAC
    expected = authenticators(rx.key, rx.data_id, pdus, rx.trip, rx.counter + 1)
    ok = (expected == auths).all(axis=1) & (rx.counter + 1 + np.arange(n) <= _COUNTER_MAX)
    n = int(np.argmin(ok)) if not ok.all() else n
    rx.counter += n
    rx.counters.verified += n
    return n


def check_run(rx: E2EReceiver, frames: np.ndarray) -> int:
    """How many of the leading frames ((n, 8) uint8) rx classifies OK one after the other
    (module docstring); rx is advanced past them."""
    if frames.ndim != 2 or frames.shape[1] != FRAME_LENGTH or not len(frames):
        return 0
    counters = frames[:, 1] & 0x0F
    first = int(counters[0]) if not rx.synced else (rx.last_counter + 1) % COUNTER_MODULO
    ok = ((protect_many(rx.data_id, frames, counters)[:, 0] == frames[:, 0])   # the CRC
          & (counters == (first + np.arange(len(frames))) % COUNTER_MODULO))
    n = int(np.argmin(ok)) if not ok.all() else len(frames)
    if n:
        rx.frames_this_period += n
        rx.counts[E2EStatus.OK] += n
        rx.last_status = E2EStatus.OK
        rx.synced, rx.last_counter = True, int(counters[n - 1])
    return n
