"""`hil verify`: the expectation language, suite validation (before anything flies), the
verdicts and reports; on the bus, the shipped suites pass against the host build and the
Cortex-M4F image, and fail naming the right requirement against deliberately wrong devices."""
from __future__ import annotations

import json
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from verify_run import run_verify
from suite_edits import edit_and_load

from hil.io.rundir import staged_run
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


@pytest.mark.parametrize("text, why", [
    ("x / 0", "'x / 0': division by zero"),
    ("x / (2 - 2) < 1", "'x / (2 - 2)': division by zero"),
    ("x / -0.0 < 1", "division by zero"),
    ("abs(x, 1) < 2", "'abs(x, 1)': abs() takes 1 argument, not 2"),
    ("abs() < 2", "abs() takes 1 argument, not 0"),
    ("min(x) < 2", "'min(x)': min() takes 2 or more arguments, not 1"),
    ("max() < 2", "max() takes 2 or more arguments, not 0"),
    ("x < 1e999", "'1e309': not a finite number"),
    ("x < " + "9" * 400, "not a finite number"),
    ("-" * 100_000 + "x < 1", "100005 characters, an expectation has at most 500"),
    ("-(" * 40 + "x" + ")" * 40, "nested deeper than 32 levels"),
    ("+".join(["min(a, b)"] * 30) + " < 1", "more than 200 parts"),
    ("x\0 < 1", "null bytes"),
])
def test_what_would_fail_after_the_flight_is_refused_before_it(text, why):
    """Arity, a constant divisor of zero, a number that is not one, an expression too large: one
    line when the suite is loaded (never a MemoryError or RecursionError)."""
    with pytest.raises(expr.ExpressionError) as e:
        expr.parse(text)
    assert why in str(e.value) and "\n" not in str(e.value) and len(str(e.value)) < 200


def test_no_string_makes_the_parser_raise_anything_else():
    """Deterministic random strings over the language's characters: parsed, or ExpressionError."""
    import random
    rng = random.Random(34)
    alphabet = "x.y 0123456789+-*/()<>=!,andortabsminx\0e"
    parsed = 0
    for _ in range(3000):
        text = "".join(rng.choice(alphabet) for _ in range(rng.randrange(1, 60)))
        try:
            expr.parse(text)
            parsed += 1
        except expr.ExpressionError:
            pass
    assert parsed > 0


def test_a_field_measured_zero_as_divisor_is_named():
    e = expr.parse("a / b < 1")
    with pytest.raises(ZeroDivisionError, match=r"a / b: division by zero \(b = 0\)"):
        expr.evaluate(e.tree, {"a": 1.0, "b": 0})


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
    assert set(names) == {"fcc-node-conformance", "seed1-identification", "seed2-autopilot", "time-sync",
                          "realtime-timing", "seed1-statistics"}
    for path in names.values():
        s = suite.load(path)
        for req in s.requirements:
            assert req.source and any(req.id in c.requirements for c in s.cases)


@pytest.mark.parametrize("expect, extra, why", [
    ('"cdrw.nonsense > 0"', "", "field 'expect.R1': 'cdrw.nonsense > 0': unknown field 'cdrw.nonsense'"),
    ('"missile.rms_q < open_loop.rms_q"', "", "needs a missile flight"),
    ('"attack.forged > 0"', "", "needs a attack flight"),
    ('"import os"', "", "field 'expect.R1'"),
    ('"overruns == 0"', 'attack = "tea"', "field 'attack': must be one of forged-control"),
    ('"overruns == 0"', 'colour = "red"', "unknown field 'colour' (allowed: id, title, aircraft"),
    ('"overruns == 0"', 'mode = "fast"', "field 'mode': must be one of lockstep, realtime, got 'fast'"),
    ('"overruns == 0"', 'default_faults = "no"', "field 'default_faults': expected true or false"),
    ('"overruns == 0"', 'title = 3', "field 'title': expected a string, got integer 3"),
    ('"overruns == 0"', 'faults = "spike:signal=alpha"', "field 'faults': expected an array"),
    ('"overruns == 0"', 'duration = 3.0',
     "faults[0] (spike): field 'start': 4.0 s is not before the end of the run (3.0 s)"),  # the default spike
    ('"overruns == 0"', 'duration = 1e7', "field 'duration': 1e+07 s needs about"),
    ('"overruns == 0"', 'seed = 1.5', "field 'seed': expected an integer, got number 1.5"),
    ('"overruns == 0"', 'lqg = { bits = 8 }', "section [lqg] is only for aircraft = \"missile\""),
])
def test_a_bad_suite_is_refused_before_anything_flies(tmp_path, expect, extra, why):
    with pytest.raises(suite.SuiteError) as e:
        suite.load(write_suite(tmp_path, expect, extra))
    assert str(e.value).startswith(f"{tmp_path / 's.toml'}: case[0] c1: ") and why in str(e.value)


