"""Factory Method: valve blocks created from the I/O configuration table.

Intent
------

Let a creator decide, through one overridable method, which concrete block
stands behind an interface, so that the code which uses the products never
names a concrete class, and a new kind of product is added by deriving a new
creator instead of editing the old one.

The PLC problem
---------------

A dosing skid has valves of several kinds: direct solenoid valves,
motorised ball valves with a stroke time, proportional control valves, and
(since the last retrofit) pneumatic pinch valves. The electrical design
delivers them as an I/O configuration table: one row per valve with its tag
and a type code. The sequence only wants to ``open`` and ``close`` valves and
wait for the end position; it must not change when the table does.

``ValveFactory.configure`` walks the CONSTANT table (given as the address of
its first row and a row count, so nothing is copied) and calls the factory
method ``create_valve`` for each row. The method takes a free block of the
right kind from a static pool and returns it as an ``IValve``; the factory
keeps the result in an ``ARRAY[1..8] OF I_Valve`` indexed like the table.
``PinchValveFactory`` adds the pinch valve by overriding ``create_valve`` and
passing every other code on to ``SUPER^``. Failures are explicit: an unknown
type code or an exhausted pool leaves that row's interface at 0 and sets the
``error`` and ``error_row`` outputs (the PLC way: a status code, no
exception); calling through the 0 raises RTSEXCPT_ACCESS_VIOLATION.

Roles
-----

- Product: ``IValve`` (``I_Valve``)
- Concrete products: ``SolenoidValve`` (``FB_SolenoidValve``),
  ``MotorisedValve`` (``FB_MotorisedValve``), ``ProportionalValve``
  (``FB_ProportionalValve``), ``PinchValve`` (``FB_PinchValve``), sharing
  the ABSTRACT ``ValveBase`` (``FB_ValveBase``); the two timed ones extend
  the ABSTRACT ``StrokeValve`` (``FB_StrokeValve``)
- Creator: ``ValveFactory`` (``FB_ValveFactory``), factory method
  ``create_valve``, seen by the client as ``IValveFactory``
  (``I_ValveFactory``)
- Concrete creator: ``PinchValveFactory`` (``FB_PinchValveFactory``)
- Configuration: ``ValveConfig`` (``ST_ValveConfig``) rows with a
  ``ValveType`` (``E_ValveType``) code
- Client: ``ValveCellMain`` (``PROGRAM ValveCellMain``)

IEC 61131-3 mapping
-------------------

::

    TYPE E_ValveType : (NONE, SOLENOID, MOTORISED, PROPORTIONAL, PINCH, BUTTERFLY) INT; END_TYPE
    TYPE ST_ValveConfig : STRUCT sTag : STRING(12); eType : E_ValveType; tStroke : TIME; END_STRUCT END_TYPE

    INTERFACE I_Valve
        METHOD Open
        METHOD Close
        METHOD Execute
        PROPERTY IsOpen : BOOL
        PROPERTY Position : REAL
        PROPERTY TypeCode : E_ValveType
        PROPERTY Tag : STRING(12)

    FUNCTION_BLOCK ABSTRACT FB_ValveBase IMPLEMENTS I_Valve
        METHOD INTERNAL Setup
            VAR_INPUT stConfig : ST_ValveConfig; END_VAR
        METHOD ABSTRACT Execute

    FUNCTION_BLOCK FB_ValveFactory IMPLEMENTS I_ValveFactory
        VAR_OUTPUT nCreated : INT; eError : E_FactoryError; nErrorRow : INT; END_VAR
        VAR aSolenoid : ARRAY[1..4] OF FB_SolenoidValve; nSolenoid : INT;
            aValve : ARRAY[1..8] OF I_Valve; END_VAR
        METHOD Configure : INT
            VAR_IN_OUT CONSTANT aTable : ARRAY[1..8] OF ST_ValveConfig; END_VAR
        METHOD PROTECTED CreateValve : I_Valve
            VAR_INPUT stConfig : ST_ValveConfig; END_VAR

    FUNCTION_BLOCK FB_PinchValveFactory EXTENDS FB_ValveFactory
        METHOD PROTECTED CreateValve : I_Valve  // PINCH here, the rest: SUPER^.CreateValve(stConfig)

When not to use it on a PLC
---------------------------

When the plant has one or two valve kinds that never change, a plain
``ARRAY OF FB_Valve`` declared per kind is simpler and shows every instance
online. The factory pays off when the configuration varies per machine
(options, retrofits) and the sequence code must stay untouched. Keep the
pools static: creating valves with ``__NEW`` at run time fragments the
router memory and hides the instance count from the engineer.

References
----------

- E. Gamma, R. Helm, R. Johnson, J. Vlissides, *Design Patterns: Elements of
  Reusable Object-Oriented Software*, Addison-Wesley 1994: "Factory Method".
- IEC 61131-3:2013, *Programmable controllers - Part 3: Programming
  languages*, 3rd edition: interfaces, methods, EXTENDS, SUPER.
- Beckhoff InfoSys, TwinCAT 3 PLC: "Object Method", "Object Interface",
  "SUPER".
- CODESYS Online Help: "Object: Method", "Extension of a function block".
"""

