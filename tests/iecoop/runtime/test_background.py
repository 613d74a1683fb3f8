"""A runtime running in a background thread: a closed loop with a plant model, a clean stop, faults surfaced."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterator

import pytest

from iecoop import BOOL, INT, REAL, ExceptionCode, PlcException, Program, T, VAR, VAR_INPUT, VAR_OUTPUT
from iecoop.runtime import ManualWall, Runtime, Task

FILL_BELOW = 50.0


class TankControl(Program):
    """The PROGRAM under test: opens the inlet valve while the level is below 50."""

    level: REAL = VAR_INPUT(0.0)
    valve: BOOL = VAR_OUTPUT(False)
    openings: INT = VAR(0)

    def body(self) -> None:
        opening = self.level < FILL_BELOW
        if opening and not self.valve:
            self.openings += 1
        self.valve = opening


class TankModel:
    """The plant: the level rises 2 per cycle while the valve is open and drains 1 per cycle."""

    def __init__(self, control: TankControl) -> None:
        self.control = control
        self.levels: list[float] = []

    def __call__(self) -> None:
        level = self.control.level + (2.0 if self.control.valve else 0.0) - 1.0
        self.control.level = max(0.0, level)
        self.levels.append(self.control.level)


def _tank(wall: ManualWall | None = None) -> tuple[Runtime, TankControl, TankModel]:
    control = TankControl()
    rt = Runtime(store=":memory:", wall=wall)
    rt.add_task(Task("PlcTask", interval=T("10ms")), control)
    model = TankModel(control)
    rt.on_cycle_end.append(model)
    return rt, control, model


def _wait_for(condition: Callable[[], bool], timeout: float = 60.0) -> None:
    """Wait until ``condition`` holds; the bound is generous, the test never measures time."""
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, "condition not reached"
        time.sleep(0.001)


@pytest.fixture
def no_thread_left() -> Iterator[None]:
    before = set(threading.enumerate())
    yield
    left = [t.name for t in set(threading.enumerate()) - before if t.name.startswith("iecoop-runtime")]
    assert left == []


@pytest.mark.usefixtures("no_thread_left")
def test_a_plant_model_closes_the_loop_in_virtual_time_in_the_background() -> None:
    rt, control, model = _tank()
    rt.start(cycles=200, realtime=False)
    assert rt.join(timeout=60)
    rt.stop_running()
    # Deterministic: virtual time, 200 cycles of 10 ms, the level held at the threshold.
    assert rt.time_ms == 2000
    assert len(model.levels) == 200
    assert model.levels[49] == FILL_BELOW
    assert all(FILL_BELOW - 1 <= level <= FILL_BELOW + 1 for level in model.levels[50:])
    assert control.openings > 50


@pytest.mark.usefixtures("no_thread_left")
def test_a_run_without_end_stops_cleanly_at_the_end_of_the_with_block() -> None:
    rt, control, model = _tank()
    with rt.running(realtime=False) as running:
        assert running is rt and rt.is_running
        _wait_for(lambda: len(model.levels) >= 100)
    alive: bool = rt.is_running
    assert not alive
    cycles = len(model.levels)
    assert rt.time_ms == cycles * 10
    rt.run(cycles=1)  # the caller's thread may run it again
    assert len(model.levels) == cycles + 1


@pytest.mark.usefixtures("no_thread_left")
def test_real_time_in_the_background_is_paced_by_the_wall() -> None:
    wall = ManualWall()
    rt, _, model = _tank(wall)
    with rt.running(cycles=30, realtime=True):
        assert rt.join(timeout=60)
    # The manual wall moved exactly as far as the pacing slept: one tick per cycle after the first.
    assert (len(model.levels), rt.time_ms, sum(wall.sleeps)) == (30, 300, 290 * 1_000_000)


@pytest.mark.usefixtures("no_thread_left")
def test_run_from_another_thread_is_refused_while_it_runs_in_the_background() -> None:
    rt, _, _ = _tank()
    with rt.running(realtime=False):
        with pytest.raises(RuntimeError, match="a Runtime runs in one thread at a time"):
            rt.run(cycles=1)
        with pytest.raises(RuntimeError, match="it already runs in the background"):
            rt.start(realtime=False)
        with pytest.raises(RuntimeError, match="one thread at a time"):
            rt.reset_cold()


class Breaks(Program):
    count: INT = VAR(0)
    divisor: INT = VAR(1)

    def body(self) -> None:
        self.count += 1
        if self.count == 5:
            self.divisor = 0
        self.count = self.count // self.divisor + 0 * self.count


def _breaking() -> Runtime:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), Breaks())
    return rt


@pytest.mark.usefixtures("no_thread_left")
def test_a_fault_in_the_background_stops_the_thread_and_is_raised_at_stop_running() -> None:
    rt = _breaking()
    rt.start(realtime=False)
    assert rt.join(timeout=60)  # the fault ended the thread by itself
    assert rt.fault is not None and rt.fault.code == ExceptionCode.RTSEXCPT_DIVIDEBYZERO
    with pytest.raises(PlcException, match="task PlcTask stopped in cycle 5") as caught:
        rt.stop_running()
    assert caught.value.code == ExceptionCode.RTSEXCPT_DIVIDEBYZERO
    rt.stop_running()  # raised once; the fault stays until a reset
    with pytest.raises(PlcException, match="stopped in cycle 5"):
        rt.start(realtime=False)


@pytest.mark.usefixtures("no_thread_left")
def test_a_fault_in_the_background_is_raised_when_the_with_block_exits() -> None:
    rt = _breaking()
    with pytest.raises(PlcException, match="RTSEXCPT_DIVIDEBYZERO|division") as caught:
        with rt.running(realtime=False):
            _wait_for(lambda: rt.fault is not None)
    assert caught.value.code == ExceptionCode.RTSEXCPT_DIVIDEBYZERO


@pytest.mark.usefixtures("no_thread_left")
def test_an_error_in_the_with_block_goes_on_and_the_thread_still_ends() -> None:
    rt, _, _ = _tank()
    with pytest.raises(KeyError):
        with rt.running(realtime=False):
            raise KeyError("the caller's own error")
    assert not rt.is_running


@pytest.mark.usefixtures("no_thread_left")
def test_stop_ends_a_background_run_first() -> None:
    rt, _, model = _tank()
    rt.start(realtime=False)
    _wait_for(lambda: len(model.levels) >= 10)
    rt.stop()
    assert not rt.is_running
    with pytest.raises(RuntimeError, match="was stopped"):
        rt.start(realtime=False)


def test_progress_is_reported_every_n_cycles_and_at_the_end() -> None:
    rt, _, _ = _tank()
    calls: list[tuple[int, int]] = []
    rt.run(cycles=25, progress=lambda done, total: calls.append((done, total)), progress_every=10)
    assert calls == [(10, 25), (20, 25), (25, 25)]
    with pytest.raises(ValueError, match="progress_every"):
        rt.run(cycles=1, progress=print, progress_every=0)


@pytest.mark.usefixtures("no_thread_left")
def test_progress_of_a_background_run() -> None:
    rt, _, _ = _tank()
    calls: list[tuple[int, int]] = []
    with rt.running(cycles=30, realtime=False, progress=lambda d, t: calls.append((d, t)), progress_every=10):
        assert rt.join(timeout=60)
    assert calls == [(10, 30), (20, 30), (30, 30)]


def test_a_runtime_keeps_cpythons_fast_attribute_reads() -> None:
    # CPython shares the keys of at most 30 instance attributes; past that, every read the
    # cycle loop makes of the runtime's state goes through a slower path.
    assert len(vars(Runtime(store=":memory:"))) <= 30


@pytest.mark.usefixtures("no_thread_left")
def test_an_error_in_a_plant_model_ends_the_background_run_and_is_raised_at_stop_running() -> None:
    rt, _, model = _tank()

    def broken() -> None:
        if len(model.levels) == 3:
            raise ValueError("the plant model's own bug")

    rt.on_cycle_end.append(broken)
    rt.start(realtime=False)
    assert rt.join(timeout=60)
    with pytest.raises(ValueError, match="plant model's own bug"):
        rt.stop_running()
    assert len(model.levels) == 3
