"""The command-line reference of the documentation, generated from the programs themselves.

In a page (docs/cli.md), the block

    <!-- generated: hil -->        one section per `hil` subcommand, from its argparse parser
    <!-- generated: scripts -->    the `--help` of every script in scripts/
    <!-- generated: hil-exit -->   the table of `hil`'s exit statuses (hil.cli.usage.EXIT_STATUS,
                                   the table `hil --help` prints)
    ...the generated text...
    <!-- end generated: NAME -->

holds the generated text, committed, so that the page reads as it is on GitHub or in an editor
as well as on the site; tests/python/test_docs.py checks it is up to date, and

    .venv/bin/python scripts/lib/cli_reference.py --write docs/cli.md

brings it up to date.  The MkDocs hook (mkdocs.yml `hooks:`) renders the same blocks afresh,
without their markers (a marker without its end line is filled in as well).  Also a program that prints the Markdown:
`.venv/bin/python scripts/lib/cli_reference.py [hil|hil-exit|scripts]`.

`hil`'s parser is found by module path at run time (PARSER_MODULES x PARSER_FACTORIES, the first
that imports and builds an argparse parser).  When none does (the package was reorganised), the
section falls back to the text of `hil --help` and `hil COMMAND --help`, and says so: the site
still builds.
"""
from __future__ import annotations

import argparse
import importlib
import logging
import os
import re
import runpy
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
#: where `hil`'s parser factory may live, tried in order
PARSER_MODULES = ("hil.cli.parser",)
PARSER_FACTORIES = ("build",)
#: the scripts whose --help goes into the reference, in this order
SCRIPTS = ("setup", "test", "hil-demo", "with-vcan", "diag", "bench")
WIDTH = 100

log = logging.getLogger("mkdocs.hooks.cli_reference")


# ---- hil, from argparse ------------------------------------------------------------------------
def find_parser() -> tuple[argparse.ArgumentParser | None, str]:
    """(parser, "module.factory") or (None, why not)."""
    tried = []
    for mod_name in PARSER_MODULES:
        try:
            mod = importlib.import_module(mod_name)
        except Exception as e:  # noqa: BLE001 - a moved module is a fallback, not an error
            tried.append(f"{mod_name}: {type(e).__name__}")
            continue
        for fn_name in PARSER_FACTORIES:
            fn = getattr(mod, fn_name, None)
            if not callable(fn):
                continue
            try:
                p = fn()
            except Exception as e:  # noqa: BLE001
                tried.append(f"{mod_name}.{fn_name}(): {type(e).__name__}")
                continue
            if isinstance(p, argparse.ArgumentParser):
                return p, f"{mod_name}.{fn_name}"
        tried.append(f"{mod_name}: no parser factory")
    return None, "; ".join(tried)


def _formatter(parser: argparse.ArgumentParser) -> argparse.HelpFormatter:
    return argparse.HelpFormatter(parser.prog, width=WIDTH)


def _usage(parser: argparse.ArgumentParser) -> str:
    f = _formatter(parser)
    f.add_usage(parser.usage, parser._actions, parser._mutually_exclusive_groups)
    return f.format_help().strip()


def _cell(text: str) -> str:
    """Help text as a table cell: `code` kept, Markdown's other special characters literal."""
    parts = re.split(r"(`[^`]*`)", text.replace("\n", " "))
    for i, part in enumerate(parts):
        if i % 2 == 0:
            part = part.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
            parts[i] = re.sub(r"([\\*_\[\]|])", r"\\\1", part)
        else:
            parts[i] = part.replace("|", "\\|")
    return "".join(parts)


def _default(action: argparse.Action) -> str:
    d = action.default
    if d is None or d is False or d is argparse.SUPPRESS or d in ([], "") or isinstance(action, argparse._HelpAction):
        return ""
    if isinstance(d, (list, tuple)):
        items = [f"{x:g}" if isinstance(x, float) else str(x) for x in d]
        if len(items) > 6:
            return f"`{','.join(items[:2])},…,{items[-1]}` ({len(items)} values)"
        return f"`{','.join(items)}`"
    return f"`{d}`"


def _name(action: argparse.Action) -> str:
    if action.option_strings:
        if action.nargs == 0:
            return ", ".join(f"`{o}`" for o in action.option_strings)
        metavar = action.metavar or (("{" + ",".join(action.choices) + "}") if action.choices else action.dest.upper())
        return ", ".join(f"`{o} {metavar}`" for o in action.option_strings)
    return f"`{action.metavar or action.dest}`"


def _arguments_table(parser: argparse.ArgumentParser, shared: frozenset[str] = frozenset()) -> list[str]:
    """The arguments' table; shared: hil's own options (-v, --debug) a subcommand also takes,
    listed once, under hil."""
    rows = []
    for a in parser._actions:
        if isinstance(a, (argparse._HelpAction, argparse._SubParsersAction)) or a.dest in shared:
            continue
        text = _cell(a.help or "")
        if a.choices and not a.option_strings:
            text = (text + " " if text else "") + "one of " + ", ".join(f"`{c}`" for c in a.choices)
        elif a.choices and a.metavar:
            text += " (" + ", ".join(f"`{c}`" for c in a.choices) + ")"
        if a.nargs in ("?", "*") and not a.option_strings:
            text += " (optional)"
        if a.nargs == "*" and not a.option_strings:
            text += ", any number"
        if getattr(a, "action", None) == "append" or isinstance(a, argparse._AppendAction):
            text += " (repeatable)"
        rows.append(f"| {_name(a)} | {text} | {_default(a)} |")
    if not rows:
        return []
    return ["| argument | meaning | default |", "|---|---|---|", *rows]


