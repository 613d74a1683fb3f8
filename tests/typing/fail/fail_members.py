"""Method, property, interface and pointer misuse mypy must report. Never run."""

from __future__ import annotations

from iecoop import (
    BOOL,
    INT,
    LREAL,
    POINTER_TO,
    REAL,
    VAR,
    VAR_INPUT,
    FunctionBlock,
    IQueryInterface,
    adr,
    method,
    new,
    prop,
    query_interface,
)


class ISensor(IQueryInterface):
    @method
    def calibrate(self, offset: REAL) -> None: ...


class Engine(FunctionBlock):
    max_velocity: LREAL = VAR_INPUT(10.0)
    gear_internal: INT = VAR(0)

    @method
    def start(self, gear: INT = 2, velocity: LREAL = 8.0) -> BOOL:
        return velocity <= self.max_velocity

    @method
    def describe(self) -> INT:
        return "engine"  # E: Incompatible return value type (got "str", expected "int")

    @prop
    def gear(self) -> INT:
        return self.gear_internal


class Pump(FunctionBlock):
    pass


def misuse_members(engine: Engine) -> None:
    engine.strat()  # E: "Engine" has no attribute "strat"
    engine.max_velocty = 3.0  # E: "Engine" has no attribute "max_velocty"
    engine.start(gear="third")  # E: Argument "gear" to "start" of "Engine" has incompatible type "str"; expected "int"
    engine.start(2, 8.0, True)  # E: Too many arguments for "start" of "Engine"
    engine.start(speed=4.0)  # E: Unexpected keyword argument "speed"
    running: str = engine.start()  # E: expression has type "bool", variable has type "str"
    engine.gear = 3  # E: Property "gear" defined in "Engine" is read-only
    del running


def misuse_interfaces(engine: Engine) -> None:
    sensor: ISensor = engine  # E: expression has type "Engine", variable has type "ISensor"
    found = query_interface(engine, ISensor)
    found.calibrate(1.0)  # E: Item "None" of "ISensor | None" has no attribute "calibrate"
    del sensor


def misuse_pointers() -> None:
    p = new(Engine)
    speed: str = p.deref.max_velocity  # E: expression has type "float", variable has type "str"
    counter: POINTER_TO[INT] = adr(p.deref, "gear_internal")
    text: str = counter.deref  # E: expression has type "int", variable has type "str"
    q: POINTER_TO[Pump] = p  # E: expression has type "Pointer[Engine]", variable has type "Pointer[Pump]"
    p.deref.stop()  # E: "Engine" has no attribute "stop"
    del speed, text, q
