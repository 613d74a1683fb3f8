"""Singleton: one plant-wide event log that every function block writes to.

Intent
------

Ensure a class has only one instance, and provide a global point of access
to it.

The PLC problem
---------------

Every device of a packaging line (conveyors, pumps, valves) records what
happened to it: started, stopped, overload trip. The maintenance HMI wants
one list of those events in time order, not one list per device, so all
devices must write into the same bounded ring buffer, stamped with the task
clock.

A PLC gives the two halves of the Singleton directly. ``VAR_STAT`` makes the
log's storage exist once per class, however many instances are declared:
every ``FB_PlantLog`` is a handle on the one buffer (the *sole instance*).
A global variable list publishes one instance that any POU reaches with
``VAR_EXTERNAL`` (the *global access point*).

The usual criticism holds on a PLC as everywhere else:

- Hidden global state: ``FB_Conveyor``'s inputs and FB_init no longer say
  that it writes to the plant log; only its body does.
- Hard to test: every test, and every program instance, shares one buffer.
  A test must clear it first, and two programs (two lines, two test rigs)
  cannot have separate logs.
- Order of initialisation: a block that logs from its FB_init depends on a
  global that may not be initialised yet; CODESYS and TwinCAT order GVLs by
  compilation unless ``{attribute 'global_init_slot'}`` says otherwise.

So the module shows the injected alternative beside it: ``FB_Pump`` receives
an ``I_Logger`` through FB_init. In production the composition root (the
program) injects the plant log itself; a test injects a fresh
``FB_RingLogger`` and gets a private, empty log.

Roles
-----

- Singleton → ``PlantLog`` (``FB_PlantLog``): its ring buffer is
  ``VAR_STAT``, so every instance is the same log.
- Global access point → ``GVL_PlantEvents`` (``GVL_PlantEvents``), the one
  published instance ``plant_events``.
- Client with a hidden dependency → ``Conveyor`` (``FB_Conveyor``), through
  ``VAR_EXTERNAL``.
- Logger abstraction → ``ILogger`` (``I_Logger``).
- Injectable logger → ``RingLogger`` (``FB_RingLogger``): the same buffer as
  a plain ``VAR``, one per instance.
- Client with an injected dependency → ``Pump`` (``FB_Pump``).
- Composition root → ``LineMain`` (``PROGRAM LineMain``).

IEC 61131-3 mapping
-------------------

::

    TYPE ST_Event : STRUCT
        tStamp : TIME; eSeverity : E_Severity;
        sSource : STRING(10); sText : STRING(30);
    END_STRUCT END_TYPE

    INTERFACE I_Logger
        METHOD Log     VAR_INPUT eSeverity : E_Severity; sSource, sText : STRING; END_VAR
        METHOD Newest : BOOL      VAR_INPUT nAge : UINT; stEvent : REFERENCE TO ST_Event; END_VAR
        PROPERTY Count : UDINT    PROPERTY Held : UINT

    FUNCTION_BLOCK FINAL FB_PlantLog IMPLEMENTS I_Logger
        VAR_STAT stBuffer : ST_LogBuffer; END_VAR     // one buffer per class

    VAR_GLOBAL plant_events : FB_PlantLog; END_VAR      // GVL_PlantEvents

    FUNCTION_BLOCK FB_Conveyor
        VAR_EXTERNAL plant_events : FB_PlantLog; END_VAR

    FUNCTION_BLOCK FINAL FB_RingLogger IMPLEMENTS I_Logger
        VAR stBuffer : ST_LogBuffer; END_VAR           // one buffer per instance

    FUNCTION_BLOCK FB_Pump
        VAR iLogger : I_Logger; END_VAR
        METHOD FB_init : BOOL  VAR_INPUT sTag : STRING; iLogger : I_Logger; END_VAR

When not to use it on a PLC
---------------------------

When the "one" is only one today: a second line, a second test rig or a
simulation beside the real plant all need their own log, and a Singleton
makes that a rewrite. Prefer injecting an interface and let the program
decide that everyone gets the same instance. Keep real singletons for things
that are one by physics (the controller's own clock, its diagnostic buffer).

References
----------

- Gamma, Helm, Johnson, Vlissides: *Design Patterns*, Addison-Wesley 1994,
  "Singleton".
- IEC 61131-3:2013 (3rd ed.), VAR_GLOBAL / VAR_EXTERNAL, FB_init (vendor
  extension), user-defined STRUCTs.
- Beckhoff InfoSys, TwinCAT 3 PLC: "Static variables - VAR_STAT",
  "Global Variable List", "Attribute 'global_init_slot'".
- CODESYS Online Help: "Static Variables - VAR_STAT", "Object: Global
  Variable List", "Methods FB_init, FB_reinit, FB_exit".
"""

