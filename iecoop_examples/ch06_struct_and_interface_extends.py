"""EXTENDS for data types and interfaces: STRUCT EXTENDS and INTERFACE EXTENDS.

Like a function block, a STRUCT can extend one other STRUCT: ST_Sub1 holds
ST_Base1's members first (in memory too) and adds its own, even a TON
instance, and ST_Sub2 extends ST_Sub1 in turn. A member name may not repeat
along the chain, and a struct cannot extend two structs; nesting one struct
inside another (ST_1 holds an ST_2) is the alternative, one level deeper.
Interfaces may extend several interfaces at once: ``I_Motor EXTENDS I_Start,
I_Stop`` holds both prototypes plus its own. A block implementing I_Motor
must implement all of them (else error C0087), and one instance can then be
assigned to an I_Motor, an I_Start or an I_Stop variable.

ST::

    TYPE ST_Base1 :
    STRUCT
        bBool1 : BOOL;
        iInt   : INT;
        rReal  : REAL;
    END_STRUCT
    END_TYPE

    TYPE ST_Sub1 EXTENDS ST_Base1 :
    STRUCT
        tTime    : TIME;
        tonTimer : TON;
    END_STRUCT
    END_TYPE

    TYPE ST_Sub2 EXTENDS ST_Sub1 :
    STRUCT
        bBool2 : BOOL;               // bBool1 here would be an error: ST_Base1 declares it
    END_STRUCT
    END_TYPE

    TYPE ST_2 : STRUCT bBool : BOOL; END_STRUCT END_TYPE
    TYPE ST_1 :                      // nesting instead of EXTENDS
    STRUCT
        sStruct : ST_2;
        sString : STRING(80);
    END_STRUCT
    END_TYPE
    // TYPE ST_Sub EXTENDS ST_Base1, ST_Base2 : ...   is not allowed

    INTERFACE I_Start    METHOD Start : BOOL
    INTERFACE I_Stop     METHOD Stop : BOOL
    INTERFACE I_Motor EXTENDS I_Start, I_Stop
    PROPERTY Speed : REAL            // Get and Set

    FUNCTION_BLOCK FB_Motor IMPLEMENTS I_Motor
    VAR bRunning : BOOL; fSpeed : REAL; nStarts : UDINT; END_VAR
    METHOD Start : BOOL              // TRUE if it was stopped
        Start := NOT bRunning;
        IF Start THEN bRunning := TRUE; nStarts := nStarts + 1; END_IF
    METHOD Stop : BOOL               // TRUE if it was running
        Stop := bRunning;
        bRunning := FALSE;
    PROPERTY Speed : REAL
        Get: Speed := fSpeed;
        Set: fSpeed := MAX(Speed, 0.0);

    PROGRAM MAIN
    VAR
        stStructure2  : ST_Sub2;
        stStructure11 : ST_1;
        fbMotor       : FB_Motor;
        itfMotor      : I_Motor;
        itfStart      : I_Start;
        itfStop       : I_Stop;
        nCycle        : INT;
    END_VAR
    nCycle := nCycle + 1;
    stStructure2.bBool1 := TRUE;                      // members of ST_Base1 ...
    stStructure2.iInt := nCycle;
    stStructure2.rReal := stStructure2.rReal + 0.5;
    stStructure2.tonTimer(IN := TRUE, PT := T#1S);    // ... of ST_Sub1 ...
    stStructure2.tTime := stStructure2.tonTimer.ET;
    stStructure2.bBool2 := stStructure2.tonTimer.Q;   // ... and its own
    stStructure11.sStruct.bBool := stStructure2.bBool2;

    itfMotor := fbMotor;
    itfStart := itfMotor;                             // an I_Motor is an I_Start
    itfStop := fbMotor;
    IF nCycle = 1 THEN
        itfStart.Start();
        itfMotor.Speed := 1450.0;
    ELSIF nCycle = 50 THEN
        itfStop.Stop();
    END_IF
"""

from __future__ import annotations

from iecoop import (
    BOOL,
    INT,
    REAL,
    STRING,
    TIME,
    UDINT,
    VAR,
    DefinitionError,
    FunctionBlock,
    Interface,
    Program,
    Struct,
    T,
    method,
    prop,
    sizeof,
    var_info,
)
from iecoop.runtime import Runtime, Task
from iecoop.stdlib import TON
from patterns.showcase.entry import Showcase

__all__ = [
    "IMotor",
    "IStart",
    "IStop",
    "Main",
    "Motor",
    "Nested1",
    "Nested2",
    "StructBase1",
    "StructSub1",
    "StructSub2",
    "main",
]


class StructBase1(Struct):
    """``TYPE ST_Base1``."""

    b_bool1: BOOL = False
    i_int: INT = 0
    r_real: REAL = 0.0


class StructSub1(StructBase1):
    """``TYPE ST_Sub1 EXTENDS ST_Base1``: adds a TIME and a TON instance."""

    t_time: TIME = 0
    ton_timer: TON = VAR()


class StructSub2(StructSub1):
    """``TYPE ST_Sub2 EXTENDS ST_Sub1``."""

    b_bool2: BOOL = False


class Nested2(Struct):
    """``TYPE ST_2 : STRUCT bBool : BOOL; END_STRUCT END_TYPE``."""

    b_bool: BOOL = False


