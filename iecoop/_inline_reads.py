"""Reads of a block's own variables that its compiled call takes from what the call already holds.

Two rewrites of the call builder (``iecoop._inline``), each giving the same
values as the read it replaces: a FOR over a block's integer variable reads
its counter from the loop (``CounterReads``), and a BOOL input given to the
call is read from the argument while nothing can have changed it since it was
stored (``GivenInputs``). Also the two helpers every rewrite of the builder
uses: ``located`` and the ``OwnCode`` transformer.
"""

from __future__ import annotations

import ast
import builtins
import typing
from collections.abc import Callable
from typing import Any

from iecoop._value_class import COUNTER

__all__ = ["PLAIN_NODES", "CounterReads", "GivenInputs", "OwnCode", "inner_statements", "located", "python_global", "self_field"]

_Node = typing.TypeVar("_Node", bound=ast.AST)


def located(new: _Node, old: ast.AST) -> _Node:
    """``new`` (a node a rewrite made) at ``old``'s place, with the nodes it made inside it, for the compiler."""
    return ast.fix_missing_locations(ast.copy_location(new, old))


class OwnCode(ast.NodeTransformer):
    """Leaves nested functions, lambdas, classes and comprehensions alone: their code must stay the body's."""

    def visit_FunctionDef(self, node: ast.AST) -> ast.AST:
        return node

    visit_AsyncFunctionDef = visit_Lambda = visit_ClassDef = visit_FunctionDef
    visit_ListComp = visit_SetComp = visit_DictComp = visit_GeneratorExp = visit_FunctionDef


def inner_statements(statement: ast.stmt) -> list[list[ast.stmt]]:
    """The lists of statements ``statement`` holds (its body, else, finally, handlers, cases); none for a def
    or class, whose code is its own."""
    if isinstance(statement, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
        return []
    found = [inner for part in ("body", "orelse", "finalbody") if isinstance(inner := getattr(statement, part, None), list)]
    return found + [part.body for part in (*getattr(statement, "handlers", ()), *getattr(statement, "cases", ()))]


def python_global(name: str, local: set[str], module_globals: dict[str, Any]) -> Any:
    """What the name ``name`` of a function's code reads, when it is not one of its ``local`` names: the
    module's global, else the builtin (None when neither)."""
    return None if name in local else module_globals.get(name, getattr(builtins, name, None))


class CounterReads:
    """``for self.i in range(1, 1000 + 1):`` over an integer variable: the pass reads ``i`` from the loop's local.

    ::

        for _iec_c_0_i in range(1, 1000 + 1):
            self.i = _iec_c_0_i              # stored first, as before: a METHOD the pass calls reads it
            ... _iec_c_0_i ...               # each read of self.i in the pass's statements

    The same values for every program IEC 61131-3 allows: its FOR's repeated
    statements shall not alter the control variable (the ST reader refuses a
    loop that writes it; a pass whose code stores it anywhere is left alone,
    and so is a range that is not constant or leaves the variable's type).
    ``iecoop.conversions.MOD(i, 50)`` of such a counter that is never negative
    is ``i % 50``, as ``MOD`` itself computes it. ``spans`` collects the values
    each local takes, for the ARRAY element reads (``_MemberCalls``).
    """

    def __init__(self, counters: dict[str, tuple[int, int]], spans: dict[str, range], module_globals: dict[str, Any],
                 local: set[str]) -> None:
        self.counters, self.spans, self.globals, self.local = counters, spans, module_globals, local

    def rewrite(self, statements: list[ast.stmt]) -> None:
        """Rewrite, in place, every FOR of ``statements`` at any depth of statements (an inner loop first);
        the expressions are not walked, nor the defs and classes nested in them."""
        for statement in statements:
            for inner in inner_statements(statement):
                self.rewrite(inner)
            if isinstance(statement, ast.For):
                self._counted(statement)

    def _counted(self, node: ast.For) -> None:
        target, field = node.target, self_field(node.target)
        if field is None:
            return
        span, values = self.counters.get(field), self._range(node.iter)
        if span is None or values is None or _stores_field(node.body, field):
            return
        if values and not (span[0] <= min(values) and max(values) <= span[1]):
            return
        local = f"{COUNTER}{len(self.spans)}_{field}"
        self.spans[local] = values
        reads = _CounterRead(field, local, values, self._is_mod)
        store = ast.Assign(targets=[target], value=ast.Name(id=local, ctx=ast.Load()))
        node.target = ast.copy_location(ast.Name(id=local, ctx=ast.Store()), target)
        node.body = [located(store, node), *(reads.visit(statement) for statement in node.body)]

    def _global(self, name: str) -> Any:
        return python_global(name, self.local, self.globals)

    def _range(self, node: ast.expr) -> range | None:
        """The values of ``range(<constants>)`` (``range`` being Python's), else None."""
        if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and self._global(node.func.id) is range):
            return None
        if node.keywords or not 1 <= len(node.args) <= 3:
            return None
        bounds = [_int_constant(a) for a in node.args]
        if None in bounds or bounds[2:] == [0]:
            return None
        return range(*(b for b in bounds if b is not None))

    def _is_mod(self, node: ast.expr) -> bool:
        from iecoop.conversions import MOD

        return isinstance(node, ast.Name) and self._global(node.id) is MOD


