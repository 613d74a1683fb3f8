"""The diagram model: boxes, members and relations read from declared classes, and state tables.

Text and picture forms are in :mod:`iecoop.uml.text` and :mod:`iecoop.uml.svg`.
"""

from __future__ import annotations

import dataclasses
import enum
import re
import types
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

from iecoop.members import Access, Member, format_signature
from iecoop.memory.typeinfo import AggregateInfo, ArrayInfo, EnumInfo, InterfaceInfo, PointerInfo, ReferenceInfo, TypeInfo
from iecoop.metadata import iec_class, kind_of, layout_of
from iecoop.sections import SECTION_RULES, Section
from iecoop.uml import text as _text

_STEREOTYPES = {
    "fb": "FUNCTION_BLOCK",
    "program": "PROGRAM",
    "interface": "INTERFACE",
    "struct": "STRUCT",
    "union": "UNION",
    "enum": "ENUM",
}

# Section -> UML visibility: the block's interface (what code outside it may touch) is public.
_SECTION_VISIBILITY = {section: "+" if rule.interface else "#" for section, rule in SECTION_RULES.items()}

_ACCESS_SYMBOL = {Access.PUBLIC: "+", Access.PRIVATE: "-", Access.PROTECTED: "#", Access.INTERNAL: "~"}

# The library's own base classes are not drawn.
_HIDDEN_NAMES = {
    ("iecoop.pou", "FunctionBlock"),
    ("iecoop.pou", "Program"),
    ("iecoop.interfaces", "Interface"),
    ("iecoop.memory.datatypes", "Struct"),
    ("iecoop.memory.datatypes", "Union"),
    ("iecoop.memory.datatypes", "IecEnum"),
}


@dataclasses.dataclass(frozen=True)
class UmlField:
    """One variable line of a box: visibility, name, IEC type and VAR section."""

    visibility: str
    name: str
    type_name: str
    section: str
    static: bool = False

    def text(self) -> str:
        return f"{self.visibility}{self.name} : {self.type_name} «{self.section}»"


@dataclasses.dataclass(frozen=True)
class UmlOperation:
    """One METHOD or PROPERTY line of a box, with its ABSTRACT / FINAL modifiers."""

    visibility: str
    name: str
    params: str
    returns: str
    abstract: bool
    final: bool
    is_property: bool = False
    accessors: str = ""

    def text(self) -> str:
        if self.is_property:
            return f"{self.visibility}{self.name} : {self.returns} «PROPERTY {self.accessors}»"
        result = f" {self.returns}" if self.returns != "None" else ""
        return f"{self.visibility}{self.name}({self.params}){result}"


@dataclasses.dataclass(frozen=True)
class UmlClass:
    """One box: a FUNCTION_BLOCK, PROGRAM, INTERFACE, STRUCT, UNION or ENUM."""

    name: str
    stereotype: str
    abstract: bool = False
    final: bool = False
    fields: tuple[UmlField, ...] = ()
    operations: tuple[UmlOperation, ...] = ()
    detailed: bool = True
    #: The part the class plays in a pattern (``State``, ``Context``), shown in a participants diagram.
    role: str = ""

    @property
    def heading(self) -> str:
        words = [w for w, on in (("ABSTRACT", self.abstract), ("FINAL", self.final)) if on]
        return " ".join([*words, self.stereotype])


@dataclasses.dataclass(frozen=True)
class Relation:
    """An arrow: ``kind`` is extends, implements, composition, aggregation or association."""

    source: str
    target: str
    kind: str
    label: str = ""
    multiplicity: str = ""


def _kind(cls: type) -> str | None:
    kind = kind_of(cls)
    return str(kind) if kind in _STEREOTYPES else None


def _visible(cls: type) -> bool:
    return _kind(cls) is not None and (cls.__module__, cls.__name__) not in _HIDDEN_NAMES


def _type_name(info: Any) -> str:
    return str(getattr(info, "name", info))


def _referenced(info: TypeInfo) -> tuple[type | None, str, str]:
    """The class a field's type points at, the relation kind, and the multiplicity."""
    if isinstance(info, ArrayInfo):
        cls, relation, _ = _referenced(info.elem)
        if len(info.bounds) == 1:
            (lo, hi), = info.bounds
            return cls, relation, f"{lo}..{hi}"
        count = 1
        for lo, hi in info.bounds:
            count *= hi - lo + 1
        return cls, relation, str(count)
    if isinstance(info, AggregateInfo):
        return info.cls, "composition", ""
    if isinstance(info, InterfaceInfo):
        return info.iface, "aggregation", ""
    if isinstance(info, (PointerInfo, ReferenceInfo)):
        target = info.target
        cls = getattr(target, "cls", None) or getattr(target, "iface", None)
        return cls, "aggregation", ""
    if isinstance(info, EnumInfo):
        return info.enum_cls, "association", ""
    return None, "", ""


