"""Chapter 7: THIS^ and SUPER^ with FB_Base and FB_1, cycle after cycle."""

from __future__ import annotations

import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from iecoop_examples.ch07_this_and_super import Base, Derived, Main, main
from iecoop import T
from iecoop.runtime import Runtime, Task
from iecoop.testing.strategies import wrap_int


def test_the_values_main_shows_after_each_cycle() -> None:
    program = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    for cycle in range(1, 11):
        rt.run(cycles=1)
        # +1 (SUPER^()), +10 +100 (THIS^.METH_DoIt), +10 (SUPER^.METH_DoIt) per call of fb1.
        assert program.i_base_cnt == cycle
        assert program.i_fb1_cnt == 121 * cycle
        assert program.fb1.i_this == 121 * (cycle - 1) + 111
        assert program.fb1.i_base == 121 * cycle


def test_super_body_runs_only_the_base_body() -> None:
    derived = Derived()
    Base.body(derived)
    assert derived.i_cnt == 1


def test_super_method_runs_only_the_base_version() -> None:
    base, derived = Base(), Derived()
    base.meth_do_it()
    derived.meth_do_it()
    assert (base.i_cnt, derived.i_cnt) == (10, 110)


def test_this_in_base_code_reaches_the_derived_override() -> None:
    base, derived = Base(), Derived()
    base.meth_do_twice()
    derived.meth_do_twice()
    assert (base.i_cnt, derived.i_cnt) == (20, 220)


def test_a_variable_typed_as_the_base_still_calls_the_override() -> None:
    blocks: list[Base] = [Base(), Derived()]
    for block in blocks:
        block.meth_do_it()
        block()
    # FB_1's body adds 121 on top of the 110 of its METH_DoIt.
    assert [b.i_cnt for b in blocks] == [11, 231]


@given(st.integers(min_value=-32768, max_value=32767))
def test_this_writes_the_block_variable_the_input_hides(value: int) -> None:
    base = Base()
    base.meth_set_count(value)
    assert base.i_cnt == value
    base()
    assert base.i_cnt == wrap_int(value + 1)


@given(st.integers(min_value=0, max_value=400))
@example(300)  # past 32767 / 121 cycles: iFb1Cnt has wrapped negative
def test_the_int_counters_wrap_like_the_plc(cycles: int) -> None:
    program = Main()
    for _ in range(cycles):
        program()
    assert program.i_base_cnt == cycles
    assert program.i_fb1_cnt == wrap_int(121 * cycles)
    assert program.fb1.i_base == program.i_fb1_cnt


def test_main_prints_the_three_cycles(capsys: pytest.CaptureFixture[str]) -> None:
    main()
    out = capsys.readouterr().out
    assert "    3         3      363        353        363" in out
    assert "FB_Base adds 20, FB_1 adds 220" in out
    assert "fb1.iCnt = 1121" in out
