"""Elementary IEC 61131-3 data types.

Each type is an ``Annotated`` alias: a type checker reads ``INT`` as ``int``,
``REAL`` as ``float``, ``BOOL`` as ``bool`` and ``STRING`` as ``str``, while the
class builder reads the ``ElementaryType`` record carried in the metadata
(size, range, the ctypes storage type). Values stored into a typed variable
behave as on the PLC: integers wrap modulo 2^n, REAL is a 32-bit float,
STRING(n) is truncated to n Latin-1 bytes.

ST: ``x : INT;``  Python: ``x: INT = VAR(0)``

>>> INT_T = elementary_type(INT)
>>> INT_T.name, INT_T.size, INT_T.low, INT_T.high
('INT', 2, -32768, 32767)
>>> INT_T.store(40000)
-25536
>>> elementary_type(REAL).store(0.1)
0.10000000149011612
"""

from __future__ import annotations

import ctypes
import dataclasses
import math
import struct
import typing
from typing import TYPE_CHECKING, Annotated, Any, Final, Literal, TypeAlias

__all__ = [
    "BOOL",
    "BYTE",
    "DATE",
    "DINT",
    "DT",
    "DWORD",
    "ELEMENTARY_TYPES",
    "ElementaryType",
    "INT",
    "LINT",
    "LREAL",
    "LTIME",
    "LWORD",
    "REAL",
    "SINT",
    "STRING",
    "StringType",
    "TIME",
    "TOD",
    "UDINT",
    "UINT",
    "ULINT",
    "USINT",
    "WORD",
    "WSTRING",
    "elementary_type",
    "iec_type_name",
]

Kind = Literal["bool", "signed", "unsigned", "real", "time", "date", "string"]

_F32 = struct.Struct("<f")


def _round_f32(value: float) -> float:
    """Round a Python float to the nearest IEEE 754 single, as a REAL store does."""
    if math.isnan(value) or math.isinf(value):
        return value
    try:
        return float(_F32.unpack(_F32.pack(value))[0])
    except OverflowError:
        return math.copysign(math.inf, value)


@dataclasses.dataclass(frozen=True, eq=False)
class ElementaryType:
    """One elementary IEC type: its name, ctypes storage, Python type and range."""

    name: str
    ctype: Any
    py_type: type
    kind: Kind
    low: int | float | None = None
    high: int | float | None = None
    #: Unit of TIME-like values ("ms", "ns", "s").
    unit: str = ""

    @property
    def size(self) -> int:
        """Size in bytes (SIZEOF)."""
        return int(ctypes.sizeof(self.ctype))

    @property
    def bits(self) -> int:
        return self.size * 8


    def store(self, value: Any) -> Any:
        """The value a variable of this type holds after ``x := value``."""
        if self.kind == "bool":
            return bool(value)
        if self.kind == "real":
            return _round_f32(float(value)) if self.size == 4 else float(value)
        bits = self.bits
        wrapped = int(value) & ((1 << bits) - 1)
        if self.kind == "signed" and wrapped >= 1 << (bits - 1):
            wrapped -= 1 << bits
        return wrapped

    def __repr__(self) -> str:
        return f"<IEC type {self.name}>"


@dataclasses.dataclass(frozen=True, eq=False)
class StringType:
    """STRING (Latin-1, one byte a character) or WSTRING (UCS-2, two bytes a character).

    The length is set at the declaration: ``VAR("", length=20)`` is STRING(20).
    """

    name: Literal["STRING", "WSTRING"]
    default_length: int = 80

    @property
    def py_type(self) -> type:
        return str

    @property
    def char_size(self) -> int:
        return 1 if self.name == "STRING" else 2

    def ctype(self, length: int) -> Any:
        """The storage for STRING(length): length characters plus the terminator."""
        char = ctypes.c_char if self.name == "STRING" else ctypes.c_uint16
        return char * (length + 1)

    def size(self, length: int) -> int:
        return (length + 1) * self.char_size

    def encode(self, value: str, length: int, where: str) -> bytes:
        """The bytes stored for ``value`` in a STRING(length): truncated from the right."""
        if not isinstance(value, str):
            raise TypeError(f"{where}: {self.name} expects str, got {type(value).__name__}")
        if self.name == "STRING":
            try:
                data = value.encode("latin-1")
            except UnicodeEncodeError as exc:
                bad = value[exc.start]
                raise ValueError(
                    f"{where}: character {bad!r} has no Latin-1 code; STRING holds Latin-1, use WSTRING"
                ) from None
            return data[:length]
        # A lone surrogate is no UCS-2 character either, and utf-16 cannot encode it.
        if any(ord(ch) > 0xFFFF or 0xD800 <= ord(ch) <= 0xDFFF for ch in value):
            raise ValueError(f"{where}: WSTRING holds UCS-2; {value!r} has a character outside it")
        return value[:length].encode("utf-16-le")

    def store(self, value: str, length: int | None = None) -> str:
        """The text a STRING(length) holds after ``s := value``."""
        n = self.default_length if length is None else length
        data = self.encode(value, n, self.name)
        cut = data.split(b"\x00", 1)[0] if self.name == "STRING" else data
        if self.name == "STRING":
            return cut.decode("latin-1")
        text = data.decode("utf-16-le")
        return text.split("\x00", 1)[0]

    def __repr__(self) -> str:
        return f"<IEC type {self.name}>"


def _int(name: str, ctype: Any, signed: bool, kind: Kind | None = None, unit: str = "") -> ElementaryType:
    bits = ctypes.sizeof(ctype) * 8
    low, high = (-(1 << (bits - 1)), (1 << (bits - 1)) - 1) if signed else (0, (1 << bits) - 1)
    return ElementaryType(name, ctype, int, kind or ("signed" if signed else "unsigned"), low, high, unit)


