"""The real-time mode: cycles paced by the wall, jitter, execution times, overruns, skipped cycles.

The runtime's wall is injected: a ``ManualWall`` moves only when the runtime
sleeps or a body says how long its work took, so every figure is exact and no
test depends on how loaded the machine is. One smoke test runs on the
machine's clock and asserts only what holds however late the machine is.
"""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import BOOL, DINT, Program, T, TIME, VAR
from iecoop.runtime import ManualWall, Runtime, SystemWall, Task, current_clock
from iecoop.stdlib import TON

MS = 1_000_000


class Script:
    """What a cycle does: record its task clock and wall start, then 'execute' for the next scripted duration."""

    def __init__(self, wall: ManualWall, durations_ms: list[float] | None = None) -> None:
        self.wall = wall
        self.durations = list(durations_ms or [0.0])
        self.clocks: list[int] = []
        self.starts: list[int] = []

    def __call__(self) -> None:
        self.clocks.append(current_clock().now_ns())
        self.starts.append(self.wall.now_ns())
        step = self.durations[(len(self.starts) - 1) % len(self.durations)]
        self.wall.advance(int(step * MS))


class Scripted(Program):
    n: DINT = VAR()

    def body(self) -> None:
        self.n += 1
        SCRIPTS[id(self)]()


SCRIPTS: dict[int, Script] = {}


def scripted(wall: ManualWall, durations_ms: list[float] | None = None) -> tuple[Scripted, Script]:
    main = Scripted()
    script = SCRIPTS[id(main)] = Script(wall, durations_ms)
    return main, script


def runtime(wall: ManualWall, *tasks: tuple[Task, Program]) -> Runtime:
    rt = Runtime(store=":memory:", wall=wall)
    for task, program in tasks:
        rt.add_task(task, program)
    return rt


def test_real_time_cycles_start_on_their_ticks_and_sleep_the_rest() -> None:
    wall = ManualWall()
    main, main_s = scripted(wall, [2])
    rt = runtime(wall, (Task("PlcTask", interval=T("20ms")), main))
    rt.run(cycles=6, realtime=True)
    info = rt.tasks[0].info
    assert main_s.starts == [k * 20 * MS for k in range(6)]
    assert main_s.clocks == main_s.starts  # on time: the task clock is the tick
    assert wall.sleeps == [18 * MS] * 5  # each cycle's 2 ms of work, then the rest of the tick
    assert (info.CycleCount, info.SkippedCycles, info.ExceedCounter, info.JitterMax) == (6, 0, 0, 0)
    assert info.LastExecTime == info.MaxExecTime == 20_000 and not info.CycleTimeExceeded
    assert rt.time_ms == 120


def test_the_same_cycles_in_virtual_time_never_sleep() -> None:
    wall = ManualWall()
    main, main_s = scripted(wall, [2])
    rt = runtime(wall, (Task("PlcTask", interval=T("1s")), main))
    rt.run(cycles=60)
    assert wall.sleeps == [] and rt.time_ms == 60_000 and main.n == 60
    assert rt.tasks[0].info.LastExecTime == 20_000  # the execution time is still measured on the wall


