"""Result safety without a bus (hil.io.rundir): a run writes into a staging directory that
is renamed into place when done, never deletes a file it did not write, refuses a foreign
--out without --force, writes every file atomically and keeps a failed run's partial results,
marked."""
from __future__ import annotations

import errno
import os
from pathlib import Path

import pytest

from hil.cli import main
from hil.io import rundir
from hil.io.output import read_json, write_csv, write_json
from hil.io.rundir import FAILED, MANIFEST, OutDirRefused, staged_run


def test_atomic_write_keeps_the_old_file_when_the_disk_is_full(tmp_path, monkeypatch):
    path = tmp_path / "summary.json"
    write_json(path, {"a": 1})

    def full(fd: int) -> None:
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(rundir.os, "fsync", full)
    with pytest.raises(OSError):
        write_json(path, {"a": 2, "b": list(range(1000))})
    monkeypatch.undo()
    assert read_json(path) == {"a": 1}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["summary.json"]  # no temporary left


def test_csv_and_json_go_through_a_temporary_file(tmp_path, monkeypatch):
    seen: list[tuple[str, str]] = []
    real = os.replace

    def spy(src, dst):
        seen.append((Path(src).name, Path(dst).name))
        return real(src, dst)

    monkeypatch.setattr(rundir.os, "replace", spy)
    write_csv(tmp_path / "x.csv", {"t": [0.0, 1.0]})
    write_json(tmp_path / "s.json", {"k": 1})
    assert [d for _, d in seen] == ["x.csv", "s.json"]
    assert all(s.startswith(".") and ".tmp-" in s for s, _ in seen)


def test_a_run_is_on_the_disk_before_it_is_published(tmp_path, monkeypatch):
    """Files in the staging directory are not fsynced one by one as they are written: the
    whole directory is made durable once (syncfs) before the rename that publishes it."""
    synced: list[int] = []
    real_fsync, real_durable = os.fsync, rundir.make_durable
    monkeypatch.setattr(rundir.os, "fsync", lambda fd: (synced.append(fd), real_fsync(fd)))
    events: list[str] = []

    def durable(root: Path) -> None:
        events.append(f"durable {sorted(p.name for p in root.iterdir())} out exists: {out.exists()}")
        real_durable(root)
    monkeypatch.setattr(rundir, "make_durable", durable)
    out = tmp_path / "out"
    with staged_run(out, "test") as stage:
        write_json(stage / "summary.json", {"k": 1})
        write_csv(stage / "x.csv", {"t": [0.0]})
        assert synced == []
    assert events == [f"durable {sorted([MANIFEST, 'summary.json', 'x.csv'])} out exists: False"]
    assert read_json(out / "summary.json") == {"k": 1}
    synced.clear()                              # (the publishing rename's directory)
    write_json(out / "later.json", {"k": 2})   # outside a staging directory: at once
    assert len(synced) == 2                     # the file and its directory


def test_a_full_disk_at_publication_publishes_nothing(tmp_path, monkeypatch):
    out = tmp_path / "out"
    _publish(out, {"summary.json": "good"})

    def full(root: Path) -> None:
        raise OSError(errno.ENOSPC, "No space left on device", str(root))
    monkeypatch.setattr(rundir, "make_durable", full)
    with pytest.raises(OSError, match="No space left"):
        _publish(out, {"summary.json": "new"})
    assert (out / "summary.json").read_text() == "good"


def test_make_durable_without_syncfs_fsyncs_every_file_and_directory(tmp_path, monkeypatch):
    (tmp_path / "d").mkdir()
    (tmp_path / "a.csv").write_text("1")
    (tmp_path / "d" / "b.csv").write_text("2")
    synced: list[int] = []
    real_fsync = os.fsync
    monkeypatch.setattr(rundir.os, "fsync", lambda fd: (synced.append(fd), real_fsync(fd)))
    rundir.make_durable(tmp_path)               # syncfs: one call, no fsync
    assert synced == []
    monkeypatch.setattr(rundir.ctypes, "CDLL", lambda *a, **k: object())   # a libc without it
    rundir.make_durable(tmp_path)
    assert len(synced) == 4                     # 2 files, 2 directories


