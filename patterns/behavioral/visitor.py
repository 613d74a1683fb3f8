"""Visitor: diagnostics exports that walk every device of a plant without touching the devices.

Intent
------

Represent an operation to be performed on the elements of an object
structure as an object of its own, so that new operations can be added
without changing the classes of the elements they operate on. Each element
answers ``accept(visitor)`` by calling the visitor method for its own kind
(double dispatch).

The PLC problem
---------------

A plant is a tree: areas holding motors, valves and sensors, each FB with its
own diagnostics. Maintenance wants a CSV health report per device with its
instance path (``Plant.Area1.Motor2``), energy management wants energy
totals per area, and next year someone will want a spare-parts list. Putting
a ``ToCsv`` method, then a ``TotalEnergy`` method, then a third one into every
device FB means editing (and re-validating) every device for every new
report. With Visitor each device gets one ``Accept`` method, once; every
report is a visitor FB with one ``Visit`` method per device kind. The walk
is bounded: the tree is three levels deep by construction (a plant holds
areas, an area holds devices, a device holds nothing) and every array has
fixed bounds.

Roles
-----

- Visitor interface → ``IDeviceVisitor`` (``I_DeviceVisitor``), with
  ``visit_area``, ``visit_motor``, ``visit_valve``, ``visit_sensor``
- Element interfaces → ``IDevice`` (``I_Device``: ``accept``, ``attach``,
  ``instance_path``, ``health``) and the read-only views ``IMotor``,
  ``IValve``, ``ISensor``, ``IArea`` a visitor receives
- Concrete elements → ``Motor`` (``FB_Motor``), ``Valve`` (``FB_Valve``),
  ``Sensor`` (``FB_Sensor``), extending the ABSTRACT ``Device``
  (``FB_Device``)
- Object structure → ``Area`` (``FB_Area``) and ``Plant`` (``FB_Plant``)
- Concrete visitors → ``CsvHealthReport`` (``FB_CsvHealthReport``) and
  ``EnergyTotals`` (``FB_EnergyTotals``)
- Client → ``PlantMain`` (``PRG_PlantMain``): exports on a rising edge of
  the HMI button

IEC 61131-3 mapping
-------------------

::

    TYPE E_Health : (OK := 0, WARNING := 1, FAULT := 2) INT; END_TYPE

    INTERFACE I_DeviceVisitor
        METHOD VisitArea    VAR_INPUT area : I_Area; END_VAR
        METHOD VisitMotor   VAR_INPUT motor : I_Motor; END_VAR
        METHOD VisitValve   VAR_INPUT valve : I_Valve; END_VAR
        METHOD VisitSensor  VAR_INPUT sensor : I_Sensor; END_VAR

    INTERFACE I_Device
        METHOD Accept  VAR_INPUT visitor : I_DeviceVisitor; END_VAR
        METHOD Attach : BOOL   VAR_INPUT parentPath : STRING; END_VAR
        PROPERTY InstancePath : STRING    (Get)
        PROPERTY Health : E_Health        (Get)

    FUNCTION_BLOCK ABSTRACT FB_Device IMPLEMENTS I_Device
        VAR name : STRING(16); path : STRING(40); END_VAR
        METHOD ABSTRACT Accept  VAR_INPUT visitor : I_DeviceVisitor; END_VAR

    FUNCTION_BLOCK FB_Motor EXTENDS FB_Device IMPLEMENTS I_Motor
        METHOD Accept    visitor.VisitMotor(THIS^);

    FUNCTION_BLOCK FB_Area IMPLEMENTS I_Area
        VAR devices : ARRAY[1..MAX_DEVICES] OF I_Device; count : INT; END_VAR
        VAR_OUTPUT refusal : E_AddRefusal; END_VAR
        METHOD Add : BOOL   VAR_INPUT device : I_Device; END_VAR
        METHOD INTERNAL Attach

    FUNCTION_BLOCK FB_Plant
        VAR areas : ARRAY[1..MAX_AREAS] OF FB_Area; count : INT; END_VAR
        METHOD AddArea : REFERENCE TO FB_Area   VAR_INPUT name : STRING; END_VAR

    FUNCTION_BLOCK FB_CsvHealthReport IMPLEMENTS I_DeviceVisitor
        VAR_OUTPUT lines : ARRAY[1..MAX_LINES] OF STRING(120);
                   count : INT; overflow : BOOL; END_VAR

    FUNCTION_BLOCK FB_EnergyTotals IMPLEMENTS I_DeviceVisitor
        VAR_OUTPUT totalWh : LREAL; areaWh : ARRAY[1..MAX_AREAS] OF LREAL; END_VAR

When not to use it on a PLC
---------------------------

Visitor fixes the set of element kinds: a new device kind (a heater) means a
new ``Visit`` method on the interface and in every visitor. If device kinds
change more often than reports, put the operation into the devices (a
``Diagnose`` method on ``I_Device``) instead. A single report over a handful
of devices is plain code reading their outputs. And a walk over hundreds of
devices in one scan costs scan time: run it on an edge (as here) or spread it
over several scans.

References
----------

- E. Gamma, R. Helm, R. Johnson, J. Vlissides, *Design Patterns: Elements of
  Reusable Object-Oriented Software*, Addison-Wesley 1994, "Visitor".
- IEC 61131-3:2013 (3rd edition), *Programmable controllers - Part 3:
  Programming languages*: interfaces, methods, ``THIS``; the R_TRIG and TON
  standard function blocks. PROPERTY is a CODESYS / TwinCAT extension.
- Beckhoff InfoSys, TwinCAT 3 PLC: "Interface", "Method", "Property",
  "THIS", "Attribute 'instance-path'".
- CODESYS Online Help: "Object: Interface", "Object: Method",
  "Attribute: instance-path".
"""

