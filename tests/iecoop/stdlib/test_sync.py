"""test_and_set, CriticalSection and the ExST S= / R= helpers (docs/reference/stdlib.md)."""

from __future__ import annotations

import dataclasses
import sys
import threading
import time
from collections.abc import Callable, Iterator

import pytest

from iecoop import (
    BOOL,
    DINT,
    DWORD,
    INT,
    POINTER_TO,
    REAL,
    STRING,
    UDINT,
    VAR,
    VAR_INPUT,
    VAR_INST,
    VAR_OUTPUT,
    VAR_STAT,
    AccessError,
    ExceptionCode,
    FunctionBlock,
    PlcException,
    Pointer,
    Struct,
    adr,
    Program,
    method,
    use_profile,
)
from iecoop import _config
from iecoop.profiles import CODESYS, TWINCAT
from iecoop.runtime import Runtime, Task
from iecoop.stdlib import CriticalSection, R, S, test_and_set

from tests import checked_only


class Shared(Struct):
    flag: BOOL = False
    dw: DWORD = 0
    ud: UDINT = 0
    small: INT = 0
    real: REAL = 0.0
    text: STRING = VAR("", length=4)
    nowhere: POINTER_TO[BOOL] = VAR()
    count: DINT = 0


@pytest.fixture
def fast_switching() -> Iterator[None]:
    """Switch threads as often as possible so races, if any, show."""
    before = sys.getswitchinterval()
    sys.setswitchinterval(1e-6)
    yield
    sys.setswitchinterval(before)


def run_threads(target: Callable[[], None], count: int) -> None:
    errors: list[BaseException] = []

    def guarded() -> None:
        try:
            target()
        except BaseException as exc:  # surfaced in the test thread
            errors.append(exc)

    threads = [threading.Thread(target=guarded) for _ in range(count)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join(timeout=30)
        assert not thread.is_alive(), "a thread is stuck"
    if errors:
        raise errors[0]


# ---------------------------------------------------------------------------
# test_and_set
# ---------------------------------------------------------------------------


def test_twincat_bool_true_when_acquired_and_unchanged_when_busy() -> None:
    shared = Shared()
    flag = adr(shared, "flag")
    assert test_and_set(flag) is True
    assert shared.flag is True
    assert test_and_set(flag) is False
    assert shared.flag is True
    shared.flag = False  # the release: Flag := FALSE
    assert test_and_set(flag) is True


def test_twincat_profile_with_an_integer_flag() -> None:
    shared = Shared()
    assert test_and_set(adr(shared, "dw")) is True
    assert shared.dw == 1
    assert test_and_set(adr(shared, "dw")) is False
    shared.dw = 5
    assert test_and_set(adr(shared, "dw")) is False
    assert shared.dw == 5


def test_codesys_dword_returns_the_previous_value_and_writes_one() -> None:
    shared = Shared()
    with use_profile("codesys"):
        assert test_and_set(adr(shared, "dw")) == 0  # acquired
        assert shared.dw == 1
        assert test_and_set(adr(shared, "dw")) == 1  # busy
        shared.dw = 7
        old = test_and_set(adr(shared, "dw"))
        assert (old, type(old), shared.dw) == (7, int, 1)
        assert test_and_set(adr(shared, "ud")) == 0 and shared.ud == 1
        assert test_and_set(adr(shared, "small")) == 0 and shared.small == 1


def test_codesys_profile_with_a_bool_flag_returns_the_previous_bool() -> None:
    shared = Shared()
    with use_profile(CODESYS):
        assert test_and_set(adr(shared, "flag")) is False
        assert shared.flag is True
        assert test_and_set(adr(shared, "flag")) is True


def test_the_two_flavours_are_inverse_on_success() -> None:
    """CDS ``TEST_AND_SET(dw) = 0`` <=> TC ``TestAndSet(flag) = TRUE``."""
    for start in (0, 1):
        tc, cds = Shared(dw=start), Shared(dw=start)
        with use_profile(TWINCAT):
            acquired = test_and_set(adr(tc, "dw"))
        with use_profile(CODESYS):
            previous = test_and_set(adr(cds, "dw"))
        assert acquired == (previous == 0)
        assert tc.dw == cds.dw == 1


def test_profile_is_read_at_the_call() -> None:
    shared = Shared()
    flag = adr(shared, "flag")
    with use_profile(dataclasses.replace(TWINCAT, test_and_set="previous_value")):
        assert test_and_set(flag) is False
    assert test_and_set(flag) is False  # TwinCAT flavour again: busy


def test_flag_inside_a_function_block() -> None:
    class Guarded(FunctionBlock):
        lock: BOOL = VAR(False)
        got: BOOL = VAR_OUTPUT(False)

        def body(self) -> None:
            self.got = bool(test_and_set(adr(self, "lock")))

    block = Guarded()
    block()
    assert block.got and block.lock
    block()
    assert not block.got


def test_rejects_what_is_not_a_pointer_to_a_flag() -> None:
    shared = Shared()
    with pytest.raises(TypeError, match="needs a pointer"):
        test_and_set(shared.flag)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="BOOL .*DWORD"):
        test_and_set(adr(shared, "real"))
    with pytest.raises(TypeError, match="BOOL .*DWORD"):
        test_and_set(adr(shared, "text"))
    with pytest.raises(TypeError, match="untyped"):
        test_and_set(Pointer())


