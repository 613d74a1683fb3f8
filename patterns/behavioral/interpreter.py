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
recursive-descent parser, written in ST with LEN, MID, FIND and CONCAT,
check it against the tag table (unknown tags, type errors such as
``LS3 > 5`` on a BOOL, unbalanced parentheses) and build an expression tree
from a static pool of node FBs. A refused text is answered with the reason
and the column, for the HMI to point at, and the running expression stays. Every scan the interlock FB
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
- Parser → ``ExpressionParser`` (``FB_ExpressionParser``): the tokens and
  the checked parse tree in bounded arrays of ``Token`` / ``ParseNode``
  (``ST_Token``, ``ST_ParseNode``), one method per grammar rule
- Client → ``Interlock`` (``FB_Interlock``), with ``compile`` (parse, check
  the pool, build; run once) and the scan-time evaluation in its body;
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

    FUNCTION_BLOCK FB_ExpressionParser
        VAR_OUTPUT tokens : ARRAY[1..MAX_TOKENS] OF ST_Token;
                   nodes : ARRAY[1..MAX_TEXT] OF ST_ParseNode; root : INT;
                   error : BOOL; errorText : STRING(120); errorColumn : INT; END_VAR
        METHOD Parse : BOOL   VAR_INPUT text : STRING; symbols : I_SymbolTable; END_VAR
        METHOD PRIVATE Expression : INT    // OR, calls XorTerm, AndTerm, Unary ...

    FUNCTION_BLOCK FB_Interlock
        VAR_OUTPUT permissive : BOOL; valid : BOOL;
                   error : BOOL; errorText : STRING(120); errorColumn : INT; END_VAR
        VAR parser : FB_ExpressionParser; pool : FB_NodePool; root : I_Expression; END_VAR
        METHOD Compile : BOOL   VAR_INPUT text : STRING; symbols : I_SymbolTable; END_VAR
        METHOD Disable                     // valid := FALSE; root := 0;
        IF valid THEN permissive := root.EvaluateBool(); ELSE permissive := FALSE; END_IF

When not to use it on a PLC
---------------------------

When the conditions are fixed at design time, write them in ST: the
compiler checks them, the online view shows them, and nobody needs to learn
a second language. An interpreter also moves errors from compile time to
recipe-download time, so it needs the careful error messages this one has,
and its parser costs PLC memory (the token and node arrays) and a burst of
scan time when a recipe arrives.
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

from iecoop import (
    ABSTRACT,
    ARRAY,
    BOOL,
    INT,
    INTERNAL,
    LREAL,
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
    Struct,
    T,
    method,
    prop,
)
from iecoop.functions import CONCAT, FIND, MID
from iecoop.runtime import Runtime, Task
from iecoop.stdlib import R_TRIG
from patterns.showcase.entry import Column, Scenario, Showcase, flag

__all__ = [
    "MAX_DEPTH",
    "MAX_TAGS",
    "MAX_TEXT",
    "MAX_TOKENS",
    "POOL_SIZE",
    "CompareNode",
    "ConstantNode",
    "ExpressionParser",
    "IExpression",
    "ISymbolTable",
    "Interlock",
    "LogicNode",
    "NodeKind",
    "NodePool",
    "NotNode",
    "Operator",
    "ParseNode",
    "TagNode",
    "TagRefusal",
    "TagTable",
    "Token",
    "TokenKind",
    "TransferMain",
    "ValueType",
    "caret",
    "main",
    "upper_text",
]

POOL_SIZE = 12
MAX_DEPTH = 16
MAX_TAGS = 16
MAX_TEXT = 200
TAG_LENGTH = 16
#: Tokens of the longest text: at most one per character, and the end.
MAX_TOKENS = MAX_TEXT + 1
ERROR_LENGTH = 120


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


class TagRefusal(IecEnum):
    """``TYPE E_TagRefusal : (NONE, BAD_NAME, KEYWORD, DUPLICATE, TABLE_FULL) INT``: why ``Declare`` gave 0."""

    NONE = 0
    BAD_NAME = 1      # not an ST identifier of at most TAG_LENGTH characters
    KEYWORD = 2       # a word of the interlock language
    DUPLICATE = 3     # declared before (names are case-insensitive)
    TABLE_FULL = 4    # MAX_TAGS tags already