from __future__ import annotations

from iecoop import (
    ABSTRACT,
    ARRAY,
    BOOL,
    DINT,
    INT,
    INTERNAL,
    LREAL,
    PRIVATE,
    REAL,
    STRING,
    TIME,
    UDINT,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    FunctionBlock,
    IecEnum,
    Interface,
    Program,
    T,
    method,
    prop,
)
from iecoop.conversions import LREAL_TO_DINT, TIME_TO_DINT, TO_TIME
from iecoop.functions import CONCAT
from iecoop.runtime import Runtime, Task, current_task
from iecoop.stdlib import R_TRIG, TON
from patterns.showcase.entry import Column, Showcase, press, steps

__all__ = [
    "MAX_AREAS",
    "MAX_DEVICES",
    "MAX_LINES",
    "AddRefusal",
    "Area",
    "CsvHealthReport",
    "EnergyTotals",
    "Health",
    "IArea",
    "IDevice",
    "IDeviceVisitor",
    "IMotor",
    "ISensor",
    "IValve",
    "Motor",
    "Plant",
    "PlantMain",
    "Sensor",
    "Valve",
    "health_text",
    "main",
    "one_decimal",
]

MAX_AREAS = 4
MAX_DEVICES = 8
MAX_LINES = 12
PATH_LENGTH = 40
LINE_LENGTH = 120
HEADER = "path,device,health,detail"


class Health(IecEnum):
    """``TYPE E_Health : (OK := 0, WARNING := 1, FAULT := 2) INT; END_TYPE``"""

    OK = 0
    WARNING = 1
    FAULT = 2


class AddRefusal(IecEnum):
    """``TYPE E_AddRefusal : (NONE, NULL_DEVICE, ALREADY_IN_AREA, AREA_FULL, NO_PATH) INT; END_TYPE``.

    Why ``FB_Area.Add`` said FALSE; NO_PATH: the device has no name, or its
    instance path does not fit ``STRING(PATH_LENGTH)``.
    """

    NONE = 0
    NULL_DEVICE = 1
    ALREADY_IN_AREA = 2
    AREA_FULL = 3
    NO_PATH = 4


