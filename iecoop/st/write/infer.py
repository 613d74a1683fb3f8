"""The types of Python expressions in a body, as the ST writer needs them.

A local's type comes from its annotation or from the expression that first
assigns it; a division, a call or a member read is written differently by
the type of what it reads. :class:`Inference` holds what a body's names
mean (its locals, inputs, the class's variables, the module's globals) and
answers ``typeof(node)``; the writers of expressions and statements build on it.
"""

from __future__ import annotations

import ast
import collections
import enum
import inspect
import typing
import weakref
from collections.abc import Callable, Sequence
from typing import Any

from iecoop.metadata import is_root, kind_of
from iecoop.memory.typeinfo import (
    AggregateInfo,
    ArrayInfo,
    ElementaryInfo,
    EnumInfo,
    InterfaceInfo,
    ReferenceInfo,
    TypeInfo,
    class_info,
    resolve_type,
)
from iecoop.memory.layout import MISSING, FieldSpec
from iecoop.memory.pointers import PointerInfo
from iecoop.st.language import MATH_BY_PYTHON
from iecoop.st.write.model import StExportError, function_parameters, ident, parameters, return_info, type_text
from iecoop.types import BOOL, DINT, LREAL, LTIME, STRING, TIME

__all__ = ["Inference", "Scope", "result_info"]

class Inference:
    """The state of one body being translated, and the types of its expressions."""

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
        #: The local the ST reader names like the member to hold its result (see BodyWriter.translate)
        self.result_local: str | None = None
        self.params = dict(params or {})
        self.rename = dict(rename or {})
        self.lenient = lenient
        self.locals: dict[str, TypeInfo | str] = {}
        #: The type Python sees of a local whose ST type differs: a REFERENCE TO bound to a block or struct is that block.
        self.local_types: dict[str, TypeInfo] = {}
        #: How many statements the body's lines hold (a comment for one left out is none).
        self.statements_written = 0
        self.references: set[str] = set()
        self.catch_vars: set[str] = set()
        self.fields = _fields_of(scope.cls)
        self.globals = getattr(func, "__globals__", {})
        self.filename = inspect.getsourcefile(func) or "<unknown>"
        self.lines: list[str] = []
        self.first_line = func.__code__.co_firstlineno
        #: Statements that became comments (lenient mode): (line, construct).
        self.untranslated: list[tuple[int, str]] = []
        #: Statements the next written line needs first: a call's result kept in a temporary.
        self.prelude: list[str] = []
        #: Temporaries of the statement being translated, by the id of the expression they hold.
        self.hoisted: dict[int, str] = {}
        #: Every local declared as a temporary (reused by later statements).
        self.temps: set[str] = set()
        #: The body's locals named like a variable, by the VAR_TEMP name they take instead.
        self.temp_names: dict[str, str] = {}
        #: The names the function binds (filled by translate()).
        self.bound: set[str] = set()
        #: How often the function reads each name (filled by translate()): a temporary read nowhere else folds away.
        self.reads: collections.Counter[str] = collections.Counter()
        #: The lines of the function's source (filled by translate()).
        self.source_lines: list[str] = []
        #: For loaded ST: the line in the function's Python -> the ST line it was read from (filled by translate()).
        self.st_lines: dict[int, int] = {}
        #: The comments of the source on lines of their own, (line, text), not written yet (filled by translate()).
        self.comments: list[tuple[int, str]] = []
        #: For each ``return value``, whether the value is a variable that outlives the call (see is_place()).
        self.return_places: list[bool] = []

    def line_of(self, node: ast.AST | None) -> int:
        """The line of ``node`` in its file: the ST line a loaded POU's statement was read from, else the Python line."""
        lineno = getattr(node, "lineno", 1)
        return self.st_lines.get(lineno, self.first_line + lineno - 1)

    def where_text(self, node: ast.AST | None = None) -> str:
        return f"{self.filename}:{self.line_of(node)}"

    def fail(self, node: ast.AST, what: str) -> typing.NoReturn:
        raise _Untranslated(node, what)

    def translate(self) -> list[str]:
        """The body's ST lines (the statement writer translates them)."""
        raise NotImplementedError

    def result_of(self, func: Any, where: str, owner: Any) -> TypeInfo | None:
        """The result type a METHOD, PROPERTY or FUNCTION is written with (see :func:`result_info`)."""
        return result_info(func, where, owner, type(self))

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

    def function_signature(self, value: Any) -> tuple[list[tuple[str, TypeInfo, Any]], TypeInfo | None] | None:
        """Inputs and result of a module function that can be an ST FUNCTION, or None."""
        if not inspect.isfunction(value):
            return None
        module = getattr(value, "__module__", "") or ""
        if module == "iecoop" or module.startswith("iecoop.") or value.__name__.startswith("<"):
            return None
        try:
            inputs = function_parameters(value, value.__qualname__)
            result = self.result_of(value, value.__qualname__, None)
        except StExportError:
            return None
        return inputs, result

    def typeof(self, node: ast.expr | None) -> TypeInfo | None:
        try:
            return self._typeof(node)
        except _Untranslated:
            return None

    def _local_info(self, name: str) -> TypeInfo | None:
        if name == self.result_local:
            return self.result
        if name in self.local_types:
            return self.local_types[name]
        info = self.locals.get(name, self.params.get(name))
        return None if isinstance(info, str) else info

    def _typeof(self, node: ast.expr | None) -> TypeInfo | None:
        return ExpressionType(self).visit(node)

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

    def member_type(self, cls: Any, name: str, fields: dict[str, TypeInfo]) -> TypeInfo | None:
        if name in fields:
            return fields[name]
        found = _member_function(cls, name)
        if found is None or found[0] is None:
            return None
        func, owner = found
        value = owner.__dict__.get(name)
        if isinstance(value, property):
            return self.result_of(func, f"{owner.__name__}.{name}", owner)
        return None



