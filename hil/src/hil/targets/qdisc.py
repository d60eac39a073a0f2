"""Frames an interface's transmit queue has dropped, read over rtnetlink (what `tc -s qdisc show
dev IFACE` prints as "dropped"), without starting a process: the M4F target asks every second
during a flight, and a `tc` process a second cost the emulated line's steps several per cent in
the User-Mode Linux guest.

    drops("slc123")  -> 0    (OSError when the interface or netlink is not there)
"""
from __future__ import annotations

import socket
import struct

RTM_NEWQDISC, RTM_GETQDISC = 36, 38
NLM_F_REQUEST, NLM_F_DUMP = 0x1, 0x300
NLMSG_ERROR, NLMSG_DONE = 2, 3
TCA_STATS2, TCA_STATS_QUEUE = 7, 3
NLMSG_HDR = struct.Struct("=IHHII")   # length, type, flags, sequence, port
TCMSG = struct.Struct("=BxxxiIII")     # family, ifindex, handle, parent, info
RTATTR = struct.Struct("=HH")          # length, type
QUEUE_STATS = struct.Struct("=IIIII")  # gnet_stats_queue: qlen, backlog, drops, requeues, overlimits


def _attrs(data: bytes) -> dict[int, bytes]:
    """The netlink attributes of data (type -> payload; 4-byte aligned)."""
    out, i = {}, 0
    while i + RTATTR.size <= len(data):
        length, kind = RTATTR.unpack_from(data, i)
        if length < RTATTR.size:
            break
        out[kind & 0x3FFF] = data[i + RTATTR.size:i + length]
        i += (length + 3) & ~3
    return out


def _queue_drops(payload: bytes) -> int:
    """The drop count of one RTM_NEWQDISC message's payload (after its tcmsg)."""
    stats = _attrs(payload).get(TCA_STATS2)
    queue = _attrs(stats).get(TCA_STATS_QUEUE) if stats is not None else None
    if queue is None or len(queue) < QUEUE_STATS.size:
        return 0
    return QUEUE_STATS.unpack_from(queue)[2]


def drops(iface: str) -> int:
    """Frames dropped by every queueing discipline of iface since it was set up."""
    index = socket.if_nametoindex(iface)
    total = 0
    with socket.socket(socket.AF_NETLINK, socket.SOCK_RAW, socket.NETLINK_ROUTE) as nl:
        body = TCMSG.pack(socket.AF_UNSPEC, index, 0, 0, 0)
        nl.send(NLMSG_HDR.pack(NLMSG_HDR.size + len(body), RTM_GETQDISC,
                               NLM_F_REQUEST | NLM_F_DUMP, 1, 0) + body)
        while True:
            data = nl.recv(65536)
            i = 0
            while i + NLMSG_HDR.size <= len(data):
                length, kind, _, _, _ = NLMSG_HDR.unpack_from(data, i)
                if length < NLMSG_HDR.size:
                    raise OSError(f"rtnetlink: a malformed answer about {iface}'s queue")
                msg = data[i + NLMSG_HDR.size:i + length]
                if kind == NLMSG_DONE:
                    return total
                if kind == NLMSG_ERROR:
                    raise OSError(f"rtnetlink refused the queue statistics of {iface}")
                if kind == RTM_NEWQDISC and len(msg) >= TCMSG.size and \
                        TCMSG.unpack_from(msg)[1] == index:
                    total += _queue_drops(msg[TCMSG.size:])
                i += (length + 3) & ~3


__all__ = ["drops"]