def health_text(health: Health) -> STRING:
    """``FUNCTION F_HealthText : STRING``: the CSV word for a health."""
    if health == Health.FAULT:
        return "FAULT"
    if health == Health.WARNING:
        return "WARNING"
    return "OK"


def one_decimal(value: LREAL) -> STRING:
    """``FUNCTION F_OneDecimal : STRING``: ``value`` rounded to tenths, ``'12.5'``, ``'-0.5'``, ``'3.0'``."""
    tenths: DINT = LREAL_TO_DINT(abs(value) * 10.0)
    text: STRING = f"{tenths // 10}.{tenths % 10}"
    if value < 0.0 and tenths > 0:
        return CONCAT("-", text)
    return text


# ---------------------------------------------------------------------------
# The views a visitor receives: read-only, one per element kind
# ---------------------------------------------------------------------------


class IArea(Interface):
    """``INTERFACE I_Area``: an area as a visitor sees it."""

    @prop
    def instance_path(self) -> STRING:
        raise NotImplementedError

    @prop
    def number(self) -> INT:
        raise NotImplementedError


class IMotor(Interface):
    """``INTERFACE I_Motor``: a motor's diagnostics."""

    @prop
    def instance_path(self) -> STRING:
        raise NotImplementedError

    @prop
    def health(self) -> Health:
        raise NotImplementedError

    @prop
    def rated_power(self) -> REAL:
        raise NotImplementedError

    @prop
    def run_seconds(self) -> LREAL:
        raise NotImplementedError

    @prop
    def starts(self) -> UDINT:
        raise NotImplementedError


class IValve(Interface):
    """``INTERFACE I_Valve``: a valve's diagnostics."""

    @prop
    def instance_path(self) -> STRING:
        raise NotImplementedError

    @prop
    def health(self) -> Health:
        raise NotImplementedError

    @prop
    def strokes(self) -> UDINT:
        raise NotImplementedError

    @prop
    def stroke_energy(self) -> REAL:
        raise NotImplementedError


class ISensor(Interface):
    """``INTERFACE I_Sensor``: an analogue transmitter's diagnostics."""

    @prop
    def instance_path(self) -> STRING:
        raise NotImplementedError

    @prop
    def health(self) -> Health:
        raise NotImplementedError

    @prop
    def value(self) -> REAL:
        raise NotImplementedError

    @prop
    def current(self) -> REAL:
        raise NotImplementedError


class IDeviceVisitor(Interface):
    """``INTERFACE I_DeviceVisitor``: one method per element kind."""

    @method
    def visit_area(self, area: IArea) -> None: ...

    @method
    def visit_motor(self, motor: IMotor) -> None: ...

    @method
    def visit_valve(self, valve: IValve) -> None: ...

    @method
    def visit_sensor(self, sensor: ISensor) -> None: ...


class IDevice(Interface):
    """``INTERFACE I_Device``: what an area holds; ``accept`` is the double dispatch."""

    @method
    def accept(self, visitor: IDeviceVisitor) -> None: ...

    @method
    def attach(self, parent_path: STRING) -> BOOL:
        raise NotImplementedError

    @prop
    def instance_path(self) -> STRING:
        raise NotImplementedError

    @prop
    def health(self) -> Health:
        raise NotImplementedError


# ---------------------------------------------------------------------------
# Devices: the concrete elements
# ---------------------------------------------------------------------------