def test_null_pointer_is_an_access_violation() -> None:
    with pytest.raises(PlcException) as caught:
        test_and_set(Shared().nowhere)
    assert caught.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


@pytest.mark.parametrize("profile", [TWINCAT, CODESYS], ids=lambda p: p.name)
@pytest.mark.parametrize("field", ["flag", "dw"])
def test_threads_contending_for_one_flag_never_hold_it_together(
    profile: object, field: str, fast_switching: None
) -> None:
    shared = Shared()
    flag = adr(shared, field)
    free: bool | int = False if field == "flag" else 0
    lock_for_stats = threading.Lock()
    holders = [0]
    most = [0]
    acquisitions = [0]
    rounds = 800

    def worker() -> None:
        with use_profile(profile):  # type: ignore[arg-type]
            done = 0
            while done < rounds:
                result = test_and_set(flag)
                got = result is True if profile is TWINCAT else result == 0
                if not got:
                    time.sleep(0)
                    continue
                with lock_for_stats:
                    holders[0] += 1
                    most[0] = max(most[0], holders[0])
                # A read-modify-write that only the holder performs.
                value = shared.count
                time.sleep(0)
                shared.count = value + 1
                with lock_for_stats:
                    holders[0] -= 1
                    acquisitions[0] += 1
                flag.deref = free
                done += 1

    run_threads(worker, 6)
    assert most[0] == 1
    assert acquisitions[0] == shared.count == 6 * rounds


# ---------------------------------------------------------------------------
# CriticalSection (FB_IecCriticalSection)
# ---------------------------------------------------------------------------


class Cell(FunctionBlock):
    section: CriticalSection = VAR()
    value: DINT = VAR_INPUT(0)


def test_enter_then_leave() -> None:
    section = CriticalSection()
    assert section.enter() is True
    assert section.leave() is True
    assert section.enter() is True
    assert section.leave() is True


def test_re_entry_by_the_holder_returns_false_without_deadlock() -> None:
    section = CriticalSection()
    assert section.enter() is True
    assert section.enter() is False
    assert section.leave() is True
    assert section.leave() is False  # already left


def test_leave_without_enter_returns_false() -> None:
    assert CriticalSection().leave() is False


def test_only_the_holder_can_leave() -> None:
    section = CriticalSection()
    assert section.enter()
    results: list[bool] = []
    run_threads(lambda: results.append(section.leave()), 1)
    assert results == [False]
    assert section.leave() is True


