"""Hypothesis strategies for IEC 61131-3 values and for the inputs of function blocks.

Needs hypothesis (``pip install iecoop[dev]``); the rest of ``iecoop.testing``
does not.

Each elementary type has a strategy of the values a variable of that type can
hold (``INT_VALUES``: -32768 .. 32767, ``STRING_VALUES``: Latin-1 text of at
most 80 characters, ...); ``ANY_INTS`` draws Python integers of any size, for
the tests of wrap-around on store. ``iec_values(INT)`` maps an annotation to
its strategy.

The ranges are written out here from the vendor tables (Beckhoff InfoSys,
TwinCAT 3 "Data types": integer, bit string and string types; CODESYS Online
Help "Data Types") rather than read from ``iecoop.types``, so a wrong range in
the library cannot agree with itself in a test.

>>> from iecoop import INT
>>> iec_values(INT) is INT_VALUES
True
>>> integer_range("UDINT")
(0, 4294967295)

``fb_inputs(Fb)`` draws one call's inputs for a function block, and
``input_sequences(Fb)`` a list of them, one per cycle:

>>> from hypothesis import given
>>> from iecoop.stdlib import TON
>>> @given(input_sequences(TON, max_size=5))
... def test_ton_never_reports_more_than_pt(sequence):
...     timer = TON()
...     for inputs in sequence:
...         timer(**inputs)
...         assert timer.ET <= timer.PT
>>> test_ton_never_reports_more_than_pt()
"""

from __future__ import annotations

import struct
from typing import Any, Final

from hypothesis import strategies as st

from iecoop.memory import IecEnum
from iecoop.sections import Section
from iecoop.types import iec_type_name
from iecoop.metadata import Kind, field_record, kind_of, layout_of
from iecoop.st.language import INTEGER_LAYOUT as ST_INTEGER_LAYOUT

__all__ = [
    "ANY_INTS",
    "BOOL_VALUES",
    "BYTE_VALUES",
    "DATE_VALUES",
    "DINT_VALUES",
    "DT_VALUES",
    "DWORD_VALUES",
    "FLT_MAX",
    "INTEGER_LAYOUT",
    "INT_VALUES",
    "LATIN_1",
    "LINT_VALUES",
    "LREAL_VALUES",
    "LTIME_VALUES",
    "LWORD_VALUES",
    "REAL_VALUES",
    "SINT_VALUES",
    "STRING_VALUES",
    "TIME_VALUES",
    "TOD_VALUES",
    "UCS_2",
    "UDINT_VALUES",
    "UINT_VALUES",
    "ULINT_VALUES",
    "USINT_VALUES",
    "WORD_VALUES",
    "WSTRING_VALUES",
    "enum_values",
    "fb_inputs",
    "iec_values",
    "input_sequences",
    "wrap",
    "wrap_int",
    "integer_range",
    "string_values",
    "wstring_values",
]

#: Storage of every integer-like type: name -> (bits, signed), from the ST vocabulary. TIME, LTIME and
#: the date types are unsigned counters of ms / ns / s.
INTEGER_LAYOUT: Final[dict[str, tuple[int, bool]]] = dict(ST_INTEGER_LAYOUT)

#: The largest finite IEEE 754 single (REAL).
FLT_MAX: Final[float] = struct.unpack("<f", b"\xff\xff\x7f\x7f")[0]


def wrap(value: int, bits: int, signed: bool) -> int:
    """Two's complement: keep the low ``bits`` bits, then read the top one as the sign if signed.

    The expected value of a store, written out independently of iecoop.
    """
    modulus = 1 << bits
    low = value % modulus  # non-negative for a positive modulus, also for negative values
    if signed and low >= modulus // 2:
        return low - modulus
    return low


def wrap_int(value: int) -> int:
    """An INT (16-bit) store."""
    return wrap(value, 16, True)


def integer_range(name: str) -> tuple[int, int]:
    """The documented range of an integer type (``TOD`` ends at 23:59:59.999)."""
    if name == "TOD":
        return 0, 86_399_999
    bits, signed = INTEGER_LAYOUT[name]
    if signed:
        return -(1 << (bits - 1)), (1 << (bits - 1)) - 1
    return 0, (1 << bits) - 1


def _in_range(name: str) -> st.SearchStrategy[int]:
    low, high = integer_range(name)
    return st.integers(min_value=low, max_value=high)


BOOL_VALUES: Final = st.booleans()
SINT_VALUES: Final = _in_range("SINT")
USINT_VALUES: Final = _in_range("USINT")
INT_VALUES: Final = _in_range("INT")
UINT_VALUES: Final = _in_range("UINT")
DINT_VALUES: Final = _in_range("DINT")
UDINT_VALUES: Final = _in_range("UDINT")
LINT_VALUES: Final = _in_range("LINT")
ULINT_VALUES: Final = _in_range("ULINT")
BYTE_VALUES: Final = _in_range("BYTE")
WORD_VALUES: Final = _in_range("WORD")
DWORD_VALUES: Final = _in_range("DWORD")
LWORD_VALUES: Final = _in_range("LWORD")
TIME_VALUES: Final = _in_range("TIME")
LTIME_VALUES: Final = _in_range("LTIME")
DATE_VALUES: Final = _in_range("DATE")
TOD_VALUES: Final = _in_range("TOD")
DT_VALUES: Final = _in_range("DT")

