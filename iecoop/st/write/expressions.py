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
import typing
from collections.abc import Callable
from typing import Any

from iecoop.metadata import kind_of
from iecoop.exceptions import ExceptionCode
from iecoop.literals import D, T, format_date, format_ltime, format_time, parse_ltime
from iecoop.parameters import parameter_sections
from iecoop.memory.typeinfo import (
    AggregateInfo,
    ArrayInfo,
    ElementaryInfo,
    EnumInfo,
    InterfaceInfo,
    ReferenceInfo,
    StringInfo,
    TypeInfo,
    class_info,
)
from iecoop.memory.pointers import PointerInfo
from iecoop.st.write.infer import (
    _MATH,
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
from iecoop.st.write.model import StExportError, ident, type_text

__all__ = ["ExpressionWriter", "literal"]

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

    def declare(self, name: str, info: TypeInfo | str, node: ast.AST) -> None:
        if name.lower() in {f.lower() for f in self.fields} and name not in self.params and self.func.__name__ == "body":
            self.temp_name(name)
        self.locals[name] = info

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
        text, prec = self._expr(node)
        return (_paren(text, prec, need), _ATOM if prec < need else prec)

    def _expr(self, node: ast.expr) -> tuple[str, int]:
        """ST text of an expression and its precedence, by the rule for its node type (_EXPR_RULES)."""
        rule = _EXPR_RULES.get(type(node))
        if rule is None:
            self.fail(node, _describe(node))
        return rule(self, node)

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
        if name in _INTEGER_NAMES:
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
        parts: list[str] = []
        left = node.left
        for op, right in zip(node.ops, node.comparators):
            if isinstance(op, (ast.In, ast.NotIn)):
                if not isinstance(right, (ast.Tuple, ast.List, ast.Set)):
                    self.fail(node, "'in' over something other than a literal tuple")
                word, join = ("=", " OR ") if isinstance(op, ast.In) else ("<>", " AND ")
                lhs = self.expr(left, _EQ + 1)[0]
                tests = [f"{lhs} {word} {self.expr(e, _EQ + 1)[0]}" for e in right.elts]
                parts.append("(" + join.join(tests) + ")" if len(tests) > 1 else tests[0])
            else:
                symbol, prec = _COMPARE[type(op)]
                parts.append(f"{self.expr(left, prec + 1)[0]} {symbol} {self.expr(right, prec + 1)[0]}")
            left = right
        if len(parts) == 1:
            only = parts[0]
            prec = _EQ if isinstance(node.ops[0], (ast.Eq, ast.NotEq, ast.Is, ast.IsNot)) else _CMP
            return only, (_ATOM if only.startswith("(") and only.endswith(")") else prec)
        return " AND ".join(p if p.startswith("(") else f"({p})" for p in parts), _AND

    def binop(self, node: ast.BinOp, where: ast.AST) -> tuple[str, int]:
        if isinstance(node.op, (ast.LShift, ast.RShift)):
            word = "SHL" if isinstance(node.op, ast.LShift) else "SHR"
            value = _constant_int(node.left)
            # SHL's result has its operand's width: a literal needs one (Python's integers have none).
            operand = f"DWORD#{value}" if value is not None and 0 <= value < 2**32 else self.expr(node.left)[0]
            return f"{word}({operand}, {self.expr(node.right)[0]})", _ATOM
        if isinstance(node.op, ast.Pow):
            return f"EXPT({self.expr(node.left)[0]}, {self.expr(node.right)[0]})", _ATOM
        op = _BINOPS.get(type(node.op))
        if op is None:
            self.fail(where, f"the operator {type(node.op).__name__}")
        symbol, prec = op
        left, right = node.left, node.right
        left_text = self.expr(left, prec)[0]
        right_text = self.expr(right, prec + 1)[0]
        if isinstance(node.op, ast.Div):
            lt, rt = self.typeof(left), self.typeof(right)
            if _is_whole(lt) and _is_whole(rt):
                # Python's / on integers (and on TIMEs, which are milliseconds) gives a float; ST's gives
                # an integer or a TIME.
                left_text = f"TO_LREAL({self.expr(left)[0]})"
                if _is_time(rt):
                    right_text = f"TO_LREAL({self.expr(right)[0]})"
        if isinstance(node.op, ast.FloorDiv) and (_is_real(self.typeof(left)) or _is_real(self.typeof(right))):
            self.fail(where, "// on REAL values (ST has no floor division: TRUNC(a / b) is the same where a / b >= 0)")
        return f"{left_text} {symbol} {right_text}", prec

    def name(self, node: ast.Name) -> str:
        name = node.id
        if name in self.rename:
            return self.rename[name]
        if name in self.locals or name in self.params:
            return self.temp_names.get(name) or ident(name)
        if name == "self":
            return "THIS^"
        if name in ("True", "False"):
            return name.upper()
        if name in ("NULL", "None"):
            return "0"
        if name in self.globals:
            value = self.globals[name]
            if isinstance(value, (bool, int, float, str)) and not isinstance(value, enum.Enum):
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
            if isinstance(value, type):
                return value.__name__
            if kind_of(type(value)) == "gvl":
                return type(value).__name__
            if typing.get_origin(value) is typing.Annotated:
                from iecoop.memory.typeinfo import resolve_type as _resolve

                try:
                    return type_text(_resolve(value, name))
                except Exception:
                    pass
        self.fail(node, f"the name {name!r}")

    def attribute(self, node: ast.Attribute) -> str:
        base = node.value
        attr = node.attr
        if isinstance(base, ast.Name) and base.id == "self" and base.id not in self.locals:
            # A local, input or the result of the same name (ST ignores case) hides the variable: THIS^ reaches it.
            hiding = [n for n in self.locals if n not in self.temp_names] + [*self.bound, *self.params, *self.rename.values(), self.st_name]
            if attr.lower() in {n.lower() for n in hiding}:
                return f"THIS^.{ident(attr)}"
            return ident(attr)
        if attr == "deref" and isinstance(base, ast.Name) and base.id in self.by_reference:
            return ident(base.id)
        if attr == "deref":
            return f"{self.expr(base, _ATOM)[0]}^"
        if isinstance(base, ast.Name) and base.id in self.catch_vars and attr == "code":
            return base.id
        owner = self.constant_object(base)
        if owner is not None:
            if owner is ExceptionCode:
                return f"__SYSTEM.ExceptionCode.{attr}"
            if isinstance(owner, type) and issubclass(owner, enum.Enum):
                return f"{owner.__name__}.{ident(attr)}"
            self.fail(node, f"the attribute {ast.unparse(node)}")
        if isinstance(base, ast.Call) and _is_name(base.func, "super"):
            return f"SUPER^.{ident(attr)}"
        if attr in ("low", "high") and isinstance(self.typeof(base), ArrayInfo):
            # An ARRAY's bounds are its declaration's constants (LOWER_BOUND / UPPER_BOUND give the same).
            bounds = typing.cast(ArrayInfo, self.typeof(base)).bounds
            if len(bounds) == 1:
                return str(bounds[0][0 if attr == "low" else 1])
        if attr == "name" and isinstance(self.typeof(base), EnumInfo):
            # TO_STRING gives a component's name where the enumeration has {attribute 'to_string'}.
            self.scope.named_enums.add(typing.cast(EnumInfo, self.typeof(base)).enum_cls)
            return f"TO_STRING({self.expr(base)[0]})"
        if isinstance(base, ast.Call):
            return self.call_member(node, base)
        return f"{self.expr(base, _ATOM)[0]}.{ident(attr)}"

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
        return f"{self.expr(holder, _ATOM)[0]}.{field.value}"

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
        func = node.func
        if isinstance(func, ast.Call) and _is_name(func.func, "super"):
            self.fail(node, "super()()")
        if isinstance(func, ast.Attribute) and isinstance(func.value, ast.Call) and _is_name(func.value.func, "super"):
            if func.attr == "body":
                return "SUPER^()", _ATOM
            return f"SUPER^.{func.attr}({self.arguments(node)})", _ATOM
        if isinstance(func, ast.Name) and func.id not in self.locals and func.id not in self.params:
            return self.named_call(node, func.id)
        if isinstance(func, ast.Attribute) and self.constant_object(func.value) is not None and isinstance(self.constant_object(func.value), type(inspect)):
            return self.named_call(node, func.attr)
        if isinstance(func, ast.Attribute) and func.attr == "typed" and isinstance(self.typeof(func.value), PointerInfo):
            # Pointer.typed(T): ST converts between POINTER types on assignment.
            return self.expr(func.value)
        if isinstance(func, ast.Attribute) and isinstance(func.value, ast.Call) and not _is_task_info(self, func.value):
            # A method of a returned interface: TwinCAT and CODESYS chain the calls (fluent interfaces).
            return f"{self.call(func.value)[0]}.{ident(func.attr)}({self.arguments(node)})", _ATOM
        if isinstance(func, ast.Attribute):
            self.python_method(func)
        callee = self.expr(func, _ATOM)[0]
        block = self.typeof(func)
        in_outs = _in_out_names(block.cls) if isinstance(block, AggregateInfo) else frozenset()
        return f"{callee}({self.arguments(node, in_outs)})", _ATOM

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
        for kw in node.keywords:
            if kw.arg is None:
                self.fail(node, "**arguments")
            value = kw.value
            if kw.arg in in_outs and isinstance(value, ast.Call) and self.resolves_to(value.func, "adr"):
                # fb(buffer=adr(self, "data")) binds a VAR_IN_OUT: ST passes the variable itself.
                parts.append(f"{ident(kw.arg)} := {self.address_operand(value)}")
                continue
            parts.append(f"{ident(kw.arg)} := {self.expr(value)[0]}")
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
        if name == "T" and value is T or name == "D" and value is D or name == "LTIME" and library:
            return self.time_literal(node, name), _ATOM
        # A builtin only while no module name hides it; iecoop's operators only when they are iecoop's.
        rules = _BUILTIN_CALLS if value is None else _LIBRARY_CALLS if library else {}
        rule = rules.get(name)
        found = rule(self, node) if rule is not None else None
        if found is not None:
            return found
        if library and callable(value) and (name.isupper() or name[:1].isupper() and "_TO_" in name):
            # iecoop's IEC functions carry their ST names (TO_INT, LIMIT, SHL, REAL_TO_INT...).
            return f"{name}({self.arguments(node)})", _ATOM
        if kind_of(value) == "enum" and _one_argument(node) is not None:
            # Mode(n): an integer is a component's value in ST (a non-strict enumeration takes it as is).
            return self.expr(node.args[0])
        if self.function_signature(value) is not None:
            known = self.scope.functions.get(name, value)
            if known is not value:
                raise StExportError(f"{self.where_text(node)}: two functions named {name} are called")
            self.scope.functions[name] = value
            return f"{ident(name)}({self.arguments(node)})", _ATOM
        self.fail(node, f"a call of {name}()")

    def time_literal(self, node: ast.Call, name: str) -> str:
        """``T("2s")`` / ``LTIME("1ms")`` / ``D("2024-01-31")``: the typed ST literal."""
        args = node.args
        if len(args) != 1 or not (isinstance(args[0], ast.Constant) and isinstance(args[0].value, str)):
            self.fail(node, f"{name}() of a value that is not a string literal")
        text = args[0].value
        if name == "T":
            return format_time(T(text)).upper()
        if name == "D":
            return format_date(D(text))
        return format_ltime(parse_ltime(text)).upper()



#: ST operator precedence, loosest first (parentheses are added where a child binds looser).
_OR, _XOR, _AND, _EQ, _CMP, _ADD, _MUL, _UNARY, _ATOM = range(1, 10)


_BINOPS: dict[type, tuple[str, int]] = {
    ast.Add: ("+", _ADD), ast.Sub: ("-", _ADD), ast.Mult: ("*", _MUL), ast.Div: ("/", _MUL),
    ast.FloorDiv: ("/", _MUL), ast.Mod: ("MOD", _MUL), ast.BitAnd: ("AND", _AND), ast.BitOr: ("OR", _OR),
    ast.BitXor: ("XOR", _XOR),
}


_COMPARE: dict[type, tuple[str, int]] = {
    ast.Eq: ("=", _EQ), ast.NotEq: ("<>", _EQ), ast.Lt: ("<", _CMP), ast.LtE: ("<=", _CMP),
    ast.Gt: (">", _CMP), ast.GtE: (">=", _CMP), ast.Is: ("=", _EQ), ast.IsNot: ("<>", _EQ),
}


#: Python builtins and their IEC standard functions.
_BUILTINS = {"min": "MIN", "max": "MAX", "abs": "ABS"}


#: iecoop operators with an ST operator of another spelling.
_OPERATORS = {
    "adr": "ADR", "sizeof": "SIZEOF", "memcpy": "MEMCPY", "memset": "MEMSET", "memcmp": "MEMCMP",
    "new": "__NEW", "delete": "__DELETE", "test_and_set": "TestAndSet",
}


#: The global variable list the module constants a body reads are declared in.
_CONSTANTS_GVL = "GVL_Constants"


def _real_text(value: float) -> str:
    text = repr(float(value))
    if "inf" in text or "nan" in text:
        raise ValueError(f"{value!r} has no ST literal")
    mantissa, _, exponent = text.partition("e")
    if "." not in mantissa:
        mantissa += ".0"
    return f"{mantissa}E{exponent}" if exponent else mantissa


#: ST's named string escapes (IEC 61131-3, 6.3.3); every other control character is ``$`` and its code in hex.
_ESCAPES = {"$": "$$", "\n": "$N", "\t": "$T", "\r": "$R", "\f": "$P"}


def _string_text(value: str, quote: str = "'") -> str:
    """A STRING ('...', ``$xx``) or WSTRING ("...", ``$xxxx``) literal: no control character is written as it is,
    so the text stays one line and the TwinCAT and PLCopen XML stay well-formed."""
    digits = 2 if quote == "'" else 4
    out = []
    for char in value:
        if char in _ESCAPES or char == quote:
            out.append(_ESCAPES.get(char) or "$" + char)
        elif char < " " or "\x7f" <= char <= "\x9f":
            out.append(f"${ord(char):0{digits}X}")
        else:
            out.append(char)
    return quote + "".join(out) + quote


def literal(value: Any, info: TypeInfo | None = None) -> str:
    """A Python value as an ST literal of type ``info`` (TIME values as ``T#...``)."""
    if isinstance(value, enum.Enum):
        return f"{type(value).__name__}.{ident(value.name)}"
    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    if isinstance(info, ElementaryInfo) and isinstance(value, int):
        kind, name = info.record.kind, info.record.name
        if name == "TIME":
            return format_time(value).upper()
        if name == "LTIME":
            return format_ltime(value).upper()
        if name == "DATE":
            return format_date(value)
        if kind == "real":
            return _real_text(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return _real_text(value)
    if isinstance(value, str):
        return _string_text(value, '"' if isinstance(info, StringInfo) and info.record.name == "WSTRING" else "'")
    if value is None:
        return "0"
    raise ValueError(f"{value!r} has no ST literal")


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
_INTEGER_NAMES = frozenset("SINT INT DINT LINT USINT UINT UDINT ULINT BYTE WORD DWORD LWORD".split())


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
    return f"{_BUILTINS[typing.cast(ast.Name, node.func).id]}({w.arguments(node)})", _ATOM


def _call_bool(w: ExpressionWriter, node: ast.Call) -> tuple[str, int] | None:
    arg = _one_argument(node)
    if arg is None:
        return None
    if _is_bool(w.typeof(arg)):
        return w.expr(arg)[0], _ATOM
    return f"{w.expr(arg, _EQ + 1)[0]} <> 0", _EQ


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
    return f"{_MATH[func.attr]}({text})", _ATOM


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


def _call_operator(w: ExpressionWriter, node: ast.Call) -> tuple[str, int]:
    return f"{_OPERATORS[typing.cast(ast.Name, node.func).id]}({w.arguments(node)})", _ATOM


def _call_current_task(w: ExpressionWriter, node: ast.Call) -> tuple[str, int]:
    # TwinCAT's task information array (Tc2_System); CODESYS has no such array.
    return "_TaskInfo[GETCURTASKINDEXEX()]", _ATOM


#: Python builtins (while no module name hides them) and their ST form.
_BUILTIN_CALLS: dict[str, _CallRule] = {
    "min": _call_min_max_abs, "max": _call_min_max_abs, "abs": _call_min_max_abs,
    "bool": _call_bool, "int": _call_int, "float": _call_float, "len": _call_len_constant, "round": _call_round,
    **{name: _call_math for name in _MATH},
}


#: iecoop's operators (only when the name is iecoop's) and their ST form.
_LIBRARY_CALLS: dict[str, _CallRule] = {
    **{name: _call_operator for name in _OPERATORS},
    "adr": _call_adr, "sizeof": _call_sizeof, "is_valid_ref": _call_is_valid_ref, "test_and_set": _call_test_and_set,
    "now_ms": lambda w, node: ("TIME()", _ATOM), "MOD": _call_mod, "current_task": _call_current_task,
    "var_info": _call_var_info,
}


def _constant_expr(w: ExpressionWriter, node: ast.Constant) -> tuple[str, int]:
    if isinstance(node.value, (bool, int, float, str)) or node.value is None:
        return literal(node.value), _ATOM
    w.fail(node, f"the constant {node.value!r}")


def _subscript_expr(w: ExpressionWriter, node: ast.Subscript) -> tuple[str, int]:
    base = w.expr(node.value, _ATOM)[0]
    index = node.slice
    parts = index.elts if isinstance(index, ast.Tuple) else [index]
    if any(isinstance(p, ast.Slice) for p in parts):
        w.fail(node, "a slice")
    return f"{base}[{', '.join(w.expr(p)[0] for p in parts)}]", _ATOM


def _unary_expr(w: ExpressionWriter, node: ast.UnaryOp) -> tuple[str, int]:
    if isinstance(node.op, ast.Not):
        info = w.typeof(node.operand)
        if info is not None and not _is_bool(info):
            return f"{w.expr(node.operand, _EQ + 1)[0]} = 0", _EQ
        return f"NOT {w.expr(node.operand, _UNARY)[0]}", _UNARY
    if isinstance(node.op, ast.USub):
        operand = node.operand
        if isinstance(operand, ast.Constant) and isinstance(operand.value, (int, float)) and not isinstance(operand.value, bool):
            return literal(-operand.value), _ATOM
        return f"-{w.expr(operand, _UNARY + 1)[0]}", _UNARY
    if isinstance(node.op, ast.UAdd):
        return w.expr(node.operand)
    if isinstance(node.op, ast.Invert):
        return f"NOT {w.expr(node.operand, _UNARY)[0]}", _UNARY
    w.fail(node, _describe(node))


def _boolop_expr(w: ExpressionWriter, node: ast.BoolOp) -> tuple[str, int]:
    word, prec = ("AND", _AND) if isinstance(node.op, ast.And) else ("OR", _OR)
    if any(w.may_act(v) for v in node.values[1:]):
        # Python's and / or stop at the first operand that decides; ST's AND / OR evaluate every
        # operand, so a call, a dereference or an index after the first is guarded by AND_THEN / OR_ELSE.
        word += "_THEN" if word == "AND" else "_ELSE"
    operands = [w.condition_operand(v, prec) for v in node.values]
    return f" {word} ".join(operands), prec


def _ifexp_expr(w: ExpressionWriter, node: ast.IfExp) -> tuple[str, int]:
    # ST's SEL(g, in0, in1) gives in0 when g is FALSE: the else value comes first
    cond = w.condition(node.test)
    return f"SEL({cond}, {w.expr(node.orelse)[0]}, {w.expr(node.body)[0]})", _ATOM


#: ST text and precedence of an expression, by its node type (see ExpressionWriter._expr).
_EXPR_RULES: dict[type, Callable[[ExpressionWriter, Any], tuple[str, int]]] = {
    ast.Constant: _constant_expr,
    ast.Name: lambda w, node: (w.name(node), _ATOM),
    ast.Attribute: lambda w, node: (w.attribute(node), _ATOM),
    ast.Subscript: _subscript_expr,
    ast.Call: ExpressionWriter.call,
    ast.BinOp: lambda w, node: w.binop(node, node),
    ast.UnaryOp: _unary_expr,
    ast.BoolOp: _boolop_expr,
    ast.Compare: ExpressionWriter.compare,
    ast.IfExp: _ifexp_expr,
    ast.JoinedStr: lambda w, node: (w.fstring(node), _ATOM),
}


