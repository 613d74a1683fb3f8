"""Methods and properties of POUs and interfaces, with their access specifiers.

``@method`` marks a METHOD and takes the specifiers as flags
(``@method(PROTECTED | FINAL)``); ``@prop`` is a PROPERTY whose getter and
setter may each carry their own specifier, given with ``@method(...)`` under
it. PUBLIC members run with no wrapper at all; PRIVATE, PROTECTED and
INTERNAL members check their caller, in every mode, and raise
``AccessError`` naming the member and the caller.

ST::

    METHOD PROTECTED Ramp : BOOL
    PROPERTY Gear : INT   (Get PUBLIC, Set PRIVATE)

Python::

    @method(PROTECTED)
    def ramp(self) -> BOOL: ...

    @prop
    def gear(self) -> INT: ...

    @gear.setter
    @method(PRIVATE)
    def gear(self, value: INT) -> None: ...
"""

from __future__ import annotations

import ast
import dataclasses
import enum
import functools
import inspect
import re
import sys
import textwrap
import types
import typing
import weakref
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, TypeVar, overload

from iecoop._codegen import definition
from iecoop.exceptions import AccessError, DefinitionError
from iecoop.metadata import Kind, kind_of, st_name
from iecoop.sections import FieldSpec, check_st_name

__all__ = [
    "ABSTRACT",
    "FINAL",
    "INTERNAL",
    "PRIVATE",
    "PROTECTED",
    "PUBLIC",
    "Access",
    "call_after_init",
    "method",
    "prop",
    "super_set",
]

_F = TypeVar("_F", bound=Callable[..., Any])


class Access(enum.IntFlag):
    """Access specifiers and modifiers of METHODs and PROPERTY accessors."""

    PUBLIC = 1
    PRIVATE = 2
    PROTECTED = 4
    INTERNAL = 8
    FINAL = 16
    ABSTRACT = 32


PUBLIC = Access.PUBLIC
PRIVATE = Access.PRIVATE
PROTECTED = Access.PROTECTED
INTERNAL = Access.INTERNAL
FINAL = Access.FINAL
ABSTRACT = Access.ABSTRACT

_VISIBILITY = Access.PUBLIC | Access.PRIVATE | Access.PROTECTED | Access.INTERNAL
#: How wide each visibility is, for "an override may not narrow access".
_WIDTH = {Access.PRIVATE: 0, Access.PROTECTED: 1, Access.INTERNAL: 1, Access.PUBLIC: 2}


def visibility(flags: Access) -> Access:
    return Access(flags & _VISIBILITY) or Access.PUBLIC


def _mark(func: _F, flags: Access, st_name: str | None = None) -> _F:
    vis = Access(flags & _VISIBILITY)
    if bin(int(vis)).count("1") > 1:
        raise DefinitionError(f"{func.__qualname__}: choose one of PUBLIC, PRIVATE, PROTECTED, INTERNAL")
    setattr(func, "_iec_flags_", Access(flags))
    setattr(func, "_iec_method_", True)
    if st_name is not None:
        setattr(func, "_iec_st_name_", check_st_name(st_name, f"METHOD {func.__qualname__}"))
    return func


@overload
def method(func: _F, /) -> _F: ...


@overload
def method(flags: Access = ..., /, *, st_name: str | None = None) -> Callable[[_F], _F]: ...


def method(arg: Any = Access.PUBLIC, /, *, st_name: str | None = None) -> Any:
    """``METHOD``: ``@method`` (PUBLIC) or ``@method(PRIVATE | FINAL)``.

    ``st_name=`` is the ST name when Python cannot spell it (``METHOD body``
    is ``@method(st_name="body") def body_(self)``); under ``@prop`` it names
    the PROPERTY.
    """
    if isinstance(arg, Access):
        return lambda func: _mark(func, arg, st_name)
    if callable(arg) and st_name is None:
        return _mark(arg, Access.PUBLIC)
    raise TypeError(f"@method takes access flags (PUBLIC, PRIVATE, ...) and st_name=, got {arg!r}")


