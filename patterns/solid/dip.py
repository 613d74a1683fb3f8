"""Dependency inversion: a conveyor controller depends on ``ILamp`` / ``IDrive``, given to it at FB_init.

Principle
---------

High-level modules should not depend on low-level modules; both should depend
on abstractions (Robert C. Martin). The policy owns the interfaces it needs;
the hardware blocks implement them, and someone outside the policy decides
which ones to plug in.

The course example
------------------

The course's device sends its data through ``I_Conexion``: an ``FB_Serial``
or an ``FB_Ethernet`` instance is handed to it in ``FB_init``, and the
device's code never names either of them.

The PLC problem
---------------

A conveyor controller decides when the belt runs and what the stack lamp
shows: start on a start request, stop on a stop request or a jam, lamp steady
while running and blinking on a jam or a drive fault. When the controller
declares its own ``FB_TowerLamp`` and ``FB_ContactorDrive``, that policy is
welded to one lamp and one starter: a conveyor with a frequency converter
needs a copy of the controller, and a test of the policy has to drive the
real contactor supervision and the lamp's blink timer, because no fake can be
put in their place.

Violating design
----------------

- ``ConveyorControllerFixed`` (``FB_ConveyorControllerFixed``): declares
  ``lamp : FB_TowerLamp`` and ``drive : FB_ContactorDrive`` inside.

Compliant design
----------------

- ``ILamp`` (``I_Lamp``) and ``IDrive`` (``I_Drive``): what the policy
  needs, declared beside it.
- ``ConveyorController`` (``FB_ConveyorController``): receives ``itfLamp`` and
  ``itfDrive`` in ``FB_init`` (both required) and uses nothing else.
- ``TowerLamp``, ``ContactorDrive``, ``VfdDrive`` (``FB_TowerLamp``,
  ``FB_ContactorDrive``, ``FB_VfdDrive``): the low-level blocks, which
  implement the interfaces.
- ``DipCell`` (``PRG_DipCell``): the composition root. It owns the lamp
  and the drive, creates the controller with ``__NEW`` in its ``FB_init``
  (passing them in) and deletes it in ``FB_exit``, before its members go.
  In an online change the new instance takes the controller over, and
  ``FB_reinit`` points it at the new instance's lamp and drive.

IEC 61131-3 mapping
-------------------

::

    TYPE E_LampMode : (OFF := 0, STEADY := 1, BLINK := 2); END_TYPE
    INTERFACE I_Lamp EXTENDS __SYSTEM.IQueryInterface
        METHOD SetMode  VAR_INPUT eMode : E_LampMode; END_VAR
        PROPERTY Mode : E_LampMode
    INTERFACE I_Drive EXTENDS __SYSTEM.IQueryInterface
        METHOD Start : BOOL
        METHOD Stop
        METHOD Reset
        PROPERTY Running : BOOL
        PROPERTY Faulted : BOOL

    FUNCTION_BLOCK FB_ConveyorControllerFixed           // violating
        VAR lamp : FB_TowerLamp; drive : FB_ContactorDrive; END_VAR

    FUNCTION_BLOCK FB_ConveyorController                // compliant
        VAR_INPUT bStart, bStop, bReset, bJam : BOOL; END_VAR
        VAR itfLamp : I_Lamp; itfDrive : I_Drive; END_VAR
        METHOD FB_init : BOOL
        VAR_INPUT bInitRetains, bInCopyCode : BOOL; itfLamp : I_Lamp; itfDrive : I_Drive; END_VAR
        METHOD Reconnect  VAR_INPUT itfLamp : I_Lamp; itfDrive : I_Drive; END_VAR
    FUNCTION_BLOCK FB_TowerLamp IMPLEMENTS I_Lamp
    FUNCTION_BLOCK FB_ContactorDrive IMPLEMENTS I_Drive
    FUNCTION_BLOCK FB_VfdDrive IMPLEMENTS I_Drive
        VAR_INPUT wStatus : WORD; END_VAR  VAR_OUTPUT wControl : WORD; END_VAR

    PROGRAM PRG_DipCell
        VAR fbLamp : FB_TowerLamp; fbDrive : FB_ContactorDrive;
            pController : POINTER TO FB_ConveyorController; END_VAR
        // FB_init:   IF NOT bInCopyCode THEN
        //              pController := __NEW(FB_ConveyorController(itfLamp := fbLamp, itfDrive := fbDrive));
        //            END_IF
        // FB_reinit: pController^.Reconnect(fbLamp, fbDrive);
        // FB_exit:   IF NOT bInCopyCode THEN __DELETE(pController); END_IF

References
----------

- R. C. Martin, "The Dependency Inversion Principle", *C++ Report*, 1996;
  *Agile Software Development: Principles, Patterns, and Practices*,
  Prentice Hall, 2002, chapter 11 "DIP".
- IEC 61131-3:2013, 3rd edition: interfaces, function block initialisation,
  enumerated data types. ``FB_init``, ``__NEW`` and ``__DELETE`` are TwinCAT 3
  / CODESYS extensions.
- Beckhoff InfoSys, TwinCAT 3 PLC: "Methods FB_init, FB_reinit and FB_exit",
  "__NEW", "__DELETE".
- CODESYS online help: "Methods FB_Init, FB_Reinit, FB_Exit", "Operator
  __NEW", "Operator __DELETE".
"""

