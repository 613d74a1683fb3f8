"""The reader's Python forms of an ST FOR loop, given back their plain shape so the writer writes FOR.

``st.load`` reads ``FOR i := a TO b BY c DO ... END_FOR`` as a ``range()`` loop with an ``else`` that
leaves ``i`` at the first value past the end, as ST does; when a bound or the step is not a constant,
the range is made first (``_for1 = range(...)``) so the ``else`` can read it. Writing ``FOR`` again gives
ST that value by itself, so the ``else`` and the made range are folded back into the loop.
"""

from __future__ import annotations

import ast

__all__ = ["reader_loops"]


def reader_loops(body: list[ast.stmt]) -> list[ast.stmt]:
    """``body`` with each loop of the reader's forms as a plain ``for T in range(...)`` without ``else``."""
    out: list[ast.stmt] = []
    index = 0
    while index < len(body):
        stmt = body[index]
        following = body[index + 1] if index + 1 < len(body) else None
        made = _made_range(stmt)
        if made is not None and isinstance(following, ast.For) and isinstance(following.iter, ast.Name) and following.iter.id == made[0]:
            loop = _plain(following, made[1])
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
    """``(name, call)`` of ``_forN = range(...)``, the reader's range made before its loop."""
    if (
        isinstance(stmt, ast.Assign)
        and len(stmt.targets) == 1
        and isinstance(stmt.targets[0], ast.Name)
        and stmt.targets[0].id.startswith("_for")
        and _is_range(stmt.value)
    ):
        return stmt.targets[0].id, stmt.value  # type: ignore[return-value]
    return None


def _is_range(node: ast.expr) -> bool:
    return isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "range" and not node.keywords


def _plain(loop: ast.For, iterable: ast.expr) -> ast.For | None:
    """``loop`` over ``iterable`` with no ``else``, when its ``else`` only sets the loop variable."""
    if loop.orelse:
        assign = loop.orelse[0]
        if not (
            len(loop.orelse) == 1
            and isinstance(assign, ast.Assign)
            and len(assign.targets) == 1
            and ast.dump(assign.targets[0]).replace("Store", "Load") == ast.dump(loop.target).replace("Store", "Load")
        ):
            return None
    plain = ast.For(loop.target, iterable, loop.body, [], loop.type_comment)
    return ast.copy_location(plain, loop)
