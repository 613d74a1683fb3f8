"""How each IEC type lives in memory: ``TypeInfo`` and the elementary, STRING and enumeration kinds.

A ``TypeInfo`` says how one IEC type is stored: its ctypes storage, its size,
how to load and store a value at (block, offset), how checked mode validates a
write, and whether a ctypes field gives the Python value directly (ints,
floats, BOOL, aggregates: no Python code on a read) or needs a descriptor
(STRING, enums, pointers, references, interfaces). Aggregates and ARRAYs are
in ``_aggregates``; how an annotation becomes a ``TypeInfo`` in ``_resolve``.
"""

from __future__ import annotations

import ctypes
import enum
from typing import Any

from iecoop.memory._handles import resolve
from iecoop.types import ElementaryType, StringType

class Address:
    """A pointer value as the memory machinery sees it: a handle and the type it designates.

    ``Pointer`` derives from it, so a reference can be bound to an address
    without this module depending on the public class.
    """

    __slots__ = ()

    _handle: int
    _target: TypeInfo | None


class TypeInfo:
    """How values of one IEC type are stored (base class)."""

    name: str = "?"
    ctype: Any = None
    #: True when a ctypes field of ``ctype`` already yields the Python value (no descriptor).
    direct: bool = True
    #: True when a value written through this type is checked as its ``target`` (REFERENCE TO T: as T).
    checked_as_target: bool = False

    @property
    def size(self) -> int:
        return int(ctypes.sizeof(self.ctype))

    @property
    def signature(self) -> str:
        """Type text recorded with remanent data so a changed type is never loaded."""
        return self.name

    def load(self, root: Any, offset: int) -> Any:
        raise NotImplementedError

    def store(self, root: Any, offset: int, value: Any, where: str) -> None:
        raise NotImplementedError

    def validate(self, value: Any, where: str) -> None:
        """Checked mode: raise TypeError naming ``where`` if ``value`` is of the wrong kind."""


    def descriptor(self, raw: Any, name: str, owner: str) -> Any:
        """A Python descriptor for a field of this type, or None to keep the raw ctypes field."""
        return None

    def load_handle(self, handle: int, what: str) -> Any:
        root, offset = resolve(handle, self.size, what)
        return self.load(root, offset)

    def store_handle(self, handle: int, value: Any, what: str) -> None:
        root, offset = resolve(handle, self.size, what)
        self.store(root, offset, value, what)

    def __repr__(self) -> str:
        return f"<TypeInfo {self.name}>"


def _kind_error(where: str, expected: str, value: object) -> TypeError:
    return TypeError(f"{where}: cannot store {type(value).__name__} {value!r} in {expected}")


class ElementaryInfo(TypeInfo):
    """BOOL, integers, bit strings, REAL/LREAL, TIME and dates: ctypes stores and wraps them."""

    def __init__(self, record: ElementaryType, name: str | None = None, initial: Any = None) -> None:
        self.record = record
        self.name = name or record.name
        self.ctype = record.ctype
        #: An alias's own initial value (``TYPE T_Index : DINT := -1;``), None for none.
        self.initial = initial

    def load(self, root: Any, offset: int) -> Any:
        return self.ctype.from_buffer(root, offset).value

    def store(self, root: Any, offset: int, value: Any, where: str) -> None:
        self.validate(value, where)
        self.ctype.from_buffer(root, offset).value = value

    def validate(self, value: Any, where: str) -> None:
        kind = self.record.kind
        if kind == "bool":
            if not isinstance(value, bool):
                raise _kind_error(where, "BOOL (use True / False)", value)
        elif kind == "real":
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise _kind_error(where, self.name, value)
            if isinstance(value, int) and value.bit_length() > 1000:
                try:
                    float(value)
                except OverflowError:
                    # No IEC integer is this large; a Python int this size has no floating-point value.
                    raise ValueError(
                        f"{where}: an integer of {value.bit_length()} bits is outside the range of {self.name}"
                    ) from None
        elif isinstance(value, bool) or not isinstance(value, int):
            raise _kind_error(where, self.name, value)


class StringInfo(TypeInfo):
    """STRING(n) / WSTRING(n): a terminated buffer shown to Python as ``str``."""

    direct = False

    def __init__(self, record: StringType, length: int) -> None:
        self.record = record
        self.length = length
        self.name = f"{record.name}({length})"
        self.ctype = record.ctype(length)

    def _decode(self, data: bytes) -> str:
        if self.record.name == "STRING":
            return data.split(b"\x00", 1)[0].decode("latin-1")
        text = data.decode("utf-16-le", errors="replace")
        return text.split("\x00", 1)[0]

    def _encode(self, value: Any, where: str) -> bytes:
        data = self.record.encode(value, self.length, where)
        return data + b"\x00" * (self.size - len(data))

    def load(self, root: Any, offset: int) -> str:
        return self._decode((ctypes.c_char * self.size).from_buffer(root, offset).raw)

    def store(self, root: Any, offset: int, value: Any, where: str) -> None:
        ctypes.memmove(ctypes.addressof(root) + offset, self._encode(value, where), self.size)

    def validate(self, value: Any, where: str) -> None:
        self.record.encode(value, self.length, where)


    def descriptor(self, raw: Any, name: str, owner: str) -> Any:
        return _StringField(self, raw.offset, f"{owner}.{name}")


class _StringField:
    __slots__ = ("info", "offset", "where")

    def __init__(self, info: StringInfo, offset: int, where: str) -> None:
        self.info, self.offset, self.where = info, offset, where

    def __get__(self, obj: Any, owner: Any = None) -> Any:
        if obj is None:
            return self
        return self.info._decode((ctypes.c_char * self.info.size).from_buffer(obj, self.offset).raw)

    def __set__(self, obj: Any, value: Any) -> None:
        data = self.info._encode(value, self.where)
        ctypes.memmove(ctypes.addressof(obj) + self.offset, data, self.info.size)


class EnumInfo(TypeInfo):
    """An enumeration with an IEC base type; reads give the member (or the raw number)."""

    direct = False

    def __init__(self, enum_cls: type[enum.IntEnum], base: ElementaryType) -> None:
        self.enum_cls = enum_cls
        self.base = base
        self.name = enum_cls.__name__
        self.ctype = base.ctype

    @property
    def signature(self) -> str:
        return f"{self.name}:{self.base.name}"

    def _member(self, raw: int) -> Any:
        try:
            return self.enum_cls(raw)
        except ValueError:
            return raw

    def load(self, root: Any, offset: int) -> Any:
        return self._member(self.ctype.from_buffer(root, offset).value)

    def store(self, root: Any, offset: int, value: Any, where: str) -> None:
        self.validate(value, where)
        self.ctype.from_buffer(root, offset).value = int(value)

    def validate(self, value: Any, where: str) -> None:
        if isinstance(value, bool) or not isinstance(value, int):
            raise _kind_error(where, self.name, value)
        if not isinstance(value, self.enum_cls) and isinstance(value, enum.Enum):
            raise _kind_error(where, self.name, value)


    def descriptor(self, raw: Any, name: str, owner: str) -> Any:
        return _EnumField(self, raw, f"{owner}.{name}")


class _EnumField:
    __slots__ = ("info", "raw", "where")

    def __init__(self, info: EnumInfo, raw: Any, where: str) -> None:
        self.info, self.raw, self.where = info, raw, where

    def __get__(self, obj: Any, owner: Any = None) -> Any:
        if obj is None:
            return self
        return self.info._member(self.raw.__get__(obj))

    def __set__(self, obj: Any, value: Any) -> None:
        self.info.validate(value, self.where)
        self.raw.__set__(obj, int(value))
