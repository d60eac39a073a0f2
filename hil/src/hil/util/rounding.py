"""Rounding as the firmware does it, shared by the bus codec and the D/A model."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np


def round_half_away(x: float) -> int:
    """C99 round(): ties away from zero (Python's round() goes to even).  Splits off the
    fraction instead of adding 0.5, which would round 0.49999999999999994 up."""
    f = math.floor(abs(x))
    r = f + (1 if abs(x) - f >= 0.5 else 0)
    return int(math.copysign(r, x)) if r else 0


def round_half_away_many(x: np.ndarray) -> np.ndarray:
    """round_half_away of every value of a float array, as floats, the fraction split off the
    same way (a zero keeps the sign of its value; NaN and infinities give NaN or themselves).
    numpy is imported here: the bus codec imports this module on every command's path."""
    import numpy as np
    mag = np.abs(x)
    whole = np.floor(mag)
    return np.copysign(whole + (mag - whole >= 0.5), x)