class Nested1(Struct):
    """``TYPE ST_1``: holds an ST_2 instead of extending it."""

    s_struct: Nested2 = VAR()
    s_string: STRING = VAR("")


class IStart(Interface):
    """``INTERFACE I_Start``."""

    @method
    def start(self) -> BOOL:
        raise NotImplementedError


class IStop(Interface):
    """``INTERFACE I_Stop``."""

    @method
    def stop(self) -> BOOL:
        raise NotImplementedError


class IMotor(IStart, IStop):
    """``INTERFACE I_Motor EXTENDS I_Start, I_Stop``: both prototypes plus ``Speed``."""

    @prop
    def speed(self) -> REAL:
        raise NotImplementedError

    @speed.setter
    def speed(self, value: REAL) -> None: ...


class Motor(FunctionBlock, IMotor):
    """``FUNCTION_BLOCK FB_Motor IMPLEMENTS I_Motor``."""

    running: BOOL = VAR(False)
    speed_internal: REAL = VAR(0.0)
    starts: UDINT = VAR(0)

    @method
    def start(self) -> BOOL:
        started = not self.running
        if started:
            self.running = True
            self.starts += 1
        return started

    @method
    def stop(self) -> BOOL:
        was_running = self.running
        self.running = False
        return was_running

    @prop
    def speed(self) -> REAL:
        return self.speed_internal

    @speed.setter
    def speed(self, value: REAL) -> None:
        self.speed_internal = max(value, 0.0)


class Main(Program):
    """``PROGRAM MAIN``: the extended and the nested struct, FB_Motor through three interfaces."""

    structure2: StructSub2 = VAR()
    structure11: Nested1 = VAR()
    motor: Motor = VAR()
    itf_motor: IMotor = VAR()
    itf_start: IStart = VAR()
    itf_stop: IStop = VAR()
    cycle: INT = VAR(0)

    def body(self) -> None:
        self.cycle += 1
        st2 = self.structure2
        st2.b_bool1 = True
        st2.i_int = self.cycle
        st2.r_real += 0.5
        st2.ton_timer(IN=True, PT=T("1s"))
        st2.t_time = st2.ton_timer.ET
        st2.b_bool2 = st2.ton_timer.Q
        self.structure11.s_struct.b_bool = st2.b_bool2

        self.itf_motor = self.motor
        self.itf_start = self.itf_motor
        self.itf_stop = self.motor
        if self.cycle == 1:
            self.itf_start.start()
            self.itf_motor.speed = 1450.0
        elif self.cycle == 50:
            self.itf_stop.stop()


def main() -> None:
    """Run MAIN for 1 s, then show the two compile errors.

    >>> main()
    SIZEOF: ST_Base1 = 8, ST_Sub1 = 48, ST_Sub2 = 56; bBool2 at byte 48, after the base members
    t= 490 ms  iInt=50   rReal=25.0  tTime=490   bBool2=False  stStructure11.sStruct.bBool=False
    t= 990 ms  iInt=100  rReal=50.0  tTime=990   bBool2=False  stStructure11.sStruct.bBool=False
    t=1000 ms  iInt=101  rReal=50.5  tTime=1000  bBool2=True   stStructure11.sStruct.bBool=True
    fbMotor through I_Start, I_Motor, I_Stop: nStarts=1, Speed=1450.0, running=False
    DefinitionError: Bad.b_bool1: b_bool1 is already declared in StructBase1; a derived type cannot declare it again
    DefinitionError: FUNCTION_BLOCK HalfMotor: there is no implementation for method 'stop' defined in interface 'IMotor' (C0087)
    """
    offset = var_info(StructSub2(), "b_bool2").ByteOffset
    print(
        f"SIZEOF: ST_Base1 = {sizeof(StructBase1)}, ST_Sub1 = {sizeof(StructSub1)}, ST_Sub2 = {sizeof(StructSub2)}; "
        f"bBool2 at byte {offset}, after the base members"
    )
    program = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    for cycles in (50, 50, 1):
        now = rt.time_ms + (cycles - 1) * 10
        rt.run(cycles=cycles)
        st2 = program.structure2
        print(
            f"t={now:4d} ms  iInt={st2.i_int:<4d} rReal={st2.r_real:<5} tTime={st2.t_time:<5d} "
            f"bBool2={st2.b_bool2!s:<5}  stStructure11.sStruct.bBool={program.structure11.s_struct.b_bool}"
        )
    motor = program.motor
    print(
        f"fbMotor through I_Start, I_Motor, I_Stop: nStarts={motor.starts}, Speed={motor.speed}, "
        f"running={motor.running}"
    )
    try:

        class Bad(StructBase1):  # TYPE ST_Bad EXTENDS ST_Base1 : STRUCT bBool1 : BOOL; END_STRUCT
            b_bool1: BOOL = False

    except DefinitionError as exc:
        print(f"DefinitionError: {exc}")
    try:

        class HalfMotor(FunctionBlock, IMotor):  # FUNCTION_BLOCK FB_HalfMotor IMPLEMENTS I_Motor: no Stop
            @method
            def start(self) -> BOOL:
                return True

            @prop
            def speed(self) -> REAL:
                return 0.0

            @speed.setter
            def speed(self, value: REAL) -> None: ...

    except DefinitionError as exc:
        print(f"DefinitionError: {exc}")


SHOWCASE = Showcase(
    demo=True,
)


if __name__ == "__main__":
    main()
