"""The documentation's tables that the code can produce, produced by the code.

In a page, the block

    <!-- generated: fault-kinds -->   the fault kinds (hil.scenario.faults.KINDS, with their
                                      fields as `hil faults` lists them; docs/scenarios.md)
    <!-- generated: frames -->        the frame table, from the DBC (hil.bus.load(): identifier,
                                      sender, receivers, period, E2E/SecOC data ID, signals;
                                      docs/bus.md)
    <!-- generated: fault-matrix -->  the fault matrix's counters, as
                                      tests/python/rig/test_fault_matrix.py requires them
                                      (docs/reliability.md)
    <!-- generated: bus-load -->      the bus load of the DBC's frames at the default rates
                                      (hil.bus.busload; dbc/README.md)
    <!-- generated: bus-load-table --> the same, frame by frame, grouped by rate (docs/bus.md)
    ...the generated text...
    <!-- end generated: NAME -->

holds the generated text, committed (as docs/cli.md's, scripts/lib/cli_reference.py), so that the
page reads the same on GitHub; tests/python/scripts/test_doc_tables.py checks it is up to date
(a new fault kind, a DBC change: the test fails until

    .venv/bin/python scripts/lib/doc_tables.py --write docs/scenarios.md docs/bus.md docs/reliability.md dbc/README.md

brings the pages up to date).  The MkDocs hook (mkdocs.yml `hooks:`) renders the same blocks
afresh, without their markers.  Also a program that prints the Markdown:
`.venv/bin/python scripts/lib/doc_tables.py [fault-kinds|frames|fault-matrix|bus-load|bus-load-table]`.
"""
from __future__ import annotations

import importlib.util
import runpy
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
#: the pages that hold the blocks (--write without pages)
PAGES = ("docs/scenarios.md", "docs/bus.md", "docs/reliability.md", "dbc/README.md")
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


def _rates(missile_period_s: float) -> dict[str, float]:
    """Frames per second of each DBC frame at the rig's default rates (hil.bus.busload)."""
    from hil.bus import busload, load
    spec = load()
    return busload.default_rates([m.name for m in spec.messages], {m.name: m.cycle_ms for m in spec.messages},
                                 missile_period_s=missile_period_s)


def bus_load(missile_period_s: float) -> tuple[float, float]:
    """Frames per second and load (%) of the DBC's frames at the rig's default rates, the
    missile's step period missile_period_s, worst-case bit stuffing."""
    from hil.bus import busload, load
    spec = load()
    rates = _rates(missile_period_s)
    bits = sum(r * busload.worst_case_bits(spec.by_name(n).length) for n, r in rates.items())
    return sum(rates.values()), busload.load_percent(bits, spec.baudrate)


def bus_load_markdown() -> str:
    """The bus load at the default missile period and at its shortest (T = 0.02 s)."""
    frames, pct = bus_load(0.05)
    frames_fast, pct_fast = bus_load(0.02)
    return (f"- Bus load at 500 kbit/s, default rates, worst-case bit stuffing: **{frames:.0f}** frames/s, "
            f"**{pct:.1f} %**; at the shortest missile period T = 0.02 s, **{pct_fast:.2f} %** "
            f"({frames_fast:.0f} frames/s).")


def bus_load_table_markdown() -> str:
    """The frames of the bus load at the default rates, grouped by rate, then the load."""
    by_rate: dict[float, list[str]] = {}
    for name, rate in _rates(0.05).items():
        if rate:
            by_rate.setdefault(rate, []).append(name)
    rows = [f"| {rate:g} | {len(names)} | {', '.join(f'`{n}`' for n in names)} | {rate * len(names):g} |"
            for rate, names in sorted(by_rate.items(), reverse=True)]
    frames = sum(rate * len(names) for rate, names in by_rate.items())
    return "\n".join(["| frames/s each | frames | which | frames/s |", "|---|---|---|---|", *rows,
                      f"| | | **total** | **{frames:g}** |", "", bus_load_markdown().removeprefix("- ")])


GENERATORS = {"fault-kinds": fault_kinds_markdown, "frames": frames_markdown,
              "fault-matrix": fault_matrix_markdown, "bus-load": bus_load_markdown,
              "bus-load-table": bus_load_table_markdown}


#: (MkDocs loads this file by its path: the shared module beside it is loaded by its path too)
BLOCKS = runpy.run_path(str(Path(__file__).with_name("generated_blocks.py")))["Blocks"](GENERATORS)
render = BLOCKS.render
on_page_markdown = BLOCKS.on_page_markdown   # the MkDocs hook (mkdocs.yml)


if __name__ == "__main__":
    BLOCKS.main(sys.argv[1:], [REPO / p for p in PAGES])
