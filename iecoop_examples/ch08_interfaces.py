"""Interfaces: one contract, several unrelated blocks, one loop that drives them all.

An INTERFACE lists method and property prototypes and nothing else. A block
that IMPLEMENTS it promises all of them, each in its own way: the motor runs at
once, the valve reports open only after its 200 ms travel time, the lamp just
lights. A variable of the interface type is a reference to any such block, so
MAIN keeps one array of ``I_Actuator`` and starts or stops everything in one
loop, never naming a concrete block. An interface variable starts as 0: check
it with ``<> 0`` before calling, because a call through 0 is an access
violation.

ST::

    INTERFACE I_Actuator
    METHOD Start
    METHOD Stop
    PROPERTY Running : BOOL              // Get
    PROPERTY Name : STRING               // Get

    FUNCTION_BLOCK FB_Motor IMPLEMENTS I_Actuator
    VAR bOn : BOOL; nRunCycles : UDINT; END_VAR
    IF bOn THEN nRunCycles := nRunCycles + 1; END_IF
    // Start: bOn := TRUE;  Stop: bOn := FALSE;  Running := bOn;  Name := 'motor'

    FUNCTION_BLOCK FB_Valve IMPLEMENTS I_Actuator
    VAR bOpenCmd : BOOL; tonTravel : TON; END_VAR
    tonTravel(IN := bOpenCmd, PT := T#200MS);
    // Start: bOpenCmd := TRUE;  Stop: bOpenCmd := FALSE;  Running := tonTravel.Q;  Name := 'valve'

    FUNCTION_BLOCK FB_Lamp IMPLEMENTS I_Actuator
    VAR bLit : BOOL; END_VAR
    // Start: bLit := TRUE;  Stop: bLit := FALSE;  Running := bLit;  Name := 'lamp'

    PROGRAM MAIN
    VAR_INPUT bStartAll : BOOL; bStopAll : BOOL; END_VAR
    VAR
        fbMotor    : FB_Motor;
        fbValve    : FB_Valve;
        fbLamp     : FB_Lamp;
        aActuators : ARRAY[1..4] OF I_Actuator;   // [4] stays 0: a free slot
        nRunning   : INT;
        i          : INT;
    END_VAR
    aActuators[1] := fbMotor;
    aActuators[2] := fbValve;
    aActuators[3] := fbLamp;
    nRunning := 0;
    FOR i := 1 TO 4 DO
        IF aActuators[i] <> 0 THEN
            IF bStartAll THEN aActuators[i].Start(); END_IF
            IF bStopAll THEN aActuators[i].Stop(); END_IF
        END_IF
    END_FOR
    fbMotor();
    fbValve();
    fbLamp();
    FOR i := 1 TO 4 DO
        IF aActuators[i] <> 0 AND_THEN aActuators[i].Running THEN
            nRunning := nRunning + 1;
        END_IF
    END_FOR
"""

from __future__ import annotations

from iecoop import (
    ARRAY,
    BOOL,
    INT,
    STRING,
    UDINT,
    VAR,
    VAR_INPUT,
    FunctionBlock,
    Interface,
    PlcException,
    Program,
    T,
    method,
    prop,
)
from iecoop.runtime import Runtime, Task
from iecoop.stdlib import TON
from patterns.showcase.entry import Column, Showcase, press, steps

__all__ = ["IActuator", "Lamp", "Main", "Motor", "Valve", "main"]


class IActuator(Interface):
    """``INTERFACE I_Actuator``."""

    @method
    def start(self) -> None: ...

    @method
    def stop(self) -> None: ...

    @prop
    def running(self) -> BOOL:
        raise NotImplementedError

    @prop
    def name(self) -> STRING:
        raise NotImplementedError


