"""A mypy plugin: block calls typed from their VAR_INPUT / VAR_IN_OUT declarations.

Turn it on in the project's mypy configuration, as for pydantic or attrs::

    [tool.mypy]
    plugins = ["iecoop.mypy"]

Without it a call ``fb(...)`` takes any keyword. With it, ``fb(enable="yes")``
(wrong kind), ``fb(nonexistent=1)`` (no such input) and a call that leaves a
VAR_IN_OUT unbound are mypy errors, as they are compile errors in ST::

    fbCounter(bEnable := 'yes');   (* cannot convert STRING to BOOL *)
    fbCounter(bNonexistent := 1);  (* bNonexistent is no input of fbCounter *)

Each input keyword takes what the call accepts at run time: the declared
type; for an ARRAY also a list or tuple of values, for a STRUCT also a dict of
member values, for an interface also None (ST ``0``); for a ``REFERENCE_TO``
input or a VAR_IN_OUT an ``adr(...)`` pointer (or the struct / block / ARRAY
instance itself); a VAR_IN_OUT CONSTANT also takes a plain value. Inherited
inputs count, for FUNCTION_BLOCKs and PROGRAMs. A call through a variable
typed ``FunctionBlock`` or ``Program`` itself stays open (generic code).

A METHOD's or FUNCTION's VAR_IN_OUT parameter (``calls: POINTER_TO[DINT] =
VAR_IN_OUT()``) is required at every call, as in ST, although its default
would let Python leave it out.

The plugin also accepts the prototype form ``def healthy(self) -> BOOL: ...``
of an INTERFACE member and of an ``@method(ABSTRACT)`` under ``--strict``
(mypy's ``empty-body`` check): those members have no body by definition.

This module is loaded by mypy only; importing iecoop never imports it.
"""

from __future__ import annotations

from collections.abc import Callable

from mypy.nodes import (
    ARG_NAMED,
    ARG_NAMED_OPT,
    ARG_OPT,
    ARG_POS,
    AssignmentStmt,
    CallExpr,
    Decorator,
    Expression,
    FuncDef,
    MemberExpr,
    NameExpr,
    OpExpr,
    OverloadedFuncDef,
    RefExpr,
    Statement,
    TypeInfo,
    Var,
)
from mypy.plugin import ClassDefContext, FunctionSigContext, MethodSigContext, Plugin, SemanticAnalyzerPluginInterface
from mypy.semanal import is_trivial_body
from mypy.types import (
    AnyType,
    CallableType,
    Instance,
    NoneType,
    ProperType,
    Type,
    TypeOfAny,
    UnboundType,
    UnionType,
    get_proper_type,
)

__all__ = ["IecoopPlugin", "plugin"]

_POU = "iecoop.pou._PouMixin"
_INTERFACE = "iecoop.interfaces.Interface"
_STRUCT = "iecoop.memory.datatypes.Struct"
_ARRAY = "iecoop.memory.arrays.ARRAY"
_POINTER = "iecoop.memory.pointers.Pointer"
_REFERENCE_TO = "iecoop.memory.references.REFERENCE_TO"
_SECTIONS = {"iecoop.declarations.VAR_INPUT": "VAR_INPUT", "iecoop.declarations.VAR_IN_OUT": "VAR_IN_OUT"}
_METHOD = "iecoop.members.method"
_VAR_IN_OUT = "iecoop.declarations.VAR_IN_OUT"
_ABSTRACT = ("iecoop.members.ABSTRACT", "iecoop.members.Access.ABSTRACT")
#: Key of the per-class record in mypy's TypeInfo metadata (kept in mypy's cache).
_KEY = "iecoop"

#: One input of a block: the name, then section, REFERENCE_TO and CONSTANT flags.
_Input = dict[str, object]


class IecoopPlugin(Plugin):
    """Reads each block's input declarations at semantic analysis, types its calls at type checking."""

    def get_base_class_hook(self, fullname: str) -> Callable[[ClassDefContext], None] | None:
        base = self.lookup_fully_qualified(fullname)
        if base is not None and isinstance(base.node, TypeInfo):
            if base.node.has_base(_POU) or base.node.has_base(_INTERFACE):
                return _read_class
        return None

    def get_method_signature_hook(self, fullname: str) -> Callable[[MethodSigContext], CallableType] | None:
        return self._call_signature if fullname.endswith(".__call__") else _in_out_required

    def get_function_signature_hook(self, fullname: str) -> Callable[[FunctionSigContext], CallableType] | None:
        return _in_out_required

    def _call_signature(self, ctx: MethodSigContext) -> CallableType:
        pointer = self.lookup_fully_qualified(_POINTER)
        if pointer is None or not isinstance(pointer.node, TypeInfo):
            return ctx.default_signature  # iecoop.memory is not part of this mypy run
        return _call_signature(ctx, Instance(pointer.node, [AnyType(TypeOfAny.explicit)]))


