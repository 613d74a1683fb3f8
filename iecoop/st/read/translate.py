"""blark tree -> a readable Python module that uses only iecoop's public API.

Two passes. The first collects every declared name (POUs, data types, GVLs,
their members, methods and properties) into a symbol table, so the second can
resolve ST's case-insensitive names to their declared spelling, type each
expression (``/`` on integers is DIV, ``AND`` on BOOL is ``and``, ``w.3`` is a
bit of a WORD) and order the classes so a class exists before it is used.
Whatever cannot be translated faithfully raises ``StUnsupportedError`` naming
the file, line and construct; nothing is dropped silently.
"""

from __future__ import annotations

import builtins
import dataclasses
import functools
import json
import keyword
import re
import struct
from collections.abc import Callable, Iterator, Sequence
from typing import Any

import blark.transform as tf

from iecoop.exceptions import DefinitionError
from iecoop.st.language import (
    ACCESS_SPECIFIERS, COMPARISONS, ELEMENTARY, INTEGER_LAYOUT, LIFECYCLE, MATH_FUNCTIONS, REAL_TYPES, STANDARD_FBS,
    STRING_FUNCTIONS, SYSTEM_FUNCTIONS, TASK_INFO_MEMBERS, TYPE_SYNONYMS, VAR_INFO_MEMBERS, canonical_type, is_reserved,
)
from iecoop.st.read.parse import StUnsupportedError, Unit

__all__ = ["translate"]

_SECTION_OF = {
    tf.LocatedVariableDeclarations: "VAR",
    tf.VariableDeclarations: "VAR", tf.InputDeclarations: "VAR_INPUT", tf.OutputDeclarations: "VAR_OUTPUT",
    tf.InputOutputDeclarations: "VAR_IN_OUT", tf.StaticDeclarations: "VAR_STAT",
    tf.TemporaryVariableDeclarations: "VAR_TEMP", tf.MethodInstanceVariableDeclarations: "VAR_INST",
    tf.ExternalVariableDeclarations: "VAR_EXTERNAL", tf.FunctionVariableDeclarations: "VAR",
}


# --- names -------------------------------------------------------------------------------------

#: The suffix and prefix of the naming rule (see ``python_name``).
NAME_SUFFIX = "_"
NAME_PREFIX = "st"
#: Names the generated code itself writes beside the user's: ``self``, a block's ``body``, FB_init's
#: PEP 8 inputs, a pointer's ``deref``, the modules it imports.
_GENERATED_NAMES = frozenset(("self", "cls", "body", "fb_init", "fb_reinit", "fb_exit", "init_retains", "in_copy_code",
                              "deref", "typed", "math", "copy", "typing", "iecoop", "Annotated", "TypeVar"))


@functools.cache
def reserved_names(attribute: bool = False) -> frozenset[str]:
    """Every Python name an ST name must not become: keywords, builtins and what the generated module uses.

    A name Python code reads bare (a POU, type, GVL or FUNCTION; a METHOD's or FUNCTION's input, output
    or local) must be none of Python's keywords and soft keywords, its builtins, the names the generated
    module may import (``iecoop``, ``iecoop.stdlib``, ``.functions``, ``.conversions``, ``.runtime``,
    ``iecoop.st.external``), the public attributes of iecoop's base classes and ``_GENERATED_NAMES``. A name read
    as an attribute (``self.x``: a variable of a block, STRUCT or GVL, a METHOD, PROPERTY or enumeration
    value) stands bare only in its class body, beside the section specifiers, types and literals
    of ``iecoop`` and ``iecoop.stdlib``: with ``attribute``, the builtins and the other modules stay
    free (a METHOD ``open``, a constant ``LIMIT``). Compared with case, as Python compares names:
    ``T`` is reserved (``T#5S``), ``t`` is not.
    """
    import iecoop
    import iecoop.conversions
    import iecoop.functions
    import iecoop.runtime
    import iecoop.stdlib

    names = {*keyword.kwlist, *_GENERATED_NAMES, *iecoop.__all__, *iecoop.stdlib.__all__}
    for base in (iecoop.FunctionBlock, iecoop.Program, iecoop.Struct, iecoop.Union, iecoop.GlobalVariables,
                 iecoop.Interface, iecoop.IecEnum):
        names.update(n for n in dir(base) if not n.startswith("_"))
    if not attribute:
        names.update(keyword.softkwlist, dir(builtins))
        for module in (iecoop.functions, iecoop.conversions, iecoop.runtime):
            names.update(module.__all__)
        names.add("external")  # iecoop.st's decorator of a FUNCTION without a body
    return frozenset(n for n in names if not n.startswith("_"))


_PREFIXED = re.compile(f"(?:{NAME_PREFIX})*_", re.IGNORECASE)


def python_name(name: str, attribute: bool = False) -> str:
    """The Python name of the ST name ``name``: itself, unless it could meet a Python or iecoop name.

    A name that is reserved (``reserved_names(attribute)``: ``attribute`` for a name only read as
    ``x.name``), or starts or ends with ``_``, gets ``_`` at its end,
    so it can be no keyword, builtin or generated name, and no other ST name's Python name (only these
    end with ``_``). If it starts with ``_`` (after any number of ``st``), it also gets ``st`` in front,
    so no ST name becomes a Python private (``_x``) or special (``__x__``) name. ``in`` is ``in_``,
    ``in_`` is ``in__``, ``_x`` is ``st_x_``, ``__del__`` is ``st__del___``; ``Speed`` is ``Speed``.

    One exception keeps the writer's names: ``TO_`` (how ``st.export`` writes a Python name that is an ST
    keyword) is ``TO`` again, since no ST name can be ``TO`` and no other name's image lacks the suffix.
    """
    stem = _keyword_stem(name, attribute)
    if stem is not None:
        return stem
    if name not in reserved_names(attribute) and not name.startswith("_") and not name.endswith("_"):
        return name
    return (NAME_PREFIX if _PREFIXED.match(name) else "") + name + NAME_SUFFIX


def _keyword_stem(name: str, attribute: bool) -> str | None:
    """``TO`` for ``TO_``: an ST keyword with one suffix, when the keyword itself is free in Python."""
    stem = name[: -len(NAME_SUFFIX)]
    if not name.endswith(NAME_SUFFIX) or not is_reserved(stem) or stem.endswith(NAME_SUFFIX) or stem.startswith("_"):
        return None
    return stem if stem not in reserved_names(attribute) else None


def st_name_of(python: str) -> str:
    """The ST name whose Python name is ``python``: the inverse of ``python_name`` (only mapped names end with ``_``).

    ``in_`` is ``in``, ``st_x_`` is ``_x``, ``TO`` is ``TO_``, ``Speed`` is ``Speed``.
    """
    if not python.endswith(NAME_SUFFIX):
        return python + NAME_SUFFIX if is_reserved(python) else python
    name = python[: -len(NAME_SUFFIX)]
    if name[: len(NAME_PREFIX)].lower() == NAME_PREFIX and _PREFIXED.match(name, len(NAME_PREFIX)):
        return name[len(NAME_PREFIX):]
    return name


# --- types --------------------------------------------------------------------------------------


@dataclasses.dataclass
class TypeRef:
    """A resolved ST type: elementary, STRING(n), ARRAY, POINTER TO, REFERENCE TO or a user type."""

    kind: str  # elem | string | array | pointer | reference | user | interface_null
    name: str
    of: TypeRef | None = None
    length: str | None = None
    bounds: list[tuple[str, str]] | None = None
    #: a subrange ``INT(0..100)``: its lower and upper limits (Python text)
    limits: tuple[str, str] | None = None

    def annotation(self) -> str:
        if self.kind == "array":
            assert self.of is not None
            return f"ARRAY[{self.of.annotation()}]"
        if self.kind == "pointer":
            assert self.of is not None
            return f"POINTER_TO[{self.of.annotation()}]"
        if self.kind == "reference":
            assert self.of is not None
            return f"REFERENCE_TO[{self.of.annotation()}]"
        return self.name

    @property
    def is_int(self) -> bool:
        return self.kind == "elem" and self.name in INTEGER_LAYOUT

    @property
    def is_real(self) -> bool:
        return self.kind == "elem" and self.name in REAL_TYPES

    @property
    def is_bool(self) -> bool:
        return self.kind == "elem" and self.name == "BOOL"

    @property
    def is_string(self) -> bool:
        return self.kind == "string"

    def deref(self) -> TypeRef:
        return self.of if self.kind == "reference" and self.of is not None else self


BOOL = TypeRef("elem", "BOOL")
LINT = TypeRef("elem", "LINT")
LREAL = TypeRef("elem", "LREAL")
STRING = TypeRef("string", "STRING", length="80")


@dataclasses.dataclass
class Member:
    """A variable: ``name`` is its Python code (``python_name`` of the ST name, or how it is reached), ``st`` its ST name."""

    name: str
    type: TypeRef | None
    section: str
    st: str = ""

    def __post_init__(self) -> None:
        self.st = self.st or self.name


class ReferenceLocal(Member):
    """An elementary ``REFERENCE TO`` local of a METHOD or FUNCTION: a pointer, read and written as an in-out."""


@dataclasses.dataclass
class Callable_:
    name: str
    returns: TypeRef | None
    params: list[Member]
    st: str = ""

    def __post_init__(self) -> None:
        self.st = self.st or self.name


@dataclasses.dataclass
class Decl:
    """Everything the second pass needs to know about one declared name."""

    kind: str  # fb program function interface struct union enum alias gvl stdfb
    #: the Python name (``python_name`` of the ST name); ``st`` is the ST name
    name: str
    node: Any = None
    unit: Unit | None = None
    bases: list[str] = dataclasses.field(default_factory=list)
    members: dict[str, Member] = dataclasses.field(default_factory=dict)
    methods: dict[str, Callable_] = dataclasses.field(default_factory=dict)
    props: dict[str, Member] = dataclasses.field(default_factory=dict)
    method_nodes: list[Any] = dataclasses.field(default_factory=list)
    action_nodes: list[Any] = dataclasses.field(default_factory=list)
    prop_nodes: list[Any] = dataclasses.field(default_factory=list)
    values: list[str] = dataclasses.field(default_factory=list)
    alias_of: TypeRef | None = None
    implements: list[str] = dataclasses.field(default_factory=list)
    #: the top-level item of the source it comes from (its lines hold its comments)
    item: Any = None
    #: for a GVL gathered from several sources: the unit of each VAR_GLOBAL block
    units: dict[int, Unit] = dataclasses.field(default_factory=dict)
    st: str = ""
    #: ST name (lower case) -> where it is declared ("file:line"), for the duplicate check
    declared: dict[str, tuple[str, str]] = dataclasses.field(default_factory=dict)

    def __post_init__(self) -> None:
        self.st = self.st or self.name


#: ``__SYSTEM.IQueryInterface``, the interface TwinCAT and CODESYS give ``__QUERYINTERFACE``: iecoop's
#: IQueryInterface, a type wherever a type may stand (its Python name is the key)
IQUERYINTERFACE = Decl("interface", "IQueryInterface")
SYSTEM_DECLS = {IQUERYINTERFACE.name.lower(): IQUERYINTERFACE}


@dataclasses.dataclass
class Ex:
    """A translated expression: Python code, its ST type (None when unknown), whether it needs parentheses."""

    code: str
    type: TypeRef | None = None
    compound: bool = False
    #: Python precedence of the outermost operator (see PRECEDENCE); 0 for other compound code
    prec: int = 100
    #: ``super().Prop`` as the target of an assignment: written with super_set
    super_property: bool = False

    def __post_init__(self) -> None:
        if self.compound and self.prec == 100:
            self.prec = 0

    def p(self) -> str:
        return f"({self.code})" if self.compound else self.code

    def wrap(self, needed: int) -> str:
        """The code as an operand of an operator of precedence ``needed``: in parentheses only when it binds looser."""
        return f"({self.code})" if self.prec < needed else self.code


#: Python operator precedence, loosest first, for the operators the translation writes.
PRECEDENCE = {"or": 1, "and": 2, "not": 3, "compare": 4, "|": 5, "^": 6, "&": 7, "shift": 8, "+": 9, "-": 9,
              "*": 10, "/": 10, "unary": 11, "**": 12}


class Scope:
    """Name resolution inside one POU body, method, property accessor or function."""

    def __init__(self, owner: Decl | None, kind: str, return_name: str | None = None) -> None:
        self.owner = owner
        self.kind = kind  # body | method | function | getter | setter
        self.locals: dict[str, Member] = {}
        self.return_name = return_name
        #: the ST name of the result variable (the METHOD's, FUNCTION's or PROPERTY's): how the body names it
        self.return_st = return_name
        self.counter = 0
        #: ``x.deref = value`` for each VAR_OUTPUT with an initial value (a METHOD / FUNCTION)
        self.output_inits: list[str] = []
        #: ``FB_X.Method`` or ``F_Name`` for a METHOD or FUNCTION: names its helper classes
        self.pou = ""
        #: the ARRAY and structured inputs passed by value, with their initialisers: copied at the call
        self.by_value: list[tuple[Member, Any]] = []
        #: whether the top statement list (the only one that may hold labels) is being written
        self.started = False
        #: JMP targets of the body (lower case) and the variable that names the part to run next
        self.labels: set[str] = set()
        self.jump = ""
        #: elementary locals given to a call as an output (=>) or in-out: they live in the holder STRUCT, which has addresses
        self.addressed: set[str] = set()

    def temp(self, stem: str) -> str:
        self.counter += 1
        return f"_{stem}{self.counter}"


# --- the translator -----------------------------------------------------------------------------


