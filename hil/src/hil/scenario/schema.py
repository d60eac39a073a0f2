"""Build frozen dataclasses from TOML tables (or parsed command-line fields), with ONE clear
error message that names where the problem is (file, section or fault), the field and why.

Field constraints ride in dataclass field metadata, written with ``spec()``:
    x: float = spec(1.0, gt=0.0)            # > 0
    n: int = spec(8, ge=8)                  # >= 8
    kind: str = spec("uniform", choices=("uniform", "triangular"))
    apps: tuple[str, ...] = spec(choices=("cdrw", "missile"))   # an array, each item checked
    duration: float = spec(gt=0.0, allow_inf=True)   # required, may be inf
"""
from __future__ import annotations

import dataclasses
import math
import tomllib
import types
import typing
from collections.abc import Mapping, Sequence
from typing import Any

from hil.util.errors import InputError

MISSING = dataclasses.MISSING


class ScenarioError(InputError, ValueError):
    """A scenario file, section, fault or command-line fault is invalid (message = one line)."""


def parse_toml(text: str, where: str) -> dict[str, Any]:
    """The TOML document of text; ScenarioError naming `where` when it is not one (tomllib
    recurses: a document nested deeper than Python's recursion limit is refused too)."""
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise ScenarioError(f"{where}: not valid TOML: {e}") from None
    except RecursionError:
        raise ScenarioError(f"{where}: not valid TOML: nested too deeply") from None


def spec(default: Any = MISSING, *, gt: float | None = None, ge: float | None = None,
         le: float | None = None, lt: float | None = None,
         choices: tuple[Any, ...] | None = None, allow_inf: bool = False,
         default_factory: Any = MISSING) -> Any:
    """A dataclass field with validation metadata (see module docstring)."""
    meta = {"gt": gt, "ge": ge, "le": le, "lt": lt, "choices": choices, "allow_inf": allow_inf}
    if default_factory is not MISSING:
        return dataclasses.field(default_factory=default_factory, metadata=meta)
    return dataclasses.field(default=default, metadata=meta)


def _type_name(v: Any) -> str:
    if isinstance(v, bool):
        return "boolean"
    if isinstance(v, int):
        return "integer"
    if isinstance(v, float):
        return "number"
    if isinstance(v, str):
        return "string"
    if isinstance(v, (list, tuple)):
        return "array"
    if isinstance(v, Mapping):
        return "table"
    return type(v).__name__


def _show(v: Any) -> str:
    return f"{_type_name(v)} {v!r}" if not isinstance(v, Mapping) else "a table"


def _coerce(value: Any, hint: Any, meta: Mapping[str, Any], where: str) -> Any:
    """Check/convert one value against a type hint; raises ScenarioError."""
    origin = typing.get_origin(hint)
    if origin in (typing.Union, types.UnionType):
        members = [h for h in typing.get_args(hint) if h is not type(None)]
        matching: ScenarioError | None = None
        for h in members:
            try:
                return _coerce(value, h, meta, where)
            except ScenarioError as e:
                if _same_family(value, h):
                    matching = e  # the right type, a wrong value: report that
        if matching is not None:
            raise matching
        names = " or ".join(_hint_name(h) for h in members)
        raise ScenarioError(f"{where}: expected {names}, got {_show(value)}")
    if origin is tuple and typing.get_args(hint)[1:] == (Ellipsis,):   # tuple[X, ...]: any length
        if not isinstance(value, (list, tuple)):
            raise ScenarioError(f"{where}: expected an array, got {_show(value)}")
        item = typing.get_args(hint)[0]
        return tuple(_coerce(v, item, meta, f"{where}[{i}]") for i, v in enumerate(value))
    if origin is tuple:
        args = typing.get_args(hint)
        if not isinstance(value, (list, tuple)):
            raise ScenarioError(f"{where}: expected an array of {len(args)}, got {_show(value)}")
        if len(value) != len(args):
            raise ScenarioError(f"{where}: expected an array of {len(args)} values, got {len(value)}")
        return tuple(_coerce(v, h, meta, f"{where}[{i}]") for i, (v, h) in enumerate(zip(value, args)))
    if isinstance(hint, type) and dataclasses.is_dataclass(hint):
        if not isinstance(value, Mapping):
            raise ScenarioError(f"{where}: expected a table, got {_show(value)}")
        return build(hint, value, where)
    if hint is bool:
        if not isinstance(value, bool):
            raise ScenarioError(f"{where}: expected true or false, got {_show(value)}")
        return value
    if hint is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise ScenarioError(f"{where}: expected an integer, got {_show(value)}")
        _check_range(value, meta, where)
        return value
    if hint is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ScenarioError(f"{where}: expected a number, got {_show(value)}")
        x = float(value)
        if math.isnan(x) or (math.isinf(x) and not meta.get("allow_inf")):
            raise ScenarioError(f"{where}: must be a finite number, got {x}")
        _check_range(x, meta, where)
        return x
    if hint is str:
        if not isinstance(value, str):
            raise ScenarioError(f"{where}: expected a string, got {_show(value)}")
        choices = meta.get("choices")
        if choices and value not in choices:
            raise ScenarioError(f"{where}: must be one of {', '.join(map(str, choices))}, got {value!r}")
        return value
    raise TypeError(f"schema: unsupported field type {hint!r}")  # programming error


