"""Declarations and bodies of each exported object, split as TwinCAT keeps them.

Every POU, interface, data type and GVL becomes a :class:`Unit`: its
declaration text, its implementation text, and its METHODs and PROPERTY
accessors as :class:`Part` s. The flat ST text, the TwinCAT files and the
PLCopen XML are all written from these.
"""

from __future__ import annotations

import dataclasses
import enum
import inspect
import typing
from collections.abc import Mapping, Sequence
from typing import Any

from iecoop import NullInterface, Pointer
from iecoop.metadata import field_record, fields_of, is_root, kind_of
from iecoop.members import Access, visibility
from iecoop.memory.typeinfo import AggregateInfo, ArrayInfo, ReferenceInfo, TypeInfo
from iecoop.memory.layout import MISSING
from iecoop.memory.operators import AddressOf, Sibling
from iecoop.st.language import SECTION_ORDER
from iecoop.st.write.expressions import _CONSTANTS_GVL
from iecoop.st.write.literals import literal
from iecoop.st.write.infer import _BOOL, Scope, _body_params, _by_reference, _fields_of
from iecoop.st.write.infer import result_info as _result_info
from iecoop.st.write.recorded import Declared
from iecoop.st.write.statements import BodyWriter
from iecoop.st.write.model import (
    LIFECYCLE,
    ClassMeta,
    field_ident,
    FieldDecl,
    MemberDecl,
    StExportError,
    access_words,
    ident,
    renamed_note,
    alias_base,
    alias_target,
    enum_base,
    enum_members,
    function_parameters,
    parameters,
    type_text,
)

__all__ = ["Part", "Unit", "passed_inputs", "units"]


def result_info(func: Any, where: str, owner: Any) -> TypeInfo | None:
    """The result type a METHOD, PROPERTY or FUNCTION is written with (see :func:`.infer.result_info`)."""
    return _result_info(func, where, owner, BodyWriter)

#: ST names of FB_init / FB_exit inputs (TwinCAT and CODESYS call them so).
_LIFECYCLE_INPUTS = {"init_retains": "bInitRetains", "in_copy_code": "bInCopyCode"}


@dataclasses.dataclass
class Part:
    """A METHOD, or one accessor (Get / Set) of a PROPERTY."""

    kind: str  # "method", "get" or "set"
    name: str
    header: str  # METHOD ... / PROPERTY ... line
    declaration: str  # the VAR sections after the header
    implementation: str
    result: TypeInfo | None = None
    inputs: tuple[tuple[str, TypeInfo, Any], ...] = ()
    #: PUBLIC, PRIVATE, PROTECTED or INTERNAL: the METHOD's, or the accessor's own
    access: Access = Access.PUBLIC
    #: The ``{attribute '...'}`` pragmas above the header, by name.
    attributes: tuple[str, ...] = ()
    #: Its own locals (VAR): (ST name, type), as the declaration lists them.
    locals: tuple[tuple[str, TypeInfo | str], ...] = ()
    #: A METHOD's VAR_INST: the block's variables it keeps between calls.
    instance: tuple[FieldDecl, ...] = ()


def _locals_of(writer: BodyWriter) -> tuple[tuple[str, TypeInfo | str], ...]:
    return tuple((writer.name_text(name), info) for name, info in writer.locals.items())


#: The attribute of a METHOD the PLC calls after FB_init (``@call_after_init``), and of its FUNCTION_BLOCK.
_CALL_AFTER_INIT = "call_after_init"


def pragma(attribute: str) -> str:
    """The ST pragma that sets an attribute: ``{attribute 'qualified_only'}``."""
    return f"{{attribute '{attribute}'}}"


