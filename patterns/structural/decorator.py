"""Decorator: filtering, simulation and maintenance counting stacked on a sensor without subclassing.

Intent
------

Attach additional responsibilities to an object dynamically. Decorators
provide a flexible alternative to subclassing for extending functionality.

The PLC problem
---------------

A tank's pressure transmitter (4-20 mA on an analog input terminal) feeds
the control logic. Over the life of the plant it needs a moving-average
filter against pump pulsation, a simulation override so the commissioning
engineer can test interlocks without pressure in the tank, and a
maintenance counter (hours in service, switching cycles over a set point)
for the service schedule. Subclassing the transmitter FB for every
combination (``FB_FilteredSimulatedCountedTransmitter`` ...) multiplies
blocks; a flag for each feature in one big FB makes every transmitter carry
all of them. Instead each feature is a small FB that implements the same
``ISensor`` interface and wraps another ``ISensor``: the control logic reads
the outermost one and cannot tell how many layers are underneath, and any
layer can be added, removed or reordered in the wiring alone.

Order matters and is chosen on purpose: the maintenance counter sits on
the raw transmitter so it counts the physical sensor's life, and the
simulation override sits outermost so a simulated value reaches the logic
unfiltered.

Roles
-----

- Component → ``ISensor`` (``I_Sensor``)
- Concrete component → ``PressureTransmitter`` (``FB_PressureTransmitter``, FINAL)
- Decorator → ``SensorDecorator`` (``FB_SensorDecorator``, ABSTRACT)
- Concrete decorators → ``MovingAverage`` (``FB_MovingAverage``),
  ``SimulationOverride`` (``FB_SimulationOverride``),
  ``MaintenanceCounter`` (``FB_MaintenanceCounter``)
- Client → ``PressureMain`` (``PRG_PressureMain``)

IEC 61131-3 mapping
-------------------

::

    INTERFACE I_Sensor
        METHOD Scan
        PROPERTY Value : LREAL
        PROPERTY Ok : BOOL

    FUNCTION_BLOCK FINAL FB_PressureTransmitter IMPLEMENTS I_Sensor
        VAR_INPUT nRaw : INT; bError : BOOL; END_VAR
        VAR fLow, fHigh, fValue : LREAL; END_VAR
        METHOD FB_init : BOOL  VAR_INPUT fLow, fHigh : LREAL; END_VAR

    FUNCTION_BLOCK ABSTRACT FB_SensorDecorator IMPLEMENTS I_Sensor
        VAR iInner : I_Sensor; END_VAR
        METHOD FB_init : BOOL  VAR_INPUT iInner : I_Sensor; END_VAR
        PROPERTY Inner : I_Sensor        (Get, Set)
        METHOD Scan                      iInner.Scan();

    FUNCTION_BLOCK FB_MovingAverage EXTENDS FB_SensorDecorator
        VAR_INPUT nWindow : INT := 4; END_VAR
        VAR aSamples : ARRAY[1..MAX_WINDOW] OF LREAL; nNewest, nFilled : INT; END_VAR

    FUNCTION_BLOCK FB_SimulationOverride EXTENDS FB_SensorDecorator
        VAR_INPUT bSimulate : BOOL; fSimValue : LREAL; END_VAR

    FUNCTION_BLOCK FB_MaintenanceCounter EXTENDS FB_SensorDecorator
        VAR_INPUT fSwitchPoint, fHysteresis : LREAL; nMaxSwitchings : UDINT; END_VAR
        VAR_OUTPUT RETAIN nOperatingSeconds, nSwitchings : UDINT; END_VAR
        VAR fbSecond : TON; fbSwitchedOn : R_TRIG; END_VAR

When not to use it on a PLC
---------------------------

When a sensor needs one fixed treatment that never changes, a plain FB
with that treatment inside is easier to monitor online: with decorators the
value passes through several instances and you must look at each one.
Deep stacks also cost a method call per layer per scan. And never use a
simulation override on a safety-related input: forcing belongs to the
safety PLC's own, audited mechanism.

References
----------

- Gamma, Helm, Johnson, Vlissides: *Design Patterns*, Addison-Wesley 1994, "Decorator".
- IEC 61131-3:2013, 3rd ed., 6.6.5 (interfaces), 6.6.7 (properties), 6.5.6 (RETAIN).
- Beckhoff InfoSys, TwinCAT 3 PLC: "Interface", "Property", "SUPER", "FB_init, FB_reinit, FB_exit",
  "Remanent variables - PERSISTENT, RETAIN".
- Beckhoff InfoSys, "EL30xx, EL31xx: process data" (analog input raw value and error bit).
- CODESYS Online Help: "Object: Interface", "Object: Property", "Extending a function block".
"""

