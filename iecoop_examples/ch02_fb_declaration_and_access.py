"""Declaring a function block, and who may use which of its members.

The declaration line says what kind of block it is: ``FUNCTION_BLOCK [PUBLIC |
INTERNAL] [FINAL | ABSTRACT] name [EXTENDS base] [IMPLEMENTS interfaces]``.
Its VAR sections say who writes each variable (inputs from the caller,
outputs and locals only from inside, in-outs by reference at every call) and
how long it lives (TEMP for one call, STAT shared by every instance, RETAIN and
PERSISTENT over restarts). Each METHOD carries an access specifier: PUBLIC,
PRIVATE, PROTECTED or INTERNAL; a call the specifier forbids is refused
(``AccessError``), and extending a FINAL block is a compile error
(``DefinitionError``).

ST::

    VAR_GLOBAL                            // GVL_Plant
        bPumpsEnabled : BOOL := TRUE;
    END_VAR

    FUNCTION_BLOCK PUBLIC FINAL FB_Pump
    VAR_INPUT
        bStart : BOOL;                    // written by the caller
        bStop  : BOOL;
    END_VAR
    VAR_OUTPUT
        bRunning : BOOL;                  // read by the caller
        sStatus  : STRING;
    END_VAR
    VAR_IN_OUT
        nStarts : UDINT;                  // the caller's counter, by reference
    END_VAR
    VAR_IN_OUT CONSTANT
        sTag : STRING;                    // by reference, read-only inside
    END_VAR
    VAR
        rtStart : R_TRIG;                 // local: only FB_Pump's code sees it
    END_VAR
    VAR_TEMP
        bStartNow : BOOL;                 // re-initialised at every call
    END_VAR
    VAR_STAT
        nAllPumpStarts : UDINT;           // one variable for every FB_Pump instance
    END_VAR
    VAR_EXTERNAL
        bPumpsEnabled : BOOL;             // the global of GVL_Plant
    END_VAR
    VAR RETAIN
        nStartsRetain : UDINT;            // remanent: kept over a restart
    END_VAR
    VAR PERSISTENT
        nRunCycles : UDINT;               // remanent: kept over a download too
    END_VAR
    VAR CONSTANT
        cMaxStarts : UDINT := 3;
    END_VAR
    rtStart(CLK := bStart);
    bStartNow := rtStart.Q AND NOT bStop AND bPumpsEnabled AND nStartsRetain < cMaxStarts;
    IF bStartNow THEN
        bRunning := TRUE;
        nStarts := nStarts + 1;
        nAllPumpStarts := nAllPumpStarts + 1;
        nStartsRetain := nStartsRetain + 1;
    END_IF
    IF bStop OR NOT bPumpsEnabled THEN
        bRunning := FALSE;
    END_IF
    IF bRunning THEN
        nRunCycles := nRunCycles + 1;
    END_IF
    sStatus := CONCAT(sTag, SEL(bRunning, ' stopped', ' running'));

    FUNCTION_BLOCK FB_Access
    METHOD PUBLIC    M_Public    : INT    M_Public    := 1;
    METHOD PRIVATE   M_Private   : INT    M_Private   := 2;
    METHOD PROTECTED M_Protected : INT    M_Protected := 3;
    METHOD INTERNAL  M_Internal  : INT    M_Internal  := 4;

    FUNCTION_BLOCK FB_AccessChild EXTENDS FB_Access

    // Who may call what (INTERNAL: the same namespace, i.e. library):
    //              inside  derived  outside  derived elsewhere  other namespace
    //  PUBLIC      yes     yes      yes      yes                yes
    //  PRIVATE     yes     no       no       no                 no
    //  PROTECTED   yes     yes      no       yes                no
    //  INTERNAL    yes     yes      yes      no                 no

    FUNCTION_BLOCK FB_BigPump EXTENDS FB_Pump    // error: FB_Pump is FINAL

    PROGRAM MAIN
    VAR_INPUT bStart, bStop : BOOL; END_VAR
    VAR fbPump : FB_Pump; nPumpStarts : UDINT; sPumpTag : STRING := 'P-101'; END_VAR
    fbPump(bStart := bStart, bStop := bStop, nStarts := nPumpStarts, sTag := sPumpTag);
"""