@dataclasses.dataclass
class Unit:
    """One exported object."""

    kind: str  # enum alias struct union gvl interface fb program
    name: str
    declaration: str
    implementation: str = ""
    parts: list[Part] = dataclasses.field(default_factory=list)
    meta: ClassMeta | None = None
    #: A FUNCTION's result, inputs and locals.
    signature: tuple[TypeInfo, tuple[tuple[str, TypeInfo, Any], ...], dict[str, TypeInfo | str]] | None = None
    #: The ``{attribute '...'}`` pragmas the declaration starts with, by name.
    attributes: list[str] = dataclasses.field(default_factory=list)
    #: The module constants of the constants' GVL: (Python name, value).
    constants: list[tuple[str, Any]] = dataclasses.field(default_factory=list)
    #: A block's or PROGRAM's body locals (its VAR_TEMP): (ST name, type).
    temps: tuple[tuple[str, TypeInfo | str], ...] = ()

    def add_attribute(self, attribute: str) -> None:
        """Set an attribute on the object: its pragma heads the declaration (once: a loaded object may have it)."""
        if attribute in self.attributes:
            return
        self.attributes.insert(0, attribute)
        self.declaration = f"{pragma(attribute)}\n{self.declaration}"

    @property
    def word(self) -> str:
        return {"fb": "FUNCTION_BLOCK", "program": "PROGRAM", "interface": "INTERFACE", "function": "FUNCTION"}.get(self.kind, "TYPE")


# ---------------------------------------------------------------------------
# Variables
# ---------------------------------------------------------------------------


def initial_text(info: TypeInfo, value: Any, where: str) -> str:
    """The ``:= ...`` text of an initial value (a list for an ARRAY, a dict for a STRUCT)."""
    if isinstance(info, ArrayInfo):
        if type(value) is info.ctype:
            value = list(value)
        if not isinstance(value, (list, tuple)):
            raise StExportError(f"{where}: an ARRAY initial value must be a list")
        return "[" + ", ".join(initial_text(info.elem, v, where) for v in value) + "]"
    if isinstance(info, AggregateInfo):
        if isinstance(value, dict):
            parts = [f"{field_ident(info.cls, k)} := {initial_text(field_record(info.cls, k).info, v, f'{where}.{k}')}" for k, v in value.items()]
            return "(" + ", ".join(parts) + ")"
        if isinstance(value, info.cls):
            parts = [f"{field_ident(info.cls, f.name)} := {initial_text(f.info, getattr(value, f.name), where)}" for f in fields_of(info.cls)]
            return "(" + ", ".join(parts) + ")"
    try:
        return literal(value, info)
    except ValueError as exc:
        raise StExportError(f"{where}: {exc}") from None


def _default_initial(info: TypeInfo, value: Any) -> bool:
    """Whether an initial value is the type's zero (left out, as ST code usually does)."""
    if value is MISSING or kind_of(type(value)) in ("fb", "program"):
        # A block instance as initial value is the declaration itself: FB instances have no literal.
        return True
    if isinstance(value, enum.Enum):
        return False
    if isinstance(value, bool) or isinstance(value, (int, float)):
        return value == 0 and not isinstance(value, bool) or value is False
    if isinstance(value, str):
        return value == ""
    # a null interface reference, a null POINTER (a METHOD's POINTER TO input without a value) are the zero
    return value is None or isinstance(value, NullInterface) or isinstance(value, Pointer) and not value


def _argument(value: Any, where: str, names: Mapping[str, str]) -> str:
    """An FB_init argument: a literal, a variable beside the member (``names``: the ST name of each of the
    block's variables), or the global instance it designates."""
    if isinstance(value, (Sibling, AddressOf)):
        target = names.get(value.member, ident(value.member))
        if value.index is not None:
            index = value.index if isinstance(value.index, tuple) else (value.index,)
            target += "[" + ", ".join(str(i) for i in index) + "]"
        return f"ADR({target})" if isinstance(value, AddressOf) else target
    if kind_of(type(value)) in ("fb", "program"):
        from iecoop.gvl import all_global_lists

        for instance in all_global_lists():
            for record in fields_of(type(instance)):
                if isinstance(record.info, AggregateInfo) and getattr(instance, record.name) == value:
                    return ident(record.name)
        raise StExportError(f"{where}: an FB_init argument that is a block instance must be a global one")
    try:
        return literal(value)
    except ValueError as exc:
        raise StExportError(f"{where}: {exc}") from None


