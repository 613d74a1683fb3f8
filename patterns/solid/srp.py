"""Single responsibility: a drive function block kept apart from its HMI text and its event log.

Principle
---------

A class should have one, and only one, reason to change (Robert C. Martin).
Code that changes for different reasons, asked for by different people,
belongs in different classes.

The course example
------------------

The course's employee block held the employee's master data (name, personnel
number, department) *and* the time recording (clock in, clock out, hours
worked). Personnel and payroll change it for different reasons, so the course
splits it into ``FB_Employee`` and ``FB_TimeRecording``.

The PLC problem
---------------

A conveyor drive block starts, ramps and trips a motor. The same block builds
the operator's status line (``'M1 RUN  75.0 %'``) and keeps the last events.
The motor logic changes when the mechanics change; the text changes whenever
the HMI team rewords it. In one block every wording change is an edit, an
online change and a re-test of the motor logic; the text is rebuilt in the
fast motion task every cycle, and the STRING buffers sit in every drive
instance of the plant.

Violating design
----------------

- ``DriveWithHmi`` (``FB_DriveWithHmi``): motor logic, status text, event log
  and their STRING buffers in one block.
- ``ViolatingCell`` (``PRG_ViolatingCell``): calls it in the 10 ms task.

Compliant design
----------------

- ``IDriveStatus`` (``I_DriveStatus``): what an HMI may read;
  ``IDrive`` (``I_Drive``) adds the commands.
- ``Drive`` (``FB_Drive``): the motor logic, nothing else.
- ``DriveEventLog`` (``FB_DriveEventLog``): the last eight state changes, in a
  ring buffer; it runs in the motion task, so it sees every change.
- ``DriveHmiFormatter`` (``FB_DriveHmiFormatter``): the status text, built
  from an ``IDriveStatus`` in the slower HMI task.
- ``MotionMain`` (``PRG_Motion``, 10 ms) and ``HmiMain`` (``PRG_Hmi``, 100 ms).

A new wording is a new formatter: ``Drive`` and ``PRG_Motion`` are not
touched, and an online change replaces only ``PRG_Hmi``.

IEC 61131-3 mapping
-------------------

::

    INTERFACE I_DriveStatus EXTENDS __SYSTEM.IQueryInterface
        PROPERTY State : E_DriveState          (Get)
        PROPERTY Speed : REAL                  (Get)
    INTERFACE I_Drive EXTENDS I_DriveStatus
        METHOD Start : BOOL  VAR_INPUT setpoint : REAL; END_VAR
        METHOD Stop
        METHOD Reset : BOOL

    FUNCTION_BLOCK FB_DriveWithHmi                  // violating
        VAR_INPUT  overload : BOOL; sName : STRING(8); END_VAR
        VAR_OUTPUT qRun : BOOL; speedRef : REAL;
                   sStatus : STRING(40); nFormatted : UDINT; END_VAR
        VAR        aEvents : ARRAY[1..8] OF STRING(40); END_VAR
        METHOD Start : BOOL
        METHOD PROTECTED Compose : STRING(40)

    FUNCTION_BLOCK FB_Drive IMPLEMENTS I_Drive      // compliant
        VAR_INPUT  overload : BOOL; END_VAR
        VAR_OUTPUT qRun : BOOL; speedRef : REAL; END_VAR
    FUNCTION_BLOCK FB_DriveEventLog
        VAR_INPUT  itfSource : I_DriveStatus; END_VAR
        VAR        aEvents : ARRAY[1..8] OF STRING(40); END_VAR
        METHOD Event : STRING(40)  VAR_INPUT age : INT; END_VAR
    FUNCTION_BLOCK FB_DriveHmiFormatter
        VAR_INPUT  itfSource : I_DriveStatus; END_VAR
        VAR_OUTPUT sStatus : STRING(40); END_VAR
        METHOD PROTECTED Compose : STRING(40)

References
----------

- R. C. Martin, *Agile Software Development: Principles, Patterns, and
  Practices*, Prentice Hall, 2002, chapter 8 "SRP".
- IEC 61131-3:2013, 3rd edition: function blocks, methods, properties,
  interfaces, enumerated data types, arrays of STRING.
- Beckhoff InfoSys, TwinCAT 3 PLC: "Object-oriented programming",
  "Online Change".
- CODESYS online help: "Object-oriented programming", "Task configuration".
"""

