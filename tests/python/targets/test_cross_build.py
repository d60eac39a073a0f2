"""The Cortex-M4F cross-build's progress (hil.targets.m4f_image.follow_build): a real Ninja build
(a small build.ninja of three steps) followed as `hil run --target qemu-m4f` follows cmake's:
its output into the log, one line when it starts, its steps as the rig's progress, nothing at
all when there is nothing to build or progress is off, one line naming the log when it fails."""
from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from hil.targets.m4f_image import PilError, follow_build

pytestmark = pytest.mark.skipif(shutil.which("ninja") is None, reason="needs ninja")

BUILD = """rule copy
  command = cp $in $out
build b.txt: copy a.txt
build c.txt: copy b.txt
build d.txt: copy c.txt
"""


def ninja(tmp_path: Path, progress: bool) -> tuple[int, bytes]:
    log = tmp_path / "build.log"
    with open(log, "wb") as fh:
        steps = follow_build(["ninja", "-C", str(tmp_path)], fh, progress, "building the test")
    return steps, log.read_bytes()


def test_progress_lines_while_it_builds(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "build.ninja").write_text(BUILD)
    (tmp_path / "a.txt").write_text("x")
    steps, log = ninja(tmp_path, progress=True)
    err = capsys.readouterr().err
    assert steps == 3 and (tmp_path / "d.txt").read_text() == "x"
    assert b"[3/3] cp c.txt d.txt" in log                       # the whole output kept
    assert err.splitlines()[0] == "hil: building the test"     # said before the first step ends
    # nothing left to build: nothing said
    steps, _ = ninja(tmp_path, progress=True)
    assert steps == 0 and capsys.readouterr().err == ""


def test_quiet(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "build.ninja").write_text(BUILD)
    (tmp_path / "a.txt").write_text("x")
    assert ninja(tmp_path, progress=False)[0] == 3
    assert capsys.readouterr().err == ""


def test_a_failed_build_is_one_error_naming_its_log(tmp_path: Path) -> None:
    (tmp_path / "build.ninja").write_text(BUILD)               # a.txt missing: the build fails
    with pytest.raises(PilError, match=r"cross build failed \(ninja -C .*\); see .*build\.log$"):
        ninja(tmp_path, progress=True)
