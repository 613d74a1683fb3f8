"""``ARRAY[*]``: a block's VAR_IN_OUT that takes an ARRAY of any bounds.

ST (TwinCAT 3, CODESYS)::

    FUNCTION_BLOCK FB_Sum
    VAR_IN_OUT
        aData : ARRAY[*] OF INT;
    END_VAR

Python: ``aData: ARRAY[INT] = VAR_IN_OUT(bounds="*")`` (``bounds=("*", "*")``
for ``ARRAY[*, *]``). A FUNCTION or METHOD takes such an array as the array
itself for the one call; a block keeps it between calls, so its memory holds
what the PLC passes hidden beside the address: the array's handle and its
bounds, set at each call that binds it. A read of ``self.aData`` is that array
with those bounds (``LOWER_BOUND`` / ``UPPER_BOUND`` read them).
"""

from __future__ import annotations

import ctypes
from typing import Any

from iecoop.memory._aggregates import ArrayInfo, array_info
from iecoop.memory._handles import access_violation, handle_of
from iecoop.memory._infos import Address, TypeInfo
from iecoop.memory.references import ReferenceInfo

__all__ = ["OpenArrayInfo", "OpenArrayReferenceInfo", "open_dimensions"]


def open_dimensions(bounds: object) -> int | None:
    """How many dimensions ``bounds="*"`` / ``("*", "*")`` leaves open; None for any other bounds."""
    if bounds == "*":
        return 1
    if isinstance(bounds, tuple) and bounds and all(isinstance(b, str) and b == "*" for b in bounds):
        return len(bounds)
    return None


class OpenArrayInfo(TypeInfo):
    """The type ``ARRAY[*] OF T``: an element type and a number of dimensions, no bounds.

    No variable has this type itself: only a VAR_IN_OUT refers to an array of it
    (``OpenArrayReferenceInfo``).
    """

    direct = False

    def __init__(self, elem: TypeInfo, dims: int) -> None:
        self.elem = elem
        self.dims = dims
        self.name = f"ARRAY[{', '.join('*' * dims)}] OF {elem.name}"

    @property
    def signature(self) -> str:
        return f"ARRAY[{', '.join('*' * self.dims)}] OF {self.elem.signature}"

    def admits(self, info: TypeInfo | None) -> bool:
        """True for an ARRAY of this element type with this many dimensions, whatever its bounds."""
        return isinstance(info, ArrayInfo) and len(info.bounds) == self.dims and info.elem.signature == self.elem.signature


class OpenArrayReferenceInfo(ReferenceInfo):
    """A block's ``VAR_IN_OUT x : ARRAY[*] OF T``: the bound array's handle and its bounds, in the block's memory."""

    def __init__(self, target: OpenArrayInfo) -> None:
        super().__init__(target)
        self.open = target
        # The handle as a reference holds it, then (lo, hi) per dimension.
        self.ctype = type(f"_OpenArray{target.dims}", (ctypes.Structure,), {
            "_fields_": [("handle", ctypes.c_uint64), ("bounds", ctypes.c_int32 * (2 * target.dims))],
        })

    @property
    def signature(self) -> str:
        return f"REFERENCE TO {self.open.signature}"

    def bound(self, root: Any, offset: int, where: str) -> tuple[int, ArrayInfo]:
        """The handle of the array last bound and its ARRAY type; unbound faults as a reference does."""
        record = self.ctype.from_buffer(root, offset)
        if record.handle == 0:
            raise access_violation(f"{where}: VAR_IN_OUT {self.open.name} is not bound (assign it at the call)")
        values = list(record.bounds)
        pairs = tuple((values[i], values[i + 1]) for i in range(0, len(values), 2))
        return record.handle, array_info(self.open.elem, pairs)

    def array_at(self, root: Any, offset: int, where: str) -> Any:
        """The array last bound, a view with its bounds."""
        handle, info = self.bound(root, offset, where)
        return info.load_handle(handle, where)

    def load(self, root: Any, offset: int) -> Any:
        return self.array_at(root, offset, self.name)

    def store(self, root: Any, offset: int, value: Any, where: str) -> None:
        handle, info = self.bound(root, offset, where)
        info.store_handle(handle, value, where)

    def bind_handle(self, target: Any, where: str) -> Any:
        """What the call stores: the array's handle and bounds; ``target`` an ARRAY or its address."""
        record = self.ctype()
        if target is None:
            return record
        if isinstance(target, Address):
            info, handle = target._target, target._handle
        else:
            info, handle = getattr(type(target), "_iec_info_", None), None
        if not self.open.admits(info):
            got = info.name if isinstance(info, TypeInfo) else type(target).__name__
            raise TypeError(f"{where}: {self.open.name} takes an ARRAY of {self.open.elem.name} with "
                            f"{self.open.dims} dimension{'s' if self.open.dims > 1 else ''}, got {got}")
        assert isinstance(info, ArrayInfo)
        record.handle = handle_of(target) if handle is None else handle
        record.bounds[:] = [b for pair in info.bounds for b in pair]
        return record

    def bind_constant(self, owner: Any, value: Any, where: str) -> Any:
        # VAR_IN_OUT CONSTANT: an ARRAY[*] takes a variable, whose handle the call keeps.
        return self.bind_handle(value, where)

    def descriptor(self, raw: Any, name: str, owner: str) -> Any:
        return _OpenArrayField(self, raw, f"{owner}.{name}")


class _OpenArrayField:
    """``self.aData``: the array bound at the last call, with its bounds; ``self.aData = other`` copies into it."""

    __slots__ = ("info", "offset", "where")

    def __init__(self, info: OpenArrayReferenceInfo, raw: Any, where: str) -> None:
        self.info, self.offset, self.where = info, raw.offset, where

    def __get__(self, obj: Any, owner: Any = None) -> Any:
        if obj is None:
            return self
        return self.info.array_at(obj, self.offset, self.where)

    def __set__(self, obj: Any, value: Any) -> None:
        self.info.store(obj, self.offset, value, self.where)
