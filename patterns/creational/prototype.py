"""Prototype: a tuned axis parameter block cloned to new stations, shallow or deep.

Intent
------

Create new objects by copying a prototype instance instead of building them
from scratch, and let the prototype decide how it is copied: which parts the
copy gets for itself and which it keeps sharing.

The PLC problem
---------------

A line has identical feed stations. The commissioning engineer tunes the
first axis (position gain, velocity limit, in-position window) and points it
at the pitch-error table measured for the line's ball-screw type. The other
stations must start with exactly those values, without anyone retyping
them. Some stations share the screw type and must follow when the shared
table is re-measured; a station fitted with a replacement screw needs its own
copy of the table, to be corrected independently.

``ParameterSet.clone(mode)`` takes a free block from a static
``ParameterPool`` and copies the tuned ``AxisParams`` STRUCT into it with
``MEMCPY``. The STRUCT holds a ``POINTER TO ST_CompTable``: a SHALLOW clone
copies the pointer, so it shares the table; a DEEP clone also copies the
table into its own storage (a STRUCT assignment) and re-points its copy of
the pointer there. A clone comes back as ``I_AxisPrototype``, so it can be
cloned again (a clone's slot clones from the same pool); a station is given
it as ``I_AxisParameters``, all it reads, and code holding only that gets
the prototype back with ``__QUERYINTERFACE``. A full pool is reported on the
pool's ``error`` output and ``clone`` returns 0; a parameter set without a
pool (the FB_init injection missing) faults with RTSEXCPT_ACCESS_VIOLATION
on ``clone``. Everything is static: no ``__NEW``, so no pointer can outlive
its target; the tables live in the program and in the pool's blocks, as long
as the clones do.

Roles
-----

- Prototype: ``IAxisPrototype`` (``I_AxisPrototype``), extending the
  product interface ``IAxisParameters`` (``I_AxisParameters``)
- Concrete prototype: ``ParameterSet`` (``FB_ParameterSet``), holding
  ``AxisParams`` (``ST_AxisParams``) with a pointer to a ``CompTable``
  (``ST_CompTable``)
- Static pool: ``ParameterPool`` (``FB_ParameterPool``) behind
  ``IParameterPool`` (``I_ParameterPool``)
- Client: ``AxisStation`` (``FB_AxisStation``), run by ``CommissioningMain``
  (``PROGRAM CommissioningMain``)

IEC 61131-3 mapping
-------------------

::

    TYPE ST_CompTable : STRUCT sName : STRING(16); aErrorUm : ARRAY[1..5] OF REAL; END_STRUCT END_TYPE
    TYPE ST_AxisParams :
    STRUCT
        fKp : REAL; fMaxVelocity : LREAL; fInPosWindow : LREAL;
        pComp : POINTER TO ST_CompTable;   // shared by a shallow copy
    END_STRUCT END_TYPE

    INTERFACE I_AxisPrototype EXTENDS I_AxisParameters
        METHOD Clone : I_AxisPrototype
            VAR_INPUT eMode : E_CopyMode; END_VAR

    FUNCTION_BLOCK FB_ParameterSet IMPLEMENTS I_AxisPrototype
        VAR_INPUT  ipPool : I_ParameterPool; END_VAR
        VAR        stParams : ST_AxisParams; stOwnTable : ST_CompTable; END_VAR
        METHOD FB_init : BOOL  VAR_INPUT ipPool : I_ParameterPool; END_VAR
        METHOD INTERNAL Load
            VAR_IN_OUT CONSTANT stSource : ST_AxisParams; END_VAR
            MEMCPY(ADR(stParams), ADR(stSource), SIZEOF(stParams));
            IF eMode = E_CopyMode.DEEP AND stSource.pComp <> 0 THEN
                stOwnTable := stSource.pComp^;
                stParams.pComp := ADR(stOwnTable);
            END_IF

    FUNCTION_BLOCK FB_ParameterPool IMPLEMENTS I_ParameterPool
        VAR aSlot : ARRAY[1..4] OF FB_ParameterSet; END_VAR
        VAR_OUTPUT nUsed : INT; eError : E_PoolError; END_VAR

When not to use it on a PLC
---------------------------

If every station gets its parameters from a recipe or a persistent data set
anyway, copy the STRUCT with ``:=`` and skip the pattern. Never clone a
function block by ``MEMCPY`` of the whole instance: it copies interface and
pointer variables that then point at the original's members, the bug that
the deep copy here avoids. And never hand out clones made with ``__NEW``
without an owner that deletes them: a public TwinCAT pattern collection
returns interfaces to deleted clones.

References
----------

- E. Gamma, R. Helm, R. Johnson, J. Vlissides, *Design Patterns: Elements of
  Reusable Object-Oriented Software*, Addison-Wesley 1994: "Prototype".
- IEC 61131-3:2013, *Programmable controllers - Part 3: Programming
  languages*, 3rd edition: STRUCT assignment, POINTER TO, ADR, interfaces,
  FB_init.
- Beckhoff InfoSys, TwinCAT 3 PLC: "MEMCPY", "POINTER TO", "FB_init,
  FB_reinit, FB_exit", "__QUERYINTERFACE".
- CODESYS Online Help: "Pointers", "Methods FB_Init, FB_Reinit, FB_Exit".
"""

