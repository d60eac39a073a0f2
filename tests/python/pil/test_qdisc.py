"""hil.targets.qdisc: an interface's queue drops over rtnetlink (the M4F line's loss check;
its drops on a real slcan queue: test_pil_line.py)."""
from __future__ import annotations

import pytest

from hil.targets import qdisc


def test_the_loopback_queue_has_dropped_nothing():
    assert qdisc.drops("lo") == 0


def test_an_interface_that_is_not_there_is_an_os_error():
    with pytest.raises(OSError):
        qdisc.drops("nosuchif0")


def test_the_drop_count_is_read_from_the_nested_queue_statistics():
    queue = qdisc.RTATTR.pack(4 + qdisc.QUEUE_STATS.size, qdisc.TCA_STATS_QUEUE) + \
        qdisc.QUEUE_STATS.pack(3, 66, 17, 0, 0)
    stats2 = qdisc.RTATTR.pack(4 + len(queue), qdisc.TCA_STATS2 | 0x8000) + queue   # nested flag
    kind = qdisc.RTATTR.pack(4 + 11, 1) + b"pfifo_fast\0" + b"\0"                   # padded to 4
    assert qdisc._queue_drops(kind + stats2) == 17
    assert qdisc._queue_drops(kind) == 0
