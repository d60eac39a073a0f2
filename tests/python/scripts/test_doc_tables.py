"""The docs' tables that the code can produce are produced by it (scripts/lib/doc_tables.py,
a MkDocs hook): each covers everything the code has, and the pages hold the markers, not hand
copies."""
from __future__ import annotations

import importlib.util
from pathlib import Path

from hil.bus import load
from hil.scenario.faults import KINDS, WIRE_KINDS

REPO = Path(__file__).resolve().parents[3]


def _tables():
    spec = importlib.util.spec_from_file_location("doc_tables", REPO / "scripts" / "lib" / "doc_tables.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _first_cells(markdown: str) -> list[str]:
    rows = [line for line in markdown.splitlines() if line.startswith("| ")][1:]
    return [row.split("|")[1].strip().strip("`") for row in rows]


def test_every_fault_kind_is_in_the_table_in_its_order():
    md = _tables().fault_kinds_markdown()
    assert _first_cells(md) == list(KINDS)
    assert "| `silence` | bus | The simulator sends nothing at all" in md


def test_every_dbc_frame_is_in_the_frame_table():
    md = _tables().frames_markdown()
    names = [line.split("|")[2].strip().strip("`") for line in md.splitlines()[2:]]
    assert names == [m.name for m in sorted(load().messages, key=lambda m: m.frame_id)]
    assert "| 0x020 | `SIM_TICK` | SIM | FCC |" in md


def test_the_fault_matrix_covers_every_kind_with_the_tests_arithmetic():
    md = _tables().fault_matrix_markdown()
    assert sorted(_first_cells(md)) == sorted(set(KINDS) - set(WIRE_KINDS))
    assert "| spike | 333 | 0 |" in md and "| silence | 275 | 0 | 1 | 5 | 0 | 50 |" in md


def test_the_pages_hold_their_tables_as_the_code_makes_them_now():
    tables = _tables()
    for page, name in (("docs/scenarios.md", "fault-kinds"), ("docs/bus.md", "frames"),
                       ("docs/reliability.md", "fault-matrix"), ("dbc/README.md", "bus-load"),
                       ("docs/bus.md", "bus-load-table")):
        text = (REPO / page).read_text()
        assert f"<!-- generated: {name} -->\n\n{tables.GENERATORS[name]()}\n\n<!-- end generated: {name} -->" \
            in text, f"{page} is not current: run .venv/bin/python scripts/lib/doc_tables.py --write"
        site = tables.on_page_markdown(text, None, None, None)   # the site: the text, no markers
        assert tables.GENERATORS[name]() in site and f"generated: {name}" not in site
    assert "scripts/lib/doc_tables.py" in (REPO / "mkdocs.yml").read_text()
