"""Expectations: a small, safe subset of Python expressions over result fields.

    detector.first_flag_step - fault.start_step <= 2
    azkf.alpha.error_integral < kf.alpha.error_integral and overruns == 0
    missile.rms_q < 0.9 * open_loop.rms_q

Allowed: numbers, field names (dotted), + - * /, unary -, comparisons (chained), and/or/not,
abs/min/max.  Anything else is refused when the suite is loaded, before a flight.
"""
from __future__ import annotations

import ast
import operator
from collections.abc import Callable, Mapping
from dataclasses import dataclass

FUNCTIONS: dict[str, Callable[..., float]] = {"abs": abs, "min": min, "max": max}
_BINARY = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv}
_COMPARE = {ast.Lt: operator.lt, ast.LtE: operator.le, ast.Gt: operator.gt, ast.GtE: operator.ge,
            ast.Eq: operator.eq, ast.NotEq: operator.ne}


class ExpressionError(ValueError):
    """An expectation that is not in the language."""


@dataclass(frozen=True)
class Expectation:
    text: str
    tree: ast.expr
    fields: frozenset[str]


def _dotted(node: ast.expr) -> str | None:
    """`a.b.c` as one field name, or None if node is not a plain dotted name."""
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        head = _dotted(node.value)
        return f"{head}.{node.attr}" if head else None
    return None


def _check(node: ast.expr, fields: set[str]) -> None:
    name = _dotted(node)
    if name is not None:
        fields.add(name)
    elif isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) \
            and not isinstance(node.value, bool):
        pass
    elif isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
        _check(node.left, fields)
        _check(node.right, fields)
    elif isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.Not)):
        _check(node.operand, fields)
    elif isinstance(node, ast.BoolOp):
        for v in node.values:
            _check(v, fields)
    elif isinstance(node, ast.Compare) and all(type(op) in _COMPARE for op in node.ops):
        for v in (node.left, *node.comparators):
            _check(v, fields)
    elif isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in FUNCTIONS \
            and node.args and not node.keywords:
        for a in node.args:
            _check(a, fields)
    else:
        raise ExpressionError(f"not allowed in an expectation: {ast.unparse(node)!r}")


def parse(text: str) -> Expectation:
    try:
        tree = ast.parse(text.strip(), mode="eval").body
    except SyntaxError as e:
        raise ExpressionError(f"{text!r}: {e.msg}") from None
    fields: set[str] = set()
    _check(tree, fields)
    return Expectation(text.strip(), tree, frozenset(fields))


def evaluate(node: ast.expr, values: Mapping[str, float]) -> float | bool:
    name = _dotted(node)
    if name is not None:
        return values[name]
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)):  # all _check admits
        return node.value
    if isinstance(node, ast.BinOp):
        return _BINARY[type(node.op)](evaluate(node.left, values), evaluate(node.right, values))
    if isinstance(node, ast.UnaryOp):
        v = evaluate(node.operand, values)
        return not v if isinstance(node.op, ast.Not) else -v
    if isinstance(node, ast.BoolOp):
        vals = [bool(evaluate(v, values)) for v in node.values]
        return all(vals) if isinstance(node.op, ast.And) else any(vals)
    if isinstance(node, ast.Compare):
        left = evaluate(node.left, values)
        for op, right_node in zip(node.ops, node.comparators):
            right = evaluate(right_node, values)
            if not _COMPARE[type(op)](left, right):
                return False
            left = right
        return True
    assert isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
    return FUNCTIONS[node.func.id](*(evaluate(a, values) for a in node.args))


def measured(exp: Expectation, values: Mapping[str, float]) -> str:
    """What was measured, for the report: each side of a comparison, else the fields."""
    tree = exp.tree
    if isinstance(tree, ast.Compare):
        sides = [tree.left, *tree.comparators]
        parts = []
        for side in sides:
            v = evaluate(side, values)
            text = ast.unparse(side)
            parts.append(f"{text} = {_fmt(v)}" if _dotted(side) or not isinstance(side, ast.Constant) else text)
        return "; ".join(p for p in parts if "=" in p) or exp.text
    return "; ".join(f"{f} = {_fmt(values[f])}" for f in sorted(exp.fields))


def _fmt(v: float | bool) -> str:
    if isinstance(v, bool):
        return str(v).lower()
    if isinstance(v, int):
        return str(v)
    return f"{v:.6g}"
