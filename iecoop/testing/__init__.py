"""Testing support: a virtual PLC per test, cycle helpers, and hypothesis strategies.

In the spirit of TcUnit, but every test gets fresh instances. Installed as a
pytest plugin, so the ``plc`` fixture (a :class:`VirtualPlc`) is there in any
project that has iecoop: ``def test_x(plc: VirtualPlc) -> None``. The
documentation's page *Testing your function blocks* has a complete test file.

Outside pytest, :class:`VirtualPlc` is a plain class:

>>> from iecoop import BOOL, INT, Program, T, VAR
>>> class Blink(Program):
...     lamp: BOOL = VAR()
...     count: INT = VAR()
...     def body(self) -> None:
...         self.lamp = not self.lamp
...         self.count += 1
>>> plc = VirtualPlc()
>>> blink = plc.add(Blink())
>>> plc.run_cycles(3)
>>> blink.count, blink.lamp, plc.time_ms
(3, True, 30)
>>> plc.run_until(lambda: blink.count == 10)
70
>>> plc.run_until(lambda: blink.count < 0, timeout=T("100ms"))
Traceback (most recent call last):
...
iecoop.testing.RunUntilTimeout: condition <lambda> still false after 100 ms of PLC time (10 base ticks of 10 ms, now t=200 ms)
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar

from iecoop.profiles import Profile
from iecoop.runtime import Runtime, Task

__all__ = ["RunUntilTimeout", "VirtualPlc", "run_cycles", "run_until"]

_P = TypeVar("_P")


class RunUntilTimeout(AssertionError):
    """``run_until`` ran out of PLC time before its condition held (a failed test, not a PLC fault)."""


def run_cycles(runtime: Runtime, n: int) -> None:
    """Run ``n`` base ticks of ``runtime`` in virtual time."""
    runtime.run(cycles=n)


def run_until(runtime: Runtime, condition: Callable[[], object], timeout: int = 10_000) -> int:
    """Run base ticks until ``condition()`` is true; return the PLC time it took, in ms.

    The condition is checked before the first tick and after every tick.
    Raises :class:`RunUntilTimeout` when ``timeout`` ms of PLC time pass first.
    """
    if timeout < 0:
        raise ValueError("timeout must not be negative")
    start = runtime.time_ms
    tick = runtime.base_tick_ms
    ticks = 0
    while not condition():
        if (ticks + 1) * tick > timeout:
            name = getattr(condition, "__name__", repr(condition))
            raise RunUntilTimeout(
                f"condition {name} still false after {timeout} ms of PLC time "
                f"({ticks} base ticks of {tick} ms, now t={runtime.time_ms} ms)"
            )
        runtime.run(cycles=1)
        ticks += 1
    return runtime.time_ms - start


class VirtualPlc:
    """A runtime on virtual time with nothing on disk, and the cycle helpers.

    ``plc.add(program)`` puts a program on a task (``PlcTask``, 10 ms, priority
    20 unless told otherwise) and returns it; ``plc.runtime`` is the
    :class:`~iecoop.runtime.Runtime` for anything else (resets, faults, task info).
    """

    def __init__(self, profile: str | Profile = "twincat") -> None:
        self.runtime = Runtime(store=":memory:", profile=profile)

    def add(self, program: _P, *, task: str = "PlcTask", interval: int = 10, priority: int = 20,
            watchdog: int | None = None) -> _P:
        """Call ``program`` every ``interval`` ms on the task ``task`` (created on first use, with ``watchdog``)."""
        existing = next((t for t in self.runtime.tasks if t.name == task), None)
        if existing is None:
            self.runtime.add_task(Task(task, interval=interval, priority=priority, watchdog=watchdog), program)
        else:
            if existing.interval != interval or existing.priority != priority:
                raise ValueError(
                    f"task {task} already runs every {existing.interval} ms at priority {existing.priority}"
                )
            self.runtime.add_program(task, program)
        return program

    @property
    def time_ms(self) -> int:
        """PLC time since the start, in ms."""
        return self.runtime.time_ms

    def run_cycles(self, n: int) -> None:
        """Run ``n`` base ticks (with one task: ``n`` cycles)."""
        run_cycles(self.runtime, n)

    def run_until(self, condition: Callable[[], object], timeout: int = 10_000) -> int:
        """Run until ``condition()`` holds; return the PLC time it took (ms). See :func:`run_until`."""
        return run_until(self.runtime, condition, timeout)
