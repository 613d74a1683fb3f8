"""Python bodies to Structured Text statements: the subset iecoop code is written in.

A POU body, a METHOD or a property accessor is read from its source
(``inspect.getsource`` + ``ast``) and translated statement by statement.
Types of locals come from their annotation or from the expression that first
assigns them. Anything outside the subset raises :class:`StExportError`
naming the file, the line and the construct, or, when the caller asks for
it, becomes an ST comment that says the same.
"""

from __future__ import annotations

import ast
import builtins
import enum
import inspect
import math
import textwrap
import typing
import weakref
from collections.abc import Callable, Iterator, Sequence
from typing import Any

from iecoop.metadata import is_root, kind_of
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
    resolve_type,
)
from iecoop.memory.layout import MISSING, FieldSpec
from iecoop.memory.pointers import PointerInfo
from iecoop.st.write.model import StExportError, annotation_info, function_parameters, ident, parameters, return_info, type_text
from iecoop.types import BOOL, DINT, LREAL, LTIME, STRING, TIME

__all__ = ["BodyWriter", "Scope", "literal"]

_BOOL = resolve_type(BOOL, "BOOL")
_DINT = resolve_type(DINT, "DINT")
_LREAL = resolve_type(LREAL, "LREAL")
_TIME = resolve_type(TIME, "TIME")
_LTIME = resolve_type(LTIME, "LTIME")
_STRING = resolve_type(STRING, "STRING")

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


def _is_real(info: TypeInfo | None) -> bool:
    return isinstance(info, ElementaryInfo) and info.record.kind == "real"


def _is_integer(info: TypeInfo | None) -> bool:
    return isinstance(info, (ElementaryInfo, EnumInfo)) and (
        isinstance(info, EnumInfo) or info.record.kind in ("signed", "unsigned")
    )


#: The global variable list the module constants a body reads are declared in.
_CONSTANTS_GVL = "GVL_Constants"


def _is_time(info: TypeInfo | None) -> bool:
    return isinstance(info, ElementaryInfo) and info.record.kind == "time"


def _is_whole(info: TypeInfo | None) -> bool:
    """An integer or a TIME: a whole number in Python, which ``/`` turns into a float."""
    return _is_integer(info) or _is_time(info)


def _is_bool(info: TypeInfo | None) -> bool:
    return isinstance(info, ElementaryInfo) and info.record.kind == "bool"


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


class Scope:
    """What a body's names mean: the class's variables and members, and module constants."""

    def __init__(
        self, cls: Any, fields: dict[str, TypeInfo], constants: dict[str, Any], functions: dict[str, Any],
        named_enums: set[Any] | None = None,
    ) -> None:
        self.cls = cls
        self.fields = fields
        #: Module constants the bodies use, by name (emitted as a VAR_GLOBAL CONSTANT list).
        self.constants = constants
        #: Module functions the bodies call, by name (emitted as FUNCTIONs).
        self.functions = functions
        #: Enumerations whose component names the bodies read (declared with {attribute 'to_string'}).
        self.named_enums: set[Any] = set() if named_enums is None else named_enums


def _fields_of(cls: Any) -> dict[str, TypeInfo]:
    """Every variable of a class (inherited ones, VAR_STAT and VAR_EXTERNAL included) by name."""
    from iecoop.st.write.model import metadata

    found: dict[str, TypeInfo] = {}
    for klass in reversed(getattr(cls, "__mro__", ())):
        if kind_of(klass) not in ("fb", "program", "struct", "union", "gvl") or is_root(klass):
            continue
        for field in metadata(klass).fields:
            info = field.info.target if field.section == "VAR_IN_OUT" and isinstance(field.info, ReferenceInfo) else field.info
            found[field.name] = info
    return found


def _member_function(cls: Any, name: str) -> tuple[Any, Any] | None:
    """(function, owner) of METHOD / PROPERTY ``name`` (a property gives its getter)."""
    for klass in getattr(cls, "__mro__", ()):
        value = klass.__dict__.get(name)
        if value is None:
            continue
        if isinstance(value, property):
            return (inspect.unwrap(value.fget) if value.fget is not None else None), klass
        if inspect.isfunction(value):
            return inspect.unwrap(value), klass
        return None
    return None


def _class_of(info: TypeInfo | None) -> Any:
    if isinstance(info, AggregateInfo):
        return info.cls
    if isinstance(info, InterfaceInfo):
        return info.iface
    return None


class _Untranslated(Exception):
    def __init__(self, node: ast.AST, what: str) -> None:
        super().__init__(what)
        self.node = node
        self.what = what


