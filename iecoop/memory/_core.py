"""The memory engine: allocations, checked handles, and how each IEC type lives in memory.

Every instance of a Struct, Union, ARRAY or POU is a real ctypes block. A
pointer, reference or interface variable stored in a block holds an 8-byte
*handle* (allocation id << 32 | byte offset), never a raw address: using a
handle looks the allocation up and checks liveness and bounds, so no user
action can read or write outside a live block.

A ``TypeInfo`` says how one IEC type is stored: its ctypes storage, its size,
how to load and store a value at (block, offset), how checked mode validates a
write, and whether a ctypes field gives the Python value directly (ints,
floats, BOOL, aggregates: no Python code on a read) or needs a descriptor
(STRING, enums, pointers, references, interfaces).
"""

from __future__ import annotations

import bisect
import ctypes
import enum
import itertools
import operator
import sys
import threading
import typing
import weakref
from collections.abc import Callable, Iterator
from typing import Annotated, Any

from iecoop import _config
from iecoop.exceptions import AccessError, DefinitionError, ExceptionCode, PlcException
from iecoop.memory.aliases import Alias
from iecoop.types import ElementaryType, StringType, elementary_type
from iecoop.metadata import Kind, kind_of

_AV = ExceptionCode.RTSEXCPT_ACCESS_VIOLATION
_HANDLE_MASK = 0xFFFFFFFF


def access_violation(message: str) -> PlcException:
    return PlcException(_AV, message)


# ---------------------------------------------------------------------------
# Allocations
# ---------------------------------------------------------------------------


class Allocation:
    """One live memory block: a root ctypes object, known by a never-reused id."""

    __slots__ = ("id", "ref", "base", "size", "label", "freed")

    def __init__(self, ident: int, root: Any, label: str) -> None:
        self.id = ident
        self.base = ctypes.addressof(root)
        self.size = ctypes.sizeof(root)
        self.label = label
        self.freed = False
        self.ref = weakref.ref(root, self._collected)

    def _collected(self, _ref: object) -> None:
        _forget(self)

    def __repr__(self) -> str:
        return f"<allocation {self.id} {self.label} {self.size} bytes>"


_allocations: dict[int, Allocation] = {}
_bases: list[int] = []
_by_base: dict[int, Allocation] = {}
_ids = itertools.count(1)
#: Guards the tables above and every C call on raw addresses (MEMCPY, MEMSET, MEMCMP, the
#: clearing of a deleted block): a block cannot be freed between its check and such a call.
#: Re-entrant because a collected block's weakref callback may run in the thread holding it.
table_lock = threading.RLock()

#: A handle's offset is a signed 32-bit number, so an address may step below its block and back.
#: Arithmetic that leaves -2**31 .. 2**31 - 2 gives this offset instead, which lies outside
#: every block and stays there: a pointer never wraps back into its block.
WILD_OFFSET = 2**31 - 1
#: The largest block (struct, array, POU) a handle can address.
MAX_BLOCK_SIZE = WILD_OFFSET - 1


def signed_offset(handle: int) -> int:
    """The byte offset in a handle, negative below the block's start."""
    offset = handle & _HANDLE_MASK
    return offset - (1 << 32) if offset > WILD_OFFSET else offset


def check_block_size(size: int, where: str) -> None:
    """Refuse, at definition, a type whose instances a handle could not address."""
    if size > MAX_BLOCK_SIZE:
        raise DefinitionError(
            f"{where}: {size} bytes is larger than the largest memory block ({MAX_BLOCK_SIZE} bytes, 2 GiB)"
        )


def _forget(alloc: Allocation) -> None:
    with table_lock:
        if _allocations.get(alloc.id) is alloc:
            del _allocations[alloc.id]
        if _by_base.get(alloc.base) is alloc:
            del _by_base[alloc.base]
            index = bisect.bisect_left(_bases, alloc.base)
            if index < len(_bases) and _bases[index] == alloc.base:
                del _bases[index]