#: REAL values are the finite singles: drawn as 32-bit floats so none is rounded on store.
REAL_VALUES: Final = st.floats(width=32, allow_nan=False, allow_infinity=False)
LREAL_VALUES: Final = st.floats(allow_nan=False, allow_infinity=False)

#: Any Python int, mostly far outside every IEC range; the wide bounded branch makes
#: sure numbers well beyond 64 bits, negative and positive, are drawn often.
ANY_INTS: Final = st.integers() | st.integers(min_value=-(1 << 200), max_value=1 << 200)

# NUL ends an IEC string in memory, so text holding it does not read back whole.
LATIN_1: Final = st.characters(min_codepoint=1, max_codepoint=0xFF)
# UCS-2 is the Basic Multilingual Plane without the surrogate block D800..DFFF.
UCS_2: Final = st.characters(min_codepoint=1, max_codepoint=0xD7FF) | st.characters(
    min_codepoint=0xE000, max_codepoint=0xFFFF
)


def string_values(length: int = 80) -> st.SearchStrategy[str]:
    """Text a STRING(length) holds unchanged: Latin-1, no NUL, at most ``length`` characters."""
    return st.text(LATIN_1, max_size=length)


def wstring_values(length: int = 80) -> st.SearchStrategy[str]:
    """Text a WSTRING(length) holds unchanged: UCS-2 (no surrogates), no NUL, at most ``length`` characters."""
    return st.text(UCS_2, max_size=length)


STRING_VALUES: Final = string_values()
WSTRING_VALUES: Final = wstring_values()

_BY_NAME: Final[dict[str, st.SearchStrategy[Any]]] = {
    "BOOL": BOOL_VALUES,
    "SINT": SINT_VALUES,
    "USINT": USINT_VALUES,
    "INT": INT_VALUES,
    "UINT": UINT_VALUES,
    "DINT": DINT_VALUES,
    "UDINT": UDINT_VALUES,
    "LINT": LINT_VALUES,
    "ULINT": ULINT_VALUES,
    "BYTE": BYTE_VALUES,
    "WORD": WORD_VALUES,
    "DWORD": DWORD_VALUES,
    "LWORD": LWORD_VALUES,
    "REAL": REAL_VALUES,
    "LREAL": LREAL_VALUES,
    "TIME": TIME_VALUES,
    "LTIME": LTIME_VALUES,
    "DATE": DATE_VALUES,
    "TOD": TOD_VALUES,
    "DT": DT_VALUES,
    "STRING": STRING_VALUES,
    "WSTRING": WSTRING_VALUES,
}


def iec_values(annotation: object, *, length: int | None = None) -> st.SearchStrategy[Any]:
    """The in-range values of an elementary annotation (``INT``, ``STRING``, ...).

    ``length`` is the declared STRING / WSTRING length (80 when omitted).
    """
    name = iec_type_name(annotation)
    if name is None:
        raise TypeError(f"{annotation!r} is not an elementary IEC type")
    if length is not None:
        if name == "STRING":
            return string_values(length)
        if name == "WSTRING":
            return wstring_values(length)
        raise TypeError(f"length= applies to STRING / WSTRING, not {name}")
    return _BY_NAME[name]


def _field_values(cls: type, name: str) -> st.SearchStrategy[Any]:
    record = field_record(cls, name)
    info = record.info
    enum_cls = getattr(info, "enum_cls", None)
    if enum_cls is not None:
        return st.sampled_from(list(enum_cls))
    length = getattr(info, "length", None)
    base = getattr(info, "record", None)
    base_name = getattr(base, "name", None)
    if base_name in _BY_NAME:
        if length is not None:
            return string_values(length) if base_name == "STRING" else wstring_values(length)
        return _BY_NAME[base_name]
    raise TypeError(
        f"{cls.__name__}.{name}: no strategy for an input of type {info.name}; "
        f"pass inputs=[...] naming the elementary inputs to draw"
    )


def fb_inputs(fb_class: type, inputs: list[str] | None = None) -> st.SearchStrategy[dict[str, Any]]:
    """One call's inputs for ``fb_class``: a dict of every VAR_INPUT (or of ``inputs``) to a drawn value.

    Elementary, STRING and enumeration inputs are drawn from their whole range.
    """
    layout = layout_of(fb_class)
    if layout is None or kind_of(fb_class) not in (Kind.FUNCTION_BLOCK, Kind.PROGRAM):
        raise TypeError(f"{fb_class!r} is not a function block class")
    if inputs is None:
        inputs = [r.name for r in layout.fields if r.section is Section.VAR_INPUT]
    for name in inputs:
        record = layout.by_name.get(name)
        if record is None or record.section is not Section.VAR_INPUT:
            raise TypeError(f"{fb_class.__name__} has no VAR_INPUT {name!r}")
    return st.fixed_dictionaries({name: _field_values(fb_class, name) for name in inputs})


def input_sequences(
    fb_class: type, *, min_size: int = 1, max_size: int = 50, inputs: list[str] | None = None
) -> st.SearchStrategy[list[dict[str, Any]]]:
    """A list of per-cycle input dicts for ``fb_class``: ``for kw in seq: fb(**kw)``."""
    return st.lists(fb_inputs(fb_class, inputs), min_size=min_size, max_size=max_size)


def enum_values(enum_cls: type[IecEnum]) -> st.SearchStrategy[Any]:
    """The members of an IEC enumeration."""
    return st.sampled_from(list(enum_cls))
