"""Chapter 10: the ABSTRACT FB_Sensor, its two sensors, and what ABSTRACT forbids."""

from __future__ import annotations

import struct

import pytest
from hypothesis import given
from hypothesis import strategies as st

from iecoop_examples.ch10_abstract import FULL_SCALE, Main, PressureSensor, Sensor, TemperatureSensor, main
from iecoop import (
    ABSTRACT,
    BOOL,
    FINAL,
    REAL,
    REFERENCE_TO,
    STRING,
    VAR,
    AccessError,
    DefinitionError,
    FunctionBlock,
    T,
    method,
    new,
    prop,
    ref_assign,
)
from iecoop.runtime import Runtime, Task


def _real(value: float) -> float:
    rounded: float = struct.unpack("<f", struct.pack("<f", value))[0]
    return rounded


def test_both_sensors_through_pointers_cycle_by_cycle() -> None:
    program = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    for cycle in range(1, 26):
        rt.run(cycles=1)
        raw = min(cycle * (FULL_SCALE // 20), FULL_SCALE)
        temperature = _real(-50.0 + raw * 200.0 / FULL_SCALE)
        pressure = _real(raw * 10.0 / FULL_SCALE)
        assert program.raw == raw
        assert (program.temperature.value, program.pressure.value) == (temperature, pressure)
        assert program.temperature.alarm is (temperature > 90.0)
        assert program.pressure.alarm is (pressure > 8.0)
        assert program.alarms == int(temperature > 90.0) + int(pressure > 8.0)
    assert program.raw == FULL_SCALE
    assert program.temperature.describe() == "150.0 degC"
    assert program.pressure.describe() == "10.0 bar"


@given(st.integers(min_value=0, max_value=FULL_SCALE))
def test_each_sensor_scales_its_own_way_in_the_common_body(raw: int) -> None:
    temperature, pressure = TemperatureSensor(), PressureSensor()
    temperature(raw=raw)
    pressure(raw=raw)
    assert -50.0 <= temperature.value <= 150.0
    assert 0.0 <= pressure.value <= 10.0
    assert temperature.alarm is (temperature.value > 90.0)
    assert pressure.alarm is (pressure.value > 8.0)


def test_the_array_of_pointers_designates_the_derived_blocks() -> None:
    program = Main()
    program()
    assert isinstance(program.sensors[1].deref, TemperatureSensor)
    assert isinstance(program.sensors[2].deref, PressureSensor)
    assert program.sensors[1].deref.unit == "degC"


def test_a_reference_to_the_abstract_type_is_allowed() -> None:
    class Display(FunctionBlock):
        sensor: REFERENCE_TO[Sensor] = VAR()

    display, pressure = Display(), PressureSensor()
    ref_assign(display, "sensor", pressure)
    display.sensor(raw=FULL_SCALE)
    assert (pressure.value, pressure.alarm) == (10.0, True)
    assert display.sensor.unit == "bar"


def test_the_abstract_block_cannot_be_instantiated_or_declared() -> None:
    with pytest.raises(DefinitionError, match="ABSTRACT FUNCTION_BLOCK Sensor cannot be instantiated"):
        Sensor()
    with pytest.raises(TypeError, match="__NEW: ABSTRACT Sensor cannot be instantiated"):
        new(Sensor)
    with pytest.raises(DefinitionError, match=r"Plant\.sensor: ABSTRACT Sensor cannot be instantiated; use REFERENCE"):

        class Plant(FunctionBlock):
            sensor: Sensor = VAR()


def test_the_protected_scale_is_not_callable_from_outside() -> None:
    with pytest.raises(AccessError, match=r"PROTECTED METHOD TemperatureSensor\.scale cannot be called from"):
        TemperatureSensor().scale(100)


def test_every_abstract_member_must_be_implemented() -> None:
    with pytest.raises(
        DefinitionError, match=r"FlowSensor must be ABSTRACT or implement PROTECTED METHOD Sensor\.scale"
    ):

        class FlowSensor(Sensor):
            @prop
            def unit(self) -> STRING:
                return "m3/h"

            @prop
            def high_limit(self) -> REAL:
                return 100.0


def test_a_derived_block_may_stay_abstract() -> None:
    class AnalogSensor(Sensor, abstract=True):
        @method
        def percent(self) -> REAL:
            return self.raw * 100.0 / FULL_SCALE

    with pytest.raises(DefinitionError, match="ABSTRACT FUNCTION_BLOCK AnalogSensor cannot be instantiated"):
        AnalogSensor()


def test_an_abstract_method_cannot_be_final() -> None:
    with pytest.raises(DefinitionError, match="METHOD reset: ABSTRACT cannot be combined with FINAL"):

        class Gauge(Sensor, abstract=True):
            @method(ABSTRACT | FINAL)
            def reset(self) -> None: ...


def test_an_abstract_member_needs_an_abstract_block() -> None:
    with pytest.raises(DefinitionError, match=r"METHOD check is ABSTRACT, so Switch must be declared abstract"):

        class Switch(FunctionBlock):
            @method(ABSTRACT)
            def check(self) -> BOOL:
                raise NotImplementedError


def test_a_block_cannot_be_abstract_and_final() -> None:
    with pytest.raises(DefinitionError, match="cannot be both ABSTRACT and FINAL"):

        class Frozen(FunctionBlock, abstract=True, final=True):
            pass


def test_main_prints_the_ramp_and_four_errors(capsys: pytest.CaptureFixture[str]) -> None:
    main()
    out = capsys.readouterr().out
    assert "t=200 ms  raw=27640   149.94 degC  10.00 bar  nAlarms=2" in out
    assert out.count("DefinitionError:") == 4
