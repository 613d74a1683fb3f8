"""Chapter 14: __NEW / __DELETE, __ISVALIDREF, __QUERYINTERFACE, __QUERYPOINTER, __TRY, __VARINFO, TEST_AND_SET."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop_examples.ch14_operators import IDiagnosis, IDrive, IPrinter, MainOperators, MainTry, Motor, main
from iecoop import (
    BOOL,
    DWORD,
    INT,
    POINTER_TO,
    REFERENCE_TO,
    TYPE_CLASS,
    VAR,
    VAR_INPUT,
    DefinitionError,
    ExceptionCode,
    Interface,
    PlcException,
    Program,
    Struct,
    T,
    adr,
    delete,
    is_valid_ref,
    method,
    new,
    query_interface,
    query_pointer,
    ref_assign,
    test_and_set,
    use_profile,
    var_info,
)
from iecoop.runtime import Runtime, Task


class Holder(Struct):
    ref: REFERENCE_TO[Motor] = VAR()


class Flags(Struct):
    lock: BOOL = False
    dw_lock: DWORD = 0


def _runtime(*programs: object) -> Runtime:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), *programs)
    return rt


def test_main_operators_records_every_result_in_its_first_cycle() -> None:
    program = MainOperators()
    _runtime(program).run(cycles=3)
    assert (program.after_new - program.before, program.after_delete - program.after_new) == (1, -1)
    assert (program.new_speed, program.deleted_is_null) == (1500.0, True)
    assert program.dangling_exception == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION
    assert (program.valid_before, program.valid_after, program.valid_unbound) == (False, True, False)
    assert (program.query_diag, program.query_printer, program.pointer_is_motor) == (True, False, True)
    assert program.itf_diag == program.motor
    assert (program.speed_offset, program.speed_bits, program.speed_type) == (16, 64, "LREAL")
    assert (program.first_take, program.second_take, program.lock) == (True, False, False)


def test_new_runs_fb_init_and_delete_runs_fb_exit() -> None:
    probe = Motor()
    start = probe.instances
    pointers = [new(Motor) for _ in range(3)]
    assert probe.instances == start + 3
    for pointer in pointers:
        delete(pointer)
        assert pointer.is_null
    assert probe.instances == start
    delete(pointers[0])  # __DELETE of 0 does nothing


def test_every_pointer_to_a_deleted_instance_is_an_access_violation() -> None:
    p_motor = new(Motor)
    p_copy: POINTER_TO[Motor] = p_motor.typed(Motor)  # pCopy := pMotor: a second variable, same address
    p_motor.deref.move(10.0)
    assert p_copy.deref.speed == 10.0
    delete(p_motor)
    with pytest.raises(PlcException, match="RTSEXCPT_ACCESS_VIOLATION") as info:
        p_copy.deref.move(20.0)
    assert info.value.code is ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


def test_delete_accepts_only_what_new_created() -> None:
    motor = Motor()
    with pytest.raises(PlcException, match="__DELETE of memory that new\\(\\) did not create"):
        delete(adr(motor))


def test_isvalidref_follows_ref_assignments() -> None:
    holder, motor = Holder(), Motor()
    assert not is_valid_ref(holder, "ref")
    ref_assign(holder, "ref", motor)
    assert is_valid_ref(holder, "ref")
    assert holder.ref == motor
    ref_assign(holder, "ref", None)
    assert not is_valid_ref(holder, "ref")
    with pytest.raises(PlcException, match="reference is not bound"):
        holder.ref.move(1.0)


def test_isvalidref_also_reports_a_reference_into_deleted_memory() -> None:
    # A PLC only compares the reference with 0; iecoop also knows the memory is gone.
    holder, p_motor = Holder(), new(Motor)
    ref_assign(holder, "ref", p_motor)
    delete(p_motor)
    assert not is_valid_ref(holder, "ref")


def test_queryinterface_asks_the_object_not_the_variable() -> None:
    motor = Motor()
    drive: IDrive = motor
    diag = query_interface(drive, IDiagnosis)
    assert diag is not None and diag == motor and diag.healthy
    assert query_interface(drive, IPrinter) is None
    assert query_interface(None, IDiagnosis) is None
    assert query_pointer(drive) == adr(motor)
    assert query_pointer(None).is_null


def test_queryinterface_needs_iqueryinterface() -> None:
    class IPlain(Interface):
        @method
        def run(self) -> BOOL:
            raise NotImplementedError

    with pytest.raises(DefinitionError, match=r"Interface IPlain does not extend __System\.IQueryInterface \(C0239\)"):
        query_interface(Motor(), IPlain)


@settings(max_examples=40)
@given(st.lists(st.integers(min_value=0, max_value=32767), min_size=1, max_size=30))
def test_try_catch_keeps_the_task_running_through_divisions_by_zero(divisors: list[int]) -> None:
    program = MainTry()
    rt = _runtime(program)
    for cycle, divisor in enumerate(divisors, 1):
        program.divisor = divisor
        rt.run(cycles=1)
        assert program.result == (100 // divisor if divisor else -1)
        assert program.calls == cycle  # __FINALLY, every cycle
    assert program.errors == divisors.count(0)
    assert rt.fault is None


def test_without_try_the_same_division_stops_the_task() -> None:
    class Unprotected(Program):
        divisor: INT = VAR_INPUT(0)
        result: INT = VAR(0)

        def body(self) -> None:
            self.result = 100 // self.divisor

    program = Unprotected()
    rt = _runtime(program)
    with pytest.raises(PlcException, match="RTSEXCPT_DIVIDEBYZERO"):
        rt.run(cycles=1)
    assert rt.fault is not None and rt.fault.code is ExceptionCode.RTSEXCPT_DIVIDEBYZERO
    with pytest.raises(PlcException):
        rt.run(cycles=1)  # stays stopped until a reset


def test_varinfo_describes_a_variable_of_an_instance() -> None:
    info = var_info(Motor(), "speed")
    assert (info.ByteOffset, info.BitSize, info.TypeName, info.TypeClass) == (16, 64, "LREAL", TYPE_CLASS.TYPE_LREAL)
    assert var_info(Motor(), "axis").TypeClass is TYPE_CLASS.TYPE_INT


def test_test_and_set_twincat_and_codesys_flavours() -> None:
    flags = Flags()
    assert [test_and_set(adr(flags, "lock")) for _ in range(2)] == [True, False]
    flags.lock = False
    assert test_and_set(adr(flags, "lock")) is True
    with use_profile("codesys"):
        assert [test_and_set(adr(flags, "dw_lock")) for _ in range(2)] == [0, 1]


def test_main_prints_every_operator(capsys: pytest.CaptureFixture[str]) -> None:
    main()
    out = capsys.readouterr().out
    assert "pCopy^ after __DELETE: RTSEXCPT_ACCESS_VIOLATION" in out
    assert "__TRY 100 / 0: nResult = -1, nErrors = 1, nCalls = 2, RTSEXCPT_DIVIDEBYZERO" in out
