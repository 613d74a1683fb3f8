"""Tc2_Utilities: Beckhoff's utility library (formatting, time structures, strings, ring buffers).

Written from Beckhoff's documentation (Infosys, "TwinCAT 3 PLC Lib:
Tc2_Utilities"); the "Tc2_Utilities" library page lists every name with what
is simulated.

* ``FB_FormatString`` formats up to ten ``T_Arg`` arguments as Beckhoff's
  format specification says (``%[flags][width][.precision]type``), with its
  format error codes; ``F_INT``, ``F_LREAL``, ``F_STRING``... make the
  arguments.
* Time blocks (``NT_GetTime``, ``FB_LocalSystemTime``) read the task clock,
  whose 0 is 1970-01-01 00:00:00 (see Tc2_System); the local time is UTC.

>>> fmt = FB_FormatString()
>>> fmt(sFormat="X: %+.3f mm, step %d of %s", arg1=F_LREAL(12.5), arg2=F_INT(3), arg3=F_STRING("ten"))
>>> fmt.sOut, fmt.bError
('X: +12.500 mm, step 3 of ten', False)
>>> from iecoop.literals import parse_dt
>>> SYSTEMTIME_TO_STRING(DT_TO_SYSTEMTIME(parse_dt("DT#2024-02-29-13:45:07")))
'2024-02-29-13:45:07.000'
"""

from __future__ import annotations

import collections
import datetime
import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Annotated, Any

from iecoop.declarations import VAR, VAR_IN_OUT, VAR_INPUT, VAR_OUTPUT
from iecoop.exceptions import ExceptionCode, PlcException
from iecoop.libraries._cstrings import c_string, put_c_string
from iecoop.libraries._printf import Arg, FormatError, render
from iecoop.libraries._utilities_data import (
    ARG_TO_CSVFIELD, BYTEARR_TO_MAXSTRING, CONCAT2, CSVFIELD_TO_ARG, DATA_TO_HEXSTR, DEG_TO_RAD, DELETE2,
    DINT_TO_DECSTR, HEXSTR_TO_DATA, RAD_TO_DEG,
)
from iecoop.libraries.tc2_system import (
    DEFAULT_ADS_TIMEOUT, MAX_STRING_LENGTH, T_AmsNetId, T_MaxString, filetime_now, lib_version, version_element,
)
from iecoop.members import method
from iecoop.memory import POINTER_TO, Alias, IecEnum, Pointer, Struct, adr
from iecoop.parameters import function
from iecoop.pou import FunctionBlock
from iecoop.runtime.clock import current_clock
from iecoop.types import (
    BOOL, BYTE, DINT, DT, DWORD, INT, LINT, LREAL, LWORD, REAL, SINT, STRING, TIME, UDINT, UINT, ULINT, USINT,
    WORD,
)

__all__ = [
    "ARG_TO_CSVFIELD", "BYTEARR_TO_MAXSTRING", "CONCAT2", "CSVFIELD_TO_ARG", "DATA_TO_HEXSTR", "DEG_TO_RAD", "DELETE2",
    "DINT_TO_DECSTR", "HEXSTR_TO_DATA", "RAD_TO_DEG",
    "BYTE_TO_BINSTR", "BYTE_TO_DECSTR", "BYTE_TO_HEXSTR", "BYTE_TO_OCTSTR", "CSVFIELD_TO_STRING", "DT_TO_FILETIME",
    "DT_TO_SYSTEMTIME",
    "DWORD_TO_BINSTR", "DWORD_TO_DECSTR", "DWORD_TO_HEXSTR", "DWORD_TO_OCTSTR", "E_ArgType", "E_TimeZoneID", "F_BIGTYPE",
    "E_TypeFieldParam", "FB_FormatString", "FB_LocalSystemTime", "FB_MemRingBuffer", "FB_StringRingBuffer", "FILETIME64_TO_SYSTEMTIME",
    "FILETIME_TO_DT", "FILETIME_TO_SYSTEMTIME", "F_BOOL", "F_BYTE", "F_DINT", "F_DWORD", "F_FormatArgToStr",
    "F_GetDOYOfYearMonthDay", "F_GetMaxMonthDays", "F_GetVersionTcUtilities", "F_INT", "F_LINT", "F_LREAL",
    "F_LTrim", "F_LWORD", "F_REAL", "F_RTrim", "F_SINT", "F_STRING", "F_ToLCase", "F_ToUCase", "F_UDINT", "F_UINT",
    "F_ULINT", "F_USINT", "F_WORD", "F_YearIsLeapYear", "FindAndReplace", "LEN2", "LREAL_TO_FMTSTR",
    "LWORD_TO_BINSTR", "LWORD_TO_DECSTR", "LWORD_TO_HEXSTR", "LWORD_TO_OCTSTR", "LrealIsFinite", "LrealIsNaN",
    "NT_GetTime", "STRING_TO_CSVFIELD", "STRING_TO_WSTRING2", "SYSTEMTIME_TO_DT", "SYSTEMTIME_TO_FILETIME",
    "SYSTEMTIME_TO_FILETIME64", "SYSTEMTIME_TO_STRING", "TIMESTRUCT", "T_Arg", "T_FILETIME", "T_FILETIME64",
    "WLEN2", "WORD_TO_BINSTR", "WORD_TO_DECSTR", "WORD_TO_HEXSTR", "WORD_TO_OCTSTR", "WSTRING_TO_STRING2",
    "stLibVersion_Tc2_Utilities",
]

#: ``stLibVersion_Tc2_Utilities``: the version of Tc2_Utilities iecoop follows.
stLibVersion_Tc2_Utilities = lib_version("Tc2_Utilities")


def F_GetVersionTcUtilities(nVersionElement: INT) -> UINT:  # noqa: N802, N803 - the ST names
    """``F_GetVersionTcUtilities(nVersionElement)``: 1 the major, 2 the minor, 3 the build number of Tc2_Utilities."""
    return version_element(stLibVersion_Tc2_Utilities, nVersionElement)


# --- T_Arg and its helpers ----------------------------------------------------------------------


class E_ArgType(IecEnum):  # noqa: N801 - the ST name
    """``E_ArgType``: the type of the data a ``T_Arg`` points to."""

    ARGTYPE_UNKNOWN = 0
    ARGTYPE_BYTE = 1
    ARGTYPE_WORD = 2
    ARGTYPE_DWORD = 3
    ARGTYPE_REAL = 4
    ARGTYPE_LREAL = 5
    ARGTYPE_SINT = 6
    ARGTYPE_INT = 7
    ARGTYPE_DINT = 8
    ARGTYPE_USINT = 9
    ARGTYPE_UINT = 10
    ARGTYPE_UDINT = 11
    ARGTYPE_STRING = 12
    ARGTYPE_BOOL = 13
    ARGTYPE_BIGTYPE = 14
    ARGTYPE_ULARGE = 15
    ARGTYPE_UHUGE = 16
    ARGTYPE_LARGE = 17
    ARGTYPE_HUGE = 18