def test_enter_blocks_another_thread_until_leave() -> None:
    section = CriticalSection()
    assert section.enter()
    entered = threading.Event()
    results: list[bool] = []

    def other() -> None:
        results.append(section.enter())
        entered.set()
        results.append(section.leave())

    thread = threading.Thread(target=other)
    thread.start()
    assert not entered.wait(0.05), "enter() must block while another thread holds the section"
    assert section.leave()
    assert entered.wait(5)
    thread.join(5)
    assert results == [True, True]


def test_instances_are_independent() -> None:
    a, b = CriticalSection(), CriticalSection()
    assert a.enter() and b.enter()  # one thread may hold two sections
    other = CriticalSection()
    results: list[bool] = []
    run_threads(lambda: results.append(other.enter() and other.leave()), 1)
    assert results == [True]
    assert a.leave() and b.leave()


def test_two_views_of_one_nested_instance_share_the_section() -> None:
    cell = Cell()
    # A second view of the same memory, through its address (reads of cell.section return one kept view).
    first, second = cell.section, adr(cell.section).deref
    assert first is not second and first == second
    assert first.enter() is True
    assert second.enter() is False  # same thread, same section
    blocked = threading.Event()
    acquired = threading.Event()

    def other() -> None:
        blocked.set()
        assert cell.section.enter()
        acquired.set()
        assert cell.section.leave()

    thread = threading.Thread(target=other)
    thread.start()
    assert blocked.wait(5)
    assert not acquired.wait(0.05)
    assert second.leave() is True
    assert acquired.wait(5)
    thread.join(5)


def test_sections_of_two_cells_are_distinct() -> None:
    one, two = Cell(), Cell()
    assert one.section.enter() and two.section.enter()
    assert one.section.leave() and two.section.leave()


def test_critical_section_serialises_threads(fast_switching: None) -> None:
    section = CriticalSection()
    shared = Shared()
    inside = [0]
    most = [0]
    rounds = 300

    def worker() -> None:
        for _ in range(rounds):
            assert section.enter()
            inside[0] += 1
            most[0] = max(most[0], inside[0])
            value = shared.count
            time.sleep(0)
            shared.count = value + 1
            inside[0] -= 1
            assert section.leave()

    run_threads(worker, 6)
    assert most[0] == 1
    assert shared.count == 6 * rounds


def test_critical_section_used_from_a_body() -> None:
    class Writer(FunctionBlock):
        guard: CriticalSection = VAR()
        writes: DINT = VAR_OUTPUT(0)

        def body(self) -> None:
            if self.guard.enter():
                self.writes += 1
                self.guard.leave()

    writer = Writer()
    for _ in range(3):
        writer()
    assert writer.writes == 3


class Guarded(Program):
    guard: CriticalSection = VAR()
    fail: BOOL = VAR_INPUT(False)
    entered: DINT = VAR(0)

    def body(self) -> None:
        if self.guard.enter():
            self.entered += 1
            if self.fail:
                raise PlcException(ExceptionCode.RTSEXCPT_DIVIDEBYZERO, "fault between Enter() and Leave()")
            self.guard.leave()


@pytest.mark.parametrize("operation", ["reset_cold", "reset_origin", "download"])
def test_a_reset_releases_a_section_held_when_a_fault_stopped_the_task(operation: str) -> None:
    program = Guarded()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask"), program)
    rt.run(cycles=1)
    program.fail = True
    with pytest.raises(PlcException, match="fault between Enter"):
        rt.run(cycles=1)
    assert program.entered == 2
    getattr(rt, operation)()
    rt.run(cycles=3)
    assert program.entered == 3, "the section stayed held after the reset: enter() is FALSE forever"
    assert program.guard.enter() and program.guard.leave()


# ---------------------------------------------------------------------------
# ExST S= and R=
# ---------------------------------------------------------------------------


class Flags(Struct):
    a: BOOL = False
    b: BOOL = False
    n: INT = 0


def a_of(flags: Flags) -> bool:
    # Read through a call so mypy does not narrow the field between assertions.
    return flags.a