class Device(FunctionBlock, IDevice, abstract=True):
    """``FUNCTION_BLOCK ABSTRACT FB_Device IMPLEMENTS I_Device``: name, instance path and the cycle time.

    ``accept`` is ABSTRACT: only the concrete kind knows which ``Visit``
    method is its own. ``attach`` composes ``parent.name`` once, when the
    device joins an area, so the path is not rebuilt at every report; it
    answers FALSE for a device without a name (FB_init input ``name``) or a
    path longer than ``STRING(PATH_LENGTH)``.
    """

    cycle_time: TIME = VAR_INPUT(T("10ms"))
    name: STRING = VAR("", length=16)
    path: STRING = VAR("", length=PATH_LENGTH)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, name: STRING = "") -> BOOL:
        self.name = name
        return True

    @method
    def attach(self, parent_path: STRING) -> BOOL:
        if self.name == "" or len(parent_path) + 1 + len(self.name) > PATH_LENGTH:
            return False
        self.path = f"{parent_path}.{self.name}"
        return True

    @prop
    def instance_path(self) -> STRING:
        return self.path

    @method(ABSTRACT)
    def accept(self, visitor: IDeviceVisitor) -> None: ...

    @prop
    @method(ABSTRACT)
    def health(self) -> Health:
        raise NotImplementedError


class Motor(Device, IMotor):
    """``FUNCTION_BLOCK FB_Motor EXTENDS FB_Device IMPLEMENTS I_Motor``: a DOL motor with run hours and starts.

    ``Motor(name="Motor1", rated_power=7.5, service_hours=2000.0)``. FAULT on
    an overload trip, WARNING once the run time reaches the service interval.
    """

    run: BOOL = VAR_INPUT(False)
    overload: BOOL = VAR_INPUT(False)
    running: BOOL = VAR_OUTPUT(False)
    power_kw: REAL = VAR(0.0)
    service_seconds: LREAL = VAR(0.0)
    seconds: LREAL = VAR(0.0)
    start_count: UDINT = VAR(0)
    start_edge: R_TRIG = VAR()

    def fb_init(
        self, init_retains: BOOL, in_copy_code: BOOL, name: STRING = "", rated_power: REAL = 1.0,
        service_hours: LREAL = 2000.0,
    ) -> BOOL:
        self.power_kw = rated_power
        self.service_seconds = service_hours * 3600.0
        return True

    def body(self) -> None:
        self.running = self.run and not self.overload
        self.start_edge(CLK=self.running)
        if self.start_edge.Q:
            self.start_count += 1
        if self.running:
            self.seconds += TIME_TO_DINT(self.cycle_time) / 1000.0

    @method
    def accept(self, visitor: IDeviceVisitor) -> None:
        visitor.visit_motor(self)

    @prop
    def health(self) -> Health:
        if self.overload:
            return Health.FAULT
        if self.seconds >= self.service_seconds:
            return Health.WARNING
        return Health.OK

    @prop
    def rated_power(self) -> REAL:
        return self.power_kw

    @prop
    def run_seconds(self) -> LREAL:
        return self.seconds

    @prop
    def starts(self) -> UDINT:
        return self.start_count


class Valve(Device, IValve):
    """``FUNCTION_BLOCK FB_Valve EXTENDS FB_Device IMPLEMENTS I_Valve``: an on/off valve with feedback.

    The simulated actuator reaches its end position ``travel_time`` after the
    command changes, unless ``stuck``; a TON flags a discrepancy between
    command and feedback that lasts longer than ``discrepancy_time``, and the
    fault latches until ``reset``. ``Valve(name="Valve1", stroke_energy=0.5)``
    (Wh per stroke).
    """

    open_cmd: BOOL = VAR_INPUT(False)
    stuck: BOOL = VAR_INPUT(False)
    reset: BOOL = VAR_INPUT(False)
    travel_time: TIME = VAR_INPUT(T("300ms"))
    discrepancy_time: TIME = VAR_INPUT(T("1s"))
    is_open: BOOL = VAR_OUTPUT(False)
    fault: BOOL = VAR_OUTPUT(False)
    wh_per_stroke: REAL = VAR(0.5)
    stroke_count: UDINT = VAR(0)
    travel: TON = VAR()
    discrepancy: TON = VAR()
    stroke_edge: R_TRIG = VAR()

    def fb_init(
        self, init_retains: BOOL, in_copy_code: BOOL, name: STRING = "", stroke_energy: REAL = 0.5
    ) -> BOOL:
        self.wh_per_stroke = stroke_energy
        return True

    def body(self) -> None:
        moving = self.open_cmd != self.is_open and not self.stuck
        self.travel(IN=moving, PT=self.travel_time)
        if self.travel.Q:
            self.is_open = self.open_cmd
        self.stroke_edge(CLK=self.is_open)
        if self.stroke_edge.Q:
            self.stroke_count += 1
        self.discrepancy(IN=self.open_cmd != self.is_open, PT=self.discrepancy_time)
        if self.discrepancy.Q:
            self.fault = True
        elif self.reset:
            self.fault = False

    @method
    def accept(self, visitor: IDeviceVisitor) -> None:
        visitor.visit_valve(self)

    @prop
    def health(self) -> Health:
        return Health.FAULT if self.fault else Health.OK

    @prop
    def strokes(self) -> UDINT:
        return self.stroke_count

    @prop
    def stroke_energy(self) -> REAL:
        return self.wh_per_stroke


