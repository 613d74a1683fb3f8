"""What the ST writer reads from a declared class: one adapter over the class builder's records.

What the class builder decided about a class (its record ``cls.__iec__``,
see :mod:`iecoop.metadata`, and its layout) is read in :func:`metadata` and
nowhere else, so a change in how classes are built is fixed here.
"""

from __future__ import annotations

import ast
import dataclasses
import enum
import inspect
import re
import textwrap
import types
import typing
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import Any

from iecoop._codegen import python_source
from iecoop.metadata import IecClass, iec_class, is_root, kind_of, layout_of
from iecoop.exceptions import DefinitionError
from iecoop.gvl import GlobalVariables, find_global
from iecoop.interfaces import Interface, IQueryInterface
from iecoop.members import Access, Member, flags_of, visibility
from iecoop.memory import Alias
from iecoop.memory.typeinfo import (
    ArrayInfo,
    ReferenceInfo,
    StringInfo,
    TypeInfo,
    resolve_type,
)
from iecoop.memory.pointers import PointerInfo
from iecoop.memory.layout import MISSING, FieldSpec
from iecoop.types import ELEMENTARY_TYPES, elementary_type
from iecoop.st import language
from iecoop.st.write.recorded import Bound, Declared
from iecoop.st.language import RESERVED

__all__ = ["RESERVED", "check_unique", "ident", "renamed_note", "type_name", "ClassMeta", "FieldDecl", "MemberDecl", "StExportError", "collect", "metadata", "type_text", "with_dependencies"]


class StExportError(DefinitionError):
    """A class or a statement has no Structured Text form the writer knows; the message names where and what."""


# Documented, and imported by users, from the public module.
StExportError.__module__ = "iecoop.st.export"


#: Kinds of declared classes, in the order a project lists them (types first, code last).
KINDS = ("enum", "alias", "struct", "union", "gvl", "interface", "fb", "program")

#: Lifecycle methods and their ST names, spelled as TwinCAT and CODESYS write them (``FB_init``).
LIFECYCLE = {python: "FB_" + python.removeprefix("fb_") for python in language.LIFECYCLE.values()}


@dataclasses.dataclass(frozen=True)
class FieldDecl:
    """One variable as ST declares it."""

    name: str
    section: str
    info: TypeInfo
    spec: FieldSpec


@dataclasses.dataclass(frozen=True)
class MemberDecl:
    """One METHOD or PROPERTY declared by the class itself."""

    name: str
    kind: str  # "method" or "property"
    flags: Access
    function: Any  # the method, or the property object
    getter: Any = None
    setter: Any = None
    get_flags: Access = Access.PUBLIC
    set_flags: Access = Access.PUBLIC
    #: The Python name, where ``name`` is it renamed (a keyword's trailing underscore).
    python_name: str = ""


@dataclasses.dataclass(frozen=True)
class ClassMeta:
    """A declared class as the ST writer sees it."""

    cls: Any
    name: str
    kind: str
    fields: tuple[FieldDecl, ...] = ()
    members: tuple[MemberDecl, ...] = ()
    parent: Any = None
    interfaces: tuple[Any, ...] = ()
    abstract: bool = False
    final: bool = False
    internal: bool = False
    body: Any = None
    lifecycle: tuple[tuple[str, Any], ...] = ()
    #: what the ST source of a loaded class declared beyond the class (pragmas, AT, bounds by name)
    declared: Declared | None = None


def _kind(obj: Any) -> str | None:
    if isinstance(obj, GlobalVariables):
        obj = type(obj)
    if typing.get_origin(obj) is typing.Annotated and any(isinstance(m, Alias) for m in obj.__metadata__):
        return "alias"
    if not isinstance(obj, type) or is_root(obj) or obj in (Interface, IQueryInterface):
        return None
    kind = kind_of(obj)
    return str(kind) if kind is not None else None


def _alias_name(obj: Any) -> str:
    return next(m.name for m in obj.__metadata__ if isinstance(m, Alias))


