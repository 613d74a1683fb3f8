"""Python expressions to Structured Text expressions.

Each expression becomes its ST text and the precedence of its operator,
so a parent adds parentheses only where a child binds looser. Calls of
names (Python builtins, iecoop's operators) are tables of rules by name.
"""

from __future__ import annotations

import ast
import enum
import inspect
import math
import sys
import typing
from collections.abc import Callable
from typing import Any

from iecoop.metadata import kind_of
from iecoop.exceptions import ExceptionCode
from iecoop import types as iec_types
from iecoop.literals import D, T, format_date, format_dt, format_ltime, format_time, format_tod, parse_dt, parse_ltime, parse_tod
from iecoop.parameters import parameter_sections
from iecoop.memory.typeinfo import (
    AggregateInfo,
    ArrayInfo,
    ElementaryInfo,
    EnumInfo,
    InterfaceInfo,
    OpenArrayInfo,
    ReferenceInfo,
    StringInfo,
    TypeInfo,
    class_info,
)
from iecoop.memory.pointers import PointerInfo
from iecoop.st.write.infer import (
    Inference,
    _class_of,
    _constant_int,
    _from_iecoop,
    _in_out_names,
    _is_bool,
    _is_integer,
    _is_name,
    _is_none,
    _is_real,
    _is_task_info,
    _is_time,
    _is_whole,
    _member_function,
)
from iecoop.st.language import BUILTIN_FUNCTIONS, ELEMENTARY, INTEGER_TYPES, MATH_BY_PYTHON, OPERATOR_FUNCTIONS, PRECEDENCE
from iecoop.st.write.literals import literal
from iecoop.st.write.model import StExportError, field_ident, ident, type_text

__all__ = ["ExpressionWriter"]

#: ST operator precedence (language.PRECEDENCE), loosest first; an atom (a name, a literal, a call) binds tightest.
_OR, _XOR, _AND, _EQ, _CMP, _ADD, _MUL, _UNARY = (PRECEDENCE[op] for op in ("OR", "XOR", "AND", "=", "<", "+", "*", "NOT"))
_ATOM = max(PRECEDENCE.values()) + 1

#: Python's arithmetic and bit operators with an ST operator (``a += b`` takes these), by the ast class name.
_BINARY_OPERATORS = {
    "Add": "+", "Sub": "-", "Mult": "*", "Div": "/", "FloorDiv": "/", "Mod": "MOD", "BitAnd": "AND", "BitOr": "OR", "BitXor": "XOR",
}

#: Names that are ST words.
_NAME_WORDS = {"self": "THIS^", "True": "TRUE", "False": "FALSE", "NULL": "0", "None": "0"}

#: Python's comparisons and the ST operator of each (``is`` / ``is not`` compare with 0, NULL, in ST).
_COMPARE = {"Eq": "=", "NotEq": "<>", "Lt": "<", "LtE": "<=", "Gt": ">", "GtE": ">=", "Is": "=", "IsNot": "<>"}

_BinaryHandler = Callable[["ExpressionWriter", ast.BinOp, ast.AST], "tuple[str, int]"]


def _make_binop(symbol: str) -> _BinaryHandler:
    """The handler of a Python operator written as the ST operator ``symbol``: ``visit_Add = _make_binop("+")``."""

    def visit(self: ExpressionWriter, node: ast.BinOp, where: ast.AST) -> tuple[str, int]:
        return self.binary(node, symbol)

    return visit


def _make_call_operator(function: str) -> _BinaryHandler:
    """The handler of a Python operator written as an ST function of both operands (``a ** b``: ``EXPT(a, b)``)."""

    def visit(self: ExpressionWriter, node: ast.BinOp, where: ast.AST) -> tuple[str, int]:
        left = self.expr(node.left)[0]
        if function in ("SHL", "SHR"):
            value = _constant_int(node.left)
            # SHL's result has its operand's width: a literal needs one (Python's integers have none).
            left = f"DWORD#{value}" if value is not None and 0 <= value < 2**32 else left
        return f"{function}({left}, {self.expr(node.right)[0]})", _ATOM

    return visit


