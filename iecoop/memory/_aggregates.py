"""Structs, unions, blocks and ARRAYs in memory: their ``TypeInfo``, the ARRAY types, the blocks' type tags.

A Struct, Union or FB placed inline reads as a view of its memory
(``AggregateInfo``); an ``ARRAY[..] OF T`` is a ctypes array type made once
per element type and bounds (``ArrayInfo``), whose index is bounds-checked.
A block carries a type tag at its start, so a handle to it finds its dynamic
class (a virtual call's target) and refuses memory that holds another.
"""

from __future__ import annotations

import ctypes
import typing
import weakref
from collections.abc import Iterator
from typing import Any

from iecoop import _config
from iecoop.exceptions import AccessError, DefinitionError, ExceptionCode, PlcException
from iecoop.memory._handles import access_violation, resolve
from iecoop.memory._infos import TypeInfo, _kind_error
from iecoop.memory._views import (
    CACHE_PREFIX,
    ELEMENT_VIEWS,
    READ_ONLY,
    CheckedMemberField,
    _MemberProperty,
    own_dict,
    set_state_without_views,
)
from iecoop.metadata import Kind, kind_of


# ---------------------------------------------------------------------------
# Class tags: how a handle to an FB finds the FB's dynamic class
# ---------------------------------------------------------------------------

#: tag -> weak reference to its class. Weak, so that a block class defined in a function can be
#: collected; its entry leaves with it, and tags are never reused (a stale tag finds no class).
_class_by_tag: dict[int, weakref.ref[type]] = {}
_next_tag = [1]


def new_class_tag(cls: type) -> int:
    tag = _next_tag[0]
    _next_tag[0] = tag + 1
    _class_by_tag[tag] = weakref.ref(cls, lambda _ref: _class_by_tag.pop(tag, None))
    return tag


def class_for_tag(tag: int) -> type | None:
    try:
        return _class_by_tag[tag]()
    except KeyError:
        return None


def _tagged_classes(cls: type, offset: int) -> frozenset[type]:
    """The tagged block classes whose instances start at ``offset`` in a block of class ``cls``.

    Fixed by the layout: an inline member keeps its declared type (a derived
    block stored into it keeps the member's tag), so the real class of the
    instance at an address is known without reading memory.
    """
    found: set[type] = set()
    if offset == 0 and getattr(cls, "_iec_tagged_", False):
        found.add(cls)
    layout = getattr(cls, "_iec_layout_", None)
    if layout is not None:
        for record in layout.fields:
            start = record.offset
            if start <= offset < start + record.info.size:
                found |= _tagged_in(record.info, offset - start)
    else:
        info = getattr(cls, "_iec_info_", None)
        if isinstance(info, TypeInfo):
            found |= _tagged_in(info, offset)
    return frozenset(found)


def _tagged_in(info: TypeInfo, offset: int) -> frozenset[type]:
    if isinstance(info, AggregateInfo):
        return real_classes(info.cls, offset)
    if isinstance(info, ArrayInfo) and isinstance(info.elem, AggregateInfo):
        return real_classes(info.elem.cls, offset % info.elem.size)
    return frozenset()


def real_classes(cls: type, offset: int) -> frozenset[type]:
    # Cached on the class itself, so the cache never keeps a class alive.
    cache: dict[int, frozenset[type]] | None = cls.__dict__.get("_iec_tagged_at_")
    if cache is None:
        cache = {}
        setattr(cls, "_iec_tagged_at_", cache)
    found = cache.get(offset)
    if found is None:
        found = cache[offset] = _tagged_classes(cls, offset)
    return found


def dynamic_class(root: Any, offset: int, what: str) -> type:
    """The block class at (root, offset) per its type tag, checked against the block's real class.

    A tag that memory operations overwrote (MEMCPY of another block's header)
    faults instead of calling into the wrong class.
    """
    tag = ctypes.c_uint64.from_buffer(root, offset).value
    cls = class_for_tag(tag)
    if offset == 0 and type(root) is cls:
        return cls
    if cls is None or cls not in real_classes(type(root), offset):
        raise access_violation(
            f"{what}: the memory holds no function block of a matching type (type tag {tag} was overwritten or never set)"
        )
    return cls




# ---------------------------------------------------------------------------
# Structs, unions and blocks placed inline
# ---------------------------------------------------------------------------