from __future__ import annotations

from collections.abc import Callable

from iecoop import (
    BOOL,
    INT,
    INTERNAL,
    PRIVATE,
    PROTECTED,
    STRING,
    UDINT,
    VAR,
    VAR_EXTERNAL,
    VAR_IN_OUT,
    VAR_INPUT,
    VAR_OUTPUT,
    VAR_STAT,
    VAR_TEMP,
    AccessError,
    DefinitionError,
    FunctionBlock,
    GlobalVariables,
    Program,
    T,
    adr,
    gvl,
    method,
)
from iecoop.functions import CONCAT, SEL
from iecoop.runtime import Runtime, Task
from iecoop.stdlib import R_TRIG
from patterns.showcase.entry import Column, Showcase, press, steps

__all__ = ["Access", "AccessChild", "MEMBERS", "Main", "PlantGlobals", "Pump", "access_table", "main"]


@gvl
class PlantGlobals(GlobalVariables):
    """``GVL_Plant``: ``VAR_GLOBAL bPumpsEnabled : BOOL := TRUE; END_VAR``."""

    pumps_enabled: BOOL = True


class Pump(FunctionBlock, final=True):
    """``FUNCTION_BLOCK PUBLIC FINAL FB_Pump``: one variable of each section."""

    start: BOOL = VAR_INPUT(False)
    stop: BOOL = VAR_INPUT(False)
    running: BOOL = VAR_OUTPUT(False)
    status: STRING = VAR_OUTPUT("")
    starts: UDINT = VAR_IN_OUT()
    tag: STRING = VAR_IN_OUT(constant=True)
    start_edge: R_TRIG = VAR()
    start_now: BOOL = VAR_TEMP(False)
    all_pump_starts: UDINT = VAR_STAT(0)
    pumps_enabled: BOOL = VAR_EXTERNAL()
    starts_retain: UDINT = VAR(0, retain=True)
    run_cycles: UDINT = VAR(0, persistent=True)
    max_starts: UDINT = VAR(3, constant=True)

    def body(self) -> None:
        self.start_edge(CLK=self.start)
        self.start_now = (
            self.start_edge.Q and not self.stop and self.pumps_enabled and self.starts_retain < self.max_starts
        )
        if self.start_now:
            self.running = True
            self.starts += 1
            self.all_pump_starts += 1
            self.starts_retain += 1
        if self.stop or not self.pumps_enabled:
            self.running = False
        if self.running:
            self.run_cycles += 1
        self.status = CONCAT(self.tag, SEL(self.running, " stopped", " running"))


class Main(Program):
    """``PROGRAM MAIN``: owns the start counter and the tag that FB_Pump gets by reference."""

    start: BOOL = VAR_INPUT(False)
    stop: BOOL = VAR_INPUT(False)
    pump: Pump = VAR()
    pump_starts: UDINT = VAR(0)
    pump_tag: STRING = VAR("P-101")

    def body(self) -> None:
        self.pump(start=self.start, stop=self.stop, starts=adr(self, "pump_starts"), tag=adr(self, "pump_tag"))


class Access(FunctionBlock):
    """``FUNCTION_BLOCK FB_Access``: one METHOD per access specifier."""

    @method
    def m_public(self) -> INT:
        return 1

    @method(PRIVATE)
    def m_private(self) -> INT:
        return 2

    @method(PROTECTED)
    def m_protected(self) -> INT:
        return 3

    @method(INTERNAL)
    def m_internal(self) -> INT:
        return 4

    @method
    def call_inside(self, name: STRING) -> INT:
        """Call the member ``name`` from FB_Access's own code (0 for a name it has not)."""
        if name == "m_public":
            return self.m_public()
        if name == "m_private":
            return self.m_private()
        if name == "m_protected":
            return self.m_protected()
        if name == "m_internal":
            return self.m_internal()
        return 0


