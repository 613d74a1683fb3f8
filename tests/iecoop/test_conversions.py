"""Conversions and IEC integer arithmetic, checked against arithmetic written out here."""

from __future__ import annotations

import dataclasses
import math
import struct
from collections.abc import Callable
from fractions import Fraction
from typing import Literal, assert_type, cast

import pytest
from hypothesis import given
from hypothesis import strategies as st

from iecoop import conversions as cv
from iecoop.exceptions import ExceptionCode, PlcException
from iecoop.profiles import CODESYS, TWINCAT, Profile, use_profile
from iecoop.testing.strategies import INTEGER_LAYOUT, wrap

EVEN = dataclasses.replace(TWINCAT, round_tie="even")
AWAY = dataclasses.replace(TWINCAT, round_tie="away")
CODESYS_AWAY = dataclasses.replace(CODESYS, round_tie="away")

# The conversion targets: every integer-like type but the dates.
INTEGER_TARGETS = {name: layout for name, layout in INTEGER_LAYOUT.items() if name not in ("DATE", "TOD", "DT")}

IntConversion = Callable[[int | float | bool], int]
RealConversion = Callable[[float], int]


def nearest(x: float, tie: Literal["even", "away"]) -> int:
    """Round with exact rational arithmetic."""
    exact = Fraction(x)
    down = exact.numerator // exact.denominator
    rest = exact - down
    if rest != Fraction(1, 2):
        return down + (1 if rest > Fraction(1, 2) else 0)
    if tie == "even":
        return down if down % 2 == 0 else down + 1
    return down + 1 if exact > 0 else down


def as_real(x: float) -> float:
    return float(struct.unpack("<f", struct.pack("<f", x))[0])


def truncating_div(a: int, b: int) -> int:
    q = abs(a) // abs(b)
    return q if (a < 0) == (b < 0) else -q


def truncating_mod(a: int, b: int) -> int:
    r = abs(a) % abs(b)
    return -r if a < 0 else r


def generic(name: str) -> IntConversion:
    return cast(IntConversion, getattr(cv, f"TO_{name}"))


# --- integer targets ---------------------------------------------------------------------------


@pytest.mark.parametrize("name", sorted(INTEGER_TARGETS))
@given(value=st.integers(-(2**80), 2**80))
def test_to_integer_of_an_int_wraps(name: str, value: int) -> None:
    bits, signed = INTEGER_TARGETS[name]
    assert generic(name)(value) == wrap(value, bits, signed)


@pytest.mark.parametrize("name", sorted(INTEGER_TARGETS))
@pytest.mark.parametrize("profile", [EVEN, AWAY], ids=["even", "away"])
@given(x=st.floats(-(2.0**70), 2.0**70))
def test_to_integer_of_a_float_rounds_then_wraps(name: str, profile: Profile, x: float) -> None:
    bits, signed = INTEGER_TARGETS[name]
    with use_profile(profile):
        assert generic(name)(x) == wrap(nearest(x, profile.round_tie), bits, signed)


@pytest.mark.parametrize("profile", [EVEN, AWAY], ids=["even", "away"])
@given(x=st.floats(-(2.0**70), 2.0**70), half=st.integers(-(2**20), 2**20))
def test_real_to_int_rounds_the_32_bit_value(profile: Profile, x: float, half: int) -> None:
    tie = half + 0.5  # exact ties, so both rules get exercised
    with use_profile(profile):
        for value in (x, tie):
            assert cv.REAL_TO_DINT(value) == wrap(nearest(as_real(value), profile.round_tie), 32, True)
            assert cv.LREAL_TO_LINT(value) == wrap(nearest(value, profile.round_tie), 64, True)