def test_s_sets_on_true_and_keeps_on_false() -> None:
    flags = Flags()
    assert S(flags, "a", False) is False
    assert a_of(flags) is False
    assert S(flags, "a", True) is True
    assert a_of(flags) is True
    assert S(flags, "a", False) is False
    assert a_of(flags) is True  # S= never resets


def test_r_resets_on_true_and_keeps_on_false() -> None:
    flags = Flags(a=True)
    assert R(flags, "a", False) is False
    assert a_of(flags) is True
    assert R(flags, "a", True) is True
    assert a_of(flags) is False
    assert R(flags, "a", False) is False
    assert a_of(flags) is False  # R= never sets


def test_chain_refers_to_the_operand_at_the_end_of_the_line() -> None:
    """``a S= b R= f(x);``: b is reset by f(x) and a is set by f(x), not by b."""
    calls: list[bool] = []

    def f(x: bool) -> bool:
        calls.append(x)
        return x

    flags = Flags(a=False, b=True)
    S(flags, "a", R(flags, "b", f(False)))
    assert (flags.a, flags.b) == (False, True)  # b was TRUE, yet a is not set
    S(flags, "a", R(flags, "b", f(True)))
    assert (flags.a, flags.b) == (True, False)
    assert calls == [False, True]  # the operand is evaluated once per line


def test_s_and_r_need_a_bool_variable() -> None:
    with pytest.raises(TypeError, match=r"Flags\.n is not a BOOL"):
        S(Flags(), "n", True)
    with pytest.raises(TypeError, match="S= and R= assign BOOL"):
        R(Flags(), "n", True)
    with pytest.raises(AttributeError):
        S(Flags(), "missing", True)


def test_false_condition_touches_nothing_not_even_an_unknown_name() -> None:
    assert S(Flags(), "missing", False) is False


class Motor(FunctionBlock):
    start: BOOL = VAR_INPUT(False)
    stop: BOOL = VAR_INPUT(False)
    running: BOOL = VAR_OUTPUT(False)
    latched: BOOL = VAR(False)
    ever: BOOL = VAR_STAT(False)
    armed: BOOL = VAR_INST(False, method="arm")
    fixed: BOOL = VAR(False, constant=True)

    def body(self) -> None:
        S(self, "latched", self.start)
        S(self, "running", self.start)
        R(self, "running", self.stop)
        S(self, "ever", self.start)

    @method
    def arm(self) -> None:
        S(self, "armed", True)

    @method
    def touch_fixed(self) -> None:
        S(self, "fixed", True)


def test_s_and_r_on_own_variables_inside_a_body() -> None:
    motor = Motor()
    def state() -> tuple[bool, bool, bool]:
        return motor.running, motor.latched, motor.ever

    motor(start=True)
    assert state() == (True, True, True)
    motor(start=False)
    assert state() == (True, True, True)
    motor(stop=True)
    assert state() == (False, True, True)
    motor.arm()
    assert motor.armed


def test_s_on_an_input_from_outside_is_allowed() -> None:
    motor = Motor()
    S(motor, "start", True)
    assert motor.start


@checked_only
def test_s_on_another_blocks_output_from_outside_is_rejected() -> None:
    motor = Motor()
    with pytest.raises(AccessError, match=r"VAR_OUTPUT Motor\.running cannot be written from"):
        S(motor, "running", True)
    with pytest.raises(AccessError, match="VAR Motor.latched"):
        R(motor, "latched", True)
    with pytest.raises(AccessError, match="VAR_STAT Motor.ever"):
        S(motor, "ever", True)
    assert not motor.running


@checked_only
def test_s_respects_constant_and_var_inst_rules() -> None:
    motor = Motor()
    with pytest.raises(AccessError, match="CONSTANT"):
        motor.touch_fixed()

    class Other(FunctionBlock):
        flag: BOOL = VAR_INST(False, method="one")

        @method
        def one(self) -> None:
            pass

        @method
        def two(self) -> None:
            S(self, "flag", True)

    with pytest.raises(AccessError, match="belongs to METHOD one"):
        Other().two()