class Translator:
    def __init__(self, units: Sequence[Unit], externals: Sequence[str] = ()) -> None:
        self.units = units
        #: ST name (lower case) -> declaration; ``by_python``: the same by Python name (a TypeRef's name)
        self.decls: dict[str, Decl] = {}
        self.by_python: dict[str, Decl] = {}
        #: top-level ST names (lower case) -> what and where they are declared, for the duplicate check
        self.declared: dict[str, tuple[str, str]] = {}
        self.enum_values: dict[str, tuple[str, str]] = {}
        self.globals: dict[str, tuple[str, Member]] = {}
        self.externals = {name.lower() for name in externals}
        self.imports: dict[str, set[str]] = {}
        self.out: list[str] = []
        self.unit: Unit | None = None
        self.line: int | None = None
        self.window: tuple[int, int] = (0, 0)
        self.used_comments: set[int] = set()
        self.pending_references: list[Any] = []
        #: id of a PROPERTY node -> "get" / "set", for accessors marked by a ``// Get`` / ``// Set`` line
        self.marked_accessors: dict[int, str] = {}
        #: PROGRAMs whose variables another POU reads or writes (P_Count.counter)
        self.named_programs: set[str] = set()
        self._stdlib_decls()

    # --- errors and imports ---

    def fail(self, construct: str, node: Any = None) -> StUnsupportedError:
        line = getattr(getattr(node, "meta", None), "line", None) or self.line
        where = self.unit.where(line) if self.unit is not None else "<st>"
        return StUnsupportedError(f"{where}: {construct}")

    def need(self, module: str, *names: str) -> None:
        self.imports.setdefault(module, set()).update(names)

    # --- pass 1: the symbol table ---

    def _stdlib_decls(self) -> None:
        import iecoop.stdlib as stdlib

        for name in STANDARD_FBS:
            cls = getattr(stdlib, name)
            decl = Decl("stdfb", name)
            for record in cls._iec_layout_.fields:
                decl.members[record.name.lower()] = Member(record.name, self._elem_or_none(record.info.name), record.section)
            self.decls[name.lower()] = self.by_python[name] = decl

    def _elem_or_none(self, name: str) -> TypeRef | None:
        name = canonical_type(name)
        if name in ELEMENTARY:
            return TypeRef("string", name, length="80") if name in ("STRING", "WSTRING") else TypeRef("elem", name)
        return None

    def collect(self) -> None:
        for unit in self.units:
            self.unit = unit
            current: Decl | None = None
            for item in unit.tree.items:
                self.line = item.meta.line if item.meta else None
                if isinstance(item, (tf.Method, tf.Property)):
                    if current is None or current.kind not in ("fb", "interface", "program"):
                        raise self.fail(f"{type(item).__name__.upper()} {item.name} does not follow a FUNCTION_BLOCK or INTERFACE", item)
                    (current.method_nodes if isinstance(item, tf.Method) else current.prop_nodes).append(item)
                    if isinstance(item, tf.Property):
                        self._mark_accessor(unit, item)
                    continue
                if isinstance(item, tf.Action):
                    if current is None or current.kind not in ("fb", "program"):
                        raise self.fail(f"ACTION {item.name} does not follow a FUNCTION_BLOCK or PROGRAM", item)
                    current.action_nodes.append(item)
                    continue
                current = self._collect_item(unit, item)
                if current is not None:
                    current.item = item

    def _mark_accessor(self, unit: Unit, node: Any) -> None:
        """Note a PROPERTY block marked by a ``// Get`` or ``// Set`` comment on the line before it.

        Besides ``Name.Get`` / ``Name.Set``, the plain-text form iecoop's ST writer uses
        (``iecoop.st.dump``) for a property with both accessors: two blocks of the same name.
        """
        line = getattr(node.meta, "line", None) if node.meta else None
        for token in unit.comments:
            if line is not None and token.line == line - 1:
                marker = str(token).strip()[2:].strip().lower() if str(token).strip().startswith("//") else ""
                if marker in ("get", "set"):
                    self.marked_accessors[id(node)] = marker
                    self.used_comments.add(id(token))  # a mark, not a comment to carry over

    def _marked_list_name(self, unit: Unit, node: Any) -> str | None:
        """The name of a VAR_GLOBAL block marked by a ``// GVL <name>`` line above it (and its pragmas), as dump writes it."""
        line = getattr(node.meta, "line", None) if node.meta else None
        if line is None:
            return None
        above = [t for t in unit.comments if t.line < line]
        # The mark is on the line right above the block or above the pragmas ({attribute ...}) heading it.
        expected = line - 1
        for token in sorted(above, key=lambda t: -t.line):
            text = str(token).strip()
            if token.line != expected:
                return None
            if text.startswith("{"):
                expected -= 1
                continue
            words = text[2:].split() if text.startswith("//") else []
            if len(words) == 2 and words[0] == "GVL" and words[1].isidentifier():
                self.used_comments.add(id(token))  # a mark, not a comment to carry over
                return words[1]
            return None
        return None

    def declare(self, registry: dict[str, tuple[str, str]], what: str, name: str, node: Any = None) -> None:
        """Note that ``what name`` is declared here; DefinitionError naming both if ``registry`` has it already."""
        line = getattr(getattr(node, "meta", None), "line", None) or self.line
        where = self.unit.where(line) if self.unit is not None else "<st>"
        first = registry.get(name.lower())
        if first is not None:
            raise DefinitionError(f"{where}: {what} is declared twice: as {first[0]} at {first[1]} and as {what} at {where} "
                                  "(ST names are case-insensitive)")
        registry[name.lower()] = (what, where)

    def _add(self, decl: Decl) -> Decl:
        keyword = {"fb": "FUNCTION_BLOCK", "gvl": "GVL", "alias": "TYPE"}.get(decl.kind, decl.kind.upper())
        self.declare(self.declared, f"{keyword} {decl.st}", decl.st, decl.node if decl.kind != "gvl" else decl.node[0])
        decl.name = python_name(decl.st)
        self.decls[decl.st.lower()] = self.by_python[decl.name] = decl
        return decl

    def _collect_item(self, unit: Unit, item: Any) -> Decl | None:
        if isinstance(item, tf.FunctionBlock):
            decl = self._add(Decl("fb", str(item.name), item, unit))
            if item.extends:
                decl.bases.append(str(item.extends.interfaces[0]))
            decl.implements = [str(i) for i in item.implements.interfaces] if item.implements else []
            return decl
        if isinstance(item, tf.Program):
            return self._add(Decl("program", str(item.name), item, unit))
        if isinstance(item, tf.Function):
            return self._add(Decl("function", str(item.name), item, unit))
        if isinstance(item, tf.Interface):
            decl = self._add(Decl("interface", str(item.name), item, unit))
            if item.extends:
                decl.bases.extend(str(i) for i in item.extends.interfaces)
            return decl
        if isinstance(item, tf.GlobalVariableDeclarations):
            name = str(item.name or "")
            if not name.isidentifier():
                stem = unit.filename.replace("\\", "/").rsplit("/", 1)[-1].split(".")[0]
                name = self._marked_list_name(unit, item) or (stem if stem.isidentifier() else "GVL")
            existing = self.decls.get(str(name).lower())
            if existing is not None and existing.kind == "gvl":
                existing.node.append(item)  # a list gathered from several sources (TwinCAT: one per file)
                existing.units[id(item)] = unit
                return None
            decl = self._add(Decl("gvl", str(name), [item], unit))
            decl.units[id(item)] = unit
            return None
        if isinstance(item, tf.DataTypeDeclaration):
            inner = item.declaration
            if isinstance(inner, tf.StructureTypeDeclaration):
                decl = self._add(Decl("struct", str(inner.name), inner, unit))
                if inner.extends:
                    decl.bases.append(str(inner.extends.interfaces[0]))
            elif isinstance(inner, tf.UnionTypeDeclaration):
                decl = self._add(Decl("union", str(inner.name), inner, unit))
            elif isinstance(inner, tf.EnumeratedTypeDeclaration):
                decl = self._add(Decl("enum", str(inner.name), inner, unit))
                for value in inner.init.spec.values or []:
                    self.declare(decl.declared, f"enumeration value {decl.st}.{value.name}", str(value.name), value)
                    decl.values.append(str(value.name))
                    self.enum_values.setdefault(str(value.name).lower(), (decl.name, python_name(str(value.name), attribute=True)))
            elif isinstance(inner, (tf.SimpleTypeDeclaration, tf.StringTypeDeclaration, tf.ArrayTypeDeclaration,
                                    tf.SubrangeTypeDeclaration)):
                decl = self._add(Decl("alias", str(inner.name), inner, unit))
            else:
                raise self.fail(f"TYPE {type(inner).__name__} is not supported", item)
            decl.item = item
            return None
        raise self.fail(f"{type(item).__name__} at the top level is not supported", item)

    def resolve_members(self) -> None:
        """Second half of pass 1: member types, once every type name is known."""
        for decl in list(self.decls.values()):
            self.unit = decl.unit
            if decl.kind in ("fb", "program", "function"):
                for block in decl.node.declarations:
                    for member in self._block_members(block, attribute=decl.kind != "function"):
                        self._add_member(decl, member)
            elif decl.kind in ("struct", "union"):
                for element in decl.node.declarations:
                    for member in self._element_members(element, decl.kind):
                        self._add_member(decl, member)
            elif decl.kind == "gvl":
                for block in decl.node:
                    self.unit = decl.units.get(id(block), decl.unit)
                    for member in self._block_members(block, attribute=True):
                        self._add_member(decl, member)
                        self.globals[member.st.lower()] = (decl.name, member)
            elif decl.kind == "alias":
                decl.alias_of = self._alias_target(decl.node)
            self.unit = decl.unit
            for node in decl.method_nodes:
                name = str(node.name)
                self.declare(decl.declared, f"METHOD {decl.st}.{name}", name, node)
                local: dict[str, tuple[str, str]] = {}
                members = []
                for block in node.declarations:
                    for member in self._block_members(block):
                        self.declare(local, f"{member.section} {member.st} of METHOD {decl.st}.{name}", member.st)
                        members.append(member)
                returns = self._spec_type(node.return_type.spec, node) if node.return_type is not None else None
                decl.methods[name.lower()] = Callable_(python_name(name, attribute=True), returns, _signature(members), st=name)
            for node in decl.action_nodes:  # an ACTION is called as a method without inputs or result
                name = str(node.name).rsplit(".", 1)[-1]
                self.declare(decl.declared, f"ACTION {decl.st}.{name}", name, node)
                decl.methods[name.lower()] = Callable_(python_name(name, attribute=True), None, [], st=name)
            for node in decl.prop_nodes:
                name = str(node.name).split(".")[0]
                if name.lower() not in decl.props:  # its Get and its Set accessor: one PROPERTY
                    self.declare(decl.declared, f"PROPERTY {decl.st}.{name}", name, node)
                type_ = self._spec_type(node.return_type.spec, node)
                decl.props[name.lower()] = Member(python_name(name, attribute=True), type_, "PROPERTY", st=name)
            if decl.kind == "function":
                returns = self._spec_type(decl.node.return_type, decl.node) if decl.node.return_type else None
                params = _signature(list(decl.members.values()))
                decl.methods["()"] = Callable_(decl.name, returns, params, st=decl.st)

    def _add_member(self, decl: Decl, member: Member) -> None:
        """A variable of ``decl``, refused if ``decl`` declares its name already (its line is ``self.line``)."""
        self.declare(decl.declared, f"{member.section} {decl.st}.{member.st}", member.st)
        decl.members[member.st.lower()] = member

    def _alias_target(self, node: Any) -> TypeRef:
        if isinstance(node, tf.SimpleTypeDeclaration):
            return self._spec_type(node.init.spec, node)
        if isinstance(node, tf.StringTypeDeclaration):
            return self._string_type(node.string_type)
        if isinstance(node, tf.SubrangeTypeDeclaration):
            return self.init_type(node.init, node)
        return self._array_type(node.init.spec, None, node)

    # --- types from blark nodes ---

    def type_named(self, name: str, node: Any) -> TypeRef:
        elem = self._elem_or_none(name)
        if elem is not None:
            return elem
        if name.upper() == "__SYSTEM.EXCEPTIONCODE":
            return TypeRef("elem", "UDINT")  # the enum's base type; compares equal to ExceptionCode members
        if name.upper() == "__SYSTEM.VAR_INFO":
            return TypeRef("varinfo", "VarInfo")  # what __VARINFO(x) gives: a local of a METHOD or FUNCTION
        if name.upper() == "__SYSTEM.IQUERYINTERFACE":
            return TypeRef("user", IQUERYINTERFACE.name)
        decl = self.decls.get(name.lower())
        if decl is None:
            raise self.fail(f"unknown type {name!r}", node)
        return TypeRef("user", decl.name)

    def _string_type(self, spec: Any) -> TypeRef:
        kind = str(spec.type_name).upper()
        length = "80"
        if spec.length is not None:
            length = self.const_expr(spec.length.length)
        return TypeRef("string", kind, length=length)

    def _indirect(self, target: TypeRef, indirection: Any) -> TypeRef:
        if indirection is None:
            return target
        if indirection.reference:
            return TypeRef("reference", "REFERENCE_TO", of=target)
        for _ in range(indirection.pointer_depth):
            target = TypeRef("pointer", "POINTER_TO", of=target)
        return target

    def _spec_type(self, spec: Any, node: Any) -> TypeRef:
        if isinstance(spec, tf.SimpleSpecification):
            if isinstance(spec.type, tf.StringTypeSpecification):
                return self._string_type(spec.type)
            return self.type_named(str(spec.type), node)
        if isinstance(spec, tf.IndirectSimpleSpecification):
            return self._indirect(self._spec_type(spec.type, node), spec.indirection)
        if isinstance(spec, tf.StringTypeSpecification):
            return self._string_type(spec)
        if isinstance(spec, tf.DataType):
            if isinstance(spec.type_name, tf.StringTypeSpecification):
                inner = self._string_type(spec.type_name)
            else:
                inner = self.type_named(str(spec.type_name), node)
            return self._indirect(inner, spec.indirection)
        if isinstance(spec, tf.ArraySpecification):
            return self._array_type(spec, None, node)
        if isinstance(spec, lark_token_type()):
            return self.type_named(str(spec), node)
        raise self.fail(f"type specification {type(spec).__name__} is not supported", node)

    def _array_type(self, spec: Any, indirection: Any, node: Any) -> TypeRef:
        bounds = []
        for sub in spec.subranges:
            if not isinstance(sub, tf.PartialSubrange):
                raise self.fail("ARRAY[*] (variable length) is not supported", node)
            bounds.append((self.const_expr(sub.start), self.const_expr(sub.stop)))
        element_spec = spec.type
        if isinstance(element_spec, tf.ArraySpecification):
            element = self._array_type(element_spec, None, node)
        else:
            element = self._spec_type(element_spec, node)
        return self._indirect(TypeRef("array", "ARRAY", of=element, bounds=bounds), indirection)

    def const_expr(self, node: Any) -> str:
        """A constant expression (ARRAY bounds, STRING length) as Python text."""
        if isinstance(node, (tf.ParenthesizedExpression, tf.BracketedExpression)):
            node = node.expr if isinstance(node, tf.ParenthesizedExpression) else node.expression
        scope = Scope(None, "const")
        return self.expr(node, scope).code

    def init_type(self, init: Any, node: Any) -> TypeRef:
        if isinstance(init, tf.ArrayTypeInitialization):
            return self._array_type(init.spec, init.indirection, node)
        if isinstance(init, tf.StringTypeInitialization):
            return self._string_type(init.spec)
        if isinstance(init, tf.TypeInitialization):
            return self._spec_type(init.spec, node)
        if isinstance(init, tf.InitializedStructure):
            return self.type_named(str(init.name), node)
        if isinstance(init, tf.EnumeratedTypeInitialization):
            if init.spec.values:
                raise self.fail("an inline enumeration in a declaration is not supported (declare a TYPE)", node)
            return self.type_named(str(init.spec.type_name), node)
        if isinstance(init, tf.SubrangeTypeInitialization):
            if init.indirection is not None or not isinstance(init.spec.subrange, tf.PartialSubrange):
                raise self.fail("a subrange type needs both limits and no POINTER TO / REFERENCE TO", node)
            base = self.type_named(str(init.spec.type_name), node)
            if not base.is_int:
                raise self.fail(f"a subrange of {base.name} (subranges are of integer types)", node)
            limits = tuple(str(eval(self.const_expr(n), {})) for n in (init.spec.subrange.start, init.spec.subrange.stop))
            return TypeRef("elem", base.name, limits=(limits[0], limits[1]))
        raise self.fail(f"declaration {type(init).__name__} is not supported", node)

    def _block_members(self, block: Any, attribute: bool = False) -> Iterator[Member]:
        """The variables of one VAR block; ``attribute``: of a block or GVL (fields), not of a METHOD or FUNCTION."""
        section = _SECTION_OF.get(type(block))
        if isinstance(block, tf.GlobalVariableDeclarations):
            section = "VAR_GLOBAL"
        if isinstance(block, tf.LocatedVariableDeclarations):
            section = "VAR"
        if section is None:
            raise self.fail(f"{type(block).__name__} is not supported", block)
        for item in block.items:
            self.line = item.meta.line if item.meta else self.line
            for name, type_ in self._item_types(item):
                yield Member(python_name(name, attribute), type_, section, st=name)

    def location(self, item: Any) -> str:
        """``AT %IX0.0`` / ``AT %I*`` of a located declaration, or ""."""
        if isinstance(item, tf.LocatedVariableDeclaration):
            return str(item.location)
        spec = getattr(item, "spec", None)
        if isinstance(spec, tf.GlobalVariableSpec) and spec.location is not None:
            return str(spec.location)
        located = [str(var.location) for var in getattr(item, "variables", []) if getattr(var, "location", None) is not None]
        return located[0] if located else ""

    def located_section(self, item: Any, section: str) -> str:
        """iecoop has no process image: a located variable is an ordinary one. An input (``%I``) of a block's
        VAR is a VAR_INPUT, so a test or a simulation can write it as the I/O update would (fields only: a
        METHOD's or FUNCTION's inputs stay the ones it declares)."""
        return "VAR_INPUT" if section == "VAR" and "%I" in self.location(item).upper() else section

    def _item_types(self, item: Any) -> Iterator[tuple[str, TypeRef | None]]:
        if isinstance(item, tf.ExternalVariableDeclaration):
            yield str(item.name), self._spec_type(item.spec, item)
            return
        if isinstance(item, tf.GlobalVariableDeclaration):
            init = item.init
            if isinstance(init, tf.FunctionCall):
                type_ = self.type_named(str(init.name.name), item)
            else:
                type_ = self.init_type(init, item)
            for name in item.spec.variables:
                yield str(name), type_
            return
        if isinstance(item, tf.FunctionBlockNameDeclaration):
            type_ = self.type_named(str(item.spec), item)
            for name in item.variables:
                yield str(name), type_
            return
        if isinstance(item, tf.FunctionBlockInvocationDeclaration):
            type_ = self.type_named(str(item.init.name.name), item)
            for name in item.variables:
                yield str(name), type_
            return
        if isinstance(item, tf.EdgeDeclaration):
            raise self.fail("R_EDGE / F_EDGE inputs are not supported (use R_TRIG / F_TRIG)", item)
        if isinstance(item, tf.LocatedVariableDeclaration):
            if item.name is None:
                raise self.fail(f"a located variable without a name ({item.location}) is not supported: name it", item)
            yield str(item.name.name), self.init_type(item.init, item)
            return
        init = getattr(item, "init", None)
        type_ = self.init_type(init, item)
        for var in item.variables:
            yield str(var.variable.name), type_

    def _element_members(self, element: Any, kind: str) -> Iterator[Member]:
        self.line = element.meta.line if element.meta else self.line
        if isinstance(element, tf.UnionElementDeclaration):
            yield Member(python_name(str(element.name), attribute=True), self._spec_type(element.spec, element), "VAR", st=str(element.name))
            return
        init = element.init
        if isinstance(init, tf.FunctionCall):
            type_ = self.type_named(str(init.name.name), element)
        else:
            type_ = self.init_type(init, element)
        for var in element.variables:
            yield Member(python_name(str(var.variable.name), attribute=True), type_, "VAR", st=str(var.variable.name))

    # --- lookups ---

    def decl_of(self, type_: TypeRef | None) -> Decl | None:
        if type_ is None:
            return None
        type_ = type_.deref()
        if type_.kind != "user":
            return None
        decl = self.by_python.get(type_.name) or SYSTEM_DECLS.get(type_.name.lower())
        while decl is not None and decl.kind == "alias" and decl.alias_of is not None and decl.alias_of.kind == "user":
            decl = self.by_python.get(decl.alias_of.name)
        return decl

    def lineage(self, decl: Decl) -> Iterator[Decl]:
        seen = set()
        pending = [decl]
        while pending:
            current = pending.pop(0)
            if current.name in seen:
                continue
            seen.add(current.name)
            yield current
            for base in current.bases:
                if base.upper() == "__SYSTEM.IQUERYINTERFACE":
                    continue
                found = self.decls.get(base.lower())
                if found is not None:
                    pending.append(found)

    def find_member(self, decl: Decl, name: str) -> tuple[str, Member | Callable_] | None:
        key = name.lower()
        for current in self.lineage(decl):
            if key in current.members:
                return "member", current.members[key]
            if key in current.props:
                return "prop", current.props[key]
            if key in current.methods:
                return "method", current.methods[key]
        return None

    # --- pass 2: emission ---

    def emit(self, text: str, level: int) -> None:
        self.out.append("    " * level + text if text else "")

    def emit_def(self, text: str, level: int) -> None:
        """A ``def`` line; one parameter per line when it would be longer than 110 characters."""
        if len(text) + 4 * level <= 110:
            self.emit(text, level)
            return
        head, rest = text.split("(", 1)
        inner, tail = rest.rsplit(") ->", 1)
        params, depth, start = [], 0, 0
        for index, char in enumerate(inner):
            depth += char in "([{"
            depth -= char in ")]}"
            if char == "," and depth == 0:
                params.append(inner[start:index].strip())
                start = index + 1
        params.append(inner[start:].strip())
        self.emit(f"{head}(", level)
        for param in params:
            self.emit(f"{param},", level + 1)
        self.emit(f") ->{tail}", level)

    def enter(self, node: Any) -> None:
        """Comments are taken from the source lines of the top-level item ``node`` from now on."""
        unit = self.unit
        line = getattr(getattr(node, "meta", None), "line", None)
        self.window = (0, 0)
        if unit is None or line is None:
            return
        previous_end = 0
        for item in unit.tree.items:
            meta = getattr(item, "meta", None)
            if item is node:
                self.window = (previous_end + 1, getattr(meta, "end_line", None) or line)
                return
            end = getattr(meta, "end_line", None)
            if end is not None and end < line:
                previous_end = max(previous_end, end)

    def comments(self, node: Any, level: int, inline: bool = False) -> str:
        """Emit the comments before ``node``; with ``inline``, return the one on its line, for the end of that line.

        Comments are placed by their line in the source (blark attaches some of them to a later
        statement), each once, within the lines of the item being written.
        """
        meta = getattr(node, "meta", None)
        line = getattr(meta, "line", None)
        trailing = ""
        if line is None or self.unit is None:
            return ""
        low, high = self.window
        tokens = [
            t for t in self.unit.comments
            if low <= t.line <= min(line, high) and id(t) not in self.used_comments
        ]
        for token in tokens:
            text = str(token).strip()
            self.used_comments.add(id(token))
            if text.startswith("{"):
                continue  # pragmas are read where they matter (call_after_init)
            if text.startswith("//"):
                body = [text[2:].strip()]
            else:
                body = [part.strip() for part in text[2:-2].strip().splitlines()]
            if inline and line is not None and getattr(token, "line", None) == line and len(body) == 1:
                trailing = body[0]
                continue
            for part in body:
                self.emit(f"# {part}".rstrip(), level)
        return trailing

    def trail(self, index: int, comment: str) -> None:
        """Put ``comment`` at the end of the line at ``index`` (an ST end-of-line comment)."""
        if comment and index < len(self.out):
            self.out[index] += f"  # {comment}"

    def pragmas(self, node: Any) -> list[str]:
        """The pragmas (``{attribute 'x'}``) written before ``node``, within the current item's lines."""
        line = getattr(getattr(node, "meta", None), "line", None)
        if line is None or self.unit is None:
            return []
        low = self.window[0]
        return [str(t).strip() for t in self.unit.comments if low <= t.line <= line and str(t).strip().startswith("{")]

    def ordered(self) -> list[Decl]:
        """User declarations, each after the ones it needs at class creation."""
        order: list[Decl] = []
        state: dict[str, int] = {}

        def needs(decl: Decl) -> Iterator[Decl | None]:
            yield from (self.decls.get(b.lower()) for b in decl.bases)
            yield from (self.decls.get(i.lower()) for i in decl.implements)
            members = [m.type for m in decl.members.values()]
            members += [p.type for p in decl.props.values()] + [m.returns for m in decl.methods.values()]
            members += [p.type for m in decl.methods.values() for p in m.params]
            # a method's ARRAY and VAR_STAT locals live in classes made before the block's
            members += [m.type for node in decl.method_nodes for block in node.declarations
                        if isinstance(block, (tf.VariableDeclarations, tf.StaticDeclarations)) for m in self._block_members(block)]
            for type_ in members:
                while type_ is not None and type_.kind in ("array", "pointer", "reference"):
                    type_ = type_.of
                if type_ is not None and type_.kind == "user":
                    yield self.by_python.get(type_.name)
            if decl.alias_of is not None and decl.alias_of.kind == "user":
                yield self.by_python.get(decl.alias_of.name)
            for member in decl.members.values():  # a VAR_EXTERNAL binds to its global when the class is made
                if member.section == "VAR_EXTERNAL" and member.st.lower() in self.globals:
                    yield self.by_python.get(self.globals[member.st.lower()][0])

        def visit(decl: Decl) -> None:
            key = decl.name
            if state.get(key) == 2 or decl.kind == "stdfb":
                return
            if state.get(key) == 1:
                return  # a cycle through a pointer or interface: annotations are strings, order does not matter
            state[key] = 1
            for dep in needs(decl):
                if dep is not None and dep is not decl:
                    visit(dep)
            state[key] = 2
            order.append(decl)

        for decl in self.decls.values():
            visit(decl)
        return order

    def translate(self) -> str:
        self.collect()
        self.resolve_members()
        body: list[str] = []
        for decl in self.ordered():
            self.unit = decl.unit
            self.out = []
            self.preamble: list[str] = []
            self.enter(decl.item)
            getattr(self, f"_emit_{decl.kind}")(decl)
            body.extend(self.preamble + ["", ""] + self.out)
        if self.named_programs:
            # P_Count.counter from another POU names the program's instance, as in ST: one per PROGRAM. A class
            # decorator makes it (as @gvl does), which mypy accepts where rebinding the class name is refused.
            self.need("typing", "TypeVar")
            for name in self.named_programs:
                index = body.index(f"class {name}(Program):")
                body.insert(index, "@_program_instance")
            body[:0] = ["", "", '_P = TypeVar("_P", bound=Program)', "", "",
                        "def _program_instance(cls: type[_P]) -> _P:",
                        '    """A PROGRAM other POUs read by name (P_Count.counter): as in ST, the name is its one instance."""',
                        "    return cls()"]
        header = ['"""Generated by iecoop.st from Structured Text; edit freely, it is plain iecoop code."""', "",
                  "from __future__ import annotations", ""]
        standard = [m for m in ("math", "typing") if m in self.imports]
        if "math" in self.imports:
            header.append("import math")
        if "typing" in self.imports:
            header.append(f"from typing import {', '.join(sorted(self.imports['typing']))}")
        if standard:
            header.append("")
        for module in sorted(m for m in self.imports if m not in standard):
            names = sorted(self.imports[module])
            line = f"from {module} import {', '.join(names)}"
            if len(line) > 110:
                header.append(f"from {module} import (")
                chunk = ""
                for name in names:
                    if len(chunk) + len(name) > 100:
                        header.append(f"    {chunk.rstrip()}")
                        chunk = ""
                    chunk += f"{name}, "
                header.append(f"    {chunk.rstrip()}")
                header.append(")")
            else:
                header.append(line)
        return "\n".join(header + body) + "\n"

    # --- data types ---

    def _emit_enum(self, decl: Decl) -> None:
        node = decl.node
        self.line = node.meta.line if node.meta else None
        base = node.init.spec.type_name
        base_kw = ""
        if base is not None:
            base_type = self.type_named(str(base), node)
            self.need("iecoop", base_type.name)
            base_kw = f", base={base_type.name}"
        self.need("iecoop", "IecEnum")
        self.comments(node, 0)
        self.emit(f"class {decl.name}(IecEnum{base_kw}):", 0)
        self.emit(f'"""TYPE {decl.name} (enumeration)."""', 1)
        value = -1
        scope = Scope(None, "const")
        for item in node.init.spec.values or []:
            if item.value is not None:
                text = self.expr(item.value, scope).code
                try:
                    value = int(eval(text, {}))  # a literal or a constant expression of literals
                except Exception:
                    raise self.fail(f"enumeration value {decl.name}.{item.name} := {text} is not a constant", node) from None
            else:
                value += 1
            self.emit(f"{python_name(str(item.name), attribute=True)} = {value}", 1)
        if node.init.value is not None:
            raise self.fail(f"a default value for enumeration {decl.name} is not supported", node)

    def _emit_alias(self, decl: Decl) -> None:
        assert decl.alias_of is not None
        target = decl.alias_of
        if target.kind in ("string", "array") and (target.length not in (None, "80") or target.bounds):
            raise self.fail(f"alias {decl.name} of {target.annotation()} with a length or bounds is not supported", decl.node)
        self.need("typing", "Annotated")
        self.need("iecoop", "Alias")
        self._need_type(target)
        self.comments(decl.node, 0)
        init = getattr(getattr(decl.node, "init", None), "value", None)
        initial = ""
        if init is not None:
            if target.kind != "elem":
                raise self.fail(f"alias {decl.name} of {target.annotation()} with an initial value is not supported", decl.node)
            initial = f", initial={self.init_value(init, target, Scope(None, 'alias'))}"
        elif target.limits is not None:
            initial = f", initial={target.limits[0]}"  # a subrange starts at its lower limit (IEC 61131-3)
        self.emit(f'{decl.name} = Annotated[{target.annotation()}, Alias("{decl.name}"{initial})]', 0)

    def _need_type(self, type_: TypeRef | None) -> None:
        if type_ is None:
            return
        if type_.kind == "array":
            self.need("iecoop", "ARRAY")
        elif type_.kind == "pointer":
            self.need("iecoop", "POINTER_TO")
        elif type_.kind == "reference":
            self.need("iecoop", "REFERENCE_TO")
        elif type_.kind in ("elem", "string"):
            self.need("iecoop", type_.name)
        elif type_.name == "ExceptionCode":
            self.need("iecoop", "ExceptionCode")
        elif getattr(self.by_python.get(type_.name), "kind", None) == "stdfb":
            self.need("iecoop.stdlib", type_.name)
        elif type_.kind == "user" and type_.name not in self.by_python and type_.name.lower() in SYSTEM_DECLS:
            self.need("iecoop", type_.name)
        if type_.of is not None:
            self._need_type(type_.of)

    def _emit_struct(self, decl: Decl) -> None:
        self._emit_datatype(decl, "Struct")

    def _emit_union(self, decl: Decl) -> None:
        self._emit_datatype(decl, "Union")

    def _emit_datatype(self, decl: Decl, base: str) -> None:
        node = decl.node
        bases = decl.bases[0] if decl.bases else base
        if not decl.bases:
            self.need("iecoop", base)
        self.comments(node, 0)
        self.emit(f"class {decl.name}({bases}):", 0)
        keyword = "STRUCT" if base == "Struct" else "UNION"
        self.emit(f'"""TYPE {decl.name} : {keyword}."""', 1)
        scope = Scope(decl, "const")
        for element in node.declarations:
            self.line = element.meta.line if element.meta else self.line
            trailing = self.comments(element, 1, inline=True)
            index = len(self.out)
            members = list(self._element_members(element, decl.kind))
            init = getattr(element, "init", None)
            if isinstance(element, tf.UnionElementDeclaration):
                init = None
            for member in members:
                self.emit(self.field_line(member, init, scope, plain=True), 1)
            self.trail(index, trailing)
        if not node.declarations:
            self.emit("pass", 1)

    # --- field declarations ---

    def field_line(self, member: Member, init: Any, scope: Scope, *, plain: bool = False, extra: str = "") -> str:
        type_ = member.type
        assert type_ is not None
        if type_.kind == "varinfo" and member.section == "VAR_TEMP" and scope.kind == "body":
            # VAR_TEMP is new at every call of the body: a Python local of body(), set by := __VARINFO(x)
            scope.locals[member.st.lower()] = Member(member.name, type_, "LOCAL", st=member.st)
            return f"# {member.st} : __SYSTEM.VAR_INFO (VAR_TEMP) is a local of body()"
        if type_.kind == "varinfo":
            raise self.fail(f"{member.section} {member.st} : __SYSTEM.VAR_INFO (declare it as a local of a METHOD or FUNCTION)")
        self._need_type(type_)
        args: list[str] = []
        value = self.initial_value(type_, init, scope)
        if value is not None:
            args.append(value)
        kwargs = []
        if type_.kind == "string" and type_.length not in (None, "80"):
            kwargs.append(f"length={type_.length}")
        shape = type_.of if type_.kind in ("pointer", "reference") and type_.of is not None and type_.of.kind == "array" else type_
        if shape.kind == "array":
            levels = []
            while shape.kind == "array" and shape.of is not None:
                assert shape.bounds is not None
                pairs = [f"({a}, {b})" for a, b in shape.bounds]
                levels.append(pairs[0] if len(pairs) == 1 else "(" + ", ".join(pairs) + ")")
                shape = shape.of
            # ARRAY OF ARRAY: one bounds entry per level, outermost first
            kwargs.append(f"bounds={levels[0] if len(levels) == 1 else '(' + ', '.join(levels) + ')'}")
            if shape.kind == "string" and shape.length not in (None, "80"):
                kwargs.append(f"length={shape.length}")
        fb_init = self.fb_init_args(init, scope)
        if fb_init:
            kwargs.append(f"fb_init={fb_init}")
        if extra:
            kwargs.append(extra)
        section = member.section if member.section != "VAR_GLOBAL" else "VAR"
        note = f"  # {type_.name}({type_.limits[0]}..{type_.limits[1]})" if type_.limits is not None else ""
        if plain and not kwargs and value is not None:
            return f"{member.name}: {type_.annotation()} = {value}{note}"
        self.need("iecoop", section)
        return f"{member.name}: {type_.annotation()} = {section}({', '.join(args + kwargs)}){note}"

    def fb_init_args(self, init: Any, scope: Scope) -> str:
        call: Any = None
        if isinstance(init, tf.FunctionBlockInvocationDeclaration):
            call = init.init
            type_name, parameters = str(call.name.name), call.parameters
        elif isinstance(init, tf.TypeInitialization) and isinstance(init.spec, tf.IndirectSimpleSpecification) and init.spec.init_parameters:
            call = init
            type_name, parameters = str(init.spec.type.type), init.spec.init_parameters
        if call is not None:
            decl = self.decls.get(type_name.lower())
            fb_init = self.find_member(decl, "FB_init") if decl is not None else None
            params = fb_init[1].params if fb_init is not None and isinstance(fb_init[1], Callable_) else []
            params = [p for p in params if p.st.lower() not in ("binitretains", "bincopycode")]
            pairs = []
            for index, param in enumerate(parameters):
                if isinstance(param, tf.OutputParameterAssignment):
                    raise self.fail("an output (=>) in an FB_init call of a declaration", init)
                if param.name is not None:
                    name = str(param.name.name)
                    match = next((p.name for p in params if p.st.lower() == name.lower()), python_name(name))
                elif index < len(params):
                    match = params[index].name
                else:
                    raise self.fail(f"FB_init of {type_name} has no input number {index + 1}", init)
                pairs.append(f'"{match}": {self.expr(param.value, scope).code}')
            return "{" + ", ".join(pairs) + "}"
        return ""

    def sibling_address(self, type_: TypeRef, init: Any, scope: Scope) -> str | None:
        """``p : POINTER TO T := ADR(x);`` / ``r : REFERENCE TO T := x;`` of a member beside it: ``adr_of("x")``."""
        target = getattr(init, "value", None)
        if type_.kind == "pointer":
            if not (isinstance(target, tf.FunctionCall) and str(target.name).upper() == "ADR" and len(target.parameters) == 1):
                return None
            target = target.parameters[0].value
        elif isinstance(target, tf.ArrayInitialization) and not target.brackets and len(target.elements) == 1:
            target = target.elements[0].element  # blark reads `ref : REFERENCE TO ARRAY.. := a` as an array value
        index = ""
        if isinstance(target, tf.MultiElementVariable) and len(target.elements) == 1 and isinstance(target.elements[0], tf.SubscriptList):
            subscripts = target.elements[0].subscripts
            if not all(isinstance(sub, tf.Integer) for sub in subscripts):
                return None
            numbers = [self.expr(sub, scope).code for sub in subscripts]
            index = ", " + (numbers[0] if len(numbers) == 1 else "(" + ", ".join(numbers) + ")")
            target = target.name
        if scope.owner is None or not isinstance(target, tf.SimpleVariable) or target.dereferenced:
            return None
        found = self.find_member(scope.owner, str(target.name))
        if found is None or not isinstance(found[1], Member):
            return None
        self.need("iecoop", "adr_of")
        return f'adr_of("{found[1].name}"{index})'

    def initial_value(self, type_: TypeRef, init: Any, scope: Scope) -> str | None:
        if type_.kind in ("pointer", "reference"):
            sibling = self.sibling_address(type_, init, scope)
            if sibling is not None:
                return sibling
        if type_.kind == "reference" and getattr(init, "value", None) is not None:
            if scope.owner is None or scope.kind != "body":
                raise self.fail("a REFERENCE TO initialised at its declaration is supported in a block's VAR only", init)
            self.pending_references.append(init.value)
            return None
        value: Any = None
        if isinstance(init, tf.FunctionBlockInvocationDeclaration):
            value = init.defaults
        elif isinstance(init, tf.FunctionBlockNameDeclaration):
            value = init.init
        elif isinstance(init, tf.InitializedStructure):
            value = init.init
        elif init is not None and not isinstance(init, tf.FunctionCall):
            value = getattr(init, "value", None)
        if value is None:
            decl = self.decl_of(type_) if type_.kind == "user" else None
            if decl is not None and decl.kind == "enum" and decl.values:
                return f"{decl.name}.{python_name(decl.values[0], attribute=True)}"
            if type_.limits is not None:
                return type_.limits[0]  # a subrange starts at its lower limit (IEC 61131-3)
            return None
        if self.subrange(type_) is not None:
            return self.limit(type_, self.expr(value, scope)).code
        if isinstance(value, lark_token_type()):
            if type_.kind == "string":
                return python_string(str(value))
            raise self.fail(f"initial value {value}", init)
        return self.init_value(value, type_, scope)

    def init_value(self, value: Any, type_: TypeRef | None, scope: Scope) -> str:
        if isinstance(value, tf.ArrayInitialization):
            element = type_.of if type_ is not None and type_.kind == "array" else None
            return "[" + ", ".join(self._array_elements(value, element, scope)) + "]"
        elements = _structure_elements(value)
        if elements is not None:
            decl = self.decl_of(type_)
            pairs = []
            for element_name, element_value in elements:
                if element_name is None:
                    raise self.fail("a structure initialiser element without a name", value)
                found = self.find_member(decl, element_name) if decl is not None else None
                name = found[1].name if found is not None else python_name(element_name, attribute=True)
                member_type = found[1].type if found is not None and isinstance(found[1], Member) else None
                pairs.append(f'"{name}": {self.init_value(element_value, member_type, scope)}')
            return "{" + ", ".join(pairs) + "}"
        if isinstance(value, tf.EnumeratedValue):
            enum_name = str(value.type_name) if value.type_name is not None else None
            return self.enum_ref(enum_name, str(value.name), value)
        return self.coerce(self.expr(value, scope, expected=type_), type_).code

    def _array_elements(self, value: Any, element: TypeRef | None, scope: Scope) -> Iterator[str]:
        for item in value.elements:
            count = 1
            if item.count is not None:
                count = int(eval(self.expr(item.count, scope).code, {}))
            if isinstance(item.element, tf.ArrayInitialization) and not item.element.brackets:
                inner = list(self._array_elements(item.element, element, scope))
                for _ in range(count):
                    yield from inner
                continue
            text = self.init_value(item.element, element, scope)
            for _ in range(count):
                yield text

    def enum_ref(self, enum_name: str | None, value: str, node: Any) -> str:
        if enum_name is not None:
            decl = self.decls.get(enum_name.lower())
            if decl is None or decl.kind != "enum":
                raise self.fail(f"unknown enumeration {enum_name!r}", node)
            match = next((v for v in decl.values if v.lower() == value.lower()), None)
            if match is None:
                raise self.fail(f"enumeration {decl.st} has no value {value!r}", node)
            return f"{decl.name}.{python_name(match, attribute=True)}"
        if "." in value:  # blark reads a qualified value (E_Mode.AUTO) as one dotted name
            prefix, _, last = value.rpartition(".")
            return self.enum_ref(prefix, last, node)
        found = self.enum_values.get(value.lower())
        if found is None:
            raise self.fail(f"unknown enumeration value {value!r}", node)
        return f"{found[0]}.{found[1]}"

    # --- POUs ---

    def _class_kwargs(self, access: Any) -> str:
        kwargs = []
        if access is not None:
            if access & tf.AccessSpecifier.abstract:
                kwargs.append("abstract=True")
            if access & tf.AccessSpecifier.final:
                kwargs.append("final=True")
            if access & tf.AccessSpecifier.internal:
                kwargs.append("internal=True")
        return "".join(f", {k}" for k in kwargs)

    def _emit_fb(self, decl: Decl) -> None:
        node = decl.node
        self.line = node.meta.line if node.meta else None
        bases = list(decl.bases)
        if not bases:
            self.need("iecoop", "FunctionBlock")
            bases.append("FunctionBlock")
        else:
            base_decl = self.decls.get(bases[0].lower())
            if base_decl is None or base_decl.kind not in ("fb", "stdfb"):
                raise self.fail(f"FUNCTION_BLOCK {decl.name} EXTENDS unknown block {bases[0]!r}", node)
            bases[0] = base_decl.name
            if base_decl.kind == "stdfb":
                self.need("iecoop.stdlib", base_decl.name)
        for itf in node.implements.interfaces if node.implements else []:
            itf_decl = self.decls.get(str(itf).lower())
            if itf_decl is None or itf_decl.kind != "interface":
                raise self.fail(f"FUNCTION_BLOCK {decl.name} IMPLEMENTS unknown interface {itf!r}", node)
            bases.append(itf_decl.name)
        self.comments(node, 0)
        self.emit(f"class {decl.name}({', '.join(bases)}{self._class_kwargs(node.access)}):", 0)
        self.emit(f'"""FUNCTION_BLOCK {decl.name}."""', 1)
        self._emit_pou(decl, "FUNCTION_BLOCK")

    def _emit_program(self, decl: Decl) -> None:
        self.need("iecoop", "Program")
        self.comments(decl.node, 0)
        self.emit(f"class {decl.name}(Program):", 0)
        self.emit(f'"""PROGRAM {decl.name}."""', 1)
        self._emit_pou(decl, "PROGRAM")

    def _emit_pou(self, decl: Decl, kind: str) -> None:
        node = decl.node
        scope = Scope(decl, "body")
        self.pending_references = []
        self._emit_fields(decl, node.declarations, scope, 1)
        self._emit_reference_inits(decl, scope)
        for method in decl.method_nodes:
            self._emit_method(decl, method)
        self._emit_actions(decl)
        self._emit_properties(decl)
        statements = statements_of(node.body)
        if statements or (kind == "FUNCTION_BLOCK" and decl.bases and node.body is not None):
            self.emit("", 0)
            self.emit("def body(self) -> None:", 1)
            self._emit_statements(statements, scope, 2)
        if len(self.out) and self.out[-1].strip().startswith('"""') and self.out[-1].strip().endswith('"""'):
            self.emit("pass", 1)

    def _emit_fields(self, decl: Decl, blocks: Sequence[Any], scope: Scope, level: int, method: str | None = None) -> None:
        for block in blocks:
            self.comments(block, level)
            section = _SECTION_OF.get(type(block))
            attrs = getattr(block, "attrs", None)
            extra = []
            if attrs is not None:
                if attrs & tf.VariableAttributes.constant:
                    extra.append("constant=True")
                if attrs & tf.VariableAttributes.retain:
                    extra.append("retain=True")
                if attrs & tf.VariableAttributes.persistent:
                    extra.append("persistent=True")
            if method is not None and section == "VAR_INST":
                extra.append(f'method="{method}"')
            for item in block.items:
                self.line = item.meta.line if item.meta else self.line
                trailing = self.comments(item, level, inline=True)
                index = len(self.out)
                if section == "VAR_EXTERNAL":
                    for name, type_ in self._item_types(item):
                        self._need_type(type_)
                        self.need("iecoop", "VAR_EXTERNAL")
                        self.emit(f"{python_name(name, attribute=True)}: {type_.annotation() if type_ else 'object'} = VAR_EXTERNAL()", level)
                    self.trail(index, trailing)
                    continue
                for name, type_ in self._item_types(item):
                    init = item if isinstance(item, (tf.FunctionBlockNameDeclaration, tf.FunctionBlockInvocationDeclaration)) else getattr(item, "init", None)
                    member = Member(python_name(name, attribute=True), type_, self.located_section(item, section or "VAR"), st=name)
                    self.emit(self.field_line(member, init, scope, extra=", ".join(extra)), level)
                self.trail(index, ": ".join(filter(None, (self.location(item), trailing))))

    def _emit_reference_inits(self, decl: Decl, scope: Scope) -> None:
        """``ref : REFERENCE TO T := x;`` binds after initialisation, as the PLC binds it: REF= in a call_after_init."""
        if not self.pending_references:
            return
        self.pending_references = []
        self.need("iecoop", "call_after_init", "ref_assign")
        self.emit("", 0)
        self.emit("@call_after_init", 1)
        self.emit(f"def _bind_references_{decl.name}(self) -> None:", 1)
        self.emit('"""The REFERENCE TO variables initialised at their declaration (ref : REFERENCE TO T := x)."""', 2)
        for block in decl.node.declarations:
            for item in block.items:
                init = getattr(item, "init", None)
                target = getattr(init, "value", None)
                if target is None or self.init_type(init, item).kind != "reference":
                    continue
                if isinstance(target, tf.ArrayInitialization) and not target.brackets and len(target.elements) == 1:
                    target = target.elements[0].element  # blark reads `ref : REFERENCE TO ARRAY.. := a` as an array value
                for var in item.variables:
                    self.emit(f'ref_assign(self, "{python_name(str(var.variable.name), attribute=True)}", {self.address_of(target, scope)})', 2)

    def _params(self, params: Sequence[Member], blocks: Sequence[Any], scope: Scope) -> str:
        inits: dict[str, Any] = {}
        for block in blocks:
            if isinstance(block, (tf.InputDeclarations, tf.OutputDeclarations)):
                for item in block.items:
                    for var in getattr(item, "variables", []):
                        name = str(var.variable.name if hasattr(var, "variable") else var)
                        inits[name.lower()] = getattr(item, "init", None)
        parts = []
        last_reference = max((i for i, p in enumerate(params) if p.type is not None and p.type.kind == "reference"), default=-1)
        for index, param in enumerate(params):
            assert param.type is not None
            self._need_type(param.type)
            if param.section in ("VAR_OUTPUT", "VAR_IN_OUT"):
                if index < last_reference:
                    raise self.fail(f"{param.section} {param.st} comes before a REFERENCE TO input; declare the REFERENCE TO inputs first")
                parts.append(self._by_reference_param(param, inits.get(param.st.lower()), scope))
                continue
            if index <= last_reference:
                # a REFERENCE TO input has no default (ST requires it), nor can an input before it in Python:
                # that one is required too, as in a Python signature (a STRUCT by value needs its default)
                if param.type.kind != "reference" and self._aggregate(param.type):
                    raise self.fail(f"input {param.st} comes before a REFERENCE TO input; declare the REFERENCE TO inputs first")
                parts.append(f"{param.name}: {param.type.annotation()}")
                scope.locals[param.st.lower()] = param
                continue
            if self._aggregate(param.type):
                if not scope.pou:
                    raise self.fail(f"input {param.st} of type {param.type.annotation()} passed by value is supported in a METHOD or FUNCTION")
                # passed by value: the callee works on a copy, made as it starts (_local_blocks); None is "not given"
                scope.by_value.append((param, inits.get(param.st.lower())))
                parts.append(f"{param.name}: {param.type.annotation()} | None = None")
                scope.locals[param.st.lower()] = param
                continue
            default = self.initial_value(param.type, inits.get(param.st.lower()), scope) or self.zero(param.type)
            if scope.owner is not None and scope.owner.kind == "interface" and self.decl_of(param.type) is scope.owner:
                # a prototype's input of its own interface type: the class does not exist yet to make its null()
                self.need("iecoop", "NULL")
                default = "NULL"
            parts.append(f"{param.name}: {param.type.annotation()} = {default}")
            scope.locals[param.st.lower()] = param
        return "".join(f", {p}" for p in parts)

    def _by_reference_param(self, param: Member, init: Any, scope: Scope) -> str:
        """``nHigh : BYTE`` of VAR_OUTPUT / VAR_IN_OUT: ``nHigh: POINTER_TO[BYTE] = VAR_OUTPUT()``, reached as ``nHigh.deref``."""
        assert param.type is not None
        if param.type.kind == "reference":
            raise self.fail(f"{param.section} {param.st} of a REFERENCE TO type is not supported")
        length = f"length={param.type.length}" if param.type.kind == "string" and param.type.length not in (None, "80") else ""
        line = self.field_line(Member(param.name, TypeRef("pointer", "POINTER", of=param.type), param.section, st=param.st), None, scope, extra=length)
        if init is not None:
            if param.section == "VAR_IN_OUT":
                raise self.fail(f"an initial value for VAR_IN_OUT {param.st}")
            # outputs start at their initial value at every call: the first statement of the body sets it
            value = self.initial_value(param.type, init, scope)
            if value is not None:
                scope.output_inits.append(f"{param.name}.deref = {value}")
        scope.locals[param.st.lower()] = param
        return line

    def _aggregate(self, type_: TypeRef) -> bool:
        """Whether a value of ``type_`` is an ARRAY, STRUCT or UNION (copied when passed by value)."""
        decl = self.decl_of(type_) if type_.kind == "user" else None
        return type_.kind == "array" or decl is not None and decl.kind in ("struct", "union")

    def _copied(self, type_: TypeRef) -> bool:
        """Whether an assignment of ``type_`` copies a value with members (STRUCT, UNION, ARRAY or block)."""
        decl = self.decl_of(type_) if type_.kind == "user" else None
        return self._aggregate(type_) or decl is not None and decl.kind in ("fb", "stdfb")

    def _holder(self, scope: Scope, suffix: str, fields: Sequence[tuple[Member, Any]], doc: str) -> str:
        """A module-level STRUCT that holds ``fields`` of the METHOD or FUNCTION ``scope``, written before its POU."""
        name = "_" + scope.pou.replace(".", "_") + suffix
        self.need("iecoop", "Struct")
        lines = ["", "", f"class {name}(Struct):", f'    """{doc}"""']
        const = Scope(None, "const")
        for member, init in fields:
            lines.append("    " + self.field_line(Member(member.name, member.type, "VAR", st=member.st), init, const))
        self.preamble.extend(lines)
        return name

    def zero(self, type_: TypeRef) -> str:
        if type_.is_bool:
            return "False"
        if type_.is_real:
            return "0.0"
        if type_.is_int:
            return "0"
        if type_.kind == "string":
            return '""'
        if type_.kind == "pointer":
            self.need("iecoop", "Pointer")
            return "Pointer(0, None)"
        decl = self.decl_of(type_)
        if decl is not None and decl.kind == "enum":
            return f"{decl.name}.{python_name(decl.values[0], attribute=True)}"
        if decl is not None and decl.kind == "interface":
            self.need("iecoop", "null")
            return f"null({decl.name})"
        if decl is not None and decl.kind == "alias" and decl.alias_of is not None:
            return self.zero(decl.alias_of)
        if decl is not None and decl.kind in ("struct", "union", "fb"):
            return f"{decl.name}()"
        raise self.fail(f"a local or input of type {type_.annotation()} has no zero value here")

    def _access_decorator(self, access: Any, extra: Sequence[str] = ()) -> str:
        flags = list(extra)
        if access is not None:
            for spec in tf.AccessSpecifier:
                if access & spec and spec.name.upper() in ACCESS_SPECIFIERS and spec.name.upper() != "PUBLIC":
                    flags.append(spec.name.upper())
        for flag in flags:
            self.need("iecoop", flag)
        self.need("iecoop", "method")
        return f"@method({' | '.join(flags)})" if flags else "@method"

    def _local_blocks(self, blocks: Sequence[Any], scope: Scope, level: int) -> None:
        arrays: list[tuple[Member, Any]] = []
        statics: list[tuple[Any, str, TypeRef | None]] = []
        self._locals_of_blocks(blocks, scope, level, arrays, statics)
        if statics:
            self._statics(scope, statics)
        held = scope.by_value + arrays
        if held:
            # ARRAY and structured locals, and the copies of such inputs passed by value, live in a STRUCT
            # made at each call: initialised as declared, and the caller's variables never written
            addressed = " and the locals passed by address" if any(m.section == "ADDRESSED" for m, _ in held) else ""
            holder = self._holder(scope, "_VAR", held, f"The ARRAY and structured inputs and locals of {scope.pou}{addressed}: new at every call.")
            self.emit(f"_var = {holder}()", level)
            for member, _ in scope.by_value:
                self.emit(f"if {member.name} is not None:", level)
                self.emit(f"_var.{member.name} = {member.name}  # passed by value: a copy", level + 1)
            for member, _ in held:
                assert member.type is not None
                self._need_type(member.type)
                if member.section == "ADDRESSED":
                    continue  # read and written as _var.name
                annotation = f": {member.type.annotation()}" if member.section != "VAR_INPUT" else ""
                self.emit(f"{member.name}{annotation} = _var.{member.name}", level)

    def _statics(self, scope: Scope, statics: Sequence[tuple[Any, str, TypeRef | None]]) -> None:
        """VAR_STAT of a METHOD or FUNCTION: one variable for every instance and every call (TwinCAT, CODESYS)."""
        owner = scope.owner
        if owner is not None:
            method = scope.pou.split(".", 1)[1]
            for item, name, type_ in statics:  # a VAR_STAT of the block, named after the method
                self.need("iecoop", "VAR_STAT")
                field = Member(f"{method}_{python_name(name)}", type_, "VAR_STAT")
                if self.find_member(owner, field.name) is not None:
                    raise self.fail(f"VAR_STAT {name} of METHOD {scope.pou} clashes with the member {field.name}", item)
                self.out.insert(self._field_insert_point(), "    " + self.field_line(field, getattr(item, "init", None), Scope(None, "const")))
                scope.locals[name.lower()] = Member(f"self.{field.name}", type_, "STAT")
            return
        holder = self._holder(scope, "_VAR_STAT", [(Member(python_name(name, attribute=True), type_, "VAR", st=name), getattr(item, "init", None)) for item, name, type_ in statics],
                              f"VAR_STAT of FUNCTION {scope.pou}: one for every call.")
        instance = f"_{scope.pou}_static"
        self.preamble.extend(["", "", f"{instance} = {holder}()"])
        for _, name, type_ in statics:
            scope.locals[name.lower()] = Member(f"{instance}.{python_name(name, attribute=True)}", type_, "STAT", st=name)

    def _locals_of_blocks(self, blocks: Sequence[Any], scope: Scope, level: int, arrays: list[tuple[Member, Any]],
                          statics: list[tuple[Any, str, TypeRef | None]]) -> None:
        for block in blocks:
            if self._non_local_block(block, scope, statics):
                continue
            constant = getattr(block, "attrs", None) is not None and block.attrs & tf.VariableAttributes.constant
            for item in block.items:
                self.line = item.meta.line if item.meta else self.line
                trailing = self.comments(item, level, inline=True)
                index = len(self.out)
                for name, type_ in self._item_types(item):
                    assert type_ is not None
                    if not self._held_local(item, name, type_, scope, arrays, constant):
                        self._declare_local(item, name, type_, scope, level, constant)
                self.trail(index, trailing)

    def _non_local_block(self, block: Any, scope: Scope, statics: list[tuple[Any, str, TypeRef | None]]) -> bool:
        """Handle a VAR section that declares no plain local (parameters, VAR_STAT, VAR_EXTERNAL); True if handled."""
        section = _SECTION_OF.get(type(block))
        if section in ("VAR_INPUT", "VAR_INST"):
            return True
        if section in ("VAR_OUTPUT", "VAR_IN_OUT"):
            if scope.kind in ("method", "function"):
                return True  # parameters (see _by_reference_param)
            raise self.fail(f"{section} in a {scope.kind} is not supported", block)
        if section == "VAR_STAT":
            if not scope.pou:
                raise self.fail(f"VAR_STAT in a {scope.kind} is not supported", block)
            statics.extend((item, name, type_) for item in block.items for name, type_ in self._item_types(item))
            return True
        if section == "VAR_EXTERNAL":  # the global itself, read and written in place (never a local copy)
            for item in block.items:
                for name, _ in self._item_types(item):
                    found = self.globals.get(name.lower())
                    if found is None:
                        raise self.fail(f"VAR_EXTERNAL {name} of {scope.pou or scope.kind} names no VAR_GLOBAL", item)
                    scope.locals[name.lower()] = Member(f"{found[0]}.{found[1].name}", found[1].type, "STAT", st=name)
            return True
        return False

    def _held_local(self, item: Any, name: str, type_: TypeRef, scope: Scope, arrays: list[tuple[Member, Any]],
                    constant: Any) -> bool:
        """A local the POU's holder makes (an addressed scalar, an ARRAY, an initialised STRUCT); True if it is one."""
        py = python_name(name)
        enum = getattr(self.decl_of(type_), "kind", None) == "enum"
        if name.lower() in scope.addressed and scope.pou and (type_.kind in ("elem", "string", "pointer") or enum) and not constant:
            # an output or in-out argument needs the variable's address: a field of the holder has one
            arrays.append((Member(py, type_, "ADDRESSED", st=name), getattr(item, "init", None)))
            scope.locals[name.lower()] = Member(f"_var.{py}", type_, "STAT", st=name)
            return True
        initialised = self._aggregate(type_) and self.initial_value(type_, getattr(item, "init", None), scope) is not None
        if type_.kind == "array" or initialised:  # a STRUCT with its own initial values too: made by the holder
            if not scope.pou:
                raise self.fail(f"{'ARRAY' if type_.kind == 'array' else 'initialised STRUCT'} local {name} in a {scope.kind} is not supported (declare it in the block)", item)
            arrays.append((Member(py, type_, "LOCAL", st=name), getattr(item, "init", None)))
            scope.locals[name.lower()] = Member(py, type_, "LOCAL", st=name)
            return True
        return False

    def _declare_local(self, item: Any, name: str, type_: TypeRef, scope: Scope, level: int, constant: Any) -> None:
        """Emit the Python local of one ST variable of a method or function body."""
        py = python_name(name)
        self._need_type(type_)
        init = getattr(item, "init", None)
        if self._local_reference(type_) and getattr(init, "value", None) is None:
            # bound by REF= to a view of its target, which is what a REFERENCE TO reads and writes through
            assert type_.of is not None
            scope.locals[name.lower()] = Member(py, type_, "LOCAL", st=name)
            self.emit(f"{py}: {type_.of.annotation()}", level)
            return
        if type_.kind == "varinfo":  # set by := __VARINFO(x) before it is read
            self.need("iecoop", "VarInfo")
            scope.locals[name.lower()] = Member(py, type_, "LOCAL", st=name)
            self.emit(f"{py}: VarInfo", level)
            return
        if type_.kind == "reference" and type_.of is not None and type_.of.kind in ("elem", "string") and getattr(init, "value", None) is None:
            # a pointer that REF= binds; reached through .deref, as an in-out is
            self.need("iecoop", "POINTER_TO", "Pointer")
            scope.locals[name.lower()] = ReferenceLocal(py, type_.of, "VAR_IN_OUT", st=name)
            self.emit(f"{py}: POINTER_TO[{type_.of.annotation()}] = Pointer(0, None).typed({type_.of.annotation()})", level)
            return
        value = self.initial_value(type_, init, scope) or self.zero(type_)
        scope.locals[name.lower()] = Member(py, type_, "CONSTANT" if constant else "LOCAL", st=name)
        self.emit(f"{py}: {self.local_annotation(type_)} = {value}", level)

    def local_annotation(self, type_: TypeRef) -> str:
        return type_.annotation()

    def _local_reference(self, type_: TypeRef | None) -> bool:
        """A REFERENCE TO a STRUCT, UNION or FB: a local of a method or function holds the view of its target."""
        decl = self.decl_of(type_) if type_ is not None and type_.kind == "reference" else None
        return decl is not None and decl.kind in ("struct", "union", "fb", "stdfb")

    def _emit_method(self, decl: Decl, node: Any) -> None:
        self.line = node.meta.line if node.meta else None
        self.enter(node)
        name = str(node.name)
        info = decl.methods[name.lower()]
        lifecycle = LIFECYCLE.get(name.upper())
        scope = Scope(decl, "method", return_name=python_name(name) if info.returns is not None else None)
        scope.return_st = name
        scope.pou = f"{decl.name}.{info.name}"
        self.emit("", 0)
        self.comments(node, 1)
        decorators = []
        for pragma in self.pragmas(node):
            if re.fullmatch(r"\{\s*attribute\s+'call_after_init'\s*\}", pragma, re.IGNORECASE):
                self.need("iecoop", "call_after_init")
                decorators.append("@call_after_init")
        # the method's VAR_INST live in the instance
        for block in node.declarations:
            if isinstance(block, tf.MethodInstanceVariableDeclarations):
                for item in block.items:
                    self.line = item.meta.line if item.meta else self.line
                    for var_name, type_ in self._item_types(item):
                        assert type_ is not None
                        self._need_type(type_)
                        member = Member(python_name(var_name, attribute=True), type_, "VAR_INST", st=var_name)
                        self._add_member(decl, member)  # a field of the instance, beside the block's own
                        self.need("iecoop", "VAR_INST")
                        self.out.insert(self._field_insert_point(), "    " + self.field_line(
                            member, getattr(item, "init", None), scope, extra=f'method="{lifecycle or info.name}"'))
        returns = info.returns
        ret_text = returns.annotation() if returns is not None else "None"
        self._need_type(returns)
        if lifecycle is not None:
            if lifecycle == "fb_init":
                inputs = info.params
                if len(inputs) < 2:
                    raise self.fail(f"METHOD FB_init of {decl.name} needs the inputs bInitRetains and bInCopyCode", node)
                # iecoop names the two implicit inputs in PEP 8; the ST names still resolve to them
                first = ", init_retains: BOOL, in_copy_code: BOOL"
                self.need("iecoop", "BOOL")
                for p, py_name in zip(inputs[:2], ("init_retains", "in_copy_code")):
                    scope.locals[p.st.lower()] = Member(py_name, p.type, "VAR_INPUT", st=p.st)
                params = first + self._params(inputs[2:], node.declarations, scope)
            elif lifecycle == "fb_exit":
                if info.params:
                    scope.locals[info.params[0].st.lower()] = Member("in_copy_code", BOOL, "VAR_INPUT", st=info.params[0].st)
                params = ", in_copy_code: BOOL" + self._params(info.params[1:], node.declarations, scope)
            else:
                params = ""
            self.emit_def(f"def {lifecycle}(self{params}) -> BOOL:", 1)
            self.need("iecoop", "BOOL")
            scope.return_name = python_name(name)
            returns = TypeRef("elem", "BOOL")
        else:
            decorators.insert(0, self._access_decorator(node.access))
            params = self._params(info.params, node.declarations, scope)
            for decorator in decorators:
                self.emit(decorator, 1)
            self.emit_def(f"def {info.name}(self{params}) -> {ret_text}:", 1)
        if node.access is not None and node.access & tf.AccessSpecifier.abstract or decl.kind == "interface":
            self.prototype(returns, 2)
            return
        self._emit_callable_body(node, scope, returns, 2)

    def _emit_actions(self, decl: Decl) -> None:
        """ACTIONs: code of the block that works on its variables; a method without inputs (``fbX.Reset()``)."""
        for node in decl.action_nodes:
            self.line = node.meta.line if node.meta else None
            self.enter(node)
            name = str(node.name).rsplit(".", 1)[-1]
            self.emit("", 0)
            self.comments(node, 1)
            self.emit(self._access_decorator(None), 1)
            self.emit(f"def {python_name(name, attribute=True)}(self) -> None:", 1)
            self.emit(f'"""ACTION {name}."""', 2)
            self._emit_statements(statements_of(node.body), Scope(decl, "body"), 2)

    def prototype(self, returns: TypeRef | None, level: int) -> None:
        """The body of an interface or ABSTRACT member: no code, and nothing a type checker reads as a return."""
        self.emit("..." if returns is None else "raise NotImplementedError", level)

    def _field_insert_point(self) -> int:
        """Just after the last field line of the class being written."""
        index = len(self.out)
        for i, line in enumerate(self.out):
            if line.startswith("    ") and not line.startswith("        ") and re.match(r"    \w+: .+ = ", line):
                index = i + 1
            if line.startswith("    def ") or line.startswith("    @"):
                break
        return index

    def _emit_callable_body(self, node: Any, scope: Scope, returns: TypeRef | None, level: int) -> None:
        if returns is not None and scope.return_name is not None:
            key = (scope.return_st or scope.return_name).lower()
            scope.locals[key] = Member(scope.return_name, returns, "RETURN", st=scope.return_st or scope.return_name)
            if self._local_reference(returns):
                # REFERENCE TO a STRUCT or block: ``F REF= x`` names the variable itself, which is what Python returns
                assert returns.of is not None
                self.emit(f"{scope.return_name}: {returns.of.annotation()}", level)
            else:
                self.emit(f"{scope.return_name}: {returns.annotation()} = {self.zero(returns)}", level)
        in_out = {c.st.lower() for d in self.decls.values() for c in d.methods.values() if any(p.section == "VAR_IN_OUT" for p in c.params)}
        scope.addressed = set(_by_reference_arguments(node.body, in_out))
        self._local_blocks(node.declarations, scope, level)
        for line in scope.output_inits:
            self.emit(line, level)
        statements = statements_of(node.body)
        self._emit_statements(statements, scope, level)
        if returns is not None and scope.return_name is not None:
            self.emit(f"return {scope.return_name}", level)
        elif not statements and not scope.output_inits and not any(isinstance(b, (tf.VariableDeclarations, tf.FunctionVariableDeclarations, tf.TemporaryVariableDeclarations)) for b in node.declarations):
            self.emit("pass", level)

    def _emit_properties(self, decl: Decl) -> None:
        accessors: dict[str, dict[str, Any]] = {}
        for node in decl.prop_nodes:
            parts = str(node.name).split(".")
            kind = parts[1].lower() if len(parts) > 1 else self.marked_accessors.get(id(node), "get")
            if kind not in ("get", "set"):
                raise self.fail(f"PROPERTY {node.name}: the accessor after the dot must be Get or Set", node)
            found = accessors.setdefault(parts[0].lower(), {})
            if kind in found:
                raise self.fail(
                    f"PROPERTY {parts[0]} has two {kind.capitalize()} accessors "
                    "(name them {0}.Get and {0}.Set, or mark them // Get and // Set)".format(parts[0]), node,
                )
            found[kind] = node
        for key, found in accessors.items():
            prop = decl.props[key]
            assert prop.type is not None
            self._need_type(prop.type)
            self.need("iecoop", "prop")
            getter = found.get("get")
            setter = found.get("set")
            annotation = prop.type.annotation()
            if getter is None:
                raise self.fail(f"PROPERTY {prop.st} has a Set accessor but no Get (iecoop needs the Get)", setter)
            self.emit("", 0)
            self.enter(getter)
            self.comments(getter, 1)
            self.emit("@prop", 1)
            access = accessor_access(getter)
            flags = self._access_decorator(access)
            if flags != "@method":
                self.emit(flags, 1)
            self.emit(f"def {prop.name}(self) -> {annotation}:", 1)
            if decl.kind == "interface" or access is not None and access & tf.AccessSpecifier.abstract:
                self.prototype(prop.type, 2)
            else:
                scope = Scope(decl, "getter", return_name=python_name(prop.st))
                scope.return_st = prop.st
                self._emit_callable_body(getter, scope, prop.type, 2)
            if setter is not None:
                self.emit("", 0)
                self.enter(setter)
                self.comments(setter, 1)
                self.emit(f"@{prop.name}.setter", 1)
                access = accessor_access(setter)
                flags = self._access_decorator(access)
                if flags != "@method":
                    self.emit(flags, 1)
                self.emit(f"def {prop.name}(self, {python_name(prop.st)}: {annotation}) -> None:", 1)
                if decl.kind == "interface" or access is not None and access & tf.AccessSpecifier.abstract:
                    self.emit("...", 2)
                else:
                    scope = Scope(decl, "setter")
                    scope.locals[prop.st.lower()] = Member(python_name(prop.st), prop.type, "VAR_INPUT", st=prop.st)
                    self._emit_callable_body(setter, scope, None, 2)

    def _emit_interface(self, decl: Decl) -> None:
        node = decl.node
        bases = []
        for base in decl.bases:
            if base.upper() == "__SYSTEM.IQUERYINTERFACE":
                self.need("iecoop", "IQueryInterface")
                bases.append("IQueryInterface")
                continue
            base_decl = self.decls.get(base.lower())
            if base_decl is None or base_decl.kind != "interface":
                raise self.fail(f"INTERFACE {decl.name} EXTENDS unknown interface {base!r}", node)
            bases.append(base_decl.name)
        if not bases:
            self.need("iecoop", "Interface")
            bases.append("Interface")
        if node.declarations:
            raise self.fail(f"INTERFACE {decl.name} declares variables; interfaces hold no state", node)
        self.comments(node, 0)
        self.emit(f"class {decl.name}({', '.join(bases)}):", 0)
        self.emit(f'"""INTERFACE {decl.name}."""', 1)
        for method in decl.method_nodes:
            self._emit_method(decl, method)
        self._emit_properties(decl)
        if not decl.method_nodes and not decl.prop_nodes:
            self.emit("pass", 1)

    def _emit_gvl(self, decl: Decl) -> None:
        self.need("iecoop", "GlobalVariables", "gvl")
        self.emit("@gvl", 0)
        self.emit(f"class {decl.name}(GlobalVariables):", 0)
        self.emit(f'"""VAR_GLOBAL list {decl.name}."""', 1)
        scope = Scope(decl, "const")
        for block in decl.node:
            self.unit = decl.units.get(id(block), self.unit)
            self.enter(block)
            self.comments(block, 1)
            attrs = block.attrs
            extra = []
            if attrs is not None:
                if attrs & tf.GlobalVariableAttributes.constant:
                    extra.append("constant=True")
                if attrs & tf.GlobalVariableAttributes.retain:
                    extra.append("retain=True")
                if attrs & tf.GlobalVariableAttributes.persistent:
                    extra.append("persistent=True")
            for item in block.items:
                self.line = item.meta.line if item.meta else self.line
                trailing = self.comments(item, 1, inline=True)
                index = len(self.out)
                init = item.init
                for name, type_ in self._item_types(item):
                    member = Member(name, type_, "VAR")
                    self.emit(self.field_line(member, init, scope, extra=", ".join(extra)), 1)
                self.trail(index, ": ".join(filter(None, (self.location(item), trailing))))

    def _emit_function(self, decl: Decl) -> None:
        node = decl.node
        self.line = node.meta.line if node.meta else None
        info = decl.methods["()"]
        scope = Scope(None, "function", return_name=decl.name if info.returns is not None else None)
        scope.return_st = decl.st
        scope.pou = decl.name
        self.comments(node, 0)
        params = self._params(info.params, node.declarations, scope)[2:]
        self._need_type(info.returns)
        ret_text = info.returns.annotation() if info.returns is not None else "None"
        statements = statements_of(node.body)
        is_external = decl.st.lower() in self.externals or not statements or any(
            re.fullmatch(r"\{\s*external\s*\}", p, re.IGNORECASE) for p in self.pragmas(node))
        if is_external:
            self.need("iecoop.st", "external")
            self.emit(f'@external("{decl.st}")', 0)
            self.emit_def(f"def {decl.name}({params}) -> {ret_text}:", 0)
            self.emit(f'"""FUNCTION {decl.st}: bound to a Python callable at load time."""', 1)
            self.emit(f'raise NotImplementedError("FUNCTION {decl.st} has no body: pass externals={{\'{decl.st}\': ...}}")', 1)
            return
        if any(p.section in ("VAR_OUTPUT", "VAR_IN_OUT") for p in info.params):
            self.need("iecoop", "function")
            self.emit("@function", 0)
        self.emit_def(f"def {decl.name}({params}) -> {ret_text}:", 0)
        self.emit(f'"""FUNCTION {decl.st}."""', 1)
        self._emit_callable_body(node, scope, info.returns, 1)

    # --- statements ---

    def _emit_statements(self, statements: Sequence[Any], scope: Scope, level: int) -> None:
        top, scope.started = not scope.started, True
        if top and any(isinstance(s, tf.LabeledStatement) for s in statements):
            self._emit_jumps(statements, scope, level)
            return
        if not statements:
            self.emit("pass", level)
            return
        start = len(self.out)
        for statement in statements:
            self.line = statement.meta.line if statement.meta else self.line
            trailing = self.comments(statement, level, inline=True)
            index = len(self.out)
            self.statement(statement, scope, level)
            self.trail(index, trailing)
        if all(line.strip().startswith("#") or not line.strip() for line in self.out[start:]):
            self.emit("pass", level)

    def statement(self, node: Any, scope: Scope, level: int) -> None:
        handler: Callable[[Any, Scope, int], None] | None = getattr(self, f"_st_{type(node).__name__}", None)
        if handler is None:
            raise self.fail(f"statement {type(node).__name__} is not supported", node)
        handler(node, scope, level)

    def _st_NoOpStatement(self, node: Any, scope: Scope, level: int) -> None:
        self.emit(self.expr(node.variable, scope).code, level)

    def _st_AssignmentStatement(self, node: Any, scope: Scope, level: int) -> None:
        self._hoisting, self._hoist_level = True, level  # __QUERYINTERFACE writes its operand first
        try:
            value = self.expr(node.expression, scope)
        finally:
            self._hoisting = False
        targets = list(node.variables)
        if len(targets) > 1:
            temp = scope.temp("value")
            self.emit(f"{temp} = {value.code}", level)
            value = Ex(temp, value.type)
        for target in targets:
            self.assign(target, value, scope, level)

    def assign(self, target: Any, value: Ex, scope: Scope, level: int) -> None:
        bit = self.bit_target(target, scope)
        if bit is not None:
            holder, index = bit
            self.need("iecoop.functions", "set_bit")
            self.emit(f"{holder} = set_bit({holder}, {index}, {value.code})", level)
            return
        lhs = self.expr(target, scope, store=True)
        if lhs.super_property:  # SUPER^.Prop := value: Python's super() refuses attribute writes
            name = lhs.code.split(".", 1)[1]
            self.emit(f'super_set(super(), "{name}", {self.store_value(lhs.type, value, False)})', level)
            return
        local = self.local_of(target, scope)
        if local is not None and local.section == "CONSTANT":
            raise self.fail(f"assignment to CONSTANT {local.name}", target)
        if local is not None and local.section == "LOCAL" and self._local_reference(local.type):
            raise self.fail(f"assignment to the whole REFERENCE TO local {local.name} (bind it with REF=, write its members)", target)
        by_reference = local is not None and local.section in ("VAR_OUTPUT", "VAR_IN_OUT")
        if local is not None and not by_reference and "." not in local.name and lhs.type is not None and lhs.type.kind != "reference" and self._copied(lhs.type):
            # a Python local names a view: ST's assignment of a STRUCT, ARRAY or block copies the value
            self.need("copy", "copy")
            value = Ex(f"copy({value.code})", value.type)
        self.emit(f"{lhs.code} = {self.store_value(lhs.type, value, local is not None and not by_reference and local.section != 'STAT')}", level)

    def local_of(self, target: Any, scope: Scope) -> Member | None:
        if isinstance(target, tf.SimpleVariable) and not target.dereferenced:
            return scope.locals.get(str(target.name).lower())
        return None

    def store_value(self, target: TypeRef | None, value: Ex, is_local: bool) -> str:
        """What to store: converted where ST converts implicitly, wrapped where a Python local would not."""
        if target is None:
            return value.code
        target = target.deref()
        limited = self.limit(target, value)
        if limited is not value:
            return limited.code
        if target.is_bool and value.type is not None and value.type.is_int:
            return f"bool({value.code})"
        if target.is_int and value.type is not None and value.type.is_real:
            self.need("iecoop.conversions", f"TO_{target.name}")
            return f"TO_{target.name}({value.code})"
        if is_local and target.is_int and not self._fits(value, target):
            self.need("iecoop.conversions", f"TO_{target.name}")
            return f"TO_{target.name}({value.code})"
        if is_local and target.name == "REAL" and not _exact_real(value.code) and not (
            value.type is not None and value.type.name == "REAL" and not value.compound
        ):
            self.need("iecoop.conversions", "TO_REAL")
            return f"TO_REAL({value.code})"
        if target.is_real and value.type is not None and value.type.is_int and is_local:
            return f"float({value.code})"
        return value.code

    def subrange(self, type_: TypeRef | None) -> TypeRef | None:
        """The subrange type behind ``type_`` (itself, or the subrange TYPE it names), or None."""
        if type_ is None:
            return None
        if type_.limits is not None:
            return type_
        decl = self.decl_of(type_)
        if decl is not None and decl.kind == "alias" and decl.alias_of is not None and decl.alias_of.limits is not None:
            return decl.alias_of
        return None

    def limit(self, target: TypeRef | None, value: Ex) -> Ex:
        """``value`` stored into a subrange: a constant must lie in it (a compile error on the PLC); another
        value is held to the limits, as TwinCAT's and CODESYS' implicit checks CheckRangeSigned / Unsigned do."""
        subrange = self.subrange(target)
        if subrange is None or subrange.limits is None:
            return value
        low, high = subrange.limits
        if re.fullmatch(r"-?\d+", value.code):
            if not int(low) <= int(value.code) <= int(high):
                raise self.fail(f"{value.code} is outside the subrange {subrange.name}({low}..{high})")
            return Ex(value.code, subrange)
        self.need("iecoop.functions", "LIMIT")
        return Ex(f"LIMIT({low}, {value.code}, {high})", subrange)

    def _fits(self, value: Ex, target: TypeRef) -> bool:
        if re.fullmatch(r"-?\d+", value.code):
            bits, signed = INTEGER_LAYOUT[target.name]
            number = int(value.code)
            low, high = (-(1 << (bits - 1)), (1 << (bits - 1)) - 1) if signed else (0, (1 << bits) - 1)
            return low <= number <= high
        return value.type is not None and value.type.name == target.name and not value.compound

    def _st_SetStatement(self, node: Any, scope: Scope, level: int) -> None:
        self._set_reset("S", True, node, scope, level)

    def _st_ResetStatement(self, node: Any, scope: Scope, level: int) -> None:
        self._set_reset("R", False, node, scope, level)

    def _set_reset(self, operator: str, value: bool, node: Any, scope: Scope, level: int) -> None:
        """``x S= c`` is ``S(self, "x", c)`` (iecoop.stdlib); a method's local is set with an IF."""
        condition = self.expr(node.expression, scope).code
        if self.local_of(node.variable, scope) is not None:
            self.emit(f"if {condition}:", level)
            self.emit(f"{self.expr(node.variable, scope).code} = {value}", level + 1)
            return
        holder, field = self.holder_field(node.variable, scope)
        self.need("iecoop.stdlib", operator)
        self.emit(f'{operator}({holder}, "{field}", {condition})', level)

    def _st_ReferenceAssignmentStatement(self, node: Any, scope: Scope, level: int) -> None:
        local = self.local_of(node.variable, scope)
        if _is_zero(node.expression):
            self._unbind(node, local, scope, level)
            return
        if local is not None and self._local_reference(local.type):
            assert local.type is not None
            bound = self.expr(node.expression, scope)
            if self.decl_of(bound.type) is not self.decl_of(local.type):
                raise self.fail(f"REF= of {local.name} needs a {local.type.deref().name} variable, got {bound.code}", node)
            self.emit(f"{local.name} = {bound.code}", level)
            return
        if isinstance(local, ReferenceLocal):
            self.emit(f"{local.name} = {self.address_of(node.expression, scope)}", level)
            return
        prop = self._reference_property(node.variable, scope)
        if prop is not None:
            # fbSample.MyProp REF= stSet: the Set accessor of a REFERENCE TO property gets stSet itself.
            bound = self.expr(node.expression, scope)
            if self.decl_of(bound.type) is not self.decl_of(prop.type):
                raise self.fail(f"REF= of {prop.code} needs a {prop.type.deref().name if prop.type else '?'} variable, got {bound.code}", node)
            self.emit(f"{prop.code} = {bound.code}", level)
            return
        holder, field = self.holder_field(node.variable, scope)
        self.need("iecoop", "ref_assign")
        target = self.address_of(node.expression, scope)
        self.emit(f'ref_assign({holder}, "{field}", {target})', level)

    def _reference_property(self, node: Any, scope: Scope) -> Ex | None:
        """``x.Prop`` when ``Prop`` is a PROPERTY of type REFERENCE TO a STRUCT, UNION or block, else None."""
        if not (isinstance(node, tf.MultiElementVariable) and isinstance(node.elements[-1], tf.FieldSelector)):
            return None
        rest = tf.MultiElementVariable(node.name, node.dereferenced, node.elements[:-1]) if len(node.elements) > 1 else node.name
        owner = self.decl_of(self.expr(rest, scope).type)
        found = self.find_member(owner, str(node.elements[-1].field)) if owner is not None else None
        if found is None or found[0] != "prop":
            return None
        target = self.expr(node, scope)
        return target if target.type is not None and self._local_reference(target.type) else None

    def _unbind(self, node: Any, local: Member | None, scope: Scope, level: int) -> None:
        """``r REF= 0``: the reference points nowhere again (``__ISVALIDREF`` is FALSE, reading it faults)."""
        if isinstance(local, ReferenceLocal):
            assert local.type is not None
            self.need("iecoop", "Pointer")
            self.emit(f"{local.name} = Pointer(0, None).typed({local.type.annotation()})", level)
            return
        if local is not None:
            raise self.fail(f"REF= 0 of {local.name}: a local REFERENCE TO a STRUCT, UNION or FB cannot be unbound "
                            "(make it a variable of the block)", node)
        holder, field = self.holder_field(node.variable, scope)
        self.need("iecoop", "ref_assign")
        self.emit(f'ref_assign({holder}, "{field}", None)', level)

    def _st_IfStatement(self, node: Any, scope: Scope, level: int) -> None:
        self.emit(f"if {self.condition(node.if_expression, scope)}:", level)
        self._emit_statements(node.statements.statements if node.statements else [], scope, level + 1)
        for clause in node.else_ifs:
            self.emit(f"elif {self.condition(clause.if_expression, scope)}:", level)
            self._emit_statements(clause.statements.statements if clause.statements else [], scope, level + 1)
        if node.else_clause is not None:
            self.emit("else:", level)
            self._emit_statements(node.else_clause.statements.statements if node.else_clause.statements else [], scope, level + 1)

    def condition(self, node: Any, scope: Scope) -> str:
        return self.expr(node, scope).code

    def _st_CaseStatement(self, node: Any, scope: Scope, level: int) -> None:
        selector = self.expr(node.expression, scope)
        subject = selector.code
        if selector.compound or "(" in subject:
            subject = scope.temp("case")
            self.emit(f"{subject} = {selector.code}", level)
        keyword = "if"
        for case in node.cases:
            tests = []
            for match in case.matches:
                if isinstance(match, tf.Subrange):
                    low = self.expr(match.start, scope).code
                    high = self.expr(match.stop, scope).code
                    tests.append(f"{low} <= {subject} <= {high}")
                else:
                    tests.append(f"{subject} == {self.case_label(match, selector.type, scope)}")
            self.emit(f"{keyword} {' or '.join(tests)}:", level)
            self._emit_statements(case.statements.statements if case.statements else [], scope, level + 1)
            keyword = "elif"
        if node.else_clause is not None:
            if keyword == "if":
                self._emit_statements(node.else_clause.statements.statements if node.else_clause.statements else [], scope, level)
                return
            self.emit("else:", level)
            self._emit_statements(node.else_clause.statements.statements if node.else_clause.statements else [], scope, level + 1)

    def case_label(self, match: Any, selector: TypeRef | None, scope: Scope) -> str:
        if isinstance(match, tf.EnumeratedValue):
            prefix, _, last = str(match.name).rpartition(".")
            decl = self.decls.get(prefix.lower())
            if match.type_name is None and prefix and (decl is None or decl.kind != "enum"):
                # a qualified constant (GVL_Const.cMax) or an enumeration value of a GVL's type
                ex = self.name_ref(prefix.split(".")[0], scope, match)
                for field in [*prefix.split(".")[1:], last]:
                    ex = self.member_ref(ex, field, match)
                return ex.code
            return self.enum_ref(str(match.type_name) if match.type_name else None, str(match.name), match)
        return self.expr(match, scope).code

    def _st_ForStatement(self, node: Any, scope: Scope, level: int) -> None:
        control = self.expr(node.control, scope, store=True)
        name = str(node.control.name).lower() if isinstance(node.control, tf.SimpleVariable) else None
        if any(isinstance(t, tf.SimpleVariable) and str(t.name).lower() == name for t in _assigned(node.statements)):
            # IEC 61131-3: the repeated statements shall not alter the control variable (a Python for would undo it)
            raise self.fail(f"the FOR loop writes its control variable {control.code.rsplit('.', 1)[-1]}", node)
        start = self.expr(node.from_, scope)
        stop = self.expr(node.to, scope)
        step = self.expr(node.step, scope) if node.step is not None else None
        if step is None:
            header = f"range({start.code}, {stop.p()} + 1)"
        elif re.fullmatch(r"-?\d+", step.code):
            sign = "+ 1" if int(step.code) > 0 else "- 1"
            if int(step.code) == 0:
                raise self.fail("FOR ... BY 0 never ends", node)
            header = f"range({start.code}, {stop.p()} {sign}, {step.code})"
        else:
            header = f"range({start.code}, {stop.p()} + (1 if {step.p()} > 0 else -1), {step.code})"
        # A loop that ends by its test leaves the variable at the first value that failed it (ST:
        # FOR i := 1 TO 10 leaves 11); after EXIT it keeps the value it had. Python's for ... else.
        literal = [int(ex.code) if re.fullmatch(r"-?\d+", ex.code) else None for ex in (start, stop, step or Ex("1"))]
        if None not in literal:
            first, last, by = (n for n in literal if n is not None)
            past = first + by * len(range(first, last + (1 if by > 0 else -1), by))
            after = Ex(str(past), start.type)
        else:
            loop = scope.temp("for")
            self.emit(f"{loop} = {header}", level)
            header = loop
            after = Ex(f"{loop}.start + {loop}.step * len({loop})", start.type or stop.type, True, PRECEDENCE["+"])
        self.emit(f"for {control.code} in {header}:", level)
        self._emit_statements(node.statements.statements, scope, level + 1)
        self.emit("else:  # the first value past the end, as ST leaves it", level)
        self.assign(node.control, after, scope, level + 1)

    def _st_WhileStatement(self, node: Any, scope: Scope, level: int) -> None:
        self.emit(f"while {self.condition(node.expression, scope)}:", level)
        self._emit_statements(node.statements.statements, scope, level + 1)

    def _st_RepeatStatement(self, node: Any, scope: Scope, level: int) -> None:
        self.emit("while True:", level)
        self._emit_statements(node.statements.statements, scope, level + 1)
        self.emit(f"if {self.condition(node.expression, scope)}:", level + 1)
        self.emit("break", level + 2)

    def _st_ExitStatement(self, node: Any, scope: Scope, level: int) -> None:
        self.emit("break", level)

    def _st_ContinueStatement(self, node: Any, scope: Scope, level: int) -> None:
        self.emit("continue", level)

    def _st_ReturnStatement(self, node: Any, scope: Scope, level: int) -> None:
        self.emit(f"return {scope.return_name}" if scope.return_name else "return", level)

    def _st_FunctionCallStatement(self, node: Any, scope: Scope, level: int) -> None:
        call = self.call(node, scope, level=level)
        if call is not None and call.code:
            self.emit(call.code, level)

    def _st_ChainedFunctionCallStatement(self, node: Any, scope: Scope, level: int) -> None:
        self.emit(self.expr(tf.ChainedFunctionCall(node.invocations), scope).code, level)

    def _st_Tree(self, node: Any, scope: Scope, level: int) -> None:
        """A statement of the grammar overlay: ``__TRY ... __CATCH(exc) ... __FINALLY ... __ENDTRY``."""
        if str(node.data) != "try_statement":
            raise self.fail(f"statement {node.data} is not supported", node)
        body, catch, final = (list(node.children) + [None, None, None])[:3]
        self.need("iecoop", "try_catch", "ExceptionCode")
        block = scope.temp("try")
        inner = level
        if final is not None:
            self.emit("try:", level)
            inner = level + 1
        self.emit(f"with try_catch() as {block}:  # __TRY", inner)
        self._emit_statements(body.statements if body is not None else [], scope, inner + 1)
        if catch is not None:
            variable, handler = (list(catch.children) + [None])[:2]
            self.emit(f"if {block}.code != ExceptionCode.RTSEXCPT_NOEXCEPTION:  # __CATCH", inner)
            self.assign(variable, Ex(f"{block}.code", TypeRef("elem", "UDINT")), scope, inner + 1)
            if handler is not None:
                self._emit_statements(handler.statements, scope, inner + 1)
        if final is not None:
            self.emit("finally:  # __FINALLY", level)
            handler = final.children[0] if final.children else None
            self._emit_statements(handler.statements if handler is not None else [], scope, level + 1)

    def _emit_jumps(self, statements: Sequence[Any], scope: Scope, level: int) -> None:
        """A body with labels: its parts, from one label to the next, in a loop that a JMP restarts at a label."""
        parts: list[tuple[str, list[Any]]] = [("", [])]
        for statement in statements:
            if isinstance(statement, tf.LabeledStatement):
                label = str(statement.label)
                if label.lower() in scope.labels:
                    raise self.fail(f"label {label} is declared twice", statement)
                scope.labels.add(label.lower())
                parts.append((label, [statement.statement] if statement.statement is not None else []))
            else:
                parts[-1][1].append(statement)
            if _jumps_in_loop(statement):
                raise self.fail("JMP inside a FOR, WHILE or REPEAT loop is not supported (labels and JMPs outside loops)", statement)
        scope.jump = scope.temp("jump")
        self.emit(f'{scope.jump} = ""  # JMP: the label the code runs from next', level)
        self.emit("while True:", level)
        for index, (label, body) in enumerate(parts):
            if index == 0 and not body:
                continue
            self.emit(f'if {scope.jump} == "{label.lower()}":' + (f"  # {label}:" if label else ""), level + 1)
            self._emit_statements(body, scope, level + 2)
            if index + 1 < len(parts) and not (body and isinstance(body[-1], (tf.ReturnStatement, tf.JumpStatement))):
                self.emit(f'{scope.jump} = "{parts[index + 1][0].lower()}"', level + 2)  # on to the next label
        self.emit("break", level + 1)

    def _st_JumpStatement(self, node: Any, scope: Scope, level: int) -> None:
        label = str(node.label)
        if label.lower() not in scope.labels:
            raise self.fail(f"JMP {label}: no label {label} at the top of this body (labels inside IF, CASE or loops are not supported)", node)
        self.emit(f'{scope.jump} = "{label.lower()}"  # JMP {label}', level)
        self.emit("continue", level)

    def _st_LabeledStatement(self, node: Any, scope: Scope, level: int) -> None:
        raise self.fail(f"label {node.label} inside IF, CASE or a loop is not supported (labels at the top of a body)", node)

    # --- expressions ---

    def expr(self, node: Any, scope: Scope, *, store: bool = False, expected: TypeRef | None = None) -> Ex:
        handler = getattr(self, f"_ex_{type(node).__name__}", None)
        if handler is None:
            raise self.fail(f"expression {type(node).__name__} is not supported", node)
        result: Ex = handler(node, scope) if not store else handler(node, scope, store=True) if type(node).__name__ in ("SimpleVariable", "MultiElementVariable") else handler(node, scope)
        return result

    def coerce(self, value: Ex, type_: TypeRef | None) -> Ex:
        if type_ is not None and type_.is_real and re.fullmatch(r"-?\d+", value.code):
            return Ex(f"{value.code}.0", type_)
        return value

    def _ex_ParenthesizedExpression(self, node: Any, scope: Scope) -> Ex:
        inner = self.expr(node.expr, scope)
        return Ex(inner.code, inner.type, inner.compound)

    def _ex_BracketedExpression(self, node: Any, scope: Scope) -> Ex:
        return self.expr(node.expression, scope)

    def _literal_type(self, type_name: Any, default: TypeRef) -> TypeRef:
        if type_name is None:
            return default
        found = self._elem_or_none(str(type_name))
        return found or default

    def _ex_Integer(self, node: Any, scope: Scope) -> Ex:
        text = str(node.value).replace("_", "")
        type_ = self._literal_type(node.type_name, LINT)
        if type_.is_bool:
            return Ex("True" if int(text) else "False", BOOL)
        if type_.is_real:
            return Ex(f"{int(text)}.0", type_)
        return Ex(str(int(text)), type_ if node.type_name is not None else None)  # 007 is 7; Python refuses the zeros

    def _based(self, node: Any, prefix: str, base: int) -> Ex:
        text = str(node.value).replace("_", "")
        type_ = self._literal_type(node.type_name, LINT)
        return Ex(f"{prefix}{text.upper() if base == 16 else text}", type_ if node.type_name is not None else None)

    def _ex_HexInteger(self, node: Any, scope: Scope) -> Ex:
        return self._based(node, "0x", 16)

    def _ex_BinaryInteger(self, node: Any, scope: Scope) -> Ex:
        return self._based(node, "0b", 2)

    def _ex_OctalInteger(self, node: Any, scope: Scope) -> Ex:
        return self._based(node, "0o", 8)

    def _ex_HexBitString(self, node: Any, scope: Scope) -> Ex:
        return self._based(node, "0x", 16)

    def _ex_BinaryBitString(self, node: Any, scope: Scope) -> Ex:
        return self._based(node, "0b", 2)

    def _ex_OctalBitString(self, node: Any, scope: Scope) -> Ex:
        return self._based(node, "0o", 8)

    def _ex_BitString(self, node: Any, scope: Scope) -> Ex:
        return self._based(node, "", 10)

    def _ex_Real(self, node: Any, scope: Scope) -> Ex:
        text = str(node.value).replace("_", "")
        if "." not in text and "e" not in text.lower():
            text += ".0"
        return Ex(text, self._literal_type(node.type_name, LREAL))

    def _ex_Boolean(self, node: Any, scope: Scope) -> Ex:
        return Ex("True" if str(node.value).upper() in ("TRUE", "1") else "False", BOOL)

    def _ex_String(self, node: Any, scope: Scope) -> Ex:
        return Ex(python_string(str(node.value)), STRING)

    def _duration(self, node: Any, units: Sequence[tuple[str, str]]) -> str:
        parts = []
        for attr, suffix in units:
            value = getattr(node, attr, None)
            if value is not None:
                parts.append(f"{str(value).replace('_', '')}{suffix}")
        return "".join(parts) or "0ms"

    def _ex_Duration(self, node: Any, scope: Scope) -> Ex:
        self.need("iecoop", "T")
        text = self._duration(node, [("days", "d"), ("hours", "h"), ("minutes", "m"), ("seconds", "s"), ("milliseconds", "ms")])
        code = f'T("{text}")'
        return Ex(f"-{code}" if node.negative else code, TypeRef("elem", "TIME"), compound=node.negative)

    def _ex_Lduration(self, node: Any, scope: Scope) -> Ex:
        self.need("iecoop", "LTIME")
        text = self._duration(node, [("days", "d"), ("hours", "h"), ("minutes", "m"), ("seconds", "s"),
                                     ("milliseconds", "ms"), ("microseconds", "us"), ("nanoseconds", "ns")])
        code = f'LTIME("{text}")'
        return Ex(f"-{code}" if node.negative else code, TypeRef("elem", "LTIME"), compound=node.negative)

    def _ex_Date(self, node: Any, scope: Scope) -> Ex:
        self.need("iecoop", "D")
        return Ex(f'D("{node.year}-{node.month}-{node.day}")', TypeRef("elem", "DATE"))

    def _ex_TimeOfDay(self, node: Any, scope: Scope) -> Ex:
        self.need("iecoop", "TOD")
        second = f":{node.second}" if node.second is not None else ""
        return Ex(f'TOD("{node.hour}:{node.minute}{second}")', TypeRef("elem", "TOD"))

    def _ex_DateTime(self, node: Any, scope: Scope) -> Ex:
        self.need("iecoop", "DT")
        date, time = node.date, node.time
        second = f":{time.second}" if time.second is not None else ""
        return Ex(f'DT("{date.year}-{date.month}-{date.day}-{time.hour}:{time.minute}{second}")', TypeRef("elem", "DT"))

    def _ex_UnaryOperation(self, node: Any, scope: Scope) -> Ex:
        op = str(node.op).upper()
        inner = self.expr(node.expr, scope)
        if op == "-":
            if re.fullmatch(r"\d+(\.\d+)?", inner.code):
                return Ex(f"-{inner.code}", inner.type)
            return Ex(f"-{inner.wrap(PRECEDENCE['unary'])}", inner.type, True, PRECEDENCE["unary"])
        if op == "+":
            return inner
        if op == "NOT":
            if inner.type is not None and inner.type.deref().is_int:
                return Ex(f"~{inner.wrap(PRECEDENCE['unary'])}", inner.type, True, PRECEDENCE["unary"])
            return Ex(f"not {inner.wrap(PRECEDENCE['not'])}", BOOL, True, PRECEDENCE["not"])
        raise self.fail(f"unary operator {op}", node)

    def _ex_BinaryOperation(self, node: Any, scope: Scope) -> Ex:
        op = str(node.op).upper()
        left = self.expr(node.left, scope)
        right = self.expr(node.right, scope)
        lt = left.type.deref() if left.type is not None else None
        rt = right.type.deref() if right.type is not None else None
        if op in COMPARISONS:
            py = COMPARISONS[op]
            for side, other in ((left, right), (right, left)):
                if other.code == "0" and side.type is not None and self._is_handle(side.type):
                    self.need("iecoop", "NULL")
                    return Ex(f"{side.p()} {py} NULL", BOOL, True)
            level = PRECEDENCE["compare"]  # both sides wrapped when they compare too: Python would chain them
            return Ex(f"{left.wrap(level + 1)} {py} {right.wrap(level + 1)}", BOOL, True, level)
        if op in ("AND", "&", "OR", "XOR", "AND_THEN", "OR_ELSE"):
            logical = (lt is None or lt.is_bool) and (rt is None or rt.is_bool)
            if op in ("AND", "&", "OR") and logical and self._has_effect(node.right, scope):
                # ST evaluates both operands of AND / OR (only AND_THEN / OR_ELSE stop early): a call on
                # the right runs even when the left decides, so the operands are combined with & / |
                symbol = "&" if op != "OR" else "|"
                level = PRECEDENCE[symbol]
                return Ex(f"{self._as_bool(left).wrap(level)} {symbol} {self._as_bool(right).wrap(level + 1)}", BOOL, True, level)
            if op in ("AND_THEN", "OR_ELSE") or logical:
                word = {"AND": "and", "&": "and", "AND_THEN": "and", "OR": "or", "OR_ELSE": "or", "XOR": "!="}[op]
                level = PRECEDENCE[word] if word != "!=" else PRECEDENCE["compare"]
                if word == "!=":
                    return Ex(f"{left.wrap(level + 1)} != {right.wrap(level + 1)}", BOOL, True, level)
                return Ex(f"{left.wrap(level)} {word} {right.wrap(level + 1)}", BOOL, True, level)
            symbol = {"AND": "&", "&": "&", "OR": "|", "XOR": "^"}[op]
            level = PRECEDENCE[symbol]
            return Ex(f"{left.wrap(level)} {symbol} {right.wrap(level + 1)}", self.wider(lt, rt), True, level)
        if op in ("+", "-", "*"):
            level = PRECEDENCE[op]
            return Ex(f"{left.wrap(level)} {op} {right.wrap(level + 1)}", self.wider(lt, rt), True, level)
        if op == "/":
            if (lt is not None and lt.is_real) or (rt is not None and rt.is_real):
                level = PRECEDENCE["/"]
                return Ex(f"{left.wrap(level)} / {right.wrap(level + 1)}", self.wider(lt, rt), True, level)
            self.need("iecoop.conversions", "DIV")
            return Ex(f"DIV({left.code}, {right.code})", self.wider(lt, rt))
        if op == "MOD":
            self.need("iecoop.conversions", "MOD")
            return Ex(f"MOD({left.code}, {right.code})", self.wider(lt, rt))
        if op == "**":
            level = PRECEDENCE["**"]
            return Ex(f"{left.wrap(level + 1)} ** {right.wrap(level)}", LREAL, True, level)
        raise self.fail(f"operator {op}", node)

    def _has_effect(self, node: Any, scope: Scope) -> bool:
        """Whether evaluating ``node`` runs code: a call, or a read of a PROPERTY (its Get accessor)."""
        if _has_call(node):
            return True
        for variable in _variables(node):
            if isinstance(variable, tf.SimpleVariable):
                owner, name = scope.owner, str(variable.name)
                if name.lower() in scope.locals:
                    continue
            elif isinstance(variable.elements[-1], tf.FieldSelector) and not str(variable.elements[-1].field).isdigit():
                rest = tf.MultiElementVariable(variable.name, False, variable.elements[:-1]) if len(variable.elements) > 1 else variable.name
                owner = self.decl_of(self.expr(rest, scope).type)
                field = variable.elements[-1].field
                name = str(field.name) if isinstance(field, tf.SimpleVariable) else str(field)
            else:
                continue
            found = self.find_member(owner, name) if owner is not None else None
            if found is not None and found[0] == "prop":
                return True
        return False

    def _as_bool(self, operand: Ex) -> Ex:
        """``operand`` as a Python bool, for ``&`` / ``|``: a call whose type is not known is wrapped in ``bool()``."""
        if operand.type is not None and operand.type.deref().is_bool:
            return operand
        return Ex(f"bool({operand.code})", BOOL)

    def _is_handle(self, type_: TypeRef) -> bool:
        if type_.kind == "pointer":
            return True
        decl = self.decl_of(type_)
        return decl is not None and decl.kind == "interface"

    def wider(self, left: TypeRef | None, right: TypeRef | None) -> TypeRef | None:
        if left is None:
            return right
        if right is None:
            return left
        if left.is_real or right.is_real:
            return LREAL if "LREAL" in (left.name, right.name) or not (left.is_real and right.is_real) and False else (left if left.is_real else right)
        if left.is_int and right.is_int:
            return left if INTEGER_LAYOUT[left.name][0] >= INTEGER_LAYOUT[right.name][0] else right
        return left

    # variables

    def _ex_SimpleVariable(self, node: Any, scope: Scope, store: bool = False) -> Ex:
        base = self.name_ref(str(node.name), scope, node)
        if node.dereferenced:
            return self.deref(base, node)
        return base

    def deref(self, base: Ex, node: Any) -> Ex:
        if base.code in ("self", "super()"):
            return base
        target = base.type.of if base.type is not None and base.type.kind == "pointer" else None
        if base.type is not None and base.type.kind != "pointer":
            raise self.fail(f"^ applied to {base.code}, which is not a POINTER", node)
        return Ex(f"{base.p()}.deref", target)

    def name_ref(self, name: str, scope: Scope, node: Any) -> Ex:
        key = name.lower()
        if key == "this":
            return Ex("self", TypeRef("user", scope.owner.name) if scope.owner else None)
        if key == "super":
            base = self.decls.get(scope.owner.bases[0].lower()) if scope.owner and scope.owner.bases else None
            return Ex("super()", TypeRef("user", base.name) if base is not None else None)
        local = scope.locals.get(key)
        if local is not None:
            if local.section in ("VAR_OUTPUT", "VAR_IN_OUT"):
                return Ex(f"{local.name}.deref", local.type)
            return Ex(local.name, local.type)
        if scope.owner is not None and scope.owner.kind in ("fb", "program", "interface", "struct", "union"):
            found = self.find_member(scope.owner, name)
            if found is not None and not (scope.kind == "const" and scope.owner.kind in ("struct", "union")):
                kind, member = found
                if kind == "method":
                    return Ex(f"self.{member.name}", None)
                assert isinstance(member, Member)
                return Ex(f"self.{member.name}", member.type)
        if key in self.globals:
            gvl_name, member = self.globals[key]
            return Ex(f"{gvl_name}.{member.name}", member.type)
        decl = self.decls.get(key)
        if decl is not None and decl.kind != "stdfb":
            return Ex(decl.name, TypeRef("user", decl.name) if decl.kind in ("gvl", "enum", "program") else None)
        if key in self.enum_values:
            enum, value = self.enum_values[key]
            return Ex(f"{enum}.{value}", TypeRef("user", enum))
        if key == "__system":
            return Ex("__SYSTEM", TypeRef("user", "__SYSTEM"))
        raise self.fail(f"unknown variable {name!r}", node)

    def member_ref(self, base: Ex, field: str, node: Any, store: bool = False) -> Ex:
        """``base.field``: a system member, an enumeration value, or a member or method of a declared type."""
        system = self._system_member_ref(base, field, node, store)
        if system is not None:
            return system
        decl = self.decl_of(base.type)
        if decl is None:
            if base.type is None:
                raise self.fail(f"cannot tell the type of {base.code} to read its member {field!r}", node)
            raise self.fail(f"{base.type.annotation()} has no member {field!r}", node)
        if decl.kind == "enum":
            match = next((v for v in decl.values if v.lower() == field.lower()), None)
            if match is None:
                raise self.fail(f"enumeration {decl.st} has no value {field!r}", node)
            return Ex(f"{decl.name}.{python_name(match, attribute=True)}", TypeRef("user", decl.name))
        found = self.find_member(decl, field)
        if decl.kind == "program" and found is not None and found[0] in ("member", "method") and base.code == decl.name:
            self.named_programs.add(decl.name)
        if found is None:
            raise self.fail(f"{decl.name} has no member {field!r}", node)
        kind, member = found
        if base.code == "super()":
            return self._super_member_ref(kind, member, store)
        if kind == "method":
            return Ex(f"{base.p()}.{member.name}", None)
        assert isinstance(member, Member)
        return Ex(f"{base.p()}.{member.name}", member.type)

    def _system_member_ref(self, base: Ex, field: str, node: Any, store: bool) -> Ex | None:
        """``__SYSTEM.ExceptionCode``, its values, and the members of a ``__SYSTEM.VAR_INFO``; None for any other base."""
        if base.type is not None and base.type.name == "__SYSTEM":
            if field.lower() == "exceptioncode":
                self.need("iecoop", "ExceptionCode")
                return Ex("ExceptionCode", TypeRef("user", "__SYSTEM.EXCEPTIONCODE"))
        if base.code == "ExceptionCode":
            return Ex(f"ExceptionCode.{field.upper()}", TypeRef("user", "ExceptionCode"))
        if base.type is not None and base.type.kind == "varinfo":
            info = next((m for m in VAR_INFO_MEMBERS if m.lower() == field.lower()), None)
            if info is None or store:
                raise self.fail(f"__SYSTEM.VAR_INFO {'member ' + field + ' is read-only' if info else 'has no member ' + repr(field)}", node)
            return Ex(f"{base.p()}.{info}", STRING if info in ("Symbol", "TypeName") else TypeRef("elem", VAR_INFO_MEMBERS[info]))
        return None

    def _super_member_ref(self, kind: str, member: Any, store: bool) -> Ex:
        """``SUPER^.name``: the parent's method or property; a variable is the instance's own."""
        if kind == "method":
            return Ex(f"super().{member.name}", None)
        if kind == "member":
            assert isinstance(member, Member)
            return Ex(f"self.{member.name}", member.type)  # a variable is not virtual: SUPER^.x is THIS^.x
        assert isinstance(member, Member)
        if store:
            self.need("iecoop", "super_set")
            return Ex(f"super().{member.name}", member.type, super_property=True)  # written as super_set(super(), ...)
        return Ex(f"super().{member.name}", member.type)

    def _ex_MultiElementVariable(self, node: Any, scope: Scope, store: bool = False) -> Ex:
        if str(node.name.name).lower() == "_taskinfo":
            return self.task_info(node, store)
        current = self._ex_SimpleVariable(node.name, scope)
        elements = list(node.elements)
        for index, element in enumerate(elements):
            if isinstance(element, tf.SubscriptList):
                indices = [self.expr(s, scope).code for s in element.subscripts]
                element_type = current.type.deref().of if current.type is not None and current.type.deref().kind == "array" else None
                current = Ex(f"{current.p()}[{', '.join(indices)}]", element_type)
                if element.dereferenced:
                    current = self.deref(current, node)
                continue
            field = element.field
            field_name = str(field.name) if isinstance(field, tf.SimpleVariable) else str(field)
            if field_name.isdigit():
                if store and index == len(elements) - 1:
                    raise self.fail("bit assignment in this position", node)
                self.need("iecoop.functions", "get_bit")
                current = Ex(f"get_bit({current.code}, {field_name})", BOOL)
                continue
            if element.dereferenced:
                # blark marks the ^ of ``p^.x[i]`` on the field selector that follows it: dereference first.
                current = self.deref(current, node)
            current = self.member_ref(current, field_name, node, store=store and index == len(elements) - 1)
            if isinstance(field, tf.SimpleVariable) and field.dereferenced:
                current = self.deref(current, node)
        return current

    def task_info(self, node: Any, store: bool) -> Ex:
        """``_TaskInfo[GETCURTASKINDEXEX()].CycleTime`` (TwinCAT's Tc2_System): the running task's ``current_task()``."""
        elements = list(node.elements)
        index = elements[0].subscripts if elements and isinstance(elements[0], tf.SubscriptList) else []
        call = index[0] if len(index) == 1 else None
        if not (isinstance(call, tf.FunctionCall) and str(call.name).upper() == "GETCURTASKINDEXEX" and not call.parameters):
            raise self.fail("_TaskInfo indexed by anything but GETCURTASKINDEXEX() (iecoop knows the running task only)", node)
        field = elements[1].field if len(elements) == 2 and isinstance(elements[1], tf.FieldSelector) else None
        name = str(field.name) if isinstance(field, tf.SimpleVariable) else str(field)
        member = next((m for m in TASK_INFO_MEMBERS if m.lower() == name.lower()), None) if field is not None else None
        if member is None:
            raise self.fail(f"_TaskInfo[...].{name if field is not None else ''}: iecoop's TaskInfo has {', '.join(TASK_INFO_MEMBERS)}", node)
        if store:
            raise self.fail(f"assignment to _TaskInfo[...].{member} (the PLC's task information is read-only)", node)
        self.need("iecoop.runtime", "current_task")
        type_ = STRING if member == "TaskName" else TypeRef("elem", TASK_INFO_MEMBERS[member])
        return Ex(f"current_task().{member}", type_)

    def bit_target(self, target: Any, scope: Scope) -> tuple[str, str] | None:
        if not isinstance(target, tf.MultiElementVariable) or not target.elements:
            return None
        last = target.elements[-1]
        if not isinstance(last, tf.FieldSelector):
            return None
        field = last.field
        name = str(field.name) if isinstance(field, tf.SimpleVariable) else str(field)
        if not name.isdigit():
            return None
        holder = tf.MultiElementVariable(target.name, False, target.elements[:-1]) if len(target.elements) > 1 else target.name
        return self.expr(holder, scope).code, name

    def holder_field(self, node: Any, scope: Scope) -> tuple[str, str]:
        """``(holder code, field name)`` of a variable that is a field of something."""
        if isinstance(node, tf.SimpleVariable):
            ex = self.name_ref(str(node.name), scope, node)
        elif isinstance(node, tf.MultiElementVariable) and isinstance(node.elements[-1], tf.FieldSelector):
            ex = self.expr(node, scope)
        else:
            raise self.fail("this variable has no holder to take its address from", node)
        if "." not in ex.code or ex.code.endswith(")"):
            raise self.fail(f"{ex.code} is a local variable; ADR / REF= need a variable of a block, struct or GVL", node)
        holder, field = ex.code.rsplit(".", 1)
        return holder, field

    def address_of(self, node: Any, scope: Scope) -> str:
        prop = self._reference_property(node, scope)
        if prop is not None:
            return prop.code  # REF= x.Prop: a REFERENCE TO property's Get gives the variable itself
        if isinstance(node, (tf.FunctionCall, tf.ChainedFunctionCall)):
            # REF= F(): a FUNCTION or METHOD that returns REFERENCE TO a STRUCT or block gives the variable itself
            ex = self.expr(node, scope)
            if ex.type is None or not self._local_reference(ex.type):
                raise self.fail(f"the address of a call's result ({ex.code}): only a call that returns REFERENCE TO a STRUCT, UNION or FUNCTION_BLOCK can be bound", node)
            return ex.code
        if isinstance(node, tf.SimpleVariable) and node.dereferenced and str(node.name).lower() != "this":
            return self.name_ref(str(node.name), scope, node).code  # ADR(p^) is p
        if isinstance(node, tf.MultiElementVariable) and getattr(node.elements[-1], "dereferenced", False):
            # ADR(a[i]^), ADR(s.p^): the pointer itself
            last = dataclasses.replace(node.elements[-1], dereferenced=False)
            return self.expr(tf.MultiElementVariable(node.name, node.dereferenced, [*node.elements[:-1], last]), scope).code
        self.need("iecoop", "adr")
        if isinstance(node, tf.MultiElementVariable) and isinstance(node.elements[-1], tf.SubscriptList) and len(node.elements[-1].subscripts) == 1:
            rest = tf.MultiElementVariable(node.name, False, node.elements[:-1]) if len(node.elements) > 1 else node.name
            holder, field = self.holder_field(rest, scope)
            index = self.expr(node.elements[-1].subscripts[0], scope).code
            return f'adr({holder}, "{field}", {index})'
        if isinstance(node, tf.SimpleVariable) and str(node.name).lower() == "this" and node.dereferenced:
            return "adr(self)"
        if isinstance(node, tf.SimpleVariable) and str(node.name).lower() in scope.locals:
            local = scope.locals[str(node.name).lower()]
            if local.section in ("VAR_OUTPUT", "VAR_IN_OUT"):
                return local.name  # ADR(nHigh) of an output / in-out: the pointer the call got
            decl = self.decl_of(local.type)
            if decl is not None and decl.kind in ("struct", "union", "fb"):
                return f"adr({local.name})"
        holder, field = self.holder_field(node, scope)
        return f'adr({holder}, "{field}")'

    # calls

    def _ex_FunctionCall(self, node: Any, scope: Scope) -> Ex:
        result = self.call(node, scope, level=None)
        assert result is not None
        return result

    def _ex_ChainedFunctionCall(self, node: Any, scope: Scope) -> Ex:
        current: Ex | None = None
        for invocation in node.invocations:
            if current is None:
                current = self.call(invocation, scope, level=None)
            else:
                method = self.member_ref(current, str(invocation.name.name), invocation)
                owner = self.decl_of(current.type)
                found = self.find_member(owner, str(invocation.name.name)) if owner is not None else None
                info = found[1] if found is not None and isinstance(found[1], Callable_) else None
                args = self.arguments(invocation.parameters, info.params if info else None, scope, invocation)
                current = Ex(f"{method.code}({', '.join(args)})", info.returns if info else None)
        assert current is not None
        return current

    def arguments(self, params: Sequence[Any], declared: Sequence[Member] | None, scope: Scope, node: Any) -> list[str]:
        args = []
        for index, param in enumerate(params):
            if isinstance(param, tf.OutputParameterAssignment):
                name = str(param.name.name)
                match = next((p for p in declared or [] if p.st.lower() == name.lower()), None)
                if match is None or match.section != "VAR_OUTPUT":
                    raise self.fail(f"call has no output {name!r}", node)
                if param.inverted:
                    raise self.fail("an inverted output (=> NOT) is not supported", node)
                if param.value is not None:  # `nLow =>` with no variable: the output is dropped
                    args.append(f"{match.name}={self.by_reference_argument(param.value, scope, '=>')}")
                continue
            expected = None
            if param.name is not None:
                name = str(param.name.name)
                match = next((p for p in declared or [] if p.st.lower() == name.lower()), None)
                if declared is not None and match is None:
                    raise self.fail(f"call has no input {name!r}", node)
                if match is not None and match.section == "VAR_OUTPUT":
                    raise self.fail(f"output {name!r} is assigned with =>, not :=", node)
                if match is not None and match.section == "VAR_IN_OUT":
                    args.append(f"{match.name}={self.by_reference_argument(param.value, scope, ':=')}")
                    continue
                value = self.expr(param.value, scope)
                expected = match.type if match is not None else None
                # A subrange input is held to its limits at the call, as a store into it is (CheckRange).
                args.append(f"{match.name if match else python_name(name)}={self.limit(expected, self.coerce(value, expected)).code}")
            else:
                if declared is not None and index < len(declared):
                    if declared[index].section == "VAR_IN_OUT":
                        args.append(self.by_reference_argument(param.value, scope, ":="))
                        continue
                    expected = declared[index].type
                args.append(self.limit(expected, self.coerce(self.expr(param.value, scope), expected)).code)
        return args

    def by_reference_argument(self, value: Any, scope: Scope, arrow: str) -> str:
        """The caller's variable an output (``=>``) or an in-out (``:=``) of a METHOD / FUNCTION is bound to."""
        if isinstance(value, tf.SimpleVariable) and not value.dereferenced:
            local = scope.locals.get(str(value.name).lower())
            if local is not None and local.section not in ("VAR_OUTPUT", "VAR_IN_OUT", "STAT") and self.decl_of(local.type) is None:
                raise self.fail(
                    f"{arrow} {value.name}: a local variable of a {'METHOD or FUNCTION' if scope.pou else 'PROPERTY accessor'} has no address here; "
                    "declare it in the block, or pass it through the block's own variable", value)
        return self.address_of(value, scope)

    def call(self, node: Any, scope: Scope, level: int | None) -> Ex | None:
        target = node.name
        if isinstance(target, tf.SimpleVariable) and not target.dereferenced:
            name = str(target.name)
            key = name.lower()
            standard = self.standard_call(name, node, scope, level)
            if standard is not None:
                return standard
            if key == "super" and node.dereferenced or (key == "super"):
                return Ex("super().body()", None)
            decl = self.decls.get(key)
            if decl is not None and decl.kind == "function" and key not in scope.locals:
                info = decl.methods["()"]
                args = self.arguments(node.parameters, info.params, scope, node)
                return Ex(f"{decl.name}({', '.join(args)})", info.returns)
        if isinstance(target, tf.SimpleVariable) and str(target.name).lower() == "super" and target.dereferenced:
            return Ex("super().body()", None)
        callee = self.expr(target, scope)
        if node.dereferenced:
            callee = self.deref(callee, node)
        if callee.code.endswith("super()"):
            return Ex("super().body()", None)
        decl = self.decl_of(callee.type)
        if decl is not None and decl.kind in ("fb", "stdfb") and callee.type is not None and callee.type.kind in ("user", "reference"):
            return self.fb_call(callee, decl, node, scope, level)
        # a method: find its declaration through the owner to type the result
        method = self.method_info(target, scope)
        args = self.arguments(node.parameters, method.params if method else None, scope, node)
        return Ex(f"{callee.code}({', '.join(args)})", method.returns if method else None)

    def method_info(self, target: Any, scope: Scope) -> Callable_ | None:
        if isinstance(target, tf.SimpleVariable):
            owner, name = scope.owner, str(target.name)
        elif isinstance(target, tf.MultiElementVariable) and isinstance(target.elements[-1], tf.FieldSelector):
            rest = tf.MultiElementVariable(target.name, False, target.elements[:-1]) if len(target.elements) > 1 else target.name
            owner_ex = self.expr(rest, scope)
            owner = self.decl_of(owner_ex.type)
            field = target.elements[-1].field
            name = str(field.name) if isinstance(field, tf.SimpleVariable) else str(field)
        else:
            return None
        if owner is None:
            return None
        found = self.find_member(owner, name)
        if found is not None and found[0] == "method":
            assert isinstance(found[1], Callable_)
            return found[1]
        return None

    def fb_call(self, callee: Ex, decl: Decl, node: Any, scope: Scope, level: int | None) -> Ex | None:
        inputs, outputs = [], []
        for param in node.parameters:
            if param.name is None:
                raise self.fail(f"a call of function block {callee.code} needs named inputs (name := value)", node)
            found = self.find_member(decl, str(param.name.name))
            if found is None or not isinstance(found[1], Member):
                raise self.fail(f"{decl.name} has no input or output {param.name.name!r}", node)
            member = found[1]
            if isinstance(param, tf.OutputParameterAssignment):
                if param.inverted:
                    raise self.fail("an inverted output (=> NOT) is not supported", node)
                outputs.append((member, param.value))
                continue
            if member.section == "VAR_IN_OUT":
                value = self.address_of(param.value, scope)
            else:
                value = self.limit(member.type, self.coerce(self.expr(param.value, scope), member.type)).code
            inputs.append(f"{member.name}={value}")
        code = f"{callee.code}({', '.join(inputs)})"
        if outputs:
            if level is None:
                raise self.fail(f"outputs (=>) of {callee.code} in an expression", node)
            self.emit(code, level)
            for member, target in outputs:
                self.assign(target, Ex(f"{callee.code}.{member.name}", member.type), scope, level)
            return None
        return Ex(code, None)

    def standard_call(self, name: str, node: Any, scope: Scope, level: int | None) -> Ex | None:
        upper = name.upper()
        if upper.lower() in scope.locals or (scope.owner is not None and self.find_member(scope.owner, name) is not None):
            return None
        if upper.lower() in self.decls and self.decls[upper.lower()].kind != "stdfb":
            return None
        if upper in ("ADR", "__QUERYPOINTER", "__QUERYINTERFACE", "__ISVALIDREF", "TEST_AND_SET", "TESTANDSET",
                     "SIZEOF", "__NEW", "__DELETE", "__VARINFO"):
            return self.operator_call(upper, node, scope, level)  # operands that are types, not values
        if upper in SYSTEM_FUNCTIONS:
            return self.system_call(upper, node, scope)
        args = [self.expr(p.value, scope) for p in node.parameters if isinstance(p, tf.InputParameterAssignment)]
        codes = [a.code for a in args]
        first = args[0].type.deref() if args and args[0].type is not None else None
        if upper == "ABS":
            return self.function_call(upper, codes, first)
        if upper in MATH_FUNCTIONS or upper == "EXPT":
            return self.function_call(upper, codes, LREAL)
        if upper in ("MIN", "MAX"):
            return self.function_call(upper, codes, self.wider(first, args[1].type if len(args) > 1 else None))
        if upper in ("LIMIT", "SEL", "MUX"):
            return self.function_call(upper, codes, args[1].type)
        if upper == "MOVE":
            return args[0]
        if upper in ("SHL", "SHR", "ROL", "ROR"):
            if first is None or not first.is_int:
                raise self.fail(f"{upper} needs an operand of a known bit width (BYTE, WORD, DWORD, LWORD ...)", node)
            self._need_type(first)
            return self.function_call(upper, [*codes, first.name], first)
        if upper == "TRUNC":
            self.need("iecoop.conversions", "TRUNC")
            return Ex(f"TRUNC({codes[0]})", TypeRef("elem", "DINT"))
        conversion = re.fullmatch(r"(?:(\w+?)_)?TO_(\w+)", upper)
        if conversion is not None:
            enum_text = self.enum_to_string(conversion.group(1), conversion.group(2), args)
            if enum_text is not None:
                return enum_text
            return self.conversion(conversion.group(1), conversion.group(2), args, node)
        strings = self.string_call(upper, args, node)
        if strings is not None:
            return strings
        if upper in ("AND", "OR", "XOR", "NOT"):
            raise self.fail(f"{upper} in function form is not supported (use the operator)", node)
        return None

    def enum_to_string(self, source: str | None, target: str, args: list[Ex]) -> Ex | None:
        """``TO_STRING(eMode)``, ``E_Mode_TO_STRING(eMode)``: the component's name when the enumeration has
        ``{attribute 'to_string'}`` (TwinCAT 3.1.4024, CODESYS), else the number's text; None if not an enumeration."""
        if target not in ("STRING", "WSTRING") or not args:
            return None
        name = source if source is not None else args[0].type.name if args[0].type is not None and args[0].type.kind == "user" else None
        decl = self.decls.get(name.lower()) if name is not None else None
        if decl is None or decl.kind != "enum":
            return None
        result = self._elem_or_none(target)
        value = args[0]
        if not any(re.fullmatch(r"\{\s*attribute\s+'to_string'\s*\}", p, re.IGNORECASE) for p in self._decl_pragmas(decl)):
            return Ex(f"str(int({value.code}))", result)
        # a value that names no component (an integer stored in the variable) gives its number's text
        return Ex(f'str(getattr({value.code}, "name", int({value.code})))', result)

    def _decl_pragmas(self, decl: Decl) -> list[str]:
        """The pragmas written before the declaration ``decl``, which may be another item than the current one."""
        saved = self.unit, self.window
        try:
            self.unit = decl.unit
            self.enter(decl.item)
            return self.pragmas(decl.node)
        finally:
            self.unit, self.window = saved

    def system_call(self, upper: str, node: Any, scope: Scope) -> Ex:
        """TwinCAT's system functions: ``TIME()`` (the task clock in ms, as TON reads it), MEMCPY, MEMSET, MEMCMP."""
        if upper == "TIME":
            if node.parameters:
                raise self.fail("TIME() takes no input", node)
            self.need("iecoop.runtime", "now_ms")
            return Ex("now_ms()", TypeRef("elem", "TIME"))
        codes = [self.expr(p.value, scope).code for p in node.parameters]
        self.need("iecoop", upper.lower())
        return Ex(f"{upper.lower()}({', '.join(codes)})", TypeRef("elem", SYSTEM_FUNCTIONS[upper]))

    def conversion(self, source: str | None, target: str, args: list[Ex], node: Any) -> Ex:
        from iecoop import conversions

        source = TYPE_SYNONYMS.get(source, source) if source else None
        target = TYPE_SYNONYMS.get(target, target)
        value = args[0]
        result_type = self._elem_or_none(target)
        if result_type is None:
            raise self.fail(f"conversion to {target} is not supported", node)
        if target in ("STRING", "WSTRING"):
            # iecoop's *_TO_STRING write the vendor text (T#1s500ms, 1.5, TRUE); TO_STRING goes by the
            # argument's declared type, which the Python function cannot see, so it gets the source-named form.
            # (an enumeration's TO_STRING is enum_to_string's, before this)
            named = source or (value.type.name if value.type is not None and value.type.kind == "elem" else None)
            named = TYPE_SYNONYMS.get(named, named) if named else None
            form = f"{named}_TO_STRING" if named else ""
            if form not in conversions.__all__:
                if value.type is None or not value.type.is_int:
                    raise self.fail(f"{source or 'ANY'}_TO_{target} is not supported", node)
                form = "TO_STRING"
            self.need("iecoop.conversions", form)
            return Ex(f"{form}({value.code})", result_type)
        if source in ("STRING", "WSTRING"):
            # the literal the text starts with, stored in the target type (TwinCAT, CODESYS: '34abc' is 34, 'abc' 0)
            if result_type.kind != "elem" or target in ("DATE", "TOD", "DT"):
                raise self.fail(f"{source}_TO_{target} is not supported", node)
            self.need("iecoop.conversions", "STRING_TO_NUMBER", f"TO_{target}")
            return Ex(f'TO_{target}(STRING_TO_NUMBER({value.code}, "{target}"))', result_type)
        name = f"{source}_TO_{target}" if source else f"TO_{target}"
        if source is not None and name not in conversions.__all__:
            if source == "BOOL":
                name = f"TO_{target}"
            elif source in INTEGER_LAYOUT and target in INTEGER_LAYOUT:
                # reinterpret through the source width, then store in the target width
                source_type = TypeRef("elem", source)
                self.need("iecoop.conversions", f"TO_{source}", f"TO_{target}")
                return Ex(f"TO_{target}(TO_{source}({value.code}))", result_type) if source_type else Ex("", None)
            else:
                name = f"TO_{target}"
        if name not in conversions.__all__:
            raise self.fail(f"conversion {name} is not supported", node)
        self.need("iecoop.conversions", name)
        return Ex(f"{name}({value.code})", result_type)

    def string_call(self, upper: str, args: list[Ex], node: Any) -> Ex | None:
        if upper not in STRING_FUNCTIONS:
            return None
        result = TypeRef("elem", "INT") if upper in ("LEN", "FIND") else STRING
        return self.function_call(upper, [a.code for a in args], result)

    def function_call(self, name: str, codes: Sequence[str], type_: TypeRef | None) -> Ex:
        """A call of the standard function ``name`` of ``iecoop.functions``: the form the Rosetta teaches."""
        self.need("iecoop.functions", name)
        return Ex(f"{name}({', '.join(codes)})", type_)

    def operator_call(self, upper: str, node: Any, scope: Scope, level: int | None) -> Ex:
        """ADR, SIZEOF, __NEW, __DELETE, __ISVALIDREF, TEST_AND_SET, __QUERYINTERFACE, __QUERYPOINTER: operands that are variables or types."""
        handler = _OPERATORS.get(upper)
        if handler is None:
            raise self.fail(f"{upper} is not supported", node)
        return handler(self, upper, [p.value for p in node.parameters], node, scope, level)

    def _op_adr(self, upper: str, params: list[Any], node: Any, scope: Scope, level: int | None) -> Ex:
        return Ex(self.address_of(params[0], scope), TypeRef("pointer", "POINTER_TO", of=self.expr(params[0], scope).type))

    def _op_varinfo(self, upper: str, params: list[Any], node: Any, scope: Scope, level: int | None) -> Ex:
        self.need("iecoop", "var_info")
        holder, field = self.holder_field(params[0], scope)
        return Ex(f'var_info({holder}, "{field}")', TypeRef("varinfo", "VarInfo"))

    def _op_sizeof(self, upper: str, params: list[Any], node: Any, scope: Scope, level: int | None) -> Ex:
        self.need("iecoop", "sizeof")
        target = params[0]
        if isinstance(target, tf.SimpleVariable) and not target.dereferenced:
            of_type = self._sizeof_type(str(target.name))
            if of_type is not None:
                return of_type
        ex = self.expr(target, scope)
        decl = self.decl_of(ex.type)
        if decl is not None and decl.kind in ("struct", "union", "fb", "stdfb"):
            return Ex(f"sizeof({ex.code})", TypeRef("elem", "UDINT"))
        holder, field = self.holder_field(target, scope)
        return Ex(f'sizeof({holder}, "{field}")', TypeRef("elem", "UDINT"))

    def _sizeof_type(self, name: str) -> Ex | None:
        """``SIZEOF(T)`` of a type name, or None when ``name`` is not one."""
        elem = self._elem_or_none(name)
        if elem is not None:
            self._need_type(elem)
            return Ex(f"sizeof({elem.name})", TypeRef("elem", "UDINT"))
        decl = self.decls.get(name.lower())
        if decl is not None and decl.kind in ("struct", "union", "fb", "stdfb", "alias", "enum"):
            if decl.kind == "stdfb":
                self.need("iecoop.stdlib", decl.name)
            return Ex(f"sizeof({decl.name})", TypeRef("elem", "UDINT"))
        return None

    def _op_new(self, upper: str, params: list[Any], node: Any, scope: Scope, level: int | None) -> Ex:
        self.need("iecoop", "new")
        target = params[0]
        if not isinstance(target, tf.SimpleVariable):
            raise self.fail("__NEW with FB_init arguments or an array is not supported", node)
        decl = self.decls.get(str(target.name).lower())
        if decl is None or decl.kind not in ("fb", "struct", "stdfb"):
            raise self.fail(f"__NEW of {target.name}: only function blocks and structs are supported", node)
        if decl.kind == "stdfb":
            self.need("iecoop.stdlib", decl.name)
        # __NEW(FB_X, a := 1): FB_init's inputs by name, as iecoop's new() takes them
        fb_init = self.find_member(decl, "FB_init")
        inputs = fb_init[1].params if fb_init is not None and isinstance(fb_init[1], Callable_) else []
        args = [decl.name]
        for param in node.parameters[1:]:
            if not isinstance(param, tf.InputParameterAssignment) or param.name is None:
                raise self.fail(f"__NEW of {decl.name} with a length (an array) is not supported", node)
            name = str(param.name.name)
            match = next((p.name for p in inputs if p.st.lower() == name.lower()), None)
            if match is None:
                raise self.fail(f"__NEW of {decl.name}: FB_init has no input {name!r}", node)
            args.append(f"{match}={self.expr(param.value, scope).code}")
        return Ex(f"new({', '.join(args)})", TypeRef("pointer", "POINTER_TO", of=TypeRef("user", decl.name)))

    def _op_delete(self, upper: str, params: list[Any], node: Any, scope: Scope, level: int | None) -> Ex:
        if level is None:
            raise self.fail("__DELETE inside an expression", node)
        self.need("iecoop", "delete")
        pointer = self.expr(params[0], scope)
        return Ex(f"delete({pointer.code})", None)  # delete() makes the pointer variable 0, as __DELETE does

    def _op_isvalidref(self, upper: str, params: list[Any], node: Any, scope: Scope, level: int | None) -> Ex:
        local = self.local_of(params[0], scope)
        if isinstance(local, ReferenceLocal):
            return Ex(f"bool({local.name})", BOOL)
        self.need("iecoop", "is_valid_ref")
        holder, field = self.holder_field(params[0], scope)
        return Ex(f'is_valid_ref({holder}, "{field}")', BOOL)

    def _op_test_and_set(self, upper: str, params: list[Any], node: Any, scope: Scope, level: int | None) -> Ex:
        self.need("iecoop", "test_and_set")
        # the result is BOOL in TwinCAT and the old flag's value in CODESYS: typed as the integer it is
        return Ex(f"test_and_set({self.address_of(params[0], scope)})", TypeRef("elem", "DWORD"))

    def _op_query(self, upper: str, params: list[Any], node: Any, scope: Scope, level: int | None) -> Ex:
        if level is None and not self._hoisting:
            raise self.fail(f"{upper} is supported as a statement or the right side of an assignment", node)
        source = self.expr(params[0], scope)
        dest = self.expr(params[1], scope, store=True)
        at = self._hoist_level if level is None else level
        if upper == "__QUERYPOINTER":
            self.need("iecoop", "query_pointer")
            self.emit(f"{dest.code} = query_pointer({source.code})", at)
            return Ex(f"bool({dest.code})" if level is None else "", BOOL)
        decl = self.decl_of(dest.type)
        if decl is None or decl.kind != "interface":
            raise self.fail(f"__QUERYINTERFACE needs an interface variable as its second operand, got {dest.code}", node)
        self.need("iecoop", "query_interface", "null")
        self.emit(f"{dest.code} = query_interface({source.code}, {decl.name}) or null({decl.name})", at)
        return Ex(f"bool({dest.code})" if level is None else "", BOOL)

    _hoisting = False
    _hoist_level = 0