def variable_line(
    name: str, info: TypeInfo, initial: Any, owner: str, fb_init: Any = None, *, python_name: str = "", declared: Declared | None = None,
    names: Mapping[str, str] | None = None,
) -> str:
    """``name : TYPE := initial;`` of a variable of ``owner`` (``python_name``: its name in Python, where it differs);
    ``declared``: what the loaded source said of it (``AT %I*``, ARRAY bounds by name); ``names``: the ST name
    of each variable of ``owner`` by its Python name, for FB_init arguments naming them."""
    where = f"{owner}.{python_name or name}"
    location = declared.locations.get(name.lower()) if declared is not None else None
    bounds = declared.dimensions(name, info.bounds) if declared is not None and isinstance(info, ArrayInfo) else None
    text = f"{ident(name, owner)}{f' {location}' if location else ''} : {type_text(info, bounds)}"
    if fb_init and isinstance(fb_init, Mapping):
        args = ", ".join(f"{ident(k)} := {_argument(v, f'{where}.{k}', names or {})}" for k, v in fb_init.items())
        text += f"({args})"
    elif fb_init:
        raise StExportError(f"{where}: FB_init inputs per ARRAY element have no declaration form the writer knows")
    if not _default_initial(info, initial):
        text += f" := {initial_text(info, initial, where)}"
    return text + ";" + renamed_note(name)


def _noted(line: str, name: str, declared: Declared | None, attributes: Sequence[str] = ()) -> list[str]:
    """A variable's declaration line (indented), after the pragmas and comments its loaded source had before
    it (and the pragmas of ``attributes`` it did not have), and with the comment it had after it."""
    before, after = declared.notes.get(name.lower(), ((), "")) if declared is not None else ((), "")
    had = {"".join(note.split()).lower() for note in before}
    added = [pragma(a) for a in attributes if "".join(pragma(a).split()).lower() not in had]
    return [*(f"    {note}" for note in (*before, *added)), f"    {line}" + (f"   {after}" if after else "")]


#: The attributes of a STRING that holds its instance's path (``VAR(instance_path=True)``), and of its POU.
_INSTANCE_PATH = ("instance-path", "noinit")
_REFLECTION = "reflection"


def _declared_type(field: FieldDecl) -> TypeInfo:
    if field.section == "VAR_IN_OUT" and isinstance(field.info, ReferenceInfo):
        return field.info.target
    return field.info


def sections(fields: Sequence[FieldDecl], owner: str, *, default: str | None = None, declared: Declared | None = None) -> list[str]:
    """VAR blocks in ST order, one per section and qualifier."""
    lines: list[str] = []
    groups: dict[tuple[str, str], list[FieldDecl]] = {}
    names = {field.name: field.spec.st_name or field.name for field in fields}
    for field in fields:
        section = default or field.section
        qualifier = field.spec.qualifiers if section != "VAR_IN_OUT" else ("CONSTANT" if field.spec.constant else "")
        groups.setdefault((section, qualifier), []).append(field)
    order = {s: i for i, s in enumerate((*SECTION_ORDER, "VAR_GLOBAL"))}
    for (section, qualifier), members in sorted(groups.items(), key=lambda item: order.get(item[0][0], 99)):
        if section == "VAR_INST" and default is None:
            continue  # declared inside the METHOD it belongs to (which asks with default="VAR_INST")
        lines.append(f"{section} {qualifier}".rstrip())
        for field in members:
            initial = field.spec.initial if section not in ("VAR_IN_OUT", "VAR_EXTERNAL") else MISSING
            attributes = _INSTANCE_PATH if field.spec.instance_path else ()
            name = field.spec.st_name or field.name
            line = variable_line(
                name, _declared_type(field), initial, owner, field.spec.fb_init, python_name=field.name, declared=declared, names=names,
            )
            lines += _noted(line, name, declared, attributes)
        lines.append("END_VAR")
    return lines


# ---------------------------------------------------------------------------
# Units
# ---------------------------------------------------------------------------


