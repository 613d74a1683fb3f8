"""C-style strings read and written through a pointer, to their terminating 0, as Tc2_Utilities' pointer
functions (FindAndReplace, LEN2, WLEN2, WSTRING_TO_STRING2, STRING_TO_WSTRING2) reach them."""

from __future__ import annotations

from typing import Any

from iecoop.exceptions import ExceptionCode, PlcException
from iecoop.memory import Pointer
from iecoop.types import BYTE, WORD

__all__ = ["MAX_CHARACTERS", "c_string", "put_c_string"]

#: How far FindAndReplace reads a source string looking for its end (Tc2_Utilities' Parameterlist.cMaxCharacters).
MAX_CHARACTERS = 2048


def c_string(pointer: Pointer[Any], what: str, function: str = "FindAndReplace", width: int = 1) -> bytes:
    """The STRING (``width`` 1) or WSTRING (2) at ``pointer``, read to its terminating 0 (at most MAX_CHARACTERS
    characters), whatever its declared length: its bytes, the terminator left out."""
    if not pointer:
        raise PlcException(ExceptionCode.RTSEXCPT_ACCESS_VIOLATION, f"{function}: {what} is a null pointer")
    data = bytearray()
    at = pointer.typed(BYTE if width == 1 else WORD)
    while len(data) < MAX_CHARACTERS * width:
        value = (at + len(data)).deref
        if value == 0:
            break
        data += value.to_bytes(width, "little")
    return bytes(data)


def put_c_string(pointer: Pointer[Any], data: bytes, size: int, width: int) -> bool:
    """``data`` written at ``pointer`` into ``size`` bytes, cut to whole characters and a 0 after them; all of it?"""
    room = max(0, (int(size) - width) // width * width)
    target = pointer.typed(BYTE)
    for index, value in enumerate(data[:room] + b"\x00" * width):
        (target + index).deref = value
    return len(data) <= room