BOOL_T: Final = ElementaryType("BOOL", ctypes.c_bool, bool, "bool", 0, 1)
SINT_T: Final = _int("SINT", ctypes.c_int8, True)
USINT_T: Final = _int("USINT", ctypes.c_uint8, False)
INT_T: Final = _int("INT", ctypes.c_int16, True)
UINT_T: Final = _int("UINT", ctypes.c_uint16, False)
DINT_T: Final = _int("DINT", ctypes.c_int32, True)
UDINT_T: Final = _int("UDINT", ctypes.c_uint32, False)
LINT_T: Final = _int("LINT", ctypes.c_int64, True)
ULINT_T: Final = _int("ULINT", ctypes.c_uint64, False)
BYTE_T: Final = _int("BYTE", ctypes.c_uint8, False)
WORD_T: Final = _int("WORD", ctypes.c_uint16, False)
DWORD_T: Final = _int("DWORD", ctypes.c_uint32, False)
LWORD_T: Final = _int("LWORD", ctypes.c_uint64, False)
REAL_T: Final = ElementaryType("REAL", ctypes.c_float, float, "real", -3.402823466e38, 3.402823466e38)
LREAL_T: Final = ElementaryType("LREAL", ctypes.c_double, float, "real", -1.7976931348623157e308, 1.7976931348623157e308)
TIME_T: Final = _int("TIME", ctypes.c_uint32, False, "time", "ms")
LTIME_T: Final = _int("LTIME", ctypes.c_uint64, False, "time", "ns")
DATE_T: Final = _int("DATE", ctypes.c_uint32, False, "date", "s")
TOD_T: Final = dataclasses.replace(_int("TOD", ctypes.c_uint32, False, "date", "ms"), high=86_399_999)
DT_T: Final = _int("DT", ctypes.c_uint32, False, "date", "s")
STRING_T: Final = StringType("STRING")
WSTRING_T: Final = StringType("WSTRING")

BOOL: TypeAlias = Annotated[bool, BOOL_T]
SINT: TypeAlias = Annotated[int, SINT_T]
USINT: TypeAlias = Annotated[int, USINT_T]
INT: TypeAlias = Annotated[int, INT_T]
UINT: TypeAlias = Annotated[int, UINT_T]
DINT: TypeAlias = Annotated[int, DINT_T]
UDINT: TypeAlias = Annotated[int, UDINT_T]
LINT: TypeAlias = Annotated[int, LINT_T]
ULINT: TypeAlias = Annotated[int, ULINT_T]
BYTE: TypeAlias = Annotated[int, BYTE_T]
WORD: TypeAlias = Annotated[int, WORD_T]
DWORD: TypeAlias = Annotated[int, DWORD_T]
LWORD: TypeAlias = Annotated[int, LWORD_T]
REAL: TypeAlias = Annotated[float, REAL_T]
LREAL: TypeAlias = Annotated[float, LREAL_T]
TIME: TypeAlias = Annotated[int, TIME_T]
DATE: TypeAlias = Annotated[int, DATE_T]

if TYPE_CHECKING:
    LTIME: TypeAlias = Annotated[int, LTIME_T]
    TOD: TypeAlias = Annotated[int, TOD_T]
    DT: TypeAlias = Annotated[int, DT_T]
else:
    # LTIME, TOD and DT name both a type and a literal prefix (LTIME#1ms), so they are
    # callable. Calling an ``Annotated`` alias calls its underlying type (typing documents
    # "instantiating is the same as instantiating the underlying type"), so the runtime
    # alias wraps an int subclass whose constructor parses the literal; a type checker
    # sees ``Annotated[int, ...]`` and ``LTIME("1ms")`` as ``int(...)``, which fits.

    class _Literal(int):
        """The underlying type of a literal-taking alias: ``LTIME("1ms")`` is ``LTIME#1ms`` as an int."""

        _parser = ""

        def __new__(cls, text: str) -> int:  # a plain int: the value, not an instance
            from iecoop import literals

            return int(getattr(literals, cls._parser)(text))

    def _literal_alias(record: ElementaryType, parser: str) -> Any:
        underlying = type(record.name, (_Literal,), {"_parser": parser, "__module__": __name__})
        return Annotated[underlying, record]

    LTIME = _literal_alias(LTIME_T, "parse_ltime")
    TOD = _literal_alias(TOD_T, "parse_tod")
    DT = _literal_alias(DT_T, "parse_dt")
STRING: TypeAlias = Annotated[str, STRING_T]
WSTRING: TypeAlias = Annotated[str, WSTRING_T]

#: Every elementary type by IEC name.
ELEMENTARY_TYPES: Final[dict[str, ElementaryType | StringType]] = {
    t.name: t
    for t in (
        BOOL_T, SINT_T, USINT_T, INT_T, UINT_T, DINT_T, UDINT_T, LINT_T, ULINT_T, BYTE_T, WORD_T,
        DWORD_T, LWORD_T, REAL_T, LREAL_T, TIME_T, LTIME_T, DATE_T, TOD_T, DT_T, STRING_T, WSTRING_T,
    )
}


def elementary_type(annotation: object) -> ElementaryType | StringType | None:
    """The IEC record behind an annotation such as ``INT``, or None if it is not elementary."""
    if typing.get_origin(annotation) is Annotated:
        for meta in getattr(annotation, "__metadata__", ()):
            if isinstance(meta, (ElementaryType, StringType)):
                return meta
    return None


def iec_type_name(annotation: object) -> str | None:
    """The IEC name of an elementary annotation (``"INT"``), else None."""
    record = elementary_type(annotation)
    return record.name if record is not None else None