class BodyWriter:
    """Translate one function of a POU into ST lines and the locals they need."""

    def __init__(
        self,
        scope: Scope,
        func: Callable[..., Any],
        *,
        st_name: str,
        result: TypeInfo | None = None,
        params: dict[str, TypeInfo] | None = None,
        rename: dict[str, str] | None = None,
        lenient: bool = False,
        by_reference: set[str] | None = None,
    ) -> None:
        func = inspect.unwrap(func)
        self.scope = scope
        self.func = func
        #: VAR_OUTPUT / VAR_IN_OUT parameters: ``x.deref`` in Python is ``x`` in ST
        self.by_reference = set(by_reference or ())
        self.st_name = st_name
        self.result = result
        self.params = dict(params or {})
        self.rename = dict(rename or {})
        self.lenient = lenient
        self.locals: dict[str, TypeInfo | str] = {}
        self.references: set[str] = set()
        self.catch_vars: set[str] = set()
        self.fields = _fields_of(scope.cls)
        self.globals = getattr(func, "__globals__", {})
        self.filename = inspect.getsourcefile(func) or "<unknown>"
        self.lines: list[str] = []
        self.first_line = func.__code__.co_firstlineno
        #: Statements that became comments (lenient mode): (line, construct).
        self.untranslated: list[tuple[int, str]] = []
        #: Statements the next emitted line needs first: a call's result kept in a temporary.
        self.prelude: list[str] = []
        #: Temporaries of the statement being translated, by the id of the expression they hold.
        self.hoisted: dict[int, str] = {}
        #: Every local declared as a temporary (reused by later statements).
        self.temps: set[str] = set()
        #: The body's locals named like a variable, by the VAR_TEMP name they take instead.
        self.temp_names: dict[str, str] = {}
        #: The names the function binds (filled by translate()).
        self.bound: set[str] = set()
        #: For each ``return value``, whether the value is a variable that outlives the call (see is_place()).
        self.return_places: list[bool] = []

    # -- entry point ---------------------------------------------------------

    def translate(self) -> list[str]:
        try:
            source = textwrap.dedent(inspect.getsource(self.func))
        except (OSError, TypeError) as exc:
            raise StExportError(f"{self.where_text()}: the source of {self.func.__qualname__} is not available ({exc})") from None
        tree = ast.parse(source)
        node = tree.body[0]
        if not isinstance(node, ast.FunctionDef):
            raise StExportError(f"{self.where_text()}: {self.func.__qualname__} is not a plain def")
        self.source_lines = source.splitlines()
        # Every name the function binds is an ST local for the whole body, so it hides a variable of the
        # same name even in the statements before its first assignment: those read THIS^.name.
        self.bound = {n.id for n in ast.walk(node) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Store)}
        if self.func.__name__ == "body":
            # The body's locals named like a variable are renamed (see declare()): they hide nothing.
            # ST names ignore case: a local axis is the variable Axis there.
            variables = {f.lower() for f in self.fields}
            for name in sorted(n for n in self.bound if n.lower() in variables):
                self.temp_name(name)
            self.bound -= set(self.temp_names)
        body = list(node.body)
        if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) and isinstance(body[0].value.value, str):
            body = body[1:]
        if len(body) == 1 and isinstance(body[0], ast.Raise) and _is_name(getattr(body[0], "exc", None), "NotImplementedError"):
            body = []
        # A final `return x` needs no RETURN after the result assignment.
        self.block(body, 0, top=True)
        return self.lines

    def where_text(self, node: ast.AST | None = None) -> str:
        line = self.first_line + (getattr(node, "lineno", 1) - 1)
        return f"{self.filename}:{line}"

    def fail(self, node: ast.AST, what: str) -> typing.NoReturn:
        raise _Untranslated(node, what)

    # -- statements ----------------------------------------------------------

    def block(self, body: list[ast.stmt], depth: int, *, top: bool = False) -> None:
        start = len(self.lines)
        self._block(body, depth, top)
        if not top and all(line.lstrip().startswith("(*") for line in self.lines[start:]):
            self.emit(depth, ";")  # ST needs a statement where Python had only pass / a docstring

    def _block(self, body: list[ast.stmt], depth: int, top: bool) -> None:
        for i, stmt in enumerate(body):
            last = top and i == len(body) - 1
            mark = len(self.lines)
            saved = (dict(self.locals), set(self.references))
            self.hoisted = {}
            try:
                self.statement(stmt, depth, last)
            except _Untranslated as exc:
                del self.lines[mark:]
                self.locals, self.references, self.prelude = saved[0], saved[1], []
                line = self.first_line + getattr(exc.node, "lineno", 1) - 1
                message = f"{self.filename}:{line}: {exc.what} has no Structured Text form (in {self.func.__qualname__})"
                if not self.lenient:
                    raise StExportError(message) from None
                if (line, exc.what) not in self.untranslated:  # once, though an unrolled loop repeats it
                    self.untranslated.append((line, exc.what))
                text = " ".join(
                    part.strip() for part in self.source_lines[stmt.lineno - 1 : (stmt.end_lineno or stmt.lineno)]
                )
                text = text.replace("(*", "( *").replace("*)", "* )")
                self.emit(depth, f"(* not translated, {exc.what} (line {line}): {text} *)")

    def emit(self, depth: int, text: str) -> None:
        pending, self.prelude = self.prelude, []
        for line in pending:
            self.lines.append("    " * depth + line)
        self.lines.append("    " * depth + text)

    def once(self, node: ast.AST, text: str) -> str:
        """A condition evaluated again and again (WHILE, ELSIF): it cannot use a temporary set before."""
        if self.prelude:
            self.fail(node, "a member of a call's result in a while or elif condition (assign the result to a local first)")
        return text

    def statement(self, node: ast.stmt, depth: int, last: bool) -> None:
        if isinstance(node, ast.Pass) or (isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant)):
            return
        if isinstance(node, ast.Expr):
            self.call_statement(node.value, depth)
        elif isinstance(node, ast.Assign):
            self.assign(node, depth)
        elif isinstance(node, ast.AnnAssign):
            if not isinstance(node.target, ast.Name):
                self.fail(node, "an annotated assignment to an attribute")
            info = annotation_info(ast.unparse(node.annotation), self.func, f"{self.func.__qualname__}.{node.target.id}", self.scope.cls)
            if info is None:
                self.fail(node, "a local annotated None")
            bound_by_call = isinstance(node.value, ast.Call) and isinstance(self.typeof(node.value), ReferenceInfo)
            if not (isinstance(info, AggregateInfo) and node.value is not None and (not isinstance(node.value, ast.Call) or bound_by_call)):
                self.declare(node.target.id, info, node)
            if node.value is not None:
                self.assign_one(node.target, node.value, depth, node)
        elif isinstance(node, ast.AugAssign):
            target = self.target(node.target)
            op = _BINOPS.get(type(node.op))
            if op is None:
                self.fail(node, f"the operator {type(node.op).__name__}=")
            value = self.binop(ast.BinOp(node.target, node.op, node.value), node)[0]
            self.emit(depth, f"{target} := {value};")
        elif isinstance(node, ast.If):
            self.if_statement(node, depth)
        elif isinstance(node, ast.For):
            self.for_statement(node, depth)
        elif isinstance(node, ast.While):
            if node.orelse:
                self.fail(node, "while ... else")
            self.emit(depth, f"WHILE {self.once(node, self.condition(node.test))} DO")
            self.block(node.body, depth + 1)
            self.emit(depth, "END_WHILE")
        elif isinstance(node, ast.Break):
            self.emit(depth, "EXIT;")
        elif isinstance(node, ast.Continue):
            self.emit(depth, "CONTINUE;")
        elif isinstance(node, ast.Return):
            self.return_statement(node, depth, last)
        elif isinstance(node, ast.With):
            self.with_statement(node, depth)
        elif isinstance(node, ast.Try):
            self.try_statement(node, depth)
        elif isinstance(node, ast.Match):
            self.match_statement(node, depth)
        else:
            self.fail(node, _describe(node))

    def return_statement(self, node: ast.Return, depth: int, last: bool) -> None:
        if node.value is not None and not (isinstance(node.value, ast.Constant) and node.value.value is None and self.result is None):
            if self.result is None:
                self.fail(node, "a return value in a block without a result")
            place = self.is_place(node.value)
            self.return_places.append(place)
            if isinstance(self.result, ReferenceInfo):
                if not place:
                    self.fail(node, f"a return of a value that ends with the call, where the result is {type_text(self.result)} "
                              "(the member's first definition hands out a variable: return a variable of the block, a GVL or an input)")
                self.emit(depth, f"{self.st_name} REF= {self.ref_target(node.value)};")
            else:
                self.emit(depth, f"{self.st_name} := {self.expr(node.value)[0]};")
        if not last:
            self.emit(depth, "RETURN;")

    def if_statement(self, node: ast.If, depth: int) -> None:
        self.emit(depth, f"IF {self.condition(node.test)} THEN")
        self.block(node.body, depth + 1)
        orelse = node.orelse
        while len(orelse) == 1 and isinstance(orelse[0], ast.If):
            branch = orelse[0]
            self.emit(depth, f"ELSIF {self.once(branch, self.condition(branch.test))} THEN")
            self.block(branch.body, depth + 1)
            orelse = branch.orelse
        if orelse:
            self.emit(depth, "ELSE")
            self.block(orelse, depth + 1)
        self.emit(depth, "END_IF")

    def for_statement(self, node: ast.For, depth: int) -> None:
        if node.orelse:
            self.fail(node, "for ... else")
        it = node.iter
        enumerated = isinstance(it, ast.Call) and _is_name(it.func, "enumerate") and "enumerate" not in self.globals
        sequence = typing.cast(ast.Call, it).args[0] if enumerated and typing.cast(ast.Call, it).args else it
        if isinstance(sequence, (ast.Tuple, ast.List)):
            self.unrolled_loop(node, sequence.elts, depth)
            return
        owner = self.constant_object(sequence)
        if isinstance(owner, type) and kind_of(owner) == "enum":
            # An enumeration's components, in declaration order.
            members = [ast.Attribute(sequence, m.name, ast.Load()) for m in typing.cast(Any, owner)]
            self.unrolled_loop(node, typing.cast(list[ast.expr], members), depth)
            return
        if isinstance(self.typeof(sequence), ArrayInfo):
            self.array_loop(node, depth)
            return
        if not (isinstance(node.target, ast.Name) and isinstance(it, ast.Call) and _is_name(it.func, "range") and not it.keywords):
            self.fail(node, "a for loop over something other than range(), an ARRAY or a tuple")
        self.range_loop(node, it, depth)

    def loop_targets(self, node: ast.For, width: int) -> tuple[ast.Name | None, list[str]]:
        """(the enumerate() counter or None, the names bound to each element) of a for loop."""
        target = node.target
        enumerated = isinstance(node.iter, ast.Call) and _is_name(node.iter.func, "enumerate")
        counter: ast.Name | None = None
        if enumerated:
            if not (isinstance(target, ast.Tuple) and len(target.elts) == 2 and isinstance(target.elts[0], ast.Name)):
                self.fail(node, "enumerate() without a (counter, element) target")
            counter, target = target.elts[0], target.elts[1]
        names = target.elts if isinstance(target, ast.Tuple) else [target]
        if not all(isinstance(n, ast.Name) for n in names) or width != len(names) and width != 0:
            self.fail(node, "a for loop target that is not one name per element")
        return counter, [typing.cast(ast.Name, n).id for n in names]

    def enumerate_start(self, node: ast.For) -> int:
        it = node.iter
        if not (isinstance(it, ast.Call) and _is_name(it.func, "enumerate")):
            return 0
        if it.keywords or len(it.args) not in (1, 2):
            self.fail(node, "enumerate() with these arguments")
        start = _constant_int(it.args[1]) if len(it.args) == 2 else 0
        if start is None:
            self.fail(node, "an enumerate() start that is not a constant integer")
        return start

    def unrolled_loop(self, node: ast.For, items: list[ast.expr], depth: int) -> None:
        """A loop over a literal tuple: the body once per element, each name standing for its element."""
        rows = [list(e.elts) if isinstance(e, ast.Tuple) else [e] for e in items]
        counter, names = self.loop_targets(node, len(rows[0]) if rows and len(rows[0]) > 1 else 1)
        start = self.enumerate_start(node)
        bound = [*names, *([counter.id] if counter is not None else [])]
        if _escapes(node.body) or any(isinstance(n, ast.Name) and n.id in bound and isinstance(n.ctx, ast.Store) for b in node.body for n in ast.walk(b)):
            self.fail(node, "a loop over a tuple whose body breaks, continues or assigns the loop names (write the statements once per element)")
        saved = dict(self.rename), dict(self.params)
        try:
            for i, row in enumerate(rows):
                if len(row) != len(names):
                    self.fail(node, "a for loop over tuples of different lengths")
                values = [*row, *([ast.Constant(start + i)] if counter is not None else [])]
                for name, value in zip(bound, values):
                    text, prec = self.expr(value)
                    if prec != _ATOM:
                        self.fail(node, "a loop over a tuple of expressions (name each element)")
                    self.rename[name] = text
                    self.params[name] = self.typeof(value)  # type: ignore[assignment]
                self.block(node.body, depth)
        finally:
            self.rename, self.params = saved

    def array_loop(self, node: ast.For, depth: int) -> None:
        """A loop over a one-dimensional ARRAY: FOR over its declared bounds, the name bound to each element."""
        it = node.iter
        array = it.args[0] if isinstance(it, ast.Call) else it
        info = typing.cast(ArrayInfo, self.typeof(array))
        if len(info.bounds) != 1:
            self.fail(node, "a for loop over an ARRAY of several dimensions")
        (low, high), elem = info.bounds[0], info.elem
        counter, (name,) = self.loop_targets(node, 1)
        start = self.enumerate_start(node)
        aggregate = isinstance(elem, AggregateInfo)
        if aggregate and any(isinstance(n, ast.Name) and n.id == name and isinstance(n.ctx, ast.Store) for b in node.body for n in ast.walk(b)):
            self.fail(node, "a loop over an ARRAY of blocks or structs whose body assigns the loop name")
        if counter is not None and start == low:
            index = counter.id
        else:
            index = next(f"{name}_index{n or ''}" for n in range(100) if f"{name}_index{n or ''}" not in {*self.locals, *self.params, *self.fields})
        if index not in self.locals and index not in self.params:
            self.declare(index, _DINT, node)
        self.emit(depth, f"FOR {self.name_text(index)} := {low} TO {high} DO")
        if counter is not None and index != counter.id:
            if counter.id not in self.locals and counter.id not in self.params:
                self.declare(counter.id, _DINT, node)
            offset = start - low
            self.emit(depth + 1, f"{self.name_text(counter.id)} := {self.name_text(index)} {'+' if offset >= 0 else '-'} {abs(offset)};")
        element = f"{self.expr(array, _ATOM)[0]}[{self.name_text(index)}]"
        if aggregate:
            # Python binds the name to the element itself: in ST that is a reference to it.
            if name not in self.references:
                self.references.add(name)
                self.declare(name, f"REFERENCE TO {type_text(elem)}", node)
            self.emit(depth + 1, f"{self.name_text(name)} REF= {element};")
        else:
            if name not in self.locals and name not in self.params:
                self.declare(name, elem, node)
            self.emit(depth + 1, f"{self.name_text(name)} := {element};")
        self.block(node.body, depth + 1)
        self.emit(depth, "END_FOR")

    def range_loop(self, node: ast.For, it: ast.Call, depth: int) -> None:
        args = it.args
        if not 1 <= len(args) <= 3:
            self.fail(node, "range() with no argument")
        start = args[0] if len(args) > 1 else ast.Constant(0)
        stop = args[1] if len(args) > 1 else args[0]
        step = 1
        if len(args) == 3:
            value = _constant_int(args[2])
            if value is None or value == 0:
                self.fail(node, "a range() step that is not a constant integer")
            step = value
        name = typing.cast(ast.Name, node.target).id
        if name not in self.locals and name not in self.params:
            self.declare(name, _DINT, node)
        end = self.end_bound(stop, -1 if step > 0 else 1)
        by = f" BY {step}" if step != 1 else ""
        self.emit(depth, f"FOR {self.name_text(name)} := {self.expr(start)[0]} TO {end}{by} DO")
        self.block(node.body, depth + 1)
        self.emit(depth, "END_FOR")

    def end_bound(self, stop: ast.expr, delta: int) -> str:
        """``stop + delta`` written simply (``n + 1`` with delta -1 is ``n``)."""
        value = _constant_int(stop)
        if value is not None:
            return str(value + delta)
        if isinstance(stop, ast.BinOp) and isinstance(stop.op, (ast.Add, ast.Sub)):
            right = _constant_int(stop.right)
            if right is not None:
                total = (right if isinstance(stop.op, ast.Add) else -right) + delta
                left = self.expr(stop.left, _ADD)[0]
                if total == 0:
                    return left
                return f"{left} {'+' if total > 0 else '-'} {abs(total)}"
        text = self.expr(stop, _ADD)[0]
        return f"{text} {'+' if delta > 0 else '-'} {abs(delta)}"

    def with_statement(self, node: ast.With, depth: int) -> None:
        if len(node.items) != 1:
            self.fail(node, "a with statement of several items")
        item = node.items[0]
        call = item.context_expr
        if not (isinstance(call, ast.Call) and self.resolves_to(call.func, "try_catch")):
            self.fail(node, "a with statement other than try_catch()")
        self.emit(depth, "__TRY")
        self.block(node.body, depth + 1)
        if isinstance(item.optional_vars, ast.Name):
            name = item.optional_vars.id
            self.catch_vars.add(name)
            self.declare(name, "__SYSTEM.ExceptionCode", node)
            self.emit(depth, f"__CATCH({name})")
        else:
            self.emit(depth, "__CATCH")
        self.emit(depth, "__ENDTRY")

    def try_statement(self, node: ast.Try, depth: int) -> None:
        """``try`` / ``except`` (/ ``finally``) where it means what __TRY / __CATCH (/ __FINALLY) mean."""
        if not node.handlers:
            # The vendors' __TRY ... __FINALLY ... __ENDTRY goes on after __ENDTRY; Python's finally re-raises.
            self.fail(node, "try / finally without except (ST goes on after __FINALLY where Python passes the exception on: "
                      "put the clean-up after the statements, or use with try_catch() and act on exc.code)")
        if len(node.handlers) > 1 or node.orelse:
            self.fail(node, "try with several except clauses or an else (write one except clause)")
        handler = node.handlers[0]
        if not self.catches_all_faults(handler.type, node.body):
            self.fail(handler, "an except clause other than except PlcException, except (PlcException, ZeroDivisionError) "
                      "or except Exception (__CATCH catches every runtime fault, a division by zero too)")
        self.emit(depth, "__TRY")
        self.block(node.body, depth + 1)
        if handler.name is not None:
            self.catch_vars.add(handler.name)
            self.declare(handler.name, "__SYSTEM.ExceptionCode", node)
            self.emit(depth, f"__CATCH({handler.name})")
        else:
            name = next(f"exc{n or ''}" for n in range(100) if f"exc{n or ''}" not in {*self.locals, *self.params, *self.fields})
            self.declare(name, "__SYSTEM.ExceptionCode", node)
            self.emit(depth, f"__CATCH({name})")
        self.block(handler.body, depth + 1)
        if node.finalbody:
            self.emit(depth, "__FINALLY")
            self.block(node.finalbody, depth + 1)
        self.emit(depth, "__ENDTRY")

    def catches_all_faults(self, node: ast.expr | None, body: list[ast.stmt]) -> bool:
        """Whether an except clause catches what try_catch() (and the PLC's __CATCH) catch: a
        ZeroDivisionError too, unless the statements divide nothing themselves."""
        names = node.elts if isinstance(node, ast.Tuple) else [node] if node is not None else []
        found = {self.constant_object(n) or getattr(builtins, getattr(n, "id", ""), None) for n in names}
        from iecoop.exceptions import PlcException

        divides = any(isinstance(n, (ast.Div, ast.FloorDiv, ast.Mod)) for b in body for n in ast.walk(b))
        return bool({Exception, BaseException} & found) or PlcException in found and (ZeroDivisionError in found or not divides)

    def match_statement(self, node: ast.Match, depth: int) -> None:
        """``match x: case A.B | A.C: ... case _: ...`` as CASE: neither falls through."""
        self.emit(depth, f"CASE {self.expr(node.subject)[0]} OF")
        for case in node.cases:
            if case.guard is not None:
                self.fail(case.guard, "a case with a guard (write an if inside the case)")
            pattern = case.pattern
            if isinstance(pattern, ast.MatchAs) and pattern.pattern is None and pattern.name is None:
                self.emit(depth, "ELSE")
                self.block(case.body, depth + 1)
                continue
            options = pattern.patterns if isinstance(pattern, ast.MatchOr) else [pattern]
            if not all(isinstance(o, ast.MatchValue) for o in options):
                self.fail(pattern, "a case pattern other than values, enumeration components and _")
            labels = ", ".join(self.expr(typing.cast(ast.MatchValue, o).value)[0] for o in options)
            self.emit(depth + 1, f"{labels}:")
            self.block(case.body, depth + 2)
        self.emit(depth, "END_CASE")

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

    def call_statement(self, node: ast.expr, depth: int) -> None:
        if not isinstance(node, ast.Call):
            self.fail(node, "an expression statement that is not a call")
        func = node.func
        if self.resolves_to(func, "ref_assign"):
            holder, field, target = self.operator_args(node, 3)
            self.emit(depth, f"{self.member_text(holder, field)} REF= {self.ref_target(target)};")
            return
        chain = self.set_reset_chain(node)
        if chain is not None:
            links, condition = chain
            reads = {ast.unparse(n) for n in ast.walk(condition) if isinstance(n, (ast.Attribute, ast.Name))}
            once = len(links) > 1 and any(isinstance(n, ast.Call) for n in ast.walk(condition))
            if once or len(links) > 1 and any(target in reads for target, _ in links):
                # The condition is evaluated once for the whole chain: ST's a S= b R= c.
                self.emit(depth, " ".join(f"{text} {word}" for _, (text, word) in links) + f" {self.expr(condition)[0]};")
            else:
                # One statement per link, the innermost first as Python runs them (blark reads no chain).
                for _, (text, word) in reversed(links):
                    self.emit(depth, f"{text} {word} {self.expr(condition)[0]};")
            return
        self.emit(depth, f"{self.call(node)[0]};")

    def set_reset_chain(self, node: ast.expr) -> tuple[list[tuple[str, tuple[str, str]]], ast.expr] | None:
        """``S(self, "a", R(self, "b", c))``: the links ((Python target, (ST target, S= / R=)), outermost
        first) and the condition ``c`` they all act on (S and R return their condition)."""
        if not isinstance(node, ast.Call):
            return None
        for op, word in (("S", "S="), ("R", "R=")):
            if self.resolves_to(node.func, op) and _from_iecoop(self.globals.get(op)):
                holder, field, condition = self.operator_args(node, 3)
                link = (f"{ast.unparse(holder)}.{getattr(field, 'value', '')}", (self.member_text(holder, field), word))
                inner = self.set_reset_chain(condition)
                return ([link], condition) if inner is None else ([link, *inner[0]], inner[1])
        return None

    def assign(self, node: ast.Assign, depth: int) -> None:
        for target in node.targets:
            if isinstance(target, ast.Tuple):
                if not (isinstance(node.value, ast.Tuple) and len(node.value.elts) == len(target.elts)) or len(node.targets) != 1:
                    self.fail(node, "unpacking a value that is not a tuple of the same length")
                self.tuple_assign(target.elts, node.value.elts, depth, node)
            else:
                self.assign_one(target, node.value, depth, node)

    def tuple_assign(self, targets: list[ast.expr], values: list[ast.expr], depth: int, node: ast.stmt) -> None:
        """``a, b = x, y``: one assignment after another; a value that reads an earlier target is kept
        in a temporary first, since Python evaluates every value before it assigns."""
        names = [ast.unparse(t) for t in targets]
        held: dict[int, str] = {}
        for i, value in enumerate(values):
            reads = {ast.unparse(n) for n in ast.walk(value) if isinstance(n, (ast.Name, ast.Attribute, ast.Subscript))}
            if not any(r == n or r.startswith((n + ".", n + "[")) for n in names[:i] for r in reads):
                continue
            info = self.typeof(targets[i]) or self.typeof(value)
            if info is None:
                self.fail(node, "a tuple assignment whose later values read an earlier target of unknown type")
            temp = self.temporary(f"{_stem(names[i])}_new", info, node)
            self.hoisted[id(value)] = temp
            self.emit(depth, f"{temp} := {self.expr(value)[0]};")
            held[i] = temp
        for i, (t, v) in enumerate(zip(targets, values)):
            self.assign_one(t, ast.Name(held[i], ast.Load()) if i in held else v, depth, node)

    def assign_one(self, target: ast.expr, value: ast.expr, depth: int, node: ast.stmt) -> None:
        if isinstance(value, ast.Call) and self.resolves_to(value.func, "query_interface"):
            source, _iface = self.operator_args(value, 2)
            self.maybe_declare(target, value, node)
            self.emit(depth, f"__QUERYINTERFACE({self.expr(source)[0]}, {self.target(target)});")
            return
        if isinstance(value, ast.Call) and self.resolves_to(value.func, "query_pointer"):
            (source,) = self.operator_args(value, 1)
            self.maybe_declare(target, value, node)
            self.emit(depth, f"__QUERYPOINTER({self.expr(source)[0]}, {self.target(target)});")
            return
        self.maybe_declare(target, value, node)
        if isinstance(target, ast.Name) and target.id in self.references:
            self.emit(depth, f"{self.name_text(target.id)} REF= {self.expr(value)[0]};")
            return
        if isinstance(target, ast.Attribute) and self.reads_property(target):
            info = self.typeof(target)
            if isinstance(info, ReferenceInfo) and isinstance(info.target, AggregateInfo):
                # The Set accessor of a REFERENCE TO property is called with REF= (fbSample.MyProp REF= stSet),
                # as Python's setter gets the object itself; := would write through the Get accessor's reference.
                self.emit(depth, f"{self.target(target)} REF= {self.expr(value)[0]};")
                return
        text, _prec = self.expr(value)
        self.emit(depth, f"{self.target(target)} := {text};")

    def maybe_declare(self, target: ast.expr, value: ast.expr, node: ast.stmt) -> None:
        if not isinstance(target, ast.Name):
            return
        name = target.id
        if name in self.locals or name in self.params:
            return
        if isinstance(value, ast.Call) and self.resolves_to(value.func, "query_interface"):
            iface = value.args[1] if len(value.args) > 1 else None
            cls = self.constant_object(iface) if iface is not None else None
            if cls is None:
                self.fail(node, "query_interface() with a target that is not an interface name")
            self.declare(name, cls.__name__, node)
            return
        if isinstance(value, ast.Call) and self.resolves_to(value.func, "query_pointer"):
            self.declare(name, "PVOID", node)
            return
        if isinstance(value, ast.Call) and self.resolves_to(value.func, "var_info"):
            self.declare(name, "__SYSTEM.VAR_INFO", node)
            return
        info = self.typeof(value)
        if info is None:
            self.fail(node, f"a local {name!r} whose type cannot be inferred (annotate it: {name}: INT = ...)")
        if isinstance(info, ReferenceInfo) and isinstance(info.target, AggregateInfo) and (
            isinstance(value, ast.Call) or self.reads_property(value)
        ):
            # A METHOD, FUNCTION or PROPERTY that gives REFERENCE TO: Python's name is the variable itself, as ST's REF= binds it.
            self.references.add(name)
            self.declare(name, info, node)
            return
        if isinstance(info, AggregateInfo) and not isinstance(value, ast.Call) and not self.reads_property(value):
            # Python binds a name to the element itself: in ST that is a reference to it (a PROPERTY's
            # Get gives a value, which has no address: that one is a copy).
            self.references.add(name)
            self.declare(name, f"REFERENCE TO {type_text(info)}", node)
            return
        self.declare(name, info, node)

    def is_place(self, node: ast.expr) -> bool:
        """Whether ``node`` names a variable that outlives the call: a variable of the block or of a GVL, an
        element or member of one, an input passed by reference, a pointer's target, a REFERENCE local bound to
        one of those, or the result of a call that returns a REFERENCE TO (ST can bind a reference to it)."""
        if isinstance(node, ast.Name):
            if node.id == "self":
                return "self" not in self.locals and self.scope.cls is not None
            if node.id in self.references:
                return True
            if node.id in self.params:
                return node.id not in self.bound and isinstance(self.params[node.id], AggregateInfo)
            return node.id not in self.locals and kind_of(type(self.globals.get(node.id))) == "gvl"
        if isinstance(node, ast.Attribute):
            if node.attr == "deref":
                return True
            if isinstance(node.value, ast.Name) and node.value.id not in self.locals and node.value.id not in self.params:
                holder = self.globals.get(node.value.id)
                if kind_of(type(holder)) == "gvl":
                    return node.attr in _fields_of(type(holder))
            return self.is_place(node.value) and self.typeof(node) is not None and not self.reads_property(node)
        if isinstance(node, ast.Subscript):
            return self.is_place(node.value)
        if isinstance(node, ast.Call):
            return isinstance(self.typeof(node), ReferenceInfo)
        return False

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

    # -- expressions ---------------------------------------------------------

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

    def constant_object(self, node: ast.expr | None) -> Any:
        """The module-level object a name or dotted name designates (an enum, an interface), or None."""
        if isinstance(node, ast.Name) and node.id not in self.locals and node.id not in self.params and node.id != "self":
            value = self.globals.get(node.id)
            if isinstance(value, type) or isinstance(value, type(inspect)):
                return value
            return None
        if isinstance(node, ast.Attribute):
            owner = self.constant_object(node.value)
            if isinstance(owner, type(inspect)):
                value = getattr(owner, node.attr, None)
                return value if isinstance(value, type) else None
        return None

    def resolves_to(self, node: ast.expr, name: str) -> bool:
        if isinstance(node, ast.Name):
            return node.id == name and node.id not in self.locals
        if isinstance(node, ast.Attribute):
            return node.attr == name and self.constant_object(node.value) is not None and not isinstance(self.constant_object(node.value), type)
        return False

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

    def function_signature(self, value: Any) -> tuple[list[tuple[str, TypeInfo, Any]], TypeInfo | None] | None:
        """Inputs and result of a module function that can be an ST FUNCTION, or None."""
        if not inspect.isfunction(value):
            return None
        module = getattr(value, "__module__", "") or ""
        if module == "iecoop" or module.startswith("iecoop.") or value.__name__.startswith("<"):
            return None
        try:
            inputs = function_parameters(value, value.__qualname__)
            result = result_info(value, value.__qualname__, None)
        except StExportError:
            return None
        return inputs, result

    # -- types ---------------------------------------------------------------

    def typeof(self, node: ast.expr | None) -> TypeInfo | None:
        try:
            return self._typeof(node)
        except _Untranslated:
            return None

    def _local_info(self, name: str) -> TypeInfo | None:
        info = self.locals.get(name, self.params.get(name))
        if isinstance(info, str):
            if info.startswith("REFERENCE TO "):
                cls = self.globals.get(info[len("REFERENCE TO ") :])
                return class_info(cls) if isinstance(cls, type) else None
            return None
        return info

    def _typeof(self, node: ast.expr | None) -> TypeInfo | None:
        rule = _TYPE_RULES.get(type(node))
        return rule(self, node) if rule is not None else None

    def name_type(self, node: ast.Name) -> TypeInfo | None:
        if node.id in self.locals or node.id in self.params:
            return self._local_info(node.id)
        if node.id in self.rename:
            return self.params.get(node.id)
        if node.id in ("True", "False"):
            return _BOOL
        return _constant_type(self.globals.get(node.id))

    def may_act(self, node: ast.expr) -> bool:
        """Whether evaluating ``node`` may do more than read variables: call, dereference, index, run a Get."""
        for sub in ast.walk(node):
            if isinstance(sub, (ast.Call, ast.Subscript)):
                return True
            if isinstance(sub, ast.Attribute) and (sub.attr == "deref" or self.reads_property(sub)):
                return True
        return False

    def reads_property(self, node: ast.expr) -> bool:
        """Whether ``node`` reads a PROPERTY (a call of its Get accessor in ST)."""
        if not isinstance(node, ast.Attribute):
            return False
        if _is_name(node.value, "self") and "self" not in self.locals:
            cls = self.scope.cls
        else:
            inner = self._typeof(node.value)
            cls = _class_of(inner.target if isinstance(inner, ReferenceInfo) else inner)
        if cls is not None and node.attr in _fields_of(cls):
            return False  # a variable (a nested block's view is a Python property, but no PROPERTY of ST)
        for klass in getattr(cls, "__mro__", ()):
            if node.attr in klass.__dict__:
                return isinstance(klass.__dict__[node.attr], property)
        return False

    def attribute_type(self, node: ast.Attribute) -> TypeInfo | None:
        base = node.value
        if _is_name(base, "self") and "self" not in self.locals or isinstance(base, ast.Call) and _is_name(base.func, "super"):
            return self.member_type(self.scope.cls, node.attr, self.fields)
        owner = self.constant_object(base)
        if isinstance(owner, type) and issubclass(owner, enum.Enum):
            return class_info(owner) if kind_of(owner) == "enum" else None
        if node.attr == "deref" and isinstance(base, ast.Name) and base.id in self.by_reference:
            return self.params.get(base.id)
        inner = self._typeof(base)
        if node.attr == "deref" and isinstance(inner, PointerInfo):
            return inner.target
        if isinstance(inner, ReferenceInfo):
            inner = inner.target
        if node.attr == "name" and isinstance(inner, EnumInfo):
            return _STRING
        if isinstance(base, ast.Call) and _is_task_info(self, base):
            return _TASK_INFO.get(node.attr)
        cls = _class_of(inner)
        return self.member_type(cls, node.attr, _fields_of(cls)) if cls is not None else None

    def subscript_type(self, node: ast.Subscript) -> TypeInfo | None:
        inner = self._typeof(node.value)
        if isinstance(inner, ReferenceInfo):
            inner = inner.target
        return inner.elem if isinstance(inner, ArrayInfo) else None

    def binop_type(self, node: ast.BinOp) -> TypeInfo | None:
        left, right = self._typeof(node.left), self._typeof(node.right)
        if isinstance(node.op, ast.Div) and _is_whole(left) and _is_whole(right):
            return _LREAL
        if _is_real(left):
            return left
        if _is_real(right):
            return right
        return left or right

    def member_type(self, cls: Any, name: str, fields: dict[str, TypeInfo]) -> TypeInfo | None:
        if name in fields:
            return fields[name]
        found = _member_function(cls, name)
        if found is None or found[0] is None:
            return None
        func, owner = found
        value = owner.__dict__.get(name)
        if isinstance(value, property):
            return result_info(func, f"{owner.__name__}.{name}", owner)
        return None

    def call_type(self, node: ast.Call) -> TypeInfo | None:
        func = node.func
        if isinstance(func, ast.Name) and func.id not in self.locals:
            return self.named_call_type(node, func.id)
        if isinstance(func, ast.Attribute):
            return self.method_call_type(func)
        return None

    def named_call_type(self, node: ast.Call, name: str) -> TypeInfo | None:
        if name in _CALL_TYPES:
            return _CALL_TYPES[name]
        rule = _CALL_TYPE_RULES.get(name)
        if rule is not None:
            return rule(self, node)
        value = self.globals.get(name)
        if isinstance(value, type) and kind_of(value) == "enum":
            return class_info(value)
        signature = self.function_signature(value)
        if signature is not None:
            return signature[1]
        return _library_result(name, value)

    def method_call_type(self, func: ast.Attribute) -> TypeInfo | None:
        base = func.value
        if isinstance(base, ast.Call) and _is_name(base.func, "super"):
            cls = self.scope.cls.__mro__[1]
        elif _is_name(base, "self") and "self" not in self.locals:
            cls = self.scope.cls
        else:
            cls = _class_of(self._typeof(base))
        if cls is None:
            return None
        found = _member_function(cls, func.attr)
        if found is None or found[0] is None:
            return None
        function, owner = found
        return result_info(function, f"{owner.__name__}.{func.attr}", owner)


