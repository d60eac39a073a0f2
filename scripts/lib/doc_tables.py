"""The documentation's tables that the code can produce, produced by the code.

A MkDocs hook (mkdocs.yml `hooks:`): in a page, the line

    <!-- generated: fault-kinds -->   becomes the fault kinds (hil.scenario.faults.KINDS, with
                                      their fields as `hil faults` lists them)
    <!-- generated: frames -->        becomes the frame table, from the DBC (hil.bus.load():
                                      identifier, sender, receivers, period, E2E/SecOC data ID,
                                      signals)
    <!-- generated: fault-matrix -->  becomes the fault matrix's expected counters
                                      (tests/python/rig/test_fault_matrix.py CASES, summed over
                                      both aircraft as the test flies them)

Also a program: `.venv/bin/python scripts/lib/doc_tables.py [fault-kinds|frames|fault-matrix]`
prints the Markdown.  tests/python/test_doc_tables.py checks that each covers what the code
has (every kind, every DBC message, every kind in the matrix).
"""
from __future__ import annotations

import importlib.util
import re
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
MARKER = re.compile(r"^<!-- generated: (fault-kinds|frames|fault-matrix) -->$", re.M)
MATRIX_TEST = REPO / "tests" / "python" / "rig" / "test_fault_matrix.py"
#: a flood's unknown_id is what the flood sent (counted in the run): shown as a name
FLOOD_SENT = "flood frames sent"


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def fault_kinds_markdown() -> str:
    """Every fault kind: level, what it does (its class's docstring), its fields."""
    from hil.scenario.catalog import fields
    from hil.scenario.faults import KINDS
    rows = []
    for kind, cls in KINDS.items():
        doc = " ".join((cls.__doc__ or "").split())
        own = [name for name, *_ in fields(cls) if name not in ("start", "duration")]
        rows.append(f"| `{kind}` | {cls.level} | {_cell(doc)} | {', '.join(f'`{n}`' for n in own) or '—'} |")
    return "\n".join(["| kind | level | what it does | fields (besides `start`, `duration`) |",
                      "|---|---|---|---|", *rows])


def frames_markdown() -> str:
    """Every DBC message, by identifier."""
    from hil.bus import load
    rows = []
    for m in sorted(load().messages, key=lambda m: m.frame_id):
        data_id = (f"SecOC 0x{m.secoc_data_id:04X}" if m.secoc_data_id
                   else f"0x{m.data_id:04X}" if m.data_id else "—")
        signals = [s.name for s in m.signals if s.name not in ("crc", "counter")]
        rows.append(f"| 0x{m.frame_id:03X} | `{m.name}` | {', '.join(m.senders)} | "
                    f"{', '.join(m.receivers) or '—'} | {m.cycle_ms or 'event'} | {data_id} | "
                    f"{_cell(', '.join(signals))} |")
    return "\n".join(["| ID | message | sender | receivers | period (ms) | E2E data ID | "
                      "signals (besides `crc`, `counter`) |", "|---|---|---|---|---|---|---|", *rows])


def _matrix_module():
    """The fault matrix test as a module (its helpers' directory on the path)."""
    sys.path.insert(0, str(MATRIX_TEST.parent.parent))
    sys.path.insert(0, str(MATRIX_TEST.parent))
    spec = importlib.util.spec_from_file_location("fault_matrix_cases", MATRIX_TEST)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def fault_matrix_markdown() -> str:
    """Each fault kind's expected counters, both aircraft in one session, as the matrix test
    derives them (`flood`'s unknown_id: the frames the flood sent, counted in the run)."""
    mod = _matrix_module()
    rows = []
    for kind in mod.CASES:
        want: dict[str, int | str] = dict(mod.expected(kind, {a: {"flood": 0} for a in mod.AIRCRAFT}))
        if kind == "flood":
            want["unknown_id"] = FLOOD_SENT
        rows.append(f"| {kind} | " + " | ".join(str(want[c]) for c in mod.COUNTERS) + " |")
    head = ["e2e ok" if c == "ok" else c for c in mod.COUNTERS]
    return "\n".join([f"| fault class | {' | '.join(head)} |", "|" + "---|" * (len(head) + 1), *rows])


GENERATORS = {"fault-kinds": fault_kinds_markdown, "frames": frames_markdown,
              "fault-matrix": fault_matrix_markdown}


# ---- the MkDocs hook -------------------------------------------------------------------------
def on_page_markdown(markdown: str, page, config, files) -> str:  # noqa: ANN001 - MkDocs' hook
    if not MARKER.search(markdown):
        return markdown
    return MARKER.sub(lambda m: GENERATORS[m.group(1)](), markdown)


if __name__ == "__main__":
    which = sys.argv[1:] or list(GENERATORS)
    print("\n\n".join(GENERATORS[w]() for w in which))
