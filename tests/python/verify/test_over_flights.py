"""Requirements over many flights (hil.verify.statistical, issue 37 item 3): a case with
`flights = N` judges each expectation over all N, with its confidence interval -- validated at
load like every expectation, judged on synthetic flights here, flown on the bus at the end."""
from __future__ import annotations

import json
import os
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from rig_helpers import cli

from hil.verify import suite
from hil.verify.runner import FAIL, PASS, judge_flights
from hil.verify.statistical import OverFlights

SUITE = """
[suite]
name = "stat"
[[requirement]]
id = "R1"
text = "the node finishes its steps"
source = "firmware/app/README.md"
[[case]]
id = "many"
aircraft = ["cdrw"]
{extra}
[case.expect]
R1 = [{expect}]
"""


def load(tmp_path: Path, expect: str, extra: str = "flights = 20") -> suite.Suite:
    p = tmp_path / "s.toml"
    p.write_text(SUITE.format(expect=expect, extra=extra))
    return suite.load(p)


def run(overruns: float, steps: float = 351.0) -> dict:
    """A flight's fields as hil.verify.fields.read_run gives them (the parts read here)."""
    return {"summary": {"firmware": {"overruns": overruns, "steps": {"cdrw": steps}}}, "info": {}}


SHARE = '{ share = "overruns == 0", expect = "lo >= 0.8" }'
P99 = '{ percentile = 99, of = "overruns", expect = "hi <= 2" }'


def test_a_share_is_judged_on_its_interval_not_its_point_estimate(tmp_path) -> None:
    case = load(tmp_path, SHARE).cases[0]
    assert case.n_flights == 20 and isinstance(case.expect[0][1], OverFlights)
    # 19 of 20 flights without an overrun: 95 %, Wilson 95 % interval 76.4-99.1 %: lo < 0.8
    (c,) = judge_flights(case.expect, [run(0)] * 19 + [run(3)])
    assert c.verdict == FAIL and c.requirement == "R1"
    assert c.measured == "lo = 0.763869; 95% (Wilson 95%: 76.39% to 99.11%) over 20 flights"
    assert c.text == "share of flights with overruns == 0: lo >= 0.8"
    (c,) = judge_flights(case.expect, [run(0)] * 20)
    assert c.verdict == PASS and "(Wilson 95%: 83.89% to 100%)" in c.measured


def test_clopper_pearson_and_a_confidence_level_can_be_asked_for(tmp_path) -> None:
    case = load(tmp_path, '{ share = "overruns == 0", expect = "lo >= 0.8", method = "clopper-pearson", '
                          'confidence = 0.9 }').cases[0]
    (c,) = judge_flights(case.expect, [run(0)] * 20)
    assert c.verdict == PASS and "(Clopper-Pearson 90%: 86.09% to 100%)" in c.measured


def test_a_percentile_over_flights_has_its_bootstrap_interval(tmp_path) -> None:
    case = load(tmp_path, P99).cases[0]
    runs = [run(0)] * 18 + [run(1), run(4)]
    (c,) = judge_flights(case.expect, runs)
    assert c.verdict == FAIL and c.measured == "hi = 4; 3.43 (bootstrap 95%: 0 to 4) over 20 flights"
    (c,) = judge_flights(case.expect, [run(0)] * 20)
    assert c.verdict == PASS


@pytest.mark.parametrize("expect, extra, why", [
    (SHARE, "", "needs a case of flights >= 2"),
    ('"overruns == 0"', "flights = 5", "a case of 5 flights judges expectations over them"),
    (SHARE, "flights = 1001", "field 'flights': must be <= 1000"),
    (SHARE, 'flights = 5\nattack = "forged-control"', "a case with an attack flies one flight"),
    ('{ share = "overruns == 0", expect = "n >= 5" }', "flights = 5", "over value, lo, hi (and n) only"),
    ('{ share = "overruns == 0", expect = "lo >= 0.9", confidence = 1.5 }', "flights = 5",
     "field 'confidence': a level from 0.5 to below 1"),
    ('{ percentile = 99, of = "overruns", expect = "hi < 1", method = "wilson" }', "flights = 5",
     "a percentile's interval is the bootstrap's"),
    ('{ percentile = 120, of = "overruns", expect = "hi < 1" }', "flights = 5", "field 'percentile': 0 to 100"),
    ('{ share = "overruns == 0", percentile = 5, expect = "lo > 0" }', "flights = 5", "name one of 'share'"),
    ('{ share = "nonsense.x > 0", expect = "lo > 0" }', "flights = 5", "unknown field 'nonsense.x'"),
    ('{ share = "overruns == 0", expect = "lo > overruns" }', "flights = 5", "over value, lo, hi (and n) only"),
    ('{ share = "overruns == 0", expect = "lo > 0", colour = 1 }', "flights = 5", "unknown key(s) colour"),
])
def test_a_bad_expectation_over_flights_is_refused_at_load(tmp_path, expect, extra, why) -> None:
    with pytest.raises(suite.SuiteError) as e:
        load(tmp_path, expect, extra)
    assert why in str(e.value), str(e.value)


