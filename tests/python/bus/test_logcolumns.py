"""The column reader of candump -L logs (hil.bus.logcolumns) gives candump.read_log's classic
data frames, whatever the lines, and refuses what read_log refuses with read_log's message."""
from __future__ import annotations

import random

import pytest

from hil.bus.candump import LogFormatError, read_log
from hil.bus.logcolumns import FrameColumns, read_blocks, read_columns

#: a rig's log: one layout, line after line
PLAIN = [f"(1795751968.{505391 + i:06d}) vcan0 {0x110 + i % 36:03X}#{(i * 0x0123456789ABCDEF) % (1 << 64):016X}"
         for i in range(300)]
#: other spacing, extended, remote, error and FD frames, blank lines, short frames, lowercase
ODD = ["(1000.000001) vcan0 110#0102030405060708", "", "  (1000.1) can1   7FF#  ",
       "(1000.2) vcan0 12345678#AABB", "(1000.3) vcan0 123#R", "(1000.4) vcan0 20000080#0000000000000000",
       "(1000.5) vcan0 123##1AABB", "(1000.6) vcan0 0A0#", "(1000.7) vcan0 1fe#abcdef\t",
       "(1000.8)\tvcan0 028#00", "(1000) vcan0 028#0011", "(1000.9) vc\xe9n0 110#0102030405060708"]


def read_log_frames(path) -> list[tuple[int, bytes]]:
    return [(f.frame_id, f.data) for f in read_log(path) if f.classic_data]


def columns(path) -> list[tuple[int, bytes]]:
    return FrameColumns.concat(read_columns(path)).tuples()


def write(path, lines: list[str], end: str = "\n", newline: str = "\n") -> None:
    path.write_bytes((newline.join(lines) + end).encode("latin-1"))


@pytest.mark.parametrize("newline", ["\n", "\r\n", "\r"])
@pytest.mark.parametrize("end", ["\n", ""])
def test_the_frames_of_read_log_across_blocks(tmp_path, monkeypatch, newline, end):
    monkeypatch.setattr("hil.bus.logcolumns.BLOCK_BYTES", 100)   # many blocks
    log = tmp_path / "bus.log"
    lines = PLAIN[:50] + ODD * 4 + PLAIN[50:]
    write(log, lines, end and newline, newline)
    want = read_log_frames(log)
    assert columns(log) == want and len(want) == 300 + 4 * 7


def test_a_plain_log_is_read_whole(tmp_path):
    log = tmp_path / "bus.log"
    write(log, PLAIN)
    assert columns(log) == read_log_frames(log) and len(columns(log)) == 300


def refusal(path, read) -> str:
    with pytest.raises(LogFormatError) as exc:
        read(path)
    return str(exc.value)


@pytest.mark.parametrize("bad", ["(1000.9) vcan0 123#ABC", "(1795751968.505391) vcan0 110#073E0081FF02A0G0",
                                 "(1795751968.50539x) vcan0 110#073E0081FF02A000",
                                 "(1795751968.505391)_vcan0 110#073E0081FF02A000", "garbage"])
def test_a_malformed_line_is_refused_as_read_log_refuses_it(tmp_path, bad):
    log = tmp_path / "bus.log"
    write(log, PLAIN[:30] + [bad] + PLAIN[30:])
    assert refusal(log, columns) == refusal(log, read_log_frames)
    assert refusal(log, columns).startswith("line 31:")


def test_any_one_changed_byte_reads_or_fails_as_read_log(tmp_path):
    """A byte of a plain log replaced by another, 400 times: the same frames, or the same
    refusal, as read_log."""
    rng = random.Random(26)
    text = "\n".join(PLAIN[:40]) + "\n"
    log = tmp_path / "bus.log"
    alphabet = b"0123456789abcdefABCDEFG.()# \t\x0b\x1cvcan\xff\r\n-#R"
    outcomes = set()
    for _ in range(400):
        raw = bytearray(text.encode("ascii"))
        raw[rng.randrange(len(raw))] = rng.choice(alphabet)
        log.write_bytes(bytes(raw))
        try:
            want = read_log_frames(log)
        except LogFormatError as exc:
            assert refusal(log, columns) == str(exc), bytes(raw)
            outcomes.add("refused")
        else:
            assert columns(log) == want, bytes(raw)
            outcomes.add("read")
    assert outcomes == {"read", "refused"}


@pytest.mark.parametrize("newline", ["\n", "\r\n"])
def test_blocks_hold_every_frame_of_read_log(tmp_path, monkeypatch, newline):
    """read_blocks: every frame read_log gives, in order; a frame of the common layout as
    columns, its line's text after the timestamp kept, any other as read_log reads it."""
    monkeypatch.setattr("hil.bus.logcolumns.BLOCK_BYTES", 100)
    log = tmp_path / "bus.log"
    write(log, PLAIN[:50] + ODD * 4 + PLAIN[50:], newline, newline)
    got = []
    for block in read_blocks(log):
        for i in range(len(block)):
            if i in block.odd:
                assert block.tails[i] == -1
                got.append(block.odd[i])
            else:
                text = block.text[block.tails[i]: block.ends[i]].decode()
                fid, data = block.frames.frame(i)
                got.append(("plain", fid, data, text))
    want = list(read_log(log))
    assert len(got) == len(want) == 300 + 4 * 11
    for g, w in zip(got, want):
        if isinstance(g, tuple):
            assert g[1:] == (w.frame_id, w.data, f") {w.channel} {w.frame_id:03X}#{w.data.hex().upper()}")
        else:
            assert g == w