from __future__ import annotations

from typing import Any

from iecoop import (
    ARRAY,
    BOOL,
    INT,
    LREAL,
    UDINT,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    FunctionBlock,
    Interface,
    Program,
    T,
    call_after_init,
    method,
    prop,
)
from iecoop.runtime import Runtime, Task
from iecoop.stdlib import R_TRIG, TON
from patterns.showcase.entry import Column, Scenario, Showcase

__all__ = [
    "MAX_WINDOW",
    "RAW_FULL_SCALE",
    "ISensor",
    "MaintenanceCounter",
    "MovingAverage",
    "PressureMain",
    "PressureTransmitter",
    "SensorDecorator",
    "SimulationOverride",
    "main",
]

#: ``VAR_GLOBAL CONSTANT MAX_WINDOW : INT := 16;``: the longest moving average.
MAX_WINDOW = 16
#: Raw value of an analog input terminal at 20 mA (4 mA reads 0).
RAW_FULL_SCALE = 32767


class ISensor(Interface):
    """``INTERFACE I_Sensor``: a measured value and whether it can be trusted."""

    @method
    def scan(self) -> None: ...

    @prop
    def value(self) -> LREAL:
        raise NotImplementedError

    @prop
    def ok(self) -> BOOL:
        raise NotImplementedError


class PressureTransmitter(FunctionBlock, ISensor, final=True):
    """``FUNCTION_BLOCK FINAL FB_PressureTransmitter IMPLEMENTS I_Sensor``: scales a 4-20 mA input.

    ``raw`` and ``error`` are the terminal's process data (0 .. 32767, wire
    break / underrange bit); FB_init sets the measuring range.
    """

    raw: INT = VAR_INPUT(0)
    error: BOOL = VAR_INPUT(False)
    low: LREAL = VAR(0.0)
    high: LREAL = VAR(10.0)
    scaled: LREAL = VAR_OUTPUT(0.0)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, low: LREAL = 0.0, high: LREAL = 10.0) -> None:
        self.low = low
        self.high = high

    @method
    def scan(self) -> None:
        self.scaled = self.low + (self.high - self.low) * self.raw / RAW_FULL_SCALE

    @prop
    def value(self) -> LREAL:
        return self.scaled

    @prop
    def ok(self) -> BOOL:
        return not self.error and self.raw >= 0


class SensorDecorator(FunctionBlock, ISensor, abstract=True):
    """``FUNCTION_BLOCK ABSTRACT FB_SensorDecorator IMPLEMENTS I_Sensor``: forwards to the wrapped sensor.

    The wrapped sensor is injected at FB_init (``MovingAverage(inner=pt)``)
    or, for instances declared side by side in a program, through the
    ``inner`` property. Scanning with nothing wrapped is an access violation.
    """

    inner_sensor: ISensor = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, inner: ISensor | None = None) -> None:
        if inner is not None:
            self.inner_sensor = inner

    @prop
    def inner(self) -> ISensor:
        return self.inner_sensor

    @inner.setter
    def inner(self, sensor: ISensor) -> None:
        self.inner_sensor = sensor

    @method
    def scan(self) -> None:
        self.inner_sensor.scan()

    @prop
    def value(self) -> LREAL:
        return self.inner_sensor.value

    @prop
    def ok(self) -> BOOL:
        return self.inner_sensor.ok


