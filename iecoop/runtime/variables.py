"""Instance paths: every variable of a program tree, with its class (plain, RETAIN, PERSISTENT).

Remanent data is restored, and online changes copy data, *by path*: a
variable is kept when the new program still has a variable of that path and
type description, so a changed program keeps what still matches. The type
description resolves aliases (``T_Speed`` of REAL is ``REAL``), so an alias
whose base type changed is a changed declaration, and renaming an alias is not.
"""

from __future__ import annotations

import ctypes
import dataclasses
from typing import Any

from iecoop.metadata import fields_of, layout_of
from iecoop.memory.typeinfo import (
    AggregateInfo, ArrayInfo, ElementaryInfo, InterfaceInfo, PointerInfo, ReferenceInfo, TypeInfo,
)

__all__ = [
    "Leaf", "copy_matching", "describe", "format_directory", "handle_offsets", "leaves", "nodes", "parse_directory",
    "translate_offset",
]

PLAIN, RETAIN, PERSISTENT = 0, 1, 2


@dataclasses.dataclass(frozen=True)
class Leaf:
    """One variable at the bottom of the tree: path, type description, place and class.

    ``address`` marks a POINTER, REFERENCE or interface variable (or an ARRAY
    of them): its bytes are a handle into this process's memory.
    """

    path: str
    signature: str
    offset: int
    size: int
    remanence: int  # PLAIN, RETAIN or PERSISTENT
    address: bool = False


def describe(info: TypeInfo) -> str:
    """The full type description stored with remanent data: aliases resolved to their base type.

    >>> from typing import Annotated
    >>> from iecoop import REAL, Alias, Struct
    >>> T_Speed = Annotated[REAL, Alias("T_Speed")]
    >>> class Limits(Struct):
    ...     speed: T_Speed = 0.0
    >>> describe(fields_of(Limits)[0].info)
    'REAL'
    """
    if isinstance(info, ElementaryInfo):
        return info.record.name
    if isinstance(info, ArrayInfo):
        dims = ", ".join(f"{lo}..{hi}" for lo, hi in info.bounds)
        return f"ARRAY[{dims}] OF {describe(info.elem)}"
    if isinstance(info, AggregateInfo):
        layout = layout_of(info.cls)
        if layout is None:
            return info.signature
        return info.name + "{" + ",".join(f"{f.name}:{describe(f.info)}" for f in layout.fields) + "}"
    return info.signature


def leaves(cls: type, prefix: str = "", base: int = 0, remanence: int = PLAIN) -> list[Leaf]:
    """Every leaf variable of an instance of ``cls`` (offsets relative to the instance)."""
    layout = layout_of(cls)
    found: list[Leaf] = []
    if layout is None:
        return found
    for record in layout.fields:
        spec = record.spec
        mark = PERSISTENT if spec.persistent else RETAIN if spec.retain else remanence
        path = f"{prefix}{record.name}"
        found.extend(_leaves_of(record.info, path, base + record.offset, mark))
    return found


def _leaves_of(info: TypeInfo, path: str, offset: int, remanence: int) -> list[Leaf]:
    if isinstance(info, AggregateInfo):
        return leaves(info.cls, f"{path}.", offset, remanence)
    if isinstance(info, ArrayInfo) and isinstance(info.elem, AggregateInfo):
        found: list[Leaf] = []
        size = info.elem.size
        index = 0
        for position in _indices(info.bounds):
            label = ",".join(str(i) for i in position)
            found.extend(leaves(info.elem.cls, f"{path}[{label}].", offset + index * size, remanence))
            index += 1
        return found
    return [Leaf(path, describe(info), offset, info.size, remanence, bool(_handles_of(info, 0)))]


def _indices(bounds: tuple[tuple[int, int], ...]) -> list[tuple[int, ...]]:
    result: list[tuple[int, ...]] = [()]
    for lo, hi in bounds:
        result = [prefix + (i,) for prefix in result for i in range(lo, hi + 1)]
    return result


