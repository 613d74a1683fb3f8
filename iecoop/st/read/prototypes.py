"""Overrides and implementations spelt in another case than their prototypes: one Python name for each.

ST names are case-insensitive, Python's are not: after pass 1 resolved the members, a METHOD or PROPERTY (and a
METHOD's inputs) takes the names of the first prototype it overrides or implements.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

from iecoop.st.read.table import Callable_, Decl

__all__ = ["align_prototype_names"]


def align_prototype_names(decls: Mapping[str, Decl]) -> None:
    """A METHOD or PROPERTY takes the Python name of the first one it overrides or implements, and a METHOD's
    inputs take that one's input names; so do the other prototypes it implements. ST names are
    case-insensitive (``Append(Text)`` of an interface is ``append(text)`` of the block), Python's are not:
    aligned, the signatures match and a call through the interface, the base or the block reaches the same
    METHOD with the same names."""
    for decl in decls.values():
        if decl.library or decl.kind != "fb":
            continue
        for key in list(decl.methods):
            protos = _prototypes(decls, decl, key, "methods")
            for owner, other in protos[1:] + [(decl, decl.methods[key])] if protos else []:
                owner.methods[key] = _aligned(other, protos[0][1])
        for key in list(decl.props):
            props = _prototypes(decls, decl, key, "props")
            for owner, other in props[1:] + [(decl, decl.props[key])] if props else []:
                owner.props[key] = dataclasses.replace(other, name=props[0][1].name)


def _prototypes(decls: Mapping[str, Decl], decl: Decl, key: str, table: str) -> list[tuple[Decl, Any]]:
    """The METHODs (``table`` "methods") or PROPERTYs ("props") ``key`` of the blocks ``decl`` extends and of
    the interfaces it or they implement, nearest first, each with the declaration it belongs to."""
    seen: set[str] = set()
    found: list[tuple[Decl, Any]] = []
    pending = list(decl.bases) + list(decl.implements)
    while pending:
        other = decls.get(pending.pop(0).lower())
        if other is None or other.name in seen:
            continue
        seen.add(other.name)
        member = getattr(other, table).get(key) if other.kind in ("fb", "interface") and not other.library else None
        if member is not None:
            found.append((other, member))
        pending += other.bases + other.implements
    return found


def _aligned(method: Callable_, proto: Callable_) -> Callable_:
    """``method`` named as ``proto``, its inputs too where their ST names agree but for the case."""
    params = method.params
    if len(params) == len(proto.params):
        params = [dataclasses.replace(own, name=theirs.name) if own.st.lower() == theirs.st.lower() else own
                  for own, theirs in zip(params, proto.params)]
    return dataclasses.replace(method, name=proto.name, params=params)
