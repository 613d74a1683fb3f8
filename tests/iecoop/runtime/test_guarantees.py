"""What the runtime and its store guarantee under misuse: addresses in remanent data,
online change and the heap, changed types, a shared store, failing resets, threads
and use after ``stop()``.
"""

from __future__ import annotations

import subprocess
import sys
import textwrap
import threading
import warnings
from pathlib import Path
from typing import Annotated, Any

import pytest

from iecoop import (
    ARRAY,
    BOOL,
    DINT,
    INT,
    POINTER_TO,
    REAL,
    REFERENCE_TO,
    VAR,
    VAR_INPUT,
    Alias,
    ExceptionCode,
    FunctionBlock,
    Interface,
    PlcException,
    Program,
    Struct,
    T,
    active_profile,
    adr,
    delete,
    is_valid_ref,
    method,
    new,
    ref_assign,
)
from iecoop.runtime import Runtime, Task, current_clock, current_task, default_clock
from iecoop.runtime.store import StoreLockedError
from iecoop.stdlib import TON

TIMEOUT = 10.0
AV = ExceptionCode.RTSEXCPT_ACCESS_VIOLATION

# ---------------------------------------------------------------------------
# Addresses inside RETAIN / PERSISTENT data are never restored
# ---------------------------------------------------------------------------


class ICount(Interface):
    @method
    def bump(self) -> INT: ...  # a prototype's body is '...'


class Counter(FunctionBlock, ICount):
    n: INT = VAR(0)

    @method
    def bump(self) -> INT:
        self.n += 1
        return self.n


class Link(Struct):
    count: INT = 0
    p: POINTER_TO[INT] = VAR()
    r: REFERENCE_TO[INT] = VAR()
    i: ICount = VAR()


class Remembers(Program):
    target: INT = VAR(0)
    counter: Counter = VAR()
    link: Link = VAR(retain=True)
    links: ARRAY[Link] = VAR(bounds=(1, 2), persistent=True)

    def body(self) -> None:
        for holder in (self.link, *self.links):
            holder.count += 1
            if holder.p.is_null:
                holder.p = adr(self, "target")
                ref_assign(holder, "r", adr(self, "target"))
                holder.i = self.counter


def _remembers_runtime(store: Path) -> tuple[Runtime, Remembers]:
    program = Remembers()
    rt = Runtime(store=store)
    rt.add_task(Task("PlcTask"), program)
    return rt, program


def test_addresses_nested_in_retain_and_persistent_data_come_back_null(tmp_path: Path) -> None:
    rt, old = _remembers_runtime(tmp_path)
    rt.run(cycles=3)
    assert old.link.p == adr(old, "target") and old.links[2].i.bump() == 1
    rt.stop()
    rt2, new_program = _remembers_runtime(tmp_path)
    rt2.run(cycles=0)
    assert rt2.boot_report == []
    for holder in (new_program.link, *new_program.links):
        # The data beside them is restored; the addresses are not (they held the old process's blocks).
        assert holder.count == 3
        assert holder.p.is_null and not is_valid_ref(holder, "r") and not holder.i
        with pytest.raises(PlcException) as caught:
            holder.p.deref = 5
        assert caught.value.code is AV
    assert old.target == 0
    # The program sets them again in its next cycle, aimed at its own variable.
    rt2.run(cycles=1)
    assert new_program.link.p == adr(new_program, "target") and new_program.links[1].r == 0
    rt2.stop()


# ---------------------------------------------------------------------------
# Online change adjusts the addresses held by new() blocks
# ---------------------------------------------------------------------------


class Feeder(FunctionBlock):
    out: POINTER_TO[INT] = VAR_INPUT()

    def body(self) -> None:
        self.out.deref += 1


class Plant(Program):
    produced: INT = VAR(0)
    feeder: POINTER_TO[Feeder] = VAR()

    def body(self) -> None:
        if self.feeder.is_null:
            self.feeder = new(Feeder)
            self.feeder.deref(out=adr(self, "produced"))
        else:
            self.feeder.deref()


class PlantMoved(Program):
    spare: DINT = VAR(0)  # declared first: produced moves
    produced: INT = VAR(0)
    feeder: POINTER_TO[Feeder] = VAR()

    def body(self) -> None:
        self.feeder.deref()


