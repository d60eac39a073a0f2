"""hil.bus.mmsg.BatchSender on a host socket (no CAN needed): a connected UDP pair, each
datagram one packed frame, shows what one sendmmsg(2) sent and in which order."""
from __future__ import annotations

import errno
import socket
from collections.abc import Iterator

import pytest

from hil.bus.mmsg import FRAME_BYTES, MSG_WAITFORONE, BatchReceiver, BatchSender
from hil.bus.rawcan import pack_frame

pytestmark = pytest.mark.skipif(not (BatchSender.available() and BatchReceiver.available()),
                                reason="no sendmmsg or recvmmsg in libc")


@pytest.fixture
def pair() -> Iterator[tuple[socket.socket, socket.socket]]:
    """(sender connected to receiver, receiver) on the loopback."""
    rx = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    tx = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    rx.bind(("127.0.0.1", 0))
    rx.settimeout(5.0)
    tx.connect(rx.getsockname())
    yield tx, rx
    tx.close()
    rx.close()


def frames(n: int, base: int = 0x100) -> list[bytes]:
    return [pack_frame(base + i, bytes([i & 0xFF, i >> 8, 0xA5])) for i in range(n)]


def received(rx: socket.socket, n: int) -> list[bytes]:
    return [rx.recv(64) for _ in range(n)]


def test_a_batch_goes_out_whole_and_in_order(pair: tuple[socket.socket, socket.socket]) -> None:
    tx, rx = pair
    sender = BatchSender(tx.fileno())
    batch = frames(5)
    assert sender.load(batch) == 5
    assert sender.send(0, 5) == 5
    assert received(rx, 5) == batch


def test_a_smaller_batch_after_a_larger_one_sends_only_its_own_frames(
        pair: tuple[socket.socket, socket.socket]) -> None:
    tx, rx = pair
    sender = BatchSender(tx.fileno())
    sender.load(frames(7))
    assert sender.send(0, 7) == 7
    second = frames(2, base=0x200)
    assert sender.load(second) == 2
    assert sender.send(0, 2) == 2
    assert received(rx, 9)[7:] == second


def test_a_send_from_a_later_frame_resumes_there(pair: tuple[socket.socket, socket.socket]) -> None:
    """What send_many does after a partial send: the rest, from the first frame not sent."""
    tx, rx = pair
    sender = BatchSender(tx.fileno())
    batch = frames(6)
    sender.load(batch)
    assert sender.send(4, 6) == 2
    assert received(rx, 2) == batch[4:]


def test_load_takes_at_most_capacity_frames(pair: tuple[socket.socket, socket.socket]) -> None:
    tx, rx = pair
    sender = BatchSender(tx.fileno())
    batch = frames(BatchSender.CAPACITY + 3)
    assert sender.load(batch) == BatchSender.CAPACITY
    assert sender.send(0, BatchSender.CAPACITY) == BatchSender.CAPACITY
    assert received(rx, BatchSender.CAPACITY) == batch[:BatchSender.CAPACITY]


def test_a_frame_that_is_not_a_packed_can_frame_is_refused(pair: tuple[socket.socket, socket.socket]) -> None:
    sender = BatchSender(pair[0].fileno())
    with pytest.raises(ValueError, match=f"{FRAME_BYTES} bytes"):
        sender.load([pack_frame(0x100, b"x"), b"short"])


def test_a_failed_send_gives_its_errno() -> None:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as unconnected:
        sender = BatchSender(unconnected.fileno())
        sender.load(frames(2))
        assert sender.send(0, 2) == -errno.EDESTADDRREQ


# -- BatchReceiver: the datagrams queued on the receiver, in one recvmmsg(2)

def test_one_receive_takes_every_queued_frame_in_order(pair: tuple[socket.socket, socket.socket]) -> None:
    tx, rx = pair
    batch = frames(4)
    for raw in batch:
        tx.send(raw)
    receiver = BatchReceiver(rx.fileno())
    got = receiver.receive(MSG_WAITFORONE)
    assert got == 4 and receiver.frames(got) == batch
    assert receiver.receive(socket.MSG_DONTWAIT) == -errno.EAGAIN   # the queue is empty now


def test_a_receive_takes_at_most_capacity_frames(pair: tuple[socket.socket, socket.socket]) -> None:
    tx, rx = pair
    batch = frames(BatchReceiver.CAPACITY + 2)
    for raw in batch:
        tx.send(raw)
    receiver = BatchReceiver(rx.fileno())
    assert receiver.frames(receiver.receive(MSG_WAITFORONE)) == batch[:BatchReceiver.CAPACITY]
    assert receiver.frames(receiver.receive(MSG_WAITFORONE)) == batch[BatchReceiver.CAPACITY:]


def test_a_message_of_another_size_is_left_out(pair: tuple[socket.socket, socket.socket]) -> None:
    tx, rx = pair
    good = frames(2)
    tx.send(good[0])
    tx.send(b"short")
    tx.send(good[1])
    receiver = BatchReceiver(rx.fileno())
    got = receiver.receive(MSG_WAITFORONE)
    assert got == 3 and receiver.frames(got) == good
