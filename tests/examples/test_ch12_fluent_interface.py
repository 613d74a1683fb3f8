"""Chapter 12: FB_Calculator's fluent interface, chained in MAIN every cycle."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from iecoop_examples.ch12_fluent_interface import Calculator, ICalculator, Main, main
from iecoop import T, adr
from iecoop.runtime import Runtime, Task

FINITE = st.floats(min_value=-1e9, max_value=1e9, allow_nan=False)


def test_main_chains_one_calculation_per_cycle() -> None:
    program = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    for cycle in range(1, 21):
        rt.run(cycles=1)
        expected = (cycle + 3) * 2 - 1
        assert program.result == expected
        assert program.half == expected / 2
        assert program.error is True
        assert program.calculator.result == expected / 2 + 1


def test_every_step_returns_the_same_instance() -> None:
    calculator = Calculator()
    step = calculator.set_number(1.0)
    assert isinstance(step, ICalculator)
    assert step == calculator and adr(step) == adr(calculator)
    assert calculator.add(1.0).multiply_by(3.0) == calculator


def test_the_chain_reads_as_the_calculation() -> None:
    calculator = Calculator()
    assert calculator.set_number(4.0).add(3.0).multiply_by(2.0).result == 14.0
    assert calculator.subtract(4.0).divide_by(5.0).result == 2.0
    assert calculator.error is False


def test_a_division_by_zero_sets_error_and_keeps_the_chain_going() -> None:
    calculator = Calculator()
    assert calculator.set_number(10.0).divide_by(0.0).add(5.0).result == 15.0
    assert calculator.error is True
    assert calculator.set_number(1.0).error is False  # SetNumber starts a fresh calculation


STEPS = st.lists(st.tuples(st.sampled_from(["add", "subtract", "multiply_by", "divide_by"]), FINITE), max_size=12)


@given(FINITE, STEPS)
def test_any_chain_equals_the_same_steps_done_one_by_one(start: float, steps: list[tuple[str, float]]) -> None:
    chained: ICalculator = Calculator().set_number(start)
    expected, error = start, False
    for name, value in steps:
        chained = getattr(chained, name)(value)
        if name == "add":
            expected += value
        elif name == "subtract":
            expected -= value
        elif name == "multiply_by":
            expected *= value
        elif value == 0.0:
            error = True
        else:
            expected /= value
    assert chained.result == expected or (math.isnan(chained.result) and math.isnan(expected))
    assert chained.error is error


def test_main_prints_three_cycles(capsys: pytest.CaptureFixture[str]) -> None:
    main()
    out = capsys.readouterr().out
    assert "    3     11.0    5.5  True    6.5" in out