def test_online_change_retargets_pointers_held_in_new_blocks() -> None:
    old = Plant()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask"), old)
    rt.run(cycles=3)
    kept_by_python = adr(old, "produced")
    rt.online_change(replace={"PlcTask.Plant": PlantMoved})
    moved = rt.programs()["PlcTask.Plant"]
    feeder = moved.feeder.deref
    assert feeder.out == adr(moved, "produced")
    rt.run(cycles=2)
    assert (moved.produced, old.produced) == (5, 3), "a write landed in the replaced instance"
    # An address nobody could adjust faults instead of reaching the orphan.
    with pytest.raises(PlcException) as caught:
        kept_by_python.deref = 9
    assert caught.value.code is AV and old.produced == 3
    delete(moved.feeder)


def test_online_change_nulls_heap_pointers_whose_variable_is_gone() -> None:
    class Gone(Program):
        feeder: POINTER_TO[Feeder] = VAR()

    old = Plant()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask"), old)
    rt.run(cycles=1)
    stray = new(Feeder)
    stray.deref.out = adr(old, "produced") + 4096  # moved past the block: designates no variable
    rt.online_change(replace={"PlcTask.Plant": Gone})
    gone = rt.programs()["PlcTask.Plant"]
    assert gone.feeder.deref.out.is_null and stray.deref.out.is_null
    delete(gone.feeder)
    delete(stray)


# ---------------------------------------------------------------------------
# The store compares full type descriptions
# ---------------------------------------------------------------------------

T_Speed = Annotated[REAL, Alias("T_Speed")]
T_SpeedDint = Annotated[DINT, Alias("T_Speed")]  # the same alias, its base type changed
T_Velocity = Annotated[REAL, Alias("T_Velocity")]  # another alias name, the same type


class before:  # noqa: N801 - the first version of the project
    class Speed(Program):
        speed: T_Speed = VAR(0.0, retain=True)
        limits: ARRAY[T_Speed] = VAR(bounds=(1, 2), persistent=True)

        def body(self) -> None:
            self.speed = 1.5
            self.limits[1] = 2.5


class retyped:  # noqa: N801 - T_Speed is now a DINT
    class Speed(Program):
        speed: T_SpeedDint = VAR(7, retain=True)
        limits: ARRAY[T_SpeedDint] = VAR(bounds=(1, 2), persistent=True)


class renamed:  # noqa: N801 - the variables now use another alias of REAL
    class Speed(Program):
        speed: T_Velocity = VAR(0.0, retain=True)
        limits: ARRAY[T_Velocity] = VAR(bounds=(1, 2), persistent=True)


def _restart(store: Path, program: Any) -> Runtime:
    rt = Runtime(store=store)
    rt.add_task(Task("PlcTask"), program)
    rt.run(cycles=0)
    return rt


@pytest.mark.parametrize(("version", "restored"), [
    (retyped.Speed, (7, [0, 0])),  # T_Speed REAL -> DINT: a changed declaration, not 1069547520
    (renamed.Speed, (1.5, [2.5, 0.0])),  # another alias name for REAL: the same declaration
])
def test_an_alias_is_compared_by_the_type_it_stands_for(tmp_path: Path, version: type, restored: Any) -> None:
    first = _restart(tmp_path, before.Speed())
    first.run(cycles=1)
    first.stop()
    again: Any = version()
    rt = _restart(tmp_path, again)
    assert (again.speed, list(again.limits)) == restored
    rt.stop()


# ---------------------------------------------------------------------------
# One Runtime per store
# ---------------------------------------------------------------------------


class Kept(Program):
    n: INT = VAR(0, retain=True)

    def body(self) -> None:
        self.n += 1


def test_a_second_runtime_on_the_same_store_is_refused_naming_the_lock_file(tmp_path: Path) -> None:
    first = _restart(tmp_path, Kept())
    first.run(cycles=2)
    second = Runtime(store=tmp_path)
    late = Kept()
    second.add_task(Task("PlcTask"), late)
    with pytest.raises(StoreLockedError, match=rf"store {tmp_path} is in use.*lock on {tmp_path / 'lock'}"):
        second.run(cycles=1)
    assert late.n == 0
    first.stop()
    # Once the first has stopped the second starts, restoring the last cycle of the first.
    second.run(cycles=1)
    assert late.n == 3
    second.stop()


def test_a_store_held_by_another_process_is_refused(tmp_path: Path) -> None:
    child = subprocess.Popen(
        [sys.executable, "-c", textwrap.dedent(f"""
            import sys
            from iecoop.runtime.store import RemanentStore
            store = RemanentStore({str(tmp_path)!r})
            print("ready", flush=True)
            sys.stdin.read()
        """)],
        stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
    )
    # Bounded: a child that never reports ready is killed, and readline() then returns b"".
    watchdog = threading.Timer(TIMEOUT, child.kill)
    watchdog.start()
    try:
        assert child.stdout is not None and child.stdout.readline().strip() == b"ready"
        rt = Runtime(store=tmp_path)
        rt.add_task(Task("PlcTask"), Kept())
        with pytest.raises(StoreLockedError, match="in use"):
            rt.run(cycles=1)
    finally:
        watchdog.cancel()
        child.kill()
        child.communicate(timeout=TIMEOUT)
    # The lock died with the process.
    rt.run(cycles=1)
    rt.stop()