def register(root: Any) -> Allocation:
    """Make ``root`` (a ctypes object owning its memory) an addressable allocation."""
    with table_lock:
        alloc = Allocation(next(_ids), root, type(root).__name__)
        stale = _by_base.get(alloc.base)
        if stale is not None:
            _forget(stale)
        _allocations[alloc.id] = alloc
        _by_base[alloc.base] = alloc
        bisect.insort(_bases, alloc.base)
        return alloc


def free(alloc: Allocation) -> None:
    """Release an allocation (``__DELETE``): every handle into it stops resolving."""
    with table_lock:
        alloc.freed = True
        root = alloc.ref()
        if root is not None:
            drop_cached_views(root)
        # Only the id stops resolving. The block stays known by its address until it is
        # collected, so ADR of the deleted instance (or of a view into it) yields a handle
        # that faults, instead of registering the same memory again as a fresh, valid block.
        if _allocations.get(alloc.id) is alloc:
            del _allocations[alloc.id]


def _root_of(obj: Any) -> Any:
    root = obj
    while getattr(root, "_b_base_", None) is not None:
        root = root._b_base_
    return root


def registered_allocation(obj: Any) -> Allocation | None:
    """The allocation starting at ``obj`` if its address was ever taken (no registration otherwise)."""
    alloc = _by_base.get(ctypes.addressof(obj))
    return alloc if alloc is not None and not alloc.freed and alloc.ref() is obj else None


def _containing(address: int) -> tuple[Allocation, int] | None:
    index = bisect.bisect_right(_bases, address) - 1
    if index >= 0:
        alloc = _by_base.get(_bases[index])
        if alloc is not None and alloc.base <= address < alloc.base + max(alloc.size, 1):
            return alloc, address - alloc.base
    return None


def allocation_of(obj: Any) -> tuple[Allocation, int]:
    """The allocation holding ctypes object ``obj`` and the byte offset of ``obj`` in it."""
    address = ctypes.addressof(obj)
    # Without the lock: a search that races a change in another thread either raises
    # IndexError or misses (then the locked search decides); a block it finds holds the
    # address, and live blocks never overlap, so that answer is right.
    try:
        alloc = _by_base.get(_bases[bisect.bisect_right(_bases, address) - 1])
    except IndexError:
        alloc = None
    if alloc is not None and alloc.base <= address < alloc.base + max(alloc.size, 1):
        return alloc, address - alloc.base
    with table_lock:
        found = _containing(address)
        if found is not None:
            return found
        alloc = register(_root_of(obj))
    offset = address - alloc.base
    if not 0 <= offset < max(alloc.size, 1):
        raise access_violation(f"{type(obj).__name__} instance lies outside any known memory block")
    return alloc, offset


def handle_of(obj: Any, extra_offset: int = 0) -> int:
    """The handle (what ADR returns, as stored in memory) of ``obj`` plus ``extra_offset`` bytes."""
    alloc, offset = allocation_of(obj)
    offset += extra_offset
    return (alloc.id << 32) | (offset if 0 <= offset < WILD_OFFSET else WILD_OFFSET)


def resolve(handle: int, size: int, what: str) -> tuple[Any, int]:
    """The (root block, offset) a handle designates, checked for ``size`` bytes."""
    if handle == 0:
        raise access_violation(f"{what}: null pointer (0) dereferenced")
    alloc = _allocations.get(handle >> 32)
    root = alloc.ref() if alloc is not None else None
    if alloc is None or root is None:
        raise access_violation(f"{what}: the target memory was deleted or no longer exists")
    offset = handle & _HANDLE_MASK
    if offset + size > alloc.size:
        where = "an address moved outside its block" if offset == WILD_OFFSET else f"address {signed_offset(offset)}"
        raise access_violation(
            f"{what}: {where} + {size} bytes lies outside its {alloc.size}-byte block ({alloc.label})"
        )
    return root, offset