def _same_family(value: Any, hint: Any) -> bool:
    if isinstance(value, bool):
        return hint is bool
    if isinstance(value, (int, float)):
        return hint in (int, float)
    return isinstance(hint, type) and isinstance(value, hint)


def _hint_name(h: Any) -> str:
    return {float: "a number", int: "an integer", str: "a string", bool: "true or false"}.get(
        h, getattr(h, "__name__", str(h)))


def _check_range(x: float, meta: Mapping[str, Any], where: str) -> None:
    gt, ge, le, lt = meta.get("gt"), meta.get("ge"), meta.get("le"), meta.get("lt")
    if gt is not None and not x > gt:
        raise ScenarioError(f"{where}: must be > {gt}, got {x}")
    if ge is not None and not x >= ge:
        raise ScenarioError(f"{where}: must be >= {ge}, got {x}")
    if le is not None and not x <= le:
        raise ScenarioError(f"{where}: must be <= {le}, got {x}")
    if lt is not None and not x < lt:
        raise ScenarioError(f"{where}: must be < {lt}, got {x}")


def field_names(cls: type) -> tuple[str, ...]:
    return tuple(f.name for f in dataclasses.fields(cls) if f.init)


def check_keys(table: Mapping[str, Any], allowed: Sequence[str], where: str) -> None:
    """ScenarioError naming the first key of table that is not allowed."""
    for key in table:
        if key not in allowed:
            raise ScenarioError(f"{where}: unknown field {key!r} (allowed: {', '.join(allowed)})")


def build(cls: type, table: Mapping[str, Any], where: str, *, skip: tuple[str, ...] = ()) -> Any:
    """cls(**table) after checking every key and value; errors name ``where`` and the field."""
    hints = typing.get_type_hints(cls)
    fields = {f.name: f for f in dataclasses.fields(cls) if f.init}
    allowed = [n for n in fields if n not in skip]
    check_keys(table, allowed, where)
    kwargs = {}
    for name in allowed:
        fld = fields[name]
        if name in table:
            kwargs[name] = _coerce(table[name], hints[name], fld.metadata,
                                   f"{where}: field {name!r}")
        elif fld.default is MISSING and fld.default_factory is MISSING:
            raise ScenarioError(f"{where}: missing field {name!r}")
    try:
        return cls(**kwargs)
    except ValueError as e:  # cross-field checks in __post_init__
        if isinstance(e, ScenarioError):
            raise
        raise ScenarioError(f"{where}: {e}") from None


def replace_fields(obj: Any, table: Mapping[str, Any], where: str) -> Any:
    """dataclasses.replace(obj, **table) with the same checks (for parameter overrides)."""
    hints = typing.get_type_hints(type(obj))
    fields = {f.name: f for f in dataclasses.fields(obj) if f.init}
    check_keys(table, list(fields), where)
    changes = {}
    for key, value in table.items():
        changes[key] = _coerce(value, hints[key], fields[key].metadata, f"{where}: field {key!r}")
    try:
        return dataclasses.replace(obj, **changes)
    except ValueError as e:
        raise ScenarioError(f"{where}: {e}") from None
