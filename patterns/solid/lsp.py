"""Liskov substitution: a read-only sensor must not inherit a writable actuator base.

Principle
---------

Objects of a derived type must be usable wherever the base type is expected,
without the caller noticing (Barbara Liskov). A derived block may accept more
and promise more than its base, never less: it must keep the base's
postconditions.

The course example
------------------

The course's driver drives through ``I_Mover``: a car, a motorbike or any
other ``FB_Vehicle`` that implements it can be handed to the driver, and each
one really moves when ``Move`` is called. A parked trailer that implemented
``I_Mover`` and ignored ``Move`` would break every driver.

The PLC problem
---------------

An analog output block scales 0..100 % to the output card's word and reads the
value back; its contract is "after ``Write(x)``, ``Value`` is ``x``". A
pressure transmitter needs the same scaling, so it is derived from the output
block and its ``Write`` is overridden to refuse. Every caller written for the
output block still accepts it, the compiler included: a setpoint ramp handed
the transmitter writes, waits for the value to follow, and runs into its
timeout while the pressure is untouched.

Violating design
----------------

- ``AnalogActuator`` (``FB_AnalogActuator``): scaling, ``Write`` and ``Value``.
- ``PressureSensorAsActuator`` (``FB_PressureSensor EXTENDS
  FB_AnalogActuator``): overrides ``Write`` to refuse; ``Value`` follows the
  input card.
- ``RampOnActuator`` (``FB_SetpointRamp``, ``VAR_IN_OUT output :
  FB_AnalogActuator``): the caller written against the base.

Compliant design
----------------

- ``IAnalogValue`` (``I_AnalogValue``): ``Value`` only. ``IActuator``
  (``I_Actuator EXTENDS I_AnalogValue``) adds ``Write``.
- ``ScaledChannel`` (``FB_ScaledChannel``, ABSTRACT, ``IMPLEMENTS
  I_AnalogValue``): the shared scaling, read-only.
- ``AnalogOutput`` (``FB_AnalogOutput EXTENDS FB_ScaledChannel IMPLEMENTS
  I_Actuator``) and ``PressureSensor`` (``FB_PressureSensor EXTENDS
  FB_ScaledChannel``): the sensor never promises ``Write``.
- ``SetpointRamp`` (``FB_SetpointRamp``, ``itfOutput : I_Actuator``) takes
  actuators only: handing it the sensor is a type error for mypy and the
  compiler, and ``__QUERYINTERFACE(sensor, I_Actuator)`` fails.
- ``ValueMonitor`` (``FB_ValueMonitor``, ``itfSignal : I_AnalogValue``)
  takes both: every actuator is a valid analog value.

IEC 61131-3 mapping
-------------------

::

    FUNCTION_BLOCK FB_AnalogActuator                          // violating
        VAR_OUTPUT nRaw : INT; END_VAR                        // 0..32000 = 0..100 %
        METHOD Write : BOOL  VAR_INPUT rValue : REAL; END_VAR
        PROPERTY Value : REAL
    FUNCTION_BLOCK FB_PressureSensor EXTENDS FB_AnalogActuator
        VAR_INPUT nRawIn : INT; END_VAR
        METHOD Write : BOOL                                   // Write := FALSE;
    FUNCTION_BLOCK FB_SetpointRamp
        VAR_IN_OUT output : FB_AnalogActuator; END_VAR

    INTERFACE I_AnalogValue EXTENDS __SYSTEM.IQueryInterface  // compliant
        PROPERTY Value : REAL
    INTERFACE I_Actuator EXTENDS I_AnalogValue
        METHOD Write : BOOL  VAR_INPUT rValue : REAL; END_VAR
    FUNCTION_BLOCK ABSTRACT FB_ScaledChannel IMPLEMENTS I_AnalogValue
    FUNCTION_BLOCK FB_AnalogOutput EXTENDS FB_ScaledChannel IMPLEMENTS I_Actuator
    FUNCTION_BLOCK FB_PressureSensor EXTENDS FB_ScaledChannel
    FUNCTION_BLOCK FB_SetpointRamp
        VAR_INPUT itfOutput : I_Actuator; rTarget : REAL; tTimeout : TIME := T#2S; END_VAR
        VAR_OUTPUT bDone, bTimedOut : BOOL; END_VAR

References
----------

- B. Liskov, J. Wing, "A behavioral notion of subtyping", *ACM TOPLAS* 16(6),
  1994.
- R. C. Martin, *Agile Software Development: Principles, Patterns, and
  Practices*, Prentice Hall, 2002, chapter 10 "LSP".
- IEC 61131-3:2013, 3rd edition: EXTENDS, ABSTRACT, interfaces and
  ``IMPLEMENTS``, VAR_IN_OUT, the standard timer TON.
- Beckhoff InfoSys, TwinCAT 3 PLC: "Object-oriented programming",
  "__QUERYINTERFACE".
- CODESYS online help: "Extension of a function block", "Operator
  __QUERYINTERFACE".
"""

from __future__ import annotations

