"""Whatever a user hands `hil` -- a FIFO, a device or a directory for a file, a broken DBC, input
nested too deeply, a signal while hil is still starting, a scenario after an option -- the answer
is one line and the exit status of the one table (hil.cli.usage), never a hang or a traceback.
Every case here is decided before anything flies: no CAN interface is needed."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import REPO
from hil.bus import dbc
from hil.cli import usage
from hil.cli.parser import build
from hil.util.bounded import NotRegularFile, TooLarge, open_regular, read_bounded

DBC = REPO / "dbc" / "fcc_hil.dbc"


def hil(*argv: str, env: dict[str, str] | None = None, timeout: float = 60) -> tuple[int, str]:
    """`hil ARGV` as a user runs it (a process of its own: a FIFO that blocked would time out
    here, not hang the test run): (exit status, stderr)."""
    r = subprocess.run([sys.executable, "-m", "hil.cli", *argv], capture_output=True, text=True,
                       timeout=timeout, env=env, stdin=subprocess.DEVNULL, check=False)
    return r.returncode, r.stderr


def one_line(err: str) -> str:
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("hil: ") and "Traceback" not in err, err
    return lines[0]


# ---- regular files only (hil.util.bounded) ------------------------------------------------------
@pytest.fixture
def not_files(tmp_path: Path) -> dict[str, tuple[str, str]]:
    """path and the words for what it is: a FIFO nobody writes to, a device that never ends, a
    directory."""
    fifo = tmp_path / "fifo.toml"
    os.mkfifo(fifo)
    return {"fifo": (str(fifo), "a FIFO"), "device": ("/dev/zero", "a character device"),
            "directory": (str(tmp_path), "a directory")}


@pytest.mark.parametrize("kind", ["fifo", "device", "directory"])
@pytest.mark.parametrize("argv, what", [
    (["run", "cdrw", "{}"], "scenario file"),
    (["run", "missile", "--key-file", "{}"], "key file"),
    (["run", "cdrw", "--dbc", "{}"], "DBC"),
    (["verify", "{}"], "suite"),
])
def test_a_file_argument_that_is_no_regular_file_is_one_line(not_files, tmp_path, kind, argv, what):
    path, words = not_files[kind]
    rc, err = hil(*[a.replace("{}", path) for a in argv], "--out", str(tmp_path / "o"))
    assert rc == usage.EXIT_USAGE, err
    assert f"{path}: {words}, not a {what} (only a regular file is read)" in one_line(err)
    assert not (tmp_path / "o").exists()


def test_the_reader_takes_regular_files_within_their_bound(tmp_path):
    f = tmp_path / "key"
    f.write_bytes(b"x" * 10)
    assert read_bounded(f, 10, "key file") == b"x" * 10
    with pytest.raises(TooLarge, match="larger than a key file can be .9 bytes at most."):
        read_bounded(f, 9, "key file")
    with open_regular(f, 10, "bus log") as fh:
        assert fh.read() == b"x" * 10
    os.mkfifo(tmp_path / "fifo")
    with pytest.raises(NotRegularFile, match="a FIFO, not a bus log"):
        open_regular(tmp_path / "fifo", 10, "bus log")         # refused, not waited for
    os.symlink("/dev/zero", tmp_path / "link")
    with pytest.raises(NotRegularFile, match="a character device"):
        read_bounded(tmp_path / "link", 10, "key file")         # what a link points at counts
    with pytest.raises(FileNotFoundError):
        read_bounded(tmp_path / "nothing", 10, "key file")


# ---- every DBC error one line -------------------------------------------------------------------
def _edits() -> dict[str, bytes]:
    text = DBC.read_bytes()
    return {
        "empty": b"",
        "binary": bytes(range(256)) * 8,
        "truncated": text[: len(text) // 2],
        "identifier too large": text.replace(b"\nBO_ 272 ", b"\nBO_ 99999 "),
        "identifier taken": text.replace(b"\nBO_ 272 ", b"\nBO_ 273 "),
        "message renamed": text.replace(b"BO_ 80 CDRW_AOA:", b"BO_ 80 CDRW_AOX:"),
        "signal renamed": text.replace(b" alpha_hat ", b" alpha_hut "),
    }


@pytest.mark.parametrize("edit, words", [
    ("empty", "an empty file, not a DBC"),
    ("binary", "not a DBC: byte "),
    ("truncated", "not a DBC this rig reads: Invalid syntax at line "),
    ("identifier too large", "Standard frame id 0x1869f is more than 11 bits"),
    ("identifier taken", "SID_AZKF_STATE and SID_AZKF_BOUNDS have the same identifier 0x111"),
    ("message renamed", "no message 'CDRW_AOA'"),
    ("signal renamed", "SID_AZKF_STATE has no signal 'alpha_hat'"),
])
@pytest.mark.parametrize("given", ["--dbc", "$FCC_HIL_DBC"])
def test_a_broken_dbc_is_one_line_before_anything_flies(tmp_path, edit, words, given):
    bad = tmp_path / "edited.dbc"
    bad.write_bytes(_edits()[edit])
    env = {**os.environ, dbc.DBC_ENV: str(bad)} if given.startswith("$") else None
    rc, err = hil("run", "cdrw", *(["--dbc", str(bad)] if env is None else []),
                  "--out", str(tmp_path / "o"), env=env)
    line = one_line(err)
    assert rc == usage.EXIT_USAGE and line.startswith(f"hil: {given}: {bad}") and words in line, line
    assert not (tmp_path / "o").exists()


def test_the_shipped_dbc_and_an_unchanged_copy_pass(tmp_path):
    copy = tmp_path / "copy.dbc"
    copy.write_bytes(DBC.read_bytes() + b"\n")          # parsed by cantools: not the digest's bytes
    dbc.check_contract(dbc.load(copy))
    assert [m.frame_id for m in dbc.load(copy).messages] == [m.frame_id for m in dbc.load().messages]


# ---- input nested too deeply, memory ------------------------------------------------------------
def test_a_scenario_nested_too_deeply_is_bad_input(tmp_path):
    sc = tmp_path / "deep.toml"
    sc.write_text('aircraft = "missile"\nx = ' + "[" * 5000 + "]" * 5000 + "\n")
    rc, err = hil("run", "missile", str(sc), "--out", str(tmp_path / "o"))
    line = one_line(err)
    assert rc == usage.EXIT_USAGE and line.startswith(f"hil: {sc}: ") and "nested too deeply" in line, line


def test_memory_exhausted_is_one_line(capsys, monkeypatch):
    import hil.cli as cli

    def exhaust(_args: object) -> int:
        raise MemoryError
    monkeypatch.setattr(cli, "dispatch", exhaust)
    assert cli.main(["run", "cdrw"]) == usage.EXIT_FAILED
    assert one_line(capsys.readouterr().err) == "hil: out of memory (MemoryError)"


# ---- signals while hil starts -------------------------------------------------------------------
#: `hil ARGV` with the signal sent to itself in the middle of its imports (when hil.io.rundir is
#: looked for): the moment a Ctrl-C in the first 0.4 s of `hil run` met in the UML guest
SIGNAL_DURING_IMPORT = """
import os, signal, sys
SIG = int(sys.argv[1])
class SignalOnImport:
    def find_spec(self, name, path=None, target=None):
        if name == "hil.io.rundir":
            os.kill(os.getpid(), SIG)
        return None
