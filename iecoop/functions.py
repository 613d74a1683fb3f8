"""The IEC 61131-3 standard functions: bit shifts, bit access, selection, numeric and string functions.

Each function returns what the ST function returns; the store into a typed
variable then wraps or truncates it, as on the PLC. Where ST takes the width
from the operand's declared type (SHL, SHR, ROL, ROR on a BYTE, WORD ...),
Python cannot see it in a plain ``int``, so the type is the last argument.

ST: ``wOut := ROL(wIn, 3);``  Python: ``self.wOut = ROL(self.wIn, 3, WORD)``

Positions in the string functions count from 1, as in ST; a length or a
position outside the string is clipped to it, as the CODESYS Standard library
documents for its STRING functions (FIND returns 0 when nothing is found).

>>> from iecoop import BYTE
>>> SHL(0x45, 2, BYTE), ROL(0x45, 2, BYTE), SHR(0x45, 2, BYTE)
(20, 21, 17)
>>> LIMIT(0, 150, 100), SEL(True, 10, 20), MUX(2, 10, 20, 30)
(100, 20, 30)
>>> get_bit(0b1010, 3), set_bit(0, 15, True)
(True, 32768)
>>> MID("SUXYSI", 2, 3), INSERT("SUSI", "XY", 2), DELETE("SUXYSI", 2, 3), FIND("abcdef", "de")
('XY', 'SUXYSI', 'SUSI', 4)

Vendor sources: CODESYS Online Help, "Operators" (SHL, SHR, ROL, ROR, SEL,
MUX, LIMIT, MIN, MAX) and the Standard library's string functions (LEN,
LEFT, RIGHT, MID, CONCAT, INSERT, DELETE, REPLACE, FIND); Beckhoff Infosys,
TwinCAT 3 PLC "Bit shift operators", "Selection operators" and
Tc2_Standard "String functions"; bit access ``<variable>.<bit number>``:
CODESYS Online Help "Bit access in variables".
"""

from __future__ import annotations

import math
from typing import TypeVar

from iecoop.types import ElementaryType, elementary_type

__all__ = [
    "ABS", "ACOS", "ASIN", "ATAN", "CONCAT", "COS", "DELETE", "EXP", "EXPT", "FIND", "INSERT", "LEFT", "LEN",
    "LIMIT", "LN", "LOG", "MAX", "MID", "MIN", "MUX", "REPLACE", "RIGHT", "ROL", "ROR", "SEL", "SHL", "SHR",
    "SIN", "SQRT", "TAN", "get_bit", "set_bit",
]

_T = TypeVar("_T")
_N = TypeVar("_N", int, float)


# --- bit shifts: the width is the operand's type ------------------------------------------------


def _bits(type_: object, op: str) -> int:
    record = elementary_type(type_) if not isinstance(type_, ElementaryType) else type_
    if not isinstance(record, ElementaryType) or record.kind not in ("signed", "unsigned"):
        raise TypeError(f"{op}: the width is an integer or bit-string type (BYTE, WORD, DWORD, LWORD, INT ...), got {type_!r}")
    return record.bits


def _count(n: int, op: str) -> int:
    if not isinstance(n, int) or isinstance(n, bool) or n < 0:
        raise ValueError(f"{op}: the shift count N is a non-negative integer, got {n!r}")
    return n


def SHL(value: int, n: int, type_: object) -> int:
    """``SHL(IN, N)``: IN shifted left by N bits inside the width of ``type_``; zeros come in on the right.

    >>> from iecoop import BYTE, WORD
    >>> SHL(0x45, 2, BYTE), SHL(1, 16, WORD)
    (20, 0)
    """
    bits = _bits(type_, "SHL")
    n = _count(n, "SHL")
    # every bit falls off: answered without building a shifted integer of n bits (SHL(x, 16#FFFFFFFF))
    return ((value & ((1 << (bits - n)) - 1)) << n) if n < bits else 0


def SHR(value: int, n: int, type_: object) -> int:
    """``SHR(IN, N)``: IN shifted right by N bits inside the width of ``type_``; zeros come in on the left.

    >>> from iecoop import BYTE, WORD
    >>> SHR(0x45, 2, BYTE), SHR(-1, 12, WORD)
    (17, 15)
    """
    mask = (1 << _bits(type_, "SHR")) - 1
    return (value & mask) >> _count(n, "SHR")


