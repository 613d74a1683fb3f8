"""Adapter: one drive interface over a Modbus VFD, a PLCopen axis and a DOL motor.

Intent
------

Convert the interface of a class into another interface clients expect.
Adapter lets classes work together that could not otherwise because of
incompatible interfaces.

The PLC problem
---------------

A line has three kinds of motors, each with its own way of being driven:

- a frequency converter on Modbus, commanded by a control WORD and a speed
  reference register and answering with a status WORD, where every flag is
  one bit;
- a servo axis behind PLCopen motion blocks, where each command is an
  Execute edge followed by Busy, then Done (or InVelocity) or Error, several
  cycles later;
- a direct-on-line motor: one contactor coil out, one auxiliary contact and
  one overload relay contact in.

The line sequence only wants "start, stop, set the speed, is it running, is
it faulted". One adapter per device kind turns that into the device's own
protocol, and advances its handshake in a ``Cyclic`` method called every
scan; the sequence talks to an ``ARRAY[1..3] OF I_Drive`` and never learns
which is which. Each device's side is simulated in ``patterns.plant`` (drive
ramps, power stage delays, contactor pull-in), so the handshakes really take
cycles.

The VFD's register map names its flags by mask, so the adapter tests and sets
bits with them: ``has_bit(status_word, SW_FAULT)`` is ST's ``wStatus.3``, and
``control_word | CW_RUN`` sets ``wControl.0`` (``get_bit`` / ``set_bit`` of
``iecoop.functions`` take the bit number instead).

Roles
-----

- Target → ``IDrive`` (``I_Drive``).
- Adaptees → the devices: ``VfdSim`` (``FB_VfdSim``, the Modbus drive's
  registers), ``AxisSim`` with ``MC_Power``, ``MC_MoveVelocity``,
  ``MC_Stop``, ``MC_Reset`` over ``AxisRef`` (``AXIS_REF``), and
  ``ContactorSim`` (``FB_ContactorSim``, the wired contactor).
- Adapters → ``VfdDrive`` (``FB_VfdDrive``), ``AxisDrive``
  (``FB_AxisDrive``), ``ContactorDrive`` (``FB_ContactorDrive``).
- Client → ``DriveLine`` (``PROGRAM DriveLine``).

IEC 61131-3 mapping
-------------------

::

    INTERFACE I_Drive
        METHOD Start    METHOD Stop    METHOD Reset    METHOD Cyclic
        METHOD SetSpeed : BOOL  VAR_INPUT fRpm : REAL; END_VAR
        PROPERTY Running : BOOL    PROPERTY Fault : BOOL
        PROPERTY ActualSpeed : REAL

    FUNCTION_BLOCK FB_VfdDrive IMPLEMENTS I_Drive
        VAR_INPUT  wStatus, wSpeedAct : WORD; END_VAR    // Modbus input registers
        VAR_OUTPUT wControl, wSpeedRef : WORD; END_VAR   // Modbus holding registers
        // Running := wStatus.1;  Fault := wStatus.3;

    FUNCTION_BLOCK FB_AxisDrive IMPLEMENTS I_Drive
        VAR stAxis : AXIS_REF; fbPower : MC_Power; fbMove : MC_MoveVelocity;
            fbStop : MC_Stop; fbReset : MC_Reset; eStep : E_AxisStep; END_VAR

    FUNCTION_BLOCK FB_ContactorDrive IMPLEMENTS I_Drive
        VAR_INPUT  bAuxK1, bOverloadOk : BOOL; END_VAR   // %I*
        VAR_OUTPUT bCoilK1 : BOOL; END_VAR                // %Q*
        VAR tonFeedback : TON; END_VAR

When not to use it on a PLC
---------------------------

When there is one device kind, or when the common interface would have to
hide what matters: a servo's position, a VFD's torque limit. An adapter that
throws away the device's strengths to fit a lowest common denominator makes
the line worse; give such devices a richer interface (``I_Axis EXTENDS
I_Drive``) instead. And no adapter should hide a safety function: safe
torque off stays wired, not behind ``Stop()``.

References
----------

- Gamma, Helm, Johnson, Vlissides: *Design Patterns*, Addison-Wesley 1994,
  "Adapter".
- IEC 61131-3:2013 (3rd ed.), interfaces, methods and properties; bit
  access on ANY_BIT (``wStatus.3``).
- PLCopen: *Function blocks for motion control*, Part 1, version 2.0
  (MC_Power, MC_MoveVelocity, MC_Stop, MC_Reset; the Execute / Busy /
  Done / Error behaviour).
- Beckhoff InfoSys: "Tc2_MC2: MC_Power", "MC_MoveVelocity", "MC_Stop";
  "Bit access to variables".
- CODESYS Online Help: "Bit access in variables", "Object: Interface".
- Modbus Organization: *MODBUS Application Protocol Specification* V1.1b3
  (holding and input registers).
"""

