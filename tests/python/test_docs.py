"""The documentation (README.md, docs/) shows only commands that work.

Every fenced shell block (```sh, ```console, ...) is preceded by a marker comment:

    <!-- run -->                 run on the host (scripts/test python)
    <!-- run: vcan -->           needs the bus, or the output of a block that did: run inside
                                 scripts/with-vcan (scripts/test vcan); this test is marked vcan
    <!-- run: exit N -->         must exit with status N (also `<!-- run: vcan, exit N -->`)
    <!-- norun: REASON -->       not run, for the reason given

The blocks of one page run in order, each with `bash -e`, from the repository root, in one
temporary scratch directory per page: every `out/...` path of a block is redirected into it, and
a `hil run|campaign|sweep|demo|verify` without `--out` gets one there, so nothing is written into the
checkout's own out/ (checked). Also: the README's shape, the site's strict build, the command-line
reference, and the bus figures that dbc/README.md keeps for other tests.
"""
from __future__ import annotations

import importlib.util
import os
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
PAGES = [REPO / "README.md", *sorted((REPO / "docs").rglob("*.md"))]
SHELL_LANGS = {"sh", "bash", "shell", "console", "shell-session"}
MARKER = re.compile(r"^<!--\s*(?P<kind>run|norun)\s*(?::\s*(?P<args>.*?))?\s*-->$")
FENCE = re.compile(r"^ {0,3}(?P<fence>`{3,}|~{3,})\s*(?P<info>[^`\s]*)")
#: `out/...` at the start of a path (not `build/out/`, not `$X/out/`)
OUT_PATH = re.compile(r"(?<![\w./$-])out/")
#: a hil command that writes a run directory, up to the end of its shell command
HIL_WRITES = re.compile(r"(?P<cmd>\bhil[ \t]+(?P<sub>run|campaign|sweep|demo|verify)\b)"
                        r"(?P<rest>(?:\\\n|[^\n;&|'\"<>])*)")
#: the checkout's out/ entries that other steps of scripts/test write while this test runs
OUT_OWNED_ELSEWHERE = {"test-results", "site"}
BLOCK_TIMEOUT_S = 600


@dataclass(frozen=True)
class Block:
    page: Path
    line: int           # 1-based line of the opening fence
    lang: str
    text: str
    kind: str | None    # "run", "norun" or None (unmarked)
    vcan: bool = False
    exit: int = 0
    reason: str = ""
    marker_error: str = ""

    @property
    def where(self) -> str:
        return f"{self.page.relative_to(REPO)}:{self.line}"

    def script(self) -> str:
        if self.lang not in ("console", "shell-session"):
            return self.text
        cmds, cont = [], False
        for line in self.text.splitlines():
            if line.startswith("$ ") or cont:
                cmds.append(line[2:] if line.startswith("$ ") and not cont else line)
                cont = line.endswith("\\")
        return "\n".join(cmds) + "\n"


def _parse_marker(kind: str, args: str | None) -> dict:
    out: dict = {"kind": kind}
    if kind == "norun":
        out["reason"] = (args or "").strip()
        if not out["reason"]:
            out["marker_error"] = "norun needs a reason: <!-- norun: REASON -->"
        return out
    for arg in filter(None, (a.strip() for a in (args or "").split(","))):
        if arg == "vcan":
            out["vcan"] = True
        elif re.fullmatch(r"exit \d{1,3}", arg):
            out["exit"] = int(arg.split()[1])
        else:
            out["marker_error"] = f"unknown run option {arg!r} (vcan, exit N)"
    return out


def blocks(page: Path) -> list[Block]:
    lines = page.read_text(encoding="utf-8").splitlines()
    found: list[Block] = []
    i = 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        fence, lang = m.group("fence"), m.group("info").lower()
        j = i + 1
        while j < len(lines) and not (lines[j].lstrip().startswith(fence[0] * len(fence))
                                      and lines[j].strip().strip(fence[0]) == ""):
            j += 1
        k = i - 1
        while k >= 0 and not lines[k].strip():
            k -= 1
        mk = MARKER.match(lines[k].strip()) if k >= 0 else None
        attrs = _parse_marker(mk.group("kind"), mk.group("args")) if mk else {"kind": None}
        found.append(Block(page, i + 1, lang, "\n".join(lines[i + 1:j]) + "\n", **attrs))
        i = j + 1
    return found


def shell_blocks(page: Path) -> list[Block]:
    return [b for b in blocks(page) if b.lang in SHELL_LANGS]