class TokenKind(IecEnum):
    """``TYPE E_TokenKind : (END_, NUMBER, WORD, KEYWORD, SYMBOL) INT; END_TYPE``."""

    END_ = 0
    NUMBER = 1
    WORD = 2
    KEYWORD = 3
    SYMBOL = 4


class NodeKind(IecEnum):
    """``TYPE E_NodeKind : (CONST := 1, TAG, COMPARE, LOGIC, NOT_) INT``: also the node pool's array number."""

    CONST = 1
    TAG = 2
    COMPARE = 3
    LOGIC = 4
    NOT_ = 5


# ---------------------------------------------------------------------------
# Text helpers: ST string functions only (LEN, MID, FIND, CONCAT)
# ---------------------------------------------------------------------------


def char_in(ch: STRING, chars: STRING) -> BOOL:
    """``FUNCTION F_CharIn : BOOL``: ``ch`` is one of ``chars`` (FALSE for the empty string past the end)."""
    return len(ch) == 1 and FIND(chars, ch) > 0


def upper_text(text: STRING) -> STRING:
    """``FUNCTION F_UpperText : STRING``: the text with a..z as A..Z (ST identifiers are case-insensitive)."""
    result: STRING = ""
    for i in range(1, len(text) + 1):
        ch: STRING = MID(text, 1, i)
        letter: INT = FIND("abcdefghijklmnopqrstuvwxyz", ch)
        if letter > 0:
            ch = MID("ABCDEFGHIJKLMNOPQRSTUVWXYZ", 1, letter)
        result = CONCAT(result, ch)
    return result


def is_keyword(word: STRING) -> BOOL:
    """``FUNCTION F_IsKeyword : BOOL``: ``word`` (upper case) is a word of the interlock language."""
    return word in ("AND", "OR", "XOR", "NOT", "TRUE", "FALSE")


def is_identifier(name: STRING) -> BOOL:
    """``FUNCTION F_IsIdentifier : BOOL``: an ST identifier of at most ``TAG_LENGTH`` characters."""
    if len(name) == 0 or len(name) > TAG_LENGTH or not char_in(MID(name, 1, 1), LETTERS):
        return False
    for i in range(2, len(name) + 1):
        if not char_in(MID(name, 1, i), LETTERS) and not char_in(MID(name, 1, i), DIGITS):
            return False
    return True


def type_name(kind: ValueType) -> STRING:
    """``FUNCTION F_TypeName : STRING``: ``'BOOL'`` or ``'REAL'``, for the error texts."""
    if kind == ValueType.BOOL_VALUE:
        return "BOOL"
    return "REAL"


def pool_name(kind: INT) -> STRING:
    """``FUNCTION F_PoolName : STRING``: the node array a ``NodeKind`` is taken from, for the error texts."""
    if kind == NodeKind.CONST:
        return "constant"
    if kind == NodeKind.TAG:
        return "tag"
    if kind == NodeKind.COMPARE:
        return "comparison"
    if kind == NodeKind.LOGIC:
        return "AND/OR/XOR"
    return "NOT"


def relation_of(symbol: STRING) -> Operator:
    """``FUNCTION F_RelationOf : E_Operator``: the operator of ``> >= < <= = <>``."""
    if symbol == ">":
        return Operator.GT
    if symbol == ">=":
        return Operator.GE
    if symbol == "<":
        return Operator.LT
    if symbol == "<=":
        return Operator.LE
    if symbol == "=":
        return Operator.EQ
    return Operator.NE


def caret(text: str, column: int, reason: str) -> str:
    """The text with a ``^`` under ``column``, as an HMI or a log shows a refused expression."""
    return f"{text}\n{' ' * (column - 1)}^ {reason}" if column else reason