from __future__ import annotations

from typing import Any

from iecoop import (
    ARRAY,
    BOOL,
    FINAL,
    REFERENCE_TO,
    STRING,
    TIME,
    UDINT,
    UINT,
    VAR,
    VAR_EXTERNAL,
    VAR_INPUT,
    VAR_OUTPUT,
    VAR_STAT,
    FunctionBlock,
    GlobalVariables,
    IecEnum,
    Interface,
    Program,
    Struct,
    T,
    gvl,
    method,
    prop,
)
from iecoop.runtime import Runtime, Task, now_ms
from iecoop.stdlib import R_TRIG
from patterns.showcase.entry import Column, Scenario, Showcase, flag, steps

__all__ = [
    "CAPACITY",
    "Conveyor",
    "Event",
    "GVL_PlantEvents",
    "ILogger",
    "LineMain",
    "LogBuffer",
    "PlantLog",
    "Pump",
    "RingLogger",
    "Severity",
    "log_copy",
    "log_push",
    "main",
]

#: Events the ring buffer holds; the oldest is overwritten when it is full.
CAPACITY = 8


class Severity(IecEnum):
    """``TYPE E_Severity : (INFO, WARNING, ALARM) INT; END_TYPE``"""

    INFO = 0
    WARNING = 1
    ALARM = 2


class Event(Struct):
    """``TYPE ST_Event : STRUCT tStamp : TIME; eSeverity; sSource : STRING(10); sText : STRING(30); END_STRUCT``"""

    stamp: TIME = 0
    severity: Severity = Severity.INFO
    source: STRING = VAR("", length=10)
    text: STRING = VAR("", length=30)


class LogBuffer(Struct):
    """``TYPE ST_LogBuffer``: ``aEvents : ARRAY[1..CAPACITY] OF ST_Event``, the newest index and counters."""

    events: ARRAY[Event] = VAR(bounds=(1, CAPACITY))
    head: UINT = 0
    held: UINT = 0
    total: UDINT = 0


def log_push(buffer: REFERENCE_TO[LogBuffer], severity: Severity, source: STRING, text: STRING) -> BOOL:
    """``FUNCTION F_LogPush : BOOL``: store one event, stamped with the task clock.

    TRUE when the buffer was full and the oldest event was overwritten.
    """
    overwritten = buffer.held >= CAPACITY
    buffer.head = buffer.head % CAPACITY + 1
    slot = buffer.events[buffer.head]
    slot.stamp = now_ms()
    slot.severity = severity
    slot.source = source
    slot.text = text
    buffer.held = min(buffer.held + 1, CAPACITY)
    buffer.total += 1
    return overwritten


def log_copy(buffer: REFERENCE_TO[LogBuffer], age: UINT, event: REFERENCE_TO[Event]) -> BOOL:
    """``FUNCTION F_LogCopy : BOOL``: copy the event ``age`` places before the newest (0 = newest) into ``event``.

    FALSE, and ``event`` left as it was, when ``age`` is not below the number
    of events held: the caller checks the result, as it would a PLCopen
    block's ``Error``.
    """
    if age >= buffer.held:
        return False
    # head + CAPACITY - 1 - age is never negative: ST's MOD keeps the sign of its left operand, Python's % does not.
    slot = buffer.events[(buffer.head + CAPACITY - 1 - age) % CAPACITY + 1]
    event.stamp = slot.stamp
    event.severity = slot.severity
    event.source = slot.source
    event.text = slot.text
    return True


class ILogger(Interface):
    """``INTERFACE I_Logger``: what a device needs from an event log."""

    @method
    def log(self, severity: Severity, source: STRING, text: STRING) -> None: ...

    @method
    def newest(self, age: UINT, event: REFERENCE_TO[Event]) -> BOOL:
        """Copy the event ``age`` places before the newest (0 = newest); FALSE when there is none."""
        raise NotImplementedError

    @prop
    def count(self) -> UDINT:
        """Events logged since the last clear, including those overwritten."""
        raise NotImplementedError

    @prop
    def held(self) -> UINT:
        """Events the buffer holds now (at most ``CAPACITY``)."""
        raise NotImplementedError