class AggregateInfo(TypeInfo):
    """A Struct, Union or FB type placed inline: reading gives a view of the memory."""

    def __init__(self, cls: type) -> None:
        self.cls = cls
        self.name = cls.__name__
        self.ctype = cls

    @property
    def signature(self) -> str:
        layout = getattr(self.cls, "_iec_layout_", None)
        if layout is None:
            return self.name
        inner = ",".join(f"{f.name}:{f.info.signature}" for f in layout.fields)
        return f"{self.name}{{{inner}}}"

    def load(self, root: Any, offset: int) -> Any:
        # Inline (a member or an ARRAY element): the memory holds exactly the declared type.
        cls = self.cls
        if offset == 0 and type(root) is cls:
            return root
        return typing.cast(Any, cls).from_buffer(root, offset)

    def descriptor(self, raw: Any, name: str, owner: str) -> Any:
        if not getattr(self.cls, "_iec_tagged_", False):
            return CheckedMemberField(self, raw, f"{owner}.{name}") if _config.CHECKS else None
        # A block member: reads stay C-level (the ctypes field's own getter); a write
        # (fbSpare := fbOther) goes through store(), which keeps the member's type tag.
        offset, where, store = raw.offset, f"{owner}.{name}", self.store

        def set_member(obj: Any, value: Any) -> None:
            store(obj, offset, value, where)

        # The ctypes field stays reachable under a private alias, read through a C-level getter.
        return _MemberProperty(raw, f"{CACHE_PREFIX}{name}", set_member, f"{self.name} member {where}")

    def load_dynamic(self, root: Any, offset: int) -> Any:
        """Through an address: the type tag says which derived block is there (a virtual call's target)."""
        cls = self.cls
        if getattr(cls, "_iec_tagged_", False):
            dynamic = dynamic_class(root, offset, self.name)
            if not issubclass(dynamic, cls):
                raise access_violation(f"no {self.name} instance at this address (it holds a {dynamic.__name__})")
            cls = dynamic
        if offset == 0 and type(root) is cls:
            return root
        return typing.cast(Any, cls).from_buffer(root, offset)

    def store(self, root: Any, offset: int, value: Any, where: str) -> None:
        if isinstance(value, dict):
            # A STRUCT from its members' values (ST: stPoint := (x := 1.5, y := 2.0)).
            if kind_of(self.cls) in (Kind.FUNCTION_BLOCK, Kind.PROGRAM):
                raise TypeError(f"{where}: a function block is not assigned from a dict; set its inputs at the call")
            # All or nothing: every member is checked before the first one is written.
            check_value(self, value, where)
            layout = getattr(self.cls, "_iec_layout_")
            for name, item in value.items():
                record = layout.by_name[name]
                record.info.store(root, offset + record.offset, item, f"{where}.{name}")
            return
        self.validate(value, where)
        tagged = getattr(self.cls, "_iec_tagged_", False)
        tag = ctypes.c_uint64.from_buffer(root, offset).value if tagged else 0
        ctypes.memmove(ctypes.addressof(root) + offset, ctypes.addressof(value), self.size)
        if tagged:
            # A derived block copied into a base-typed variable: the variable stays the base type.
            ctypes.c_uint64.from_buffer(root, offset).value = tag

    def validate(self, value: Any, where: str) -> None:
        if not isinstance(value, self.cls):
            raise _kind_error(where, self.name, value)

    def load_handle(self, handle: int, what: str) -> Any:
        root, offset = resolve(handle, self.size, what)
        return self.load_dynamic(root, offset)


# ---------------------------------------------------------------------------
# Arrays
# ---------------------------------------------------------------------------


def _bounds_error(cls: Any, index: object) -> PlcException:
    dims = ", ".join(f"{lo}..{hi}" for lo, hi in cls._iec_bounds_)
    return PlcException(
        ExceptionCode.RTSEXCPT_ARRAYBOUNDS, f"index {index!r} outside ARRAY[{dims}] OF {cls._iec_elem_.name}"
    )