class AccessChild(Access):
    """``FUNCTION_BLOCK FB_AccessChild EXTENDS FB_Access``."""

    @method
    def call_derived(self, name: STRING) -> INT:
        """Call the inherited member ``name`` from the derived block's code (0 for a name it has not).

        TwinCAT and CODESYS reject the PRIVATE call at compile time; iecoop
        raises AccessError at the call, so the table can show the row.
        """
        if name == "m_public":
            return self.m_public()
        if name == "m_private":
            return self.m_private()
        if name == "m_protected":
            return self.m_protected()
        if name == "m_internal":
            return self.m_internal()
        return 0


#: The member of FB_Access for each access specifier.
MEMBERS = {"PUBLIC": "m_public", "PRIVATE": "m_private", "PROTECTED": "m_protected", "INTERNAL": "m_internal"}


def _outside(name: str) -> INT:
    member: Callable[[], INT] = getattr(Access(), name)
    return member()


def access_table() -> dict[str, tuple[str, str, str]]:
    """Call every member from inside, from a derived block and from outside: the result or ``denied``."""
    places: tuple[Callable[[str], INT], ...] = (Access().call_inside, AccessChild().call_derived, _outside)
    table: dict[str, tuple[str, str, str]] = {}
    for specifier, name in MEMBERS.items():
        cells: list[str] = []
        for call in places:
            try:
                cells.append(str(call(name)))
            except AccessError:
                cells.append("denied")
        table[specifier] = (cells[0], cells[1], cells[2])
    return table


def main() -> None:
    """Run the pump through MAIN, reset cold, then print the access table and the two refusals.

    >>> main()
    start, stop, start: bRunning=True, sStatus='P-101 running', MAIN.nPumpStarts=2, nStartsRetain=2, nRunCycles=2
    after Reset cold: bRunning=False, MAIN.nPumpStarts=0, nStartsRetain=2 (RETAIN), nRunCycles=2 (PERSISTENT)
    specifier  inside  derived  outside
    PUBLIC     1       1        1
    PRIVATE    2       denied   denied
    PROTECTED  3       3        denied
    INTERNAL   4       4        4
    AccessError: PRIVATE METHOD Access.m_private cannot be called from main in module ...: PRIVATE members are callable only inside Access
    DefinitionError: FUNCTION_BLOCK BigPump cannot EXTEND Pump: Pump is FINAL
    """
    program = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    for start, stop in ((True, False), (False, True), (False, False), (True, False)):
        program.start, program.stop = start, stop
        rt.run(cycles=1)
    pump = program.pump
    print(
        f"start, stop, start: bRunning={pump.running}, sStatus={pump.status!r}, "
        f"MAIN.nPumpStarts={program.pump_starts}, nStartsRetain={pump.starts_retain}, nRunCycles={pump.run_cycles}"
    )
    rt.reset_cold()
    print(
        f"after Reset cold: bRunning={pump.running}, MAIN.nPumpStarts={program.pump_starts}, "
        f"nStartsRetain={pump.starts_retain} (RETAIN), nRunCycles={pump.run_cycles} (PERSISTENT)"
    )
    print("specifier  inside  derived  outside")
    for specifier, (inside, derived, outside) in access_table().items():
        print(f"{specifier:<10} {inside:<7} {derived:<8} {outside}")
    try:
        Access().m_private()
    except AccessError as exc:
        print(f"AccessError: {exc}")
    try:

        class BigPump(Pump):  # FUNCTION_BLOCK FB_BigPump EXTENDS FB_Pump
            pass

    except DefinitionError as exc:
        print(f"DefinitionError: {exc}")


SHOWCASE = Showcase(
    columns=(Column("start", lambda p: p.start), Column("stop", lambda p: p.stop), Column("running", lambda p: p.pump.running),
             Column("MAIN's starts", lambda p: p.pump_starts)),
    script=steps(*press("start", 2), *press("stop", 5), *press("start", 8)),
    cycles=10,
)


if __name__ == "__main__":
    main()
