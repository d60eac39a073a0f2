"""Nothing the bus says is taken on trust, the file side (issue items 3-6): runs never
corrupt each other, the user's files are never overwritten, file arguments are read with a
bound.  Ordered by events and files, never by wall-clock time."""
from __future__ import annotations

import json
import os
import threading
from pathlib import Path

import pytest

from hil.io import rundir
from hil.io.rundir import OutDirRefused, staged_run


def _run(out: Path, table: str, staged: threading.Event, go: threading.Event,
         results: dict[str, object]) -> None:
    try:
        with staged_run(out, "run") as stage:
            (stage / "summary.json").write_text(json.dumps({"table4": table}))
            staged.set()
            go.wait()
        results[table] = "published"
    except OutDirRefused as e:
        results[table] = str(e)


def test_two_runs_with_the_same_pid_into_one_out_never_mix(tmp_path, monkeypatch):
    """Two guests' runs whose PIDs are equal: separate staging directories; whichever
    publishes, --out holds one whole run (its own table), and the other's is kept whole."""
    monkeypatch.setattr(os, "getpid", lambda: 4242)
    out = tmp_path / "out"
    results: dict[str, object] = {}
    sa, sb, ga, gb = (threading.Event() for _ in range(4))
    a = threading.Thread(target=_run, args=(out, "A", sa, ga, results))
    b = threading.Thread(target=_run, args=(out, "B", sb, gb, results))
    a.start()
    b.start()
    sa.wait()
    sb.wait()
    stages = sorted(p.name for p in tmp_path.iterdir() if ".partial-" in p.name)
    assert len(stages) == 2 and all("-4242-" in s for s in stages)
    ga.set()
    a.join()
    gb.set()
    b.join()
    assert results == {"A": "published", "B": "published"}   # B replaced A's complete run
    assert json.loads((out / "summary.json").read_text()) == {"table4": "B"}
    assert rundir.is_own_run(out)
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


def test_a_run_that_loses_the_publish_race_keeps_its_results_and_removes_nothing(tmp_path, monkeypatch):
    out = tmp_path / "out"
    rename = os.rename
    other = tmp_path / "other"

    def racing_rename(src, dst):  # type: ignore[no-untyped-def]
        if Path(dst) == out and ".partial-" in Path(src).name and not out.exists():
            other.mkdir()
            (other / "summary.json").write_text('{"table4": "other"}')
            rename(other, out)   # another run's publish, just before ours
        return rename(src, dst)

    monkeypatch.setattr(os, "rename", racing_rename)
    with pytest.raises(OutDirRefused, match="another run published into it") as e:
        with staged_run(out, "run") as stage:
            (stage / "summary.json").write_text('{"table4": "mine"}')
    assert json.loads((out / "summary.json").read_text()) == {"table4": "other"}
    kept = Path(str(e.value).rsplit(" ", 1)[1])
    assert json.loads((kept / "summary.json").read_text()) == {"table4": "mine"}


def test_a_staging_directory_is_never_shared_or_removed_by_another_run(tmp_path, monkeypatch):
    monkeypatch.setattr(os, "getpid", lambda: 7)
    out = tmp_path / "out"
    foreign = tmp_path / ".out.partial-7"       # the old name of pid 7's stage: not ours
    foreign.mkdir()
    (foreign / "bus.log").write_text("someone else's\n")
    with staged_run(out, "run") as stage:
        (stage / "x.csv").write_text("1\n")
    assert (foreign / "bus.log").read_text() == "someone else's\n"
    assert rundir.published_path(stage) == out


def _summary_dir(path: Path) -> Path:
    """A published run directory (manifest) whose summary has data for Fig. 3."""
    runs = [{"period": T, "bits": b, "rms_q": 0.07, "rms_alpha": 0.005}
            for T in (0.1, 0.05) for b in (8, None)]
    with staged_run(path, "sweep") as stage:
        (stage / "summary.json").write_text(json.dumps({"command": "sweep", "missile": {"runs": runs}}))
    return path


def test_report_never_overwrites_a_users_figure(tmp_path, capsys):
    from hil.cli import main
    run = _summary_dir(tmp_path / "run")
    rc = main(["report", str(run)])
    assert rc == 0
    assert "fig3_missile_rms.png" in json.loads((run / rundir.MANIFEST).read_text())["files"]
    # the user's own figure of the same name in a run directory that did not list it
    other = _summary_dir(tmp_path / "other")
    (other / "fig3_missile_rms.png").write_bytes(b"my figure")
    capsys.readouterr()
    rc = main(["report", str(other)])
    err = capsys.readouterr().err
    assert rc == 0
    assert (other / "fig3_missile_rms.png").read_bytes() == b"my figure"
    assert "fig3_missile_rms.png" not in json.loads((other / rundir.MANIFEST).read_text())["files"]
    assert err.count("\n") == 1 and "fig3_missile_rms.png is not hil's" in err


