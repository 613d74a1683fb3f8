"""Inheritance: FB_NewEngine EXTENDS FB_Engine and adds what the old one lacked.

A derived block gets every variable, method and property of its base, may add
its own (the ``Gear`` property), and may override a method: FB_NewEngine's
``Start`` first runs the base's ``Start`` with ``SUPER^.Start(...)`` and then
does its own part. A PROTECTED method (``Ramp``) is usable in the base and in
every derived block, never from outside. Through the interface both engines
are used the same way, and each call reaches the most derived ``Start``. An
override must keep the base's signature, and a FINAL method or block cannot
be overridden or extended: both are compile errors.

ST::

    INTERFACE I_Engine
    METHOD Start
    VAR_INPUT gear : INT := 2; velocity : LREAL := 8.0; END_VAR

    FUNCTION_BLOCK FB_Engine IMPLEMENTS I_Engine
    VAR_INPUT  MaxVelocity : LREAL := 10.0; END_VAR
    VAR_OUTPUT Running : BOOL; Odometer : LREAL; END_VAR
    VAR        VelocityInternal : LREAL; RampSteps : INT; END_VAR
    IF Running THEN Odometer := Odometer + VelocityInternal; END_IF

    METHOD Start
    VelocityInternal := MIN(velocity, MaxVelocity);
    Running := TRUE;
    Ramp();

    METHOD Stop
    Running := FALSE;
    VelocityInternal := 0;

    METHOD PROTECTED Ramp
    RampSteps := RampSteps + 1;

    FUNCTION_BLOCK FB_NewEngine EXTENDS FB_Engine
    VAR GearInternal : INT; END_VAR

    PROPERTY Gear : INT
        Get: Gear := GearInternal;
        Set: GearInternal := Gear;

    METHOD Start
    SUPER^.Start(gear := gear, velocity := velocity);
    THIS^.Gear := gear;
    Ramp();

    PROGRAM MAIN
    VAR
        fbEngine    : FB_Engine;
        fbNewEngine : FB_NewEngine;
        aEngines    : ARRAY[1..2] OF I_Engine;
        nCycle, i   : INT;
    END_VAR
    nCycle := nCycle + 1;
    IF nCycle = 1 THEN
        aEngines[1] := fbEngine;
        aEngines[2] := fbNewEngine;
        FOR i := 1 TO 2 DO
            aEngines[i].Start(1, 7.5);           // FB_NewEngine's own Start for [2]
        END_FOR
    ELSIF nCycle = 6 THEN
        fbEngine.Stop();
        fbNewEngine.Stop();
    END_IF
    fbEngine();
    fbNewEngine();
"""

from __future__ import annotations

from iecoop import (
    ARRAY,
    BOOL,
    FINAL,
    INT,
    LREAL,
    PROTECTED,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    AccessError,
    DefinitionError,
    FunctionBlock,
    Interface,
    Program,
    T,
    method,
    prop,
)
from iecoop.runtime import Runtime, Task
from patterns.showcase.entry import Column, Showcase

__all__ = ["Engine", "IEngine", "Main", "NewEngine", "main"]


class IEngine(Interface):
    """``INTERFACE I_Engine``."""

    @method
    def start(self, gear: INT = 2, velocity: LREAL = 8.0) -> None: ...


class Engine(FunctionBlock, IEngine):
    """``FUNCTION_BLOCK FB_Engine IMPLEMENTS I_Engine``: the base block."""

    max_velocity: LREAL = VAR_INPUT(10.0)
    running: BOOL = VAR_OUTPUT(False)
    odometer: LREAL = VAR_OUTPUT(0.0)
    velocity_internal: LREAL = VAR(0.0)
    ramp_steps: INT = VAR(0)

    def body(self) -> None:
        if self.running:
            self.odometer += self.velocity_internal

    @method
    def start(self, gear: INT = 2, velocity: LREAL = 8.0) -> None:
        self.velocity_internal = min(velocity, self.max_velocity)
        self.running = True
        self.ramp()

    @method
    def stop(self) -> None:
        self.running = False
        self.velocity_internal = 0.0

    @method(PROTECTED)
    def ramp(self) -> None:
        self.ramp_steps += 1