class PlantLog(FunctionBlock, ILogger, final=True):
    """The Singleton: ``FUNCTION_BLOCK FINAL FB_PlantLog IMPLEMENTS I_Logger``.

    The buffer is ``VAR_STAT``, so every instance, wherever it is declared,
    reads and writes the same events. FINAL: a subclass would get its own
    VAR_STAT block and quietly become a second log.
    """

    buffer: LogBuffer = VAR_STAT()

    @method
    def log(self, severity: Severity, source: STRING, text: STRING) -> None:
        log_push(self.buffer, severity, source, text)

    @method
    def newest(self, age: UINT, event: REFERENCE_TO[Event]) -> BOOL:
        return log_copy(self.buffer, age, event)

    @prop
    def count(self) -> UDINT:
        return self.buffer.total

    @prop
    def held(self) -> UINT:
        return self.buffer.held

    @method(FINAL)
    def clear(self) -> None:
        """Empty the shared buffer: what every test of a Singleton must remember to call."""
        self.buffer.head = 0
        self.buffer.held = 0
        self.buffer.total = 0


@gvl
class GVL_PlantEvents(GlobalVariables):
    """``VAR_GLOBAL plant_events : FB_PlantLog; END_VAR``: the global access point."""

    plant_events: PlantLog = VAR()


class RingLogger(FunctionBlock, ILogger, final=True):
    """The injectable log: ``FUNCTION_BLOCK FINAL FB_RingLogger IMPLEMENTS I_Logger``, one buffer per instance."""

    buffer: LogBuffer = VAR()

    @method
    def log(self, severity: Severity, source: STRING, text: STRING) -> None:
        log_push(self.buffer, severity, source, text)

    @method
    def newest(self, age: UINT, event: REFERENCE_TO[Event]) -> BOOL:
        return log_copy(self.buffer, age, event)

    @prop
    def count(self) -> UDINT:
        return self.buffer.total

    @prop
    def held(self) -> UINT:
        return self.buffer.held


class Conveyor(FunctionBlock):
    """A client of the Singleton: ``FUNCTION_BLOCK FB_Conveyor``.

    ST::

        VAR_INPUT bRun, bOverload : BOOL; END_VAR
        VAR_OUTPUT bMotorOn : BOOL; END_VAR
        VAR_EXTERNAL plant_events : FB_PlantLog; END_VAR   // hidden dependency
    """

    run: BOOL = VAR_INPUT(False)
    overload: BOOL = VAR_INPUT(False)
    motor_on: BOOL = VAR_OUTPUT(False)
    tag: STRING = VAR("", length=10)
    plant_events: PlantLog = VAR_EXTERNAL()
    was_on: BOOL = VAR(False)
    trip_edge: R_TRIG = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, tag: STRING = "") -> None:
        self.tag = tag

    def body(self) -> None:
        self.trip_edge(CLK=self.overload)
        if self.trip_edge.Q:
            self.plant_events.log(Severity.ALARM, self.tag, "overload trip")
        self.motor_on = self.run and not self.overload
        # Not F_TRIG: its memory starts FALSE, so it fires in the first cycle and logs a stop that never happened.
        if self.motor_on != self.was_on:
            self.plant_events.log(Severity.INFO, self.tag, "started" if self.motor_on else "stopped")
        self.was_on = self.motor_on


