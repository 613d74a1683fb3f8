"""LSP: the base's caller breaks on the derived sensor; the compliant hierarchy makes the misuse impossible."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import REAL, ExceptionCode, PlcException, T, query_interface
from iecoop.runtime import Runtime, Task
from patterns.solid.lsp import (
    COUNTS_PER_PERCENT,
    LSB,
    AnalogActuator,
    AnalogOutput,
    IActuator,
    IAnalogValue,
    LspCell,
    PressureSensor,
    PressureSensorAsActuator,
    RampOnActuator,
    SetpointRamp,
    ValueMonitor,
    clamp,
)

percent = st.floats(min_value=-50.0, max_value=150.0, allow_nan=False)
raw = st.integers(min_value=0, max_value=100 * COUNTS_PER_PERCENT)


def _cell() -> tuple[Runtime, LspCell]:
    cell = LspCell()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), cell)
    return rt, cell


def keeps_the_write_contract(channel: AnalogActuator, value: REAL) -> bool:
    """``FB_AnalogActuator.Write``'s postcondition, as every caller of the base relies on it."""
    accepted = channel.write(value)
    return accepted and abs(channel.value - clamp(value)) <= LSB / 2


# ---------------------------------------------------------------------------
# What goes wrong in the violating design
# ---------------------------------------------------------------------------


@settings(max_examples=100, deadline=None)
@given(percent)
def test_the_actuator_keeps_the_base_contract_for_every_value(value: float) -> None:
    assert keeps_the_write_contract(AnalogActuator(), value)


@settings(max_examples=100, deadline=None)
@given(percent, raw)
def test_the_derived_sensor_breaks_the_base_contract(value: float, measured: int) -> None:
    sensor = PressureSensorAsActuator()
    sensor(raw_in=measured)
    # mypy accepts the sensor as an AnalogActuator, as the compiler accepts it for FB_AnalogActuator.
    assert not keeps_the_write_contract(sensor, value)
    assert sensor.raw == measured and sensor.refused == 1


def test_the_ramp_written_for_the_base_accepts_the_sensor_and_times_out() -> None:
    rt, cell = _cell()
    flags = []
    for _ in range(201):  # t = 0 .. 2000 ms
        rt.run(cycles=1)
        flags.append((cell.ramp_sensor.done, cell.ramp_sensor.timed_out))
    # The watchdog started at t = 0 and fires at t = 2000 ms; the ramp is never done.
    assert flags == [(False, False)] * 200 + [(False, True)]
    assert cell.sensor_on_base.value == 42.5  # the pressure never moved
    assert cell.sensor_on_base.refused == 201  # one refused write per cycle, silently
    assert (cell.ramp_actuator.done, cell.actuator.value) == (True, 75.0)


def test_the_same_ramp_on_the_actuator_is_done_after_six_cycles() -> None:
    rt, cell = _cell()
    values = []
    for _ in range(7):
        rt.run(cycles=1)
        values.append(cell.actuator.value)
    assert values == [12.5, 25.0, 37.5, 50.0, 62.5, 75.0, 75.0]
    assert (cell.ramp_actuator.done, cell.ramp_actuator.timed_out) == (True, False)


def test_the_base_caller_still_needs_its_in_out_output() -> None:
    with pytest.raises(TypeError, match=r"VAR_IN_OUT 'output' must be assigned at every call"):
        RampOnActuator()(target=10.0)  # type: ignore[call-arg]


# ---------------------------------------------------------------------------
# What holds in the compliant design
# ---------------------------------------------------------------------------


def test_the_sensor_is_not_an_actuator_for_mypy_or_at_runtime() -> None:
    sensor = PressureSensor()
    ramp = SetpointRamp()
    # mypy --strict (warn_unused_ignores) fails this file if it ever accepts the line below.
    with pytest.raises(TypeError, match=r"SetpointRamp\.output: PressureSensor does not implement IActuator"):
        ramp.output = sensor  # type: ignore[assignment]
    assert not ramp.output
    assert query_interface(sensor, IActuator) is None
    assert query_interface(sensor, IAnalogValue) is not None
    assert query_interface(AnalogOutput(), IActuator) is not None
    assert not hasattr(sensor, "write")


def test_every_actuator_substitutes_for_an_analog_value() -> None:
    rt, cell = _cell()
    rt.run(cycles=10)
    assert (cell.monitor_output.shown, cell.monitor_sensor.shown) == (75.0, 42.5)
    cell.pressure_raw = 30400  # 95 %
    rt.run(cycles=1)
    assert (cell.monitor_sensor.shown, cell.monitor_sensor.high, cell.monitor_output.high) == (95.0, True, False)


@settings(max_examples=100, deadline=None)
@given(percent, percent, st.sampled_from([2.5, 10.0, 12.5, 40.0]))
def test_the_compliant_ramp_reaches_any_target_monotonically(start: float, target: float, step: float) -> None:
    output = AnalogOutput()
    output.write(start)
    ramp = SetpointRamp()
    ramp.output = output
    goal = clamp(target)
    first = output.value
    cycles = math.ceil(abs(goal - first) / step) if abs(goal - first) > LSB else 0
    previous = first
    for _ in range(cycles):
        ramp(target=target, step=step)
        now = output.value
        assert min(first, goal) - LSB <= now <= max(first, goal) + LSB  # never overshoots
        assert abs(goal - now) <= abs(goal - previous) + LSB  # never moves away
        previous = now
    ramp(target=target, step=step)
    assert ramp.done and not ramp.timed_out
    assert abs(output.value - goal) <= LSB


def test_the_compliant_ramp_on_the_output_matches_the_base_ramp_on_the_actuator() -> None:
    rt, cell = _cell()
    for target in (75.0, 20.0, 100.0, 0.0):
        cell.target = target
        for _ in range(10):
            rt.run(cycles=1)
            assert cell.output.value == cell.actuator.value
            assert cell.output_ramp.done == cell.ramp_actuator.done
    assert cell.output.value == 0.0


def test_a_ramp_without_an_output_faults_with_an_access_violation() -> None:
    with pytest.raises(PlcException, match=r"SetpointRamp\.output: IActuator\.value called through a null") as info:
        SetpointRamp()(target=10.0)
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION
    with pytest.raises(PlcException, match="null interface reference"):
        ValueMonitor()()
