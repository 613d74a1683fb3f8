"""Block calls the iecoop.mypy plugin must report. Never run: each mistake sits in a function nobody calls."""

from __future__ import annotations

from iecoop import (
    ARRAY,
    BOOL,
    INT,
    REAL,
    REFERENCE_TO,
    VAR,
    VAR_IN_OUT,
    VAR_INPUT,
    FunctionBlock,
    Interface,
    Program,
    Struct,
    adr,
    method,
)


class IValve(Interface):
    @method
    def open(self) -> BOOL: ...


class Recipe(Struct):
    temperature: REAL = 20.0


class Pump(FunctionBlock):
    pass


class Dosing(FunctionBlock):
    enable: BOOL = VAR_INPUT(False)
    setpoint: REAL = VAR_INPUT(0.0)
    steps: ARRAY[INT] = VAR_INPUT(bounds=(1, 3))
    recipe: Recipe = VAR_INPUT()
    valve: IValve = VAR_INPUT()
    limit: REFERENCE_TO[INT] = VAR_INPUT()

    @method
    def level(self) -> INT: ...  # E: Missing return statement


class Mixer(Dosing):
    batch: Recipe = VAR_IN_OUT()
    counter: INT = VAR_IN_OUT()


class Main(Program):
    mode: INT = VAR_INPUT(0)
    mixer: Mixer = VAR()
    counter: INT = VAR(0)

    def body(self) -> None:
        self.mixer(enable=True)  # E: Missing named argument "batch" for "Mixer" # E: Missing named argument "counter" for "Mixer"


def wrong_inputs(dosing: Dosing, mixer: Mixer, main: Main) -> None:
    dosing(enable="yes")  # E: Argument "enable" to "Dosing" has incompatible type "str"; expected "bool"
    dosing(nonexistent=1)  # E: Unexpected keyword argument "nonexistent" for "Dosing"
    dosing(enabel=True)  # E: Unexpected keyword argument "enabel" for "Dosing"; did you mean "enable"?
    dosing(True)  # E: Too many positional arguments for "Dosing"
    dosing(setpoint="fast")  # E: Argument "setpoint" to "Dosing" has incompatible type "str"; expected "float"
    dosing(steps=5)  # E: Argument "steps" to "Dosing" has incompatible type "int"; expected "ARRAY[int] | list[Any] | tuple[Any, ...]"
    dosing(recipe=[20.0])  # E: Argument "recipe" to "Dosing" has incompatible type "list[float]"; expected "Recipe | dict[str, Any]"
    dosing(valve=Pump())  # E: Argument "valve" to "Dosing" has incompatible type "Pump"; expected "IValve | None"
    dosing(limit=5)  # E: Argument "limit" to "Dosing" has incompatible type "int"; expected "Pointer[Any]"
    mixer(batch=Recipe(), counter=adr(main, "counter"), enable=1.5)  # E: Argument "enable" to "Mixer" has incompatible type "float"; expected "bool"
    mixer(batch=Recipe(), counter=3)  # E: Argument "counter" to "Mixer" has incompatible type "int"; expected "Pointer[Any]"
    mixer(batch=Pump(), counter=adr(main, "counter"))  # E: Argument "batch" to "Mixer" has incompatible type "Pump"; expected "Recipe | Pointer[Any]"
    main(mode="auto")  # E: Argument "mode" to "Main" has incompatible type "str"; expected "int"
    main(mixer=Mixer())  # E: Unexpected keyword argument "mixer" for "Main"