class ExpressionWriter(Inference):
    """The ST text of the expressions of one body, and the locals and temporaries they need."""

    def temporary(self, stem: str, info: TypeInfo, node: ast.AST) -> str:
        """A local for a value a statement needs kept: a new one, or one of the same type that no
        expression of the statement being translated holds."""
        busy = set(self.hoisted.values())
        for n in range(1000):
            name = f"{stem}{n or ''}"
            if name in self.temps and self.locals.get(name) is info and name not in busy:
                return name
            if name not in self.locals and name not in self.params and name not in self.fields:
                self.temps.add(name)
                self.declare(name, info, node)
                return name
        self.fail(node, "a statement that needs more than 1000 temporaries")

    def declare(self, name: str, info: TypeInfo | str, node: ast.AST, *, seen_as: TypeInfo | None = None) -> None:
        """Declare the local ``name`` of ST type ``info``; ``seen_as`` is the type Python sees where it differs."""
        if name == self.result_local:
            return  # the member's result: ST declares it by the member itself
        if name.lower() in {f.lower() for f in self.fields} and name not in self.params and self.func.__name__ == "body":
            self.temp_name(name)
        self.locals[name] = info
        if seen_as is not None:
            self.local_types[name] = seen_as

    def declare_once(self, name: str, info: TypeInfo, node: ast.AST) -> None:
        """Declare the local ``name`` unless it is one already (a local or an input)."""
        if name not in self.locals and name not in self.params:
            self.declare(name, info, node)

    def fresh_name(self, stem: str) -> str:
        """``stem``, ``stem1``, ...: the first that names no local, input or variable yet."""
        taken = {*self.locals, *self.params, *self.fields}
        return next(f"{stem}{n or ''}" for n in range(100) if f"{stem}{n or ''}" not in taken)

    def temp_name(self, name: str) -> str:
        """The VAR_TEMP name of the body's local ``name``, which a variable of the block already has.

        A method's local hides the variable (ST reads that as THIS^.name), but the body's VAR_TEMP is
        declared beside the variables, where the same name twice is an error.
        """
        if name not in self.temp_names:
            taken = {n.lower() for n in (*self.fields, *self.locals, *self.params, *self.bound, *self.temp_names.values())}
            self.temp_names[name] = next(f"{name}_temp{n or ''}" for n in range(100) if f"{name}_temp{n or ''}".lower() not in taken)
        return self.temp_names[name]

    def target(self, node: ast.expr) -> str:
        if isinstance(node, (ast.Name, ast.Attribute, ast.Subscript)):
            return self.expr(node)[0]
        self.fail(node, f"an assignment to {_describe(node)}")

    def condition(self, node: ast.expr) -> str:
        info = self.typeof(node)
        text, prec = self.expr(node)
        if info is not None and not _is_bool(info):
            return f"{_paren(text, prec, _EQ + 1)} <> 0"
        return text

    def name_text(self, name: str) -> str:
        return self.rename.get(name) or self.temp_names.get(name) or ident(name)

    def expr(self, node: ast.expr, need: int = 0) -> tuple[str, int]:
        """ST text of an expression and its precedence, in parentheses where it binds looser than ``need``."""
        text, prec = self.visit(node)
        return (_paren(text, prec, need), _ATOM if prec < need else prec)

    def visit(self, node: ast.AST, *args: Any) -> Any:
        """Write ``node`` by its handler ``visit_<ast class name>`` (as :class:`ast.NodeVisitor` does)."""
        handler = getattr(self, f"visit_{type(node).__name__}", self.generic_visit)
        return handler(node, *args)

    def generic_visit(self, node: ast.AST, *args: Any) -> typing.NoReturn:
        """A construct without a handler has no ST form: StExportError naming the file, the line and the
        construct, or, when lenient, an ST comment that says the same (see :meth:`StatementWriter.block`)."""
        self.fail(node, _describe(node))

    # -- one handler per expression: visit_<ast class name>(node) -> (text, precedence) ------------------

    def visit_Constant(self, node: ast.Constant) -> tuple[str, int]:
        """``3``, ``'text'``, ``True``, ``None``: the ST literal (None is 0)."""
        if isinstance(node.value, (bool, int, float, str)) or node.value is None:
            return literal(node.value), _ATOM
        self.fail(node, f"the constant {node.value!r}")

    def visit_Name(self, node: ast.Name) -> tuple[str, int]:
        return self.name(node), _ATOM

    def visit_Attribute(self, node: ast.Attribute) -> tuple[str, int]:
        return self.attribute(node), _ATOM

    def visit_Subscript(self, node: ast.Subscript) -> tuple[str, int]:
        """``a[i, j]``: ``a[i, j]`` (a slice has no ST form)."""
        bound = _bound_function(self, node)
        if bound is not None:
            return bound, _ATOM
        base = self.expr(node.value, _ATOM)[0]
        index = node.slice
        parts = index.elts if isinstance(index, ast.Tuple) else [index]
        if any(isinstance(p, ast.Slice) for p in parts):
            self.fail(node, "a slice")
        return f"{base}[{', '.join(self.expr(p)[0] for p in parts)}]", _ATOM

    def visit_Call(self, node: ast.Call) -> tuple[str, int]:
        return self.call(node)

    def visit_JoinedStr(self, node: ast.JoinedStr) -> tuple[str, int]:
        return self.fstring(node), _ATOM

    def visit_IfExp(self, node: ast.IfExp) -> tuple[str, int]:
        """``b if c else a``: ``SEL(c, a, b)`` (SEL gives its first value when the condition is FALSE)."""
        cond = self.condition(node.test)
        return f"SEL({cond}, {self.expr(node.orelse)[0]}, {self.expr(node.body)[0]})", _ATOM

    def visit_BoolOp(self, node: ast.BoolOp) -> tuple[str, int]:
        """``a and b`` / ``a or b``: AND / OR, or AND_THEN / OR_ELSE where a later operand may act."""
        word, prec = ("AND", _AND) if isinstance(node.op, ast.And) else ("OR", _OR)
        if any(self.may_act(v) for v in node.values[1:]):
            # Python's and / or stop at the first operand that decides; ST's AND / OR evaluate every
            # operand, so a call, a dereference or an index after the first is guarded by AND_THEN / OR_ELSE.
            word += "_THEN" if word == "AND" else "_ELSE"
        operands = [self.condition_operand(v, prec) for v in node.values]
        return f" {word} ".join(operands), prec

    def visit_UnaryOp(self, node: ast.UnaryOp) -> tuple[str, int]:
        """``not a``, ``-a``, ``+a``, ``~a``: by the operator's handler."""
        return typing.cast(tuple[str, int], self.visit(node.op, node))

    def visit_Not(self, op: ast.Not, node: ast.UnaryOp) -> tuple[str, int]:
        info = self.typeof(node.operand)
        if info is not None and not _is_bool(info):
            return f"{self.expr(node.operand, _EQ + 1)[0]} = 0", _EQ
        return f"NOT {self.expr(node.operand, _UNARY)[0]}", _UNARY

    def visit_USub(self, op: ast.USub, node: ast.UnaryOp) -> tuple[str, int]:
        operand = node.operand
        if isinstance(operand, ast.Constant) and isinstance(operand.value, (int, float)) and not isinstance(operand.value, bool):
            return literal(-operand.value), _ATOM
        return f"-{self.expr(operand, _UNARY + 1)[0]}", _UNARY

    def visit_UAdd(self, op: ast.UAdd, node: ast.UnaryOp) -> tuple[str, int]:
        return self.expr(node.operand)

    def visit_Invert(self, op: ast.Invert, node: ast.UnaryOp) -> tuple[str, int]:
        return f"NOT {self.expr(node.operand, _UNARY)[0]}", _UNARY

    def visit_Compare(self, node: ast.Compare) -> tuple[str, int]:
        return self.compare(node)

    def fstring(self, node: ast.JoinedStr) -> str:
        """An f-string as nested CONCATs: TwinCAT's and CODESYS's CONCAT take two strings."""
        pieces = [
            literal(part.value) if isinstance(part, ast.Constant) else self.string_piece(typing.cast(ast.FormattedValue, part))
            for part in node.values
            if not (isinstance(part, ast.Constant) and part.value == "")
        ]
        text = pieces[0] if pieces else "''"
        for piece in pieces[1:]:
            text = f"CONCAT({text}, {piece})"
        return text

    def string_piece(self, node: ast.FormattedValue) -> str:
        """One ``{value}`` of an f-string: only where ST writes the text Python writes."""
        if node.conversion != -1:
            self.fail(node, f"the f-string conversion !{chr(node.conversion)} (write the value itself)")
        if node.format_spec is not None:
            spec = "".join(str(getattr(p, "value", "{...}")) for p in typing.cast(ast.JoinedStr, node.format_spec).values)
            self.fail(node, f"the f-string format :{spec} (ST has no format specifiers: {_REAL_IN_TEXT})")
        info = self.typeof(node.value)
        text = self.expr(node.value)[0]
        if isinstance(info, StringInfo) and info.record.name == "STRING":
            return text
        name = getattr(getattr(info, "record", None), "name", None)
        if name in INTEGER_TYPES:
            return f"{name}_TO_STRING({text})"
        if name == "BOOL":
            return f"SEL({text}, 'False', 'True')"  # Python writes True / False, BOOL_TO_STRING TRUE / FALSE
        self.fail(node, _piece_refusal(info))

    def query_test(self, node: ast.Call, found: bool) -> tuple[str, int]:
        """``query_interface(a, IB) is not None``: __QUERYINTERFACE's BOOL result, into a temporary of IB."""
        source, iface = self.operator_args(node, 2)
        cls = self.constant_object(iface)
        info = class_info(cls) if isinstance(cls, type) else None
        if not isinstance(info, InterfaceInfo):
            self.fail(node, "query_interface() with a target that is not an interface name")
        temp = self.hoisted.get(id(node)) or self.temporary(f"{cls.__name__}_query", info, node)
        self.hoisted[id(node)] = temp
        text = f"__QUERYINTERFACE({self.expr(source)[0]}, {temp})"
        return (text, _ATOM) if found else (f"NOT {text}", _UNARY)

    def condition_operand(self, node: ast.expr, prec: int) -> str:
        info = self.typeof(node)
        if info is not None and not _is_bool(info):
            return f"({self.expr(node, _EQ + 1)[0]} <> 0)"
        return self.expr(node, prec + 1)[0]

    def compare(self, node: ast.Compare) -> tuple[str, int]:
        left = node.left
        if (
            len(node.ops) == 1 and isinstance(node.ops[0], (ast.Is, ast.IsNot)) and isinstance(left, ast.Call)
            and self.resolves_to(left.func, "query_interface") and _is_none(node.comparators[0])
        ):
            return self.query_test(left, isinstance(node.ops[0], ast.IsNot))
        parts: list[tuple[str, bool]] = []  # (text, whether it is in parentheses of its own)
        left = node.left
        for op, right in zip(node.ops, node.comparators):
            if isinstance(op, (ast.In, ast.NotIn)):
                if not isinstance(right, (ast.Tuple, ast.List, ast.Set)):
                    self.fail(node, "'in' over something other than a literal tuple")
                word, join = ("=", " OR ") if isinstance(op, ast.In) else ("<>", " AND ")
                lhs = self.expr(left, _EQ + 1)[0]
                tests = [f"{lhs} {word} {self.expr(e, _EQ + 1)[0]}" for e in right.elts]
                parts.append(("(" + join.join(tests) + ")", True) if len(tests) > 1 else (tests[0], False))
            else:
                symbol = _COMPARE[type(op).__name__]
                prec = PRECEDENCE[symbol]
                parts.append((f"{self.expr(left, prec + 1)[0]} {symbol} {self.expr(right, prec + 1)[0]}", False))
            left = right
        if len(parts) == 1:
            only, grouped = parts[0]
            prec = _EQ if isinstance(node.ops[0], (ast.Eq, ast.NotEq, ast.Is, ast.IsNot)) else _CMP
            return only, (_ATOM if grouped else prec)
        return " AND ".join(text if grouped else f"({text})" for text, grouped in parts), _AND

    def visit_BinOp(self, node: ast.BinOp) -> tuple[str, int]:
        return self.binop(node, node)

    def binop(self, node: ast.BinOp, where: ast.AST) -> tuple[str, int]:
        """``a + b``...: by the operator's handler, ``visit_Add(node, where)``; ``where`` is the node a refusal names."""
        handler = getattr(self, f"visit_{type(node.op).__name__}", None)
        if handler is None:
            self.fail(where, f"the operator {type(node.op).__name__}")
        return typing.cast(tuple[str, int], handler(node, where))

    def binary(self, node: ast.BinOp, symbol: str, left_text: str | None = None, right_text: str | None = None) -> tuple[str, int]:
        """``left symbol right``, each side in parentheses where it binds looser (the right one where equal)."""
        prec = PRECEDENCE[symbol]
        left = left_text if left_text is not None else self.expr(node.left, prec)[0]
        right = right_text if right_text is not None else self.expr(node.right, prec + 1)[0]
        return f"{left} {symbol} {right}", prec

    visit_Add = _make_binop("+")
    visit_Sub = _make_binop("-")
    visit_Mult = _make_binop("*")
    visit_Mod = _make_binop("MOD")
    visit_BitAnd = _make_binop("AND")
    visit_BitOr = _make_binop("OR")
    visit_BitXor = _make_binop("XOR")
    visit_LShift = _make_call_operator("SHL")
    visit_RShift = _make_call_operator("SHR")
    visit_Pow = _make_call_operator("EXPT")

    def visit_Div(self, node: ast.BinOp, where: ast.AST) -> tuple[str, int]:
        """``a / b``: Python's / on integers (and on TIMEs, which are milliseconds) gives a float; ST's gives
        an integer or a TIME, so whole operands go to LREAL first."""
        left, right = self.typeof(node.left), self.typeof(node.right)
        if not (_is_whole(left) and _is_whole(right)):
            return self.binary(node, "/")
        left_text = f"TO_LREAL({self.expr(node.left)[0]})"
        right_text = f"TO_LREAL({self.expr(node.right)[0]})" if _is_time(right) else None
        return self.binary(node, "/", left_text, right_text)

    def visit_FloorDiv(self, node: ast.BinOp, where: ast.AST) -> tuple[str, int]:
        """``a // b`` on integers: ST's ``/`` (both truncate alike where the operands are not negative)."""
        if _is_real(self.typeof(node.left)) or _is_real(self.typeof(node.right)):
            self.fail(where, "// on REAL values (ST has no floor division: TRUNC(a / b) is the same where a / b >= 0)")
        return self.binary(node, "/")


    def name(self, node: ast.Name) -> str:
        """A name: a local or input, ``self`` (THIS^), a word (True, None), or a module-level name."""
        name = node.id
        if name in self.rename:
            return self.rename[name]
        if name == self.result_local:
            return self.st_name
        if name in self.locals or name in self.params:
            return self.temp_names.get(name) or ident(name)
        if name in _NAME_WORDS:
            return _NAME_WORDS[name]
        if name in self.globals:
            text = self.global_name(node, self.globals[name])
            if text is not None:
                return text
        self.fail(node, f"the name {name!r}")

    def global_name(self, node: ast.Name, value: Any) -> str | None:
        """A module-level name: a constant (declared in GVL_Constants), a type, a GVL, an IEC type alias."""
        if isinstance(value, (bool, int, float, str)) and not isinstance(value, enum.Enum):
            return self.module_constant(node, value)
        if isinstance(value, type):
            return value.__name__
        if kind_of(type(value)) in ("gvl", "program"):  # a PROGRAM is named as its instance is: MAIN.Next()
            return type(value).__name__
        if typing.get_origin(value) is typing.Annotated:
            from iecoop.memory.typeinfo import resolve_type as _resolve

            try:
                return type_text(_resolve(value, node.id))
            except Exception:
                return None
        return None

    def module_constant(self, node: ast.Name, value: Any) -> str:
        """A module constant the body reads: declared once in the constants' GVL (a library's is the library's)."""
        name = node.id
        if library_name(name, value):  # a shipped library's constant (ADSLOG_MSGTYPE_HINT)
            return ident(name)
        known = self.scope.constants.get(name, value)
        if known != value:
            raise StExportError(f"{self.where_text(node)}: two module constants named {name} have different values")
        self.scope.constants[name] = value
        own = {*self.fields, *self.locals, *self.params, *self.bound, *self.rename.values(), self.st_name}
        if self.scope.cls is not None:  # its methods and properties, and its interfaces'
            own.update(n for klass in self.scope.cls.__mro__ for n in vars(klass) if not n.startswith("_"))
        if name.lower() in {n.lower() for n in own}:
            # ST names ignore case: buttons would hide BUTTONS, so name the list it is declared in.
            return f"{_CONSTANTS_GVL}.{ident(name)}"
        return ident(name)

    def attribute(self, node: ast.Attribute) -> str:
        """``a.b``: a variable of the block, a dereference, an enumeration value, a member of a value."""
        base = node.value
        attr = node.attr
        if isinstance(base, ast.Name) and base.id == "self" and base.id not in self.locals:
            return self.own_member(attr)
        if attr == "deref":
            return ident(base.id) if isinstance(base, ast.Name) and base.id in self.by_reference else f"{self.expr(base, _ATOM)[0]}^"
        if isinstance(base, ast.Name) and base.id in self.catch_vars and attr == "code":
            return base.id
        owner = self.constant_object(base)
        if owner is not None:
            return self.constant_member(node, owner)
        if isinstance(base, ast.Call) and _is_name(base.func, "super"):
            return f"SUPER^.{ident(attr)}"
        typed = self.typed_member(node)
        if typed is not None:
            return typed
        if isinstance(base, ast.Call):
            return self.call_member(node, base)
        return f"{self.expr(base, _ATOM)[0]}.{field_ident(_class_of(self.typeof(base)), attr)}"

    def own_member(self, attr: str) -> str:
        """``self.x``: ``x``, or ``THIS^.x`` where a local, input or the result of the same name hides it (ST ignores case)."""
        hiding = [n for n in self.locals if n not in self.temp_names] + [*self.bound, *self.params, *self.rename.values(), self.st_name]
        name = field_ident(self.scope.cls, attr)
        # compared by Python name and by ST name: the input `word` (ST `word_`) hides the variable `word`
        hidden = {n.lower() for n in hiding} | {ident(n).lower() for n in hiding if n.isascii() and n.isidentifier()}
        if {attr.lower(), name.lower()} & hidden:
            return f"THIS^.{name}"
        return name

    def constant_member(self, node: ast.Attribute, owner: Any) -> str:
        """A member of a module-level object: an exception code or an enumeration value."""
        if owner is ExceptionCode:
            return f"__SYSTEM.ExceptionCode.{node.attr}"
        if isinstance(owner, type) and issubclass(owner, enum.Enum):
            return f"{owner.__name__}.{ident(node.attr)}"
        self.fail(node, f"the attribute {ast.unparse(node)}")

    def typed_member(self, node: ast.Attribute) -> str | None:
        """What Python reads of a value that ST writes otherwise: an ARRAY's ``low`` / ``high``, an enumeration value's ``name``."""
        info = self.typeof(node.value)
        if node.attr in ("low", "high") and isinstance(info, ArrayInfo) and len(info.bounds) == 1:
            # An ARRAY's bounds are its declaration's constants (LOWER_BOUND / UPPER_BOUND give the same).
            return str(info.bounds[0][0 if node.attr == "low" else 1])
        open_array = info.target if isinstance(info, ReferenceInfo) else info
        if node.attr in ("low", "high") and isinstance(open_array, OpenArrayInfo) and open_array.dims == 1:
            # ARRAY[*]: the bounds of the array bound at the call
            return f"{'LOWER_BOUND' if node.attr == 'low' else 'UPPER_BOUND'}({self.expr(node.value)[0]}, 1)"
        if node.attr == "name" and isinstance(info, EnumInfo):
            # TO_STRING gives a component's name where the enumeration has {attribute 'to_string'}.
            self.scope.named_enums.add(info.enum_cls)
            return f"TO_STRING({self.expr(node.value)[0]})"
        return None

    def call_member(self, node: ast.Attribute, call: ast.Call) -> str:
        """``obj.get().x``: TwinCAT reads a member of a returned value, but blark's grammar does not,
        so the result goes to a temporary first (a METHOD's STRUCT result is a copy there)."""
        if _is_task_info(self, call):
            return f"{self.expr(call, _ATOM)[0]}.{ident(node.attr)}"
        info = self.typeof(call)
        bind = isinstance(info, ReferenceInfo)  # the variable itself: a REFERENCE local bound with REF=
        target = info.target if isinstance(info, ReferenceInfo) else info
        if not isinstance(target, (InterfaceInfo, AggregateInfo)):
            self.fail(node, "a member of a call's result whose type is not an interface, block or struct")
        if isinstance(node.ctx, ast.Store) and isinstance(target, AggregateInfo) and not bind:
            self.fail(node, "a write into a member of a call's result (the METHOD returns a copy in ST: return an interface, or bind a REFERENCE local)")
        temp = self.hoisted.get(id(call))
        if temp is None:
            assert info is not None
            func = call.func
            stem = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "call")
            temp = self.temporary(f"{stem}_result", info, node)
            self.prelude.append(f"{temp} {'REF=' if bind else ':='} {self.call(call)[0]};")
            self.hoisted[id(call)] = temp
        return f"{temp}.{ident(node.attr)}"

    def operator_args(self, node: ast.Call, count: int) -> list[ast.expr]:
        if node.keywords or len(node.args) != count:
            self.fail(node, f"{ast.unparse(node.func)}() with other than {count} positional arguments")
        return list(node.args)

    def member_text(self, holder: ast.expr, field: ast.expr) -> str:
        if not (isinstance(field, ast.Constant) and isinstance(field.value, str)):
            self.fail(field, "a member name that is not a string literal")
        if isinstance(holder, ast.Name) and holder.id == "self":
            return self.attribute(ast.Attribute(holder, field.value, ast.Load()))
        return f"{self.expr(holder, _ATOM)[0]}.{field_ident(_class_of(self.typeof(holder)), field.value)}"

    def address_operand(self, node: ast.Call) -> str:
        """``adr(obj)`` / ``adr(obj, "field")`` / ``adr(array, index)``: the variable ADR takes."""
        if node.keywords or not 1 <= len(node.args) <= 3:
            self.fail(node, "adr() with these arguments")
        holder = node.args[0]
        if len(node.args) == 1:
            return self.expr(holder, _ATOM)[0]
        text = self.member_text(holder, node.args[1]) if isinstance(node.args[1], ast.Constant) and isinstance(node.args[1].value, str) else f"{self.expr(holder, _ATOM)[0]}[{self.expr(node.args[1])[0]}]"
        if len(node.args) == 3:
            text += f"[{self.expr(node.args[2])[0]}]"
        return text

    def ref_target(self, node: ast.expr) -> str:
        if isinstance(node, ast.Constant) and node.value is None:
            return "0"
        if isinstance(node, ast.Call) and self.resolves_to(node.func, "adr"):
            return self.address_operand(node)
        info = self.typeof(node)
        if isinstance(info, PointerInfo):
            return f"{self.expr(node, _ATOM)[0]}^"
        return self.expr(node)[0]

    def call(self, node: ast.Call) -> tuple[str, int]:
        """A call: of a name (a table of rules by name), of a METHOD, of a block instance."""
        func = node.func
        if isinstance(func, ast.Call) and _is_name(func.func, "super"):
            self.fail(node, "super()()")
        if isinstance(func, ast.Name) and func.id not in self.locals and func.id not in self.params:
            return self.named_call(node, func.id)
        if isinstance(func, ast.Attribute):
            found = self.method_call(node, func)
            if found is not None:
                return found
        callee = self.expr(func, _ATOM)[0]
        block = self.typeof(func)
        in_outs = _in_out_names(block.cls) if isinstance(block, AggregateInfo) else frozenset()
        return f"{callee}({self.arguments(node, in_outs)})", _ATOM

    def method_call(self, node: ast.Call, func: ast.Attribute) -> tuple[str, int] | None:
        """``super().m()``, ``module.f()``, ``pointer.typed(T)``, ``a.get().m()``; None for a plain ``obj.m()``."""
        if isinstance(func.value, ast.Call) and _is_name(func.value.func, "super"):
            if func.attr == "body":
                return "SUPER^()", _ATOM
            return f"SUPER^.{func.attr}({self.arguments(node)})", _ATOM
        if isinstance(self.constant_object(func.value), type(inspect)):
            return self.named_call(node, func.attr)
        if func.attr == "typed" and isinstance(self.typeof(func.value), PointerInfo):
            # Pointer.typed(T): ST converts between POINTER types on assignment.
            return self.expr(func.value)
        if isinstance(func.value, ast.Call) and not _is_task_info(self, func.value):
            # A method of a returned interface: TwinCAT and CODESYS chain the calls (fluent interfaces).
            return f"{self.call(func.value)[0]}.{ident(func.attr)}({self.arguments(node)})", _ATOM
        self.python_method(func)
        return None

    def python_method(self, func: ast.Attribute) -> None:
        """Refuse a Python method of a value (``name.upper()``): ST has no methods on elementary values."""
        info = self.typeof(func.value)
        if isinstance(info, (ElementaryInfo, StringInfo, EnumInfo)):
            self.fail(func, f"the Python method {func.attr}() of a {info.name} value")

    def arguments(self, node: ast.Call, in_outs: frozenset[str] = frozenset()) -> str:
        callee = self.callee(node)
        sections = parameter_sections(callee) if callee is not None else {}
        if sections:
            return self.formal_arguments(node, callee, sections)
        parts = [self.expr(a)[0] for a in node.args]
        block = _class_of(self.typeof(node.func))  # a block's inputs keep their ST names: fb(st_bIn_=x) is fb(_bIn := x)
        for kw in node.keywords:
            if kw.arg is None:
                self.fail(node, "**arguments")
            value = kw.value
            if kw.arg in in_outs and isinstance(value, ast.Call) and self.resolves_to(value.func, "adr"):
                # fb(buffer=adr(self, "data")) binds a VAR_IN_OUT: ST passes the variable itself.
                parts.append(f"{field_ident(block, kw.arg)} := {self.address_operand(value)}")
                continue
            parts.append(f"{field_ident(block, kw.arg)} := {self.expr(value)[0]}")
        return ", ".join(parts)

    def callee(self, node: ast.Call) -> Any:
        """The METHOD or FUNCTION a call runs, when the writer can tell (its VAR_OUTPUTs need ``=>``)."""
        func = node.func
        if isinstance(func, ast.Name):
            return self.globals.get(func.id) if func.id not in self.locals and func.id not in self.params else None
        if not isinstance(func, ast.Attribute):
            return None
        base = func.value
        if isinstance(base, ast.Call) and _is_name(base.func, "super"):
            cls = self.scope.cls.__mro__[1]
        elif isinstance(base, ast.Name) and base.id == "self" and "self" not in self.locals:
            cls = self.scope.cls
        else:
            cls = _class_of(self.typeof(base))
        found = _member_function(cls, func.attr) if cls is not None else None
        return found[0] if found is not None else None

    def formal_arguments(self, node: ast.Call, callee: Any, sections: dict[str, Any]) -> str:
        """Every argument by name, outputs with ``=>``: ``Split(nValue := 1000, nHigh => nHi, nCount := nCalls)``."""
        names = [p.name for p in inspect.signature(callee).parameters.values()]
        if names and names[0] == "self" and isinstance(node.func, ast.Attribute):
            names = names[1:]
        if len(node.args) > len(names):
            self.fail(node, "more positional arguments than the callee declares")
        given = list(zip(names, node.args))
        for kw in node.keywords:
            if kw.arg is None:
                self.fail(node, "**arguments")
            given.append((kw.arg, kw.value))
        parts = []
        for name, value in given:
            spec = sections.get(name)
            if spec is None:
                parts.append(f"{ident(name)} := {self.expr(value)[0]}")
            else:
                arrow = "=>" if spec.section == "VAR_OUTPUT" else ":="
                parts.append(f"{ident(name)} {arrow} {self.variable_argument(value)}")
        return ", ".join(parts)

    def variable_argument(self, node: ast.expr) -> str:
        """The caller's variable an output / in-out is bound to: ``adr(self, "x")`` is ``x``."""
        if isinstance(node, ast.Call) and self.resolves_to(node.func, "adr"):
            return self.address_operand(node)
        if isinstance(node, ast.Name) and node.id in self.by_reference:
            return ident(node.id)  # an output / in-out of this METHOD passed on
        info = self.typeof(node)
        if isinstance(info, PointerInfo):
            return f"{self.expr(node, _ATOM)[0]}^"
        self.fail(node, "an output or in-out bound to something that is not adr(...) of a variable")

    def named_call(self, node: ast.Call, name: str) -> tuple[str, int]:
        value = self.globals.get(name)
        library = _from_iecoop(value)
        # DT and TOD are an Annotated type that parses its literal: its __module__ is typing's on 3.12
        if name == "T" and value is T or name == "D" and value is D or name == "LTIME" and library \
                or name == "DT" and value is iec_types.DT or name == "TOD" and value is iec_types.TOD:
            return self.time_literal(node, name), _ATOM
        # A builtin only while no module name hides it; iecoop's operators only when they are iecoop's.
        rules = _BUILTIN_CALLS if value is None else _LIBRARY_CALLS if library else {}
        rule = rules.get(name)
        found = rule(self, node) if rule is not None else None
        if found is not None:
            return found
        if library and callable(value) and (name.isupper() or name[:1].isupper() and "_TO_" in name or library_name(name, value)):
            # iecoop's IEC functions carry their ST names (TO_INT, LIMIT, SHL, REAL_TO_INT...), a shipped
            # library's FUNCTIONs theirs (Tc2_Utilities' LrealIsNaN).
            return f"{name}({self.arguments(node)})", _ATOM
        found = self.declared_call(node, name, value)
        if found is not None:
            return found
        self.fail(node, f"a call of {name}()")

    def declared_call(self, node: ast.Call, name: str, value: Any) -> tuple[str, int] | None:
        """A call of a PROGRAM, of an enumeration (a value to a component) or of a module function (a FUNCTION)."""
        if kind_of(type(value)) == "program":
            # a PROGRAM (st.load makes each one an instance) called from another POU: PRG_Dose(), with its inputs
            return f"{ident(name)}({self.arguments(node)})", _ATOM
        if kind_of(value) == "enum" and _one_argument(node) is not None:
            # Mode(n): an integer is a component's value in ST (a non-strict enumeration takes it as is).
            return self.expr(node.args[0])
        if self.function_signature(value) is not None:
            known = self.scope.functions.get(name, value)
            if known is not value:
                raise StExportError(f"{self.where_text(node)}: two functions named {name} are called")
            self.scope.functions[name] = value
            return f"{ident(name)}({self.arguments(node)})", _ATOM
        return None

    def time_literal(self, node: ast.Call, name: str) -> str:
        """``T("2s")`` / ``LTIME("1ms")`` / ``D("2024-01-31")`` / ``DT(...)`` / ``TOD(...)``: the typed ST literal."""
        args = node.args
        if len(args) != 1 or not (isinstance(args[0], ast.Constant) and isinstance(args[0].value, str)):
            self.fail(node, f"{name}() of a value that is not a string literal")
        text = args[0].value
        if name == "T":
            return format_time(T(text)).upper()
        if name == "D":
            return format_date(D(text))
        if name == "DT":
            return format_dt(parse_dt(text))
        if name == "TOD":
            return format_tod(parse_tod(text))
        return format_ltime(parse_ltime(text)).upper()





