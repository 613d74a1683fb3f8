"""Pass 2, TwinCAT's implicit checks: the project's CheckBounds and CheckDiv* FUNCTIONs, called where TwinCAT calls them.

A project that declares ``CheckBounds`` has every ARRAY index handed to it with its dimension's bounds, and the
index it returns is used; ``CheckDivDInt`` / ``CheckDivLInt`` / ``CheckDivReal`` / ``CheckDivLReal`` get the
divisor of every ``/`` of their type. The code inside the check functions themselves is not checked.
"""

from __future__ import annotations

from typing import Any

from iecoop.st.read.frames import Ex, Scope
from iecoop.st.read.lookup import Lookup
from iecoop.st.read.table import LREAL, TypeRef

__all__ = ["checked_divisor", "checked_indices", "implicit_check"]

#: TwinCAT's POUs for implicit checks (lower case): the code inside one of them is not checked by the others.
_CHECK_FUNCTIONS = frozenset(name.lower() for name in (
    "CheckBounds", "CheckDivDInt", "CheckDivLInt", "CheckDivReal", "CheckDivLReal", "CheckRangeSigned",
    "CheckRangeUnsigned", "CheckLRangeSigned", "CheckLRangeUnsigned", "CheckPointer"))


def implicit_check(decls: Lookup[Any], name: str, scope: Scope) -> str | None:
    """The Python name of the project's FUNCTION ``name`` (CheckBounds, CheckDivDInt...) when TwinCAT would call
    it implicitly here; None when the project declares none, or the code is that check function's own."""
    decl = decls.get(name.lower())
    if decl is None or decl.kind != "function" or scope.pou_name.lower() in _CHECK_FUNCTIONS:
        return None
    return str(decl.name)


def checked_divisor(decls: Lookup[Any], op: str, kind: TypeRef | None, right: Ex, scope: Scope) -> Ex:
    """The divisor of a ``/`` computed in ``kind``, passed through CheckDivDInt / CheckDivLInt / CheckDivReal /
    CheckDivLReal when the project declares it."""
    if op != "/":
        return right
    name = "CheckDivLReal" if kind == LREAL else "CheckDivReal" if kind is not None and kind.is_real else \
        "CheckDivLInt" if kind is not None and kind.name in ("LINT", "ULINT", "LWORD") else "CheckDivDInt"
    check = implicit_check(decls, name, scope)
    return right if check is None else Ex(f"{check}({right.code})", right.type)


def checked_indices(decls: Lookup[Any], array: TypeRef | None, indices: list[str], scope: Scope) -> list[str]:
    """The indices of ``a[i, j]``, each handed to the project's CheckBounds with its dimension's bounds."""
    check = implicit_check(decls, "CheckBounds", scope) if array is not None and array.bounds else None
    if check is None or array is None or array.bounds is None or len(array.bounds) != len(indices):
        return indices
    return [f"{check}({index}, {low}, {high})" for index, (low, high) in zip(indices, array.bounds)]
