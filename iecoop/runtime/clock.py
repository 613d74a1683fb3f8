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

Apart from the task clock, a runtime has a *wall*: what it paces real-time
cycles by and measures each cycle's execution time with (``TaskInfo``'s
``LastExecTime``, the watchdog). ``SystemWall`` is the machine's clock;
``ManualWall`` is a wall a test moves by hand, so real-time behaviour (jitter,
overruns, skipped cycles) is checked exactly, whatever the machine's load.

A ``WallClock`` is read at every call, so two timers of one cycle can see
different instants; a runtime that wants the PLC's one instant per cycle
installs a ``VirtualClock`` and sets it from the wall clock at the cycle start.

The installed clock belongs to the thread that installed it: ``task_clock``
is a context variable (``contextvars``), and every thread runs in its own
context, so two runtimes running in two threads each see their own task
clock. Timers read ``task_clock.get()``, as fast as indexing a list. A
thread that never installed a clock reads ``default_clock()``, which all
such threads share.

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
import contextvars
import time
from types import TracebackType

__all__ = [
    "Clock", "ManualWall", "SystemWall", "VirtualClock", "Wall", "WallClock", "current_clock", "default_clock",
    "now_ms", "task_clock", "use_clock",
]


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


class Wall(abc.ABC):
    """The time a runtime paces real-time cycles by and measures cycle execution with.

    ``now_ns()`` never decreases; ``sleep(ns)`` returns when ``now_ns()`` has
    moved at least ``ns`` on (as far as the wall can promise it).
    """

    __slots__ = ()

    @abc.abstractmethod
    def now_ns(self) -> int:
        """The current wall time in nanoseconds (any origin)."""

    @abc.abstractmethod
    def sleep(self, ns: int) -> None:
        """Wait ``ns`` nanoseconds."""


class SystemWall(Wall):
    """The machine's clock: ``time.perf_counter_ns()`` and ``time.sleep`` (a runtime's default wall)."""

    __slots__ = ()

    def now_ns(self) -> int:
        return time.perf_counter_ns()

    def sleep(self, ns: int) -> None:
        time.sleep(ns / 1e9)


class ManualWall(Wall):
    """A wall that moves only when told to: real-time runs checked exactly, on any machine.

    ``sleep(ns)`` moves it ``ns`` on at once (and records the wait in
    ``sleeps``); a program body stands for its execution time with
    ``advance(ns)``.

    >>> from iecoop import DINT, Program, T, VAR
    >>> from iecoop.runtime import Runtime, Task
    >>> wall = ManualWall()
    >>> class Slow(Program):
    ...     n: DINT = VAR()
    ...     def body(self) -> None:
    ...         self.n += 1
    ...         wall.advance(T("15ms") * 1_000_000)   # this cycle executes for 15 ms
    >>> rt = Runtime(store=":memory:", wall=wall)
    >>> rt.add_task(Task("PlcTask", interval=T("10ms")), Slow())
    >>> rt.run(cycles=4, realtime=True)
    >>> info = rt.tasks[0].info
    >>> info.CycleCount, info.SkippedCycles, info.ExceedCounter, info.JitterMax
    (3, 1, 4, 50000)
    """

    __slots__ = ("_ns", "sleeps")

    def __init__(self, start_ns: int = 0) -> None:
        if start_ns < 0:
            raise ValueError(f"ManualWall: time starts at 0, got {start_ns} ns")
        self._ns = start_ns
        #: every wait asked of the wall, in ns, in order
        self.sleeps: list[int] = []

    def now_ns(self) -> int:
        return self._ns

    def advance(self, ns: int) -> None:
        """Move the wall ``ns`` nanoseconds on (the time a body's work takes)."""
        if ns < 0:
            raise ValueError(f"ManualWall.advance: time cannot go backwards ({ns} ns)")
        self._ns += ns

    def sleep(self, ns: int) -> None:
        self.sleeps.append(ns)
        self.advance(max(0, ns))

    def __repr__(self) -> str:
        return f"<ManualWall {self._ns} ns>"


_DEFAULT = VirtualClock()


#: The clock of the task running in the calling thread (``task_clock.get()``); set it with ``use_clock``.
task_clock: contextvars.ContextVar[Clock] = contextvars.ContextVar("iecoop_task_clock", default=_DEFAULT)


def default_clock() -> VirtualClock:
    """The clock timers read when no runtime has installed one."""
    return _DEFAULT


def current_clock() -> Clock:
    """The clock of the task running in this thread, or ``default_clock()`` outside a task cycle."""
    return task_clock.get()


def now_ms() -> int:
    """``current_clock()``'s time in milliseconds (what TON / TOF / TP use)."""
    return task_clock.get().now_ns() // 1_000_000


class use_clock:  # noqa: N801 - used as a function: ``with use_clock(clock):``
    """Install ``clock`` as the calling thread's clock inside the ``with`` block.

    Cheap enough to wrap every task cycle: entering sets the context variable
    and leaving resets it to the clock before. Blocks nest; leaving them out
    of order is an error. Other threads are not affected.
    """

    __slots__ = ("_clock", "_tokens")

    def __init__(self, clock: Clock) -> None:
        if not isinstance(clock, Clock):
            raise TypeError(f"use_clock needs a Clock, got {type(clock).__name__}")
        self._clock = clock
        self._tokens: list[contextvars.Token[Clock]] = []

    def __enter__(self) -> Clock:
        self._tokens.append(task_clock.set(self._clock))
        return self._clock

    def __exit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None
    ) -> None:
        if not self._tokens or task_clock.get() is not self._clock:
            raise RuntimeError("use_clock blocks were left out of order; the clock stack is inconsistent")
        task_clock.reset(self._tokens.pop())