from __future__ import annotations

from typing import Any

from iecoop import (
    ARRAY,
    BOOL,
    INT,
    INTERNAL,
    LREAL,
    POINTER_TO,
    REAL,
    STRING,
    TIME,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    VAR_STAT,
    FunctionBlock,
    IecEnum,
    Interface,
    IQueryInterface,
    Program,
    Struct,
    T,
    adr,
    memcpy,
    method,
    prop,
    sizeof,
)
from iecoop.runtime import Runtime, Task
from patterns.showcase.entry import Column, Getter, Scenario, Showcase

__all__ = [
    "AxisParams",
    "AxisStation",
    "CommissioningMain",
    "CompTable",
    "CopyMode",
    "IAxisParameters",
    "IAxisPrototype",
    "IParameterPool",
    "POINT_SPACING",
    "ParameterPool",
    "ParameterSet",
    "PoolError",
    "main",
]

#: The pitch-error table has one point every POINT_SPACING mm, from 0 mm.
POINT_SPACING = 100.0


class CopyMode(IecEnum):
    """``E_CopyMode``: SHALLOW shares the pitch-error table, DEEP copies it."""

    SHALLOW = 0
    DEEP = 1


class PoolError(IecEnum):
    """``E_PoolError``."""

    NONE = 0
    POOL_FULL = 1


class CompTable(Struct):
    """``ST_CompTable``: ball-screw pitch error (µm) at 0, 100, 200, 300 and 400 mm."""

    name: STRING = VAR("", length=16)
    error_um: ARRAY[REAL] = VAR(bounds=(1, 5))


class AxisParams(Struct):
    """``ST_AxisParams``: the tuned values, and a pointer to the pitch-error table in use."""

    kp: REAL = 1.0
    max_velocity: LREAL = 100.0
    in_position_window: LREAL = 0.1
    comp: POINTER_TO[CompTable] = VAR()


class IAxisParameters(IQueryInterface):
    """``INTERFACE I_AxisParameters EXTENDS __SYSTEM.IQueryInterface``: what a station reads."""

    @prop
    def params(self) -> AxisParams:
        raise NotImplementedError

    @method
    def compensation(self, position: LREAL) -> LREAL:
        raise NotImplementedError

    @method
    def set_compensation(self, point: INT, error_um: REAL) -> None: ...


class IAxisPrototype(IAxisParameters):
    """``INTERFACE I_AxisPrototype EXTENDS I_AxisParameters``: a parameter set that can be cloned."""

    @method
    def clone(self, mode: CopyMode) -> IAxisPrototype:
        raise NotImplementedError