#: The operators whose operands are variables or types, not values: ST name -> Translator method.
_OPERATORS: dict[str, Callable[[Translator, str, list[Any], Any, Scope, int | None], Ex]] = {
    "ADR": Translator._op_adr,
    "SIZEOF": Translator._op_sizeof,
    "__VARINFO": Translator._op_varinfo,
    "__NEW": Translator._op_new,
    "__DELETE": Translator._op_delete,
    "__ISVALIDREF": Translator._op_isvalidref,
    "TEST_AND_SET": Translator._op_test_and_set,
    "TESTANDSET": Translator._op_test_and_set,
    "__QUERYINTERFACE": Translator._op_query,
    "__QUERYPOINTER": Translator._op_query,
}


def _structure_elements(value: Any) -> list[tuple[str | None, Any]] | None:
    """``(name, value)`` of each element of a structure initialiser, or None if ``value`` is not one.

    blark reads a one-element initialiser, ``(x := 1)``, as a parenthesised assignment, and
    inside an array initialiser may read ``(a := 1, b := 2, c := 3)`` as ``a := [1, b := 2], c := 3``.
    """
    if isinstance(value, tf.StructureInitialization):
        found: list[tuple[str | None, Any]] = []
        for element in value.elements:
            found += _misread_elements(str(element.name) if element.name is not None else None, element.value)
        return found
    inner = value.expr if isinstance(value, tf.ParenthesizedExpression) else None
    if isinstance(inner, tf.BinaryOperation) and str(inner.op) == ":=" and isinstance(inner.left, tf.SimpleVariable):
        return [(str(inner.left.name), inner.right)]
    return None