from __future__ import annotations

from typing import Any

from iecoop import (
    BOOL,
    POINTER_TO,
    TIME,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    WORD,
    FunctionBlock,
    IecEnum,
    IQueryInterface,
    Program,
    T,
    delete,
    method,
    new,
    prop,
)
from iecoop.runtime import Runtime, Task
from iecoop.stdlib import R_TRIG, TON
from patterns.showcase.entry import Column, Showcase, flag, steps

#: ``FB_VfdDrive`` control words (a CiA 402 subset): shutdown, enable operation, fault reset.
CW_SHUTDOWN = 0x0006
CW_ENABLE_OPERATION = 0x000F
CW_FAULT_RESET = 0x0080
#: ``FB_VfdDrive`` status word bits: operation enabled, fault.
SW_OPERATION_ENABLED = 0x0004
SW_FAULT = 0x0008


class LampMode(IecEnum):
    """``TYPE E_LampMode : (OFF := 0, STEADY := 1, BLINK := 2);``"""

    OFF = 0
    STEADY = 1
    BLINK = 2


class ILamp(IQueryInterface):
    """``INTERFACE I_Lamp``: the indication the controller asks for, whatever the lamp is."""

    @method
    def set_mode(self, mode: LampMode) -> None: ...

    @prop
    def mode(self) -> LampMode:
        raise NotImplementedError


class IDrive(IQueryInterface):
    """``INTERFACE I_Drive``: what the controller needs from whatever moves the belt."""

    @method
    def start(self) -> BOOL:
        raise NotImplementedError

    @method
    def stop(self) -> None: ...

    @method
    def reset(self) -> None: ...

    @prop
    def running(self) -> BOOL:
        raise NotImplementedError

    @prop
    def faulted(self) -> BOOL:
        raise NotImplementedError


# ---------------------------------------------------------------------------
# Low-level blocks: they implement the controller's interfaces
# ---------------------------------------------------------------------------


class TowerLamp(FunctionBlock, ILamp):
    """``FUNCTION_BLOCK FB_TowerLamp IMPLEMENTS I_Lamp``: one digital output; BLINK toggles every ``blink_time``."""

    blink_time: TIME = VAR_INPUT(T("500ms"))
    q_lamp: BOOL = VAR_OUTPUT(False)
    wanted: LampMode = VAR(LampMode.OFF)
    toggle: TON = VAR()

    @method
    def set_mode(self, mode: LampMode) -> None:
        self.wanted = mode

    @prop
    def mode(self) -> LampMode:
        return self.wanted

    def body(self) -> None:
        if self.wanted == LampMode.BLINK:
            self.toggle(IN=True, PT=self.blink_time)
            if self.toggle.Q:
                self.q_lamp = not self.q_lamp
                self.toggle(IN=False)  # the next half period counts from this toggle
                self.toggle(IN=True, PT=self.blink_time)
        else:
            self.toggle(IN=False)
            self.q_lamp = self.wanted == LampMode.STEADY


class ContactorDrive(FunctionBlock, IDrive):
    """``FUNCTION_BLOCK FB_ContactorDrive IMPLEMENTS I_Drive``: a direct-on-line starter.

    The auxiliary contact must confirm within ``feedback_time``, otherwise the
    drive faults and drops out until ``reset``.
    """

    feedback: BOOL = VAR_INPUT(False)
    feedback_time: TIME = VAR_INPUT(T("300ms"))
    q_contactor: BOOL = VAR_OUTPUT(False)
    fault: BOOL = VAR_OUTPUT(False)
    supervision: TON = VAR()

    @method
    def start(self) -> BOOL:
        if self.fault:
            return False
        self.q_contactor = True
        return True

    @method
    def stop(self) -> None:
        self.q_contactor = False

    @method
    def reset(self) -> None:
        self.fault = False

    @prop
    def running(self) -> BOOL:
        return self.q_contactor and self.feedback

    @prop
    def faulted(self) -> BOOL:
        return self.fault

    def body(self) -> None:
        self.supervision(IN=self.q_contactor != self.feedback, PT=self.feedback_time)
        if self.supervision.Q:
            self.fault = True
            self.q_contactor = False


