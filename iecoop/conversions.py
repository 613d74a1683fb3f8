"""Type conversions (``TO_INT``, ``REAL_TO_INT`` ...) and IEC integer division (DIV, MOD).

A conversion returns what a variable of the target type holds afterwards:

* a float becomes an integer by rounding to the nearest value. The vendors do
  not document the rule for an exact .5 (UNCONFIRMED), so it is the setting
  ``active_profile().round_tie``: "even" in both vendor profiles, as x64 SSE
  conversion does, or "away" from zero. NaN and infinity raise
  RTSEXCPT_FPU_INVALID_OPERATION;
* the integer is then stored as the target stores it, modulo 2^n. A value out
  of the target's range is undefined on a PLC (platform dependent, may even
  fault); the emulation wraps, which is what an integer store does;
* to REAL the value is rounded to the nearest 32-bit float; to BOOL it is
  ``x <> 0``.

A source-named form (``REAL_TO_INT``, ``WORD_TO_INT``) first takes its argument
as the source type holds it, so ``REAL_TO_INT`` sees the 32-bit value and
``WORD_TO_INT(65535)`` reads the WORD's bits as an INT.

``STRING_TO_<type>`` is ``TO_<type>(STRING_TO_NUMBER(text, "<type>"))``: the
literal the text starts with, stored in the target type.

``<type>_TO_STRING`` writes the text TwinCAT 3 writes: ``'TRUE'``, ``'T#1s500ms'``,
decimal digits for an integer, and for a REAL the fewest digits that read back
as the same REAL (``'1.5'``, ``'0.1'``); see ``REAL_TO_STRING`` for what is
documented and what is not.

DIV truncates toward zero and MOD takes the sign of the dividend (C semantics,
as the PLCs' native code); dividing by zero raises a PlcException, as TwinCAT
does.

ST: ``iValue := REAL_TO_INT(rValue);``  Python: ``self.iValue = REAL_TO_INT(self.rValue)``

>>> REAL_TO_INT(1.5), REAL_TO_INT(-1.5), REAL_TO_INT(2.5), TO_USINT(300)
(2, -2, 2, 44)
>>> DIV(-7, 2), MOD(-7, 2), WORD_TO_INT(65535)
(-3, -1, -1)
>>> DIV(1, 0)
Traceback (most recent call last):
    ...
iecoop.exceptions.PlcException: RTSEXCPT_DIVIDEBYZERO (16#102): DIV(1, 0): integer division by zero
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from typing import Final, TypeVar, overload

from iecoop.exceptions import ExceptionCode, PlcException
from iecoop.literals import format_date, format_dt, format_ltime, format_time, format_tod
from iecoop.profiles import active_profile
from iecoop.types import (
    BOOL_T,
    BYTE_T,
    DATE_T,
    DINT_T,
    DT_T,
    DWORD_T,
    INT_T,
    LINT_T,
    LREAL_T,
    LTIME_T,
    LWORD_T,
    REAL_T,
    SINT_T,
    TIME_T,
    TOD_T,
    UDINT_T,
    UINT_T,
    ULINT_T,
    USINT_T,
    WORD_T,
    ElementaryType,
)

__all__ = [
    "BOOL_TO_INT",
    "BOOL_TO_STRING",
    "BOOL_TO_WSTRING",
    "BYTE_TO_STRING",
    "DATE_TO_STRING",
    "DINT_TO_DWORD",
    "DINT_TO_LREAL",
    "DINT_TO_REAL",
    "DINT_TO_STRING",
    "DINT_TO_TIME",
    "DINT_TO_WSTRING",
    "DIV",
    "DT_TO_DATE",
    "DT_TO_STRING",
    "DT_TO_TOD",
    "DWORD_TO_DINT",
    "DWORD_TO_STRING",
    "INT_TO_BOOL",
    "INT_TO_BYTE",
    "INT_TO_LREAL",
    "INT_TO_REAL",
    "INT_TO_STRING",
    "INT_TO_UINT",
    "INT_TO_WORD",
    "INT_TO_WSTRING",
    "LINT_TO_STRING",
    "LREAL_TO_BOOL",
    "LREAL_TO_BYTE",
    "LREAL_TO_DINT",
    "LREAL_TO_DWORD",
    "LREAL_TO_INT",
    "LREAL_TO_LINT",
    "LREAL_TO_LTIME",
    "LREAL_TO_LWORD",
    "LREAL_TO_REAL",
    "LREAL_TO_SINT",
    "LREAL_TO_STRING",
    "LREAL_TO_TIME",
    "LREAL_TO_UDINT",
    "LREAL_TO_UINT",
    "LREAL_TO_ULINT",
    "LREAL_TO_USINT",
    "LREAL_TO_WORD",
    "LREAL_TO_WSTRING",
    "LTIME_TO_STRING",
    "LTIME_TO_TIME",
    "LTIME_TO_WSTRING",
    "LWORD_TO_STRING",
    "MOD",
    "REAL_TO_BOOL",
    "REAL_TO_BYTE",
    "REAL_TO_DINT",
    "REAL_TO_DWORD",
    "REAL_TO_INT",
    "REAL_TO_LINT",
    "REAL_TO_LREAL",
    "REAL_TO_LTIME",
    "REAL_TO_LWORD",
    "REAL_TO_SINT",
    "REAL_TO_STRING",
    "REAL_TO_TIME",
    "REAL_TO_UDINT",
    "REAL_TO_UINT",
    "REAL_TO_ULINT",
    "REAL_TO_USINT",
    "REAL_TO_WORD",
    "REAL_TO_WSTRING",
    "SINT_TO_STRING",
    "STRING_TO_NUMBER",
    "TIME_TO_DINT",
    "TIME_TO_LTIME",
    "TIME_TO_STRING",
    "TIME_TO_WSTRING",
    "TOD_TO_STRING",
    "TO_BOOL",
    "TO_BYTE",
    "TO_DATE",
    "TO_DINT",
    "TO_DT",
    "TO_DWORD",
    "TO_INT",
    "TO_LINT",
    "TO_LREAL",
    "TO_LTIME",
    "TO_LWORD",
    "TO_REAL",
    "TO_SINT",
    "TO_STRING",
    "TO_TIME",
    "TO_TOD",
    "TO_UDINT",
    "TO_UINT",
    "TO_ULINT",
    "TO_USINT",
    "TO_WORD",
    "TO_WSTRING",
    "TRUNC",
    "TRUNC_INT",
    "UDINT_TO_STRING",
    "UINT_TO_INT",
    "UINT_TO_STRING",
    "ULINT_TO_STRING",
    "USINT_TO_STRING",
    "WORD_TO_INT",
    "WORD_TO_STRING",
]

Number = int | float | bool
_Source = TypeVar("_Source", int, float, bool, Number)

# Above 2^53 a Python int -> float conversion already rounds, and rounding that
# double again to 24 bits can land on the wrong float32 (double rounding).
_EXACT_IN_DOUBLE: Final = 1 << 53
_REAL_MANTISSA_BITS: Final = 24
_NS_PER_MS: Final = 1_000_000


# --- the engine ------------------------------------------------------------------------------


def _round_to_int(x: float, op: str) -> int:
    """``x`` rounded to the nearest integer, ties per the active profile."""
    if math.isnan(x) or math.isinf(x):
        raise PlcException(
            ExceptionCode.RTSEXCPT_FPU_INVALID_OPERATION, f"{op}({x}): {x} has no integer value"
        )
    low = math.floor(x)
    # x - low is exact for a float, so the tie test below is exact too.
    rest = x - low
    if rest > 0.5:
        return low + 1
    if rest < 0.5:
        return low
    if active_profile().round_tie == "even":
        return low if low % 2 == 0 else low + 1
    return low + 1 if x > 0 else low


def _to_integer(x: Number, target: ElementaryType, op: str) -> int:
    value = _round_to_int(x, op) if isinstance(x, float) else int(x)
    return int(target.store(value))


def _int_to_real(n: int) -> float:
    """The float32 nearest to ``n``, rounded once, half to even (as cvtsi2ss does)."""
    if -_EXACT_IN_DOUBLE <= n <= _EXACT_IN_DOUBLE:
        return float(REAL_T.store(n))
    magnitude = abs(n)
    if magnitude.bit_length() > 128:
        return math.copysign(math.inf, n)
    shift = magnitude.bit_length() - _REAL_MANTISSA_BITS
    kept, dropped = divmod(magnitude, 1 << shift)
    half = 1 << (shift - 1)
    if dropped > half or (dropped == half and kept & 1):
        kept += 1
    # kept has at most 25 bits, so ldexp is exact; REAL's store maps 2^128 to infinity.
    return float(REAL_T.store(math.copysign(math.ldexp(kept, shift), n)))


def _to_real(x: Number) -> float:
    if isinstance(x, float):
        return float(REAL_T.store(x))
    return _int_to_real(int(x))


def _from_real(x: float) -> float:
    """The argument as a REAL variable would hold it."""
    return float(REAL_T.store(x))


def _source(x: int, source: ElementaryType) -> int:
    """The argument as a variable of the source type would hold it."""
    return int(source.store(x))


# --- generic TO_<type> -----------------------------------------------------------------------


def TO_BOOL(x: Number) -> bool:
    """TO_BOOL: ``x <> 0``."""
    return bool(x != 0)


def TO_SINT(x: Number) -> int:
    """TO_SINT: nearest integer, stored as a SINT (wraps modulo 2^8)."""
    return _to_integer(x, SINT_T, "TO_SINT")


def TO_USINT(x: Number) -> int:
    """TO_USINT: nearest integer, stored as a USINT (wraps modulo 2^8)."""
    return _to_integer(x, USINT_T, "TO_USINT")


def TO_INT(x: Number) -> int:
    """TO_INT: nearest integer, stored as an INT (wraps modulo 2^16).

    >>> TO_INT(40000), TO_INT(-2.5)
    (-25536, -2)
    """
    return _to_integer(x, INT_T, "TO_INT")


def TO_UINT(x: Number) -> int:
    """TO_UINT: nearest integer, stored as a UINT (wraps modulo 2^16)."""
    return _to_integer(x, UINT_T, "TO_UINT")


def TO_DINT(x: Number) -> int:
    """TO_DINT: nearest integer, stored as a DINT (wraps modulo 2^32)."""
    return _to_integer(x, DINT_T, "TO_DINT")


def TO_UDINT(x: Number) -> int:
    """TO_UDINT: nearest integer, stored as a UDINT (wraps modulo 2^32)."""
    return _to_integer(x, UDINT_T, "TO_UDINT")


def TO_LINT(x: Number) -> int:
    """TO_LINT: nearest integer, stored as a LINT (wraps modulo 2^64)."""
    return _to_integer(x, LINT_T, "TO_LINT")


def TO_ULINT(x: Number) -> int:
    """TO_ULINT: nearest integer, stored as a ULINT (wraps modulo 2^64)."""
    return _to_integer(x, ULINT_T, "TO_ULINT")


def TO_BYTE(x: Number) -> int:
    """TO_BYTE: nearest integer, stored as a BYTE (wraps modulo 2^8).

    >>> TO_BYTE(-1)
    255
    """
    return _to_integer(x, BYTE_T, "TO_BYTE")


def TO_WORD(x: Number) -> int:
    """TO_WORD: nearest integer, stored as a WORD (wraps modulo 2^16)."""
    return _to_integer(x, WORD_T, "TO_WORD")


def TO_DWORD(x: Number) -> int:
    """TO_DWORD: nearest integer, stored as a DWORD (wraps modulo 2^32)."""
    return _to_integer(x, DWORD_T, "TO_DWORD")


def TO_LWORD(x: Number) -> int:
    """TO_LWORD: nearest integer, stored as an LWORD (wraps modulo 2^64)."""
    return _to_integer(x, LWORD_T, "TO_LWORD")


def TO_REAL(x: Number) -> float:
    """TO_REAL: the nearest 32-bit float.

    >>> TO_REAL(16777217), TO_REAL(0.1)
    (16777216.0, 0.10000000149011612)
    """
    return _to_real(x)


def TO_LREAL(x: Number) -> float:
    """TO_LREAL: the nearest 64-bit float."""
    return float(x)


def TO_TIME(x: Number) -> int:
    """TO_TIME: ``x`` milliseconds, rounded to the nearest, stored as a TIME (wraps modulo 2^32).

    >>> TO_TIME(1500), TO_TIME(2.5)
    (1500, 2)
    """
    return _to_integer(x, TIME_T, "TO_TIME")


def TO_LTIME(x: Number) -> int:
    """TO_LTIME: ``x`` nanoseconds, rounded to the nearest, stored as an LTIME (wraps modulo 2^64)."""
    return _to_integer(x, LTIME_T, "TO_LTIME")


def TO_DATE(x: Number) -> int:
    """TO_DATE: ``x`` seconds since 1970-01-01, rounded to the nearest, stored as a DATE (wraps modulo 2^32)."""
    return _to_integer(x, DATE_T, "TO_DATE")


def TO_TOD(x: Number) -> int:
    """TO_TOD: ``x`` milliseconds after midnight, rounded to the nearest, stored as a TIME_OF_DAY."""
    return _to_integer(x, TOD_T, "TO_TOD")


def TO_DT(x: Number) -> int:
    """TO_DT: ``x`` seconds since 1970-01-01, rounded to the nearest, stored as a DATE_AND_TIME (wraps modulo 2^32).

    >>> TO_DT(86400 + 3600)  # DT#1970-01-02-01:00:00
    90000
    """
    return _to_integer(x, DT_T, "TO_DT")


def DT_TO_DATE(x: int) -> int:
    """DT_TO_DATE: the day of a DATE_AND_TIME (its midnight)."""
    return int(DT_T.store(x)) // 86_400 * 86_400


def DT_TO_TOD(x: int) -> int:
    """DT_TO_TOD: the time of day of a DATE_AND_TIME, in milliseconds after midnight."""
    return int(DT_T.store(x)) % 86_400 * 1_000


# --- REAL_TO_<type> --------------------------------------------------------------------------


def REAL_TO_BOOL(x: float) -> bool:
    """REAL_TO_BOOL: ``x <> 0``."""
    return _from_real(x) != 0


def REAL_TO_SINT(x: float) -> int:
    """REAL_TO_SINT: nearest integer, stored as a SINT."""
    return _to_integer(_from_real(x), SINT_T, "REAL_TO_SINT")


def REAL_TO_USINT(x: float) -> int:
    """REAL_TO_USINT: nearest integer, stored as a USINT."""
    return _to_integer(_from_real(x), USINT_T, "REAL_TO_USINT")


def REAL_TO_INT(x: float) -> int:
    """REAL_TO_INT: nearest integer, stored as an INT.

    >>> REAL_TO_INT(1.4), REAL_TO_INT(-1.4), REAL_TO_INT(-1.5)
    (1, -1, -2)
    """
    return _to_integer(_from_real(x), INT_T, "REAL_TO_INT")


def REAL_TO_UINT(x: float) -> int:
    """REAL_TO_UINT: nearest integer, stored as a UINT."""
    return _to_integer(_from_real(x), UINT_T, "REAL_TO_UINT")


def REAL_TO_DINT(x: float) -> int:
    """REAL_TO_DINT: nearest integer, stored as a DINT."""
    return _to_integer(_from_real(x), DINT_T, "REAL_TO_DINT")


def REAL_TO_UDINT(x: float) -> int:
    """REAL_TO_UDINT: nearest integer, stored as a UDINT."""
    return _to_integer(_from_real(x), UDINT_T, "REAL_TO_UDINT")


def REAL_TO_LINT(x: float) -> int:
    """REAL_TO_LINT: nearest integer, stored as a LINT."""
    return _to_integer(_from_real(x), LINT_T, "REAL_TO_LINT")


def REAL_TO_ULINT(x: float) -> int:
    """REAL_TO_ULINT: nearest integer, stored as a ULINT."""
    return _to_integer(_from_real(x), ULINT_T, "REAL_TO_ULINT")


def REAL_TO_BYTE(x: float) -> int:
    """REAL_TO_BYTE: nearest integer, stored as a BYTE."""
    return _to_integer(_from_real(x), BYTE_T, "REAL_TO_BYTE")


def REAL_TO_WORD(x: float) -> int:
    """REAL_TO_WORD: nearest integer, stored as a WORD."""
    return _to_integer(_from_real(x), WORD_T, "REAL_TO_WORD")


def REAL_TO_DWORD(x: float) -> int:
    """REAL_TO_DWORD: nearest integer, stored as a DWORD."""
    return _to_integer(_from_real(x), DWORD_T, "REAL_TO_DWORD")


def REAL_TO_LWORD(x: float) -> int:
    """REAL_TO_LWORD: nearest integer, stored as an LWORD."""
    return _to_integer(_from_real(x), LWORD_T, "REAL_TO_LWORD")


def REAL_TO_TIME(x: float) -> int:
    """REAL_TO_TIME: ``x`` milliseconds, rounded to the nearest, as a TIME."""
    return _to_integer(_from_real(x), TIME_T, "REAL_TO_TIME")


def REAL_TO_LTIME(x: float) -> int:
    """REAL_TO_LTIME: ``x`` nanoseconds, rounded to the nearest, as an LTIME."""
    return _to_integer(_from_real(x), LTIME_T, "REAL_TO_LTIME")


def REAL_TO_LREAL(x: float) -> float:
    """REAL_TO_LREAL: widening, exact.

    >>> REAL_TO_LREAL(0.1)
    0.10000000149011612
    """
    return _from_real(x)


# --- LREAL_TO_<type> -------------------------------------------------------------------------


def LREAL_TO_BOOL(x: float) -> bool:
    """LREAL_TO_BOOL: ``x <> 0``."""
    return x != 0


def LREAL_TO_SINT(x: float) -> int:
    """LREAL_TO_SINT: nearest integer, stored as a SINT."""
    return _to_integer(float(x), SINT_T, "LREAL_TO_SINT")


def LREAL_TO_USINT(x: float) -> int:
    """LREAL_TO_USINT: nearest integer, stored as a USINT."""
    return _to_integer(float(x), USINT_T, "LREAL_TO_USINT")


def LREAL_TO_INT(x: float) -> int:
    """LREAL_TO_INT: nearest integer, stored as an INT."""
    return _to_integer(float(x), INT_T, "LREAL_TO_INT")


def LREAL_TO_UINT(x: float) -> int:
    """LREAL_TO_UINT: nearest integer, stored as a UINT."""
    return _to_integer(float(x), UINT_T, "LREAL_TO_UINT")


def LREAL_TO_DINT(x: float) -> int:
    """LREAL_TO_DINT: nearest integer, stored as a DINT."""
    return _to_integer(float(x), DINT_T, "LREAL_TO_DINT")


def LREAL_TO_UDINT(x: float) -> int:
    """LREAL_TO_UDINT: nearest integer, stored as a UDINT."""
    return _to_integer(float(x), UDINT_T, "LREAL_TO_UDINT")


def LREAL_TO_LINT(x: float) -> int:
    """LREAL_TO_LINT: nearest integer, stored as a LINT."""
    return _to_integer(float(x), LINT_T, "LREAL_TO_LINT")


def LREAL_TO_ULINT(x: float) -> int:
    """LREAL_TO_ULINT: nearest integer, stored as a ULINT."""
    return _to_integer(float(x), ULINT_T, "LREAL_TO_ULINT")


def LREAL_TO_BYTE(x: float) -> int:
    """LREAL_TO_BYTE: nearest integer, stored as a BYTE."""
    return _to_integer(float(x), BYTE_T, "LREAL_TO_BYTE")


def LREAL_TO_WORD(x: float) -> int:
    """LREAL_TO_WORD: nearest integer, stored as a WORD."""
    return _to_integer(float(x), WORD_T, "LREAL_TO_WORD")


def LREAL_TO_DWORD(x: float) -> int:
    """LREAL_TO_DWORD: nearest integer, stored as a DWORD."""
    return _to_integer(float(x), DWORD_T, "LREAL_TO_DWORD")


def LREAL_TO_LWORD(x: float) -> int:
    """LREAL_TO_LWORD: nearest integer, stored as an LWORD."""
    return _to_integer(float(x), LWORD_T, "LREAL_TO_LWORD")


def LREAL_TO_TIME(x: float) -> int:
    """LREAL_TO_TIME: ``x`` milliseconds, rounded to the nearest, as a TIME."""
    return _to_integer(float(x), TIME_T, "LREAL_TO_TIME")


def LREAL_TO_LTIME(x: float) -> int:
    """LREAL_TO_LTIME: ``x`` nanoseconds, rounded to the nearest, as an LTIME."""
    return _to_integer(float(x), LTIME_T, "LREAL_TO_LTIME")


def LREAL_TO_REAL(x: float) -> float:
    """LREAL_TO_REAL: the nearest 32-bit float (infinity past REAL's range).

    >>> LREAL_TO_REAL(16777217.0)
    16777216.0
    """
    return _from_real(x)


# --- other source-named conversions ----------------------------------------------------------


def INT_TO_REAL(x: int) -> float:
    """INT_TO_REAL: exact."""
    return _int_to_real(_source(x, INT_T))


def DINT_TO_REAL(x: int) -> float:
    """DINT_TO_REAL: the nearest 32-bit float (a DINT has more digits than a REAL holds).

    >>> DINT_TO_REAL(16777217)
    16777216.0
    """
    return _int_to_real(_source(x, DINT_T))


def INT_TO_LREAL(x: int) -> float:
    """INT_TO_LREAL: exact."""
    return float(_source(x, INT_T))


def DINT_TO_LREAL(x: int) -> float:
    """DINT_TO_LREAL: exact."""
    return float(_source(x, DINT_T))


def BOOL_TO_INT(x: bool) -> int:
    """BOOL_TO_INT: FALSE -> 0, TRUE -> 1."""
    return int(BOOL_T.store(x))


def INT_TO_BOOL(x: int) -> bool:
    """INT_TO_BOOL: ``x <> 0``."""
    return _source(x, INT_T) != 0


def TIME_TO_DINT(x: int) -> int:
    """TIME_TO_DINT: the milliseconds, read as a DINT (a TIME past 2^31-1 ms turns negative)."""
    return int(DINT_T.store(_source(x, TIME_T)))


def DINT_TO_TIME(x: int) -> int:
    """DINT_TO_TIME: ``x`` milliseconds as a TIME (a negative DINT wraps, TIME is unsigned)."""
    return int(TIME_T.store(_source(x, DINT_T)))


def TIME_TO_LTIME(x: int) -> int:
    """TIME_TO_LTIME: milliseconds to nanoseconds, exact.

    >>> TIME_TO_LTIME(1500)
    1500000000
    """
    return int(LTIME_T.store(_source(x, TIME_T) * _NS_PER_MS))


def LTIME_TO_TIME(x: int) -> int:
    """LTIME_TO_TIME: nanoseconds to milliseconds, truncated; wraps past T#49d17h2m47s295ms.

    >>> LTIME_TO_TIME(1_999_999)
    1
    """
    return int(TIME_T.store(_source(x, LTIME_T) // _NS_PER_MS))


def INT_TO_BYTE(x: int) -> int:
    """INT_TO_BYTE: the low 8 bits."""
    return int(BYTE_T.store(_source(x, INT_T)))


def WORD_TO_INT(x: int) -> int:
    """WORD_TO_INT: the 16 bits read as a signed INT."""
    return int(INT_T.store(_source(x, WORD_T)))


def INT_TO_WORD(x: int) -> int:
    """INT_TO_WORD: the INT's 16 bits as a WORD."""
    return int(WORD_T.store(_source(x, INT_T)))


def DWORD_TO_DINT(x: int) -> int:
    """DWORD_TO_DINT: the 32 bits read as a signed DINT."""
    return int(DINT_T.store(_source(x, DWORD_T)))


def DINT_TO_DWORD(x: int) -> int:
    """DINT_TO_DWORD: the DINT's 32 bits as a DWORD."""
    return int(DWORD_T.store(_source(x, DINT_T)))


def UINT_TO_INT(x: int) -> int:
    """UINT_TO_INT: the 16 bits read as a signed INT."""
    return int(INT_T.store(_source(x, UINT_T)))


def INT_TO_UINT(x: int) -> int:
    """INT_TO_UINT: the INT's 16 bits as a UINT."""
    return int(UINT_T.store(_source(x, INT_T)))


# --- TRUNC, DIV, MOD -------------------------------------------------------------------------


def _truncate(x: float, op: str) -> int:
    if math.isnan(x) or math.isinf(x):
        raise PlcException(
            ExceptionCode.RTSEXCPT_FPU_INVALID_OPERATION, f"{op}({x}): {x} has no integer value"
        )
    return math.trunc(x)


def TRUNC(x: float) -> int:
    """TRUNC: toward zero, as a DINT.

    >>> TRUNC(1.9), TRUNC(-1.4)
    (1, -1)
    """
    return int(DINT_T.store(_truncate(x, "TRUNC")))


def TRUNC_INT(x: float) -> int:
    """TRUNC_INT: toward zero, as an INT."""
    return int(INT_T.store(_truncate(x, "TRUNC_INT")))


@overload
def DIV(a: int, b: int) -> int: ...


@overload
def DIV(a: float, b: float) -> float: ...


def DIV(a: int | float, b: int | float) -> int | float:
    """DIV (ST: ``a / b``): integers truncate toward zero; otherwise a float quotient.

    Division by zero raises RTSEXCPT_DIVIDEBYZERO for integers and
    RTSEXCPT_FPU_DIVIDEBYZERO for floats (TwinCAT stops the task either way).

    >>> DIV(7, 2), DIV(-7, 2), DIV(7.0, 2)
    (3, -3, 3.5)
    """
    if isinstance(a, float) or isinstance(b, float):
        if b == 0:
            raise PlcException(
                ExceptionCode.RTSEXCPT_FPU_DIVIDEBYZERO, f"DIV({a}, {b}): floating-point division by zero"
            )
        return a / b
    return _int_div(a, b, "DIV")


def _int_div(a: int, b: int, op: str) -> int:
    if b == 0:
        raise PlcException(ExceptionCode.RTSEXCPT_DIVIDEBYZERO, f"{op}({a}, {b}): integer division by zero")
    quotient = a // b
    # Python floors; the PLC truncates, which differs when the division is inexact and negative.
    if quotient < 0 and quotient * b != a:
        quotient += 1
    return quotient


def MOD(a: int, b: int) -> int:
    """MOD (ST: ``a MOD b``): remainder with the sign of the dividend; integer types only.

    >>> MOD(7, 2), MOD(-7, 2), MOD(7, -2)
    (1, -1, 1)
    """
    if type(a) is int and type(b) is int and a >= 0 and b > 0:
        # Where Python's % (which floors) and the PLC's MOD (which truncates) agree: one frame, no checks to make.
        return a % b
    for operand in (a, b):
        _require_integer(operand)
    return a - b * _int_div(a, b, "MOD")


def _require_integer(operand: object) -> None:
    if not isinstance(operand, int):
        raise TypeError(
            f"MOD is defined for integer types only, got {type(operand).__name__} {operand!r}"
        )


_STRING_NUMBER: Final = {
    "integer": re.compile(r"[+-]?(?:(?:16#[0-9A-Fa-f][0-9A-Fa-f_]*)|(?:8#[0-7][0-7_]*)|(?:2#[01][01_]*)|(?:\d[\d_]*))"),
    "real": re.compile(r"[+-]?\d[\d_]*(?:\.\d[\d_]*)?(?:[eE][+-]?\d+)?"),
}
_STRING_TIME: Final = re.compile(r"(?:T|TIME|LT|LTIME)#[0-9dhmsun_.]+", re.IGNORECASE)


def STRING_TO_NUMBER(text: str, target: str) -> Number:
    """The value a STRING holds for ``STRING_TO_<target>`` (ST: ``STRING_TO_INT('34abc')`` is 34).

    Read as TwinCAT and CODESYS read it: blanks before the value are skipped,
    the text must start as a literal of the target type (``16#FF``,
    ``2#1111_0000``, ``1.5E3``, ``TRUE``, ``T#127ms``; a type prefix such as
    ``INT#`` is allowed) and anything after it is ignored; text that does not
    start with one gives 0. Pass the result to ``TO_<target>`` to store it in
    the target type (``TO_BYTE(STRING_TO_NUMBER('500', "BYTE"))`` is 244).

    >>> STRING_TO_NUMBER(" 34abc", "WORD"), STRING_TO_NUMBER("abc34", "WORD"), STRING_TO_NUMBER("16#FF", "INT")
    (34, 0, 255)
    >>> STRING_TO_NUMBER("1.5E3", "REAL"), STRING_TO_NUMBER("TRUE", "BOOL"), STRING_TO_NUMBER("T#1s5ms", "TIME")
    (1500.0, True, 1005)
    """
    from iecoop.literals import T, parse_ltime

    text = text.lstrip()
    target = target.upper()
    typed = re.match(r"[A-Za-z_]+#", text)
    if typed is not None and typed.group(0)[:-1].upper() not in ("T", "TIME", "LT", "LTIME"):
        text = text[typed.end():]  # INT#5, BOOL#1: the type prefix names the type already given
    if target == "BOOL":
        word = re.match(r"(TRUE|FALSE)\b", text, re.IGNORECASE)
        if word is not None:
            return word.group(1).upper() == "TRUE"
        return STRING_TO_NUMBER(text, "INT") != 0
    if target in ("TIME", "LTIME"):
        found = _STRING_TIME.match(text)
        if found is None:
            return 0
        literal = found.group(0)
        try:
            return T(literal) if target == "TIME" else parse_ltime(literal)
        except ValueError:
            return 0
    match = _STRING_NUMBER["real" if target in ("REAL", "LREAL") else "integer"].match(text)
    if match is None:
        return 0
    number = match.group(0).replace("_", "")
    if target in ("REAL", "LREAL"):
        return float(number)
    sign = -1 if number.startswith("-") else 1
    digits = number.lstrip("+-")
    base, _, value = digits.rpartition("#")
    return sign * int(value, int(base) if base else 10)



# --- <type>_TO_STRING ------------------------------------------------------------------------
#
# The text TwinCAT 3 writes. BOOL gives 'TRUE' / 'FALSE' and TIME the literal
# ('T#12ms'): Beckhoff Infosys, "BOOL_TO conversions" and "TIME_TO conversions"
# (infosys.beckhoff.com/content/1033/tcplccontrol/925577611.html, 925587851.html).
# Integers give their decimal digits. For REAL and LREAL Beckhoff documents a
# limit of 16 digits, the sixteenth rounded ("REAL/LREAL_TO_<type>",
# infosys.beckhoff.com/content/1033/tc3_plc_intro/9007201783799179.html), and
# CODESYS Control Win writes REAL 0.7 as '0.7' (forge.codesys.com, "Unexpected
# output from REAL_TO_STRING", 2014). The rest of the float format is not
# documented (UNCONFIRMED): the fewest digits that read back as the same value
# (at most 9 for a REAL, 16 for an LREAL), a '.0' on a whole number, and the
# exponent form d.ddddE+nn past 16 digits before the point or below 1E-5.
# Some other runtimes write 0.7 as '7.0e-1' (same thread); iecoop follows TwinCAT.

_REAL_DIGITS: Final = 9  # enough for every float32 to read back exactly
_LREAL_DIGITS: Final = 16  # Beckhoff: "the total number of digits is limited to 16"
_FIXED_EXPONENTS: Final = range(-5, 16)


def _float_text(x: float, digits: tuple[str, int]) -> str:
    """``digits`` (significant digits, decimal exponent of the first) as TwinCAT writes them."""
    mantissa, exponent = digits
    sign = "-" if x < 0 else ""
    if exponent not in _FIXED_EXPONENTS:
        tail = mantissa[1:] or "0"
        return f"{sign}{mantissa[0]}.{tail}E{exponent:+03d}"
    if exponent < 0:
        return f"{sign}0.{'0' * (-exponent - 1)}{mantissa}"
    whole = mantissa[: exponent + 1].ljust(exponent + 1, "0")
    fraction = mantissa[exponent + 1:] or "0"
    return f"{sign}{whole}.{fraction}"


def _float_to_string(x: float, most: int, store: Callable[[float], float]) -> str:
    """The fewest significant digits (up to ``most``) whose decimal, stored, reads back as ``x``."""
    if math.isnan(x):  # the forms of Tc2_Utilities' LREAL_TO_FMTSTR (the conversion documents none)
        return "#QNAN"
    if math.isinf(x):
        return "#INF" if x > 0 else "-#INF"
    if x == 0:
        return "0.0"
    text = ""
    for count in range(1, most + 1):
        text = f"{x:.{count - 1}e}"
        if store(float(text)) == x:
            break
    mantissa, _, exponent = text.lstrip("-").partition("e")
    return _float_text(x, (mantissa.replace(".", "").rstrip("0") or "0", int(exponent)))


def REAL_TO_STRING(x: float) -> str:
    """REAL_TO_STRING: the fewest digits that read back as the same REAL (at most 9).

    ST: ``sText := REAL_TO_STRING(rValue);``  (exponent form past 16 digits, UNCONFIRMED)

    >>> REAL_TO_STRING(1.5), REAL_TO_STRING(0.1), REAL_TO_STRING(-50.1), REAL_TO_STRING(2.0)
    ('1.5', '0.1', '-50.1', '2.0')
    >>> REAL_TO_STRING(1.0 / 3.0), REAL_TO_STRING(3.0e20), REAL_TO_STRING(1.5e-7)
    ('0.33333334', '3.0E+20', '1.5E-07')
    """
    return _float_to_string(_from_real(x), _REAL_DIGITS, _from_real)


def LREAL_TO_STRING(x: float) -> str:
    """LREAL_TO_STRING: the fewest digits that read back as the same LREAL, at most 16 (the 16th rounded).

    ST: ``sText := LREAL_TO_STRING(lrValue);``

    >>> LREAL_TO_STRING(1.4), LREAL_TO_STRING(0.1 + 0.2), LREAL_TO_STRING(1e100)
    ('1.4', '0.3', '1.0E+100')
    """
    return _float_to_string(float(x), _LREAL_DIGITS, float)


def BOOL_TO_STRING(x: bool) -> str:
    """BOOL_TO_STRING: 'TRUE' or 'FALSE' (Python's str() writes 'True').

    >>> BOOL_TO_STRING(True), BOOL_TO_STRING(False)
    ('TRUE', 'FALSE')
    """
    return "TRUE" if BOOL_T.store(x) else "FALSE"


def TIME_TO_STRING(x: int) -> str:
    """TIME_TO_STRING: the TIME literal, zero units left out.

    >>> TIME_TO_STRING(1500), TIME_TO_STRING(12), TIME_TO_STRING(0)
    ('T#1s500ms', 'T#12ms', 'T#0ms')
    """
    return format_time(_source(x, TIME_T))


def _named_to_string(source: ElementaryType, text: Callable[[int], str], what: str) -> Callable[[int], str]:
    """``<source>_TO_STRING``: the argument as a ``source`` variable holds it, written by ``text``."""

    def convert(x: int) -> str:
        return text(_source(x, source))

    convert.__name__ = convert.__qualname__ = f"{source.name}_TO_STRING"
    convert.__doc__ = f"{source.name}_TO_STRING: {what} (ST: ``sText := {source.name}_TO_STRING(x);``)."
    return convert


LTIME_TO_STRING: Final = _named_to_string(LTIME_T, format_ltime, "the LTIME literal, ``LTIME#1ms500us``")
DATE_TO_STRING: Final = _named_to_string(DATE_T, format_date, "the DATE literal, ``D#2024-01-28``")
TOD_TO_STRING: Final = _named_to_string(TOD_T, format_tod, "the TIME_OF_DAY literal, ``TOD#12:30:00.5``")
DT_TO_STRING: Final = _named_to_string(DT_T, format_dt, "the DATE_AND_TIME literal, ``DT#2024-01-28-11:05:43``")


_DIGITS: Final = "the decimal digits of the value the source type holds"
SINT_TO_STRING: Final = _named_to_string(SINT_T, str, _DIGITS)
USINT_TO_STRING: Final = _named_to_string(USINT_T, str, _DIGITS)
INT_TO_STRING: Final = _named_to_string(INT_T, str, _DIGITS)
UINT_TO_STRING: Final = _named_to_string(UINT_T, str, _DIGITS)
DINT_TO_STRING: Final = _named_to_string(DINT_T, str, _DIGITS)
UDINT_TO_STRING: Final = _named_to_string(UDINT_T, str, _DIGITS)
LINT_TO_STRING: Final = _named_to_string(LINT_T, str, _DIGITS)
ULINT_TO_STRING: Final = _named_to_string(ULINT_T, str, _DIGITS)
BYTE_TO_STRING: Final = _named_to_string(BYTE_T, str, _DIGITS)
WORD_TO_STRING: Final = _named_to_string(WORD_T, str, _DIGITS)
DWORD_TO_STRING: Final = _named_to_string(DWORD_T, str, _DIGITS)
LWORD_TO_STRING: Final = _named_to_string(LWORD_T, str, _DIGITS)


def TO_STRING(x: Number) -> str:
    """TO_STRING: by the Python type, since an int does not say which IEC type it is.

    A bool gives 'TRUE' / 'FALSE', an int its decimal digits, a float the
    LREAL text. For a REAL, TIME, DATE, TOD or DT variable call the source-named
    form (``REAL_TO_STRING``, ``TIME_TO_STRING`` ...): their text differs.

    >>> TO_STRING(True), TO_STRING(-7), TO_STRING(0.5)
    ('TRUE', '-7', '0.5')
    """
    if isinstance(x, bool):
        return BOOL_TO_STRING(x)
    if isinstance(x, float):
        return LREAL_TO_STRING(x)
    return str(int(x))


def _wide(convert: Callable[[_Source], str]) -> Callable[[_Source], str]:
    """The WSTRING form of a *_TO_STRING conversion: the same characters (a WSTRING is a Python str too)."""

    def wide(x: _Source) -> str:
        return convert(x)

    wide.__annotations__ = dict(convert.__annotations__)  # the source type, for the reference pages
    name = convert.__name__.replace("TO_STRING", "TO_WSTRING")
    wide.__name__ = wide.__qualname__ = name
    wide.__doc__ = f"{name}: the text of {convert.__name__}, as a WSTRING (ST: ``wsText := {name}(x);``)."
    return wide


REAL_TO_WSTRING: Final = _wide(REAL_TO_STRING)
LREAL_TO_WSTRING: Final = _wide(LREAL_TO_STRING)
BOOL_TO_WSTRING: Final = _wide(BOOL_TO_STRING)
TIME_TO_WSTRING: Final = _wide(TIME_TO_STRING)
LTIME_TO_WSTRING: Final = _wide(LTIME_TO_STRING)
INT_TO_WSTRING: Final = _wide(INT_TO_STRING)
DINT_TO_WSTRING: Final = _wide(DINT_TO_STRING)
TO_WSTRING: Final = _wide(TO_STRING)