#: The global variable list the module constants a body reads are declared in.
_CONSTANTS_GVL = "GVL_Constants"


def library_name(name: str, value: Any) -> bool:
    """``name`` is what a shipped library declares by that name (a constant, a FUNCTION): never in the export."""
    from iecoop.libraries import KNOWN

    for library in KNOWN:
        module = sys.modules.get(library.module)  # only a library the exported code imported can be where it is from
        if module is not None and name in getattr(module, "__all__", ()) and getattr(module, name, None) == value:
            return True
    return False


def _bound_function(w: ExpressionWriter, node: ast.Subscript) -> str | None:
    """``a.bounds[d - 1][0]`` / ``[1]``, an ARRAY's bounds in dimension d: ``LOWER_BOUND(a, d)`` / ``UPPER_BOUND(a, d)``."""
    inner = node.value
    if not (isinstance(inner, ast.Subscript) and isinstance(inner.value, ast.Attribute) and inner.value.attr == "bounds"
            and isinstance(node.slice, ast.Constant) and node.slice.value in (0, 1)):
        return None
    info = w.typeof(inner.value.value)
    if not isinstance(info.target if isinstance(info, ReferenceInfo) else info, (ArrayInfo, OpenArrayInfo)):
        return None
    dim = inner.slice
    if isinstance(dim, ast.BinOp) and isinstance(dim.op, ast.Sub) and isinstance(dim.right, ast.Constant) and dim.right.value == 1:
        text = w.expr(dim.left)[0]  # the reader's `d - 1`
    elif isinstance(dim, ast.Constant) and isinstance(dim.value, int) and not isinstance(dim.value, bool):
        text = str(dim.value + 1)
    else:
        text = f"{w.expr(dim, _ADD)[0]} + 1"
    word = "LOWER_BOUND" if node.slice.value == 0 else "UPPER_BOUND"
    return f"{word}({w.expr(inner.value.value)[0]}, {text})"


