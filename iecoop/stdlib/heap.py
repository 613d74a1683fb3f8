"""``__NEW(T, n)``: an array of n elements of an elementary type on the heap, as TwinCAT and CODESYS
allocate a buffer whose size is known only at run time (a message payload, a JSON document).

>>> from iecoop import BYTE, delete
>>> buffer = new_array(BYTE, 4)
>>> (buffer + 3).deref = 0x7F
>>> (buffer + 3).deref, (buffer + 0).deref
(127, 0)
>>> delete(buffer); buffer
<POINTER TO BYTE: 0>
"""

from __future__ import annotations

import functools
from typing import Any

from iecoop.declarations import VAR
from iecoop.lifecycle import new
from iecoop.memory import ARRAY, Pointer, Struct
from iecoop.memory.typeinfo import resolve_type

__all__ = ["MAX_NEW_BYTES", "new_array"]

#: The most bytes one ``__NEW(T, n)`` gets; a larger request returns 0, as __NEW does when memory runs out.
MAX_NEW_BYTES = 64 * 1024 * 1024


@functools.lru_cache(maxsize=256)
def _block(element: Any, count: int) -> type[Struct]:
    """The STRUCT that holds ``count`` elements (made once for each size in use; 256 kept)."""
    namespace = {"__annotations__": {"data": ARRAY[element]}, "data": VAR(bounds=(0, count - 1)),
                 "__module__": __name__, "__qualname__": f"NEW_{count}"}
    return type(f"NEW_{count}", (Struct,), namespace)


def new_array(element: Any, count: int) -> Pointer[Any]:
    """``__NEW(T, n)``: a POINTER TO T at the first of n zeroed elements; 0 when n is not positive or the
    request is larger than MAX_NEW_BYTES. ``__DELETE(p)`` (``delete``) gives the memory back."""
    size = resolve_type(element, "__NEW").size
    count = int(count)
    if count <= 0 or count * size > MAX_NEW_BYTES:
        return Pointer(0, None).typed(element)
    return new(_block(element, count)).typed(element)
