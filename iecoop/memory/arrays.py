"""``ARRAY[lo..hi] OF T``: the public array annotation, ``ARRAY``.

``ARRAY[INT]`` with ``VAR(bounds=(1, 20))`` declares ``ARRAY[1..20] OF INT``;
the ctypes array type behind it is made by the memory machinery.
"""

from __future__ import annotations

import typing
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, Any, ClassVar, Generic, TypeVar

from iecoop.exceptions import DefinitionError
from iecoop.memory._aggregates import AggregateInfo, ArrayInfo, array_info, normalise_bounds
from iecoop.memory._handles import check_block_size
from iecoop.memory._infos import TypeInfo
from iecoop.memory._resolve import _Resolver, resolve_type
from iecoop.memory.open_arrays import OpenArrayInfo, open_dimensions
from iecoop.memory.references import ReferenceInfo
from iecoop.metadata import Kind, kind_of

__all__ = ["ARRAY"]

_T = TypeVar("_T")


class ARRAY(Generic[_T]):
    """``ARRAY[lo..hi] OF T``: declared as ``ARRAY[INT]`` with ``VAR(bounds=(lo, hi))``.

    Indices are the declared ones (``a[lo]`` .. ``a[hi]``); several bound pairs
    make a multi-dimensional array indexed ``a[i, j]``. An index outside the
    bounds raises RTSEXCPT_ARRAYBOUNDS.

    >>> from iecoop import INT, Struct, VAR
    >>> class Fifo(Struct):
    ...     items: ARRAY[INT] = VAR(bounds=(1, 3))
    >>> fifo = Fifo()
    >>> fifo.items[3] = 7
    >>> list(fifo.items), fifo.items.low, fifo.items.high
    ([0, 0, 7], 1, 3)
    """

    #: How ``resolve_type`` reads ``ARRAY[T]``.
    _iec_resolve_: ClassVar[Callable[..., TypeInfo]]

    if TYPE_CHECKING:
        low: int
        high: int
        bounds: tuple[tuple[int, int], ...]

        def __getitem__(self, index: int | tuple[int, ...]) -> _T: ...

        def __setitem__(self, index: int | tuple[int, ...], value: _T) -> None: ...

        def __len__(self) -> int: ...

        def __iter__(self) -> Iterator[_T]: ...


def _array_depth(annotation: Any) -> int:
    """How many ARRAY levels ``ARRAY[ARRAY[...]]`` nests (1 for a plain ARRAY)."""
    depth = 0
    while typing.get_origin(annotation) is ARRAY:
        depth += 1
        (annotation,) = typing.get_args(annotation)
    return depth


def _resolve_array(annotation: Any, where: str, length: int | None, bounds: object, resolver: _Resolver) -> TypeInfo:
    """``ARRAY[T]`` with ``bounds=``; ``ARRAY[ARRAY[T]]`` takes one bounds entry per level, outermost first."""
    if annotation is ARRAY:
        raise DefinitionError(f"{where}: ARRAY is not an IEC type")
    (elem_annotation,) = typing.get_args(annotation)
    depth = _array_depth(annotation)
    dims = open_dimensions(bounds)
    if dims is not None:
        # ARRAY[*]: what a VAR_IN_OUT refers to (the layout refuses it anywhere else)
        if depth > 1:
            raise DefinitionError(f"{where}: ARRAY[*] OF ARRAY is not supported; write ARRAY[*, *] OF the element (bounds=('*', '*'))")
        elem = resolve_type(elem_annotation, where, length=length, bounds=None, resolver=resolver)
        if isinstance(elem, ReferenceInfo):
            raise DefinitionError(f"{where}: ARRAY[*] OF {elem.name} is not allowed")
        return OpenArrayInfo(elem, dims)
    if bounds is None:
        example = "bounds=(1, 10)" if depth == 1 else "bounds=((0, 4), (0, 9)), one (lo, hi) per ARRAY level"
        raise DefinitionError(f"{where}: ARRAY needs bounds=, e.g. VAR({example})")
    if depth > 1:
        if not isinstance(bounds, tuple) or len(bounds) != depth or not all(isinstance(b, tuple) for b in bounds):
            raise DefinitionError(
                f"{where}: an ARRAY of ARRAY nests {depth} levels and takes one bounds entry per level, "
                f"outermost first, e.g. bounds=((0, 4), (0, 9)); got {bounds!r}"
            )
        level_bounds, inner_bounds = bounds[0], bounds[1:] if depth > 2 else bounds[1]
    else:
        level_bounds, inner_bounds = bounds, None
    pairs = normalise_bounds(level_bounds, where)
    elem = resolve_type(elem_annotation, where, length=length, bounds=inner_bounds, resolver=resolver)
    if isinstance(elem, ReferenceInfo):
        raise DefinitionError(f"{where}: ARRAY OF REFERENCE is not allowed")
    if isinstance(elem, OpenArrayInfo):
        raise DefinitionError(f"{where}: ARRAY OF {elem.name} is not allowed: an element needs its bounds")
    leaf = _array_leaf(elem)
    if leaf is not elem and isinstance(leaf, AggregateInfo) and kind_of(leaf.cls) in (Kind.FUNCTION_BLOCK, Kind.PROGRAM):
        raise DefinitionError(
            f"{where}: ARRAY OF ARRAY OF a function block is not supported; write ARRAY[a..b, c..d] OF the block"
        )
    count = 1
    for lo, hi in pairs:
        count *= hi - lo + 1
    check_block_size(count * elem.size, f"{where}: ARRAY of {count} {elem.name}")
    return array_info(elem, pairs)


ARRAY._iec_resolve_ = staticmethod(_resolve_array)


def _array_leaf(info: TypeInfo) -> TypeInfo:
    """The innermost element type of a (nested) ARRAY."""
    while isinstance(info, ArrayInfo):
        info = info.elem
    return info
