"""The real-time mode: cycles paced by the wall clock, jitter, execution times, overruns, watchdog.

Wall-clock tests on a shared machine: each asserts what must hold however
loaded the machine is (a cycle never starts early, a busy cycle is never
shorter than its busy time), not figures that depend on the load.
"""

from __future__ import annotations

import time

import pytest

from iecoop import BOOL, DINT, LREAL, ExceptionCode, PlcException, Program, T, TIME, VAR
from iecoop.runtime import Runtime, Task, current_clock
from iecoop.stdlib import TON


def busy(ms: float) -> None:
    end = time.perf_counter() + ms / 1000
    while time.perf_counter() < end:
        pass


STARTS: list[float] = []
CLOCKS: list[int] = []


class Stamp(Program):
    """Records the wall time at which each cycle started (in STARTS) and its task clock (in CLOCKS)."""

    n: DINT = VAR()

    def body(self) -> None:
        STARTS.append(time.monotonic())
        CLOCKS.append(current_clock().now_ns())
        self.n += 1


def test_real_time_cycles_never_start_before_their_tick() -> None:
    STARTS.clear()
    CLOCKS.clear()
    main = Stamp()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("20ms")), main)
    began = time.monotonic()
    rt.run(cycles=6, realtime=True)
    took = time.monotonic() - began
    info = rt.tasks[0].info
    assert rt.time_ms == 120
    assert 1 <= info.CycleCount == main.n <= 6
    # The task clock is the tick's time plus the cycle's lateness, which stays under a
    # tick (a later cycle is skipped), so it names the tick each cycle ran for.
    ticks = [clock // 20_000_000 for clock in CLOCKS]
    assert ticks == sorted(set(ticks)) and ticks[0] == 0
    # Cycle k starts no earlier than k ticks after the first tick, which the first
    # cycle may itself have started late (1 ms slack for timer granularity).
    first = STARTS[0] - CLOCKS[0] / 1e9
    for k, s in zip(ticks, STARTS):
        assert s - first >= k * 0.020 - 0.001
    assert took >= 0.099  # the sixth tick is 100 ms after the first
    assert info.LastExecTime > 0


def test_the_same_cycles_in_virtual_time_take_no_wall_time() -> None:
    main = Stamp()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("1s")), main)
    began = time.monotonic()
    rt.run(cycles=60)
    assert time.monotonic() - began < 1.0 and rt.time_ms == 60_000 and main.n == 60


class Delay(Program):
    timer: TON = VAR()
    done_at: TIME = VAR()
    seen: BOOL = VAR()
    wall_start: LREAL = VAR()
    wall_done: LREAL = VAR()

    def body(self) -> None:
        if not self.wall_start:
            self.wall_start = time.monotonic()
        self.timer(IN=True, PT=T("60ms"))
        if self.timer.Q and not self.seen:
            self.seen = True
            self.wall_done = time.monotonic()


def test_timers_read_the_real_start_of_the_cycle() -> None:
    main = Delay()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), main)
    rt.run(cycles=12, realtime=True)
    assert main.seen and main.timer.ET == 60
    assert main.wall_done - main.wall_start >= 0.059


class Heavy(Program):
    n: DINT = VAR()

    def body(self) -> None:
        self.n += 1
        busy(15)


def test_an_overrun_is_counted_and_the_missed_cycles_are_skipped() -> None:
    main = Heavy()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), main)
    rt.run(duration=T("100ms"), realtime=True)
    info = rt.tasks[0].info
    # Every cycle runs 15 ms on a 10 ms task: each one exceeds, and the PLC does not
    # run the missed cycles back to back, so fewer than 10 cycles fit in 100 ms.
    assert info.CycleTimeExceeded and info.ExceedCounter == info.CycleCount == main.n
    assert 1 <= main.n <= 7
    assert info.LastExecTime >= 150_000  # 100 ns units
    # The second cycle's tick came 10 ms in, while the first still ran until 15 ms: 5 ms late.
    assert info.JitterMax >= 45_000
    assert info.MaxExecTime >= info.LastExecTime
    assert rt.time_ms == 100


class Stuck(Program):
    n: DINT = VAR()

    def body(self) -> None:
        self.n += 1
        if self.n == 3:
            busy(60)


@pytest.mark.parametrize("realtime", [False, True])
def test_the_watchdog_faults_a_cycle_that_runs_too_long(realtime: bool) -> None:
    main = Stuck()
    rt = Runtime(store=":memory:")
    # Margins wide enough that an idle cycle preempted on a loaded machine stays under the watchdog.
    rt.add_task(Task("PlcTask", interval=T("100ms"), watchdog=T("40ms")), main)
    with pytest.raises(PlcException, match=r"task PlcTask stopped in cycle 2: .*cycle 2 took \d+\.\d+ ms, watchdog 40 ms") as exc:
        rt.run(cycles=10, realtime=realtime)
    assert exc.value.code == ExceptionCode.RTSEXCPT_WATCHDOG
    # At least its 60 busy ms; a loaded machine may add any amount to that.
    took = float(str(exc.value).rsplit(" took ", 1)[1].split(" ms")[0])
    assert took >= 60.0
    assert rt.tasks[0].info.WatchdogHits == 1 and main.n == 3
    rt.reset_cold()
    assert main.n == 0
