"""ABSTRACT: a block that is only a base, with members its derived blocks must write.

An ABSTRACT method or property has a declaration and no code; a block holding
one must itself be ABSTRACT, and an ABSTRACT block cannot be instantiated:
only a derived block that implements every abstract member can. The abstract
block may still hold data and finished code that uses the abstract members:
FB_Sensor's body scales the raw value with ``Scale``, which each sensor
writes its own way, and raises the alarm above ``HighLimit``. Variables of
the abstract type are allowed as ``POINTER TO`` / ``REFERENCE TO`` (or an
interface), never as an instance. ABSTRACT cannot be combined with PRIVATE
(nobody could implement it) nor with FINAL (nobody could override it).

ST::

    FUNCTION_BLOCK ABSTRACT FB_Sensor
    VAR_INPUT  nRaw : INT; END_VAR                 // analog card counts, 0..27648
    VAR_OUTPUT fValue : REAL; bAlarm : BOOL; END_VAR
    fValue := Scale(nRaw);
    bAlarm := fValue > HighLimit;

    METHOD PROTECTED ABSTRACT Scale : REAL
    VAR_INPUT nRaw : INT; END_VAR

    PROPERTY ABSTRACT Unit : STRING                // Get
    PROPERTY ABSTRACT HighLimit : REAL             // Get

    METHOD Describe : STRING                       // finished code using abstract members
    Describe := CONCAT(REAL_TO_STRING(fValue), CONCAT(' ', Unit));

    FUNCTION_BLOCK FB_TemperatureSensor EXTENDS FB_Sensor   // -50..150 degC
    METHOD PROTECTED Scale : REAL
    Scale := -50.0 + INT_TO_REAL(nRaw) * 200.0 / 27648.0;
    PROPERTY Unit : STRING         Get: Unit := 'degC';
    PROPERTY HighLimit : REAL      Get: HighLimit := 90.0;

    FUNCTION_BLOCK FB_PressureSensor EXTENDS FB_Sensor      // 0..10 bar
    METHOD PROTECTED Scale : REAL
    Scale := INT_TO_REAL(nRaw) * 10.0 / 27648.0;
    PROPERTY Unit : STRING         Get: Unit := 'bar';
    PROPERTY HighLimit : REAL      Get: HighLimit := 8.0;

    PROGRAM MAIN
    VAR
        fbTemperature : FB_TemperatureSensor;
        fbPressure    : FB_PressureSensor;
        aSensors      : ARRAY[1..2] OF POINTER TO FB_Sensor;
        nRaw          : INT;
        nAlarms, i    : INT;
    END_VAR
    aSensors[1] := ADR(fbTemperature);
    aSensors[2] := ADR(fbPressure);
    nRaw := MIN(nRaw + 1382, 27648);               // both inputs ramp up 5 % per cycle
    nAlarms := 0;
    FOR i := 1 TO 2 DO
        aSensors[i]^(nRaw := nRaw);
        IF aSensors[i]^.bAlarm THEN nAlarms := nAlarms + 1; END_IF
    END_FOR

    fbSensor : FB_Sensor;                          // error: FB_Sensor is ABSTRACT
"""

from __future__ import annotations

from iecoop import (
    ABSTRACT,
    ARRAY,
    BOOL,
    INT,
    POINTER_TO,
    PRIVATE,
    PROTECTED,
    REAL,
    STRING,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    DefinitionError,
    FunctionBlock,
    Program,
    T,
    adr,
    method,
    prop,
)
from iecoop.conversions import DINT_TO_REAL, REAL_TO_DINT, REAL_TO_STRING
from iecoop.runtime import Runtime, Task
from patterns.showcase.entry import Column, Showcase

__all__ = ["Main", "PressureSensor", "Sensor", "TemperatureSensor", "main"]

#: The full-scale count of a 16-bit analog input card (S7 / EL30xx style).
FULL_SCALE = 27648


def tenths(value: REAL) -> STRING:
    """``FUNCTION F_Tenths : STRING``: ``value`` to one decimal, as the HMI shows it ('72.5', '80.0').

    ST has no format specifier: round to tenths as a DINT, back to REAL, and let
    REAL_TO_STRING write the fewest digits that read back ('72.5', not '72.500000').
    """
    return REAL_TO_STRING(DINT_TO_REAL(REAL_TO_DINT(value * 10.0)) / 10.0)


class Sensor(FunctionBlock, abstract=True):
    """``FUNCTION_BLOCK ABSTRACT FB_Sensor``: finished code around abstract members."""

    raw: INT = VAR_INPUT(0)
    value: REAL = VAR_OUTPUT(0.0)
    alarm: BOOL = VAR_OUTPUT(False)

    def body(self) -> None:
        self.value = self.scale(self.raw)
        self.alarm = self.value > self.high_limit

    @method(PROTECTED | ABSTRACT)
    def scale(self, raw: INT) -> REAL:
        """``METHOD PROTECTED ABSTRACT Scale : REAL``."""
        raise NotImplementedError

    @prop
    @method(ABSTRACT)
    def unit(self) -> STRING:
        """``PROPERTY ABSTRACT Unit : STRING``."""
        raise NotImplementedError

    @prop
    @method(ABSTRACT)
    def high_limit(self) -> REAL:
        """``PROPERTY ABSTRACT HighLimit : REAL``."""
        raise NotImplementedError

    @method
    def describe(self) -> STRING:
        """``METHOD Describe : STRING``: uses the abstract ``Unit``, written by the derived block."""
        return f"{tenths(self.value)} {self.unit}"