class T_Arg(Struct):  # noqa: N801 - the ST name
    """``T_Arg``: one argument of FB_FormatString: its type, byte length and address.

    For a STRING, cbLen is the length plus 1 (the terminating null).
    """

    eType: E_ArgType = E_ArgType.ARGTYPE_UNKNOWN
    cbLen: UDINT = 0
    pData: Pointer[Any] = VAR()


class _BoxBYTE(Struct):
    value: BYTE = 0


class _BoxWORD(Struct):
    value: WORD = 0


class _BoxDWORD(Struct):
    value: DWORD = 0


class _BoxLWORD(Struct):
    value: LWORD = 0


class _BoxSINT(Struct):
    value: SINT = 0


class _BoxINT(Struct):
    value: INT = 0


class _BoxDINT(Struct):
    value: DINT = 0


class _BoxLINT(Struct):
    value: LINT = 0


class _BoxUSINT(Struct):
    value: USINT = 0


class _BoxUINT(Struct):
    value: UINT = 0


class _BoxUDINT(Struct):
    value: UDINT = 0


class _BoxULINT(Struct):
    value: ULINT = 0


class _BoxREAL(Struct):
    value: REAL = 0.0


class _BoxLREAL(Struct):
    value: LREAL = 0.0


class _BoxBOOL(Struct):
    value: BOOL = False


class _BoxSTRING(Struct):
    value: T_MaxString = ""


# The data a T_Arg points to. On the PLC it is the helper function's own
# variable, valid until the next call; here the most recent ones are kept.
_recent: collections.deque[Struct] = collections.deque(maxlen=4096)

#: ST type, the box that holds it, its E_ArgType and its byte size (0: a STRING, its length + 1)
_ARG_TYPES: dict[str, tuple[type[Struct], E_ArgType, int]] = {
    "BYTE": (_BoxBYTE, E_ArgType.ARGTYPE_BYTE, 1),
    "WORD": (_BoxWORD, E_ArgType.ARGTYPE_WORD, 2),
    "DWORD": (_BoxDWORD, E_ArgType.ARGTYPE_DWORD, 4),
    "LWORD": (_BoxLWORD, E_ArgType.ARGTYPE_ULARGE, 8),
    "SINT": (_BoxSINT, E_ArgType.ARGTYPE_SINT, 1),
    "INT": (_BoxINT, E_ArgType.ARGTYPE_INT, 2),
    "DINT": (_BoxDINT, E_ArgType.ARGTYPE_DINT, 4),
    "LINT": (_BoxLINT, E_ArgType.ARGTYPE_LARGE, 8),
    "USINT": (_BoxUSINT, E_ArgType.ARGTYPE_USINT, 1),
    "UINT": (_BoxUINT, E_ArgType.ARGTYPE_UINT, 2),
    "UDINT": (_BoxUDINT, E_ArgType.ARGTYPE_UDINT, 4),
    "ULINT": (_BoxULINT, E_ArgType.ARGTYPE_ULARGE, 8),
    "REAL": (_BoxREAL, E_ArgType.ARGTYPE_REAL, 4),
    "LREAL": (_BoxLREAL, E_ArgType.ARGTYPE_LREAL, 8),
    "BOOL": (_BoxBOOL, E_ArgType.ARGTYPE_BOOL, 1),
    "STRING": (_BoxSTRING, E_ArgType.ARGTYPE_STRING, 0),
}

#: How FB_FormatString reads each E_ArgType: the ST type the formatter sees and the box type that reads it.
_READ_AS: dict[int, tuple[str, Any]] = {
    E_ArgType.ARGTYPE_BYTE: ("BYTE", BYTE), E_ArgType.ARGTYPE_WORD: ("WORD", WORD),
    E_ArgType.ARGTYPE_DWORD: ("DWORD", DWORD), E_ArgType.ARGTYPE_REAL: ("REAL", REAL),
    E_ArgType.ARGTYPE_LREAL: ("LREAL", LREAL), E_ArgType.ARGTYPE_SINT: ("SINT", SINT),
    E_ArgType.ARGTYPE_INT: ("INT", INT), E_ArgType.ARGTYPE_DINT: ("DINT", DINT),
    E_ArgType.ARGTYPE_USINT: ("USINT", USINT), E_ArgType.ARGTYPE_UINT: ("UINT", UINT),
    E_ArgType.ARGTYPE_UDINT: ("UDINT", UDINT), E_ArgType.ARGTYPE_BOOL: ("BOOL", BOOL),
    E_ArgType.ARGTYPE_ULARGE: ("ULINT", ULINT), E_ArgType.ARGTYPE_LARGE: ("LINT", LINT),
}


def _make_arg(type_name: str, value: object) -> T_Arg:
    box_type, arg_type, size = _ARG_TYPES[type_name]
    box: Any = box_type(value=value)
    _recent.append(box)
    if not size:
        size = len(box.value.encode("latin-1")) + 1
    arg = T_Arg(eType=arg_type, cbLen=size)
    arg.pData = adr(box, "value")
    return arg


def F_BYTE(in_: BYTE) -> T_Arg:  # noqa: N802 - the ST name
    """``F_BYTE(in)``: a BYTE as a T_Arg."""
    return _make_arg("BYTE", in_)


def F_WORD(in_: WORD) -> T_Arg:  # noqa: N802
    """``F_WORD(in)``: a WORD as a T_Arg."""
    return _make_arg("WORD", in_)


def F_DWORD(in_: DWORD) -> T_Arg:  # noqa: N802
    """``F_DWORD(in)``: a DWORD as a T_Arg."""
    return _make_arg("DWORD", in_)


def F_LWORD(in_: LWORD) -> T_Arg:  # noqa: N802
    """``F_LWORD(in)``: an LWORD as a T_Arg (ARGTYPE_ULARGE)."""
    return _make_arg("LWORD", in_)


def F_SINT(in_: SINT) -> T_Arg:  # noqa: N802
    """``F_SINT(in)``: a SINT as a T_Arg."""
    return _make_arg("SINT", in_)


