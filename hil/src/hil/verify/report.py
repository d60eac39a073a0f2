"""What a verification run says: one line per case, JUnit XML for CI, an HTML report for a
review (summary, traceability matrix, each case with its measured values, figures and the
command to re-fly it).  Each file is written whole or not at all (a temporary sibling renamed
over it); the report's directory is staged and published by hil.io.rundir, and a run with a
case that could not run is not published (hil.cli.verify)."""
from __future__ import annotations

import html
import os
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from pathlib import Path

from hil.io.rundir import atomic_write, atomic_write_text
from hil.verify.coverage import Matrix, count_lines, work_text
from hil.verify.platform import INCONCLUSIVE
from hil.verify.runner import ERROR, EVERY_REQUIREMENT, FAIL, PASS, CaseResult, Check
from hil.verify.suite import Suite

NOT_RUN = "not run"
_WORD = {PASS: "PASS", FAIL: "FAIL", ERROR: "ERROR", INCONCLUSIVE: "INCONCLUSIVE", NOT_RUN: "-"}
#: the verdicts counted, in the order the summary line gives them
VERDICTS = (PASS, FAIL, INCONCLUSIVE, ERROR)


def line(r: CaseResult) -> str:
    """`PASS  suite/case  [REQ-1, REQ-2]  (3 expectations, 1.9 s)` and, when not passed, why."""
    head = (f"{_WORD[r.verdict]:<5}  {r.suite}/{r.case.id}  [{', '.join(r.case.requirements)}]  "
            f"({len(r.case.expect)} expectation{'s' if len(r.case.expect) != 1 else ''}, {r.seconds:.1f} s)")
    if r.verdict == ERROR:
        return f"{head}\n       error: {r.error}"
    return "\n".join([head] + [f"       {'failed' if c.verdict == FAIL else c.verdict} {c.requirement}: {c.text}   "
                               f"measured: {c.measured}" for c in r.failed_checks])


def counts(results: Sequence[CaseResult]) -> dict[str, int]:
    return {v: sum(1 for r in results if r.verdict == v) for v in VERDICTS}


def requirement_verdict(req_id: str, results: Sequence[CaseResult], suite: str) -> str:
    """A requirement passes when every expectation traced to it passed; a case of it that could
    not run makes it an error; no case of it ran (--case): not run."""
    mine = [r for r in results if r.suite == suite and req_id in r.case.requirements]
    if not mine:
        return NOT_RUN
    if any(r.verdict == ERROR for r in mine):
        return ERROR
    checks = [c.verdict for r in mine for c in r.checks if c.requirement in (req_id, EVERY_REQUIREMENT)]
    return FAIL if FAIL in checks else INCONCLUSIVE if INCONCLUSIVE in checks else PASS


def junit(results: Sequence[CaseResult], suites: Sequence[Suite], path: Path, target: str,
          matrix: Matrix | None = None) -> None:
    root = ET.Element("testsuites", name="hil verify")
    for s in suites:
        mine = [r for r in results if r.suite == s.name]
        c = counts(mine)
        ts = ET.SubElement(root, "testsuite", name=s.name, tests=str(len(mine)), failures=str(c[FAIL]),
                           errors=str(c[ERROR]), skipped=str(c[INCONCLUSIVE]),
                           time=f"{sum(r.seconds for r in mine):.3f}")
        props = ET.SubElement(ts, "properties")
        ET.SubElement(props, "property", name="target", value=target)
        if matrix is not None:
            _coverage_properties(props, matrix, s.name)
        for r in mine:
            tc = ET.SubElement(ts, "testcase", classname=s.name, name=r.case.id, time=f"{r.seconds:.3f}")
            tprops = ET.SubElement(tc, "properties")
            for req in r.case.requirements:
                ET.SubElement(tprops, "property", name="requirement", value=req)
            if r.verdict == FAIL:
                bad = r.failed_checks
                f = ET.SubElement(tc, "failure",
                                  message=f"{bad[0].requirement}: {bad[0].text} (measured: {bad[0].measured})")
                f.text = "\n".join(f"{c.requirement}: {c.text}: measured {c.measured}" for c in bad)
            elif r.verdict == ERROR:
                ET.SubElement(tc, "error", message=r.error)
            elif r.verdict == INCONCLUSIVE:   # JUnit's word for "neither passed nor failed"
                bad = r.failed_checks
                sk = ET.SubElement(tc, "skipped", message=f"inconclusive: {bad[0].requirement}: {bad[0].text} "
                                                          f"(measured: {bad[0].measured})")
                sk.text = "\n".join(f"{c.requirement}: {c.text}: measured {c.measured}" for c in bad)
            out = ET.SubElement(tc, "system-out")
            out.text = f"re-fly: {r.command}\n" + "\n".join(
                f"{_WORD[c.verdict]} {c.requirement} {c.text}: {c.measured}" for c in r.checks)
    ET.indent(root)
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic_write(path, ET.tostring(root, encoding="utf-8", xml_declaration=True))  # never half a file