from __future__ import annotations

from typing import Any

from iecoop import (
    ARRAY,
    BOOL,
    LREAL,
    PROTECTED,
    REAL,
    STRING,
    UDINT,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    WORD,
    FunctionBlock,
    IecEnum,
    Interface,
    Program,
    T,
    method,
    prop,
)
from iecoop.runtime import Runtime, Task
from iecoop.stdlib import R_TRIG, TON
from patterns.plant.contactor import ContactorSim
from patterns.plant.motion import (
    ERR_AXIS_NOT_READY,
    ERR_DRIVE_TRIP,
    ERR_VELOCITY_RANGE,
    AxisRef,
    AxisSim,
    MC_MoveVelocity,
    MC_Power,
    MC_Reset,
    MC_Stop,
)
from patterns.plant.vfd import (
    CW_FAULT_RESET,
    CW_RUN,
    RPM_PER_HZ,
    SW_FAULT,
    SW_RUNNING,
    VFD_MAX_RPM,
    VfdSim,
    has_bit,
)
from patterns.showcase.entry import Column, Getter, Showcase, press, steps

__all__ = [
    "AxisDrive",
    "AxisRef",
    "AxisSim",
    "AxisStep",
    "ContactorDrive",
    "ContactorSim",
    "DriveLine",
    "ERR_AXIS_NOT_READY",
    "ERR_DRIVE_TRIP",
    "ERR_VELOCITY_RANGE",
    "IDrive",
    "MC_MoveVelocity",
    "MC_Power",
    "MC_Reset",
    "MC_Stop",
    "VfdDrive",
    "VfdSim",
    "main",
]

# ---------------------------------------------------------------------------
# Register layout of the Modbus VFD: one bit per flag (ST: wControl.0, wStatus.3, ...)
# ---------------------------------------------------------------------------

class IDrive(Interface):
    """``INTERFACE I_Drive``: what the line sequence needs from any motor."""

    @method
    def start(self) -> None: ...

    @method
    def stop(self) -> None: ...

    @method
    def set_speed(self, rpm: REAL) -> BOOL:
        """Accept a speed setpoint; FALSE if this drive cannot run at it."""
        raise NotImplementedError

    @method
    def reset(self) -> None:
        """Acknowledge a fault."""
        ...

    @method
    def cyclic(self) -> None:
        """Advance the device handshake; call once per scan."""
        ...

    @prop
    def running(self) -> BOOL:
        raise NotImplementedError

    @prop
    def fault(self) -> BOOL:
        raise NotImplementedError

    @prop
    def actual_speed(self) -> REAL:
        raise NotImplementedError


# ---------------------------------------------------------------------------
# (a) Modbus VFD: control / status words
# ---------------------------------------------------------------------------


class VfdDrive(FunctionBlock, IDrive):
    """Adapter for the Modbus VFD: ``FUNCTION_BLOCK FB_VfdDrive IMPLEMENTS I_Drive``.

    The program maps the registers every scan: ``status_word`` and
    ``speed_act`` in (input registers 30001-30002), ``control_word`` and
    ``speed_ref`` out (holding registers 40001-40002). A fault drops the run
    command, so a reset never restarts the motor by itself.
    """

    status_word: WORD = VAR_INPUT(0)
    speed_act: WORD = VAR_INPUT(0)
    control_word: WORD = VAR_OUTPUT(0)
    speed_ref: WORD = VAR_OUTPUT(0)
    run_request: BOOL = VAR(False)
    reset_request: BOOL = VAR(False)

    @method
    def start(self) -> None:
        self.run_request = True

    @method
    def stop(self) -> None:
        self.run_request = False

    @method
    def set_speed(self, rpm: REAL) -> BOOL:
        if not 0.0 <= rpm <= VFD_MAX_RPM:
            return False
        self.speed_ref = round(rpm / RPM_PER_HZ * 10.0)  # 0.1 Hz units
        return True

    @method
    def reset(self) -> None:
        self.reset_request = True

    @method
    def cyclic(self) -> None:
        if self.fault:
            self.run_request = False
        word = 0
        if self.run_request:
            word |= CW_RUN  # wControl.0 := TRUE
        if self.reset_request:
            word |= CW_FAULT_RESET  # one scan high: the drive acts on the edge
            self.reset_request = False
        self.control_word = word

    @prop
    def running(self) -> BOOL:
        return has_bit(self.status_word, SW_RUNNING)  # wStatus.1

    @prop
    def fault(self) -> BOOL:
        return has_bit(self.status_word, SW_FAULT)  # wStatus.3

    @prop
    def actual_speed(self) -> REAL:
        return self.speed_act / 10.0 * RPM_PER_HZ


