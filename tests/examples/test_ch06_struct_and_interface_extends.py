"""Chapter 6: STRUCT EXTENDS (members, layout, a TON inside) and INTERFACE EXTENDS (several bases)."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from iecoop_examples.ch06_struct_and_interface_extends import (
    IMotor,
    IStart,
    IStop,
    Main,
    Motor,
    Nested1,
    Nested2,
    StructBase1,
    StructSub1,
    StructSub2,
    main,
)
from iecoop import BOOL, REAL, DefinitionError, FunctionBlock, Struct, T, method, prop, sizeof, var_info
from iecoop.runtime import Runtime, Task


def test_main_cycle_by_cycle() -> None:
    program = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    for cycle in range(1, 121):
        rt.run(cycles=1)
        st2 = program.structure2
        elapsed = min((cycle - 1) * 10, 1000)
        assert (st2.b_bool1, st2.i_int, st2.r_real) == (True, cycle, 0.5 * cycle)
        assert st2.t_time == elapsed
        assert st2.b_bool2 is program.structure11.s_struct.b_bool is ((cycle - 1) * 10 >= 1000)
        assert program.motor.running is (cycle < 50)
    assert (program.motor.starts, program.motor.speed) == (1, 1450.0)


def test_the_derived_structs_hold_the_base_members_first() -> None:
    assert (sizeof(StructBase1), sizeof(StructSub1), sizeof(StructSub2)) == (8, 48, 56)
    st2 = StructSub2()
    names = ("b_bool1", "i_int", "r_real", "t_time", "ton_timer", "b_bool2")
    offsets = [var_info(st2, name).ByteOffset for name in names]
    assert offsets == [0, 2, 4, 8, 16, 48]
    assert isinstance(st2, StructSub1) and isinstance(st2, StructBase1)


@given(st.booleans(), st.integers(min_value=-32768, max_value=32767), st.floats(width=32, allow_nan=False))
def test_the_sub_struct_takes_the_base_members_at_construction(flag: bool, number: int, real: float) -> None:
    st2 = StructSub2(b_bool1=flag, i_int=number, r_real=real, b_bool2=not flag)
    assert (st2.b_bool1, st2.i_int, st2.r_real, st2.b_bool2) == (flag, number, real, not flag)


def test_nesting_reaches_the_same_member_one_level_deeper() -> None:
    outer = Nested1(s_string="outer")
    outer.s_struct.b_bool = True
    assert outer.s_struct == Nested2(b_bool=True)
    assert sizeof(Nested1) == sizeof(Nested2) + 81


def test_a_derived_struct_cannot_repeat_a_base_member_anywhere_up_the_chain() -> None:
    with pytest.raises(DefinitionError, match=r"Bad\.b_bool1: b_bool1 is already declared in StructBase1"):

        class Bad(StructSub1):
            b_bool1: BOOL = False


def test_a_struct_cannot_extend_two_structs() -> None:
    class OtherBase(Struct):
        flag: BOOL = False

    with pytest.raises(DefinitionError, match=r"STRUCT Both cannot EXTEND both StructBase1 and OtherBase"):

        class Both(StructBase1, OtherBase):
            pass


def test_the_derived_interface_holds_every_prototype() -> None:
    motor = Motor()
    assert isinstance(motor, IMotor) and isinstance(motor, IStart) and isinstance(motor, IStop)
    assert issubclass(IMotor, IStart) and issubclass(IMotor, IStop)


def test_start_and_stop_report_whether_they_changed_anything() -> None:
    motor = Motor()
    assert [motor.start(), motor.start(), motor.stop(), motor.stop(), motor.start()] == [True, False, True, False, True]
    assert motor.starts == 2
    motor.speed = -10.0
    assert motor.speed == 0.0


def test_one_instance_behind_the_three_interface_variables() -> None:
    program = Main()
    program()
    for itf in (program.itf_motor, program.itf_start, program.itf_stop):
        assert itf == program.motor


def test_a_block_must_implement_the_base_interfaces_prototypes_too() -> None:
    with pytest.raises(
        DefinitionError, match=r"there is no implementation for method 'stop' defined in interface 'IMotor' \(C0087\)"
    ):

        class HalfMotor(FunctionBlock, IMotor):
            @method
            def start(self) -> BOOL:
                return True

            @prop
            def speed(self) -> REAL:
                return 0.0

            @speed.setter
            def speed(self, value: REAL) -> None: ...


def test_main_prints_layout_cycles_and_errors(capsys: pytest.CaptureFixture[str]) -> None:
    main()
    out = capsys.readouterr().out
    assert "ST_Sub2 = 56; bBool2 at byte 48" in out
    assert "t=1000 ms  iInt=101  rReal=50.5  tTime=1000  bBool2=True" in out
    assert out.count("DefinitionError:") == 2
