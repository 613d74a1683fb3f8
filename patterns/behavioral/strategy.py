"""Strategy: a heater zone whose control algorithm is swapped at run time, without a bump.

Intent
------

Define a family of algorithms, put each one behind the same interface and
make them interchangeable: the client keeps one interface reference and the
algorithm behind it can change while the machine runs.

The PLC problem
---------------

An extruder barrel or a sealing jaw has heater zones. Commissioning starts
with a plain on/off thermostat (robust, no tuning); once the zone is tuned it
runs a PID driving a thyristor power controller; zones with only a solid-state
relay run the same PID through a time-proportional output (a PWM built from a
TON period timer and a TP on-pulse). The operator picks the mode on the HMI
while the zone is hot, so the change must be *bumpless*: the new algorithm
starts from the output the old one was giving, the heater power does not jump
and the temperature does not dip or overshoot. Writing the three algorithms
into one FB with a CASE on the mode grows a block nobody dares to touch; with
Strategy the zone holds an ``I_ControlStrategy`` and each algorithm is a small
FB of its own.

Roles
-----

- Strategy interface → ``IControlStrategy`` (``I_ControlStrategy``)
- Concrete strategies → ``OnOffControl`` (``FB_OnOffControl``), ``PidControl``
  (``FB_PidControl``), ``PwmControl`` (``FB_PwmControl``)
- Context → ``HeaterZone`` (``FB_HeaterZone``), with the ``strategy`` property
  whose setter performs the bumpless transfer
- Simulated plant → ``ThermalProcess`` (``FB_ThermalProcess``), a first-order lag
- Client → ``ZoneMain`` (``PRG_ZoneMain``), selecting the strategy from the
  ``ControlMode`` enum (``E_ControlMode``)

IEC 61131-3 mapping
-------------------

::

    INTERFACE I_ControlStrategy
        METHOD Takeover    // VAR_INPUT output, setpoint, actual : REAL;
        METHOD Execute : REAL   // VAR_INPUT setpoint, actual : REAL; cycleTime : TIME;
        PROPERTY Output : REAL  // Get: the manipulated value in %
        PROPERTY Name : STRING  // Get

    FUNCTION_BLOCK FB_OnOffControl IMPLEMENTS I_ControlStrategy
        VAR_INPUT hysteresis : REAL := 2.0; END_VAR
        VAR relay : BOOL; END_VAR

    FUNCTION_BLOCK FB_PidControl IMPLEMENTS I_ControlStrategy
        VAR kp, ti, td, integral, lastActual : REAL; END_VAR
        VAR_OUTPUT y : REAL; tuneError : BOOL; END_VAR
        METHOD Tune : BOOL // VAR_INPUT kp, ti, td : REAL; END_VAR  FALSE: gains kept

    FUNCTION_BLOCK FB_PwmControl IMPLEMENTS I_ControlStrategy
        VAR pid : FB_PidControl; periodTimer : TON; pulse : TP; END_VAR
        PROPERTY Period : TIME  // Get, Set (raised to T#100MS if shorter)

    FUNCTION_BLOCK FB_HeaterZone
        VAR_INPUT setpoint : REAL; actual : REAL; cycleTime : TIME; END_VAR
        VAR_OUTPUT power : REAL; output : REAL;
                   noStrategy : BOOL; END_VAR  // TRUE: the heater gets 0 %
        VAR activeStrategy : I_ControlStrategy; END_VAR
        PROPERTY Strategy : I_ControlStrategy  // Set: new.Takeover(output, ...);
                                               // a null one is ignored

When not to use it on a PLC
---------------------------

When there is one algorithm and no realistic second one, an interface only
adds an indirection to read through online. When the algorithms differ only
in a few parameters (two PID tunings), a parameter set is the simpler answer.
And when the variants must be certified separately (a safety function), keep
them in separate, fixed code paths rather than behind a reference that can be
re-pointed at run time.

References
----------

- E. Gamma, R. Helm, R. Johnson, J. Vlissides, *Design Patterns: Elements of
  Reusable Object-Oriented Software*, Addison-Wesley 1994, "Strategy".
- IEC 61131-3:2013 (3rd edition), *Programmable controllers - Part 3:
  Programming languages*: interfaces and methods of function blocks; the
  standard timer function blocks TP and TON. PROPERTY is a CODESYS / TwinCAT
  extension, not part of the standard.
- Beckhoff InfoSys, TwinCAT 3 PLC: "Interface", "Property", "Method",
  "TP", "TON".
- CODESYS Online Help: "Object: Interface", "Object: Property",
  "Object: Method".
"""