class MovingAverage(SensorDecorator):
    """``FUNCTION_BLOCK FB_MovingAverage EXTENDS FB_SensorDecorator``: mean of the last ``window`` good samples.

    A bad sample is not stored: the average holds and ``ok`` follows the
    wrapped sensor. ``window`` is clamped to 1 .. MAX_WINDOW.
    """

    window: INT = VAR_INPUT(4)
    samples: ARRAY[LREAL] = VAR(bounds=(1, MAX_WINDOW))
    newest: INT = VAR(0)
    filled: INT = VAR(0)
    average: LREAL = VAR_OUTPUT(0.0)

    @method
    def scan(self) -> None:
        super().scan()
        if not self.inner_sensor.ok:
            return
        self.newest = self.newest % MAX_WINDOW + 1
        self.samples[self.newest] = self.inner_sensor.value
        self.filled = min(self.filled + 1, MAX_WINDOW)
        n = min(max(self.window, 1), MAX_WINDOW, self.filled)
        total = 0.0
        for k in range(n):
            # + MAX_WINDOW keeps the dividend positive: ST's MOD follows its sign, Python's % the divisor's.
            total += self.samples[(self.newest - 1 - k + MAX_WINDOW) % MAX_WINDOW + 1]
        self.average = total / n

    @method
    def clear(self) -> None:
        """Forget the stored samples (e.g. after a range change)."""
        self.filled = 0
        self.average = 0.0

    @prop
    def value(self) -> LREAL:
        return self.average

    @prop
    def ok(self) -> BOOL:
        return self.inner_sensor.ok and self.filled > 0


class SimulationOverride(SensorDecorator):
    """``FUNCTION_BLOCK FB_SimulationOverride EXTENDS FB_SensorDecorator``: ``sim_value`` replaces the reading.

    The wrapped sensor keeps being scanned, so counters below keep counting.
    """

    simulate: BOOL = VAR_INPUT(False)
    sim_value: LREAL = VAR_INPUT(0.0)

    @prop
    def value(self) -> LREAL:
        return self.sim_value if self.simulate else self.inner_sensor.value

    @prop
    def ok(self) -> BOOL:
        return True if self.simulate else self.inner_sensor.ok


class MaintenanceCounter(SensorDecorator):
    """``FUNCTION_BLOCK FB_MaintenanceCounter EXTENDS FB_SensorDecorator``: hours in service and switchings.

    Counts whole seconds while the sensor is ok (a second cut short by an
    outage is not counted), and each rise of the value
    over ``switch_point`` (it must fall below ``switch_point - hysteresis``
    before the next one counts). Both counters are RETAIN. The value passes
    through unchanged.
    """

    switch_point: LREAL = VAR_INPUT(5.0)
    hysteresis: LREAL = VAR_INPUT(0.5)
    max_switchings: UDINT = VAR_INPUT(100_000)
    operating_s: UDINT = VAR_OUTPUT(0, retain=True)
    switchings: UDINT = VAR_OUTPUT(0, retain=True)
    service_due: BOOL = VAR_OUTPUT(False)
    switched_on: BOOL = VAR(False)
    second: TON = VAR()
    rising: R_TRIG = VAR()

    @method
    def scan(self) -> None:
        super().scan()
        in_service = self.inner_sensor.ok
        self.second(IN=in_service, PT=T("1s"))
        if self.second.Q:
            self.operating_s += 1
            self.second(IN=False)
            self.second(IN=True)
        level = self.inner_sensor.value
        if level >= self.switch_point:
            self.switched_on = True
        elif level < self.switch_point - self.hysteresis:
            self.switched_on = False
        self.rising(CLK=in_service and self.switched_on)
        if self.rising.Q:
            self.switchings += 1
        self.service_due = self.switchings >= self.max_switchings

    @method
    def reset_counters(self) -> None:
        """After the sensor is serviced or replaced."""
        self.operating_s = 0
        self.switchings = 0
        self.service_due = False

    @prop
    def operating_hours(self) -> LREAL:
        return self.operating_s / 3600.0


