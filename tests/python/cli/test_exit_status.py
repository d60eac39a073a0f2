"""`hil`'s exit statuses come from one table (hil.cli.usage.EXIT_STATUS): `hil --help` prints it,
the documentation's command-line reference renders it, docs/reliability.md lists what each
leaves behind, and the statuses the code returns are the table's."""
from __future__ import annotations

import importlib.util
import re
import signal
import subprocess
import sys
from pathlib import Path

from hil.cli import usage
from hil.rig.errors import FccDied, FccTimeout, RigError

REPO = Path(__file__).resolve().parents[3]


def _statuses_of_table(text: str) -> list[int]:
    return [int(m.group(1)) for m in re.finditer(r"^\| (\d+) \|", text, re.M)]


def test_help_ends_with_every_status() -> None:
    exe = Path(sys.executable).with_name("hil")
    r = subprocess.run([str(exe), "--help"], capture_output=True, text=True, timeout=60,
                       env={"COLUMNS": "80", "PATH": "/usr/bin:/bin"})
    assert r.returncode == 0
    tail = r.stdout.split("\nexit status", 1)[1]
    listed = [int(m.group(1)) for m in re.finditer(r"^  (\d+) +\S", tail, re.M)]
    assert listed == [s for s, _ in usage.EXIT_STATUS]
    assert "fcc died during the run" in tail and "`" not in tail
    assert max(len(line) for line in tail.splitlines()) <= 79


def test_the_reference_renders_the_same_table() -> None:
    spec = importlib.util.spec_from_file_location("cli_reference", REPO / "scripts/lib/cli_reference.py")
    ref = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ref)
    page = ref.on_page_markdown((REPO / "docs/cli.md").read_text(encoding="utf-8"), None, None, None)
    assert "generated:" not in page
    assert _statuses_of_table(page.split("## Exit status", 1)[1]) == [s for s, _ in usage.EXIT_STATUS]


def test_reliability_says_what_each_status_leaves() -> None:
    text = (REPO / "docs/reliability.md").read_text(encoding="utf-8")
    assert sorted(_statuses_of_table(text)) == sorted(s for s, _ in usage.EXIT_STATUS)


def test_the_code_returns_the_tables_statuses() -> None:
    assert (RigError.exit_status, FccTimeout.exit_status, FccDied.exit_status) == \
        (usage.EXIT_FAILED, usage.EXIT_TIMEOUT, usage.EXIT_DIED)
    assert tuple(128 + s for s in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)) == \
        (usage.EXIT_SIGINT, usage.EXIT_SIGTERM, usage.EXIT_SIGHUP)