def _constant_int(node: ast.expr) -> int | None:
    if isinstance(node, ast.Constant) and isinstance(node.value, int) and not isinstance(node.value, bool):
        return node.value
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
        inner = _constant_int(node.operand)
        return -inner if inner is not None else None
    return None


def _in_out_names(cls: Any) -> frozenset[str]:
    """The VAR_IN_OUT variables of a block, inherited ones too."""
    from iecoop.st.write.model import metadata

    found: set[str] = set()
    for klass in getattr(cls, "__mro__", ()):
        if kind_of(klass) in ("fb", "program") and not is_root(klass):
            found.update(f.name for f in metadata(klass).fields if f.section == "VAR_IN_OUT")
    return frozenset(found)


def _is_none(node: ast.expr) -> bool:
    return isinstance(node, ast.Constant) and node.value is None or _is_name(node, "None")


def _stem(target: str) -> str:
    """A name for a temporary from an assignment target's text (``self.a[i]`` gives ``a``)."""
    return target.removeprefix("self.").split("[", 1)[0].replace(".", "_")


def _escapes(body: list[ast.stmt]) -> bool:
    """Whether a loop body breaks or continues its own loop (not one nested in it)."""
    for stmt in body:
        if isinstance(stmt, (ast.Break, ast.Continue)):
            return True
        if isinstance(stmt, (ast.For, ast.While)):
            continue
        if _escapes([c for c in ast.iter_child_nodes(stmt) if isinstance(c, ast.stmt)]):
            return True
    return False


