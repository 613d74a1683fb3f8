"""An ``if`` / ``elif`` chain that tests one variable against constants, given back as ST's CASE.

``st.load`` reads ``CASE eState OF E.IDLE: ... E.RUN, E.STOP: ... 1..5: ... ELSE ... END_CASE`` as
``if self.eState == E.IDLE: ... elif self.eState == E.RUN or self.eState == E.STOP: ... elif 1 <= self.eState
<= 5: ... else: ...``, and a selector that is not a variable is kept in a temporary first (``_case1 = ...``).
Such a chain means what CASE means (the variable is only read, each label is a distinct constant, the first
branch whose labels match runs), so the writer writes CASE again: a PLC programmer reads the state machine
as written, and a Python one written that way comes out the same.

The decision is made on the syntax tree and on the labels' values, asked of the writer (``value_of``):
an integer literal, an enumeration component, a constant of a global list.
"""

from __future__ import annotations

import ast
import dataclasses
from collections.abc import Callable

from iecoop.st.write.loops import same_variable

__all__ = ["Branch", "CaseForm", "Label", "case_form"]


@dataclasses.dataclass(frozen=True)
class Label:
    """One label of a CASE branch: a value (``E.IDLE``), or a range ``low..high`` (``high`` set)."""

    value: ast.expr
    high: ast.expr | None = None


@dataclasses.dataclass(frozen=True)
class Branch:
    labels: tuple[Label, ...]
    body: list[ast.stmt]


@dataclasses.dataclass(frozen=True)
class CaseForm:
    """``CASE subject OF`` each branch ``ELSE`` orelse ``END_CASE``."""

    subject: ast.expr
    branches: tuple[Branch, ...]
    orelse: list[ast.stmt]


def case_form(node: ast.If, value_of: Callable[[ast.expr], int | None], subject: ast.expr | None = None) -> CaseForm | None:
    """The CASE an ``if`` / ``elif`` chain of at least two tests is, or None when it is not one.

    ``subject``: the variable every test must read (None: the one the first test reads); ``value_of``: the
    value of a constant label, None for anything else.
    """
    branches: list[Branch] = []
    current: ast.If | None = node
    orelse: list[ast.stmt] = []
    while current is not None:
        found = _labels(current.test, value_of)
        if found is None:
            return None
        tested, labels = found
        if subject is None:
            subject = tested
        if not same_variable(subject, tested):
            return None
        branches.append(Branch(labels, current.body))
        nested = current.orelse
        current = nested[0] if len(nested) == 1 and isinstance(nested[0], ast.If) else None
        if current is None:
            orelse = nested
    if subject is None or len(branches) < 2 or not _distinct(branches, value_of):
        return None
    return CaseForm(subject, tuple(branches), orelse)


def _labels(test: ast.expr, value_of: Callable[[ast.expr], int | None]) -> tuple[ast.expr, tuple[Label, ...]] | None:
    """(the variable tested, the labels) of ``x == A``, ``low <= x <= high`` or ``or`` of those; else None."""
    options = test.values if isinstance(test, ast.BoolOp) and isinstance(test.op, ast.Or) else [test]
    subject: ast.expr | None = None
    labels: list[Label] = []
    for option in options:
        found = _label(option, value_of)
        if found is None:
            return None
        tested, label = found
        if subject is not None and not same_variable(subject, tested):
            return None
        subject = tested
        labels.append(label)
    assert subject is not None
    return subject, tuple(labels)


def _label(test: ast.expr, value_of: Callable[[ast.expr], int | None]) -> tuple[ast.expr, Label] | None:
    if not isinstance(test, ast.Compare) or not isinstance(test.left, (ast.Name, ast.Attribute, ast.Constant, ast.UnaryOp)):
        return None
    if len(test.ops) == 1 and isinstance(test.ops[0], ast.Eq):
        variable: ast.expr = test.left
        value = test.comparators[0]
        if value_of(variable) is not None:  # ``A == x``
            variable, value = value, variable
        if _is_variable(variable) and value_of(value) is not None:
            return variable, Label(value)
        return None
    if len(test.ops) == 2 and all(isinstance(op, ast.LtE) for op in test.ops):
        low, variable, high = test.left, test.comparators[0], test.comparators[1]
        if _is_variable(variable) and value_of(low) is not None and value_of(high) is not None:
            return variable, Label(low, high)
    return None


def _is_variable(node: ast.expr) -> bool:
    """A name or a chain of members (``self.eState``, ``GVL_IO.nMode``): read without running anything."""
    return isinstance(node, ast.Name) or isinstance(node, ast.Attribute) and _is_variable(node.value)


def _distinct(branches: list[Branch], value_of: Callable[[ast.expr], int | None]) -> bool:
    """Whether no value is the label of two branches (ST refuses that; Python runs the first)."""
    spans: list[tuple[int, int]] = []
    for branch in branches:
        for label in branch.labels:
            low = value_of(label.value)
            high = value_of(label.high) if label.high is not None else low
            if low is None or high is None or low > high:
                return False
            spans.append((low, high))
    spans.sort()
    return all(previous[1] < following[0] for previous, following in zip(spans, spans[1:]))
