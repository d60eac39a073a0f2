"""The input format of the firmware's sid_replay tool: CSV `t,alpha,q,de[,fault]`.

One writer for every producer (the CDRW flight generator, the identification study, the
synthetic test flights), full precision so that the C tool sees what Python computed.
"""
from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    #: a column: a list, or a numpy array as the flight generator holds it
    Column = Sequence[float] | npt.NDArray[np.float64]
    Flags = Sequence[int] | npt.NDArray[np.int8]

HEADER = "t,alpha,q,de"


def sid_csv(t: Column, alpha: Column, q: Column, de: Column, fault: Flags | None = None) -> str:
    """The flight as sid_replay input (rad, rad/s, rad); NaN readings are written as 'nan'
    (a dropout), `fault` is the optional 0/1 column the oracle detector reads."""
    lines = [HEADER + (",fault" if fault is not None else "")]
    for k in range(len(t)):
        row = f"{t[k]:.17g},{alpha[k]:.17g},{q[k]:.17g},{de[k]:.17g}"
        if fault is not None:
            row += f",{int(fault[k])}"
        lines.append(row)
    return "\n".join(lines) + "\n"