def copy_matching(
    source: bytes, source_leaves: list[Leaf], target: Any, target_leaves: list[Leaf], classes: set[int],
    *, addresses: bool = True,
) -> int:
    """Copy into ``target`` every leaf of the given classes whose path and type description match; count them.

    ``addresses=False`` leaves POINTER, REFERENCE and interface variables
    alone: an image from another process holds handles that mean nothing here.
    """
    by_path = {leaf.path: leaf for leaf in source_leaves}
    base = ctypes.addressof(target)
    copied = 0
    for leaf in target_leaves:
        if leaf.remanence not in classes or (leaf.address and not addresses):
            continue
        old = by_path.get(leaf.path)
        if old is None or old.signature != leaf.signature or old.size != leaf.size:
            continue
        if old.offset < 0 or old.offset + old.size > len(source):
            continue
        ctypes.memmove(base + leaf.offset, source[old.offset : old.offset + old.size], leaf.size)
        copied += 1
    return copied


def format_directory(found: list[Leaf]) -> str:
    """A text directory of leaves, stored with a block image (one leaf per line)."""
    return "\n".join(f"{leaf.path}\t{leaf.signature}\t{leaf.offset}\t{leaf.size}\t{leaf.remanence}" for leaf in found)


def parse_directory(text: str) -> list[Leaf]:
    """Parse a stored directory; a malformed line raises ValueError (the image is then not loaded)."""
    found: list[Leaf] = []
    if not text:
        return found
    for number, line in enumerate(text.split("\n"), 1):
        parts = line.split("\t")
        if len(parts) != 5:
            raise ValueError(f"directory line {number} has {len(parts)} fields, expected 5")
        path, signature, offset, size, remanence = parts
        values = (int(offset), int(size), int(remanence))
        if values[0] < 0 or values[1] < 0 or values[2] not in (PLAIN, RETAIN, PERSISTENT):
            raise ValueError(f"directory line {number} is out of range")
        found.append(Leaf(path, signature, *values))
    return found


def nodes(cls: type, prefix: str = "", base: int = 0) -> dict[str, tuple[int, int]]:
    """Every variable of an instance of ``cls``, leaves and the blocks / structs above them: path -> (offset, size)."""
    found: dict[str, tuple[int, int]] = {}
    layout = layout_of(cls)
    if layout is None:
        return found
    for record in layout.fields:
        path, offset, info = f"{prefix}{record.name}", base + record.offset, record.info
        found[path] = (offset, info.size)
        if isinstance(info, AggregateInfo):
            found.update(nodes(info.cls, f"{path}.", offset))
        elif isinstance(info, ArrayInfo):
            size = info.elem.size
            for index, position in enumerate(_indices(info.bounds)):
                label = f"{path}[{','.join(str(i) for i in position)}]"
                found[label] = (offset + index * size, size)
                if isinstance(info.elem, AggregateInfo):
                    found.update(nodes(info.elem.cls, f"{label}.", offset + index * size))
    return found


def handle_offsets(cls: type, base: int = 0) -> list[int]:
    """Where an instance of ``cls`` holds addresses: POINTER TO, REFERENCE TO and interface variables."""
    found: list[int] = []
    layout = layout_of(cls)
    if layout is None:
        return found
    for record in layout.fields:
        found.extend(_handles_of(record.info, base + record.offset))
    return found


def _handles_of(info: TypeInfo, offset: int) -> list[int]:
    if isinstance(info, (PointerInfo, ReferenceInfo, InterfaceInfo)):
        return [offset]
    if isinstance(info, AggregateInfo):
        return handle_offsets(info.cls, offset)
    if isinstance(info, ArrayInfo):
        inner = _handles_of(info.elem, 0)
        return [offset + i * info.elem.size + o for i in range(info.count) for o in inner]
    return []


def translate_offset(old: dict[str, tuple[int, int]], new: dict[str, tuple[int, int]], offset: int) -> int | None:
    """The offset in the new layout of what sat at ``offset`` in the old one (by path), or None if it is gone."""
    best: tuple[str, int, int] | None = None
    for path, (start, size) in old.items():
        if start <= offset < start + size and (best is None or size < best[2] or (size == best[2] and len(path) > len(best[0]))):
            best = (path, start, size)
    if best is None:
        return None
    path, start, size = best
    moved = new.get(path)
    if moved is None or offset - start >= moved[1]:
        return None
    return moved[0] + (offset - start)