def F_INT(in_: INT) -> T_Arg:  # noqa: N802
    """``F_INT(in)``: an INT as a T_Arg."""
    return _make_arg("INT", in_)


def F_DINT(in_: DINT) -> T_Arg:  # noqa: N802
    """``F_DINT(in)``: a DINT as a T_Arg."""
    return _make_arg("DINT", in_)


def F_LINT(in_: LINT) -> T_Arg:  # noqa: N802
    """``F_LINT(in)``: an LINT as a T_Arg (ARGTYPE_LARGE)."""
    return _make_arg("LINT", in_)


def F_USINT(in_: USINT) -> T_Arg:  # noqa: N802
    """``F_USINT(in)``: a USINT as a T_Arg."""
    return _make_arg("USINT", in_)


def F_UINT(in_: UINT) -> T_Arg:  # noqa: N802
    """``F_UINT(in)``: a UINT as a T_Arg."""
    return _make_arg("UINT", in_)


def F_UDINT(in_: UDINT) -> T_Arg:  # noqa: N802
    """``F_UDINT(in)``: a UDINT as a T_Arg."""
    return _make_arg("UDINT", in_)


def F_ULINT(in_: ULINT) -> T_Arg:  # noqa: N802
    """``F_ULINT(in)``: a ULINT as a T_Arg (ARGTYPE_ULARGE)."""
    return _make_arg("ULINT", in_)


def F_REAL(in_: REAL) -> T_Arg:  # noqa: N802
    """``F_REAL(in)``: a REAL as a T_Arg (stored as 32 bits, as on the PLC)."""
    return _make_arg("REAL", in_)


def F_LREAL(in_: LREAL) -> T_Arg:  # noqa: N802
    """``F_LREAL(in)``: an LREAL as a T_Arg."""
    return _make_arg("LREAL", in_)


def F_BOOL(in_: BOOL) -> T_Arg:  # noqa: N802
    """``F_BOOL(in)``: a BOOL as a T_Arg (``%s`` prints TRUE / FALSE)."""
    return _make_arg("BOOL", in_)


def F_STRING(in_: T_MaxString) -> T_Arg:  # noqa: N802
    """``F_STRING(in)``: a STRING as a T_Arg (cbLen: its length + 1)."""
    return _make_arg("STRING", in_)


def F_BIGTYPE(pData: Pointer[Any], cbLen: DWORD) -> T_Arg:  # noqa: N802, N803 - the ST names
    """``F_BIGTYPE(pData, cbLen)``: a STRUCT or ARRAY variable as a T_Arg (ARGTYPE_BIGTYPE): its address and size."""
    arg = T_Arg(eType=E_ArgType.ARGTYPE_BIGTYPE, cbLen=cbLen)
    arg.pData = pData
    return arg


def _read_arg(arg: T_Arg) -> Arg | None:
    """The formatter's view of ``arg``: its type and value read at pData, or None when it was never set."""
    kind = int(arg.eType)
    if kind == E_ArgType.ARGTYPE_UNKNOWN:
        return None
    if not arg.pData:
        return Arg("POINTER", 0)  # no data: the formatter refuses it as a type mismatch
    if kind == E_ArgType.ARGTYPE_STRING:
        data = arg.pData.typed(BYTE)
        raw = bytearray()
        for i in range(max(0, arg.cbLen - 1)):
            byte = (data + i).deref
            if not byte:
                break
            raw.append(byte)
        return Arg("STRING", raw.decode("latin-1"))
    read = _READ_AS.get(kind)
    if read is None:
        return Arg(E_ArgType(kind).name, 0)
    return Arg(read[0], arg.pData.typed(read[1]).deref)


# --- FB_FormatString, F_FormatArgToStr ----------------------------------------------------------


class FB_FormatString(FunctionBlock):
    """``FB_FormatString``: sFormat with up to ten arguments formatted into sOut, in the same call.

    ST: ``VAR_INPUT sFormat : T_MaxString; arg1 .. arg10 : T_Arg; END_VAR
    VAR_OUTPUT bError : BOOL; nErrId : UDINT; sOut : T_MaxString; END_VAR``.
    On a format error sOut is empty and nErrId is Beckhoff's format error
    code: a class (16#10 '%' misplaced ... 16#8000 sOut overflow) plus the
    number of the argument being formatted.

    >>> fmt = FB_FormatString()
    >>> fmt(sFormat="%d %q", arg1=F_INT(1), arg2=F_INT(2))
    >>> fmt.bError, hex(fmt.nErrId), fmt.sOut
    (True, '0x802', '')
    """

    sFormat: T_MaxString = VAR_INPUT("")
    arg1: T_Arg = VAR_INPUT()
    arg2: T_Arg = VAR_INPUT()
    arg3: T_Arg = VAR_INPUT()
    arg4: T_Arg = VAR_INPUT()
    arg5: T_Arg = VAR_INPUT()
    arg6: T_Arg = VAR_INPUT()
    arg7: T_Arg = VAR_INPUT()
    arg8: T_Arg = VAR_INPUT()
    arg9: T_Arg = VAR_INPUT()
    arg10: T_Arg = VAR_INPUT()
    bError: BOOL = VAR_OUTPUT(False)
    nErrId: UDINT = VAR_OUTPUT(0)
    sOut: T_MaxString = VAR_OUTPUT("")

    def body(self) -> None:
        args = [
            _read_arg(a) for a in (
                self.arg1, self.arg2, self.arg3, self.arg4, self.arg5,
                self.arg6, self.arg7, self.arg8, self.arg9, self.arg10,
            )
        ]
        try:
            self.sOut = render(self.sFormat, args, MAX_STRING_LENGTH)
        except FormatError as exc:
            self.bError, self.nErrId, self.sOut = True, exc.code, ""
        else:
            self.bError, self.nErrId = False, 0


class E_TypeFieldParam(IecEnum):  # noqa: N801 - the ST name
    """``E_TypeFieldParam``: the type field of ``F_FormatArgToStr``."""

    TYPEFIELD_UNKNOWN = 0
    TYPEFIELD_B = 1
    TYPEFIELD_O = 2
    TYPEFIELD_U = 3
    TYPEFIELD_C = 4
    TYPEFIELD_F = 5
    TYPEFIELD_D = 6
    TYPEFIELD_S = 7
    TYPEFIELD_XU = 8
    TYPEFIELD_XL = 9
    TYPEFIELD_EU = 10
    TYPEFIELD_EL = 11


