"""matplotlib on the Agg backend (files only, no display), one place."""
from __future__ import annotations

import io
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from hil.io.rundir import atomic_write, published_path

#: fixed metadata: the same data give the same PNG bytes
_META = {"Software": None}
#: files a figure must not overwrite (the user's, in a run directory: hil.cli.report); a
#: figure whose file is here is not written (save returns None)
KEEP: set[Path] = set()
#: the run directory the figures being drawn come from, when they are written elsewhere
#: (`hil plot DIR --out OUT`); None: the directory each figure is written into
SOURCE: Path | None = None


def caption_path(png: Path) -> Path:
    """The one-line caption written beside every figure: NAME.caption.txt."""
    return png.with_name(png.stem + ".caption.txt")


def title_of(fig: plt.Figure) -> str:
    sup = getattr(fig, "_suptitle", None)
    text = sup.get_text() if sup is not None else ""
    if not text:
        text = next((ax.get_title() for ax in fig.axes if ax.get_title()), "")
    return " ".join(text.split())


def _run_of(run_dir: Path) -> str:
    """Which run wrote run_dir (its summary.json's command), and how to redraw; named where
    it will be when the run is done (a run draws its figures in its staging directory)."""
    try:
        cmd = json.loads((run_dir / "summary.json").read_text()).get("command")
    except (OSError, ValueError, AttributeError):
        cmd = None
    where = published_path(run_dir)
    what = f"hil {cmd} into {where}" if isinstance(cmd, str) and cmd else f"the run in {where}"
    return f"{what} (redraw: hil plot {where})"


def save(fig: plt.Figure, path: Path, rect: tuple[float, float, float, float] | None = None,
         made_by: str | None = None) -> Path | None:
    """Lay out (inside rect, figure fraction, when given: room for a figure legend) and write,
    with a one-line caption file beside it: the title and the run that made the figure
    (made_by; default: the run directory it comes from, redrawn by `hil plot DIR`).  Not when
    the file is in KEEP (a user's file): None."""
    if Path(path).resolve() in KEEP:
        plt.close(fig)
        return None
    fig.tight_layout(rect=rect)
    title = title_of(fig)

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110, metadata=_META)
    plt.close(fig)
    out = atomic_write(path, buf.getvalue())  # never a half-written PNG
    run = made_by or _run_of(SOURCE or path.parent)
    atomic_write(caption_path(path), f"{title}. Made by: {run}\n".encode())
    return out


__all__ = ["caption_path", "plt", "save", "title_of"]