from __future__ import annotations

from collections.abc import Sequence
from types import ModuleType
from typing import Any

from iecoop import (
    ARRAY,
    BOOL,
    INT,
    PROTECTED,
    REAL,
    STRING,
    UDINT,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    FunctionBlock,
    IecEnum,
    IQueryInterface,
    Program,
    T,
    method,
    prop,
    sizeof,
)
from iecoop.conversions import DINT_TO_REAL, REAL_TO_DINT, REAL_TO_STRING
from iecoop.runtime import Runtime, Task
from iecoop.stdlib import R_TRIG
from patterns.plant import ramp
from patterns.showcase.entry import Column, Scenario, Showcase, plc_task

#: Entries kept by an event log: ``ARRAY[1..MAX_EVENTS] OF STRING(40)``.
MAX_EVENTS = 8


class DriveState(IecEnum):
    """``TYPE E_DriveState : (STOPPED := 0, RUNNING := 1, TRIPPED := 2);``"""

    STOPPED = 0
    RUNNING = 1
    TRIPPED = 2


def tenths(value: REAL) -> STRING:
    """``FUNCTION F_Tenths : STRING``: ``value`` to one decimal, as the HMI shows it ('72.5', '80.0').

    ST has no format specifier: round to tenths as a DINT, back to REAL, and let
    REAL_TO_STRING write the fewest digits that read back ('72.5', not '72.500000').
    """
    return REAL_TO_STRING(DINT_TO_REAL(REAL_TO_DINT(value * 10.0)) / 10.0)


def state_word(state: DriveState) -> STRING:
    """``FUNCTION F_StateWord : STRING``: the four-letter word the operator's status line shows."""
    if state == DriveState.RUNNING:
        return "RUN "
    if state == DriveState.TRIPPED:
        return "TRIP"
    return "STOP"


# ---------------------------------------------------------------------------
# Violating design: one block, three reasons to change
# ---------------------------------------------------------------------------