def call_after_init(func: _F) -> _F:
    """``{attribute 'call_after_init'}``: run after FB_init and declaration-site inputs."""
    if len(inspect.signature(func).parameters) != 1:
        raise DefinitionError(f"{func.__qualname__}: a call_after_init method takes no inputs")
    setattr(func, "_iec_call_after_init_", True)
    return func


if TYPE_CHECKING:
    prop = property
else:

    class prop(property):
        """``PROPERTY``: ``@prop`` on the getter (Get), ``@name.setter`` on the setter (Set).

        Give an accessor its own specifier by stacking ``@method(PRIVATE)``
        under the decorator. A property without a setter is read-only.
        """


def super_set(base: super, name: str, value: Any) -> None:
    """``SUPER^.name := value``: write the base block's PROPERTY ``name`` (its Set accessor).

    Python's ``super()`` reads (``super().gear``) but refuses attribute writes,
    so the write is ``super_set(super(), "gear", 3)`` inside a method or body.
    A variable is not virtual: ``SUPER^.nCount`` is ``THIS^.nCount``, plain
    ``self.count = ...``.

    >>> from iecoop import INT, VAR, FunctionBlock, prop
    >>> class Axis(FunctionBlock):
    ...     _gear: INT = VAR(0)
    ...     @prop
    ...     def gear(self) -> INT:
    ...         return self._gear
    ...     @gear.setter
    ...     def gear(self, value: INT) -> None:
    ...         self._gear = value
    >>> class LimitedAxis(Axis):
    ...     @prop
    ...     def gear(self) -> INT:
    ...         return self._gear
    ...     @gear.setter
    ...     def gear(self, value: INT) -> None:
    ...         super_set(super(), "gear", min(value, 3))   # SUPER^.Gear := MIN(Gear, 3);
    >>> axis = LimitedAxis()
    >>> axis.gear = 5
    >>> axis.gear
    3
    """
    # super's __self__ / __thisclass__ are documented attributes that typeshed does not declare
    obj, this = getattr(base, "__self__", None), getattr(base, "__thisclass__", None)
    if not isinstance(base, super) or obj is None or this is None:
        raise TypeError(f"SUPER^.{name} :=: the first argument is super() inside a method, got {base!r}")
    mro = type(obj).__mro__
    for cls in mro[mro.index(this) + 1 :]:
        member = cls.__dict__.get(name)
        if member is None:
            continue
        setter = getattr(type(member), "__set__", None)
        if setter is None:
            raise AccessError(f"SUPER^.{name} := ...: {cls.__name__}.{name} is a METHOD, not a variable or PROPERTY")
        setter(member, obj, value)
        return
    raise AccessError(f"SUPER^.{name} := ...: no base of {this.__name__} declares {name}")


def flags_of(func: Any) -> Access:
    return typing.cast(Access, getattr(func, "_iec_flags_", Access.PUBLIC))


def st_name_of(func: Any, name: str) -> str:
    """The ST name ``@method(st_name=...)`` gave ``func``, else ``name``."""
    return typing.cast(str, getattr(func, "_iec_st_name_", name))


# ---------------------------------------------------------------------------
# Which class a piece of code belongs to (for PRIVATE / PROTECTED / outside-write checks)
# ---------------------------------------------------------------------------

#: code object -> weak references to every class whose body defined it (nested functions and
#: comprehensions included). A class statement run twice (a factory function, a parametrised
#: test, a re-executed module) gives several classes the same code object; each of them owns it.
#: Weak, and an entry leaves with its last class, so a class defined in a function can be
#: collected. The per-write check does not look here: each class keeps the code it owns in
#: ``_iec_own_codes_`` and, with its bases' code, in ``_iec_codes_`` (two set lookups in C).
_code_owners: dict[types.CodeType, tuple[weakref.ref[type], ...]] = {}

#: Code that only passes an attribute write on (checked mode's ``__setattr__``). A property
#: setter reached through it must judge the frame that wrote ``obj.prop = v``, not the forwarder.
FORWARDING_CODES: set[types.CodeType] = set()


