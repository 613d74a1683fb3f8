"""Methods, properties, interfaces, inheritance and dynamic instances as mypy sees them.

ST::

    INTERFACE I_Sensor EXTENDS __SYSTEM.IQueryInterface
    METHOD Read : REAL   VAR_INPUT channel : INT; END_VAR
    PROPERTY Healthy : BOOL

    FUNCTION_BLOCK ABSTRACT FB_SensorBase IMPLEMENTS I_Sensor
    FUNCTION_BLOCK FB_Thermometer EXTENDS FB_SensorBase
"""

from __future__ import annotations

from typing import Any, assert_type

from iecoop import (
    ABSTRACT,
    BOOL,
    INT,
    LREAL,
    POINTER_TO,
    PRIVATE,
    PROTECTED,
    REAL,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    FunctionBlock,
    IQueryInterface,
    Pointer,
    Program,
    adr,
    delete,
    method,
    new,
    prop,
    query_interface,
    query_pointer,
)


class ISensor(IQueryInterface):
    # A prototype's body is '...'; mypy --strict reports it under a non-None result type.
    @method
    def read(self, channel: INT) -> REAL: ...

    @prop
    def healthy(self) -> BOOL: ...


class IResettable(IQueryInterface):
    @method
    def reset(self) -> None: ...


class SensorBase(FunctionBlock, ISensor, abstract=True):
    offset: REAL = VAR_INPUT(0.0)
    reads: INT = VAR_OUTPUT(0)

    @method(ABSTRACT)
    def raw(self, channel: INT) -> REAL: ...

    @method
    def read(self, channel: INT) -> REAL:
        self.reads += 1
        return self.raw(channel) + self.offset

    @prop
    def healthy(self) -> BOOL:
        return self.reads < 1000


class Thermometer(SensorBase, IResettable):
    calibration: LREAL = VAR(1.0)
    gain_internal: REAL = VAR(1.0)

    @method
    def raw(self, channel: INT) -> REAL:
        return channel * self.gain

    @method
    def reset(self) -> None:
        self.reads = 0
        self.scale()

    @method(PRIVATE)
    def scale(self) -> None:
        self.calibration = self.calibration * 2

    @method(PROTECTED)
    def trim(self, by: LREAL = 0.5) -> LREAL:
        return self.calibration - by

    @prop
    def gain(self) -> REAL:
        return self.gain_internal

    @gain.setter
    @method(PRIVATE)
    def gain(self, value: REAL) -> None:
        self.gain_internal = value


class Monitor(Program):
    sensor: ISensor = VAR_INPUT()
    value: REAL = VAR_OUTPUT(0.0)
    sensors_seen: INT = VAR(0)

    def body(self) -> None:
        if self.sensor:
            self.value = self.sensor.read(1)
            self.sensors_seen += 1


def use_blocks() -> None:
    thermo = Thermometer()
    thermo(offset=0.5)
    assert_type(thermo.read(3), float)
    assert_type(thermo.read(channel=3), float)
    assert_type(thermo.healthy, bool)
    assert_type(thermo.gain, float)
    thermo.reset()
    sensor: ISensor = thermo
    assert_type(sensor.read(2), float)
    monitor = Monitor()
    monitor(sensor=thermo)
    assert_type(monitor.sensor, ISensor)
    assert_type(monitor.value, float)
    resettable = query_interface(monitor.sensor, IResettable)
    assert_type(resettable, IResettable | None)
    if resettable is not None:
        resettable.reset()
    behind = query_pointer(monitor.sensor)
    assert_type(behind, Pointer[Any])
    assert behind == adr(thermo)
    monitor()
    assert (monitor.value, monitor.sensors_seen) == (1.5, 2)


def use_pointers() -> None:
    p = new(Thermometer)
    assert_type(p, Pointer[Thermometer])
    typed: POINTER_TO[Thermometer] = p
    assert_type(typed.deref, Thermometer)
    assert_type(p.deref.read(1), float)
    assert_type(p.deref.reads, int)
    counter: POINTER_TO[INT] = adr(p.deref, "reads")
    assert_type(counter.deref, int)
    counter.deref = counter.deref + 1
    assert_type(p + 2, Pointer[Thermometer])
    assert_type(p.is_null, bool)
    base: POINTER_TO[SensorBase] = new(Thermometer)
    assert_type(base.deref, SensorBase)
    delete(p)
    delete(base)
    assert not p and not base


def main() -> None:
    use_blocks()
    use_pointers()
