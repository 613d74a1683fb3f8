"""Member views: what reading a STRUCT, ARRAY or block member of a holder gives, and where it is kept.

A view designates fixed memory (the holder's, at a fixed offset), so one view
serves every read: the holder keeps it in its ``__dict__`` under a private
key (``CACHE_PREFIX``), dropped on ``__DELETE`` and never copied. In checked
mode a STRUCT / ARRAY member read from code that may not write it gives a
view marked read-only (``CheckedMemberField``).
"""

from __future__ import annotations

import ctypes
import operator
import sys
import typing
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from iecoop.exceptions import AccessError

if TYPE_CHECKING:
    from iecoop.memory._infos import TypeInfo

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
    members' aliases keep, so both names give one view per member. An ARRAY OF
    blocks keeps its element views then.
    """
    cls = type(obj)
    views = {key: getattr(obj, alias) for alias, key in cls._iec_view_keys_}
    # Checked mode: the STRUCT / ARRAY views the body reads as its own (CheckedMemberField.own_read).
    views.update({key: read(obj) for key, read in cls.__dict__.get("_iec_own_views_", ())})
    for view in views.values():
        # An ARRAY OF blocks: its element views too, which the compiled call reads in place.
        keep_elements = getattr(type(view), "_iec_keep_elements_", None)
        if keep_elements is not None and ELEMENT_VIEWS not in view.__dict__:
            keep_elements(view)
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