def _headed(meta: ClassMeta, own: Sequence[str], lines: Sequence[str]) -> tuple[str, list[str]]:
    """The declaration ``lines`` headed as the loaded source headed it (its pragmas and comments, as written)
    and by the pragmas of the attributes ``own`` the writer sets that it did not have; and every attribute."""
    declared = meta.declared
    kept = declared.head if declared is not None else ()
    had = sorted(declared.attributes) if declared is not None else []
    added = [a for a in own if a not in had]
    return "\n".join([*map(pragma, added), *kept, *lines]), [*added, *had]


def _type_unit(meta: ClassMeta) -> Unit:
    name = meta.name
    if meta.kind == "enum":
        items = enum_members(meta.cls)
        body = "\n".join(
            f"    {ident(n)} := {v}{',' if i < len(items) - 1 else ''}{renamed_note(n)}" for i, (n, v) in enumerate(items)
        )
        lines = [f"TYPE {name} :", "(", body, f") {enum_base(meta.cls)};", "END_TYPE", ""]
    elif meta.kind == "alias":
        found = alias_base(meta.cls)
        # its own initial value (a subrange's lower limit is where it starts anyway)
        initial = f" := {literal(found[1].initial, found[0])}" if found is not None and found[1].initial is not None \
            and not (found[1].limits is not None and found[1].initial == found[1].limits[0]) else ""
        lines = [f"TYPE {name} : {alias_target(meta.cls)}{initial};", "END_TYPE", ""]
    else:
        word = "STRUCT" if meta.kind == "struct" else "UNION"
        extends = f" EXTENDS {meta.parent.__name__}" if meta.parent is not None else ""
        lines = [f"TYPE {name}{extends} :", word]
        for field in meta.fields:
            st = field.spec.st_name or field.name
            lines += _noted(variable_line(st, field.info, field.spec.initial, name, python_name=field.name, declared=meta.declared), st, meta.declared)
        lines += [f"END_{word}", "END_TYPE", ""]
    declaration, attributes = _headed(meta, (), lines)
    return Unit(meta.kind, name, declaration, meta=meta, attributes=attributes)


def _gvl_unit(meta: ClassMeta) -> Unit:
    # A list written from Python needs its name in front of its variables; a loaded one keeps what it had.
    own = ("qualified_only",) if meta.declared is None or not meta.declared.from_st else ()
    declaration, attributes = _headed(meta, own, [*sections(meta.fields, meta.name, default="VAR_GLOBAL", declared=meta.declared), ""])
    return Unit("gvl", meta.name, declaration, meta=meta, attributes=attributes)


def _local_lines(writer: BodyWriter) -> list[str]:
    own = _locals_of(writer)
    if not own:
        return []
    return ["VAR", *(f"    {name} : {info if isinstance(info, str) else type_text(info)};" for name, info in own), "END_VAR"]


def passed_inputs(inputs: Sequence[tuple[str, TypeInfo, Any]]) -> list[tuple[str, TypeInfo, Any]]:
    """The inputs as a METHOD or FUNCTION declares them: Python passes a STRUCT or block itself, where a
    VAR_INPUT of its type would hold a copy, so such an input is ``REFERENCE TO`` it (bound by the call)."""
    return [(n, ReferenceInfo(i), MISSING) if isinstance(i, AggregateInfo) else (n, i, d) for n, i, d in inputs]


def _inputs_lines(inputs: Sequence[tuple[str, TypeInfo, Any]], owner: str, rename: Mapping[str, str]) -> list[str]:
    if not inputs:
        return []
    lines = ["VAR_INPUT"]
    for name, info, default in inputs:
        lines.append("    " + variable_line(rename.get(name, name), info, default, owner, python_name=name))
    lines.append("END_VAR")
    return lines


