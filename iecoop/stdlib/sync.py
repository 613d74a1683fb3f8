"""Synchronisation and ExST set / reset: test_and_set, CriticalSection, S and R.

``test_and_set(adr(obj, "flag"))`` is TwinCAT's ``TestAndSet(Flag)`` and
CODESYS's ``TEST_AND_SET(dw)``; ``CriticalSection`` is TwinCAT's
``FB_IecCriticalSection``. Both are atomic across Python threads, which is
what a runtime that runs tasks on threads needs (Beckhoff InfoSys "TestAndSet",
"FB_IecCriticalSection"; CODESYS Online Help "TEST_AND_SET").

``S(self, "x", cond)`` and ``R(self, "x", cond)`` are the ExST assignments
``x S= cond`` and ``x R= cond``.
"""

from __future__ import annotations

import sys
import threading
import types
from typing import Any

from iecoop import _config
from iecoop.members import method
from iecoop.memory import Pointer, adr
from iecoop.pou import FunctionBlock, Program
from iecoop.profiles import active_profile
from iecoop.types import BOOL
from iecoop.writes import check_write

__all__ = ["CriticalSection", "R", "S", "test_and_set"]

# ---------------------------------------------------------------------------
# TEST_AND_SET / TestAndSet
# ---------------------------------------------------------------------------

_TEST_AND_SET_LOCK = threading.Lock()


def test_and_set(flag: Pointer[Any]) -> bool | int:
    """``TestAndSet(Flag)`` (TwinCAT) / ``TEST_AND_SET(dw)`` (CODESYS): atomically take a flag.

    ``flag`` is ``adr(obj, "name")`` of a BOOL (TwinCAT) or a DWORD / UDINT
    (CODESYS; any integer variable is accepted). The read-modify-write holds
    one module-wide lock, so it is atomic across threads; release the flag
    by writing FALSE / 0 to it, as on the PLC.

    The result depends on the active profile's ``test_and_set``:

    * ``"acquired"`` (TwinCAT): if the flag was FALSE / 0 it is set to
      TRUE / 1 and the result is TRUE; otherwise the flag is left unchanged
      and the result is FALSE.
    * ``"previous_value"`` (CODESYS): TRUE / 1 is written whatever the flag
      held and the previous value is returned (a bool for a BOOL flag, an
      int for an integer one); ``0`` / FALSE means the lock was acquired.

    ST (TwinCAT)::

        IF TestAndSet(bLock) THEN  (* ... *)  bLock := FALSE; END_IF

    >>> from iecoop import BOOL, DWORD, Struct, adr, use_profile
    >>> class Shared(Struct):
    ...     lock: BOOL = False
    ...     dw: DWORD = 0
    >>> shared = Shared()
    >>> test_and_set(adr(shared, "lock")), test_and_set(adr(shared, "lock"))
    (True, False)
    >>> with use_profile("codesys"):
    ...     test_and_set(adr(shared, "dw")), test_and_set(adr(shared, "dw"))
    (0, 1)
    """
    if not isinstance(flag, Pointer):
        raise TypeError(f"test_and_set needs a pointer (adr(obj, 'flag')), got {type(flag).__name__}")
    acquired_mode = active_profile().test_and_set == "acquired"
    with _TEST_AND_SET_LOCK:
        old: bool | int = flag.deref
        if isinstance(old, bool):
            taken: bool | int = True
        elif type(old) is int:
            taken = 1
        else:
            raise TypeError(
                f"TEST_AND_SET needs a pointer to a BOOL (TwinCAT) or DWORD (CODESYS) variable, got {flag!r}"
            )
        if acquired_mode:
            if old:
                return False
            flag.deref = taken
            return True
        if old != taken:
            flag.deref = taken
        return old


# Its name starts with "test": without this, pytest collects it as a test
# from every test module that imports it.
test_and_set.__test__ = False  # type: ignore[attr-defined]


# ---------------------------------------------------------------------------
# FB_IecCriticalSection
# ---------------------------------------------------------------------------


class _Section:
    """The lock of one CriticalSection instance and the thread that holds it."""

    __slots__ = ("lock", "owner")

    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.owner: int | None = None


# Keyed by the instance's address handle: an FB instance is a memory view, so
# no Python object can live in it, and two views of one instance share the key.
# Handles are never reused, so an entry can never be taken over by another
# instance; each instance that ever entered keeps one small entry.
_SECTIONS: dict[int, _Section] = {}
_SECTIONS_LOCK = threading.Lock()


def _section(instance: Any) -> _Section:
    key = adr(instance).handle
    section = _SECTIONS.get(key)
    if section is None:
        with _SECTIONS_LOCK:
            section = _SECTIONS.setdefault(key, _Section())
    return section


