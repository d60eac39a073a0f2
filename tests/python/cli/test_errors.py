"""hil's one exception hierarchy (hil.util.errors): every error hil reports is a HilError whose
class carries its exit status, which is in the one table of statuses (hil.cli.usage); an
exception that is not one is a bug: exit 70, one line, the traceback in a file."""
from __future__ import annotations

import importlib
import inspect
import sys
import pkgutil
from pathlib import Path

import pytest

import hil
from hil import cli
from hil.bus.candump import LogFormatError
from hil.bus.codec import EncodeError
from hil.bus.dbcfile import DbcError, DbcMissing
from hil.bus.secoc import KeyFileError
from hil.cli import usage
from hil.io.paths import NotShipped, ToolNotFound
from hil.io.rundir import OutDirRefused
from hil.parallel.guest import RigDown, RigFailed
from hil.parallel.warm import RigBusy, RigNotUp
from hil.results.sidframes import DuplicateOutput
from hil.rig.errors import FccDied, FccTimeout, RigError
from hil.rig.inject import InjectRefused
from hil.rig.link import LinkError
from hil.rig.txsched import TxError
from hil.runs.replay import ReplayError
from hil.scenario.schema import ScenarioError
from hil.targets.board import SlcanError
from hil.targets.device import ArgsRefused
from hil.targets.m4f_image import PilError
from hil.util.bounded import NotRegularFile, TooLarge, UnfitFile
from hil.util.errors import EXIT_SOFTWARE, HilError
from hil.util.processes import ProcessError
from hil.verify.coverage import CoverageError
from hil.verify.expr import ExpressionError
from hil.verify.series import SeriesError
from hil.verify.statistical import StatisticalError
from hil.verify.suite import SuiteError
from hil.verify.window import WindowError

#: every error class hil raises for its user, with the status the command line answers it with
EXPECTED = {
    ArgsRefused: 2, NotShipped: 2, StatisticalError: 1, CoverageError: 1,
    LogFormatError: 2, EncodeError: 1, DbcError: 2, DbcMissing: 2, KeyFileError: 1,
    usage.UsageError: 2, ToolNotFound: 1, OutDirRefused: 2, RigFailed: 1, RigDown: 1, RigBusy: 8,
    RigNotUp: 2, DuplicateOutput: 1, RigError: 1, FccTimeout: 3, FccDied: 4, LinkError: 1,
    TxError: 1, ReplayError: 2, ScenarioError: 2, SlcanError: 1, PilError: 1, UnfitFile: 2,
    TooLarge: 2, NotRegularFile: 2, ProcessError: 1, ExpressionError: 1, SeriesError: 1,
    SuiteError: 1, WindowError: 1, InjectRefused: 9,
}
#: the exceptions of hil that are no errors of its user: signals caught where they are raised
#: (a flow of control), KeyboardInterrupt's SIGTERM/SIGHUP, an OSError of the rig server
NOT_ERRORS = {"hil.bus.diag._Fail", "hil.cli.Terminated", "hil.cli.verify.Unpublished",
              "hil.parallel.keeper.Stopped", "hil.parallel.server.Unauthentic",
              "hil.verify.window.NoWindow"}


def _every_module() -> None:
    """Imports every module of hil: an error class anywhere is then a subclass seen here."""
    for info in pkgutil.walk_packages(hil.__path__, "hil."):
        if not info.name.endswith(".__main__"):  # (runs the program)
            importlib.import_module(info.name)


def _subclasses(cls: type) -> set[type]:
    return {c for s in cls.__subclasses__() for c in {s} | _subclasses(s)}


def test_every_error_class_is_listed_and_its_status_in_the_table() -> None:
    _every_module()
    known = {s for s, _ in usage.EXIT_STATUS}
    hil_classes = {c for c in _subclasses(HilError) if c.__module__.startswith("hil.")
                   and c.__name__ != "InputError"}
    assert hil_classes <= set(EXPECTED), f"an error class without its expected status: {hil_classes - set(EXPECTED)}"
    for cls, status in EXPECTED.items():
        assert issubclass(cls, HilError) and cls.exit_status == status, cls
        assert status in known


def test_every_exception_class_of_hil_is_a_hil_error() -> None:
    """A new exception class is a HilError (its exit status on the class), or one of the
    signals above: else the command line would call it a bug (exit 70)."""
    _every_module()
    found = {f"{c.__module__}.{c.__qualname__}" for m in list(sys.modules.values())
             if getattr(m, "__name__", "").startswith("hil.")
             for c in vars(m).values() if inspect.isclass(c) and issubclass(c, BaseException)
             and c.__module__ == m.__name__ and not issubclass(c, HilError)}
    assert found == NOT_ERRORS


def _planted(monkeypatch: pytest.MonkeyPatch, exc: BaseException) -> None:
    """`hil faults` raises exc from inside its command (a stand-in for any command's code)."""
    def run(_args: object) -> int:
        raise exc
    monkeypatch.setattr(importlib.import_module("hil.cli.faults"), "run", run)


@pytest.mark.parametrize("cls", sorted(EXPECTED, key=lambda c: c.__name__))
def test_each_user_error_exits_with_its_class_status(cls: type[HilError], monkeypatch: pytest.MonkeyPatch,
                                                      capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    _planted(monkeypatch, cls("what went wrong"))
    assert cli.main(["faults"]) == EXPECTED[cls]
    err = capsys.readouterr().err
    assert err == "hil: what went wrong\n"
    assert not list(tmp_path.rglob("crash-*.log"))


def _one_division(_args: object) -> int:
    return 1 // 0  # the planted bug


def test_a_bug_is_exit_70_one_line_and_its_traceback_in_a_file(monkeypatch: pytest.MonkeyPatch,
                                                               capsys: pytest.CaptureFixture[str],
                                                               tmp_path: Path) -> None:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.setattr(importlib.import_module("hil.cli.faults"), "run", _one_division)
    assert cli.main(["faults"]) == EXIT_SOFTWARE == 70
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("hil: internal error: ZeroDivisionError: ")
    logs = list((tmp_path / "hil").glob("crash-*.log"))
    assert len(logs) == 1 and f"(traceback in {logs[0]})" in err
    text = logs[0].read_text(encoding="utf-8")
    assert "Traceback (most recent call last)" in text and "_one_division" in text
    assert text.rstrip().endswith("ZeroDivisionError: integer division or modulo by zero")


@pytest.mark.parametrize("bug", [ValueError("a value no check refused"), RuntimeError("a state"),
                                 KeyError("x"), AttributeError("y")])
def test_a_builtin_error_nobody_turned_into_a_hil_error_is_a_bug(bug: Exception, monkeypatch: pytest.MonkeyPatch,
                                                                  capsys: pytest.CaptureFixture[str],
                                                                  tmp_path: Path) -> None:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    _planted(monkeypatch, bug)
    assert cli.main(["faults"]) == 70
    assert capsys.readouterr().err.startswith(f"hil: internal error: {type(bug).__name__}")


def test_no_writable_cache_still_one_line(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str],
                                          tmp_path: Path) -> None:
    blocked = tmp_path / "file"
    blocked.write_text("")
    monkeypatch.setenv("XDG_CACHE_HOME", str(blocked))  # hil/ cannot be made under a file
    monkeypatch.setattr(importlib.import_module("hil.cli.faults"), "run", _one_division)
    assert cli.main(["faults"]) == 70
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no traceback file could be written" in err
