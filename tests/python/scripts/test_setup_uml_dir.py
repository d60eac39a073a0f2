"""scripts/setup never deletes a user's file: the directory it provisions the User-Mode Linux
kernel into ($WITH_VCAN_UML_DIR) is replaced only when it is new, empty or one setup
provisioned; anything else is refused in one line, before anything is downloaded.

Every directory here is a temporary one, and the mirror is an empty one: a refusal that came
after the download would show as apt's failure instead of the refusal."""
from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest

from conftest import REPO

UML_SH = REPO / "scripts" / "lib" / "uml.sh"
MARKER = ".provisioned-by-fcc-hil"


def _env(uml_dir: Path, tmp_path: Path) -> dict[str, str]:
    return {**os.environ, "WITH_VCAN_UML_DIR": str(uml_dir), "UML_DEBIAN_MIRROR": f"file://{tmp_path}/no-mirror",
            "TMPDIR": str(tmp_path)}


def _provision(uml_dir: Path, tmp_path: Path) -> subprocess.CompletedProcess[str]:
    """uml_provision as setup calls it (setup itself skips it where the host has vcan)."""
    return subprocess.run(["bash", "-c", 'source "$1"; prog=setup; uml_provision "$2"', "t",
                           str(UML_SH), str(uml_dir)],
                          env=_env(uml_dir, tmp_path), capture_output=True, text=True, timeout=120)


def _users_dir(tmp_path: Path) -> Path:
    d = tmp_path / "mine"
    d.mkdir()
    (d / "thesis.tex").write_text("years of work\n")
    return d


def _refused(result: subprocess.CompletedProcess[str], uml_dir: Path) -> None:
    assert result.returncode == 1
    lines = result.stderr.splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith(f"setup: refusing to put the User-Mode Linux kernel into {uml_dir}")
    assert MARKER in lines[0] and "apt" not in lines[0]


def _host_has_vcan() -> bool:
    return Path("/sys/class/net/vcan0").exists() or subprocess.run(
        ["modprobe", "-q", "vcan"], capture_output=True).returncode == 0


@pytest.mark.skipif(_host_has_vcan(), reason="the host has vcan: setup provisions no kernel")
def test_setup_refuses_a_directory_of_the_users_and_keeps_its_files(tmp_path):
    mine = _users_dir(tmp_path)
    result = subprocess.run([str(REPO / "scripts" / "setup")], cwd=REPO, env=_env(mine, tmp_path),
                            capture_output=True, text=True, timeout=300)
    _refused(result, mine)
    assert (mine / "thesis.tex").read_text() == "years of work\n"
    assert sorted(p.name for p in mine.iterdir()) == ["thesis.tex"]
    assert not list(tmp_path.glob("mine.new.*")) and not list(tmp_path.glob("uml-provision.*"))


@pytest.mark.parametrize("what", ["a file", "a directory of the user's", "a dangling link"])
def test_provision_refuses_what_it_did_not_provision(tmp_path, what):
    if what == "a file":
        target = tmp_path / "notes.txt"
        target.write_text("mine\n")
    elif what == "a dangling link":
        target = tmp_path / "link"
        target.symlink_to(tmp_path / "nowhere")
    else:
        target = _users_dir(tmp_path)
    before = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()}
    _refused(_provision(target, tmp_path), target)
    assert {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()} == before
    assert target.is_symlink() == (what == "a dangling link")


@pytest.mark.parametrize("what", ["new", "empty", "marked", "provisioned before the marker"])
def test_provision_goes_on_to_the_download_for_its_own_directories(tmp_path, what):
    uml_dir = tmp_path / "uml"
    if what != "new":
        uml_dir.mkdir()
    if what == "marked":
        (uml_dir / MARKER).touch()
        (uml_dir / "lpj").write_text("lpj=1\n")
    if what == "provisioned before the marker":
        (uml_dir / "lib").mkdir()
        for name in ("linux.uml", "release", "lib/ld-linux-x86-64.so.2"):
            (uml_dir / name).write_text("x\n")
    result = _provision(uml_dir, tmp_path)
    assert result.returncode == 1            # past the check: the empty mirror fails it
    assert "cannot provision User-Mode Linux" in result.stderr and "refusing" not in result.stderr
    assert uml_dir.exists() == (what != "new")   # a failed download replaces nothing