def _misread_elements(name: str | None, value: Any) -> list[tuple[str | None, Any]]:
    """``name := value`` of a structure initialiser, split again where blark read the next elements into ``value``."""
    items = value.elements if isinstance(value, tf.ArrayInitialization) and not value.brackets else []
    rest = items[1:]
    if len(items) > 1 and items[0].count is None and all(
        item.count is None and isinstance(item.element, tf.BinaryOperation) and str(item.element.op) == ":="
        and isinstance(item.element.left, tf.SimpleVariable) for item in rest
    ):
        return [(name, items[0].element)] + [(str(item.element.left.name), item.element.right) for item in rest]
    return [(name, value)]


def _exact_real(code: str) -> bool:
    """Whether ``code`` is a number literal that a REAL (32-bit) holds exactly: no TO_REAL needed."""
    try:
        number = float(code)
    except ValueError:
        return False
    return bool(struct.unpack("<f", struct.pack("<f", number))[0] == number)


_VISIBILITY = tf.AccessSpecifier.public | tf.AccessSpecifier.private | tf.AccessSpecifier.protected | tf.AccessSpecifier.internal


def accessor_access(node: Any) -> Any:
    """The access of one PROPERTY accessor: its own specifier, where it has one, in place of the property's.

    TwinCAT keeps an accessor's specifier at the head of the accessor's declaration, so the flat form
    reads ``PROPERTY PUBLIC Capacity : REAL PRIVATE`` (blark's ``access_override``); ABSTRACT and
    FINAL stay those of the property.
    """
    own = node.access_override
    if own is None:
        return node.access
    kept = node.access & ~_VISIBILITY if node.access is not None else tf.AccessSpecifier(0)
    return kept | own


