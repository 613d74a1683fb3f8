"""Pass 1, PLCopen XML: a project CODESYS (or another IDE) exported as TC6 XML, read as the flat ST it declares.

CODESYS keeps a project in a binary file; the text it exports is PLCopen XML (TC6 2.00 / 2.01, IEC 61131-10's
predecessor), with CODESYS's own ``addData`` blocks for what TC6 has no element for: METHODs, PROPERTYs,
INTERFACEs, global variable lists, EXTENDS / IMPLEMENTS, access specifiers and attributes. This room turns
such a file into the flat ST the rest of the reader parses, one line at a time, each line mapped back to the
XML line it comes from, so every message names the XML file and its line.

Only ST bodies are read: a POU, METHOD, accessor or ACTION whose body is FBD, LD, IL, SFC or CFC is refused by
name. The XML is parsed as TwinCAT's files are (``parse.read_xml``): no DTD, entity or network.
"""

from __future__ import annotations

import dataclasses
import pathlib
from collections.abc import Iterator
from typing import Any

from iecoop.st.language import PLCOPEN_ST_DECLARATION
from iecoop.st.read.errors import StUnsupportedError

__all__ = ["flatten_plcopen"]

#: CODESYS's addData blocks, by the end of their name.
_METHOD, _PROPERTY, _INTERFACE, _GLOBALS = "/method", "/property", "/interface", "/globalvars"
#: TC6's variable sections, and the ST section each declares.
_SECTIONS = {
    "inputVars": "VAR_INPUT", "outputVars": "VAR_OUTPUT", "inOutVars": "VAR_IN_OUT", "localVars": "VAR",
    "tempVars": "VAR_TEMP", "externalVars": "VAR_EXTERNAL", "globalVars": "VAR_GLOBAL",
}
_POU_WORDS = {"program": "PROGRAM", "functionBlock": "FUNCTION_BLOCK", "function": "FUNCTION"}
#: TC6's elementary type elements whose ST name differs.
_TYPE_NAMES = {"DATE_AND_TIME": "DT", "TIME_OF_DAY": "TOD"}
_BODY_LANGUAGES = ("ST", "FBD", "LD", "IL", "SFC", "CFC")


@dataclasses.dataclass
class Element:
    """One XML element: its local name (namespace left off), attributes, children, text, and the line it starts on."""

    tag: str
    attrs: dict[str, str]
    line: int
    children: list[Element] = dataclasses.field(default_factory=list)
    #: its text (a body's code starts on the element's line, right after its start tag)
    text: str = ""

    def child(self, tag: str) -> Element | None:
        return next((c for c in self.children if c.tag == tag), None)

    def all(self, tag: str) -> list[Element]:
        return [c for c in self.children if c.tag == tag]


def _element(node: Any) -> Element:
    """Our element of one of lxml's (namespace left off, comments and processing instructions dropped)."""
    local = node.tag.rpartition("}")[2]
    element = Element(local, dict(node.attrib), node.sourceline or 0, text=node.text or "")
    element.children = [_element(child) for child in node if isinstance(child.tag, str)]
    return element


def project_root(root: Any, path: pathlib.Path) -> Element:
    """The ``<project>`` of a PLCopen file (``root`` as the reader's safe XML parse gives it)."""
    if not isinstance(root.tag, str) or root.tag.rpartition("}")[2] != "project":
        raise StUnsupportedError(f"{path}: not a PLCopen XML project (its root element is <{root.tag}>, not <project>)")
    return _element(root)