def runnable(vcan: bool) -> list[Path]:
    return [p for p in PAGES if any(b.kind == "run" and b.vcan == vcan for b in shell_blocks(p))]


def _default_out(sub: str, rest: str) -> str:
    if sub == "run":
        m = re.search(r"\b(cdrw|missile)\b", rest)
        return f"run-{m.group(1) if m else 'cdrw'}"
    return {"campaign": "campaign-cdrw", "sweep": "sweep-missile", "demo": "demo", "verify": "verify"}[sub]


def rewrite(script: str, scratch: Path) -> str:
    """The block as it runs: out/ paths into the scratch directory, a run directory for every
    hil command that would write one into the checkout's out/."""
    script = OUT_PATH.sub(f"{scratch}/out/", script)

    def add_out(m: re.Match) -> str:
        if "--out" in m.group("rest"):
            return m.group(0)
        return f"{m.group('cmd')} --out {scratch}/out/{_default_out(m.group('sub'), m.group('rest'))}{m.group('rest')}"

    return HIL_WRITES.sub(add_out, script)


def _checkout_state() -> tuple[frozenset, str]:
    out = REPO / "out"
    entries = frozenset((p.name, p.stat().st_mtime_ns) for p in out.iterdir()
                        if p.name not in OUT_OWNED_ELSEWHERE) if out.is_dir() else frozenset()
    git = subprocess.run(["git", "status", "--porcelain", "--untracked-files=all"], cwd=REPO,
                         capture_output=True, text=True).stdout
    return entries, git


def _tail(text: str, n: int = 40) -> str:
    return "\n".join(text.splitlines()[-n:])


def run_page(page: Path, vcan: bool, tmp_path: Path) -> None:
    todo = [b for b in shell_blocks(page) if b.kind == "run" and b.vcan == vcan]
    (tmp_path / "out").mkdir()
    before = _checkout_state()
    for b in todo:
        script = rewrite(b.script(), tmp_path)
        r = subprocess.run(["bash", "-e", "-c", script], cwd=REPO, capture_output=True, text=True,
                           timeout=BLOCK_TIMEOUT_S, env=dict(os.environ, DOCS_SCRATCH=str(tmp_path)))
        assert r.returncode == b.exit, (
            f"{b.where}: exit status {r.returncode}, the page says {b.exit}\n--- ran:\n{script}"
            f"--- stdout:\n{_tail(r.stdout)}\n--- stderr:\n{_tail(r.stderr)}")
    after = _checkout_state()
    assert after[0] == before[0], f"{page.name}: the blocks wrote into the checkout's out/"
    assert after[1] == before[1], f"{page.name}: the blocks changed the checkout:\n{after[1]}"


# ---- the blocks ------------------------------------------------------------------------------
@pytest.mark.parametrize("page", runnable(vcan=False), ids=lambda p: str(p.relative_to(REPO)))
def test_host_blocks_run(page: Path, tmp_path: Path) -> None:
    run_page(page, False, tmp_path)


@pytest.mark.vcan
@pytest.mark.parametrize("page", runnable(vcan=True), ids=lambda p: str(p.relative_to(REPO)))
def test_vcan_blocks_run(page: Path, tmp_path: Path) -> None:
    run_page(page, True, tmp_path)


def test_every_shell_block_is_marked() -> None:
    problems = []
    for page in PAGES:
        for b in shell_blocks(page):
            if b.kind is None:
                problems.append(f"{b.where}: ```{b.lang} block without <!-- run... --> or <!-- norun: REASON -->")
            elif b.marker_error:
                problems.append(f"{b.where}: {b.marker_error}")
        lines = page.read_text(encoding="utf-8").splitlines()
        marked = {b.line for b in shell_blocks(page) if b.kind}
        for n, line in enumerate(lines, 1):
            if MARKER.match(line.strip()):
                nxt = next((k for k in range(n, len(lines)) if lines[k].strip()), None)
                if nxt is None or nxt + 1 not in marked:
                    problems.append(f"{page.relative_to(REPO)}:{n}: a marker not followed by a shell block")
    assert not problems, "\n".join(problems)