class IParameterPool(Interface):
    """``INTERFACE I_ParameterPool``: where clones come from."""

    @method
    def clone_of(self, source: AxisParams, mode: CopyMode) -> IAxisPrototype:
        raise NotImplementedError


class ParameterSet(FunctionBlock, IAxisPrototype):
    """``FUNCTION_BLOCK FB_ParameterSet IMPLEMENTS I_AxisPrototype``: the concrete prototype."""

    pool: IParameterPool = VAR_INPUT()
    tuned: AxisParams = VAR()
    own_table: CompTable = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, pool: IParameterPool | None = None) -> None:
        if pool is not None:
            self.pool = pool

    @method
    def tune(self, kp: REAL, max_velocity: LREAL, table: POINTER_TO[CompTable]) -> None:
        """Commissioning: set the gain, the velocity limit and the table to use."""
        self.tuned.kp = kp
        self.tuned.max_velocity = max_velocity
        self.tuned.comp = table

    @method
    def clone(self, mode: CopyMode) -> IAxisPrototype:
        return self.pool.clone_of(self.tuned, mode)

    @method(INTERNAL)
    def load(self, source: AxisParams, mode: CopyMode) -> None:
        """Become a copy of ``source``; only the pool of this package calls it."""
        memcpy(adr(self, "tuned"), adr(source), sizeof(AxisParams))
        if mode == CopyMode.DEEP and source.comp:
            self.own_table = source.comp.deref
            self.tuned.comp = adr(self, "own_table")

    @prop
    def params(self) -> AxisParams:
        return self.tuned

    @method
    def compensation(self, position: LREAL) -> LREAL:
        """The pitch error at ``position`` (mm), interpolated; 0 without a table."""
        if not self.tuned.comp:
            return 0.0
        table = self.tuned.comp.deref.error_um
        span = max(0.0, min(position, POINT_SPACING * (table.high - table.low)))
        point: INT = min(int(span / POINT_SPACING) + table.low, table.high - 1)
        fraction = span / POINT_SPACING - (point - table.low)
        return (table[point] + (table[point + 1] - table[point]) * fraction) / 1000.0

    @method
    def set_compensation(self, point: INT, error_um: REAL) -> None:
        """Re-measure one point, in whichever table this set points at."""
        self.tuned.comp.deref.error_um[point] = error_um


class ParameterPool(FunctionBlock, IParameterPool):
    """``FUNCTION_BLOCK FB_ParameterPool IMPLEMENTS I_ParameterPool``: four static parameter sets."""

    NO_SET: IAxisPrototype = VAR_STAT(constant=True)
    slots: ARRAY[ParameterSet] = VAR(bounds=(1, 4))
    used: INT = VAR_OUTPUT(0)
    error: PoolError = VAR_OUTPUT(PoolError.NONE)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> None:
        # A clone is itself a prototype: each slot clones from this pool too.
        for slot in self.slots:
            slot.pool = self

    @method
    def clone_of(self, source: AxisParams, mode: CopyMode) -> IAxisPrototype:
        if self.used >= self.slots.high:
            self.error = PoolError.POOL_FULL
            return self.NO_SET
        self.used += 1
        slot = self.slots[self.used]
        slot.load(source, mode)
        return slot


class AxisStation(FunctionBlock):
    """``FUNCTION_BLOCK FB_AxisStation``: a P position loop that reads its parameters through the interface."""

    setpoint: LREAL = VAR_INPUT(0.0)
    parameters: IAxisParameters = VAR_INPUT()
    cycle_time: TIME = VAR_INPUT(T("10ms"))
    position: LREAL = VAR_OUTPUT(0.0)
    load_position: LREAL = VAR_OUTPUT(0.0)
    in_position: BOOL = VAR_OUTPUT(False)

    def body(self) -> None:
        params = self.parameters.params
        error = self.setpoint - self.position
        velocity = max(-params.max_velocity, min(params.kp * error, params.max_velocity))
        self.position += velocity * self.cycle_time / 1000
        # Where the carriage really is: the screw's pitch error added to the motor's position.
        self.load_position = self.position + self.parameters.compensation(self.position)
        self.in_position = abs(self.setpoint - self.position) <= params.in_position_window