_TYPE_LETTER = {
    E_TypeFieldParam.TYPEFIELD_B: "b", E_TypeFieldParam.TYPEFIELD_O: "o", E_TypeFieldParam.TYPEFIELD_U: "u",
    E_TypeFieldParam.TYPEFIELD_C: "c", E_TypeFieldParam.TYPEFIELD_F: "f", E_TypeFieldParam.TYPEFIELD_D: "d",
    E_TypeFieldParam.TYPEFIELD_S: "s", E_TypeFieldParam.TYPEFIELD_XU: "X", E_TypeFieldParam.TYPEFIELD_XL: "x",
    E_TypeFieldParam.TYPEFIELD_EU: "E", E_TypeFieldParam.TYPEFIELD_EL: "e",
}


@function
def F_FormatArgToStr(  # noqa: N802 - the ST names
    bSign: BOOL, bBlank: BOOL, bNull: BOOL, bHash: BOOL, bLAlign: BOOL,  # noqa: N803
    bWidth: BOOL, iWidth: INT, bPrecision: BOOL, iPrecision: INT,  # noqa: N803
    eFmtType: E_TypeFieldParam, args: T_Arg,  # noqa: N803
    sOut: POINTER_TO[T_MaxString] = VAR_IN_OUT(),  # noqa: N803
) -> UDINT:
    """``F_FormatArgToStr``: one argument formatted by the fields given one by one; the format error code (0: none).

    The flags are '+' (bSign), ' ' (bBlank), '0' (bNull), '#' (bHash), '-'
    (bLAlign); iWidth and iPrecision count when bWidth / bPrecision are TRUE.
    """
    letter = _TYPE_LETTER.get(eFmtType)
    if letter is None:
        return 0x800 + 1  # invalid (unsupported) type field value, argument 1
    flags = "".join(f for f, on in (("+", bSign), (" ", bBlank), ("0", bNull), ("#", bHash), ("-", bLAlign)) if on)
    width = str(iWidth) if bWidth else ""
    precision = f".{iPrecision}" if bPrecision else ""
    try:
        sOut.deref = render(f"%{flags}{width}{precision}{letter}", [_read_arg(args)], MAX_STRING_LENGTH)
    except FormatError as exc:
        return exc.code
    return 0


def LREAL_TO_FMTSTR(in_: LREAL, iPrecision: INT, bRound: BOOL) -> T_MaxString:  # noqa: N802, N803
    """``LREAL_TO_FMTSTR(in, iPrecision, bRound)``: ``in`` with iPrecision decimals, rounded or cut.

    iPrecision is clipped to 0..15 (Beckhoff's MAX_DECIMAL_PLACES); an
    infinite value is '#INF' / '-#INF', not-a-number '#QNAN'.

    >>> LREAL_TO_FMTSTR(2.71828, 3, True), LREAL_TO_FMTSTR(2.71828, 3, False), LREAL_TO_FMTSTR(-0.5, 0, True)
    ('2.718', '2.718', '-1')
    """
    precision = min(max(int(iPrecision), 0), 15)
    if in_ != in_:
        return "#QNAN"
    if in_ in (float("inf"), float("-inf")):
        return "#INF" if in_ > 0 else "-#INF"
    if not bRound:
        scale = 10 ** precision
        in_ = int(in_ * scale) / scale
        return f"{in_:.{precision}f}"
    # Half away from zero, as Beckhoff's rounding, not Python's half to even.
    scaled = abs(in_) * 10 ** precision
    whole = int(scaled + 0.5)
    text = f"{whole / 10 ** precision:.{precision}f}"
    return "-" + text if in_ < 0 and whole else text


def F_ToLCase(in_: T_MaxString) -> T_MaxString:  # noqa: N802 - the ST name
    """``F_ToLCase(in)``: ``in`` with A..Z made a..z (other characters unchanged)."""
    return in_.translate(_LOWER)


def F_ToUCase(in_: T_MaxString) -> T_MaxString:  # noqa: N802 - the ST name
    """``F_ToUCase(in)``: ``in`` with a..z made A..Z (other characters unchanged)."""
    return in_.translate(_UPPER)


_LOWER = str.maketrans("ABCDEFGHIJKLMNOPQRSTUVWXYZ", "abcdefghijklmnopqrstuvwxyz")
_UPPER = str.maketrans("abcdefghijklmnopqrstuvwxyz", "ABCDEFGHIJKLMNOPQRSTUVWXYZ")


def F_LTrim(in_: T_MaxString) -> T_MaxString:  # noqa: N802 - the ST name
    """``F_LTrim(in)``: ``in`` without its leading blanks."""
    return in_.lstrip(" ")


def F_RTrim(in_: T_MaxString) -> T_MaxString:  # noqa: N802 - the ST name
    """``F_RTrim(in)``: ``in`` without its trailing blanks."""
    return in_.rstrip(" ")


def LrealIsNaN(x: LREAL) -> BOOL:  # noqa: N802 - the ST name
    """``LrealIsNaN(x)``: TRUE when x is not a number (NaN)."""
    return math.isnan(x)


def LrealIsFinite(x: LREAL) -> BOOL:  # noqa: N802 - the ST name
    """``LrealIsFinite(x)``: TRUE when x is neither infinite nor NaN."""
    return math.isfinite(x)


def STRING_TO_CSVFIELD(in_: T_MaxString, bQM: BOOL) -> T_MaxString:  # noqa: N802, N803 - the ST names
    """``STRING_TO_CSVFIELD(in, bQM)``: ``in`` as a CSV data field, each ``"`` doubled, enclosed in ``"`` when bQM.

    A field longer than T_MaxString (255 characters) is an error: the result is ''.
    """
    field = in_.replace('"', '""')
    field = f'"{field}"' if bQM else field
    return field if len(field) <= MAX_STRING_LENGTH else ""


def CSVFIELD_TO_STRING(in_: T_MaxString, bQM: BOOL) -> T_MaxString:  # noqa: N802, N803 - the ST names
    """``CSVFIELD_TO_STRING(in, bQM)``: the value of the CSV data field ``in``, each ``""`` one ``"``; with bQM the
    enclosing ``"`` are removed. A field bQM finds unenclosed, or with a ``"`` not doubled, is an error: ''."""
    body = in_
    if bQM:
        if len(in_) < 2 or in_[0] != '"' or in_[-1] != '"':
            return ""
        body = in_[1:-1]
    if body.replace('""', "").count('"'):
        return ""
    return body.replace('""', '"')