def _parameter_lines(params: Sequence[tuple[str, TypeInfo, Any]], owner: str, rename: Mapping[str, str]) -> list[str]:
    """VAR_INPUT, VAR_OUTPUT and VAR_IN_OUT of a METHOD or FUNCTION (outputs and in-outs are POINTER_TO parameters in Python)."""
    by_reference = _by_reference(params)
    lines = _inputs_lines([p for p in params if p[0] not in by_reference], owner, rename)
    for section in ("VAR_OUTPUT", "VAR_IN_OUT"):
        chosen = [(n, info, initial) for n, (sec, info, initial) in by_reference.items() if sec == section]
        if chosen:
            lines.append(section)
            lines += ["    " + variable_line(n, info, initial, owner) for n, info, initial in chosen]
            lines.append("END_VAR")
    return lines


def parameter_groups(params: Sequence[tuple[str, TypeInfo, Any]]) -> dict[str, list[tuple[str, TypeInfo, Any]]]:
    """The parameters by section (VAR_INPUT, VAR_OUTPUT, VAR_IN_OUT), each with its variable's type and initial value."""
    by_reference = _by_reference(params)
    groups: dict[str, list[tuple[str, TypeInfo, Any]]] = {"VAR_INPUT": [], "VAR_OUTPUT": [], "VAR_IN_OUT": []}
    for name, info, default in params:
        section, target, initial = by_reference.get(name, ("VAR_INPUT", info, default))
        groups[section].append((name, target, initial))
    return groups


class _Writer:
    def __init__(self, scope: Scope, lenient: bool, untranslated: list[str]) -> None:
        self.scope = scope
        self.lenient = lenient
        self.untranslated = untranslated

    def body(self, func: Any, **kwargs: Any) -> BodyWriter:
        writer = BodyWriter(self.scope, func, lenient=self.lenient, **kwargs)
        writer.translate()
        for line, what in writer.untranslated:
            self.untranslated.append(f"{writer.filename}:{line}: {what}")
        return writer

    def method(self, meta: ClassMeta, member: MemberDecl, interface: bool) -> Part:
        func = member.function
        where = f"{meta.name}.{member.name}"
        inputs = parameters(func, where, meta.cls)
        result = result_info(func, where, meta.cls)
        # Interface prototypes carry no access specifier (they are PUBLIC by definition).
        words = "" if interface else f"{access_words(member.flags)} "
        header = f"METHOD {words}{member.name}" + (f" : {type_text(result)}" if result is not None else "")
        attributes = (_CALL_AFTER_INIT,) if getattr(func, "_iec_call_after_init_", False) else ()
        header = "\n".join([*map(pragma, attributes), header])
        # VAR_INST(method=...) names the METHOD as Python does (``constant``, not ``constant_``).
        inst = [f for f in meta.fields if f.section == "VAR_INST" and f.spec.method == (member.python_name or member.name)]
        declared = passed_inputs(inputs)
        decl = _member_note(member) + _parameter_lines(declared, where, {})
        implementation = ""
        own: tuple[tuple[str, TypeInfo | str], ...] = ()
        if not interface and not member.flags & Access.ABSTRACT:
            writer = self.body(
                func, st_name=member.name, result=result, params=_body_params(inputs), by_reference=set(_by_reference(inputs)),
            )
            decl += _local_lines(writer)
            own = _locals_of(writer)
            implementation = "\n".join(writer.lines)
        if inst:
            decl += sections(inst, meta.name, default="VAR_INST")
        return Part("method", member.name, header, "\n".join(decl), implementation, result, tuple(declared), visibility(member.flags),
                    attributes, own, tuple(inst))

    def lifecycle(self, meta: ClassMeta, name: str, func: Any) -> Part:
        st_name = LIFECYCLE[name]
        where = f"{meta.name}.{st_name}"
        inputs = parameters(func, where, meta.cls)
        writer = self.body(func, st_name=st_name, result=_BOOL, params={n: i for n, i, _ in inputs}, rename=_LIFECYCLE_INPUTS)

        decl = _inputs_lines(inputs, where, _LIFECYCLE_INPUTS) + _local_lines(writer)
        renamed = tuple((_LIFECYCLE_INPUTS.get(n, n), i, d) for n, i, d in inputs)
        return Part("method", st_name, f"METHOD {st_name} : BOOL", "\n".join(decl), "\n".join(writer.lines), _BOOL, renamed,
                    locals=_locals_of(writer))

    def accessors(self, meta: ClassMeta, member: MemberDecl, interface: bool) -> list[Part]:
        where = f"{meta.name}.{member.name}"
        result = result_info(member.getter, where, meta.cls)
        if result is None:
            raise StExportError(f"{where}: a PROPERTY needs a type (annotate the getter's return)")
        words = "" if interface else f"{access_words(member.flags)} "
        header = f"PROPERTY {words}{member.name} : {type_text(result)}"
        parts: list[Part] = []
        for kind, func, flags in (("get", member.getter, member.get_flags), ("set", member.setter, member.set_flags)):
            if func is None:
                continue
            implementation, decl = "", ["VAR", "END_VAR"]
            own: tuple[tuple[str, TypeInfo | str], ...] = ()
            if not interface and not flags & Access.ABSTRACT:
                rename: dict[str, str] = {}
                params: dict[str, TypeInfo] = {}
                if kind == "set":
                    inputs = parameters(func, where, meta.cls)
                    if len(inputs) != 1:
                        raise StExportError(f"{where}: a Set accessor takes exactly one value")
                    rename = {inputs[0][0]: member.name}
                    params = {inputs[0][0]: inputs[0][1]}
                writer = self.body(func, st_name=member.name, result=result if kind == "get" else None, params=params, rename=rename)
                decl = _local_lines(writer) or decl
                own = _locals_of(writer)
                implementation = "\n".join(writer.lines)
            decl = _member_note(member) + decl
            if not interface and visibility(flags) != visibility(member.flags):
                # An accessor's own specifier heads its declaration, as TwinCAT stores it (in the flat
                # form it follows the PROPERTY line: PROPERTY PUBLIC Capacity : REAL / PRIVATE / VAR ...)
                decl = [typing.cast(str, visibility(flags).name), *decl]
            parts.append(Part(kind, member.name, header, "\n".join(decl), implementation, result, access=visibility(flags), locals=own))
        return parts


