"""One record per declared class: what its builder decided, as ``cls.__iec__``.

Every class an iecoop builder makes (FUNCTION_BLOCK, PROGRAM, STRUCT, UNION,
GVL, INTERFACE, enumeration) carries one frozen ``IecClass``: its kind, its
class keywords, its variables and its METHODs and PROPERTYs. The library's
own base classes (``FunctionBlock``, ``Struct``...) carry one marked
``root``. The record is read when classes are built, checked, drawn or
exported; what runs on every call or variable access is installed on the class
by the builders and never looks it up.

ST::

    FUNCTION_BLOCK ABSTRACT FB_Axis

>>> from iecoop import FunctionBlock
>>> from iecoop.metadata import Kind, iec_class
>>> class Axis(FunctionBlock, abstract=True):
...     pass
>>> record = iec_class(Axis)
>>> record.kind is Kind.FUNCTION_BLOCK, record.abstract, record.final
(True, True, False)
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

from iecoop.sections import Kind

if TYPE_CHECKING:
    from iecoop.members import Member
    from iecoop.memory.layout import ClassLayout, FieldRecord

__all__ = ["IecClass", "Kind", "field_record", "fields_of", "iec_class", "is_root", "kind_of", "layout_of", "member_named",
           "st_name"]

_NO_MEMBERS: Mapping[str, Any] = MappingProxyType({})

@dataclasses.dataclass(frozen=True)
class IecClass:
    """A declared class as its builder left it (``cls.__iec__``)."""

    kind: Kind
    #: The class keywords: ``class Axis(FunctionBlock, abstract=True)``.
    abstract: bool = False
    final: bool = False
    internal: bool = False
    #: The library's own base class of the kind (``FunctionBlock``), not a declared type.
    root: bool = False
    #: The variables in the instance's memory, base fields first (None: a root, an interface, an enum).
    layout: ClassLayout | None = None
    #: Every METHOD and PROPERTY, inherited ones included.
    members: Mapping[str, Member] = dataclasses.field(default_factory=lambda: _NO_MEMBERS)
    #: The VAR_STAT variables this class declares (kept in its static block).
    static_fields: tuple[FieldRecord, ...] = ()
    #: The class keyword ``st_name=``: the ST name when Python could not spell it ("" : the class name).
    st_name: str = ""
    #: An enumeration's ``st_names=``: the ST name of each value Python could not spell.
    value_names: Mapping[str, str] = dataclasses.field(default_factory=lambda: _NO_MEMBERS)

    def complete(self, **changes: Any) -> None:
        """Fill in what the later build phases add (layout, members, statics), while the class is being built.

        The record a builder puts in the class namespace is completed in place, never replaced:
        replacing an attribute of a ctypes Structure class after ctypes has set the class up
        left a dangling reference behind on CPython 3.11 (a crash in the garbage collector after
        classes were collected), so a block class's ``__iec__`` is assigned exactly once.
        """
        if "members" in changes:
            changes["members"] = MappingProxyType(dict(changes["members"]))
        for name, value in changes.items():
            object.__setattr__(self, name, value)


def iec_class(cls: object) -> IecClass | None:
    """The record of a class an iecoop builder made, or None for any other object."""
    record = getattr(cls, "__iec__", None)
    return record if isinstance(record, IecClass) else None


def kind_of(cls: object) -> Kind | None:
    """The kind of a declared class (``Kind.FUNCTION_BLOCK``...), or None for any other object."""
    record = getattr(cls, "__iec__", None)
    return record.kind if isinstance(record, IecClass) else None


def layout_of(cls: object, *, own: bool = False) -> ClassLayout | None:
    """The memory layout of a declared STRUCT, UNION, FUNCTION_BLOCK, PROGRAM or GVL class, or None for any other.

    Its ``fields`` are every variable, base fields first, and ``by_name`` finds one by Python name.
    With ``own``, only a layout the class itself declares (not one inherited from its base).

    >>> from iecoop import INT, Struct
    >>> from iecoop.metadata import layout_of
    >>> class Limits(Struct):
    ...     low: INT = 0
    >>> [record.name for record in layout_of(Limits).fields], layout_of(int)
    (['low'], None)
    """
    if own:
        layout: ClassLayout | None = getattr(cls, "__dict__", {}).get("_iec_layout_")
    else:
        layout = getattr(cls, "_iec_layout_", None)
    return layout


def _required_layout(cls: object) -> ClassLayout:
    layout = layout_of(cls)
    if layout is None:
        raise TypeError(f"{cls!r} is not a STRUCT, UNION, FUNCTION_BLOCK, PROGRAM or GVL class declared with iecoop")
    return layout


def fields_of(cls: object) -> tuple[FieldRecord, ...]:
    """The record of every variable of a class with a layout (see ``layout_of``), base fields first."""
    return _required_layout(cls).fields


def field_record(cls: object, name: str) -> FieldRecord:
    """The record of the variable ``name`` (its Python name) of a class with a layout; KeyError if it has none."""
    return _required_layout(cls).by_name[name]


def is_root(cls: object) -> bool:
    """Whether ``cls`` is one of the library's own base classes (``FunctionBlock``, ``Struct``...), not a declared type."""
    record = getattr(cls, "__iec__", None)
    # The record is inherited: only a root's own (in its __dict__) says root.
    return isinstance(record, IecClass) and record.root and getattr(cls, "__dict__", {}).get("__iec__") is record


