"""`hil verify`: the expectation language, suite validation (before anything flies), the
verdicts and reports; on the bus, the shipped suites pass against the host build and the
Cortex-M4F image, and fail naming the right requirement against deliberately wrong devices."""
from __future__ import annotations

import json
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from hil.verify import expr, suite
from hil.verify.fields import FIELDS, NEVER
from hil.verify.report import html_report, junit, requirement_verdict, traceability
from hil.verify.runner import ERROR, FAIL, PASS, CaseResult, Check
from browser import PNG_MAGIC, screenshot
from rig_helpers import cli

ROOT = Path(__file__).resolve().parents[3]


# ---- the expectation language ------------------------------------------------------------------
def test_expressions_evaluate_fields_and_arithmetic():
    e = expr.parse("detector.first_flag_step - fault.start_step <= 2 and overruns == 0")
    assert e.fields == {"detector.first_flag_step", "fault.start_step", "overruns"}
    assert expr.evaluate(e.tree, {"detector.first_flag_step": 201, "fault.start_step": 200, "overruns": 0})
    assert not expr.evaluate(e.tree, {"detector.first_flag_step": 203, "fault.start_step": 200, "overruns": 0})
    chained = expr.parse("0.9 < abs(-x) <= max(y, 1)")
    assert expr.evaluate(chained.tree, {"x": 1.0, "y": 0.5})


def test_never_is_a_failure_not_a_pass():
    e = expr.parse("detector.latency_steps <= 2")
    assert not expr.evaluate(e.tree, {"detector.latency_steps": NEVER})
    assert expr.measured(e, {"detector.latency_steps": NEVER}) == "detector.latency_steps = inf"


@pytest.mark.parametrize("text", ["__import__('os').system('true')", "x.real()", "[1, 2]", "x if y else z",
                                  "'text' == x", "lambda: 1", "x ** 2", "True"])
def test_anything_else_is_refused(text):
    with pytest.raises(expr.ExpressionError):
        expr.parse(text)


def test_measured_shows_each_side_of_a_comparison():
    e = expr.parse("missile.rms_q < 0.9 * open_loop.rms_q")
    assert expr.measured(e, {"missile.rms_q": 0.072, "open_loop.rms_q": 0.082}) == \
        "missile.rms_q = 0.072; 0.9 * open_loop.rms_q = 0.0738"


# ---- suites -----------------------------------------------------------------------------------
SUITE = """
[suite]
name = "t"
[[requirement]]
id = "R1"
text = "the node answers every step"
source = "firmware/app/README.md"
[[case]]
id = "c1"
aircraft = ["cdrw"]
{extra}
[case.expect]
R1 = [{expect}]
"""


def write_suite(tmp_path: Path, expect: str = '"cdrw.unanswered_steps == 0"', extra: str = "") -> Path:
    p = tmp_path / "s.toml"
    p.write_text(SUITE.format(expect=expect, extra=extra))
    return p


def test_the_shipped_suites_load_and_trace_every_requirement():
    names = suite.shipped()
    assert set(names) == {"fcc-node-conformance", "seed1-identification", "seed2-autopilot"}
    for path in names.values():
        s = suite.load(path)
        for req in s.requirements:
            assert req.source and any(req.id in c.requirements for c in s.cases)


@pytest.mark.parametrize("expect, extra, why", [
    ('"cdrw.nonsense > 0"', "", "unknown field 'cdrw.nonsense'"),
    ('"missile.rms_q < open_loop.rms_q"', "", "needs a missile flight"),
    ('"attack.forged > 0"', "", "needs a attack flight"),
    ('"import os"', "", "expect"),
    ('"overruns == 0"', 'attack = "tea"', "unknown attack 'tea'"),
    ('"overruns == 0"', 'colour = "red"', "unknown key(s) colour"),
    ('"overruns == 0"', 'mode = "fast"', "'mode' must be one of"),
])
def test_a_bad_suite_is_refused_before_anything_flies(tmp_path, expect, extra, why):
    with pytest.raises(suite.SuiteError, match="s.toml: "):
        suite.load(write_suite(tmp_path, expect, extra))
    with pytest.raises(suite.SuiteError) as e:
        suite.load(write_suite(tmp_path, expect, extra))
    assert why in str(e.value)