def _member_note(member: MemberDecl) -> list[str]:
    """The comment line of a METHOD or PROPERTY whose Python name is a keyword (see ``renamed_note``)."""
    note = renamed_note(member.python_name) if member.python_name else ""
    return [note.strip()] if note else []


def _pou_unit(meta: ClassMeta, writer: _Writer) -> Unit:
    """The PROGRAM, FUNCTION_BLOCK or INTERFACE of a class: declaration, body, methods and properties."""
    name = meta.name
    interface = meta.kind == "interface"
    implementation = ""
    # TwinCAT wants call_after_init above the FUNCTION_BLOCK too, not only above the METHOD it calls.
    after_init = any(getattr(m.function, "_iec_call_after_init_", False) for m in meta.members if m.kind == "method")
    decl_lines = [_pou_header(meta)]
    own_temps: tuple[tuple[str, TypeInfo | str], ...] = ()
    if not interface:
        temps: list[str] = []
        if meta.body is not None:
            body = writer.body(meta.body, st_name=name)
            implementation = "\n".join(body.lines)
            own_temps = _locals_of(body)
            temps = _local_lines(body)
            if temps:
                temps[0] = "VAR_TEMP"
        decl_lines += sections(meta.fields, name, declared=meta.declared) + temps
    parts = _pou_parts(meta, writer, interface)
    own = [_CALL_AFTER_INIT] if after_init else []
    if any(field.spec.instance_path for field in meta.fields):
        own.append(_REFLECTION)  # the PLC's compiler fills an instance-path STRING of a POU marked so only
    declaration, attributes = _headed(meta, own, decl_lines)
    return Unit(meta.kind, name, declaration + "\n", implementation, parts, meta, attributes=attributes, temps=own_temps)