def _publish(out: Path, files: dict[str, str], force: bool = False) -> None:
    with staged_run(out, "test", force=force) as stage:
        assert stage != out and stage.parent == out.parent
        assert not (out / "summary.json").exists() or (out / MANIFEST).exists()
        for name, text in files.items():
            (stage / name).parent.mkdir(parents=True, exist_ok=True)
            (stage / name).write_text(text)


def test_a_run_appears_whole_and_replaces_only_an_earlier_run(tmp_path):
    out = tmp_path / "out"
    _publish(out, {"summary.json": "1", "bus.log": "a", "sweep/x.csv": "c"})
    assert (out / "summary.json").read_text() == "1" and (out / "sweep/x.csv").exists()
    _publish(out, {"summary.json": "2"})             # an earlier hil run: replaced whole
    assert sorted(p.name for p in out.iterdir()) == [MANIFEST, "summary.json"]
    assert (out / "summary.json").read_text() == "2"
    assert [p.name for p in tmp_path.iterdir()] == ["out"]  # no staging or old copy left


def test_a_foreign_out_is_refused_and_kept(tmp_path):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("my notes")
    (out / "summary.json").write_text("my own summary")
    with pytest.raises(OutDirRefused, match="not a hil run directory"):
        _publish(out, {"summary.json": "new"})
    assert (out / "notes.txt").read_text() == "my notes"
    assert (out / "summary.json").read_text() == "my own summary"
    # an earlier run's directory with a user's file added is foreign too
    run = tmp_path / "run"
    _publish(run, {"summary.json": "1"})
    (run / "analysis.ipynb").write_text("{}")
    with pytest.raises(OutDirRefused):
        _publish(run, {"summary.json": "2"})
    assert (run / "analysis.ipynb").exists() and (run / "summary.json").read_text() == "1"


def test_force_adds_the_results_and_keeps_every_other_file(tmp_path):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("my notes")
    _publish(out, {"summary.json": "new", "sweep/a.csv": "x"}, force=True)
    assert (out / "notes.txt").read_text() == "my notes"
    assert (out / "summary.json").read_text() == "new" and (out / "sweep/a.csv").exists()


def test_a_failed_run_keeps_its_partial_results_marked(tmp_path):
    out = tmp_path / "out"
    _publish(out, {"summary.json": "good"})
    with pytest.raises(RuntimeError) as ei:
        with staged_run(out, "run") as stage:
            (stage / "bus.log").write_text("frames")
            raise RuntimeError("fcc died")
    assert (out / "summary.json").read_text() == "good"        # the earlier results stay
    failed = [p for p in tmp_path.iterdir() if p.name.startswith("out.failed-")]
    assert len(failed) == 1
    assert (failed[0] / "bus.log").read_text() == "frames"
    assert "fcc died" in (failed[0] / FAILED).read_text()
    assert str(failed[0]) in ei.value.__notes__[0]
    # a failure before anything was written leaves nothing behind
    with pytest.raises(ValueError):
        with staged_run(tmp_path / "other", "run"):
            raise ValueError("bad")
    assert not any(p.name.startswith((".other", "other")) for p in tmp_path.iterdir())


def test_cli_refuses_a_foreign_out_in_one_line(capsys, tmp_path):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "thesis.tex").write_text("chapter 1")
    rc = main(["run", "cdrw", "--out", str(out), "--iface", "rigtest9", "--quiet"])
    err = capsys.readouterr().err
    assert rc == 2
    assert err.count("\n") == 1 and "--force" in err and str(out) in err
    assert (out / "thesis.tex").read_text() == "chapter 1"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mine"]


def test_cli_never_deletes_a_users_file_with_force(capsys, tmp_path):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "thesis.tex").write_text("chapter 1")
    rc = main(["run", "cdrw", "--out", str(out), "--iface", "rigtest9", "--quiet", "--force"])
    assert rc == 1  # no such interface; nothing was written, so no failed directory either
    assert (out / "thesis.tex").read_text() == "chapter 1"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mine"]