def ROL(value: int, n: int, type_: object) -> int:
    """``ROL(IN, N)``: IN rotated left by N bits inside the width of ``type_``.

    >>> from iecoop import BYTE, WORD
    >>> ROL(0x45, 2, BYTE), ROL(0x8001, 1, WORD)
    (21, 3)
    """
    bits = _bits(type_, "ROL")
    mask = (1 << bits) - 1
    value &= mask
    n = _count(n, "ROL") % bits
    return ((value << n) | (value >> (bits - n))) & mask


def ROR(value: int, n: int, type_: object) -> int:
    """``ROR(IN, N)``: IN rotated right by N bits inside the width of ``type_``.

    >>> from iecoop import BYTE, WORD
    >>> ROR(0x45, 2, BYTE), ROR(3, 1, WORD)
    (81, 32769)
    """
    bits = _bits(type_, "ROR")
    mask = (1 << bits) - 1
    value &= mask
    n = _count(n, "ROR") % bits
    return ((value >> n) | (value << (bits - n))) & mask


# --- bit access: x.3 ----------------------------------------------------------------------------


def _bit_number(n: int) -> int:
    if not isinstance(n, int) or isinstance(n, bool) or not 0 <= n <= 63:
        raise ValueError(f"bit number {n!r} is outside 0..63")
    return n


def get_bit(value: int, n: int) -> bool:
    """Bit ``n`` of an integer or bit string (ST ``x.n``); bit 0 is the least significant.

    >>> get_bit(0b1000, 3), get_bit(-1, 15)
    (True, True)
    """
    return bool((value >> _bit_number(n)) & 1)


def set_bit(value: int, n: int, flag: bool) -> int:
    """``value`` with bit ``n`` set to ``flag`` (ST ``x.n := flag`` is ``self.x = set_bit(self.x, n, flag)``).

    >>> set_bit(0, 3, True), set_bit(0b1111, 0, False)
    (8, 14)
    """
    bit = 1 << _bit_number(n)
    return value | bit if flag else value & ~bit


# --- selection ----------------------------------------------------------------------------------


def SEL(g: bool, in0: _T, in1: _T) -> _T:
    """``SEL(G, IN0, IN1)``: IN0 when G is FALSE, IN1 when G is TRUE.

    >>> SEL(False, "a", "b")
    'a'
    """
    return in1 if g else in0


def MUX(k: int, *inputs: _T) -> _T:
    """``MUX(K, IN0, ..., INn)``: the input number K (from 0).

    A K outside 0..n is undefined on the PLC; here it is refused.

    >>> MUX(0, 5, 6, 7)
    5
    """
    if not 0 <= k < len(inputs):
        raise ValueError(f"MUX: K = {k} selects no input (K runs 0..{len(inputs) - 1})")
    return inputs[k]


def MIN(first: _N, *others: _N) -> _N:
    """``MIN(IN0, IN1, ...)``: the smallest input.

    >>> MIN(3, -2, 7)
    -2
    """
    return min(first, *others) if others else first


def MAX(first: _N, *others: _N) -> _N:
    """``MAX(IN0, IN1, ...)``: the largest input.

    >>> MAX(3, -2, 7)
    7
    """
    return max(first, *others) if others else first


def LIMIT(mn: _N, value: _N, mx: _N) -> _N:
    """``LIMIT(MN, IN, MX)``: IN kept within MN .. MX.

    >>> LIMIT(0, -5, 10), LIMIT(0.0, 3.5, 1.0)
    (0, 1.0)
    """
    return mn if value < mn else mx if value > mx else value


# --- numeric functions --------------------------------------------------------------------------


def ABS(value: _N) -> _N:
    """``ABS(IN)``: the absolute value (``ABS(INT#-32768)`` wraps back to -32768 on the store)."""
    return abs(value)


def SQRT(value: float) -> float:
    """``SQRT(IN)``; a negative input gives NaN, as the FPU does."""
    return math.sqrt(value) if value >= 0 else math.nan


def LN(value: float) -> float:
    """``LN(IN)``: natural logarithm; 0 gives -infinity and a negative input NaN."""
    return math.log(value) if value > 0 else (-math.inf if value == 0 else math.nan)


