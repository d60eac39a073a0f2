"""The types of `hil`'s option values: each turns the text of one option into its value or
refuses it in one line (argparse prints it as the usage error, exit 2)."""
from __future__ import annotations

import argparse
import math


def floats(text: str) -> list[float]:
    try:
        vals = [float(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected numbers separated by commas, got {text!r}") from None
    if not vals or not all(math.isfinite(v) and v > 0 for v in vals):
        raise argparse.ArgumentTypeError(f"expected positive numbers separated by commas, got {text!r}")
    return vals


def ints(text: str) -> list[int]:
    try:
        vals = [int(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected whole numbers separated by commas, got {text!r}") from None
    if not vals:
        raise argparse.ArgumentTypeError("expected at least one number")
    return vals


def seed(text: str) -> int:
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 0, got {text!r}") from None
    if v < 0:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 0, got {text!r}")
    return v


def positive(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not (math.isfinite(v) and v > 0):
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text!r}")
    return v


def bitrate(text: str) -> int:
    """Bits per second: 500000, or with a k or M suffix (500k, 1M)."""
    scale = {"k": 1_000, "M": 1_000_000}.get(text[-1:], 1)
    try:
        v = int(text[:-1] if scale > 1 else text) * scale
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected bits per second, e.g. 500000 or 500k, got {text!r}") from None
    if not 10_000 <= v <= 1_000_000:
        raise argparse.ArgumentTypeError(f"expected 10000 to 1000000 bit/s, got {v}")
    return v


def nonnegative(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not (math.isfinite(v) and v >= 0):
        raise argparse.ArgumentTypeError(f"expected a number >= 0, got {text!r}")
    return v


def bitrates(text: str) -> list[int]:
    """Bit rates separated by commas: 125k,250k,500k,1M."""
    vals = [bitrate(x.strip()) for x in text.split(",") if x.strip()]
    if not vals:
        raise argparse.ArgumentTypeError("expected at least one bit rate")
    return vals


def utilisations(text: str) -> list[float]:
    """Shares of the bus separated by commas, each in [0, 1): 0,0.2,0.4."""
    try:
        vals = [float(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected numbers separated by commas, got {text!r}") from None
    if not vals or not all(0.0 <= v < 1.0 for v in vals):
        raise argparse.ArgumentTypeError(f"expected shares of the bus in [0, 1) separated by commas, got {text!r}")
    return vals


def id_range(text: str) -> tuple[int, int]:
    """Two 11-bit identifiers LO-HI (hexadecimal with 0x, or decimal): 0x004-0x00f."""
    try:
        lo, hi = (int(x, 0) for x in text.split("-"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected LO-HI, e.g. 0x004-0x00f, got {text!r}") from None
    if not 0 <= lo <= hi <= 0x7FF:
        raise argparse.ArgumentTypeError(f"expected 0 <= LO <= HI <= 0x7ff, got {text!r}")
    return lo, hi


def rate_and_load(text: str) -> tuple[int, float]:
    """A bit rate and a share of the bus: 250k,0.5."""
    rate, sep, load = text.partition(",")
    if not sep:
        raise argparse.ArgumentTypeError(f"expected RATE,LOAD, e.g. 250k,0.5, got {text!r}")
    return bitrate(rate.strip()), utilisations(load)[0]
