"""The class of a value the body's code computes, when the code alone says it (``value_class``).

A store written out by the call builder (``iecoop._inline``) leaves out the
class check a value is sure to pass: a constant, a read of a variable whose
ctypes field gives one class, arithmetic and comparisons over those.
"""

from __future__ import annotations

import ast

__all__ = ["COUNTER", "value_class"]

#: The prefix of the local a FOR over a block's variable counts in (``_inline._CounterReads``): range's ints.
COUNTER = "_iec_c_"

_INTEGER_OPS = (ast.Add, ast.Sub, ast.Mult, ast.FloorDiv, ast.Mod, ast.LShift, ast.RShift)
_BIT_OPS = (ast.BitAnd, ast.BitOr, ast.BitXor)
_REAL_OPS = (ast.Add, ast.Sub, ast.Mult, ast.Div, ast.FloorDiv, ast.Mod)


def value_class(node: ast.expr, known: dict[str, type]) -> type | None:
    """The exact class of the value ``node`` gives, when the code alone says it (else None).

    ``known``: per variable read (``"x"`` for ``self.x``, ``"timer.Q"`` for
    ``self.timer.Q``), the class its ctypes field gives (``bool``, ``int``,
    ``float``). Constants, and arithmetic, comparisons and ``not`` over those,
    follow Python's own rules for these three classes.
    """
    if isinstance(node, ast.Constant):
        return type(node.value) if type(node.value) in (bool, int, float) else None
    if isinstance(node, ast.Name):
        return int if node.id.startswith(COUNTER) else None  # a FOR counter's local holds range's ints
    if isinstance(node, ast.Attribute):
        path = _read_path(node)
        return known.get(path) if path is not None else None
    if isinstance(node, ast.Compare):
        operands = [node.left, *node.comparators]
        return bool if all(value_class(o, known) in (bool, int, float) for o in operands) else None
    if isinstance(node, ast.BoolOp):
        classes = {value_class(v, known) for v in node.values}
        return classes.pop() if len(classes) == 1 else None
    if isinstance(node, ast.IfExp):
        body, orelse = value_class(node.body, known), value_class(node.orelse, known)
        return body if body is orelse else None
    if isinstance(node, ast.UnaryOp):
        return _unary_class(node, known)
    if isinstance(node, ast.BinOp):
        return _binary_class(node, value_class(node.left, known), value_class(node.right, known))
    return None


def _unary_class(node: ast.UnaryOp, known: dict[str, type]) -> type | None:
    if isinstance(node.op, ast.Not):
        return bool
    operand = value_class(node.operand, known)
    if operand is float and not isinstance(node.op, ast.Invert):
        return float
    return int if operand in (bool, int) else None


def _binary_class(node: ast.BinOp, left: type | None, right: type | None) -> type | None:
    integers = (bool, int)
    if left in integers and right in integers:
        if isinstance(node.op, _BIT_OPS):
            return bool if left is right is bool else int
        if isinstance(node.op, _INTEGER_OPS):
            return int
        return float if isinstance(node.op, ast.Div) else None
    if float in (left, right) and {left, right} <= {bool, int, float} and isinstance(node.op, _REAL_OPS):
        return float
    return None


def _read_path(node: ast.Attribute) -> str | None:
    """``self.x`` -> ``"x"``, ``self.timer.Q`` -> ``"timer.Q"`` (a read), else None."""
    if not isinstance(node.ctx, ast.Load):
        return None
    if isinstance(node.value, ast.Name) and node.value.id == "self":
        return node.attr
    inner = node.value
    if isinstance(inner, ast.Attribute) and isinstance(inner.value, ast.Name) and inner.value.id == "self":
        return f"{inner.attr}.{node.attr}"
    return None
