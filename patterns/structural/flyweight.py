"""Flyweight: two hundred thermocouples sharing one calibration table per sensor type.

Intent
------

Use sharing to support large numbers of fine-grained objects efficiently.

The PLC problem
---------------

A heat-treatment line measures its furnace and preheater with 200
thermocouples (type K in the furnace, type J in the preheater). Converting
a thermocouple's voltage to a temperature needs the sensor type's
calibration curve: a table of (mV, degC) points from the ITS-90 reference
tables, interpolated linearly. If every thermocouple FB carries its own copy
of the table, the 200 instances hold 200 identical tables: six times the
memory, a longer online-change, and 200 places to patch when the table is
corrected.

The table is the flyweight's intrinsic state: it depends only on the
sensor type, so it lives once, as a CONSTANT in a global variable list.
Each thermocouple keeps only its extrinsic state (its raw voltage and its
individual offset correction) and a ``REFERENCE TO`` the shared table,
bound with ``REF=`` (``ref_assign``) when the sensor type is chosen.
``calibration_for`` plays the flyweight factory: it hands out the one
table of a type, never a new one.

Roles
-----

- Flyweight → ``CalibrationTable`` (``ST_CalibrationTable``) in ``GVL_Thermocouples``
  (``VAR_GLOBAL CONSTANT``)
- Flyweight factory → ``calibration_for`` (``F_CalibrationFor``)
- Client interface → ``ITemperatureSensor`` (``I_TemperatureSensor``)
- Context holding the extrinsic state → ``Thermocouple`` (``FB_Thermocouple``)
- The design without sharing, for comparison → ``ThermocoupleWithTable`` (``FB_ThermocoupleWithTable``)
- Client → ``FurnaceMain`` (``PRG_FurnaceMain``)

IEC 61131-3 mapping
-------------------

::

    TYPE ST_CalPoint : STRUCT fMV : REAL; fDegC : REAL; END_STRUCT END_TYPE
    TYPE ST_CalibrationTable : STRUCT
        eType : E_ThermocoupleType; nCount : INT;
        aPoints : ARRAY[1..MAX_POINTS] OF ST_CalPoint;
    END_STRUCT END_TYPE

    VAR_GLOBAL CONSTANT   // GVL_Thermocouples
        TC_TYPE_K : ST_CalibrationTable := (eType := TYPE_K, nCount := 16, aPoints := [...]);
        TC_TYPE_J : ST_CalibrationTable := (eType := TYPE_J, nCount := 15, aPoints := [...]);
    END_VAR

    INTERFACE I_TemperatureSensor
        PROPERTY Temperature : LREAL; PROPERTY InRange : BOOL

    FUNCTION_BLOCK FINAL FB_Thermocouple IMPLEMENTS I_TemperatureSensor
        VAR_INPUT nRawUV : DINT; fOffset : REAL; END_VAR
        VAR refTable : REFERENCE TO ST_CalibrationTable; END_VAR
        METHOD Use  VAR_INPUT eType : E_ThermocoupleType; END_VAR
            refTable REF= F_CalibrationFor(eType);

    FUNCTION F_Interpolate : LREAL
        VAR_IN_OUT CONSTANT table : ST_CalibrationTable; END_VAR
        VAR_INPUT fMV : LREAL; END_VAR

When not to use it on a PLC
---------------------------

With a handful of sensors the saving is a few hundred bytes and a plain
table per FB is easier to read online. Share only what is truly
immutable: a table some instance may patch at run time (a per-sensor
two-point calibration, say) must stay per instance, or one sensor's
correction silently moves all the others. And a reference is one more
thing that can be unbound: an FB whose type was never chosen faults on
first use.

References
----------

- Gamma, Helm, Johnson, Vlissides: *Design Patterns*, Addison-Wesley 1994, "Flyweight".
- IEC 61131-3:2013, 3rd ed., 6.5.2 (VAR_GLOBAL CONSTANT), 6.4.4 (references, REF=), 6.6.5 (interfaces).
- IEC 60584-1:2013, Thermocouples - EMF specifications and tolerances (the ITS-90 reference tables).
- Beckhoff InfoSys, TwinCAT 3 PLC: "REFERENCE", "Global Variable List", "SIZEOF", "Structure".
- CODESYS Online Help: "Reference", "Operator: SIZEOF", "Object: Global Variable List".
"""

