"""How a Python value is written as an ST literal: ``TRUE``, ``T#1S500MS``, ``1.5E3``, ``'a$Nb'``, ``E_Mode.Run``.

The one place the writer turns a value into literal text: initial values,
constants and the constants of bodies all come through :func:`literal`.
"""

from __future__ import annotations

import enum
import math
from typing import Any

from iecoop.literals import format_date, format_dt, format_ltime, format_time, format_tod
from iecoop.memory.typeinfo import ElementaryInfo, StringInfo, TypeInfo
from iecoop.st.write.model import ident

__all__ = ["literal"]


def _real_text(value: float) -> str:
    text = repr(float(value))
    if not math.isfinite(value):
        raise ValueError(f"{value!r} has no ST literal")
    mantissa, _, exponent = text.partition("e")
    if "." not in mantissa:
        mantissa += ".0"
    return f"{mantissa}E{exponent}" if exponent else mantissa


#: ST's named string escapes (IEC 61131-3, 6.3.3); every other control character is ``$`` and its code in hex.
_ESCAPES = {"$": "$$", "\n": "$N", "\t": "$T", "\r": "$R", "\f": "$P"}


def _string_text(value: str, quote: str = "'") -> str:
    """A STRING ('...', ``$xx``) or WSTRING ("...", ``$xxxx``) literal: no control character is written as it is,
    so the text stays one line and the TwinCAT and PLCopen XML stay well-formed."""
    digits = 2 if quote == "'" else 4
    out = []
    for char in value:
        if char in _ESCAPES or char == quote:
            out.append(_ESCAPES.get(char) or "$" + char)
        elif char < " " or "\x7f" <= char <= "\x9f" or char in "\ufffe\uffff":  # the last two: no XML holds them
            out.append(f"${ord(char):0{digits}X}")
        else:
            out.append(char)
    return quote + "".join(out) + quote


def literal(value: Any, info: TypeInfo | None = None) -> str:
    """A Python value as an ST literal of type ``info`` (TIME values as ``T#...``, DT as ``DT#...``...)."""
    if isinstance(value, enum.Enum):
        return f"{type(value).__name__}.{ident(value.name)}"
    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    if isinstance(info, ElementaryInfo) and isinstance(value, int):
        kind, name = info.record.kind, info.record.name
        if name == "TIME":
            return format_time(value).upper()
        if name == "LTIME":
            return format_ltime(value).upper()
        if name == "DATE":
            return format_date(value)
        if name in ("DT", "DATE_AND_TIME"):
            return format_dt(value)
        if name in ("TOD", "TIME_OF_DAY"):
            return format_tod(value)
        if kind == "real":
            return _real_text(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return _real_text(value)
    if isinstance(value, str):
        return _string_text(value, '"' if isinstance(info, StringInfo) and info.record.name == "WSTRING" else "'")
    if value is None:
        return "0"
    raise ValueError(f"{value!r} has no ST literal")
