"""User data types: ``Struct`` (STRUCT), ``Union`` (UNION), ``IecEnum`` and aliases.

A Struct is a real C-compatible block laid out like a TwinCAT 3 x64 target
(natural alignment, pack mode 8). A subclass is ``STRUCT ... EXTENDS``: the
base members come first and a member name may not repeat.

ST::

    TYPE ST_Recipe :
    STRUCT
        speed : REAL := 1.5;
        name  : STRING(20);
    END_STRUCT
    END_TYPE

Python:

>>> from iecoop import REAL, STRING, VAR, Struct, sizeof
>>> class Recipe(Struct):
...     speed: REAL = 1.5
...     name: STRING = VAR("", length=20)
>>> r = Recipe(name="bread")
>>> r
Recipe(speed=1.5, name='bread')
>>> sizeof(Recipe)
28
"""

from __future__ import annotations

import ctypes
import enum
from collections.abc import Mapping
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, ClassVar

from iecoop.exceptions import DefinitionError
from iecoop.memory.aliases import Alias
from iecoop.memory.layout import ClassLayout, DataClassBuilder, assign, class_st_name, register_builder
from iecoop.metadata import IecClass
from iecoop.sections import Kind, check_st_name
from iecoop.types import INT_T, ElementaryType, elementary_type

register_builder(__file__)

__all__ = ["Alias", "IecEnum", "Struct", "Union"]

if TYPE_CHECKING:
    _StructBase = object
    _UnionBase = object
    _StructMetaBase = type
    _UnionMetaBase = type
else:
    _StructBase = ctypes.Structure
    _UnionBase = ctypes.Union
    _StructMetaBase = type(ctypes.Structure)
    _UnionMetaBase = type(ctypes.Union)


def _member_values(obj: Any) -> tuple[Any, ...]:
    layout: ClassLayout = type(obj)._iec_layout_
    return tuple(getattr(obj, f.name) for f in layout.fields)


_STRUCT_BUILDER = DataClassBuilder("STRUCT", Kind.STRUCT)
_UNION_BUILDER = DataClassBuilder("UNION", Kind.UNION)


def _finish(cls: Any, builder: DataClassBuilder) -> None:
    layout = builder.init(cls)
    if layout is not None and not layout.fields:
        raise DefinitionError(f"{builder.kind} {cls.__name__} has no members; declare at least one")


class _StructMeta(_StructMetaBase):
    def __new__(
        mcls, name: str, bases: tuple[type, ...], namespace: dict[str, Any], st_name: str | None = None, **kwargs: Any
    ) -> Any:
        parents = [b.__name__ for b in bases if getattr(b, "_iec_layout_", None) is not None]
        if len(parents) > 1:
            raise DefinitionError(
                f"STRUCT {name} cannot EXTEND both {' and '.join(parents)}: a STRUCT extends one STRUCT at most"
            )
        return super().__new__(mcls, name, bases, _STRUCT_BUILDER.new(name, bases, namespace, st_name), **kwargs)

    def __init__(cls, name: str, bases: tuple[type, ...], namespace: dict[str, Any], **kwargs: Any) -> None:
        super().__init__(name, bases, namespace)
        _finish(cls, _STRUCT_BUILDER)


class _UnionMeta(_UnionMetaBase):
    def __new__(
        mcls, name: str, bases: tuple[type, ...], namespace: dict[str, Any], st_name: str | None = None, **kwargs: Any
    ) -> Any:
        if not namespace.get("_iec_base_class_") and any(getattr(b, "_iec_layout_", None) is not None for b in bases):
            raise DefinitionError(f"UNION {name}: a union cannot extend another union")
        return super().__new__(mcls, name, bases, _UNION_BUILDER.new(name, bases, namespace, st_name), **kwargs)

    def __init__(cls, name: str, bases: tuple[type, ...], namespace: dict[str, Any], **kwargs: Any) -> None:
        super().__init__(name, bases, namespace)
        _finish(cls, _UNION_BUILDER)


