"""Classes and objects: one class, ``FB_Car``, and three cars built from it.

A class is a template and an object is an instance of it. In IEC 61131-3 the
class is the FUNCTION_BLOCK: it declares the data every car has (its VAR
sections), what a car does (its METHODs) and how its data is read and written
(its PROPERTYs). Each instance declared in a program is an object with its
own memory, so ``fbMercedes``, ``fbBmw`` and ``fbAudi`` keep their own brand,
colour and last action: a command given to the Mercedes never moves the others.

ST::

    FUNCTION_BLOCK FB_Car
    VAR
        _sBrand : STRING;
        _sColor : STRING;
        sAction : STRING;
    END_VAR

    METHOD PUBLIC Accelerate
    sAction := 'accelerate';

    METHOD PUBLIC Drive
    sAction := 'drive';

    METHOD PUBLIC Brake
    sAction := 'brake';

    PROPERTY PUBLIC Brand : STRING
        Get: Brand := _sBrand;
        Set: _sBrand := Brand;

    PROPERTY PUBLIC Color : STRING
        Get: Color := _sColor;
        Set: _sColor := Color;

    PROGRAM MAIN
    VAR
        // the class FB_Car, instantiated three times: three objects
        fbMercedes  : FB_Car;
        fbBmw       : FB_Car;
        fbAudi      : FB_Car;
        sColor      : STRING;
        bAccelerate : BOOL;        // commands for fbMercedes, reset once done
        bDrive      : BOOL;
        bBrake      : BOOL;
    END_VAR
    // the object fbMercedes: calls to its methods
    IF bAccelerate THEN
        fbMercedes.Accelerate();
        bAccelerate := FALSE;
    END_IF
    IF bDrive THEN
        fbMercedes.Drive();
        bDrive := FALSE;
    END_IF
    IF bBrake THEN
        fbMercedes.Brake();
        bBrake := FALSE;
    END_IF
    // calls to the properties of the three objects
    fbMercedes.Brand := 'Mercedes';
    fbMercedes.Color := 'black';
    fbBmw.Brand := 'BMW';
    fbBmw.Color := 'white';
    fbAudi.Brand := 'Audi';
    fbAudi.Color := 'red';
    sColor := fbMercedes.Color;
"""

from __future__ import annotations

from iecoop import BOOL, STRING, VAR, VAR_INPUT, FunctionBlock, Program, T, adr, method, prop, sizeof
from iecoop.runtime import Runtime, Task
from patterns.showcase.entry import Column, Showcase, press, steps

__all__ = ["Car", "Main", "main"]


class Car(FunctionBlock):
    """``FUNCTION_BLOCK FB_Car``: the class; every instance is one car."""

    brand_internal: STRING = VAR("")
    color_internal: STRING = VAR("")
    last_action: STRING = VAR("")

    @method
    def accelerate(self) -> None:
        """``METHOD PUBLIC Accelerate``."""
        self.last_action = "accelerate"

    @method
    def drive(self) -> None:
        """``METHOD PUBLIC Drive``."""
        self.last_action = "drive"

    @method
    def brake(self) -> None:
        """``METHOD PUBLIC Brake``."""
        self.last_action = "brake"

    @prop
    def brand(self) -> STRING:
        """``PROPERTY PUBLIC Brand : STRING``."""
        return self.brand_internal

    @brand.setter
    def brand(self, value: STRING) -> None:
        self.brand_internal = value

    @prop
    def color(self) -> STRING:
        """``PROPERTY PUBLIC Color : STRING``."""
        return self.color_internal

    @color.setter
    def color(self, value: STRING) -> None:
        self.color_internal = value


class Main(Program):
    """``PROGRAM MAIN``: three objects of one class, commands for one of them."""

    accelerate: BOOL = VAR_INPUT(False)
    drive: BOOL = VAR_INPUT(False)
    brake: BOOL = VAR_INPUT(False)
    mercedes: Car = VAR()
    bmw: Car = VAR()
    audi: Car = VAR()
    color: STRING = VAR("")

    def body(self) -> None:
        if self.accelerate:
            self.mercedes.accelerate()
            self.accelerate = False
        if self.drive:
            self.mercedes.drive()
            self.drive = False
        if self.brake:
            self.mercedes.brake()
            self.brake = False
        self.mercedes.brand = "Mercedes"
        self.mercedes.color = "black"
        self.bmw.brand = "BMW"
        self.bmw.color = "white"
        self.audi.brand = "Audi"
        self.audi.color = "red"
        self.color = self.mercedes.color


def main() -> None:
    """Give fbMercedes a command every 20 ms and show the three objects after each.

    >>> main()
    t= 0 ms  bAccelerate  Mercedes black: 'accelerate'  BMW white: ''  Audi red: ''
    t=20 ms  bDrive       Mercedes black: 'drive'  BMW white: ''  Audi red: ''
    t=40 ms  bBrake       Mercedes black: 'brake'  BMW white: ''  Audi red: ''
    MAIN.sColor = 'black'; the command flags are FALSE again: True
    SIZEOF(FB_Car) = 256 bytes for each object; ADR(fbBmw) - ADR(fbMercedes) = 256
    """
    program = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    cars = (program.mercedes, program.bmw, program.audi)
    for command in ("accelerate", "drive", "brake"):
        now = rt.time_ms
        setattr(program, command, True)  # an operator's one-shot command (an online write)
        rt.run(cycles=2)
        objects = "  ".join(f"{car.brand} {car.color}: {car.last_action!r}" for car in cars)
        print(f"t={now:2d} ms  b{command.capitalize():<11} {objects}")
    flags_reset = not (program.accelerate or program.drive or program.brake)
    print(f"MAIN.sColor = {program.color!r}; the command flags are FALSE again: {flags_reset}")
    gap = adr(program.bmw) - adr(program.mercedes)
    print(f"SIZEOF(FB_Car) = {sizeof(Car)} bytes for each object; ADR(fbBmw) - ADR(fbMercedes) = {gap}")


SHOWCASE = Showcase(
    columns=(Column("fbMercedes", lambda p: p.mercedes.last_action), Column("fbBMW", lambda p: p.bmw.last_action),
             Column("fbAudi", lambda p: p.audi.last_action), Column("sColor", lambda p: p.color)),
    script=steps(*press("accelerate", 2), *press("drive", 4), *press("brake", 6)),
    cycles=8,
)


if __name__ == "__main__":
    main()
