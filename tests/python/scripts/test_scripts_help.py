"""Every script and every tool a user runs answers --help with what it does (exit 0, nothing
started), and a wrong option with one line on stderr and exit 2 (nothing started either): the
scripts in scripts/ and scripts/bench.d/, dbc/generate, and the firmware's programs."""
from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from conftest import REPO, build_dir


def _executables(folder: Path) -> list[Path]:
    return [p for p in folder.iterdir() if p.is_file() and p.stat().st_mode & 0o111]


SCRIPTS = sorted(_executables(REPO / "scripts") + _executables(REPO / "scripts" / "bench.d")
                 + [REPO / "dbc" / "generate"])
TOOLS = ("fcc", "sid_replay", "lqg_design", "canrec", "can_echo", "slcan_bridge")
#: what each program is called in its own words (help and errors)
PROGRAMS = [(p, p.name) for p in SCRIPTS] + [(build_dir() / "bin" / t, t) for t in TOOLS]


def _id(case: tuple[Path, str]) -> str:
    path, _ = case
    return str(path.relative_to(REPO)) if path.is_relative_to(REPO) else path.name


def _run(path: Path, *args: str) -> subprocess.CompletedProcess:
    assert path.exists(), f"{path} is missing (the tools: cmake --build {build_dir()})"
    # stdin closed: a program that would read it (sid_replay) does not wait; 60 s: nothing runs
    return subprocess.run([str(path), *args], capture_output=True, text=True, timeout=60,
                          stdin=subprocess.DEVNULL, cwd=REPO)


@pytest.mark.parametrize("case", PROGRAMS, ids=_id)
def test_help(case: tuple[Path, str]) -> None:
    path, name = case
    r = _run(path, "--help")
    assert r.returncode == 0, r.stderr
    text = r.stdout.strip()
    assert text.startswith((f"{name} -- ", "usage: ")) and name in text.splitlines()[0], text[:80]
    assert len(text.splitlines()) >= 3
    assert r.stderr == ""


@pytest.mark.parametrize("case", PROGRAMS, ids=_id)
def test_a_wrong_option(case: tuple[Path, str]) -> None:
    path, name = case
    r = _run(path, "--no-such-option")
    assert r.returncode == 2, (r.returncode, r.stdout[-300:], r.stderr[-300:])
    lines = r.stderr.splitlines()
    assert len(lines) == 1, r.stderr
    assert name in lines[0] and r.stdout == ""


#: the bench parts that pass their options on to a Python module: the options the wrapper
#: accepts (check_options) are the module's, no more, no fewer
PASSED_ON = {"parallel": ["hil.bench.parallel", "scaling"], "table5-1000": ["hil.bench.parallel", "table5"],
             "recorder": ["hil.bench.recorder"], "rig": ["hil.bench.rig"],
             "hostarch": ["hil.bench.hostarch"]}


@pytest.mark.parametrize("part", sorted(PASSED_ON))
def test_a_bench_part_accepts_its_modules_options(part: str) -> None:
    import re
    import sys
    text = (REPO / "scripts" / "bench.d" / part).read_text(encoding="utf-8")
    spec = re.search(r'check_options "\$0" "([^"]*)"', text).group(1)
    accepted = {o.rstrip("=") for o in spec.split()}
    r = subprocess.run([sys.executable, "-m", *PASSED_ON[part], "--help"], capture_output=True,
                       text=True, timeout=60, cwd=REPO)
    assert r.returncode == 0, r.stderr
    assert accepted == set(re.findall(r"(--[a-z][a-z-]+)", r.stdout)) - {"--help"}
    for option in accepted:  # and the --help of the wrapper shows them
        assert option in text.split("\nset -")[0]