def plugin(version: str) -> type[Plugin]:
    """The entry point mypy calls for ``plugins = ["iecoop.mypy"]``."""
    return IecoopPlugin


# ---------------------------------------------------------------------------
# Semantic analysis: which variables are inputs, which members are prototypes
# ---------------------------------------------------------------------------


def _read_class(ctx: ClassDefContext) -> None:
    info = ctx.cls.info
    if info.module_name == "iecoop.pou":
        return  # FunctionBlock and Program themselves: a call through them stays open, for generic code
    if info.has_base(_POU):
        inputs: dict[str, _Input] = {}
        for stmt in ctx.cls.defs.body:
            record = _input_of(stmt, ctx.api)
            if record is not None:
                inputs[str(record["name"])] = record
            elif _is_abstract_method(stmt):
                _accept_empty_body(info, stmt)
        info.metadata[_KEY] = {"inputs": list(inputs.values())}
    elif info.has_base(_INTERFACE):
        # An interface declares prototypes only (the runtime rejects a body), so '...' is the whole member.
        for stmt in ctx.cls.defs.body:
            _accept_empty_body(info, stmt)


def _input_of(stmt: Statement, api: SemanticAnalyzerPluginInterface) -> _Input | None:
    """``name: T = VAR_INPUT(...)`` / ``VAR_IN_OUT(...)`` as a record, else None."""
    if not (isinstance(stmt, AssignmentStmt) and len(stmt.lvalues) == 1 and isinstance(stmt.lvalues[0], NameExpr)):
        return None
    call = stmt.rvalue
    if not (isinstance(call, CallExpr) and isinstance(call.callee, RefExpr)):
        return None
    section = _SECTIONS.get(call.callee.fullname)
    if section is None:
        return None
    constant = any(
        name == "constant" and isinstance(arg, NameExpr) and arg.fullname == "builtins.True"
        for name, arg in zip(call.arg_names, call.args)
    )
    return {
        "name": stmt.lvalues[0].name,
        "section": section,
        "reference": _is_reference(stmt.unanalyzed_type, api, stmt),
        "constant": constant,
    }


def _is_reference(annotation: Type | None, api: SemanticAnalyzerPluginInterface, context: AssignmentStmt) -> bool:
    # mypy drops Annotated metadata, so REFERENCE_TO[T] is told from T by the name written.
    if not isinstance(annotation, UnboundType):
        return False
    found = api.lookup_qualified(annotation.name, context, suppress_errors=True)
    return found is not None and found.fullname == _REFERENCE_TO


def _is_abstract_method(stmt: Statement) -> bool:
    """``@method(ABSTRACT)`` (or ``ABSTRACT`` combined with other flags) on a method."""
    if not isinstance(stmt, Decorator):
        return False
    for decorator in stmt.decorators:
        if isinstance(decorator, CallExpr) and isinstance(decorator.callee, RefExpr):
            if decorator.callee.fullname == _METHOD and any(_mentions_abstract(arg) for arg in decorator.args):
                return True
    return False


def _mentions_abstract(expr: Expression) -> bool:
    if isinstance(expr, OpExpr):
        return _mentions_abstract(expr.left) or _mentions_abstract(expr.right)
    return isinstance(expr, (NameExpr, MemberExpr)) and expr.fullname in _ABSTRACT


def _accept_empty_body(info: TypeInfo, stmt: Statement) -> None:
    if isinstance(stmt, Decorator):
        func: FuncDef | None = stmt.func
    elif isinstance(stmt, OverloadedFuncDef) and isinstance(stmt.items[0], Decorator):
        func = stmt.items[0].func  # a property: the getter carries the result type
    elif isinstance(stmt, FuncDef):
        func = stmt
    else:
        func = None
    symbol = info.names.get(func.name) if func is not None else None
    if func is not None and symbol is not None and is_trivial_body(func.body):
        # mypy skips the empty-body check for members a plugin declares; this member is such a declaration.
        symbol.plugin_generated = True


