"""Elementary types in memory: integer wrap-around, REAL precision, BOOL, STRING and WSTRING.

Every expectation is computed here from the vendor rules (two's complement,
IEEE 754 single via ``struct``, Latin-1 / UCS-2 bytes), never read back from
the library.
"""

from __future__ import annotations

import ctypes
import math
import struct
from typing import Any, cast

import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from iecoop import (
    BOOL, BYTE, DATE, DINT, DT, DWORD, INT, LINT, LREAL, LTIME, LWORD, REAL, SINT, STRING, TIME, TOD, UDINT,
    UINT, ULINT, USINT, VAR, WORD, WSTRING, Struct, adr, sizeof, var_info,
)
from iecoop import _config
from iecoop.types import ElementaryType, elementary_type
from iecoop.testing.strategies import ANY_INTS, FLT_MAX, INTEGER_LAYOUT, LATIN_1, UCS_2, iec_values, wrap

from tests import checked_only


class Numbers(Struct):
    f_sint: SINT = 0
    f_usint: USINT = 0
    f_int: INT = 0
    f_uint: UINT = 0
    f_dint: DINT = 0
    f_udint: UDINT = 0
    f_lint: LINT = 0
    f_ulint: ULINT = 0
    f_byte: BYTE = 0
    f_word: WORD = 0
    f_dword: DWORD = 0
    f_lword: LWORD = 0
    f_time: TIME = 0
    f_ltime: LTIME = 0
    f_date: DATE = 0
    f_tod: TOD = 0
    f_dt: DT = 0
    f_real: REAL = 0.0
    f_lreal: LREAL = 0.0
    flag: BOOL = False
    count: INT = 0


class Texts(Struct):
    name: STRING = VAR()
    short: STRING = VAR("", length=5)
    wide: WSTRING = VAR()
    wshort: WSTRING = VAR("", length=3)


# IEC name, annotation, field of Numbers holding it.
INTEGER_FIELDS: list[tuple[str, object, str]] = [
    ("SINT", SINT, "f_sint"),
    ("USINT", USINT, "f_usint"),
    ("INT", INT, "f_int"),
    ("UINT", UINT, "f_uint"),
    ("DINT", DINT, "f_dint"),
    ("UDINT", UDINT, "f_udint"),
    ("LINT", LINT, "f_lint"),
    ("ULINT", ULINT, "f_ulint"),
    ("BYTE", BYTE, "f_byte"),
    ("WORD", WORD, "f_word"),
    ("DWORD", DWORD, "f_dword"),
    ("LWORD", LWORD, "f_lword"),
    ("TIME", TIME, "f_time"),
    ("LTIME", LTIME, "f_ltime"),
    ("DATE", DATE, "f_date"),
    ("TOD", TOD, "f_tod"),
    ("DT", DT, "f_dt"),
]
INTEGER_IDS = [name for name, _, _ in INTEGER_FIELDS]

ALL_FIELDS: list[tuple[str, object, type[Struct], str]] = [
    *((name, annotation, Numbers, field) for name, annotation, field in INTEGER_FIELDS),
    ("REAL", REAL, Numbers, "f_real"),
    ("LREAL", LREAL, Numbers, "f_lreal"),
    ("BOOL", BOOL, Numbers, "flag"),
    ("STRING", STRING, Texts, "name"),
    ("WSTRING", WSTRING, Texts, "wide"),
]


def f32(value: float) -> float:
    """The nearest IEEE 754 single, through the standard library's own packing."""
    result: float = struct.unpack("<f", struct.pack("<f", value))[0]
    return result


def raw(obj: object, field: str) -> bytes:
    """The bytes of ``obj.field`` as they lie in the instance's memory."""
    offset = var_info(obj, field).ByteOffset
    size = sizeof(obj, field)
    return ctypes.string_at(ctypes.addressof(cast(Any, obj)) + offset, size)


# ---------------------------------------------------------------------------
# Integers
# ---------------------------------------------------------------------------