def test_an_erased_newest_retain_slot_is_reported_not_silently_rolled_back(tmp_path: Path) -> None:
    first = _restart(tmp_path, Kept())
    first.run(cycles=3)  # three writes: sequence 3 is the newest
    first.stop()
    retain = tmp_path / "retain.dat"
    raw = bytearray(retain.read_bytes())
    slot_size = len(raw) // 2
    newest = max((0, 1), key=lambda slot: int.from_bytes(raw[slot * slot_size + 16:slot * slot_size + 24], "little"))
    raw[newest * slot_size:newest * slot_size + 80] = bytes(80)
    retain.write_bytes(bytes(raw))
    restarted = Kept()
    rt = Runtime(store=tmp_path)
    rt.add_task(Task("PlcTask"), restarted)
    with pytest.warns(RuntimeWarning, match="all zero bytes"):
        rt.run(cycles=0)
    assert any("a written slot was erased" in line for line in rt.boot_report), rt.boot_report
    assert restarted.n == 2  # the older generation, and the report says so
    rt.stop()


# ---------------------------------------------------------------------------
# A reset whose FB_init raises keeps the remanent data
# ---------------------------------------------------------------------------

fail_init = [False]


class Fragile(FunctionBlock):
    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
        if fail_init[0]:
            raise ValueError("encoder not found")
        return False


class Machine(Program):
    plain: INT = VAR(0)
    kept: INT = VAR(0, retain=True)
    saved: INT = VAR(0, persistent=True)
    part: Fragile = VAR()

    def body(self) -> None:
        self.plain += 1
        self.kept += 1
        self.saved += 1


@pytest.mark.parametrize("profile", ["twincat", "codesys"])
@pytest.mark.parametrize("operation", ["reset_cold", "download", "reset_origin"])
def test_a_reset_whose_fb_init_raises_keeps_remanent_data_and_faults(
    tmp_path: Path, profile: str, operation: str
) -> None:
    machine = Machine()
    rt = Runtime(store=tmp_path, profile=profile)
    rt.add_task(Task("PlcTask"), machine)
    rt.run(cycles=3)
    fail_init[0] = True
    try:
        with pytest.raises(PlcException, match=rf"{operation} failed at PlcTask.Machine: .*ValueError: encoder not found"):
            getattr(rt, operation)()
    finally:
        fail_init[0] = False
    assert (machine.kept, machine.saved) == (3, 3)
    assert rt.fault is not None and rt.fault.operation == operation
    assert isinstance(rt.fault.exception.__cause__ or rt.fault.exception, PlcException)
    assert "ValueError: encoder not found" in rt.fault.traceback
    with pytest.raises(PlcException, match="until a reset succeeds"):
        rt.run(cycles=1)
    assert (tmp_path / "retain.dat").exists(), "the store was cleared by a reset that failed"
    rt.stop()
    again = Machine()
    restarted = _restart(tmp_path, again)
    assert (again.kept, again.saved) == (3, 3)
    restarted.stop()


def test_a_reset_that_succeeds_after_a_failed_one_leaves_the_exception_state() -> None:
    machine = Machine()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask"), machine)
    rt.run(cycles=2)
    fail_init[0] = True
    try:
        with pytest.raises(PlcException):
            rt.reset_cold()
    finally:
        fail_init[0] = False
    rt.reset_cold()
    assert rt.fault is None and (machine.plain, machine.kept) == (0, 2)
    rt.run(cycles=1)
    assert machine.plain == 1


# ---------------------------------------------------------------------------
# One thread at a time; clock and profile per runtime
# ---------------------------------------------------------------------------


def test_run_from_a_second_thread_while_running_raises() -> None:
    inside = threading.Event()
    release = threading.Event()

    class Slow(Program):
        n: INT = VAR(0)

        def body(self) -> None:
            self.n += 1
            inside.set()
            release.wait(TIMEOUT)

    slow = Slow()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask"), slow)
    worker = threading.Thread(target=rt.run, kwargs={"cycles": 1}, name="first")
    worker.start()
    try:
        assert inside.wait(TIMEOUT)
        with pytest.raises(RuntimeError, match="from thread 'MainThread' while thread 'first' is in run"):
            rt.run(cycles=1)
        with pytest.raises(RuntimeError, match="one thread at a time"):
            rt.reset_cold()
    finally:
        release.set()
        worker.join(TIMEOUT)
    assert not worker.is_alive() and slow.n == 1
    rt.run(cycles=1)  # free again
    assert slow.n == 2