class PressureMain(Program):
    """``PROGRAM PRG_PressureMain``: PT101 → maintenance counter → moving average → simulation → logic."""

    pt101: PressureTransmitter = VAR(fb_init={"low": 0.0, "high": 10.0})
    counter: MaintenanceCounter = VAR({"switch_point": 6.0, "hysteresis": 0.5})
    average: MovingAverage = VAR({"window": 4})
    override: SimulationOverride = VAR()
    pv: ISensor = VAR()
    pressure: LREAL = VAR_OUTPUT(0.0)
    pressure_ok: BOOL = VAR_OUTPUT(False)

    @call_after_init
    def wire(self) -> None:
        self.counter.inner = self.pt101
        self.average.inner = self.counter
        self.override.inner = self.average
        self.pv = self.override

    def body(self) -> None:
        self.pv.scan()
        self.pressure = self.pv.value
        self.pressure_ok = self.pv.ok


def _raw(bar: float) -> int:
    return round(bar / 10.0 * RAW_FULL_SCALE)


def main() -> None:
    """Feed PT101 a pulsating pressure, then simulate it; print what the logic sees.

    >>> main()
    t=   0 ms  PT101 2.00 bar  logic 2.00 bar  ok   switchings 0
    t=  50 ms  PT101 9.00 bar  logic 3.75 bar  ok   switchings 1
    t=  90 ms  PT101 2.00 bar  logic 2.00 bar  ok   switchings 1
    t= 120 ms  PT101 7.00 bar  logic 5.75 bar  ok   switchings 2
    t= 250 ms  PT101 2.00 bar  logic 2.00 bar  ok   switchings 2
    t= 350 ms  PT101 -.-- bar  logic 2.00 bar  BAD  switchings 2
    t= 450 ms  PT101 2.00 bar  logic 2.00 bar  ok   switchings 2
    t= 550 ms  PT101 7.00 bar  logic 4.50 bar  SIM  switchings 3
    after 2.00 s: 1 s in service, 3 switchings
    """
    prog = PressureMain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), prog)
    for cycle in range(200):
        t = cycle * 10
        bar = 9.0 if t == 50 else 7.0 if 100 <= t < 200 or t >= 500 else 2.0
        prog.pt101.raw = _raw(bar)
        prog.pt101.error = 300 <= t < 400
        if t == 500:
            prog.override.sim_value = 4.5
            prog.override.simulate = True
        shown = rt.time_ms
        rt.run(cycles=1)
        if shown in (0, 50, 90, 120, 250, 350, 450, 550):
            reading = "-.--" if prog.pt101.error else f"{prog.pt101.value:4.2f}"
            quality = "SIM" if prog.override.simulate else "ok " if prog.pressure_ok else "BAD"
            print(
                f"t={shown:4d} ms  PT101 {reading} bar  logic {prog.pressure:4.2f} bar  {quality}  "
                f"switchings {prog.counter.switchings}"
            )
    print(f"after {rt.time_ms / 1000:.2f} s: {prog.counter.operating_s} s in service, "
          f"{prog.counter.switchings} switchings")


def _pressure(scenario: Scenario, cycle: int) -> None:
    prog = scenario.program
    t = (cycle - 1) * 10
    bar = 9.0 if t == 50 else 7.0 if 100 <= t < 200 or t >= 500 else 2.0
    prog.pt101.raw = round(bar / 10.0 * RAW_FULL_SCALE)
    prog.pt101.error = 300 <= t < 400
    if t == 500:
        prog.override.sim_value = 4.5
        prog.override.simulate = True


def _pt101(prog: Any) -> object:
    pt101 = prog.pt101
    return "-.--" if pt101.error else f"{pt101.value:.2f}"


SHOWCASE = Showcase(
    use_when="signal treatments (filtering, simulation, counting) are stacked per channel at configuration",
    columns=(
        Column("PT101 bar", _pt101),
        Column("logic bar", lambda p: p.pressure, ".2f", watch=False),
        Column("ok", lambda p: p.pressure_ok),
        Column("simulate", lambda p: p.override.simulate),
        Column("switchings", lambda p: p.counter.switchings),
    ),
    script=_pressure,
    cycles=70,
    tour_cycles=70,
)


if __name__ == "__main__":
    main()