def LOG(value: float) -> float:
    """``LOG(IN)``: base-10 logarithm; 0 gives -infinity and a negative input NaN."""
    return math.log10(value) if value > 0 else (-math.inf if value == 0 else math.nan)


def EXP(value: float) -> float:
    """``EXP(IN)``: e to the power IN (infinity when it overflows)."""
    try:
        return math.exp(value)
    except OverflowError:
        return math.inf


def EXPT(base: float, exponent: float) -> float:
    """``EXPT(IN1, IN2)``: IN1 to the power IN2, as a floating-point result.

    >>> EXPT(2, 10)
    1024.0
    """
    try:
        result = math.pow(base, exponent)
    except OverflowError:
        return math.inf
    except ValueError:
        return math.nan
    return result


def SIN(value: float) -> float:
    """``SIN(IN)``, IN in radians."""
    return math.sin(value)


def COS(value: float) -> float:
    """``COS(IN)``, IN in radians."""
    return math.cos(value)


def TAN(value: float) -> float:
    """``TAN(IN)``, IN in radians."""
    return math.tan(value)


def ASIN(value: float) -> float:
    """``ASIN(IN)``; outside -1..1 gives NaN."""
    return math.asin(value) if -1 <= value <= 1 else math.nan


def ACOS(value: float) -> float:
    """``ACOS(IN)``; outside -1..1 gives NaN."""
    return math.acos(value) if -1 <= value <= 1 else math.nan


def ATAN(value: float) -> float:
    """``ATAN(IN)`` in radians."""
    return math.atan(value)


# --- string functions (positions from 1) --------------------------------------------------------


def LEN(text: str) -> int:
    """``LEN(STR)``: the number of characters.

    >>> LEN("SUSI")
    4
    """
    return len(text)


def LEFT(text: str, size: int) -> str:
    """``LEFT(STR, SIZE)``: the first SIZE characters.

    >>> LEFT("SUSI", 3), LEFT("SUSI", 9)
    ('SUS', 'SUSI')
    """
    return text[: max(size, 0)]


def RIGHT(text: str, size: int) -> str:
    """``RIGHT(STR, SIZE)``: the last SIZE characters.

    >>> RIGHT("SUSI", 3), RIGHT("SUSI", 0)
    ('USI', '')
    """
    return text[len(text) - min(max(size, 0), len(text)) :]


def MID(text: str, length: int, pos: int) -> str:
    """``MID(STR, LEN, POS)``: LEN characters from position POS.

    >>> MID("SUSI", 2, 2)
    'US'
    """
    start = max(pos, 1) - 1
    return text[start : start + max(length, 0)]


def CONCAT(first: str, second: str, *more: str) -> str:
    """``CONCAT(STR1, STR2, ...)``: the strings one after the other (IEC 61131-3 makes CONCAT extensible).

    >>> CONCAT("SUSI", "WILLI"), CONCAT("a", "b", "c")
    ('SUSIWILLI', 'abc')
    """
    return first + second + "".join(more)


def INSERT(text: str, insert: str, pos: int) -> str:
    """``INSERT(STR1, STR2, POS)``: STR2 inserted into STR1 after position POS.

    >>> INSERT("SUSI", "XY", 2), INSERT("SUSI", "XY", 0)
    ('SUXYSI', 'XYSUSI')
    """
    at = min(max(pos, 0), len(text))
    return text[:at] + insert + text[at:]


def DELETE(text: str, length: int, pos: int) -> str:
    """``DELETE(STR, LEN, POS)``: STR without the LEN characters from position POS.

    >>> DELETE("SUXYSI", 2, 3)
    'SUSI'
    """
    start = max(pos, 1) - 1
    return text[:start] + text[start + max(length, 0) :]


def REPLACE(text: str, replacement: str, length: int, pos: int) -> str:
    """``REPLACE(STR1, STR2, L, P)``: the L characters of STR1 from position P replaced by STR2.

    >>> REPLACE("SUXYSI", "K", 2, 2)
    'SKYSI'
    """
    start = min(max(pos, 1) - 1, len(text))
    return text[:start] + replacement + text[start + max(length, 0) :]


def FIND(text: str, search: str) -> int:
    """``FIND(STR1, STR2)``: the position of the first STR2 in STR1, 0 when there is none.

    >>> FIND("abcdef", "de"), FIND("abcdef", "x")
    (4, 0)
    """
    return text.find(search) + 1 if search else 0