@pytest.mark.parametrize(
    ("profile", "expected"),
    [(TWINCAT, (2, -2, 2, -2, 0, 4)), (CODESYS, (2, -2, 2, -2, 0, 4)),
     (AWAY, (2, -2, 3, -3, 1, 4)), (CODESYS_AWAY, (2, -2, 3, -3, 1, 4))],
    ids=["twincat", "codesys", "twincat-away", "codesys-away"],
)
def test_real_to_int_ties_follow_the_profile(profile: Profile, expected: tuple[int, ...]) -> None:
    with use_profile(profile):
        got = tuple(cv.REAL_TO_INT(x) for x in (1.5, -1.5, 2.5, -2.5, 0.5, 3.5))
        assert got == expected
        assert tuple(cv.LREAL_TO_INT(x) for x in (1.5, -1.5, 2.5, -2.5, 0.5, 3.5)) == expected
        assert tuple(cv.TO_INT(x) for x in (1.5, -1.5, 2.5, -2.5, 0.5, 3.5)) == expected


def test_documented_rounding_examples() -> None:
    assert (cv.REAL_TO_INT(1.5), cv.REAL_TO_INT(1.4), cv.REAL_TO_INT(-1.5), cv.REAL_TO_INT(-1.4)) == (2, 1, -2, -1)
    # The largest float below 0.5 is no tie: adding 0.5 to it would round up by mistake.
    assert cv.LREAL_TO_INT(0.49999999999999994) == 0
    # As a REAL the same argument is exactly 0.5, a tie.
    assert cv.REAL_TO_INT(0.49999999999999994) == 0
    assert cv.REAL_TO_INT(0.5000000001) == 0
    assert cv.LREAL_TO_INT(0.5000000001) == 1


def test_out_of_range_float_wraps() -> None:
    assert cv.REAL_TO_INT(40000.0) == 40000 - 65536
    assert cv.REAL_TO_USINT(-1.0) == 255
    assert cv.LREAL_TO_UDINT(-1.0) == 2**32 - 1


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
@pytest.mark.parametrize(
    "convert", [cv.TO_INT, cv.TO_ULINT, cv.TO_TIME, cv.REAL_TO_DINT, cv.LREAL_TO_LWORD, cv.TRUNC, cv.TRUNC_INT]
)
def test_nan_and_infinity_have_no_integer(convert: RealConversion, bad: float) -> None:
    with pytest.raises(PlcException, match="has no integer value") as exc:
        convert(bad)
    assert exc.value.code is ExceptionCode.RTSEXCPT_FPU_INVALID_OPERATION


def test_every_real_and_lreal_conversion_exists() -> None:
    for source in ("REAL", "LREAL"):
        for name, (bits, signed) in INTEGER_TARGETS.items():
            convert = cast(RealConversion, getattr(cv, f"{source}_TO_{name}"))
            assert convert(-2.0) == wrap(-2, bits, signed)
            assert f"{source}_TO_{name}" in cv.__all__
    assert cv.REAL_TO_BOOL(0.0) is False and cv.LREAL_TO_BOOL(-0.5) is True


# --- BOOL, REAL, LREAL targets ------------------------------------------------------------------


def test_to_bool_is_not_equal_zero() -> None:
    assert [cv.TO_BOOL(v) for v in (0, 1, -1, 0.0, 0.1, -0.0, True, False)] == [
        False, True, True, False, True, False, True, False,
    ]
    assert cv.INT_TO_BOOL(7) is True and cv.INT_TO_BOOL(0) is False
    assert cv.BOOL_TO_INT(True) == 1 and cv.BOOL_TO_INT(False) == 0