def test_undeclared_and_untested_requirements_and_bad_files_are_refused(tmp_path):
    p = write_suite(tmp_path)
    p.write_text(p.read_text().replace("R1 = [", "R2 = ["))
    with pytest.raises(suite.SuiteError, match="R2 not declared"):
        suite.load(p)
    p.write_text(SUITE.format(expect='"overruns == 0"', extra="") +
                 '[[requirement]]\nid = "R9"\ntext = "x"\nsource = "y"\n')
    with pytest.raises(suite.SuiteError, match="R9 verified by no case"):
        suite.load(p)
    p.write_text("not = [toml")
    with pytest.raises(suite.SuiteError, match="not a TOML suite"):
        suite.load(p)
    p.write_bytes(b"#" * (suite.MAX_SUITE_BYTES + 1))
    with pytest.raises(suite.SuiteError, match="larger than"):
        suite.load(p)


def test_cli_refuses_bad_suites_and_cases_in_one_line(tmp_path, capsys):
    rc, out, err = cli(capsys, "verify", "no-such-suite")
    assert rc == 2 and out == "" and err.count("\n") == 1 and "no suite named 'no-such-suite'" in err
    rc, _, err = cli(capsys, "verify", "seed2-autopilot", "--case", "nope")
    assert rc == 2 and "--case nope: no such case" in err
    rc, _, err = cli(capsys, "verify", str(write_suite(tmp_path, '"cdrw.nonsense > 0"')))
    assert rc == 2 and "unknown field" in err
    rc, out, _ = cli(capsys, "verify", "--fields")
    assert rc == 0 and all(name in out for name in FIELDS)


# ---- verdicts and reports ----------------------------------------------------------------------
def results() -> tuple[list[suite.Suite], list[CaseResult]]:
    s = suite.load(suite.shipped()["seed1-identification"])
    by_id = {c.id: c for c in s.cases}
    ok = CaseResult(s.name, by_id["fault-free"], PASS,
                    [Check("SID-DET-2", "detector.flagged_steps == 0", PASS, "detector.flagged_steps = 0"),
                     Check("SID-REF-1", "replay.max_difference <= 1e-4", PASS, "replay.max_difference = 5e-06")],
                    seconds=1.5, command="hil verify seed1-identification --case fault-free")
    bad = CaseResult(s.name, by_id["paper-spike"], FAIL,
                     [Check("SID-DET-1", "detector.latency_steps <= 2", FAIL, "detector.latency_steps = inf"),
                      Check("SID-EST-1", "azkf.alpha.error_integral < kf.alpha.error_integral", PASS, "..."),
                      Check("SID-BND-1", "azkf.alpha.coverage >= 0.95", PASS, "..."),
                      Check("SID-REF-1", "replay.max_difference <= 1e-4", PASS, "...")], seconds=2.0)
    err = CaseResult(s.name, by_id["spike-at-2s"], ERROR, error="fcc did not answer step 3", seconds=0.5)
    return [s], [ok, bad, err]


def test_a_requirement_fails_only_by_its_own_expectations():
    suites, rs = results()
    assert requirement_verdict("SID-EST-1", rs[:2], "seed1-identification") == PASS
    assert requirement_verdict("SID-DET-1", rs[:2], "seed1-identification") == FAIL
    assert requirement_verdict("SID-DET-1", rs, "seed1-identification") == ERROR   # an error outranks
    assert requirement_verdict("SID-DET-2", rs[1:2], "seed1-identification") == "not run"
    matrix = traceability(rs[:2], suites).splitlines()
    assert "FAIL   SID-DET-1       paper-spike, spike-at-2s" not in matrix    # (that case did not run)
    assert "FAIL   SID-DET-1       paper-spike" in matrix and "PASS   SID-EST-1       paper-spike" in matrix


def test_junit_xml_is_valid_and_names_the_requirement(tmp_path):
    suites, rs = results()
    junit(rs, suites, tmp_path / "j.xml", "host")
    root = ET.parse(tmp_path / "j.xml").getroot()
    (ts,) = root.findall("testsuite")
    assert (ts.get("tests"), ts.get("failures"), ts.get("errors")) == ("3", "1", "1")
    cases = {tc.get("name"): tc for tc in ts.findall("testcase")}
    assert cases["paper-spike"].find("failure").get("message").startswith("SID-DET-1: detector.latency_steps")
    assert cases["spike-at-2s"].find("error").get("message") == "fcc did not answer step 3"
    assert cases["fault-free"].find("failure") is None
    reqs = [p.get("value") for p in cases["paper-spike"].iter("property") if p.get("name") == "requirement"]
    assert reqs == ["SID-DET-1", "SID-EST-1", "SID-BND-1", "SID-REF-1"]