def _forget(codes: set[types.CodeType], dead: weakref.ref[type]) -> None:
    for code in codes:
        rest = tuple(ref for ref in _code_owners.get(code, ()) if ref is not dead)
        if rest:
            _code_owners[code] = rest
        else:
            _code_owners.pop(code, None)


def _code_sets(cls: type) -> tuple[set[types.CodeType], set[types.CodeType]]:
    """The code ``cls`` owns and the code its instances count as their own (with its bases'), made at first use."""
    klass: Any = cls
    own: set[types.CodeType] | None = klass.__dict__.get("_iec_own_codes_")
    if own is None:
        own = set()
        klass._iec_own_codes_ = own
        klass._iec_codes_ = set().union(*(base.__dict__.get("_iec_own_codes_", ()) for base in cls.__mro__[1:]))
        klass._iec_owner_ref_ = weakref.ref(cls, functools.partial(_forget, own))
    return own, klass._iec_codes_


def own_code(code: types.CodeType, cls: type) -> None:
    """Record ``cls`` as an owner of ``code``."""
    own, codes = _code_sets(cls)
    if code not in own:
        own.add(code)
        codes.add(code)
        _code_owners[code] = (*_code_owners.get(code, ()), typing.cast(Any, cls)._iec_owner_ref_)


def adopt_code(copy: types.CodeType, original: types.CodeType, cls: type) -> None:
    """``copy`` is ``original`` compiled into ``cls``'s call: it has the same owners and counts as ``cls``'s own where ``original`` does."""
    for owner in _owners(original):
        own_code(copy, owner)
    codes = _code_sets(cls)[1]
    if original in codes:
        codes.add(copy)


def code_of(code: types.CodeType, obj: Any) -> bool:
    """Whether ``code`` belongs to the class of ``obj`` or one of its bases: the block's own code."""
    return code in getattr(type(obj), "_iec_codes_", ())


def _owners(code: types.CodeType) -> list[type]:
    return [owner for ref in _code_owners.get(code, ()) if (owner := ref()) is not None]


def code_within(code: types.CodeType, cls: type) -> bool:
    """Whether ``code`` belongs to ``cls`` or a class derived from it (the PROTECTED rule)."""
    return any(issubclass(owner, cls) for owner in _owners(code))


def _codes(code: types.CodeType) -> list[types.CodeType]:
    found = [code]
    for const in code.co_consts:
        if isinstance(const, types.CodeType):
            found.extend(_codes(const))
    return found


def _functions_of(value: Any) -> list[Any]:
    if isinstance(value, property):
        return [f for f in (value.fget, value.fset, value.fdel) if f is not None]
    if isinstance(value, (staticmethod, classmethod)):
        return [value.__func__]
    if isinstance(value, types.FunctionType):
        return [value]
    wrapped = getattr(value, "__wrapped__", None)
    if isinstance(wrapped, types.FunctionType):
        return [wrapped]
    return []


def register_code(cls: type, namespace: dict[str, Any]) -> None:
    """Record every function the class body defined as belonging to ``cls``."""
    for value in namespace.values():
        for func in _functions_of(value):
            inner = inspect.unwrap(func)
            for code in _codes(inner.__code__):
                own_code(code, cls)


def caller_description(frame: Any) -> str:
    code = frame.f_code
    owners = _owners(code)
    if owners:
        owner = owners[-1]
        try:
            shown = st_name(owner, code.co_name)  # a METHOD by its ST name
        except (AttributeError, TypeError):
            shown = code.co_name  # the body, a nested function
        return f"{st_name(owner)}.{shown}"
    module = frame.f_globals.get("__name__", "?")
    return f"{code.co_name} in module {module}" if code.co_name != "<module>" else f"module {module}"


def _top_package(module: str) -> str:
    return module.split(".", 1)[0]


