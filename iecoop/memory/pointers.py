"""``POINTER TO T``: the public pointer type, ``Pointer`` (``POINTER_TO`` in annotations).

A pointer holds a checked handle into a memory block, never a raw address;
``adr`` makes one and ``p.deref`` is ST's ``p^``.
"""

from __future__ import annotations

import ctypes
import typing
from collections.abc import Callable
from typing import Any, ClassVar, Generic, TypeVar

from iecoop.memory._handles import (
    WILD_OFFSET,
    _HANDLE_MASK,
    access_violation,
    allocation_for_handle,
    hold,
    signed_offset,
    target_root,
)
from iecoop.memory._infos import Address, TypeInfo, _kind_error
from iecoop.memory._resolve import _Resolver, _annotation_name, _check_plain, resolve_type
from iecoop.exceptions import DefinitionError
from iecoop.memory.arrays import ARRAY
from iecoop.memory.open_arrays import open_dimensions
from iecoop.memory.references import REFERENCE, ReferenceInfo

__all__ = ["POINTER_TO", "Pointer", "PointerInfo"]

_T = TypeVar("_T")


class Pointer(Address, Generic[_T]):
    """``POINTER TO T``: an address into a checked memory block.

    Arithmetic is in bytes, as in ST (``p + 2 * sizeof(INT)``); ``p.deref`` is
    ``p^``. A null pointer is falsy; dereferencing it, or an address outside
    its block or into deleted memory, raises RTSEXCPT_ACCESS_VIOLATION.

    >>> from iecoop import INT, Struct, adr, sizeof
    >>> class Pair(Struct):
    ...     a: INT = 1
    ...     b: INT = 2
    >>> pair = Pair()
    >>> p = adr(pair, "a")
    >>> (p + sizeof(INT)).deref
    2
    """

    __slots__ = ("_handle", "_target", "_origin", "_keep")

    #: How ``resolve_type`` reads ``POINTER_TO[T]``.
    _iec_resolve_: ClassVar[Callable[..., TypeInfo]]

    _handle: int
    _target: TypeInfo | None
    _origin: tuple[Any, Any] | None
    #: The block the address is into, when ADR took it of an object Python owns: the pointer
    #: keeps it alive, and so does a block the pointer is stored in.
    _keep: Any

    def __init__(
        self, handle: int = 0, target: TypeInfo | None = None, origin: tuple[Any, Any] | None = None, keep: Any = None
    ) -> None:
        self._handle = handle & 0xFFFFFFFFFFFFFFFF
        self._target = target
        self._origin = origin
        self._keep = keep

    def _clear(self) -> None:
        """Set the pointer to 0, and the variable it was read from (``__DELETE(p)`` does)."""
        self._handle = 0
        if self._origin is not None:
            holder, raw = self._origin
            raw.__set__(holder, 0)
            hold(holder, raw.offset, None)

    @property
    def handle(self) -> int:
        """The stored 8-byte value (the address as PVOID / __UXINT)."""
        return self._handle

    def _require_target(self) -> TypeInfo:
        if self._target is None:
            raise TypeError("an untyped pointer (PVOID) cannot be dereferenced; cast it with typed()")
        return self._target

    @property
    def deref(self) -> _T:
        """``p^``: the value (or a view of the struct / FB) the pointer designates."""
        target = self._require_target()
        return typing.cast(_T, target.load_handle(self._handle, f"POINTER TO {target.name}"))

    @deref.setter
    def deref(self, value: _T) -> None:
        target = self._require_target()
        target.store_handle(self._handle, value, f"POINTER TO {target.name}")

    @property
    def is_null(self) -> bool:
        return self._handle == 0

    def typed(self, target: Any) -> Pointer[Any]:
        """The same address seen as ``POINTER TO target`` (an IEC type annotation)."""
        return Pointer(self._handle, resolve_type(target, "pointer cast"), keep=self._keep)

    def __bool__(self) -> bool:
        return self._handle != 0

    def __int__(self) -> int:
        return self._handle

    def __index__(self) -> int:
        return self._handle

    def _moved(self, delta: int) -> Pointer[_T]:
        handle = self._handle
        offset = signed_offset(handle)
        if offset != WILD_OFFSET:
            # Full width: an address moved outside the 32-bit offset range becomes wild for
            # good, so no amount of arithmetic wraps it back into its block.
            offset += delta
            if not -(2**31) <= offset < WILD_OFFSET:
                offset = WILD_OFFSET
        return Pointer((handle & ~_HANDLE_MASK) | (offset & _HANDLE_MASK), self._target, keep=self._keep)

    def __add__(self, offset: int) -> Pointer[_T]:
        if not isinstance(offset, int):
            return NotImplemented
        return self._moved(offset)

    __radd__ = __add__

    @typing.overload
    def __sub__(self, other: int) -> Pointer[_T]: ...

    @typing.overload
    def __sub__(self, other: Pointer[Any]) -> int: ...

    def __sub__(self, other: int | Pointer[Any]) -> Pointer[_T] | int:
        if isinstance(other, Pointer):
            if (self._handle >> 32) != (other._handle >> 32):
                raise access_violation("pointer difference between two different memory blocks")
            return signed_offset(self._handle) - signed_offset(other._handle)
        if isinstance(other, int):
            return self._moved(-other)
        return NotImplemented

    def __eq__(self, other: object) -> bool:
        if isinstance(other, Pointer):
            return self._handle == other._handle
        if isinstance(other, int) and not isinstance(other, bool):
            return self._handle == other
        if other is None:  # NULL
            return self._handle == 0
        return NotImplemented

    def __hash__(self) -> int:
        return hash(self._handle)

    # ``p < q`` compares addresses, as CODESYS and TwinCAT compile it. Within one block that is
    # the byte offset; 0 (NULL) is below every address; two blocks compare in the order they
    # were allocated (a real PLC orders them by where the linker put them, as fixed).
    @staticmethod
    def _address_key(value: object, op: str) -> tuple[int, int]:
        if isinstance(value, Pointer):
            handle = value._handle
            return (handle >> 32, signed_offset(handle)) if handle else (0, 0)
        if value is None or (type(value) is int and value == 0):
            return (0, 0)
        raise TypeError(f"POINTER {op}: a pointer compares with a pointer or with 0 (NULL), got {value!r}")

    def __lt__(self, other: object) -> bool:
        return self._address_key(self, "<") < self._address_key(other, "<")

    def __le__(self, other: object) -> bool:
        return self._address_key(self, "<=") <= self._address_key(other, "<=")

    def __gt__(self, other: object) -> bool:
        return self._address_key(self, ">") > self._address_key(other, ">")

    def __ge__(self, other: object) -> bool:
        return self._address_key(self, ">=") >= self._address_key(other, ">=")

    def __repr__(self) -> str:
        target = self._target.name if self._target is not None else "PVOID"
        if self._handle == 0:
            return f"<POINTER TO {target}: 0>"
        alloc = allocation_for_handle(self._handle)
        where = alloc.label if alloc is not None else "freed memory"
        return f"<POINTER TO {target}: {where}{signed_offset(self._handle):+d}>"