class Pump(FunctionBlock):
    """A client with an injected log: ``FUNCTION_BLOCK FB_Pump``.

    ST::

        VAR_INPUT bRun, bDryRun : BOOL; END_VAR
        VAR_OUTPUT bMotorOn : BOOL; END_VAR
        VAR iLogger : I_Logger; END_VAR
        METHOD FB_init : BOOL
        VAR_INPUT bInitRetains, bInCopyCode : BOOL; sTag : STRING; iLogger : I_Logger; END_VAR

    Everything it depends on is in its FB_init. A pump that was never given a
    logger faults with RTSEXCPT_ACCESS_VIOLATION the first time it logs.
    """

    run: BOOL = VAR_INPUT(False)
    dry_run: BOOL = VAR_INPUT(False)
    motor_on: BOOL = VAR_OUTPUT(False)
    tag: STRING = VAR("", length=10)
    logger_ref: ILogger = VAR()
    was_on: BOOL = VAR(False)
    dry_edge: R_TRIG = VAR()

    def fb_init(
        self, init_retains: BOOL, in_copy_code: BOOL, tag: STRING = "", logger: ILogger | None = None
    ) -> None:
        self.tag = tag
        if logger is not None:
            self.logger_ref = logger

    @prop
    def logger(self) -> ILogger:
        """``PROPERTY Logger : I_Logger``: the Set accessor lets a program rewire it."""
        return self.logger_ref

    @logger.setter
    def logger(self, value: ILogger) -> None:
        self.logger_ref = value

    def body(self) -> None:
        self.dry_edge(CLK=self.dry_run)
        if self.dry_edge.Q:
            self.logger_ref.log(Severity.WARNING, self.tag, "dry running")
        self.motor_on = self.run and not self.dry_run
        # Not F_TRIG: its memory starts FALSE, so it fires in the first cycle and logs a stop that never happened.
        if self.motor_on != self.was_on:
            self.logger_ref.log(Severity.INFO, self.tag, "started" if self.motor_on else "stopped")
        self.was_on = self.motor_on


class LineMain(Program):
    """``PROGRAM LineMain``: two conveyors on the Singleton, one pump given the same log by injection.

    ST::

        VAR
            cv101 : FB_Conveyor(sTag := 'CV101');
            cv102 : FB_Conveyor(sTag := 'CV102');
            p101  : FB_Pump(sTag := 'P101', iLogger := plant_events);
        END_VAR
    """

    cmd_run: BOOL = VAR_INPUT(False)
    overload_cv102: BOOL = VAR_INPUT(False)
    dry_run_p101: BOOL = VAR_INPUT(False)
    cv101: Conveyor = VAR(fb_init={"tag": "CV101"})
    cv102: Conveyor = VAR(fb_init={"tag": "CV102"})
    p101: Pump = VAR(fb_init={"tag": "P101", "logger": GVL_PlantEvents.plant_events})

    def body(self) -> None:
        self.cv101(run=self.cmd_run)
        self.cv102(run=self.cmd_run, overload=self.overload_cv102)
        self.p101(run=self.cmd_run, dry_run=self.dry_run_p101)


def main() -> None:
    """Run the line for 150 ms of PLC time and print the plant log, oldest first.

    >>> main()
    t=   0 ms  INFO     CV101  started
    t=   0 ms  INFO     CV102  started
    t=   0 ms  INFO     P101   started
    t=  50 ms  ALARM    CV102  overload trip
    t=  50 ms  INFO     CV102  stopped
    t=  80 ms  WARNING  P101   dry running
    t=  80 ms  INFO     P101   stopped
    t= 120 ms  INFO     CV101  stopped
    logged 8, held 8 of 8, one log: True
    """
    log = GVL_PlantEvents.plant_events
    log.clear()
    line = LineMain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), line)
    line.cmd_run = True
    rt.run(cycles=5)
    line.overload_cv102 = True
    rt.run(cycles=3)
    line.dry_run_p101 = True
    rt.run(cycles=4)
    line.cmd_run = False
    rt.run(cycles=3)
    event = Event()
    for age in reversed(range(log.held)):
        log.newest(age, event)
        print(f"t={event.stamp:4d} ms  {event.severity.name:<8} {event.source:<6} {event.text}")
    print(f"logged {log.count}, held {log.held} of {CAPACITY}, one log: {PlantLog().count == log.count}")


def _clear_log(scenario: Scenario) -> None:
    GVL_PlantEvents.plant_events.clear()


def _newest_event(prog: Any) -> object:
    event = Event()
    if not GVL_PlantEvents.plant_events.newest(0, event):
        return ""
    return f"{event.source} {event.text}"


SHOWCASE = Showcase(
    use_when="something that is one by physics (the controller's clock, its diagnostic buffer); otherwise inject it",
    columns=(
        Column("CV101", lambda p: p.cv101.motor_on, flag),
        Column("CV102", lambda p: p.cv102.motor_on, flag),
        Column("P101", lambda p: p.p101.motor_on, flag),
        Column("logged", lambda p: GVL_PlantEvents.plant_events.count),
        Column("newest event", _newest_event),
    ),
    setup=_clear_log,
    script=steps((1, "cmd_run", True), (6, "overload_cv102", True), (9, "dry_run_p101", True), (13, "cmd_run", False)),
    cycles=20,
    tour_cycles=20,
)
