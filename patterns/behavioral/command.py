"""Command: HMI buttons on a dosing skid, with a bounded undo history, macros and an audit trail.

Intent
------

Turn each operator request ("open the inlet valve", "pump to 60 %", "start
the mixer") into an object with ``execute`` and ``undo``, so the HMI panel can
trigger, queue, group, log and take back requests without knowing which
device each one drives.

The PLC problem
---------------

A dosing skid has an inlet valve ``XV101``, a dosing pump ``P201`` and a
mixer ``M301``. The operator panel has one button per request and an UNDO
button. Each button is a BOOL the HMI holds TRUE for as long as the finger is
on the screen, so every request must fire on the rising edge only (one
``R_TRIG`` per button). The operator may undo the last requests in reverse
order, a "prime skid" button runs several requests as one step and is undone
as one step, and every executed, undone or refused request is written to an
audit trail with the task-clock time. Nothing the operator does faults the
PLC: a request that cannot run (its device is gone, a macro would not fit
the undo record) answers FALSE, changes nothing and is logged as REFUSED.

The undo history is a ring buffer of ``HISTORY_DEPTH`` entries: when it is full
the **oldest entry is dropped** (and the drop is written to the audit trail),
so the newest requests can always be undone. Each history entry stores the
command and an ``UndoRecord``: the states the command replaced, pushed by
``execute`` and popped by ``undo`` like a small stack. Because the undo data
lives in the history and not in the command, one command may be pressed many
times, or used by a button and a macro, and every press is undone correctly.

Roles
-----

- Command → ``ICommand`` (``I_Command``): ``execute`` / ``undo`` with the
  entry's ``UndoRecord`` (``ST_UndoRecord``), ``name`` and ``undo_steps``;
  a refusal answers FALSE and names its reason (``CommandError``,
  ``E_CommandError``) in the command's ``error`` output.
- Concrete commands → ``OpenValveCommand`` (``FB_OpenValveCommand``),
  ``SetPumpSpeedCommand`` (``FB_SetPumpSpeedCommand``),
  ``StartMixerCommand`` (``FB_StartMixerCommand``), on the abstract base
  ``ReceiverCommand`` (``FB_ReceiverCommand``).
- Macro command → ``MacroCommand`` (``FB_MacroCommand``): a bounded list of
  commands, executed in order and undone in reverse order.
- Receivers → ``DosingValve`` (``FB_DosingValve``), ``DosingPump``
  (``FB_DosingPump``), ``Mixer`` (``FB_Mixer``), held by the commands as
  ``REFERENCE TO`` and injected at FB_init.
- Invoker → ``CommandPanel`` (``FB_CommandPanel``) with its
  ``CommandHistory`` (``FB_CommandHistory``) and ``AuditTrail``
  (``FB_AuditTrail``).
- Client → ``DosingSkid`` (``PRG_DosingSkid``): creates the receivers and the
  commands and assigns the commands to the buttons.

IEC 61131-3 mapping
-------------------

::

    INTERFACE I_Command
        PROPERTY Name : STRING(24)
        PROPERTY UndoSteps : INT
        METHOD Execute : BOOL   VAR_IN_OUT record : ST_UndoRecord; END_VAR
        METHOD Undo    : BOOL   VAR_IN_OUT record : ST_UndoRecord; END_VAR
        // FALSE: refused, nothing changed; the command's eError says why

    FUNCTION_BLOCK ABSTRACT FB_ReceiverCommand IMPLEMENTS I_Command
        VAR_OUTPUT eError : E_CommandError; END_VAR
        METHOD PROTECTED ABSTRACT HasReceiver : BOOL   // __ISVALIDREF(rValve)
        METHOD PROTECTED CanExecute : BOOL
        METHOD PROTECTED PushStep   VAR_INPUT bFlag : BOOL; rValue : REAL; END_VAR
        METHOD PROTECTED PopStep : ST_UndoStep

    FUNCTION_BLOCK FB_OpenValveCommand EXTENDS FB_ReceiverCommand
        VAR rValve : REFERENCE TO FB_DosingValve; END_VAR
        METHOD FB_init : BOOL
        VAR_INPUT bInitRetains, bInCopyCode : BOOL;
                  rValve : REFERENCE TO FB_DosingValve; END_VAR

    FUNCTION_BLOCK FB_MacroCommand IMPLEMENTS I_Command
        VAR aCommands : ARRAY[1..MACRO_CAPACITY] OF I_Command;
            nCount : INT; bBusy : BOOL; END_VAR
        VAR_OUTPUT eError : E_CommandError; END_VAR
        METHOD Add : BOOL   VAR_INPUT iCommand : I_Command; END_VAR

    FUNCTION_BLOCK FB_CommandHistory
        VAR aEntries : ARRAY[1..HISTORY_DEPTH] OF I_Command;
            aRecords : ARRAY[1..HISTORY_DEPTH] OF ST_UndoRecord;
            nTop, nCount : INT; END_VAR
        METHOD Execute  : BOOL  VAR_INPUT iCommand : I_Command; END_VAR
        METHOD UndoLast : BOOL

    FUNCTION_BLOCK FB_CommandPanel
        VAR_INPUT aButtons : ARRAY[1..BUTTONS] OF BOOL; bUndo : BOOL; END_VAR
        VAR aEdges : ARRAY[1..BUTTONS] OF R_TRIG;
            aCommands : ARRAY[1..BUTTONS] OF I_Command;
            fbHistory : FB_CommandHistory; fbAudit : FB_AuditTrail; END_VAR
        METHOD Assign : BOOL   VAR_INPUT nButton : INT; iCommand : I_Command; END_VAR

When not to use it on a PLC
---------------------------

When a button only ever does one thing and nothing is undone or logged, a
plain ``IF R_TRIG.Q THEN valve.Open(); END_IF`` is clearer. Undo is an
operator convenience, never a safety function: interlocks and emergency stops
act on the devices directly and are never routed through a command history
that the operator can roll back. Undo also cannot give back what the process
did meanwhile (the litres already dosed stay dosed).

References
----------

- Gamma, Helm, Johnson, Vlissides: *Design Patterns*, Addison-Wesley 1994,
  "Command" (and "Composite" for the macro).
- IEC 61131-3:2013 (3rd edition), object-oriented extensions: interfaces,
  methods, properties, ``REFERENCE TO``; standard function block ``R_TRIG``.
- Beckhoff InfoSys, TwinCAT 3 PLC: "Interface", "REFERENCE", "FB_init,
  FB_reinit, FB_exit", "R_TRIG".
- CODESYS Online Help: "Object: Interface", "Reference", "Method FB_Init,
  FB_Reinit, FB_Exit".
"""