#: The characters of the language, for FIND.
LETTERS = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz_"
DIGITS = "0123456789"
SYMBOLS = "<>=()-"
WHITESPACE = " \t\r\n"


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
    the tag's index (resolved once), or 0 with the reason in ``refusal``; the
    program writes the I/O image into the table every scan with ``set_real``
    / ``set_bool`` by index, which answer FALSE for a tag of the other type
    or an index that was never declared.
    """

    names: ARRAY[STRING] = VAR(bounds=(1, MAX_TAGS), length=TAG_LENGTH)
    kinds: ARRAY[ValueType] = VAR(bounds=(1, MAX_TAGS))
    reals: ARRAY[REAL] = VAR(bounds=(1, MAX_TAGS))
    bools: ARRAY[BOOL] = VAR(bounds=(1, MAX_TAGS))
    count: INT = VAR_OUTPUT(0)
    refusal: TagRefusal = VAR_OUTPUT(TagRefusal.NONE)

    @method
    def declare(self, name: STRING, kind: ValueType) -> INT:
        if not is_identifier(name):
            self.refusal = TagRefusal.BAD_NAME
        elif is_keyword(upper_text(name)):
            self.refusal = TagRefusal.KEYWORD
        elif self.find(name) > 0:
            self.refusal = TagRefusal.DUPLICATE
        elif self.count >= MAX_TAGS:
            self.refusal = TagRefusal.TABLE_FULL
        else:
            self.refusal = TagRefusal.NONE
            self.count += 1
            self.names[self.count] = upper_text(name)
            self.kinds[self.count] = kind
            return self.count
        return 0

    @method
    def find(self, name: STRING) -> INT:
        wanted = upper_text(name)
        for i in range(1, self.count + 1):
            if self.names[i] == wanted:
                return i
        return 0

    @method
    def kind_of(self, index: INT) -> ValueType:
        kind: ValueType = self.kinds[index]
        return kind

    # The nodes read the tags the parser checked: by index, of the right type, without a check per scan.
    @method
    def get_real(self, index: INT) -> REAL:
        value: REAL = self.reals[index]
        return value

    @method
    def get_bool(self, index: INT) -> BOOL:
        value: BOOL = self.bools[index]
        return value

    @method
    def set_real(self, index: INT, value: REAL) -> BOOL:
        if not self.holds(index, ValueType.REAL_VALUE):
            return False
        self.reals[index] = value
        return True

    @method
    def set_bool(self, index: INT, value: BOOL) -> BOOL:
        if not self.holds(index, ValueType.BOOL_VALUE):
            return False
        self.bools[index] = value
        return True

    @method(PRIVATE)
    def holds(self, index: INT, kind: ValueType) -> BOOL:
        """TRUE when tag ``index`` is declared and of type ``kind``."""
        if index < 1 or index > self.count:
            return False
        return self.kinds[index] == kind


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
        return self.kind

    @method(ABSTRACT)
    def evaluate_bool(self) -> BOOL:
        raise NotImplementedError

    @method
    def evaluate_real(self) -> REAL:
        # Never asked: the parser lets only REAL nodes into a comparison of REALs.
        return 0.0


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
            a: BOOL = self.left.evaluate_bool()
            b: BOOL = self.right.evaluate_bool()
            if op == Operator.EQ:
                return a == b
            return a != b
        x: REAL = self.left.evaluate_real()
        y: REAL = self.right.evaluate_real()
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
        a: BOOL = self.left.evaluate_bool()
        b: BOOL = self.right.evaluate_bool()
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
    again (its nodes are only reused by the next ``compile``). ``compile``
    checks the counts first: asking a full array for one more node would
    fault on its bound (RTSEXCPT_ARRAYBOUNDS).
    """

    constants: ARRAY[ConstantNode] = VAR(bounds=(1, POOL_SIZE))
    tags: ARRAY[TagNode] = VAR(bounds=(1, POOL_SIZE))
    compares: ARRAY[CompareNode] = VAR(bounds=(1, POOL_SIZE))
    logics: ARRAY[LogicNode] = VAR(bounds=(1, POOL_SIZE))
    nots: ARRAY[NotNode] = VAR(bounds=(1, POOL_SIZE))
    used: ARRAY[INT] = VAR_OUTPUT(bounds=(NodeKind.CONST, NodeKind.NOT_))

    @method
    def clear(self) -> None:
        for kind in range(NodeKind.CONST, NodeKind.NOT_ + 1):
            self.used[kind] = 0

    @method(INTERNAL)
    def take(self, kind: NodeKind) -> INT:
        self.used[kind] += 1
        return self.used[kind]

    @method(INTERNAL)
    def constant(self, kind: ValueType, real_value: REAL, bool_value: BOOL) -> IExpression:
        node = self.constants[self.take(NodeKind.CONST)]
        node.configure(kind, real_value, bool_value)
        return node

    @method(INTERNAL)
    def tag(self, symbols: ISymbolTable, index: INT) -> IExpression:
        node = self.tags[self.take(NodeKind.TAG)]
        node.configure(symbols, index)
        return node

    @method(INTERNAL)
    def compare(self, op: Operator, operand_type: ValueType, left: IExpression, right: IExpression) -> IExpression:
        node = self.compares[self.take(NodeKind.COMPARE)]
        node.configure(op, operand_type, left, right)
        return node

    @method(INTERNAL)
    def logic(self, op: Operator, left: IExpression, right: IExpression) -> IExpression:
        node = self.logics[self.take(NodeKind.LOGIC)]
        node.configure(op, left, right)
        return node

    @method(INTERNAL)
    def negation(self, operand: IExpression) -> IExpression:
        node = self.nots[self.take(NodeKind.NOT_)]
        node.configure(operand)
        return node

    @prop
    def node_count(self) -> INT:
        total: INT = 0
        for kind in range(NodeKind.CONST, NodeKind.NOT_ + 1):
            total += self.used[kind]
        return total


