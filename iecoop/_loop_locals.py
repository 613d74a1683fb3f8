"""Fast mode: a loop of a block's own code that calls nothing keeps the block's variables in locals.

In fast mode a read of ``self.x`` is a ctypes field read and ``self.x = v`` a
ctypes store, each many times the cost of a local's. A loop whose statements
call nothing, and read and write only local names and the block's own
elementary variables, lets no other code of the program run between two of
its passes (a client reading from another thread sees the value from before
the loop, as a PLC's client sees what its compiled code has stored so far).
So, as a compiler keeps a variable in a register through a loop, the loop
reads each such variable once before it starts, works on a local, and stores
what it wrote when it ends, by whatever way it ends (``finally``)::

    _iec_w_l_f_x = self.x
    try:
        for _ in range(n):
            _iec_w_l_value = _iec_w_l_f_x + 1
            _iec_w_l_f_x = (_iec_w_l_value if _iec_w_l_value.__class__ is _iec_w_l_int
                            and -32768 <= _iec_w_l_value <= 32767 else _iec_w_l_t_x(_iec_w_l_value).value)
    finally:
        self.x = _iec_w_l_f_x

Each store to the local takes the value the field would hold after the store:
an ``int`` within the type's range (a ``bool`` for BOOL, a ``float`` for
LREAL) as it is, anything else through the variable's ctypes type, which
wraps, converts and refuses as the field's store does, with the same error.
REAL is left in its field (its every store rounds). Checked mode, the
default, keeps every read and write where the code has it: a debugger stopped
in the loop sees the block's memory as the code left it.
"""

from __future__ import annotations

import ast
import ctypes
from typing import TYPE_CHECKING, Any

from iecoop._inline_reads import PLAIN_NODES, inner_statements, located, python_global, self_field

if TYPE_CHECKING:
    from iecoop.memory.layout import FieldRecord

__all__ = ["LoopLocals", "loop_types"]

_PREFIX = "_iec_w_l_"
_VALUE = f"{_PREFIX}value"
_INT, _FLOAT = f"{_PREFIX}int", f"{_PREFIX}float"
_INTEGERS = (
    ctypes.c_int8, ctypes.c_uint8, ctypes.c_int16, ctypes.c_uint16, ctypes.c_int32, ctypes.c_uint32,
    ctypes.c_int64, ctypes.c_uint64,
)
#: The nodes of an expression that runs no code of its own: constants, names and operators over the values read.
_VALUE_NODES = (*PLAIN_NODES, ast.Name)
_KEPT = (*_INTEGERS, ctypes.c_bool, ctypes.c_double)


def loop_types(plain: list[FieldRecord]) -> dict[str, Any]:
    """Of the elementary variables read from their ctypes fields (``writes.raw_elementary``), those a loop may
    keep in a local, with their ctypes types."""
    return {r.name: r.info.ctype for r in plain if r.info.ctype in _KEPT}


