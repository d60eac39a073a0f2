"""The input format of the firmware's sid_replay tool: CSV `t,alpha,q,de[,fault]`.

One writer for every producer (the CDRW flight generator, the identification study, the
synthetic test flights), full precision so that the C tool sees what Python computed.
"""
from __future__ import annotations

from collections.abc import Sequence

HEADER = "t,alpha,q,de"


def sid_csv(t: Sequence[float], alpha: Sequence[float], q: Sequence[float],
            de: Sequence[float], fault: Sequence[int] | None = None) -> str:
    """The flight as sid_replay input (rad, rad/s, rad); NaN readings are written as 'nan'
    (a dropout), `fault` is the optional 0/1 column the oracle detector reads."""
    lines = [HEADER + (",fault" if fault is not None else "")]
    for k in range(len(t)):
        row = f"{t[k]:.17g},{alpha[k]:.17g},{q[k]:.17g},{de[k]:.17g}"
        if fault is not None:
            row += f",{int(fault[k])}"
        lines.append(row)
    return "\n".join(lines) + "\n"