class DriveWithHmi(FunctionBlock):
    """``FUNCTION_BLOCK FB_DriveWithHmi``: the motor, its HMI text and its event log in one block.

    The text is rebuilt every call, in the motion task, and the STRING
    buffers are part of every drive instance.
    """

    overload: BOOL = VAR_INPUT(False)
    ramp_step: REAL = VAR_INPUT(12.5)
    name: STRING = VAR_INPUT("M1", length=8)
    q_run: BOOL = VAR_OUTPUT(False)
    speed_ref: REAL = VAR_OUTPUT(0.0)
    status_text: STRING = VAR_OUTPUT("", length=40)
    format_count: UDINT = VAR_OUTPUT(0)
    event_total: UDINT = VAR_OUTPUT(0)
    current: DriveState = VAR(DriveState.STOPPED)
    setpoint: REAL = VAR(0.0)
    logged: DriveState = VAR(DriveState.STOPPED)
    events: ARRAY[STRING] = VAR(bounds=(1, MAX_EVENTS), length=40)

    @method
    def start(self, setpoint: REAL) -> BOOL:
        if self.current == DriveState.TRIPPED:
            return False
        self.setpoint = min(max(setpoint, 0.0), 100.0)
        self.current = DriveState.RUNNING
        return True

    @method
    def stop(self) -> None:
        if self.current == DriveState.RUNNING:
            self.current = DriveState.STOPPED

    @method
    def reset(self) -> BOOL:
        if self.current == DriveState.TRIPPED:
            self.current = DriveState.STOPPED  # trips again at the next call while the overload persists
            return True
        return False

    @prop
    def state(self) -> DriveState:
        return self.current

    @method(PROTECTED)
    def compose(self) -> STRING:
        """The HMI wording, owned by the drive: a new wording is a new drive block."""
        return f"{self.name} {state_word(self.current)} {tenths(self.speed_ref)} %"

    @method
    def event(self, age: INT) -> STRING:
        """The event ``age`` changes ago (0 = newest); an empty STRING when fewer changes are kept."""
        if age < 0 or age >= min(self.event_total, MAX_EVENTS):
            return ""
        return self.events[(self.event_total - 1 - age) % MAX_EVENTS + 1]

    def body(self) -> None:
        if self.overload:
            self.current = DriveState.TRIPPED
        if self.current == DriveState.TRIPPED:
            self.speed_ref = 0.0
        elif self.current == DriveState.RUNNING:
            self.speed_ref = ramp(self.speed_ref, self.setpoint, self.ramp_step)
        else:  # stopping: ramp down (no local: sizeof counts the block's variables only)
            self.speed_ref = ramp(self.speed_ref, 0.0, self.ramp_step)
        self.q_run = self.current == DriveState.RUNNING or self.speed_ref > 0.0
        # HMI text and event log: the second and third reasons to change.
        self.status_text = self.compose()
        self.format_count += 1
        if self.current != self.logged:
            self.logged = self.current
            self.events[self.event_total % MAX_EVENTS + 1] = f"{self.name} {self.current.name}"
            self.event_total += 1


class ViolatingCell(Program):
    """``PROGRAM PRG_ViolatingCell`` (10 ms task): buttons and overload contact to ``FB_DriveWithHmi``."""

    start_button: BOOL = VAR_INPUT(False)
    stop_button: BOOL = VAR_INPUT(False)
    reset_button: BOOL = VAR_INPUT(False)
    overload: BOOL = VAR_INPUT(False)
    setpoint: REAL = VAR_INPUT(75.0)
    start_edge: R_TRIG = VAR()
    reset_edge: R_TRIG = VAR()
    drive: DriveWithHmi = VAR()

    def body(self) -> None:
        self.start_edge(CLK=self.start_button)
        self.reset_edge(CLK=self.reset_button)
        if self.reset_edge.Q:
            self.drive.reset()
        if self.start_edge.Q:
            self.drive.start(self.setpoint)
        if self.stop_button:
            self.drive.stop()
        self.drive(overload=self.overload)


# ---------------------------------------------------------------------------
# Compliant design: one block per reason to change
# ---------------------------------------------------------------------------


class IDriveStatus(IQueryInterface):
    """``INTERFACE I_DriveStatus``: what an HMI or a log may read from a drive."""

    @prop
    def state(self) -> DriveState:
        raise NotImplementedError

    @prop
    def speed(self) -> REAL:
        raise NotImplementedError


class IDrive(IDriveStatus):
    """``INTERFACE I_Drive EXTENDS I_DriveStatus``: the commands of a drive."""

    @method
    def start(self, setpoint: REAL) -> BOOL:
        raise NotImplementedError

    @method
    def stop(self) -> None: ...

    @method
    def reset(self) -> BOOL:
        raise NotImplementedError