def allocation_for_handle(handle: int) -> Allocation | None:
    return _allocations.get(handle >> 32)


# ---------------------------------------------------------------------------
# Keeping a target alive while a block holds its address
# ---------------------------------------------------------------------------

_KEEP = "_iec_keep_"


def owning_root(obj: Any) -> Any:
    """The root block (the object owning the memory) that ctypes object ``obj`` lies in."""
    top = obj
    base = top._b_base_
    while base is not None:
        top = base
        base = top._b_base_
    if top._b_needsfree_:  # ctypes allocated this object's memory: it is the owner
        return top
    # A view made by from_buffer: ask the allocation table.
    return allocation_of(obj)[0].ref()


def hold(holder: Any, offset: int, target: Any) -> None:
    """Record that ``holder``'s slot at ``offset`` refers to block ``target`` (None: to nothing).

    A block holding a pointer, reference or interface to an instance keeps that
    instance alive, as a Python object keeps what it refers to (ctypes'
    ``_objects`` does the same); overwriting the slot drops the old target.
    """
    root = holder
    if holder._b_base_ is not None or not holder._b_needsfree_:
        root = owning_root(holder)
        if root is None:
            return
    keep = root.__dict__.get(_KEEP)
    if target is None or target is root:
        if keep:
            keep.pop(ctypes.addressof(holder) + offset, None)
        return
    if keep is None:
        keep = root.__dict__[_KEEP] = {}
    keep[ctypes.addressof(holder) + offset] = target


def release_held(block: Any) -> None:
    """Drop what the slots of ``block`` kept alive (its memory was just cleared)."""
    keep = owning_root(block).__dict__.get(_KEEP)
    if keep:
        start = ctypes.addressof(block)
        for slot in [s for s in keep if start <= s < start + ctypes.sizeof(block)]:
            del keep[slot]


def target_root(handle: int) -> Any:
    """The live root block ``handle`` is into, or None."""
    alloc = _allocations.get(handle >> 32)
    return alloc.ref() if alloc is not None else None


# ---------------------------------------------------------------------------
# Deleted instances kept by Python
# ---------------------------------------------------------------------------

_CTYPES_INTERNALS = frozenset(("_b_base_", "_b_needsfree_", "_objects"))


def _deleted_fault(obj: Any, what: str) -> PlcException:
    label = object.__getattribute__(obj, "__dict__").get("_iec_deleted_", "instance")
    return access_violation(f"{what} of a deleted {label} (the instance was freed by __DELETE)")


class DeletedInstance(ctypes.Structure):
    """What an instance freed by ``delete()`` becomes for Python code still holding it.

    Reading or writing a member, calling a method or the block itself faults
    with RTSEXCPT_ACCESS_VIOLATION, like use through a handle into freed memory.
    """

    def __getattribute__(self, name: str) -> Any:
        if name in _CTYPES_INTERNALS or (name.startswith("__") and name.endswith("__")):
            return object.__getattribute__(self, name)
        # A block member read through its alias (as a block's own compiled call reads it) is named as declared.
        raise _deleted_fault(self, f"{name.removeprefix(VIEW_PREFIX).removeprefix(CACHE_PREFIX)!r} read")

    def __setattr__(self, name: str, value: Any) -> None:
        raise _deleted_fault(self, f"{name!r} written")

    def __delattr__(self, name: str) -> None:
        raise _deleted_fault(self, f"{name!r} deleted")

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        raise _deleted_fault(self, "call")

    def __eq__(self, other: object) -> bool:
        return isinstance(other, ctypes._CData) and ctypes.addressof(self) == ctypes.addressof(other)

    def __hash__(self) -> int:
        return hash(ctypes.addressof(self))

    def __repr__(self) -> str:
        label = object.__getattribute__(self, "__dict__").get("_iec_deleted_", "instance")
        return f"<deleted {label}>"


