"""The format engine behind Tc2_Utilities' FB_FormatString / F_FormatArgToStr and Tc2_System's ADSLOG functions.

Beckhoff documents one format specification for all of them (Infosys,
Tc2_Utilities "Format specification"): ``%[flags][width][.precision]type``,
printf-like, with its own error codes (Infosys, Tc2_Utilities "Format error
codes"): each is a class code plus the number of the argument being formatted.

``render(text, args)`` takes the arguments as ``Arg`` records (their ST type
and value) and returns the formatted text, or raises ``FormatError`` with that
code. The type letters and which argument types each accepts:

==========  =========================================================  ======================
type        argument                                                   output
==========  =========================================================  ======================
d i         an integer type                                            signed decimal
u           an integer type                                            unsigned decimal
b B o O     an integer type, REAL (its bit pattern)                    binary / octal
x X         an integer type, REAL (its bit pattern)                    hexadecimal
c C         BYTE, USINT                                                one character
f F         REAL, LREAL                                                [-]dddd.dddd
e E         REAL, LREAL                                                [-]d.dddde[sign]ddd
s S         STRING (BOOL: TRUE / FALSE)                                the text
==========  =========================================================  ======================

A negative integer printed unsigned (``u b o x``) is its two's complement in
the argument's width, as the PLC stores it.
"""

from __future__ import annotations

import dataclasses
import math
import struct

__all__ = [
    "Arg", "FMT_ERR_ARGTYPE", "FMT_ERR_ASTERISK", "FMT_ERR_DOT", "FMT_ERR_FLAG", "FMT_ERR_OVERFLOW",
    "FMT_ERR_PARAMS", "FMT_ERR_PERCENT", "FMT_ERR_PRECISION", "FMT_ERR_TOO_MANY", "FMT_ERR_TYPE",
    "FMT_ERR_WIDTH", "FMT_ERR_WIDTH_POSITION", "FormatError", "render",
]

# Beckhoff's format error classes; the code reported is the class plus the argument number.
FMT_ERR_PERCENT = 0x10  #: percent sign (%) at invalid position
FMT_ERR_ASTERISK = 0x20  #: asterisk parameter at invalid position
FMT_ERR_WIDTH = 0x40  #: invalid width field value
FMT_ERR_PRECISION = 0x80  #: invalid precision field value
FMT_ERR_FLAG = 0x100  #: one of the flags at invalid position
FMT_ERR_WIDTH_POSITION = 0x200  #: the width or precision field value at invalid position
FMT_ERR_DOT = 0x400  #: dot of the precision field at invalid position
FMT_ERR_TYPE = 0x800  #: invalid (unsupported) type field value
FMT_ERR_ARGTYPE = 0x1000  #: type field and argument type differ
FMT_ERR_PARAMS = 0x2000  #: invalid format string parameters
FMT_ERR_TOO_MANY = 0x4000  #: more format fields than arguments
FMT_ERR_OVERFLOW = 0x8000  #: the formatted string is longer than the destination

_INTEGERS = {
    "BYTE": (8, False), "WORD": (16, False), "DWORD": (32, False), "LWORD": (64, False),
    "SINT": (8, True), "INT": (16, True), "DINT": (32, True), "LINT": (64, True),
    "USINT": (8, False), "UINT": (16, False), "UDINT": (32, False), "ULINT": (64, False),
}
_REALS = ("REAL", "LREAL")
_FLAGS = "-+0 #"
_MAX_FIELD = 255


class FormatError(Exception):
    """A format error: ``code`` is Beckhoff's format error code (class + argument number)."""

    def __init__(self, code: int, reason: str) -> None:
        super().__init__(f"format error 16#{code:08X}: {reason}")
        self.code = code


@dataclasses.dataclass(frozen=True)
class Arg:
    """One argument: its ST type name (``"INT"``, ``"LREAL"``, ``"STRING"``...) and its value."""

    type_name: str
    value: object