@pytest.mark.vcan
def test_a_case_of_three_flights_flies_three_seeds_and_reports_its_interval(tmp_path, capsys) -> None:
    p = tmp_path / "s.toml"
    p.write_text(SUITE.format(extra="flights = 3\nduration = 2.0\ndefault_faults = false", expect=", ".join([
        '{ share = "cdrw.unanswered_steps == 0 and overruns == 0", expect = "value >= 1" }',
        '{ percentile = 50, of = "azkf.alpha.error_integral_truth", expect = "hi < 1" }'])))
    rc, out, err = cli(capsys, "verify", str(p), "--no-plots", "--out", str(tmp_path / "report"))
    assert rc == 0, out + err
    runs = sorted((tmp_path / "report" / "cases" / "many").glob("flight-*"))
    assert [r.name for r in runs] == ["flight-000", "flight-001", "flight-002"]
    seeds = {json.loads((r / "summary.json").read_text())["cdrw"]["flight"]["seed"] for r in runs}
    assert len(seeds) == 3
    page = (tmp_path / "report" / "index.html").read_text()
    assert "cdrw, lockstep, 3 flights;" in page
    assert "(Wilson 95%: 43.85% to 100%) over 3 flights" in page and "(bootstrap 95%: " in page


# ---- on --workers (hil.verify.flights over hil.parallel) ---------------------------------------
REPO = Path(__file__).resolve().parents[3]
UML = Path(os.environ.get("WITH_VCAN_UML_DIR") or REPO / ".uml")
needs_rig = pytest.mark.skipif(not (UML / "linux.uml").exists() and not Path("/sys/class/net/vcan0").exists(),
                               reason="needs User-Mode Linux (scripts/setup) or a kernel with vcan")
FOUR = SUITE.format(extra="flights = 4\nduration = 2.0\ndefault_faults = false", expect=", ".join([
    '{ share = "cdrw.unanswered_steps == 0 and overruns == 0", expect = "value >= 1" }',
    '{ percentile = 50, of = "azkf.alpha.error_integral_truth", expect = "hi < 1" }']))


def test_workers_fly_only_cases_of_many_flights_and_say_so_in_one_line(tmp_path, capsys) -> None:
    rc, out, err = cli(capsys, "verify", "seed1-identification", "--workers", "2", "--out", str(tmp_path / "r"))
    assert rc == 2 and out == "" and err.count("\n") == 1, err
    assert "--workers/--scheduler fly the flights of lockstep cases of `flights = N`; paper-spike" in err
    assert not (tmp_path / "r").exists()


@needs_rig
def test_a_case_of_many_flights_on_workers_judges_the_flights_the_sequential_form_flies(tmp_path) -> None:
    """Lockstep flights are deterministic in their seed: flown on 2 rigs (each its own guest,
    from the host shell) they give the sequential form's figures, flight by flight, and the same
    measured values and intervals."""
    p = tmp_path / "s.toml"
    p.write_text(FOUR)
    base = [sys.executable, "-m", "hil.cli", "verify", str(p), "--no-plots", "--quiet"]
    seq = subprocess.run([str(REPO / "scripts" / "with-vcan"), *base, "--out", str(tmp_path / "seq"),
                          "--junit", str(tmp_path / "seq.xml")], cwd=REPO, capture_output=True, text=True,
                         timeout=600, check=False)
    assert seq.returncode == 0, seq.stdout + seq.stderr
    par = subprocess.run([*base, "--workers", "2", "--out", str(tmp_path / "par"),
                          "--junit", str(tmp_path / "par.xml")], cwd=REPO, capture_output=True, text=True,
                         timeout=600, check=False)
    assert par.returncode == 0, par.stdout + par.stderr

    def figures(root: Path) -> list[dict]:
        flights = root / "cases" / "many"
        return [json.loads((flights / f"flight-{i:03d}" / "summary.json").read_text())["cdrw"]["table4_truth"]
                for i in range(4)]
    assert figures(tmp_path / "seq") == figures(tmp_path / "par")
    assert measured_lines(tmp_path / "seq.xml") == measured_lines(tmp_path / "par.xml")
    info = json.loads((tmp_path / "par" / "cases" / "many" / "run_info.json").read_text())
    assert info["flights"] == 4 and info["parallel"]["workers"] == 2 and info["parallel"]["failed"] == 0


def measured_lines(junit_file: Path) -> list[str]:
    cases = ET.parse(junit_file).getroot().iter("testcase")
    return [ln for tc in cases for ln in tc.find("system-out").text.splitlines() if not ln.startswith("re-fly")]
