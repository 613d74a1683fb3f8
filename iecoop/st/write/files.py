"""TwinCAT source files and PLCopen XML from the exported units.

TwinCAT XAE keeps one XML file per object (``.TcPOU``, ``.TcDUT``,
``.TcGVL``, ``.TcIO``) with the declaration and the implementation as CDATA
and a GUID per object; here each GUID is a UUID 5 of the object's path, so
the same classes always give the same bytes. The PLCopen file follows the
TC6 XML 2.01 schema; METHODs, PROPERTYs, interfaces and EXTENDS /
IMPLEMENTS, which the schema has no element for, go where CODESYS puts them:
in ``addData`` blocks under CODESYS's own names.
"""

from __future__ import annotations

import re
import uuid
import xml.etree.ElementTree as ET
from collections.abc import Iterator, Sequence
import typing
from typing import Any

from iecoop.members import Access
from iecoop.metadata import fields_of, kind_of
from iecoop.memory.typeinfo import (
    ArrayInfo,
    ElementaryInfo,
    InterfaceInfo,
    ReferenceInfo,
    StringInfo,
    TypeInfo,
)
from iecoop.memory.pointers import PointerInfo
from iecoop.memory.layout import MISSING
from iecoop.st.language import PLCOPEN_ELEMENTARY, PLCOPEN_ST_DECLARATION
from iecoop.st.write.literals import literal
from iecoop.st.write.units import Part, Unit, constant_type, initial_text, parameter_groups, variable_line
from iecoop.st.write.model import FieldDecl, StExportError, alias_base, enum_base, enum_members, ident, type_text

__all__ = ["guid", "plcopen_project", "twincat_file"]

_NAMESPACE = uuid.UUID("6f1c2a1e-5b0e-4c7e-9d8a-1e0c0b7a3f11")
_EXTENSIONS = {"fb": "TcPOU", "program": "TcPOU", "function": "TcPOU", "interface": "TcIO", "gvl": "TcGVL"}
_TAGS = {"fb": "POU", "program": "POU", "function": "POU", "interface": "Itf", "gvl": "GVL"}
_NL = "\r\n"


def guid(*path: str) -> str:
    """``{xxxxxxxx-...}``: the same path always gives the same id."""
    return "{" + str(uuid.uuid5(_NAMESPACE, "/".join(path))) + "}"


#: What XML 1.0 cannot hold, escaped or not: the writer escapes it in ST strings, so finding it is a bug.
_NOT_XML = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ufffe\uffff]")


def _xml_text(text: str) -> str:
    found = _NOT_XML.search(text)
    if found is not None:
        raise StExportError(f"the export text holds the control character {found.group()!r}, which XML cannot hold: {text[:60]!r}")
    return text


def _cdata(text: str) -> str:
    text = _xml_text(text).replace("\r\n", "\n").replace("\n", _NL)
    return "<![CDATA[" + text.replace("]]>", "]]]]><![CDATA[>") + "]]>"


def _attr(value: str) -> str:
    return _xml_text(value).replace("&", "&amp;").replace('"', "&quot;").replace("<", "&lt;")


def _groups(parts: Sequence[Part]) -> Iterator[list[Part]]:
    """Methods one by one; the Get and Set accessors of one PROPERTY together."""
    i = 0
    while i < len(parts):
        part = parts[i]
        if part.kind == "method":
            yield [part]
            i += 1
            continue
        group = [part]
        while i + len(group) < len(parts) and parts[i + len(group)].kind in ("get", "set") and parts[i + len(group)].name == part.name:
            group.append(parts[i + len(group)])
        yield group
        i += len(group)


def _implementation(lines: list[str], indent: str, text: str) -> None:
    lines.append(f"{indent}<Implementation>")
    lines.append(f"{indent}  <ST>{_cdata(text)}</ST>")
    lines.append(f"{indent}</Implementation>")