from iecoop import (
    BOOL,
    INT,
    REAL,
    TIME,
    UDINT,
    VAR,
    VAR_IN_OUT,
    VAR_INPUT,
    VAR_OUTPUT,
    FunctionBlock,
    IQueryInterface,
    Program,
    T,
    method,
    prop,
    query_interface,
)
from iecoop.runtime import Runtime, Task
from iecoop.stdlib import TON
from patterns.plant import ramp
from patterns.showcase.entry import Column, Showcase

#: Card counts per percent: the cards are configured for 0..32000 = 0..100 %.
COUNTS_PER_PERCENT = 320
#: One count, in percent: how close a read-back must be.
LSB = 1.0 / COUNTS_PER_PERCENT


def clamp(value: REAL) -> REAL:
    """``FUNCTION F_Clamp : REAL``: ``LIMIT(0.0, value, 100.0)``."""
    return min(max(value, 0.0), 100.0)


def to_raw(value: REAL) -> INT:
    """``FUNCTION F_ToRaw : INT``: percent to card counts, clamped."""
    return round(clamp(value) * COUNTS_PER_PERCENT)


# ---------------------------------------------------------------------------
# Violating design: the sensor inherits the actuator to reuse its scaling
# ---------------------------------------------------------------------------


class AnalogActuator(FunctionBlock):
    """``FUNCTION_BLOCK FB_AnalogActuator``: a 0..100 % analog output.

    Contract of ``write``: it returns TRUE, and ``value`` then reads back the
    written value, clamped to 0..100 %, within one count.
    """

    raw: INT = VAR_OUTPUT(0)

    @method
    def write(self, value: REAL) -> BOOL:
        self.raw = to_raw(value)
        return True

    @prop
    def value(self) -> REAL:
        return self.raw / COUNTS_PER_PERCENT


class PressureSensorAsActuator(AnalogActuator):
    """``FUNCTION_BLOCK FB_PressureSensor EXTENDS FB_AnalogActuator``: reuses the scaling, breaks ``write``.

    A transmitter cannot be written, so ``write`` refuses: the base's
    postcondition no longer holds, yet every caller of the base accepts it.
    """

    raw_in: INT = VAR_INPUT(0)
    refused: UDINT = VAR_OUTPUT(0)

    @method
    def write(self, value: REAL) -> BOOL:
        self.refused += 1
        return False

    def body(self) -> None:
        self.raw = self.raw_in


class RampOnActuator(FunctionBlock):
    """``FUNCTION_BLOCK FB_SetpointRamp`` written for the base: ``VAR_IN_OUT output : FB_AnalogActuator``.

    It ramps ``output`` to ``target`` and waits for the read-back; per the
    base's contract a write in range cannot fail, so the ramp only guards
    the whole move with a timeout.
    """

    output: AnalogActuator = VAR_IN_OUT()
    target: REAL = VAR_INPUT(0.0)
    step: REAL = VAR_INPUT(12.5)
    timeout: TIME = VAR_INPUT(T("2s"))
    done: BOOL = VAR_OUTPUT(False)
    timed_out: BOOL = VAR_OUTPUT(False)
    watchdog: TON = VAR()

    def body(self) -> None:
        target = clamp(self.target)
        current = self.output.value
        if abs(current - target) > LSB:
            self.output.write(ramp(current, target, self.step))
        self.done = abs(self.output.value - target) <= LSB
        self.watchdog(IN=not self.done, PT=self.timeout)
        self.timed_out = self.watchdog.Q


# ---------------------------------------------------------------------------
# Compliant design: read-only and writable are different promises
# ---------------------------------------------------------------------------


class IAnalogValue(IQueryInterface):
    """``INTERFACE I_AnalogValue``: a value in percent that can be read."""

    @prop
    def value(self) -> REAL:
        raise NotImplementedError


class IActuator(IAnalogValue):
    """``INTERFACE I_Actuator EXTENDS I_AnalogValue``: a value that can also be written.

    Contract of ``write``: as ``FB_AnalogActuator.Write``.
    """

    @method
    def write(self, value: REAL) -> BOOL:
        raise NotImplementedError


class ScaledChannel(FunctionBlock, IAnalogValue, abstract=True):
    """``FUNCTION_BLOCK ABSTRACT FB_ScaledChannel IMPLEMENTS I_AnalogValue``: the shared, read-only scaling."""

    raw: INT = VAR_OUTPUT(0)

    @prop
    def value(self) -> REAL:
        return self.raw / COUNTS_PER_PERCENT


class AnalogOutput(ScaledChannel, IActuator):
    """``FUNCTION_BLOCK FB_AnalogOutput EXTENDS FB_ScaledChannel IMPLEMENTS I_Actuator``."""

    @method
    def write(self, value: REAL) -> BOOL:
        self.raw = to_raw(value)
        return True


class PressureSensor(ScaledChannel):
    """``FUNCTION_BLOCK FB_PressureSensor EXTENDS FB_ScaledChannel``: read-only; it promises no ``write``."""

    raw_in: INT = VAR_INPUT(0)

    def body(self) -> None:
        self.raw = self.raw_in


