"""Shared pytest fixtures: where the repository and the built C tools are.

The tests are arranged like hil (bus/, scenario/, sim/, rig/, targets/, results/, runs/, ...;
fcc/ and pil/ for the firmware on the bus and under QEMU, reference/, cli/, scripts/, bench/).
Their shared helpers stay here, beside this file: conftest (REPO, build_dir), rig_helpers and
fcc_harness, importable by name from every folder (this folder is put on sys.path).
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
HELPERS = str(Path(__file__).resolve().parent)
if HELPERS not in sys.path:  # `from rig_helpers import ...` in tests/python/*/test_*.py
    sys.path.insert(0, HELPERS)


def build_dir() -> Path:
    """The CMake build whose binaries the tests run (FCC_BUILD_DIR, default build/)."""
    return Path(os.environ.get("FCC_BUILD_DIR", REPO / "build")).resolve()


@pytest.fixture(scope="session")
def repo() -> Path:
    return REPO


@pytest.fixture(scope="session")
def bin_path():
    """bin_path('lqg_design') -> Path of build/bin/lqg_design; skips nothing: a missing tool fails."""

    def _find(name: str) -> Path:
        path = build_dir() / "bin" / name
        assert path.exists(), f"{path} is not built: run cmake --build {build_dir()}"
        return path

    return _find