def twincat_file(unit: Unit) -> tuple[str, str]:
    """(file name, contents) of one unit as TwinCAT XAE writes it."""
    extension = _EXTENSIONS.get(unit.kind, "TcDUT")
    tag = _TAGS.get(unit.kind, "DUT")
    interface = unit.kind == "interface"
    special = ' SpecialFunc="None"' if tag == "POU" else ""
    lines = [
        '<?xml version="1.0" encoding="utf-8"?>',
        '<TcPlcObject Version="1.1.0.1" ProductVersion="3.1.4024.12">',
        f'  <{tag} Name="{_attr(unit.name)}" Id="{guid(unit.name)}"{special}>',
        f"    <Declaration>{_cdata(unit.declaration)}</Declaration>",
    ]
    if tag == "POU":
        _implementation(lines, "    ", unit.implementation)
    for group in _groups(unit.parts):
        first = group[0]
        if first.kind == "method":
            lines.append(f'    <Method Name="{_attr(first.name)}" Id="{guid(unit.name, first.name)}">')
            declaration = first.header + ("\n" + first.declaration if first.declaration else "") + "\n"
            lines.append(f"      <Declaration>{_cdata(declaration)}</Declaration>")
            if not interface:
                _implementation(lines, "      ", first.implementation)
            lines.append("    </Method>")
            continue
        lines.append(f'    <Property Name="{_attr(first.name)}" Id="{guid(unit.name, first.name)}">')
        lines.append(f"      <Declaration>{_cdata(first.header + chr(10))}</Declaration>")
        for accessor in group:
            word = accessor.kind.capitalize()
            lines.append(f'      <{word} Name="{word}" Id="{guid(unit.name, first.name, word)}">')
            lines.append(f"        <Declaration>{_cdata('' if interface else accessor.declaration + chr(10))}</Declaration>")
            if not interface:
                _implementation(lines, "        ", accessor.implementation)
            lines.append(f"      </{word}>")
        lines.append("    </Property>")
    lines.append(f"  </{tag}>")
    lines.append("</TcPlcObject>")
    return f"{unit.name}.{extension}", _NL.join(lines) + _NL


# ---------------------------------------------------------------------------
# PLCopen XML (TC6 2.01)
# ---------------------------------------------------------------------------

TC6 = "http://www.plcopen.org/xml/tc6_0201"
XHTML = "http://www.w3.org/1999/xhtml"
_CODESYS = "http://www.3s-software.com/plcopenxml/"
#: A fixed date, so that exporting again gives the same file.
_DATE = "2000-01-01T00:00:00"

_SECTION_TAGS = {
    "VAR_INPUT": "inputVars", "VAR_OUTPUT": "outputVars", "VAR_IN_OUT": "inOutVars", "VAR": "localVars",
    "VAR_TEMP": "tempVars", "VAR_EXTERNAL": "externalVars", "VAR_STAT": "localVars", "VAR_INST": "localVars",
}
#: The order PLCopen XML lists the sections of a POU in.
_SECTION_ORDER = ("VAR_INPUT", "VAR_OUTPUT", "VAR_IN_OUT", "VAR_EXTERNAL", "VAR", "VAR_STAT", "VAR_TEMP")


def _q(tag: str) -> str:
    return f"{{{TC6}}}{tag}"


def _sub(parent: ET.Element, tag: str, **attrs: str) -> ET.Element:
    return ET.SubElement(parent, _q(tag), attrs)


def _type(parent: ET.Element, info: TypeInfo) -> None:
    """The TC6 ``<type>`` content of a TypeInfo."""
    if isinstance(info, StringInfo):
        _sub(parent, "string" if info.record.name == "STRING" else "wstring", length=str(info.length))
    elif isinstance(info, ArrayInfo):
        array = _sub(parent, "array")
        for lo, hi in info.bounds:
            _sub(array, "dimension", lower=str(lo), upper=str(hi))
        _type(_sub(array, "baseType"), info.elem)
    elif isinstance(info, PointerInfo) and info.target is not None:
        _type(_sub(_sub(parent, "pointer"), "baseType"), info.target)
    elif isinstance(info, ElementaryInfo) and info.name in PLCOPEN_ELEMENTARY:
        _sub(parent, info.name)
    else:
        # Derived types, interfaces, LTIME, REFERENCE TO and PVOID: CODESYS names them.
        _sub(parent, "derived", name=type_text(info))


def _value(parent: ET.Element, info: TypeInfo, value: Any, where: str) -> None:
    _sub(_sub(parent, "initialValue"), "simpleValue", value=initial_text(info, value, where))