class Sensor(Device, ISensor):
    """``FUNCTION_BLOCK FB_Sensor EXTENDS FB_Device IMPLEMENTS I_Sensor``: a 4-20 mA transmitter.

    ``Sensor(name="TT101", low=0.0, high=150.0)`` scales 4..20 mA to
    ``low..high``. FAULT on a wire break (below 3.6 mA), WARNING out of
    range (above 20.5 mA).
    """

    WIRE_BREAK_MA: REAL = VAR(3.6, constant=True)
    OVER_RANGE_MA: REAL = VAR(20.5, constant=True)
    raw_ma: REAL = VAR_INPUT(4.0)
    scaled: REAL = VAR_OUTPUT(0.0)
    low: REAL = VAR(0.0)
    high: REAL = VAR(100.0)

    def fb_init(
        self, init_retains: BOOL, in_copy_code: BOOL, name: STRING = "", low: REAL = 0.0, high: REAL = 100.0
    ) -> BOOL:
        self.low, self.high = low, high
        return True

    def body(self) -> None:
        self.scaled = self.low + (self.raw_ma - 4.0) / 16.0 * (self.high - self.low)

    @method
    def accept(self, visitor: IDeviceVisitor) -> None:
        visitor.visit_sensor(self)

    @prop
    def health(self) -> Health:
        # REAL against REAL constants, as on the PLC: 3.6 mA read from the card is not below 3.6.
        if self.raw_ma < self.WIRE_BREAK_MA:
            return Health.FAULT
        if self.raw_ma > self.OVER_RANGE_MA:
            return Health.WARNING
        return Health.OK

    @prop
    def value(self) -> REAL:
        return self.scaled

    @prop
    def current(self) -> REAL:
        return self.raw_ma


# ---------------------------------------------------------------------------
# The object structure: bounded arrays, three levels deep
# ---------------------------------------------------------------------------


class Area(FunctionBlock, IArea):
    """``FUNCTION_BLOCK FB_Area IMPLEMENTS I_Area``: up to MAX_DEVICES device references.

    Areas live in their plant's static pool and are handed out by
    ``Plant.add_area``. An area is not an ``I_Device``, so it cannot be put
    into another area: the tree stays three levels deep and the walk stays
    bounded. ``add`` refuses (FALSE, the reason in ``refusal``) a full area,
    a null reference, a device that already belongs to an area (it would be
    counted twice) and one without a path.
    """

    name: STRING = VAR("", length=16)
    path: STRING = VAR("", length=PATH_LENGTH)
    position: INT = VAR(0)
    devices: ARRAY[IDevice] = VAR(bounds=(1, MAX_DEVICES))
    count: INT = VAR_OUTPUT(0)
    refusal: AddRefusal = VAR_OUTPUT(AddRefusal.NONE)

    @method(INTERNAL)
    def attach(self, parent_path: STRING, name: STRING, position: INT) -> None:
        """Called by the plant when it hands the area out: its name, path and number."""
        self.name = name
        self.path = f"{parent_path}.{name}"
        self.position = position

    @method
    def add(self, device: IDevice) -> BOOL:
        """Take ``device`` into the area and give it its path; FALSE, the reason in ``refusal``, if refused."""
        if not device:
            self.refusal = AddRefusal.NULL_DEVICE
        elif device.instance_path != "":
            self.refusal = AddRefusal.ALREADY_IN_AREA
        elif self.count >= MAX_DEVICES:
            self.refusal = AddRefusal.AREA_FULL
        elif not device.attach(self.path):
            self.refusal = AddRefusal.NO_PATH
        else:
            self.refusal = AddRefusal.NONE
            self.count += 1
            self.devices[self.count] = device
        return self.refusal == AddRefusal.NONE

    @method
    def accept(self, visitor: IDeviceVisitor) -> None:
        visitor.visit_area(self)
        for i in range(1, self.count + 1):
            self.devices[i].accept(visitor)

    @prop
    def instance_path(self) -> STRING:
        return self.path

    @prop
    def number(self) -> INT:
        return self.position


