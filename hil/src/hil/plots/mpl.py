"""matplotlib on the Agg backend (files only, no display), one place."""
from __future__ import annotations

import io
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from hil.io.rundir import atomic_write

#: fixed metadata: the same data give the same PNG bytes
_META = {"Software": None}
#: files a figure must not overwrite (the user's, in a run directory: hil.cli.report); a
#: figure whose file is here is not written (save returns None)
KEEP: set[Path] = set()


def save(fig: "plt.Figure", path: Path, rect: tuple[float, float, float, float] | None = None) -> Path | None:
    """Lay out (inside rect, figure fraction, when given: room for a figure legend) and write
    (not when the file is in KEEP: None)."""
    if Path(path).resolve() in KEEP:
        plt.close(fig)
        return None
    fig.tight_layout(rect=rect)

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110, metadata=_META)
    plt.close(fig)
    return atomic_write(path, buf.getvalue())  # never a half-written PNG


__all__ = ["plt", "save"]