sys.meta_path.insert(0, SignalOnImport())
sys.argv = ["hil", *sys.argv[2:]]
from hil.cli import entry
entry()
"""


@pytest.mark.parametrize("sig, status, words", [
    (signal.SIGINT, usage.EXIT_SIGINT, "hil: interrupted"),
    (signal.SIGTERM, usage.EXIT_SIGTERM, "hil: terminated by SIGTERM"),
    (signal.SIGHUP, usage.EXIT_SIGHUP, "hil: terminated by SIGHUP"),
])
def test_a_signal_while_hil_imports_is_one_line_and_its_status(tmp_path, sig, status, words):
    r = subprocess.run([sys.executable, "-c", SIGNAL_DURING_IMPORT, str(int(sig)), "run", "missile",
                        "--mode", "realtime", "--out", str(tmp_path / "o")],
                       capture_output=True, text=True, timeout=60, check=False)
    assert r.returncode == status, r.stderr
    assert r.stderr == words + "\n" and r.stdout == ""
    assert not any(tmp_path.iterdir())


def test_an_ignored_hangup_stays_ignored(tmp_path):
    """`nohup hil ...`: SIGHUP ignored before hil starts is not hil's to take."""
    r = subprocess.run([sys.executable, "-c", SIGNAL_DURING_IMPORT, str(int(signal.SIGHUP)), "--version"],
                       capture_output=True, text=True, timeout=60, check=False,
                       preexec_fn=lambda: signal.signal(signal.SIGHUP, signal.SIG_IGN))
    assert r.returncode == 0 and r.stdout.startswith("hil ") and r.stderr == ""


