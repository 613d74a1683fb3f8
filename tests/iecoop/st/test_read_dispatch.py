"""The read wing dispatches each blark node to its visit_<node class> handler; others are named errors."""

from __future__ import annotations

import types

import pytest

pytest.importorskip("blark")

import blark.transform as tf  # noqa: E402

from iecoop.st import StUnsupportedError  # noqa: E402
from iecoop.st.read.frames import Scope  # noqa: E402
from iecoop.st.read.parse import parse_sources  # noqa: E402
from iecoop.st.read.translate import Translator  # noqa: E402


def _translator() -> Translator:
    translator = Translator(parse_sources("PROGRAM P\nVAR x : INT; END_VAR\nx := 1;\nEND_PROGRAM\n"))
    translator.unit = translator.units[0]
    return translator


def test_a_statement_without_a_handler_names_the_file_line_and_construct() -> None:
    node = type("FooStatement", (tf.Statement,), {})()
    node.meta = types.SimpleNamespace(line=3)
    with pytest.raises(StUnsupportedError, match=r"^<st>:3: statement FooStatement is not supported$"):
        _translator().statement(node, Scope(None, "body"), 0)


def test_an_expression_node_is_never_read_as_a_statement_and_a_statement_never_as_an_expression() -> None:
    translator = _translator()
    expression = type("Integer", (tf.Expression,), {})()
    with pytest.raises(StUnsupportedError, match="statement Integer is not supported"):
        translator.statement(expression, Scope(None, "body"), 0)
    statement = type("ExitStatement", (tf.Statement,), {})()
    with pytest.raises(StUnsupportedError, match="expression ExitStatement is not supported"):
        translator.expr(statement, Scope(None, "body"))


def test_every_handler_is_named_after_a_blark_node_class() -> None:
    handlers = [name.removeprefix("visit_") for name in dir(Translator) if name.startswith("visit_")]
    assert len(handlers) > 40
    assert [name for name in handlers if name != "Tree" and not hasattr(tf, name)] == []
