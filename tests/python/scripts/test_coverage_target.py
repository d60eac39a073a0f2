"""scripts/lib/coverage_target.py's comparison of the host's and the target's line counts: only lines
both compilers count as code, and only a line run on one build and never on the other."""

import importlib.util
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[3]
_spec = importlib.util.spec_from_file_location("coverage_target", REPO / "scripts/lib/coverage_target.py")
assert _spec is not None and _spec.loader is not None
target = importlib.util.module_from_spec(_spec)
sys.modules["coverage_target"] = target  # dataclasses look their module up there
_spec.loader.exec_module(target)


def test_only_lines_run_on_one_build_disagree() -> None:
    host = {"a.c": {1: 5, 2: 0, 3: 7, 4: 1}, "host_only.c": {1: 1}}
    tgt = {"a.c": {1: 2, 2: 0, 3: 0, 5: 0}, "b.c": {1: 0}}
    assert target.compare(host, tgt) == [target.Disagreement("a.c", 3, 7, 0)]
    assert target.compare({"a.c": {2: 0}}, {"a.c": {2: 3}}) == [target.Disagreement("a.c", 2, 0, 3)]


def test_only_hand_written_portable_sources_count() -> None:
    firmware = REPO / "firmware"
    assert target.portable_name(str(firmware / "sid/fcc_kf.c")) == "sid/fcc_kf.c"
    assert target.portable_name(str(firmware / "bus/generated/fcc_hil.c")) is None
    assert target.portable_name(str(firmware / "port/linux/fcc_port_linux.c")) is None
    assert target.portable_name(str(REPO / "tests/c/fcc_test.h")) is None
