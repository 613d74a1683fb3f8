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
    """

    __slots__ = ("name", "initial")

    def __init__(self, name: str, initial: Any = None) -> None:
        self.name = name
        self.initial = initial

    def __repr__(self) -> str:
        return f"Alias({self.name!r})" if self.initial is None else f"Alias({self.name!r}, initial={self.initial!r})"
