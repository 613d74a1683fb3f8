"""The cyclic runtime: tasks, virtual time, faults, resets and remanent data.

A ``Runtime`` holds tasks; each task calls its programs in order every cycle.
Virtual time is the default: the clock jumps from one task tick to the next,
so timing logic is exact, deterministic and runs as fast as the CPU allows.
``realtime=True`` paces the cycles by the wall clock and counts jitter and
overruns.

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

import ctypes
import dataclasses
import math
import os
import time
import traceback
import typing
import warnings
from pathlib import Path
from collections.abc import Callable
from typing import Any, Literal

from iecoop.exceptions import ExceptionCode, PlcException
from iecoop.gvl import global_lists
from iecoop.lifecycle import finalise, initialise, reinitialise
from iecoop.memory._core import allocation_of, registered_allocation
from iecoop.pou import static_blocks
from iecoop.profiles import Profile, get_profile, use_profile
from iecoop.runtime.clock import VirtualClock, use_clock
from iecoop.runtime.store import ImageLayout, RemanentStore
from iecoop.runtime.variables import (
    PERSISTENT, PLAIN, RETAIN, Leaf, copy_matching, format_directory, handle_offsets, leaves, nodes, parse_directory,
    translate_offset,
)

__all__ = ["Fault", "Runtime", "Task", "TaskInfo", "current_task"]


@dataclasses.dataclass
class TaskInfo:
    """What the PLC reports about a task (TwinCAT ``_TaskInfo`` / ``PlcTaskSystemInfo``).

    Times are in 100 ns units, as TwinCAT reports them.
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


class Task:
    """A cyclic task: ``Task("PlcTask", interval=T("10ms"), priority=20)``.

    ``watchdog`` (a TIME) with ``sensitivity`` raises RTSEXCPT_WATCHDOG when
    that many consecutive cycles run longer than the watchdog time.
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
        self.programs: list[tuple[str, Any]] = []
        self.info = TaskInfo(name, interval * 10_000, priority)
        self._overruns = 0

    def __repr__(self) -> str:
        return f"<Task {self.name} {self.interval} ms prio {self.priority}>"


@dataclasses.dataclass(frozen=True)
class Fault:
    """The exception state: which task and cycle failed, with what code and traceback."""

    task: str
    cycle: int
    code: ExceptionCode
    message: str
    traceback: str
    exception: PlcException


_current: list[Task] = []


def current_task() -> TaskInfo:
    """The running task's info (ST: ``_TaskInfo[GETCURTASKINDEXEX()]``)."""
    if not _current:
        raise RuntimeError("no task is running: current_task() is for code called by a Runtime cycle")
    return _current[-1].info


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


class _Entry:
    """One program instance in a task, with its instance path and variable directory."""

    __slots__ = ("path", "program", "leaves", "remanent")

    def __init__(self, path: str, program: Any) -> None:
        self.path = path
        self.program = program
        self.leaves: list[Leaf] = leaves(type(program))
        self.remanent = any(leaf.remanence != PLAIN for leaf in self.leaves)