from __future__ import annotations

from typing import Any

from iecoop import (
    ABSTRACT,
    ARRAY,
    BOOL,
    DINT,
    INT,
    NULL,
    PROTECTED,
    REAL,
    REFERENCE_TO,
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
    Struct,
    T,
    is_valid_ref,
    method,
    prop,
    ref_assign,
)
from iecoop.conversions import LREAL_TO_DINT
from iecoop.functions import CONCAT
from iecoop.runtime import Runtime, Task, now_ms
from iecoop.stdlib import R_TRIG
from patterns.showcase.entry import Column, Showcase, steps

__all__ = [
    "AUDIT_DEPTH",
    "BUTTONS",
    "HISTORY_DEPTH",
    "MACRO_CAPACITY",
    "UNDO_STEPS",
    "AuditAction",
    "AuditEntry",
    "AuditTrail",
    "CommandError",
    "CommandHistory",
    "CommandPanel",
    "DosingPump",
    "DosingSkid",
    "DosingValve",
    "ICommand",
    "MacroCommand",
    "Mixer",
    "OpenValveCommand",
    "ReceiverCommand",
    "SetPumpSpeedCommand",
    "StartMixerCommand",
    "UndoRecord",
    "UndoStep",
    "main",
    "skid_state",
    "speed_text",
]

#: Entries the undo history keeps; the oldest is dropped when a new one arrives.
HISTORY_DEPTH = 8
#: Undo steps one history entry can hold (a leaf command uses one).
UNDO_STEPS = 6
#: Commands one macro can hold.
MACRO_CAPACITY = 4
#: Entries the audit trail keeps (a ring: the oldest is overwritten).
AUDIT_DEPTH = 16
#: Command buttons on the panel (the UNDO button comes on top).
BUTTONS = 4


