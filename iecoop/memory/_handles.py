"""The allocation table and checked handles: how an address designates live memory.

Every instance of a Struct, Union, ARRAY or POU is a real ctypes block. A
pointer, reference or interface variable stored in a block holds an 8-byte
*handle* (allocation id << 32 | byte offset), never a raw address: using a
handle looks the allocation up and checks liveness and bounds, so no user
action can read or write outside a live block. A block holding a handle keeps
its target alive; an instance freed by ``__DELETE`` faults on every use.
"""

from __future__ import annotations

import bisect
import ctypes
import itertools
import threading
import weakref
from typing import Any

from iecoop.exceptions import DefinitionError, ExceptionCode, PlcException
from iecoop.memory._views import CACHE_PREFIX, VIEW_PREFIX, drop_cached_views

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
