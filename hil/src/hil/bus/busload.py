"""Length of classic CAN frames on the wire and the load they put on a bus.

A classic data frame with an 11-bit identifier and n data bytes has 34 + 8n bits
between the start of frame and the end of the CRC that are subject to bit
stuffing (a complement bit after five equal bits), then 13 fixed bits: CRC
delimiter, ACK slot and delimiter, 7 bits end of frame, 3 bits interframe space.
So its length is 47 + 8n + s bits, s stuff bits, and s <= floor((34 + 8n - 1)/4)
in the worst case (Davis, Burns, Bril, Lukkien 2007): 135 bits for n = 8.
frame_bits() computes s exactly by building the bit stream with its CRC-15.
"""
from __future__ import annotations

from collections.abc import Iterable, Sequence

CAN_CRC15_POLY = 0x4599
FIXED_TAIL_BITS = 13  # CRC delimiter, ACK slot, ACK delimiter, EOF (7), IFS (3)


def nominal_bits(n: int, extended: bool = False) -> int:
    """Frame length without stuff bits."""
    return (67 if extended else 47) + 8 * n


def worst_case_bits(n: int, extended: bool = False) -> int:
    """Frame length with the worst possible bit stuffing."""
    g = 54 if extended else 34
    return nominal_bits(n, extended) + (g + 8 * n - 1) // 4


def _crc15(bits: Sequence[int]) -> int:
    crc = 0
    for b in bits:
        nxt = b ^ ((crc >> 14) & 1)
        crc = (crc << 1) & 0x7FFF
        if nxt:
            crc ^= CAN_CRC15_POLY
    return crc


def _bits(value: int, width: int) -> list[int]:
    return [(value >> (width - 1 - i)) & 1 for i in range(width)]


def _stuff_count(bits: Sequence[int]) -> int:
    count, run, last = 0, 0, None
    for b in bits:
        if b == last:
            run += 1
        else:
            run, last = 1, b
        if run == 5:
            count += 1
            # the stuff bit is the complement and starts a new run
            last, run = 1 - b, 1
    return count


def frame_bits(frame_id: int, data: bytes | bytearray, extended: bool = False,
               remote: bool = False) -> int:
    """Exact length on the wire of one classic CAN frame (interframe space included)."""
    n = len(data)
    if n > 8:
        raise ValueError(f"classic CAN frames carry at most 8 bytes, not {n}")
    if extended:
        head = ([0] + _bits(frame_id >> 18, 11) + [1, 1] + _bits(frame_id & 0x3FFFF, 18)
                + [1 if remote else 0, 0, 0])
    else:
        head = [0] + _bits(frame_id, 11) + [1 if remote else 0, 0, 0]
    body = head + _bits(n, 4) + ([] if remote else [b for byte in data for b in _bits(byte, 8)])
    stuffed_region = body + _bits(_crc15(body), 15)
    return len(stuffed_region) + _stuff_count(stuffed_region) + FIXED_TAIL_BITS


def load_percent(bits_per_second: float, baudrate: int) -> float:
    return 100.0 * bits_per_second / baudrate


def default_rates(message_names: Iterable[str], cycle_ms: dict[str, int], *,
                  cdrw_hz: float = 50.0, missile_period_s: float = 0.05,
                  status_hz: float = 10.0) -> dict[str, float]:
    """Frames per second of each cyclic message at the rig's default rates.

    SIM_TICK and FCC_ACK run once per step of each application; MSL_* frames once
    per missile period; FCC_* status frames at status_hz; TSYNC_* (time sync) at their
    own GenMsgCycleTime; the other cyclic frames (CDRW sensors and identification
    outputs) at cdrw_hz.  Event frames: 0.
    """
    rates: dict[str, float] = {}
    missile_hz = 1.0 / missile_period_s
    for name in message_names:
        if name in ("SIM_TICK", "SIM_TICK_AUTH", "FCC_ACK"):
            rates[name] = cdrw_hz + missile_hz
        elif not cycle_ms.get(name):
            rates[name] = 0.0
        elif name.startswith("MSL_"):
            rates[name] = missile_hz
        elif name.startswith("TSYNC_"):
            rates[name] = 1000.0 / cycle_ms[name]
        elif name.startswith("FCC_"):
            rates[name] = status_hz
        else:
            rates[name] = cdrw_hz
    return rates