def poison(obj: Any) -> bool:
    """Turn a freed root block into a DeletedInstance; False if its class does not allow it."""
    label = type(obj).__name__
    try:
        object.__setattr__(obj, "__class__", DeletedInstance)
    except TypeError:
        return False
    object.__getattribute__(obj, "__dict__")["_iec_deleted_"] = label
    return True


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
# Type information
# ---------------------------------------------------------------------------


class Address:
    """A pointer value as the memory machinery sees it: a handle and the type it designates.

    ``Pointer`` derives from it, so a reference can be bound to an address
    without this module depending on the public class.
    """

    __slots__ = ()

    _handle: int
    _target: TypeInfo | None


class TypeInfo:
    """How values of one IEC type are stored (base class)."""

    name: str = "?"
    ctype: Any = None
    #: True when a ctypes field of ``ctype`` already yields the Python value (no descriptor).
    direct: bool = True
    #: True when a value written through this type is checked as its ``target`` (REFERENCE TO T: as T).
    checked_as_target: bool = False

    @property
    def size(self) -> int:
        return int(ctypes.sizeof(self.ctype))

    @property
    def signature(self) -> str:
        """Type text recorded with remanent data so a changed type is never loaded."""
        return self.name

    def load(self, root: Any, offset: int) -> Any:
        raise NotImplementedError

    def store(self, root: Any, offset: int, value: Any, where: str) -> None:
        raise NotImplementedError

    def validate(self, value: Any, where: str) -> None:
        """Checked mode: raise TypeError naming ``where`` if ``value`` is of the wrong kind."""


    def descriptor(self, raw: Any, name: str, owner: str) -> Any:
        """A Python descriptor for a field of this type, or None to keep the raw ctypes field."""
        return None

    def load_handle(self, handle: int, what: str) -> Any:
        root, offset = resolve(handle, self.size, what)
        return self.load(root, offset)

    def store_handle(self, handle: int, value: Any, what: str) -> None:
        root, offset = resolve(handle, self.size, what)
        self.store(root, offset, value, what)

    def __repr__(self) -> str:
        return f"<TypeInfo {self.name}>"


def _kind_error(where: str, expected: str, value: object) -> TypeError:
    return TypeError(f"{where}: cannot store {type(value).__name__} {value!r} in {expected}")


class ElementaryInfo(TypeInfo):
    """BOOL, integers, bit strings, REAL/LREAL, TIME and dates: ctypes stores and wraps them."""

    def __init__(self, record: ElementaryType, name: str | None = None, initial: Any = None) -> None:
        self.record = record
        self.name = name or record.name
        self.ctype = record.ctype
        #: An alias's own initial value (``TYPE T_Index : DINT := -1;``), None for none.
        self.initial = initial

    def load(self, root: Any, offset: int) -> Any:
        return self.ctype.from_buffer(root, offset).value

    def store(self, root: Any, offset: int, value: Any, where: str) -> None:
        self.validate(value, where)
        self.ctype.from_buffer(root, offset).value = value

    def validate(self, value: Any, where: str) -> None:
        kind = self.record.kind
        if kind == "bool":
            if not isinstance(value, bool):
                raise _kind_error(where, "BOOL (use True / False)", value)
        elif kind == "real":
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise _kind_error(where, self.name, value)
            if isinstance(value, int) and value.bit_length() > 1000:
                try:
                    float(value)
                except OverflowError:
                    # No IEC integer is this large; a Python int this size has no floating-point value.
                    raise ValueError(
                        f"{where}: an integer of {value.bit_length()} bits is outside the range of {self.name}"
                    ) from None
        elif isinstance(value, bool) or not isinstance(value, int):
            raise _kind_error(where, self.name, value)