def _digits(value: int, base: int, precision: int, lower: bool = False) -> str:
    """``value`` in ``base``, zero-filled to ``precision`` digits, never cut; 0 with precision 0 is ``''`` (Infosys)."""
    if value == 0 and precision <= 0:
        return ""
    text = {2: "b", 8: "o", 10: "d", 16: "x" if lower else "X"}[base]
    return format(value, text).rjust(max(0, int(precision)), "0")


def _to_digits(source: str, base: int) -> Callable[..., str]:
    """``FUNCTION <source>_TO_<BIN|OCT|DEC|HEX>STR(in, iPrecision[, bLoCase]) : T_MaxString``."""
    kind = {2: "BIN", 8: "OCT", 10: "DEC", 16: "HEX"}[base]
    name = f"{source}_TO_{kind}STR"
    annotation = {"BYTE": BYTE, "WORD": WORD, "DWORD": DWORD, "LWORD": LWORD}[source]
    mask = {"BYTE": 0xFF, "WORD": 0xFFFF, "DWORD": 0xFFFF_FFFF, "LWORD": 0xFFFF_FFFF_FFFF_FFFF}[source]

    def convert(in_: Any, iPrecision: Any, bLoCase: Any = False) -> str:  # noqa: N803 - the ST names
        return _digits(int(in_) & mask, base, int(iPrecision), bool(bLoCase))

    def convert_plain(in_: Any, iPrecision: Any) -> str:  # noqa: N803 - the ST names
        return _digits(int(in_) & mask, base, int(iPrecision))

    converter = convert if base == 16 else convert_plain
    converter.__name__ = converter.__qualname__ = name
    converter.__doc__ = (
        f"``{name}(in, iPrecision{', bLoCase' if base == 16 else ''})``: ``in`` in base {base}, zero-filled to at "
        "least iPrecision digits (never cut); 0 with iPrecision 0 is the empty string."
    )
    converter.__annotations__ = {"in_": annotation, "iPrecision": INT, "return": T_MaxString}
    if base == 16:
        converter.__annotations__["bLoCase"] = BOOL
    return converter


BYTE_TO_BINSTR = _to_digits("BYTE", 2)
BYTE_TO_OCTSTR = _to_digits("BYTE", 8)
BYTE_TO_DECSTR = _to_digits("BYTE", 10)
BYTE_TO_HEXSTR = _to_digits("BYTE", 16)
WORD_TO_BINSTR = _to_digits("WORD", 2)
WORD_TO_OCTSTR = _to_digits("WORD", 8)
WORD_TO_DECSTR = _to_digits("WORD", 10)
WORD_TO_HEXSTR = _to_digits("WORD", 16)
DWORD_TO_BINSTR = _to_digits("DWORD", 2)
DWORD_TO_OCTSTR = _to_digits("DWORD", 8)
DWORD_TO_DECSTR = _to_digits("DWORD", 10)
DWORD_TO_HEXSTR = _to_digits("DWORD", 16)
LWORD_TO_BINSTR = _to_digits("LWORD", 2)
LWORD_TO_OCTSTR = _to_digits("LWORD", 8)
LWORD_TO_DECSTR = _to_digits("LWORD", 10)
LWORD_TO_HEXSTR = _to_digits("LWORD", 16)


# --- time ---------------------------------------------------------------------------------------


class TIMESTRUCT(Struct):
    """``TIMESTRUCT``: a date and time in fields (Windows' SYSTEMTIME); wDayOfWeek 0 is Sunday."""

    wYear: WORD = 0
    wMonth: WORD = 0
    wDayOfWeek: WORD = 0
    wDay: WORD = 0
    wHour: WORD = 0
    wMinute: WORD = 0
    wSecond: WORD = 0
    wMilliseconds: WORD = 0


class T_FILETIME(Struct):  # noqa: N801 - the ST name
    """``T_FILETIME``: 100 ns intervals since 1601-01-01, in two DWORDs."""

    dwLowDateTime: DWORD = 0
    dwHighDateTime: DWORD = 0


class E_TimeZoneID(IecEnum):  # noqa: N801 - the ST name
    """``E_TimeZoneID``: which time zone rule FB_LocalSystemTime's time follows."""

    eTimeZoneID_Invalid = -1
    eTimeZoneID_Unknown = 0
    eTimeZoneID_Standard = 1
    eTimeZoneID_Daylight = 2


_EPOCH = datetime.datetime(1970, 1, 1)
_FILETIME_EPOCH = datetime.datetime(1601, 1, 1)


def _timestruct(moment: datetime.datetime) -> TIMESTRUCT:
    return TIMESTRUCT(
        wYear=moment.year, wMonth=moment.month, wDayOfWeek=(moment.weekday() + 1) % 7, wDay=moment.day,
        wHour=moment.hour, wMinute=moment.minute, wSecond=moment.second, wMilliseconds=moment.microsecond // 1000,
    )


def _moment(value: TIMESTRUCT) -> datetime.datetime | None:
    try:
        return datetime.datetime(
            value.wYear, value.wMonth, value.wDay, value.wHour, value.wMinute, value.wSecond, value.wMilliseconds * 1000
        )
    except ValueError:
        return None


def DT_TO_SYSTEMTIME(DTIN: DT) -> TIMESTRUCT:  # noqa: N802, N803 - the ST names
    """``DT_TO_SYSTEMTIME(DTIN)``: a DT (seconds since 1970) as a TIMESTRUCT (milliseconds 0)."""
    return _timestruct(_EPOCH + datetime.timedelta(seconds=int(DTIN)))


def SYSTEMTIME_TO_DT(TIMESTR: TIMESTRUCT) -> DT:  # noqa: N802, N803 - the ST names
    """``SYSTEMTIME_TO_DT(TIMESTR)``: a TIMESTRUCT as a DT; milliseconds are dropped, an invalid date is DT#1970-01-01-00:00."""
    moment = _moment(TIMESTR)
    if moment is None or moment < _EPOCH:
        return 0
    return int((moment - _EPOCH).total_seconds()) & 0xFFFF_FFFF


def SYSTEMTIME_TO_STRING(in_: TIMESTRUCT) -> STRING:  # noqa: N802 - the ST name
    """``SYSTEMTIME_TO_STRING(in)``: 'YYYY-MM-DD-hh:mm:ss.xxx'."""
    return (
        f"{in_.wYear:04d}-{in_.wMonth:02d}-{in_.wDay:02d}-"
        f"{in_.wHour:02d}:{in_.wMinute:02d}:{in_.wSecond:02d}.{in_.wMilliseconds:03d}"
    )