@dataclasses.dataclass
class _Field:
    flags: str = ""
    width: int | None = None
    precision: int | None = None
    type_: str = ""


def _parse(fmt: str, i: int, number: int) -> tuple[_Field, int]:
    """The field whose flags start at ``i`` (after its ``%``), and the index after its type letter."""
    field = _Field()
    n = len(fmt)
    while i < n and fmt[i] in _FLAGS:
        field.flags += fmt[i]
        i += 1
    field.width, i = _number(fmt, i, number, FMT_ERR_WIDTH, "width")
    if i < n and fmt[i] == ".":
        precision, i = _number(fmt, i + 1, number, FMT_ERR_PRECISION, "precision")
        field.precision = precision or 0  # '%.f' is precision 0, as in C
    if i >= n:
        raise FormatError(FMT_ERR_PERCENT + number, "a format field without a type at the end of the format")
    ch = fmt[i]
    if ch in _FLAGS and not ch.isdigit():
        raise FormatError(FMT_ERR_FLAG + number, f"flag {ch!r} after the width or precision")
    if ch == ".":
        raise FormatError(FMT_ERR_DOT + number, "a second '.' in one field")
    if ch == "%":
        raise FormatError(FMT_ERR_PERCENT + number, "'%' inside a format field")
    field.type_ = ch
    return field, i + 1


def _number(fmt: str, i: int, number: int, error: int, what: str) -> tuple[int | None, int]:
    """The width or precision digits at ``i`` (None when there are none) and the index after them."""
    if i < len(fmt) and fmt[i] == "*":
        raise FormatError(FMT_ERR_ASTERISK + number, f"'*' {what} is not supported")
    j = i
    while j < len(fmt) and fmt[j].isdigit():
        j += 1
    if j == i:
        return None, i
    value = int(fmt[i:j])
    if value > _MAX_FIELD:
        raise FormatError(error + number, f"{what} {value} is over {_MAX_FIELD}")
    return value, j


def _pad(field: _Field, sign: str, body: str, zero_ok: bool) -> str:
    width = field.width or 0
    size = len(sign) + len(body)
    if size >= width:
        return sign + body
    if "-" in field.flags:
        return sign + body + " " * (width - size)
    if "0" in field.flags and zero_ok:
        return sign + "0" * (width - size) + body
    return " " * (width - size) + sign + body


def _sign(field: _Field, negative: bool) -> str:
    if negative:
        return "-"
    if "+" in field.flags:
        return "+"
    return " " if " " in field.flags else ""


def _integer(field: _Field, arg: Arg, number: int) -> str:
    type_ = field.type_.lower()
    value = arg.value
    if arg.type_name == "REAL" and type_ in "box":
        value, bits, signed = struct.unpack("<I", struct.pack("<f", float(value)))[0], 32, False  # type: ignore[arg-type]
    elif arg.type_name in _INTEGERS:
        bits, signed = _INTEGERS[arg.type_name]
    else:
        raise FormatError(FMT_ERR_ARGTYPE + number, f"%{field.type_} does not take a {arg.type_name} argument")
    assert isinstance(value, int)
    negative = False
    if type_ in "di":
        negative = signed and value < 0
        magnitude = abs(value)
        sign = _sign(field, negative)
    else:
        magnitude = value & ((1 << bits) - 1)
        sign = ""
    base = {"d": 10, "i": 10, "u": 10, "b": 2, "o": 8, "x": 16}[type_]
    digits = "" if magnitude == 0 and field.precision == 0 else _digits(magnitude, base)
    if field.type_ == "X":
        digits = digits.upper()
    if field.precision is not None and len(digits) < field.precision:
        digits = "0" * (field.precision - len(digits)) + digits
    if "#" in field.flags and magnitude:
        if type_ == "o" and not digits.startswith("0"):
            digits = "0" + digits
        elif type_ == "x":
            sign += "0X" if field.type_ == "X" else "0x"
    return _pad(field, sign, digits, zero_ok=field.precision is None)


