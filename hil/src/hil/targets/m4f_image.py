"""The Cortex-M4F image of `--target qemu-m4f`: where its cross build is, and the build itself,
run when the image is missing or stale (cmake + the M4F toolchain file, Ninja), its output into
the build's hil-build.log and, when asked, its progress on stderr (hil.util.progress): a line
when it starts, its steps, a line when it is done (about 50 s from scratch on the 2-core
machine).  Installed (no source tree), the image is found as every program is (hil.io.paths).
"""
from __future__ import annotations

import os
import re
import subprocess
import time
from collections.abc import Sequence
from pathlib import Path
from typing import BinaryIO

from hil.io.paths import M4F_BUILD_ENV, M4F_IMAGE, source_tree, tool
from hil.util.errors import HilError
from hil.util.progress import bar, say


class PilError(HilError, RuntimeError):
    """The image, the emulated board or its serial link could not be set up (one line)."""


def m4f_build_dir() -> Path:
    """Where the cross build lives in a clone ($FCC_M4F_BUILD_DIR, default <tree>/build-m4f)."""
    if os.environ.get(M4F_BUILD_ENV):
        return Path(os.environ[M4F_BUILD_ENV]).resolve()
    tree = source_tree()
    if tree is None:
        raise PilError("hil runs outside its source tree: give the Cortex-M4F image with --fcc "
                       f"IMAGE.elf (or ${M4F_BUILD_ENV})")
    return tree / "build-m4f"


def build_image(build: Path | None = None, progress: bool = False) -> Path:
    """The ELF image, cross-built (cmake + the M4F toolchain file) when missing or stale; with
    progress, a line when the build starts and ends and its steps as the rig's progress."""
    tree = source_tree()
    if tree is None:  # installed: the image as it is, found as every program is (hil.io.paths)
        return build / "bin" / M4F_IMAGE if build else tool(M4F_IMAGE)
    build = build or m4f_build_dir()
    log = build / "hil-build.log"
    steps = []
    if not (build / "CMakeCache.txt").is_file():
        say(f"configuring the cross build of {M4F_IMAGE} in {build}", progress)
        steps.append(["cmake", "-S", str(tree), "-B", str(build), "-G", "Ninja",
                      f"-DCMAKE_TOOLCHAIN_FILE={tree / 'cmake' / 'arm-none-eabi-cortex-m4f.cmake'}"])
    steps.append(["cmake", "--build", str(build)])
    build.mkdir(parents=True, exist_ok=True)
    t0 = time.monotonic()
    with open(log, "wb") as fh:
        for cmd in steps:
            built = follow_build(cmd, fh, progress, f"cross-building {M4F_IMAGE} in {build} (log: {log})")
            if built:
                say(f"cross-built {M4F_IMAGE}: {built} steps in {time.monotonic() - t0:.0f} s", progress)
    image = build / "bin" / M4F_IMAGE
    if not image.is_file():
        raise PilError(f"the cross build made no {image}")
    return image


#: a build step as Ninja reports it: "[3/128] Building C object ..."
NINJA_STEP = re.compile(rb"\[(\d+)/(\d+)\] ")


def follow_build(cmd: Sequence[str], log: BinaryIO, progress: bool, what: str) -> int:
    """Run a build command, its output into log; with progress, `what` once the first step
    starts, then the steps as the rig's progress (hil.util.progress).  The steps it ran."""
    try:
        proc = subprocess.Popen(list(cmd), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                stdin=subprocess.DEVNULL)
    except OSError as e:
        raise PilError(f"cannot run {cmd[0]}: {e.strerror}") from None
    display, done = None, 0
    assert proc.stdout is not None
    with proc, proc.stdout:
        for line in proc.stdout:
            log.write(line)
            step = NINJA_STEP.match(line)
            if step is None:
                continue
            if display is None:
                say(what, progress)
                display = bar(int(step[2]), progress, "cross-build", unit="step")
            display.update(int(step[1]) - done)
            done = int(step[1])
    if display is not None:
        display.close()
    if proc.returncode != 0:
        raise PilError(f"the Cortex-M4F cross build failed ({' '.join(cmd[:3])} ...); see {log.name}")
    return done