def _make_array_type(elem: TypeInfo, bounds: tuple[tuple[int, int], ...]) -> type:
    count = 1
    for lo, hi in bounds:
        count *= hi - lo + 1
    # Subclassing ctypes.Array (as the ctypes docs allow) rather than ``elem.ctype * count``:
    # ctypes keeps every product type in a cache for good, and with it a block class.
    base: Any = type(f"{elem.ctype.__name__}_Array_{count}", (ctypes.Array,), {"_type_": elem.ctype, "_length_": count})
    one_dim = len(bounds) == 1
    lo0, hi0 = bounds[0]
    strides: list[int] = []
    step = 1
    for lo, hi in reversed(bounds):
        strides.insert(0, step)
        step *= hi - lo + 1
    raw_get = base.__getitem__
    raw_set = base.__setitem__
    size = elem.size

    def flat(self: Any, index: Any) -> int:
        if one_dim:
            # An enumeration value indexes like its number (ST: aCounts[E_Station.FILLER]).
            if isinstance(index, int) and not isinstance(index, bool) and lo0 <= index <= hi0:
                return int(index) - lo0
            raise _bounds_error(type(self), index)
        if not isinstance(index, tuple) or len(index) != len(bounds):
            raise _bounds_error(type(self), index)
        position = 0
        for i, (lo, hi), stride in zip(index, bounds, strides):
            if not isinstance(i, int) or isinstance(i, bool) or not lo <= i <= hi:
                raise _bounds_error(type(self), index)
            position += (int(i) - lo) * stride
        return position

    namespace: dict[str, Any] = {
        "__slots__": (),
        "_iec_elem_": elem,
        "_iec_bounds_": bounds,
        "low": lo0,
        "high": hi0,
        "bounds": bounds,
        "_flat": flat,
    }
    # An element ARRAY (ARRAY OF ARRAY) is a view, written through its info so a list can be stored.
    if elem.direct and not isinstance(elem, ArrayInfo):

        def getitem(self: Any, index: Any) -> Any:
            if type(index) is int and lo0 <= index <= hi0 and one_dim:
                return raw_get(self, index - lo0)
            return raw_get(self, flat(self, index))

        if _config.CHECKS:
            validate = elem.validate

            def setitem(self: Any, index: Any, value: Any) -> None:
                position = index - lo0 if type(index) is int and lo0 <= index <= hi0 and one_dim else flat(self, index)
                refusal = self.__dict__.get(READ_ONLY)
                if refusal is not None:
                    raise AccessError(refusal)
                validate(value, f"{type(self).__name__} element [{index!r}]")
                raw_set(self, position, value)

        else:

            def setitem(self: Any, index: Any, value: Any) -> None:
                if type(index) is int and lo0 <= index <= hi0 and one_dim:
                    raw_set(self, index - lo0, value)
                else:
                    raw_set(self, flat(self, index), value)

    elif isinstance(elem, AggregateInfo) and one_dim and not _config.CHECKS:
        # An element of an ARRAY OF STRUCT / FB is a view of the declared type at its offset.
        view_of = typing.cast(Any, elem.cls).from_buffer

        def getitem(self: Any, index: Any) -> Any:
            if type(index) is int and lo0 <= index <= hi0:
                return view_of(self, (index - lo0) * size)
            return elem.load(self, flat(self, index) * size)

        def setitem(self: Any, index: Any, value: Any) -> None:
            elem.store(self, flat(self, index) * size, value, f"element {index!r}")

    elif _config.CHECKS:

        def getitem(self: Any, index: Any) -> Any:
            view = elem.load(self, flat(self, index) * size)
            refusal = self.__dict__.get(READ_ONLY)
            if refusal is not None and hasattr(view, "__dict__"):
                view.__dict__[READ_ONLY] = refusal
            return view

        def setitem(self: Any, index: Any, value: Any) -> None:
            refusal = self.__dict__.get(READ_ONLY)
            if refusal is not None:
                raise AccessError(refusal)
            elem.store(self, flat(self, index) * size, value, f"element {index!r}")

    else:

        def getitem(self: Any, index: Any) -> Any:
            return elem.load(self, flat(self, index) * size)

        def setitem(self: Any, index: Any, value: Any) -> None:
            elem.store(self, flat(self, index) * size, value, f"element {index!r}")

    if elem.direct and getattr(getattr(elem, "cls", None), "_iec_tagged_", False):
        # ARRAY OF FB: the element views are made once and kept in the array's view (their members cached
        # in them), read as a plain instance attribute; the first index makes them.

        def kept(self: Any) -> list[Any]:
            views = own_dict(self)[ELEMENT_VIEWS] = [raw_get(self, i) for i in range(count)]
            return views

        if one_dim:

            def getitem(self: Any, index: Any) -> Any:
                # Exactly an int: a bool or a float is no index (flat() refuses it with RTSEXCPT_ARRAYBOUNDS).
                position = index - lo0 if type(index) is int and lo0 <= index <= hi0 else flat(self, index)
                try:
                    return self._iec_m_elements[position]
                except AttributeError:
                    return kept(self)[position]

        else:

            def getitem(self: Any, index: Any) -> Any:
                position = flat(self, index)
                try:
                    return self._iec_m_elements[position]
                except AttributeError:
                    return kept(self)[position]

        namespace["_iec_keep_elements_"] = kept

        def iterate(self: Any) -> Iterator[Any]:
            # The kept element views, as indexing gives them (their members' views kept in them).
            try:
                views = self._iec_m_elements
            except AttributeError:
                views = kept(self)
            yield from views

    else:

        def iterate(self: Any) -> Iterator[Any]:
            if elem.direct:
                for i in range(count):
                    yield raw_get(self, i)
            else:
                for i in range(count):
                    yield elem.load(self, i * size)

    def eq(self: Any, other: Any) -> Any:
        if type(other) is not type(self):
            return NotImplemented
        return bytes(memoryview(self).cast("B")) == bytes(memoryview(other).cast("B"))

    dims = ", ".join(f"{lo}..{hi}" for lo, hi in bounds)

    def rep(self: Any) -> str:
        return f"ARRAY[{dims}] OF {elem.name}({list(iterate(self))!r})"

    namespace.update(
        __getitem__=getitem,
        __setitem__=setitem,
        __iter__=iterate,
        __len__=lambda self: count,
        __eq__=eq,
        __hash__=None,
        __repr__=rep,
        __setstate__=set_state_without_views,
    )
    return type(f"ARRAY[{dims}] OF {elem.name}", (base,), namespace)