#: ``POINTER TO T``; ``POINTER_TO[INT]`` in annotations.
POINTER_TO = Pointer


class PointerInfo(TypeInfo):
    direct = False
    ctype = ctypes.c_uint64

    def __init__(self, target: Callable[[], TypeInfo | None], target_name: str) -> None:
        self._target_thunk = target
        self._target: TypeInfo | None = None
        self.name = f"POINTER TO {target_name}"

    @property
    def target(self) -> TypeInfo | None:
        if self._target is None:
            self._target = self._target_thunk()
        return self._target

    def load(self, root: Any, offset: int) -> Pointer[Any]:
        return Pointer(ctypes.c_uint64.from_buffer(root, offset).value, self.target)

    def store(self, root: Any, offset: int, value: Any, where: str) -> None:
        handle = self.coerce(value, where)
        ctypes.c_uint64.from_buffer(root, offset).value = handle
        hold(root, offset, _kept_target(value, handle))

    def coerce(self, value: Any, where: str) -> int:
        if isinstance(value, Pointer):
            return value._handle
        if value is None or (isinstance(value, int) and not isinstance(value, bool) and value == 0):
            return 0
        raise _kind_error(where, self.name + " (use adr(...))", value)

    def validate(self, value: Any, where: str) -> None:
        self.coerce(value, where)


    def descriptor(self, raw: Any, name: str, owner: str) -> Any:
        return _PointerField(self, raw, f"{owner}.{name}")


class _PointerField:
    __slots__ = ("info", "raw", "where")

    def __init__(self, info: PointerInfo, raw: Any, where: str) -> None:
        self.info, self.raw, self.where = info, raw, where

    def __get__(self, obj: Any, owner: Any = None) -> Any:
        if obj is None:
            return self
        return Pointer(self.raw.__get__(obj), self.info.target, (obj, self.raw))

    def __set__(self, obj: Any, value: Any) -> None:
        handle = value._handle if type(value) is Pointer else self.info.coerce(value, self.where)
        raw = self.raw
        # Storing the address the variable already holds (every cycle, often) changes nothing.
        if raw.__get__(obj) != handle:
            raw.__set__(obj, handle)
            hold(obj, raw.offset, _kept_target(value, handle))


def _kept_target(value: Any, handle: int) -> Any:
    """The block a stored pointer keeps alive: the one its address is into."""
    if not handle:
        return None
    keep = getattr(value, "_keep", None)
    return keep if keep is not None else target_root(handle)


def _resolve_pointer(annotation: Any, where: str, length: int | None, bounds: object, resolver: _Resolver) -> TypeInfo:
    """``POINTER_TO[T]`` (its target resolved lazily, so a block may point to itself), or ``Pointer``: PVOID."""
    if annotation is Pointer:
        return PointerInfo(lambda: None, "PVOID")
    (target_annotation,) = typing.get_args(annotation) or (None,)
    if typing.get_origin(target_annotation) is typing.Annotated and REFERENCE in target_annotation.__metadata__:
        # CODESYS: a reference type is never the base type of an array, a pointer or a reference.
        raise DefinitionError(f"{where}: POINTER TO REFERENCE is not allowed; point to the referenced type instead")
    to_array = typing.get_origin(target_annotation) is ARRAY
    if to_array and open_dimensions(bounds) is not None:
        raise DefinitionError(f"{where}: POINTER TO ARRAY[*] is not allowed; only a block's VAR_IN_OUT takes an ARRAY[*]")
    if not to_array:
        _check_plain(None, bounds, where, "POINTER")

    def thunk() -> TypeInfo | None:
        if target_annotation is None or target_annotation is Any:
            return None
        # bounds= belong to a pointed-to ARRAY (POINTER TO ARRAY[1..8] OF INT)
        target = resolve_type(target_annotation, where, length=length, bounds=bounds if to_array else None, resolver=resolver)
        if isinstance(target, ReferenceInfo):  # named by a string, so seen only now
            raise DefinitionError(f"{where}: POINTER TO REFERENCE is not allowed; point to the referenced type instead")
        return target

    return PointerInfo(thunk, _annotation_name(target_annotation))


Pointer._iec_resolve_ = staticmethod(_resolve_pointer)
