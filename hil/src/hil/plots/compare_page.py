"""compare.html: the page of `hil compare`, one self-contained file (its figures inlined as
data URIs, its style inline: it opens anywhere, mailed or copied alone).  Each run with its
verdict line, the figures (hil.plots.compare), and the headline numbers side by side with
each run's difference from the first.
"""
from __future__ import annotations

import base64
import html
import math
from collections.abc import Sequence
from pathlib import Path

from hil.io.rundir import atomic_write_text
from hil.plots.compare import Run
from hil.results.verdict import lines as verdict_lines

NAME = "compare.html"
_STYLE = """body{font-family:sans-serif;margin:1.5em;max-width:1100px}
table{border-collapse:collapse;font-size:0.85em}td,th{border:1px solid #bbb;padding:3px 8px}
td.n{text-align:right;font-family:monospace}th{background:#eee}img{max-width:100%;border:1px solid #ddd}
code{font-size:0.85em}.v{font-family:monospace;font-size:0.8em}"""


def _num(v: float | None) -> str:
    return "–" if v is None or not math.isfinite(v) else f"{v:.4g}"


def _diff(d: float | None, base: float | None) -> str:
    """+0.0026 (+3.6 %): a difference, and relative to the first run's value."""
    if d is None or base is None or not math.isfinite(d):
        return "–"
    if d == 0:
        return "0"
    return f"{d:+.4g}" + (f" ({100 * d / base:+.1f} %)" if base else "")


def rows(runs: Sequence[Run]) -> list[tuple[str, list[float | None], list[float | None]]]:
    """(metric, each run's value, each later run's difference from the first) for every
    headline number some run has."""
    names = list(dict.fromkeys(k for r in runs for k in r.metrics))
    out = []
    for n in names:
        vals = [r.metrics.get(n) for r in runs]
        base = vals[0]
        diffs = [None if base is None or v is None else v - base for v in vals[1:]]
        out.append((n, vals, diffs))
    return out


def write_page(runs: Sequence[Run], figures: Sequence[Path], out: Path, command: str) -> Path:
    e = html.escape
    parts = [f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>hil compare: "
             f"{e(', '.join(r.label for r in runs))}</title><style>{_STYLE}</style></head><body>",
             f"<h1>{len(runs)} runs compared</h1><p><code>{e(command)}</code></p><h2>Runs</h2><ol>"]
    for r in runs:
        verdicts = "".join(f"<div class='v'>{e(v)}</div>" for v in verdict_lines(r.summary))
        parts.append(f"<li><b>{e(r.label)}</b> <code>{e(str(r.path))}</code>{verdicts}</li>")
    parts.append("</ol><h2>Headline numbers</h2><table><tr><th>number</th>"
                 + "".join(f"<th>{e(r.label)}</th>" for r in runs)
                 + "".join(f"<th>{e(r.label)} − {e(runs[0].label)}</th>" for r in runs[1:]) + "</tr>")
    for name, vals, diffs in rows(runs):
        parts.append(f"<tr><td>{e(name)}</td>" + "".join(f"<td class='n'>{_num(v)}</td>" for v in vals)
                     + "".join(f"<td class='n'>{_diff(d, vals[0])}</td>" for d in diffs) + "</tr>")
    parts.append("</table><h2>Figures</h2>")
    for png in figures:
        data = base64.b64encode(png.read_bytes()).decode("ascii")
        parts.append(f"<h3>{e(png.name)}</h3><img alt='{e(png.name)}' src='data:image/png;base64,{data}'>")
    parts.append("</body></html>\n")
    return atomic_write_text(out / NAME, "\n".join(parts))