class CriticalSection(FunctionBlock):
    """``FB_IecCriticalSection`` (TwinCAT, Tc2_System): mutual exclusion between tasks.

    ST::

        fbCritical : FB_IecCriticalSection;
        IF fbCritical.Enter() THEN  (* ... *)  fbCritical.Leave(); END_IF

    ``enter()`` blocks the calling thread while another thread holds the
    section, then returns TRUE. A thread that already holds it gets FALSE at
    once instead of deadlocking (so in a single-threaded virtual-time runtime
    a second task entering a held section gets FALSE; a TwinCAT runtime would
    block that task). Waiting threads are served in the order the operating
    system grants the lock, not by task priority as on TwinCAT. ``leave()``
    returns TRUE when the calling thread held the section, else FALSE.

    The lock belongs to the instance (its address), not to the Python view
    of it; a copy made with ``memcpy`` is a different section. Like the rest
    of the instance's state it does not outlive the instance's memory: its
    FB_exit (a reset re-initialising the application, ``delete``, ``stop``)
    releases a section still held, such as one whose holder was stopped by a
    fault between ``enter()`` and ``leave()``.

    >>> section = CriticalSection()
    >>> section.enter(), section.enter()
    (True, False)
    >>> section.leave(), section.leave()
    (True, False)
    """

    @method
    def enter(self) -> BOOL:
        """``Enter()``: TRUE once the section is held by the calling thread."""
        section = _section(self)
        me = threading.get_ident()
        if section.owner == me:
            return False
        section.lock.acquire()
        section.owner = me
        return True

    @method
    def leave(self) -> BOOL:
        """``Leave()``: release the section; FALSE if the calling thread did not hold it."""
        section = _section(self)
        if section.owner != threading.get_ident():
            return False
        section.owner = None
        section.lock.release()
        return True

    def fb_exit(self, in_copy_code: BOOL) -> BOOL:
        """FB_exit: the instance's memory is re-initialised or freed, so a held section is released."""
        if _SECTIONS:
            section = _SECTIONS.get(adr(self).handle)
            with _SECTIONS_LOCK:
                if section is not None and section.owner is not None:
                    section.owner = None
                    section.lock.release()
        return False


# ---------------------------------------------------------------------------
# ExST S= and R=
# ---------------------------------------------------------------------------

def _store(holder: Any, field: str, value: bool, caller: types.FrameType, op: str) -> None:
    current = getattr(holder, field)
    if type(current) is not bool:
        raise TypeError(f"{op}: {type(holder).__name__}.{field} is not a BOOL variable; S= and R= assign BOOL")
    if _config.CHECKS and isinstance(holder, (FunctionBlock, Program)):
        # A POU's checked __setattr__ judges its caller's frame, which here would
        # be this helper; judge the frame that wrote ``x S= cond`` instead.
        check_write(holder, field, caller)
        if current != value:
            object.__setattr__(holder, field, value)
    elif current != value:
        setattr(holder, field, value)


def S(holder: Any, field: str, condition: bool) -> bool:  # noqa: N802 - ST operator name
    """ExST ``x S= condition``: if ``condition`` is TRUE, ``x := TRUE``; returns ``condition``.

    ``holder`` and ``field`` name the BOOL variable (``S(self, "running",
    start)`` is ``running S= start;``). Nothing happens while the condition
    is FALSE, so the variable keeps TRUE once set.

    Chains follow TwinCAT / CODESYS: in ``a S= b R= f(x);`` every assignment
    refers to the operand at the end of the line, so ``a`` is set by ``f(x)``
    and ``b`` is reset by ``f(x)`` (``a`` is *not* set by ``b``). Because S and
    R return their condition, the same line is ``S(self, "a", R(self, "b", f(x)))``.

    >>> from iecoop import BOOL, FunctionBlock, VAR_INPUT, VAR_OUTPUT
    >>> class Motor(FunctionBlock):
    ...     start: BOOL = VAR_INPUT(False)
    ...     stop: BOOL = VAR_INPUT(False)
    ...     running: BOOL = VAR_OUTPUT(False)
    ...     def body(self) -> None:
    ...         S(self, "running", self.start)
    ...         R(self, "running", self.stop)
    >>> motor = Motor()
    >>> motor(start=True); motor(start=False); motor.running
    True
    >>> motor(stop=True); motor.running
    False
    """
    if condition:
        _store(holder, field, True, sys._getframe(1), "S=")
    return condition


def R(holder: Any, field: str, condition: bool) -> bool:  # noqa: N802 - ST operator name
    """ExST ``x R= condition``: if ``condition`` is TRUE, ``x := FALSE``; returns ``condition``.

    See ``S`` for chains: ``a R= b S= c;`` is ``R(self, "a", S(self, "b", c))``,
    both assignments acting on ``c``.

    >>> from iecoop import BOOL, Struct
    >>> class Flags(Struct):
    ...     a: BOOL = True
    ...     b: BOOL = False
    >>> flags = Flags()
    >>> R(flags, "a", S(flags, "b", True))
    True
    >>> flags.a, flags.b
    (False, True)
    """
    if condition:
        _store(holder, field, False, sys._getframe(1), "R=")
    return condition
