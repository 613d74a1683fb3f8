"""Block calls the iecoop.mypy plugin accepts: each input takes what the call accepts at run time.

ST::

    INTERFACE I_Valve
        METHOD Open : BOOL
        PROPERTY Healthy : BOOL
    FUNCTION_BLOCK FB_Dosing
    VAR_INPUT  enable : BOOL; setpoint : REAL; mode : E_Mode; steps : ARRAY[1..3] OF INT;
               recipe : ST_Recipe; valve : I_Valve; limit : REFERENCE TO INT; END_VAR
    VAR_IN_OUT batch : ST_Recipe; counter : INT; END_VAR
    VAR_IN_OUT CONSTANT scale : INT; END_VAR
    FUNCTION_BLOCK FB_FastDosing EXTENDS FB_Dosing   VAR_INPUT boost : BOOL; END_VAR
"""

from __future__ import annotations

from iecoop import (
    ABSTRACT,
    ARRAY,
    BOOL,
    INT,
    NULL,
    PROTECTED,
    REAL,
    REFERENCE_TO,
    STRING,
    VAR,
    VAR_IN_OUT,
    VAR_INPUT,
    VAR_OUTPUT,
    FunctionBlock,
    IecEnum,
    Interface,
    Program,
    Struct,
    adr,
    method,
    prop,
)


class IValve(Interface):
    # The prototype form the docs teach: '...' is the whole member, under --strict.
    @method
    def open(self) -> BOOL: ...

    @prop
    def healthy(self) -> BOOL: ...


class Mode(IecEnum):
    MANUAL = 0
    AUTO = 1


class Recipe(Struct):
    temperature: REAL = 20.0
    steps: INT = 0


class Valve(FunctionBlock, IValve):
    @method
    def open(self) -> BOOL:
        return True

    @prop
    def healthy(self) -> BOOL:
        return True


class Dosing(FunctionBlock):
    enable: BOOL = VAR_INPUT(False)
    setpoint: REAL = VAR_INPUT(0.0)
    mode: Mode = VAR_INPUT(Mode.MANUAL)
    label: STRING = VAR_INPUT("", length=8)
    steps: ARRAY[INT] = VAR_INPUT(bounds=(1, 3))
    recipe: Recipe = VAR_INPUT()
    valve: IValve = VAR_INPUT()
    limit: REFERENCE_TO[INT] = VAR_INPUT()
    batch: Recipe = VAR_IN_OUT()
    counter: INT = VAR_IN_OUT()
    scale: INT = VAR_IN_OUT(constant=True)
    dosed: INT = VAR_OUTPUT(0)

    def body(self) -> None:
        self.counter += 1
        if self.enable and self.mode == Mode.AUTO and self.valve and self.valve.open():
            self.dosed += self.steps[1] * self.scale
            self.batch.steps += 1


class FastDosing(Dosing):
    boost: BOOL = VAR_INPUT(False)


class Dispenser(FunctionBlock, abstract=True):
    @method(ABSTRACT | PROTECTED)
    def amount(self) -> INT: ...


class Main(Program):
    dosing: FastDosing = VAR()
    valve: Valve = VAR()
    batch: Recipe = VAR()
    counter: INT = VAR(0)
    limit: INT = VAR(100)

    def body(self) -> None:
        # inherited inputs, a list for an ARRAY, a dict for a STRUCT, an object for an interface,
        # adr() for a REFERENCE TO and an elementary in-out, the instance for a STRUCT in-out,
        # a plain value for an in-out CONSTANT
        self.dosing(
            enable=True, boost=True, setpoint=2, mode=Mode.AUTO, label="A1", steps=[3, 0, 0],
            recipe={"temperature": 40.0}, valve=self.valve, limit=adr(self, "limit"),
            batch=self.batch, counter=adr(self, "counter"), scale=2,
        )


def later_calls(main: Main) -> None:
    dosing = main.dosing
    dosing(batch=adr(main, "batch"), counter=adr(main, "counter"), scale=adr(main, "limit"), steps=dosing.steps)
    dosing(batch=main.batch, counter=adr(main, "counter"), scale=1, valve=NULL)
    dosing(batch=main.batch, counter=adr(main, "counter"), scale=1, valve=None, recipe=Recipe(), steps=(1, 2))


def drive_any(block: FunctionBlock, program: Program, inputs: dict[str, object]) -> None:
    # Through the base types themselves a call stays open: generic code passes inputs it got as data.
    block(**inputs)
    program(enable=True)


def main() -> None:
    program = Main()
    program()
    assert (program.dosing.dosed, program.counter, program.batch.steps) == (6, 1, 1)
    later_calls(program)
    assert (program.counter, program.dosing.dosed, program.batch.steps) == (4, 6 + 3 * 100, 2)