class Runtime:
    """A PLC runtime: tasks, virtual (or real) time, remanent store, resets.

    ``store`` is a folder for RETAIN / PERSISTENT data (default ``./.iecoop``);
    ``":memory:"`` keeps nothing on disk. ``profile`` is ``"twincat"``
    (default) or ``"codesys"``.

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
    ) -> None:
        self.profile = get_profile(profile)
        self.tasks: list[Task] = []
        self._entries: list[_Entry] = []
        self._globals: list[_Entry] = []
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
        #: Called in the PLC's thread before / after the tasks of each base tick (an OPC UA server's
        #: writes go in before, its consistent image of the cycle is taken after).
        self.on_cycle_start: list[Callable[[], None]] = []
        self.on_cycle_end: list[Callable[[], None]] = []

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
            if getattr(type(program), "_iec_kind_", "") not in ("program", "fb"):
                raise TypeError(f"task {task.name}: {program!r} is not a Program instance")

    def _attach(self, task: Task, programs: tuple[Any, ...]) -> None:
        for program in programs:
            base = f"{task.name}.{type(program).__name__}"
            path = base
            n = 2
            while any(e.path == path for e in self._entries):
                path = f"{base}_{n}"
                n += 1
            entry = _Entry(path, program)
            self._entries.append(entry)
            task.programs.append((path, program))
        self._retain_plan = None

    def _global_entries(self) -> list[_Entry]:
        """The application's global data: every GVL (path: its name) and VAR_STAT block (``Class.VAR_STAT``)."""
        current = [(name, block) for name, block in global_lists().items()]
        current += [(f"{cls.__qualname__}.VAR_STAT", block) for cls, block in static_blocks()]
        key = tuple(id(block) for _, block in current)
        if key != self._globals_key:
            self._globals_key = key
            self._globals = [_Entry(path, block) for path, block in current]
            self._retain_plan = None
        return self._globals

    def _all_entries(self) -> list[_Entry]:
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

    def run(self, cycles: int | None = None, duration: int | None = None, *, realtime: bool = False) -> None:
        """Run ``cycles`` base ticks, or for ``duration`` (a TIME in ms) of PLC time.

        The base tick is the greatest common divisor of the task intervals, so
        with one task a tick is one cycle. At each tick the due tasks run in
        priority order; the task clock (what TON / TOF / TP read) is the
        cycle's start.

        ``realtime=True`` paces the ticks by the wall clock: a cycle never
        starts before its tick, the lateness is the task's jitter
        (``TaskInfo.JitterMax``) and is part of the task clock, and a cycle
        that overruns makes the PLC skip the ticks it missed rather than run
        them back to back (``CycleTimeExceeded`` / ``ExceedCounter`` count the
        overruns). Tasks run one after the other in the calling thread.
        """
        self._raise_if_faulted()
        if self._stopped:
            raise RuntimeError("the runtime was stopped; create a new Runtime on the same store to start again")
        if (cycles is None) == (duration is None):
            raise ValueError("run() takes either cycles= or duration=")
        tick_ms = self.base_tick_ms
        if cycles is None:
            assert duration is not None
            if duration < 0:
                raise ValueError("duration must not be negative")
            cycles = duration // tick_ms
        if cycles < 0:
            raise ValueError("cycles must not be negative")
        if not self._started:
            self._start()
        tick_ns = tick_ms * 1_000_000
        end_tick = self._tick + cycles
        wall_start = time.monotonic_ns()
        first_tick = self._tick
        with use_profile(self.profile), use_clock(self._clock):
            while self._tick < end_tick:
                tick_time = self._tick * tick_ns
                jitter = 0
                if realtime:
                    planned = wall_start + (self._tick - first_tick) * tick_ns
                    delay = planned - time.monotonic_ns()
                    if delay > 0:
                        time.sleep(delay / 1e9)
                    late = time.monotonic_ns() - planned
                    if late >= tick_ns:
                        # An overrun: like the PLC, start at the next tick boundary
                        # instead of running the missed cycles back to back.
                        self._tick = min(self._tick + late // tick_ns, end_tick)
                        continue
                    jitter = max(0, late)
                # The task clock is the cycle's start, so every timer in the cycle
                # reads the same time (in real time, the actual start, jitter included).
                self._clock.set(tick_time + jitter)
                self.time_ns = tick_time
                for hook in self.on_cycle_start:
                    hook()
                self._run_tick(tick_ms, jitter)
                self._tick += 1
                for hook in self.on_cycle_end:
                    hook()
            self.time_ns = self._tick * tick_ns
            self._clock.set(self.time_ns)

    def _run_tick(self, tick_ms: int, jitter: int) -> None:
        now_ms = self._tick * tick_ms
        for task in self.tasks:
            if now_ms % task.interval:
                continue
            info = task.info
            info.JitterMax = max(info.JitterMax, jitter // 100)
            info.FirstCycle = info.CycleCount == 0
            started = time.perf_counter_ns()
            _current.append(task)
            try:
                for path, program in task.programs:
                    program.body()
            except BaseException as exc:
                if isinstance(exc, (KeyboardInterrupt, SystemExit)):
                    raise
                self._enter_fault(task, exc)
            finally:
                _current.pop()
            elapsed = time.perf_counter_ns() - started
            cycle = info.CycleCount
            info.LastExecTime = elapsed // 100
            info.MaxExecTime = max(info.MaxExecTime, info.LastExecTime)
            info.CycleCount += 1
            exceeded = elapsed > task.interval * 1_000_000
            info.CycleTimeExceeded = exceeded
            if exceeded:
                info.ExceedCounter += 1
            if task.watchdog is not None:
                if elapsed > task.watchdog * 1_000_000:
                    task._overruns += 1
                    if task._overruns >= task.sensitivity:
                        info.WatchdogHits += 1
                        self._enter_fault(
                            task,
                            PlcException(
                                ExceptionCode.RTSEXCPT_WATCHDOG,
                                f"task {task.name}: cycle {cycle} took {elapsed / 1e6:.3f} ms, "
                                f"watchdog {task.watchdog} ms",
                            ),
                            cycle,
                        )
                else:
                    task._overruns = 0
        self._capture_retain()

    def _enter_fault(self, task: Task, exc: BaseException, cycle: int | None = None) -> typing.NoReturn:
        code = _fault_code(exc)
        plc = exc if isinstance(exc, PlcException) else PlcException(code, f"{type(exc).__name__}: {exc}")
        text = "".join(traceback.format_exception(exc))
        where = task.info.CycleCount if cycle is None else cycle
        self.fault = Fault(task.name, where, code, str(plc), text, plc)
        raise self._fault_error() from exc

    def _fault_error(self) -> PlcException:
        assert self.fault is not None
        f = self.fault
        return PlcException(f.code, f"task {f.task} stopped in cycle {f.cycle}: {f.message}")

    def _raise_if_faulted(self) -> None:
        if self.fault is not None:
            raise self._fault_error()

    # -- remanent data ---------------------------------------------------------

    def _store_or_none(self) -> RemanentStore | None:
        if self._store_path is None:
            return None
        if self._store is None:
            self._store = RemanentStore(self._store_path, durability=self._durability)
        return self._store

    def _start(self) -> None:
        """Controller start: restore RETAIN and PERSISTENT data that still match."""
        self._started = True
        if not any(e.remanent for e in self._all_entries()):
            return
        store = self._store_or_none()
        if store is None:
            return
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            retain = store.load_retain()
            persistent = store.load_persistent()
        self.boot_report = [str(w.message) for w in caught]
        for message in self.boot_report:
            warnings.warn(message, RuntimeWarning, stacklevel=3)
        if retain is not None:
            self._apply_image(retain.values(), {RETAIN})
        if persistent is not None:
            self._apply_image(persistent.values(), {PERSISTENT})

    def _apply_image(self, values: dict[str, tuple[str, bytes]], classes: set[int]) -> None:
        for entry in self._all_entries():
            stored = values.get(entry.path)
            if stored is None:
                continue
            directory, data = stored
            try:
                old_leaves = parse_directory(directory)
            except ValueError as exc:
                self.boot_report.append(f"{entry.path}: stored directory rejected ({exc})")
                continue
            copy_matching(data, old_leaves, entry.program, entry.leaves, classes)

    def _plan(self, classes: set[int]) -> tuple[ImageLayout, list[Any]]:
        """The layout of an image of the given classes and the program blocks it copies."""
        entries = []
        blocks = []
        for entry in self._all_entries():
            kept = [leaf for leaf in entry.leaves if leaf.remanence in classes]
            if kept:
                entries.append((entry.path, format_directory(kept), ctypes.sizeof(entry.program)))
                blocks.append(entry.program)
        return ImageLayout(tuple(entries)), blocks

    @staticmethod
    def _gather(blocks: list[Any]) -> bytes:
        """One C-level copy per program block: the image data."""
        return b"".join(ctypes.string_at(ctypes.addressof(b), ctypes.sizeof(b)) for b in blocks)

    def _capture_retain(self) -> None:
        if self._retain_plan is None:
            self._retain_plan = self._plan({RETAIN})
        layout, blocks = self._retain_plan
        if not blocks:
            return
        store = self._store_or_none()
        if store is not None:
            store.write_retain(layout, self._gather(blocks))

    def save_persistent(self) -> None:
        """Write the PERSISTENT image now (TwinCAT ``FB_WritePersistentData``)."""
        layout, blocks = self._plan({PERSISTENT})
        store = self._store_or_none() if blocks else None
        if store is not None:
            store.write_persistent(layout, self._gather(blocks))

    def stop(self) -> None:
        """Orderly shutdown: write PERSISTENT data, run FB_exit, close the store."""
        if self._stopped:
            return
        self.save_persistent()
        with use_profile(self.profile):
            for entry in self._all_entries():
                finalise(entry.program, in_copy_code=False)
        self._stopped = True
        if self._store is not None:
            self._store.close()

    # -- resets, download, online change -----------------------------------------

    def _snapshot(self, entry: _Entry) -> bytes:
        return ctypes.string_at(ctypes.addressof(entry.program), ctypes.sizeof(entry.program))

    def _reinit(self, kept: set[int], init_retains: bool) -> None:
        # The whole application is re-initialised: programs, GVLs and VAR_STAT blocks.
        with use_profile(self.profile), use_clock(self._clock):
            for entry in self._all_entries():
                saved = self._snapshot(entry)
                finalise(entry.program, in_copy_code=False)
                # The instance's declaration (constructor) FB_init inputs hold on every re-initialisation.
                args = entry.program.__dict__.get("_iec_init_args_")
                initialise(entry.program, init_retains=init_retains, in_copy_code=False, args=args, zero=True)
                if kept:
                    copy_matching(saved, entry.leaves, entry.program, entry.leaves, kept)
        self.fault = None
        for task in self.tasks:
            task.info.FirstCycle = True
            task.info.CycleCount = 0
            task._overruns = 0
        if RETAIN not in kept and self._started:
            # The store must not bring back RETAIN values this reset has re-initialised.
            self._capture_retain()

    def reset_cold(self) -> None:
        """Reset cold: plain variables re-initialised; RETAIN per profile; PERSISTENT kept."""
        kept = {PERSISTENT}
        if self.profile.retain_on_reset_cold:
            kept.add(RETAIN)
        self._reinit(kept, init_retains=RETAIN not in kept)

    def reset_warm(self) -> None:
        """Reset warm (CODESYS only): plain variables re-initialised, RETAIN and PERSISTENT kept."""
        if not self.profile.has_reset_warm:
            raise RuntimeError(f"the {self.profile.name} profile has no reset warm (TwinCAT 3 offers reset cold and reset origin)")
        self._reinit({RETAIN, PERSISTENT}, init_retains=False)

    def reset_origin(self) -> None:
        """Reset origin: everything re-initialised, the store cleared."""
        self._reinit(set(), init_retains=True)
        # Only a store that exists holds anything to clear; do not create one for it.
        exists = self._store is not None or (self._store_path is not None and self._store_path.exists())
        store = self._store_or_none() if exists else None
        if store is not None:
            store.clear_retain()
            store.clear_persistent()

    def download(self) -> None:
        """A (re-)download of the project: plain re-initialised; RETAIN per profile; PERSISTENT kept."""
        kept = {PERSISTENT}
        if self.profile.retain_on_download:
            kept.add(RETAIN)
        self._reinit(kept, init_retains=RETAIN not in kept)

    def _retarget(self, old: Any, new: Any) -> None:
        """Online change: pointers, references and interfaces into the old instance now designate the new one.

        Every address held by the application's programs, GVLs and VAR_STAT
        blocks is adjusted by instance path; one whose target is gone becomes 0.
        """
        old_alloc = registered_allocation(old)
        if old_alloc is None:
            return  # nobody took an address of the old instance
        new_alloc, _ = allocation_of(new)
        old_nodes, new_nodes = nodes(type(old)), nodes(type(new))
        for entry in self._all_entries():
            block = entry.program
            for offset in handle_offsets(type(block)):
                cell = ctypes.c_uint64.from_buffer(block, offset)
                handle = cell.value
                if handle >> 32 != old_alloc.id:
                    continue
                moved = translate_offset(old_nodes, new_nodes, handle & 0xFFFF_FFFF)
                cell.value = 0 if moved is None else (new_alloc.id << 32) | moved

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
        if not replace:
            return
        with use_profile(self.profile), use_clock(self._clock):
            for path, replacement in replace.items():
                entry = next((e for e in self._entries if e.path == path), None)
                if entry is None:
                    raise KeyError(f"online change: no program at {path!r} (known: {', '.join(self.programs())})")
                if isinstance(replacement, type):
                    if getattr(replacement, "_iec_kind_", "") not in ("program", "fb"):
                        raise TypeError(f"online change: {replacement.__name__} is not a Program class")
                    new_program: Any = typing.cast(Any, replacement).__new__(replacement)
                else:
                    new_program = replacement
                saved = self._snapshot(entry)
                finalise(entry.program, in_copy_code=True)
                initialise(new_program, init_retains=False, in_copy_code=True, zero=True)
                new_entry = _Entry(path, new_program)
                copy_matching(saved, entry.leaves, new_program, new_entry.leaves, {PLAIN, RETAIN, PERSISTENT})
                index = self._entries.index(entry)
                self._entries[index] = new_entry
                self._retarget(entry.program, new_program)
                reinitialise(new_program)
                for task in self.tasks:
                    task.programs = [(p, new_program if p == path else prog) for p, prog in task.programs]
        self._retain_plan = None