class VfdDrive(FunctionBlock, IDrive):
    """``FUNCTION_BLOCK FB_VfdDrive IMPLEMENTS I_Drive``: a frequency converter on the fieldbus.

    It speaks control and status words; the controller never sees them.
    """

    status_word: WORD = VAR_INPUT(0)
    control_word: WORD = VAR_OUTPUT(CW_SHUTDOWN)

    @method
    def start(self) -> BOOL:
        if self.status_word & SW_FAULT:
            return False
        self.control_word = CW_ENABLE_OPERATION
        return True

    @method
    def stop(self) -> None:
        self.control_word = CW_SHUTDOWN

    @method
    def reset(self) -> None:
        self.control_word = CW_SHUTDOWN | CW_FAULT_RESET

    @prop
    def running(self) -> BOOL:
        return bool(self.status_word & SW_OPERATION_ENABLED)

    @prop
    def faulted(self) -> BOOL:
        return bool(self.status_word & SW_FAULT)


def lamp_mode(jam: BOOL, faulted: BOOL, running: BOOL) -> LampMode:
    """``FUNCTION F_LampMode : E_LampMode``: the indication rule both controllers apply."""
    if jam or faulted:
        return LampMode.BLINK
    return LampMode.STEADY if running else LampMode.OFF


# ---------------------------------------------------------------------------
# Violating design: the policy declares its hardware
# ---------------------------------------------------------------------------


class ConveyorControllerFixed(FunctionBlock):
    """``FUNCTION_BLOCK FB_ConveyorControllerFixed``: the policy, welded to one lamp and one starter."""

    start_request: BOOL = VAR_INPUT(False)
    stop_request: BOOL = VAR_INPUT(False)
    reset_request: BOOL = VAR_INPUT(False)
    jam: BOOL = VAR_INPUT(False)
    contactor_feedback: BOOL = VAR_INPUT(False)
    lamp: TowerLamp = VAR()
    drive: ContactorDrive = VAR()
    start_edge: R_TRIG = VAR()
    reset_edge: R_TRIG = VAR()
    stopping: BOOL = VAR(False)

    def body(self) -> None:
        self.drive(feedback=self.contactor_feedback)
        self.start_edge(CLK=self.start_request)
        self.reset_edge(CLK=self.reset_request)
        if self.reset_edge.Q:
            self.drive.reset()
        stop = self.stop_request or self.jam  # stop dominates start
        if stop:
            if not self.stopping:
                self.drive.stop()
        elif self.start_edge.Q:
            self.drive.start()
        self.stopping = stop
        mode = lamp_mode(self.jam, self.drive.faulted, self.drive.running)
        if self.lamp.mode != mode:
            self.lamp.set_mode(mode)
        self.lamp()


# ---------------------------------------------------------------------------
# Compliant design: the policy receives its abstractions in FB_init
# ---------------------------------------------------------------------------


class ConveyorController(FunctionBlock):
    """``FUNCTION_BLOCK FB_ConveyorController``: the policy, over ``I_Lamp`` and ``I_Drive`` only.

    Both are required ``FB_init`` inputs: ``ConveyorController(lamp=..., drive=...)``.
    The owner calls the lamp and drive blocks themselves each cycle.
    """

    start_request: BOOL = VAR_INPUT(False)
    stop_request: BOOL = VAR_INPUT(False)
    reset_request: BOOL = VAR_INPUT(False)
    jam: BOOL = VAR_INPUT(False)
    lamp: ILamp = VAR()
    drive: IDrive = VAR()
    start_edge: R_TRIG = VAR()
    reset_edge: R_TRIG = VAR()
    stopping: BOOL = VAR(False)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, lamp: ILamp, drive: IDrive) -> BOOL:
        self.reconnect(lamp, drive)
        return True

    @method
    def reconnect(self, lamp: ILamp, drive: IDrive) -> None:
        """The FB_init injection again, for an owner whose blocks an online change has moved."""
        self.lamp = lamp
        self.drive = drive

    def body(self) -> None:
        self.start_edge(CLK=self.start_request)
        self.reset_edge(CLK=self.reset_request)
        if self.reset_edge.Q:
            self.drive.reset()
        stop = self.stop_request or self.jam  # stop dominates start
        if stop:
            if not self.stopping:
                self.drive.stop()
        elif self.start_edge.Q:
            self.drive.start()
        self.stopping = stop
        mode = lamp_mode(self.jam, self.drive.faulted, self.drive.running)
        if self.lamp.mode != mode:
            self.lamp.set_mode(mode)


