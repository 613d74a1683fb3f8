"""``REFERENCE TO T``: the public reference annotation, ``REFERENCE_TO``, and its ``ReferenceInfo``.

A reference holds a checked handle, bound with ``REF=`` (``ref_assign``);
reads and writes go through to the variable it designates, and using an
unbound reference raises RTSEXCPT_ACCESS_VIOLATION.
"""

from __future__ import annotations

import ctypes
from collections.abc import Callable
from typing import Annotated, Any, ClassVar, TypeVar

from iecoop.exceptions import DefinitionError
from iecoop.memory._aggregates import AggregateInfo, ArrayInfo
from iecoop.memory._handles import access_violation, handle_of
from iecoop.memory._infos import Address, TypeInfo
from iecoop.memory._resolve import _Resolver, resolve_type
from iecoop.memory.interface_references import InterfaceInfo

__all__ = ["REFERENCE_TO", "ReferenceInfo"]

_T = TypeVar("_T")


class _ReferenceMarker:
    """Metadata marking ``REFERENCE_TO[T]`` inside an Annotated type."""

    #: How ``resolve_type`` reads an Annotated type carrying this marker.
    _iec_resolve_: ClassVar[Callable[..., TypeInfo]]

    def __repr__(self) -> str:
        return "REFERENCE"


REFERENCE: Any = _ReferenceMarker()

#: ``REFERENCE TO T``: a type checker sees ``T`` (reads and writes go through).
REFERENCE_TO = Annotated[_T, REFERENCE]


class ReferenceInfo(TypeInfo):
    direct = False
    ctype: Any = ctypes.c_uint64
    checked_as_target = True

    def __init__(self, target: TypeInfo) -> None:
        self.target = target
        self.name = f"REFERENCE TO {target.name}"

    def load(self, root: Any, offset: int) -> Any:
        handle = ctypes.c_uint64.from_buffer(root, offset).value
        return self.target.load_handle(handle, self.name)

    def store(self, root: Any, offset: int, value: Any, where: str) -> None:
        handle = ctypes.c_uint64.from_buffer(root, offset).value
        if handle == 0:
            raise access_violation(f"{where}: reference is not bound (REF= missing)")
        self.target.store_handle(handle, value, where)

    def bind_handle(self, target: Any, where: str) -> int:
        """The handle ``REF= target`` stores: target is a pointer or an aggregate instance."""
        if isinstance(target, Address):
            if target._target is not None and target._target.size < self.target.size:
                raise TypeError(f"{where}: REF= to {target._target.name} does not fit {self.name}")
            return target._handle
        if target is None:
            return 0
        if isinstance(self.target, AggregateInfo):
            self.target.validate(target, where)
            return handle_of(target)
        if isinstance(self.target, ArrayInfo) and type(target) is self.target.ctype:
            return handle_of(target)
        raise TypeError(
            f"{where}: REF= needs adr(...), a struct / FB instance or an ARRAY, got {type(target).__name__}"
        )

    def bind_constant(self, owner: Any, value: Any, where: str) -> int:
        """VAR_IN_OUT CONSTANT: a literal or expression is passed through a temporary the call owns."""
        if isinstance(value, Address) or value is None or isinstance(self.target, AggregateInfo):
            return self.bind_handle(value, where)
        if isinstance(self.target, ArrayInfo) and type(value) is self.target.ctype:
            return handle_of(value)
        holder = self.target.ctype()
        self.target.store(holder, 0, value, where)
        # Kept by the instance until the next call binds another value, so the handle stays valid.
        owner.__dict__[f"_iec_const_{where}"] = holder
        return handle_of(holder)

    def descriptor(self, raw: Any, name: str, owner: str) -> Any:
        return _ReferenceField(self, raw, f"{owner}.{name}")


class _ReferenceField:
    __slots__ = ("info", "raw", "where")

    def __init__(self, info: ReferenceInfo, raw: Any, where: str) -> None:
        self.info, self.raw, self.where = info, raw, where

    def __get__(self, obj: Any, owner: Any = None) -> Any:
        if obj is None:
            return self
        handle = self.raw.__get__(obj)
        if handle == 0:
            raise access_violation(f"{self.where}: reference is not bound (REF= missing)")
        return self.info.target.load_handle(handle, self.where)

    def __set__(self, obj: Any, value: Any) -> None:
        handle = self.raw.__get__(obj)
        if handle == 0:
            raise access_violation(f"{self.where}: reference is not bound (REF= missing)")
        self.info.target.store_handle(handle, value, self.where)


def _resolve_reference(annotation: Any, where: str, length: int | None, bounds: object, resolver: _Resolver) -> TypeInfo:
    """``Annotated[T, REFERENCE]``: REFERENCE TO the type the rest of the annotation names."""
    metadata = annotation.__metadata__
    rest = tuple(m for m in metadata if m is not REFERENCE)
    inner = annotation.__origin__
    target_annotation = Annotated[(inner, *rest)] if rest else inner
    # bounds= belong to a referenced ARRAY (REFERENCE TO ARRAY[1..16] OF REAL)
    target = resolve_type(target_annotation, where, length=length, bounds=bounds, resolver=resolver)
    if len(rest) < len(metadata) - 1:
        # Annotated flattens REFERENCE_TO[REFERENCE_TO[T]] into one marker list: T with two markers.
        target = ReferenceInfo(target)
    if isinstance(target, InterfaceInfo):
        raise DefinitionError(f"{where}: REFERENCE TO {target.name} is not allowed; declare the variable as {target.name} "
                              "itself (an interface variable refers to its instance already)")
    if isinstance(target, ReferenceInfo):
        raise DefinitionError(f"{where}: REFERENCE TO {target.name} is not allowed")
    return ReferenceInfo(target)


_ReferenceMarker._iec_resolve_ = staticmethod(_resolve_reference)