class Plant(FunctionBlock):
    """``FUNCTION_BLOCK FB_Plant``: the root, owning a static pool of MAX_AREAS areas.

    ``Plant(name="Plant")``; ``add_area("Area1")`` hands out the next area
    of the pool (ST: a ``REFERENCE TO FB_Area``). Asking a full pool for one
    more is a configuration error: the index past ``MAX_AREAS`` faults with
    RTSEXCPT_ARRAYBOUNDS, as any out-of-bounds access does.
    """

    name: STRING = VAR("", length=16)
    areas: ARRAY[Area] = VAR(bounds=(1, MAX_AREAS))
    count: INT = VAR_OUTPUT(0)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, name: STRING = "Plant") -> BOOL:
        self.name = name
        return True

    @method
    def add_area(self, name: STRING) -> Area:
        area = self.areas[self.count + 1]   # past MAX_AREAS: RTSEXCPT_ARRAYBOUNDS, the count unchanged
        self.count += 1
        area.attach(self.name, name, self.count)
        return area

    @method
    def accept(self, visitor: IDeviceVisitor) -> None:
        for i in range(1, self.count + 1):
            self.areas[i].accept(visitor)


# ---------------------------------------------------------------------------
# Visitors: the reports
# ---------------------------------------------------------------------------


class CsvHealthReport(FunctionBlock, IDeviceVisitor):
    """``FUNCTION_BLOCK FB_CsvHealthReport IMPLEMENTS I_DeviceVisitor``: one CSV line per device.

    ``lines`` is ``ARRAY[1..MAX_LINES] OF STRING(120)``, the header first. A
    report that does not fit sets ``overflow`` and counts the ``dropped``
    lines instead of writing past the array. Each kind formats its own
    detail column: that is what the double dispatch buys.
    """

    lines: ARRAY[STRING] = VAR_OUTPUT(bounds=(1, MAX_LINES), length=LINE_LENGTH)
    count: INT = VAR_OUTPUT(0)
    overflow: BOOL = VAR_OUTPUT(False)
    dropped: INT = VAR_OUTPUT(0)
    faults: INT = VAR_OUTPUT(0)
    warnings: INT = VAR_OUTPUT(0)

    @method
    def clear(self) -> None:
        for i in range(1, MAX_LINES + 1):
            self.lines[i] = ""
        self.count = self.dropped = self.faults = self.warnings = 0
        self.overflow = False
        self.append(HEADER)

    @method(PRIVATE)
    def append(self, line: STRING) -> None:
        if self.count >= MAX_LINES:
            self.overflow = True
            self.dropped += 1
            return
        self.count += 1
        self.lines[self.count] = line

    @method(PRIVATE)
    def row(self, path: STRING, kind: STRING, health: Health, detail: STRING) -> None:
        if health == Health.FAULT:
            self.faults += 1
        elif health == Health.WARNING:
            self.warnings += 1
        self.append(f"{path},{kind},{health_text(health)},{detail}")

    @method
    def visit_area(self, area: IArea) -> None:
        pass

    @method
    def visit_motor(self, motor: IMotor) -> None:
        health = motor.health
        detail: STRING
        if health == Health.FAULT:
            detail = "overload trip"
        else:
            detail = f"starts={motor.starts} run={one_decimal(motor.run_seconds)}s"
            if health == Health.WARNING:
                detail = CONCAT(detail, " service due")
        self.row(motor.instance_path, "motor", health, detail)

    @method
    def visit_valve(self, valve: IValve) -> None:
        health = valve.health
        detail: STRING = "no end position feedback" if health == Health.FAULT else f"strokes={valve.strokes}"
        self.row(valve.instance_path, "valve", health, detail)

    @method
    def visit_sensor(self, sensor: ISensor) -> None:
        health = sensor.health
        detail: STRING
        if health == Health.FAULT:
            detail = f"wire break current={one_decimal(sensor.current)}mA"
        else:
            detail = f"value={one_decimal(sensor.value)} current={one_decimal(sensor.current)}mA"
        self.row(sensor.instance_path, "sensor", health, detail)