def _own_members(cls: type) -> list[Member]:
    record = iec_class(cls)
    members: Mapping[str, Member] = record.members if record is not None else {}
    return [m for m in members.values() if m.owner is cls]


# ``pkg.module.Name`` -> ``Name``; ``Pointer[X]`` -> ``POINTER TO X``, as the fields are written.
_QUALIFIER = re.compile(r"\b(?:[a-z_][a-z0-9_]*\.)+(?=[A-Za-z_])")
_POINTER = re.compile(r"\bPointer\[([^\[\]]+)\]")


def _operation(member: Member) -> UmlOperation:
    text = _POINTER.sub(r"POINTER TO \1", _QUALIFIER.sub("", format_signature(member.signature)))
    params, _, returns = text.partition(" -> ")
    if member.kind == "property":
        get_symbol = _ACCESS_SYMBOL.get(Access(member.get_flags & ~(Access.FINAL | Access.ABSTRACT)) or Access.PUBLIC, "+")
        parts = ["get"]
        if member.has_set:
            set_symbol = _ACCESS_SYMBOL.get(
                Access(member.set_flags & ~(Access.FINAL | Access.ABSTRACT)) or Access.PUBLIC, "+"
            )
            parts.append("set" if set_symbol == get_symbol else f"{set_symbol}set")
        return UmlOperation(
            get_symbol, member.name, "", returns, member.abstract, member.final, True, "/".join(parts)
        )
    symbol = _ACCESS_SYMBOL.get(member.visibility, "+")
    return UmlOperation(symbol, member.name, params[1:-1], returns, member.abstract, member.final)


def _describe(cls: type, detailed: bool) -> UmlClass:
    kind = _kind(cls)
    assert kind is not None
    stereotype = _STEREOTYPES[kind]
    meta = iec_class(cls)
    abstract = meta is not None and meta.abstract
    final = meta is not None and meta.final
    if not detailed:
        return UmlClass(cls.__name__, stereotype, abstract, final, detailed=False)
    fields: list[UmlField] = []
    if kind == "enum":
        assert issubclass(cls, enum.Enum)
        for item in cls:
            fields.append(UmlField("+", item.name, str(int(item.value)), "value"))
    else:
        layout = layout_of(cls)
        own = layout.own if layout is not None else ()
        for record in own:
            if record.name.startswith("_iec"):
                continue
            section = record.section
            visibility = "+" if kind in ("struct", "union") else _SECTION_VISIBILITY.get(section, "#")
            fields.append(UmlField(visibility, record.name, _type_name(record.info), section))
        # VAR_STAT lives in one block per declaring class, outside the instance layout.
        for record in meta.static_fields if meta is not None else ():
            fields.append(UmlField("#", record.name, _type_name(record.info), Section.VAR_STAT, True))
    operations = tuple(_operation(m) for m in _own_members(cls))
    return UmlClass(cls.__name__, stereotype, abstract, final, tuple(fields), operations)


def _relations(cls: type) -> list[tuple[type, Relation]]:
    found: list[tuple[type, Relation]] = []
    kind = _kind(cls)
    for base in cls.__bases__:
        if not _visible(base):
            continue
        base_kind = _kind(base)
        if base_kind == "interface" and kind != "interface":
            found.append((base, Relation(base.__name__, cls.__name__, "implements")))
        else:
            found.append((base, Relation(base.__name__, cls.__name__, "extends")))
    layout = layout_of(cls)
    if kind != "enum" and layout is not None:
        for record in layout.own:
            target, relation, multiplicity = _referenced(record.info)
            if target is not None and _visible(target):
                found.append((target, Relation(cls.__name__, target.__name__, relation, record.name, multiplicity)))
    return found


class ClassDiagram:
    """Boxes and arrows, renderable as Mermaid, PlantUML or SVG."""

    def __init__(self, classes: Sequence[UmlClass], relations: Sequence[Relation], title: str = "") -> None:
        self.classes = list(classes)
        self.relations = list(relations)
        self.title = title

    def names(self) -> list[str]:
        return [c.name for c in self.classes]

    def participants(self, roles: Mapping[str, str], title: str = "") -> ClassDiagram:
        """The boxes named in ``roles`` (class name -> role), in that order, without members, marked with the role.

        The pattern's participants at a glance: the relations among them are
        kept, without the field names that label them in the full diagram.
        """
        by_name = {box.name: box for box in self.classes}
        missing = [name for name in roles if name not in by_name]
        if missing:
            raise ValueError(f"the diagram has no class {missing[0]!r} (it has {', '.join(by_name)})")
        boxes = [
            dataclasses.replace(by_name[name], fields=(), operations=(), detailed=False, role=role)
            for name, role in roles.items()
        ]
        kept: list[Relation] = []
        for r in self.relations:
            if r.source in roles and r.target in roles:
                plain = dataclasses.replace(r, label="")
                if plain not in kept:
                    kept.append(plain)
        return ClassDiagram(boxes, kept, title or self.title)

    # -- text forms ------------------------------------------------------------

    def to_mermaid(self) -> str:
        """Mermaid ``classDiagram`` text."""
        return _text.class_mermaid(self)

    def to_plantuml(self) -> str:
        """PlantUML text."""
        return _text.class_plantuml(self)

    def to_d2(self) -> str:
        """D2 text, for the D2 layout engines (``d2 --layout elk``)."""
        return _text.class_d2(self)

    # -- picture ---------------------------------------------------------------

    def to_svg(self) -> str:
        """A self-contained SVG drawn without any tool (``iecoop.uml.svg.class_svg``)."""
        from iecoop.uml.svg import class_svg  # svg draws the model's classes: imported when first drawn

        return class_svg(self)