_BOOL = resolve_type(BOOL, "BOOL")


_DINT = resolve_type(DINT, "DINT")


_LREAL = resolve_type(LREAL, "LREAL")


_TIME = resolve_type(TIME, "TIME")


_LTIME = resolve_type(LTIME, "LTIME")


_STRING = resolve_type(STRING, "STRING")


def _is_real(info: TypeInfo | None) -> bool:
    return isinstance(info, ElementaryInfo) and info.record.kind == "real"


def _is_integer(info: TypeInfo | None) -> bool:
    return isinstance(info, (ElementaryInfo, EnumInfo)) and (
        isinstance(info, EnumInfo) or info.record.kind in ("signed", "unsigned")
    )


def _is_time(info: TypeInfo | None) -> bool:
    return isinstance(info, ElementaryInfo) and info.record.kind == "time"


def _is_whole(info: TypeInfo | None) -> bool:
    """An integer or a TIME: a whole number in Python, which ``/`` turns into a float."""
    return _is_integer(info) or _is_time(info)


def _is_bool(info: TypeInfo | None) -> bool:
    return isinstance(info, ElementaryInfo) and info.record.kind == "bool"


class Scope:
    """What a body's names mean: the class's variables and members, and module constants."""

    def __init__(
        self, cls: Any, fields: dict[str, TypeInfo], constants: dict[str, Any], functions: dict[str, Any],
        named_enums: set[Any] | None = None,
    ) -> None:
        self.cls = cls
        self.fields = fields
        #: Module constants the bodies use, by name (written as a VAR_GLOBAL CONSTANT list).
        self.constants = constants
        #: Module functions the bodies call, by name (written as FUNCTIONs).
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


def _is_name(node: ast.AST | None, name: str) -> bool:
    return isinstance(node, ast.Name) and node.id == name


def _from_iecoop(value: Any) -> bool:
    module = getattr(value, "__module__", "") or ""
    return module == "iecoop" or module.startswith("iecoop.")


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


