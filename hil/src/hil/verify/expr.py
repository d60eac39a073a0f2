"""Expectations: a small, safe subset of Python expressions over result fields.

    detector.first_flag_step - fault.start_step <= 2
    azkf.alpha.error_integral < kf.alpha.error_integral and overruns == 0
    missile.rms_q < 0.9 * open_loop.rms_q

Allowed: numbers, field names (dotted), + - * /, unary -, comparisons (chained), and/or/not,
abs(x), min(x, y, ...), max(x, y, ...).  Anything else is refused when the suite is loaded,
before a flight: another name or call, a function with the wrong number of arguments, a
division by a constant zero, a number that is not finite, an expression longer than
MAX_CHARS characters, deeper than MAX_DEPTH or of more than MAX_NODES nodes (so that no input
exhausts the parser's memory or Python's recursion).
"""
from __future__ import annotations

import ast
import math
import operator
import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass

from hil.util.errors import HilError

FUNCTIONS: dict[str, Callable[..., float]] = {"abs": abs, "min": min, "max": max}
#: each function's number of arguments: (at least, at most)
ARITY: dict[str, tuple[int, int]] = {"abs": (1, 1), "min": (2, 64), "max": (2, 64)}
#: bounds on an expectation's size: its text, its tree's depth and its number of nodes
MAX_CHARS = 500
MAX_DEPTH = 32
MAX_NODES = 200
_BINARY = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv}
_COMPARE = {ast.Lt: operator.lt, ast.LtE: operator.le, ast.Gt: operator.gt, ast.GtE: operator.ge,
            ast.Eq: operator.eq, ast.NotEq: operator.ne}


class ExpressionError(HilError, ValueError):
    """An expectation that is not in the language."""


@dataclass(frozen=True)
class Expectation:
    text: str
    tree: ast.expr
    fields: frozenset[str]


def dotted(node: ast.expr) -> str | None:
    """`a.b.c` as one field name, or None if node is not a plain dotted name."""
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        head = dotted(node.value)
        return f"{head}.{node.attr}" if head else None
    return None


def _quote(text: str) -> str:
    """text for an error message: quoted, at most 40 characters of it."""
    return repr(text) if len(text) <= 40 else f"{text[:40]!r}..."


def _check_size(text: str, tree: ast.expr) -> None:
    """The tree's depth and node count within bounds (counted without recursion)."""
    nodes = 0
    stack: list[tuple[ast.AST, int]] = [(tree, 1)]
    while stack:
        node, depth = stack.pop()
        nodes += 1
        if depth > MAX_DEPTH:
            raise ExpressionError(f"{_quote(text)}: nested deeper than {MAX_DEPTH} levels")
        if nodes > MAX_NODES:
            raise ExpressionError(f"{_quote(text)}: more than {MAX_NODES} parts")
        stack += [(child, depth + 1) for child in ast.iter_child_nodes(node)]


def _check_number(node: ast.Constant) -> None:
    value = node.value
    if not isinstance(value, (int, float)) or isinstance(value, bool):
        raise ExpressionError(f"not allowed in an expectation: {_quote(ast.unparse(node))}")
    try:
        finite = math.isfinite(float(value))
    except OverflowError:
        finite = False
    if not finite:
        raise ExpressionError(f"{_quote(ast.unparse(node))}: not a finite number")


def _check_call(node: ast.Call) -> None:
    name = node.func.id if isinstance(node.func, ast.Name) else None
    if name not in FUNCTIONS or node.keywords:
        raise ExpressionError(f"not allowed in an expectation: {_quote(ast.unparse(node))}")
    least, most = ARITY[name]
    if not least <= len(node.args) <= most:
        want = f"{least}" if least == most else f"{least} or more"
        raise ExpressionError(f"{_quote(ast.unparse(node))}: {name}() takes {want} argument"
                              f"{'s' if want != '1' else ''}, not {len(node.args)}")


def _check_divisor(node: ast.BinOp, fields: set[str]) -> None:
    """A divisor without fields is known now: zero (or not computable) is refused."""
    if fields:
        return
    try:
        zero = evaluate(node.right, {}) == 0
    except ArithmeticError:
        zero = True
    if zero:
        raise ExpressionError(f"{_quote(ast.unparse(node))}: division by zero")


def _check(node: ast.expr, fields: set[str]) -> None:
    """Every node in the language (fields: the names it reads, collected)."""
    name = dotted(node)
    if name is not None:
        fields.add(name)
    elif isinstance(node, ast.Constant):
        _check_number(node)
    elif isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
        _check(node.left, fields)
        divisor: set[str] = set()
        _check(node.right, divisor)
        if isinstance(node.op, ast.Div):
            _check_divisor(node, divisor)
        fields |= divisor
    elif isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.Not)):
        _check(node.operand, fields)
    elif isinstance(node, ast.BoolOp):
        for v in node.values:
            _check(v, fields)
    elif isinstance(node, ast.Compare) and all(type(op) in _COMPARE for op in node.ops):
        for v in (node.left, *node.comparators):
            _check(v, fields)
    elif isinstance(node, ast.Call):
        _check_call(node)
        for a in node.args:
            _check(a, fields)
    else:
        raise ExpressionError(f"not allowed in an expectation: {_quote(ast.unparse(node))}")


def parse(text: str) -> Expectation:
    """The expectation of text, checked (ExpressionError: one line)."""
    text = text.strip()
    if len(text) > MAX_CHARS:
        raise ExpressionError(f"{_quote(text)}: {len(text)} characters, an expectation has at most "
                              f"{MAX_CHARS}")
    try:
        with warnings.catch_warnings():   # ("1and x": a SyntaxWarning would be a second line)
            warnings.simplefilter("ignore")
            tree = ast.parse(text, mode="eval").body
    except SyntaxError as e:
        raise ExpressionError(f"{_quote(text)}: {e.msg}") from None
    except (ValueError, MemoryError, RecursionError) as e:   # (a NUL byte; nesting the parser refuses)
        raise ExpressionError(f"{_quote(text)}: {str(e) or type(e).__name__}") from None
    _check_size(text, tree)
    fields: set[str] = set()
    _check(tree, fields)
    return Expectation(text, tree, frozenset(fields))


def evaluate(node: ast.expr, values: Mapping[str, float]) -> float | bool:
    name = dotted(node)
    if name is not None:
        return values[name]
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)):  # all _check admits
        return node.value
    if isinstance(node, ast.BinOp):
        left, right = evaluate(node.left, values), evaluate(node.right, values)
        if isinstance(node.op, ast.Div) and right == 0:
            raise ZeroDivisionError(f"{ast.unparse(node)}: division by zero "
                                    f"({ast.unparse(node.right)} = 0)")
        return _BINARY[type(node.op)](left, right)
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
            parts.append(f"{text} = {_fmt(v)}" if dotted(side) or not isinstance(side, ast.Constant) else text)
        return "; ".join(p for p in parts if "=" in p) or exp.text
    return "; ".join(f"{f} = {_fmt(values[f])}" for f in sorted(exp.fields))


def _fmt(v: float | bool) -> str:
    if isinstance(v, bool):
        return str(v).lower()
    if isinstance(v, int):
        return str(v)
    return f"{v:.6g}"