# ---------------------------------------------------------------------------
# Member records and signatures
# ---------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class Member:
    """A METHOD or PROPERTY as declared in one class."""

    name: str
    kind: str  # "method" or "property"
    owner: type
    flags: Access
    signature: tuple[Any, ...]
    has_get: bool = False
    has_set: bool = False
    get_flags: Access = Access.PUBLIC
    set_flags: Access = Access.PUBLIC
    #: The ST name (``@method(st_name=...)``), "" when it is ``name``.
    st_name: str = ""

    @property
    def abstract(self) -> bool:
        return bool(self.flags & Access.ABSTRACT)

    @property
    def final(self) -> bool:
        return bool(self.flags & Access.FINAL)

    @property
    def visibility(self) -> Access:
        return visibility(self.flags)

    def describe(self) -> str:
        vis = typing.cast(str, self.visibility.name)
        word = "METHOD" if self.kind == "method" else "PROPERTY"
        return f"{vis} {word} {st_name(self.owner)}.{self.st_name or self.name}"


def signature_of(func: Callable[..., Any], resolve: Callable[[str], Any]) -> tuple[Any, ...]:
    """(name, kind, annotation) of each parameter after self, then the return annotation."""
    sig = inspect.signature(func)
    items: list[Any] = []
    for i, param in enumerate(sig.parameters.values()):
        if i == 0:
            continue
        # a VAR_OUTPUT / VAR_IN_OUT parameter (its default is the specifier) differs from an input of the same type
        section = param.default.section if isinstance(param.default, FieldSpec) else None
        kind = section if section in ("VAR_OUTPUT", "VAR_IN_OUT") else param.kind
        items.append((param.name, kind, _resolved(param.annotation, resolve)))
    items.append(("return", None, _resolved(sig.return_annotation, resolve)))
    return tuple(items)


def _resolved(annotation: Any, resolve: Callable[[str], Any]) -> Any:
    if annotation is inspect.Parameter.empty or annotation is inspect.Signature.empty:
        return "?"
    if isinstance(annotation, str):
        try:
            return resolve(annotation)
        except Exception:
            return annotation
    return annotation


_QUALIFIED = re.compile(r"\b(?:[A-Za-z_]\w*\.)+([A-Za-z_]\w*)")


def _annotation_key(annotation: Any) -> str:
    """A comparable text for an annotation, resolved or not (a forward reference stays a string)."""
    if isinstance(annotation, str):
        return _QUALIFIED.sub(r"\1", annotation).replace(" ", "").replace("'", "").replace('"', "")
    if annotation is None or annotation is type(None):
        return "None"
    if isinstance(annotation, type) and not typing.get_args(annotation):
        return annotation.__name__
    from iecoop.types import elementary_type

    record = elementary_type(annotation)
    if record is not None:
        return record.name
    args = typing.get_args(annotation)
    if isinstance(annotation, types.UnionType) or typing.get_origin(annotation) is typing.Union:
        return "|".join(_annotation_key(a) for a in args)
    return _QUALIFIED.sub(r"\1", repr(annotation)).replace(" ", "")


def same_signature(a: tuple[Any, ...], b: tuple[Any, ...]) -> bool:
    """Whether two METHOD / PROPERTY signatures match: names, kinds and types of every parameter and the result.

    Types compare by name, so a forward reference (a class declared later, or
    the interface itself) matches the class it names.
    """
    if len(a) != len(b):
        return False
    return all(
        n1 == n2 and k1 == k2 and (t1 == t2 or _annotation_key(t1) == _annotation_key(t2))
        for (n1, k1, t1), (n2, k2, t2) in zip(a, b)
    )


def format_signature(signature: tuple[Any, ...]) -> str:
    def name(annotation: Any) -> str:
        if annotation is None:
            return "None"
        if isinstance(annotation, str):
            return annotation
        if isinstance(annotation, type):
            return annotation.__name__
        from iecoop.types import elementary_type

        record = elementary_type(annotation)
        if record is not None:
            return record.name
        origin, args = typing.get_origin(annotation), typing.get_args(annotation)
        if isinstance(origin, type) and args:  # POINTER_TO[INT], ARRAY[REAL]
            shown = "POINTER_TO" if origin.__name__ == "Pointer" else origin.__name__
            return f"{shown}[{', '.join(name(a) for a in args)}]"
        return str(annotation)

    params = ", ".join(f"{n}: {name(a)}" + (f" = {k}()" if isinstance(k, str) else "") for n, k, a in signature[:-1])
    return f"({params}) -> {name(signature[-1][2])}"


