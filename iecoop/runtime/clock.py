"""The task clock: where TON, TOF and TP read the current time.

A PLC task samples its clock once per cycle and every timer called in that
cycle sees the same instant. Here a runtime installs its task's clock with
``use_clock(clock)`` around each cycle; ``current_clock()`` returns the one
installed last. Outside a runtime, ``current_clock()`` is ``default_clock()``,
a module-level ``VirtualClock``, so a unit test drives timers by advancing it.

===================  ==========================================================
``VirtualClock``     starts at 0 ns and moves only by ``advance`` / ``set``;
                     deterministic, the default
``WallClock``        ``time.monotonic_ns()`` relative to its creation
===================  ==========================================================

A ``WallClock`` is read at every call, so two timers of one cycle can see
different instants; a runtime that wants the PLC's one instant per cycle
installs a ``VirtualClock`` and sets it from the wall clock at the cycle start.

The installed clocks form one module-level stack, shared by all threads, so
installing one costs a list append. A runtime that runs tasks on several
threads at once needs a clock per thread; that runtime will have to replace
the stack by a thread-local one.

>>> from iecoop import LTIME
>>> clock = default_clock()
>>> clock.set(0)
>>> clock.advance(LTIME("1s500ms"))
>>> now_ms()
1500
>>> with use_clock(VirtualClock(start_ns=LTIME("2s"))):
...     now_ms()
2000
>>> now_ms()
1500
"""

from __future__ import annotations

import abc
import time
from types import TracebackType

__all__ = ["Clock", "VirtualClock", "WallClock", "current_clock", "default_clock", "now_ms", "use_clock"]


class Clock(abc.ABC):
    """A source of the current time in nanoseconds, never decreasing during a run."""

    __slots__ = ()

    @abc.abstractmethod
    def now_ns(self) -> int:
        """The current time in nanoseconds (LTIME resolution)."""

    def now_ms(self) -> int:
        """The current time in milliseconds (TIME resolution), rounded down."""
        return self.now_ns() // 1_000_000


class VirtualClock(Clock):
    """Simulated time: it moves only when told to, so timing tests are exact and instant.

    >>> clock = VirtualClock()
    >>> clock.advance(250_000_000)
    >>> clock.now_ms()
    250
    """

    __slots__ = ("_ns",)

    def __init__(self, start_ns: int = 0) -> None:
        self._ns = 0
        self.set(start_ns)

    def now_ns(self) -> int:
        return self._ns

    def advance(self, ns: int) -> None:
        """Move the clock ``ns`` nanoseconds forward."""
        if ns < 0:
            raise ValueError(f"VirtualClock.advance: time cannot go backwards ({ns} ns)")
        self._ns += ns

    def set(self, ns: int) -> None:
        """Put the clock at ``ns`` nanoseconds.

        For setting up a test: a timer that is running when the clock is set
        backwards sees a huge elapsed time (the difference wraps, as TIME
        arithmetic does on the PLC) and expires.
        """
        if ns < 0:
            raise ValueError(f"VirtualClock.set: time starts at 0, got {ns} ns")
        self._ns = int(ns)

    def __repr__(self) -> str:
        return f"<VirtualClock {self._ns} ns>"


class WallClock(Clock):
    """Real elapsed time, from ``time.monotonic_ns()``, counted from the clock's creation."""

    __slots__ = ("_origin",)

    def __init__(self) -> None:
        self._origin = time.monotonic_ns()

    def now_ns(self) -> int:
        return time.monotonic_ns() - self._origin

    def __repr__(self) -> str:
        return f"<WallClock {self.now_ns()} ns>"


_DEFAULT = VirtualClock()
# The default sits at the bottom and is never popped, so the timers' hot path
# is a plain ``_stack[-1]`` with no emptiness test.
_stack: list[Clock] = [_DEFAULT]


def default_clock() -> VirtualClock:
    """The clock timers read when no runtime has installed one."""
    return _DEFAULT


def current_clock() -> Clock:
    """The clock of the running task, or ``default_clock()`` outside a task cycle."""
    return _stack[-1]


def now_ms() -> int:
    """``current_clock()``'s time in milliseconds (what TON / TOF / TP use)."""
    return _stack[-1].now_ns() // 1_000_000


class use_clock:  # noqa: N801 - used as a function: ``with use_clock(clock):``
    """Install ``clock`` as the current clock inside the ``with`` block.

    Cheap enough to wrap every task cycle: entering appends to a list and
    leaving pops it. Blocks nest; leaving them out of order is an error.
    """

    __slots__ = ("_clock",)

    def __init__(self, clock: Clock) -> None:
        if not isinstance(clock, Clock):
            raise TypeError(f"use_clock needs a Clock, got {type(clock).__name__}")
        self._clock = clock

    def __enter__(self) -> Clock:
        _stack.append(self._clock)
        return self._clock

    def __exit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None
    ) -> None:
        if len(_stack) < 2 or _stack[-1] is not self._clock:
            raise RuntimeError("use_clock blocks were left out of order; the clock stack is inconsistent")
        _stack.pop()