def _is_zero(node: Any) -> bool:
    """Whether ``node`` is the literal 0 (``16#0``, ``UDINT#0`` too): the address of nothing."""
    return isinstance(node, tf.Integer) and int(str(node.value).replace("_", ""), node.base) == 0


def _signature(members: Sequence[Member]) -> list[Member]:
    """A METHOD's / FUNCTION's parameters: inputs and in-outs in declaration order, then the outputs."""
    inputs = [m for m in members if m.section in ("VAR_INPUT", "VAR_IN_OUT")]
    return inputs + [m for m in members if m.section == "VAR_OUTPUT"]


def _variables(node: Any) -> Iterator[Any]:
    """The variables (``x``, ``fb.Prop``) read by the expression ``node``."""
    if isinstance(node, (tf.SimpleVariable, tf.MultiElementVariable)):
        yield node
        if isinstance(node, tf.MultiElementVariable):
            for element in node.elements:
                if isinstance(element, tf.SubscriptList):
                    for subscript in element.subscripts:
                        yield from _variables(subscript)
        return
    if dataclasses.is_dataclass(node):
        for field in dataclasses.fields(node):
            yield from _variables(getattr(node, field.name))
    elif isinstance(node, (list, tuple)):
        for item in node:
            yield from _variables(item)


def _by_reference_arguments(node: Any, in_out: set[str]) -> Iterator[str]:
    """The bare variables (lower case) that the calls in ``node`` get as an output (``=>``), or as an argument of
    a METHOD or FUNCTION whose name (in ``in_out``) has a VAR_IN_OUT: by name, so never fewer than need an address."""
    if isinstance(node, tf.FunctionCall):
        callee = str(node.name).split(".")[-1].lower()
        for param in node.parameters or []:
            value = getattr(param, "value", None)
            if isinstance(value, tf.SimpleVariable) and not value.dereferenced and (
                    isinstance(param, tf.OutputParameterAssignment) or callee in in_out):
                yield str(value.name).lower()
    if dataclasses.is_dataclass(node):
        for field in dataclasses.fields(node):
            yield from _by_reference_arguments(getattr(node, field.name), in_out)
    elif isinstance(node, (list, tuple)):
        for item in node:
            yield from _by_reference_arguments(item, in_out)


