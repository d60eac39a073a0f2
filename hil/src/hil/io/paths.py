"""Where the firmware and its tools are.

``fcc`` is found, first match wins: ``--fcc PATH`` (``set_fcc``), ``$FCC_HIL_FCC``,
``$FCC_BUILD_DIR/bin/fcc``, ``<repo>/build/bin/fcc`` when the package runs from its source
tree, then ``fcc`` on ``$PATH``.  The other built tools (``sid_replay``, ``can_echo``, ...)
come from the build directory: ``$FCC_BUILD_DIR/bin``, default ``<repo>/build/bin``.
"""
from __future__ import annotations

import os
import shutil
from pathlib import Path

#: the source tree this package lives in (None when installed: site-packages has no dbc/)
_TREE = Path(__file__).resolve().parents[4]
REPO: Path | None = _TREE if (_TREE / "dbc" / "fcc_hil.dbc").is_file() else None
FCC_ENV = "FCC_HIL_FCC"

_fcc_override: Path | None = None


class ToolNotFound(FileNotFoundError):
    """A built program is missing (one line, says how to build it)."""


def set_fcc(path: Path | None) -> None:
    """The fcc binary given on the command line (--fcc), ahead of every other rule."""
    global _fcc_override  # noqa: PLW0603 - one process-wide choice, made by the CLI
    _fcc_override = None if path is None else Path(path)


def build_dir() -> Path:
    default = (REPO or Path.cwd()) / "build"
    return Path(os.environ.get("FCC_BUILD_DIR", default)).resolve()


def _executable(path: Path) -> bool:
    return path.is_file() and os.access(path, os.X_OK)


def _build_hint() -> str:
    return (f"build it (`cmake -S . -B build -G Ninja && cmake --build build` in the source tree), "
            f"or give --fcc PATH / ${FCC_ENV} / $FCC_BUILD_DIR")


def fcc_binary() -> Path:
    """The firmware to run (rules in the module docstring)."""
    for given, what in ((_fcc_override, "--fcc"), (os.environ.get(FCC_ENV), f"${FCC_ENV}")):
        if given:
            p = Path(given).expanduser()
            if not _executable(p):
                raise ToolNotFound(f"{what} {p}: not an executable file")
            return p.resolve()
    candidates = []
    if "FCC_BUILD_DIR" in os.environ or REPO is not None:
        candidates.append(build_dir() / "bin" / "fcc")
    on_path = shutil.which("fcc")
    if on_path:
        candidates.append(Path(on_path))
    for p in candidates:
        if _executable(p):
            return p.resolve()
    where = candidates[0] if candidates else "fcc"
    raise ToolNotFound(f"{where} is not built: {_build_hint()}")


def tool(name: str) -> Path:
    """Path of a built program, e.g. tool('sid_replay') -> <build>/bin/sid_replay."""
    if name == "fcc":
        return fcc_binary()
    path = build_dir() / "bin" / name
    if not _executable(path):
        raise ToolNotFound(f"{path} is not built: run `cmake -S . -B {build_dir().name} -G Ninja "
                           f"&& cmake --build {build_dir().name}` (or set FCC_BUILD_DIR)")
    return path
