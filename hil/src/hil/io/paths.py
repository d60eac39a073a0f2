"""Where the firmware's programs, the package's data and the vcan launcher are.

Every program a command runs -- ``fcc``, ``sid_replay``, ``lqg_design``, ``canrec``,
``can_echo`` and the Cortex-M4F image ``fcc_m4f.elf`` -- is found by tool(NAME), first match
wins:

1. the command line: ``--fcc PATH`` (fcc; with ``--target qemu-m4f`` the image, which the
   target takes as given) and ``--build-dir DIR`` (every program: ``DIR/bin/NAME``; the option
   sets ``$FCC_BUILD_DIR`` for the run, so that its workers see it too);
2. the environment: ``$FCC_HIL_FCC`` (fcc), ``$FCC_BUILD_DIR/bin/NAME`` (the image:
   ``$FCC_M4F_BUILD_DIR/bin``);
3. the source tree's build directory, when hil runs from a clone (an editable install):
   ``build/bin/NAME`` (the image: ``build-m4f/bin``, cross-built on demand by hil.targets);
4. ``NAME`` on ``$PATH``.

A path or directory given in 1 or 2 that does not hold the program is an error, not a reason
to look further: what the user named is what runs.  source_tree() is the one place that
knows the layout of the clone; everything else hil reads ships inside the package (DATA).
"""
from __future__ import annotations

import logging
import os
import shutil
from collections.abc import Iterable
from pathlib import Path

from hil.util.errors import HilError, InputError

FCC_ENV = "FCC_HIL_FCC"
BUILD_ENV = "FCC_BUILD_DIR"
M4F_BUILD_ENV = "FCC_M4F_BUILD_DIR"
#: the Cortex-M4F image's file name (in the cross build's bin/)
M4F_IMAGE = "fcc_m4f.elf"
#: the package's data: the DBC and its digest, the published test key, the vcan launcher
DATA = Path(__file__).resolve().parent.parent / "data"
#: the scenarios and test suites that come with hil (TOML files, named by their stem)
SCENARIOS = DATA.parent / "scenarios"
SUITES = DATA.parent / "suites"

_fcc_override: Path | None = None
_log = logging.getLogger(__name__)


class ToolNotFound(HilError, FileNotFoundError):
    """A firmware program is missing (one line: which, and the ways to give it)."""


class NotShipped(InputError, ValueError):
    """A name that is neither a path nor a shipped scenario's or suite's (one line: the names)."""


#: where this module is: <tree>/hil/src/hil/io/paths.py in a clone (resolved once: a dozen
#: look-ups a time, 2 ms in the UML guest, and a run asks about seven times)
_HERE = Path(__file__).resolve()


def source_tree() -> Path | None:
    """The clone this package runs from (an editable install), or None when installed."""
    tree = _HERE.parents[4]
    marks = (tree / "CMakeLists.txt", tree / "dbc" / "fcc_hil.dbc", tree / "scripts" / "with-vcan")
    return tree if all(m.is_file() for m in marks) else None


def set_fcc(path: Path | None) -> None:
    """The fcc binary given on the command line (--fcc), ahead of every other rule."""
    global _fcc_override  # noqa: PLW0603 - one process-wide choice, made by the CLI
    _fcc_override = None if path is None else Path(path)


def build_dir() -> Path:
    """The host build directory: $FCC_BUILD_DIR, else the clone's build/ (rule 2, then 3)."""
    given = os.environ.get(BUILD_ENV)
    if given:
        return Path(given).expanduser().resolve()
    tree = source_tree()
    if tree is None:
        raise ToolNotFound(f"no build directory: hil is installed, not run from its source tree; "
                           f"{_HOW}")
    return tree / "build"


_HOW = (f"give --build-dir DIR or ${BUILD_ENV} (a CMake build of the firmware: "
        f"`cmake -S SRC -B DIR -G Ninja && cmake --build DIR`), or put it on $PATH")


def _executable(path: Path) -> bool:
    return path.is_file() and os.access(path, os.X_OK)


def _given(path: str | Path, what: str, where: str = "") -> Path:
    p = Path(path).expanduser()
    if not _executable(p):
        raise ToolNotFound(f"{what}{p}: not an executable file{where}")
    return p.resolve()


def tool(name: str) -> Path:
    """The program NAME (the rules in the module docstring)."""
    found = _find(name)
    _log.debug("%s: %s", name, found)
    return found