class Motor(FunctionBlock, IActuator):
    """``FUNCTION_BLOCK FB_Motor IMPLEMENTS I_Actuator``: runs as soon as it is started."""

    on: BOOL = VAR(False)
    run_cycles: UDINT = VAR(0)

    def body(self) -> None:
        if self.on:
            self.run_cycles += 1

    @method
    def start(self) -> None:
        self.on = True

    @method
    def stop(self) -> None:
        self.on = False

    @prop
    def running(self) -> BOOL:
        return self.on

    @prop
    def name(self) -> STRING:
        return "motor"


class Valve(FunctionBlock, IActuator):
    """``FUNCTION_BLOCK FB_Valve IMPLEMENTS I_Actuator``: open once its travel time has passed."""

    open_cmd: BOOL = VAR(False)
    travel: TON = VAR()

    def body(self) -> None:
        self.travel(IN=self.open_cmd, PT=T("200ms"))

    @method
    def start(self) -> None:
        self.open_cmd = True

    @method
    def stop(self) -> None:
        self.open_cmd = False

    @prop
    def running(self) -> BOOL:
        return self.travel.Q

    @prop
    def name(self) -> STRING:
        return "valve"


class Lamp(FunctionBlock, IActuator):
    """``FUNCTION_BLOCK FB_Lamp IMPLEMENTS I_Actuator``."""

    lit: BOOL = VAR(False)

    @method
    def start(self) -> None:
        self.lit = True

    @method
    def stop(self) -> None:
        self.lit = False

    @prop
    def running(self) -> BOOL:
        return self.lit

    @prop
    def name(self) -> STRING:
        return "lamp"


class Main(Program):
    """``PROGRAM MAIN``: everything through ``ARRAY[1..4] OF I_Actuator``."""

    start_all: BOOL = VAR_INPUT(False)
    stop_all: BOOL = VAR_INPUT(False)
    motor: Motor = VAR()
    valve: Valve = VAR()
    lamp: Lamp = VAR()
    actuators: ARRAY[IActuator] = VAR(bounds=(1, 4))
    running: INT = VAR(0)

    def body(self) -> None:
        self.actuators[1] = self.motor
        self.actuators[2] = self.valve
        self.actuators[3] = self.lamp
        self.running = 0
        for i in range(1, 5):
            actuator = self.actuators[i]
            if actuator:
                if self.start_all:
                    actuator.start()
                if self.stop_all:
                    actuator.stop()
        self.motor()
        self.valve()
        self.lamp()
        for i in range(1, 5):
            actuator = self.actuators[i]
            if actuator and actuator.running:
                self.running += 1


def main() -> None:
    """Press "start all" in the first cycle and "stop all" at 500 ms; print every change.

    >>> main()
    t=  0 ms  nRunning=2  motor lamp
    t=200 ms  nRunning=3  motor valve lamp
    t=500 ms  nRunning=0
    motor ran 50 cycles
    aActuators[4].Start(): RTSEXCPT_ACCESS_VIOLATION
    """
    program = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    last = -1
    for _ in range(60):
        now = rt.time_ms
        program.start_all = now == 0
        program.stop_all = now == 500
        rt.run(cycles=1)
        if program.running != last:
            last = program.running
            names = [a.name for a in program.actuators if a and a.running]
            print(f"t={now:3d} ms  nRunning={last}  {' '.join(names)}".rstrip())
    print(f"motor ran {program.motor.run_cycles} cycles")
    try:
        program.actuators[4].start()
    except PlcException as exc:
        print(f"aActuators[4].Start(): {exc.code.name}")


SHOWCASE = Showcase(
    columns=(Column("nRunning", lambda p: p.running), Column("motor", lambda p: p.motor.running), Column("valve", lambda p: p.valve.running),
             Column("lamp", lambda p: p.lamp.running), Column("motor cycles", lambda p: p.motor.run_cycles, watch=False)),
    script=steps(*press("start_all", 1), *press("stop_all", 51)),
    cycles=60,
)


if __name__ == "__main__":
    main()
