"""Rounding as the firmware does it, shared by the bus codec and the D/A model."""
from __future__ import annotations

import math


def round_half_away(x: float) -> int:
    """C99 round(): ties away from zero (Python's round() goes to even).  Splits off the
    fraction instead of adding 0.5, which would round 0.49999999999999994 up."""
    f = math.floor(abs(x))
    r = f + (1 if abs(x) - f >= 0.5 else 0)
    return int(math.copysign(r, x)) if r else 0