class CommissioningMain(Program):
    """``PROGRAM CommissioningMain``: station 1 is tuned; 2 is a shallow and 3 a deep clone of it."""

    MEASURED_UM: ARRAY[REAL] = VAR([0.0, 4.0, 12.0, 9.0, 15.0], bounds=(1, 5), constant=True)
    screw_table: CompTable = VAR({"name": "screw A"})
    pool: ParameterPool = VAR()
    master: ParameterSet = VAR()
    stations: ARRAY[AxisStation] = VAR(bounds=(1, 3))
    setpoint: LREAL = VAR_INPUT(250.0)
    first_scan: BOOL = VAR(True)

    def body(self) -> None:
        if self.first_scan:
            self.first_scan = False
            self.screw_table.error_um = self.MEASURED_UM
            self.master.pool = self.pool
            self.master.tune(8.0, 200.0, adr(self, "screw_table"))
            self.stations[1].parameters = self.master
            self.stations[2].parameters = self.master.clone(CopyMode.SHALLOW)
            self.stations[3].parameters = self.master.clone(CopyMode.DEEP)
        for station in self.stations:
            station(setpoint=self.setpoint)


def main() -> None:
    """Clone the tuned axis, move all stations, then re-measure the shared table.

    >>> main()
    station 1 master   kp=8.0 v_max=200 table=screw A (shared)
    station 2 SHALLOW  kp=8.0 v_max=200 table=screw A (shared)
    station 3 DEEP     kp=8.0 v_max=200 table=screw A (own copy)
    t=2000 ms  in position: [True, True, True]  load at 250 mm: +10.5 um +10.5 um +10.5 um
    point 3 re-measured in the shared table: 12 um -> 30 um
    t=2010 ms  load at 250 mm: +19.5 um +19.5 um +10.5 um
    """
    cell = CommissioningMain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), cell)
    rt.run(cycles=1)
    shared = adr(cell, "screw_table")
    for number, role in ((1, "master"), (2, "SHALLOW"), (3, "DEEP")):
        params = cell.stations[number].parameters.params
        where = "shared" if params.comp == shared else "own copy"
        table = params.comp.deref.name
        print(f"station {number} {role:<8} kp={params.kp:.1f} v_max={params.max_velocity:.0f} table={table} ({where})")

    def report() -> str:
        return " ".join(f"{(s.load_position - s.position) * 1000:+.1f} um" for s in cell.stations)

    rt.run(cycles=199)
    in_position = [s.in_position for s in cell.stations]
    print(f"t={rt.time_ms:4d} ms  in position: {in_position}  load at 250 mm: {report()}")
    old = cell.screw_table.error_um[3]
    cell.master.set_compensation(3, 30.0)
    print(f"point 3 re-measured in the shared table: {old:.0f} um -> {cell.screw_table.error_um[3]:.0f} um")
    rt.run(cycles=1)
    print(f"t={rt.time_ms:4d} ms  load at 250 mm: {report()}")


def _remeasure(scenario: Scenario, cycle: int) -> None:
    if cycle == 211:
        scenario.program.master.set_compensation(3, 30.0)


def _load_error(station: int) -> Getter:
    def get(prog: Any) -> object:
        s = prog.stations[station]
        return (s.load_position - s.position) * 1000.0

    return get


SHOWCASE = Showcase(
    use_when="new stations start from a tuned parameter block and each needs its own copy, not a shared reference",
    columns=(
        Column("x1 mm", lambda p: p.stations[1].position, ".1f", watch=False),
        Column("in pos", lambda p: "".join("T" if st.in_position else "-" for st in p.stations)),
        Column("table[3] um", lambda p: p.screw_table.error_um[3], ".0f"),
        *(Column(f"err{i} um", _load_error(i), "+.1f", watch=False) for i in range(1, 4)),
    ),
    script=_remeasure,
    cycles=220,
    tour_cycles=220,
)