class _Flat:
    """The flat ST text being written, with the XML line of each of its lines."""

    def __init__(self, path: pathlib.Path) -> None:
        self.path = path
        self.lines: list[str] = []
        self.line_map: dict[int, tuple[str, int]] = {}

    def add(self, text: str, line: int) -> None:
        for offset, part in enumerate(text.split("\n")):
            self.lines.append(part)
            self.line_map[len(self.lines)] = (str(self.path), line + offset)

    def fail(self, element: Element, what: str) -> StUnsupportedError:
        return StUnsupportedError(f"{self.path}:{element.line}: {what}")

    # -- types and values -------------------------------------------------------------------------------

    def type_text(self, holder: Element | None, where: str) -> str:
        """The ST type of a ``<type>`` / ``<baseType>`` / ``<returnType>`` element's one child."""
        kind = next(iter(holder.children), None) if holder is not None else None
        if kind is None:
            raise self.fail(holder or Element("type", {}, 0), f"{where}: a type element without a type")
        if kind.tag == "derived":
            return kind.attrs.get("name", "")
        if kind.tag in ("string", "wstring"):
            length = kind.attrs.get("length")
            return kind.tag.upper() + (f"({length})" if length else "")
        if kind.tag == "array":
            dims = ", ".join(f"{d.attrs.get('lower', '0')}..{d.attrs.get('upper', '0')}" for d in kind.all("dimension"))
            return f"ARRAY[{dims}] OF {self.type_text(kind.child('baseType'), where)}"
        if kind.tag == "pointer":
            return f"POINTER TO {self.type_text(kind.child('baseType'), where)}"
        if kind.tag in ("subrangeSigned", "subrangeUnsigned"):
            bounds = kind.child("range")
            low, high = (bounds.attrs.get("lower", "0"), bounds.attrs.get("upper", "0")) if bounds is not None else ("0", "0")
            return f"{self.type_text(kind.child('baseType'), where)}({low}..{high})"
        if kind.tag in ("struct", "enum"):
            raise self.fail(kind, f"{where}: an inline {kind.tag.upper()} is not supported (declare it as a data type)")
        if kind.children or kind.attrs:
            raise self.fail(kind, f"{where}: the type element <{kind.tag}> is not read")
        return _TYPE_NAMES.get(kind.tag, kind.tag)

    def value_text(self, holder: Element) -> str:
        """ST text of an ``<initialValue>``'s simpleValue, arrayValue or structValue."""
        value = next(iter(holder.children), None)
        if value is None:
            raise self.fail(holder, "an initial value element without a value")
        if value.tag == "simpleValue":
            return value.attrs.get("value", "")
        if value.tag == "arrayValue":
            items = []
            for item in value.all("value"):
                text = self.value_text(item)
                repeat = item.attrs.get("repetitionValue")
                items.append(f"{repeat}({text})" if repeat else text)
            return "[" + ", ".join(items) + "]"
        if value.tag == "structValue":
            return "(" + ", ".join(f"{m.attrs.get('member', '')} := {self.value_text(m)}" for m in value.all("value")) + ")"
        raise self.fail(value, f"the initial value element <{value.tag}> is not read")

    def variables(self, section: Element, word: str) -> None:
        """A ``VAR_INPUT ... END_VAR`` block of a section element's variables (those iecoop's writer declared in ST
        text of their own, a VAR_STAT or a block given FB_init values, in the section the text names)."""
        qualifiers = " ".join(q.upper() for q in ("constant", "retain", "persistent") if section.attrs.get(q) == "true")
        own: list[tuple[str, str, int]] = []
        plain: list[Element] = []
        for variable in section.all("variable"):
            declared = _st_declaration(variable)
            if declared is not None and ("\n" in declared[1] or not declared[1].rstrip().endswith(";")):
                raise self.fail(variable, f"variable {variable.attrs.get('name', '')}: an ST declaration is one line ending in ';'")
            if declared is None:
                plain.append(variable)
            else:
                own.append((*declared, variable.line))
        for other, text, at in own:
            if other != word:
                self.add(f"{other}\n    {text}\nEND_VAR", at)
        self.add(f"{word} {qualifiers}".rstrip(), section.line)
        for other, text, at in own:
            if other == word:
                self.add(f"    {text}", at)
        for variable in plain:
            name = variable.attrs.get("name", "")
            line = f"    {name}"
            address = variable.attrs.get("address")
            if address:
                line += f" AT {address}"
            line += f" : {self.type_text(variable.child('type'), name)}"
            initial = variable.child("initialValue")
            if initial is not None:
                line += f" := {self.value_text(initial)}"
            self.add(line + ";", variable.line)
        self.add("END_VAR", section.line)

    def interface(self, interface: Element | None) -> None:
        for section in interface.children if interface is not None else ():
            word = _SECTIONS.get(section.tag)
            if word is not None:
                self.variables(section, word)

    # -- bodies and members -----------------------------------------------------------------------------

    def body(self, owner: Element, what: str) -> None:
        body = owner.child("body")
        if body is None:
            return
        language = next((c for c in body.children if c.tag in _BODY_LANGUAGES), None)
        if language is None:
            return
        if language.tag != "ST":
            raise self.fail(language, f"{what}: its body is written in {language.tag}, not Structured Text: "
                                      "iecoop reads ST only (write the body in ST)")
        xhtml = language.child("xhtml")
        source = xhtml if xhtml is not None else language
        code = source.text.lstrip("\n")
        if code.strip():
            # the body's lines from its first one on, each at its line of the XML file
            self.add(code.rstrip(), source.line + source.text.count("\n", 0, len(source.text) - len(code)))

    def members(self, owner: Element, name: str, with_bodies: bool) -> None:
        """The METHODs and PROPERTYs of CODESYS's addData blocks, after their POU or INTERFACE."""
        for data in _add_data(owner):
            kind = data.attrs.get("name", "")
            for member in data.children:
                if kind.endswith(_METHOD) and member.tag == "Method":
                    self.method(member, name, with_bodies)
                elif kind.endswith(_PROPERTY) and member.tag == "Property":
                    self.property(member, name, with_bodies)

    def method(self, member: Element, owner: str, with_bodies: bool) -> None:
        interface = member.child("interface")
        header = f"METHOD{_access(interface)} {member.attrs.get('name', '')}"
        result = interface.child("returnType") if interface is not None else None
        self.attributes(interface)
        self.add(header + (f" : {self.type_text(result, member.attrs.get('name', ''))}" if result is not None else ""), member.line)
        self.interface(interface)
        if with_bodies:
            self.body(member, f"METHOD {owner}.{member.attrs.get('name', '')}")
        self.add("END_METHOD", member.line)

    def property(self, member: Element, owner: str, with_bodies: bool) -> None:
        name = member.attrs.get("name", "")
        interface = member.child("interface")
        type_ = self.type_text(interface.child("returnType") if interface is not None else None, name)
        for tag, accessor in (("GetAccessor", "Get"), ("SetAccessor", "Set")):
            element = member.child(tag)
            if element is None:
                continue
            access = _access(element.child("interface")) or _access(interface)
            self.add(f"PROPERTY{access} {name}.{accessor} : {type_}", element.line)
            self.interface(element.child("interface"))
            if with_bodies:
                self.body(element, f"PROPERTY {owner}.{name}.{accessor}")
            self.add("END_PROPERTY", element.line)

    def attributes(self, holder: Element | None) -> None:
        """CODESYS's ``Attributes`` block as the ``{attribute ...}`` pragmas it stands for."""
        for data in _add_data(holder):
            if data.attrs.get("name", "").endswith("/attributes"):
                for block in data.all("Attributes"):
                    for attribute in block.all("Attribute"):
                        value = attribute.attrs.get("Value", "")
                        self.add(f"{{attribute '{attribute.attrs.get('Name', '')}'" + (f" := '{value}'" if value else "") + "}",
                                 attribute.line)

    # -- the objects --------------------------------------------------------------------------------------

    def data_type(self, element: Element) -> None:
        name = element.attrs.get("name", "")
        base = element.child("baseType")
        kind = next(iter(base.children), None) if base is not None else None
        if kind is None:
            raise self.fail(element, f"data type {name}: no base type")
        self.attributes(element)
        if any(d.attrs.get("name", "").endswith("/union") for d in _add_data(element)):
            word = "UNION"
        else:
            word = "STRUCT"
        if kind.tag == "struct":
            self.add(f"TYPE {name} :\n{word}", element.line)
            for variable in kind.all("variable"):
                member = variable.attrs.get("name", "")
                line = f"    {member} : {self.type_text(variable.child('type'), f'{name}.{member}')}"
                initial = variable.child("initialValue")
                self.add(line + (f" := {self.value_text(initial)}" if initial is not None else "") + ";", variable.line)
            self.add(f"END_{word}\nEND_TYPE", element.line)
        elif kind.tag == "enum":
            values = kind.child("values")
            items = [(v.attrs.get("name", ""), v.attrs.get("value"), v.line) for v in (values.all("value") if values is not None else [])]
            self.add(f"TYPE {name} :\n(", element.line)
            for index, (item, value, at) in enumerate(items):
                self.add(f"    {item}" + (f" := {value}" if value is not None else "") + ("," if index < len(items) - 1 else ""), at)
            enum_base = kind.child("baseType")
            self.add(f"){' ' + self.type_text(enum_base, name) if enum_base is not None else ''};\nEND_TYPE", element.line)
        else:
            initial = element.child("initialValue")
            self.add(f"TYPE {name} : {self.type_text(base, name)}" + (f" := {self.value_text(initial)}" if initial is not None else "")
                     + ";\nEND_TYPE", element.line)
        self.add("", element.line)

    def pou(self, element: Element) -> None:
        name = element.attrs.get("name", "")
        word = _POU_WORDS.get(element.attrs.get("pouType", ""))
        if word is None:
            raise self.fail(element, f"POU {name}: pouType {element.attrs.get('pouType', '')!r} is not read "
                                     "(program, functionBlock or function)")
        interface = element.child("interface")
        self.attributes(interface)
        header = f"{word} {name}{_inheritance(element)}"
        result = interface.child("returnType") if interface is not None else None
        if word == "FUNCTION" and result is not None:
            header += f" : {self.type_text(result, name)}"
        self.add(header, element.line)
        self.interface(interface)
        self.body(element, f"{word} {name}")
        self.add(f"END_{word}", element.line)
        self.add("", element.line)
        self.members(element, name, True)
        actions = element.child("actions")
        for action in actions.all("action") if actions is not None else ():
            self.add(f"ACTION {action.attrs.get('name', '')}:", action.line)
            self.body(action, f"ACTION {name}.{action.attrs.get('name', '')}")
            self.add("END_ACTION", action.line)

    def interface_object(self, element: Element) -> None:
        name = element.attrs.get("name", "")
        self.add(f"INTERFACE {name}{_inheritance(element)}", element.line)
        self.add("END_INTERFACE", element.line)
        self.add("", element.line)
        self.members(element, name, False)

    def global_list(self, element: Element) -> None:
        name = element.attrs.get("name", "")
        pragmas = _Flat(self.path)
        pragmas.attributes(element)
        # The list is named by a ``// GVL name`` line right above it and its pragmas, as flat ST names one: those
        # lines are given the XML lines just above the list's, so the reader finds them in place.
        for offset, text in enumerate([f"// GVL {name}", *pragmas.lines]):
            self.add(text, element.line - len(pragmas.lines) - 1 + offset)
        self.variables(element, "VAR_GLOBAL")
        self.add("", element.line)