class ArrayInfo(TypeInfo):
    def __init__(self, elem: TypeInfo, bounds: tuple[tuple[int, int], ...]) -> None:
        self.elem = elem
        self.bounds = bounds
        dims = ", ".join(f"{lo}..{hi}" for lo, hi in bounds)
        self.name = f"ARRAY[{dims}] OF {elem.name}"
        self.ctype = _make_array_type(elem, bounds)
        self.ctype._iec_info_ = self

    @property
    def signature(self) -> str:
        dims = ", ".join(f"{lo}..{hi}" for lo, hi in self.bounds)
        return f"ARRAY[{dims}] OF {self.elem.signature}"

    @property
    def count(self) -> int:
        return int(self.ctype._length_)

    def load(self, root: Any, offset: int) -> Any:
        return self.ctype.from_buffer(root, offset)

    def descriptor(self, raw: Any, name: str, owner: str) -> Any:
        # An ARRAY OF FB: the holder keeps the array's view, and the view its elements' views.
        of_blocks = isinstance(self.elem, AggregateInfo) and getattr(self.elem.cls, "_iec_tagged_", False)
        if _config.CHECKS:
            return CheckedMemberField(self, raw, f"{owner}.{name}", f"{CACHE_PREFIX}{name}" if of_blocks else None)
        if of_blocks:
            return _MemberProperty(raw, f"{CACHE_PREFIX}{name}", raw.__set__, f"{self.name} member {owner}.{name}")
        return None

    def store(self, root: Any, offset: int, value: Any, where: str) -> None:
        if isinstance(value, (list, tuple)):
            # Element by element, in row-major order (ST: aValues := [1, 2, 3]); the rest is left as it is.
            # All or nothing: every element is checked before the first one is written.
            items = check_value(self, value, where)
            size = self.elem.size
            for i, item in enumerate(items):
                self.elem.store(root, offset + i * size, item, self.element_label(where, i))
            return
        self.validate(value, where)
        ctypes.memmove(ctypes.addressof(root) + offset, ctypes.addressof(value), self.size)

    def validate(self, value: Any, where: str) -> None:
        if type(value) is not self.ctype:
            raise _kind_error(where, self.name, value)

    def element_label(self, where: str, position: int) -> str:
        return f"{where}[{self.bounds[0][0] + position if len(self.bounds) == 1 else position}]"


