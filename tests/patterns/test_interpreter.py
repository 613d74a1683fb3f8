"""Interpreter: the interlock language, parsed once and evaluated every scan."""

from __future__ import annotations

import struct
from dataclasses import dataclass

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import NULL, AccessError, Program, T
from iecoop.runtime import Runtime, Task
from patterns.behavioral.interpreter import (
    MAX_DEPTH,
    MAX_TAGS,
    MAX_TEXT,
    POOL_SIZE,
    ExpressionParser,
    Interlock,
    NodeKind,
    Operator,
    TagRefusal,
    TagTable,
    TokenKind,
    TransferMain,
    ValueType,
    caret,
    upper_text,
)


def start(program: Program) -> Runtime:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    return rt


def plant_tags() -> TagTable:
    tags = TagTable()
    for name, kind in (
        ("TT101", ValueType.REAL_VALUE),
        ("LS3", ValueType.BOOL_VALUE),
        ("PT102", ValueType.REAL_VALUE),
        ("BYPASS", ValueType.BOOL_VALUE),
    ):
        tags.declare(name, kind)
    return tags


def evaluate(text: str, **values: float | bool) -> bool:
    tags = plant_tags()
    for name, value in values.items():
        index = tags.find(name)
        if isinstance(value, bool):
            tags.set_bool(index, value)
        else:
            tags.set_real(index, value)
    interlock = Interlock()
    interlock.compile(text, tags)
    interlock()
    return interlock.permissive


# ---------------------------------------------------------------------------
# The transfer permissive across cycles
# ---------------------------------------------------------------------------


def pump_after(rt: Runtime, program: TransferMain, cycles: int) -> bool:
    rt.run(cycles=cycles)
    return program.pump_on


def test_the_pump_follows_the_permissive_scan_by_scan() -> None:
    program = TransferMain()
    rt = start(program)
    seen = []
    program.tt101 = 80.0
    seen.append(pump_after(rt, program, 5))
    program.tt101 = 80.5
    seen.append(pump_after(rt, program, 1))
    program.pt102 = 2.5
    seen.append(pump_after(rt, program, 1))
    program.bypass = True
    seen.append(pump_after(rt, program, 1))
    program.ls3 = True
    seen.append(pump_after(rt, program, 3))
    program.ls3 = False
    seen.append(pump_after(rt, program, 1))
    assert seen == [False, True, False, True, False, True]
    assert program.pump_starts == 3
    assert program.transfer.scans == 12 == rt.time_ms // 10


def test_every_scan_evaluates_every_node_exactly_once_whatever_the_values() -> None:
    program = TransferMain()
    rt = start(program)
    pool = program.transfer.pool
    nodes = [
        node
        for array, used in (
            (pool.constants, pool.used[1]), (pool.tags, pool.used[2]), (pool.compares, pool.used[3]),
            (pool.logics, pool.used[4]), (pool.nots, pool.used[5]),
        )
        for node in list(array)[:used]
    ]
    assert len(nodes) == program.transfer.node_count == 12
    # TT101 = 20 makes the first AND operand FALSE: ST's AND still evaluates the rest.
    assert pump_after(rt, program, 7) is False
    assert [node.evaluations for node in nodes] == [7] * 12
    program.tt101 = 95.0
    assert pump_after(rt, program, 3) is True
    assert [node.evaluations for node in nodes] == [10] * 12


def test_an_interlock_without_an_expression_blocks_without_faulting() -> None:
    interlock = Interlock()
    for _ in range(3):
        interlock()
    assert (interlock.valid, interlock.permissive, interlock.scans) == (False, False, 3)


def pumping() -> tuple[TransferMain, Runtime]:
    """The transfer program one scan after its permissive released the pump."""
    program = TransferMain()
    rt = start(program)
    program.tt101 = 90.0
    rt.run(cycles=1)
    assert program.pump_on is True
    return program, rt


def test_a_rejected_text_leaves_the_running_expression_in_place() -> None:
    program, rt = pumping()
    transfer = program.transfer
    assert transfer.compile("TT999 > 1 AND NOT LS3 AND LS3 AND LS3", program.tags) is False
    assert (transfer.error, transfer.error_text, transfer.error_column) == (True, "unknown tag 'TT999'", 1)
    rt.run(cycles=1)
    assert program.pump_on is True
    assert program.transfer.source == "TT101 > 80 AND NOT LS3 AND (PT102 < 2.5 OR BYPASS)"
    assert program.transfer.node_count == 12