class StringInfo(TypeInfo):
    """STRING(n) / WSTRING(n): a terminated buffer shown to Python as ``str``."""

    direct = False

    def __init__(self, record: StringType, length: int) -> None:
        self.record = record
        self.length = length
        self.name = f"{record.name}({length})"
        self.ctype = record.ctype(length)

    def _decode(self, data: bytes) -> str:
        if self.record.name == "STRING":
            return data.split(b"\x00", 1)[0].decode("latin-1")
        text = data.decode("utf-16-le", errors="replace")
        return text.split("\x00", 1)[0]

    def _encode(self, value: Any, where: str) -> bytes:
        data = self.record.encode(value, self.length, where)
        return data + b"\x00" * (self.size - len(data))

    def load(self, root: Any, offset: int) -> str:
        return self._decode((ctypes.c_char * self.size).from_buffer(root, offset).raw)

    def store(self, root: Any, offset: int, value: Any, where: str) -> None:
        ctypes.memmove(ctypes.addressof(root) + offset, self._encode(value, where), self.size)

    def validate(self, value: Any, where: str) -> None:
        self.record.encode(value, self.length, where)


    def descriptor(self, raw: Any, name: str, owner: str) -> Any:
        return _StringField(self, raw.offset, f"{owner}.{name}")


class _StringField:
    __slots__ = ("info", "offset", "where")

    def __init__(self, info: StringInfo, offset: int, where: str) -> None:
        self.info, self.offset, self.where = info, offset, where

    def __get__(self, obj: Any, owner: Any = None) -> Any:
        if obj is None:
            return self
        return self.info._decode((ctypes.c_char * self.info.size).from_buffer(obj, self.offset).raw)

    def __set__(self, obj: Any, value: Any) -> None:
        data = self.info._encode(value, self.where)
        ctypes.memmove(ctypes.addressof(obj) + self.offset, data, self.info.size)


class EnumInfo(TypeInfo):
    """An enumeration with an IEC base type; reads give the member (or the raw number)."""

    direct = False

    def __init__(self, enum_cls: type[enum.IntEnum], base: ElementaryType) -> None:
        self.enum_cls = enum_cls
        self.base = base
        self.name = enum_cls.__name__
        self.ctype = base.ctype

    @property
    def signature(self) -> str:
        return f"{self.name}:{self.base.name}"

    def _member(self, raw: int) -> Any:
        try:
            return self.enum_cls(raw)
        except ValueError:
            return raw

    def load(self, root: Any, offset: int) -> Any:
        return self._member(self.ctype.from_buffer(root, offset).value)

    def store(self, root: Any, offset: int, value: Any, where: str) -> None:
        self.validate(value, where)
        self.ctype.from_buffer(root, offset).value = int(value)

    def validate(self, value: Any, where: str) -> None:
        if isinstance(value, bool) or not isinstance(value, int):
            raise _kind_error(where, self.name, value)
        if not isinstance(value, self.enum_cls) and isinstance(value, enum.Enum):
            raise _kind_error(where, self.name, value)


    def descriptor(self, raw: Any, name: str, owner: str) -> Any:
        return _EnumField(self, raw, f"{owner}.{name}")


class _EnumField:
    __slots__ = ("info", "raw", "where")

    def __init__(self, info: EnumInfo, raw: Any, where: str) -> None:
        self.info, self.raw, self.where = info, raw, where

    def __get__(self, obj: Any, owner: Any = None) -> Any:
        if obj is None:
            return self
        return self.info._member(self.raw.__get__(obj))

    def __set__(self, obj: Any, value: Any) -> None:
        self.info.validate(value, self.where)
        self.raw.__set__(obj, int(value))


READ_ONLY = "_iec_ro_"


