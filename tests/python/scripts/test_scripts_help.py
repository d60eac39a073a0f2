"""Every script a user runs answers --help with what it does (exit 0, nothing started)."""
from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from conftest import REPO

SCRIPTS = sorted([p for p in (REPO / "scripts").iterdir() if p.is_file() and p.stat().st_mode & 0o111]
                 + [REPO / "dbc" / "generate"])


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.name)
def test_help(script: Path) -> None:
    r = subprocess.run([str(script), "--help"], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    text = r.stdout.strip()
    assert text.startswith((f"{script.name} -- ", f"usage: {script.name}")), text[:80]
    assert len(text.splitlines()) >= 3