@pytest.mark.parametrize("lqg, why", [
    ("{ bits = 40 }", "[lqg]: field 'bits': must be <= 16, got 40"),
    ("{ period = 0.01 }", "[lqg]: field 'period': fcc runs the LQG at 0.02 to 0.3 s, got 0.01"),
    ("{ period = 0.1, colour = 1 }", "[lqg]: unknown field 'colour'"),
    ('"fast"', "key 'lqg': expected a table"),
])
def test_a_case_lqg_is_checked_as_a_scenario_lqg_and_as_fcc_takes_it(tmp_path, lqg, why):
    p = write_suite(tmp_path, '"missile.unanswered_steps == 0"', f"lqg = {lqg}")
    p.write_text(p.read_text().replace('aircraft = ["cdrw"]', 'aircraft = ["missile"]'))
    with pytest.raises(suite.SuiteError) as e:
        suite.load(p)
    assert str(e.value).startswith(f"{p}: case[0] c1: ") and why in str(e.value)


@pytest.mark.parametrize("aircraft, why", [
    ("[]", "field 'aircraft': name cdrw and/or missile, once each"),
    ('["cdrw", "cdrw"]', "field 'aircraft': name cdrw and/or missile, once each"),
    ('["plane"]', "field 'aircraft'[0]: must be one of cdrw, missile, got 'plane'"),
    ('"cdrw"', "field 'aircraft': expected an array, got string 'cdrw'"),
])
def test_a_case_names_each_aircraft_it_flies_once(tmp_path, aircraft, why):
    p = write_suite(tmp_path, '"overruns == 0"')
    p.write_text(p.read_text().replace('aircraft = ["cdrw"]', f"aircraft = {aircraft}"))
    with pytest.raises(suite.SuiteError) as e:
        suite.load(p)
    assert str(e.value).startswith(f"{p}: case[0] c1: ") and why in str(e.value)


@pytest.mark.parametrize("case_id", ["../../escape", "", ".hidden", "a/b", "x" * 65])
def test_a_case_id_names_a_directory_inside_the_report_only(tmp_path, case_id):
    p = write_suite(tmp_path)
    p.write_text(p.read_text().replace('id = "c1"', f"id = {json.dumps(case_id)}"))
    with pytest.raises(suite.SuiteError, match=r"field 'id': letters, digits and \. _ -"):
        suite.load(p)


def test_a_case_flies_its_faults_on_the_aircraft_they_belong_to(tmp_path):
    p = write_suite(tmp_path, '"missile.unanswered_steps == 0"',
                    'aircraft = ["cdrw", "missile"]\nduration = 3.0\ndefault_faults = false\n'
                    'seed = 5\nlqg = { period = 0.05, bits = 12 }\n'
                    'faults = ["bias:signal=q_g,start=1,duration=0.5,magnitude=2", '
                    '"bad_crc:frame=CDRW_AOA,start=2,duration=0.5"]')
    p.write_text(p.read_text().replace('aircraft = ["cdrw"]\n', "", 1))
    (case,) = suite.load(p).cases
    cdrw, missile = case.flights
    assert (cdrw.aircraft, cdrw.seed, cdrw.duration, cdrw.lqg) == ("cdrw", 5, 3.0, None)
    assert [f.describe() for f in cdrw.faults] == ["bad_crc:start=2,duration=0.5,frame=CDRW_AOA,probability=1"]
    assert (missile.seed, missile.duration, missile.lqg.period, missile.lqg.bits) == (5, 3.0, 0.05, 12)
    assert missile.lqg.closed_loop   # (the embedded scenario's, the case not saying otherwise)
    assert [f.describe() for f in missile.faults] == ["bias:start=1,duration=0.5,signal=q_g,magnitude=2"]


def test_the_top_of_a_suite_is_checked_too(tmp_path):
    p = write_suite(tmp_path)
    text = p.read_text()
    for bad, why in [("[suite]", "unknown field 'suites' (allowed: suite, requirement, case)"),
                     ('name = "t"', "[suite]: missing field 'name'"),
                     ('source = "firmware/app/README.md"', "requirement[0]: missing field 'source'"),
                     ("[[case]]", "key 'case': expected an array of tables ([[case]])"),
                     ('id = "c1"', "case[0]: missing field 'id'"),
                     ('id = "R1"', "requirement[0]: missing field 'id'")]:
        p.write_text(text.replace(bad, {"[suite]": "[suites]", "[[case]]": "[case]"}.get(bad, ""), 1))
        with pytest.raises(suite.SuiteError) as e:
            suite.load(p)
        assert why in str(e.value), bad


