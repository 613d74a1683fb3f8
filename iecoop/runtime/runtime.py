"""The cyclic runtime: tasks, virtual time, faults, resets and remanent data.

A ``Runtime`` holds tasks; each task calls its programs in order every cycle.
Virtual time is the default: the clock jumps from one task tick to the next,
so timing logic is exact, deterministic and runs as fast as the CPU allows.
``realtime=True`` paces the cycles by the wall clock and counts jitter,
overruns and skipped cycles. A task's watchdog stops a cycle that runs too
long, in either mode.

At each tick the due tasks run in priority order (0 is the highest). At the
end of every tick the RETAIN image is captured into the store; PERSISTENT
data is written by ``stop()`` and ``save_persistent()``. A fault in a cycle
puts the runtime into an exception state that ``run()`` raises until a reset.

>>> from iecoop import BOOL, INT, Program, T, VAR
>>> from iecoop.runtime import Runtime, Task
>>> class Main(Program):
...     count: INT = VAR(0)
...     def body(self) -> None:
...         self.count += 1
>>> main = Main()
>>> rt = Runtime(store=":memory:")
>>> rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), main)
>>> rt.run(cycles=5)
>>> main.count, rt.time_ms
(5, 50)
"""

from __future__ import annotations

import contextlib
import contextvars
import dataclasses
import math
import os
import threading
import time
import traceback
import typing
import weakref
from pathlib import Path
from collections.abc import Callable
from typing import Any, Literal

from iecoop.exceptions import ExceptionCode, PlcException, SourceLocation, location_of
from iecoop.gvl import global_lists
from iecoop.lifecycle import finalise, initialise
from iecoop.pou import static_blocks
from iecoop.profiles import Profile, get_profile, use_profile
from iecoop.runtime.clock import SystemWall, VirtualClock, Wall, use_clock
from iecoop.runtime.background import Background
from iecoop.runtime.online import OnlineTable, Symbol, resolve_symbol, symbol_roots
from iecoop.runtime.store import ImageLayout, RemanentStore
from iecoop.runtime.trace import DEFAULT_TRACE_SIZE, Trace
from iecoop.runtime.variables import PERSISTENT, RETAIN
from iecoop.runtime import remanence, resets
from iecoop.runtime.remanence import Entry
from iecoop.runtime.watchdog import Watchdog, WatchdogInterrupt
from iecoop.metadata import Kind, kind_of, st_name

__all__ = ["Fault", "Runtime", "Task", "TaskInfo", "current_task"]


@dataclasses.dataclass
class TaskInfo:
    """What the PLC reports about a task (TwinCAT ``_TaskInfo`` / ``PlcTaskSystemInfo``).

    Times are in 100 ns units, as TwinCAT reports them. ``ExceedCounter``
    counts the cycles that were not on time: every cycle that executed longer
    than the task's interval, and (in real time) every cycle that never ran
    because the task was still busy or the runtime started late, which are
    also counted alone in ``SkippedCycles``. ``CycleTimeExceeded`` says
    whether the last cycle ran longer than the interval or came after skipped
    ones.
    """

    TaskName: str
    CycleTime: int
    Priority: int
    CycleCount: int = 0
    FirstCycle: bool = True
    CycleTimeExceeded: bool = False
    ExceedCounter: int = 0
    LastExecTime: int = 0
    MaxExecTime: int = 0
    JitterMax: int = 0
    WatchdogHits: int = 0
    SkippedCycles: int = 0