def test_to_real_rounds_to_32_bits() -> None:
    assert cv.TO_REAL(16777217) == 16777216.0
    assert cv.TO_REAL(16777219) == 16777220.0  # tie, to even
    assert cv.DINT_TO_REAL(16777217) == 16777216.0
    assert cv.INT_TO_REAL(-32768) == -32768.0
    assert cv.TO_REAL(0.1) == as_real(0.1) != 0.1
    assert cv.LREAL_TO_REAL(1e39) == math.inf
    assert cv.REAL_TO_LREAL(0.1) == as_real(0.1)
    assert cv.TO_LREAL(2**53 + 1) == 2.0**53
    assert cv.INT_TO_LREAL(-5) == -5.0 and cv.DINT_TO_LREAL(2**31 - 1) == 2147483647.0
    # 2^60 + 2^36 + 1 lies above the midpoint between two REALs; going through a
    # double first would drop the +1 and land on the lower one.
    assert cv.TO_REAL(2**60 + 2**36 + 1) == float(2**60 + 2**37)
    assert cv.TO_REAL(-(2**60 + 2**36 + 1)) == -float(2**60 + 2**37)
    assert cv.TO_REAL(2**128) == math.inf


def f32_bits(x: float) -> int:
    return int(struct.unpack("<I", struct.pack("<f", x))[0])


def f32_from_bits(bits: int) -> float:
    return float(struct.unpack("<f", struct.pack("<I", bits))[0])


@given(st.integers(-(2**64), 2**64).filter(lambda n: n != 0))
def test_to_real_of_an_int_is_the_nearest_float32(n: int) -> None:
    got = cv.TO_REAL(n)
    bits = f32_bits(got)
    # Adjacent bit patterns of same-signed finite floats are adjacent float32 values.
    neighbours = [f32_from_bits(bits - 1), f32_from_bits(bits + 1)]
    error = abs(Fraction(got) - n)
    for other in neighbours:
        other_error = abs(Fraction(other) - n)
        assert error <= other_error
        if error == other_error:
            assert bits % 2 == 0, "a tie goes to the even mantissa"


# --- source-named integer conversions --------------------------------------------------------


@given(st.integers(-(2**40), 2**40))
def test_source_named_integer_conversions(n: int) -> None:
    assert cv.WORD_TO_INT(n) == wrap(wrap(n, 16, False), 16, True)
    assert cv.INT_TO_WORD(n) == wrap(n, 16, False)
    assert cv.UINT_TO_INT(n) == wrap(n, 16, True)
    assert cv.INT_TO_UINT(n) == wrap(n, 16, False)
    assert cv.DWORD_TO_DINT(n) == wrap(n, 32, True)
    assert cv.DINT_TO_DWORD(n) == wrap(n, 32, False)
    assert cv.INT_TO_BYTE(n) == wrap(n, 8, False)
    assert cv.TIME_TO_DINT(n) == wrap(n, 32, True)
    assert cv.DINT_TO_TIME(n) == wrap(n, 32, False)