# ---------------------------------------------------------------------------
# Configuration time: tokenizer and recursive-descent parser, in ST
# ---------------------------------------------------------------------------


class Token(Struct):
    """``TYPE ST_Token : STRUCT``: a token is ``length`` characters of the text from ``column`` (1-based)."""

    kind: TokenKind = TokenKind.END_
    column: INT = 0
    length: INT = 0
    number: REAL = 0.0


class ParseNode(Struct):
    """``TYPE ST_ParseNode : STRUCT``: one node of the checked tree, before it is built from the pool.

    ``left`` / ``right`` are the children's numbers in the parser's ``nodes``
    (0: none); a NOT has only ``left``.
    """

    kind: NodeKind = NodeKind.CONST
    value_type: ValueType = ValueType.BOOL_VALUE
    column: INT = 0
    op: Operator = Operator.EQ
    real_value: REAL = 0.0
    bool_value: BOOL = False
    index: INT = 0
    left: INT = 0
    right: INT = 0


class ExpressionParser(FunctionBlock):
    """``FUNCTION_BLOCK FB_ExpressionParser``: tokenizer and recursive-descent parser, one method per rule.

    ``parse(text, symbols)`` splits the text into ``tokens``, parses and
    type-checks it into ``nodes`` (``root`` is the top node) and counts the
    nodes of each kind in ``counts``; nothing is built yet. FALSE on the
    first error, with ``error_text`` and ``error_column`` (1-based, 0: the
    expression as a whole). The recursion is bounded: parentheses nest at most
    ``MAX_DEPTH`` deep, and the tree is checked against ``MAX_DEPTH`` levels.
    """

    tokens: ARRAY[Token] = VAR_OUTPUT(bounds=(1, MAX_TOKENS))
    token_count: INT = VAR_OUTPUT(0)
    nodes: ARRAY[ParseNode] = VAR_OUTPUT(bounds=(1, MAX_TEXT))
    node_count: INT = VAR_OUTPUT(0)
    counts: ARRAY[INT] = VAR_OUTPUT(bounds=(NodeKind.CONST, NodeKind.NOT_))
    root: INT = VAR_OUTPUT(0)
    error: BOOL = VAR_OUTPUT(False)
    error_text: STRING = VAR_OUTPUT("", length=ERROR_LENGTH)
    error_column: INT = VAR_OUTPUT(0)
    text: STRING = VAR("", length=MAX_TEXT)
    symbols: ISymbolTable = VAR()
    pos: INT = VAR(1)
    parens: ARRAY[INT] = VAR(bounds=(1, MAX_DEPTH))
    open_parens: INT = VAR(0)

    @method
    def parse(self, text: STRING, symbols: ISymbolTable) -> BOOL:
        self.error, self.error_text, self.error_column = False, "", 0
        self.token_count, self.node_count, self.root, self.open_parens = 0, 0, 0, 0
        for kind in range(NodeKind.CONST, NodeKind.NOT_ + 1):
            self.counts[kind] = 0
        if len(text) > MAX_TEXT:
            self.fail(f"expression longer than {MAX_TEXT} characters ({len(text)})", 0)
            return False
        self.text = text
        self.symbols = symbols
        if not self.tokenize():
            return False
        self.pos = 1
        if self.tokens[1].kind == TokenKind.END_:
            self.fail("empty expression", 0)
            return False
        top = self.expression()
        if self.error:
            return False
        if self.tokens[self.pos].kind != TokenKind.END_:
            self.unexpected("AND, OR, XOR or the end")
            return False
        if self.nodes[top].value_type != ValueType.BOOL_VALUE:
            self.fail("type error: an interlock must be BOOL, this expression is REAL", 1)
            return False
        too_deep = self.deeper_than(top, 1)
        if too_deep > 0:
            self.fail(f"expression nested deeper than {MAX_DEPTH} levels", self.nodes[too_deep].column)
            return False
        self.root = top
        return True

    @method
    def token_text(self, number: INT) -> STRING:
        """The text of token ``number``; a keyword in upper case."""
        token: Token = self.tokens[number]
        word: STRING = MID(self.text, token.length, token.column)
        if token.kind == TokenKind.KEYWORD:
            return upper_text(word)
        return word

    # -- the tokenizer --------------------------------------------------------

    @method(PRIVATE)
    def tokenize(self) -> BOOL:
        length: INT = len(self.text)
        i: INT = 1
        while True:
            while i <= length and char_in(MID(self.text, 1, i), WHITESPACE):
                i += 1
            if i > length:
                self.add_token(TokenKind.END_, i, 0, 0.0)
                return True
            start = i
            ch: STRING = MID(self.text, 1, i)
            if char_in(ch, DIGITS):
                # number := digits [ '.' digits ]: the digits build the mantissa, one division places the point.
                mantissa: LREAL = 0.0
                scale: LREAL = 1.0
                while char_in(MID(self.text, 1, i), DIGITS):
                    mantissa = mantissa * 10.0 + (FIND(DIGITS, MID(self.text, 1, i)) - 1)
                    i += 1
                if MID(self.text, 1, i) == "." and char_in(MID(self.text, 1, i + 1), DIGITS):
                    i += 1
                    while char_in(MID(self.text, 1, i), DIGITS):
                        mantissa = mantissa * 10.0 + (FIND(DIGITS, MID(self.text, 1, i)) - 1)
                        scale = scale * 10.0
                        i += 1
                self.add_token(TokenKind.NUMBER, start, i - start, mantissa / scale)
            elif char_in(ch, LETTERS):
                while char_in(MID(self.text, 1, i), LETTERS) or char_in(MID(self.text, 1, i), DIGITS):
                    i += 1
                if is_keyword(upper_text(MID(self.text, i - start, start))):
                    self.add_token(TokenKind.KEYWORD, start, i - start, 0.0)
                else:
                    self.add_token(TokenKind.WORD, start, i - start, 0.0)
            elif MID(self.text, 2, i) in ("<>", ">=", "<="):
                i += 2
                self.add_token(TokenKind.SYMBOL, start, 2, 0.0)
            elif char_in(ch, SYMBOLS):
                i += 1
                self.add_token(TokenKind.SYMBOL, start, 1, 0.0)
            else:
                self.fail(f"unexpected character '{ch}'", i)
                return False

    @method(PRIVATE)
    def add_token(self, kind: TokenKind, column: INT, length: INT, number: LREAL) -> None:
        self.token_count += 1
        token = self.tokens[self.token_count]
        token.kind, token.column, token.length, token.number = kind, column, length, number

    # -- the parser: one method per rule, lowest precedence first -------------

    @method(PRIVATE)
    def expression(self) -> INT:
        left = self.xor_term()
        while not self.error and self.at_keyword("OR"):
            column = self.advance()
            right = self.xor_term()
            left = self.logic(Operator.OR_, "OR", left, right, column)
        return left

    @method(PRIVATE)
    def xor_term(self) -> INT:
        left = self.and_term()
        while not self.error and self.at_keyword("XOR"):
            column = self.advance()
            right = self.and_term()
            left = self.logic(Operator.XOR_, "XOR", left, right, column)
        return left

    @method(PRIVATE)
    def and_term(self) -> INT:
        left = self.unary()
        while not self.error and self.at_keyword("AND"):
            column = self.advance()
            right = self.unary()
            left = self.logic(Operator.AND_, "AND", left, right, column)
        return left

    @method(PRIVATE)
    def logic(self, op: Operator, keyword: STRING, left: INT, right: INT, column: INT) -> INT:
        # ST's OR evaluates both sides: node 0 (after an error) must not be looked at.
        if self.error:
            return 0
        if not self.require_bool(left, keyword, column) or not self.require_bool(right, keyword, column):
            return 0
        node = self.add_node(NodeKind.LOGIC, ValueType.BOOL_VALUE, column)
        self.nodes[node].op = op
        self.nodes[node].left = left
        self.nodes[node].right = right
        return node

    @method(PRIVATE)
    def unary(self) -> INT:
        if not self.at_keyword("NOT"):
            return self.comparison()
        column = self.advance()
        operand = self.unary()
        if self.error:
            return 0
        if not self.require_bool(operand, "NOT", column):
            return 0
        node = self.add_node(NodeKind.NOT_, ValueType.BOOL_VALUE, column)
        self.nodes[node].left = operand
        return node

    @method(PRIVATE)
    def comparison(self) -> INT:
        left = self.operand()
        if self.error or not self.at_relation():
            return left
        symbol: STRING = self.token_text(self.pos)
        column = self.advance()
        right = self.operand()
        if right == 0:
            return 0
        if self.at_relation():
            self.fail(
                f"unexpected '{self.token_text(self.pos)}': comparisons do not chain, use AND",
                self.tokens[self.pos].column,
            )
            return 0
        left_type: ValueType = self.nodes[left].value_type
        right_type: ValueType = self.nodes[right].value_type
        if left_type != right_type:
            self.fail(f"type error: '{symbol}' compares {type_name(left_type)} with {type_name(right_type)}", column)
            return 0
        op = relation_of(symbol)
        if left_type == ValueType.BOOL_VALUE and op != Operator.EQ and op != Operator.NE:
            self.fail(f"type error: '{symbol}' needs REAL operands, got BOOL", column)
            return 0
        node = self.add_node(NodeKind.COMPARE, ValueType.BOOL_VALUE, column)
        self.nodes[node].op = op
        self.nodes[node].left = left
        self.nodes[node].right = right
        return node

    @method(PRIVATE)
    def operand(self) -> INT:
        token: Token = self.tokens[self.pos]
        if token.kind == TokenKind.NUMBER:
            self.advance()
            return self.constant(ValueType.REAL_VALUE, token.number, False, token.column)
        if self.at_symbol("-"):
            self.advance()
            if self.tokens[self.pos].kind != TokenKind.NUMBER:
                self.unexpected("a number after '-'")
                return 0
            number: REAL = self.tokens[self.pos].number
            self.advance()
            return self.constant(ValueType.REAL_VALUE, -number, False, token.column)
        if self.at_keyword("TRUE") or self.at_keyword("FALSE"):
            literal = self.at_keyword("TRUE")
            self.advance()
            return self.constant(ValueType.BOOL_VALUE, 0.0, literal, token.column)
        if token.kind == TokenKind.WORD:
            name: STRING = self.token_text(self.pos)
            self.advance()
            index = self.symbols.find(name)
            if index == 0:
                self.fail(f"unknown tag '{name}'", token.column)
                return 0
            node = self.add_node(NodeKind.TAG, self.symbols.kind_of(index), token.column)
            self.nodes[node].index = index
            return node
        if self.at_symbol("("):
            if self.open_parens >= MAX_DEPTH:
                self.fail(f"expression nested deeper than {MAX_DEPTH} levels", token.column)
                return 0
            self.advance()
            self.open_parens += 1
            self.parens[self.open_parens] = token.column
            inner = self.expression()
            if self.error:
                return 0
            if not self.at_symbol(")"):
                self.unexpected("')'")
                return 0
            self.advance()
            self.open_parens -= 1
            return inner
        self.unexpected("a tag, a number, TRUE, FALSE, NOT or '('")
        return 0

    # -- the parser's helpers -------------------------------------------------

    @method(PRIVATE)
    def advance(self) -> INT:
        """Step past the current token; its column."""
        column: INT = self.tokens[self.pos].column
        self.pos += 1
        return column

    @method(PRIVATE)
    def at_keyword(self, keyword: STRING) -> BOOL:
        return self.tokens[self.pos].kind == TokenKind.KEYWORD and self.token_text(self.pos) == keyword

    @method(PRIVATE)
    def at_symbol(self, symbol: STRING) -> BOOL:
        return self.tokens[self.pos].kind == TokenKind.SYMBOL and self.token_text(self.pos) == symbol

    @method(PRIVATE)
    def at_relation(self) -> BOOL:
        return self.tokens[self.pos].kind == TokenKind.SYMBOL and self.token_text(self.pos) in (
            ">", ">=", "<", "<=", "=", "<>",
        )

    @method(PRIVATE)
    def add_node(self, kind: NodeKind, value_type: ValueType, column: INT) -> INT:
        """A new node; the array cannot overflow, as every node takes at least one token of its own."""
        self.node_count += 1
        node = self.nodes[self.node_count]
        node.kind, node.value_type, node.column, node.op = kind, value_type, column, Operator.EQ
        node.real_value, node.bool_value, node.index, node.left, node.right = 0.0, False, 0, 0, 0
        self.counts[kind] += 1
        return self.node_count

    @method(PRIVATE)
    def constant(self, value_type: ValueType, real_value: REAL, bool_value: BOOL, column: INT) -> INT:
        node = self.add_node(NodeKind.CONST, value_type, column)
        self.nodes[node].real_value = real_value
        self.nodes[node].bool_value = bool_value
        return node

    @method(PRIVATE)
    def require_bool(self, node: INT, what: STRING, column: INT) -> BOOL:
        if self.nodes[node].value_type != ValueType.BOOL_VALUE:
            self.fail(f"type error: {what} needs BOOL operands, got REAL", column)
            return False
        return True

    @method(PRIVATE)
    def unexpected(self, expected: STRING) -> None:
        token: Token = self.tokens[self.pos]
        if token.kind == TokenKind.END_ and self.open_parens > 0:
            self.fail("unbalanced parentheses: '(' is never closed", self.parens[self.open_parens])
        elif token.kind == TokenKind.END_:
            self.fail(f"unexpected end of expression, expected {expected}", token.column)
        elif self.token_text(self.pos) == ")" and self.open_parens == 0:
            self.fail("unbalanced parentheses: ')' has no '(' to close", token.column)
        else:
            self.fail(f"unexpected '{self.token_text(self.pos)}', expected {expected}", token.column)

    @method(PRIVATE)
    def fail(self, message: STRING, column: INT) -> None:
        """Keep the first error: the rules return 0 from there on."""
        if not self.error:
            self.error, self.error_text, self.error_column = True, message, column

    @method(PRIVATE)
    def deeper_than(self, node: INT, depth: INT) -> INT:
        """The first node (in text order) below ``MAX_DEPTH`` levels, or 0: the evaluation's call depth is the height."""
        if depth > MAX_DEPTH:
            return node
        kind: NodeKind = self.nodes[node].kind
        if kind == NodeKind.CONST or kind == NodeKind.TAG:
            return 0
        found = self.deeper_than(self.nodes[node].left, depth + 1)
        if found > 0 or kind == NodeKind.NOT_:
            return found
        return self.deeper_than(self.nodes[node].right, depth + 1)