def test_run_from_inside_a_cycle_does_not_nest_cycles() -> None:
    seen: list[str] = []
    runtimes: list[Runtime] = []

    class Reentrant(Program):
        n: INT = VAR(0)

        def body(self) -> None:
            self.n += 1
            try:
                runtimes[0].run(cycles=5)
            except RuntimeError as exc:
                seen.append(str(exc))

    program = Reentrant()
    rt = Runtime(store=":memory:")
    runtimes.append(rt)
    rt.add_task(Task("PlcTask"), program)
    rt.run(cycles=2)
    assert program.n == 2 and len(seen) == 2
    assert "called from inside run()" in seen[0] and "cycles do not nest" in seen[0]


meet = threading.Barrier(2, timeout=TIMEOUT)
samples: dict[str, list[tuple[int, int, str]]] = {"Fast": [], "Slow": []}


class Sampler(Program):
    timer: TON = VAR()

    def body(self) -> None:
        # Both cycles are in progress at once: each must still see its own task's clock and vendor.
        meet.wait()
        self.timer(IN=True, PT=T("50ms"))
        samples[current_task().TaskName].append((current_clock().now_ms(), self.timer.ET, active_profile().name))
        meet.wait()


def test_two_runtimes_in_two_threads_read_their_own_clock_and_profile() -> None:
    cycles = 6
    meet.reset()
    fast = Runtime(store=":memory:", profile="twincat")
    fast.add_task(Task("Fast", interval=10), Sampler())
    slow = Runtime(store=":memory:", profile="codesys")
    slow.add_task(Task("Slow", interval=100), Sampler())
    errors: list[BaseException] = []

    def drive(rt: Runtime) -> None:
        try:
            rt.run(cycles=cycles)
        except BaseException as exc:  # reported below; the broken barrier frees the other thread
            errors.append(exc)
            meet.abort()

    threads = [threading.Thread(target=drive, args=(rt,)) for rt in (fast, slow)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join(TIMEOUT)
    assert not any(thread.is_alive() for thread in threads)
    assert errors == []
    # The timers read their own task's clock: 10 ms steps up to PT, or PT reached at the second call.
    assert samples["Fast"] == [(10 * i, min(10 * i, 50), "twincat") for i in range(cycles)]
    assert samples["Slow"] == [(100 * i, min(100 * i, 50), "codesys") for i in range(cycles)]
    # Neither leaked into the thread that started them.
    assert current_clock() is default_clock() and active_profile().name == "twincat"


# ---------------------------------------------------------------------------
# Nothing runs after stop()
# ---------------------------------------------------------------------------

exits: list[str] = []


class Closing(Program):
    kept: INT = VAR(0, retain=True)

    def fb_exit(self, in_copy_code: BOOL) -> BOOL:
        exits.append(f"FB_exit({in_copy_code})")
        return False


@pytest.mark.parametrize("operation", ["reset_cold", "reset_warm", "reset_origin", "download", "save_persistent",
                                       "online_change", "run"])
def test_after_stop_every_operation_raises_and_runs_no_fb_exit(tmp_path: Path, operation: str) -> None:
    rt = Runtime(store=tmp_path, profile="codesys")
    rt.add_task(Task("PlcTask"), Closing())
    rt.run(cycles=1)
    exits.clear()
    rt.stop()
    assert exits == ["FB_exit(False)"]
    call: dict[str, Any] = {"online_change": {"replace": {"PlcTask.Closing": Closing}}, "run": {"cycles": 1}}
    with pytest.raises(RuntimeError, match=rf"Runtime.{operation}\(\): the runtime was stopped"):
        getattr(rt, operation)(**call.get(operation, {}))
    assert exits == ["FB_exit(False)"]
    rt.stop()  # a second stop is still allowed and does nothing
    assert exits == ["FB_exit(False)"]


def test_a_store_left_without_stop_warns_nothing_and_is_reusable(tmp_path: Path) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        rt = _restart(tmp_path, Kept())
        rt.run(cycles=1)
        del rt  # dropped without stop(): its lock is released with it
        again = Kept()
        _restart(tmp_path, again).stop()
    assert again.n == 1