class DipCell(Program):
    """``PROGRAM PRG_DipCell``: both designs on the same inputs; the composition root of the compliant one."""

    start_request: BOOL = VAR_INPUT(False)
    stop_request: BOOL = VAR_INPUT(False)
    reset_request: BOOL = VAR_INPUT(False)
    jam: BOOL = VAR_INPUT(False)
    contactor_feedback: BOOL = VAR_INPUT(False)
    fixed: ConveyorControllerFixed = VAR()
    lamp: TowerLamp = VAR()
    drive: ContactorDrive = VAR()
    controller: POINTER_TO[ConveyorController] = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
        if not in_copy_code:  # in an online change the controller is taken over from the old instance
            self.controller = new(ConveyorController, lamp=self.lamp, drive=self.drive)
        return True

    def fb_reinit(self) -> BOOL:
        # After an online change the copied controller still refers to the old instance's lamp and drive.
        self.controller.deref.reconnect(self.lamp, self.drive)
        return True

    def fb_exit(self, in_copy_code: BOOL) -> BOOL:
        if not in_copy_code:
            delete(self.controller)  # before the lamp and drive it refers to are finalised
        return True

    def body(self) -> None:
        self.fixed(
            start_request=self.start_request, stop_request=self.stop_request, reset_request=self.reset_request,
            jam=self.jam, contactor_feedback=self.contactor_feedback,
        )
        # Read the hardware, run the policy, write the outputs: the same order as inside the fixed controller.
        self.drive(feedback=self.contactor_feedback)
        self.controller.deref(
            start_request=self.start_request, stop_request=self.stop_request, reset_request=self.reset_request,
            jam=self.jam,
        )
        self.lamp()


def main() -> None:
    """Start, jam and clear the conveyor in both designs, then give the same controller a frequency converter.

    >>> main()
    t=   0 ms  start  fixed: contactor ON  lamp STEADY   injected: contactor ON  lamp STEADY
    t= 200 ms  jam    fixed: contactor OFF lamp BLINK    injected: contactor OFF lamp BLINK
    t= 800 ms  clear  fixed: contactor OFF lamp OFF      injected: contactor OFF lamp OFF
    TypeError: ConveyorControllerFixed: FB_init has no input 'lamp' (its extra inputs: none)
    ConveyorController(lamp=TowerLamp(), drive=VfdDrive()): control word 16#000F after start
    """
    cell = DipCell()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), cell)

    def show(event: str) -> None:
        fixed = f"contactor {'ON ' if cell.fixed.drive.q_contactor else 'OFF'} lamp {cell.fixed.lamp.mode.name:<6}"
        injected = f"contactor {'ON ' if cell.drive.q_contactor else 'OFF'} lamp {cell.lamp.mode.name}"
        print(f"t={rt.time_ms - 10:4d} ms  {event:<5}  fixed: {fixed}   injected: {injected}".rstrip())

    cell.start_request = cell.contactor_feedback = True  # the auxiliary contact follows at once
    rt.run(cycles=1)
    show("start")
    cell.start_request = False
    rt.run(cycles=19)
    cell.jam = True
    rt.run(cycles=1)
    show("jam")
    cell.contactor_feedback = False
    rt.run(cycles=59)
    cell.jam = False
    rt.run(cycles=1)
    show("clear")
    try:
        ConveyorControllerFixed(lamp=TowerLamp())
    except TypeError as exc:
        print(f"TypeError: {exc}")
    lamp, vfd = TowerLamp(), VfdDrive()
    same_policy = ConveyorController(lamp=lamp, drive=vfd)
    same_policy(start_request=True)
    print(f"ConveyorController(lamp=TowerLamp(), drive=VfdDrive()): control word 16#{vfd.control_word:04X} after start")


def _lamp(value: Any) -> str:
    return str(value.name)


SHOWCASE = Showcase(
    use_when="a controller is to be tested or reused with other devices: it depends on interfaces given at FB_init",
    columns=(
        Column("fixed: contactor", lambda p: p.fixed.drive.q_contactor, flag),
        Column("lamp", lambda p: p.fixed.lamp.mode, _lamp),
        Column("injected: contactor", lambda p: p.drive.q_contactor, flag),
        Column("lamp ", lambda p: p.lamp.mode, _lamp),
        Column("jam", lambda p: p.jam),
    ),
    script=steps((1, "start_request", True), (1, "contactor_feedback", True), (2, "start_request", False),
                 (21, "jam", True), (22, "contactor_feedback", False), (81, "jam", False)),
    cycles=90,
    tour_cycles=90,
)