def test_an_interrupt_between_the_handlers_is_the_same_line(capsys, monkeypatch):
    """A KeyboardInterrupt outside main's own try (after the imports, before or after its
    handlers) still ends `hil` with the one line and 130."""
    import hil.cli as cli

    def interrupted(_argv: object = None) -> int:
        raise KeyboardInterrupt
    monkeypatch.setattr(cli, "main", interrupted)
    with pytest.raises(SystemExit) as stop:
        cli.entry()
    assert stop.value.code == usage.EXIT_SIGINT
    assert one_line(capsys.readouterr().err) == "hil: interrupted"


# ---- the command line: positionals and options in any order -------------------------------------
@pytest.mark.parametrize("argv", [
    ["run", "missile", "--quiet", "S.toml"],
    ["run", "missile", "S.toml", "--quiet"],
    ["run", "--quiet", "missile", "--seed", "3", "S.toml", "--no-plots"],
    ["campaign", "cdrw", "--runs", "3", "S.toml"],
    ["sweep", "missile", "--bits", "6", "S.toml"],
])
def test_a_scenario_may_follow_the_options(argv):
    args = build().parse_args(argv)
    assert args.scenario == "S.toml" and args.aircraft == argv[argv.index(args.aircraft)]


def test_a_second_scenario_is_still_refused(capsys):
    from hil.cli import main
    assert main(["run", "missile", "--quiet", "A.toml", "B.toml"]) == usage.EXIT_USAGE
    assert "unrecognized arguments: B.toml" in one_line(capsys.readouterr().err)


def test_a_fifo_as_an_out_directorys_manifest_makes_it_no_hil_run(tmp_path):
    """--out's manifest (.hil-run.json) is read as every file is: a FIFO there is no manifest
    (the directory is not hil's own, so not replaced), not a read that waits."""
    from hil.io import rundir
    out = tmp_path / "o"
    out.mkdir()
    os.mkfifo(out / rundir.MANIFEST)
    assert not rundir.is_own_run(out)


@pytest.mark.parametrize("log", [b"this is not candump\n", b"(1.0) vcan0 7F0#012\n"])
def test_report_of_a_malformed_bus_log_is_one_line(capsys, tmp_path, log):
    from hil.cli import main
    (tmp_path / "summary.json").write_text('{"command": "run"}')
    (tmp_path / "bus.log").write_bytes(log)
    assert main(["report", str(tmp_path), "--bus", "--no-plots"]) == usage.EXIT_USAGE
    assert f"{tmp_path / 'bus.log'}: not a bus log hil can read: line 1" in one_line(capsys.readouterr().err)