def _digits(value: int, base: int) -> str:
    if base == 10:
        return str(value)
    return format(value, {2: "b", 8: "o", 16: "x"}[base])


def _real(field: _Field, arg: Arg, number: int) -> str:
    if arg.type_name not in _REALS:
        raise FormatError(FMT_ERR_ARGTYPE + number, f"%{field.type_} does not take a {arg.type_name} argument")
    value = float(arg.value)  # type: ignore[arg-type]
    if math.isnan(value):
        return _pad(field, "", "#QNAN", zero_ok=False)
    negative = math.copysign(1.0, value) < 0  # -0.0 prints as '-0.000000', as in C
    if math.isinf(value):
        return _pad(field, _sign(field, negative), "#INF", zero_ok=False)
    precision = 6 if field.precision is None else field.precision
    alternate = "#" if "#" in field.flags else ""
    if field.type_ in "fF":
        body = f"{abs(value):{alternate}.{precision}f}"
    else:
        body = f"{abs(value):{alternate}.{precision}e}"
        mantissa, _, exponent = body.partition("e")
        body = f"{mantissa}e{exponent[0]}{int(exponent[1:]):03d}"  # three exponent digits, as Beckhoff documents
        if field.type_ == "E":
            body = body.upper()
    return _pad(field, _sign(field, negative), body, zero_ok=True)


def _text(field: _Field, arg: Arg, number: int) -> str:
    if field.type_ in "cC":
        if arg.type_name not in ("BYTE", "USINT"):
            raise FormatError(FMT_ERR_ARGTYPE + number, f"%c takes a BYTE or USINT, not a {arg.type_name}")
        return _pad(field, "", chr(int(arg.value) & 0xFF), zero_ok=False)  # type: ignore[call-overload]
    if arg.type_name == "BOOL":
        text = "TRUE" if arg.value else "FALSE"
    elif arg.type_name in ("STRING", "WSTRING"):
        text = str(arg.value)
    else:
        raise FormatError(FMT_ERR_ARGTYPE + number, f"%s takes a STRING, not a {arg.type_name}")
    if field.precision is not None:
        text = text[: field.precision]
    return _pad(field, "", text, zero_ok=False)


_RENDER = {
    **dict.fromkeys("diuUbBoOxX", _integer),
    **dict.fromkeys("fFeE", _real),
    **dict.fromkeys("sScC", _text),
}


def render(fmt: str, args: list[Arg | None], limit: int = 255) -> str:
    """``fmt`` with each ``%`` field replaced by the next argument; ``FormatError`` on a bad field.

    ``args[k]`` is argument k + 1 (None: not given). ``limit`` is the
    destination's length (T_MaxString: 255 characters).
    """
    out: list[str] = []
    number = 0
    i = 0
    n = len(fmt)
    while i < n:
        ch = fmt[i]
        if ch != "%":
            out.append(ch)
            i += 1
            continue
        if i + 1 < n and fmt[i + 1] == "%":
            out.append("%")
            i += 2
            continue
        number += 1
        field, i = _parse(fmt, i + 1, number)
        handler = _RENDER.get(field.type_)
        if handler is None:
            raise FormatError(FMT_ERR_TYPE + number, f"type field {field.type_!r} is not supported")
        if number > len(args):
            raise FormatError(FMT_ERR_TOO_MANY + number, f"the format has more fields than the {len(args)} arguments")
        arg = args[number - 1]
        if arg is None:
            raise FormatError(FMT_ERR_ARGTYPE + number, f"argument {number} was not given")
        out.append(handler(field, arg, number))
    text = "".join(out)
    if len(text) > limit:
        raise FormatError(FMT_ERR_OVERFLOW + number, f"the formatted string has {len(text)} characters, over {limit}")
    return text
