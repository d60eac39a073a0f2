"""A classic CAN frame's exact length on the wire (hil.bus.busload.frame_bits) against two
independent computations, for 11- and 29-bit identifiers and every DLC 0-8:

* ISO 11898-1's rule applied here to the frame's bits written out as text: CRC-15 by
  polynomial long division (not a shift register), bit stuffing by scanning the text;
* can-utils' `canbusload -e` (exact stuffing of received frames; in the guest, on vcan: run
  inside scripts/with-vcan) over a candump log replayed by canplayer, one interface per
  (identifier length, DLC) so that each class is counted on its own.

    scripts/with-vcan .venv/bin/python -m pytest -m vcan tests/python/bus/test_wiretime.py
"""
from __future__ import annotations

import random
import re
import select
import subprocess
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from hil.bus.busload import frame_bits, nominal_bits, worst_case_bits
from hil.bus.candump import format_line

#: x^15 + x^14 + x^10 + x^8 + x^7 + x^4 + x^3 + 1: ISO 11898-1's generator (0x4599 + x^15)
GENERATOR = 0xC599
DLCS = range(9)


def iso_crc15(bits: str) -> int:
    """The remainder of bits * x^15 divided by the generator, mod 2 (long division)."""
    rem = int(bits, 2) << 15
    for shift in range(rem.bit_length() - 16, -1, -1):
        if rem >> (shift + 15) & 1:
            rem ^= GENERATOR << shift
    return rem


def iso_stuffed(bits: str) -> str:
    """The bits as sent: after five equal bits their complement, which starts the next run."""
    out = ""
    for b in bits:
        out += b
        if out.endswith(b * 5) and not out[:-5].endswith(b):  # five of them since the last change
            out += "1" if b == "0" else "0"
    return out


def iso_frame_bits(frame_id: int, data: bytes, extended: bool) -> int:
    """SOF, arbitration, control, data and CRC sequence stuffed; then CRC delimiter, ACK slot
    and delimiter, EOF (7) and the interframe space (3): 13 bits."""
    # 29-bit: base identifier, SRR (1), IDE (1), extension, RTR (0), r1, r0;
    # 11-bit: identifier, RTR (0), IDE (0), r0
    head = (f"0{frame_id >> 18:011b}11{frame_id & 0x3FFFF:018b}000" if extended
            else f"0{frame_id:011b}000")
    body = head + f"{len(data):04b}" + "".join(f"{b:08b}" for b in data)
    return len(iso_stuffed(body + f"{iso_crc15(body):015b}")) + 13


def test_the_iso_rule_written_out() -> None:
    # the CRC of a message that is only the generator's own low bits' pattern: x^15 mod g
    assert iso_crc15("1") == GENERATOR ^ (1 << 15) == 0x4599
    assert iso_crc15("0" * 20) == 0
    assert iso_stuffed("00000") == "000001"
    assert iso_stuffed("000000000") == "0000010000"       # the stuff bit ends the run
    assert iso_stuffed("0000011111") == "000001111101"     # ... and counts in the next one
    assert iso_stuffed("0000" + "1111") == "00001111"
    # an 8-byte 11-bit frame without stuffing is 111 bits, at worst 135 (SPEC §8); 29-bit: 131, 160
    assert (nominal_bits(8), worst_case_bits(8)) == (111, 135)
    assert (nominal_bits(8, True), worst_case_bits(8, True)) == (131, 160)
    assert [nominal_bits(n) for n in DLCS] == [47 + 8 * n for n in DLCS]