from __future__ import annotations

from typing import Any

from iecoop import (
    ABSTRACT,
    ARRAY,
    BOOL,
    INT,
    INTERNAL,
    POINTER_TO,
    PROTECTED,
    REAL,
    STRING,
    TIME,
    VAR,
    VAR_OUTPUT,
    VAR_STAT,
    FunctionBlock,
    IecEnum,
    Interface,
    Program,
    Struct,
    T,
    adr,
    method,
    prop,
    sizeof,
)
from iecoop.runtime import Runtime, Task
from iecoop.stdlib import TON
from patterns.showcase.entry import Column, Getter, Showcase

__all__ = [
    "FactoryError",
    "IO_CONFIG",
    "IValve",
    "IValveFactory",
    "MAX_VALVES",
    "MotorisedValve",
    "PinchValve",
    "PinchValveFactory",
    "ProportionalValve",
    "SolenoidValve",
    "StrokeValve",
    "ValveBase",
    "ValveCellMain",
    "ValveConfig",
    "ValveFactory",
    "ValveType",
    "main",
]

#: Rows of the I/O configuration table (``ARRAY[1..MAX_VALVES]``).
MAX_VALVES = 8


class ValveType(IecEnum):
    """``E_ValveType``: the plant-wide valve type codes used by the I/O configuration."""

    NONE = 0
    SOLENOID = 1
    MOTORISED = 2
    PROPORTIONAL = 3
    PINCH = 4
    BUTTERFLY = 5


class FactoryError(IecEnum):
    """``E_FactoryError``: why a row of the configuration table got no valve."""

    NONE = 0
    UNKNOWN_TYPE = 1
    POOL_FULL = 2
    ALREADY_CONFIGURED = 3


class ValveConfig(Struct):
    """``ST_ValveConfig``: one row of the I/O configuration table."""

    tag: STRING = VAR("", length=12)
    type_code: ValveType = ValveType.NONE
    stroke: TIME = 0


#: The skid's I/O configuration (``VAR CONSTANT`` rows of ``ValveCellMain``).
IO_CONFIG: list[ValveConfig] = [
    ValveConfig(tag="V101", type_code=ValveType.SOLENOID),
    ValveConfig(tag="V102", type_code=ValveType.MOTORISED, stroke=T("1s")),
    ValveConfig(tag="V103", type_code=ValveType.PROPORTIONAL, stroke=T("200ms")),
    ValveConfig(tag="V104", type_code=ValveType.PINCH),
    ValveConfig(tag="V105", type_code=ValveType.BUTTERFLY),
]


class IValve(Interface):
    """``INTERFACE I_Valve``: what the sequence knows about any valve."""

    @method
    def open(self) -> None: ...

    @method
    def close(self) -> None: ...

    @method
    def execute(self) -> None: ...

    @prop
    def is_open(self) -> BOOL:
        raise NotImplementedError

    @prop
    def position(self) -> REAL:
        raise NotImplementedError

    @prop
    def type_code(self) -> ValveType:
        raise NotImplementedError

    @prop
    def tag(self) -> STRING:
        raise NotImplementedError


class IValveFactory(Interface):
    """``INTERFACE I_ValveFactory``: what the sequence knows about the factory."""

    @method
    def configure(self, rows: POINTER_TO[ValveConfig], count: INT) -> INT:
        raise NotImplementedError

    @method
    def valve(self, row: INT) -> IValve:
        raise NotImplementedError


class ValveBase(FunctionBlock, IValve, abstract=True):
    """``FUNCTION_BLOCK ABSTRACT FB_ValveBase IMPLEMENTS I_Valve``: command, position, tag."""

    cmd_open: BOOL = VAR(False)
    pos: REAL = VAR(0.0)
    config: ValveConfig = VAR()

    @method(INTERNAL)
    def setup(self, config: ValveConfig) -> None:
        """Take the table row; only the factories of this package configure a valve."""
        self.config = config

    @method
    def open(self) -> None:
        self.cmd_open = True

    @method
    def close(self) -> None:
        self.cmd_open = False

    @method(ABSTRACT)
    def execute(self) -> None: ...

    @prop
    def is_open(self) -> BOOL:
        return self.pos >= 100.0

    @prop
    def position(self) -> REAL:
        return self.pos

    @prop
    def type_code(self) -> ValveType:
        return self.config.type_code

    @prop
    def tag(self) -> STRING:
        return self.config.tag