def _subcommands(parser: argparse.ArgumentParser, prefix: str = "") -> list[tuple[str, str, argparse.ArgumentParser]]:
    """(name, help, parser) of every subcommand, a group's (`hil bus wcrt`) after the group."""
    out = []
    for a in parser._actions:
        if isinstance(a, argparse._SubParsersAction):
            helps = {c.dest: c.help or "" for c in a._choices_actions}
            for name, sub in a.choices.items():
                out.append((prefix + name, helps.get(name, ""), sub))
                out += _subcommands(sub, f"{prefix}{name} ")
    return out


def hil_markdown_from_parser(parser: argparse.ArgumentParser, source: str) -> str:
    lines = [f"Generated from `hil`'s argparse parser (`{source}`) by scripts/lib/cli_reference.py.", ""]
    if parser.description:
        lines += [parser.description, ""]
    lines += ["```text", _usage(parser), "```", ""]
    lines += _arguments_table(parser) + [""]
    shared = frozenset(a.dest for a in parser._actions if a.option_strings)
    for name, helptext, sub in _subcommands(parser):
        lines += [f"### hil {name}", ""]
        if helptext:
            lines += [helptext[0].upper() + helptext[1:] + ".", ""]
        lines += ["```text", _usage(sub), "```", ""]
        lines += _arguments_table(sub, shared) + [""]
    return "\n".join(lines)


def _hil_command() -> list[str]:
    exe = Path(sys.executable).with_name("hil")
    return [str(exe)] if exe.exists() else [sys.executable, "-m", "hil.cli"]


def _help_text(cmd: list[str]) -> str:
    env = dict(os.environ, COLUMNS=str(WIDTH))
    r = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=REPO, timeout=120)
    return (r.stdout or r.stderr).rstrip()


def hil_markdown_from_help(why: str) -> str:
    """The fallback: `hil --help` and each `hil COMMAND --help` as text."""
    hil = _hil_command()
    top = _help_text([*hil, "--help"])
    lines = ["The parser could not be imported at build time (" + why + "); this section is the "
             "text of `hil --help` and `hil COMMAND --help` instead.", "", "```text", top, "```", ""]
    in_list = False
    for line in top.splitlines():
        if re.match(r"^(positional arguments|commands):", line, re.I) or line.strip().startswith("COMMAND"):
            in_list = True
            continue
        m = re.match(r"^    ([a-z][a-z-]*)\s{2,}", line)
        if in_list and m and m.group(1) not in ("COMMAND",):
            name = m.group(1)
            lines += [f"### hil {name}", "", "```text", _help_text([*hil, name, "--help"]), "```", ""]
        elif in_list and line and not line.startswith(" "):
            in_list = False
    return "\n".join(lines)


def hil_markdown() -> str:
    parser, source = find_parser()
    if parser is not None:
        return hil_markdown_from_parser(parser, source)
    log.info("cli_reference: no hil parser among %s (%s): using `hil --help`", PARSER_MODULES, source)
    return hil_markdown_from_help(source)


def exit_markdown() -> str:
    """`hil`'s exit statuses as a table, from the one table `hil --help` prints."""
    try:
        from hil.cli.usage import EXIT_STATUS
    except Exception as e:  # noqa: BLE001 - a moved module is a fallback, not an error
        log.info("cli_reference: no hil.cli.usage.EXIT_STATUS (%s): using `hil --help`", type(e).__name__)
        return "```text\n" + _help_text([*_hil_command(), "--help"]).split("\nexit status")[-1] + "\n```"
    rows = [f"| {status} | {_cell(meaning)} |" for status, meaning in EXIT_STATUS]
    return "\n".join(["| exit | meaning |", "|---|---|", *rows])


# ---- the scripts, from their --help -----------------------------------------------------------
def scripts_markdown() -> str:
    lines = ["Generated from each script's `--help` by scripts/lib/cli_reference.py.", ""]
    for name in SCRIPTS:
        path = REPO / "scripts" / name
        if not path.exists():
            continue
        lines += [f"### scripts/{name}", "", "```text", _help_text([str(path), "--help"]), "```", ""]
    return "\n".join(lines)


GENERATORS = {"hil": hil_markdown, "hil-exit": exit_markdown, "scripts": scripts_markdown}


#: (MkDocs loads this file by its path: the shared module beside it is loaded by its path too)
BLOCKS = runpy.run_path(str(Path(__file__).with_name("generated_blocks.py")))["Blocks"](GENERATORS)
render = BLOCKS.render
on_page_markdown = BLOCKS.on_page_markdown   # the MkDocs hook (mkdocs.yml)


if __name__ == "__main__":
    BLOCKS.main(sys.argv[1:], sep="\n")