# ---------------------------------------------------------------------------
# Type checking: the signature of fb(...)
# ---------------------------------------------------------------------------


def _call_signature(ctx: MethodSigContext, pointer: Instance) -> CallableType:
    self_type = get_proper_type(ctx.type)
    if not isinstance(self_type, Instance) or not self_type.type.has_base(_POU):
        return ctx.default_signature
    info = self_type.type
    inputs: dict[str, tuple[_Input, TypeInfo]] = {}
    # Base classes first, as EXTENDS lays them out.
    for base in reversed(info.mro):
        for record in base.metadata.get(_KEY, {}).get("inputs", []):
            inputs[str(record["name"])] = (record, base)
    if not inputs and _KEY not in info.metadata:
        return ctx.default_signature  # a class mypy analysed without the plugin: leave the call open
    names: list[str | None] = []
    kinds = []
    types: list[Type] = []
    for name, (record, base) in inputs.items():
        node = base.names[name].node if name in base.names else None
        declared = node.type if isinstance(node, Var) and node.type is not None else AnyType(TypeOfAny.unannotated)
        names.append(name)
        kinds.append(ARG_NAMED if record["section"] == "VAR_IN_OUT" else ARG_NAMED_OPT)
        types.append(_accepted(declared, record, ctx, pointer))
    return ctx.default_signature.copy_modified(
        arg_types=types, arg_kinds=kinds, arg_names=names, name=info.name, definition=None
    )


def _in_out_required(ctx: MethodSigContext | FunctionSigContext) -> CallableType:
    """A METHOD's / FUNCTION's VAR_IN_OUT (``x: POINTER_TO[T] = VAR_IN_OUT()``) must be given at every call.

    The default makes Python accept the call without it, so the plugin makes it
    required again: leaving it out is a mypy error, as it is a compile error in ST.
    (A module mypy reads from its cache has no defaults to look at; its calls stay as declared.)
    """
    signature = ctx.default_signature
    definition = signature.definition
    if isinstance(definition, Decorator):  # @method, @function
        definition = definition.func
    # A function read from a cache or a stub has no arguments (nor defaults) to look at.
    arguments = getattr(definition, "arguments", None) if isinstance(definition, FuncDef) else None
    if not arguments:
        return signature
    required = {
        arg.variable.name for arg in arguments
        if isinstance(arg.initializer, CallExpr) and isinstance(arg.initializer.callee, RefExpr)
        and arg.initializer.callee.fullname == _VAR_IN_OUT
    }
    if not required:
        return signature
    kinds = [
        (ARG_NAMED if kind == ARG_NAMED_OPT else ARG_POS if kind == ARG_OPT else kind) if name in required else kind
        for name, kind in zip(signature.arg_names, signature.arg_kinds)
    ]
    return signature.copy_modified(arg_kinds=kinds)


def _accepted(declared: Type, record: _Input, ctx: MethodSigContext, pointer: Instance) -> Type:
    """What a call accepts for one input, as the generated call accepts it at run time."""
    target = get_proper_type(declared)
    options: list[Type] = [declared]
    by_reference = record["section"] == "VAR_IN_OUT" or bool(record["reference"])
    if by_reference:
        if not record["constant"] and not _is_aggregate(target):
            options = []  # an elementary in-out is bound to a variable, through its address
        options.append(pointer)
    elif isinstance(target, Instance) and target.type.fullname == _ARRAY:
        any_type = AnyType(TypeOfAny.explicit)
        options += [ctx.api.named_generic_type(name, [any_type]) for name in ("builtins.list", "builtins.tuple")]
    elif isinstance(target, Instance) and target.type.has_base(_INTERFACE):
        options.append(NoneType())  # ST: fb(itfSensor := 0), the null reference
    elif isinstance(target, Instance) and target.type.has_base(_STRUCT):
        key = ctx.api.named_generic_type("builtins.str", [])
        options.append(ctx.api.named_generic_type("builtins.dict", [key, AnyType(TypeOfAny.explicit)]))
    return UnionType.make_union(options) if len(options) > 1 else options[0]


def _is_aggregate(target: ProperType) -> bool:
    """A STRUCT, a block or an ARRAY: bound by passing the instance itself."""
    return isinstance(target, Instance) and (
        target.type.fullname == _ARRAY or target.type.has_base(_STRUCT) or target.type.has_base(_POU)
    )
