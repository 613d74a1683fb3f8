"""The reader's forms of CASE and __TRY, recognised on the syntax tree and written as the ST they came from.

``st.load`` writes ``CASE`` as an ``if`` / ``elif`` chain (its selector kept in a temporary when it is
not a variable) and ``__TRY ... __CATCH(exc) ... __FINALLY ... __ENDTRY`` as ``with try_catch() as t:``,
an ``if t.code != RTSEXCPT_NOEXCEPTION:`` and a ``try`` / ``finally``. :class:`ReaderForms` finds those
shapes before the statements are written (:meth:`reader_cases`, :meth:`reader_tries`) and hands them on as
one node each, :class:`CaseStatement` and :class:`TryStatement`, which their handlers write back as CASE
and __TRY. Every decision is on the tree and on the values the writer knows, never on printed text.
"""

from __future__ import annotations

import ast
import dataclasses
import enum
from collections.abc import Callable

from iecoop.metadata import field_record, kind_of
from iecoop.st.write.cases import CaseForm, case_form
from iecoop.st.write.expressions import ExpressionWriter
from iecoop.st.write.infer import _fields_of, _is_integer, _is_name
from iecoop.st.write.loops import number

__all__ = ["CaseStatement", "ReaderForms", "TryStatement"]


class CaseStatement(ast.stmt):
    """A CASE the reader wrote as a selector kept in a temporary and an ``if`` chain (see reader_cases())."""

    _fields = ()

    def __init__(self, form: CaseForm) -> None:
        super().__init__()
        self.form = form


@dataclasses.dataclass
class TryStatement(ast.stmt):
    """__TRY ``body`` __CATCH(``name``) ``handler`` __FINALLY ``finalbody`` __ENDTRY, as the reader wrote it (see reader_tries())."""

    body: list[ast.stmt]
    name: str
    handler: list[ast.stmt]
    finalbody: list[ast.stmt] = dataclasses.field(default_factory=list)
    #: the variable of the block __CATCH stores the code in (``__CATCH(exc)``), None for a local of its own
    caught: ast.expr | None = None
    _fields = ()


