"""Pass 2, arithmetic on the date types: TOD, DATE and DT with TIME, as IEC 61131-3 defines it.

TIME and TOD count milliseconds, DATE and DT seconds (iecoop.types); IEC 61131-3's ADD_TOD_TIME,
ADD_DT_TIME, SUB_TOD_TIME, SUB_DT_TIME, SUB_TOD_TOD, SUB_DT_DT and SUB_DATE_DATE are the ``+`` and ``-``
TwinCAT and CODESYS write between them. Any other mix with a date type is refused.
"""

from __future__ import annotations

from iecoop.st.read.frames import PRECEDENCE, Ex
from iecoop.st.read.table import TypeRef

__all__ = ["DATE_TYPES", "date_arithmetic"]

#: The date types (IEC 61131-3 ANY_DATE).
DATE_TYPES = frozenset({"DATE", "TOD", "DT"})
_ADD, _SUB = PRECEDENCE["+"], PRECEDENCE["-"]


def _elem(type_: TypeRef | None) -> str:
    return type_.name if type_ is not None and type_.kind == "elem" else ""


def date_arithmetic(op: str, left: Ex, right: Ex) -> Ex | str | None:
    """``left op right`` with a date operand: the expression, or the refusal's message; None without a date operand."""
    lt, rt = _elem(left.type and left.type.deref()), _elem(right.type and right.type.deref())
    if lt not in DATE_TYPES and rt not in DATE_TYPES:
        return None
    pair = (lt, rt) if op == "-" or lt in DATE_TYPES else (rt, lt)  # TIME + TOD is TOD + TIME
    date, other = (left, right) if pair == (lt, rt) else (right, left)
    if op in ("+", "-") and pair == ("TOD", "TIME"):
        return Ex(f"{date.wrap(_ADD)} {op} {other.wrap(_ADD + 1)}", TypeRef("elem", "TOD"), True, _ADD)
    if op in ("+", "-") and pair == ("DT", "TIME"):  # whole seconds of the TIME, as ADD_DT_TIME keeps them
        return Ex(f"{date.wrap(_ADD)} {op} {other.wrap(PRECEDENCE['*'])} // 1000", TypeRef("elem", "DT"), True, _ADD)
    if op == "-" and pair == ("TOD", "TOD"):
        return Ex(f"{left.wrap(_SUB)} - {right.wrap(_SUB + 1)}", TypeRef("elem", "TIME"), True, _SUB)
    if op == "-" and pair in (("DT", "DT"), ("DATE", "DATE")):
        return Ex(f"({left.wrap(_SUB)} - {right.wrap(_SUB + 1)}) * 1000", TypeRef("elem", "TIME"), True, PRECEDENCE["*"])
    return (f"{lt or 'an untyped value'} {op} {rt or 'an untyped value'} is not supported: IEC 61131-3 defines TOD + TIME, "
            "TOD - TIME, DT + TIME, DT - TIME (a TOD or DT) and TOD - TOD, DT - DT, DATE - DATE (a TIME)")