def test_disable_takes_the_expression_out_of_service_until_the_next_compile() -> None:
    program, rt = pumping()
    program.transfer.disable()
    rt.run(cycles=1)
    transfer = program.transfer
    assert (program.pump_on, transfer.valid, transfer.root == NULL) == (False, False, True)
    assert (transfer.node_count, transfer.pool.node_count, transfer.source) == (0, 0, "")
    assert transfer.compile("NOT LS3", program.tags) is True
    assert (transfer.error, transfer.error_text, transfer.error_column) == (False, "", 0)
    rt.run(cycles=1)
    assert program.pump_on is True and program.pump_starts == 2


def test_recompiling_reuses_the_pool_for_the_new_tree() -> None:
    program = TransferMain()
    rt = start(program)
    rt.run(cycles=2)
    program.transfer.compile("LS3 OR TT101 >= 20", program.tags)
    assert program.transfer.node_count == 5
    assert [program.transfer.pool.used[i] for i in range(1, 6)] == [1, 2, 1, 1, 0]
    rt.run(cycles=1)
    assert program.pump_on is True
    assert program.transfer.pool.compares[1].evaluations == 1


# ---------------------------------------------------------------------------
# The language: precedence, case, REAL semantics
# ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "values", "expected"),
    [
        ("TT101 > 80 AND NOT LS3", {"TT101": 81.0, "LS3": False}, True),
        ("TT101 > 80 AND NOT LS3", {"TT101": 81.0, "LS3": True}, False),
        ("NOT TT101 > 80", {"TT101": 81.0}, False),
        ("LS3 OR BYPASS AND FALSE", {"LS3": True, "BYPASS": False}, True),
        ("(LS3 OR BYPASS) AND FALSE", {"LS3": True}, False),
        ("LS3 XOR BYPASS OR TRUE", {"LS3": True, "BYPASS": True}, True),
        ("LS3 XOR BYPASS AND FALSE", {"LS3": True, "BYPASS": True}, True),
        ("LS3 = BYPASS", {"LS3": False, "BYPASS": False}, True),
        ("(TT101 > 1) <> LS3", {"TT101": 5.0, "LS3": True}, False),
        ("TT101 >= -2.5 AND TT101 <= 0", {"TT101": -2.5}, True),
        ("tt101 > 80 and not ls3", {"TT101": 90.0}, True),
        ("NOT NOT LS3", {"LS3": True}, True),
        ("TT101 = 0.1", {"TT101": 0.1}, True),
        ("TT101 <> PT102", {"TT101": 1.0, "PT102": 1.0}, False),
    ],
)
def test_expressions_evaluate_like_st(text: str, values: dict[str, float | bool], expected: bool) -> None:
    assert evaluate(text, **values) is expected


def test_the_tokenizer_reports_kinds_and_columns() -> None:
    parser = ExpressionParser()
    assert parser.parse("  NOT(TT101<>-5)", plant_tags()) is True
    tokens = [parser.tokens[i] for i in range(1, parser.token_count + 1)]
    assert [(t.kind, parser.token_text(i), t.column) for i, t in enumerate(tokens, 1)] == [
        (TokenKind.KEYWORD, "NOT", 3), (TokenKind.SYMBOL, "(", 6), (TokenKind.WORD, "TT101", 7),
        (TokenKind.SYMBOL, "<>", 12), (TokenKind.SYMBOL, "-", 14), (TokenKind.NUMBER, "5", 15),
        (TokenKind.SYMBOL, ")", 16), (TokenKind.END_, "", 17),
    ]
    assert tokens[5].number == 5.0


@pytest.mark.parametrize(("text", "value"), [("80", 80.0), ("2.5", 2.5), ("0.1", 0.1), ("007.250", 7.25), ("123456.789", 123456.789)])
def test_numbers_are_read_as_the_nearest_real(text: str, value: float) -> None:
    parser = ExpressionParser()
    assert parser.parse(f"TT101 > {text}", plant_tags()) is True
    assert parser.tokens[3].number == _float32(value)


