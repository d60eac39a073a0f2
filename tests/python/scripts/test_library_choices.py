"""scripts/lib/library_choices.py times hil's own code beside the library that could replace it
(docs/decisions.md): each pair must give the same answers first, or the timing compares
different work.  Checked here (the timings are the script's run, not a test's)."""
from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest
from conftest import REPO


def _script():
    spec = importlib.util.spec_from_file_location("library_choices", REPO / "scripts" / "lib" / "library_choices.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


lib = _script()


def test_frame_packing_is_cantools_bytes() -> None:
    calls, same = lib.packers()
    assert same and set(calls) == {"hil.bus.dbc", "cantools"}
    assert calls["hil.bus.dbc"]() == calls["cantools"]()


def test_candump_parsing_is_python_cans(tmp_path: Path) -> None:
    calls, same = lib.readers(lib.candump_log(tmp_path, 500))
    assert same and calls["hil.bus.candump"]() == calls["python-can"]() == 500


@pytest.mark.skipif(importlib.util.find_spec("crccheck") is None, reason="crccheck not installed")
def test_crc8_is_crcchecks() -> None:
    frames = [bytes([i, 255 - i, 0, 7, i, i, 0xAA, 0x55]) for i in range(256)] + [b"123456789"]
    calls, same = lib.crcs(frames)
    assert same and calls["hil.bus.e2e"]()[-1] == 0x4B


def test_bootstrap_is_scipys() -> None:
    calls, (diff, width) = lib.bootstraps(500)
    assert diff < 1e-9 and np.all(width > 0)            # the same resamples: the same interval


def test_the_validators_accept_the_scenario() -> None:
    calls = lib.validators()
    for name, load in calls.items():
        assert load() is not None, name