def metadata(obj: Any) -> ClassMeta:
    """Read a class (a GVL instance, an alias) into a :class:`ClassMeta`.

    Every name the class gives ST is checked here, before anything is written: the class's own
    (:func:`type_name`), and its variables', METHODs', PROPERTYs' and values' (:func:`ident`), which must
    also stay apart once case is ignored (:func:`check_unique`).
    """
    kind = _kind(obj)
    if kind is None:
        raise StExportError(f"{obj!r} is not a declared IEC type, POU, interface or GVL")
    if kind == "alias":
        return ClassMeta(obj, type_name(_alias_name(obj), kind), kind)
    cls = type(obj) if isinstance(obj, GlobalVariables) else obj
    name = type_name(cls.__name__, kind)
    if kind == "enum":
        check_unique(f"TYPE {name}", (n for n, _ in enum_members(cls)), "values")
        return ClassMeta(cls, name, kind)
    return _class_meta(cls, name, kind)


def _class_meta(cls: Any, name: str, kind: str) -> ClassMeta:
    """A STRUCT, UNION, GVL, INTERFACE, FUNCTION_BLOCK or PROGRAM: its variables, members, bases and code."""
    layout = layout_of(cls, own=True)
    outside = _outside_fields(cls) if kind in ("fb", "program") else []
    fields = [FieldDecl(r.name, r.section, r.info, r.spec) for r in (layout.own if layout is not None else ())] + outside
    record = _record(cls)
    # The whole EXTENDS chain is one scope: its variables, VAR_STAT / VAR_EXTERNAL and members.
    every = [r.name for r in (layout.fields if layout is not None else ())] + [f.name for f in outside]
    check_unique(f"{kind_word(kind)} {name}", [*every, *record.members], "variable and member names")
    parent = next((b for b in cls.__bases__ if _kind(b) == kind and kind in ("fb", "program", "struct")), None)
    interfaces = tuple(b for b in cls.__bases__ if kind_of(b) == "interface" and b is not Interface)
    members = _own_members(cls)
    body = cls.__dict__.get("body") if kind in ("fb", "program") else None
    lifecycle = tuple((n, cls.__dict__[n]) for n in LIFECYCLE if kind in ("fb", "program") and n in cls.__dict__)
    return ClassMeta(
        cls, name, kind, tuple(fields), members, parent, interfaces,
        record.abstract, record.final, record.internal, body, lifecycle,
    )


def kind_word(kind: str) -> str:
    """The ST keyword that declares a class of ``kind`` (``TYPE`` for the data types)."""
    return {"gvl": "GVL", "interface": "INTERFACE", "fb": "FUNCTION_BLOCK", "program": "PROGRAM", "function": "FUNCTION"}.get(kind, "TYPE")


def _record(cls: type) -> IecClass:
    record = iec_class(cls)
    assert record is not None, cls  # every kind metadata() reads has one
    return record


def _outside_fields(cls: Any) -> list[FieldDecl]:
    """VAR_STAT and VAR_EXTERNAL variables: the builder keeps them outside the instance block."""
    found: list[FieldDecl] = []
    own_statics = _record(cls).static_fields
    for record in own_statics:
        found.append(FieldDecl(record.name, "VAR_STAT", record.info, record.spec))
    statics = {r.name for r in own_statics}
    for name, value in cls.__dict__.items():
        if type(value).__name__ == "_Static" and name not in statics:
            _block, record = find_global(name, f"{cls.__name__}.{name}", cls.__module__)
            found.append(FieldDecl(name, "VAR_EXTERNAL", record.info, FieldSpec("VAR_EXTERNAL")))
    return found


def _own_members(cls: Any) -> tuple[MemberDecl, ...]:
    record = iec_class(cls)
    members: Mapping[str, Member] = record.members if record is not None else {}
    found: list[MemberDecl] = []
    for name, value in cls.__dict__.items():
        member = members.get(name)
        if member is None or member.owner is not cls:
            continue
        if member.kind == "property":
            getter = inspect.unwrap(value.fget) if value.fget is not None else None
            raw_setter = value.fset if value.fset is not None and getattr(value.fset, "__name__", "") != "read_only" else None
            setter = inspect.unwrap(raw_setter) if raw_setter is not None else None
            found.append(MemberDecl(
                ident(name, f"{cls.__name__} PROPERTY"), "property", member.flags, value, getter, setter, flags_of(getter), flags_of(setter) if setter else Access.PUBLIC, name,
            ))
        else:
            found.append(MemberDecl(ident(name, f"{cls.__name__} METHOD"), "method", member.flags, inspect.unwrap(value), python_name=name))
    return tuple(found)


