"""The reader's Python forms of an ST FOR loop, given back their plain shape so the writer writes FOR.

``st.load`` reads ``FOR i := a TO b BY c DO ... END_FOR`` as a ``range()`` loop with an ``else`` that
leaves ``i`` at the first value past the end, as ST does; when a bound or the step is not a constant,
the range is made first (``_for1 = range(...)``) so the ``else`` can read it. Writing ``FOR`` again gives
ST that value by itself, so the ``else`` and the made range are folded back into the loop.

What makes a range "made for its loop" is the syntax, not its name: a ``range()`` bound to a name that the
function reads only in the loop right after it (as its iterable and in its ``else``).
"""

from __future__ import annotations

import ast
from collections.abc import Mapping

__all__ = ["number", "reader_loops", "same_variable"]


def reader_loops(body: list[ast.stmt], reads: Mapping[str, int]) -> list[ast.stmt]:
    """``body`` with each loop of the reader's forms as a plain ``for T in range(...)`` without ``else``.

    ``reads``: how often the whole function reads each name (a made range read elsewhere stays as it is).
    """
    out: list[ast.stmt] = []
    index = 0
    while index < len(body):
        stmt = body[index]
        following = body[index + 1] if index + 1 < len(body) else None
        made = _made_range(stmt)
        if made is not None and isinstance(following, ast.For) and _only_in(made[0], following, reads):
            loop = _plain(following, made[1], made[0])
            if loop is not None:
                out.append(loop)
                index += 2
                continue
        if isinstance(stmt, ast.For) and _is_range(stmt.iter):
            loop = _plain(stmt, stmt.iter)
            out.append(loop if loop is not None else stmt)
        else:
            out.append(stmt)
        index += 1
    return out


def _made_range(stmt: ast.stmt) -> tuple[str, ast.Call] | None:
    """``(name, call)`` of ``name = range(...)``, a range made before a loop."""
    if isinstance(stmt, ast.Assign) and len(stmt.targets) == 1 and isinstance(stmt.targets[0], ast.Name) and isinstance(stmt.value, ast.Call) and _is_range(stmt.value):
        return stmt.targets[0].id, stmt.value
    return None


def _only_in(name: str, loop: ast.For, reads: Mapping[str, int]) -> bool:
    """Whether ``loop`` iterates over ``name`` and every read of ``name`` in the function is in the loop's
    iterable or its ``else`` (which :func:`_plain` folds away)."""
    if not (isinstance(loop.iter, ast.Name) and loop.iter.id == name):
        return False
    in_loop = sum(isinstance(n, ast.Name) and n.id == name for part in (loop.iter, *loop.orelse) for n in ast.walk(part))
    in_body = any(isinstance(n, ast.Name) and n.id == name for part in loop.body for n in ast.walk(part))
    return not in_body and in_loop == reads.get(name, 0)


def _is_range(node: ast.expr) -> bool:
    return isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "range" and not node.keywords


def same_variable(a: ast.expr, b: ast.expr) -> bool:
    """Whether two names or members (``i``, ``self.nStep``) designate the same variable, whatever their context."""
    if isinstance(a, ast.Name) and isinstance(b, ast.Name):
        return a.id == b.id
    if isinstance(a, ast.Attribute) and isinstance(b, ast.Attribute):
        return a.attr == b.attr and same_variable(a.value, b.value)
    return False


def _plain(loop: ast.For, iterable: ast.expr, made: str | None = None) -> ast.For | None:
    """``loop`` over ``iterable`` with no ``else``, when its ``else`` only sets the loop variable to the first
    value past the end, as FOR leaves it: a constant that is that value for a range of constants, or a value
    computed from the range ``made`` before the loop."""
    if loop.orelse:
        assign = loop.orelse[0]
        if not (len(loop.orelse) == 1 and isinstance(assign, ast.Assign) and len(assign.targets) == 1
                and same_variable(assign.targets[0], loop.target)):
            return None
        if made is not None:
            if not any(isinstance(n, ast.Name) and n.id == made for n in ast.walk(assign.value)):
                return None
        elif _past_end(iterable) is None or _past_end(iterable) != number(assign.value):
            return None
    plain = ast.For(loop.target, iterable, loop.body, [], loop.type_comment)
    return ast.copy_location(plain, loop)


def number(node: ast.expr) -> int | None:
    """The value of an integer written with constants, ``+`` and ``-`` (``0 - 1``, ``-5``); None otherwise."""
    if isinstance(node, ast.Constant) and type(node.value) is int:
        return node.value
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        inner = number(node.operand)
        return None if inner is None else -inner if isinstance(node.op, ast.USub) else inner
    if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Add, ast.Sub)):
        left, right = number(node.left), number(node.right)
        if left is None or right is None:
            return None
        return left + right if isinstance(node.op, ast.Add) else left - right
    return None


def _past_end(call: ast.expr) -> int | None:
    """The first value past the end of a ``range()`` of constants (where FOR leaves its variable), else None."""
    if not isinstance(call, ast.Call) or not 1 <= len(call.args) <= 3:
        return None
    values = [number(a) for a in call.args]
    if None in values or values[-1] == 0 and len(values) == 3:
        return None
    numbers = [v for v in values if v is not None]
    start, stop, step = (0, numbers[0], 1) if len(numbers) == 1 else (*numbers, 1)[:3]
    steps = range(start, stop, step)
    return start + step * len(steps)