def check_value(info: TypeInfo, value: Any, where: str) -> list[Any]:
    """Raise what storing ``value`` would raise, without writing; the flattened items of a list.

    A list into an ARRAY and a dict into a STRUCT are checked to the leaves
    first, so a bad item leaves the target untouched.
    """
    if info.checked_as_target:
        check_value(typing.cast(Any, info).target, value, where)
    elif isinstance(info, ArrayInfo) and isinstance(value, (list, tuple)):
        # ARRAY OF ARRAY takes one list per element array; a multi-dimensional ARRAY any nesting, row-major
        items = list(value) if isinstance(info.elem, ArrayInfo) else list(_flatten(value))
        if len(items) > info.count:
            raise TypeError(f"{where}: {len(items)} values for {info.name}, which has {info.count} elements")
        for i, item in enumerate(items):
            check_value(info.elem, item, info.element_label(where, i))
        return items
    elif isinstance(info, AggregateInfo) and isinstance(value, dict):
        if kind_of(info.cls) in (Kind.FUNCTION_BLOCK, Kind.PROGRAM):
            raise TypeError(f"{where}: a function block is not assigned from a dict; set its inputs at the call")
        by_name = getattr(info.cls, "_iec_layout_").by_name
        for name, item in value.items():
            record = by_name.get(name)
            if record is None:
                raise TypeError(f"{where}: {info.name} has no member {name!r}")
            check_value(record.info, item, f"{where}.{name}")
    else:
        info.validate(value, where)
    return []


def _flatten(values: Any) -> Iterator[Any]:
    for item in values:
        if isinstance(item, (list, tuple)):
            yield from _flatten(item)
        else:
            yield item


#: One ArrayInfo (and so one ctypes array type) per element type and bounds, while in use.
#: Weak values: the fields declaring an ARRAY hold its info, and an ARRAY OF a block class goes
#: with the last class using it. (An id key cannot be reused while its info lives: the info holds
#: the element.) Not kept on the element: CPython before 3.13 does not show the collector the
#: array type's reference to its element type, so that cycle would never be collected.
_array_infos: weakref.WeakValueDictionary[tuple[int, tuple[tuple[int, int], ...]], ArrayInfo] = weakref.WeakValueDictionary()


def array_info(elem: TypeInfo, bounds: tuple[tuple[int, int], ...]) -> ArrayInfo:
    key = (id(elem), bounds)
    info = _array_infos.get(key)
    if info is None:
        info = _array_infos[key] = ArrayInfo(elem, bounds)
    return info


def normalise_bounds(bounds: object, where: str) -> tuple[tuple[int, int], ...]:
    """``(1, 20)`` or ``((1, 3), (1, 4))`` as a tuple of (lo, hi) pairs, checked."""
    if not isinstance(bounds, tuple) or not bounds:
        raise DefinitionError(f"{where}: ARRAY needs bounds=(lo, hi), got {bounds!r}")
    pairs: list[tuple[int, int]]
    if all(isinstance(b, int) and not isinstance(b, bool) for b in bounds):
        if len(bounds) % 2:
            raise DefinitionError(f"{where}: ARRAY bounds come in (lo, hi) pairs, got {bounds!r}")
        pairs = [(int(bounds[i]), int(bounds[i + 1])) for i in range(0, len(bounds), 2)]
    elif all(isinstance(b, tuple) and len(b) == 2 for b in bounds):
        pairs = [(b[0], b[1]) for b in typing.cast(tuple[tuple[int, int], ...], bounds)]
    else:
        raise DefinitionError(f"{where}: ARRAY bounds must be (lo, hi) integer pairs, got {bounds!r}")
    for lo, hi in pairs:
        if not (isinstance(lo, int) and isinstance(hi, int)) or isinstance(lo, bool) or isinstance(hi, bool):
            raise DefinitionError(f"{where}: ARRAY bounds must be integers, got {lo!r}..{hi!r}")
        if hi < lo:
            raise DefinitionError(f"{where}: ARRAY[{lo}..{hi}] is empty: the upper bound is below the lower one")
        if not -(2**31) <= lo <= hi < 2**31:
            raise DefinitionError(f"{where}: ARRAY bounds {lo}..{hi} are outside the DINT range")
    return tuple(pairs)