# ---------------------------------------------------------------------------
# Receivers: the skid's devices
# ---------------------------------------------------------------------------


class DosingValve(FunctionBlock):
    """An on/off inlet valve. ST: ``FUNCTION_BLOCK FB_DosingValve``."""

    tag: STRING = VAR("XV", length=12)
    open_cmd: BOOL = VAR_OUTPUT(False)

    def fb_init(self, init_retains: bool, in_copy_code: bool, tag: STRING = "XV") -> None:
        self.tag = tag

    @prop
    def is_open(self) -> BOOL:
        return self.open_cmd

    @method
    def open(self) -> None:
        self.open_cmd = True

    @method
    def close(self) -> None:
        self.open_cmd = False


class DosingPump(FunctionBlock):
    """A speed-controlled dosing pump, setpoint 0..100 %. ST: ``FUNCTION_BLOCK FB_DosingPump``."""

    tag: STRING = VAR("P", length=12)
    speed_setpoint: REAL = VAR_OUTPUT(0.0)

    def fb_init(self, init_retains: bool, in_copy_code: bool, tag: STRING = "P") -> None:
        self.tag = tag

    @prop
    def speed(self) -> REAL:
        return self.speed_setpoint

    @method
    def set_speed(self, percent: REAL) -> None:
        self.speed_setpoint = max(0.0, min(100.0, percent))


class Mixer(FunctionBlock):
    """The tank mixer. ST: ``FUNCTION_BLOCK FB_Mixer``."""

    tag: STRING = VAR("M", length=12)
    run_cmd: BOOL = VAR_OUTPUT(False)

    def fb_init(self, init_retains: bool, in_copy_code: bool, tag: STRING = "M") -> None:
        self.tag = tag

    @prop
    def running(self) -> BOOL:
        return self.run_cmd

    @method
    def start(self) -> None:
        self.run_cmd = True

    @method
    def stop(self) -> None:
        self.run_cmd = False


# ---------------------------------------------------------------------------
# Command: the interface and the undo data
# ---------------------------------------------------------------------------


class UndoStep(Struct):
    """One state a command replaced. ST: ``TYPE ST_UndoStep : STRUCT``."""

    flag: BOOL = False
    value: REAL = 0.0


class UndoRecord(Struct):
    """The undo data of one history entry, used as a stack. ST: ``TYPE ST_UndoRecord : STRUCT``."""

    used: INT = 0
    steps: ARRAY[UndoStep] = VAR(bounds=(1, UNDO_STEPS))


class CommandError(IecEnum):
    """Why a command, a macro or the panel said FALSE. ST: ``TYPE E_CommandError : (...) INT``."""

    NONE = 0
    NO_RECEIVER = 1        # not injected, or deleted since
    RECORD_FULL = 2        # the undo record has no room for the steps
    NOTHING_TO_UNDO = 3    # undo without a matching execute
    NULL_COMMAND = 4
    MACRO_FULL = 5         # MACRO_CAPACITY commands already
    TOO_MANY_STEPS = 6     # more undo steps than one history entry holds
    CONTAINS_ITSELF = 7    # directly or through another macro
    STEP_REFUSED = 8       # a command of the macro refused; the ones before were taken back
    NO_BUTTON = 9          # a button number outside 1..BUTTONS


def speed_text(percent: REAL) -> STRING:
    """``FUNCTION F_SpeedText : STRING``: a speed to a tenth, without a trailing ``.0`` (``'60'``, ``'12.5'``)."""
    # On the magnitude: ST's / and MOD truncate toward zero where Python's // and % floor.
    tenths: DINT = LREAL_TO_DINT(abs(percent) * 10.0)
    text: STRING = f"{tenths // 10}"
    if tenths % 10 != 0:
        text = f"{tenths // 10}.{tenths % 10}"
    if percent < 0.0 and tenths > 0:
        return CONCAT("-", text)
    return text


