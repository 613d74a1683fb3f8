"""Chapter 9: the rectangle by value, pointer and reference; pointer arithmetic; the 20-value average."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from iecoop_examples.ch09_pointers_and_references import (
    Rectangle,
    SrArrays,
    SrAverage,
    SrRectangles,
    area_calc_pointer,
    area_calc_ref,
    area_calc_val,
    average_reference,
    average_values,
    main,
)
from iecoop import (
    ARRAY,
    INT,
    REAL,
    REFERENCE_TO,
    VAR,
    ExceptionCode,
    PlcException,
    Pointer,
    Struct,
    T,
    adr,
    sizeof,
)
from iecoop.runtime import Runtime, Task

SIDES = st.floats(min_value=0.0, max_value=1e4, width=32)
READINGS = st.floats(min_value=-1e6, max_value=1e6, width=32)


class Readings(Struct):
    values: ARRAY[REAL] = VAR(bounds=(1, 20))


class Holder(Struct):
    rect: REFERENCE_TO[Rectangle] = VAR()


def _runtime(*programs: object) -> Runtime:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), *programs)
    return rt


def test_the_area_is_50_by_value_pointer_and_reference_every_cycle() -> None:
    program = SrRectangles()
    rt = _runtime(program)
    assert (program.rectangle1.area, program.rectangle2.area, program.rectangle3.area) == (0.0, 0.0, 0.0)
    for _ in range(3):
        rt.run(cycles=1)
        assert (program.rectangle1.area, program.rectangle2.area, program.rectangle3.area) == (50.0, 50.0, 50.0)
    assert adr(program.ref_rectangle) == adr(program, "rectangle3")  # the reference is an alias


@given(SIDES, SIDES)
def test_the_three_ways_agree_for_any_rectangle(a_side: float, b_side: float) -> None:
    by_value, by_pointer, by_reference = (Rectangle(a_side=a_side, b_side=b_side) for _ in range(3))
    by_value.area = area_calc_val(by_value.a_side, by_value.b_side)
    assert area_calc_pointer(adr(by_pointer)) is True
    returned = area_calc_ref(by_reference)
    assert by_value.area == by_pointer.area == by_reference.area == returned


def test_a_null_pointer_is_checked_a_reference_cannot_be() -> None:
    assert area_calc_pointer(Pointer()) is False  # IF pRect = 0: RETURN, nothing written
    holder = Holder()
    with pytest.raises(PlcException, match=r"RTSEXCPT_ACCESS_VIOLATION.*reference is not bound") as info:
        area_calc_ref(holder.rect)
    assert info.value.code is ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


def test_the_array_through_pointers_cycle_by_cycle() -> None:
    program = SrArrays()
    rt = _runtime(program)
    rt.run(cycles=1)
    assert (program.fifo[3], program.fifo[5], program.fifo2[3], program.fifo2[5]) == (4, 5, 4, 0)
    assert program.total == 9
    rt.run(cycles=1)  # now aintFIFO2 := paint^ copies the 5 written in the first cycle
    assert (program.fifo2[3], program.fifo2[5], program.total) == (4, 5, 9)


def test_pointer_arithmetic_steps_sizeof_int_bytes() -> None:
    program = SrArrays()
    for i in range(1, 21):
        adr(program, "fifo", i).deref = 10 * i  # test set-up through explicit addresses
    first = adr(program, "fifo", 1)
    for i in range(1, 21):
        assert adr(program, "fifo", i) - first == (i - 1) * sizeof(INT)
        assert (first + (i - 1) * sizeof(INT)).deref == 10 * i
    assert program.paint == 0  # not called yet: the pointer is still 0
    assert adr(program, "fifo") == first


def test_the_loop_leaves_pint_one_past_the_array_on_the_next_variable() -> None:
    program = SrArrays()
    program()
    assert program.pint - adr(program, "fifo", 1) == 20 * sizeof(INT)
    assert program.pint == adr(program, "fifo2", 1)  # no bounds check on a pointer, as on the PLC


def test_a_pointer_outside_its_block_is_an_access_violation() -> None:
    readings = Readings()
    outside = adr(readings, "values", 20) + sizeof(REAL)
    with pytest.raises(PlcException, match=r"RTSEXCPT_ACCESS_VIOLATION.*outside its 80-byte block"):
        _ = outside.deref
    with pytest.raises(PlcException, match="RTSEXCPT_ARRAYBOUNDS"):
        _ = readings.values[21]


def test_the_average_by_value_and_by_reference_every_cycle() -> None:
    program = SrAverage()
    rt = _runtime(program)
    for _ in range(3):
        rt.run(cycles=1)
        assert program.avg_values == program.avg_reference
        assert math.isclose(program.avg_values, 124.0, abs_tol=1e-4)
    assert min(program.fifo) < 118.1 and max(program.fifo) > 129.9  # the sine of amplitude 6


@given(st.lists(READINGS, min_size=20, max_size=20))
def test_the_average_by_value_equals_the_average_by_reference(values: list[float]) -> None:
    readings = Readings()
    for i, value in enumerate(values, 1):
        readings.values[i] = value
    by_value = average_values(*readings.values)
    assert by_value == average_reference(adr(readings, "values"))
    assert math.isclose(by_value, sum(values) / 20, rel_tol=1e-9, abs_tol=1e-6)


def test_main_prints_areas_pointers_and_averages(capsys: pytest.CaptureFixture[str]) -> None:
    main()
    out = capsys.readouterr().out
    assert "areas: by value 50.0, by pointer 50.0, by reference 50.0" in out
    assert "= 40 bytes after the loop: 20 steps of SIZEOF(INT) = 2; nSum = 9" in out
    assert "by value 124.0000, by reference 124.0000" in out
