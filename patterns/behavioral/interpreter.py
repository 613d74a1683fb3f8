"""Interpreter: a tiny interlock language for recipes, parsed once and evaluated every scan.

Intent
------

Given a language, define a representation for its grammar (a tree of
objects, one class per rule) and an interpreter that evaluates sentences by
walking that tree.

The PLC problem
---------------

A batch plant runs many recipes on the same equipment, and each recipe step
carries its own permissive: "transfer only when the batch is hot, the
receiving tank is not full and the line pressure is low, unless the
operator bypasses the pressure check". Hard-coding each permissive means a
program download for every recipe change. Instead the recipe holds the
condition as text::

    TT101 > 80 AND NOT LS3 AND (PT102 < 2.5 OR BYPASS)

At configuration time (recipe download, not every scan) a tokenizer and a
recursive-descent parser check it against the tag table (unknown tags, type
errors such as ``LS3 > 5`` on a BOOL, unbalanced parentheses) and build an
expression tree from a static pool of node FBs. Every scan the interlock FB
evaluates that tree: each node once, no allocation, a depth and a node count
fixed when the text was accepted, so the scan time is bounded.

The language (case-insensitive, like ST)::

    expression := xor_term { OR xor_term }
    xor_term   := and_term { XOR and_term }
    and_term   := unary { AND unary }
    unary      := NOT unary | comparison
    comparison := operand [ ( > | >= | < | <= | = | <> ) operand ]
    operand    := number | - number | TRUE | FALSE | tag | ( expression )

``NOT`` applies to a whole comparison (``NOT TT101 > 80`` is
``NOT (TT101 > 80)``); comparisons do not chain; ``= <>`` compare two REALs
or two BOOLs; ``AND OR XOR NOT`` take BOOLs; the whole interlock is BOOL.

Roles
-----

- Abstract expression → ``IExpression`` (``I_Expression``)
- Terminal expressions → ``ConstantNode`` (``FB_ConstantNode``), ``TagNode``
  (``FB_TagNode``)
- Non-terminal expressions → ``CompareNode`` (``FB_CompareNode``),
  ``LogicNode`` (``FB_LogicNode``: AND / OR / XOR), ``NotNode``
  (``FB_NotNode``)
- Context → ``TagTable`` (``FB_TagTable``) behind ``ISymbolTable``
  (``I_SymbolTable``), the REAL / BOOL tags the nodes read
- Node pool → ``NodePool`` (``FB_NodePool``): fixed arrays of each node kind
- Client → ``Interlock`` (``FB_Interlock``), with ``compile`` (tokenizer +
  parser, Python, run once) and the scan-time evaluation in its body;
  ``TransferMain`` (``PRG_TransferMain``) wires a recipe step's permissive

IEC 61131-3 mapping
-------------------

::

    TYPE E_ValueType : (BOOL_VALUE := 1, REAL_VALUE := 2) INT; END_TYPE
    TYPE E_Operator : (GT, GE, LT, LE, EQ, NE, AND_, OR_, XOR_) INT; END_TYPE

    INTERFACE I_Expression
        METHOD EvaluateBool : BOOL
        METHOD EvaluateReal : REAL
        PROPERTY ValueType : E_ValueType   (Get)

    FUNCTION_BLOCK FB_CompareNode IMPLEMENTS I_Expression
        VAR op : E_Operator; operandType : E_ValueType;
            left, right : I_Expression; END_VAR
        METHOD INTERNAL Configure

    FUNCTION_BLOCK FB_TagNode IMPLEMENTS I_Expression
        VAR symbols : I_SymbolTable; index : INT; END_VAR

    FUNCTION_BLOCK FB_NodePool
        VAR compares : ARRAY[1..POOL_SIZE] OF FB_CompareNode; ... END_VAR

    FUNCTION_BLOCK FB_Interlock
        VAR_OUTPUT permissive : BOOL; valid : BOOL; END_VAR
        VAR pool : FB_NodePool; root : I_Expression; END_VAR
        METHOD Disable                     // valid := FALSE; root := 0;
        permissive := valid AND_THEN root.EvaluateBool();

When not to use it on a PLC
---------------------------

When the conditions are fixed at design time, write them in ST: the
compiler checks them, the online view shows them, and nobody needs to learn
a second language. An interpreter also moves errors from compile time to
recipe-download time, so it needs the careful error messages this one has.
And never put safety interlocks into a recipe language: those belong in the
safety PLC, fixed and validated.

References
----------

- E. Gamma, R. Helm, R. Johnson, J. Vlissides, *Design Patterns: Elements of
  Reusable Object-Oriented Software*, Addison-Wesley 1994, "Interpreter".
- IEC 61131-3:2013 (3rd edition), *Programmable controllers - Part 3:
  Programming languages*: interfaces and methods of function blocks; the
  operator precedence of ST (NOT, comparison, AND, XOR, OR); ACCESS
  specifier INTERNAL. PROPERTY is a CODESYS / TwinCAT extension.
- ANSI/ISA-88.00.01 (IEC 61512-1) *Batch Control*: recipe procedures and
  the transition conditions between their steps.
- Beckhoff InfoSys, TwinCAT 3 PLC: "Interface", "Method", "Property",
  "ST operators".
- CODESYS Online Help: "Object: Interface", "Object: Method",
  "ST Expression".
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field

from iecoop import (
    ABSTRACT,
    ARRAY,
    BOOL,
    INT,
    INTERNAL,
    NULL,
    PRIVATE,
    REAL,
    STRING,
    UDINT,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    FunctionBlock,
    IecEnum,
    Interface,
    Program,
    T,
    method,
    prop,
)
from iecoop.runtime import Runtime, Task
from iecoop.stdlib import R_TRIG
from patterns.showcase.entry import Column, Scenario, Showcase, flag

__all__ = [
    "MAX_DEPTH",
    "MAX_TAGS",
    "MAX_TEXT",
    "POOL_SIZE",
    "CompareNode",
    "ConstantNode",
    "ExpressionError",
    "IExpression",
    "ISymbolTable",
    "Interlock",
    "LogicNode",
    "Node",
    "NodePool",
    "NotNode",
    "Operator",
    "TagNode",
    "TagTable",
    "Token",
    "TransferMain",
    "ValueType",
    "count_nodes",
    "main",
    "parse",
    "tokenize",
]

POOL_SIZE = 12
MAX_DEPTH = 16
MAX_TAGS = 16
MAX_TEXT = 200
TAG_LENGTH = 16


class ValueType(IecEnum):
    """``TYPE E_ValueType : (BOOL_VALUE := 1, REAL_VALUE := 2) INT; END_TYPE``"""

    BOOL_VALUE = 1
    REAL_VALUE = 2


class Operator(IecEnum):
    """``TYPE E_Operator``: the binary operators of the language."""

    GT = 1
    GE = 2
    LT = 3
    LE = 4
    EQ = 5
    NE = 6
    AND_ = 7
    OR_ = 8
    XOR_ = 9


TYPE_NAMES = {ValueType.BOOL_VALUE: "BOOL", ValueType.REAL_VALUE: "REAL"}


# ---------------------------------------------------------------------------
# The context: tags the expressions read
# ---------------------------------------------------------------------------


class ISymbolTable(Interface):
    """``INTERFACE I_SymbolTable``: tag lookup at configuration, tag values at run time."""

    @method
    def find(self, name: STRING) -> INT:
        raise NotImplementedError

    @method
    def kind_of(self, index: INT) -> ValueType:
        raise NotImplementedError

    @method
    def get_real(self, index: INT) -> REAL:
        raise NotImplementedError

    @method
    def get_bool(self, index: INT) -> BOOL:
        raise NotImplementedError


class TagTable(FunctionBlock, ISymbolTable):
    """``FUNCTION_BLOCK FB_TagTable IMPLEMENTS I_SymbolTable``: up to MAX_TAGS REAL / BOOL tags.

    Names follow ST identifiers and are case-insensitive. ``declare`` returns
    the tag's index (resolved once); the program writes the I/O image into
    the table every scan with ``set_real`` / ``set_bool`` by index.
    """

    names: ARRAY[STRING] = VAR(bounds=(1, MAX_TAGS), length=TAG_LENGTH)
    kinds: ARRAY[ValueType] = VAR(bounds=(1, MAX_TAGS))
    reals: ARRAY[REAL] = VAR(bounds=(1, MAX_TAGS))
    bools: ARRAY[BOOL] = VAR(bounds=(1, MAX_TAGS))
    count: INT = VAR_OUTPUT(0)

    @method
    def declare(self, name: STRING, kind: ValueType) -> INT:
        if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name) or len(name) > TAG_LENGTH:
            raise ValueError(
                f"TagTable: {name!r} is not a tag name (an ST identifier of at most {TAG_LENGTH} characters)"
            )
        if name.upper() in KEYWORDS:
            raise ValueError(f"TagTable: {name!r} is a keyword of the interlock language")
        if self.find(name):
            raise ValueError(f"TagTable: tag {name!r} is already declared")
        if self.count >= MAX_TAGS:
            raise ValueError(f"TagTable is full: {MAX_TAGS} tags (ARRAY[1..{MAX_TAGS}])")
        self.count += 1
        self.names[self.count] = name.upper()
        self.kinds[self.count] = kind
        return self.count

    @method
    def find(self, name: STRING) -> INT:
        wanted = name.upper()
        for i in range(1, self.count + 1):
            if self.names[i] == wanted:
                return i
        return 0

    @method
    def kind_of(self, index: INT) -> ValueType:
        self.check(index)
        return ValueType(self.kinds[index])

    @method
    def get_real(self, index: INT) -> REAL:
        self.check(index, ValueType.REAL_VALUE)
        return self.reals[index]

    @method
    def get_bool(self, index: INT) -> BOOL:
        self.check(index, ValueType.BOOL_VALUE)
        return self.bools[index]

    @method
    def set_real(self, index: INT, value: REAL) -> None:
        self.check(index, ValueType.REAL_VALUE)
        self.reals[index] = value

    @method
    def set_bool(self, index: INT, value: BOOL) -> None:
        self.check(index, ValueType.BOOL_VALUE)
        self.bools[index] = value

    @method(PRIVATE)
    def check(self, index: INT, kind: ValueType | None = None) -> None:
        if not 1 <= index <= self.count:
            raise ValueError(f"TagTable: no tag {index} (1..{self.count} are declared)")
        if kind is not None and self.kinds[index] != kind:
            raise ValueError(f"TagTable: tag {self.names[index]} is {TYPE_NAMES[ValueType(self.kinds[index])]}")


# ---------------------------------------------------------------------------
# The expression nodes
# ---------------------------------------------------------------------------


class IExpression(Interface):
    """``INTERFACE I_Expression``: every node of the tree, terminal or not."""

    @method
    def evaluate_bool(self) -> BOOL:
        raise NotImplementedError

    @method
    def evaluate_real(self) -> REAL:
        raise NotImplementedError

    @prop
    def value_type(self) -> ValueType:
        raise NotImplementedError


class ExpressionNode(FunctionBlock, IExpression, abstract=True):
    """``FUNCTION_BLOCK ABSTRACT FB_ExpressionNode IMPLEMENTS I_Expression``: what every node shares.

    ``kind`` is the node's value type, fixed by the parser; ``evaluations``
    counts the node's evaluations, so a test can prove that one scan
    evaluates each node exactly once.
    """

    kind: ValueType = VAR(ValueType.BOOL_VALUE)
    evaluations: UDINT = VAR_OUTPUT(0)

    @prop
    def value_type(self) -> ValueType:
        return ValueType(self.kind)

    @method(ABSTRACT)
    def evaluate_bool(self) -> BOOL:
        raise NotImplementedError

    @method
    def evaluate_real(self) -> REAL:
        raise ValueError(f"{type(self).__name__}: a BOOL node has no REAL value")


class ConstantNode(ExpressionNode):
    """``FUNCTION_BLOCK FB_ConstantNode EXTENDS FB_ExpressionNode``: a REAL or BOOL literal."""

    real_value: REAL = VAR(0.0)
    bool_value: BOOL = VAR(False)

    @method(INTERNAL)
    def configure(self, kind: ValueType, real_value: REAL, bool_value: BOOL) -> None:
        self.kind, self.real_value, self.bool_value = kind, real_value, bool_value
        self.evaluations = 0

    @method
    def evaluate_bool(self) -> BOOL:
        self.evaluations += 1
        return self.bool_value

    @method
    def evaluate_real(self) -> REAL:
        self.evaluations += 1
        return self.real_value


class TagNode(ExpressionNode):
    """``FUNCTION_BLOCK FB_TagNode EXTENDS FB_ExpressionNode``: reads one tag of the symbol table."""

    symbols: ISymbolTable = VAR()
    index: INT = VAR(0)

    @method(INTERNAL)
    def configure(self, symbols: ISymbolTable, index: INT) -> None:
        self.symbols, self.index = symbols, index
        self.kind = symbols.kind_of(index)
        self.evaluations = 0

    @method
    def evaluate_bool(self) -> BOOL:
        self.evaluations += 1
        return self.symbols.get_bool(self.index)

    @method
    def evaluate_real(self) -> REAL:
        self.evaluations += 1
        return self.symbols.get_real(self.index)


class CompareNode(ExpressionNode):
    """``FUNCTION_BLOCK FB_CompareNode EXTENDS FB_ExpressionNode``: ``> >= < <= = <>``, a BOOL result."""

    op: Operator = VAR(Operator.EQ)
    operand_type: ValueType = VAR(ValueType.REAL_VALUE)
    left: IExpression = VAR()
    right: IExpression = VAR()

    @method(INTERNAL)
    def configure(self, op: Operator, operand_type: ValueType, left: IExpression, right: IExpression) -> None:
        self.op, self.operand_type, self.left, self.right = op, operand_type, left, right
        self.kind = ValueType.BOOL_VALUE
        self.evaluations = 0

    @method
    def evaluate_bool(self) -> BOOL:
        self.evaluations += 1
        op = self.op
        if self.operand_type == ValueType.BOOL_VALUE:
            a, b = self.left.evaluate_bool(), self.right.evaluate_bool()
            return a == b if op == Operator.EQ else a != b
        x, y = self.left.evaluate_real(), self.right.evaluate_real()
        if op == Operator.GT:
            return x > y
        if op == Operator.GE:
            return x >= y
        if op == Operator.LT:
            return x < y
        if op == Operator.LE:
            return x <= y
        if op == Operator.EQ:
            return x == y
        return x != y


class LogicNode(ExpressionNode):
    """``FUNCTION_BLOCK FB_LogicNode EXTENDS FB_ExpressionNode``: AND / OR / XOR of two BOOLs.

    Both operands are evaluated every scan, as ST's AND does (not AND_THEN):
    the scan time does not depend on the tag values.
    """

    op: Operator = VAR(Operator.AND_)
    left: IExpression = VAR()
    right: IExpression = VAR()

    @method(INTERNAL)
    def configure(self, op: Operator, left: IExpression, right: IExpression) -> None:
        self.op, self.left, self.right = op, left, right
        self.kind = ValueType.BOOL_VALUE
        self.evaluations = 0

    @method
    def evaluate_bool(self) -> BOOL:
        self.evaluations += 1
        a, b = self.left.evaluate_bool(), self.right.evaluate_bool()
        if self.op == Operator.AND_:
            return a and b
        if self.op == Operator.OR_:
            return a or b
        return a != b


class NotNode(ExpressionNode):
    """``FUNCTION_BLOCK FB_NotNode EXTENDS FB_ExpressionNode``: NOT of a BOOL."""

    operand: IExpression = VAR()

    @method(INTERNAL)
    def configure(self, operand: IExpression) -> None:
        self.operand = operand
        self.kind = ValueType.BOOL_VALUE
        self.evaluations = 0

    @method
    def evaluate_bool(self) -> BOOL:
        self.evaluations += 1
        return not self.operand.evaluate_bool()


class NodePool(FunctionBlock):
    """``FUNCTION_BLOCK FB_NodePool``: ``ARRAY[1..POOL_SIZE]`` of each node kind, handed out in order.

    Nothing is allocated at run time; ``clear`` makes the whole pool free
    again (its nodes are only reused by the next ``compile``). Asking a full
    array for a node is an error naming the array.
    """

    constants: ARRAY[ConstantNode] = VAR(bounds=(1, POOL_SIZE))
    tags: ARRAY[TagNode] = VAR(bounds=(1, POOL_SIZE))
    compares: ARRAY[CompareNode] = VAR(bounds=(1, POOL_SIZE))
    logics: ARRAY[LogicNode] = VAR(bounds=(1, POOL_SIZE))
    nots: ARRAY[NotNode] = VAR(bounds=(1, POOL_SIZE))
    used: ARRAY[INT] = VAR_OUTPUT(bounds=(1, 5))

    @method
    def clear(self) -> None:
        for i in range(1, 6):
            self.used[i] = 0

    @method(INTERNAL)
    def take(self, slot: INT, what: STRING) -> INT:
        if self.used[slot] >= POOL_SIZE:
            raise ExpressionError(f"node pool full: more than {POOL_SIZE} {what} nodes (ARRAY[1..{POOL_SIZE}])")
        self.used[slot] += 1
        return self.used[slot]

    @method(INTERNAL)
    def constant(self, kind: ValueType, real_value: REAL, bool_value: BOOL) -> IExpression:
        node = self.constants[self.take(1, "constant")]
        node.configure(kind, real_value, bool_value)
        return node

    @method(INTERNAL)
    def tag(self, symbols: ISymbolTable, index: INT) -> IExpression:
        node = self.tags[self.take(2, "tag")]
        node.configure(symbols, index)
        return node

    @method(INTERNAL)
    def compare(self, op: Operator, operand_type: ValueType, left: IExpression, right: IExpression) -> IExpression:
        node = self.compares[self.take(3, "comparison")]
        node.configure(op, operand_type, left, right)
        return node

    @method(INTERNAL)
    def logic(self, op: Operator, left: IExpression, right: IExpression) -> IExpression:
        node = self.logics[self.take(4, "AND/OR/XOR")]
        node.configure(op, left, right)
        return node

    @method(INTERNAL)
    def negation(self, operand: IExpression) -> IExpression:
        node = self.nots[self.take(5, "NOT")]
        node.configure(operand)
        return node

    @prop
    def node_count(self) -> INT:
        return sum(self.used)


# ---------------------------------------------------------------------------
# Configuration time: tokenizer and recursive-descent parser (Python, run once)
# ---------------------------------------------------------------------------


class ExpressionError(ValueError):
    """A rejected interlock expression; ``position`` is the 1-based column (0: the expression as a whole)."""

    def __init__(self, message: str, text: str = "", position: int = 0) -> None:
        where = f" at column {position}" if position else ""
        super().__init__(f"{message}{where}" + (f" in {text!r}" if text else ""))
        self.reason, self.text, self.position = message, text, position

    def caret(self) -> str:
        """The text with a ``^`` under the column, as an HMI or a log would show it."""
        return f"{self.text}\n{' ' * (self.position - 1)}^ {self.reason}" if self.position else self.reason


KEYWORDS = frozenset({"AND", "OR", "XOR", "NOT", "TRUE", "FALSE"})
RELATIONS = {
    ">": Operator.GT, ">=": Operator.GE, "<": Operator.LT, "<=": Operator.LE, "=": Operator.EQ, "<>": Operator.NE,
}
_TOKEN = re.compile(r"\s*(?:(?P<number>\d+(?:\.\d+)?)|(?P<word>[A-Za-z_][A-Za-z0-9_]*)|(?P<symbol><>|>=|<=|[<>=()\-]))")


@dataclass(frozen=True)
class Token:
    """One token: ``kind`` is ``number``, ``word``, ``keyword``, ``symbol`` or ``end``; ``column`` is 1-based."""

    kind: str
    text: str
    column: int


def tokenize(text: str) -> list[Token]:
    """Split an interlock expression into tokens, ending with an ``end`` token.

    >>> [t.text for t in tokenize("TT101>=80 and not(LS3)")]
    ['TT101', '>=', '80', 'AND', 'NOT', '(', 'LS3', ')', '']
    """
    tokens: list[Token] = []
    pos = 0
    while True:
        while pos < len(text) and text[pos].isspace():
            pos += 1
        if pos == len(text):
            tokens.append(Token("end", "", pos + 1))
            return tokens
        match = _TOKEN.match(text, pos)
        if match is None:
            raise ExpressionError(f"unexpected character {text[pos]!r}", text, pos + 1)
        kind = match.lastgroup or "symbol"
        value = match.group(kind)
        column = match.start(kind) + 1
        if kind == "word" and value.upper() in KEYWORDS:
            kind, value = "keyword", value.upper()
        tokens.append(Token(kind, value, column))
        pos = match.end()


@dataclass
class Node:
    """The parse tree, before it is built from the pool: ``kind`` is const / tag / compare / logic / not."""

    kind: str
    value_type: ValueType
    column: int
    op: Operator = Operator.EQ
    real_value: float = 0.0
    bool_value: bool = False
    index: int = 0
    children: list[Node] = field(default_factory=list)


class _Parser:
    """One parse: a method per grammar rule, each returning a type-checked ``Node``."""

    def __init__(self, text: str, symbols: ISymbolTable) -> None:
        self.text, self.symbols = text, symbols
        self.tokens = tokenize(text)
        self.pos = 0
        self.open_parens: list[int] = []

    @property
    def token(self) -> Token:
        return self.tokens[self.pos]

    def advance(self) -> Token:
        token = self.tokens[self.pos]
        self.pos += 1
        return token

    def at(self, kind: str, *texts: str) -> bool:
        return self.token.kind == kind and self.token.text in texts

    def error(self, message: str, column: int) -> ExpressionError:
        return ExpressionError(message, self.text, column)

    def unexpected(self, expected: str) -> ExpressionError:
        token = self.token
        if token.kind == "end" and self.open_parens:
            return self.error("unbalanced parentheses: '(' is never closed", self.open_parens[-1])
        if token.kind == "end":
            return self.error(f"unexpected end of expression, expected {expected}", token.column)
        if token.text == ")" and not self.open_parens:
            return self.error("unbalanced parentheses: ')' has no '(' to close", token.column)
        return self.error(f"unexpected {token.text!r}, expected {expected}", token.column)

    def require_bool(self, node: Node, what: str, column: int) -> None:
        if node.value_type != ValueType.BOOL_VALUE:
            raise self.error(f"type error: {what} needs BOOL operands, got REAL", column)

    def parse(self) -> Node:
        if self.token.kind == "end":
            raise self.error("empty expression", 0)
        node = self.expression()
        if self.token.kind != "end":
            raise self.unexpected("AND, OR, XOR or the end")
        if node.value_type != ValueType.BOOL_VALUE:
            raise self.error("type error: an interlock must be BOOL, this expression is REAL", 1)
        too_deep = _deeper_than(node, MAX_DEPTH)
        if too_deep is not None:
            raise self.error(f"expression nested deeper than {MAX_DEPTH} levels", too_deep.column)
        return node

    # One method per rule, lowest precedence first.

    def expression(self) -> Node:
        return self.logic_chain("OR", Operator.OR_, self.xor_term)

    def xor_term(self) -> Node:
        return self.logic_chain("XOR", Operator.XOR_, self.and_term)

    def and_term(self) -> Node:
        return self.logic_chain("AND", Operator.AND_, self.unary)

    def logic_chain(self, keyword: str, op: Operator, operand: Callable[[], Node]) -> Node:
        left = operand()
        while self.at("keyword", keyword):
            column = self.advance().column
            right = operand()
            self.require_bool(left, keyword, column)
            self.require_bool(right, keyword, column)
            left = Node("logic", ValueType.BOOL_VALUE, column, op=op, children=[left, right])
        return left

    def unary(self) -> Node:
        if not self.at("keyword", "NOT"):
            return self.comparison()
        column = self.advance().column
        operand = self.unary()
        self.require_bool(operand, "NOT", column)
        return Node("not", ValueType.BOOL_VALUE, column, children=[operand])

    def comparison(self) -> Node:
        left = self.operand()
        if not self.at("symbol", *RELATIONS):
            return left
        symbol = self.advance()
        op = RELATIONS[symbol.text]
        right = self.operand()
        if self.at("symbol", *RELATIONS):
            raise self.error(f"unexpected {self.token.text!r}: comparisons do not chain, use AND", self.token.column)
        if left.value_type != right.value_type:
            raise self.error(
                f"type error: {symbol.text!r} compares {TYPE_NAMES[left.value_type]} with "
                f"{TYPE_NAMES[right.value_type]}", symbol.column,
            )
        if left.value_type == ValueType.BOOL_VALUE and op not in (Operator.EQ, Operator.NE):
            raise self.error(f"type error: {symbol.text!r} needs REAL operands, got BOOL", symbol.column)
        return Node("compare", ValueType.BOOL_VALUE, symbol.column, op=op, children=[left, right])

    def operand(self) -> Node:
        token = self.token
        if token.kind == "number":
            self.advance()
            return Node("const", ValueType.REAL_VALUE, token.column, real_value=float(token.text))
        if self.at("symbol", "-"):
            self.advance()
            if self.token.kind != "number":
                raise self.unexpected("a number after '-'")
            return Node("const", ValueType.REAL_VALUE, token.column, real_value=-float(self.advance().text))
        if self.at("keyword", "TRUE", "FALSE"):
            self.advance()
            return Node("const", ValueType.BOOL_VALUE, token.column, bool_value=token.text == "TRUE")
        if token.kind == "word":
            self.advance()
            index = self.symbols.find(token.text)
            if index == 0:
                raise self.error(f"unknown tag {token.text!r}", token.column)
            return Node("tag", self.symbols.kind_of(index), token.column, index=index)
        if self.at("symbol", "("):
            self.advance()
            self.open_parens.append(token.column)
            inner = self.expression()
            if not self.at("symbol", ")"):
                raise self.unexpected("')'")
            self.advance()
            self.open_parens.pop()
            return inner
        raise self.unexpected("a tag, a number, TRUE, FALSE, NOT or '('")


def _deeper_than(node: Node, limit: int, depth: int = 1) -> Node | None:
    """The first node below ``limit`` levels, or None: the evaluation's call depth is the tree's height."""
    if depth > limit:
        return node
    for child in node.children:
        found = _deeper_than(child, limit, depth + 1)
        if found is not None:
            return found
    return None


def parse(text: str, symbols: ISymbolTable) -> Node:
    """Parse and type-check an interlock expression against ``symbols``; nothing is built yet.

    >>> tags = TagTable()
    >>> tags.declare("TT101", ValueType.REAL_VALUE), tags.declare("LS3", ValueType.BOOL_VALUE)
    (1, 2)
    >>> parse("TT101 > 80 AND NOT LS3", tags).op.name
    'AND_'
    >>> parse("LS3 > 5", tags)
    Traceback (most recent call last):
    ...
    patterns.behavioral.interpreter.ExpressionError: type error: '>' compares BOOL with REAL at column 5 in 'LS3 > 5'
    """
    if len(text) > MAX_TEXT:
        raise ExpressionError(f"expression longer than {MAX_TEXT} characters ({len(text)})")
    return _Parser(text, symbols).parse()


def count_nodes(node: Node, counts: dict[str, int] | None = None) -> dict[str, int]:
    """How many nodes of each kind the tree needs from the pool."""
    counts = {} if counts is None else counts
    counts[node.kind] = counts.get(node.kind, 0) + 1
    for child in node.children:
        count_nodes(child, counts)
    return counts


POOL_ARRAYS = {"const": "constant", "tag": "tag", "compare": "comparison", "logic": "AND/OR/XOR", "not": "NOT"}


# ---------------------------------------------------------------------------
# The client: the interlock FB
# ---------------------------------------------------------------------------


class Interlock(FunctionBlock):
    """``FUNCTION_BLOCK FB_Interlock``: owns a node pool, evaluates its tree once per call.

    ``compile(text, symbols)`` runs at configuration: it parses, checks the
    pool has room, and only then rebuilds the tree, so a rejected text
    leaves the running interlock as it was. Without an accepted expression
    the interlock is not ``valid`` and never permissive (fail-safe);
    ``disable`` takes an accepted one out of service again.
    """

    permissive: BOOL = VAR_OUTPUT(False)
    valid: BOOL = VAR_OUTPUT(False)
    node_count: INT = VAR_OUTPUT(0)
    scans: UDINT = VAR_OUTPUT(0)
    source: STRING = VAR_OUTPUT("", length=MAX_TEXT)
    pool: NodePool = VAR()
    root: IExpression = VAR()

    @method
    def compile(self, text: STRING, symbols: ISymbolTable) -> None:
        tree = parse(text, symbols)
        for kind, needed in count_nodes(tree).items():
            if needed > POOL_SIZE:
                raise ExpressionError(
                    f"node pool full: the expression needs {needed} {POOL_ARRAYS[kind]} nodes, "
                    f"the pool holds {POOL_SIZE} (ARRAY[1..{POOL_SIZE}])", text,
                )
        self.pool.clear()
        self.root = self.build(tree, symbols)
        self.node_count = self.pool.node_count
        self.source = text
        self.valid = True

    @method
    def disable(self) -> None:
        """Drop the expression: not ``valid``, never permissive, the tree released (``root := 0``)."""
        self.valid = False
        self.root = NULL
        self.pool.clear()
        self.node_count = 0
        self.source = ""

    @method(INTERNAL)
    def build(self, node: Node, symbols: ISymbolTable) -> IExpression:
        pool = self.pool
        if node.kind == "const":
            return pool.constant(node.value_type, node.real_value, node.bool_value)
        if node.kind == "tag":
            return pool.tag(symbols, node.index)
        if node.kind == "not":
            return pool.negation(self.build(node.children[0], symbols))
        left, right = self.build(node.children[0], symbols), self.build(node.children[1], symbols)
        if node.kind == "compare":
            return pool.compare(node.op, node.children[0].value_type, left, right)
        return pool.logic(node.op, left, right)

    def body(self) -> None:
        self.scans += 1
        self.permissive = self.valid and self.root.evaluate_bool()


# ---------------------------------------------------------------------------
# The program: a recipe step's transfer permissive
# ---------------------------------------------------------------------------

TRANSFER_PERMIT = "TT101 > 80 AND NOT LS3 AND (PT102 < 2.5 OR BYPASS)"


class TransferMain(Program):
    """``PROGRAM PRG_TransferMain``: the transfer pump runs only while the recipe's permissive holds.

    The inputs are the I/O image (set by the plant, here by the caller); each
    scan they are copied into the tag table by index, then the interlock is
    evaluated once. The expression is compiled in FB_init, i.e. at download.
    """

    tt101: REAL = VAR_INPUT(20.0)
    ls3: BOOL = VAR_INPUT(False)
    pt102: REAL = VAR_INPUT(1.0)
    bypass: BOOL = VAR_INPUT(False)
    pump_on: BOOL = VAR_OUTPUT(False)
    pump_starts: UDINT = VAR_OUTPUT(0)
    tags: TagTable = VAR()
    transfer: Interlock = VAR()
    start_edge: R_TRIG = VAR()
    i_tt101: INT = VAR(0)
    i_ls3: INT = VAR(0)
    i_pt102: INT = VAR(0)
    i_bypass: INT = VAR(0)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
        self.i_tt101 = self.tags.declare("TT101", ValueType.REAL_VALUE)
        self.i_ls3 = self.tags.declare("LS3", ValueType.BOOL_VALUE)
        self.i_pt102 = self.tags.declare("PT102", ValueType.REAL_VALUE)
        self.i_bypass = self.tags.declare("BYPASS", ValueType.BOOL_VALUE)
        self.transfer.compile(TRANSFER_PERMIT, self.tags)
        return True

    def body(self) -> None:
        self.tags.set_real(self.i_tt101, self.tt101)
        self.tags.set_bool(self.i_ls3, self.ls3)
        self.tags.set_real(self.i_pt102, self.pt102)
        self.tags.set_bool(self.i_bypass, self.bypass)
        self.transfer()
        self.pump_on = self.transfer.permissive
        self.start_edge(CLK=self.pump_on)
        if self.start_edge.Q:
            self.pump_starts += 1


def main() -> None:
    """Heat a batch, let the interlock release and block the transfer pump, and reject two bad recipe texts.

    >>> main()
    permissive: TT101 > 80 AND NOT LS3 AND (PT102 < 2.5 OR BYPASS) (12 nodes)
    t=  600 ms  pump ON   TT101= 81.0 LS3=False PT102=1.0 BYPASS=False
    t=  700 ms  pump OFF  TT101= 90.0 LS3=False PT102=3.0 BYPASS=False
    t=  800 ms  pump ON   TT101= 90.0 LS3=False PT102=3.0 BYPASS=True
    t=  900 ms  pump OFF  TT101= 90.0 LS3=True  PT102=3.0 BYPASS=True
    TT101 > 80 AND NOT LS3)
                          ^ unbalanced parentheses: ')' has no '(' to close
    LS3 > 5 OR BYPASS
        ^ type error: '>' compares BOOL with REAL
    still active: TT101 > 80 AND NOT LS3 AND (PT102 < 2.5 OR BYPASS)
    """
    program = TransferMain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    print(f"permissive: {program.transfer.source} ({program.transfer.node_count} nodes)")
    pump = False

    def step(cycles: int) -> None:
        nonlocal pump
        for _ in range(cycles):
            rt.run(cycles=1)
            if program.pump_on != pump:
                pump = program.pump_on
                print(
                    f"t={rt.time_ms - 10:5d} ms  pump {'ON ' if pump else 'OFF'}  TT101={program.tt101:5.1f} "
                    f"LS3={program.ls3!s:<5} PT102={program.pt102:.1f} BYPASS={program.bypass}"
                )

    for _ in range(70):
        program.tt101 = program.tt101 + 1.0
        step(1)
    program.pt102 = 3.0
    step(10)
    program.bypass = True
    step(10)
    program.ls3 = True
    step(10)
    for bad in ("TT101 > 80 AND NOT LS3)", "LS3 > 5 OR BYPASS"):
        try:
            program.transfer.compile(bad, program.tags)
        except ExpressionError as error:
            print(error.caret())
    print(f"still active: {program.transfer.source}")


def _heat(scenario: Scenario, cycle: int) -> None:
    prog = scenario.program
    if cycle <= 70:
        prog.tt101 = 20.0 + cycle
    prog.pt102 = 3.0 if cycle > 70 else 1.0
    prog.bypass = cycle > 80
    prog.ls3 = cycle > 90


SHOWCASE = Showcase(
    use_when="conditions arrive with the recipe at download time rather than at design time",
    columns=(
        Column("TT101", lambda p: p.tt101, ".1f", watch=False),
        Column("LS3", lambda p: p.ls3),
        Column("PT102", lambda p: p.pt102, ".1f"),
        Column("BYPASS", lambda p: p.bypass),
        Column("pump", lambda p: p.pump_on, flag),
        Column("starts", lambda p: p.pump_starts),
    ),
    script=_heat,
    cycles=100,
    tour_cycles=100,
)