def test_no_edit_of_a_shipped_suite_makes_loading_raise_anything_but_one_line(tmp_path):
    """Deterministic random edits (tokens of TOML, faults and expectations put in anywhere):
    each suite loads, or SuiteError of one line (8,000 such edits, seeds 1-3: no other)."""
    texts = [p.read_text() for p in suite.shipped().values()]
    tokens = ['"', "[", "]", "{", "}", "=", ",", "-1", "1e999", "nan", "true", '"x"', "\n", "alpa", "q_g",
              "*", "/", "(", "min(", "abs(", "start=99", "frame=SIM_TICK", "[]", "1.5"]
    outcomes = edit_and_load(texts, tokens, 34, tmp_path / "fz.toml")
    assert outcomes["loaded"] and outcomes["refused"]


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
    with pytest.raises(suite.SuiteError, match="not valid TOML"):
        suite.load(p)
    p.write_text("a = " + "[" * 100_000)   # (tomllib recurses)
    with pytest.raises(suite.SuiteError, match="s.toml: not valid TOML: nested too deeply"):
        suite.load(p)
    p.write_bytes(b"\xff\xfe")
    with pytest.raises(suite.SuiteError, match="s.toml: not UTF-8 text"):
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


# what was measured on main 91d7a8e: each flew (or failed after the flight), now refused first
MEASURED = [
    ('faults = ["spike:signal=alpa,start=4,duration=0.1,magnitude=0.15"]', "overruns == 0",
     "faults[0] 'spike:signal=alpa,start=4,duration=0.1,magnitude=0.15' (spike): field 'signal': "
     "unknown signal 'alpa' for aircraft cdrw"),
    ('faults = ["spkie:signal=alpha,start=4,duration=0.1,magnitude=0.15"]', "overruns == 0",
     "field 'kind': unknown fault kind 'spkie'"),
    ('faults = ["spike:signal=alpha,start=9,duration=0.1,magnitude=0.15"]', "overruns == 0",
     "(spike): field 'start': 9.0 s is not before the end of the run (7.0 s)"),
    ('faults = ["bias:signal=q_g,start=1,duration=0.5,magnitude=2"]', "overruns == 0",
     "(bias): field 'signal': a missile fault, and the flight is cdrw"),
    ('faults = ["spike:signal=alpha,start=4,duration=0.1,magnitude=oops"]', "overruns == 0",
     "(spike): field 'magnitude': expected a number, got string 'oops'"),
    ("seed = -4", "overruns == 0", "field 'seed': must be >= 0, got -4"),
    ("", "overruns / 0 == 0", "field 'expect.R1': 'overruns / 0': division by zero"),
    ("", "abs(overruns, 1) == 0", "field 'expect.R1': 'abs(overruns, 1)': abs() takes 1 argument, not 2"),
    ("", "min(overruns) == 0", "field 'expect.R1': 'min(overruns)': min() takes 2 or more arguments, not 1"),
    ("", "-" * 100_000 + "overruns == 0", "field 'expect.R1': "),
]


@pytest.mark.parametrize("extra, expect, why", MEASURED, ids=[
    "typo-signal", "unknown-kind", "start-after-end", "other-aircraft", "bad-parameter", "seed-4",
    "x-over-0", "abs-2-args", "min-1-arg", "100000-minus"])
def test_a_case_that_cannot_fly_as_written_exits_2_before_anything_flies(tmp_path, capsys, extra, expect, why):
    """One line naming the file, the case and the field; no report, no staging directory, no
    flight (and no bus needed: the interface does not exist, which would be exit 1)."""
    p = write_suite(tmp_path, json.dumps(expect), extra)
    rc, out, err = cli(capsys, "verify", str(p), "--iface", "nosuch0", "--out", str(tmp_path / "report"))
    assert rc == 2 and out == "" and err.count("\n") == 1 and len(err) < 400, err
    assert err.startswith(f"hil: verify: {p}: case[0] c1: ") and why in err, err
    assert list(tmp_path.iterdir()) == [p]


