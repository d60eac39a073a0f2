"""Where the repository, the build and its tools are.

The CLI runs the firmware from ``$FCC_BUILD_DIR/bin`` (the same variable the tests use),
defaulting to ``<repo>/build/bin``.
"""
from __future__ import annotations

import os
from pathlib import Path

REPO = Path(__file__).resolve().parents[4]


class ToolNotFound(FileNotFoundError):
    """A built program is missing (one line, says how to build it)."""


def build_dir() -> Path:
    return Path(os.environ.get("FCC_BUILD_DIR", REPO / "build")).resolve()


def tool(name: str) -> Path:
    """Path of a built program, e.g. tool('fcc') -> <build>/bin/fcc."""
    path = build_dir() / "bin" / name
    if not (path.is_file() and os.access(path, os.X_OK)):
        raise ToolNotFound(f"{path} is not built: run `cmake -S . -B {build_dir().name} -G Ninja "
                           f"&& cmake --build {build_dir().name}` (or set FCC_BUILD_DIR)")
    return path