def FILETIME_TO_SYSTEMTIME(fileTime: T_FILETIME) -> TIMESTRUCT:  # noqa: N802, N803 - the ST names
    """``FILETIME_TO_SYSTEMTIME(fileTime)``: a T_FILETIME as a TIMESTRUCT."""
    ticks = (fileTime.dwHighDateTime << 32) | fileTime.dwLowDateTime
    return _timestruct(_FILETIME_EPOCH + datetime.timedelta(microseconds=ticks // 10))


def SYSTEMTIME_TO_FILETIME(systemTime: TIMESTRUCT) -> T_FILETIME:  # noqa: N802, N803 - the ST names
    """``SYSTEMTIME_TO_FILETIME(systemTime)``: a TIMESTRUCT as a T_FILETIME (an invalid date: 0)."""
    moment = _moment(systemTime)
    ticks = 0 if moment is None else (moment - _FILETIME_EPOCH) // datetime.timedelta(microseconds=1) * 10
    return T_FILETIME(dwLowDateTime=ticks & 0xFFFF_FFFF, dwHighDateTime=ticks >> 32)


def F_YearIsLeapYear(wYear: WORD) -> BOOL:  # noqa: N802, N803 - the ST names
    """``F_YearIsLeapYear(wYear)``: whether wYear is a leap year of the Gregorian calendar."""
    return wYear % 4 == 0 and (wYear % 100 != 0 or wYear % 400 == 0)


def F_GetMaxMonthDays(wYear: WORD, wMonth: WORD) -> WORD:  # noqa: N802, N803 - the ST names
    """``F_GetMaxMonthDays(wYear, wMonth)``: the days of month wMonth (1..12) of wYear; 0 for another wMonth."""
    if not 1 <= wMonth <= 12:
        return 0
    if wMonth == 2:
        return 29 if F_YearIsLeapYear(wYear) else 28
    return 30 if wMonth in (4, 6, 9, 11) else 31


def F_GetDOYOfYearMonthDay(wYear: WORD, wMonth: WORD, wDay: WORD) -> WORD:  # noqa: N802, N803 - the ST names
    """``F_GetDOYOfYearMonthDay(wYear, wMonth, wDay)``: the day of the year (1..366); 0 for a date that does not exist."""
    if not 1 <= wDay <= F_GetMaxMonthDays(wYear, wMonth):
        return 0
    return sum(F_GetMaxMonthDays(wYear, month) for month in range(1, wMonth)) + wDay


#: FILETIME's ticks (100 ns since 1601-01-01) at DT#1970-01-01-00:00, where DT counts from.
_DT_ZERO_TICKS = 116_444_736_000_000_000


def FILETIME_TO_DT(fileTime: T_FILETIME) -> DT:  # noqa: N802, N803 - the ST names
    """``FILETIME_TO_DT(fileTime)``: a T_FILETIME as a DT (whole seconds); a time before 1970 is DT#1970-01-01-00:00."""
    ticks = (fileTime.dwHighDateTime << 32) | fileTime.dwLowDateTime
    return max(0, (ticks - _DT_ZERO_TICKS) // 10_000_000) & 0xFFFF_FFFF


def DT_TO_FILETIME(DTIN: DT) -> T_FILETIME:  # noqa: N802, N803 - the ST names
    """``DT_TO_FILETIME(DTIN)``: a DT as a T_FILETIME."""
    ticks = int(DTIN) * 10_000_000 + _DT_ZERO_TICKS
    return T_FILETIME(dwLowDateTime=ticks & 0xFFFF_FFFF, dwHighDateTime=ticks >> 32)


#: ``TYPE T_FILETIME64 : ULINT``: a FILETIME in one 64-bit number.
T_FILETIME64 = Annotated[ULINT, Alias("T_FILETIME64")]


def FILETIME64_TO_SYSTEMTIME(in_: T_FILETIME64) -> TIMESTRUCT:  # noqa: N802 - the ST name
    """``FILETIME64_TO_SYSTEMTIME(in)``: a T_FILETIME64 as a TIMESTRUCT."""
    return FILETIME_TO_SYSTEMTIME(T_FILETIME(dwLowDateTime=in_ & 0xFFFF_FFFF, dwHighDateTime=in_ >> 32))


def SYSTEMTIME_TO_FILETIME64(in_: TIMESTRUCT) -> T_FILETIME64:  # noqa: N802 - the ST name
    """``SYSTEMTIME_TO_FILETIME64(in)``: a TIMESTRUCT as a T_FILETIME64 (an invalid date: 0)."""
    filetime = SYSTEMTIME_TO_FILETIME(in_)
    return (filetime.dwHighDateTime << 32) | filetime.dwLowDateTime


def _now() -> TIMESTRUCT:
    return _timestruct(_FILETIME_EPOCH + datetime.timedelta(microseconds=filetime_now() // 10))


class NT_GetTime(FunctionBlock):  # noqa: N801 - the ST name
    """``NT_GetTime``: read the local time of the system; an ADS request, busy for one call.

    ST: ``VAR_INPUT NETID : T_AmsNetId; START : BOOL; TMOUT : TIME; END_VAR
    VAR_OUTPUT BUSY : BOOL; ERR : BOOL; ERRID : UDINT; TIMESTR : TIMESTRUCT; END_VAR``.
    A rising edge of START sets BUSY; the next call sets TIMESTR (the task
    clock, see the module) and drops BUSY.
    """

    NETID: T_AmsNetId = VAR_INPUT("")
    START: BOOL = VAR_INPUT(False)
    TMOUT: TIME = VAR_INPUT(DEFAULT_ADS_TIMEOUT)
    BUSY: BOOL = VAR_OUTPUT(False)
    ERR: BOOL = VAR_OUTPUT(False)
    ERRID: UDINT = VAR_OUTPUT(0)
    TIMESTR: TIMESTRUCT = VAR_OUTPUT()
    PREV_START: BOOL = VAR(False)

    def body(self) -> None:
        if self.BUSY:
            self.BUSY = False
            self.TIMESTR = _now()
        elif self.START and not self.PREV_START:
            self.BUSY, self.ERR, self.ERRID = True, False, 0
        self.PREV_START = self.START


class FB_LocalSystemTime(FunctionBlock):  # noqa: N801 - the ST name
    """``FB_LocalSystemTime``: the local time, kept current every call while bEnable is TRUE.

    ST: ``VAR_INPUT sNetID : T_AmsNetId; bEnable : BOOL; dwCycle : DWORD := 5; dwOpt : DWORD := 1;
    tTimeout : TIME; END_VAR  VAR_OUTPUT bValid : BOOL; systemTime : TIMESTRUCT; tzID : E_TimeZoneID; END_VAR``.
    The first synchronisation takes one call (bValid FALSE); after it,
    systemTime is the task clock at every call. The local time is UTC here,
    so tzID is eTimeZoneID_Unknown.
    """

    sNetID: T_AmsNetId = VAR_INPUT("")
    bEnable: BOOL = VAR_INPUT(False)
    dwCycle: DWORD = VAR_INPUT(5)
    dwOpt: DWORD = VAR_INPUT(1)
    tTimeout: TIME = VAR_INPUT(DEFAULT_ADS_TIMEOUT)
    bValid: BOOL = VAR_OUTPUT(False)
    systemTime: TIMESTRUCT = VAR_OUTPUT()
    tzID: E_TimeZoneID = VAR_OUTPUT(E_TimeZoneID.eTimeZoneID_Unknown)
    SYNCING: BOOL = VAR(False)

    def body(self) -> None:
        if not self.bEnable:
            self.SYNCING = False
            self.bValid = False
            return
        if self.bValid or self.SYNCING:
            self.bValid, self.SYNCING = True, False
            self.systemTime = _now()
        else:
            self.SYNCING = True


# --- FB_MemRingBuffer ---------------------------------------------------------------------------

_HEADER = 4  # each entry is stored as its UDINT byte length, then its bytes


def LEN2(pSTRING: Pointer[Any]) -> UDINT:  # noqa: N802, N803 - the ST names
    """``LEN2(pSTRING)``: the number of characters of the STRING at pSTRING, counted to its 0 (any length)."""
    return len(c_string(pSTRING, "pSTRING", "LEN2"))


def WLEN2(pWSTRING: Pointer[Any]) -> UDINT:  # noqa: N802, N803 - the ST names
    """``WLEN2(pWSTRING)``: the number of characters of the WSTRING at pWSTRING, counted to its 0."""
    return len(c_string(pWSTRING, "pWSTRING", "WLEN2", 2)) // 2


def WSTRING_TO_STRING2(pDstString: Pointer[Any], pSrcWString: Pointer[Any], nDstSize: UDINT) -> BOOL:  # noqa: N802, N803
    """``WSTRING_TO_STRING2(pDstString, pSrcWString, nDstSize)``: the WSTRING as a STRING into nDstSize bytes (its
    0 included); characters a STRING cannot hold are left out. FALSE when the result was cut to fit."""
    text = c_string(pSrcWString, "pSrcWString", "WSTRING_TO_STRING2", 2).decode("utf-16-le", errors="ignore")
    if not pDstString:
        raise PlcException(ExceptionCode.RTSEXCPT_ACCESS_VIOLATION, "WSTRING_TO_STRING2: pDstString is a null pointer")
    return put_c_string(pDstString, text.encode("latin-1", errors="ignore"), nDstSize, 1)


def STRING_TO_WSTRING2(pDstWSTRING: Pointer[Any], pSrcSTRING: Pointer[Any], nDstSize: UDINT) -> BOOL:  # noqa: N802, N803
    """``STRING_TO_WSTRING2(pDstWSTRING, pSrcSTRING, nDstSize)``: the STRING as a WSTRING into nDstSize bytes (its
    0 included). FALSE when the result was cut to fit."""
    text = c_string(pSrcSTRING, "pSrcSTRING", "STRING_TO_WSTRING2").decode("latin-1")
    if not pDstWSTRING:
        raise PlcException(ExceptionCode.RTSEXCPT_ACCESS_VIOLATION, "STRING_TO_WSTRING2: pDstWSTRING is a null pointer")
    return put_c_string(pDstWSTRING, text.encode("utf-16-le"), nDstSize, 2)


def FindAndReplace(  # noqa: N802 - the ST name
    pSrcString: Pointer[Any], pDeleteString: Pointer[Any] | None = None, pInsertString: Pointer[Any] | None = None,  # noqa: N803
    pDstString: Pointer[Any] | None = None, nDstSize: UDINT = 0, *, pSrcFindString: Pointer[Any] | None = None,  # noqa: N803
    pSrcReplaceWithString: Pointer[Any] | None = None, cbDstString: UDINT = 0,  # noqa: N803
) -> UDINT:
    """``FindAndReplace(pSrcString, pDeleteString, pInsertString, pDstString, nDstSize)``: every *pDeleteString in
    *pSrcString replaced by *pInsertString, into *pDstString (nDstSize bytes, its terminator included); the count.

    The strings are read to their terminating 0, as the PLC's pointers are. ``pSrcFindString``,
    ``pSrcReplaceWithString`` and ``cbDstString`` are the names earlier Tc2_Utilities versions give the same inputs.
    """
    find = pDeleteString if pDeleteString is not None else pSrcFindString
    insert = pInsertString if pInsertString is not None else pSrcReplaceWithString
    size = nDstSize or cbDstString
    if find is None or insert is None or pDstString is None:
        raise PlcException(ExceptionCode.RTSEXCPT_ACCESS_VIOLATION, "FindAndReplace: a string pointer is missing")
    source, old, new = c_string(pSrcString, "pSrcString"), c_string(find, "pDeleteString"), c_string(insert, "pInsertString")
    count = source.count(old) if old else 0
    result = source.replace(old, new) if count else source
    result = result[: max(0, int(size) - 1)]
    target = pDstString.typed(BYTE)
    for index, value in enumerate(result + b"\x00"):
        (target + index).deref = value
    return count


class _RingBuffer(FunctionBlock, abstract=True):
    """The record ring of FB_MemRingBuffer and FB_StringRingBuffer: each record its UDINT length, then its bytes,
    in the caller's buffer (pBuffer, cbBuffer); nCount records of cbSize bytes in all."""

    idxFirst: UDINT = VAR(0)
    idxLast: UDINT = VAR(0)
    if TYPE_CHECKING:  # declared by each block, in the order of its ST declaration
        pBuffer: Pointer[Any]
        cbBuffer: int
        nCount: int
        cbSize: int

    def _head(self, remove: bool) -> None:
        """The oldest record handed out (each block its own way), and removed when ``remove``."""
        raise NotImplementedError

    @method
    def A_GetHead(self) -> None:  # noqa: N802 - the ST name
        """The oldest record read out (FB_MemRingBuffer: to pRead; FB_StringRingBuffer: into getValue), kept."""
        self._head(remove=False)

    @method
    def A_RemoveHead(self) -> None:  # noqa: N802 - the ST name
        """The oldest record read out as A_GetHead does, and removed."""
        self._head(remove=True)

    def _byte(self, index: int) -> Any:
        return self.pBuffer.typed(BYTE) + index % self.cbBuffer

    def _put(self, data: bytes) -> bool:
        """``data`` appended as a record; FALSE when it does not fit."""
        need = _HEADER + len(data)
        if not self.pBuffer or not self.cbBuffer or self.cbSize + need > self.cbBuffer:
            return False
        for i, value in enumerate(len(data).to_bytes(4, "little") + data):
            self._byte(self.idxLast + i).deref = value
        self.idxLast = (self.idxLast + need) % self.cbBuffer
        self.nCount += 1
        self.cbSize += need
        return True

    def _first(self) -> bytes | None:
        """The oldest record's bytes, or None when there is none."""
        if not self.nCount or not self.pBuffer or not self.cbBuffer:
            return None
        size = int.from_bytes(bytes(self._byte(self.idxFirst + i).deref for i in range(_HEADER)), "little")
        return bytes(self._byte(self.idxFirst + _HEADER + i).deref for i in range(size))

    def _drop(self, size: int) -> None:
        """The oldest record, of ``size`` bytes, removed."""
        self.idxFirst = (self.idxFirst + _HEADER + size) % self.cbBuffer
        self.nCount -= 1
        self.cbSize -= _HEADER + size
        if not self.nCount:
            self.idxFirst = self.idxLast = 0


class FB_MemRingBuffer(_RingBuffer):  # noqa: N801 - the ST name
    """``FB_MemRingBuffer``: a FIFO of byte records of any length in a buffer the caller gives.

    ST: ``VAR_INPUT pWrite : PVOID; cbWrite : UDINT; pRead : PVOID; cbRead : UDINT;
    pBuffer : PVOID; cbBuffer : UDINT; END_VAR  VAR_OUTPUT bOk : BOOL; nCount : UDINT;
    cbSize : UDINT; cbReturn : UDINT; END_VAR`` and the actions A_AddTail,
    A_RemoveHead, A_GetHead, A_Reset (methods here: set the inputs, then call
    ``buffer.A_AddTail()``). Each entry takes 4 bytes (its length) plus its
    data in the buffer. bOk FALSE: the buffer is full (A_AddTail) or empty;
    with cbReturn > 0 it says pRead's cbRead bytes are too few for the entry,
    whose size cbReturn is.
    """

    pWrite: Pointer[Any] = VAR_INPUT()
    cbWrite: UDINT = VAR_INPUT(0)
    pRead: Pointer[Any] = VAR_INPUT()
    cbRead: UDINT = VAR_INPUT(0)
    pBuffer: Pointer[Any] = VAR_INPUT()
    cbBuffer: UDINT = VAR_INPUT(0)
    bOk: BOOL = VAR_OUTPUT(False)
    nCount: UDINT = VAR_OUTPUT(0)
    cbSize: UDINT = VAR_OUTPUT(0)
    cbReturn: UDINT = VAR_OUTPUT(0)

    def body(self) -> None:
        """Calling the block itself changes nothing; its actions do the work."""

    @method
    def A_AddTail(self) -> None:  # noqa: N802 - the ST name
        """Append cbWrite bytes from pWrite; bOk FALSE when they do not fit."""
        self.cbReturn = 0
        if self.cbWrite and not self.pWrite:
            self.bOk = False
            return
        source = self.pWrite.typed(BYTE) if self.cbWrite else None
        self.bOk = self._put(bytes((source + i).deref for i in range(self.cbWrite)) if source is not None else b"")

    def _head(self, remove: bool) -> None:
        self.cbReturn = 0
        data = self._first()
        if data is None:
            self.bOk = False
            return
        size = len(data)
        if size > self.cbRead or (size and not self.pRead):
            self.bOk, self.cbReturn = False, size
            return
        target = self.pRead.typed(BYTE) if size else None
        for i, value in enumerate(data):
            assert target is not None
            (target + i).deref = value
        self.cbReturn = size
        self.bOk = True
        if remove:
            self._drop(size)

    @method
    def A_Reset(self) -> None:  # noqa: N802 - the ST name
        """Empty the buffer."""
        self.idxFirst = self.idxLast = self.nCount = self.cbSize = self.cbReturn = 0
        self.bOk = True


class FB_StringRingBuffer(_RingBuffer):  # noqa: N801 - the ST name
    """``FB_StringRingBuffer``: a FIFO of STRINGs in a buffer the caller gives, kept as FB_MemRingBuffer keeps its
    records (each its 4-byte length, then the string and its 0).

    ST: ``VAR_INPUT bOverwrite : BOOL; putValue : T_MaxString; pBuffer : POINTER TO BYTE; cbBuffer : UDINT;
    END_VAR  VAR_OUTPUT bOk : BOOL; getValue : T_MaxString; nCount : UDINT; cbSize : UDINT; END_VAR`` and the
    actions A_AddTail (putValue), A_GetHead / A_RemoveHead (into getValue), A_Reset. bOk FALSE: the buffer is
    full (with bOverwrite the oldest strings make room instead) or empty.
    """

    bOverwrite: BOOL = VAR_INPUT(False)
    putValue: T_MaxString = VAR_INPUT("")
    pBuffer: Pointer[Any] = VAR_INPUT()
    cbBuffer: UDINT = VAR_INPUT(0)
    bOk: BOOL = VAR_OUTPUT(False)
    getValue: T_MaxString = VAR_OUTPUT("")
    nCount: UDINT = VAR_OUTPUT(0)
    cbSize: UDINT = VAR_OUTPUT(0)

    def body(self) -> None:
        """Calling the block itself changes nothing; its actions do the work."""

    @method
    def A_AddTail(self) -> None:  # noqa: N802 - the ST name
        """Append putValue; with bOverwrite the oldest strings are removed until it fits."""
        data = self.putValue.encode("latin-1", errors="replace") + b"\x00"
        fits = self.cbBuffer and _HEADER + len(data) <= self.cbBuffer
        while self.bOverwrite and fits and self.nCount and self.cbSize + _HEADER + len(data) > self.cbBuffer:
            head = self._first()
            assert head is not None
            self._drop(len(head))
        self.bOk = self._put(data)

    def _head(self, remove: bool) -> None:
        data = self._first()
        self.bOk = data is not None
        if data is not None:
            self.getValue = data.split(b"\x00", 1)[0].decode("latin-1")
            if remove:
                self._drop(len(data))

    @method
    def A_Reset(self) -> None:  # noqa: N802 - the ST name
        """Empty the buffer."""
        self.idxFirst = self.idxLast = self.nCount = self.cbSize = 0
        self.bOk = True