def test_no_bus_is_hil_runs_one_line_and_exit_1_and_the_last_report_stays(tmp_path, capsys):
    out, junit_file = tmp_path / "report", tmp_path / "j.xml"
    suites, rs = results()
    with staged_run(out, "verify") as stage:    # the last report, published as hil verify does
        html_report(rs, suites, stage, "host", "hil verify seed1-identification")
    junit(rs, suites, junit_file, "host")
    rc_run, _, err_run = cli(capsys, "run", "cdrw", "--iface", "nosuch0", "--quiet", "--no-plots",
                             "--out", str(tmp_path / "run"))
    before = {f: f.read_bytes() for f in tmp_path.rglob("*") if f.is_file()}
    rc, stdout, err = cli(capsys, "verify", "seed1-identification", "--iface", "nosuch0", "--no-plots",
                          "--out", str(out), "--junit", str(junit_file))
    assert (rc, rc_run) == (1, 1) and stdout == "" and err == err_run and err.count("\n") == 1
    assert err.startswith("hil: cannot open CAN interface 'nosuch0': ")
    assert {f: f.read_bytes() for f in tmp_path.rglob("*") if f.is_file()} == before


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
    assert reqs == ["SID-DET-1", "SID-EST-1", "SID-BND-1", "SID-BND-2", "SID-REF-1"]


def test_the_html_report_opens_in_a_real_browser(tmp_path):
    suites, rs = results()
    page = html_report(rs, suites, tmp_path / "report", "host", "hil verify seed1-identification")
    text = page.read_text()
    assert "1 passed, 1 failed, 1 errors" in text and "SID-DET-1" in text and "fcc did not answer" in text
    data = screenshot(page, tmp_path / "shot.png")
    assert data[:8] == PNG_MAGIC and len(data) > 10_000   # a page was drawn, not a blank


# ---- on the bus ---------------------------------------------------------------------------------
def verify(*args: str, tmp: Path) -> tuple[int, str, dict[str, str]]:
    return run_verify(*args, "--no-plots", tmp=tmp)


@pytest.mark.vcan
@pytest.mark.parametrize("target", ["host", "qemu-m4f"])
def test_the_shipped_suites_pass_on_the_host_build_and_the_m4f_image(tmp_path, target):
    rc, out, verdicts = verify("fcc-node-conformance", "seed1-identification", "seed2-autopilot",
                               "--target", target, tmp=tmp_path)
    assert rc == 0, out
    assert len(verdicts) == 20 and set(verdicts.values()) == {"PASS"}, out
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
    """...and its report is not published: the last good one (and its JUnit file) stays as it
    was; this run's is kept aside in report.failed-TIME."""
    rc, out, _ = verify("fcc-node-conformance", "--case", "clean-cdrw", tmp=tmp_path)
    assert rc == 0, out
    good = {f: f.read_bytes() for f in tmp_path.rglob("*") if f.is_file()}
    other = tmp_path / "other.key"
    other.write_text("00112233445566778899aabbccddeeff\n")
    rc, out, verdicts = verify("fcc-node-conformance", "--case", "clean-cdrw", "--fcc-args",
                               f"--key-file {other}", tmp=tmp_path)
    assert rc == 6, out
    assert verdicts["NODE-HB-1"] == "ERROR" and verdicts["NODE-SEC-1"] == "-"
    assert "authenticated heartbeat" in out and "the report is not published" in out
    assert {f: f.read_bytes() for f in good} == good
    (kept,) = tmp_path.glob("report.failed-*")
    assert "0 passed, 0 failed, 1 errors" in (kept / "index.html").read_text()
    assert ET.parse(kept / "junit.xml").getroot().find("testsuite").get("errors") == "1"


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
    got = values(run, frozenset(n for n, f in FIELDS.items()
                                if f.source not in ("realtime", "sync") and not n.startswith("bus_trust.")))
    assert got["detector.latency_steps"] == 0 and got["attack.forged"] == 3.0
    trust = ROOT / "tests" / "vectors" / "verify-trust"    # seed1-identification's paper-spike, 2026-12-02
    run = read_run(trust, json.loads((trust / "summary.json").read_text()),
                   json.loads((trust / "run_info.json").read_text()), None)
    assert values(run, frozenset(n for n in FIELDS if n.startswith("bus_trust."))) == \
        {"bus_trust.ok": 1.0, "bus_trust.forged_frames": 0.0, "bus_trust.own_id": 0.0}
    assert got["steps.cdrw"] == got["cdrw.steps"] == 351
    rt = ROOT / "tests" / "vectors" / "verify-realtime"     # realtime-timing's T0.1, 2026-12-02
    run = read_run(rt, json.loads((rt / "summary.json").read_text()), json.loads((rt / "run_info.json").read_text()),
                   None)
    got = values(run, frozenset(n for n, f in FIELDS.items() if f.source in ("realtime", "sync", "missile")))
    assert got["realtime.period_us"] == 100_000 and got["sync.verdict.ok"] == 1 and got["sync.locked"] == 1
    assert 0 < got["realtime.latency_p50_us"] <= got["realtime.latency_p99_us"] <= got["realtime.latency_max_us"]
