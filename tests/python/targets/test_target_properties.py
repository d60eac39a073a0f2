"""Every target has every property (hil.targets.registry.Target), its Device class says the
same name, and the command line takes its defaults from them (no table of target names
elsewhere: a new target is one Target and its Device class)."""
from __future__ import annotations

import argparse
import dataclasses
import typing
from pathlib import Path

import pytest

from hil.cli import common
from hil.cli.parser import TARGET_CHOICES, build
from hil.cli.usage import UsageError
from hil.rig import lockstep
from hil.targets.device import Device
from hil.targets.registry import TARGETS, Target, device_class, target

HINTS = typing.get_type_hints(Target)


@pytest.mark.parametrize("name", TARGETS)
def test_every_target_has_every_property(name: str) -> None:
    t = target(name)
    assert t.name == name
    for f in dataclasses.fields(Target):
        value = getattr(t, f.name)
        hint = HINTS[f.name]
        kinds = tuple(a for a in typing.get_args(hint) if isinstance(a, type)) or (hint,)
        assert isinstance(value, kinds), f"{name}.{f.name} = {value!r} is not {hint}"
    assert t.lockstep_timeout_s > 0
    assert (t.program is None) <= (not t.builds_program)   # it builds only a program it has
    assert t.runs_rig_firmware or not (t.program or t.parallel or t.warm_rig)


@pytest.mark.parametrize("name", TARGETS)
def test_each_target_names_its_device_class(name: str) -> None:
    cls = device_class(name)
    assert issubclass(cls, Device) and cls.target == name
    assert cls.owned == target(name).runs_rig_firmware


def test_no_target_is_a_lookup_error_of_one_line() -> None:
    with pytest.raises(ValueError, match="target must be one of host, qemu-m4f, external, not 'board'"):
        target("board")


def _run_args(tmp_path: Path, *extra: str) -> argparse.Namespace:
    return build().parse_args(["run", "cdrw", "--out", str(tmp_path / "o"), *extra])


@pytest.mark.parametrize("name", TARGETS)
def test_the_timeout_default_is_the_targets(name: str, tmp_path: Path) -> None:
    cfg = common.rig_config(_run_args(tmp_path, "--target", name), tmp_path / "stage")
    assert cfg.timeout == target(name).lockstep_timeout_s
    assert common.rig_config(_run_args(tmp_path, "--target", name, "--timeout", "7"),
                             tmp_path / "stage").timeout == 7.0


def test_the_command_line_offers_the_targets() -> None:
    assert tuple(TARGETS) == TARGET_CHOICES
    up = build().parse_args(["rig", "up", "--target", "qemu-m4f"])
    assert up.target == "qemu-m4f"
    assert target("host").lockstep_timeout_s == lockstep.DEFAULT_TIMEOUT_S
    warm = [n for n, t in TARGETS.items() if t.warm_rig]
    assert warm == ["host", "qemu-m4f"]
    with pytest.raises(UsageError, match="invalid choice: 'external'"):
        build().parse_args(["rig", "up", "--target", "external"])