def _paren(text: str, prec: int, need: int) -> str:
    return f"({text})" if prec < need else text


_DESCRIPTIONS = {
    "Raise": "raise", "Try": "try / except", "Match": "match", "JoinedStr": "an f-string",
    "GeneratorExp": "a generator expression", "ListComp": "a list comprehension", "Lambda": "lambda",
    "Delete": "del", "Global": "global", "Nonlocal": "nonlocal", "Import": "import", "ImportFrom": "import",
    "FunctionDef": "a nested def", "ClassDef": "a nested class", "Assert": "assert", "List": "a list",
    "Dict": "a dict", "Tuple": "a tuple", "Set": "a set", "Yield": "yield", "Await": "await",
    "AsyncFor": "async for", "AsyncWith": "async with", "Starred": "*unpacking", "NamedExpr": "the := operator",
}


def _describe(node: ast.AST) -> str:
    return _DESCRIPTIONS.get(type(node).__name__, type(node).__name__)


#: Types whose *_TO_STRING text is the one Python's f-string gives (decimal digits, a minus sign).


_REAL_IN_TEXT = "round to an integer and write CONCAT(...) with DINT_TO_STRING(...), or LREAL_TO_STRING(...), whose text differs from Python's"


def _piece_refusal(info: TypeInfo | None) -> str:
    """What an f-string value is that ST would write differently, and what to write instead."""
    if _is_real(info):
        return f"a REAL value in an f-string (Python writes repr(): {_REAL_IN_TEXT})"
    kind = getattr(getattr(info, "record", None), "kind", None)
    if kind in ("time", "date"):
        return "a TIME or DATE value in an f-string (Python writes the number, TIME_TO_STRING writes T#...: write CONCAT(...) with TIME_TO_DINT(...) or TIME_TO_STRING(...))"
    if isinstance(info, EnumInfo):
        return "an enumeration value in an f-string (Python writes its number: write {x.name} for its name, or its base type's *_TO_STRING)"
    if isinstance(info, StringInfo):
        return "a WSTRING in an f-string (write CONCAT(...) with WSTRING_TO_STRING(...))"
    return "a value of unknown type in an f-string (give it an IEC type annotation)"