def frames(extended: bool, dlc: int, count: int, seed: int) -> Iterator[tuple[int, bytes]]:
    """Frames of one class: the stuffing-heavy extremes, then random ones."""
    top = (1 << 29) - 1 if extended else 0x7FF
    for frame_id, byte in ((0, 0x00), (top, 0xFF), (top // 3, 0x55), (1, 0x0F), (top - 1, 0xF0)):
        yield frame_id, bytes([byte] * dlc)
    rng = random.Random(seed)
    for _ in range(count):
        yield rng.randint(0, top), rng.randbytes(dlc)


@pytest.mark.parametrize("extended", [False, True], ids=["11-bit", "29-bit"])
@pytest.mark.parametrize("dlc", DLCS)
def test_frame_bits_is_iso_11898_1s_rule(extended: bool, dlc: int) -> None:
    for frame_id, data in frames(extended, dlc, 300, seed=dlc + 9 * extended):
        bits = frame_bits(frame_id, data, extended)
        assert bits == iso_frame_bits(frame_id, data, extended), (hex(frame_id), data.hex())
        assert nominal_bits(dlc, extended) <= bits <= worst_case_bits(dlc, extended)


# ---- canbusload -e, on vcan ----------------------------------------------------------------
CLASSES = [(extended, dlc) for extended in (False, True) for dlc in DLCS]
PER_CLASS = 40
LINE = re.compile(r"^\s*(\w+)@\d+\s+(\d+)\s+(\d+)\s+\d+")


def iface(extended: bool, dlc: int) -> str:
    return f"wt{'e' if extended else 's'}{dlc}"


Counts = dict[str, tuple[int, int]]  # interface: (frames, bits)


def read_blocks(proc: subprocess.Popen[str], ifaces: list[str], deadline: float) -> Iterator[Counts]:
    """canbusload's output, one {interface: (frames, bits)} per second it prints."""
    assert proc.stdout is not None
    block: Counts = {}
    while time.monotonic() < deadline:
        ready, _, _ = select.select([proc.stdout], [], [], max(0.0, deadline - time.monotonic()))
        line = proc.stdout.readline() if ready else ""
        assert line, f"canbusload stopped or fell silent: {proc.poll()}"
        m = LINE.match(line)
        if m and m.group(1) in ifaces:
            block[m.group(1)] = (int(m.group(2)), int(m.group(3)))
            if len(block) == len(ifaces):
                yield block
                block = {}
    raise AssertionError("canbusload did not count every frame within 60 s")


@pytest.mark.vcan
def test_frame_bits_is_canbusloads_exact_count(tmp_path: Path) -> None:
    log, expected = [], {}
    for extended, dlc in CLASSES:
        name = iface(extended, dlc)
        batch = list(frames(extended, dlc, PER_CLASS, seed=100 + dlc + 9 * extended))
        log += [format_line(0.0, name, fid, data, extended) for fid, data in batch]
        expected[name] = (len(batch), sum(frame_bits(fid, data, extended) for fid, data in batch))
    (tmp_path / "frames.log").write_text("\n".join(log) + "\n")
    names = list(expected)
    for name in names:
        subprocess.run(["ip", "link", "add", "dev", name, "type", "vcan"], check=True)
        subprocess.run(["ip", "link", "set", name, "up"], check=True)
    halves = (names[:9], names[9:])  # canbusload takes up to 16 interfaces
    procs = [subprocess.Popen(["stdbuf", "-oL", "canbusload", "-e", *(f"{n}@500000" for n in half)],
                              stdout=subprocess.PIPE, text=True) for half in halves]
    try:
        deadline = time.monotonic() + 60
        readers = [read_blocks(p, list(half), deadline) for p, half in zip(procs, halves)]
        for r in readers:  # a first report: canbusload's sockets are open, nothing sent yet
            assert all(v == (0, 0) for v in next(r).values())
        subprocess.run(["canplayer", "-t", "-I", str(tmp_path / "frames.log")], check=True)
        counted = dict.fromkeys(names, (0, 0))
        for r, half in zip(readers, halves):
            while any(counted[n][0] < expected[n][0] for n in half):
                for n, (k, bits) in next(r).items():
                    counted[n] = (counted[n][0] + k, counted[n][1] + bits)
        assert counted == expected
    finally:
        for p in procs:
            p.terminate()
            p.wait(timeout=10)
        for name in names:
            subprocess.run(["ip", "link", "del", "dev", name], check=False)