class CheckedMemberField:
    """Checked mode: a STRUCT / ARRAY member whose view remembers it may not be written through.

    A block's local or output read from outside the block (or any CONSTANT)
    gives a view marked read-only: writing a member or an element through it
    raises AccessError, as writing the variable itself does. Members and
    elements of a marked view are marked too.
    """

    __slots__ = ("info", "raw", "offset", "where", "rule", "cache_key")

    def __init__(self, info: TypeInfo, raw: Any, where: str, cache_key: str | None = None) -> None:
        self.info, self.raw, self.offset, self.where = info, raw, int(raw.offset), where
        #: Set by the POU layer: (holder, reading frame) -> the refusal text, or None when the reader may write.
        self.rule: Callable[[Any, Any], str | None] | None = None
        #: An ARRAY OF FB: the holder keeps the writable view (a marked one is made for each read).
        self.cache_key = cache_key

    def __get__(self, obj: Any, owner: Any = None) -> Any:
        if obj is None:
            return self
        state = obj.__dict__
        refusal = state.get(READ_ONLY)
        if refusal is None and self.rule is not None:
            refusal = self.rule(obj, sys._getframe(1))
        if refusal is not None:
            view = self.raw.__get__(obj)
            view.__dict__[READ_ONLY] = refusal
            return view
        key = self.cache_key
        if key is None:
            return self.raw.__get__(obj)
        view = state.get(key)
        if view is None:
            view = state[key] = self.raw.__get__(obj)
        return view

    def own_read(self, obj: Any) -> Any:
        """The read by ``obj``'s own compiled body: the rule allows its own code, so no frame is inspected.

        A holder itself read through a read-only view keeps that refusal.
        """
        state = obj.__dict__
        key = self.cache_key
        if key is not None:
            view = state.get(key)
            if view is not None and READ_ONLY not in state:
                return view
        refusal = state.get(READ_ONLY)
        if refusal is not None:
            view = self.raw.__get__(obj)
            view.__dict__[READ_ONLY] = refusal
            return view
        if key is None:
            return self.raw.__get__(obj)
        view = state[key] = self.raw.__get__(obj)
        return view

    def __set__(self, obj: Any, value: Any) -> None:
        refusal = obj.__dict__.get(READ_ONLY)
        if refusal is not None:
            raise AccessError(refusal)
        self.info.store(obj, self.offset, value, self.where)


class _MemberProperty(property):
    """A property whose getter is ``operator.attrgetter`` of the ctypes field's alias (no Python frame on a read).

    The alias (``cached``) keeps the member's view in the holder's ``__dict__``
    at the first read, so later reads return it from C without building a view.
    """

    def __init__(self, raw: Any, alias: str, fset: Callable[[Any, Any], None], doc: str) -> None:
        super().__init__(operator.attrgetter(alias), fset, None, doc)
        self.raw = raw
        self.alias = alias
        self.cached = CachedView(raw, alias)


#: Holder ``__dict__`` keys that keep cached views (dropped on ``__DELETE``, never copied).
CACHE_PREFIX = "_iec_m_"


class CachedView:
    """A non-data descriptor under a member's alias: makes the view once, then the holder's ``__dict__`` answers.

    A view designates fixed memory (the holder's, at a fixed offset), so one
    view serves every read; a write still copies memory through the member's setter.
    """

    __slots__ = ("raw", "alias")

    def __init__(self, raw: Any, alias: str) -> None:
        self.raw, self.alias = raw, alias

    def __get__(self, obj: Any, owner: Any = None) -> Any:
        if obj is None:
            return self.raw
        view = obj.__dict__[self.alias] = self.raw.__get__(obj)
        return view


#: Where a block's own compiled call finds a member's view: an instance attribute with no class attribute of
#: that name, which the interpreter's specialised attribute read answers from the instance (from CPython 3.12 on,
#: a class attribute under the name, even a non-data descriptor such as CachedView, stops that specialisation).
#: An identifier never starts with a digit, so no member's alias is one of these keys.
VIEW_PREFIX = f"{CACHE_PREFIX}0"


def keep_member_views(obj: Any) -> None:
    """Keep every block member's view of ``obj`` under its ``VIEW_PREFIX`` key, all at once.

    The compiled call tries one key first and calls this when it is missing, so
    one key present means all of ``type(obj)``'s are; the views are the ones its
    members' aliases keep, so both names give one view per member.
    """
    cls = type(obj)
    views = {key: getattr(obj, alias) for alias, key in cls._iec_view_keys_}
    # Checked mode: the STRUCT / ARRAY views the body reads as its own (CheckedMemberField.own_read).
    views.update({key: read(obj) for key, read in cls.__dict__.get("_iec_own_views_", ())})
    own_dict(obj).update(views)