# ---------------------------------------------------------------------------
# The client: the interlock FB
# ---------------------------------------------------------------------------


class Interlock(FunctionBlock):
    """``FUNCTION_BLOCK FB_Interlock``: owns a parser and a node pool, evaluates its tree once per call.

    ``compile(text, symbols)`` runs at configuration: it parses, checks the
    pool has room, and only then rebuilds the tree, so a rejected text
    leaves the running interlock as it was; it answers FALSE with
    ``error_text`` and ``error_column`` (0: the text as a whole). Without an
    accepted expression the interlock is not ``valid`` and never permissive
    (fail-safe); ``disable`` takes an accepted one out of service again.
    """

    permissive: BOOL = VAR_OUTPUT(False)
    valid: BOOL = VAR_OUTPUT(False)
    node_count: INT = VAR_OUTPUT(0)
    scans: UDINT = VAR_OUTPUT(0)
    source: STRING = VAR_OUTPUT("", length=MAX_TEXT)
    error: BOOL = VAR_OUTPUT(False)
    error_text: STRING = VAR_OUTPUT("", length=ERROR_LENGTH)
    error_column: INT = VAR_OUTPUT(0)
    parser: ExpressionParser = VAR()
    pool: NodePool = VAR()
    root: IExpression = VAR()

    @method
    def compile(self, text: STRING, symbols: ISymbolTable) -> BOOL:
        if not self.parser.parse(text, symbols):
            self.refuse(self.parser.error_text, self.parser.error_column)
            return False
        for kind in range(NodeKind.CONST, NodeKind.NOT_ + 1):
            needed: INT = self.parser.counts[kind]
            if needed > POOL_SIZE:
                self.refuse(
                    f"node pool full: the expression needs {needed} {pool_name(kind)} nodes, "
                    f"the pool holds {POOL_SIZE} (ARRAY[1..{POOL_SIZE}])", 0,
                )
                return False
        self.pool.clear()
        self.root = self.build(self.parser.root, symbols)
        self.node_count = self.pool.node_count
        self.source = text
        self.valid = True
        self.error, self.error_text, self.error_column = False, "", 0
        return True

    @method
    def disable(self) -> None:
        """Drop the expression: not ``valid``, never permissive, the tree released (``root := 0``)."""
        self.valid = False
        self.root = NULL
        self.pool.clear()
        self.node_count = 0
        self.source = ""

    @method(PRIVATE)
    def refuse(self, reason: STRING, column: INT) -> None:
        self.error, self.error_text, self.error_column = True, reason, column

    @method(PRIVATE)
    def build(self, number: INT, symbols: ISymbolTable) -> IExpression:
        """The pool nodes for parse node ``number`` and its children, left before right."""
        node: ParseNode = self.parser.nodes[number]
        if node.kind == NodeKind.CONST:
            return self.pool.constant(node.value_type, node.real_value, node.bool_value)
        if node.kind == NodeKind.TAG:
            return self.pool.tag(symbols, node.index)
        if node.kind == NodeKind.NOT_:
            return self.pool.negation(self.build(node.left, symbols))
        left = self.build(node.left, symbols)
        right = self.build(node.right, symbols)
        if node.kind == NodeKind.COMPARE:
            return self.pool.compare(node.op, self.parser.nodes[node.left].value_type, left, right)
        return self.pool.logic(node.op, left, right)

    def body(self) -> None:
        self.scans += 1
        # Not "valid AND root.EvaluateBool()": ST's AND would call through a null root.
        if self.valid:
            self.permissive = self.root.evaluate_bool()
        else:
            self.permissive = False


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
    transfer = program.transfer
    for bad in ("TT101 > 80 AND NOT LS3)", "LS3 > 5 OR BYPASS"):
        if not transfer.compile(bad, program.tags):
            print(caret(bad, transfer.error_column, transfer.error_text))
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