class NewEngine(Engine):
    """``FUNCTION_BLOCK FB_NewEngine EXTENDS FB_Engine``: adds the gear, extends Start."""

    gear_internal: INT = VAR(0)

    @prop
    def gear(self) -> INT:
        """``PROPERTY Gear : INT``."""
        return self.gear_internal

    @gear.setter
    def gear(self, value: INT) -> None:
        self.gear_internal = value

    @method
    def start(self, gear: INT = 2, velocity: LREAL = 8.0) -> None:
        super().start(gear, velocity)  # SUPER^.Start(gear := gear, velocity := velocity)
        self.gear = gear
        self.ramp()


class Main(Program):
    """``PROGRAM MAIN``: starts both engines through I_Engine, stops them at cycle 6."""

    engine: Engine = VAR()
    new_engine: NewEngine = VAR()
    engines: ARRAY[IEngine] = VAR(bounds=(1, 2))
    cycle: INT = VAR(0)

    def body(self) -> None:
        self.cycle += 1
        if self.cycle == 1:
            self.engines[1] = self.engine
            self.engines[2] = self.new_engine
            for i in range(1, 3):
                self.engines[i].start(1, 7.5)
        elif self.cycle == 6:
            self.engine.stop()
            self.new_engine.stop()
        self.engine()
        self.new_engine()


def main() -> None:
    """Run MAIN for 100 ms, then try what inheritance forbids.

    >>> main()
    t=100 ms
      FB_Engine     Running=False  Odometer=37.5  RampSteps=1
      FB_NewEngine  Running=False  Odometer=37.5  RampSteps=2  Gear=1
    fbNewEngine.Ramp(): AccessError: PROTECTED METHOD Engine.ramp cannot be called from main in module ...: PROTECTED members are callable only inside Engine and its derived blocks
    Start(gear : LREAL): DefinitionError: FUNCTION_BLOCK BadEngine: interface of overridden method 'start' ... (C0094): base (gear: INT, ...) -> None, here (gear: LREAL, ...) -> None
    FINAL Stop: DefinitionError: FUNCTION_BLOCK QuietEngine: FINAL PUBLIC METHOD SafeEngine.stop cannot be overridden
    """
    program = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    rt.run(cycles=10)
    old, new = program.engine, program.new_engine
    print(f"t={rt.time_ms} ms")
    print(f"  FB_Engine     Running={old.running}  Odometer={old.odometer}  RampSteps={old.ramp_steps}")
    print(
        f"  FB_NewEngine  Running={new.running}  Odometer={new.odometer}  RampSteps={new.ramp_steps}  Gear={new.gear}"
    )
    try:
        new.ramp()
    except AccessError as exc:
        print(f"fbNewEngine.Ramp(): AccessError: {exc}")
    try:

        class BadEngine(Engine):  # METHOD Start with VAR_INPUT gear : LREAL
            @method
            def start(self, gear: LREAL = 2.0, velocity: LREAL = 8.0) -> None: ...

    except DefinitionError as exc:
        print(f"Start(gear : LREAL): DefinitionError: {exc}")
    try:

        class SafeEngine(Engine):  # METHOD FINAL Stop
            @method(FINAL)
            def stop(self) -> None:
                super().stop()

        class QuietEngine(SafeEngine):
            @method
            def stop(self) -> None: ...

    except DefinitionError as exc:
        print(f"FINAL Stop: DefinitionError: {exc}")


SHOWCASE = Showcase(
    columns=(Column("FB_Engine running", lambda p: p.engine.running), Column("odometer", lambda p: p.engine.odometer, ".1f"),
             Column("FB_NewEngine running", lambda p: p.new_engine.running), Column("odometer ", lambda p: p.new_engine.odometer, ".1f"),
             Column("gear", lambda p: p.new_engine.gear)),
    cycles=10,
)


if __name__ == "__main__":
    main()