def own_dict(obj: Any) -> dict[str, Any]:
    """``obj.__dict__``, replaced first by a plain copy of itself (same items).

    CPython (3.12, 3.13) starts an instance's ``__dict__`` as a dict sharing its
    keys with the class's other instances, and its specialised attribute read
    does not answer from such a dict; a dict made by ``dict()`` is never one.
    Only the speed differs: the items are the same.
    """
    state = obj.__dict__ = dict(obj.__dict__)
    return state


#: Where an ARRAY OF FB keeps its element views: an instance attribute with no class attribute of that
#: name (see VIEW_PREFIX), made at the first index.
ELEMENT_VIEWS = sys.intern(f"{CACHE_PREFIX}elements")


def set_state_without_views(obj: Any, values: dict[str, Any], memory: bytes) -> None:
    """``__setstate__`` of a copy (``copy.copy``): the memory and ``__dict__``, but not the original's kept views."""
    fresh = {k: v for k, v in values.items() if not k.startswith(CACHE_PREFIX)}
    typing.cast(Any, ctypes.Structure).__setstate__(obj, fresh, memory)  # ctypes' own, for structures and arrays


def drop_cached_views(obj: Any) -> None:
    """Forget the views cached in ``obj`` and in them, so no cached view outlives a deleted block."""
    state = getattr(obj, "__dict__", None)
    if not state:
        return
    for key in [k for k in state if k.startswith(CACHE_PREFIX)]:
        cached = state.pop(key)
        for view in cached if isinstance(cached, list) else (cached,):
            drop_cached_views(view)


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


# ---------------------------------------------------------------------------
# Resolving annotations into TypeInfo
# ---------------------------------------------------------------------------

_elementary_infos: dict[int, ElementaryInfo] = {}
_string_infos: dict[tuple[str, int], StringInfo] = {}

MAX_STRING_LENGTH = 65535


def elementary_info(record: ElementaryType) -> ElementaryInfo:
    info = _elementary_infos.get(id(record))
    if info is None:
        info = _elementary_infos[id(record)] = ElementaryInfo(record)
    return info


def string_info(record: StringType, length: int) -> StringInfo:
    key = (record.name, length)
    info = _string_infos.get(key)
    if info is None:
        info = _string_infos[key] = StringInfo(record, length)
    return info


#: How a class of another kind is described (an interface: InterfaceInfo), registered by the
#: module that defines that description, so this module does not import it.
_class_infos: dict[Kind, Callable[[type], TypeInfo]] = {}


def register_class_info(kind: Kind, make: Callable[[type], TypeInfo]) -> None:
    """Describe the classes of ``kind`` with ``make(cls)`` in ``class_info``."""
    _class_infos[kind] = make


def class_info(cls: type) -> TypeInfo | None:
    """The TypeInfo of a Struct / Union / FB / interface / enum class, or None."""
    # Kept on the class itself (its own __dict__, never a base's), so it goes with the class.
    info: TypeInfo | None = cls.__dict__.get("_iec_type_info_")
    if info is not None:
        return info
    kind = kind_of(cls)
    if kind in (Kind.STRUCT, Kind.UNION, Kind.FUNCTION_BLOCK):
        if getattr(cls, "_iec_layout_", None) is None:
            return None
        info = AggregateInfo(cls)
    elif kind is Kind.ENUM:
        base = typing.cast(ElementaryType, getattr(cls, "_iec_base_"))
        info = EnumInfo(typing.cast(type[enum.IntEnum], cls), base)
    elif kind in _class_infos:
        info = _class_infos[kind](cls)
    else:
        return None
    setattr(cls, "_iec_type_info_", info)
    return info