class SolenoidValve(ValveBase):
    """``FUNCTION_BLOCK FB_SolenoidValve EXTENDS FB_ValveBase``: follows the command at once."""

    @method
    def execute(self) -> None:
        self.pos = 100.0 if self.cmd_open else 0.0


class StrokeValve(ValveBase, abstract=True):
    """``FUNCTION_BLOCK ABSTRACT FB_StrokeValve EXTENDS FB_ValveBase``: travels for a stroke time (TON)."""

    travel: TON = VAR()
    moving_open: BOOL = VAR(False)
    start_pos: REAL = VAR(0.0)

    @prop
    def rated_stroke(self) -> TIME:
        """The stroke time when the table gives none."""
        return T("1s")

    @method
    def execute(self) -> None:
        stroke = self.config.stroke if self.config.stroke > 0 else self.rated_stroke
        if self.cmd_open != self.moving_open:
            # A new command restarts the timer from the position reached so far.
            self.moving_open = self.cmd_open
            self.start_pos = self.pos
            self.travel(IN=False)
        goal = 100.0 if self.cmd_open else 0.0
        if self.pos == goal:
            self.travel(IN=False)
            return
        self.travel(IN=True, PT=stroke)
        fraction = self.travel.ET / stroke
        self.pos = goal if self.travel.Q else self.start_pos + (goal - self.start_pos) * fraction


class MotorisedValve(StrokeValve):
    """``FUNCTION_BLOCK FB_MotorisedValve EXTENDS FB_StrokeValve``: a ball valve with an actuator (1 s stroke)."""


class ProportionalValve(StrokeValve):
    """``FUNCTION_BLOCK FB_ProportionalValve EXTENDS FB_StrokeValve``: a control valve ramping over 250 ms."""

    @prop
    def rated_stroke(self) -> TIME:
        return T("250ms")


class PinchValve(ValveBase):
    """``FUNCTION_BLOCK FB_PinchValve EXTENDS FB_ValveBase``: pneumatic, open after a 50 ms delay (TON)."""

    delay: TON = VAR()

    @method
    def execute(self) -> None:
        self.delay(IN=self.cmd_open, PT=T("50ms"))
        self.pos = 100.0 if self.delay.Q else 0.0


class ValveFactory(FunctionBlock, IValveFactory):
    """``FUNCTION_BLOCK FB_ValveFactory IMPLEMENTS I_ValveFactory``: fills ``ARRAY[1..8] OF I_Valve`` from the table, from static pools."""

    NO_VALVE: IValve = VAR_STAT(constant=True)
    created: INT = VAR_OUTPUT(0)
    error: FactoryError = VAR_OUTPUT(FactoryError.NONE)
    error_row: INT = VAR_OUTPUT(0)
    configured: BOOL = VAR_OUTPUT(False)
    row: INT = VAR(0)
    valves: ARRAY[IValve] = VAR(bounds=(1, MAX_VALVES))
    solenoids: ARRAY[SolenoidValve] = VAR(bounds=(1, 4))
    n_solenoid: INT = VAR(0)
    motorised: ARRAY[MotorisedValve] = VAR(bounds=(1, 2))
    n_motorised: INT = VAR(0)
    proportional: ARRAY[ProportionalValve] = VAR(bounds=(1, 2))
    n_proportional: INT = VAR(0)

    @method
    def configure(self, rows: POINTER_TO[ValveConfig], count: INT) -> INT:
        """Create one valve per used row; returns how many were created. Runs once.

        ``Configure(pRows := ADR(aIoConfig[1]), nRows := MAX_VALVES)``: the first
        row of the caller's table and how many follow. The table is a CONSTANT,
        which a VAR_IN_OUT cannot take, and an input of type ARRAY would copy it.
        """
        if self.configured:
            self.fail(FactoryError.ALREADY_CONFIGURED)
            return 0
        self.configured = True
        row_ptr = rows
        for row in range(1, min(count, MAX_VALVES) + 1):
            config = row_ptr.deref
            row_ptr = row_ptr + sizeof(ValveConfig)  # the next row
            if config.type_code == ValveType.NONE:
                continue
            self.row = row
            valve = self.create_valve(config)
            self.valves[row] = valve
            if valve:
                self.created += 1
        return self.created

    @method
    def valve(self, row: INT) -> IValve:
        """The valve of table row ``row`` (0 when the row has none)."""
        return self.valves[row]

    @method
    def execute_all(self) -> None:
        """Call every created valve once (their timers run here)."""
        for valve in self.valves:
            if valve:
                valve.execute()

    @method(PROTECTED)
    def fail(self, error: FactoryError) -> IValve:
        """Record the first failure and return a null interface."""
        if self.error == FactoryError.NONE:
            self.error = error
            self.error_row = self.row
        return self.NO_VALVE

    @method(PROTECTED)
    def create_valve(self, config: ValveConfig) -> IValve:
        """The factory method: a configured valve of ``config.type_code``, or 0."""
        code = config.type_code
        # Each pool has its own block type, so each branch sets up and returns its own element.
        if code == ValveType.SOLENOID:
            if self.n_solenoid >= self.solenoids.high:
                return self.fail(FactoryError.POOL_FULL)
            self.n_solenoid += 1
            self.solenoids[self.n_solenoid].setup(config)
            return self.solenoids[self.n_solenoid]
        if code == ValveType.MOTORISED:
            if self.n_motorised >= self.motorised.high:
                return self.fail(FactoryError.POOL_FULL)
            self.n_motorised += 1
            self.motorised[self.n_motorised].setup(config)
            return self.motorised[self.n_motorised]
        if code == ValveType.PROPORTIONAL:
            if self.n_proportional >= self.proportional.high:
                return self.fail(FactoryError.POOL_FULL)
            self.n_proportional += 1
            self.proportional[self.n_proportional].setup(config)
            return self.proportional[self.n_proportional]
        return self.fail(FactoryError.UNKNOWN_TYPE)