def _is_prototype_statement(node: ast.stmt, first: bool) -> bool:
    """``...``, ``pass``, a leading docstring or ``raise NotImplementedError[(...)]``."""
    if isinstance(node, ast.Pass):
        return True
    if isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant):
        return node.value.value is Ellipsis or (first and isinstance(node.value.value, str))
    if isinstance(node, ast.Raise) and node.cause is None and node.exc is not None:
        exc = node.exc.func if isinstance(node.exc, ast.Call) else node.exc
        return isinstance(exc, ast.Name) and exc.id == "NotImplementedError"
    return False


def _definition_node(func: Any) -> ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda | None:
    """The syntax tree of ``func`` from its source, or None when the source cannot be had."""
    registered = definition(getattr(func, "__code__", None))
    if registered is not None and isinstance(registered[0], (ast.FunctionDef, ast.AsyncFunctionDef)):
        return registered[0]  # loaded ST: its file holds ST, the generated def is recorded
    try:
        source = inspect.getsource(func)
    except (OSError, TypeError):
        return None
    try:
        tree = ast.parse(textwrap.dedent(source))
    except SyntaxError:  # a lambda inside a larger expression: its lines do not parse on their own
        return None
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.name == func.__name__:
            return node
        if isinstance(node, ast.Lambda) and func.__name__ == "<lambda>":
            return node
    return None


def has_body(func: Callable[..., Any]) -> bool:
    """Whether a function does anything beyond ``...`` / ``pass`` / a docstring / ``raise NotImplementedError``.

    Read from the function's source with ``ast``. ``raise NotImplementedError``
    is accepted as a prototype so that a method returning a value type-checks
    under ``mypy --strict`` without an ignore. When the source is not available
    (code built with ``exec`` and not registered in ``linecache``) the body
    cannot be seen, and the function is taken as a prototype.
    """
    node = _definition_node(inspect.unwrap(func))
    if node is None:
        return False
    if isinstance(node, ast.Lambda):
        body = node.body
        return not (isinstance(body, ast.Constant) and body.value in (None, Ellipsis))
    return not all(_is_prototype_statement(stmt, i == 0) for i, stmt in enumerate(node.body))


def _st_name(func: Any, name: str) -> str:
    """The ``st_name=`` of ``func`` ("" when it has none or it is ``name``)."""
    shown = st_name_of(func, name)
    return "" if shown == name else shown


def members_of_namespace(
    owner: type, namespace: dict[str, Any], resolve: Callable[[str], Any], skip: frozenset[str]
) -> dict[str, Member]:
    """The METHODs and PROPERTYs a class body declares."""
    found: dict[str, Member] = {}
    for name, value in namespace.items():
        if name in skip or (name.startswith("__") and name.endswith("__")):
            continue
        if isinstance(value, property):
            getter, setter = value.fget, value.fset
            if getter is None:
                raise DefinitionError(f"{owner.__name__}.{name}: a PROPERTY needs a Get accessor (@prop on the getter)")
            get_flags = flags_of(getter)
            set_flags = flags_of(setter) if setter is not None else Access.PUBLIC
            flags = Access(get_flags & (Access.FINAL | Access.ABSTRACT)) | visibility(get_flags)
            found[name] = Member(
                name, "property", owner, flags, signature_of(getter, resolve), True, setter is not None,
                get_flags, set_flags, _st_name(getter, name),
            )
        elif isinstance(value, types.FunctionType):
            found[name] = Member(
                name, "method", owner, flags_of(value), signature_of(value, resolve), st_name=_st_name(value, name)
            )
    return found


# ---------------------------------------------------------------------------
# Guards: the callers a non-public member admits
# ---------------------------------------------------------------------------


def _deny(member: str, rule: str, frame: Any) -> AccessError:
    return AccessError(f"{member} cannot be called from {caller_description(frame)}: {rule}")