from __future__ import annotations

from iecoop import (
    ARRAY,
    BOOL,
    DINT,
    INT,
    LREAL,
    REAL,
    REFERENCE_TO,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    FunctionBlock,
    GlobalVariables,
    IecEnum,
    Interface,
    Program,
    Struct,
    T,
    call_after_init,
    gvl,
    method,
    prop,
    ref_assign,
    sizeof,
)
from iecoop.runtime import Runtime, Task
from patterns.showcase.entry import Column, Scenario, Showcase

__all__ = [
    "MAX_POINTS",
    "N_THERMOCOUPLES",
    "CalPoint",
    "CalibrationTable",
    "FurnaceMain",
    "GVL_Thermocouples",
    "ITemperatureSensor",
    "Thermocouple",
    "ThermocoupleType",
    "ThermocoupleWithTable",
    "calibration_for",
    "calibration_table",
    "interpolate",
    "main",
]

#: ``VAR_GLOBAL CONSTANT MAX_POINTS : INT := 16;``: points per calibration table.
MAX_POINTS = 16
#: Thermocouples on the line: 120 type K in the furnace, 80 type J in the preheater.
N_THERMOCOUPLES = 200
N_TYPE_K = 120


class ThermocoupleType(IecEnum):
    """``TYPE E_ThermocoupleType : (TYPE_K := 1, TYPE_J := 2) INT;``"""

    TYPE_K = 1
    TYPE_J = 2


class CalPoint(Struct):
    """``STRUCT ST_CalPoint``: the thermo-voltage at one temperature (cold junction at 0 degC)."""

    mv: REAL = 0.0
    deg_c: REAL = 0.0


class CalibrationTable(Struct):
    """``STRUCT ST_CalibrationTable``: the flyweight, ``count`` points in ascending order."""

    sensor: ThermocoupleType = ThermocoupleType.TYPE_K
    count: INT = 0
    points: ARRAY[CalPoint] = VAR(bounds=(1, MAX_POINTS))


def calibration_table(sensor: ThermocoupleType, rows: tuple[tuple[float, float], ...]) -> CalibrationTable:
    """The initial value of a table, as ST's ``(eType := ..., aPoints := [(fMV := ..., fDegC := ...), ...])``."""
    if not 2 <= len(rows) <= MAX_POINTS:
        raise ValueError(f"a calibration table holds 2 .. {MAX_POINTS} points, got {len(rows)}")
    table = CalibrationTable(sensor=sensor, count=len(rows))
    for i, (mv, deg_c) in enumerate(rows, start=1):
        table.points[i].mv = mv
        table.points[i].deg_c = deg_c
    return table


# ITS-90 reference values (IEC 60584-1), every 100 degC, as (mV, degC).
_TYPE_K = (
    (-5.891, -200.0), (-3.554, -100.0), (0.0, 0.0), (4.096, 100.0), (8.138, 200.0), (12.209, 300.0),
    (16.397, 400.0), (20.644, 500.0), (24.905, 600.0), (29.129, 700.0), (33.275, 800.0), (37.326, 900.0),
    (41.276, 1000.0), (45.119, 1100.0), (48.838, 1200.0), (52.410, 1300.0),
)
_TYPE_J = (
    (-7.890, -200.0), (-4.633, -100.0), (0.0, 0.0), (5.269, 100.0), (10.779, 200.0), (16.327, 300.0),
    (21.848, 400.0), (27.393, 500.0), (33.102, 600.0), (39.132, 700.0), (45.494, 800.0), (51.877, 900.0),
    (57.953, 1000.0), (63.792, 1100.0), (69.553, 1200.0),
)


@gvl
class GVL_Thermocouples(GlobalVariables):
    """``VAR_GLOBAL CONSTANT``: one calibration table per thermocouple type, shared by every instance."""

    TC_TYPE_K: CalibrationTable = VAR(calibration_table(ThermocoupleType.TYPE_K, _TYPE_K), constant=True)
    TC_TYPE_J: CalibrationTable = VAR(calibration_table(ThermocoupleType.TYPE_J, _TYPE_J), constant=True)