# ---------------------------------------------------------------------------
# (b) PLCopen-style axis: Execute / Busy / Done / Error over several cycles
# ---------------------------------------------------------------------------


class AxisStep(IecEnum):
    """``TYPE E_AxisStep : (IDLE, POWERING, MOVING, STOPPING, FAULTED, RESETTING) INT; END_TYPE``"""

    IDLE = 0
    POWERING = 1
    MOVING = 2
    STOPPING = 3
    FAULTED = 4
    RESETTING = 5


class AxisDrive(FunctionBlock, IDrive):
    """Adapter for a PLCopen axis: ``FUNCTION_BLOCK FB_AxisDrive IMPLEMENTS I_Drive``.

    ``Cyclic`` is a step chain over the motion blocks: power on, move at
    velocity (re-triggered by an Execute edge when the setpoint changes),
    stop, reset. ``axis`` is its ``AXIS_REF``, linked to the axis by the
    program. A handshake that hangs for 1 s is a fault.
    """

    axis: AxisRef = VAR()
    power: MC_Power = VAR()
    move: MC_MoveVelocity = VAR()
    halt: MC_Stop = VAR()
    ack: MC_Reset = VAR()
    step: AxisStep = VAR(AxisStep.IDLE)
    run_request: BOOL = VAR(False)
    reset_request: BOOL = VAR(False)
    setpoint: LREAL = VAR(0.0)
    retrigger: BOOL = VAR(False)
    error_id: UDINT = VAR_OUTPUT(0)
    watchdog: TON = VAR()

    @method
    def start(self) -> None:
        self.run_request = True

    @method
    def stop(self) -> None:
        self.run_request = False

    @method
    def set_speed(self, rpm: REAL) -> BOOL:
        if not 0.0 <= rpm <= self.axis.max_velocity:
            return False
        if rpm != self.setpoint:
            self.setpoint = rpm
            self.retrigger = self.step == AxisStep.MOVING
        return True

    @method
    def reset(self) -> None:
        self.reset_request = True

    @method
    def cyclic(self) -> None:
        if self.step == AxisStep.IDLE and self.run_request:
            self.step = AxisStep.POWERING
        enable = self.step in (AxisStep.POWERING, AxisStep.MOVING, AxisStep.STOPPING)
        self.power(Axis=self.axis, Enable=enable)
        move_execute = halt_execute = ack_execute = False
        if self.step == AxisStep.POWERING:
            if not self.run_request:
                self.step = AxisStep.IDLE
            elif self.power.Status:
                self.step = AxisStep.MOVING
        if self.step == AxisStep.MOVING:
            if not self.run_request:
                self.step = AxisStep.STOPPING
            elif self.retrigger:
                self.retrigger = False  # Execute low for one scan: the next scan is a new edge
            else:
                move_execute = True
        if self.step == AxisStep.STOPPING:
            halt_execute = not self.halt.Done
            if self.halt.Done:
                self.step = AxisStep.IDLE
        if self.step == AxisStep.RESETTING:
            ack_execute = not self.ack.Done
            if self.ack.Done:
                self.step = AxisStep.IDLE
        elif self.step == AxisStep.FAULTED and self.reset_request:
            self.step = AxisStep.RESETTING
            ack_execute = True
        self.reset_request = False
        self.move(Axis=self.axis, Execute=move_execute, Velocity=self.setpoint)
        self.halt(Axis=self.axis, Execute=halt_execute)
        self.ack(Axis=self.axis, Execute=ack_execute)
        self.watchdog(IN=self.step in (AxisStep.POWERING, AxisStep.STOPPING, AxisStep.RESETTING), PT=T("1s"))
        failed = self.move.Error or self.halt.Error or self.power.Error
        if self.watchdog.Q or (failed and self.step != AxisStep.RESETTING):
            self.error_id = self.move.ErrorID or self.halt.ErrorID or self.power.ErrorID or ERR_AXIS_NOT_READY
            self.step = AxisStep.FAULTED
            self.run_request = False
        elif self.step == AxisStep.IDLE:
            self.error_id = 0

    @prop
    def running(self) -> BOOL:
        return self.move.Busy or self.halt.Busy

    @prop
    def fault(self) -> BOOL:
        return self.step == AxisStep.FAULTED

    @prop
    def actual_speed(self) -> REAL:
        return self.axis.act_velocity


