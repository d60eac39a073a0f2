"""Headless Chromium for the tests of hil's HTML pages (the verify report, `hil compare`'s
page): a page opened as a user opens it, its screenshot taken."""
from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def screenshot(page: Path, shot: Path, size: str = "1200,900") -> bytes:
    """The PNG Chromium draws of page (file URI), written to shot and returned."""
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    assert browser, "chromium is not installed (scripts/setup installs it)"
    subprocess.run([browser, "--headless", "--no-sandbox", "--disable-gpu", f"--window-size={size}",
                    f"--screenshot={shot}", page.resolve().as_uri()], check=True, capture_output=True,
                   timeout=120)
    return shot.read_bytes()