def st_name(cls: type, member: str | None = None) -> str:
    """The ST name of a declared class, or of its variable, METHOD, PROPERTY or enumeration value ``member``.

    It is the ``st_name=`` given at the declaration (``in_: INT = VAR_INPUT(st_name="in")``,
    ``@method(st_name="body")``, ``class IQueryInterface_(Interface, st_name="IQueryInterface")``,
    ``class E(IecEnum, st_names={"None_": "None"})``), else the Python name. Read from the
    class record: nothing is stored on instances and no variable access looks here.

    ST::

        VAR_INPUT in : BOOL; END_VAR

    >>> from iecoop import BOOL, FunctionBlock, VAR_INPUT
    >>> from iecoop.metadata import st_name
    >>> class Gate(FunctionBlock, st_name="FB_Gate"):
    ...     in_: BOOL = VAR_INPUT(st_name="in")
    >>> st_name(Gate), st_name(Gate, "in_")
    ('FB_Gate', 'in')
    """
    record = getattr(cls, "__dict__", {}).get("__iec__")
    if member is None:
        return record.st_name if isinstance(record, IecClass) and record.st_name else cls.__name__
    record = iec_class(cls)
    if record is None:
        raise TypeError(f"st_name: {cls!r} is not a class declared with iecoop")
    found = _st_names(cls, record).get(member)
    if found is None:
        raise AttributeError(f"st_name: {st_name(cls)} declares no variable, METHOD, PROPERTY or value {member!r}")
    return found


def member_named(cls: type, name: str) -> str | None:
    """The Python name of ``cls``'s member whose ST name is ``name`` (case-insensitive, as ST), or None.

    >>> from iecoop import BOOL, FunctionBlock, VAR_INPUT
    >>> from iecoop.metadata import member_named
    >>> class Gate(FunctionBlock):
    ...     in_: BOOL = VAR_INPUT(st_name="in")
    >>> member_named(Gate, "IN"), member_named(Gate, "out")
    ('in_', None)
    """
    record = iec_class(cls)
    if record is None:
        return None
    lowered = name.lower()
    return next((python for python, st in _st_names(cls, record).items() if st.lower() == lowered), None)


def _st_names(cls: type, record: IecClass) -> dict[str, str]:
    """Python name -> ST name of every member of ``cls``, its bases' included."""
    names: dict[str, str] = {}
    if record.kind is Kind.ENUM:
        names.update((python, record.value_names.get(python, python)) for python in getattr(cls, "__members__", {}))
        return names
    if record.layout is not None:
        names.update((field.name, field.st_name) for field in record.layout.fields)
    names.update((field.name, field.st_name) for field in record.static_fields)
    names.update((member.name, member.st_name or member.name) for member in record.members.values())
    return names