def _pou_header(meta: ClassMeta) -> str:
    """The first line of a POU: ``FUNCTION_BLOCK ABSTRACT FB_x EXTENDS FB_base IMPLEMENTS I_y``."""
    interface = meta.kind == "interface"
    words = [meta.kind == "program" and "PROGRAM" or interface and "INTERFACE" or "FUNCTION_BLOCK"]
    words += [word for word, on in (("ABSTRACT", meta.abstract), ("FINAL", meta.final), ("INTERNAL", meta.internal)) if on]
    words.append(meta.name)
    if interface:
        bases = [b for b in meta.cls.__bases__ if kind_of(b) == "interface" and not is_root(b) and b.__name__ != "Interface"]
        if bases:
            words.append("EXTENDS " + ", ".join(type_text(_iface_info(b)) for b in bases))
    else:
        if meta.parent is not None:
            words.append(f"EXTENDS {meta.parent.__name__}")
        if meta.interfaces:
            words.append("IMPLEMENTS " + ", ".join(type_text(_iface_info(i)) for i in meta.interfaces))
    return " ".join(words)


def _pou_parts(meta: ClassMeta, writer: _Writer, interface: bool) -> list[Part]:
    """The FB_init/FB_exit, METHODs and PROPERTYs of a POU; when lenient, one that does not translate is left out."""
    parts: list[Part] = []
    if not interface:
        for lifecycle_name, func in meta.lifecycle:
            try:
                parts.append(writer.lifecycle(meta, lifecycle_name, func))
            except StExportError as exc:
                if not writer.lenient:
                    raise
                writer.untranslated.append(f"{_where(func)}: {meta.name}.{LIFECYCLE[lifecycle_name]}: member left out: {exc}")
    for member in meta.members:
        try:
            if member.kind == "method":
                parts.append(writer.method(meta, member, interface))
            else:
                parts.extend(writer.accessors(meta, member, interface))
        except StExportError as exc:
            if not writer.lenient:
                raise
            # A Python-only helper (its signature has no IEC type): left out, and said so.
            where = _where(member.function if member.kind == "method" else member.getter)
            writer.untranslated.append(f"{where}: {meta.name}.{member.name}: member left out: {exc}")
    return parts


def _where(func: Any) -> str:
    """``FILE:LINE`` of a function's definition (a loaded POU's: its ST file and line)."""
    code = getattr(inspect.unwrap(func), "__code__", None) if func is not None else None
    return f"{code.co_filename}:{code.co_firstlineno}" if code is not None else "<unknown>"


def _iface_info(cls: Any) -> TypeInfo:
    from iecoop.memory.typeinfo import class_info

    info = class_info(cls)
    assert info is not None
    return info


def _function_unit(name: str, func: Any, writer: _Writer) -> Unit:
    inputs = function_parameters(func, name)
    # A FUNCTION has a result in TwinCAT and CODESYS: one that returns nothing in Python gives a BOOL left FALSE.
    result = result_info(func, name, None) or _BOOL
    by_reference = _by_reference(inputs)
    body = writer.body(func, st_name=ident(name), result=result, params=_body_params(inputs), by_reference=set(by_reference))
    declared = passed_inputs(inputs)
    lines = [f"FUNCTION {ident(name)} : {type_text(result)}", *_parameter_lines(declared, name, {}), *_local_lines(body)]
    return Unit(
        "function", ident(name), "\n".join(lines) + "\n", "\n".join(body.lines),
        signature=(result, tuple(declared), dict(body.locals)),
    )