# ---------------------------------------------------------------------------
# (c) Direct-on-line motor: a contactor with feedback
# ---------------------------------------------------------------------------


class ContactorDrive(FunctionBlock, IDrive):
    """Adapter for a DOL motor: ``FUNCTION_BLOCK FB_ContactorDrive IMPLEMENTS I_Drive``.

    Fixed speed: ``SetSpeed`` always answers FALSE. The fault latches on an
    overload trip or when the auxiliary contact disagrees with the coil for
    longer than 200 ms.
    """

    aux_k1: BOOL = VAR_INPUT(False)
    overload_ok: BOOL = VAR_INPUT(True)  # NC contact: TRUE = healthy
    coil_k1: BOOL = VAR_OUTPUT(False)
    rated_rpm: REAL = VAR(1450.0, constant=True)
    run_request: BOOL = VAR(False)
    faulted: BOOL = VAR(False)
    reason: STRING = VAR_OUTPUT("", length=30)
    discrepancy: TON = VAR()

    @method
    def start(self) -> None:
        self.run_request = not self.faulted

    @method
    def stop(self) -> None:
        self.run_request = False

    @method
    def set_speed(self, rpm: REAL) -> BOOL:
        return False

    @method
    def reset(self) -> None:
        if self.overload_ok and self.aux_k1 == self.coil_k1:
            self.faulted = False
            self.reason = ""

    @method
    def cyclic(self) -> None:
        self.discrepancy(IN=self.coil_k1 != self.aux_k1, PT=T("200ms"))
        if not self.overload_ok:
            self.trip("overload relay tripped")
        elif self.discrepancy.Q:
            self.trip("contactor feedback missing" if self.coil_k1 else "contactor welded")
        self.coil_k1 = self.run_request and not self.faulted

    @method(PROTECTED)
    def trip(self, reason: STRING) -> None:
        if not self.faulted:
            self.reason = reason
        self.faulted = True
        self.run_request = False

    @prop
    def running(self) -> BOOL:
        return self.aux_k1

    @prop
    def fault(self) -> BOOL:
        return self.faulted

    @prop
    def actual_speed(self) -> REAL:
        return self.rated_rpm if self.aux_k1 else 0.0


# ---------------------------------------------------------------------------
# The client: a line sequence that only knows I_Drive
# ---------------------------------------------------------------------------


class DriveLine(Program):
    """``PROGRAM DriveLine``: three drives behind ``ARRAY[1..3] OF I_Drive``, plus the I/O mapping.

    ST::

        VAR_INPUT bStart, bStop, bReset : BOOL; fSpeed : REAL := 1200; END_VAR
        VAR aDrives : ARRAY[1..3] OF I_Drive; aAccepted : ARRAY[1..3] OF BOOL; END_VAR
        IF rtStart.Q THEN
            FOR i := 1 TO 3 DO aAccepted[i] := aDrives[i].SetSpeed(fSpeed); aDrives[i].Start(); END_FOR
        END_IF
        FOR i := 1 TO 3 DO aDrives[i].Cyclic(); END_FOR
    """

    cmd_start: BOOL = VAR_INPUT(False)
    cmd_stop: BOOL = VAR_INPUT(False)
    cmd_reset: BOOL = VAR_INPUT(False)
    speed: REAL = VAR_INPUT(1200.0)
    vfd: VfdDrive = VAR()
    axis: AxisDrive = VAR()
    dol: ContactorDrive = VAR()
    vfd_sim: VfdSim = VAR()
    axis_sim: AxisSim = VAR()
    dol_sim: ContactorSim = VAR()
    drives: ARRAY[IDrive] = VAR(bounds=(1, 3))
    accepted: ARRAY[BOOL] = VAR(bounds=(1, 3))
    start_edge: R_TRIG = VAR()
    stop_edge: R_TRIG = VAR()
    reset_edge: R_TRIG = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> None:
        self.drives[1] = self.vfd
        self.drives[2] = self.axis
        self.drives[3] = self.dol

    def body(self) -> None:
        # Inputs: the devices' answers from the previous scan (Modbus read, %I).
        self.vfd.status_word = self.vfd_sim.status_word
        self.vfd.speed_act = self.vfd_sim.speed_act
        self.dol.aux_k1 = self.dol_sim.aux
        self.dol.overload_ok = self.dol_sim.overload_ok
        self.start_edge(CLK=self.cmd_start)
        self.stop_edge(CLK=self.cmd_stop)
        self.reset_edge(CLK=self.cmd_reset)
        for i in range(1, 4):
            drive = self.drives[i]
            if self.start_edge.Q:
                self.accepted[i] = drive.set_speed(self.speed)
                drive.start()
            if self.stop_edge.Q:
                drive.stop()
            if self.reset_edge.Q:
                drive.reset()
            drive.cyclic()
        # Outputs and the devices (Modbus write, %Q, the motion kernel).
        self.vfd_sim(control_word=self.vfd.control_word, speed_ref=self.vfd.speed_ref)
        self.axis_sim(Axis=self.axis.axis)
        self.dol_sim(coil=self.dol.coil_k1)

    @prop
    def all_running(self) -> BOOL:
        for i in range(1, 4):
            if not self.drives[i].running:
                return False
        return True

    @prop
    def any_fault(self) -> BOOL:
        for i in range(1, 4):
            if self.drives[i].fault:
                return True
        return False