class ICommand(Interface):
    """An operator request that can be executed and undone. ST: ``INTERFACE I_Command``.

    ``execute`` and ``undo`` answer FALSE when they refuse, having changed
    nothing; the command's ``error`` output says why.
    """

    @prop
    def name(self) -> STRING:
        raise NotImplementedError

    @prop
    def undo_steps(self) -> INT:
        raise NotImplementedError

    @method
    def execute(self, record: UndoRecord) -> BOOL:
        raise NotImplementedError

    @method
    def undo(self, record: UndoRecord) -> BOOL:
        raise NotImplementedError


class ReceiverCommand(FunctionBlock, ICommand, abstract=True):
    """A command acting on one receiver; it pushes one undo step.

    ST: ``FUNCTION_BLOCK ABSTRACT FB_ReceiverCommand IMPLEMENTS I_Command``.
    ``can_execute`` / ``can_undo`` check the receiver (``__ISVALIDREF``) and
    the record before anything is touched; a refusal leaves its reason in
    ``error``.
    """

    error: CommandError = VAR_OUTPUT(CommandError.NONE)

    @prop
    def undo_steps(self) -> INT:
        return 1

    @method(PROTECTED | ABSTRACT)
    def has_receiver(self) -> BOOL:
        """TRUE while the receiver is injected and alive."""
        raise NotImplementedError

    @method(PROTECTED)
    def can_execute(self, record: UndoRecord) -> BOOL:
        if not self.has_receiver():
            self.error = CommandError.NO_RECEIVER
        elif record.used >= UNDO_STEPS:
            self.error = CommandError.RECORD_FULL
        else:
            self.error = CommandError.NONE
        return self.error == CommandError.NONE

    @method(PROTECTED)
    def can_undo(self, record: UndoRecord) -> BOOL:
        if not self.has_receiver():
            self.error = CommandError.NO_RECEIVER
        elif record.used <= 0:
            self.error = CommandError.NOTHING_TO_UNDO
        else:
            self.error = CommandError.NONE
        return self.error == CommandError.NONE

    @method(PROTECTED)
    def push_step(self, record: UndoRecord, flag: BOOL, value: REAL) -> None:
        """Keep the replaced state; past ``UNDO_STEPS`` the index faults (``can_execute`` checks first)."""
        record.steps[record.used + 1].flag = flag
        record.steps[record.used + 1].value = value
        record.used += 1

    @method(PROTECTED)
    def pop_step(self, record: UndoRecord) -> UndoStep:
        step: UndoStep = record.steps[record.used]
        record.used -= 1
        return step


class OpenValveCommand(ReceiverCommand):
    """Open the valve; undo closes it again if it was closed. ST: ``FB_OpenValveCommand``."""

    valve: REFERENCE_TO[DosingValve] = VAR()

    def fb_init(self, init_retains: bool, in_copy_code: bool, valve: DosingValve | None = None) -> None:
        if valve is not None:
            self.bind(valve)

    @method
    def bind(self, valve: DosingValve) -> None:
        ref_assign(self, "valve", valve)

    @method(PROTECTED)
    def has_receiver(self) -> BOOL:
        return is_valid_ref(self, "valve")

    @prop
    def name(self) -> STRING:
        if not self.has_receiver():
            return "open valve"
        return f"open {self.valve.tag}"

    @method
    def execute(self, record: UndoRecord) -> BOOL:
        if not self.can_execute(record):
            return False
        self.push_step(record, self.valve.is_open, 0.0)
        self.valve.open()
        return True

    @method
    def undo(self, record: UndoRecord) -> BOOL:
        if not self.can_undo(record):
            return False
        step: UndoStep = self.pop_step(record)
        if not step.flag:
            self.valve.close()
        return True


class SetPumpSpeedCommand(ReceiverCommand):
    """Set the pump to a fixed speed; undo restores the previous speed. ST: ``FB_SetPumpSpeedCommand``."""

    pump: REFERENCE_TO[DosingPump] = VAR()
    speed: REAL = VAR(0.0)

    def fb_init(
        self, init_retains: bool, in_copy_code: bool, pump: DosingPump | None = None, speed: REAL = 0.0
    ) -> None:
        self.speed = speed
        if pump is not None:
            self.bind(pump)

    @method
    def bind(self, pump: DosingPump) -> None:
        ref_assign(self, "pump", pump)

    @method(PROTECTED)
    def has_receiver(self) -> BOOL:
        return is_valid_ref(self, "pump")

    @prop
    def name(self) -> STRING:
        if not self.has_receiver():
            return f"pump to {speed_text(self.speed)} %"
        return f"{self.pump.tag} to {speed_text(self.speed)} %"

    @method
    def execute(self, record: UndoRecord) -> BOOL:
        if not self.can_execute(record):
            return False
        self.push_step(record, False, self.pump.speed)
        self.pump.set_speed(self.speed)
        return True

    @method
    def undo(self, record: UndoRecord) -> BOOL:
        if not self.can_undo(record):
            return False
        step: UndoStep = self.pop_step(record)
        self.pump.set_speed(step.value)
        return True