_CallRule = Callable[[ExpressionWriter, ast.Call], "tuple[str, int] | None"]


def _one_argument(node: ast.Call) -> ast.expr | None:
    return node.args[0] if len(node.args) == 1 and not node.keywords else None


def _call_min_max_abs(w: ExpressionWriter, node: ast.Call) -> tuple[str, int]:
    return f"{BUILTIN_FUNCTIONS[typing.cast(ast.Name, node.func).id]}({w.arguments(node)})", _ATOM


def _call_bool(w: ExpressionWriter, node: ast.Call) -> tuple[str, int] | None:
    arg = _one_argument(node)
    if arg is None:
        return None
    if _is_bool(w.typeof(arg)):
        return w.expr(arg)[0], _ATOM
    return f"{w.expr(arg, _EQ + 1)[0]} <> 0", _EQ


def _call_str_of_enum(w: ExpressionWriter, node: ast.Call) -> tuple[str, int] | None:
    """``str(getattr(e, "name", int(e)))``, the reader's ``TO_STRING(e)`` of an enumeration: ``TO_STRING(e)``."""
    arg = _one_argument(node)
    if not (
        isinstance(arg, ast.Call) and _is_name(arg.func, "getattr") and len(arg.args) == 3 and not arg.keywords
        and isinstance(arg.args[1], ast.Constant) and arg.args[1].value == "name"
        and isinstance(arg.args[2], ast.Call) and _is_name(arg.args[2].func, "int") and len(arg.args[2].args) == 1
        and ast.dump(arg.args[2].args[0]) == ast.dump(arg.args[0])
    ):
        return None
    info = w.typeof(arg.args[0])
    if isinstance(info, EnumInfo):  # the names need {attribute 'to_string'} on the enumeration
        w.scope.named_enums.add(info.enum_cls)
    return f"TO_STRING({w.expr(arg.args[0])[0]})", _ATOM