def calibration_for(sensor: ThermocoupleType) -> CalibrationTable:
    """``F_CalibrationFor``: the flyweight factory, handing out the one shared table of a type."""
    if sensor == ThermocoupleType.TYPE_J:
        return GVL_Thermocouples.TC_TYPE_J
    return GVL_Thermocouples.TC_TYPE_K


def interpolate(table: CalibrationTable, mv: LREAL) -> LREAL:
    """``F_Interpolate``: linear interpolation between the table's points, clamped at both ends."""
    points = table.points
    if mv <= points[1].mv:
        return points[1].deg_c
    last = table.count
    if mv >= points[last].mv:
        return points[last].deg_c
    i = 1
    while i < last - 1 and mv >= points[i + 1].mv:
        i += 1
    low, high = points[i], points[i + 1]
    return low.deg_c + (mv - low.mv) * (high.deg_c - low.deg_c) / (high.mv - low.mv)


def _in_range(table: CalibrationTable, mv: LREAL) -> BOOL:
    return table.points[1].mv <= mv <= table.points[table.count].mv


class ITemperatureSensor(Interface):
    """``INTERFACE I_TemperatureSensor``."""

    @prop
    def temperature(self) -> LREAL:
        raise NotImplementedError

    @prop
    def in_range(self) -> BOOL:
        raise NotImplementedError


class Thermocouple(FunctionBlock, ITemperatureSensor, final=True):
    """``FUNCTION_BLOCK FINAL FB_Thermocouple IMPLEMENTS I_TemperatureSensor``: raw value, offset, reference.

    ``raw_uv`` is the terminal's thermo-voltage in microvolts (cold junction
    compensated); ``offset`` is this sensor's correction in degC. The table
    is chosen at FB_init (``Thermocouple(sensor=...)``) or with ``use()``;
    reading a temperature before that is an access violation.
    """

    raw_uv: DINT = VAR_INPUT(0)
    offset: REAL = VAR_INPUT(0.0)
    table: REFERENCE_TO[CalibrationTable] = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, sensor: ThermocoupleType | None = None) -> None:
        if sensor is not None:
            self.use(sensor)

    @method
    def use(self, sensor: ThermocoupleType) -> None:
        """``refTable REF= F_CalibrationFor(sensor)``."""
        ref_assign(self, "table", calibration_for(sensor))

    @prop
    def sensor(self) -> ThermocoupleType:
        return self.table.sensor

    @prop
    def temperature(self) -> LREAL:
        return interpolate(self.table, self.raw_uv / 1000.0) + self.offset

    @prop
    def in_range(self) -> BOOL:
        return _in_range(self.table, self.raw_uv / 1000.0)


class ThermocoupleWithTable(FunctionBlock, ITemperatureSensor, final=True):
    """``FUNCTION_BLOCK FINAL FB_ThermocoupleWithTable``: the same sensor with its own copy of the table.

    Only here to show what the flyweight saves; ``use()`` copies the table
    (``table := F_CalibrationFor(sensor)``).
    """

    raw_uv: DINT = VAR_INPUT(0)
    offset: REAL = VAR_INPUT(0.0)
    table: CalibrationTable = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, sensor: ThermocoupleType | None = None) -> None:
        if sensor is not None:
            self.use(sensor)

    @method
    def use(self, sensor: ThermocoupleType) -> None:
        self.table = calibration_for(sensor)

    @prop
    def temperature(self) -> LREAL:
        return interpolate(self.table, self.raw_uv / 1000.0) + self.offset

    @prop
    def in_range(self) -> BOOL:
        return _in_range(self.table, self.raw_uv / 1000.0)


