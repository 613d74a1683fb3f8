"""The task watchdog: it stops a cycle that runs too long, and leaves nothing behind.

Waits are bounded by the watchdog, never asserted against the wall: a loaded
machine only delivers the stop later, and the tests assert lower bounds and
outcomes, not durations.
"""

from __future__ import annotations

import gc
import re
import threading
import time

import pytest

from iecoop import BOOL, DINT, ExceptionCode, PlcException, Program, T, VAR, VAR_INPUT
from iecoop.runtime import ManualWall, Runtime, Task
from iecoop.runtime.watchdog import WatchdogInterrupt

MS = 1_000_000


def watchdog_threads() -> list[threading.Thread]:
    return [t for t in threading.enumerate() if t.name == "iecoop watchdog"]


class Runaway(Program):
    """``WHILE TRUE DO END_WHILE`` in its second cycle while ``hang`` is TRUE."""

    n: DINT = VAR()
    hang: BOOL = VAR_INPUT(True)
    mode: DINT = VAR_INPUT()  # 0 plain loop, 1 catches Exception, 2 catches BaseException and returns

    def body(self) -> None:
        self.n += 1
        if self.n != 2 or not self.hang:
            return
        if self.mode == 0:
            while True:
                pass
        if self.mode == 1:
            while True:
                try:
                    while True:
                        pass
                except Exception:  # does not catch the watchdog's interrupt
                    pass
        try:
            while True:
                pass
        except BaseException:  # swallows it and ends the cycle: still a watchdog fault
            return


def runaway(mode: int = 0, hang: bool = True) -> Runaway:
    main = Runaway()
    main.mode, main.hang = mode, hang
    return main


def took(exc: pytest.ExceptionInfo[PlcException]) -> float:
    found = re.search(r"after (\d+\.\d+) ms", str(exc.value))
    assert found is not None, str(exc.value)
    return float(found.group(1))


@pytest.mark.parametrize("realtime", [False, True])
@pytest.mark.parametrize("mode", [0, 1, 2], ids=["loop", "except-Exception", "except-BaseException"])
def test_the_watchdog_stops_a_cycle_that_never_ends(realtime: bool, mode: int) -> None:
    main = runaway(mode)
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), watchdog=T("50ms")), main)
    with pytest.raises(PlcException, match=r"task PlcTask stopped in cycle 2: .*cycle 2 stopped by the watchdog "
                                           r"after \d+\.\d+ ms, watchdog 50 ms") as exc:
        rt.run(cycles=100, realtime=realtime)  # the fault ends the run in the second cycle
    assert exc.value.code == ExceptionCode.RTSEXCPT_WATCHDOG and took(exc) >= 50.0
    assert rt.fault is not None and (rt.fault.task, rt.fault.cycle) == ("PlcTask", 2)
    assert rt.fault.code == ExceptionCode.RTSEXCPT_WATCHDOG
    assert "WatchdogInterrupt" in rt.fault.traceback
    if mode != 2:
        assert "in body" in rt.fault.traceback  # where it was stopped
    info = rt.tasks[0].info
    assert info.WatchdogHits == 1 and info.ExceedCounter >= 1 and main.n == 2
    with pytest.raises(PlcException, match="RTSEXCPT_WATCHDOG"):
        rt.run(cycles=1)  # the exception state holds until a reset
    rt.reset_cold()
    main.hang = False
    skipped = info.SkippedCycles
    rt.run(cycles=3, realtime=realtime)
    # In real time a busy machine may make the runtime skip cycles: each is run or counted.
    assert main.n == info.CycleCount >= 1 and info.CycleCount + info.SkippedCycles - skipped == 3
    assert getattr(rt, "fault") is None  # (getattr: mypy narrowed it above)
    rt.stop()
    assert watchdog_threads() == []


def test_sensitivity_lets_a_never_ending_cycle_run_watchdog_times_sensitivity() -> None:
    main = runaway()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), watchdog=T("30ms"), sensitivity=3), main)
    with pytest.raises(PlcException, match=r"watchdog 30 ms, sensitivity 3") as exc:
        rt.run(cycles=3)
    assert took(exc) >= 90.0
    rt.stop()


class Timed(Program):
    """Each cycle 'executes' for the next of ``durations`` ms of the manual wall."""

    n: DINT = VAR()

    def body(self) -> None:
        WALL.advance(DURATIONS[self.n % len(DURATIONS)] * MS)
        self.n += 1


WALL = ManualWall()
DURATIONS: list[int] = []


def test_sensitivity_counts_consecutive_overruns_of_cycles_that_end() -> None:
    DURATIONS[:] = [25, 25, 5, 25, 25, 25]  # two overruns, a good cycle, then three in a row
    main = Timed()
    rt = Runtime(store=":memory:", wall=WALL)
    rt.add_task(Task("PlcTask", interval=T("100ms"), watchdog=T("20ms"), sensitivity=3), main)
    with pytest.raises(PlcException, match=r"cycle 6 (took|stopped by the watchdog after) \d+\.\d+ ms, "
                                           r"watchdog 20 ms, sensitivity 3") as exc:
        rt.run(cycles=10)
    assert exc.value.code == ExceptionCode.RTSEXCPT_WATCHDOG
    assert main.n == 6 and rt.tasks[0].info.WatchdogHits == 1
    rt.stop()


def test_no_watchdog_no_thread_and_a_dropped_runtime_ends_its_thread() -> None:
    before = len(watchdog_threads())
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), runaway(hang=False))
    rt.run(cycles=3)
    assert len(watchdog_threads()) == before
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), watchdog=T("50ms")), runaway(hang=False))
    rt.run(cycles=3)
    assert len(watchdog_threads()) == before + 1
    del rt
    gc.collect()
    assert len(watchdog_threads()) == before


class Edge(Program):
    """Ends right around its watchdog: the interrupt comes inside the body or after it, never later."""

    n: DINT = VAR()

    def body(self) -> None:
        self.n += 1
        WALL.advance(3 * MS)  # past the 2 ms watchdog: the thread fires at its next look
        end = time.perf_counter() + (self.n % 5) * 0.0005
        while time.perf_counter() < end:
            pass


def test_an_interrupt_never_lands_after_its_cycle() -> None:
    rt = Runtime(store=":memory:", wall=WALL)
    rt.add_task(Task("PlcTask", interval=T("10ms"), watchdog=T("2ms")), Edge())
    stopped = 0
    for _ in range(40):
        try:
            rt.run(cycles=1)
        except PlcException as exc:
            assert exc.code == ExceptionCode.RTSEXCPT_WATCHDOG
            stopped += 1
            rt.reset_cold()
        # Python code after the cycle: a late interrupt would be raised here.
        try:
            end = time.perf_counter() + 0.003
            while time.perf_counter() < end:
                pass
        except WatchdogInterrupt:  # pragma: no cover - the failure this test is for
            pytest.fail("the watchdog's interrupt landed after its cycle ended")
    # Every cycle ran 3 ms on a 2 ms watchdog: each is a watchdog fault, stopped or ended.
    assert stopped == 40
    rt.stop()
    assert watchdog_threads() == []