class Task:
    """A cyclic task: ``Task("PlcTask", interval=T("10ms"), priority=20)``.

    ``watchdog`` (a TIME) with ``sensitivity`` faults the task with
    RTSEXCPT_WATCHDOG when ``sensitivity`` consecutive cycles execute longer
    than the watchdog time, and stops a running cycle that reaches that
    fault: one that has run ``watchdog × sensitivity`` (CODESYS's single
    timeout rule; TwinCAT's sensitivity 1: the watchdog time), or the
    watchdog time when the cycles before it already overran
    ``sensitivity - 1`` times. Execution time is wall time, in real and
    virtual time alike.
    """

    def __init__(
        self,
        name: str,
        interval: int = 10,
        priority: int = 20,
        *,
        watchdog: int | None = None,
        sensitivity: int = 1,
    ) -> None:
        if not isinstance(interval, int) or isinstance(interval, bool) or interval <= 0:
            raise ValueError(f"task {name}: the interval is a positive TIME in ms, got {interval!r}")
        if not isinstance(priority, int) or not 0 <= priority <= 31:
            raise ValueError(f"task {name}: priority must be 0..31 (0 is the highest), got {priority!r}")
        if watchdog is not None and watchdog <= 0:
            raise ValueError(f"task {name}: the watchdog time must be positive")
        self.name = name
        self.interval = interval
        self.priority = priority
        self.watchdog = watchdog
        self.sensitivity = max(1, sensitivity)
        self._programs: tuple[tuple[str, Any], ...] = ()
        #: what a cycle calls, one per program (set with ``programs``, so the two never disagree)
        self._steps: list[typing.Callable[[], object]] = []
        self.info = TaskInfo(name, interval * 10_000, priority)
        self._overruns = 0
        #: ticks of this task were skipped since its last cycle (the next one is late)
        self._late = False

    def __repr__(self) -> str:
        return f"<Task {self.name} {self.interval} ms prio {self.priority}>"

    @property
    def programs(self) -> tuple[tuple[str, Any], ...]:
        """The (path, program) pairs the task calls, in order; ``Runtime.add_program`` adds one."""
        return self._programs

    def _set_programs(self, programs: typing.Iterable[tuple[str, Any]]) -> None:
        self._programs = tuple(programs)
        self._steps = [_step(program) for _, program in self._programs]


def _step(program: Any) -> typing.Callable[[], object]:
    """What a cycle calls for ``program``: its body, after re-initialising its VAR_TEMP if it has any.

    A task's call is a call of the POU, and every call starts with fresh VAR_TEMP
    (IEC 61131-3; TwinCAT and CODESYS alike). A program without VAR_TEMP is its
    bound body, so the cycle costs what it did.
    """
    cls = type(program)
    built = getattr(cls, "_iec_built_call_", None)
    if built is not None and cls.__call__ is built and getattr(cls, "_iec_task_call_", False) and (
        "body" not in getattr(program, "__dict__", {})
    ):
        # The POU's own call resets VAR_TEMP and runs the body compiled into it (one frame, and the
        # body's own reads and writes take the paths its class decided when it was built).
        return typing.cast(typing.Callable[[], object], program.__call__)
    body = program.body
    reset = getattr(cls, "_iec_temp_reset_", None)
    if reset is None:
        return typing.cast(typing.Callable[[], object], body)

    def step() -> None:
        reset(program)
        body()

    return step


def _skip(tasks: typing.Iterable[Task], first: int, resume: int, tick_ms: int) -> None:
    """Count, per task, its cycles on the base ticks ``first`` .. ``resume - 1`` that will never run."""
    for task in tasks:
        every = task.interval // tick_ms
        # the multiples of ``every`` in [first, resume)
        missed = (resume - 1) // every - (first - 1) // every
        if missed:
            info = task.info
            info.SkippedCycles += missed
            info.ExceedCounter += missed
            info.CycleTimeExceeded = True
            task._late = True


@dataclasses.dataclass(frozen=True)
class Fault:
    """The exception state: which task and cycle failed, with what code and traceback.

    ``operation`` is empty for a fault in a cycle; for a reset or download
    whose FB_init / FB_exit raised, it names the operation (``"reset_cold"``)
    and ``task`` is the instance path of the block that raised.
    """

    task: str
    #: the task's cycle that failed, counted from 1 as its CycleCount counts cycles (0: a reset or download)
    cycle: int
    code: ExceptionCode
    message: str
    traceback: str
    exception: PlcException
    operation: str = ""
    #: where in loaded Structured Text the fault arose (file, line, POU, member); None outside loaded ST
    location: SourceLocation | None = None


# The task running in the calling thread (each thread has its own context).
_current: contextvars.ContextVar[Task | None] = contextvars.ContextVar("iecoop_current_task", default=None)


def current_task() -> TaskInfo:
    """The running task's info (ST: ``_TaskInfo[GETCURTASKINDEXEX()]``)."""
    task = _current.get()
    if task is None:
        raise RuntimeError("no task is running: current_task() is for code called by a Runtime cycle")
    return task.info