def _has_call(node: Any) -> bool:
    """Whether the expression ``node`` calls a function, method or block (something that may have a side effect)."""
    if isinstance(node, (tf.FunctionCall, tf.ChainedFunctionCall)):
        return True
    if dataclasses.is_dataclass(node):
        return any(_has_call(getattr(node, field.name)) for field in dataclasses.fields(node))
    if isinstance(node, (list, tuple)):
        return any(_has_call(item) for item in node)
    return False


def _assigned(node: Any) -> Iterator[Any]:
    """The variables the statements in ``node`` assign with ``:=`` (each target of each assignment)."""
    if isinstance(node, tf.AssignmentStatement):
        yield from node.variables
    if dataclasses.is_dataclass(node):
        for field in dataclasses.fields(node):
            yield from _assigned(getattr(node, field.name))
    elif isinstance(node, (list, tuple)):
        for item in node:
            yield from _assigned(item)


def _jumps_in_loop(node: Any, in_loop: bool = False) -> bool:
    """Whether a JMP in ``node`` sits inside a FOR, WHILE or REPEAT loop (it would leave the loop)."""
    if isinstance(node, tf.JumpStatement):
        return in_loop
    in_loop = in_loop or isinstance(node, (tf.ForStatement, tf.WhileStatement, tf.RepeatStatement))
    if dataclasses.is_dataclass(node):
        return any(_jumps_in_loop(getattr(node, field.name), in_loop) for field in dataclasses.fields(node))
    if isinstance(node, (list, tuple)):
        return any(_jumps_in_loop(item, in_loop) for item in node)
    return False