class _CounterRead(OwnCode):
    """One FOR pass's reads of ``self.<field>`` from the loop's ``local`` (see ``CounterReads``)."""

    def __init__(self, field: str, local: str, values: range, is_mod: Callable[[ast.expr], bool]) -> None:
        self.field, self.local, self.values, self.is_mod = field, local, values, is_mod

    def visit_Attribute(self, node: ast.Attribute) -> ast.AST:
        self.generic_visit(node)
        if _self_read(node) == self.field:
            return ast.copy_location(ast.Name(id=self.local, ctx=ast.Load()), node)
        return node

    def visit_Call(self, node: ast.Call) -> ast.AST:
        self.generic_visit(node)
        if not (self.is_mod(node.func) and len(node.args) == 2 and not node.keywords):
            return node
        counter, divisor = node.args
        if not (isinstance(counter, ast.Name) and counter.id == self.local and min(self.values, default=0) >= 0):
            return node
        if not (isinstance(divisor, ast.Constant) and type(divisor.value) is int and divisor.value > 0):
            return node
        return located(ast.BinOp(left=counter, op=ast.Mod(), right=divisor), node)


def _stores_field(statements: list[ast.stmt], field: str) -> bool:
    """Whether ``statements`` (nested code too) store or delete ``self.<field>``, or call setattr / delattr."""
    for statement in statements:
        for n in ast.walk(statement):
            if isinstance(n, ast.Attribute) and n.attr == field and not isinstance(n.ctx, ast.Load):
                return True
            if isinstance(n, ast.Name) and n.id in ("setattr", "delattr"):
                return True
    return False


def _int_constant(node: ast.expr) -> int | None:
    """The value of an integer constant expression (``1000 + 1``, ``-5``), else None."""
    if isinstance(node, ast.Constant):
        return node.value if type(node.value) is int else None
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        operand = _int_constant(node.operand)
        return None if operand is None else (-operand if isinstance(node.op, ast.USub) else operand)
    if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Add, ast.Sub, ast.Mult)):
        left, right = _int_constant(node.left), _int_constant(node.right)
        if left is None or right is None or max(abs(left), abs(right)) > 1 << 64:
            return None
        return left + right if isinstance(node.op, ast.Add) else left - right if isinstance(node.op, ast.Sub) else left * right
    return None