class PinchValveFactory(ValveFactory):
    """``FUNCTION_BLOCK FB_PinchValveFactory EXTENDS FB_ValveFactory``: adds PINCH, the base is untouched."""

    pinches: ARRAY[PinchValve] = VAR(bounds=(1, 2))
    n_pinch: INT = VAR(0)

    @method(PROTECTED)
    def create_valve(self, config: ValveConfig) -> IValve:
        if config.type_code != ValveType.PINCH:
            return super().create_valve(config)
        if self.n_pinch >= self.pinches.high:
            return self.fail(FactoryError.POOL_FULL)
        self.n_pinch += 1
        made = self.pinches[self.n_pinch]
        made.setup(config)
        return made


class ValveCellMain(Program):
    """``PROGRAM ValveCellMain``: configures the skid on the first scan, then opens every valve."""

    io_config: ARRAY[ValveConfig] = VAR(IO_CONFIG, bounds=(1, MAX_VALVES), constant=True)
    factory: PinchValveFactory = VAR()
    first_scan: BOOL = VAR(True)

    def body(self) -> None:
        if self.first_scan:
            self.first_scan = False
            self.factory.configure(adr(self, "io_config", 1), MAX_VALVES)
            for row in range(1, MAX_VALVES + 1):
                valve = self.factory.valve(row)
                if valve:
                    valve.open()
        self.factory.execute_all()


def main() -> None:
    """Configure the skid from its table, open every valve and report when each is open.

    >>> main()
    created 4 valves; BUTTERFLY refused: UNKNOWN_TYPE at row 5
    t=   0 ms  V101  SOLENOID      open
    t=  50 ms  V104  PINCH         open
    t= 200 ms  V103  PROPORTIONAL  open
    t=1000 ms  V102  MOTORISED     open
    """
    cell = ValveCellMain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), cell)
    factory = cell.factory
    reported: set[int] = set()
    while rt.time_ms < 2000 and (not factory.configured or len(reported) < factory.created):
        cycle_start = rt.time_ms
        rt.run(cycles=1)
        if cycle_start == 0:
            refused = cell.io_config[factory.error_row].type_code.name
            print(f"created {factory.created} valves; {refused} refused: {factory.error.name} at row {factory.error_row}")
        for row in range(1, MAX_VALVES + 1):
            valve = factory.valve(row)
            if valve and valve.is_open and row not in reported:
                reported.add(row)
                print(f"t={cycle_start:4d} ms  {valve.tag:<5} {valve.type_code.name:<13} open")


def _valve_open(row: int) -> Getter:
    def get(prog: Any) -> object:
        valve = prog.factory.valve(row)
        return bool(valve) and valve.is_open

    return get


SHOWCASE = Showcase(
    use_when="the device mix varies per machine (options, retrofits) while the sequence code stays untouched",
    columns=(
        Column("created", lambda p: p.factory.created),
        Column("error", lambda p: p.factory.error),
        *(Column(f"V10{row} open", _valve_open(row)) for row in range(1, 5)),
    ),
    cycles=110,
    tour_cycles=110,
    expected=(("UNKNOWN_TYPE", "row 5 of the I/O table names a BUTTERFLY valve, a type no factory builds"),),
)