def test_the_html_report_opens_in_a_real_browser(tmp_path):
    suites, rs = results()
    page = html_report(rs, suites, tmp_path / "report", "host", "hil verify seed1-identification")
    text = page.read_text()
    assert "1 passed, 1 failed, 1 errors" in text and "SID-DET-1" in text and "fcc did not answer" in text
    data = screenshot(page, tmp_path / "shot.png")
    assert data[:8] == PNG_MAGIC and len(data) > 10_000   # a page was drawn, not a blank


# ---- on the bus ---------------------------------------------------------------------------------
def verify(*args: str, tmp: Path) -> tuple[int, str, dict]:
    p = subprocess.run([sys.executable, "-m", "hil.cli", "verify", *args, "--no-plots", "--force",
                        "--out", str(tmp / "report"), "--junit", str(tmp / "j.xml")],
                       capture_output=True, text=True, timeout=900, cwd=ROOT)
    verdicts = {}
    for ln in p.stdout.splitlines():
        parts = ln.split()
        if len(parts) >= 2 and parts[0] in ("PASS", "FAIL", "ERROR", "-") and "/" not in parts[1]:
            verdicts[parts[1]] = parts[0]
    return p.returncode, p.stdout + p.stderr, verdicts


@pytest.mark.vcan
@pytest.mark.parametrize("target", ["host", "qemu-m4f"])
def test_the_shipped_suites_pass_on_the_host_build_and_the_m4f_image(tmp_path, target):
    rc, out, verdicts = verify("fcc-node-conformance", "seed1-identification", "seed2-autopilot",
                               "--target", target, tmp=tmp_path)
    assert rc == 0, out
    assert len(verdicts) == 18 and set(verdicts.values()) == {"PASS"}, out
    ts = ET.parse(tmp_path / "j.xml").getroot().findall("testsuite")
    assert [int(t.get("tests")) for t in ts] == [8, 3, 2]
    assert all(t.get("failures") == "0" and t.get("errors") == "0" for t in ts)


@pytest.mark.vcan
@pytest.mark.parametrize("suite_name, device, failed", [
    ("seed1-identification", ["--fcc-args", "--detector off"], {"SID-DET-1"}),
    ("seed2-autopilot", ["--fcc", "PLANTED"], {"LQG-REF-1"}),
])
def test_a_wrong_device_fails_the_right_requirement(tmp_path, suite_name, device, failed, planted_fcc):
    device = [planted_fcc if a == "PLANTED" else a for a in device]
    rc, out, verdicts = verify(suite_name, *device, tmp=tmp_path)
    assert rc == 1, out
    assert {r for r, v in verdicts.items() if v == "FAIL"} == failed, out
    assert "ERROR" not in verdicts.values()


@pytest.mark.vcan
def test_a_device_that_cannot_run_is_an_error_never_a_pass(tmp_path):
    other = tmp_path / "other.key"
    other.write_text("00112233445566778899aabbccddeeff\n")
    rc, out, verdicts = verify("fcc-node-conformance", "--case", "clean-cdrw", "--fcc-args",
                               f"--key-file {other}", tmp=tmp_path)
    assert rc == 6, out
    assert verdicts["NODE-HB-1"] == "ERROR" and verdicts["NODE-SEC-1"] == "-"
    assert "authenticated heartbeat" in out


@pytest.fixture(scope="module")
def planted_fcc() -> str:
    """fcc built with FCC_PLANTED_BUG (its D/A truncates instead of rounding): scripts/test's
    vcan step builds it on the host (compiling in the guest is slow)."""
    fcc = ROOT / "build-planted" / "bin" / "fcc"
    assert fcc.is_file(), "build-planted/bin/fcc is not built (scripts/test vcan builds it)"
    return str(fcc)


def test_summary_fields_exist_for_every_documented_source():
    """Every field reads something a real run directory has (the demo's run is the sample)."""
    sample = ROOT / "tests" / "vectors" / "verify"
    summary = json.loads((sample / "summary.json").read_text())
    info = json.loads((sample / "run_info.json").read_text())
    from hil.verify.fields import read_run, values
    run = read_run(sample, summary, info, {"forged": 3.0})
    got = values(run, frozenset(FIELDS))
    assert got["detector.latency_steps"] == 0 and got["attack.forged"] == 3.0
    assert got["steps.cdrw"] == got["cdrw.steps"] == 351