class EnergyTotals(FunctionBlock, IDeviceVisitor):
    """``FUNCTION_BLOCK FB_EnergyTotals IMPLEMENTS I_DeviceVisitor``: Wh per area and in total.

    Motors count rated power times run time, valves their stroke energy;
    sensors are loop-powered and ``visit_sensor`` does nothing: a visitor
    handles the kinds it cares about.
    """

    total_wh: LREAL = VAR_OUTPUT(0.0)
    motors_wh: LREAL = VAR_OUTPUT(0.0)
    valves_wh: LREAL = VAR_OUTPUT(0.0)
    area_wh: ARRAY[LREAL] = VAR_OUTPUT(bounds=(1, MAX_AREAS))
    current_area: INT = VAR(0)

    @method
    def clear(self) -> None:
        self.total_wh = self.motors_wh = self.valves_wh = 0.0
        for i in range(1, MAX_AREAS + 1):
            self.area_wh[i] = 0.0
        self.current_area = 0

    @method(PRIVATE)
    def book(self, wh: LREAL) -> None:
        self.total_wh += wh
        self.area_wh[self.current_area] += wh

    @method
    def visit_area(self, area: IArea) -> None:
        self.current_area = area.number

    @method
    def visit_motor(self, motor: IMotor) -> None:
        wh = motor.rated_power * 1000.0 * motor.run_seconds / 3600.0
        self.motors_wh += wh
        self.book(wh)

    @method
    def visit_valve(self, valve: IValve) -> None:
        wh = valve.stroke_energy * valve.strokes
        self.valves_wh += wh
        self.book(wh)

    @method
    def visit_sensor(self, sensor: ISensor) -> None:
        pass


# ---------------------------------------------------------------------------
# The program
# ---------------------------------------------------------------------------