def _is_name(node: ast.AST | None, name: str) -> bool:
    return isinstance(node, ast.Name) and node.id == name


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


def walk_calls(tree: ast.AST) -> Iterator[ast.Call]:
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            yield node


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


def _from_iecoop(value: Any) -> bool:
    module = getattr(value, "__module__", "") or ""
    return module == "iecoop" or module.startswith("iecoop.")


# ---------------------------------------------------------------------------
# Calls of names: one rule per Python builtin and per iecoop operator
# ---------------------------------------------------------------------------

_CallRule = Callable[[BodyWriter, ast.Call], "tuple[str, int] | None"]


def _one_argument(node: ast.Call) -> ast.expr | None:
    return node.args[0] if len(node.args) == 1 and not node.keywords else None


def _call_min_max_abs(w: BodyWriter, node: ast.Call) -> tuple[str, int]:
    return f"{_BUILTINS[typing.cast(ast.Name, node.func).id]}({w.arguments(node)})", _ATOM


def _call_bool(w: BodyWriter, node: ast.Call) -> tuple[str, int] | None:
    arg = _one_argument(node)
    if arg is None:
        return None
    if _is_bool(w.typeof(arg)):
        return w.expr(arg)[0], _ATOM
    return f"{w.expr(arg, _EQ + 1)[0]} <> 0", _EQ