def access_words(flags: Access, *, default_public: bool = True) -> str:
    """``PUBLIC`` / ``PRIVATE ABSTRACT`` ... as ST writes them after METHOD / PROPERTY."""
    words = [typing.cast(str, visibility(flags).name)]
    if flags & Access.ABSTRACT:
        words.append("ABSTRACT")
    if flags & Access.FINAL:
        words.append("FINAL")
    return " ".join(words)


# ---------------------------------------------------------------------------
# Types
# ---------------------------------------------------------------------------


def type_text(info: TypeInfo, bounds: Sequence[Bound] | None = None) -> str:
    """The ST type of a resolved TypeInfo (``STRING(20)``, ``ARRAY[1..4] OF INT``, ``POINTER TO X``); an ARRAY's
    bounds as ``bounds`` writes them when given (``1..GVL_Param.cMax``)."""
    if isinstance(info, StringInfo):
        # The language's default length, not the record's: a library alias (T_MaxString) has a record of its own.
        default = ELEMENTARY_TYPES[info.record.name].default_length  # type: ignore[union-attr]
        return info.record.name if info.length == default else f"{info.record.name}({info.length})"
    if isinstance(info, ArrayInfo):
        dims = ", ".join(f"{b.low}..{b.high}" for b in bounds) if bounds else ", ".join(f"{lo}..{hi}" for lo, hi in info.bounds)
        return f"ARRAY[{dims}] OF {type_text(info.elem)}"
    if isinstance(info, PointerInfo):
        target = info.target
        return "PVOID" if target is None else f"POINTER TO {type_text(target)}"
    if isinstance(info, ReferenceInfo):
        return f"REFERENCE TO {type_text(info.target)}"
    if getattr(info, "iface", None) is IQueryInterface:
        return "__SYSTEM.IQueryInterface"
    return info.name


def annotation_info(
    annotation: Any, func: Any, where: str, owner: Any = None, *, length: int | None = None, bounds: object = None,
) -> TypeInfo | None:
    """The TypeInfo of a parameter / return annotation of ``func`` (None for ``-> None``)."""
    if annotation is None or annotation is type(None) or annotation == "None" or annotation is inspect.Signature.empty:
        return None
    if isinstance(annotation, str):
        func = inspect.unwrap(func)  # a generated wrapper's globals are not the module's
        namespace: dict[str, Any] = {}
        if owner is not None:
            namespace[owner.__name__] = owner
        try:
            annotation = eval(annotation, getattr(func, "__globals__", {}), namespace)  # noqa: S307 - the user's own annotation
        except Exception as exc:
            raise StExportError(f"{where}: cannot resolve the annotation {annotation!r} ({exc})") from None
    if annotation is None or annotation is type(None):
        return None
    if isinstance(annotation, types.UnionType) or typing.get_origin(annotation) is typing.Union:
        # `IValve | None`: an interface or pointer input that may be 0 is just that type in ST.
        options = [a for a in typing.get_args(annotation) if a is not type(None)]
        if len(options) == 1:
            annotation = options[0]
    annotation = _PLAIN.get(annotation, annotation)
    try:
        return resolve_type(annotation, where, length=length, bounds=bounds)
    except DefinitionError as exc:
        raise StExportError(str(exc) if str(exc).startswith(where) else f"{where}: {exc}") from None


def _plain_annotations() -> dict[Any, Any]:
    from iecoop.types import BOOL, DINT, LREAL, STRING

    return {bool: BOOL, int: DINT, float: LREAL, str: STRING}


#: Plain Python annotations and the IEC type a value of them is in ST.
_PLAIN = _plain_annotations()

#: ST identifiers as TwinCAT 3 and CODESYS take them: IEC 61131-3's rule, ASCII only. Two underscores in a
#: row (``a__b``), which the standard forbids, are kept: both accept them, and their own system names
#: (``__QUERYINTERFACE``, ``__SYSTEM``) are spelled so.
_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_IDENTIFIER_RULE = "an ST identifier is a letter or underscore, then letters, digits and underscores, ASCII only"

#: What a declared class of each kind is usually called in ST: the name to suggest instead of a keyword.
_PREFIX = {
    "enum": "E_", "alias": "T_", "struct": "ST_", "union": "U_", "gvl": "GVL_", "interface": "I_", "fb": "FB_",
    "program": "PRG_", "function": "F_",
}