def _find(name: str) -> Path:
    image = name == M4F_IMAGE
    if name == "fcc":
        for given, what in ((_fcc_override, "--fcc"), (os.environ.get(FCC_ENV), f"${FCC_ENV}")):
            if given:
                return _given(given, f"{what} ")
    env = M4F_BUILD_ENV if image else BUILD_ENV
    if os.environ.get(env):
        given_by = f"--build-dir or ${env}" if env == BUILD_ENV else f"${env}"
        return _given(Path(os.environ[env]).expanduser() / "bin" / name, "", f" (from {given_by})")
    tree = source_tree()
    if tree is not None:
        built = tree / ("build-m4f" if image else "build") / "bin" / name
        if _executable(built):
            return built
    on_path = shutil.which(name)
    if on_path:
        return Path(on_path).resolve()
    if tree is not None:
        build = "build-m4f" if image else "build"
        raise ToolNotFound(f"{name} is not built: run `cmake -S . -B {build} -G Ninja && cmake "
                           f"--build {build}` in {tree}, or {_HOW}")
    if image:
        how = (f"give --fcc IMAGE or ${M4F_BUILD_ENV} (the Cortex-M4F cross build: "
               f"firmware/port/mps2_an386/README.md), or put it on $PATH")
    else:
        how = _HOW + (" (fcc: also --fcc PATH or $FCC_HIL_FCC)" if name == "fcc" else "")
    raise ToolNotFound(f"{name} not found: {how}")


def fcc_binary() -> Path:
    """The firmware to run on the host (tool('fcc'))."""
    return tool("fcc")


def require(names: Iterable[str]) -> None:
    """Every program of a run, looked up before it starts: the first missing one raises
    ToolNotFound (one line), so that nothing flies that cannot finish."""
    for name in names:
        tool(name)


def user_cache() -> Path | None:
    """hil's directory in the user's cache: $XDG_CACHE_HOME/hil (only when absolute, as the XDG
    specification says), else ~/.cache/hil; None without a home directory (rather than a cache
    under the current directory)."""
    xdg = Path(os.environ.get("XDG_CACHE_HOME", ""))
    base = xdg if xdg.is_absolute() else Path(os.path.expanduser("~")) / ".cache"
    return base / "hil" if base.is_absolute() else None


def uml_dir() -> Path:
    """Where the packaged vcan launcher keeps its User-Mode Linux kernel: $WITH_VCAN_UML_DIR,
    else uml/ in user_cache()."""
    given = os.environ.get("WITH_VCAN_UML_DIR")
    if given:
        return Path(given).expanduser()
    cache = user_cache()
    if cache is None:
        raise ToolNotFound("no home directory for the User-Mode Linux kernel: set $WITH_VCAN_UML_DIR")
    return cache / "uml"


def with_vcan() -> list[str]:
    """The command prefix that runs a command where vcan0 exists: the clone's scripts/with-vcan,
    else the same script shipped in the package (data/with-vcan) with its kernel in uml_dir()."""
    tree = source_tree()
    if tree is not None:
        return [str(tree / "scripts" / "with-vcan")]
    return ["env", f"WITH_VCAN_UML_DIR={uml_dir()}", "bash", str(DATA / "with-vcan")]


def vcan_launcher() -> str:
    """What runs a command where vcan0 exists, as this installation has it (for messages): the
    clone's scripts/with-vcan, or the installed package's hil-vcan."""
    return "scripts/with-vcan" if source_tree() is not None else "hil-vcan"


def shipped(directory: Path) -> dict[str, Path]:
    """The TOML files that come with hil in directory (SCENARIOS, SUITES), by name (stem)."""
    return {p.stem: p for p in sorted(directory.glob("*.toml"))}


def find_shipped(name_or_path: str, directory: Path, what: str) -> Path:
    """A path (one that ends in .toml, holds a '/' or exists: a path always wins), else the
    name of a file shipped in directory; NotShipped names the shipped ones."""
    p = Path(name_or_path)
    if p.suffix == ".toml" or "/" in name_or_path or p.exists():
        return p
    known = shipped(directory)
    if name_or_path not in known:
        raise NotShipped(f"no {what} named {name_or_path!r} (shipped: {', '.join(known)}; "
                         f"or give a .toml path)")
    return known[name_or_path]
