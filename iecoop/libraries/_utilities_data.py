"""Tc2_Utilities' string and data functions that work through pointers or on raw bytes: CONCAT2, DELETE2,
DATA_TO_HEXSTR, HEXSTR_TO_DATA, ARG_TO_CSVFIELD, CSVFIELD_TO_ARG, BYTEARR_TO_MAXSTRING, and the number
formatting DINT_TO_DECSTR, DEG_TO_RAD, RAD_TO_DEG (Infosys, "TwinCAT 3 PLC Lib: Tc2_Utilities").

>>> from iecoop import STRING, Struct, VAR, adr
>>> class Log(Struct):
...     source: STRING = VAR("Pump", length=20)
...     text: STRING = VAR(": level low", length=20)
...     line: STRING = VAR(length=12)
>>> log = Log()
>>> CONCAT2(adr(log, "source"), adr(log, "text"), adr(log, "line"), 13), log.line
(False, 'Pump: level ')
>>> DINT_TO_DECSTR(-1234, 10)
'-0000001234'
"""

from __future__ import annotations

import math
from typing import Any

from iecoop.exceptions import ExceptionCode, PlcException
from iecoop.libraries._cstrings import c_string, put_c_string
from iecoop.libraries.tc2_system import MAX_STRING_LENGTH, T_MaxString
from iecoop.memory import Pointer
from iecoop.types import BOOL, BYTE, DINT, INT, LREAL, UDINT

__all__ = [
    "ARG_TO_CSVFIELD", "BYTEARR_TO_MAXSTRING", "CONCAT2", "CSVFIELD_TO_ARG", "DATA_TO_HEXSTR", "DEG_TO_RAD",
    "DELETE2", "DINT_TO_DECSTR", "HEXSTR_TO_DATA", "RAD_TO_DEG",
]

#: DATA_TO_HEXSTR converts at most this many bytes: two digits and a blank each fill a T_MaxString.
MAX_HEX_BYTES = 85
# ``in`` / ``out`` of ARG_TO_CSVFIELD / CSVFIELD_TO_ARG are T_Arg, typed Any: tc2_utilities, which declares
# T_Arg, imports this module.
#: ARGTYPE_STRING of E_ArgType: a T_Arg whose data is a STRING (cbLen its length + 1).
_ARGTYPE_STRING = 12


def _needed(pointer: Pointer[Any], what: str, function: str) -> Pointer[Any]:
    if not pointer:
        raise PlcException(ExceptionCode.RTSEXCPT_ACCESS_VIOLATION, f"{function}: {what} is a null pointer")
    return pointer


def _read(pointer: Pointer[Any], size: int) -> bytes:
    at = pointer.typed(BYTE)
    return bytes((at + index).deref for index in range(max(0, int(size))))


def _write(pointer: Pointer[Any], data: bytes) -> None:
    at = pointer.typed(BYTE)
    for index, value in enumerate(data):
        (at + index).deref = value


def CONCAT2(pSrcString1: Pointer[Any], pSrcString2: Pointer[Any], pDstString: Pointer[Any],  # noqa: N802, N803
            nDstSize: UDINT) -> BOOL:
    """``CONCAT2(pSrcString1, pSrcString2, pDstString, nDstSize)``: the two STRINGs, of any length, one after the
    other into nDstSize bytes (its 0 included); FALSE when the result was cut to fit."""
    first = c_string(pSrcString1, "pSrcString1", "CONCAT2")
    second = c_string(pSrcString2, "pSrcString2", "CONCAT2")
    return put_c_string(_needed(pDstString, "pDstString", "CONCAT2"), first + second, nDstSize, 1)


def DELETE2(pSrcString: Pointer[Any], pDstString: Pointer[Any], nDstSize: UDINT, nLen: UDINT,  # noqa: N802, N803
            nPos: UDINT) -> BOOL:
    """``DELETE2(pSrcString, pDstString, nDstSize, nLen, nPos)``: the STRING without nLen characters from nPos (1
    is the first) into nDstSize bytes; FALSE when the result was cut to fit. A position before the first
    character or past the last removes nothing."""
    source = c_string(pSrcString, "pSrcString", "DELETE2")
    start = int(nPos) - 1
    result = source[:start] + source[start + int(nLen):] if 0 <= start < len(source) else source
    return put_c_string(_needed(pDstString, "pDstString", "DELETE2"), result, nDstSize, 1)


def DINT_TO_DECSTR(in_: DINT, iPrecision: INT) -> T_MaxString:  # noqa: N802, N803 - the ST names
    """``DINT_TO_DECSTR(in, iPrecision)``: ``in`` in decimal, zero-filled to iPrecision digits (never cut), a negative
    one with its ``-`` before the zeros; 0 with iPrecision 0 is ``''``."""
    if in_ == 0 and iPrecision <= 0:
        return ""
    digits = str(abs(int(in_))).rjust(max(0, int(iPrecision)), "0")
    return "-" + digits if in_ < 0 else digits