def _add_data(holder: Element | None) -> Iterator[Element]:
    """The ``<data>`` blocks of an element's ``<addData>``."""
    add = holder.child("addData") if holder is not None else None
    yield from add.all("data") if add is not None else ()


def _st_declaration(variable: Element) -> tuple[str, str] | None:
    """(section, ST text) of a variable iecoop's writer declared in ST (``language.PLCOPEN_ST_DECLARATION``)."""
    for data in _add_data(variable):
        if data.attrs.get("name") == PLCOPEN_ST_DECLARATION:
            for declaration in data.all("StDeclaration"):
                section = declaration.attrs.get("section", "")
                if section in _SECTIONS.values() or section in ("VAR_STAT", "VAR_INST"):
                    return section, declaration.text.strip()
    return None


def _access(interface: Element | None) -> str:
    """`` PRIVATE`` (with its space) of CODESYS's ``<AccessModifiers Private="true"/>``, or nothing."""
    for data in _add_data(interface):
        for modifiers in data.all("AccessModifiers"):
            for word in ("Private", "Protected", "Internal", "Public"):
                if modifiers.attrs.get(word) == "true":
                    return f" {word.upper()}"
    return ""


def _inheritance(element: Element) -> str:
    """`` EXTENDS B IMPLEMENTS I, J`` of CODESYS's ``pouinheritance`` block."""
    text = ""
    for data in _add_data(element):
        for inheritance in data.all("Inheritance"):
            extends = [e.text.strip() for e in inheritance.all("Extends") if e.text.strip()]
            implements = [e.text.strip() for e in inheritance.all("Implements") if e.text.strip()]
            text += f" EXTENDS {', '.join(extends)}" if extends else ""
            text += f" IMPLEMENTS {', '.join(implements)}" if implements else ""
    return text