def _call_int(w: ExpressionWriter, node: ast.Call) -> tuple[str, int] | None:
    arg = _one_argument(node)
    if arg is None:
        return None
    info, inner = w.typeof(arg), w.expr(arg)[0]
    if _is_integer(info):
        return inner, _ATOM
    # int() of a float truncates towards zero, as TRUNC does.
    return (f"TRUNC({inner})" if _is_real(info) else f"TO_DINT({inner})"), _ATOM


def _call_float(w: ExpressionWriter, node: ast.Call) -> tuple[str, int] | None:
    arg = _one_argument(node)
    return (f"TO_LREAL({w.expr(arg)[0]})", _ATOM) if arg is not None else None


def _call_len(w: ExpressionWriter, node: ast.Call) -> tuple[str, int] | None:
    arg = _one_argument(node)
    if arg is None or not isinstance(w.typeof(arg), StringInfo):
        return None
    return f"LEN({w.expr(arg)[0]})", _ATOM


def _call_round(w: ExpressionWriter, node: ast.Call) -> tuple[str, int] | None:
    arg = _one_argument(node)
    if arg is None:
        w.fail(node, "round() with a number of digits (ST rounds only to an integer: LREAL_TO_DINT(x))")
    info = w.typeof(arg)
    if _is_integer(info):
        return w.expr(arg)
    if not _is_real(info):
        return None
    # Python rounds half to even; so does iecoop's REAL_TO_DINT in both vendor profiles (x64 SSE rounding).
    return f"{typing.cast(ElementaryInfo, info).record.name}_TO_DINT({w.expr(arg)[0]})", _ATOM


