"""scripts/hil-demo builds every program `hil` runs, so that every command the README and the
quickstart show after it (hil run, campaign, sweep, study, replay) finds its tools built."""
from __future__ import annotations

import re

from conftest import REPO


def _demo_tools() -> set[str]:
    text = (REPO / "scripts" / "hil-demo").read_text(encoding="utf-8")
    return set(re.search(r"^tools=\(([^)]*)\)$", text, re.M).group(1).split())


def _tools_hil_runs() -> set[str]:
    """Every name hil.io.paths.tool() is called with, in the package's source."""
    names = {"fcc"}  # the firmware under test (paths.fcc_binary, through tool("fcc") too)
    for path in (REPO / "hil" / "src" / "hil").rglob("*.py"):
        names |= set(re.findall(r"\btool\(\"([a-z_]+)\"\)", path.read_text(encoding="utf-8")))
    return names


def test_hil_demo_builds_every_tool_hil_runs() -> None:
    runs = _tools_hil_runs()
    assert {"fcc", "canrec", "lqg_design", "sid_replay"} <= runs  # the search finds the calls
    assert runs <= _demo_tools(), f"scripts/hil-demo does not build {sorted(runs - _demo_tools())}"


def test_hil_demo_builds_them_by_that_list() -> None:
    text = (REPO / "scripts" / "hil-demo").read_text(encoding="utf-8")
    assert '--target "${tools[@]}"' in text and 'building ${tools[*]}' in text