class Drive(FunctionBlock, IDrive):
    """``FUNCTION_BLOCK FB_Drive IMPLEMENTS I_Drive``: start, ramp, trip, reset; no text at all."""

    overload: BOOL = VAR_INPUT(False)
    ramp_step: REAL = VAR_INPUT(12.5)
    q_run: BOOL = VAR_OUTPUT(False)
    speed_ref: REAL = VAR_OUTPUT(0.0)
    current: DriveState = VAR(DriveState.STOPPED)
    setpoint: REAL = VAR(0.0)

    @method
    def start(self, setpoint: REAL) -> BOOL:
        if self.current == DriveState.TRIPPED:
            return False
        self.setpoint = min(max(setpoint, 0.0), 100.0)
        self.current = DriveState.RUNNING
        return True

    @method
    def stop(self) -> None:
        if self.current == DriveState.RUNNING:
            self.current = DriveState.STOPPED

    @method
    def reset(self) -> BOOL:
        if self.current == DriveState.TRIPPED:
            self.current = DriveState.STOPPED  # trips again at the next call while the overload persists
            return True
        return False

    @prop
    def state(self) -> DriveState:
        return self.current

    @prop
    def speed(self) -> REAL:
        return self.speed_ref

    def body(self) -> None:
        if self.overload:
            self.current = DriveState.TRIPPED
        if self.current == DriveState.TRIPPED:
            self.speed_ref = 0.0
        elif self.current == DriveState.RUNNING:
            self.speed_ref = ramp(self.speed_ref, self.setpoint, self.ramp_step)
        else:  # stopping: ramp down (no local: sizeof counts the block's variables only)
            self.speed_ref = ramp(self.speed_ref, 0.0, self.ramp_step)
        self.q_run = self.current == DriveState.RUNNING or self.speed_ref > 0.0


class DriveEventLog(FunctionBlock):
    """``FUNCTION_BLOCK FB_DriveEventLog``: the last ``MAX_EVENTS`` state changes of an ``I_DriveStatus``.

    Called after the drive in the same task, so no change is missed; the
    oldest entry is overwritten when the ring is full.
    """

    source: IDriveStatus = VAR_INPUT()
    name: STRING = VAR_INPUT("M1", length=8)
    event_total: UDINT = VAR_OUTPUT(0)
    logged: DriveState = VAR(DriveState.STOPPED)
    events: ARRAY[STRING] = VAR(bounds=(1, MAX_EVENTS), length=40)

    @method
    def event(self, age: INT) -> STRING:
        """The event ``age`` changes ago (0 = newest); an empty STRING when fewer changes are kept."""
        if age < 0 or age >= min(self.event_total, MAX_EVENTS):
            return ""
        return self.events[(self.event_total - 1 - age) % MAX_EVENTS + 1]

    def body(self) -> None:
        state = self.source.state
        if state != self.logged:
            self.logged = state
            self.events[self.event_total % MAX_EVENTS + 1] = f"{self.name} {state.name}"
            self.event_total += 1


class DriveHmiFormatter(FunctionBlock):
    """``FUNCTION_BLOCK FB_DriveHmiFormatter``: the operator's status line for an ``I_DriveStatus``.

    A new wording is a block derived from this one that overrides
    ``compose``; the drive does not change.
    """

    source: IDriveStatus = VAR_INPUT()
    name: STRING = VAR_INPUT("M1", length=8)
    status_text: STRING = VAR_OUTPUT("", length=40)
    format_count: UDINT = VAR_OUTPUT(0)

    @method(PROTECTED)
    def compose(self) -> STRING:
        return f"{self.name} {state_word(self.source.state)} {tenths(self.source.speed)} %"

    def body(self) -> None:
        self.status_text = self.compose()
        self.format_count += 1


class MotionMain(Program):
    """``PROGRAM PRG_Motion`` (10 ms task): buttons to ``FB_Drive``, then its event log."""

    start_button: BOOL = VAR_INPUT(False)
    stop_button: BOOL = VAR_INPUT(False)
    reset_button: BOOL = VAR_INPUT(False)
    overload: BOOL = VAR_INPUT(False)
    setpoint: REAL = VAR_INPUT(75.0)
    start_edge: R_TRIG = VAR()
    reset_edge: R_TRIG = VAR()
    drive: Drive = VAR()
    log: DriveEventLog = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
        self.log.source = self.drive
        return True

    def body(self) -> None:
        self.start_edge(CLK=self.start_button)
        self.reset_edge(CLK=self.reset_button)
        if self.reset_edge.Q:
            self.drive.reset()
        if self.start_edge.Q:
            self.drive.start(self.setpoint)
        if self.stop_button:
            self.drive.stop()
        self.drive(overload=self.overload)
        self.log()