def units(
    metas: Sequence[ClassMeta], *, lenient: bool = False, functions: Mapping[str, Any] | None = None
) -> tuple[list[Unit], list[str]]:
    """Every object to export, with a GVL of the module constants the bodies use, and what was not translated.

    ``functions`` (ST name -> Python function) are written as FUNCTIONs whether or not a body calls them.
    """
    constants: dict[str, Any] = {}
    functions = dict(functions or {})
    named_enums: set[Any] = set()
    untranslated: list[str] = []
    found: list[Unit] = []
    for meta in metas:
        if meta.kind in ("enum", "alias", "struct", "union"):
            found.append(_type_unit(meta))
        elif meta.kind == "gvl":
            found.append(_gvl_unit(meta))
        else:
            scope = Scope(meta.cls, _fields_of(meta.cls), constants, functions, named_enums)
            found.append(_pou_unit(meta, _Writer(scope, lenient, untranslated)))
    done: set[str] = set()
    while set(functions) - done:
        for fname in sorted(set(functions) - done):
            done.add(fname)
            scope = Scope(None, {}, constants, functions, named_enums)
            try:
                unit = _function_unit(fname, functions[fname], _Writer(scope, lenient, untranslated))
            except StExportError as exc:
                message = f"{_where(functions[fname])}: FUNCTION {fname}: {exc}"
                if not lenient:
                    raise StExportError(message) from None
                untranslated.append(f"{message} (left out)")
                continue
            index = next((i for i, u in enumerate(found) if u.kind in ("fb", "program")), len(found))
            found.insert(index, unit)
    _mark_named_enums(found, named_enums, lenient, untranslated)
    if constants:
        lines = ["VAR_GLOBAL CONSTANT"]
        for cname, value in sorted(constants.items()):
            st_type = constant_type(value)
            lines.append(f"    {ident(cname, _CONSTANTS_GVL)} : {st_type} := {literal(value)};{renamed_note(cname)}")
        lines += ["END_VAR", ""]
        index = next((i for i, u in enumerate(found) if u.kind in ("gvl", "interface", "fb", "program")), len(found))
        found.insert(index, Unit("gvl", _CONSTANTS_GVL, "\n".join(lines), constants=sorted(constants.items())))
    return found, untranslated


def constant_type(value: Any) -> str:
    """The ST type a module constant is declared with: BOOL, DINT, LREAL or STRING(n)."""
    return "BOOL" if isinstance(value, bool) else "DINT" if isinstance(value, int) else "LREAL" if isinstance(value, float) else f"STRING({max(1, len(value))})"


def _mark_named_enums(found: list[Unit], named_enums: set[Any], lenient: bool, untranslated: list[str]) -> None:
    """Declare {attribute 'to_string'} on each enumeration whose component names the bodies read."""
    exported = {unit.meta.cls: unit for unit in found if unit.kind == "enum" and unit.meta is not None}
    for cls in sorted(named_enums, key=lambda c: c.__name__):
        unit = exported.get(cls)
        if unit is not None:
            unit.add_attribute("to_string")
            continue
        # Without the attribute TO_STRING gives the number: the enumeration must come along.
        message = f"{cls.__name__}: its component names are read (TO_STRING needs {{attribute 'to_string'}} on it): export {cls.__name__} too"
        if not lenient:
            raise StExportError(message)
        untranslated.append(message)


def flat_text(unit: Unit) -> str:
    """The unit in the flat convention: the POU, then each METHOD / PROPERTY accessor after it.

    A global list is preceded by a ``// GVL <name>`` line, and a PROPERTY
    accessor by ``// Get`` or ``// Set``: marks ``st.load`` reads.
    """
    out: list[str] = []
    if unit.kind == "gvl":
        # ST gives a global list no name in the text (TwinCAT takes the file's): a mark the reader takes it from.
        return f"// GVL {unit.name}\n{unit.declaration}"
    if unit.kind in ("enum", "alias", "struct", "union"):
        return unit.declaration
    end = {"fb": "END_FUNCTION_BLOCK", "program": "END_PROGRAM", "interface": "END_INTERFACE", "function": "END_FUNCTION"}[unit.kind]
    out.append(unit.declaration.rstrip("\n"))
    if unit.implementation:
        out.append(unit.implementation)
    out.append(end)
    for part in unit.parts:
        out.append("")
        if part.kind in ("get", "set"):
            out.append(f"// {part.kind.capitalize()}")
        out.append(part.header)
        if part.declaration:
            out.append(part.declaration)
        if part.implementation:
            out.append(part.implementation)
        out.append("END_METHOD" if part.kind == "method" else "END_PROPERTY")
    return "\n".join(out) + "\n"
