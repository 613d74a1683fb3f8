"""Resolving a type annotation into its ``TypeInfo``, once per declared field.

``INT``, ``STRING`` with ``length=``, an alias, an enumeration, a Struct, FB
or interface class; ``ARRAY[T]``, ``POINTER_TO[T]`` and ``REFERENCE_TO[T]``
resolve through their own classes (``_iec_resolve_``). Anything else is a
``DefinitionError`` naming the field.
"""

from __future__ import annotations

import enum
import typing
from collections.abc import Callable
from typing import Annotated, Any

from iecoop.exceptions import DefinitionError
from iecoop.memory._aggregates import AggregateInfo
from iecoop.memory._infos import ElementaryInfo, EnumInfo, StringInfo, TypeInfo
from iecoop.memory.aliases import Alias
from iecoop.metadata import Kind, kind_of
from iecoop.types import ElementaryType, StringType, elementary_type

_elementary_infos: dict[int, ElementaryInfo] = {}
_string_infos: dict[tuple[str, int], StringInfo] = {}

MAX_STRING_LENGTH = 65535


def elementary_info(record: ElementaryType) -> ElementaryInfo:
    info = _elementary_infos.get(id(record))
    if info is None:
        info = _elementary_infos[id(record)] = ElementaryInfo(record)
    return info


def string_info(record: StringType, length: int) -> StringInfo:
    key = (record.name, length)
    info = _string_infos.get(key)
    if info is None:
        info = _string_infos[key] = StringInfo(record, length)
    return info


#: How a class of another kind is described (an interface: InterfaceInfo), registered by the
#: module that defines that description, so this module does not import it.
_class_infos: dict[Kind, Callable[[type], TypeInfo]] = {}


def register_class_info(kind: Kind, make: Callable[[type], TypeInfo]) -> None:
    """Describe the classes of ``kind`` with ``make(cls)`` in ``class_info``."""
    _class_infos[kind] = make


def class_info(cls: type) -> TypeInfo | None:
    """The TypeInfo of a Struct / Union / FB / interface / enum class, or None."""
    # Kept on the class itself (its own __dict__, never a base's), so it goes with the class.
    info: TypeInfo | None = cls.__dict__.get("_iec_type_info_")
    if info is not None:
        return info
    kind = kind_of(cls)
    if kind in (Kind.STRUCT, Kind.UNION, Kind.FUNCTION_BLOCK):
        if getattr(cls, "_iec_layout_", None) is None:
            return None
        info = AggregateInfo(cls)
    elif kind is Kind.ENUM:
        base = typing.cast(ElementaryType, getattr(cls, "_iec_base_"))
        info = EnumInfo(typing.cast(type[enum.IntEnum], cls), base)
    elif kind in _class_infos:
        info = _class_infos[kind](cls)
    else:
        return None
    setattr(cls, "_iec_type_info_", info)
    return info


def resolve_type(
    annotation: Any,
    where: str,
    *,
    length: int | None = None,
    bounds: object = None,
    resolver: Callable[[Any], Any] | None = None,
) -> TypeInfo:
    """The TypeInfo of an IEC type annotation, or DefinitionError naming ``where``."""
    if isinstance(annotation, str) or isinstance(annotation, typing.ForwardRef):
        if resolver is None:
            raise DefinitionError(f"{where}: cannot resolve the type name {annotation!r}")
        annotation = resolver(annotation)
    origin = typing.get_origin(annotation)
    if origin is Annotated:
        return _resolve_annotated(annotation, where, length, bounds, resolver)
    # ARRAY[T], POINTER_TO[T] and a bare POINTER_TO (PVOID): their classes know how they resolve
    # (iecoop.memory.arrays and .pointers; REFERENCE_TO: iecoop.memory.references).
    resolve = getattr(origin if origin is not None else annotation, "_iec_resolve_", None)
    if resolve is not None:
        return typing.cast(TypeInfo, resolve(annotation, where, length, bounds, resolver))
    if isinstance(annotation, type):
        info = class_info(annotation)
        if info is not None:
            _check_plain(length, bounds, where, info.name)
            return info
        if annotation in (int, float, bool, str):
            raise DefinitionError(
                f"{where}: plain {annotation.__name__} is not an IEC type; use INT, DINT, REAL, LREAL, BOOL or STRING"
            )
        if kind_of(annotation) is Kind.PROGRAM:
            name = annotation.__name__
            raise DefinitionError(
                f"{where}: PROGRAM {name} is not a data type (a program has one instance, no variable holds one); "
                f"read its variables through that instance, as ST reads {name}.x"
            )
    raise DefinitionError(f"{where}: {_annotation_name(annotation)} is not an IEC type")


_Resolver = Callable[[Any], Any] | None


def _resolve_annotated(annotation: Any, where: str, length: int | None, bounds: object, resolver: _Resolver) -> TypeInfo:
    """``Annotated[...]``: a REFERENCE_TO, a STRING(n), an alias of an elementary type, or metadata to look through."""
    metadata = annotation.__metadata__
    # The REFERENCE marker of REFERENCE_TO[T] knows how it resolves, wherever it stands.
    marker = next((m for m in metadata if hasattr(type(m), "_iec_resolve_")), None)
    if marker is not None:
        return typing.cast(TypeInfo, marker._iec_resolve_(annotation, where, length, bounds, resolver))
    record = elementary_type(annotation)
    if isinstance(record, StringType):
        n = record.default_length if length is None else length
        if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= MAX_STRING_LENGTH:
            raise DefinitionError(f"{where}: {record.name} length must be an integer 1..{MAX_STRING_LENGTH}, got {n!r}")
        _check_no_bounds(bounds, where, record.name)
        return string_info(record, n)
    if isinstance(record, ElementaryType):
        _check_plain(length, bounds, where, record.name)
        alias = next((m for m in metadata if isinstance(m, Alias)), None)
        if alias is not None:
            return ElementaryInfo(record, alias.name, alias.initial)
        return elementary_info(record)
    return resolve_type(annotation.__origin__, where, length=length, bounds=bounds, resolver=resolver)


def _annotation_name(annotation: Any) -> str:
    if annotation is None:
        return "PVOID"
    record = elementary_type(annotation)
    if record is not None:
        return record.name
    if isinstance(annotation, type):
        return annotation.__name__
    if isinstance(annotation, str):
        return annotation
    if isinstance(annotation, typing.ForwardRef):
        return annotation.__forward_arg__
    return repr(annotation)


def _check_plain(length: object, bounds: object, where: str, name: str) -> None:
    if length is not None:
        raise DefinitionError(f"{where}: length= applies to STRING / WSTRING, not {name}")
    _check_no_bounds(bounds, where, name)


def _check_no_bounds(bounds: object, where: str, name: str) -> None:
    if bounds is not None:
        raise DefinitionError(f"{where}: bounds= applies to ARRAY, not {name}")
