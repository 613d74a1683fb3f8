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

__all__ = ["IecClass", "Kind", "iec_class", "is_root", "kind_of"]

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


def is_root(cls: object) -> bool:
    """Whether ``cls`` is one of the library's own base classes (``FunctionBlock``, ``Struct``...), not a declared type."""
    record = getattr(cls, "__iec__", None)
    # The record is inherited: only a root's own (in its __dict__) says root.
    return isinstance(record, IecClass) and record.root and getattr(cls, "__dict__", {}).get("__iec__") is record