def _st_declaration(variable: ET.Element, section: str, text: str) -> None:
    """The ST declaration of a variable TC6 cannot declare (an IDE that does not know the block reads the
    variable as TC6 declares it; iecoop's reader takes the ST)."""
    data = _sub(_sub(variable, "addData"), "data", name=PLCOPEN_ST_DECLARATION, handleUnknown="implementation")
    ET.SubElement(data, _q("StDeclaration"), {"section": section}).text = text


def _variable(parent: ET.Element, name: str, info: TypeInfo, initial: Any, where: str) -> ET.Element:
    var = _sub(parent, "variable", name=ident(name))
    _type(_sub(var, "type"), info)
    if initial is not MISSING and initial is not None and not (isinstance(info, (ReferenceInfo, InterfaceInfo, PointerInfo))):
        if not (isinstance(initial, (dict, list)) and not initial):
            _value(var, info, initial, where)
    return var


def _sections(interface: ET.Element, fields: Sequence[FieldDecl], owner: str) -> None:
    for section in _SECTION_ORDER:
        members = [f for f in fields if f.section == section]
        for qualifier in sorted({f.spec.qualifiers for f in members}):
            spec = next(f.spec for f in members if f.spec.qualifiers == qualifier)
            flags = (("constant", spec.constant), ("retain", spec.retain), ("persistent", spec.persistent))
            attrs = {name: "true" for name, on in flags if on}
            block = _sub(interface, _SECTION_TAGS[section], **attrs)
            for field in (f for f in members if f.spec.qualifiers == qualifier):
                info = field.info.target if section == "VAR_IN_OUT" and isinstance(field.info, ReferenceInfo) else field.info
                initial = MISSING if section in ("VAR_IN_OUT", "VAR_EXTERNAL") else field.spec.initial
                name = field.spec.st_name or field.name
                variable = _variable(block, name, info, initial, f"{owner}.{field.name}")
                if section == "VAR_STAT" or field.spec.fb_init:
                    names = {f.name: f.spec.st_name or f.name for f in fields}
                    text = variable_line(name, info, initial, owner, field.spec.fb_init, python_name=field.name, names=names)
                    _st_declaration(variable, section, text)


def _st_body(parent: ET.Element, text: str) -> None:
    body = _sub(parent, "body")
    st = _sub(body, "ST")
    xhtml = ET.SubElement(st, f"{{{XHTML}}}xhtml")
    xhtml.text = text


def _add_data(parent: ET.Element, name: str) -> ET.Element:
    add = parent.find(_q("addData"))
    if add is None:
        add = _sub(parent, "addData")
    return _sub(add, "data", name=_CODESYS + name, handleUnknown="implementation")


def _attributes(parent: ET.Element, names: Sequence[str]) -> None:
    """CODESYS keeps an object's ``{attribute ...}`` pragmas in an addData block of this name."""
    if names:
        attributes = ET.SubElement(_add_data(parent, "attributes"), _q("Attributes"))
        for name in names:
            ET.SubElement(attributes, _q("Attribute"), {"Name": name, "Value": ""})


def _part_interface(parent: ET.Element, part: Part, where: str) -> None:
    interface = _sub(parent, "interface")
    if part.result is not None:
        _type(_sub(interface, "returnType"), part.result)
    _parameter_vars(interface, part.inputs, where)
    _local_vars(interface, part.locals)
    if part.instance:  # VAR_INST: TC6 has no such section; a localVars block each of whose variables says it
        block = _sub(interface, "localVars")
        for field in part.instance:
            name = field.spec.st_name or field.name
            variable = _variable(block, name, field.info, field.spec.initial, f"{where}.{field.name}")
            _st_declaration(variable, "VAR_INST", variable_line(name, field.info, field.spec.initial, where, python_name=field.name))
    _attributes(interface, part.attributes)
    _access_modifiers(interface, part.access)


def _local_vars(interface: ET.Element, own: Sequence[tuple[str, TypeInfo | str]], tag: str = "localVars") -> None:
    """A METHOD's, accessor's or FUNCTION's own variables (their types only: they start at zero on every call)."""
    if own:
        block = _sub(interface, tag)
        for name, local in own:
            variable = _sub(block, "variable", name=name)
            if isinstance(local, str):
                _sub(_sub(variable, "type"), "derived", name=local)
            else:
                _type(_sub(variable, "type"), local)