class FurnaceMain(Program):
    """``PROGRAM PRG_FurnaceMain``: 200 thermocouples; reports the hottest and how many read out of range."""

    thermocouples: ARRAY[Thermocouple] = VAR(bounds=(1, N_THERMOCOUPLES))
    hottest: LREAL = VAR_OUTPUT(0.0)
    hottest_at: INT = VAR_OUTPUT(0)
    out_of_range: INT = VAR_OUTPUT(0)

    @call_after_init
    def wire(self) -> None:
        for i in range(1, N_THERMOCOUPLES + 1):
            self.thermocouples[i].use(ThermocoupleType.TYPE_K if i <= N_TYPE_K else ThermocoupleType.TYPE_J)

    def body(self) -> None:
        self.hottest_at = 0
        self.out_of_range = 0
        for i in range(1, N_THERMOCOUPLES + 1):
            sensor = self.thermocouples[i]
            if not sensor.in_range:
                self.out_of_range += 1
                continue
            temperature = sensor.temperature
            if self.hottest_at == 0 or temperature > self.hottest:
                self.hottest = temperature
                self.hottest_at = i


def main() -> None:
    """Compare the memory of both designs, then read a few thermocouples on the line.

    >>> main()
    200 thermocouples, shared tables:  200 x  24 B + 2 x 132 B =  5064 B
    200 thermocouples, copied tables:  200 x 152 B             = 30400 B
    TC1   type K   4.096 mV ->  100.0 degC
    TC2   type K  41.276 mV ->  998.5 degC (offset -1.5)
    TC150 type J  41.276 mV ->  733.7 degC
    TC151 type J  80.000 mV -> 1200.0 degC OUT OF RANGE
    hottest: TC2 at 998.5 degC; 1 out of range
    """
    shared = N_THERMOCOUPLES * sizeof(Thermocouple) + 2 * sizeof(CalibrationTable)
    copied = N_THERMOCOUPLES * sizeof(ThermocoupleWithTable)
    print(f"{N_THERMOCOUPLES} thermocouples, shared tables:  {N_THERMOCOUPLES} x {sizeof(Thermocouple):3d} B"
          f" + 2 x {sizeof(CalibrationTable)} B = {shared:5d} B")
    print(f"{N_THERMOCOUPLES} thermocouples, copied tables:  {N_THERMOCOUPLES} x "
          f"{sizeof(ThermocoupleWithTable):3d} B             = {copied:5d} B")
    prog = FurnaceMain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), prog)
    readings = {1: (4096, 0.0), 2: (41276, -1.5), 150: (41276, 0.0), 151: (80000, 0.0)}
    for index, (raw_uv, offset) in readings.items():
        prog.thermocouples[index].raw_uv = raw_uv
        prog.thermocouples[index].offset = offset
    rt.run(cycles=1)
    for index, (raw_uv, offset) in readings.items():
        tc = prog.thermocouples[index]
        kind = "K" if tc.sensor == ThermocoupleType.TYPE_K else "J"
        note = " OUT OF RANGE" if not tc.in_range else f" (offset {offset})" if offset else ""
        print(f"{'TC' + str(index):<5} type {kind} {raw_uv / 1000:7.3f} mV -> {tc.temperature:6.1f} degC{note}")
    print(f"hottest: TC{prog.hottest_at} at {prog.hottest:.1f} degC; {prog.out_of_range} out of range")


_READINGS = {1: (1, 4096, 0.0), 2: (2, 41276, -1.5), 3: (150, 41276, 0.0), 11: (151, 80000, 0.0), 21: (150, 60000, 0.0)}


def _thermocouples(scenario: Scenario, cycle: int) -> None:
    if cycle in _READINGS:
        index, raw_uv, offset = _READINGS[cycle]
        tc = scenario.program.thermocouples[index]
        tc.raw_uv = raw_uv
        tc.offset = offset


SHOWCASE = Showcase(
    use_when="hundreds of instances share large, immutable data such as a calibration table per sensor type",
    columns=(
        Column("TC2 degC", lambda p: p.thermocouples[2].temperature, ".1f"),
        Column("TC150 degC", lambda p: p.thermocouples[150].temperature, ".1f"),
        Column("hottest degC", lambda p: p.hottest, ".1f"),
        Column("at TC", lambda p: p.hottest_at),
        Column("out of range", lambda p: p.out_of_range),
    ),
    script=_thermocouples,
    cycles=30,
    tour_cycles=25,
)


if __name__ == "__main__":
    main()