def _call_int(w: BodyWriter, node: ast.Call) -> tuple[str, int] | None:
    arg = _one_argument(node)
    if arg is None:
        return None
    info, inner = w.typeof(arg), w.expr(arg)[0]
    if _is_integer(info):
        return inner, _ATOM
    # int() of a float truncates towards zero, as TRUNC does.
    return (f"TRUNC({inner})" if _is_real(info) else f"TO_DINT({inner})"), _ATOM


def _call_float(w: BodyWriter, node: ast.Call) -> tuple[str, int] | None:
    arg = _one_argument(node)
    return (f"TO_LREAL({w.expr(arg)[0]})", _ATOM) if arg is not None else None


def _call_len(w: BodyWriter, node: ast.Call) -> tuple[str, int] | None:
    arg = _one_argument(node)
    if arg is None or not isinstance(w.typeof(arg), StringInfo):
        return None
    return f"LEN({w.expr(arg)[0]})", _ATOM


def _call_round(w: BodyWriter, node: ast.Call) -> tuple[str, int] | None:
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


def _call_len_constant(w: BodyWriter, node: ast.Call) -> tuple[str, int] | None:
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


def _call_math(w: BodyWriter, node: ast.Call) -> tuple[str, int] | None:
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


#: Functions of Python's math module and the IEC standard function that computes the same.
_MATH = {"sin": "SIN", "cos": "COS", "tan": "TAN", "asin": "ASIN", "acos": "ACOS", "atan": "ATAN", "sqrt": "SQRT", "exp": "EXP", "log10": "LOG"}


