"""The task watchdog: a thread that stops a cycle running longer than its task allows.

A PLC's watchdog does not wait for the cycle to end: TwinCAT and CODESYS
abort the running cycle and put the PLC into the exception state
(RTSEXCPT_WATCHDOG). Here one thread per runtime, started when the first task
with a watchdog runs, watches the cycle the runtime publishes (``begin`` /
``end``: two attribute writes and an uncontended lock, nothing else per cycle).
When a cycle outlives its deadline the thread raises ``WatchdogInterrupt`` in
the running thread (``PyThreadState_SetAsyncExc``), which CPython delivers at
the next bytecode boundary of pure Python code. A blocking C call
(``time.sleep``, a socket read) is not interrupted: the exception lands when
it returns.

The interrupt derives from ``BaseException`` so that a body's
``except Exception`` cannot swallow it, and is sent again while the cycle goes
on; the runtime turns it into the PlcException fault. It never lands after
the cycle: ``end`` retires the cycle under the lock the thread fires under and
cancels a delivery still pending.
"""

from __future__ import annotations

import ctypes
import threading

from iecoop.runtime.clock import Wall

__all__ = ["Watchdog", "WatchdogInterrupt"]

# One C function, two prototypes: with an exception class it raises it in the thread, with NULL it
# clears a pending one.
_set_async_exc = ctypes.PYFUNCTYPE(ctypes.c_int, ctypes.c_ulong, ctypes.py_object)(
    ("PyThreadState_SetAsyncExc", ctypes.pythonapi)
)
_cancel_async_exc = ctypes.PYFUNCTYPE(ctypes.c_int, ctypes.c_ulong, ctypes.c_void_p)(
    ("PyThreadState_SetAsyncExc", ctypes.pythonapi)
)


class WatchdogInterrupt(BaseException):
    """Raised inside a cycle by the watchdog; the runtime turns it into RTSEXCPT_WATCHDOG.

    A BaseException, so ``except Exception`` in a body does not swallow it.
    """


class _Cycle:
    """The cycle being watched: which thread runs it, and when it must have ended (wall ns)."""

    __slots__ = ("thread_id", "deadline_ns", "fired", "ended")

    def __init__(self, thread_id: int, deadline_ns: int) -> None:
        self.thread_id = thread_id
        self.deadline_ns = deadline_ns
        self.fired = False
        #: set by the running thread when the cycle's code is done (an attribute store: no call, so
        #: no interrupt can be delivered while setting it); the thread fires no more from then on
        self.ended = False


class Watchdog:
    """One runtime's watchdog thread.

    The thread holds this object only, never the runtime, so a runtime that is
    dropped is collected and its finaliser (or ``Runtime.stop``) calls
    ``close``, which ends the thread.
    """

    def __init__(self, wall: Wall) -> None:
        self._wall = wall
        self._lock = threading.Lock()
        self._wake = threading.Event()
        self._closed = False
        self._cycle: _Cycle | None = None
        #: how long the thread waits between looks while no cycle is running (ns), set by ``begin``
        self._idle_ns = 10_000_000
        self._thread: threading.Thread | None = None

    def begin(self, limit_ns: int) -> _Cycle:
        """Watch the cycle the calling thread is about to run, for at most ``limit_ns`` of wall time."""
        if self._thread is None:
            self._start()
        self._idle_ns = min(self._idle_ns, max(limit_ns // 4, 1_000_000))
        cycle = _Cycle(threading.get_ident(), self._wall.now_ns() + limit_ns)
        self._cycle = cycle
        return cycle

    def end(self, cycle: _Cycle) -> bool:
        """Stop watching ``cycle``; True if the watchdog fired in it. Call until it returns (it may be interrupted)."""
        cycle.ended = True
        self._cycle = None
        with self._lock:
            # A delivery the thread made before the line above is still pending: cancel it.
            if cycle.fired:
                _cancel_async_exc(cycle.thread_id, None)
        return cycle.fired

    def _start(self) -> None:
        thread = threading.Thread(target=self._watch, name="iecoop watchdog", daemon=True)
        self._thread = thread
        thread.start()

    def close(self) -> None:
        """End the thread (waits for it); the watchdog can be started again by ``begin``."""
        self._closed = True
        self._wake.set()
        thread, self._thread = self._thread, None
        if thread is not None and thread is not threading.current_thread():
            thread.join()
        self._closed = False
        self._wake.clear()

    def _watch(self) -> None:
        while not self._closed:
            cycle = self._cycle
            if cycle is None:
                self._wake.wait(self._idle_ns / 1e9)
                continue
            remaining = cycle.deadline_ns - self._wall.now_ns()
            if remaining > 0:
                # Never longer than the idle wait: a manual wall may jump past the deadline at any time.
                self._wake.wait(min(remaining, self._idle_ns) / 1e9)
                continue
            with self._lock:
                if self._cycle is cycle and not cycle.ended:
                    cycle.fired = True
                    _set_async_exc(cycle.thread_id, WatchdogInterrupt)
            # Again and again while the cycle goes on: a body catching BaseException gets it next time.
            self._wake.wait(self._idle_ns / 1e9)