def DEG_TO_RAD(ANGLE: LREAL) -> LREAL:  # noqa: N802, N803 - the ST names
    """``DEG_TO_RAD(ANGLE)``: an angle in degrees, in radians."""
    return ANGLE * math.pi / 180.0


def RAD_TO_DEG(ANGLE: LREAL) -> LREAL:  # noqa: N802, N803 - the ST names
    """``RAD_TO_DEG(ANGLE)``: an angle in radians, in degrees."""
    return ANGLE * 180.0 / math.pi


def BYTEARR_TO_MAXSTRING(in_: Any) -> T_MaxString:  # noqa: N802 - the ST name
    """``BYTEARR_TO_MAXSTRING(in)``: the ASCII codes of ``in : ARRAY[0..255] OF BYTE`` as a STRING, to the first 0."""
    text = bytearray()
    for index in range(MAX_STRING_LENGTH):
        value = int(in_[index])
        if value == 0:
            break
        text.append(value)
    return text.decode("latin-1")


def DATA_TO_HEXSTR(pData: Pointer[Any], cbData: UDINT, bLoCase: BOOL = False) -> T_MaxString:  # noqa: N802, N803
    """``DATA_TO_HEXSTR(pData, cbData, bLoCase)``: cbData bytes at pData in hexadecimal, two digits a byte, blanks
    between them (lower-case digits with bLoCase). More than 85 bytes: the first 85 and a ``.``; no data: ``''``."""
    if not pData or cbData == 0:
        return ""
    data = _read(pData, min(int(cbData), MAX_HEX_BYTES))
    text = " ".join(format(byte, "02x" if bLoCase else "02X") for byte in data)
    return text + "." if cbData > MAX_HEX_BYTES else text


def HEXSTR_TO_DATA(sHex: T_MaxString, pData: Pointer[Any], cbData: UDINT) -> UDINT:  # noqa: N802, N803
    """``HEXSTR_TO_DATA(sHex, pData, cbData)``: the bytes the hexadecimal string spells (pairs of digits, blanks
    between them allowed) written at pData, at most cbData; their number, 0 at a character that is neither."""
    data = bytearray()
    for word in sHex.split(" "):
        if len(word) % 2 or any(c not in "0123456789abcdefABCDEF" for c in word):
            return 0
        data += bytes.fromhex(word)
    data = data[: int(cbData)]
    if data:
        _write(_needed(pData, "pData", "HEXSTR_TO_DATA"), bytes(data))
    return len(data)


def _arg_data(arg: Any) -> bytes:
    """The bytes a T_Arg points to: a STRING's characters (to its 0), any other type's cbLen bytes."""
    if not arg.pData or arg.cbLen == 0:
        return b""
    data = _read(arg.pData, arg.cbLen)
    return data.split(b"\x00", 1)[0] if int(arg.eType) == _ARGTYPE_STRING else data


def ARG_TO_CSVFIELD(in_: Any, bQM: BOOL, pOutput: Pointer[Any], cbOutput: UDINT) -> UDINT:  # noqa: N802, N803
    """``ARG_TO_CSVFIELD(in, bQM, pOutput, cbOutput)``: the data ``in`` points to as a CSV field at pOutput (each ``"``
    doubled, enclosed in ``"`` with bQM, no 0 after it); its length, 0 with no data or when cbOutput is too small."""
    data = _arg_data(in_)
    if not data:
        return 0
    field = data.replace(b'"', b'""')
    field = b'"' + field + b'"' if bQM else field
    if len(field) > cbOutput:
        return 0
    _write(_needed(pOutput, "pOutput", "ARG_TO_CSVFIELD"), field)
    return len(field)


def CSVFIELD_TO_ARG(pInput: Pointer[Any], cbInput: UDINT, bQM: BOOL, out: Any) -> UDINT:  # noqa: N802, N803
    """``CSVFIELD_TO_ARG(pInput, cbInput, bQM, out)``: the CSV field of cbInput bytes at pInput written where ``out``
    points (each ``""`` one ``"``, the enclosing ``"`` removed with bQM; a STRING gets its 0); the length of the value,
    0 with no input, a field bQM finds unenclosed, a ``"`` not doubled, or a value longer than out.cbLen."""
    if cbInput == 0:
        return 0
    body = _read(_needed(pInput, "pInput", "CSVFIELD_TO_ARG"), cbInput)
    if bQM:
        if len(body) < 2 or body[:1] != b'"' or body[-1:] != b'"':
            return 0
        body = body[1:-1]
    if body.replace(b'""', b"").count(b'"'):
        return 0
    value = body.replace(b'""', b'"')
    text = int(out.eType) == _ARGTYPE_STRING
    if not out.pData or len(value) + (1 if text else 0) > out.cbLen:
        return 0
    _write(out.pData, value + (b"\x00" if text else b""))
    return len(value)