def test_an_overrun_is_counted_and_the_missed_cycles_are_skipped() -> None:
    wall = ManualWall()
    main, main_s = scripted(wall, [15])  # 15 ms of work on a 10 ms task
    rt = runtime(wall, (Task("PlcTask", interval=T("10ms")), main))
    rt.run(duration=T("100ms"), realtime=True)
    info = rt.tasks[0].info
    # Tick 1 starts 5 ms late (at 15 ms); tick 2's cycle would start at 30 ms, a whole tick late: skipped.
    assert [start // MS for start in main_s.starts] == [0, 15, 30, 45, 60, 75, 90]
    assert [clock // MS for clock in main_s.clocks] == [0, 15, 30, 45, 60, 75, 90]  # ticks 0 1 3 4 6 7 9
    assert info.CycleCount == main.n == 7 and info.SkippedCycles == 3  # ticks 2, 5 and 8
    assert info.ExceedCounter == 7 + 3  # every cycle ran too long, and three never ran
    assert info.JitterMax == 50_000 and info.LastExecTime == 150_000  # 100 ns units
    assert info.CycleTimeExceeded
    assert rt.time_ms == 100


def test_a_late_start_skips_cycles_even_when_no_cycle_runs_long() -> None:
    """The busy machine: each cycle is short, but the runtime wakes up late and misses ticks."""

    class LateWall(ManualWall):
        def sleep(self, ns: int) -> None:
            super().sleep(ns + 3 * MS)  # the process is scheduled 3 ms after it asked to be

    wall = LateWall()
    main, main_s = scripted(wall, [0.5])
    rt = runtime(wall, (Task("PlcTask", interval=T("2ms")), main))
    rt.run(duration=T("3s"), realtime=True)
    info = rt.tasks[0].info
    assert info.CycleCount + info.SkippedCycles == 1500
    assert info.SkippedCycles > 0 and info.ExceedCounter == info.SkippedCycles
    assert info.CycleTimeExceeded and info.MaxExecTime == 5_000


def test_skipped_ticks_count_only_for_the_tasks_due_on_them() -> None:
    wall = ManualWall()
    fast, fast_s = scripted(wall, [0, 0, 35, 0, 0, 0])  # the third fast cycle (tick 2, at 20 ms) runs 35 ms
    slow, slow_s = scripted(wall, [0])
    rt = runtime(wall, (Task("Fast", interval=T("10ms"), priority=1), fast),
                 (Task("Slow", interval=T("20ms"), priority=2), slow))
    rt.run(cycles=8, realtime=True)
    f, s = rt.tasks[0].info, rt.tasks[1].info
    # Tick 2's tasks end at 55 ms: ticks 3 and 4 (30, 40 ms) are missed, tick 5 starts 5 ms late.
    assert [c // MS for c in fast_s.clocks] == [0, 10, 20, 55, 60, 70]
    assert [c // MS for c in slow_s.clocks] == [0, 20, 60]
    assert (f.CycleCount, f.SkippedCycles, f.ExceedCounter) == (6, 2, 3)
    assert (s.CycleCount, s.SkippedCycles, s.ExceedCounter) == (3, 1, 1)  # its tick 4 was missed
    assert not f.CycleTimeExceeded  # its last cycle was on time
    assert s.CycleTimeExceeded  # its last cycle came right after the missed one


@settings(max_examples=60, deadline=None)
@given(
    durations=st.lists(st.integers(0, 35), min_size=1, max_size=8),
    oversleep=st.integers(0, 25),
    cycles=st.integers(1, 40),
)
def test_every_tick_is_run_or_counted_as_skipped(durations: list[int], oversleep: int, cycles: int) -> None:
    class Wall(ManualWall):
        def sleep(self, ns: int) -> None:
            super().sleep(ns + oversleep * MS)

    wall = Wall()
    main, main_s = scripted(wall, [float(d) for d in durations])
    rt = runtime(wall, (Task("PlcTask", interval=T("10ms")), main))
    rt.run(cycles=cycles, realtime=True)
    info = rt.tasks[0].info
    assert info.CycleCount + info.SkippedCycles == cycles
    long_cycles = sum(1 for k in range(info.CycleCount) if durations[k % len(durations)] > 10)
    assert info.ExceedCounter == long_cycles + info.SkippedCycles
    ticks = [clock // (10 * MS) for clock in main_s.clocks]
    assert ticks == sorted(set(ticks))  # each cycle names its own tick: lateness stays under a tick
    for tick, start, clock in zip(ticks, main_s.starts, main_s.clocks):
        assert start >= tick * 10 * MS  # never before its tick
        assert clock - tick * 10 * MS <= info.JitterMax * 100 < 10 * MS


class Delay(Program):
    timer: TON = VAR()
    done_at: TIME = VAR()
    seen: BOOL = VAR()

    def body(self) -> None:
        self.timer(IN=True, PT=T("60ms"))
        if self.timer.Q and not self.seen:
            self.seen = True
            self.done_at = current_clock().now_ns() // MS


def test_timers_read_the_real_start_of_the_cycle() -> None:
    class LateWall(ManualWall):
        def sleep(self, ns: int) -> None:
            super().sleep(ns + 2 * MS)  # every cycle starts 2 ms after its tick

    main = Delay()
    rt = Runtime(store=":memory:", wall=LateWall())
    rt.add_task(Task("PlcTask", interval=T("10ms")), main)
    rt.run(cycles=12, realtime=True)
    # The first cycle started on time (0 ms), the seventh 2 ms late: 62 ms, which the timer saw.
    assert main.seen and main.done_at == 62 and main.timer.ET == 60
    assert rt.tasks[0].info.JitterMax == 20_000


def test_the_runtime_wall_must_be_a_wall() -> None:
    with pytest.raises(TypeError, match=r"Runtime: wall must be a Wall .*got int"):
        Runtime(store=":memory:", wall=5)  # type: ignore[arg-type]
    assert isinstance(Runtime(store=":memory:").wall, SystemWall)
    with pytest.raises(ValueError, match="backwards"):
        ManualWall().advance(-1)


def test_real_time_on_the_machine_clock_returns_with_consistent_counts() -> None:
    """The one test on the real clock: whatever the load, every tick is run or counted."""
    main, main_s = scripted(ManualWall())
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), main)
    rt.run(cycles=5, realtime=True)
    info = rt.tasks[0].info
    assert rt.time_ms == 50 and info.CycleCount == main.n
    assert info.CycleCount + info.SkippedCycles == 5