def _call_len_constant(w: ExpressionWriter, node: ast.Call) -> tuple[str, int] | None:
    """len() of a module constant (a tuple, a string) or of an enumeration: a number the PLC knows at compile time."""
    arg = _one_argument(node)
    if arg is None:
        return _call_len(w, node)
    if isinstance(arg, ast.Name):
        value = w.globals.get(arg.id) if arg.id not in w.locals and arg.id not in w.params else None
    else:
        value = w.constant_object(arg)
    if isinstance(value, (tuple, str)) or isinstance(value, type) and issubclass(value, enum.Enum):
        return str(len(value)), _ATOM
    return _call_len(w, node)


def _call_math(w: ExpressionWriter, node: ast.Call) -> tuple[str, int] | None:
    """``math.sin(x)``...: Python computes in double precision, so a REAL argument goes to LREAL first."""
    func = node.func
    arg = _one_argument(node)
    if not (isinstance(func, ast.Attribute) and w.constant_object(func.value) is math) or arg is None:
        return None
    info = w.typeof(arg)
    if not (_is_real(info) or _is_integer(info)):
        return None
    text = w.expr(arg)[0]
    if typing.cast(ElementaryInfo, info).record.name != "LREAL":
        text = f"TO_LREAL({text})"
    return f"{MATH_BY_PYTHON[func.attr]}({text})", _ATOM


