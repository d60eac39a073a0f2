"""Generated blocks of the documentation's pages, for the programs that fill them in
(scripts/lib/cli_reference.py, scripts/lib/doc_tables.py): in a page,

    <!-- generated: NAME -->

    ...the text NAME's generator produces...

    <!-- end generated: NAME -->

is committed filled in (the page reads the same on GitHub; a test fails while it is stale),
`--write` fills it in afresh (a bare opening marker as well), and the MkDocs hook
(on_page_markdown) renders the text alone, without the markers, for the site.

MkDocs loads the two programs by path (mkdocs.yml `hooks:`), not as a package, so they load
this module by its path beside them (runpy), not by an import.
"""
from __future__ import annotations

import re
import sys
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any


class Blocks:
    """The blocks of one program: each NAME and its generator (in the order printed)."""

    def __init__(self, generators: Mapping[str, Callable[[], str]]) -> None:
        self.generators = generators
        names = "|".join(re.escape(n) for n in sorted(generators, key=len, reverse=True))
        #: a block: its opening marker, then (when committed) its text and its end marker
        self.marker = re.compile(rf"^<!-- generated: ({names}) -->"
                                 r"(?:\n(?:(?!<!-- generated: ).*\n)*?<!-- end generated: \1 -->)?$",
                                 re.MULTILINE)

    def render(self, markdown: str, markers: bool = True) -> str:
        """The page with every block generated afresh, between its markers (the committed
        page), or in their place (markers=False: the site's page)."""
        def block(m: re.Match[str]) -> str:
            name, text = m.group(1), self.generators[m.group(1)]().strip()
            return f"<!-- generated: {name} -->\n\n{text}\n\n<!-- end generated: {name} -->" if markers else text
        return self.marker.sub(block, markdown)

    def on_page_markdown(self, markdown: str, page: Any, config: Any, files: Any) -> str:
        """The MkDocs hook: a page with blocks, rendered for the site."""
        return self.render(markdown, markers=False) if self.marker.search(markdown) else markdown

    def main(self, argv: Sequence[str], pages: Sequence[Path] = (), sep: str = "\n\n") -> None:
        """`--write [PAGE...]`: the pages filled in (no PAGE: `pages`); else the Markdown of
        the blocks named (none named: all) on stdout."""
        if argv[:1] == ["--write"]:
            for page in [Path(p) for p in argv[1:]] or pages:
                page.write_text(self.render(page.read_text(encoding="utf-8")), encoding="utf-8")
        else:
            sys.stdout.write(sep.join(self.generators[w]() for w in (argv or list(self.generators))) + "\n")
