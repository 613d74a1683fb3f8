"""Which values ST stores where: the implicit conversions a PLC's compiler refuses, refused at load.

TwinCAT and CODESYS convert numbers into numbers implicitly, but no number, BOOL or date into a STRING, no
STRING into anything else, and nothing elementary into a STRUCT, a block or an ARRAY, nor back (the compiler's
"Cannot convert type 'STRING' to type 'INT'"). Without this check such a store reached the cycle, where it
stopped the program as RTSEXCPT_UNKNOWN, or worse ran: ``F_Square('ab')`` doubled the text. Only types known
for certain are compared; an expression of unknown or generic type is left to the run-time checks.
"""

from __future__ import annotations

from collections.abc import Callable

from iecoop.st.read.dates import DATE_TYPES
from iecoop.st.read.table import Decl, TypeRef

__all__ = ["comparison_mismatch", "store_mismatch"]

#: The elementary types of durations and dates (the ST bridge's short names).
_TIMES = frozenset({"TIME", "LTIME", *DATE_TYPES})
#: What each shape is called in a message.
_SHAPE_NAMES = {"struct": "STRUCT", "fb": "FUNCTION_BLOCK", "union": "UNION", "array": "ARRAY"}


def shape(type_: TypeRef | None, decl_of: Callable[[TypeRef], Decl | None]) -> str | None:
    """``string``, ``number``, ``bool``, ``time``, ``array``, ``struct``, ``union`` or ``fb``; None when not known
    for certain (a pointer, an enumeration, an interface, a generic or unresolved type)."""
    if type_ is None:
        return None
    type_ = type_.deref()
    if type_.kind == "user":
        decl = decl_of(type_)
        if decl is not None and decl.kind == "alias" and decl.alias_of is not None and decl.alias_of.kind != "user":
            return shape(decl.alias_of, decl_of)
        return decl.kind if decl is not None and decl.kind in ("struct", "union", "fb") else None
    if type_.kind == "string":
        return "string"
    if type_.kind == "array":
        return "array"
    if type_.kind != "elem":
        return None
    if type_.is_bool:
        return "bool"
    if type_.is_int or type_.is_real:
        return "number"
    return "time" if type_.name in _TIMES else None


def _spelt(type_: TypeRef, kind: str) -> str:
    type_ = type_.deref()
    if kind == "array":
        return f"ARRAY OF {type_.of.name}" if type_.of is not None else "ARRAY"
    return f"{type_.name} (a {_SHAPE_NAMES[kind]})" if kind in _SHAPE_NAMES else type_.name


def store_mismatch(target: TypeRef | None, value: TypeRef | None, decl_of: Callable[[TypeRef], Decl | None]) -> str | None:
    """Why a value of type ``value`` cannot be stored in a variable (or input) of type ``target``; None if it can
    or the types are not both known."""
    into, held = shape(target, decl_of), shape(value, decl_of)
    if into is None or held is None or into == held or (into in ("number", "bool") and held in ("number", "bool")):
        return None
    if into in ("struct", "union", "fb", "array") and held in ("struct", "union", "fb", "array"):
        return None  # aggregates of different types: their own rules (a derived block, an ARRAY's bounds) apply
    assert target is not None and value is not None
    if into == "time" and held == "number" or into == "number" and held == "time":
        return None  # TIME and the integers convert into each other on the PLC (with a warning)
    hint = "ST converts nothing implicitly into or out of a STRUCT, block or ARRAY"
    if into == "string" and held in ("number", "bool", "time"):
        hint = f"ST converts nothing implicitly into a STRING: convert it with {value.deref().name}_TO_STRING or TO_STRING"
    elif held == "string" and into in ("number", "bool", "time"):
        hint = f"ST converts no STRING implicitly: convert it with STRING_TO_{target.deref().name} or TO_{target.deref().name}"
    elif "string" in (into, held) or "time" in (into, held):
        hint = f"ST converts no {value.deref().name} implicitly into a {target.deref().name}"
    return f"cannot convert type {_spelt(value, held)} to type {_spelt(target, into)} ({hint})"


def comparison_mismatch(left: TypeRef | None, right: TypeRef | None, decl_of: Callable[[TypeRef], Decl | None]) -> str | None:
    """Why ``left`` and ``right`` cannot be compared: a STRING with anything but a STRING."""
    sides = shape(left, decl_of), shape(right, decl_of)
    if None in sides or sides[0] == sides[1] or "string" not in sides:
        return None
    assert left is not None and right is not None
    return f"cannot compare type {_spelt(left, str(sides[0]))} with type {_spelt(right, str(sides[1]))} " \
        f"(a STRING compares with a STRING only: convert the other side with TO_STRING or the STRING with STRING_TO_...)"