def test_parse_builds_a_typed_tree_without_touching_any_pool() -> None:
    parser = ExpressionParser()
    assert parser.parse("TT101 > 80 AND NOT LS3", plant_tags()) is True
    top = parser.nodes[parser.root]
    assert (top.kind, top.op, top.column, top.value_type) == (NodeKind.LOGIC, Operator.AND_, 12, ValueType.BOOL_VALUE)
    compare, negation = parser.nodes[top.left], parser.nodes[top.right]
    assert (compare.kind, compare.op, parser.nodes[compare.right].real_value) == (NodeKind.COMPARE, Operator.GT, 80.0)
    assert (negation.kind, parser.nodes[negation.left].kind, parser.nodes[negation.left].index) == (
        NodeKind.NOT_, NodeKind.TAG, 2,
    )
    assert [parser.counts[k] for k in NodeKind] == [1, 2, 1, 1, 1]


# ---------------------------------------------------------------------------
# Clear errors for bad expressions
# ---------------------------------------------------------------------------


def refused(text: str) -> tuple[str, int]:
    """Compile ``text`` on a fresh interlock, which must refuse it: the reason and the column."""
    interlock = Interlock()
    assert interlock.compile(text, plant_tags()) is False
    assert (interlock.error, interlock.valid, interlock.source) == (True, False, "")
    return interlock.error_text, interlock.error_column


@pytest.mark.parametrize(
    ("text", "message", "column"),
    [
        ("TT999 > 80", "unknown tag 'TT999'", 1),
        ("TT101 > 80 AND (NOT LS3", "unbalanced parentheses: '(' is never closed", 16),
        ("TT101 > 80 AND NOT LS3)", "unbalanced parentheses: ')' has no '(' to close", 23),
        ("((LS3)", "unbalanced parentheses: '(' is never closed", 1),
        ("TT101 > 80 AND AND LS3", "unexpected 'AND', expected a tag, a number, TRUE, FALSE, NOT or '('", 16),
        ("TT101 > 80 LS3", "unexpected 'LS3', expected AND, OR, XOR or the end", 12),
        ("TT101 >", "unexpected end of expression, expected a tag, a number, TRUE, FALSE, NOT or '('", 8),
        ("LS3 > 5", "type error: '>' compares BOOL with REAL", 5),
        ("LS3 < BYPASS", "type error: '<' needs REAL operands, got BOOL", 5),
        ("TT101 AND LS3", "type error: AND needs BOOL operands, got REAL", 7),
        ("LS3 OR PT102", "type error: OR needs BOOL operands, got REAL", 5),
        ("NOT TT101", "type error: NOT needs BOOL operands, got REAL", 1),
        ("TT101", "type error: an interlock must be BOOL, this expression is REAL", 1),
        ("0 < TT101 < 100", "unexpected '<': comparisons do not chain, use AND", 11),
        ("TT101 > 8O0", "unexpected 'O0', expected AND, OR, XOR or the end", 10),
        ("TT101 > 80 & LS3", "unexpected character '&'", 12),
        ("TT999 > 1.5.", "unexpected character '.'", 12),
        ("TT101 > - LS3", "unexpected 'LS3', expected a number after '-'", 11),
        ("   ", "empty expression", 0),
        ("", "empty expression", 0),
    ],
)
def test_bad_expressions_are_rejected_with_reason_and_column(text: str, message: str, column: int) -> None:
    assert refused(text) == (message, column)


def test_the_caret_points_at_the_column() -> None:
    text = "TT101 > 80 AND LS3 > 5"
    reason, column = refused(text)
    assert caret(text, column, reason) == "TT101 > 80 AND LS3 > 5\n                   ^ type error: '>' compares BOOL with REAL"
    assert caret("   ", 0, "empty expression") == "empty expression"


def test_too_many_nodes_of_one_kind_is_a_clear_error_and_changes_nothing() -> None:
    tags = plant_tags()
    interlock = Interlock()
    assert interlock.compile("LS3", tags) is True
    fits = " AND ".join(["LS3"] * POOL_SIZE)
    assert interlock.compile(fits, tags) is True
    assert interlock.node_count == 2 * POOL_SIZE - 1
    too_many = " AND ".join(["LS3=BYPASS"] * (POOL_SIZE + 1))
    assert interlock.compile(too_many, tags) is False
    assert (interlock.error_text, interlock.error_column) == (
        f"node pool full: the expression needs {2 * POOL_SIZE + 2} tag nodes, "
        f"the pool holds {POOL_SIZE} (ARRAY[1..{POOL_SIZE}])", 0,
    )
    assert (interlock.source, interlock.valid, interlock.node_count) == (fits, True, 2 * POOL_SIZE - 1)