def _access_modifiers(interface: ET.Element, access: Access, default: Access = Access.PUBLIC) -> None:
    """A specifier other than ``default``, where CODESYS's PLCopen export keeps it: ``<AccessModifiers Private="true" />``."""
    if access != default:
        modifiers = ET.SubElement(_add_data(interface, "accessmodifiers"), _q("AccessModifiers"))
        modifiers.set(typing.cast(str, access.name).capitalize(), "true")


def _parameter_vars(interface: ET.Element, params: Sequence[tuple[str, TypeInfo, Any]], where: str) -> None:
    """inputVars, outputVars and inOutVars of a METHOD or FUNCTION."""
    for section, group in parameter_groups(params).items():
        if group:
            block = _sub(interface, _SECTION_TAGS[section])
            for name, info, default in group:
                _variable(block, name, info, default, f"{where}.{name}")


def _members(pou: ET.Element, unit: Unit, with_bodies: bool) -> None:
    for group in _groups(unit.parts):
        first = group[0]
        where = f"{unit.name}.{first.name}"
        if first.kind == "method":
            data = _add_data(pou, "method")
            method = ET.SubElement(data, "Method", {"name": first.name, "ObjectId": guid(unit.name, first.name)[1:-1]})
            method.tag = _q("Method")
            _part_interface(method, first, where)
            if with_bodies:
                _st_body(method, first.implementation)
            continue
        data = _add_data(pou, "property")
        prop = ET.SubElement(data, _q("Property"), {"name": first.name, "ObjectId": guid(unit.name, first.name)[1:-1]})
        interface = _sub(prop, "interface")
        if first.result is not None:
            _type(_sub(interface, "returnType"), first.result)
        # the PROPERTY's specifier is its Get's (the header's); a Set with another one carries its own
        own = first.access if first.kind == "get" else Access.PUBLIC
        _access_modifiers(interface, own)
        for accessor in group:
            tag = "GetAccessor" if accessor.kind == "get" else "SetAccessor"
            element = ET.SubElement(prop, _q(tag))
            accessor_interface = _sub(element, "interface")
            _local_vars(accessor_interface, accessor.locals)
            _access_modifiers(accessor_interface, accessor.access, default=own)
            if with_bodies:
                _st_body(element, accessor.implementation)


def _inheritance(pou: ET.Element, unit: Unit) -> None:
    meta = unit.meta
    if meta is None:
        return
    parent = meta.parent.__name__ if meta.parent is not None and unit.kind in ("fb", "program", "interface") else None
    interfaces = [type_text(_iface(i)) for i in meta.interfaces]
    if unit.kind == "interface":
        interfaces = []
        bases = [b for b in meta.cls.__bases__ if kind_of(b) == "interface" and b.__name__ != "Interface"]
        parent = ", ".join(type_text(_iface(b)) for b in bases) or None
    if parent is None and not interfaces:
        return
    data = _add_data(pou, "pouinheritance")
    inheritance = ET.SubElement(data, _q("Inheritance"))
    if parent:
        ET.SubElement(inheritance, _q("Extends")).text = parent
    for name in interfaces:
        ET.SubElement(inheritance, _q("Implements")).text = name


def _iface(cls: Any) -> TypeInfo:
    from iecoop.memory.typeinfo import class_info

    info = class_info(cls)
    assert info is not None
    return info