def class_diagram(*classes: type, related: bool = True, title: str = "") -> ClassDiagram:
    """The class diagram of ``classes`` (shown with their members), in the order given.

    With ``related`` (the default), the classes they extend, implement or hold
    are added as plain boxes (name and stereotype only) when not listed.
    """
    listed = list(dict.fromkeys(classes))
    for cls in listed:
        if not _visible(cls):
            raise TypeError(f"{cls!r} is not a FUNCTION_BLOCK, PROGRAM, INTERFACE, STRUCT, UNION or ENUM")
    described = [_describe(cls, True) for cls in listed]
    relations: list[Relation] = []
    extra: list[type] = []
    for cls in listed:
        for target, relation in _relations(cls):
            if target not in listed:
                if not related:
                    continue
                if target not in extra:
                    extra.append(target)
            if relation not in relations:
                relations.append(relation)
    described.extend(_describe(cls, False) for cls in extra)
    return ClassDiagram(described, relations, title)


def module_diagram(module: types.ModuleType, *, related: bool = True, title: str = "") -> ClassDiagram:
    """The class diagram of every FB, interface, struct and enum a module defines, in definition order."""
    own = [
        value for value in vars(module).values()
        if isinstance(value, type) and _visible(value) and value.__module__ == module.__name__
    ]
    if not own:
        raise ValueError(f"module {module.__name__} defines no FUNCTION_BLOCK, INTERFACE, STRUCT or ENUM")
    return class_diagram(*own, related=related, title=title or module.__name__)


# ---------------------------------------------------------------------------
# State diagrams
# ---------------------------------------------------------------------------


class StateDiagram:
    """States and labelled transitions, renderable as Mermaid, PlantUML or SVG."""

    def __init__(
        self,
        states: Sequence[str],
        transitions: Sequence[tuple[str, str, str]],
        initial: str,
        title: str = "",
        positions: Mapping[str, tuple[float, float]] | None = None,
    ) -> None:
        self.states = list(states)
        self.transitions = list(transitions)
        self.initial = initial
        self.title = title
        self.positions = dict(positions or {})

    def merged(self) -> dict[tuple[str, str], list[str]]:
        """Transition labels per (source, target): parallel transitions are drawn as one arrow."""
        merged: dict[tuple[str, str], list[str]] = {}
        for source, label, target in self.transitions:
            merged.setdefault((source, target), []).append(label)
        return merged

    def to_mermaid(self) -> str:
        """Mermaid ``stateDiagram-v2`` text."""
        return _text.state_mermaid(self)

    def to_plantuml(self) -> str:
        """PlantUML text."""
        return _text.state_plantuml(self)

    def to_svg(self) -> str:
        """A self-contained SVG: states on the given grid positions (or a circle), labelled arrows."""
        from iecoop.uml.svg import state_svg  # svg draws the model's classes: imported when first drawn

        return state_svg(self)

def state_diagram(
    transitions: Iterable[tuple[str, str, str]],
    initial: str,
    *,
    title: str = "",
    positions: Mapping[str, tuple[float, float]] | None = None,
) -> StateDiagram:
    """A state diagram from ``(source, event, target)`` rows, e.g. a PackML transition table.

    ``positions`` (state -> (column, row)) places the states on a grid for
    the SVG; without it they stand on a circle.

    >>> print(state_diagram([("Idle", "Start", "Running"), ("Running", "Stop", "Idle")], "Idle").to_mermaid())
    stateDiagram-v2
        [*] --> Idle
        Idle --> Running : Start
        Running --> Idle : Stop
    """
    rows = [tuple(row) for row in transitions]
    for row in rows:
        if len(row) != 3 or not all(isinstance(part, str) and part for part in row):
            raise ValueError(f"a transition is (source, event, target) as non-empty strings, got {row!r}")
    states: list[str] = [initial]
    for source, _, target in rows:
        for s in (source, target):
            if s not in states:
                states.append(s)
    if not any(initial in (s, t) for s, _, t in rows):
        raise ValueError(f"the initial state {initial!r} takes part in no transition")
    return StateDiagram(states, [(s, e, t) for s, e, t in rows], initial, title, positions)