def test_time_conversions() -> None:
    assert cv.DINT_TO_TIME(-1) == 2**32 - 1
    assert cv.TIME_TO_DINT(2**32 - 1) == -1
    assert cv.TIME_TO_LTIME(1500) == 1_500_000_000
    assert cv.TIME_TO_LTIME(2**32 - 1) == (2**32 - 1) * 1_000_000
    assert cv.LTIME_TO_TIME(1_999_999) == 1
    assert cv.LTIME_TO_TIME(2**64 - 1) == ((2**64 - 1) // 1_000_000) % 2**32
    assert cv.TO_TIME(1500) == 1500
    assert cv.TO_TIME(2.5) == 2 and cv.TO_LTIME(3.5) == 4
    assert cv.REAL_TO_TIME(1500.4) == 1500 and cv.LREAL_TO_LTIME(1e9) == 10**9


@given(st.integers(0, 2**64 - 1))
def test_ltime_to_time_truncates(ns: int) -> None:
    assert cv.LTIME_TO_TIME(ns) == wrap(ns // 1_000_000, 32, False)


# --- TRUNC, DIV, MOD ---------------------------------------------------------------------------


def test_trunc_goes_toward_zero() -> None:
    assert (cv.TRUNC(1.9), cv.TRUNC(-1.4), cv.TRUNC(-1.9), cv.TRUNC(0.99)) == (1, -1, -1, 0)
    assert cv.TRUNC(3e9) == wrap(3_000_000_000, 32, True)
    assert cv.TRUNC_INT(-40000.7) == wrap(-40000, 16, True)


@given(st.floats(-(2.0**40), 2.0**40))
def test_trunc_matches_rational_truncation(x: float) -> None:
    exact = Fraction(x)
    toward_zero = exact.numerator // exact.denominator if exact >= 0 else -((-exact.numerator) // exact.denominator)
    assert cv.TRUNC(x) == wrap(toward_zero, 32, True)
    assert cv.TRUNC_INT(x) == wrap(toward_zero, 16, True)


nonzero = st.integers(-(2**70), 2**70).filter(lambda n: n != 0)


@given(st.integers(-(2**70), 2**70), nonzero)
def test_div_and_mod_truncate_like_c(a: int, b: int) -> None:
    assert cv.DIV(a, b) == truncating_div(a, b)
    assert cv.MOD(a, b) == truncating_mod(a, b)
    assert cv.DIV(a, b) * b + cv.MOD(a, b) == a


def test_div_mod_known_values() -> None:
    assert (cv.DIV(-7, 2), cv.DIV(7, -2), cv.DIV(-7, -2), cv.DIV(7, 2)) == (-3, -3, 3, 3)
    assert (cv.MOD(-7, 2), cv.MOD(7, -2), cv.MOD(-7, -2), cv.MOD(7, 2)) == (-1, 1, -1, 1)
    assert cv.DIV(7.0, 2) == 3.5 and cv.DIV(-7, 2.0) == -3.5


def test_div_types() -> None:
    assert_type(cv.DIV(7, 2), int)
    assert_type(cv.DIV(7.0, 2), float)
    assert isinstance(cv.DIV(7, 2), int) and isinstance(cv.DIV(7, 2.0), float)


def test_integer_division_by_zero() -> None:
    with pytest.raises(PlcException, match=r"DIV\(5, 0\): integer division by zero") as exc:
        cv.DIV(5, 0)
    assert exc.value.code is ExceptionCode.RTSEXCPT_DIVIDEBYZERO
    with pytest.raises(PlcException, match=r"MOD\(5, 0\): integer division by zero") as exc:
        cv.MOD(5, 0)
    assert exc.value.code is ExceptionCode.RTSEXCPT_DIVIDEBYZERO


@pytest.mark.parametrize(("a", "b"), [(1.0, 0.0), (1, 0.0), (1.0, 0), (0.0, -0.0)])
def test_float_division_by_zero(a: float, b: float) -> None:
    with pytest.raises(PlcException, match="floating-point division by zero") as exc:
        cv.DIV(a, b)
    assert exc.value.code is ExceptionCode.RTSEXCPT_FPU_DIVIDEBYZERO


@pytest.mark.parametrize(("a", "b"), [(7.0, 2), (7, 2.0), (7.5, 2.5)])
def test_mod_refuses_floats(a: float, b: float) -> None:
    with pytest.raises(TypeError, match="MOD is defined for integer types only"):
        cv.MOD(cast(int, a), cast(int, b))


def test_public_names_are_all_defined() -> None:
    for name in cv.__all__:
        assert callable(getattr(cv, name)), name
        assert name in (getattr(cv, name).__doc__ or ""), f"{name}'s docstring should give its ST name"


# --- <type>_TO_STRING ------------------------------------------------------------------------


def test_real_to_string_hand_worked_values() -> None:
    # 50.1 as a REAL is 50.09999847...: nine digits would show that, three read back the same.
    assert [cv.REAL_TO_STRING(x) for x in (1.5, 0.1, -50.1, 2.0, 0.0, 1.0 / 3.0, 100.0)] == [
        "1.5", "0.1", "-50.1", "2.0", "0.0", "0.33333334", "100.0",
    ]
    assert cv.REAL_TO_STRING(16777217.0) == "16777216.0"  # stored as the REAL first
    assert [cv.REAL_TO_STRING(x) for x in (3.0e20, 1.5e-7, 0.00001, 1.0e16)] == [
        "3.0E+20", "1.5E-07", "0.00001", "1.0E+16",
    ]
    assert [cv.REAL_TO_STRING(x) for x in (math.inf, -math.inf, math.nan)] == ["#INF", "-#INF", "#QNAN"]


def test_lreal_to_string_keeps_16_digits() -> None:
    assert cv.LREAL_TO_STRING(1.4) == "1.4"
    assert cv.LREAL_TO_STRING(0.1) == "0.1"  # not the REAL's 0.100000001
    assert cv.REAL_TO_STRING(0.1) == "0.1" and cv.LREAL_TO_STRING(cv.REAL_TO_LREAL(0.1)) == "0.1000000014901161"
    # 0.30000000000000004 needs 17 digits: the sixteenth is rounded, which reads 0.3
    assert cv.LREAL_TO_STRING(0.1 + 0.2) == "0.3"
    assert cv.LREAL_TO_STRING(-1e100) == "-1.0E+100"


finite_reals = st.floats(width=32, allow_nan=False, allow_infinity=False)


@given(finite_reals)
def test_real_text_reads_back_as_the_same_real(x: float) -> None:
    text = cv.REAL_TO_STRING(x)
    assert cv.TO_REAL(cv.STRING_TO_NUMBER(text, "REAL")) == x
    digits = text.split("E")[0].replace("-", "").replace(".", "").strip("0")
    assert len(digits) <= 9


@given(st.floats(-1e308, 1e308))
def test_lreal_text_reads_back_within_16_digits(x: float) -> None:
    # Not exact: 17-digit LREALs lose their last digit. Near the top of the range
    # (1.7976931348623157E+308) the rounded sixteenth digit even reads back as infinity.
    back = float(cv.STRING_TO_NUMBER(cv.LREAL_TO_STRING(x), "LREAL"))
    assert back == x or abs(back - x) <= abs(x) * 1e-15


def test_bool_time_and_date_to_string() -> None:
    assert (cv.BOOL_TO_STRING(True), cv.BOOL_TO_STRING(False), cv.BOOL_TO_WSTRING(True)) == ("TRUE", "FALSE", "TRUE")
    assert cv.TIME_TO_STRING(1500) == "T#1s500ms"
    assert cv.TIME_TO_STRING(-1) == "T#49d17h2m47s295ms"  # a TIME is unsigned: the store wraps
    assert cv.LTIME_TO_STRING(1_500_000) == "LTIME#1ms500us"
    assert cv.DATE_TO_STRING(1706400000) == "D#2024-01-28"
    assert cv.TOD_TO_STRING(45000500) == "TOD#12:30:00.5"
    assert cv.DT_TO_STRING(1706439943) == "DT#2024-01-28-11:05:43"


@given(st.integers(0, 2**32 - 1))
def test_time_text_reads_back(ms: int) -> None:
    assert cv.STRING_TO_NUMBER(cv.TIME_TO_STRING(ms), "TIME") == ms


@pytest.mark.parametrize("name", sorted(set(INTEGER_TARGETS) - {"TIME", "LTIME"}))
@given(value=st.integers(-(2**70), 2**70))
def test_integer_to_string_is_the_stored_value(name: str, value: int) -> None:
    convert = cast(Callable[[int], str], getattr(cv, f"{name}_TO_STRING"))
    assert convert.__name__ == f"{name}_TO_STRING"
    assert convert(value) == str(wrap(value, *INTEGER_LAYOUT[name]))


def test_integer_to_string_known_values() -> None:
    assert (cv.INT_TO_STRING(40000), cv.WORD_TO_STRING(-1), cv.BYTE_TO_STRING(255)) == ("-25536", "65535", "255")


def test_generic_to_string_follows_the_python_type() -> None:
    assert (cv.TO_STRING(True), cv.TO_STRING(-7), cv.TO_STRING(0.5), cv.TO_WSTRING(False)) == ("TRUE", "-7", "0.5", "FALSE")
