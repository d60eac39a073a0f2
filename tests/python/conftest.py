"""Shared pytest fixtures: where the repository and the built C tools are."""
from __future__ import annotations

import os
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


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
