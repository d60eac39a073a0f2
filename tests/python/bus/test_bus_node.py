"""BusNode (FrameCodec + python-can + one Notifier) on python-can's in-process virtual bus.

The same class runs on vcan0 in test_bus_vcan.py; here it needs no kernel CAN.
"""
from __future__ import annotations

import threading
import uuid
from collections.abc import Iterator

import can
import pytest

from hil.bus import FCC_NODE, SIM_NODES
from hil.bus.codec import Decoded, EncodeError, Verdict
from hil.bus.e2e import E2EStatus
from hil.bus.node import BusNode


@pytest.fixture()
def pair() -> Iterator[tuple[BusNode, BusNode]]:
    chan = f"test-{uuid.uuid4()}"
    with BusNode(chan, SIM_NODES, interface="virtual") as sim, \
            BusNode(chan, FCC_NODE, interface="virtual") as fcc:
        yield sim, fcc


def test_lockstep_exchange(pair: tuple[BusNode, BusNode]) -> None:
    sim, fcc = pair
    for k in range(30):
        assert sim.send("CDRW_AOA", {"step": k, "alpha": 0.16})
        assert sim.send("SIM_TICK", {"app": 0, "step": k})
        tick = fcc.wait_for("SIM_TICK", 2.0)
        assert tick is not None and tick.values == {"app": 0, "step": k}
        assert fcc.end_period("CDRW_AOA") is False
        assert fcc.send("FCC_ACK", {"app": 0, "degraded": 0, "step": k, "exec_us": 120})
        ack = sim.wait_for("FCC_ACK", 2.0, match=lambda d, k=k: d.values["step"] == k)
        assert ack is not None and ack.e2e is E2EStatus.OK
    assert fcc.codec.counters.e2e[E2EStatus.OK] == 60
    assert sim.port.tx_frames == 60 and fcc.port.rx_frames >= 60


def test_filters_and_rejections(pair: tuple[BusNode, BusNode]) -> None:
    sim, fcc = pair
    sim.send_raw(0x124, bytes(8))                 # filtered away by the FCC node
    sim.send_raw(0x050, bytes(8))                 # CDRW_AOA with a bad CRC
    sim.send_raw(0x050, bytes(5))                 # wrong DLC
    got = [fcc.recv(2.0) for _ in range(2)]
    assert fcc.recv(0.2) is None
    assert [(d.verdict, d.e2e) for d in got if d] == [(Verdict.E2E, E2EStatus.ERROR),
                                                     (Verdict.WRONG_DLC, E2EStatus.OK)]
    with pytest.raises(EncodeError):
        fcc.send("SIM_TICK", {"app": 0, "step": 0})
    assert fcc.codec.counters.tx_refused == 1


def test_callback_mode_and_full_queue() -> None:
    chan = f"test-{uuid.uuid4()}"
    seen: list[Decoded] = []
    done = threading.Event()

    def on_frame(d: Decoded) -> None:
        seen.append(d)
        if len(seen) == 5:
            done.set()

    with BusNode(chan, FCC_NODE, interface="virtual", on_frame=on_frame), \
            BusNode(chan, SIM_NODES, interface="virtual") as sim:
        for k in range(5):
            sim.send("SIM_TICK", {"app": 1, "step": k})
        assert done.wait(2.0)
        assert [d.values["step"] for d in seen] == list(range(5))

        class Full(can.BusABC):  # a transmit queue that never drains (ENOBUFS forever)
            def __init__(self) -> None:
                super().__init__(channel="full")

            def send(self, msg: can.Message, timeout: float | None = None) -> None:
                raise can.CanOperationError("No buffer space available", error_code=105)

            def _recv_internal(self, timeout: float | None):
                return None, False

        real = sim.bus
        sim.bus = Full()
        try:
            assert sim.send("SIM_TICK", {"app": 1, "step": 99}) is False
        finally:
            sim.bus = real
        assert sim.port.tx_dropped == 1 and sim.port.tx_retries > 0