def _global_lists(root: Element) -> Iterator[Element]:
    """The global variable lists: CODESYS's addData ones, and TC6's in a configuration or resource."""
    for data in _add_data(root):
        if data.attrs.get("name", "").endswith(_GLOBALS):
            yield from data.all("globalVars")
    instances = root.child("instances")
    configurations = instances.child("configurations") if instances is not None else None
    for configuration in configurations.all("configuration") if configurations is not None else ():
        yield from configuration.all("globalVars")
        for resource in configuration.all("resource"):
            yield from resource.all("globalVars")


def flatten_plcopen(path: pathlib.Path, xml: Any) -> tuple[str, str, dict[int, tuple[str, int]]]:
    """(flat ST text, the file's name, each text line's (file, XML line)) of a PLCopen XML project; ``xml`` is the
    root element the reader's safe XML parse gives (no DTD, entity or network)."""
    root = project_root(xml, path)
    flat = _Flat(path)
    types = root.child("types")
    data_types = types.child("dataTypes") if types is not None else None
    for element in data_types.all("dataType") if data_types is not None else ():
        flat.data_type(element)
    for data_block in _add_data(root):
        if data_block.attrs.get("name", "").endswith(_INTERFACE):
            for element in data_block.all("Interface"):
                flat.interface_object(element)
    for element in _global_lists(root):
        flat.global_list(element)
    pous = types.child("pous") if types is not None else None
    for element in pous.all("pou") if pous is not None else ():
        flat.pou(element)
    return "\n".join(flat.lines) + "\n", str(path), flat.line_map