class ReaderForms(ExpressionWriter):
    """The CASE and __TRY forms of the reader, found in a body's statements and written as CASE and __TRY."""

    def block(self, body: list[ast.stmt], depth: int, *, top: bool = False) -> None:
        """Write ``body`` one level deeper (see :meth:`.statements.StatementWriter.block`)."""
        raise NotImplementedError

    def write(self, depth: int, text: str) -> None:
        """Write one line (see :meth:`.statements.StatementWriter.write`)."""
        raise NotImplementedError

    def reader_cases(self, body: list[ast.stmt]) -> list[ast.stmt]:
        """``body`` with each selector kept in a temporary and tested by the ``if`` after it as one CASE."""
        return _folded(body, self.folded_case)

    def folded_case(self, stmt: ast.stmt, following: ast.stmt | None) -> tuple[ast.stmt, int] | None:
        """``_case1 = F(x)`` then ``if _case1 == 1: ... elif ...``: one :class:`CaseStatement` of the two
        statements, when the temporary is read nowhere else and the selector is an integer or enumeration."""
        held = stmt.targets[0] if isinstance(stmt, ast.Assign) and len(stmt.targets) == 1 else None
        if not (isinstance(stmt, ast.Assign) and isinstance(held, ast.Name) and isinstance(following, ast.If) and held.id not in self.params):
            return None
        form = case_form(following, self.case_value, ast.Name(held.id, ast.Load()))
        if form is None or not _is_integer(self.typeof(stmt.value)):
            return None
        tests = sum(isinstance(n, ast.Name) and n.id == held.id for n in ast.walk(following) if n is not following)
        in_bodies = any(_reads(s, held.id) for part in (*[b.body for b in form.branches], form.orelse) for s in part)
        if in_bodies or tests != self.reads[held.id]:
            return None
        return ast.copy_location(CaseStatement(dataclasses.replace(form, subject=stmt.value)), stmt), 2

    def reader_tries(self, body: list[ast.stmt]) -> list[ast.stmt]:
        """``body`` with the reader's __TRY / __CATCH / __FINALLY as one :class:`TryStatement`: ``with try_catch()
        as t:`` then ``if t.code != RTSEXCPT_NOEXCEPTION:`` (the __CATCH part), in a ``try`` / ``finally`` when
        there is a __FINALLY (try_catch() catches the fault, so the ``finally`` runs after, as __FINALLY does)."""
        return _folded(body, self.folded_try)

    def folded_try(self, stmt: ast.stmt, following: ast.stmt | None) -> tuple[ast.stmt, int] | None:
        """The :class:`TryStatement` ``stmt`` (and ``following``, the __CATCH part) make, and how many they are."""
        if isinstance(stmt, ast.Try) and not stmt.handlers and not stmt.orelse and stmt.finalbody:
            inner = self.reader_tries(stmt.body)
            if len(inner) == 1 and isinstance(inner[0], TryStatement) and not inner[0].finalbody:
                return ast.copy_location(dataclasses.replace(inner[0], finalbody=stmt.finalbody), stmt), 1
            return None
        name = self.try_catch_name(stmt)
        if name is None or not (isinstance(following, ast.If) and not following.orelse and self.is_fault_test(following.test, name)):
            return None
        assert isinstance(stmt, ast.With)
        handler, caught = following.body, None
        first = handler[0] if handler else None
        if (isinstance(first, ast.Assign) and len(first.targets) == 1 and isinstance(first.targets[0], ast.Attribute)
                and isinstance(first.value, ast.Attribute) and first.value.attr == "code" and _is_name(first.value.value, name)):
            # ``self.exc = t.code`` first: the reader's __CATCH(exc) of a variable of the block
            handler, caught = handler[1:], first.targets[0]
        return ast.copy_location(TryStatement(stmt.body, name, handler, caught=caught), stmt), 2

    def try_catch_name(self, stmt: ast.stmt) -> str | None:
        """The name of ``with try_catch() as name:``, None for another statement."""
        if not (isinstance(stmt, ast.With) and len(stmt.items) == 1 and isinstance(stmt.items[0].optional_vars, ast.Name)):
            return None
        call = stmt.items[0].context_expr
        return stmt.items[0].optional_vars.id if isinstance(call, ast.Call) and self.resolves_to(call.func, "try_catch") else None

    def is_fault_test(self, test: ast.expr, name: str) -> bool:
        """``name.code != ExceptionCode.RTSEXCPT_NOEXCEPTION``: a fault was caught."""
        from iecoop.exceptions import ExceptionCode

        if not (isinstance(test, ast.Compare) and len(test.ops) == 1 and isinstance(test.ops[0], ast.NotEq)):
            return False
        left, right = test.left, test.comparators[0]
        owner = self.constant_object(right.value) if isinstance(right, ast.Attribute) else None
        return (isinstance(left, ast.Attribute) and left.attr == "code" and _is_name(left.value, name)
                and owner is ExceptionCode and isinstance(right, ast.Attribute) and right.attr == ExceptionCode.RTSEXCPT_NOEXCEPTION.name)

    def visit_TryStatement(self, node: TryStatement, depth: int, last: bool) -> None:
        """The reader's __TRY body __CATCH(name) handler [__FINALLY final] __ENDTRY, written as it was."""
        self.write(depth, "__TRY")
        self.block(node.body, depth + 1)
        if node.caught is not None:
            self.write(depth, f"__CATCH({self.target(node.caught)})")
        else:
            self.catch_vars.add(node.name)
            self.declare(node.name, "__SYSTEM.ExceptionCode", node)
            self.write(depth, f"__CATCH({node.name})")
        self.block(node.handler, depth + 1)
        if node.finalbody:
            self.write(depth, "__FINALLY")
            self.block(node.finalbody, depth + 1)
        self.write(depth, "__ENDTRY")

    def visit_CaseStatement(self, node: CaseStatement, depth: int, last: bool) -> None:
        """A selector kept in a temporary, then tested (``_case1 = F(x)``, ``if _case1 == 1: ...``): ``CASE F(x) OF``."""
        self.write_case(node.form, depth)

    def case_value(self, node: ast.expr) -> int | None:
        """The value of a CASE label: an integer literal, an enumeration component, a constant of a global list."""
        value = number(node)
        if value is not None or not isinstance(node, ast.Attribute):
            return value
        owner = self.constant_object(node.value)
        if isinstance(owner, type) and kind_of(owner) == "enum":
            member = getattr(owner, node.attr, None)
            return int(member.value) if isinstance(member, enum.Enum) else None
        holder = self.globals.get(node.value.id) if isinstance(node.value, ast.Name) and node.value.id not in self.locals else None
        if kind_of(type(holder)) == "gvl" and node.attr in _fields_of(type(holder)) and field_record(type(holder), node.attr).spec.constant:
            found = getattr(holder, node.attr)
            return found if type(found) is int else None
        return None

    def write_case(self, form: CaseForm, depth: int) -> None:
        """``CASE subject OF labels: ... ELSE ... END_CASE``."""
        self.write(depth, f"CASE {self.expr(form.subject)[0]} OF")
        for branch in form.branches:
            labels = ", ".join(
                self.expr(label.value)[0] + (f"..{self.expr(label.high)[0]}" if label.high is not None else "")
                for label in branch.labels
            )
            self.write(depth + 1, f"{labels}:")
            self.block(branch.body, depth + 2)
        if form.orelse:
            self.write(depth, "ELSE")
            self.block(form.orelse, depth + 1)
        self.write(depth, "END_CASE")


def _folded(body: list[ast.stmt], fold: Callable[[ast.stmt, ast.stmt | None], tuple[ast.stmt, int] | None]) -> list[ast.stmt]:
    """``body`` with each statement (and the one after it) that ``fold`` takes replaced by what it gives."""
    out: list[ast.stmt] = []
    index = 0
    while index < len(body):
        found = fold(body[index], body[index + 1] if index + 1 < len(body) else None)
        if found is None:
            out.append(body[index])
            index += 1
        else:
            out.append(found[0])
            index += found[1]
    return out


def _reads(stmt: ast.stmt, name: str) -> bool:
    return any(isinstance(n, ast.Name) and n.id == name for n in ast.walk(stmt))
