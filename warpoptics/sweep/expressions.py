"""The per-job expression evaluator of sweeps: a small interpreter over Python's ``ast``.

Expressions (``[expr]`` values, ``view.expr``) are Python syntax restricted to numbers, strings,
booleans, lists, dicts, arithmetic, comparisons, ``a if c else b``, subscripts and the functions
of :data:`FUNCTIONS` with the constants of :data:`CONSTANTS`.  Anything else (attributes, calls of
other names, comprehensions, lambdas, slices, keyword arguments) is refused with an
:class:`~warpoptics.errors.InputError` naming the field and the expression.

Why not a library (PyPI's ``simpleeval`` 1.0.8 and ``asteval`` 1.0 were
evaluated):

- ``asteval`` is a whole interpreter (statements, loops, function definitions, NumPy) - far more
  surface than a sweep needs, which is the opposite of what a restricted evaluator is for.
- ``simpleeval`` is the closest fit but not safe against hostile expressions: its power
  guard only bounds the operands (``MAX_POWER = 4e6``), so ``3999999**3999999`` (a 26-million-digit
  integer) still runs for minutes, and ``round(5, -10**9)`` hangs (CPython computes
  ``10**10**9``); its errors would need wrapping into ``InputError`` with field, expression and
  the did-you-mean hint anyway, and TOML lists/tables need list and dict literals.
- What the sweep needs is 120 lines: a tree walk over nine node types with explicit resource
  bounds, which this module is.

Resource bounds (each refused before the work is done, so refusals take microseconds): the
expression's length (:data:`MAX_LENGTH`), its nesting depth (:data:`MAX_DEPTH`, checked without
recursion before evaluating), the size of every string, list or table built (:data:`MAX_ITEMS`
elements, counting nested ones), integers beyond :data:`MAX_INT_BITS` bits (``9**9**9``), string
formatting with ``%`` (``"%0999999999d" % 1``) and ``round`` to more than :data:`MAX_ROUND_DIGITS`
digits.
"""

from __future__ import annotations

import ast
import difflib
import math
from collections.abc import Callable
from typing import Any

from ..errors import InputError

__all__ = [
    "evaluate_expression",
    "FUNCTIONS",
    "CONSTANTS",
    "MAX_LENGTH",
    "MAX_DEPTH",
    "MAX_ITEMS",
    "MAX_INT_BITS",
    "MAX_ROUND_DIGITS",
]

FUNCTIONS: dict[str, Callable] = {
    "abs": abs,
    "min": min,
    "max": max,
    "round": round,
    "float": float,
    "int": int,
    "bool": bool,
    "sqrt": math.sqrt,
    "exp": math.exp,
    "log": math.log,
    "log10": math.log10,
    "sin": math.sin,
    "cos": math.cos,
    "tan": math.tan,
    "asin": math.asin,
    "acos": math.acos,
    "atan": math.atan,
    "atan2": math.atan2,
    "radians": math.radians,
    "degrees": math.degrees,
}
CONSTANTS = {"pi": math.pi, "e": math.e, "true": True, "false": False}

# Bounds far above any scene value (a camera position, a list of band tables) and far below what
# takes noticeable time or memory.
MAX_LENGTH = 2000  # characters of one expression
MAX_DEPTH = 64  # levels of the syntax tree (a sum of 60 terms is 60 levels)
MAX_ITEMS = 100_000  # characters of a string / elements of a list or table, nested ones counted
MAX_INT_BITS = 4096  # an integer beyond float range (2**1024) is never a scene value
MAX_ROUND_DIGITS = 400  # round(x, n): |n| beyond float precision means nothing, 10**|n| is costly

_CMPOPS = {
    ast.Eq: lambda a, b: a == b,
    ast.NotEq: lambda a, b: a != b,
    ast.Lt: lambda a, b: a < b,
    ast.LtE: lambda a, b: a <= b,
    ast.Gt: lambda a, b: a > b,
    ast.GtE: lambda a, b: a >= b,
}


class _TooLarge(Exception):
    """A bound of the module docstring was hit (the message says which)."""


def _is_int(v) -> bool:
    return isinstance(v, int)  # bool is an int too: True * [0] is a repetition


def _size(v, budget: int = MAX_ITEMS) -> int:
    """Elements in ``v`` (characters of a string, 1 for a number, nested containers summed),
    counting at most ``budget + 1`` so that the cost stays bounded by the budget."""
    if isinstance(v, str):
        return len(v)
    if isinstance(v, (list, tuple)):
        n = 1
        for x in v:
            n += _size(x, budget - n)
            if n > budget:
                break
        return n
    if isinstance(v, dict):
        n = 1
        for k, x in v.items():
            n += _size(k, budget - n) + _size(x, budget - n)
            if n > budget:
                break
        return n
    return 1


def _check_size(v):
    if isinstance(v, (str, list, tuple, dict)) and _size(v) > MAX_ITEMS:
        raise _TooLarge(f"the result would have more than {MAX_ITEMS} elements")
    if _is_int(v) and v.bit_length() > MAX_INT_BITS:
        raise _TooLarge(f"integers are limited to {MAX_INT_BITS} bits")
    return v


def _mult(a, b):
    if isinstance(a, (str, list)) and _is_int(b):
        a, b = b, a
    if _is_int(a) and isinstance(b, (str, list)):
        # the repeated list's size: its elements a times, plus the list itself (as _size counts)
        size = len(b) * a if isinstance(b, str) else (_size(b) - 1) * a + 1
        if a > 0 and size > MAX_ITEMS:
            raise _TooLarge(f"the result would have more than {MAX_ITEMS} elements")
        return a * b
    if _is_int(a) and _is_int(b) and a.bit_length() + b.bit_length() > MAX_INT_BITS + 1:
        raise _TooLarge(f"integers are limited to {MAX_INT_BITS} bits")
    return a * b


