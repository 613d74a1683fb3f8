"""The scheduler: several tasks, priorities, the base tick, TaskInfo and run()'s arguments.

docs/concepts/runtime.md: priority 0..31 with 0 the highest; at each tick the
due tasks run in priority order; TwinCAT's ``PlcTaskSystemInfo`` reports
``CycleTime`` and ``LastExecTime`` in 100 ns units, ``CycleCount`` and
``FirstCycle``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import INT, VAR, VAR_TEMP, Program, T
from iecoop.runtime import Runtime, Task, TaskInfo, current_task, now_ms

#: (time in ms, task name, priority, CycleCount, FirstCycle) of every cycle.
trace: list[tuple[int, str, int, int, bool]] = []


class Recorder(Program):
    calls: INT = VAR(0)

    def body(self) -> None:
        info = current_task()
        trace.append((now_ms(), info.TaskName, info.Priority, info.CycleCount, info.FirstCycle))
        self.calls += 1


class Busy(Program):
    """Takes measurably long (well over 100 ns) so LastExecTime is not 0."""

    total: INT = VAR(0)

    def body(self) -> None:
        self.total = sum(range(3000)) % 1000


@pytest.fixture(autouse=True)
def _clear_trace() -> None:
    trace.clear()


def _runtime(*tasks: tuple[str, int, int]) -> Runtime:
    rt = Runtime(store=":memory:")
    for name, interval, priority in tasks:
        rt.add_task(Task(name, interval=interval, priority=priority), Recorder())
    return rt


# ---------------------------------------------------------------------------
# Several tasks
# ---------------------------------------------------------------------------


def test_due_tasks_run_in_priority_order_on_the_gcd_tick() -> None:
    rt = _runtime(("Slow", 10, 25), ("Mid", 6, 10), ("Fast", 4, 1))
    assert rt.base_tick_ms == 2
    assert [t.name for t in rt.tasks] == ["Fast", "Mid", "Slow"]
    rt.run(cycles=10)  # t = 0, 2, ..., 18 ms
    assert rt.time_ms == 20
    assert [(t, name) for t, name, *_ in trace] == [
        (0, "Fast"), (0, "Mid"), (0, "Slow"),
        (4, "Fast"),
        (6, "Mid"),
        (8, "Fast"),
        (10, "Slow"),
        (12, "Fast"), (12, "Mid"),
        (16, "Fast"),
        (18, "Mid"),
    ]
    assert {t.name: t.info.CycleCount for t in rt.tasks} == {"Fast": 5, "Mid": 4, "Slow": 2}


def test_a_task_added_later_with_a_higher_priority_runs_first() -> None:
    rt = _runtime(("Background", 10, 30))
    rt.add_task(Task("Urgent", interval=T("10ms"), priority=0), Recorder())
    rt.run(cycles=2)
    assert [name for _, name, *_ in trace] == ["Urgent", "Background"] * 2


def test_the_base_tick_follows_the_tasks() -> None:
    rt = Runtime(store=":memory:")
    with pytest.raises(RuntimeError, match=r"the runtime has no task; add one with add_task\(\)"):
        _ = rt.base_tick_ms
    with pytest.raises(RuntimeError, match="the runtime has no task"):
        rt.run(cycles=1)
    rt.add_task(Task("A", interval=12), Recorder())
    assert rt.base_tick_ms == 12
    rt.add_task(Task("B", interval=T("18ms")), Recorder())
    assert rt.base_tick_ms == 6
    rt.add_task(Task("C", interval=7), Recorder())
    assert rt.base_tick_ms == 1


def test_programs_of_a_task_run_in_order_and_add_program_appends() -> None:
    order: list[str] = []

    class First(Program):
        def body(self) -> None:
            order.append("First")

    class Second(Program):
        def body(self) -> None:
            order.append("Second")

    rt = Runtime(store=":memory:")
    first, second, again = First(), Second(), First()
    rt.add_task(Task("PlcTask"), first, second)
    rt.add_program("PlcTask", again)
    assert rt.programs() == {"PlcTask.First": first, "PlcTask.Second": second, "PlcTask.First_2": again}
    assert [path for path, _ in rt.tasks[0].programs] == ["PlcTask.First", "PlcTask.Second", "PlcTask.First_2"]
    # The list is the runtime's: a task's programs change only through add_task / add_program / online change.
    with pytest.raises(AttributeError):
        rt.tasks[0].programs.append(("PlcTask.Stray", first))  # type: ignore[attr-defined]
    with pytest.raises(AttributeError):
        rt.tasks[0].programs = ()  # type: ignore[misc]
    rt.run(cycles=2)
    assert order == ["First", "Second", "First"] * 2


def test_add_program_errors() -> None:
    rt = _runtime(("PlcTask", 10, 20))
    with pytest.raises(ValueError, match=r"no task named 'Other'; add it with add_task\(\)"):
        rt.add_program("Other", Recorder())
    with pytest.raises(TypeError, match=r"task PlcTask: 5 is not a Program instance"):
        rt.add_program("PlcTask", 5)
    assert list(rt.programs()) == ["PlcTask.Recorder"]


def test_a_rejected_add_task_adds_nothing() -> None:
    rt = Runtime(store=":memory:")
    with pytest.raises(TypeError, match="is not a Program instance"):
        rt.add_task(Task("PlcTask"), Recorder(), "not a program")
    assert rt.tasks == []
    assert rt.programs() == {}


# ---------------------------------------------------------------------------
# TaskInfo
# ---------------------------------------------------------------------------


def test_task_info_fields() -> None:
    task = Task("PlcTask", interval=T("10ms"), priority=7)
    assert task.info == TaskInfo("PlcTask", CycleTime=100_000, Priority=7)  # 10 ms in 100 ns units
    assert (task.info.CycleCount, task.info.FirstCycle, task.info.LastExecTime) == (0, True, 0)
    assert repr(task) == "<Task PlcTask 10 ms prio 7>"
    rt = Runtime(store=":memory:")
    rt.add_task(task, Recorder(), Busy())
    rt.run(cycles=3)
    assert [(count, first) for *_, count, first in trace] == [(0, True), (1, False), (2, False)]
    info = rt.tasks[0].info
    assert info is task.info
    assert (info.CycleCount, info.FirstCycle, info.CycleTime, info.Priority, info.TaskName) == (
        3, False, 100_000, 7, "PlcTask"
    )
    assert 0 < info.LastExecTime <= info.MaxExecTime
    assert info.LastExecTime < 10 * 1_000_000  # well below a second, in 100 ns units


@pytest.mark.parametrize("reset", ["reset_cold", "reset_origin", "download"])
def test_first_cycle_is_true_again_after_a_reset(reset: str) -> None:
    rt = _runtime(("Fast", 2, 1), ("Slow", 4, 2))
    rt.run(cycles=4)
    getattr(rt, reset)()
    assert [(t.info.CycleCount, t.info.FirstCycle) for t in rt.tasks] == [(0, True), (0, True)]
    trace.clear()
    rt.run(cycles=2)
    assert [(name, count, first) for _, name, _, count, first in trace] == [
        ("Fast", 0, True), ("Slow", 0, True), ("Fast", 1, False),
    ]


def test_first_cycle_after_a_codesys_reset_warm() -> None:
    rt = Runtime(store=":memory:", profile="codesys")
    rt.add_task(Task("PlcTask"), Recorder())
    rt.run(cycles=2)
    rt.reset_warm()
    trace.clear()
    rt.run(cycles=2)
    assert [(count, first) for *_, count, first in trace] == [(0, True), (1, False)]


def test_an_online_change_does_not_restart_the_cycle_count() -> None:
    rt = _runtime(("PlcTask", 10, 20))
    rt.run(cycles=2)
    rt.online_change(replace={"PlcTask.Recorder": Recorder})
    trace.clear()
    rt.run(cycles=1)
    assert [(count, first) for *_, count, first in trace] == [(2, False)]


class Scratch(Program):
    """Counts in a VAR_TEMP: each call starts it again at its initial value."""

    scratch: INT = VAR_TEMP(10)
    seen: INT = VAR(0)
    calls: INT = VAR(0)

    def body(self) -> None:
        self.scratch += 1
        self.seen = self.scratch
        self.calls += 1


class ScratchMoved(Scratch):
    """The same program after an online change (a new class, a new instance)."""


def test_a_task_call_re_initialises_var_temp_every_cycle() -> None:
    # IEC 61131-3 (TwinCAT, CODESYS): a task's call of a PROGRAM is a call; VAR_TEMP starts fresh at each.
    rt = Runtime(store=":memory:")
    program = Scratch()
    rt.add_task(Task("PlcTask"), program)
    rt.run(cycles=3)
    assert (program.seen, program.calls) == (11, 3)
    rt.run(cycles=1)
    assert program.seen == 11
    rt.online_change(replace={"PlcTask.Scratch": ScratchMoved})
    moved = rt.programs()["PlcTask.Scratch"]
    assert type(moved) is ScratchMoved and moved is not program
    rt.run(cycles=2)
    assert (moved.seen, moved.calls, program.calls) == (11, 6, 4)  # the new instance runs; its calls carried over


def test_current_task_is_only_for_code_a_cycle_calls() -> None:
    with pytest.raises(RuntimeError, match=r"no task is running: current_task\(\) is for code called by a Runtime cycle"):
        current_task()
    rt = _runtime(("A", 10, 3), ("B", 5, 4))
    rt.run(cycles=2)
    assert {name for _, name, *_ in trace} == {"A", "B"}
    with pytest.raises(RuntimeError, match="no task is running"):
        current_task()


# ---------------------------------------------------------------------------
# run(): cycles or duration
# ---------------------------------------------------------------------------


def test_run_by_duration_is_whole_base_ticks() -> None:
    rt = _runtime(("PlcTask", 10, 20))
    rt.run(duration=T("25ms"))  # two ticks: 0 and 10 ms
    assert (len(trace), rt.time_ms) == (2, 20)
    rt.run(duration=T("5ms"))  # less than a tick: nothing
    assert (len(trace), rt.time_ms) == (2, 20)
    rt.run(cycles=3)
    assert [t for t, *_ in trace] == [0, 10, 20, 30, 40]
    assert rt.time_ms == 50
    rt.run(duration=0)
    rt.run(cycles=0)
    assert (len(trace), rt.time_ms, rt.time_ns) == (5, 50, 50_000_000)


def test_run_by_duration_counts_in_the_gcd_tick() -> None:
    rt = _runtime(("A", 4, 1), ("B", 6, 2))
    rt.run(duration=T("12ms"))  # ticks of 2 ms: 0, 2, ..., 10
    assert [(t, name) for t, name, *_ in trace] == [(0, "A"), (0, "B"), (4, "A"), (6, "B"), (8, "A")]
    assert rt.time_ms == 12


@pytest.mark.parametrize(
    ("kwargs", "error", "message"),
    [
        ({"cycles": -1}, ValueError, "cycles must not be negative"),
        ({"duration": -10}, ValueError, "duration must not be negative"),
        ({"cycles": 1, "duration": 10}, ValueError, r"run\(\) takes either cycles= or duration="),
        ({}, ValueError, r"run\(\) takes either cycles= or duration="),
    ],
)
def test_run_argument_errors(kwargs: dict[str, Any], error: type[Exception], message: str) -> None:
    rt = _runtime(("PlcTask", 10, 20))
    with pytest.raises(error, match=message):
        rt.run(**kwargs)
    assert (trace, rt.time_ms) == ([], 0)


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda: Task("T1", priority=32), r"task T1: priority must be 0\.\.31 \(0 is the highest\), got 32"),
        (lambda: Task("T1", priority=-1), r"task T1: priority must be 0\.\.31 \(0 is the highest\), got -1"),
        (lambda: Task("T1", interval=0), r"task T1: the interval is a positive TIME in ms, got 0"),
        (lambda: Task("T1", interval=-10), r"task T1: the interval is a positive TIME in ms, got -10"),
        (lambda: Task("T1", interval=2.5), r"task T1: the interval is a positive TIME in ms, got 2\.5"),  # type: ignore[arg-type]
        (lambda: Task("T1", interval=True), r"task T1: the interval is a positive TIME in ms, got True"),
        (lambda: Task("T1", watchdog=0), r"task T1: the watchdog time must be positive"),
    ],
    ids=["priority-32", "priority-minus-1", "interval-0", "interval-negative", "interval-float", "interval-bool",
         "watchdog-0"],
)
def test_task_argument_errors(make: Callable[[], Task], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        make()


def test_priorities_0_and_31_are_the_limits() -> None:
    assert (Task("High", priority=0).priority, Task("Low", priority=31).priority) == (0, 31)


def test_add_task_errors() -> None:
    rt = _runtime(("PlcTask", 10, 20))
    with pytest.raises(ValueError, match=r"a task named 'PlcTask' already exists"):
        rt.add_task(Task("PlcTask", interval=5, priority=3), Recorder())
    with pytest.raises(ValueError, match=r"task Other: give at least one program instance"):
        rt.add_task(Task("Other"))
    assert [t.name for t in rt.tasks] == ["PlcTask"]


# ---------------------------------------------------------------------------
# The scheduling invariant
# ---------------------------------------------------------------------------


@settings(max_examples=60, deadline=None)
@given(
    tasks=st.lists(st.tuples(st.integers(1, 50), st.integers(0, 31)), min_size=1, max_size=5),
    chunks=st.lists(st.integers(0, 60), min_size=1, max_size=3),
)
def test_each_task_runs_on_its_grid_in_priority_order(tasks: list[tuple[int, int]], chunks: list[int]) -> None:
    trace.clear()
    rt = _runtime(*((f"T{index}", interval, priority) for index, (interval, priority) in enumerate(tasks)))
    tick = math.gcd(*(interval for interval, _ in tasks))
    assert rt.base_tick_ms == tick
    for cycles in chunks:  # several run() calls go on where the last one stopped
        rt.run(cycles=cycles)
    ticks = sum(chunks)
    assert rt.time_ms == ticks * tick
    last = (ticks - 1) * tick  # the time of the last tick that ran
    for index, (interval, _) in enumerate(tasks):
        runs = [t for t, name, *_ in trace if name == f"T{index}"]
        expected = last // interval + 1 if ticks else 0  # floor(time / interval), +1 for t = 0
        assert len(runs) == expected
        assert runs == [n * interval for n in range(expected)]
        assert rt.tasks[[t.name for t in rt.tasks].index(f"T{index}")].info.CycleCount == expected
    times = [t for t, *_ in trace]
    assert times == sorted(times)
    for moment in sorted(set(times)):
        priorities = [priority for t, _, priority, *_ in trace if t == moment]
        assert priorities == sorted(priorities)