def _coverage_properties(props: ET.Element, matrix: Matrix, suite: str) -> None:
    """Per requirement the lines its cases reach; the two work lists' sizes."""
    for row in matrix.rows:
        if row.suite == suite:
            got, of = matrix.total(row.lines)
            ET.SubElement(props, "property", name=f"coverage {row.requirement}", value=f"{got}/{of} lines")
    for name, work in (("unit-only", matrix.unit_only()), ("unreached", matrix.unreached())):
        ET.SubElement(props, "property", name=f"coverage {name} lines", value=str(count_lines(work, matrix)))


_CSS = """body{font-family:sans-serif;margin:2em;max-width:70em}table{border-collapse:collapse;margin:1em 0}
td,th{border:1px solid #bbb;padding:.3em .6em;text-align:left;vertical-align:top}
.pass{background:#d9f2d9}.fail{background:#f8d0d0}.error{background:#ffe9b3}.not-run{color:#888}
.inconclusive{background:#dde4f5}
code{font-size:90%}
table.cov td{text-align:right;font-size:80%}table.cov th{font-size:70%;writing-mode:vertical-rl}
img{max-width:32em;margin:.3em;border:1px solid #ddd}img.evidence{max-width:28em}"""


def _cell(verdict: str) -> str:
    return f'<td class="{verdict.replace(" ", "-")}">{_WORD[verdict]}</td>'


def _evidence(c: Check, report_dir: Path) -> str:
    """A windowed check's figure (the window shaded, the band, the value marked), in its row."""
    if c.figure is None:
        return ""
    rel = html.escape(os.path.relpath(c.figure, report_dir))
    return f'<br><a href="{rel}"><img class="evidence" src="{rel}" alt="evidence: {html.escape(c.requirement)}"></a>'


def _case_html(r: CaseResult, report_dir: Path) -> list[str]:
    e = html.escape
    out = [f'<h3 id="{e(r.suite)}-{e(r.case.id)}">{e(r.suite)} / {e(r.case.id)} '
           f'<span class="{r.verdict}">{_WORD[r.verdict]}</span></h3>',
           f"<p>{e(r.case.title)}</p>" if r.case.title else "",
           f"<p>Requirements: {e(', '.join(r.case.requirements))}; aircraft: {e(', '.join(r.case.aircraft))}, "
           f"{e(r.case.mode)}{', attack: ' + e(r.case.attack) if r.case.attack else ''}"
           f"{f', {r.case.n_flights} flights' if r.case.n_flights > 1 else ''}; {r.seconds:.1f} s</p>",
           f"<p>Re-fly: <code>{e(r.command)}</code></p>"]
    if r.verdict == ERROR:
        out.append(f'<p class="error">Could not run: {e(r.error)}</p>')
    if r.checks:
        out.append("<table><tr><th>requirement</th><th>expectation</th><th>measured</th><th>verdict</th></tr>")
        out += [f"<tr><td>{e(c.requirement)}</td><td><code>{e(c.text)}</code></td><td>{e(c.measured)}"
                f"{_evidence(c, report_dir)}</td>{_cell(c.verdict)}</tr>" for c in r.checks]
        out.append("</table>")
    drawn = {c.figure for c in r.checks if c.figure is not None}
    if r.run_dir is not None and r.run_dir.is_dir():
        for png in sorted(p for p in r.run_dir.glob("*.png") if p not in drawn):
            rel = os.path.relpath(png, report_dir)
            out.append(f'<a href="{e(rel)}"><img src="{e(rel)}" alt="{e(png.name)}"></a>')
    return out


