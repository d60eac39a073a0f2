"""`hil replay` of a run directory whose files are malformed: one line naming the file and
exit status 2 (bad input), never 1 (which says DIFFERENT) nor a traceback -- and nothing is
started: the log and run_info.json are read before fcc is (no CAN interface needed here)."""
from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

from hil.bus.secoc import TEST_KEY_FILE
from hil.rig.session import KEPT_KEY
from rig_helpers import cli

RUN_INFO = '{"mode": "lockstep", "fcc_command": "fcc --iface vcan0 --trip 3"}'
GOOD_LINE = "(1.000000) vcan0 7F0#0102030405060708\n"


def _run_dir(tmp_path: Path, log_name: str = "bus.log", log: bytes = GOOD_LINE.encode(),
             run_info: str = RUN_INFO) -> Path:
    run = tmp_path / "rec"
    run.mkdir()
    (run / "run_info.json").write_text(run_info)
    shutil.copy(TEST_KEY_FILE, run / KEPT_KEY)
    (run / log_name).write_bytes(log)
    return run


def _refused(capsys, run: Path, *words: str) -> None:
    rc, out, err = cli(capsys, "replay", str(run), "--out", str(run.parent / "replay-out"))
    assert rc == 2, (out, err)
    assert out == "" and err.count("\n") == 1 and err.startswith("hil: "), err
    assert "Traceback" not in err and all(w in err for w in words), err
    assert not (run.parent / "replay-out" / "fcc.log").exists()     # nothing was started


@pytest.mark.parametrize("log", [
    b"(1.000000) vcan0 7F0#0102\nthis is not candump\n",
    GOOD_LINE.encode() + b"(2.0) vcan0 7F0#012\n",                  # odd number of hex digits
    GOOD_LINE.encode() + b"(2.0) vcan0 7F0#" + b"00" * 9 + b"\n",   # 9 data bytes
    b"\x00\xff\xfe" * 100,                                          # binary
])
def test_a_malformed_candump_log_is_bad_input(tmp_path, capsys, log):
    _refused(capsys, _run_dir(tmp_path, log=log), "bus.log", "not a bus log hil can replay", "line ")


def test_a_malformed_vector_log_is_bad_input(tmp_path, capsys):
    _refused(capsys, _run_dir(tmp_path, "bus.blf", b"NOPE" + os.urandom(300)), "bus.blf",
             "not a bus log hil can replay")


@pytest.mark.parametrize("log", [b"", GOOD_LINE.encode()])
def test_a_log_without_an_acknowledged_step_is_nothing_to_replay(tmp_path, capsys, log):
    _refused(capsys, _run_dir(tmp_path, log=log), "bus.log", "nothing to replay")


@pytest.mark.parametrize("run_info, words", [
    ("{not json", "not valid JSON"),
    ("[" * 100_000 + "]" * 100_000, "RecursionError"),
    ('["a list"]', "not a run_info object"),
    ('{"mode": "lockstep"}', "no fcc command line"),
])
def test_a_malformed_run_info_is_bad_input(tmp_path, capsys, run_info, words):
    _refused(capsys, _run_dir(tmp_path, run_info=run_info), "run_info.json", words)


def test_a_fifo_as_run_info_is_refused_not_waited_for(tmp_path, capsys):
    run = _run_dir(tmp_path)
    (run / "run_info.json").unlink()
    os.mkfifo(run / "run_info.json")
    _refused(capsys, run, "run_info.json: a FIFO, not a run_info.json")