NAMES = ("VFD", "AXIS", "DOL")


def main() -> None:
    """Drive three different motors through one interface for 1 s of PLC time; print what each reports.

    >>> main()
    t=   0 ms  start at 1200 rpm: VFD accepted, AXIS accepted, DOL refused
    t=  30 ms  DOL   running    1450 rpm
    t=  40 ms  AXIS  running      60 rpm
    t=  60 ms  VFD   running      30 rpm
    t= 500 ms  speeds: VFD 1200, AXIS 1200, DOL 1450
    t= 500 ms  the VFD trips (overcurrent)
    t= 510 ms  VFD   fault         0 rpm
    t= 600 ms  stop all
    t= 610 ms  DOL   stopped       0 rpm
    t= 700 ms  reset all
    t= 710 ms  VFD   stopped       0 rpm
    t= 800 ms  AXIS  stopped       0 rpm
    """
    line = DriveLine()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), line)
    seen = [(False, False)] * 3
    for _ in range(100):
        t = rt.time_ms
        line.cmd_start = t == 0
        line.cmd_stop = t == 600
        line.cmd_reset = t == 700
        line.vfd_sim.trip = t == 500
        rt.run(cycles=1)
        if t == 0:
            verdict = ", ".join(f"{n} {'accepted' if ok else 'refused'}" for n, ok in zip(NAMES, line.accepted))
            print(f"t=   0 ms  start at {line.speed:.0f} rpm: {verdict}")
        if t == 500:
            speeds = ", ".join(f"{n} {line.drives[i].actual_speed:.0f}" for i, n in enumerate(NAMES, 1))
            print(f"t= 500 ms  speeds: {speeds}")
            print("t= 500 ms  the VFD trips (overcurrent)")
        if t in (600, 700):
            print(f"t={t:4d} ms  {'stop' if t == 600 else 'reset'} all")
        for i, name in enumerate(NAMES, 1):
            drive = line.drives[i]
            now = (drive.running, drive.fault)
            if now != seen[i - 1]:
                state = "fault" if drive.fault else "running" if drive.running else "stopped"
                print(f"t={t:4d} ms  {name:<5} {state:<8} {drive.actual_speed:6.0f} rpm")
                seen[i - 1] = now


def _drive_state(index: int) -> Getter:
    def get(prog: Any) -> object:
        drive = prog.drives[index]
        return "fault" if drive.fault else "running" if drive.running else "stopped"

    return get


def _drive_speed(index: int) -> Getter:
    return lambda prog: prog.drives[index].actual_speed


SHOWCASE = Showcase(
    use_when="devices of different makes must look alike to the line without hiding what matters about them",
    columns=(
        Column("VFD", _drive_state(1)), Column("rpm", _drive_speed(1), ".0f", watch=False),
        Column("AXIS", _drive_state(2)), Column("rpm ", _drive_speed(2), ".0f", watch=False),
        Column("DOL", _drive_state(3)), Column(" rpm", _drive_speed(3), ".0f", watch=False),
    ),
    script=steps(*press("cmd_start", 1), *press("vfd_sim.trip", 51), *press("cmd_stop", 61), *press("cmd_reset", 71)),
    cycles=100,
    tour_cycles=100,
    expected=(("VFD fault", "the Modbus drive trips in cycle 51 and is reset in cycle 71"),),
)