def test_nesting_deeper_than_the_limit_is_refused() -> None:
    parser, tags = ExpressionParser(), plant_tags()
    assert parser.parse("NOT " * (MAX_DEPTH - 1) + "LS3", tags) is True
    assert parser.nodes[parser.root].kind == NodeKind.NOT_
    assert refused("NOT " * MAX_DEPTH + "LS3") == (f"expression nested deeper than {MAX_DEPTH} levels", 4 * MAX_DEPTH + 1)
    # Parentheses add no node but a level of the parser's recursion: bounded as well.
    assert parser.parse("(" * MAX_DEPTH + "LS3" + ")" * MAX_DEPTH, tags) is True
    assert refused("(" * (MAX_DEPTH + 1) + "LS3" + ")" * (MAX_DEPTH + 1)) == (
        f"expression nested deeper than {MAX_DEPTH} levels", MAX_DEPTH + 1,
    )


def test_text_longer_than_the_source_string_is_refused() -> None:
    text = "LS3" + " OR LS3" * 40
    assert len(text) > MAX_TEXT
    assert refused(text) == (f"expression longer than {MAX_TEXT} characters ({len(text)})", 0)


def test_the_tag_table_refuses_bad_names_duplicates_and_overflow() -> None:
    tags = plant_tags()
    for name, refusal in (
        ("tt101", TagRefusal.DUPLICATE), ("Xor", TagRefusal.KEYWORD), ("1TT", TagRefusal.BAD_NAME),
        ("", TagRefusal.BAD_NAME), ("A-B", TagRefusal.BAD_NAME), ("X" * 17, TagRefusal.BAD_NAME),
    ):
        assert (tags.declare(name, ValueType.BOOL_VALUE), tags.refusal) == (0, refusal), name
    assert tags.count == 4
    assert tags.declare("_x" + "9" * 14, ValueType.REAL_VALUE) == 5
    assert (tags.refusal, tags.find("_X99999999999999")) == (TagRefusal.NONE, 5)
    # Setters refuse an index never declared and a tag of the other type; nothing is written.
    ls3 = tags.find("LS3")
    assert (tags.set_real(ls3, 1.0), tags.set_bool(9, True), tags.set_bool(0, True)) == (False, False, False)
    assert (tags.get_real(ls3), tags.get_bool(9)) == (0.0, False)
    assert tags.set_bool(ls3, True) and tags.get_bool(ls3)
    for i in range(tags.count + 1, MAX_TAGS + 1):
        assert tags.declare(f"T{i}", ValueType.BOOL_VALUE) == i
    assert (tags.declare("ONE_MORE", ValueType.BOOL_VALUE), tags.refusal, tags.count) == (
        0, TagRefusal.TABLE_FULL, MAX_TAGS,
    )


def test_upper_text_changes_only_the_letters() -> None:
    assert upper_text("tt101_a Zz-9") == "TT101_A ZZ-9"
    assert upper_text("") == ""


def test_only_the_interlock_builds_nodes_from_its_pool() -> None:
    interlock = Interlock()
    with pytest.raises(AccessError, match=r"INTERNAL METHOD NodePool\.constant"):
        interlock.pool.constant(ValueType.BOOL_VALUE, 0.0, True)
    assert interlock.pool.node_count == 0


# ---------------------------------------------------------------------------
# Property: the tree agrees with Python's own evaluation of the same text
# ---------------------------------------------------------------------------

REAL_TAGS = ("TT101", "PT102")
BOOL_TAGS = ("LS3", "BYPASS")
CONSTANTS = (-1.5, 0.0, 2.5, 80.0, 80.5)
LEVEL = {"OR": 1, "XOR": 2, "AND": 3, "NOT": 4, "CMP": 5, "ATOM": 6}
PY_RELATION = {">": ">", ">=": ">=", "<": "<", "<=": "<=", "=": "==", "<>": "!="}


@dataclass(frozen=True)
class Expr:
    """A generated expression: its interlock text, its Python text, its precedence level and node count."""

    text: str
    python: str
    level: int
    nodes: dict[str, int]
    height: int


def _merge(*parts: dict[str, int], **extra: int) -> dict[str, int]:
    total: dict[str, int] = {}
    for part in (*parts, extra):
        for kind, n in part.items():
            total[kind] = total.get(kind, 0) + n
    return total


def _wrap(expr: Expr, level: int) -> str:
    return expr.text if expr.level >= level else f"({expr.text})"