class LoopLocals:
    """Rewrites, in place, each loop of a list of statements that calls nothing (see the module's text).

    ``fields``: per variable a loop may keep, its ctypes type (``loop_types``);
    the rewritten code reads the objects added to ``names``.
    """

    def __init__(self, fields: dict[str, Any], module_globals: dict[str, Any], local: set[str],
                 names: dict[str, Any]) -> None:
        self.fields, self.globals, self.local, self.names = fields, module_globals, local, names

    def rewrite(self, statements: list[ast.stmt]) -> bool:
        """Rewrite the loops of ``statements`` at any depth (an outer loop that calls nothing as a whole);
        whether any variable is now kept in a local."""
        changed = False
        index = 0
        while index < len(statements):
            statement = statements[index]
            if isinstance(statement, (ast.For, ast.While)) and (used := self._used(statement)):
                kept = self._kept(statement, used)
                statements[index:index + 1] = kept
                index += len(kept)
                changed = True
                continue
            index += 1
            for inner in inner_statements(statement):
                changed = self.rewrite(inner) or changed
        return changed

    def finds(self, statements: list[ast.stmt]) -> bool:
        """Whether ``rewrite`` would keep a variable of a loop of ``statements`` in a local (nothing changed)."""
        return any(
            isinstance(statement, (ast.For, ast.While)) and self._used(statement)
            or any(self.finds(inner) for inner in inner_statements(statement))
            for statement in statements
        )

    # -- which loops, which variables ------------------------------------------

    def _used(self, loop: ast.For | ast.While) -> dict[str, bool] | None:
        """Per variable the loop reads or writes, whether it writes it; None when the loop may run code."""
        used: dict[str, bool] = {}
        return used if self._statement(loop, used) else None

    def _statement(self, node: ast.stmt, used: dict[str, bool]) -> bool:
        if isinstance(node, ast.For):
            return (
                not node.orelse and self._target(node.target, used) and self._range(node.iter, used)
                and all(self._statement(s, used) for s in node.body)
            )
        if isinstance(node, ast.While):
            return not node.orelse and self._value(node.test, used) and all(self._statement(s, used) for s in node.body)
        if isinstance(node, ast.If):
            return self._value(node.test, used) and all(self._statement(s, used) for s in (*node.body, *node.orelse))
        if isinstance(node, ast.Assign):
            return self._value(node.value, used) and all(self._target(t, used) for t in node.targets)
        if isinstance(node, ast.AugAssign):
            # `self.x += v` reads x first, as it does
            return self._value(node.target, used) and self._value(node.value, used) and self._target(node.target, used)
        if isinstance(node, ast.Return):
            return node.value is None or self._value(node.value, used)
        if isinstance(node, ast.Expr):  # a docstring or a bare constant
            return isinstance(node.value, ast.Constant)
        return isinstance(node, (ast.Break, ast.Continue, ast.Pass))

    def _target(self, node: ast.expr, used: dict[str, bool]) -> bool:
        if isinstance(node, ast.Name):
            return node.id != "self"
        field = self_field(node)
        if field is None or field not in self.fields:
            return False
        used[field] = True
        return True

    def _value(self, node: ast.expr, used: dict[str, bool]) -> bool:
        """Whether ``node`` reads only constants, local names and kept variables, through operators."""
        todo: list[ast.AST] = [node]
        while todo:
            n = todo.pop()
            if isinstance(n, ast.Attribute):
                field = self_field(n)
                if field is None or field not in self.fields:
                    return False
                used.setdefault(field, False)
                continue
            if isinstance(n, ast.Name) and n.id == "self" or not isinstance(n, _VALUE_NODES):
                return False
            todo.extend(ast.iter_child_nodes(n))
        return True

    def _range(self, node: ast.expr, used: dict[str, bool]) -> bool:
        """``range(<values>)``, ``range`` being Python's."""
        if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and not node.keywords):
            return False
        found = python_global(node.func.id, self.local, self.globals)
        return found is range and 1 <= len(node.args) <= 3 and all(self._value(a, used) for a in node.args)

    # -- the rewrite -----------------------------------------------------------

    def _kept(self, loop: ast.For | ast.While, used: dict[str, bool]) -> list[ast.stmt]:
        """The loop between the reads of its variables into locals and the stores of those it writes."""
        for field in used:
            self.names[_type(field)] = self.fields[field]
        _Locals(self).visit(loop)
        reads = [_assign(_local(f), _self(f, ast.Load())) for f in sorted(used)]
        stores: list[ast.stmt] = [_assign(_self(f, ast.Store()), ast.Name(_local(f), ast.Load())) for f in sorted(used) if used[f]]
        placed: list[ast.stmt] = [located(s, loop) for s in reads]
        if stores:
            placed.append(located(ast.Try(body=[loop], handlers=[], orelse=[], finalbody=stores), loop))
        else:
            placed.append(loop)
        return placed

    def converted(self, field: str, value: ast.expr) -> ast.expr:
        """The value the field would hold after storing ``value`` (a name, read more than once)."""
        ctype = self.fields[field]
        convert = ast.Attribute(
            ast.Call(ast.Name(_type(field), ast.Load()), [value], []), "value", ast.Load(),
        )
        if ctype is ctypes.c_bool:
            test: ast.expr = ast.BoolOp(ast.Or(), [
                ast.Compare(value, [ast.Is()], [ast.Constant(True)]), ast.Compare(value, [ast.Is()], [ast.Constant(False)]),
            ])
        else:
            # int / float themselves: the module may bind those names to something else
            python = _FLOAT if ctype is ctypes.c_double else _INT
            self.names[python] = float if ctype is ctypes.c_double else int
            kind = ast.Compare(ast.Attribute(value, "__class__", ast.Load()), [ast.Is()], [ast.Name(python, ast.Load())])
            if ctype is ctypes.c_double:
                test = kind
            else:
                bits = ctypes.sizeof(ctype) * 8
                signed = ctype(-1).value == -1
                low, high = (-(1 << (bits - 1)), (1 << (bits - 1)) - 1) if signed else (0, (1 << bits) - 1)
                within = ast.Compare(ast.Constant(low), [ast.LtE(), ast.LtE()], [value, ast.Constant(high)])
                test = ast.BoolOp(ast.And(), [kind, within])
        return ast.IfExp(test, value, convert)