def _call_adr(w: BodyWriter, node: ast.Call) -> tuple[str, int]:
    return f"ADR({w.address_operand(node)})", _ATOM


def _call_sizeof(w: BodyWriter, node: ast.Call) -> tuple[str, int]:
    args = node.args
    if len(args) == 2:
        return f"SIZEOF({w.member_text(args[0], args[1])})", _ATOM
    return f"SIZEOF({w.expr(args[0])[0]})", _ATOM


def _call_is_valid_ref(w: BodyWriter, node: ast.Call) -> tuple[str, int]:
    holder, field = w.operator_args(node, 2)
    return f"__ISVALIDREF({w.member_text(holder, field)})", _ATOM


def _call_test_and_set(w: BodyWriter, node: ast.Call) -> tuple[str, int]:
    (flag,) = w.operator_args(node, 1)
    if isinstance(flag, ast.Call) and w.resolves_to(flag.func, "adr"):
        return f"TestAndSet({w.address_operand(flag)})", _ATOM
    return f"TestAndSet({w.expr(flag)[0]}^)", _ATOM


def _call_var_info(w: BodyWriter, node: ast.Call) -> tuple[str, int]:
    holder, field = w.operator_args(node, 2)
    return f"__VARINFO({w.member_text(holder, field)})", _ATOM