def _call_adr(w: ExpressionWriter, node: ast.Call) -> tuple[str, int]:
    return f"ADR({w.address_operand(node)})", _ATOM


def _call_sizeof(w: ExpressionWriter, node: ast.Call) -> tuple[str, int]:
    args = node.args
    if len(args) == 2:
        return f"SIZEOF({w.member_text(args[0], args[1])})", _ATOM
    return f"SIZEOF({w.expr(args[0])[0]})", _ATOM


def _call_is_valid_ref(w: ExpressionWriter, node: ast.Call) -> tuple[str, int]:
    holder, field = w.operator_args(node, 2)
    return f"__ISVALIDREF({w.member_text(holder, field)})", _ATOM


def _call_test_and_set(w: ExpressionWriter, node: ast.Call) -> tuple[str, int]:
    (flag,) = w.operator_args(node, 1)
    if isinstance(flag, ast.Call) and w.resolves_to(flag.func, "adr"):
        return f"TestAndSet({w.address_operand(flag)})", _ATOM
    return f"TestAndSet({w.expr(flag)[0]}^)", _ATOM


def _call_var_info(w: ExpressionWriter, node: ast.Call) -> tuple[str, int]:
    holder, field = w.operator_args(node, 2)
    return f"__VARINFO({w.member_text(holder, field)})", _ATOM


def _call_mod(w: ExpressionWriter, node: ast.Call) -> tuple[str, int] | None:
    if len(node.args) != 2:
        return None
    return f"{w.expr(node.args[0], _MUL)[0]} MOD {w.expr(node.args[1], _MUL + 1)[0]}", _MUL


def _call_shift(w: ExpressionWriter, node: ast.Call) -> tuple[str, int] | None:
    """``SHL(x, n, WORD)`` (iecoop's shifts and rotations take the width as a type): ST's ``SHL(x, n)``, a literal
    operand given the width as its type (``ROL(WORD#1, 3)``), since the operand's type is the width in ST."""
    if node.keywords or len(node.args) != 3:
        return None
    value, count, width = node.args
    if not (isinstance(width, ast.Name) and width.id in ELEMENTARY):
        w.fail(node, f"a {typing.cast(ast.Name, node.func).id}() whose width is not a type name")
    constant = _constant_int(value)
    operand = f"{width.id}#{constant}" if constant is not None and constant >= 0 else w.expr(value)[0]
    return f"{typing.cast(ast.Name, node.func).id}({operand}, {w.expr(count)[0]})", _ATOM


def _call_get_bit(w: ExpressionWriter, node: ast.Call) -> tuple[str, int] | None:
    """``get_bit(x, 3)``: ST's bit access ``x.3``."""
    bit = _constant_int(node.args[1]) if len(node.args) == 2 and not node.keywords else None
    if bit is None:
        w.fail(node, "get_bit() with a bit number that is not a constant")
    return f"{w.expr(node.args[0], _ATOM)[0]}.{bit}", _ATOM


def _call_div(w: ExpressionWriter, node: ast.Call) -> tuple[str, int] | None:
    """``DIV(a, b)`` (iecoop's division as ST's ``/`` does it, truncating integers): ``a / b``."""
    if node.keywords or len(node.args) != 2:
        return None
    return w.binary(ast.BinOp(node.args[0], ast.Div(), node.args[1]), "/")


def _call_operator(w: ExpressionWriter, node: ast.Call) -> tuple[str, int]:
    return f"{OPERATOR_FUNCTIONS[typing.cast(ast.Name, node.func).id]}({w.arguments(node)})", _ATOM


def _call_current_task(w: ExpressionWriter, node: ast.Call) -> tuple[str, int]:
    # TwinCAT's task information array (Tc2_System); CODESYS has no such array.
    return "_TaskInfo[GETCURTASKINDEXEX()]", _ATOM


#: Python builtins (while no module name hides them) and their ST form.
_BUILTIN_CALLS: dict[str, _CallRule] = {
    "min": _call_min_max_abs, "max": _call_min_max_abs, "abs": _call_min_max_abs,
    "bool": _call_bool, "int": _call_int, "str": _call_str_of_enum, "float": _call_float, "len": _call_len_constant, "round": _call_round,
    **{name: _call_math for name in MATH_BY_PYTHON},
}


#: iecoop's operators (only when the name is iecoop's) and their ST form.
_LIBRARY_CALLS: dict[str, _CallRule] = {
    **{name: _call_operator for name in OPERATOR_FUNCTIONS},
    "adr": _call_adr, "sizeof": _call_sizeof, "is_valid_ref": _call_is_valid_ref, "test_and_set": _call_test_and_set,
    "now_ms": lambda w, node: ("TIME()", _ATOM), "MOD": _call_mod, "current_task": _call_current_task,
    "var_info": _call_var_info, "get_bit": _call_get_bit, "DIV": _call_div,
    **{name: _call_shift for name in ("SHL", "SHR", "ROL", "ROR")},
    # null(ITF): the null reference of an interface; ST writes 0 for every interface type.
    "null": lambda w, node: ("0", _ATOM),
}