class StartMixerCommand(ReceiverCommand):
    """Start the mixer; undo stops it again if it was stopped. ST: ``FB_StartMixerCommand``."""

    mixer: REFERENCE_TO[Mixer] = VAR()

    def fb_init(self, init_retains: bool, in_copy_code: bool, mixer: Mixer | None = None) -> None:
        if mixer is not None:
            self.bind(mixer)

    @method
    def bind(self, mixer: Mixer) -> None:
        ref_assign(self, "mixer", mixer)

    @method(PROTECTED)
    def has_receiver(self) -> BOOL:
        return is_valid_ref(self, "mixer")

    @prop
    def name(self) -> STRING:
        if not self.has_receiver():
            return "start mixer"
        return f"start {self.mixer.tag}"

    @method
    def execute(self, record: UndoRecord) -> BOOL:
        if not self.can_execute(record):
            return False
        self.push_step(record, self.mixer.running, 0.0)
        self.mixer.start()
        return True

    @method
    def undo(self, record: UndoRecord) -> BOOL:
        if not self.can_undo(record):
            return False
        step: UndoStep = self.pop_step(record)
        if not step.flag:
            self.mixer.stop()
        return True


class MacroCommand(FunctionBlock, ICommand):
    """Several commands as one: executed in order, undone in reverse order.

    ST: ``FUNCTION_BLOCK FB_MacroCommand IMPLEMENTS I_Command``. A macro may
    hold other macros; ``busy`` marks the macro while it walks its commands,
    so a macro that (through others) contains itself is noticed when it is
    re-entered instead of recursing until the stack overflows. ``add``
    refuses such a link; ``execute`` is all or nothing: when one command
    refuses, the ones before it are taken back.
    """

    label: STRING = VAR("macro", length=24)
    children: ARRAY[ICommand] = VAR(bounds=(1, MACRO_CAPACITY))
    count: INT = VAR_OUTPUT(0)
    error: CommandError = VAR_OUTPUT(CommandError.NONE)
    busy: BOOL = VAR(False)
    looped: BOOL = VAR(False)

    def fb_init(self, init_retains: bool, in_copy_code: bool, label: STRING = "macro") -> None:
        self.label = label

    @prop
    def name(self) -> STRING:
        return self.label

    @prop
    def undo_steps(self) -> INT:
        if self.busy:
            # Re-entered while walking its commands: this macro contains itself.
            self.looped = True
            return 0
        self.busy = True
        total: INT = 0
        for i in range(1, self.count + 1):
            total += self.children[i].undo_steps
        self.busy = False
        return total

    @method
    def add(self, command: ICommand) -> BOOL:
        """Append ``command``; FALSE for a null one, a full macro, one that contains this macro, too many undo steps."""
        if not command:
            self.error = CommandError.NULL_COMMAND
            return False
        if self.count >= MACRO_CAPACITY:
            self.error = CommandError.MACRO_FULL
            return False
        needed = self.undo_steps
        self.looped = False
        self.busy = True  # a command that contains this macro re-enters undo_steps and sets looped
        needed += command.undo_steps
        self.busy = False
        if self.looped:
            self.error = CommandError.CONTAINS_ITSELF
            return False
        if needed > UNDO_STEPS:
            self.error = CommandError.TOO_MANY_STEPS
            return False
        self.error = CommandError.NONE
        self.count += 1
        self.children[self.count] = command
        return True

    @method
    def execute(self, record: UndoRecord) -> BOOL:
        if self.busy:
            self.error = CommandError.CONTAINS_ITSELF
            return False
        if record.used + self.undo_steps > UNDO_STEPS:
            self.error = CommandError.RECORD_FULL
            return False
        self.busy = True
        done: INT = 0
        while done < self.count:
            if not self.children[done + 1].execute(record):
                break
            done += 1
        if done < self.count:
            # All or nothing: take back the commands that ran, newest first.
            for i in range(done, 0, -1):
                self.children[i].undo(record)
            self.error = CommandError.STEP_REFUSED
        else:
            self.error = CommandError.NONE
        self.busy = False
        return self.error == CommandError.NONE

    @method
    def undo(self, record: UndoRecord) -> BOOL:
        if self.busy:
            self.error = CommandError.CONTAINS_ITSELF
            return False
        self.busy = True
        self.error = CommandError.NONE
        for i in range(self.count, 0, -1):
            if not self.children[i].undo(record):
                self.error = CommandError.STEP_REFUSED
        self.busy = False
        return self.error == CommandError.NONE