def _call_mod(w: BodyWriter, node: ast.Call) -> tuple[str, int] | None:
    if len(node.args) != 2:
        return None
    return f"{w.expr(node.args[0], _MUL)[0]} MOD {w.expr(node.args[1], _MUL + 1)[0]}", _MUL


def _call_operator(w: BodyWriter, node: ast.Call) -> tuple[str, int]:
    return f"{_OPERATORS[typing.cast(ast.Name, node.func).id]}({w.arguments(node)})", _ATOM


def _call_current_task(w: BodyWriter, node: ast.Call) -> tuple[str, int]:
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


# ---------------------------------------------------------------------------
# Types of expressions: one rule per kind of node
# ---------------------------------------------------------------------------


def _constant_type(value: Any) -> TypeInfo | None:
    """The type of a Python constant (a literal, or a module constant's value)."""
    if isinstance(value, bool):
        return _BOOL
    if isinstance(value, enum.Enum):
        return None
    if isinstance(value, int):
        return _DINT
    if isinstance(value, float):
        return _LREAL
    if isinstance(value, str):
        return _STRING
    return None


def _literal_type(w: BodyWriter, node: ast.Constant) -> TypeInfo | None:
    return _constant_type(node.value)


def _unary_type(w: BodyWriter, node: ast.UnaryOp) -> TypeInfo | None:
    return _BOOL if isinstance(node.op, ast.Not) else w._typeof(node.operand)


def _ifexp_type(w: BodyWriter, node: ast.IfExp) -> TypeInfo | None:
    return w._typeof(node.body) or w._typeof(node.orelse)


_TYPE_RULES: dict[type, Callable[[BodyWriter, Any], TypeInfo | None]] = {
    ast.Constant: _literal_type,
    ast.Name: BodyWriter.name_type,
    ast.Attribute: BodyWriter.attribute_type,
    ast.Subscript: BodyWriter.subscript_type,
    ast.Call: BodyWriter.call_type,
    ast.BinOp: BodyWriter.binop_type,
    ast.Compare: lambda w, node: _BOOL,
    ast.BoolOp: lambda w, node: _BOOL,
    ast.UnaryOp: _unary_type,
    ast.IfExp: _ifexp_type,
    ast.JoinedStr: lambda w, node: _STRING,
}


def _constant_expr(w: BodyWriter, node: ast.Constant) -> tuple[str, int]:
    if isinstance(node.value, (bool, int, float, str)) or node.value is None:
        return literal(node.value), _ATOM
    w.fail(node, f"the constant {node.value!r}")


def _subscript_expr(w: BodyWriter, node: ast.Subscript) -> tuple[str, int]:
    base = w.expr(node.value, _ATOM)[0]
    index = node.slice
    parts = index.elts if isinstance(index, ast.Tuple) else [index]
    if any(isinstance(p, ast.Slice) for p in parts):
        w.fail(node, "a slice")
    return f"{base}[{', '.join(w.expr(p)[0] for p in parts)}]", _ATOM


def _unary_expr(w: BodyWriter, node: ast.UnaryOp) -> tuple[str, int]:
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


def _boolop_expr(w: BodyWriter, node: ast.BoolOp) -> tuple[str, int]:
    word, prec = ("AND", _AND) if isinstance(node.op, ast.And) else ("OR", _OR)
    if any(w.may_act(v) for v in node.values[1:]):
        # Python's and / or stop at the first operand that decides; ST's AND / OR evaluate every
        # operand, so a call, a dereference or an index after the first is guarded by AND_THEN / OR_ELSE.
        word += "_THEN" if word == "AND" else "_ELSE"
    operands = [w.condition_operand(v, prec) for v in node.values]
    return f" {word} ".join(operands), prec


def _ifexp_expr(w: BodyWriter, node: ast.IfExp) -> tuple[str, int]:
    # ST's SEL(g, in0, in1) gives in0 when g is FALSE: the else value comes first
    cond = w.condition(node.test)
    return f"SEL({cond}, {w.expr(node.orelse)[0]}, {w.expr(node.body)[0]})", _ATOM


#: ST text and precedence of an expression, by its node type (see BodyWriter._expr).
_EXPR_RULES: dict[type, Callable[[BodyWriter, Any], tuple[str, int]]] = {
    ast.Constant: _constant_expr,
    ast.Name: lambda w, node: (w.name(node), _ATOM),
    ast.Attribute: lambda w, node: (w.attribute(node), _ATOM),
    ast.Subscript: _subscript_expr,
    ast.Call: BodyWriter.call,
    ast.BinOp: lambda w, node: w.binop(node, node),
    ast.UnaryOp: _unary_expr,
    ast.BoolOp: _boolop_expr,
    ast.Compare: BodyWriter.compare,
    ast.IfExp: _ifexp_expr,
    ast.JoinedStr: lambda w, node: (w.fstring(node), _ATOM),
}