def test_force_never_overwrites_a_users_summary(tmp_path):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "summary.json").write_text("my notes")
    with pytest.raises(OutDirRefused, match="summary.json is not hil's") as e:
        with staged_run(out, "run", force=True) as stage:
            (stage / "summary.json").write_text("{}")
            (stage / "cdrw.csv").write_text("t\n0\n")
    assert (out / "summary.json").read_text() == "my notes"
    assert sorted(p.name for p in out.iterdir()) == ["summary.json"]
    kept = Path(str(e.value).rsplit(" ", 1)[1])
    assert (kept / "summary.json").read_text() == "{}"
    # a file hil wrote there before (listed in its manifest) is replaced
    with staged_run(tmp_path / "hils", "run") as stage:
        (stage / "summary.json").write_text('{"n": 1}')
    (tmp_path / "hils" / "notes.txt").write_text("mine")
    with staged_run(tmp_path / "hils", "run", force=True) as stage:
        (stage / "summary.json").write_text('{"n": 2}')
    assert (tmp_path / "hils" / "summary.json").read_text() == '{"n": 2}'
    assert (tmp_path / "hils" / "notes.txt").read_text() == "mine"


# ---- bounded reads and clear lines (item 6) ----------------------------------------------------
@pytest.mark.parametrize("argv, words", [
    (["run", "cdrw", "--key-file", "/dev/zero"], "/dev/zero: a character device, not a key file"),
    (["run", "cdrw", "/dev/zero"], "/dev/zero: a character device, not a scenario file"),
    (["campaign", "cdrw", "--workers", "1000"], "--workers must be 1..64, got 1000"),
])
def test_file_arguments_are_read_with_a_bound(capsys, tmp_path, argv, words):
    from hil.cli import main
    rc = main([*argv, "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1 and words in err, err
    assert not (tmp_path / "o").exists()


def test_a_zero_variance_is_refused_by_the_scenario_check(capsys, tmp_path):
    from hil.cli import main
    sc = tmp_path / "m.toml"
    sc.write_text('aircraft = "missile"\n[sensors]\nvar_gyro = 0\n')
    rc = main(["run", "missile", str(sc), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2 and "var_gyro and var_acc must be > 0" in err and err.count("\n") == 1


@pytest.mark.parametrize("exc, line", [
    (OSError(28, "No space left on device", "/mnt/full/o"), "hil: no space left on device: /mnt/full/o"),
    (OSError(30, "Read-only file system", "/ro/o"), "hil: read-only file system: /ro/o"),
    (FileNotFoundError(2, "No such file or directory", "/x/y"), "hil: no such file or directory: /x/y"),
])
def test_errno_failures_are_one_clear_line(capsys, monkeypatch, exc, line):
    import hil.cli as cli
    def fail(_args):  # type: ignore[no-untyped-def]
        raise exc
    monkeypatch.setattr(cli, "dispatch", fail)
    rc = cli.main(["run", "cdrw"])
    err = capsys.readouterr().err
    assert rc == 1 and err == line + "\n" and "Errno" not in err


def test_a_killed_candump_is_not_reported_by_its_banner(tmp_path):
    from hil.rig.recorder import Candump
    rec = Candump.__new__(Candump)
    rec._err_path = tmp_path / "stderr"
    rec._err_path.write_text("Enabling Logfile 'candump-2026-01-01_000000.log'\n")
    rec._error = None
    class P:  # a candump killed by SIGKILL
        returncode = -9
    rec.proc = P()  # type: ignore[assignment]
    assert rec.error() == "killed by SIGKILL"


def test_a_full_disk_is_named_not_a_slow_recorder(tmp_path, monkeypatch):
    from types import SimpleNamespace

    from hil.rig import flight
    from hil.rig.errors import RigError
    rig = SimpleNamespace(log_complete=False, recorder_error="", run_dir=tmp_path)
    monkeypatch.setattr(os, "statvfs", lambda _p: SimpleNamespace(f_bavail=0, f_frsize=4096))
    with pytest.raises(RigError, match=f"no space left on the device of {tmp_path}"):
        flight.require_log(rig)  # type: ignore[arg-type]