def resolve_type(
    annotation: Any,
    where: str,
    *,
    length: int | None = None,
    bounds: object = None,
    resolver: Callable[[Any], Any] | None = None,
) -> TypeInfo:
    """The TypeInfo of an IEC type annotation, or DefinitionError naming ``where``."""
    if isinstance(annotation, str) or isinstance(annotation, typing.ForwardRef):
        if resolver is None:
            raise DefinitionError(f"{where}: cannot resolve the type name {annotation!r}")
        annotation = resolver(annotation)
    origin = typing.get_origin(annotation)
    if origin is Annotated:
        return _resolve_annotated(annotation, where, length, bounds, resolver)
    # ARRAY[T], POINTER_TO[T] and a bare POINTER_TO (PVOID): their classes know how they resolve
    # (iecoop.memory.arrays and .pointers; REFERENCE_TO: iecoop.memory.references).
    resolve = getattr(origin if origin is not None else annotation, "_iec_resolve_", None)
    if resolve is not None:
        return typing.cast(TypeInfo, resolve(annotation, where, length, bounds, resolver))
    if isinstance(annotation, type):
        info = class_info(annotation)
        if info is not None:
            _check_plain(length, bounds, where, info.name)
            return info
        if annotation in (int, float, bool, str):
            raise DefinitionError(
                f"{where}: plain {annotation.__name__} is not an IEC type; use INT, DINT, REAL, LREAL, BOOL or STRING"
            )
        if kind_of(annotation) is Kind.PROGRAM:
            name = annotation.__name__
            raise DefinitionError(
                f"{where}: PROGRAM {name} is not a data type (a program has one instance, no variable holds one); "
                f"read its variables through that instance, as ST reads {name}.x"
            )
    raise DefinitionError(f"{where}: {_annotation_name(annotation)} is not an IEC type")


_Resolver = Callable[[Any], Any] | None


def _resolve_annotated(annotation: Any, where: str, length: int | None, bounds: object, resolver: _Resolver) -> TypeInfo:
    """``Annotated[...]``: a REFERENCE_TO, a STRING(n), an alias of an elementary type, or metadata to look through."""
    metadata = annotation.__metadata__
    # The REFERENCE marker of REFERENCE_TO[T] knows how it resolves, wherever it stands.
    marker = next((m for m in metadata if hasattr(type(m), "_iec_resolve_")), None)
    if marker is not None:
        return typing.cast(TypeInfo, marker._iec_resolve_(annotation, where, length, bounds, resolver))
    record = elementary_type(annotation)
    if isinstance(record, StringType):
        n = record.default_length if length is None else length
        if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= MAX_STRING_LENGTH:
            raise DefinitionError(f"{where}: {record.name} length must be an integer 1..{MAX_STRING_LENGTH}, got {n!r}")
        _check_no_bounds(bounds, where, record.name)
        return string_info(record, n)
    if isinstance(record, ElementaryType):
        _check_plain(length, bounds, where, record.name)
        alias = next((m for m in metadata if isinstance(m, Alias)), None)
        if alias is not None:
            return ElementaryInfo(record, alias.name, alias.initial)
        return elementary_info(record)
    return resolve_type(annotation.__origin__, where, length=length, bounds=bounds, resolver=resolver)


def _annotation_name(annotation: Any) -> str:
    if annotation is None:
        return "PVOID"
    record = elementary_type(annotation)
    if record is not None:
        return record.name
    if isinstance(annotation, type):
        return annotation.__name__
    if isinstance(annotation, str):
        return annotation
    if isinstance(annotation, typing.ForwardRef):
        return annotation.__forward_arg__
    return repr(annotation)


def _check_plain(length: object, bounds: object, where: str, name: str) -> None:
    if length is not None:
        raise DefinitionError(f"{where}: length= applies to STRING / WSTRING, not {name}")
    _check_no_bounds(bounds, where, name)


def _check_no_bounds(bounds: object, where: str, name: str) -> None:
    if bounds is not None:
        raise DefinitionError(f"{where}: bounds= applies to ARRAY, not {name}")
