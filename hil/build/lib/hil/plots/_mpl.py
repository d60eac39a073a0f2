"""matplotlib on the Agg backend (files only, no display), one place."""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

#: fixed metadata: the same data give the same PNG bytes
_META = {"Software": None}


def save(fig: "plt.Figure", path: Path) -> Path:
    fig.tight_layout()
    fig.savefig(path, dpi=110, metadata=_META)
    plt.close(fig)
    return path


__all__ = ["plt", "save"]