def _data_type(types: ET.Element, unit: Unit) -> None:
    meta = unit.meta
    if unit.kind == "gvl" or meta is None:
        return
    data_type = _sub(types, "dataType", name=unit.name)
    base = _sub(data_type, "baseType")
    if unit.kind == "enum":
        enumeration = _sub(base, "enum")
        values = _sub(enumeration, "values")
        for name, value in enum_members(meta.cls):
            _sub(values, "value", name=ident(name), value=str(value))
        _sub(_sub(enumeration, "baseType"), enum_base(meta.cls))
        _attributes(data_type, unit.attributes)
    elif unit.kind == "alias":
        found = alias_base(meta.cls)
        if found is None:
            from iecoop.memory.typeinfo import resolve_type

            _type(base, resolve_type(meta.cls, unit.name))
        elif found[1].limits is not None:
            unsigned = found[0].name in ("USINT", "UINT", "UDINT", "ULINT", "BYTE", "WORD", "DWORD", "LWORD")
            subrange = _sub(base, "subrangeUnsigned" if unsigned else "subrangeSigned")
            _sub(subrange, "range", lower=str(found[1].limits[0]), upper=str(found[1].limits[1]))
            _type(_sub(subrange, "baseType"), found[0])
        else:
            _type(base, found[0])
        if found is not None and found[1].initial is not None and found[1].limits is None:
            _value(data_type, found[0], found[1].initial, unit.name)
    else:
        # TC6 2.01 has no STRUCT EXTENDS and no UNION: the members are listed whole (base members first).
        struct = _sub(base, "struct")
        for record in fields_of(meta.cls):
            _variable(struct, record.name, record.info, record.spec.initial, f"{unit.name}.{record.name}")
        if unit.kind == "union":
            _add_data(data_type, "union")


def _function_interface(interface: ET.Element, unit: Unit) -> None:
    """A FUNCTION's result, inputs and locals (its signature)."""
    assert unit.signature is not None
    result, inputs, temps = unit.signature
    _type(_sub(interface, "returnType"), result)
    _parameter_vars(interface, inputs, unit.name)
    _local_vars(interface, list(temps.items()), "tempVars")


def plcopen_project(name: str, units: Sequence[Unit]) -> str:
    """One PLCopen XML (TC6 2.01) project holding every unit."""
    ET.register_namespace("", TC6)
    ET.register_namespace("xhtml", XHTML)
    project = ET.Element(_q("project"))
    _sub(project, "fileHeader", companyName="iecoop", productName="iecoop", productVersion="1.0", creationDateTime=_DATE)
    header = _sub(project, "contentHeader", name=name, modificationDateTime=_DATE)
    coordinates = _sub(header, "coordinateInfo")
    for language in ("fbd", "ld", "sfc"):
        _sub(_sub(coordinates, language), "scaling", x="1", y="1")
    types = _sub(project, "types")
    data_types = _sub(types, "dataTypes")
    pous = _sub(types, "pous")
    instances = _sub(project, "instances")
    _sub(instances, "configurations")
    globals_: list[Unit] = []
    interfaces: list[Unit] = []
    for unit in units:
        if unit.kind in ("enum", "alias", "struct", "union"):
            _data_type(data_types, unit)
        elif unit.kind == "gvl":
            globals_.append(unit)
        elif unit.kind == "interface":
            interfaces.append(unit)
        else:
            pou_type = {"program": "program", "function": "function"}.get(unit.kind, "functionBlock")
            pou = _sub(pous, "pou", name=unit.name, pouType=pou_type)
            interface = _sub(pou, "interface")
            if unit.meta is not None:
                _sections(interface, [f for f in unit.meta.fields if f.section != "VAR_INST"], unit.name)
                _local_vars(interface, unit.temps, "tempVars")
            else:
                _function_interface(interface, unit)
            _attributes(interface, unit.attributes)
            _st_body(pou, unit.implementation)
            _members(pou, unit, True)
            _inheritance(pou, unit)
    if globals_ or interfaces:
        for unit in interfaces:
            data = _add_data(project, "interface")
            itf = ET.SubElement(data, _q("Interface"), {"name": unit.name, "ObjectId": guid(unit.name)[1:-1]})
            _members(itf, unit, False)
            _inheritance(itf, unit)
        for unit in globals_:
            data = _add_data(project, "globalvars")
            block = ET.SubElement(data, _q("globalVars"), {"name": unit.name})
            if unit.meta is not None:
                for field in unit.meta.fields:
                    _variable(block, field.spec.st_name or field.name, field.info, field.spec.initial, f"{unit.name}.{field.name}")
            else:
                block.set("constant", "true")
                for constant, value in unit.constants:
                    var = _sub(block, "variable", name=ident(constant))
                    _sub(_sub(var, "type"), "string" if isinstance(value, str) else constant_type(value))
                    _sub(_sub(var, "initialValue"), "simpleValue", value=literal(value))
            _attributes(block, unit.attributes)
    ET.indent(project, "  ")
    return '<?xml version="1.0" encoding="utf-8"?>\n' + _xml_text(ET.tostring(project, encoding="unicode")) + "\n"