def test_rewrite_keeps_the_checkout_out_of_reach(tmp_path: Path) -> None:
    s = rewrite("scripts/with-vcan .venv/bin/hil run cdrw\n"
                "scripts/with-vcan bash -c '.venv/bin/hil run missile --quiet --out out/x >/dev/null &'\n"
                ".venv/bin/hil campaign cdrw --runs 2 | tail -n 1\n"
                "scripts/diag --log out/x/bus.log; scripts/hil-demo; ls build/out/\n", tmp_path)
    assert s.splitlines() == [
        f"scripts/with-vcan .venv/bin/hil run --out {tmp_path}/out/run-cdrw cdrw",
        f"scripts/with-vcan bash -c '.venv/bin/hil run missile --quiet --out {tmp_path}/out/x >/dev/null &'",
        f".venv/bin/hil campaign --out {tmp_path}/out/campaign-cdrw cdrw --runs 2 | tail -n 1",
        f"scripts/diag --log {tmp_path}/out/x/bus.log; scripts/hil-demo; ls build/out/"]


# ---- README ----------------------------------------------------------------------------------
def test_readme_is_the_front_door() -> None:
    text = (REPO / "README.md").read_text(encoding="utf-8")
    assert len(text.splitlines()) <= 150
    assert "SPEC.md" not in text                      # ../shared/SPEC.md: a clone does not have it
    first = blocks(REPO / "README.md")[0]
    assert [ln.split("#")[0].strip() for ln in first.text.splitlines()] == ["scripts/hil-demo", "scripts/test"]
    assert any(b.kind == "run" and b.vcan and b.text.strip() == "scripts/with-vcan .venv/bin/hil run cdrw"
               for b in blocks(REPO / "README.md"))
    for target in re.findall(r"\]\((docs/[^)#]+)(?:#[^)]*)?\)", text):
        assert (REPO / target).is_file(), f"README links to {target}, which does not exist"


def test_dbc_readme_figures_are_the_docs_figures() -> None:
    """dbc/README.md keeps the figures other tests read from it; the bus page says the same."""
    pointer = (REPO / "dbc" / "README.md").read_text(encoding="utf-8")
    page = (REPO / "docs" / "bus.md").read_text(encoding="utf-8")
    assert "docs/bus.md" in pointer
    for fig in re.findall(r"\*\*[^*]+\*\*", pointer):
        assert fig in page, f"{fig} is in dbc/README.md but not in docs/bus.md"
    for vector in re.findall(r"`((?:[0-9A-F]{2} ){7}[0-9A-F]{2})`", pointer):
        assert vector in page


# ---- the site --------------------------------------------------------------------------------
def _generator():
    spec = importlib.util.spec_from_file_location("cli_reference", REPO / "scripts" / "lib" / "cli_reference.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_cli_reference_is_committed_up_to_date() -> None:
    """docs/cli.md holds its generated blocks (plain Markdown reads them without MkDocs), as the
    program generates them now; rendering a page with the blocks filled in changes nothing."""
    gen = _generator()
    page = (REPO / "docs" / "cli.md").read_text(encoding="utf-8")
    for name in ("hil", "hil-exit", "scripts"):
        assert f"<!-- generated: {name} -->\n\n" in page and f"<!-- end generated: {name} -->" in page
    assert "### hil run\n" in page and "| `--out DIR` |" in page
    assert gen.render(page) == page, ("docs/cli.md is stale: run `.venv/bin/python "
                                      "scripts/lib/cli_reference.py --write docs/cli.md`")
    bare = re.sub(r"(<!-- generated: (\S+) -->)\n.*?<!-- end generated: \2 -->", r"\1", page, flags=re.S)
    assert bare != page and gen.render(bare) == page          # a bare marker is filled in alike


def test_cli_reference_has_every_subcommand() -> None:
    gen = _generator()
    hil = Path(sys.executable).with_name("hil")
    top = subprocess.run([str(hil), "--help"], capture_output=True, text=True, check=True).stdout
    commands = re.findall(r"^ {4}([a-z][a-z-]*) ", top, re.M)
    assert {"run", "campaign", "sweep", "demo", "replay"} <= set(commands)
    md = gen.hil_markdown()
    for c in commands:
        assert f"### hil {c}\n" in md, c
    parser, source = gen.find_parser()
    if parser is not None:                            # the structured form, with every option
        assert "| `--out DIR` |" in md and "`--fault SPEC`" in md, source
    fallback = gen.hil_markdown_from_help("test")     # the form used when the module moved
    for c in commands:
        assert f"### hil {c}\n" in fallback, c


def test_site_builds_strict(tmp_path: Path) -> None:
    r = subprocess.run([str(Path(sys.executable).with_name("mkdocs")), "build", "--strict", "--quiet",
                        "--site-dir", str(tmp_path / "site")], cwd=REPO, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    cli = (tmp_path / "site" / "cli.html").read_text(encoding="utf-8")
    assert "hil campaign" in cli and "scripts/with-vcan" in cli and "generated:" not in cli
