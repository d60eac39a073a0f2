"""`hil` command line without a bus: bad flags, bad scenarios and bad faults are one clear
line on stderr and exit status 2, found before anything is started; a missing interface is
one line and exit status 1."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from hil.cli import main


def run(capsys, *argv: str) -> tuple[int, str, str]:
    rc = main(list(argv))
    out, err = capsys.readouterr()
    return rc, out, err


def one_line(err: str) -> str:
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1, err
    assert lines[0].startswith("hil: ")
    return lines[0]


@pytest.mark.parametrize("argv, words", [
    (["run", "boat"], "invalid choice: 'boat'"),
    (["run", "cdrw", "--bogus"], "unrecognized arguments: --bogus"),
    (["fly"], "invalid choice: 'fly'"),
    (["run", "cdrw", "--seed", "-3"], "--seed"),
    (["run", "cdrw", "--mode", "fast"], "--mode"),
    (["run", "cdrw", "--timeout", "0"], "--timeout"),
    (["sweep", "missile", "--periods", "0.1,x"], "--periods"),
    (["sweep", "missile", "--bits", ""], "--bits"),
    (["campaign", "cdrw", "--runs", "0"], "--runs must be at least 1"),
    (["campaign", "glider"], "invalid choice: 'glider'"),
    ([], "required: COMMAND"),
])
def test_bad_command_line(capsys, tmp_path, argv, words):
    if argv[:1] in (["run"], ["campaign"]) and "--bogus" not in argv:
        argv = [*argv, "--out", str(tmp_path / "o")]
    rc, out, err = run(capsys, *argv)
    assert rc == 2
    assert words in one_line(err)


@pytest.mark.parametrize("fault, words", [
    ("sparkle:signal=alpha,start=1,duration=0.1", "unknown fault kind 'sparkle'"),
    ("spike:signal=alpha,start=1,duration=-0.1,magnitude=0.1", "field 'duration': must be > 0.0"),
    ("spike:signal=beta,start=1,duration=0.1,magnitude=0.1", "unknown signal 'beta'"),
    ("spike:signal=alpha,start=1,duration=0.1", "missing field 'magnitude'"),
    ("loss:frame=NO_SUCH_FRAME,start=1,duration=0.1", "unknown frame 'NO_SUCH_FRAME'"),
    ("spike:signal=alpha,start=99,duration=0.1,magnitude=1", "start"),
])
def test_bad_fault_on_the_command_line(capsys, tmp_path, fault, words):
    rc, _, err = run(capsys, "run", "cdrw", "--fault", fault, "--out", str(tmp_path / "o"))
    assert rc == 2
    assert words in one_line(err)


@pytest.mark.parametrize("text, words", [
    ('aircraft = "cdrw"\n[[faults]]\nkind = "sparkle"\nstart = 1.0\nduration = 0.1\n',
     "unknown fault kind 'sparkle'"),
    ('aircraft = "cdrw"\n[[faults]]\nkind = "bias"\nsignal = "alpha"\nstart = 1.0\n'
     'duration = -2.0\nmagnitude = 0.1\n', "must be > 0.0"),
    ('aircraft = "cdrw"\n[[faults]]\nkind = "bias"\nsignal = "n_a"\nstart = 1.0\n'
     'duration = 1.0\nmagnitude = 0.1\n', "unknown signal 'n_a'"),
    ('aircraft = "cdrw"\nduration = -7.0\n', "duration"),
    ('aircraft = "cdrw"\nwings = 2\n', "unknown key 'wings'"),
    ('aircraft = "cdrw\n', "not valid TOML"),
    ('aircraft = "missile"\n', "aircraft 'missile', not 'cdrw'"),
])
def test_bad_scenario_file(capsys, tmp_path, text, words):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    rc, _, err = run(capsys, "run", "cdrw", str(path), "--out", str(tmp_path / "o"))
    assert rc == 2
    line = one_line(err)
    assert words in line
    assert not (tmp_path / "o" / "bus.log").exists()   # nothing was started


def test_missing_scenario_file(capsys, tmp_path):
    rc, _, err = run(capsys, "run", "cdrw", str(tmp_path / "nope.toml"), "--out", str(tmp_path / "o"))
    assert rc == 2 and "cannot read scenario" in one_line(err)


def test_shipped_scenario_by_name(capsys, tmp_path, monkeypatch):
    """A shipped scenario's name resolves as a suite's does (hil.io.paths.find_shipped), from any
    directory; an unknown name is one line naming the shipped ones; a path always wins."""
    monkeypatch.chdir(tmp_path)
    rc, _, err = run(capsys, "run", "cdrw", "cdrw_nope", "--out", "o")
    line = one_line(err)
    assert rc == 2 and "no scenario named 'cdrw_nope' (shipped: cdrw_bus_attack, " in line, line
    assert "cdrw_multi_fault" in line and "missile_default" in line
    rc, _, err = run(capsys, "campaign", "cdrw", "missile_default", "--out", "o")   # found: the shipped file's
    line = one_line(err)
    assert rc == 2 and "scenarios/missile_default.toml: a scenario for aircraft 'missile', not 'cdrw'" in line
    Path("cdrw_multi_fault").write_text('aircraft = "missile"\n')                 # a file of that name wins
    rc, _, err = run(capsys, "run", "cdrw", "cdrw_multi_fault", "--out", "o")
    assert rc == 2 and one_line(err) == "hil: cdrw_multi_fault: a scenario for aircraft 'missile', not 'cdrw'"
    assert not Path("o").exists()


def test_list_scenarios(tmp_path):
    """--list-scenarios without an aircraft, as --version: one line per shipped scenario."""
    r = subprocess.run([sys.executable, "-m", "hil.cli", "run", "--list-scenarios"], capture_output=True,
                       text=True, cwd=tmp_path, timeout=60)
    assert r.returncode == 0 and r.stderr == "", r
    names = [line.split()[0] for line in r.stdout.splitlines()]
    assert "cdrw_multi_fault" in names and "missile_default" in names and len(names) == len(set(names))
    assert all(line.split()[1] in ("cdrw", "missile") for line in r.stdout.splitlines())


def test_lqg_period_fcc_cannot_run(capsys, tmp_path):
    path = tmp_path / "m.toml"
    path.write_text('aircraft = "missile"\nduration = 2.0\n[lqg]\nperiod = 0.5\n')
    rc, _, err = run(capsys, "run", "missile", str(path), "--out", str(tmp_path / "o"))
    assert rc == 2 and "0.02 to 0.3 s" in one_line(err)


def test_sweep_bad_word_length(capsys, tmp_path):
    rc, _, err = run(capsys, "sweep", "missile", "--bits", "8,20", "--out", str(tmp_path / "o"))
    assert rc == 2 and "2 to 16" in one_line(err)


def test_missing_interface(capsys, tmp_path):
    # a flight on an interface that does not exist: one line, exit 1, no process left behind
    rc, _, err = run(capsys, "run", "cdrw", "--iface", "rigtest9", "--quiet", "--no-plots",
                     "--out", str(tmp_path / "o"))
    assert rc == 1
    assert "cannot open CAN interface 'rigtest9'" in one_line(err)


def test_report_needs_a_run_directory(capsys, tmp_path):
    rc, _, err = run(capsys, "report", str(tmp_path))
    assert rc == 2 and "no summary.json" in one_line(err)
    (tmp_path / "summary.json").write_text("{not json")
    rc, _, err = run(capsys, "report", str(tmp_path))
    assert rc == 2 and "not valid JSON" in one_line(err)


def test_report_prints_the_tables(capsys, tmp_path):
    import json
    from hil.results import metrics
    summary = {"command": "campaign", "runs_count": 2,
               "cdrw": {"table5": metrics.PAPER_TABLE5, "table5_truth": metrics.PAPER_TABLE5,
                        "azkf_better_than_kf_runs": {"alpha": 2, "q": 1}},
               "missile": {"runs": [{"period": 0.1, "bits": 8, "rms_q": 0.07, "rms_alpha": 0.005},
                                    {"period": 0.1, "bits": None, "rms_q": 0.08, "rms_alpha": 0.006}]}}
    (tmp_path / "summary.json").write_text(json.dumps(summary))
    rc, out, err = run(capsys, "report", str(tmp_path), "--no-plots")
    assert rc == 0, err
    assert "Table 5" in out and "0.0895 (+46.9%)" in out and "8 bit" in out
    assert "AZKF better than KF in 2 of 2 flights" in out


def test_entry_point_help():
    exe = Path(sys.executable).with_name("hil")
    r = subprocess.run([str(exe), "--help"], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0
    for cmd in ("run", "campaign", "sweep", "report", "demo"):
        assert cmd in r.stdout


# ---- no garbage with exit 0: the smaller defects of issue 13 ----------------------------------
@pytest.mark.parametrize("fault, words", [
    # frames nobody the rig plays sends: accepted and "injected" before, yet did nothing
    ("loss:frame=SID_AZKF_STATE,start=1,duration=1", "does not send SID_AZKF_STATE in a cdrw run"),
    ("loss:frame=MSL_RATE_GYRO,start=1,duration=1", "does not send MSL_RATE_GYRO in a cdrw run"),
    ("bad_crc:frame=SIM_CONTROL,start=1,duration=1", "does not send SIM_CONTROL"),
    # out_of_range on a signal its frame does not have: exit 1 at run time before
    ("out_of_range:frame=CDRW_AOA,signal=q,start=1,duration=1", "CDRW_AOA has no signal 'q'"),
    ("out_of_range:frame=*,signal=alpha,start=1,duration=1", "needs one frame"),
])
def test_fault_targets_are_what_the_simulator_sends(capsys, tmp_path, fault, words):
    rc, _, err = run(capsys, "run", "cdrw", "--fault", fault, "--out", str(tmp_path / "o"))
    assert rc == 2
    assert words in one_line(err)
    assert not (tmp_path / "o").exists()


def test_scenario_that_is_not_utf8(capsys, tmp_path):
    path = tmp_path / "latin1.toml"
    path.write_bytes('aircraft = "cdrw"\nname = "Flügel"\n'.encode("latin-1"))
    rc, _, err = run(capsys, "run", "cdrw", str(path), "--out", str(tmp_path / "o"))
    assert rc == 2 and "not UTF-8" in one_line(err) and str(path) in err


@pytest.mark.parametrize("text, words", [
    ('aircraft = "cdrw"\nduration = 1e9\n', "GB of memory"),
    ('aircraft = "missile"\nduration = 1e9\n', "GB of memory"),
    ('aircraft = "cdrw"\n[plant]\ndt = 1e-9\n', "field 'dt': must be >= 0.001"),
    ('aircraft = "cdrw"\n[plant]\nsubstep = 1e-12\n', "field 'substep'"),
])
def test_duration_and_steps_are_bounded_before_flying(capsys, tmp_path, text, words):
    path = tmp_path / "big.toml"
    path.write_text(text)
    aircraft = "missile" if "missile" in text else "cdrw"
    rc, _, err = run(capsys, "run", aircraft, str(path), "--out", str(tmp_path / "o"),
                     "--iface", "rigtest9")
    assert rc == 2 and words in one_line(err)


def test_campaign_memory_counts_every_flight():
    from hil.scenario.file import load_default_scenario
    from hil.scenario.schema import ScenarioError
    from hil.runs.budget import check_memory, estimate_bytes

    sc = load_default_scenario("cdrw")
    assert estimate_bytes(sc, 1000) > 10 * estimate_bytes(sc, 1)
    check_memory([sc], 100, available=2 * 10**9)      # the README's campaign: fits
    with pytest.raises(ScenarioError, match="GB of memory"):
        check_memory([sc.replace(duration=7000.0)], 100, available=2 * 10**9)


def test_fcc_args_may_be_a_single_flag(capsys, tmp_path):
    # `--fcc-args "--mls-intercept"` was refused as a missing argument (exit 2)
    rc, _, err = run(capsys, "run", "cdrw", "--fcc-args", "--mls-intercept", "--iface", "rigtest9",
                     "--quiet", "--out", str(tmp_path / "o"))
    assert rc == 1 and "cannot open CAN interface 'rigtest9'" in one_line(err)


@pytest.mark.parametrize("doc, words", [
    ("null", "expected a JSON object, got null"),
    ("[1, 2]", "expected a JSON object, got list"),
    ('{"firmware": {}}', "missing key 'e2e'"),
    ('{"cdrw": {"table4": {}}}', "missing key"),
    ('{"missile": {"runs": [1, 2]}}', "not a hil summary"),
])
def test_report_on_a_damaged_summary_is_one_line(capsys, tmp_path, doc, words):
    (tmp_path / "summary.json").write_text(doc)
    rc, _, err = run(capsys, "report", str(tmp_path))
    line = one_line(err)
    assert rc == 2 and words in line and str(tmp_path / "summary.json") in line


def test_report_into_a_closed_pipe(tmp_path):
    """`hil report DIR | head`: no broken-pipe message, exit 0 (the results are in place).
    The reader here (`true`) exits before hil has started, so hil's first print meets a
    closed pipe whatever the timing."""
    import json
    from hil.results import metrics
    summary = {"cdrw": {"table4": metrics.PAPER_TABLE4, "table4_truth": metrics.PAPER_TABLE4}}
    (tmp_path / "summary.json").write_text(json.dumps(summary))
    exe = Path(sys.executable).with_name("hil")
    r = subprocess.run(["bash", "-o", "pipefail", "-c",
                        f"'{exe}' report '{tmp_path}' --no-plots | true"],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    assert r.stderr == ""

def test_report_paper_rows_only_for_the_papers_scenario(capsys, tmp_path):
    import json
    from hil.results import metrics
    t = metrics.PAPER_TABLE4
    for paper in (True, False):
        summary = {"command": "run", "cdrw": {"table4": t, "table4_truth": t, "rows": "posterior",
                                               "paper_scenario": paper}}
        (tmp_path / "summary.json").write_text(json.dumps(summary))
        rc, out, err = run(capsys, "report", str(tmp_path), "--no-plots")
        assert rc == 0, err
        assert ("  paper" in out) is paper and "posterior rows" in out


@pytest.mark.parametrize("flags, shown", [
    ([], []),
    (["-v"], ["hil: scenario: missile_default ("]),
    (["--debug"], ["hil.io.paths: fcc: ", "hil.cli.common: scenario: missile_default ("]),
])
def test_verbose_and_debug(capsys, tmp_path, flags, shown):
    """-v/--verbose and --debug (before the command or after it) add hil's log records on
    stderr (hil.util.log) ahead of the one-line error, which stays the last line as it was."""
    for argv in ([*flags, "run", "cdrw", "missile_default"], ["run", "cdrw", "missile_default", *flags]):
        rc, out, err = run(capsys, *argv, "--out", str(tmp_path / "o"))
        lines = err.splitlines()
        assert rc == 2 and out == ""
        assert lines[-1].startswith("hil: ") and "not 'cdrw'" in lines[-1]
        records = lines[:-1]
        assert len(records) >= len(shown) and all(r.startswith("hil: ") for r in records), err
        for text in shown:
            assert any(text in r for r in records), (text, err)
        if not flags:
            assert records == []


@pytest.mark.parametrize("target, fcc_args, words", [
    ("host", "--bogus", "--fcc-args: fcc refuses them: unknown option '--bogus' (try fcc --help)"),
    ("host", "--lqg-bits 40", "--fcc-args: fcc refuses them: --lqg-bits"),
    ("qemu-m4f", "--window 10", "--fcc-args: the M4F image takes no --window"),
])
def test_fcc_args_checked_before_start_up(capsys, tmp_path, target, fcc_args, words):
    """A bad --fcc-args is one line and exit 2 before anything starts (fcc --check-args; the
    image's boot configuration): no rig, no interface, no cross-build, no run directory."""
    rc, out, err = run(capsys, "run", "cdrw", "--target", target, "--fcc-args", fcc_args,
                       "--quiet", "--out", str(tmp_path / "o"))
    assert rc == 2 and out == ""
    assert one_line(err) == f"hil: {words}" if words.endswith(")") else words in one_line(err)
    assert list(tmp_path.iterdir()) == []


def test_replay_checks_fcc_args_first(capsys, tmp_path):
    rc, _, err = run(capsys, "replay", str(tmp_path), "--fcc-args", "--bogus")
    assert rc == 2 and one_line(err) == "hil: --fcc-args: fcc refuses them: unknown option '--bogus' (try fcc --help)"
    assert list(tmp_path.iterdir()) == []