def guard(func: Callable[..., Any], label: str, flags: Access, owner_ref: list[type]) -> Callable[..., Any]:
    """Wrap ``func`` so that only callers the specifier admits may run it."""
    vis = visibility(flags)
    if vis == Access.PUBLIC:
        return func
    getframe = sys._getframe
    forwarders = FORWARDING_CODES

    def caller() -> Any:
        frame = getframe(2)
        return frame.f_back if frame.f_code in forwarders else frame

    if vis == Access.PRIVATE:

        @functools.wraps(func)
        def private(*args: Any, **kwargs: Any) -> Any:
            frame = caller()
            if frame.f_code not in owner_ref[0]._iec_own_codes_:  # type: ignore[attr-defined]
                raise _deny(label, f"PRIVATE members are callable only inside {st_name(owner_ref[0])}", frame)
            return func(*args, **kwargs)

        return private
    if vis == Access.PROTECTED:
        declared: list[type] = []

        def declaring_class() -> type:
            # The member belongs to the hierarchy of the class that first declared it:
            # base code calling an override (the Template Method shape) is inside it.
            if not declared:
                owner = owner_ref[0]
                top = owner
                for base in owner.__mro__[1:]:
                    if func.__name__ in base.__dict__ and kind_of(base) in (Kind.FUNCTION_BLOCK, Kind.PROGRAM):
                        top = base
                declared.append(top)
            return declared[0]

        @functools.wraps(func)
        def protected(*args: Any, **kwargs: Any) -> Any:
            frame = caller()
            if not code_within(frame.f_code, declaring_class()):
                raise _deny(
                    label, f"PROTECTED members are callable only inside {st_name(declaring_class())} and its derived blocks",
                    frame,
                )
            return func(*args, **kwargs)

        return protected

    @functools.wraps(func)
    def internal(*args: Any, **kwargs: Any) -> Any:
        frame = caller()
        package = _top_package(str(frame.f_globals.get("__name__", "")))
        home = _top_package(owner_ref[0].__module__)
        if package != home:
            raise _deny(label, f"INTERNAL members are callable only inside the package {home!r}", frame)
        return func(*args, **kwargs)

    return internal


def rewrap(guarded: Any, func: Callable[..., Any], replacement: Callable[..., Any]) -> None:
    """Make the guard ``guarded`` made for ``func`` call ``replacement`` instead (the same METHOD, compiled again)."""
    if getattr(guarded, "__wrapped__", None) is not func:
        return
    cell = guarded.__closure__[guarded.__code__.co_freevars.index("func")]
    cell.cell_contents = replacement
    guarded.__wrapped__ = replacement


def _no_set_accessor(where: str) -> Callable[[Any, Any], None]:
    def read_only(self: Any, value: Any) -> None:
        raise AttributeError(f"PROPERTY {where} has no Set accessor: it is read-only")

    return read_only


def guard_namespace(owner_ref: list[type], name: str, namespace: dict[str, Any]) -> None:
    """Replace each non-public method / accessor in the class body with its guarded form (``name``: the class's ST name)."""
    for member_name, value in list(namespace.items()):
        if isinstance(value, property):
            getter, setter = value.fget, value.fset
            shown = st_name_of(getter, member_name)
            g = guard(getter, f"{visibility(flags_of(getter)).name} PROPERTY {name}.{shown} (Get)", flags_of(getter), owner_ref) if getter else None
            s = guard(setter, f"{visibility(flags_of(setter)).name} PROPERTY {name}.{shown} (Set)", flags_of(setter), owner_ref) if setter else None
            if s is None:
                s = _no_set_accessor(f"{name}.{shown}")
            if g is not getter or s is not setter:
                namespace[member_name] = type(value)(g, s, value.fdel, value.__doc__)
        elif isinstance(value, types.FunctionType) and not (member_name.startswith("__") and member_name.endswith("__")):
            flags = flags_of(value)
            if visibility(flags) != Access.PUBLIC:
                shown = st_name_of(value, member_name)
                namespace[member_name] = guard(value, f"{visibility(flags).name} METHOD {name}.{shown}", flags, owner_ref)


def narrower(child: Access, parent: Access) -> bool:
    return _WIDTH[visibility(child)] < _WIDTH[visibility(parent)]