def ident(name: str, where: str | None = None) -> str:
    """The ST identifier of a Python name: itself, or with a trailing underscore if it spells a keyword.

    Every variable, METHOD, PROPERTY, enumeration value and parameter name the writer
    writes comes through here; a name that is not an ST identifier is refused, naming ``where``.
    """
    if not isinstance(name, str) or _IDENTIFIER.fullmatch(name) is None:
        place = f"{where} " if where else ""
        raise StExportError(f"{place}{name!r} is not an ST identifier ({_IDENTIFIER_RULE}): rename it")
    return f"{name}_" if name.upper() in RESERVED else name


def field_ident(cls: Any, name: str) -> str:
    """The ST name of the variable ``name`` (its Python name) of ``cls``: the ``st_name=`` the reader kept for a
    name Python could not take (``_nCount`` is ``st_nCount_`` in Python), else ``ident(name)``."""
    layout = layout_of(cls) if cls is not None else None
    record = layout.by_name.get(name) if layout is not None else None
    return record.spec.st_name if record is not None and record.spec.st_name else ident(name)


def renamed_note(name: str) -> str:
    """The comment a declaration carries when ``ident`` renamed its Python name (empty otherwise)."""
    return f" // {name} is an ST keyword: {ident(name)} in ST" if ident(name) != name else ""


def type_name(name: str, kind: str) -> str:
    """The ST name of a declared class (a type, POU, interface or GVL): its Python name, which must be an ST
    identifier and no keyword. It is not renamed: it is the object's name in the PLC project, in other
    projects' code and on its file."""
    word = kind_word(kind)
    if ident(name, f"{word} {name!r}") != name:
        raise StExportError(
            f"{word} {name}: {name} is an ST keyword, so it cannot name a {word} (ST ignores case): "
            f"rename the class, for example {_PREFIX.get(kind, '')}{name}"
        )
    return name


def check_unique(owner: str, names: Iterable[str], what: str = "names") -> None:
    """ST names ignore case: two ``names`` of one scope that are one ST name are refused, naming both."""
    seen: dict[str, str] = {}
    for name in names:
        other = seen.setdefault(ident(name, owner).lower(), name)
        if other != name:
            raise StExportError(
                f"{owner}: the {what} {other} and {name} differ only in case (or by a keyword's trailing underscore), "
                "and ST ignores case: they would be one name; rename one"
            )


def parameters(func: Any, where: str, owner: Any) -> list[tuple[str, TypeInfo, Any]]:
    """(name, type, default or MISSING) of each parameter after ``self``."""
    found: list[tuple[str, TypeInfo, Any]] = []
    for i, param in enumerate(inspect.signature(func).parameters.values()):
        if i == 0:
            continue
        if param.kind in (param.VAR_POSITIONAL, param.VAR_KEYWORD):
            raise StExportError(f"{where}: *{param.name} has no ST form; declare each input")
        ident(param.name, f"{where} input")
        default = MISSING if param.default is inspect.Parameter.empty else param.default
        # a VAR_OUTPUT(length=20) parameter: the STRING(20) it points to
        shape = (default.length, default.bounds) if isinstance(default, FieldSpec) else (None, None)
        info = annotation_info(param.annotation, func, f"{where}.{param.name}", owner, length=shape[0], bounds=shape[1])
        if info is None:
            raise StExportError(f"{where}: input {param.name} has no IEC type annotation")
        found.append((param.name, info, default))
    return found


def function_parameters(func: Any, where: str) -> list[tuple[str, TypeInfo, Any]]:
    """(name, type, default) of each input of a module function (no ``self``)."""
    found: list[tuple[str, TypeInfo, Any]] = []
    for param in inspect.signature(func).parameters.values():
        if param.kind in (param.VAR_POSITIONAL, param.VAR_KEYWORD):
            raise StExportError(f"{where}: *{param.name} has no ST form; declare each input")
        ident(param.name, f"{where} input")
        default = MISSING if param.default is inspect.Parameter.empty else param.default
        shape = (default.length, default.bounds) if isinstance(default, FieldSpec) else (None, None)
        info = annotation_info(param.annotation, func, f"{where}.{param.name}", length=shape[0], bounds=shape[1])
        if info is None:
            raise StExportError(f"{where}: input {param.name} has no IEC type annotation")
        found.append((param.name, info, default))
    return found


