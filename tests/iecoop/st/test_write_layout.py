"""The write wing stays a compiler one can work in: small rooms, one handler per syntax node, its words from language."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from iecoop.st import language
from iecoop.st.write import expressions, infer, statements
from tests.iecoop.st.layout import oversized

WING = Path(statements.__file__).parent
ROOMS = sorted(WING.glob("*.py"))


@pytest.mark.parametrize("room", ROOMS, ids=lambda p: p.name)
def test_no_room_over_1000_lines_and_no_class_over_600(room: Path) -> None:
    assert oversized(room, module_lines=1000, class_lines=600) == []


def test_every_statement_and_expression_has_its_visit_handler() -> None:
    # The statements and expressions the writer translates, each by visit_<ast class name>.
    handled = {name.removeprefix("visit_") for name in dir(statements.StatementWriter) if name.startswith("visit_")}
    assert {"If", "For", "While", "Return", "Assign", "AugAssign", "AnnAssign", "Try", "With", "Match", "Expr"} <= handled
    assert {"Constant", "Name", "Attribute", "Subscript", "Call", "BinOp", "UnaryOp", "BoolOp", "Compare", "IfExp", "JoinedStr"} <= handled
    assert {"Add", "Sub", "Mult", "Div", "FloorDiv", "Mod", "BitAnd", "BitOr", "BitXor", "LShift", "RShift", "Pow"} <= handled
    types = {name.removeprefix("visit_") for name in dir(infer.ExpressionType) if name.startswith("visit_")}
    assert {"Constant", "Name", "Attribute", "Subscript", "Call", "BinOp", "Compare"} <= types


def test_the_wing_writes_and_takes_its_words_from_language() -> None:
    for room in ROOMS:
        names = {n.name for n in ast.walk(ast.parse(room.read_text(encoding="utf-8"))) if isinstance(n, ast.FunctionDef)}
        assert not {n for n in names if "emit" in n}, f"{room.name}: 'write' is the write wing's verb"
    assert expressions._UNARY == language.PRECEDENCE["NOT"] and expressions._ATOM > max(language.PRECEDENCE.values())