def _first_argument_type(w: BodyWriter, node: ast.Call) -> TypeInfo | None:
    return w._typeof(node.args[0]) if node.args else None


def _round_type(w: BodyWriter, node: ast.Call) -> TypeInfo | None:
    info = _first_argument_type(w, node)
    return info if _is_integer(info) else _DINT


def _new_type(w: BodyWriter, node: ast.Call) -> TypeInfo | None:
    cls = w.constant_object(node.args[0]) if node.args else None
    info = class_info(cls) if isinstance(cls, type) else None
    return PointerInfo(lambda: info, type_text(info)) if info is not None else None


def _adr_type(w: BodyWriter, node: ast.Call) -> TypeInfo | None:
    if not node.args:
        return None
    target = w._typeof(node.args[0]) if len(node.args) == 1 else None
    return PointerInfo(lambda: target, type_text(target) if target is not None else "BYTE")


#: Result types of calls of names that do not depend on the arguments.
_CALL_TYPES: dict[str, TypeInfo] = {
    "T": _TIME, "LTIME": _LTIME, "float": _LREAL, "int": _DINT, "bool": _BOOL, "is_valid_ref": _BOOL,
    "test_and_set": _BOOL, "now_ms": _TIME, "len": _DINT,
}
#: Result types of calls of names that depend on the arguments.
_CALL_TYPE_RULES: dict[str, Callable[[BodyWriter, ast.Call], TypeInfo | None]] = {
    "min": _first_argument_type, "max": _first_argument_type, "abs": _first_argument_type,
    "round": _round_type, "new": _new_type, "adr": _adr_type, **{name: lambda w, node: _LREAL for name in _MATH},
}


def _library_result(name: str, value: Any) -> TypeInfo | None:
    """The result type of one of iecoop's IEC functions, from its annotation and its ST name."""
    if not (callable(value) and _from_iecoop(value)) or isinstance(value, type):
        return None
    ret = typing.get_type_hints(value).get("return")
    if ret is int:
        suffix = name.rsplit("TO_", 1)[-1] if "TO_" in name else "DINT"
        try:
            from iecoop import types as iec_types

            return resolve_type(getattr(iec_types, suffix), suffix)
        except Exception:
            return _DINT
    results: dict[Any, TypeInfo] = {float: _LREAL, bool: _BOOL, str: _STRING}
    return results.get(ret)


def _is_task_info(w: BodyWriter, node: ast.Call) -> bool:
    return w.resolves_to(node.func, "current_task") and _from_iecoop(w.globals.get("current_task"))


def _task_info_types() -> dict[str, TypeInfo]:
    from iecoop.types import BOOL as B, STRING as S, UDINT, UINT

    udint, uint = resolve_type(UDINT, "UDINT"), resolve_type(UINT, "UINT")
    return {
        "CycleTime": udint, "CycleCount": udint, "LastExecTime": udint, "Priority": uint,
        "FirstCycle": resolve_type(B, "BOOL"), "CycleTimeExceeded": resolve_type(B, "BOOL"),
        "TaskName": resolve_type(S, "STRING"),
    }


#: The members of TwinCAT's PlcTaskSystemInfo that iecoop's TaskInfo also has, and their ST types.
_TASK_INFO = _task_info_types()


def _by_reference(params: Sequence[tuple[str, TypeInfo, Any]]) -> dict[str, tuple[str, TypeInfo, Any]]:
    """The VAR_OUTPUT / VAR_IN_OUT parameters: name -> (section, the variable's type, initial value)."""
    found: dict[str, tuple[str, TypeInfo, Any]] = {}
    for name, info, default in params:
        if isinstance(default, FieldSpec) and default.section in ("VAR_OUTPUT", "VAR_IN_OUT"):
            target = info.target if isinstance(info, PointerInfo) else None
            if target is None:
                raise StExportError(f"{default.section} {name}: annotate it POINTER_TO[<type>]")
            found[name] = (default.section, target, default.initial if default.section == "VAR_OUTPUT" else MISSING)
    return found


def _body_params(params: Sequence[tuple[str, TypeInfo, Any]]) -> dict[str, TypeInfo]:
    """The parameters as the body sees them: an output / in-out has its variable's type (``x.deref`` is ``x``)."""
    by_reference = _by_reference(params)
    return {n: by_reference[n][1] if n in by_reference else i for n, i, _ in params}


#: The result each METHOD / FUNCTION is written with, by the function that first defines it (see result_info()).
_RESULTS: weakref.WeakKeyDictionary[Any, TypeInfo] = weakref.WeakKeyDictionary()


def result_info(func: Any, where: str, owner: Any) -> TypeInfo | None:
    """The result type a METHOD or PROPERTY (``owner`` its class) or FUNCTION (``owner`` None) is written with.

    Python returns a STRUCT or block itself, never a copy. Where every ``return`` of the member's first
    definition gives a variable that outlives the call (a variable of the block or of a GVL, an element of
    one, an input passed by reference), the result is ``REFERENCE TO`` it, bound with ``REF=``, so a caller
    that keeps the result (``area = plant.add_area(...)``, ``REF= calibration_for(...)``) keeps the variable,
    as in Python; ``x := F()`` still copies. Any other result is the type itself, a copy, as is every
    result an interface declares (its implementations are not all known).
    """
    info = return_info(func, where, owner)
    if not isinstance(info, AggregateInfo):
        return info
    root = _first_definition(func, owner)
    if root is None:
        return info
    found = _RESULTS.get(root[0])
    if found is None:
        _RESULTS[root[0]] = info  # while its body is read: a recursive call sees the copy
        found = ReferenceInfo(info) if _returns_variables(*root, info) else info
        _RESULTS[root[0]] = found
    return found


def _first_definition(func: Any, owner: Any) -> tuple[Any, Any] | None:
    """(function, class) of the first definition of a METHOD in the EXTENDS chain; None for an interface's."""
    if owner is None:
        return inspect.unwrap(func), None
    first = None
    for klass in owner.__mro__:
        if func.__name__ in klass.__dict__:
            if kind_of(klass) == "interface":
                return None
            if kind_of(klass) in ("fb", "program"):
                first = klass
    value = first.__dict__[func.__name__] if first is not None else None
    if isinstance(value, property):
        value = value.fget  # a PROPERTY: its Get accessor
    return (inspect.unwrap(value), first) if inspect.isfunction(value) else None


def _returns_variables(func: Any, owner: Any, info: TypeInfo) -> bool:
    """Whether every ``return`` of ``func`` gives a variable that outlives the call (read by translating it)."""
    name = func.__name__
    try:
        inputs = function_parameters(func, name) if owner is None else parameters(func, f"{owner.__name__}.{name}", owner)
        scope = Scope(owner, _fields_of(owner) if owner is not None else {}, {}, {}, set())
        writer = BodyWriter(
            scope, func, st_name=ident(name), result=info, params=_body_params(inputs),
            by_reference=set(_by_reference(inputs)), lenient=True,
        )
        writer.translate()
    except StExportError:
        return False
    return bool(writer.return_places) and all(writer.return_places)