class SetpointRamp(FunctionBlock):
    """``FUNCTION_BLOCK FB_SetpointRamp``: ramps an ``I_Actuator`` (and nothing else) to ``target``."""

    output: IActuator = VAR_INPUT()
    target: REAL = VAR_INPUT(0.0)
    step: REAL = VAR_INPUT(12.5)
    timeout: TIME = VAR_INPUT(T("2s"))
    done: BOOL = VAR_OUTPUT(False)
    timed_out: BOOL = VAR_OUTPUT(False)
    watchdog: TON = VAR()

    def body(self) -> None:
        target = clamp(self.target)
        current = self.output.value
        if abs(current - target) > LSB:
            self.output.write(ramp(current, target, self.step))
        self.done = abs(self.output.value - target) <= LSB
        self.watchdog(IN=not self.done, PT=self.timeout)
        self.timed_out = self.watchdog.Q


class ValueMonitor(FunctionBlock):
    """``FUNCTION_BLOCK FB_ValueMonitor``: shows any ``I_AnalogValue`` and flags it above ``high_limit``."""

    signal: IAnalogValue = VAR_INPUT()
    high_limit: REAL = VAR_INPUT(90.0)
    shown: REAL = VAR_OUTPUT(0.0)
    high: BOOL = VAR_OUTPUT(False)

    def body(self) -> None:
        self.shown = self.signal.value
        self.high = self.shown > self.high_limit


class LspCell(Program):
    """``PROGRAM PRG_LspCell``: the same ramp request to an output and to a transmitter, in both designs."""

    target: REAL = VAR_INPUT(75.0)
    pressure_raw: INT = VAR_INPUT(13600)
    actuator: AnalogActuator = VAR()
    sensor_on_base: PressureSensorAsActuator = VAR()
    ramp_actuator: RampOnActuator = VAR()
    ramp_sensor: RampOnActuator = VAR()
    output: AnalogOutput = VAR()
    sensor: PressureSensor = VAR()
    output_ramp: SetpointRamp = VAR()
    monitor_output: ValueMonitor = VAR()
    monitor_sensor: ValueMonitor = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
        self.output_ramp.output = self.output
        self.monitor_output.signal = self.output
        self.monitor_sensor.signal = self.sensor
        return True

    def body(self) -> None:
        self.sensor_on_base(raw_in=self.pressure_raw)
        self.sensor(raw_in=self.pressure_raw)
        self.ramp_actuator(output=self.actuator, target=self.target)
        self.ramp_sensor(output=self.sensor_on_base, target=self.target)
        self.output_ramp(target=self.target)
        self.monitor_output()
        self.monitor_sensor()


def main() -> None:
    """Ask for 75 % from an output and from a transmitter in both designs, for 2.5 s of PLC time.

    >>> main()
    violating  ramp on FB_AnalogActuator  done at t=50 ms, value 75.0 %
    violating  ramp on FB_PressureSensor  timed out at t=2000 ms, value 42.5 %, 250 writes refused
    compliant  FB_PressureSensor as I_Actuator: __QUERYINTERFACE -> None
    compliant  ramp on FB_AnalogOutput    done at t=50 ms, value 75.0 %
    compliant  monitors (I_AnalogValue): output 75.0 %, sensor 42.5 %
    """
    cell = LspCell()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), cell)
    seen: dict[str, int] = {}
    for _ in range(250):
        for name, flag in (
            ("actuator done", cell.ramp_actuator.done),
            ("sensor timed out", cell.ramp_sensor.timed_out),
            ("output done", cell.output_ramp.done),
        ):
            if flag and name not in seen:
                seen[name] = rt.time_ms - 10
        rt.run(cycles=1)
    print(
        f"violating  ramp on FB_AnalogActuator  done at t={seen['actuator done']} ms, "
        f"value {cell.actuator.value:.1f} %"
    )
    print(
        f"violating  ramp on FB_PressureSensor  timed out at t={seen['sensor timed out']} ms, "
        f"value {cell.sensor_on_base.value:.1f} %, {cell.sensor_on_base.refused} writes refused"
    )
    print(f"compliant  FB_PressureSensor as I_Actuator: __QUERYINTERFACE -> {query_interface(cell.sensor, IActuator)}")
    print(f"compliant  ramp on FB_AnalogOutput    done at t={seen['output done']} ms, value {cell.output.value:.1f} %")
    print(
        f"compliant  monitors (I_AnalogValue): output {cell.monitor_output.shown:.1f} %, "
        f"sensor {cell.monitor_sensor.shown:.1f} %"
    )


SHOWCASE = Showcase(
    use_when="a derived block must work wherever its base does: never extend a base whose promises it cannot keep",
    columns=(
        Column("actuator %", lambda p: p.actuator.value, ".1f", watch=False),
        Column("sensor-as-actuator %", lambda p: p.sensor_on_base.value, ".1f"),
        Column("timed out", lambda p: p.ramp_sensor.timed_out),
        Column("refused", lambda p: p.sensor_on_base.refused, watch=False),
        Column("output %", lambda p: p.output.value, ".1f", watch=False),
        Column("done", lambda p: p.output_ramp.done),
    ),
    cycles=250,
    tour_cycles=250,
)