from __future__ import annotations

from typing import Any

from iecoop import (
    BOOL,
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
from iecoop.conversions import DINT_TO_TIME, TIME_TO_DINT, TO_TIME, TRUNC
from iecoop.runtime import Runtime, Task, current_task
from iecoop.stdlib import TON, TP
from patterns.showcase.entry import Column, Scenario, Showcase

__all__ = [
    "ControlMode",
    "HeaterZone",
    "IControlStrategy",
    "OnOffControl",
    "PidControl",
    "PwmControl",
    "ThermalProcess",
    "ZoneMain",
    "main",
]

OUTPUT_MIN = 0.0
OUTPUT_MAX = 100.0


def limit(value: float) -> float:
    """``LIMIT(0.0, value, 100.0)``: the heater power range in %."""
    return max(OUTPUT_MIN, min(OUTPUT_MAX, value))


class IControlStrategy(Interface):
    """``INTERFACE I_ControlStrategy``: one temperature control algorithm.

    ``execute`` runs once per scan and returns the heater power to apply
    (0..100 %); ``output`` is the manipulated value the algorithm holds (for a
    PWM the duty cycle, not the instantaneous relay state); ``takeover``
    initialises the algorithm from the output of the one it replaces.
    """

    @method
    def takeover(self, output: REAL, setpoint: REAL, actual: REAL) -> None: ...

    @method
    def execute(self, setpoint: REAL, actual: REAL, cycle_time: TIME) -> REAL:
        raise NotImplementedError

    @prop
    def output(self) -> REAL:
        raise NotImplementedError

    @prop
    def name(self) -> STRING:
        raise NotImplementedError


class OnOffControl(FunctionBlock, IControlStrategy):
    """``FUNCTION_BLOCK FB_OnOffControl IMPLEMENTS I_ControlStrategy``: a thermostat with hysteresis.

    The relay switches on below ``setpoint - hysteresis / 2`` and off above
    ``setpoint + hysteresis / 2``. It has two output levels only, so a
    takeover keeps the relay state nearest the current output (on at 50 % and
    above): the first output after the swap is 0 % or 100 %.
    """

    hysteresis: REAL = VAR_INPUT(2.0)
    relay: BOOL = VAR_OUTPUT(False)

    @method
    def takeover(self, output: REAL, setpoint: REAL, actual: REAL) -> None:
        self.relay = output >= 50.0

    @method
    def execute(self, setpoint: REAL, actual: REAL, cycle_time: TIME) -> REAL:
        half = self.hysteresis / 2.0
        if actual < setpoint - half:
            self.relay = True
        elif actual > setpoint + half:
            self.relay = False
        return OUTPUT_MAX if self.relay else OUTPUT_MIN

    @prop
    def output(self) -> REAL:
        return OUTPUT_MAX if self.relay else OUTPUT_MIN

    @prop
    def name(self) -> STRING:
        return "on/off"


class PidControl(FunctionBlock, IControlStrategy):
    """``FUNCTION_BLOCK FB_PidControl IMPLEMENTS I_ControlStrategy``: positional PID with anti-windup.

    ``y = kp * (e + integral + td * d(-actual)/dt)``, the integral in the
    units of ``e`` (``integral += e * dt / ti``; ``ti = 0`` switches it off).
    The derivative acts on the measurement, so a setpoint step gives no kick.
    Anti-windup by conditional integration: while the output is saturated and
    the error would drive it further, the integral is frozen, so the output
    leaves the limit as soon as the error changes sign. ``takeover`` solves
    ``y = kp * (e + integral)`` for the integral, so the first output after a
    swap equals the output before it.

    ``PidControl(kp=12.0, ti=6.0, td=0.0)``: gains are FB_init inputs.
    """

    kp: REAL = VAR(12.0)
    ti: REAL = VAR(6.0)
    td: REAL = VAR(0.0)
    integral: REAL = VAR(0.0)
    last_actual: REAL = VAR(0.0)
    primed: BOOL = VAR(False)
    y: REAL = VAR_OUTPUT(0.0)
    tune_error: BOOL = VAR_OUTPUT(False)

    def fb_init(
        self, init_retains: BOOL, in_copy_code: BOOL, kp: REAL = 12.0, ti: REAL = 6.0, td: REAL = 0.0
    ) -> BOOL:
        self.tune(kp, ti, td)
        return True

    @method
    def tune(self, kp: REAL, ti: REAL, td: REAL = 0.0) -> BOOL:
        """New gains: ``kp`` in % per kelvin, ``ti`` and ``td`` in seconds (0 switches the term off).

        ``kp <= 0`` or a negative ``ti`` / ``td`` is refused: FALSE, the gains
        before stay, and ``tune_error`` is set until a valid tuning.
        """
        self.tune_error = kp <= 0.0 or ti < 0.0 or td < 0.0
        if self.tune_error:
            return False
        self.kp, self.ti, self.td = kp, ti, td
        return True

    @method
    def takeover(self, output: REAL, setpoint: REAL, actual: REAL) -> None:
        # y = kp * (e + integral) with no derivative at the first scan: solve for the integral.
        self.integral = limit(output) / self.kp - (setpoint - actual)
        self.last_actual = actual
        self.primed = True
        self.y = limit(output)

    @method
    def execute(self, setpoint: REAL, actual: REAL, cycle_time: TIME) -> REAL:
        dt = TIME_TO_DINT(cycle_time) / 1000.0   # TIME / REAL would be a TIME in ST
        error = setpoint - actual
        if not self.primed:
            self.last_actual = actual
            self.primed = True
        derivative = 0.0
        if self.td > 0.0 and dt > 0.0:
            derivative = -self.td * (actual - self.last_actual) / dt
        self.last_actual = actual
        if self.ti > 0.0:
            candidate = self.integral + error * dt / self.ti
            raw = self.kp * (error + candidate + derivative)
            winding_up = (raw > OUTPUT_MAX and error > 0.0) or (raw < OUTPUT_MIN and error < 0.0)
            if not winding_up:
                self.integral = candidate
        self.y = limit(self.kp * (error + self.integral + derivative))
        return self.y

    @prop
    def output(self) -> REAL:
        return self.y

    @prop
    def name(self) -> STRING:
        return "PID"


class PwmControl(FunctionBlock, IControlStrategy):
    """``FUNCTION_BLOCK FB_PwmControl IMPLEMENTS I_ControlStrategy``: PID through a time-proportional output.

    A solid-state relay is on or off; the PID's output becomes a duty cycle.
    A TON times the period; at each period start the on-time
    ``duty * period`` is latched and a TP gives exactly that pulse. The
    ``output`` is the duty (the PID's output), so a swap to or from the PID
    is bumpless in the manipulated value.

    ``PwmControl(period=T("1s"), kp=12.0, ti=6.0)``.
    """

    pid: PidControl = VAR()
    period_timer: TON = VAR()
    pulse: TP = VAR()
    period_time: TIME = VAR(T("1s"))
    on_time: TIME = VAR_OUTPUT(0)
    running: BOOL = VAR(False)
    periods: UDINT = VAR_OUTPUT(0)

    def fb_init(
        self, init_retains: BOOL, in_copy_code: BOOL, period: TIME = T("1s"), kp: REAL = 12.0, ti: REAL = 6.0
    ) -> BOOL:
        self.period = period
        self.pid.tune(kp, ti)
        return True

    @prop
    def period(self) -> TIME:
        """The PWM period. The on-time is a whole number of scans, so the period must span many scans."""
        return self.period_time

    @period.setter
    def period(self, value: TIME) -> None:
        # Shorter than 10 scans the on-time cannot be resolved: a shorter period is raised to T#100MS.
        self.period_time = max(value, T("100ms"))
        self.running = False

    @method
    def takeover(self, output: REAL, setpoint: REAL, actual: REAL) -> None:
        self.pid.takeover(output, setpoint, actual)
        self.running = False

    @method
    def execute(self, setpoint: REAL, actual: REAL, cycle_time: TIME) -> REAL:
        duty = self.pid.execute(setpoint, actual, cycle_time)
        self.period_timer(IN=True, PT=self.period)
        if self.period_timer.Q or not self.running:
            # A new period: restart both timers now and latch the on-time.
            self.running = True
            self.periods += 1
            self.period_timer(IN=False)
            self.period_timer(IN=True, PT=self.period)
            self.on_time = DINT_TO_TIME(TRUNC(duty / 100.0 * TIME_TO_DINT(self.period) + 0.5))
            self.pulse(IN=False)
            self.pulse(IN=self.on_time > 0, PT=self.on_time)
        else:
            self.pulse()
        return OUTPUT_MAX if self.pulse.Q else OUTPUT_MIN

    @prop
    def output(self) -> REAL:
        return self.pid.output

    @prop
    def name(self) -> STRING:
        return "PWM"


class ThermalProcess(FunctionBlock):
    """``FUNCTION_BLOCK FB_ThermalProcess``: the heated zone as a first-order lag (the plant, simulated).

    ``T := T + dt / tau * (ambient + gain * power - T)``: at 100 % power the
    zone settles ``gain * 100`` kelvin above ambient with time constant
    ``tau`` seconds.
    """

    power: REAL = VAR_INPUT(0.0)
    cycle_time: TIME = VAR_INPUT(T("10ms"))
    temperature: REAL = VAR_OUTPUT(20.0)
    ambient: REAL = VAR(20.0)
    gain: REAL = VAR(1.0)
    tau: REAL = VAR(20.0)

    def fb_init(
        self, init_retains: BOOL, in_copy_code: BOOL, ambient: REAL = 20.0, gain: REAL = 1.0, tau: REAL = 20.0
    ) -> BOOL:
        # A time constant of 0 s or less has no meaning (and would divide by zero): the default stays.
        if tau > 0.0:
            self.tau = tau
        self.ambient, self.gain = ambient, gain
        self.temperature = ambient
        return True

    def body(self) -> None:
        dt = TIME_TO_DINT(self.cycle_time) / 1000.0
        target = self.ambient + self.gain * limit(self.power)
        self.temperature = self.temperature + dt / self.tau * (target - self.temperature)


class HeaterZone(FunctionBlock):
    """``FUNCTION_BLOCK FB_HeaterZone``: the context, holding one ``I_ControlStrategy``.

    Each call runs the active strategy: ``power`` is what the heater gets,
    ``output`` the strategy's manipulated value. Setting ``strategy``
    performs the bumpless transfer: the new strategy's ``takeover`` gets the
    current output, setpoint and actual value before it takes control (the
    first strategy of a zone has nothing to take over and starts cold).

    ``HeaterZone(strategy=pid)`` injects the first strategy at FB_init.
    """

    setpoint: REAL = VAR_INPUT(60.0)
    actual: REAL = VAR_INPUT(20.0)
    cycle_time: TIME = VAR_INPUT(T("10ms"))
    power: REAL = VAR_OUTPUT(0.0)
    output: REAL = VAR_OUTPUT(0.0)
    swaps: UDINT = VAR_OUTPUT(0)
    no_strategy: BOOL = VAR_OUTPUT(False)
    active_strategy: IControlStrategy = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, strategy: IControlStrategy | None = None) -> BOOL:
        if strategy is not None:
            self.strategy = strategy
        return True

    @prop
    def strategy(self) -> IControlStrategy:
        return self.active_strategy

    @strategy.setter
    def strategy(self, value: IControlStrategy) -> None:
        # A null strategy cannot control the heater: it is ignored and the running one stays.
        if not value or value == self.active_strategy:
            return
        if self.active_strategy:
            # Bumpless: the newcomer starts from what the running strategy gives now.
            value.takeover(self.output, self.setpoint, self.actual)
        self.active_strategy = value
        self.swaps += 1

    def body(self) -> None:
        # A zone without a strategy is a configuration error: the heater stays off and it shows.
        self.no_strategy = not self.active_strategy
        if self.no_strategy:
            self.power, self.output = OUTPUT_MIN, OUTPUT_MIN
            return
        self.power = self.active_strategy.execute(self.setpoint, self.actual, self.cycle_time)
        self.output = self.active_strategy.output


