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


def test_a_runtime_without_remanent_variables_writes_no_store(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # The application here is one program: no GVL or VAR_STAT of other tests in this process.
    monkeypatch.setattr("iecoop.runtime.runtime.global_lists", dict)
    monkeypatch.setattr("iecoop.runtime.runtime.static_blocks", list)
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
    with pytest.raises(PlcException, match="task Fast stopped in cycle 3") as exc:
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


# ---------------------------------------------------------------------------
# The application's global data: GVLs and VAR_STAT blocks
# ---------------------------------------------------------------------------

from iecoop import VAR_EXTERNAL, VAR_STAT, FunctionBlock, GlobalVariables, gvl  # noqa: E402

init_calls: list[tuple[str, bool]] = []


class GlobalLogger(FunctionBlock):
    lines: INT = VAR(0)

    def fb_init(self, init_retains: bool, in_copy_code: bool) -> None:
        init_calls.append(("GlobalLogger", init_retains))


@gvl
class GVL_RuntimeTest(GlobalVariables):
    g_plain: INT = 0
    g_kept: INT = VAR(0, retain=True)
    g_saved: DINT = VAR(0, persistent=True)
    g_logger: GlobalLogger = VAR()


class SharedCounter(FunctionBlock):
    total: INT = VAR_STAT(0)

    def body(self) -> None:
        self.total += 1


class UsesGlobals(Program):
    g_plain: INT = VAR_EXTERNAL()
    g_kept: INT = VAR_EXTERNAL()
    g_saved: DINT = VAR_EXTERNAL()
    counter: SharedCounter = VAR()

    def body(self) -> None:
        self.g_plain += 1
        self.g_kept += 1
        self.g_saved += 10
        self.counter()


def _globals() -> tuple[int, int, int, int]:
    return GVL_RuntimeTest.g_plain, GVL_RuntimeTest.g_kept, GVL_RuntimeTest.g_saved, SharedCounter().total


@pytest.fixture
def fresh_globals() -> None:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask"), Plain())
    rt.reset_origin()  # the whole application's data back to its initial values
    assert _globals() == (0, 0, 0, 0)


@pytest.mark.usefixtures("fresh_globals")
@pytest.mark.parametrize(
    ("profile", "after_cold"),
    [("twincat", (0, 3, 30, 0)), ("codesys", (0, 0, 30, 0))],
)
def test_resets_reinitialise_gvls_and_var_stat_per_the_table(
    tmp_path: Path, profile: str, after_cold: tuple[int, int, int, int]
) -> None:
    main = UsesGlobals()
    rt = _runtime(tmp_path, main, profile)
    rt.run(cycles=3)
    assert _globals() == (3, 3, 30, 3)
    init_calls.clear()
    rt.reset_cold()
    assert _globals() == after_cold
    assert init_calls == [("GlobalLogger", after_cold[1] == 0)]  # FB_init of the global FB instance, init_retains
    rt.run(cycles=1)
    rt.reset_origin()
    assert _globals() == (0, 0, 0, 0)


@pytest.mark.usefixtures("fresh_globals")
def test_global_retain_and_persistent_survive_a_restart(tmp_path: Path) -> None:
    rt = _runtime(tmp_path, UsesGlobals())
    rt.run(cycles=4)
    rt.stop()
    GVL_RuntimeTest.g_plain = GVL_RuntimeTest.g_kept = 0  # a new process starts from the initial values
    GVL_RuntimeTest.g_saved = 0
    rt2 = _runtime(tmp_path, UsesGlobals())
    rt2.run(cycles=0)
    assert (GVL_RuntimeTest.g_plain, GVL_RuntimeTest.g_kept, GVL_RuntimeTest.g_saved) == (0, 4, 40)


def test_a_global_fb_instance_gets_its_fb_init_at_definition() -> None:
    init_calls.clear()

    @gvl
    class GVL_WithLogger(GlobalVariables):
        logger_b: GlobalLogger = VAR()

    assert init_calls == [("GlobalLogger", True)]
    assert GVL_WithLogger.logger_b.lines == 0


lifecycle: list[str] = []


class Tracked(Program):
    n: INT = VAR(0)

    def fb_init(self, init_retains: bool, in_copy_code: bool) -> None:
        lifecycle.append(f"{type(self).__name__}.FB_init({init_retains}, {in_copy_code})")

    def fb_exit(self, in_copy_code: bool) -> None:
        lifecycle.append(f"{type(self).__name__}.FB_exit({in_copy_code})")

    def body(self) -> None:
        self.n += 1


class TrackedV2(Tracked):
    extra: INT = VAR(7)

    def fb_reinit(self) -> None:
        lifecycle.append(f"TrackedV2.FB_reinit (n={self.n})")


def test_online_change_to_a_class_runs_only_the_online_change_fb_init() -> None:
    lifecycle.clear()
    rt = Runtime(store=":memory:")
    old = Tracked()
    rt.add_task(Task("PlcTask"), old)
    rt.run(cycles=3)
    rt.online_change(replace={"PlcTask.Tracked": TrackedV2})
    new = rt.programs()["PlcTask.Tracked"]
    assert isinstance(new, TrackedV2) and (new.n, new.extra) == (3, 7)
    assert lifecycle == [
        "Tracked.FB_init(True, False)",
        "Tracked.FB_exit(True)",
        "TrackedV2.FB_init(False, True)",
        "TrackedV2.FB_reinit (n=3)",
    ]
    rt.run(cycles=1)
    assert new.n == 4
    with pytest.raises(TypeError, match="online change: int is not a Program class"):
        rt.online_change(replace={"PlcTask.Tracked": int})


from iecoop import LREAL, POINTER_TO, adr, method  # noqa: E402


class PointsAtTarget(Program):
    target: INT = VAR(0)
    p: POINTER_TO[INT] = VAR()

    def fb_init(self, init_retains: bool, in_copy_code: bool) -> None:
        if not in_copy_code:
            self.p = adr(self, "target")

    def body(self) -> None:
        self.p.deref += 1


class TargetMoved(Program):
    extra: LREAL = VAR(0.0)  # a new variable before: target's offset changes
    target: INT = VAR(0)
    p: POINTER_TO[INT] = VAR()

    def body(self) -> None:
        self.p.deref += 1


class TargetGone(Program):
    p: POINTER_TO[INT] = VAR()

    @method
    def is_null(self) -> bool:
        return bool(self.p.is_null)


def test_online_change_moves_pointers_to_the_same_variable_or_nulls_them() -> None:
    old = PointsAtTarget()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask"), old)
    rt.run(cycles=3)
    rt.online_change(replace={"PlcTask.PointsAtTarget": TargetMoved})
    moved = rt.programs()["PlcTask.PointsAtTarget"]
    assert moved.p == adr(moved, "target") and moved.p != adr(old, "target")
    rt.run(cycles=2)
    assert (moved.target, old.target) == (5, 3)
    rt.online_change(replace={"PlcTask.PointsAtTarget": TargetGone})
    gone = rt.programs()["PlcTask.PointsAtTarget"]
    assert gone.is_null()  # its target no longer exists