class _DataTypeMixin:
    """Construction, equality and repr shared by Struct and Union."""

    _iec_layout_: ClassVar[ClassLayout | None] = None

    def __init__(self, **members: Any) -> None:
        layout = type(self)._iec_layout_
        if layout is None:
            raise DefinitionError(f"{type(self).__name__} is the base class; declare a subclass with members")
        layout.implicit_init(self)
        for name, value in members.items():
            record = layout.by_name.get(name)
            if record is None:
                raise TypeError(f"{type(self).__name__} has no member {name!r}")
            assign(self, record, value)

    def __eq__(self, other: object) -> bool:
        if type(other) is not type(self):
            return NotImplemented
        return _member_values(self) == _member_values(other)

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        layout = type(self)._iec_layout_
        fields = layout.fields if layout is not None else ()
        inner = ", ".join(f"{f.name}={getattr(self, f.name)!r}" for f in fields)
        return f"{type(self).__name__}({inner})"


class Struct(_DataTypeMixin, _StructBase, metaclass=_StructMeta):
    """``STRUCT ... END_STRUCT``; subclass it and declare members with their types."""

    _iec_base_class_: ClassVar[bool] = True
    __iec__: ClassVar[IecClass] = IecClass(Kind.STRUCT, root=True)


class Union(_DataTypeMixin, _UnionBase, metaclass=_UnionMeta):
    """``UNION ... END_UNION``: every member starts at offset 0 and shares the memory.

    >>> from iecoop import BYTE, WORD, ARRAY, VAR, Union
    >>> class Split(Union):
    ...     whole: WORD = 0
    ...     parts: ARRAY[BYTE] = VAR(bounds=(0, 1))
    >>> u = Split(whole=0x1234)
    >>> hex(u.parts[0]), hex(u.parts[1])
    ('0x34', '0x12')
    """

    _iec_base_class_: ClassVar[bool] = True
    __iec__: ClassVar[IecClass] = IecClass(Kind.UNION, root=True)


class _IecEnumMeta(enum.EnumMeta):
    def __new__(
        metacls, cls: str, bases: tuple[type, ...], classdict: Any, *, base: Any = None,
        st_name: str | None = None, st_names: Mapping[str, str] | None = None, **kwds: Any,
    ) -> Any:
        enum_cls = super().__new__(metacls, cls, bases, classdict, **kwds)
        title = f"enumeration {cls}"
        label = class_st_name(st_name, title)
        value_names = {}
        for value_name, value_st in (st_names or {}).items():
            if value_name not in enum_cls.__members__:
                raise DefinitionError(f"{title}: st_names= names {value_name!r}, which is no value of {cls}")
            value_names[value_name] = check_st_name(value_st, f"{title}.{value_name}")
        inherited = getattr(enum_cls, "_iec_base_", INT_T)
        record = elementary_type(base) if base is not None else inherited
        if not isinstance(record, ElementaryType) or record.kind not in ("signed", "unsigned"):
            raise DefinitionError(f"enumeration {cls}: base type must be an integer type, got {base!r}")
        for member in enum_cls:  # type: ignore[var-annotated]
            value = int(member)
            assert record.low is not None and record.high is not None
            if not record.low <= value <= record.high:
                raise DefinitionError(
                    f"enumeration {cls}: {member.name} := {value} does not fit the base type {record.name}"
                )
        type.__setattr__(enum_cls, "_iec_base_", record)
        type.__setattr__(enum_cls, "__iec__", IecClass(Kind.ENUM, st_name=label, value_names=MappingProxyType(value_names)))
        return enum_cls


class IecEnum(enum.IntEnum, metaclass=_IecEnumMeta):
    """An enumeration with an IEC base type (INT unless ``base=`` says otherwise).

    ST: ``TYPE E_Mode : (AUTO := 0, MANUAL := 1) UDINT; END_TYPE``

    >>> from iecoop import UDINT
    >>> class Mode(IecEnum, base=UDINT):
    ...     AUTO = 0
    ...     MANUAL = 1
    >>> Mode.MANUAL, int(Mode.MANUAL)
    (<Mode.MANUAL: 1>, 1)
    """