class ExpressionType:
    """The ST type of a Python expression of a body, by the handler of its node: ``visit_<ast class name>``;
    None where the writer cannot tell (a name it does not know, an untyped value)."""

    def __init__(self, body: Inference) -> None:
        self.body = body

    def visit(self, node: ast.AST | None) -> TypeInfo | None:
        handler = getattr(self, f"visit_{type(node).__name__}", None)
        return typing.cast("TypeInfo | None", handler(node)) if handler is not None else None

    def visit_Constant(self, node: ast.Constant) -> TypeInfo | None:
        return _constant_type(node.value)

    def visit_UnaryOp(self, node: ast.UnaryOp) -> TypeInfo | None:
        return _BOOL if isinstance(node.op, ast.Not) else self.visit(node.operand)

    def visit_IfExp(self, node: ast.IfExp) -> TypeInfo | None:
        return self.visit(node.body) or self.visit(node.orelse)

    def visit_Compare(self, node: ast.Compare) -> TypeInfo | None:
        return _BOOL

    def visit_BoolOp(self, node: ast.BoolOp) -> TypeInfo | None:
        return _BOOL

    def visit_JoinedStr(self, node: ast.JoinedStr) -> TypeInfo | None:
        return _STRING

    def visit_Name(self, node: ast.Name) -> TypeInfo | None:
        w = self.body
        if node.id in w.locals or node.id in w.params:
            return w._local_info(node.id)
        if node.id in w.rename:
            return w.params.get(node.id)
        if node.id in ("True", "False"):
            return _BOOL
        return _constant_type(w.globals.get(node.id))

    def visit_Attribute(self, node: ast.Attribute) -> TypeInfo | None:
        w = self.body
        base = node.value
        if _is_name(base, "self") and "self" not in w.locals or isinstance(base, ast.Call) and _is_name(base.func, "super"):
            return w.member_type(w.scope.cls, node.attr, w.fields)
        owner = w.constant_object(base)
        if isinstance(owner, type) and issubclass(owner, enum.Enum):
            return class_info(owner) if kind_of(owner) == "enum" else None
        if node.attr == "deref" and isinstance(base, ast.Name) and base.id in w.by_reference:
            return w.params.get(base.id)
        inner = self.visit(base)
        if node.attr == "deref" and isinstance(inner, PointerInfo):
            return inner.target
        if isinstance(inner, ReferenceInfo):
            inner = inner.target
        if node.attr == "name" and isinstance(inner, EnumInfo):
            return _STRING
        if isinstance(base, ast.Call) and _is_task_info(w, base):
            return _TASK_INFO.get(node.attr)
        cls = _class_of(inner)
        return w.member_type(cls, node.attr, _fields_of(cls)) if cls is not None else None

    def visit_Subscript(self, node: ast.Subscript) -> TypeInfo | None:
        inner = self.visit(node.value)
        if isinstance(inner, ReferenceInfo):
            inner = inner.target
        return inner.elem if isinstance(inner, ArrayInfo) else None

    def visit_BinOp(self, node: ast.BinOp) -> TypeInfo | None:
        left, right = self.visit(node.left), self.visit(node.right)
        if isinstance(node.op, ast.Div) and _is_whole(left) and _is_whole(right):
            return _LREAL
        if _is_real(left):
            return left
        if _is_real(right):
            return right
        return left or right

    def visit_Call(self, node: ast.Call) -> TypeInfo | None:
        w = self.body
        func = node.func
        if isinstance(func, ast.Name) and func.id not in w.locals:
            return self.named_call(node, func.id)
        if isinstance(func, ast.Attribute):
            return self.method_call(func)
        return None

    def named_call(self, node: ast.Call, name: str) -> TypeInfo | None:
        w = self.body
        if name in _CALL_TYPES:
            return _CALL_TYPES[name]
        rule = _CALL_TYPE_RULES.get(name)
        if rule is not None:
            return rule(w, node)
        value = w.globals.get(name)
        if isinstance(value, type) and kind_of(value) == "enum":
            return class_info(value)
        signature = w.function_signature(value)
        if signature is not None:
            return signature[1]
        return _library_result(name, value)

    def method_call(self, func: ast.Attribute) -> TypeInfo | None:
        w = self.body
        base = func.value
        if isinstance(base, ast.Call) and _is_name(base.func, "super"):
            cls = w.scope.cls.__mro__[1]
        elif _is_name(base, "self") and "self" not in w.locals:
            cls = w.scope.cls
        else:
            cls = _class_of(self.visit(base))
        if cls is None:
            return None
        found = _member_function(cls, func.attr)
        if found is None or found[0] is None:
            return None
        function, owner = found
        return w.result_of(function, f"{owner.__name__}.{func.attr}", owner)


def _first_argument_type(w: Inference, node: ast.Call) -> TypeInfo | None:
    return w._typeof(node.args[0]) if node.args else None


def _round_type(w: Inference, node: ast.Call) -> TypeInfo | None:
    info = _first_argument_type(w, node)
    return info if _is_integer(info) else _DINT


def _new_type(w: Inference, node: ast.Call) -> TypeInfo | None:
    cls = w.constant_object(node.args[0]) if node.args else None
    info = class_info(cls) if isinstance(cls, type) else None
    return PointerInfo(lambda: info, type_text(info)) if info is not None else None


def _adr_type(w: Inference, node: ast.Call) -> TypeInfo | None:
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
_CALL_TYPE_RULES: dict[str, Callable[[Inference, ast.Call], TypeInfo | None]] = {
    "min": _first_argument_type, "max": _first_argument_type, "abs": _first_argument_type,
    "round": _round_type, "new": _new_type, "adr": _adr_type, **{name: lambda w, node: _LREAL for name in MATH_BY_PYTHON},
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


def _is_task_info(w: Inference, node: ast.Call) -> bool:
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


def result_info(func: Any, where: str, owner: Any, writer: type[Inference]) -> TypeInfo | None:
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
        found = ReferenceInfo(info) if _returns_variables(*root, info, writer) else info
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


def _returns_variables(func: Any, owner: Any, info: TypeInfo, writer: type[Inference]) -> bool:
    """Whether every ``return`` of ``func`` gives a variable that outlives the call (read by translating it)."""
    name = func.__name__
    try:
        inputs = function_parameters(func, name) if owner is None else parameters(func, f"{owner.__name__}.{name}", owner)
        scope = Scope(owner, _fields_of(owner) if owner is not None else {}, {}, {}, set())
        body = writer(
            scope, func, st_name=ident(name), result=info, params=_body_params(inputs),
            by_reference=set(_by_reference(inputs)), lenient=True,
        )
        body.translate()
    except StExportError:
        return False
    return bool(body.return_places) and all(body.return_places)