# ---------------------------------------------------------------------------
# Invoker: undo history, audit trail, HMI panel
# ---------------------------------------------------------------------------


class CommandHistory(FunctionBlock):
    """The bounded undo history: a ring of (command, undo record) entries.

    ST: ``FUNCTION_BLOCK FB_CommandHistory``. When all ``HISTORY_DEPTH``
    entries are used, ``execute`` overwrites the oldest one (its undo is
    lost); ``dropped`` counts those losses. ``newest`` and ``oldest`` are
    the null reference while the history is empty.
    """

    entries: ARRAY[ICommand] = VAR(bounds=(1, HISTORY_DEPTH))
    records: ARRAY[UndoRecord] = VAR(bounds=(1, HISTORY_DEPTH))
    scratch: UndoRecord = VAR()
    top: INT = VAR(0)
    count: INT = VAR_OUTPUT(0)
    dropped: UDINT = VAR_OUTPUT(0)

    @prop
    def full(self) -> BOOL:
        return self.count == HISTORY_DEPTH

    @prop
    def newest(self) -> ICommand:
        found: ICommand = NULL
        if self.count > 0:
            found = self.entries[self.top]
        return found

    @prop
    def oldest(self) -> ICommand:
        found: ICommand = NULL
        if self.count > 0:
            # + HISTORY_DEPTH: ST's MOD keeps the sign of a negative operand, Python's % does not.
            found = self.entries[(self.top - self.count + HISTORY_DEPTH) % HISTORY_DEPTH + 1]
        return found

    @method
    def execute(self, command: ICommand) -> BOOL:
        """Execute ``command`` and record it; FALSE, the history unchanged, when the command refuses.

        The command runs on a scratch record first, so a refused command
        leaves no trace in the history.
        """
        self.scratch.used = 0
        if not command.execute(self.scratch):
            return False
        slot = self.top % HISTORY_DEPTH + 1
        self.records[slot] = self.scratch
        self.entries[slot] = command
        self.top = slot
        if self.count == HISTORY_DEPTH:
            self.dropped += 1
        else:
            self.count += 1
        return True

    @method
    def undo_last(self) -> BOOL:
        """Undo the newest entry; FALSE when there is nothing to undo or the command refuses.

        A refused undo (its receiver is gone) leaves the history all the same:
        it could never succeed, and the entries before it stay reachable.
        """
        if self.count == 0:
            return False
        undone = self.entries[self.top].undo(self.records[self.top])
        self.top = (self.top + HISTORY_DEPTH - 2) % HISTORY_DEPTH + 1
        self.count -= 1
        return undone


class AuditAction(IecEnum):
    """What happened to a request. ST: ``TYPE E_AuditAction : (...) INT``."""

    EXECUTED = 1
    UNDONE = 2
    DROPPED = 3
    REFUSED = 4


class AuditEntry(Struct):
    """One audit line. ST: ``TYPE ST_AuditEntry : STRUCT``."""

    stamp: TIME = 0
    outcome: AuditAction = AuditAction.EXECUTED
    command: STRING = VAR("", length=24)