def _fault_code(exc: BaseException) -> ExceptionCode:
    if isinstance(exc, PlcException):
        return exc.code
    if isinstance(exc, ZeroDivisionError):
        return ExceptionCode.RTSEXCPT_DIVIDEBYZERO
    if isinstance(exc, RecursionError):
        return ExceptionCode.RTSEXCPT_STACK_OVERFLOW
    if isinstance(exc, MemoryError):
        return ExceptionCode.RTSEXCPT_OUT_OF_MEMORY
    return ExceptionCode.RTSEXCPT_UNKNOWN




class Runtime:
    """A PLC runtime: tasks, virtual (or real) time, remanent store, resets.

    ``store`` is a folder for RETAIN / PERSISTENT data (default ``./.iecoop``);
    ``":memory:"`` keeps nothing on disk. ``profile`` is ``"twincat"``
    (default) or ``"codesys"``.

    A Runtime runs in one thread at a time; its clock and profile are
    installed in the thread running it, so runtimes in different threads are
    independent. Its store is locked while open: one Runtime per store.
    ``wall`` is what real time is paced by and execution measured with
    (default ``SystemWall()``; a test passes a ``ManualWall``).

    The application is the programs on its tasks plus the process's global
    data: every GVL (``@gvl``) and every VAR_STAT block. Resets re-initialise
    all of it per the vendor table, and RETAIN / PERSISTENT variables of a GVL
    are stored and restored by path (``GVL_Plant.counter``) like a program's.
    """

    def __init__(
        self,
        store: str | os.PathLike[str] | None = None,
        profile: str | Profile = "twincat",
        *,
        durability: Literal["process", "power"] = "process",
        wall: Wall | None = None,
    ) -> None:
        if wall is not None and not isinstance(wall, Wall):
            raise TypeError(f"Runtime: wall must be a Wall (SystemWall, ManualWall), got {type(wall).__name__}")
        #: what real-time cycles are paced by and execution times measured with (``ManualWall`` in tests)
        self.wall: Wall = SystemWall() if wall is None else wall
        # The machine's clock is read directly: no method call per cycle for it.
        self._now: Callable[[], int] = time.perf_counter_ns if type(self.wall) is SystemWall else self.wall.now_ns
        self._watchdog: Watchdog | None = None
        self.profile = get_profile(profile)
        self.tasks: list[Task] = []
        self._entries: list[Entry] = []
        self._globals: list[Entry] = []
        self._globals_key: tuple[int, ...] = ()
        self.time_ns = 0
        self.fault: Fault | None = None
        self._clock = VirtualClock()
        self._store_path = None if store == ":memory:" else Path(store if store is not None else ".iecoop")
        self._durability = durability
        self._store: RemanentStore | None = None
        self._started = False
        self._stopped = False
        self._retain_plan: tuple[ImageLayout, list[Any]] | None = None
        self._tick = 0
        self.boot_report: list[str] = []
        # One thread at a time: the thread running run() / a reset, set under the lock.
        self._busy_lock = threading.Lock()
        self._busy: tuple[int, str, str] | None = None
        #: Called in the PLC's thread before / after the tasks of each base tick: a plant model
        #: reads the outputs and sets the inputs in ``on_cycle_end`` (see ``running``); an OPC UA
        #: server's writes go in before, its consistent image of the cycle is taken after.
        self.on_cycle_start: list[Callable[[], None]] = []
        self.on_cycle_end: list[Callable[[], None]] = []
        # Few attributes, grouped: an instance with more than 30 loses CPython's fast attribute
        # reads, and every cycle reads a dozen of them.
        self._online = OnlineTable()
        self._background = Background()

    # -- configuration -----------------------------------------------------

    def add_task(self, task: Task, *programs: Any) -> None:
        """Add a task and the program instances it calls each cycle, in order."""
        if any(t.name == task.name for t in self.tasks):
            raise ValueError(f"a task named {task.name!r} already exists")
        if not programs:
            raise ValueError(f"task {task.name}: give at least one program instance")
        self._check_programs(task, programs)
        self._attach(task, programs)
        self.tasks.append(task)
        self.tasks.sort(key=lambda t: t.priority)

    def add_program(self, task: str, *programs: Any) -> None:
        """Append program instances to the task named ``task``; they run after its current ones."""
        found = next((t for t in self.tasks if t.name == task), None)
        if found is None:
            raise ValueError(f"no task named {task!r}; add it with add_task()")
        self._check_programs(found, programs)
        self._attach(found, programs)

    @staticmethod
    def _check_programs(task: Task, programs: tuple[Any, ...]) -> None:
        # All or nothing: a rejected call registers none of its programs.
        for program in programs:
            if kind_of(type(program)) not in (Kind.FUNCTION_BLOCK, Kind.PROGRAM):
                raise TypeError(f"task {task.name}: {program!r} is not a Program instance")

    def _attach(self, task: Task, programs: tuple[Any, ...]) -> None:
        for program in programs:
            base = f"{task.name}.{st_name(type(program))}"  # the instance path names the PROGRAM in ST
            path = base
            n = 2
            while any(e.path == path for e in self._entries):
                path = f"{base}_{n}"
                n += 1
            entry = Entry(path, program)
            self._entries.append(entry)
            task._set_programs([*task.programs, (path, program)])
        self._retain_plan = None

    def _global_entries(self) -> list[Entry]:
        """The application's global data: every GVL (path: its name) and VAR_STAT block (``Class.VAR_STAT``)."""
        current = [(name, block) for name, block in global_lists().items()]
        current += [(f"{cls.__qualname__}.VAR_STAT", block) for cls, block in static_blocks()]
        key = tuple(id(block) for _, block in current)
        if key != self._globals_key:
            self._globals_key = key
            self._globals = [Entry(path, block) for path, block in current]
            self._retain_plan = None
        return self._globals

    def _all_entries(self) -> list[Entry]:
        return self._entries + self._global_entries()

    def programs(self) -> dict[str, Any]:
        """Every program instance by instance path (``"PlcTask.Main"``)."""
        return {e.path: e.program for e in self._entries}

    @property
    def time_ms(self) -> int:
        return self.time_ns // 1_000_000

    @property
    def base_tick_ms(self) -> int:
        if not self.tasks:
            raise RuntimeError("the runtime has no task; add one with add_task()")
        return math.gcd(*(t.interval for t in self.tasks))

    # -- running -------------------------------------------------------------

    def run(
        self, cycles: int | None = None, duration: int | None = None, *, realtime: bool = False,
        progress: Callable[[int, int], object] | None = None, progress_every: int = 1000,
    ) -> None:
        """Run ``cycles`` base ticks, or for ``duration`` (a TIME in ms) of PLC time.

        The base tick is the greatest common divisor of the task intervals, so
        with one task a tick is one cycle. At each tick the due tasks run in
        priority order; the task clock (what TON / TOF / TP read) is the
        cycle's start.

        ``realtime=True`` paces the ticks by the runtime's ``wall``: a cycle
        never starts before its tick, the lateness is the task's jitter
        (``TaskInfo.JitterMax``) and is part of the task clock, and a cycle
        that starts a whole tick late or more (an overrun before it, a busy
        machine) makes the PLC skip the ticks it missed rather than run them
        back to back: each task's cycles on those ticks are counted in
        ``SkippedCycles`` and ``ExceedCounter`` and set ``CycleTimeExceeded``.
        Tasks run one after the other in the calling thread (``start()`` /
        ``running()`` run them in a background thread instead).

        ``progress(cycles_done, cycles_total)`` is called after every
        ``progress_every`` base ticks and once at the end (a run without end,
        in the background, passes 0 as the total); without it the loop costs
        what it did.

        A task with a ``watchdog`` is watched by a thread of the runtime that
        stops a cycle running too long (see ``Task``), in real and virtual
        time: the task faults with RTSEXCPT_WATCHDOG and ``run()`` raises it.

        A Runtime runs in one thread at a time: ``run()`` from a second thread
        while it runs, or from inside a cycle (a body calling ``rt.run()``),
        raises RuntimeError. Its clock and profile are installed in the
        calling thread only, so runtimes in different threads are independent.
        """
        self._raise_if_faulted()
        self._check_not_stopped("run")
        if (cycles is None) == (duration is None):
            raise ValueError("run() takes either cycles= or duration=")
        total = self._cycle_count("run", cycles, duration, progress_every)
        assert total is not None
        with self._exclusive("run"):
            self._run(total, self.base_tick_ms, realtime, progress, progress_every)

    def _cycle_count(self, operation: str, cycles: int | None, duration: int | None, every: int) -> int | None:
        """How many base ticks ``cycles`` or ``duration`` (ms) make, checked; None: no end."""
        if cycles is not None and duration is not None:
            raise ValueError(f"{operation}() takes either cycles= or duration=")
        if not isinstance(every, int) or every < 1:
            raise ValueError(f"{operation}(): progress_every is a number of cycles >= 1, got {every!r}")
        tick_ms = self.base_tick_ms
        if duration is not None:
            if duration < 0:
                raise ValueError("duration must not be negative")
            cycles = duration // tick_ms
        if cycles is not None and cycles < 0:
            raise ValueError("cycles must not be negative")
        return cycles

    def _run(self, cycles: int | None, tick_ms: int, realtime: bool,
             progress: Callable[[int, int], object] | None = None, progress_every: int = 1000,
             halt: threading.Event | None = None) -> None:
        """Run ``cycles`` base ticks (None: until ``halt`` is set)."""
        if not self._started:
            self._start()
        tick_ns = tick_ms * 1_000_000
        end_tick: float = math.inf if cycles is None else self._tick + cycles
        # The progress callback's count and total (0: a run without end).
        total = 0 if cycles is None else cycles
        report = self._tick + progress_every
        wall = self.wall
        wall_start = wall.now_ns()
        first_tick = self._tick
        # One test per cycle when there is nothing to watch: the plain run() costs what it did.
        watched = halt is not None or progress is not None
        online = self._online
        with use_profile(self.profile), use_clock(self._clock):
            while self._tick < end_tick:
                if watched:
                    if halt is not None and halt.is_set():
                        break
                    if progress is not None and self._tick >= report:
                        report = self._tick + progress_every
                        progress(self._tick - first_tick, total)
                tick_time = self._tick * tick_ns
                jitter = 0
                if realtime:
                    planned = wall_start + (self._tick - first_tick) * tick_ns
                    delay = planned - wall.now_ns()
                    if delay > 0:
                        wall.sleep(delay)
                    late = wall.now_ns() - planned
                    if late >= tick_ns:
                        # Late by a tick or more: like the PLC, start at the next tick boundary
                        # instead of running the missed cycles back to back, and count them.
                        resume = int(min(self._tick + late // tick_ns, end_tick))
                        _skip(self.tasks, self._tick, resume, tick_ms)
                        self._tick = resume
                        continue
                    jitter = max(0, late)
                # The task clock is the cycle's start, so every timer in the cycle
                # reads the same time (in real time, the actual start, jitter included).
                self._clock.set(tick_time + jitter)
                self.time_ns = tick_time
                for hook in self.on_cycle_start:
                    hook()
                if online.active:
                    online.apply()
                self._run_tick(tick_ms, jitter)
                if online.active:
                    # A forced variable holds its value after the code too, as the outputs are written.
                    online.hold()
                self._tick += 1
                for hook in self.on_cycle_end:
                    hook()
            self.time_ns = self._tick * tick_ns
            self._clock.set(self.time_ns)
        if progress is not None:
            progress(self._tick - first_tick, total)

    # -- in the background ------------------------------------------------------

    def start(
        self, cycles: int | None = None, duration: int | None = None, *, realtime: bool = True,
        progress: Callable[[int, int], object] | None = None, progress_every: int = 1000,
    ) -> None:
        """Run the tasks in a background (daemon) thread until ``stop_running()``, or for ``cycles`` / ``duration``.

        ``realtime=False`` runs virtual time as fast as the CPU allows. A fault
        ends the thread: ``fault`` shows it, ``stop_running()`` raises it.
        Meanwhile ``run()`` and the resets raise RuntimeError; ``stop()`` ends
        the background run first.
        """
        self._raise_if_faulted()
        self._check_not_stopped("start")
        if self._background.thread is not None:
            raise RuntimeError("Runtime.start(): it already runs in the background; call stop_running() first")
        total = self._cycle_count("start", cycles, duration, progress_every)
        tick_ms = self.base_tick_ms
        self._background.start(
            f"iecoop-runtime-{id(self):x}",
            lambda: self._exclusive("run"),
            lambda halt: self._run(total, tick_ms, realtime, progress, progress_every, halt),
        )

    @property
    def is_running(self) -> bool:
        """True while a background run's thread is alive (it ends at its last cycle, a fault or a stop)."""
        return self._background.alive

    def join(self, timeout: float | None = None) -> bool:
        """Wait for a background run to end by itself (its cycles done, or a fault); True if it has ended."""
        return self._background.join(timeout)

    def stop_running(self) -> None:
        """End the background run after its current cycle, join its thread, and raise what ended it.

        A fault is raised as its PlcException (``fault`` keeps it until a reset).
        """
        error = self._background.stop()
        if error is not None:
            raise error

    @contextlib.contextmanager
    def running(
        self, cycles: int | None = None, duration: int | None = None, *, realtime: bool = True,
        progress: Callable[[int, int], object] | None = None, progress_every: int = 1000,
    ) -> typing.Iterator[Runtime]:
        """``with rt.running():`` runs the tasks in the background for the block; its end is ``stop_running()``.

        If the block raises, that exception goes on (a fault stays in ``fault``).
        """
        self.start(cycles, duration, realtime=realtime, progress=progress, progress_every=progress_every)
        try:
            yield self
        except BaseException:
            with contextlib.suppress(BaseException):
                self.stop_running()
            raise
        self.stop_running()

    # -- online write, force and trace by symbol path --------------------------------

    def symbol(self, path: str | Symbol) -> Symbol:
        """The variable at a TwinCAT symbol path (``MAIN.fbStation.nBottles``, ``GVL_IO.bStart``), resolved once.

        ``load()`` reads it, ``store(value)`` writes it at once (from a hook);
        AccessError names a path that names no elementary variable. A Symbol
        is taken as it is, by this method and by ``write``, ``force`` and ``release``.
        """
        return path if isinstance(path, Symbol) else resolve_symbol(symbol_roots(self.tasks), path)

    def write(self, path: str | Symbol, value: Any) -> None:
        """Write ``value`` once, at the next cycle start (TwinCAT's online *Write values*, Ctrl+F7).

        Any variable can be written, inputs, outputs and internals alike, from
        any thread; the path and the value are checked here, at the call.
        """
        self._check_not_stopped("write")
        symbol = self.symbol(path)
        symbol.check(value)
        self._online.write(symbol, value)

    def force(self, path: str | Symbol, value: Any) -> None:
        """Hold ``value`` in the variable until ``release`` (TwinCAT's *Force values*, F7).

        Set at every cycle start (after ``on_cycle_start``) and again after the
        code, so the code and every reader between cycles see it.
        """
        self._check_not_stopped("force")
        symbol = self.symbol(path)
        symbol.check(value)
        self._online.force(symbol, value)

    def release(self, path: str | Symbol, *, restore: bool = False) -> None:
        """Stop forcing ``path``: from the next cycle the code's own assignments hold (TwinCAT: Alt+F7).

        The variable keeps the forced value (*Unforce*) until something
        assigns it; ``restore=True`` writes back, at the next cycle start, the
        value it had before its first forced cycle (*Unforce and restore*).
        """
        self._online.release(self.symbol(path), restore)

    def release_all(self, *, restore: bool = False) -> None:
        """Stop forcing every variable (``restore`` as in ``release``)."""
        self._online.release_all(restore)

    @property
    def forced(self) -> dict[str, Any]:
        """The forced variables: path -> value."""
        return self._online.forced()

    def trace(self, paths: typing.Sequence[str], every: int = 1, size: int = DEFAULT_TRACE_SIZE,
              file: str | os.PathLike[str] | typing.TextIO | None = None) -> Trace:
        """Record ``paths`` after every ``every``-th cycle into a ring buffer of ``size`` rows (and to ``file``).

        The trace is a hook on ``on_cycle_end``; ``trace.detach()`` removes it
        and ends a stream to ``file``.
        """
        found = Trace(paths, self.symbol, stamp=lambda: (self._tick, self.time_ms), online=self._online,
                      hooks=self.on_cycle_end, every=every, size=size, file=file)
        self.on_cycle_end.append(found._sample)
        return found

    def _run_tick(self, tick_ms: int, jitter: int) -> None:
        now_ms = self._tick * tick_ms
        now = self._now
        for task in self.tasks:
            if now_ms % task.interval:
                continue
            info = task.info
            info.JitterMax = max(info.JitterMax, jitter // 100)
            info.FirstCycle = info.CycleCount == 0
            interrupt: WatchdogInterrupt | None = None
            started = now()
            token = _current.set(task)
            try:
                if task.watchdog is None:
                    for step in task._steps:
                        step()
                else:
                    interrupt = self._watched_steps(task)
            except BaseException as exc:
                if isinstance(exc, (KeyboardInterrupt, SystemExit)):
                    raise
                self._enter_fault(task, exc)
            finally:
                _current.reset(token)
            elapsed = now() - started
            info.LastExecTime = elapsed // 100
            info.MaxExecTime = max(info.MaxExecTime, info.LastExecTime)
            info.CycleCount += 1
            # Cycles are numbered as the task counts them: the first is cycle 1 (CycleCount once it has run).
            cycle = info.CycleCount
            exceeded = elapsed > task.interval * 1_000_000
            info.CycleTimeExceeded = exceeded or task._late
            task._late = False
            if exceeded:
                info.ExceedCounter += 1
            if task.watchdog is not None:
                self._check_watchdog(task, cycle, elapsed, interrupt)
        self._capture_retain()

    def _watched_steps(self, task: Task) -> WatchdogInterrupt | None:
        """Run ``task``'s programs under the watchdog; the interrupt if it stopped them (or fired in them)."""
        watchdog = self._watchdog
        if watchdog is None:
            watchdog = self._watchdog = Watchdog(self.wall)
            # The thread ends with the runtime, also when nobody calls stop().
            weakref.finalize(self, watchdog.close)
        assert task.watchdog is not None
        cycle = watchdog.begin(task.watchdog * 1_000_000 * (task.sensitivity - task._overruns))
        interrupt: WatchdogInterrupt | None = None
        try:
            for step in task._steps:
                step()
        except WatchdogInterrupt as exc:
            interrupt = exc
        finally:
            # CPython delivers the interrupt at calls and loops only: from this store on the thread
            # fires no more, the one delivery still possible lands inside the ``try`` below, and
            # ``end`` cancels it if it is still pending. An interrupt lands in its cycle or nowhere.
            cycle.ended = True
            while True:
                try:
                    fired = watchdog.end(cycle)
                    break
                except WatchdogInterrupt as exc:
                    interrupt = exc
        if fired and interrupt is None:
            # A body that caught the interrupt and ended anyway: the watchdog stopped it all the same.
            interrupt = WatchdogInterrupt()
        return interrupt

    def _check_watchdog(self, task: Task, cycle: int, elapsed: int, interrupt: WatchdogInterrupt | None) -> None:
        """Fault ``task`` if its watchdog stopped the cycle or ``sensitivity`` cycles in a row overran it."""
        assert task.watchdog is not None
        if interrupt is None and elapsed <= task.watchdog * 1_000_000:
            task._overruns = 0
            return
        task._overruns += 1
        if interrupt is None and task._overruns < task.sensitivity:
            return
        task.info.WatchdogHits += 1
        limit = f"watchdog {task.watchdog} ms"
        if task.sensitivity > 1:
            limit += f", sensitivity {task.sensitivity}"
        done = "took" if interrupt is None else "stopped by the watchdog after"
        fault = PlcException(
            ExceptionCode.RTSEXCPT_WATCHDOG, f"task {task.name}: cycle {cycle} {done} {elapsed / 1e6:.3f} ms, {limit}"
        )
        # The interrupt's traceback shows where the cycle was when it was stopped.
        fault.__cause__ = interrupt
        self._enter_fault(task, fault, cycle)

    def _enter_fault(self, task: Task, exc: BaseException, cycle: int | None = None) -> typing.NoReturn:
        code = _fault_code(exc)
        location = location_of(exc)
        plc = exc if isinstance(exc, PlcException) else PlcException(code, f"{type(exc).__name__}: {exc}", location)
        text = "".join(traceback.format_exception(exc))
        where = task.info.CycleCount + 1 if cycle is None else cycle  # the cycle that failed is not counted yet
        self.fault = Fault(task.name, where, code, str(plc), text, plc, location=location)
        raise self._fault_error() from exc

    def _fault_error(self) -> PlcException:
        assert self.fault is not None
        f = self.fault
        at = f" at {f.location}" if f.location is not None else ""
        if f.operation:
            return PlcException(f.code, f"{f.operation} failed at {f.task}{at}: {f.message}; the runtime stays "
                                        f"in the exception state until a reset succeeds", f.location)
        return PlcException(f.code, f"task {f.task} stopped in cycle {f.cycle}{at}: {f.message}", f.location)

    def _raise_if_faulted(self) -> None:
        if self.fault is not None:
            raise self._fault_error()

    # -- one thread at a time, nothing after stop() --------------------------------

    @contextlib.contextmanager
    def _exclusive(self, operation: str) -> typing.Iterator[None]:
        """Hold the runtime for ``operation``: another thread, or a cycle calling back in, gets RuntimeError."""
        me = threading.current_thread()
        with self._busy_lock:
            busy = self._busy
            if busy is None:
                self._busy = (me.ident or 0, me.name, operation)
        if busy is not None:
            ident, name, running = busy
            if ident == me.ident:
                raise RuntimeError(
                    f"Runtime.{operation}() called from inside {running}() (a program body calling the runtime): "
                    f"cycles do not nest; a Runtime runs one operation at a time"
                )
            raise RuntimeError(
                f"Runtime.{operation}() called from thread {me.name!r} while thread {name!r} is in {running}(): "
                f"a Runtime runs in one thread at a time"
            )
        try:
            yield
        finally:
            self._busy = None

    def _check_not_stopped(self, operation: str) -> None:
        if self._stopped:
            raise RuntimeError(
                f"Runtime.{operation}(): the runtime was stopped; create a new Runtime on the same store "
                f"to start again (stop() ran FB_exit and closed the store)"
            )

    # -- remanent data (iecoop.runtime.remanence) ----------------------------------

    def _start(self) -> None:
        remanence.start(self)

    def _capture_retain(self) -> None:
        remanence.capture_retain(self)

    def save_persistent(self) -> None:
        """Write the PERSISTENT image now (TwinCAT ``FB_WritePersistentData``)."""
        remanence.save_persistent(self)

    def stop(self) -> None:
        """Orderly shutdown: end the watchdog thread, write PERSISTENT data, run FB_exit, close the store.

        A second ``stop()`` does nothing; every other operation after it
        raises RuntimeError.
        """
        if self._stopped:
            return
        # The PLC STOP ends a background run first; a fault that ended it stays in ``fault``.
        self._background.stop()
        with self._exclusive("stop"):
            if self._watchdog is not None:
                self._watchdog.close()
            self.save_persistent()
            try:
                with use_profile(self.profile), use_clock(self._clock):
                    for entry in self._all_entries():
                        finalise(entry.program, in_copy_code=False)
            finally:
                self._stopped = True
                if self._store is not None:
                    self._store.close()

    # -- resets, download, online change (iecoop.runtime.resets) ----------------------

    def _enter_operation_fault(self, operation: str, path: str, exc: BaseException) -> typing.NoReturn:
        code = _fault_code(exc)
        location = location_of(exc)
        plc = exc if isinstance(exc, PlcException) else PlcException(code, f"{type(exc).__name__}: {exc}", location)
        text = "".join(traceback.format_exception(exc))
        self.fault = Fault(path, 0, code, str(plc), text, plc, operation, location)
        raise self._fault_error() from exc

    def reset_cold(self) -> None:
        """Reset cold: plain variables re-initialised; RETAIN per profile; PERSISTENT kept."""
        resets.reset_cold(self)

    def reset_warm(self) -> None:
        """Reset warm (CODESYS only): plain variables re-initialised, RETAIN and PERSISTENT kept."""
        resets.reset_warm(self)

    def reset_origin(self) -> None:
        """Reset origin: everything re-initialised, the store cleared."""
        resets.reset_origin(self)

    def download(self) -> None:
        """A (re-)download of the project: plain re-initialised; RETAIN per profile; PERSISTENT kept."""
        resets.download(self)

    def online_change(self, replace: dict[str, Any] | None = None) -> None:
        """An online change: every variable kept.

        Without ``replace`` it is a code-only change (no FB_exit / FB_init /
        FB_reinit). ``replace`` maps instance paths (``"PlcTask.Main"``) to the
        changed declaration: a program class (the runtime creates the new
        instance, whose only FB_init is the online change's), or an instance
        already built (its constructor ran FB_init(TRUE, FALSE) first). The old
        instance gets FB_exit(TRUE), the new one FB_init(FALSE, TRUE), the data
        is copied by path and type, then FB_reinit runs.
        """
        resets.online_change(self, replace)