class ControlMode(IecEnum):
    """``TYPE E_ControlMode : (ON_OFF := 1, PID := 2, PWM := 3) INT; END_TYPE``"""

    ON_OFF = 1
    PID = 2
    PWM = 3


class ZoneMain(Program):
    """``PROGRAM PRG_ZoneMain``: one heater zone on its simulated process, the mode chosen on the HMI.

    The cycle time comes from the task (``_TaskInfo[GETCURTASKINDEXEX()].CycleTime``,
    in 100 ns units), so the PID and the process integrate over the real scan.
    """

    mode: ControlMode = VAR_INPUT(ControlMode.PID)
    setpoint: REAL = VAR_INPUT(60.0)
    selected: ControlMode = VAR_OUTPUT(ControlMode.PID)
    process: ThermalProcess = VAR()
    zone: HeaterZone = VAR()
    on_off: OnOffControl = VAR()
    pid: PidControl = VAR()
    pwm: PwmControl = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
        self.select(self.mode)
        return True

    @method
    def select(self, mode: ControlMode) -> None:
        if mode == ControlMode.ON_OFF:
            self.zone.strategy = self.on_off
        elif mode == ControlMode.PWM:
            self.zone.strategy = self.pwm
        else:
            self.zone.strategy = self.pid
        self.selected = mode

    def body(self) -> None:
        cycle_time: TIME = TO_TIME(current_task().CycleTime // 10_000)
        if self.mode != self.selected:
            self.select(self.mode)
        self.zone(setpoint=self.setpoint, actual=self.process.temperature, cycle_time=cycle_time)
        self.process(power=self.zone.power, cycle_time=cycle_time)


def main() -> None:
    """Heat a zone with the PID, swap strategies while it is hot, and print a trace.

    >>> main()
    t=  5.0 s  PID     T= 42.1 degC  output=100.0 %
    t= 10.0 s  PID     T= 56.9 degC  output= 62.7 %
    t= 15.0 s  PID     T= 59.6 degC  output= 42.9 %
    t= 20.0 s  PID     T= 60.0 degC  output= 40.3 %
             swap PID -> PWM: output  40.3 % ->  40.3 %
    t= 25.0 s  PWM     T= 59.7 degC  output= 38.9 %
    t= 30.0 s  PWM     T= 59.5 degC  output= 39.4 %
             swap PWM -> PID: output  39.4 % ->  39.1 %
    t= 35.0 s  PID     T= 59.7 degC  output= 40.7 %
    t= 40.0 s  PID     T= 59.9 degC  output= 40.3 %
             swap PID -> on/off: output  40.3 % ->   0.0 %
    t= 45.0 s  on/off  T= 60.0 degC  output=  0.0 %
    t= 50.0 s  on/off  T= 60.2 degC  output=  0.0 %
    """
    program = ZoneMain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)

    def report() -> None:
        print(
            f"t={rt.time_ms / 1000:5.1f} s  {program.zone.strategy.name:<6}  "
            f"T={program.process.temperature:5.1f} degC  output={program.zone.output:5.1f} %"
        )

    for _ in range(4):
        rt.run(cycles=500)
        report()
    for mode in (ControlMode.PWM, ControlMode.PID, ControlMode.ON_OFF):
        before, old = program.zone.output, program.zone.strategy.name
        program.mode = mode
        rt.run(cycles=1)
        new, after = program.zone.strategy.name, program.zone.output
        print(f"         swap {old} -> {new}: output {before:5.1f} % -> {after:5.1f} %")
        for _ in range(2):
            rt.run(cycles=500)
            report()


def _modes(scenario: Scenario, cycle: int) -> None:
    modes = {2001: "PWM", 3001: "PID", 4001: "ON_OFF"}
    if cycle in modes:
        scenario.program.mode = ControlMode[modes[cycle]]


def _strategy_name(prog: Any) -> object:
    return prog.zone.strategy.name


SHOWCASE = Showcase(
    use_when="an algorithm (PID, PWM, on/off) is swapped at run time behind one interface, without a bump",
    columns=(
        Column("mode", lambda p: p.mode),
        Column("strategy", _strategy_name),
        Column("T degC", lambda p: p.process.temperature, ".1f", watch=False),
        Column("output %", lambda p: p.zone.output, ".1f", watch=False),
        Column("swaps", lambda p: p.zone.swaps),
    ),
    script=_modes,
    cycles=5000,
    tour_cycles=5000,
)
