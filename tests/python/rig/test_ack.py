"""The lockstep loop's reading of fcc's acknowledgement (hil.rig.ack): the same answer and the
same codec counters as the generic decode, for good, corrupted, repeated and foreign frames."""
from __future__ import annotations

from hil.bus import SIM_NODES, FrameCodec, load
from hil.bus.e2e import protect
from hil.rig.ack import AckReader, whole_width


def acks(n: int) -> list[bytes]:
    """fcc's acknowledgements of CDRW steps 0..n-1 (its own codec: counters 0, 1, ...)."""
    fcc = FrameCodec(load(), "FCC")
    return [fcc.encode("FCC_ACK", {"app": 0, "degraded": k % 2, "step": k, "exec_us": 30 + k})[1]
            for k in range(n)]


def generic(codec: FrameCodec, data: bytes, app: int, k: int) -> tuple[bool, int] | None:
    """What the loop read through FrameCodec.decode before AckReader."""
    dec = codec.decode(codec.spec.by_name("FCC_ACK").frame_id, data)
    v = dec.values
    if not dec.ok or v is None or int(v["app"]) != app or int(v["step"]) != k:
        return None
    return bool(v["degraded"]), int(v["exec_us"])


def test_the_dbcs_ack_is_read_directly():
    """FCC_ACK's degraded and exec_us cover their whole width: no range check to keep there."""
    spec = load()
    fields = {f.name: f for f in spec.by_name("FCC_ACK").data_fields}
    assert whole_width(fields["degraded"]) and whole_width(fields["exec_us"])
    assert not whole_width(fields["app"])   # 2 bits, 0..1: an app of 2 or 3 is out of range
    assert AckReader(FrameCodec(spec, SIM_NODES))._direct


def test_reads_as_the_generic_decode_and_counts_alike():
    frames = acks(40)
    bad_crc = bytes((frames[7][0] ^ 0xFF,)) + frames[7][1:]
    # the steps as the loop meets them: good, a repeated ACK (earlier step), a bad CRC, a
    # short frame, another application's, a jump of the alive counter, a replay
    app3 = FrameCodec(load(), "FCC")   # an application field out of its DBC range
    app3.senders["FCC_ACK"].counter = 5
    _, out_of_range = app3.encode("FCC_ACK", {"app": 1, "degraded": 0, "step": 5, "exec_us": 9})
    out_of_range = bytes((out_of_range[0], out_of_range[1] | 0x30)) + out_of_range[2:]
    out_of_range = protect(load().by_name("FCC_ACK").data_id, out_of_range, 5)
    seq = [(frames[0], 0, 0), (frames[1], 0, 1), (frames[1], 0, 2), (frames[2], 0, 2),
           (bad_crc, 0, 7), (frames[3][:6], 0, 3), (frames[3], 1, 3), (frames[4], 0, 4),
           (out_of_range, 0, 5), (frames[6], 0, 6),
           (frames[9], 0, 9), (frames[30], 0, 30), (frames[31], 0, 31), (frames[5], 0, 5)]
    spec = load()
    a, b = FrameCodec(spec, SIM_NODES), FrameCodec(spec, SIM_NODES)
    reader = AckReader(a)
    got = [reader.read(data, app, k) for data, app, k in seq]
    assert got == [generic(b, data, app, k) for data, app, k in seq]
    assert got[0] == (False, 30) and got[1] == (True, 31) and got[2] is None and got[3] == (False, 32)
    assert got[4] is None and got[5] is None and got[6] is None
    assert a.counters == b.counters
    assert a.receivers["FCC_ACK"].counts == b.receivers["FCC_ACK"].counts
    assert a.counters.wrong_dlc == 1 and sum(a.counters.e2e.values()) == len(seq) - 1
    assert a.counters.out_of_range == 1 and got[8] is None and got[9] == (False, 36)