def return_info(func: Any, where: str, owner: Any) -> TypeInfo | None:
    return annotation_info(inspect.signature(func).return_annotation, func, where, owner)


# ---------------------------------------------------------------------------
# Which classes a module or a list declares
# ---------------------------------------------------------------------------


def _library(obj: Any) -> bool:
    """Library classes (TON, CTU...) exist on the PLC already: they are referenced, not exported."""
    module = getattr(obj, "__module__", "") or ""
    return module == "iecoop" or module.startswith("iecoop.")


def collect(source: Any) -> list[ClassMeta]:
    """The declared classes of a module (in definition order) or of an iterable of classes."""
    if isinstance(source, types.ModuleType):
        # a PROGRAM is an instance in a loaded module (st.load makes it): its class is what is written
        objects = [type(v) if _kind(type(v)) == "program" else v for v in vars(source).values()]
        candidates: Iterable[Any] = [
            v for v in objects
            if _kind(v) is not None and (getattr(type(v) if isinstance(v, GlobalVariables) else v, "__module__", None) == source.__name__ or _kind(v) == "alias")
        ]
    elif isinstance(source, (type, GlobalVariables)):
        candidates = [source]
    elif _kind(type(source)) == "program":
        candidates = [type(source)]
    else:
        # a PROGRAM instance (what st.load makes of a PROGRAM) is written as its class
        candidates = [type(v) if _kind(type(v)) == "program" else v for v in source]
    seen: set[int] = set()
    metas: list[ClassMeta] = []
    for obj in candidates:
        key = id(type(obj) if isinstance(obj, GlobalVariables) else obj)
        if key in seen or (_kind(obj) != "alias" and _library(type(obj) if isinstance(obj, GlobalVariables) else obj)):
            continue
        seen.add(key)
        metas.append(metadata(obj))
    order = {kind: i for i, kind in enumerate(KINDS)}
    return sorted(metas, key=lambda m: order[m.kind])


def with_dependencies(metas: list[ClassMeta]) -> list[ClassMeta]:
    """``metas`` and, transitively, the user-defined types, interfaces, POUs and GVLs they use from other modules.

    A class uses what its variables, EXTENDS / IMPLEMENTS, METHOD and PROPERTY signatures and bodies name
    (``AxisRef``, ``MC_Power``, ``AxisStep.IDLE``, a GVL). iecoop's own library (TON, R_TRIG, the IEC
    types) is on the PLC already and stays out. Two different objects with one ST name cannot share a PLC
    project's namespace: that raises StExportError naming both. The order is the one :func:`collect`
    gives (types first, code last; discovery order within a kind), so exporting again gives the same files.
    """
    found = list(metas)
    by_name: dict[str, Any] = {}
    for meta in found:
        _claim(by_name, meta)
    queue = list(found)
    while queue:
        meta = queue.pop(0)
        for obj in _uses(meta):
            key = type(obj) if isinstance(obj, GlobalVariables) else obj
            if _kind(obj) in (None, "alias") or _library(key) or any(m.cls is key for m in found):
                continue
            dependency = metadata(obj)
            _claim(by_name, dependency)
            found.append(dependency)
            queue.append(dependency)
    order = {kind: i for i, kind in enumerate(KINDS)}
    return sorted(found, key=lambda m: order[m.kind])


def _claim(by_name: dict[str, Any], meta: ClassMeta) -> None:
    """Register ``meta``'s ST name (ST names ignore case); a second object of that name is an error."""
    other = by_name.setdefault(meta.name.lower(), meta.cls)
    if other is not meta.cls:
        def qualified(obj: Any) -> str:
            return f"{getattr(obj, '__module__', '?')}.{getattr(obj, '__qualname__', obj)}"

        raise StExportError(
            f"two objects are named {meta.name} in one export: {qualified(other)} and {qualified(meta.cls)} "
            "(a PLC project has one namespace: rename one, or export the modules to separate projects)"
        )