class TemperatureSensor(Sensor):
    """``FUNCTION_BLOCK FB_TemperatureSensor EXTENDS FB_Sensor``: -50..150 degC."""

    @method(PROTECTED)
    def scale(self, raw: INT) -> REAL:
        return -50.0 + raw * 200.0 / FULL_SCALE

    @prop
    def unit(self) -> STRING:
        return "degC"

    @prop
    def high_limit(self) -> REAL:
        return 90.0


class PressureSensor(Sensor):
    """``FUNCTION_BLOCK FB_PressureSensor EXTENDS FB_Sensor``: 0..10 bar."""

    @method(PROTECTED)
    def scale(self, raw: INT) -> REAL:
        return raw * 10.0 / FULL_SCALE

    @prop
    def unit(self) -> STRING:
        return "bar"

    @prop
    def high_limit(self) -> REAL:
        return 8.0


class Main(Program):
    """``PROGRAM MAIN``: both sensors through ``ARRAY[1..2] OF POINTER TO FB_Sensor``."""

    temperature: TemperatureSensor = VAR()
    pressure: PressureSensor = VAR()
    sensors: ARRAY[POINTER_TO[Sensor]] = VAR(bounds=(1, 2))
    raw: INT = VAR(0)
    alarms: INT = VAR(0)

    def body(self) -> None:
        self.sensors[1] = adr(self, "temperature")
        self.sensors[2] = adr(self, "pressure")
        self.raw = min(self.raw + FULL_SCALE // 20, FULL_SCALE)
        self.alarms = 0
        for i in range(1, 3):
            sensor = self.sensors[i].deref
            sensor(raw=self.raw)
            if sensor.alarm:
                self.alarms += 1


def main() -> None:
    """Ramp both sensors up over 20 cycles, then show the four compile errors.

    >>> main()
    t= 50 ms  raw= 6910    -0.01 degC   2.50 bar  nAlarms=0
    t=100 ms  raw=13820    49.97 degC   5.00 bar  nAlarms=0
    t=170 ms  raw=23494   119.95 degC   8.50 bar  nAlarms=2
    t=200 ms  raw=27640   149.94 degC  10.00 bar  nAlarms=2
    fbSensor : FB_Sensor: DefinitionError: Plant.sensor: ABSTRACT Sensor cannot be instantiated; use REFERENCE_TO, POINTER_TO or an interface
    no Scale: DefinitionError: FUNCTION_BLOCK FlowSensor must be ABSTRACT or implement PROTECTED METHOD Sensor.scale: an ABSTRACT member is left unimplemented
    PRIVATE ABSTRACT: DefinitionError: FUNCTION_BLOCK LevelSensor: METHOD calibrate: ABSTRACT cannot be combined with PRIVATE
    ABSTRACT member: DefinitionError: FUNCTION_BLOCK Switch: METHOD check is ABSTRACT, so Switch must be declared abstract: class Switch(..., abstract=True)
    """
    program = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    for cycles in (5, 5, 7, 3):
        rt.run(cycles=cycles)
        temperature, pressure = program.temperature, program.pressure
        print(
            f"t={rt.time_ms:3d} ms  raw={program.raw:5d}  {temperature.value:7.2f} {temperature.unit}  "
            f"{pressure.value:5.2f} {pressure.unit}  nAlarms={program.alarms}"
        )
    try:

        class Plant(Program):  # VAR fbSensor : FB_Sensor; END_VAR
            sensor: Sensor = VAR()

    except DefinitionError as exc:
        print(f"fbSensor : FB_Sensor: DefinitionError: {exc}")
    try:

        class FlowSensor(Sensor):  # implements Unit and HighLimit, forgets Scale
            @prop
            def unit(self) -> STRING:
                return "m3/h"

            @prop
            def high_limit(self) -> REAL:
                return 100.0

    except DefinitionError as exc:
        print(f"no Scale: DefinitionError: {exc}")
    try:

        class LevelSensor(Sensor, abstract=True):
            @method(PRIVATE | ABSTRACT)
            def calibrate(self) -> None: ...

    except DefinitionError as exc:
        print(f"PRIVATE ABSTRACT: DefinitionError: {exc}")
    try:

        class Switch(FunctionBlock):
            @method(ABSTRACT)
            def check(self) -> BOOL:
                raise NotImplementedError

    except DefinitionError as exc:
        print(f"ABSTRACT member: DefinitionError: {exc}")


SHOWCASE = Showcase(
    columns=(Column("raw", lambda p: p.raw), Column("degC", lambda p: p.temperature.value, ".2f"), Column("bar", lambda p: p.pressure.value, ".2f"),
             Column("nAlarms", lambda p: p.alarms)),
    cycles=20,
)


if __name__ == "__main__":
    main()