class GivenInputs:
    """The body's first reads of a BOOL input given to the call come from the argument, not the block's memory.

    The call stores each given input before the body runs (``if IN is not ...:
    self.IN = IN``); up to the body's first statement that could change
    anything (a call, a store to the block, a read that runs code), each
    ``self.IN`` is::

        (IN if IN is True or IN is False else self.IN)

    An exact ``bool`` given is what the BOOL holds after the store; ``...`` (not
    given) and any other value read the variable, as before. The leading
    statements taken are assignments to local names and the test of an
    ``if``, or the arguments of one member call, whose values read only
    constants, local names and ``self.<plain>``: an elementary variable read
    from its ctypes field (``plain``), which runs no code.
    """

    def __init__(self, bools: set[str], plain: set[str], members: set[str]) -> None:
        self.bools, self.plain, self.members = bools, plain, members

    def rewrite(self, statements: list[ast.stmt]) -> None:
        """Rewrite the leading ``statements`` in place."""
        for statement in statements:
            if isinstance(statement, ast.Assign) and all(isinstance(t, ast.Name) for t in statement.targets):
                reads = self._plain(statement.value)
                if reads is None:
                    return
                if reads:
                    statement.value = self._given(statement.value)
                continue
            if isinstance(statement, ast.If) and self._plain(statement.test):
                statement.test = self._given_test(statement.test)
            elif isinstance(statement, ast.Expr) and self._member_call(statement.value):
                call = typing.cast(ast.Call, statement.value)
                call.args = [self._given(a) for a in call.args]
                for keyword in call.keywords:
                    keyword.value = self._given(keyword.value)
            return

    def _member_call(self, node: ast.expr) -> bool:
        """``self.member(<plain>, name=<plain>)``: the member's view is read before the arguments, running no code."""
        if not (isinstance(node, ast.Call) and _self_read(node.func) in self.members):
            return False
        arguments = [*node.args, *(k.value for k in node.keywords)]
        return all(k.arg is not None for k in node.keywords) and all(self._plain(a) is not None for a in arguments)

    def _plain(self, node: ast.expr) -> bool | None:
        """None when ``node`` may run code or store; else whether it reads one of the BOOL inputs."""
        reads = False
        for n in ast.walk(node):
            if isinstance(n, ast.Attribute):
                field = _self_read(n)
                if field is None or field not in self.plain:
                    return None
                reads = reads or field in self.bools
            elif isinstance(n, ast.Name):
                if not isinstance(n.ctx, ast.Load):
                    return None
            elif not isinstance(n, PLAIN_NODES):
                return None
        return reads

    def _given_test(self, node: ast.expr) -> ast.expr:
        """``node`` rewritten where only its truth is used (an ``if``'s test): there, ``self.IN`` is

            IN is True or IN is not False and self.IN

        which answers an exact ``bool`` in one identity test; the operands of
        ``and`` / ``or`` / ``not`` in such a place are in one too."""
        field = _self_read(node)
        if field in self.bools:
            place = {name: getattr(node, name) for name in ("lineno", "col_offset", "end_lineno", "end_col_offset")}
            load = ast.Load()
            given, other = (ast.Compare(ast.Name(field, load, **place), [test], [ast.Constant(v, **place)], **place)
                            for test, v in ((ast.Is(), True), (ast.IsNot(), False)))
            return ast.BoolOp(ast.Or(), [given, ast.BoolOp(ast.And(), [other, node], **place)], **place)
        if isinstance(node, ast.BoolOp):
            node.values = [self._given_test(v) for v in node.values]
            return node
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.Not):
            node.operand = self._given_test(node.operand)
            return node
        return self._given(node)

    def _given(self, node: ast.expr) -> ast.expr:
        bools = self.bools

        class Reads(ast.NodeTransformer):
            def visit_Attribute(self, attribute: ast.Attribute) -> ast.AST:
                field = _self_read(attribute)
                if field is None or field not in bools:
                    return attribute
                # `is True or is False`: an exact bool in two identity tests, no attribute read and no call
                place = {name: getattr(attribute, name) for name in ("lineno", "col_offset", "end_lineno", "end_col_offset")}
                load = ast.Load()
                tests: list[ast.expr] = [
                    ast.Compare(ast.Name(field, load, **place), [ast.Is()], [ast.Constant(v, **place)], **place)
                    for v in (True, False)
                ]
                exact = ast.BoolOp(ast.Or(), tests, **place)
                return ast.IfExp(exact, ast.Name(field, load, **place), attribute, **place)

        return typing.cast(ast.expr, Reads().visit(node))


#: The nodes of an expression that runs no code of its own: constants and operators over the values read.
PLAIN_NODES = (ast.Constant, ast.BoolOp, ast.UnaryOp, ast.Compare, ast.BinOp, ast.IfExp, ast.boolop, ast.unaryop,
                ast.cmpop, ast.operator, ast.expr_context)


def self_field(node: ast.expr) -> str | None:
    """``self.x`` (read, stored or deleted) -> ``"x"``, else None."""
    if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id == "self":
        return node.attr
    return None


def _self_read(node: ast.expr) -> str | None:
    """``self.x`` (a read) -> ``"x"``, else None."""
    return self_field(node) if isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Load) else None