class AuditTrail(FunctionBlock):
    """A bounded log of requests with the task-clock time; the oldest line is overwritten.

    ST: ``FUNCTION_BLOCK FB_AuditTrail``.
    """

    lines: ARRAY[AuditEntry] = VAR(bounds=(1, AUDIT_DEPTH))
    no_line: AuditEntry = VAR()
    newest: INT = VAR(0)
    count: INT = VAR_OUTPUT(0)
    total: UDINT = VAR_OUTPUT(0)

    @method
    def log(self, outcome: AuditAction, command: STRING) -> None:
        self.newest = self.newest % AUDIT_DEPTH + 1
        line = self.lines[self.newest]
        line.stamp, line.outcome, line.command = now_ms(), outcome, command
        self.count = min(self.count + 1, AUDIT_DEPTH)
        self.total += 1

    @method
    def entry(self, index: INT) -> AuditEntry:
        """A copy of line ``index``: 1 is the oldest line kept, ``count`` the newest; an empty line outside them."""
        if not 1 <= index <= self.count:
            return self.no_line
        line: AuditEntry = self.lines[(self.newest - self.count + index - 1 + AUDIT_DEPTH) % AUDIT_DEPTH + 1]
        return line


class CommandPanel(FunctionBlock):
    """The HMI panel: one R_TRIG per button, so a held button executes once.

    ST: ``FUNCTION_BLOCK FB_CommandPanel``. A button without a command, a
    command that refuses and an UNDO with an empty history are refused and
    logged, never a fault. ``assign`` answers FALSE (``error``) for a button
    number outside ``1..BUTTONS`` or a null command.
    """

    buttons: ARRAY[BOOL] = VAR_INPUT(bounds=(1, BUTTONS))
    undo_button: BOOL = VAR_INPUT(False)
    error: CommandError = VAR_OUTPUT(CommandError.NONE)
    edges: ARRAY[R_TRIG] = VAR(bounds=(1, BUTTONS))
    undo_edge: R_TRIG = VAR()
    commands: ARRAY[ICommand] = VAR(bounds=(1, BUTTONS))
    history: CommandHistory = VAR()
    audit: AuditTrail = VAR()

    @method
    def assign(self, button: INT, command: ICommand) -> BOOL:
        if not 1 <= button <= BUTTONS:
            self.error = CommandError.NO_BUTTON
        elif not command:
            self.error = CommandError.NULL_COMMAND
        else:
            self.error = CommandError.NONE
            self.commands[button] = command
        return self.error == CommandError.NONE

    def body(self) -> None:
        for i in range(1, BUTTONS + 1):
            self.edges[i](CLK=self.buttons[i])
            if self.edges[i].Q:
                self.press(i)
        self.undo_edge(CLK=self.undo_button)
        if self.undo_edge.Q:
            self.undo_newest()

    @method(PROTECTED)
    def press(self, button: INT) -> None:
        command = self.commands[button]
        if not command:
            self.audit.log(AuditAction.REFUSED, f"button {button} unassigned")
            return
        dropping = self.history.full
        oldest: STRING = ""
        if dropping:
            oldest = self.history.oldest.name   # read before the new entry overwrites it
        if not self.history.execute(command):
            self.audit.log(AuditAction.REFUSED, command.name)
            return
        if dropping:
            self.audit.log(AuditAction.DROPPED, oldest)
        self.audit.log(AuditAction.EXECUTED, command.name)

    @method(PROTECTED)
    def undo_newest(self) -> None:
        if self.history.count == 0:
            self.audit.log(AuditAction.REFUSED, "undo: history empty")
            return
        name = self.history.newest.name
        if self.history.undo_last():
            self.audit.log(AuditAction.UNDONE, name)
        else:
            self.audit.log(AuditAction.REFUSED, name)


# ---------------------------------------------------------------------------
# Client: the skid program
# ---------------------------------------------------------------------------