class PlantMain(Program):
    """``PROGRAM PRG_PlantMain``: two areas, seven devices, an export on the HMI button's rising edge."""

    export: BOOL = VAR_INPUT(False)
    exports: UDINT = VAR_OUTPUT(0)
    plant: Plant = VAR(fb_init={"name": "Plant"})
    motor1: Motor = VAR(fb_init={"name": "Motor1", "rated_power": 7.5})
    motor2: Motor = VAR(fb_init={"name": "Motor2", "rated_power": 15.0, "service_hours": 0.001})
    valve1: Valve = VAR(fb_init={"name": "Valve1"})
    tt101: Sensor = VAR(fb_init={"name": "TT101", "low": 0.0, "high": 150.0})
    motor3: Motor = VAR(fb_init={"name": "Motor3", "rated_power": 4.0})
    valve2: Valve = VAR(fb_init={"name": "Valve2"})
    lt201: Sensor = VAR(fb_init={"name": "LT201", "low": 0.0, "high": 100.0})
    report: CsvHealthReport = VAR()
    energy: EnergyTotals = VAR()
    export_edge: R_TRIG = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
        area1 = self.plant.add_area("Area1")
        area1.add(self.motor1)
        area1.add(self.motor2)
        area1.add(self.valve1)
        area1.add(self.tt101)
        area2 = self.plant.add_area("Area2")
        area2.add(self.motor3)
        area2.add(self.valve2)
        area2.add(self.lt201)
        return True

    def body(self) -> None:
        cycle_time: TIME = TO_TIME(current_task().CycleTime // 10_000)
        self.motor1(cycle_time=cycle_time)
        self.motor2(cycle_time=cycle_time)
        self.motor3(cycle_time=cycle_time)
        self.valve1(cycle_time=cycle_time)
        self.valve2(cycle_time=cycle_time)
        self.tt101(cycle_time=cycle_time)
        self.lt201(cycle_time=cycle_time)
        self.export_edge(CLK=self.export)
        if self.export_edge.Q:
            self.report.clear()
            self.plant.accept(self.report)
            self.energy.clear()
            self.plant.accept(self.energy)
            self.exports += 1


def main() -> None:
    """Run the plant for 20 s of PLC time, press "export" and print the CSV report and the energy.

    >>> main()
    path,device,health,detail
    Plant.Area1.Motor1,motor,FAULT,overload trip
    Plant.Area1.Motor2,motor,WARNING,starts=1 run=20.0s service due
    Plant.Area1.Valve1,valve,OK,strokes=3
    Plant.Area1.TT101,sensor,OK,value=75.0 current=12.0mA
    Plant.Area2.Motor3,motor,OK,starts=1 run=15.0s
    Plant.Area2.Valve2,valve,FAULT,no end position feedback
    Plant.Area2.LT201,sensor,FAULT,wire break current=2.1mA
    energy: 143.2 Wh (motors 141.7, valves 1.5); Area1 126.5 Wh, Area2 16.7 Wh
    """
    program = PlantMain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    program.motor1.run = True
    program.motor2.run = True
    program.tt101.raw_ma = 12.0
    program.lt201.raw_ma = 2.1
    rt.run(cycles=500)
    program.motor3.run = True
    program.valve2.stuck = True
    for _ in range(3):
        program.valve1.open_cmd = program.valve2.open_cmd = True
        rt.run(cycles=250)
        program.valve1.open_cmd = program.valve2.open_cmd = False
        rt.run(cycles=250)
    program.motor1.overload = True
    program.export = True
    rt.run(cycles=1)
    for i in range(1, program.report.count + 1):
        print(program.report.lines[i])
    energy = program.energy
    print(
        f"energy: {energy.total_wh:.1f} Wh (motors {energy.motors_wh:.1f}, valves {energy.valves_wh:.1f}); "
        f"Area1 {energy.area_wh[1]:.1f} Wh, Area2 {energy.area_wh[2]:.1f} Wh"
    )


SHOWCASE = Showcase(
    use_when="new reports or exports over a fixed set of device kinds are added often",
    columns=(
        Column("exports", lambda p: p.exports),
        Column("report rows", lambda p: p.report.count),
        Column("faults", lambda p: p.report.faults),
        Column("warnings", lambda p: p.report.warnings),
        Column("energy Wh", lambda p: p.energy.total_wh, ".1f"),
    ),
    script=steps(
        (1, "motor1.run", True), (1, "motor2.run", True), (1, "tt101.raw_ma", 12.0), (1, "lt201.raw_ma", 2.1),
        *press("export", 50), (101, "motor3.run", True), (101, "valve2.stuck", True),
        (101, "valve1.open_cmd", True), (101, "valve2.open_cmd", True), *press("export", 150),
        (251, "motor1.overload", True), *press("export", 300), *press("export", 400),
    ),
    cycles=400,
    tour_cycles=400,
    expected=(("faults, warnings", "a valve sticks in cycle 101 and a motor overloads in cycle 251"),),
)