def _uses(meta: ClassMeta) -> Iterable[Any]:
    """The declared classes and GVLs ``meta`` names, in a fixed order (duplicates included)."""
    cls = meta.cls
    if meta.kind in ("enum", "alias"):
        return
    yield from (b for b in cls.__bases__ if _kind(b) is not None)
    for field in meta.fields:
        yield from _classes_in(field.info)
        if field.section == "VAR_EXTERNAL":
            yield find_global(field.name, f"{meta.name}.{field.name}", cls.__module__)[0]
    functions: list[Any] = []
    for member in meta.members:
        functions += [member.function] if member.kind == "method" else [f for f in (member.getter, member.setter) if f is not None]
    functions += [func for _name, func in meta.lifecycle]
    if meta.body is not None:
        functions.append(meta.body)
    for func in functions:
        func = inspect.unwrap(func)
        try:
            hints = typing.get_type_hints(func, include_extras=True)
        except Exception:  # an annotation only a type checker resolves: the writer reports it where it matters
            hints = {}
        for value in hints.values():
            yield from _annotation_classes(value)
        yield from _named_in_body(func)


def _annotation_classes(annotation: Any) -> Iterable[Any]:
    """The declared classes an annotation names (``Motor``, ``POINTER_TO[AxisRef]``, ``IDrive | None``)."""
    if _kind(annotation) not in (None, "alias"):
        yield annotation
        return
    for arg in typing.get_args(annotation):
        yield from _annotation_classes(arg)
    for extra in getattr(annotation, "__metadata__", ()):
        target = getattr(extra, "target", None)
        if target is not None:
            yield from _annotation_classes(target)


def _classes_in(info: TypeInfo | None) -> Iterable[Any]:
    """The declared classes a resolved type refers to (an ARRAY's element, a POINTER's target...)."""
    if isinstance(info, ArrayInfo):
        yield from _classes_in(info.elem)
    elif isinstance(info, (PointerInfo, ReferenceInfo)):
        yield from _classes_in(info.target)
    else:
        for attribute in ("cls", "iface", "enum_cls"):
            value = getattr(info, attribute, None)
            if isinstance(value, type):
                yield value


def _named_in_body(func: Any) -> Iterable[Any]:
    """The module-level declared classes and GVLs a function's source names (``AxisStep.IDLE``, ``new(Motor)``)."""
    try:
        tree = ast.parse(textwrap.dedent(python_source(func)))
    except (OSError, TypeError, SyntaxError):
        return
    namespace = getattr(func, "__globals__", {})
    for node in ast.walk(tree):
        if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load) and node.id in namespace:
            yield namespace[node.id]


def enum_members(cls: Any) -> list[tuple[str, int]]:
    return [(m.name, int(m.value)) for m in typing.cast(Iterable[enum.IntEnum], cls)]


def enum_base(cls: Any) -> str:
    return typing.cast(str, cls._iec_base_.name)


def alias_base(obj: Any) -> tuple[TypeInfo, Alias] | None:
    """(the type an alias stands for, its Alias) of ``Annotated[..., Alias(...)]``; None for another annotation."""
    alias = next((m for m in getattr(obj, "__metadata__", ()) if isinstance(m, Alias)), None)
    if alias is None:
        return None
    others = tuple(m for m in obj.__metadata__ if not isinstance(m, Alias))  # the base type's own marks
    base = obj.__origin__
    return resolve_type(typing.Annotated[(base, *others)] if others else base, alias.name, length=alias.length,
                        bounds=alias.bounds), alias


def alias_target(obj: Any) -> str:
    """``STRING(20)``, ``ARRAY[1..3] OF INT``, ``INT(0..100)``: what ``TYPE name : ...;`` declares of an alias."""
    found = alias_base(obj)
    if found is None:
        record = elementary_type(obj)
        return record.name if record is not None else str(getattr(obj, "__origin__", obj))
    info, alias = found
    text = type_text(info)
    if alias.limits is not None:
        text += f"({alias.limits[0]}..{alias.limits[1]})"
    return text


def functions_of(meta: ClassMeta) -> Iterable[Callable[..., Any]]:
    """Every function whose body the writer translates."""
    if meta.body is not None:
        yield meta.body
    for _name, func in meta.lifecycle:
        yield func
    for member in meta.members:
        if member.kind == "method":
            yield member.function
        else:
            for func in (member.getter, member.setter):
                if func is not None:
                    yield func