class DosingSkid(Program):
    """Devices, commands and panel of the skid. ST: ``PROGRAM PRG_DosingSkid``.

    Buttons: 1 open XV101, 2 P201 to 60 %, 3 start M301, 4 prime skid
    (P201 to 25 %, open XV101, start M301). FB_init of the program binds
    the commands to their sibling devices (in ST:
    ``fbOpenInlet : FB_OpenValveCommand(rValve := fbInlet);``).
    """

    inlet: DosingValve = VAR(fb_init={"tag": "XV101"})
    pump: DosingPump = VAR(fb_init={"tag": "P201"})
    mixer: Mixer = VAR(fb_init={"tag": "M301"})
    open_inlet: OpenValveCommand = VAR()
    pump_60: SetPumpSpeedCommand = VAR(fb_init={"speed": 60.0})
    pump_25: SetPumpSpeedCommand = VAR(fb_init={"speed": 25.0})
    start_mixer: StartMixerCommand = VAR()
    prime: MacroCommand = VAR(fb_init={"label": "prime skid"})
    panel: CommandPanel = VAR()

    def fb_init(self, init_retains: bool, in_copy_code: bool) -> None:
        self.open_inlet.bind(self.inlet)
        self.pump_60.bind(self.pump)
        self.pump_25.bind(self.pump)
        self.start_mixer.bind(self.mixer)
        self.prime.add(self.pump_25)
        self.prime.add(self.open_inlet)
        self.prime.add(self.start_mixer)
        self.panel.assign(1, self.open_inlet)
        self.panel.assign(2, self.pump_60)
        self.panel.assign(3, self.start_mixer)
        self.panel.assign(4, self.prime)

    def body(self) -> None:
        self.panel()


def main() -> None:
    """Press the skid's buttons (each held several cycles), undo four times, print the audit trail.

    >>> main()
    t=  10 ms  EXECUTED  P201 to 60 %
    t=  50 ms  EXECUTED  prime skid
    t=  90 ms  EXECUTED  open XV101
    t= 120 ms  UNDONE    open XV101
    t= 150 ms  UNDONE    prime skid
    t= 180 ms  UNDONE    P201 to 60 %
    t= 210 ms  REFUSED   undo: history empty
    after the buttons: XV101 open=True, P201 25 %, M301 running=True
    after the undos:   XV101 open=False, P201 0 %, M301 running=False
    """
    skid = DosingSkid()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), skid)
    panel = skid.panel
    rt.run(cycles=1)

    def hold(button: int, cycles: int) -> None:
        panel.buttons[button] = True
        rt.run(cycles=cycles)
        panel.buttons[button] = False
        rt.run(cycles=1)

    def undo() -> None:
        panel.undo_button = True
        rt.run(cycles=2)
        panel.undo_button = False
        rt.run(cycles=1)

    hold(2, 3)
    hold(4, 3)
    hold(1, 2)
    pressed = skid_state(skid)
    for _ in range(4):
        undo()
    for i in range(1, panel.audit.count + 1):
        line = panel.audit.entry(i)
        print(f"t={line.stamp:4d} ms  {AuditAction(line.outcome).name:<9} {line.command}")
    print(f"after the buttons: {pressed}")
    print(f"after the undos:   {skid_state(skid)}")


def skid_state(skid: DosingSkid) -> str:
    """The receivers' state in one line, for the HMI status bar."""
    return (
        f"{skid.inlet.tag} open={skid.inlet.is_open}, {skid.pump.tag} {skid.pump.speed:g} %, "
        f"{skid.mixer.tag} running={skid.mixer.running}"
    )


_COMMANDS = [
    *[(c, "panel.buttons[2]", v) for c, v in ((2, True), (5, False))],
    *[(c, "panel.buttons[4]", v) for c, v in ((6, True), (9, False))],
    *[(c, "panel.buttons[1]", v) for c, v in ((10, True), (12, False))],
    *[(c, "panel.undo_button", v) for n in range(4) for c, v in ((13 + 3 * n, True), (15 + 3 * n, False))],
]


def _audit(prog: Any) -> object:
    audit = prog.panel.audit
    if not audit.count:
        return "-"
    line = audit.entry(audit.count)
    return f"{AuditAction(line.outcome).name} {line.command}"


SHOWCASE = Showcase(
    use_when="HMI actions must be logged, queued, combined into macros or undone",
    columns=(
        Column("XV101", lambda p: p.inlet.is_open),
        Column("P201 %", lambda p: p.pump.speed, fmt=".0f"),
        Column("M301", lambda p: p.mixer.running),
        Column("history", lambda p: p.panel.history.count),
        Column("audit", _audit),
    ),
    script=steps(*_COMMANDS),
    cycles=26,
    tour_cycles=26,
    expected=(("REFUSED undo: history empty", "Undo is pressed once more than there are commands to undo"),),
)