def statements_of(body: Any) -> list[Any]:
    """The statements of a POU body (blark gives a lone statement of the grammar overlay as itself)."""
    if body is None:
        return []
    statements = getattr(body, "statements", None)
    return list(statements) if statements is not None else [body]


def lark_token_type() -> type:
    import lark

    return lark.Token


def python_string(text: str) -> str:
    """An ST string literal ('...' or "...") as a Python literal."""
    quote = text[0]
    body = text[1:-1]
    escapes = {"$$": "$", "$'": "'", '$"': '"', "$L": "\n", "$N": "\n", "$P": "\f", "$R": "\r", "$T": "\t"}
    out = []
    i = 0
    while i < len(body):
        if body[i] == "$" and i + 1 < len(body):
            pair = body[i:i + 2].upper() if body[i + 1].isalpha() else body[i:i + 2]
            if pair in escapes:
                out.append(escapes[pair])
                i += 2
                continue
            if i + 2 < len(body) and all(c in "0123456789abcdefABCDEF" for c in body[i + 1:i + 3]):
                out.append(chr(int(body[i + 1:i + 3], 16)))
                i += 3
                continue
        out.append(body[i])
        i += 1
    del quote
    return json.dumps("".join(out), ensure_ascii=False)


def translate(units: Sequence[Unit], externals: Sequence[str] = ()) -> tuple[str, list[tuple[str, str]]]:
    """The Python module text for ``units`` and the ``(kind, name)`` of each top-level ST name."""
    translator = Translator(units, externals)
    text = translator.translate()
    names = [(d.kind, d.name) for d in translator.decls.values() if d.kind != "stdfb"]
    return text, names