@pytest.mark.parametrize(("name", "field"), [(n, f) for n, _, f in INTEGER_FIELDS], ids=INTEGER_IDS)
@given(value=ANY_INTS)
@example(value=0)
@example(value=-1)
@example(value=1 << 64)
@example(value=-(1 << 63) - 1)
def test_integer_store_wraps_modulo_2_to_the_n(name: str, field: str, value: int) -> None:
    bits, signed = INTEGER_LAYOUT[name]
    numbers = Numbers()
    setattr(numbers, field, value)
    expected = wrap(value, bits, signed)
    assert getattr(numbers, field) == expected
    assert raw(numbers, field) == expected.to_bytes(bits // 8, "little", signed=signed)


@pytest.mark.parametrize(("name", "field"), [(n, f) for n, _, f in INTEGER_FIELDS], ids=INTEGER_IDS)
@given(value=ANY_INTS)
def test_integer_store_through_a_pointer_wraps_the_same_way(name: str, field: str, value: int) -> None:
    bits, signed = INTEGER_LAYOUT[name]
    numbers = Numbers()
    adr(numbers, field).deref = value
    assert getattr(numbers, field) == wrap(value, bits, signed)


@pytest.mark.parametrize(("name", "annotation"), [(n, a) for n, a, _ in INTEGER_FIELDS], ids=INTEGER_IDS)
@given(value=ANY_INTS)
def test_the_type_records_store_agrees_with_memory(name: str, annotation: object, value: int) -> None:
    bits, signed = INTEGER_LAYOUT[name]
    record = elementary_type(annotation)
    assert isinstance(record, ElementaryType)
    assert record.store(value) == wrap(value, bits, signed)


@pytest.mark.parametrize(
    ("field", "value", "expected"),
    [
        ("f_int", 32767 + 1, -32768),
        ("f_int", -32768 - 1, 32767),
        ("f_uint", -1, 65535),
        ("f_sint", 200, -56),
        ("f_word", 65535 + 1, 0),
        ("f_dint", 2**31, -(2**31)),
        ("f_udint", -1, 4294967295),
        ("f_lint", 2**63, -(2**63)),
        ("f_ulint", -1, 2**64 - 1),
        ("f_time", -1, 4294967295),  # TIME is unsigned: T#0ms - 1ms wraps
        ("f_ltime", -1, 2**64 - 1),
    ],
)
def test_documented_overflow_cases(field: str, value: int, expected: int) -> None:
    numbers = Numbers()
    setattr(numbers, field, value)
    assert getattr(numbers, field) == expected


def test_wrap_happens_on_construction_too() -> None:
    assert Numbers(count=40000, f_usint=256 + 7).count == -25536
    assert Numbers(f_usint=256 + 7).f_usint == 7


@pytest.mark.parametrize(("name", "annotation", "cls", "field"), ALL_FIELDS, ids=[row[0] for row in ALL_FIELDS])
@given(data=st.data())
def test_in_range_values_read_back_unchanged(
    name: str, annotation: object, cls: type[Struct], field: str, data: st.DataObject
) -> None:
    value = data.draw(iec_values(annotation), label=name)
    obj = cls()
    setattr(obj, field, value)
    assert getattr(obj, field) == value


# ---------------------------------------------------------------------------
# REAL and LREAL
# ---------------------------------------------------------------------------


@given(value=st.floats(min_value=-FLT_MAX, max_value=FLT_MAX) | st.integers(min_value=-(1 << 100), max_value=1 << 100))
@example(value=0.1)
@example(value=16_777_217)  # 2**24 + 1: the first integer a single cannot hold
@example(value=1.0000001)
@example(value=1e-45)  # below the smallest denormal single: rounds to the denormal or 0
def test_real_store_is_a_float32_round_trip(value: float) -> None:
    numbers = Numbers()
    numbers.f_real = value
    expected = f32(value)
    assert numbers.f_real == expected
    assert math.copysign(1.0, numbers.f_real) == math.copysign(1.0, expected)
    assert raw(numbers, "f_real") == struct.pack("<f", value)


def test_real_keeps_only_single_precision() -> None:
    numbers = Numbers(f_real=0.1)
    assert numbers.f_real == 0.10000000149011612
    assert numbers.f_real != 0.1
    numbers.f_real = 16_777_217
    assert numbers.f_real == 16_777_216.0


@pytest.mark.parametrize(
    ("value", "expected"),
    [
        (1e39, math.inf),
        (-1e39, -math.inf),
        (FLT_MAX + 2.0**103, math.inf),  # exactly half an ulp above FLT_MAX rounds to even: infinity
        (math.nextafter(FLT_MAX + 2.0**103, 0.0), FLT_MAX),
        (math.inf, math.inf),
    ],
    ids=["above", "below", "half-ulp-up", "just-under-half-ulp", "inf"],
)
def test_real_overflow_stores_infinity(value: float, expected: float) -> None:
    numbers = Numbers()
    numbers.f_real = value
    assert numbers.f_real == expected
    record = elementary_type(REAL)
    assert isinstance(record, ElementaryType)
    assert record.store(value) == expected


def test_real_and_lreal_keep_nan() -> None:
    numbers = Numbers(f_real=math.nan, f_lreal=math.nan)
    assert math.isnan(numbers.f_real)
    assert math.isnan(numbers.f_lreal)


@given(value=st.floats(allow_nan=False))
@example(value=-0.0)
@example(value=5e-324)
@example(value=0.1)
def test_lreal_store_is_exact(value: float) -> None:
    numbers = Numbers()
    numbers.f_lreal = value
    assert numbers.f_lreal == value
    assert math.copysign(1.0, numbers.f_lreal) == math.copysign(1.0, value)
    assert raw(numbers, "f_lreal") == struct.pack("<d", value)


def test_lreal_takes_an_int_as_the_nearest_double() -> None:
    numbers = Numbers()
    numbers.f_lreal = 2**53 + 1
    assert numbers.f_lreal == 9_007_199_254_740_992.0


# ---------------------------------------------------------------------------
# BOOL and kind checks
# ---------------------------------------------------------------------------


def test_bool_stores_one_byte_zero_or_one() -> None:
    numbers = Numbers()
    numbers.flag = True
    assert numbers.flag is True
    assert raw(numbers, "flag") == b"\x01"
    numbers.flag = False
    assert numbers.flag is False
    assert raw(numbers, "flag") == b"\x00"


@checked_only
@pytest.mark.parametrize("value", [1, 0, 1.0, None, "TRUE"], ids=repr)
def test_bool_accepts_only_bool_in_checked_mode(value: object) -> None:
    numbers = Numbers(flag=True)
    with pytest.raises(TypeError, match=r"Numbers\.flag: cannot store .* in BOOL \(use True / False\)"):
        numbers.flag = value  # type: ignore[assignment]
    assert numbers.flag is True


@pytest.mark.parametrize("value", [1, 0], ids=repr)
def test_bool_through_a_pointer_accepts_only_bool_in_both_modes(value: int) -> None:
    numbers = Numbers()
    with pytest.raises(TypeError, match=r"POINTER TO BOOL: cannot store int .* in BOOL"):
        adr(numbers, "flag").deref = value
    assert numbers.flag is False


@checked_only
def test_str_into_int_is_a_type_error_naming_class_and_field() -> None:
    numbers = Numbers(count=7)
    with pytest.raises(TypeError, match=r"Numbers\.count: cannot store str '12' in INT"):
        numbers.count = "12"  # type: ignore[assignment]
    assert numbers.count == 7
    with pytest.raises(TypeError, match=r"Numbers\.count: cannot store str 'x' in INT"):
        Numbers(count="x")


@checked_only
@pytest.mark.parametrize(
    ("field", "value", "kind"),
    [
        ("count", 1.5, "float"),
        ("count", True, "bool"),
        ("f_lword", None, "NoneType"),
        ("f_real", "1.0", "str"),
        ("f_real", False, "bool"),
        ("f_time", 2.0, "float"),
    ],
)
def test_wrong_kinds_are_type_errors_in_checked_mode(field: str, value: object, kind: str) -> None:
    with pytest.raises(TypeError, match=rf"Numbers\.{field}: cannot store {kind} "):
        setattr(Numbers(), field, value)


@checked_only
def test_unknown_member_is_rejected_in_checked_mode() -> None:
    with pytest.raises(AttributeError, match=r"Numbers has no member 'speed'; declare it as a field"):
        Numbers().speed = 1  # type: ignore[attr-defined]


def test_unknown_member_in_the_constructor_is_rejected() -> None:
    with pytest.raises(TypeError, match=r"Numbers has no member 'speed'"):
        Numbers(speed=1)


# ---------------------------------------------------------------------------
# STRING
# ---------------------------------------------------------------------------


def test_string_sizes_are_length_plus_terminator() -> None:
    texts = Texts()
    assert sizeof(texts, "name") == 81  # STRING = STRING(80)
    assert sizeof(texts, "short") == 6
    assert sizeof(STRING) == 81


@given(value=st.text(LATIN_1, max_size=120))
@example(value="x" * 80)
@example(value="x" * 81)
def test_string_80_truncates_to_80_latin_1_bytes(value: str) -> None:
    texts = Texts()
    texts.name = value
    assert texts.name == value[:80]
    data = value.encode("latin-1")[:80]
    assert raw(texts, "name") == data + b"\x00" * (81 - len(data))


@given(value=st.text(LATIN_1, max_size=12))
def test_string_n_truncates_to_n_bytes(value: str) -> None:
    texts = Texts()
    texts.short = value
    assert texts.short == value[:5]
    assert raw(texts, "short")[-1:] == b"\x00"


def test_string_holds_latin_1_one_byte_per_character() -> None:
    texts = Texts(short="Größe")
    assert texts.short == "Größe"
    assert raw(texts, "short") == b"Gr\xf6\xdfe\x00"
    texts.short = "ÀÉÎÕÜý"
    assert texts.short == "ÀÉÎÕÜ"


def test_string_ends_at_an_embedded_nul() -> None:
    texts = Texts(short="ab\x00cd")
    assert texts.short == "ab"
    assert raw(texts, "short") == b"ab\x00cd\x00"


@pytest.mark.parametrize(("value", "bad"), [("20 €", "€"), ("Ωmega", "Ω"), ("日本", "日")])
def test_non_latin_1_text_is_a_value_error_naming_the_field(value: str, bad: str) -> None:
    texts = Texts(name="kept")
    with pytest.raises(ValueError, match=rf"Texts\.name: character '{bad}' has no Latin-1 code; .*use WSTRING"):
        texts.name = value
    assert texts.name == "kept"


def test_string_rejects_non_text() -> None:
    with pytest.raises(TypeError, match=r"Texts\.name: STRING expects str, got int"):
        Texts().name = 5  # type: ignore[assignment]


def test_string_through_a_pointer_truncates_and_checks_too() -> None:
    texts = Texts()
    pointer = adr(texts, "short")
    pointer.deref = "pointer"
    assert texts.short == "point"
    assert pointer.deref == "point"
    with pytest.raises(ValueError, match=r"POINTER TO STRING\(5\): character '€'"):
        pointer.deref = "€"


# ---------------------------------------------------------------------------
# WSTRING
# ---------------------------------------------------------------------------


def test_wstring_sizes_are_two_bytes_a_character_plus_terminator() -> None:
    texts = Texts()
    assert sizeof(texts, "wide") == 162
    assert sizeof(texts, "wshort") == 8
    assert sizeof(WSTRING) == 162


@given(value=st.text(UCS_2, max_size=100))
@example(value="€" * 81)
def test_wstring_80_truncates_after_80_characters(value: str) -> None:
    texts = Texts()
    texts.wide = value
    assert texts.wide == value[:80]
    data = value[:80].encode("utf-16-le")
    assert raw(texts, "wide") == data + b"\x00" * (162 - len(data))


def test_wstring_n_truncates_after_n_characters() -> None:
    texts = Texts(wshort="€abcd")
    assert texts.wshort == "€ab"
    assert raw(texts, "wshort") == b"\xac\x20a\x00b\x00\x00\x00"


@given(value=st.text(UCS_2, max_size=5), astral=st.characters(min_codepoint=0x10000))
def test_wstring_rejects_characters_outside_ucs_2(value: str, astral: str) -> None:
    texts = Texts(wide="kept")
    with pytest.raises(ValueError, match=r"Texts\.wide: WSTRING holds UCS-2"):
        texts.wide = value + astral
    assert texts.wide == "kept"


@pytest.mark.parametrize("surrogate", ["\ud800", "\udfff", "a\udc00b"], ids=["high", "low", "inside"])
def test_wstring_rejects_lone_surrogates_naming_the_field(surrogate: str) -> None:
    texts = Texts()
    with pytest.raises(ValueError, match=r"Texts\.wshort: WSTRING holds UCS-2"):
        texts.wshort = surrogate


@checked_only
def test_an_integer_beyond_any_float_names_the_real_variable() -> None:
    numbers = Numbers()
    with pytest.raises(ValueError, match=r"Numbers\.f_real: an integer of 1329 bits is outside the range of REAL"):
        numbers.f_real = 10**400
    numbers.f_real = 2**100  # large, but a float: REAL rounds it
    assert numbers.f_real == float(2**100)


@checked_only
def test_checked_mode_validates_array_elements() -> None:
    from iecoop import ARRAY, VAR, Struct

    class Flags(Struct):
        bits: ARRAY[BOOL] = VAR(bounds=(1, 3))
        levels: ARRAY[INT] = VAR(bounds=((1, 2), (1, 2)))

    flags = Flags()
    with pytest.raises(TypeError, match=r"ARRAY\[1\.\.3\] OF BOOL element \[1\]: cannot store int 5 in BOOL"):
        flags.bits[1] = 5  # type: ignore[assignment]
    with pytest.raises(TypeError, match=r"element \[\(2, 1\)\]: cannot store float 1\.5 in INT"):
        flags.levels[2, 1] = 1.5  # type: ignore[assignment]
    flags.bits[2] = True
    flags.levels[2, 1] = 7
    assert list(flags.bits) == [False, True, False] and flags.levels[2, 1] == 7