def _add(a, b):
    if isinstance(a, (str, list)) and isinstance(b, (str, list)):
        size = len(a) + len(b) if isinstance(a, str) else _size(a) + _size(b) - 1  # one list, not two
        if size > MAX_ITEMS:
            raise _TooLarge(f"the result would have more than {MAX_ITEMS} elements")
    return a + b


def _pow(a, b):
    # an integer power's result has about b * log2|a| bits: refuse it before computing it
    if _is_int(a) and _is_int(b) and b > 0 and abs(a) > 1 and b * (abs(a).bit_length() - 1) > MAX_INT_BITS:
        raise _TooLarge(f"integers are limited to {MAX_INT_BITS} bits")
    return a**b


def _mod(a, b):
    if isinstance(a, str):
        raise _TooLarge("string formatting with % is not supported")
    return a % b


def _round(*args):
    if len(args) == 2 and _is_int(args[1]) and abs(args[1]) > MAX_ROUND_DIGITS:
        raise _TooLarge(f"round() takes at most {MAX_ROUND_DIGITS} digits")
    return round(*args)


_BINOPS = {
    ast.Add: _add,
    ast.Sub: lambda a, b: a - b,
    ast.Mult: _mult,
    ast.Div: lambda a, b: a / b,
    ast.FloorDiv: lambda a, b: a // b,
    ast.Mod: _mod,
    ast.Pow: _pow,
}
_GUARDED_FUNCTIONS = {**FUNCTIONS, "round": _round}


def _depth(tree: ast.AST) -> int:
    """Depth of the syntax tree, walked with an explicit stack (no recursion to overflow)."""
    deepest, stack = 0, [(tree, 1)]
    while stack:
        node, d = stack.pop()
        deepest = max(deepest, d)
        if deepest > MAX_DEPTH:
            break
        stack.extend((child, d + 1) for child in ast.iter_child_nodes(node))
    return deepest


def evaluate_expression(
    text: str, variables: dict[str, Any], *, file: str | None = None, field_name: str | None = None
) -> Any:
    """Evaluate a sweep expression (restricted Python syntax, see the module docstring).

    ``variables``: name -> value (axis values, earlier ``[expr]`` variables).  Errors, including
    the resource bounds, are an :class:`~warpoptics.errors.InputError` naming ``file``,
    ``field_name`` and the expression.
    """
    shown = text if len(text) <= 200 else text[:200] + "..."

    def fail(msg: str):
        raise InputError(msg, file=file, field=field_name, value=shown)

    if len(text) > MAX_LENGTH:
        fail(f"an expression is limited to {MAX_LENGTH} characters (this one has {len(text)})")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as exc:
        fail(f"not a valid expression ({exc.msg})")
    except (MemoryError, RecursionError):  # CPython's parser gives up on very deep nesting
        fail(f"nested too deeply (at most {MAX_DEPTH} levels)")
    if _depth(tree) > MAX_DEPTH:
        fail(f"nested too deeply (at most {MAX_DEPTH} levels)")

    def ev(node):
        if isinstance(node, ast.Expression):
            return ev(node.body)
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float, str, bool)):
            return node.value
        if isinstance(node, ast.Name):
            if node.id in variables:
                return variables[node.id]
            if node.id in CONSTANTS:
                return CONSTANTS[node.id]
            hint = difflib.get_close_matches(node.id, list(variables) + list(CONSTANTS), n=1)
            fail(
                f"unknown name {node.id!r}"
                + (f"; did you mean {hint[0]!r}?" if hint else "")
                + f" (variables: {', '.join(variables) or 'none'})"
            )
        if isinstance(node, ast.BinOp) and type(node.op) in _BINOPS:
            return _BINOPS[type(node.op)](ev(node.left), ev(node.right))
        if isinstance(node, ast.UnaryOp):
            v = ev(node.operand)
            if isinstance(node.op, ast.USub):
                return -v
            if isinstance(node.op, ast.UAdd):
                return +v
            if isinstance(node.op, ast.Not):
                return not v
        if isinstance(node, ast.BoolOp):
            vals = [ev(v) for v in node.values]
            return all(vals) if isinstance(node.op, ast.And) else any(vals)
        if isinstance(node, ast.Compare):
            left = ev(node.left)
            for op, right_node in zip(node.ops, node.comparators, strict=True):
                if type(op) not in _CMPOPS:
                    fail("unsupported comparison")
                right = ev(right_node)
                if not _CMPOPS[type(op)](left, right):
                    return False
                left = right
            return True
        if isinstance(node, ast.IfExp):
            return ev(node.body) if ev(node.test) else ev(node.orelse)
        if isinstance(node, (ast.List, ast.Tuple)):
            return _check_size([ev(v) for v in node.elts])
        if isinstance(node, ast.Dict):
            if any(k is None for k in node.keys):
                fail("** in a table is not supported")
            return _check_size({ev(k): ev(v) for k, v in zip(node.keys, node.values, strict=True)})
        if isinstance(node, ast.Subscript):
            return ev(node.value)[ev(node.slice)]
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and not node.keywords:
            fn = _GUARDED_FUNCTIONS.get(node.func.id)
            if fn is None:
                fail(f"unknown function {node.func.id!r} (allowed: {', '.join(FUNCTIONS)})")
            return fn(*[ev(a) for a in node.args])
        fail(f"unsupported syntax: {type(node).__name__}")

    try:
        return ev(tree)
    except InputError:
        raise
    except _TooLarge as exc:
        fail(f"too large to evaluate: {exc}")
    except (ArithmeticError, TypeError, ValueError, IndexError, KeyError) as exc:
        fail(f"cannot evaluate ({type(exc).__name__}: {exc})")