class _Locals(ast.NodeTransformer):
    """The loop's reads and writes of kept variables made on their locals (see ``LoopLocals``)."""

    def __init__(self, loops: LoopLocals) -> None:
        self.loops = loops

    def visit_Attribute(self, node: ast.Attribute) -> ast.AST:
        field = self_field(node)
        if field is not None and field in self.loops.fields and isinstance(node.ctx, ast.Load):
            return ast.copy_location(ast.Name(_local(field), ast.Load()), node)
        return self.generic_visit(node)

    def visit_Assign(self, node: ast.Assign) -> Any:
        node.value = self.visit(node.value)
        if all(isinstance(t, ast.Name) for t in node.targets):
            return node
        # `a = self.x = v`: v once, then each target from left to right, as Python assigns them
        done: list[ast.stmt] = [located(_assign(_VALUE, node.value), node)]
        for target in node.targets:
            done.append(located(self._store(target), node))
        return done

    def visit_AugAssign(self, node: ast.AugAssign) -> Any:
        field = self_field(node.target)
        node.value = self.visit(node.value)
        if field is None:
            return node
        value = ast.BinOp(ast.Name(_local(field), ast.Load()), node.op, node.value)
        return [located(_assign(_VALUE, value), node), located(self._store(node.target), node)]

    def visit_For(self, node: ast.For) -> ast.AST:
        self.generic_visit(node)
        if isinstance(node.target, ast.Name):
            return node
        # `for self.i in range(...)`: each value stored as the field would hold it
        store = located(self._store(node.target), node.target)
        node.target = ast.copy_location(ast.Name(_VALUE, ast.Store()), node.target)
        node.body = [store, *node.body]
        return node

    def _store(self, target: ast.expr) -> ast.stmt:
        """``target = _iec_w_l_value``, a kept variable's local taking the value its field would hold."""
        value = ast.Name(_VALUE, ast.Load())
        field = self_field(target)
        if field is None:
            return ast.Assign(targets=[target], value=value)
        return _assign(_local(field), self.loops.converted(field, value))


def _local(field: str) -> str:
    """The local a loop keeps ``field`` in: a name of its own beside the rewrite's (``_VALUE``, ``_INT``, ``_FLOAT``)."""
    return f"{_PREFIX}f_{field}"


def _type(field: str) -> str:
    """The name the rewritten code reads ``field``'s ctypes type under."""
    return f"{_PREFIX}t_{field}"


def _self(field: str, ctx: ast.expr_context) -> ast.Attribute:
    return ast.Attribute(ast.Name("self", ast.Load()), field, ctx)


def _assign(name: str | ast.expr, value: ast.expr) -> ast.Assign:
    target = ast.Name(name, ast.Store()) if isinstance(name, str) else name
    return ast.Assign(targets=[target], value=value)