def _real_operand() -> st.SearchStrategy[Expr]:
    tags = st.sampled_from(REAL_TAGS).map(lambda name: Expr(name, name, LEVEL["ATOM"], {"tag": 1}, 1))
    numbers = st.sampled_from(CONSTANTS).map(lambda c: Expr(f"{c:g}", repr(c), LEVEL["ATOM"], {"const": 1}, 1))
    return st.one_of(tags, numbers)


def _bool_leaf() -> st.SearchStrategy[Expr]:
    tags = st.sampled_from(BOOL_TAGS).map(lambda name: Expr(name, name, LEVEL["ATOM"], {"tag": 1}, 1))
    literals = st.sampled_from(("TRUE", "FALSE")).map(
        lambda word: Expr(word, word.title(), LEVEL["ATOM"], {"const": 1}, 1)
    )
    comparisons = st.builds(
        lambda a, rel, b: Expr(
            f"{a.text} {rel} {b.text}", f"({a.python} {PY_RELATION[rel]} {b.python})", LEVEL["CMP"],
            _merge(a.nodes, b.nodes, compare=1), 2,
        ),
        _real_operand(), st.sampled_from(tuple(PY_RELATION)), _real_operand(),
    )
    return st.one_of(tags, literals, comparisons)


def _extend(children: st.SearchStrategy[Expr]) -> st.SearchStrategy[Expr]:
    def logic(a: Expr, op: str, b: Expr) -> Expr:
        level = LEVEL[op]
        py = {"AND": "and", "OR": "or", "XOR": "^"}[op]
        return Expr(
            f"{_wrap(a, level)} {op} {_wrap(b, level + 1)}", f"({a.python} {py} {b.python})", level,
            _merge(a.nodes, b.nodes, logic=1), 1 + max(a.height, b.height),
        )

    def negation(a: Expr) -> Expr:
        return Expr(f"NOT {_wrap(a, LEVEL['NOT'])}", f"(not {a.python})", LEVEL["NOT"], _merge(a.nodes, **{"not": 1}),
                    1 + a.height)

    def bool_compare(a: Expr, rel: str, b: Expr) -> Expr:
        return Expr(
            f"{_wrap(a, LEVEL['ATOM'])} {rel} {_wrap(b, LEVEL['ATOM'])}", f"({a.python} {PY_RELATION[rel]} {b.python})",
            LEVEL["CMP"], _merge(a.nodes, b.nodes, compare=1), 1 + max(a.height, b.height),
        )

    def parenthesised(a: Expr) -> Expr:
        return Expr(f"({a.text})", a.python, LEVEL["ATOM"], a.nodes, a.height)

    return st.one_of(
        st.builds(logic, children, st.sampled_from(("AND", "OR", "XOR")), children),
        st.builds(negation, children),
        st.builds(bool_compare, children, st.sampled_from(("=", "<>")), children),
        st.builds(parenthesised, children),
    )


EXPRESSIONS = st.recursive(_bool_leaf(), _extend, max_leaves=10).filter(
    lambda e: e.height <= MAX_DEPTH and all(n <= POOL_SIZE for n in e.nodes.values()) and len(e.text) <= MAX_TEXT
)


def _float32(value: float) -> float:
    return float(struct.unpack("f", struct.pack("f", value))[0])


TAG_VALUES = st.fixed_dictionaries(
    {
        "TT101": st.one_of(st.sampled_from(CONSTANTS), st.floats(-200.0, 200.0, width=32)),
        "PT102": st.one_of(st.sampled_from(CONSTANTS), st.floats(-200.0, 200.0, width=32)),
        "LS3": st.booleans(),
        "BYPASS": st.booleans(),
    }
)


@settings(max_examples=100, deadline=None)
@given(expr=EXPRESSIONS, scans=st.lists(TAG_VALUES, min_size=1, max_size=5))
def test_the_tree_agrees_with_python_on_random_expressions_and_values(
    expr: Expr, scans: list[dict[str, float | bool]]
) -> None:
    tags = plant_tags()
    interlock = Interlock()
    interlock.compile(expr.text, tags)
    assert interlock.node_count == sum(expr.nodes.values())
    for values in scans:
        for name, value in values.items():
            if isinstance(value, bool):
                tags.set_bool(tags.find(name), value)
            else:
                tags.set_real(tags.find(name), value)
        interlock()
        namespace = {name: _float32(v) if not isinstance(v, bool) else v for name, v in values.items()}
        expected = eval(expr.python, {"__builtins__": {}}, namespace)  # noqa: S307 - generated test input
        assert interlock.permissive is bool(expected), (expr.text, expr.python, values)
