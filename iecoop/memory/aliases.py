"""``TYPE T_Speed : REAL; END_TYPE``: the public type-alias metadata, ``Alias``.

An alias is written ``Annotated[REAL, Alias("T_Speed")]``; values behave as
the base type and the alias name shows in ``var_info``, diagrams and the ST
export.
"""

from __future__ import annotations

from typing import Any

__all__ = ["Alias"]


class Alias:
    """Metadata naming a type alias: ``T_Speed = Annotated[REAL, Alias("T_Speed")]``.

    ST: ``TYPE T_Speed : REAL; END_TYPE``. Values behave as the base type; the
    alias name shows in ``var_info`` and diagrams. ``initial=`` is the alias's
    own initial value (``TYPE T_Index : DINT := -1; END_TYPE`` is
    ``Annotated[DINT, Alias("T_Index", initial=-1)]``): a variable of the alias
    type starts with it unless its declaration gives one, and so does each
    element of an ARRAY OF the alias.

    ``length=``, ``bounds=`` and ``limits=`` say what the TYPE declares of a
    STRING, an ARRAY or a subrange (``TYPE T_Name : STRING(20)``,
    ``ARRAY[1..3] OF INT``, ``INT(0..100)``), so the alias is written back as
    declared; the variables declared with it carry the same themselves.
    """

    __slots__ = ("bounds", "initial", "length", "limits", "name")

    def __init__(self, name: str, initial: Any = None, *, length: int | None = None,
                 bounds: tuple[tuple[int, int], ...] | None = None, limits: tuple[int, int] | None = None) -> None:
        self.name = name
        self.initial = initial
        self.length = length
        self.bounds = bounds
        self.limits = limits

    def __repr__(self) -> str:
        extra = [f"initial={self.initial!r}"] if self.initial is not None else []
        extra += [f"{k}={getattr(self, k)!r}" for k in ("length", "bounds", "limits") if getattr(self, k) is not None]
        return f"Alias({', '.join([repr(self.name), *extra])})"