class HmiMain(Program):
    """``PROGRAM PRG_Hmi`` (100 ms task): the status line of the drive it is given."""

    drive: IDriveStatus = VAR_INPUT()
    formatter: DriveHmiFormatter = VAR()

    def body(self) -> None:
        self.formatter(source=self.drive)


def main() -> None:
    """Run both designs side by side for 1 s of PLC time and compare them.

    >>> main()
    design     drive block      sizeof  texts built in 1 s  HMI text
    violating  FB_DriveWithHmi   424 B                 100  M1 RUN  75.0 %
    compliant  FB_Drive           32 B                  10  M1 RUN  75.0 %
    events, newest first (the same in both designs):
      M1 RUNNING
      M1 STOPPED
      M1 TRIPPED
      M1 RUNNING
    """
    violating, motion, hmi = ViolatingCell(), MotionMain(), HmiMain()
    hmi.drive = motion.drive
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), violating, motion)
    rt.add_task(Task("HmiTask", interval=T("100ms"), priority=30), hmi)

    def press(**inputs: bool) -> None:
        for cell in (violating, motion):
            for name, value in inputs.items():
                setattr(cell, name, value)

    press(start_button=True)
    rt.run(cycles=30)
    press(start_button=False, overload=True)
    rt.run(cycles=5)
    press(overload=False, reset_button=True)
    rt.run(cycles=5)
    press(reset_button=False, start_button=True)
    rt.run(cycles=60)
    print("design     drive block      sizeof  texts built in 1 s  HMI text")
    fat, formatter = violating.drive, hmi.formatter
    rows = [
        ("violating", "FB_DriveWithHmi", sizeof(DriveWithHmi), fat.format_count, fat.status_text),
        ("compliant", "FB_Drive", sizeof(Drive), formatter.format_count, formatter.status_text),
    ]
    for design, block, size, built, text in rows:
        print(f"{design:<10} {block:<16} {size:4d} B  {built:18d}  {text}")
    shown = range(min(motion.log.event_total, 4))
    same = [violating.drive.event(age) for age in shown] == [motion.log.event(age) for age in shown]
    print(f"events, newest first ({'the same in both designs' if same else 'the designs differ'}):")
    for age in shown:
        print(f"  {motion.log.event(age)}")


def _srp(module: ModuleType, runtime: Runtime) -> Sequence[Any]:
    violating, motion, hmi = module.ViolatingCell(), module.MotionMain(), module.HmiMain()
    hmi.drive = motion.drive
    runtime.add_task(plc_task(), motion, violating)
    runtime.add_task(Task("HmiTask", interval=T("100ms"), priority=30), hmi)
    return [motion, violating, hmi]


def _srp_buttons(scenario: Scenario, cycle: int) -> None:
    plan = {1: {"start_button": True}, 31: {"start_button": False, "overload": True},
            36: {"overload": False, "reset_button": True}, 41: {"reset_button": False, "start_button": True}}
    for name, value in plan.get(cycle, {}).items():
        for cell in scenario.programs[:2]:
            setattr(cell, name, value)


SHOWCASE = Showcase(
    use_when="a block starts mixing control, HMI text and logging: split it so that each part changes for one reason",
    columns=(
        Column("drive", lambda p: p.drive.state),
        Column("speed %", lambda p: p.drive.speed_ref, ".1f", watch=False),
        Column("events", lambda p: p.log.event_total),
        Column("texts: violating", lambda p: p.drive.format_count, watch=False, of=1),
        Column("compliant", lambda p: p.formatter.format_count, watch=False, of=2),
        Column("HMI text", lambda p: p.formatter.status_text, watch=False, of=2),
    ),
    builder=_srp,
    script=_srp_buttons,
    cycles=100,
    tour_cycles=100,
)
