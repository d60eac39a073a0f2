"""A bug's traceback, kept for its report: hil's command line says one line (`hil: internal
error: ...`) and names the file written here, $XDG_CACHE_HOME/hil/crash-TIME-PID.log (the
user's cache, hil.io.paths.user_cache), rather than printing a traceback at its user."""
from __future__ import annotations

import os
import sys
import time
import traceback
from pathlib import Path

from hil.io import paths


def write(e: BaseException, directory: Path | None = None) -> Path | None:
    """The traceback of `e` (and the command line) in a new file in `directory` (default: the
    user's cache); None when no file can be written (no home, a read-only disk)."""
    where = directory if directory is not None else paths.user_cache()
    if where is None:
        return None
    stamp = time.strftime("%Y%m%dT%H%M%S", time.gmtime())
    path = where / f"crash-{stamp}-{os.getpid()}.log"
    text = (f"hil {' '.join(sys.argv[1:])}\n"
            + "".join(traceback.format_exception(type(e), e, e.__traceback__)))
    try:
        where.mkdir(parents=True, exist_ok=True)
        with open(path, "x", encoding="utf-8") as f:
            f.write(text)
    except OSError:
        return None
    return path