def coverage_html(matrix: Matrix) -> list[str]:
    """The section "Coverage per requirement": the matrix (% of each file's lines its cases
    reach) and the two DO-178C work lists."""
    e = html.escape
    out = ["<h2>Coverage per requirement</h2>",
           "<p>Lines of the hand-written firmware (fcc's coverage build) each requirement's cases reach, "
           "in % of each file's lines of code.</p>",
           '<table class="cov"><tr><th>requirement</th><th>all</th>'
           + "".join(f"<th>{e(f)}</th>" for f in matrix.files) + "</tr>"]
    for row in matrix.rows:
        got, of = matrix.total(row.lines)
        out.append(f"<tr><td>{e(row.suite)} / {e(row.requirement)}</td><td>{100.0 * got / of if of else 0:.1f}</td>"
                   + "".join(f"<td>{matrix.percent(row, f):.0f}</td>" for f in matrix.files) + "</tr>")
    out.append("</table>")
    for title, work in (("Reached by unit tests only (each needs a requirement or a rationale)", matrix.unit_only()),
                        ("Reached by nothing (dead-code candidates)", matrix.unreached())):
        ranges = work_text(work)
        out.append(f"<h3>{e(title)}: {count_lines(work, matrix)} lines, {len(ranges)} ranges</h3>"
                   f"<details><summary>file:lines</summary><pre>{e(chr(10).join(ranges))}</pre></details>")
    return out


def work_lists(matrix: Matrix, report_dir: Path) -> None:
    """coverage/unit-only.txt and coverage/unreached.txt: file:first-last, one range a line."""
    (report_dir / "coverage").mkdir(parents=True, exist_ok=True)
    for name, work in (("unit-only", matrix.unit_only()), ("unreached", matrix.unreached())):
        atomic_write_text(report_dir / "coverage" / f"{name}.txt", "".join(f"{r}\n" for r in work_text(work)))


def html_report(results: Sequence[CaseResult], suites: Sequence[Suite], report_dir: Path,
                target: str, command: str, matrix: Matrix | None = None) -> Path:
    """report_dir/index.html (the figures stay in the cases' run directories beside it)."""
    e = html.escape
    c = counts(results)
    inconclusive = f"{c[INCONCLUSIVE]} inconclusive (platform-limited), " if c[INCONCLUSIVE] else ""
    body = [f"<h1>hil verify: {c[PASS]} passed, {c[FAIL]} failed, {inconclusive}{c[ERROR]} errors</h1>",
            f"<p>Target: <b>{e(target)}</b>. Command: <code>{e(command)}</code></p>"]
    for s in suites:
        mine = [r for r in results if r.suite == s.name]
        body += [f"<h2>{e(s.name)}</h2>", f"<p>{e(s.title)}</p>",
                 "<table><tr><th>requirement</th><th>text</th><th>source</th><th>cases</th><th>verdict</th></tr>"]
        for req in s.requirements:
            cases = [r for r in mine if req.id in r.case.requirements]
            links = ", ".join(f'<a href="#{e(s.name)}-{e(r.case.id)}">{e(r.case.id)}</a> ({_WORD[r.verdict]})'
                              for r in cases)
            body.append(f"<tr><td>{e(req.id)}</td><td>{e(req.text)}</td><td>{e(req.source)}</td><td>{links}</td>"
                        f"{_cell(requirement_verdict(req.id, results, s.name))}</tr>")
        body.append("</table>")
        for r in mine:
            body += _case_html(r, report_dir)
    if matrix is not None:
        body += coverage_html(matrix)
    page = ("<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>hil verify</title>"
            f"<style>{_CSS}</style></head><body>\n" + "\n".join(b for b in body if b) + "\n</body></html>\n")
    report_dir.mkdir(parents=True, exist_ok=True)
    return atomic_write_text(report_dir / "index.html", page)


def traceability(results: Sequence[CaseResult], suites: Sequence[Suite]) -> str:
    """The matrix as text: requirement, its verdict, the cases that verify it."""
    rows = []
    for s in suites:
        for req in s.requirements:
            cases = [r.case.id for r in results if r.suite == s.name and req.id in r.case.requirements]
            rows.append(f"{_WORD[requirement_verdict(req.id, results, s.name)]:<5}  {req.id:<14}  "
                        f"{', '.join(cases)}")
    return "\n".join(rows)
