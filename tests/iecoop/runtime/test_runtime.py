"""The cyclic runtime: virtual time, faults, resets and remanent data across cycles."""

from __future__ import annotations

from pathlib import Path

import pytest

from iecoop import DINT, INT, ExceptionCode, PlcException, Program, T, VAR
from iecoop.runtime import Runtime, Task, current_task


class Plant(Program):
    plain: INT = VAR(0)
    kept: INT = VAR(0, retain=True)
    saved: DINT = VAR(0, persistent=True)

    def body(self) -> None:
        self.plain += 1
        self.kept += 1
        self.saved += 10


class Plain(Program):
    n: INT = VAR(0)

    def body(self) -> None:
        self.n += 1


def _runtime(store: Path, program: Program, profile: str = "twincat") -> Runtime:
    rt = Runtime(store=store, profile=profile)
    rt.add_task(Task("PlcTask", interval=T("10ms")), program)
    return rt


def test_virtual_time_advances_one_interval_per_cycle() -> None:
    main = Plain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), main)
    rt.run(cycles=7)
    rt.run(duration=T("30ms"))
    assert (main.n, rt.time_ms) == (10, 100)


def test_a_runtime_without_remanent_variables_writes_no_store(tmp_path: Path) -> None:
    store = tmp_path / "store"
    rt = _runtime(store, Plain())
    rt.run(cycles=5)
    rt.reset_origin()
    rt.run(cycles=1)
    rt.stop()
    assert not store.exists()


def test_retain_and_persistent_survive_a_restart_on_the_same_store(tmp_path: Path) -> None:
    first = Plant()
    rt = _runtime(tmp_path, first)
    rt.run(cycles=4)
    rt.stop()
    second = Plant()
    rt2 = _runtime(tmp_path, second)
    rt2.run(cycles=1)
    # plain restarts from its initial value; RETAIN from the last cycle; PERSISTENT from stop().
    assert (second.plain, second.kept, second.saved) == (1, 5, 50)


@pytest.mark.parametrize(
    ("profile", "after_cold"),
    [("twincat", (0, 3, 30)), ("codesys", (0, 0, 30))],
)
def test_reset_cold_follows_the_profile_table(tmp_path: Path, profile: str, after_cold: tuple[int, int, int]) -> None:
    plant = Plant()
    rt = _runtime(tmp_path, plant, profile)
    rt.run(cycles=3)
    rt.reset_cold()
    assert (plant.plain, plant.kept, plant.saved) == after_cold
    rt.reset_origin()
    assert (plant.plain, plant.kept, plant.saved) == (0, 0, 0)


def test_reset_warm_exists_only_in_the_codesys_profile(tmp_path: Path) -> None:
    with pytest.raises(RuntimeError, match="no reset warm"):
        _runtime(tmp_path, Plant()).reset_warm()
    plant = Plant()
    rt = _runtime(tmp_path / "cds", plant, "codesys")
    rt.run(cycles=2)
    rt.reset_warm()
    assert (plant.plain, plant.kept, plant.saved) == (0, 2, 20)


class Divider(Program):
    n: INT = VAR(0)

    def body(self) -> None:
        self.n += 1
        if self.n == 3:
            self.n = self.n // 0


def test_a_fault_stops_the_runtime_until_a_reset() -> None:
    divider = Divider()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("Fast", interval=T("2ms"), priority=1), divider)
    with pytest.raises(PlcException, match="task Fast stopped in cycle 2") as exc:
        rt.run(cycles=10)
    assert exc.value.code == ExceptionCode.RTSEXCPT_DIVIDEBYZERO
    assert rt.fault is not None and rt.fault.task == "Fast" and "ZeroDivisionError" in rt.fault.traceback
    with pytest.raises(PlcException, match="DIVIDEBYZERO"):
        rt.run(cycles=1)
    rt.reset_cold()
    rt.run(cycles=2)
    assert divider.n == 2


order: list[str] = []


class Fast(Program):
    def body(self) -> None:
        order.append(f"fast{current_task().CycleCount}")


class Slow(Program):
    def body(self) -> None:
        order.append(f"slow{current_task().CycleCount}")


def test_due_tasks_run_in_priority_order_at_each_tick() -> None:
    order.clear()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("Slow", interval=T("4ms"), priority=10), Slow())
    rt.add_task(Task("Fast", interval=T("2ms"), priority=1), Fast())
    rt.run(cycles=3)
    assert order == ["fast0", "slow0", "fast1", "fast2", "slow1"]
    assert (rt.base_tick_ms, rt.time_ms) == (2, 6)
