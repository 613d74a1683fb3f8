"""Tc2_MC2 as a hardware double: PLCopen motion blocks driving a simulated NC axis.

A project that calls ``MC_Power``, ``MC_MoveAbsolute``... on an ``AXIS_REF``
runs unchanged against this module: each ``AXIS_REF`` is a simulated NC axis
that moves in the task's virtual time (``current_clock()``), with a
trapezoidal velocity profile (a triangle when the distance is short; jerk is
accepted and not limited) from its parameters, the PLCopen state machine
(Disabled, Standstill, Homing, DiscreteMotion, ContinuousMotion, Stopping,
ErrorStop) and the PLCopen handshakes. Written from Beckhoff's Tc2_MC2
documentation (Infosys "Tc2_MC2") and PLCopen Motion Control Part 1.

ST::

    PROGRAM MAIN
    VAR
        Axis  : AXIS_REF;
        Power : MC_Power;
        Move  : MC_MoveAbsolute;
    END_VAR
    Power(Axis := Axis, Enable := TRUE, Enable_Positive := TRUE, Enable_Negative := TRUE);
    Move(Axis := Axis, Execute := Power.Status, Position := 100, Velocity := 50);

What the simulation does:

* The axis is integrated once per task cycle, at the first MC call (or
  ``Axis.ReadStatus()``) of the cycle, however many blocks are called on it;
  a command given in a cycle starts from the axis' state at that cycle and
  moves it from the next one. The profile is evaluated in closed form, so
  ``NcToPlc.SetPos`` at a cycle is exact.
* The actual position follows the set position exactly (``PosDiff`` 0)
  unless a test injects a position lag (``simulate_position_lag``).
* Faults put the axis in ErrorStop with Beckhoff's NC error codes:
  a target beyond an enabled software limit is refused at the start
  (0x4460 / 0x4461, the axis errors), a set position crossing one during
  motion stops it (0x4462 / 0x4463), a lag beyond the maximum position lag
  stops it at once (0x4550), and ``inject_fault(code)`` raises any code.
* Refused commands set Error / ErrorID on the block with the NC-PLC codes:
  0x4B01 (the axis cannot be started: disabled, in ErrorStop, Stopping or
  Homing), 0x4B04 (invalid Direction at MC_MoveModulo), 0x4B05 (continuous
  motion in an unspecified direction, unknown parameter), 0x4B06 (a
  parameter is not correct: velocity <= 0, override outside 0..100 %).

``Axis.Status`` is refreshed by ``Axis.ReadStatus()`` or ``MC_ReadStatus``,
as on the PLC; ``Axis.NcToPlc`` is refreshed every cycle.
"""

from __future__ import annotations

import functools
import math
from typing import TYPE_CHECKING, Annotated, Any

from iecoop.declarations import VAR, VAR_IN_OUT, VAR_INPUT, VAR_OUTPUT
from iecoop.libraries import _motion
from iecoop.libraries._mc2_axis import (
    _ABORTED, _ACTIVE, _DONE, _HALT, _HOME, _IN_VELOCITY, _MOVE, _PENDING, _STATES, _STOP, _VELOCITY, AXIS_REF,
    ERR_INVALID_MODE, ERR_NOT_PERMITTED, ERR_PARAMETER, NCTOPLC_AXIS_REF, PLCTONC_AXIS_REF, E_JogMode, E_ReadMode,
    MC_AxisParameter, MC_AxisStates, MC_BufferMode, MC_Direction, MC_HomingMode, ST_AxisStatus, ST_MoveOptions,
)
from iecoop.pou import FunctionBlock
from iecoop.memory import Alias, Struct
from iecoop.types import BOOL, LREAL, UDINT, UINT

__all__ = [
    "AXIS_REF", "E_JogMode", "E_ReadMode", "MC_AxisParameter", "MC_AxisStates", "MC_BufferMode", "MC_Direction",
    "MC_GearIn", "MC_GearOut", "MC_Halt", "MC_Home", "MC_HomingMode", "MC_Jog", "MC_LREAL", "MC_MoveAbsolute",
    "MC_MoveModulo", "MC_MoveRelative", "MC_MoveVelocity", "MC_Power", "MC_ReadActualPosition",
    "MC_ReadActualVelocity", "MC_ReadAxisError", "MC_ReadParameter", "MC_ReadStatus", "MC_Reset", "MC_SetPosition",
    "MC_Stop", "NCTOPLC_AXIS_REF", "PLCTONC_AXIS_REF", "ST_AxisStatus", "ST_MoveOptions", "ST_PowerOptions",
]

class ST_PowerOptions(Struct):  # noqa: N801 - Beckhoff's name
    """MC_Power's ``Options`` (one reserved BOOL on the PLC); accepted, not simulated."""

    reserved: BOOL = False


#: ``TYPE MC_LREAL : LREAL; END_TYPE``: the LREAL of the motion blocks' pins.
MC_LREAL = Annotated[LREAL, Alias("MC_LREAL")]

# ---------------------------------------------------------------------------
# The function blocks
# ---------------------------------------------------------------------------


@functools.cache
def _has(cls: type, pin: str) -> bool:
    return hasattr(cls, pin)


class _Handshake(FunctionBlock, abstract=True):
    """The PLCopen output handshake every MC block shares, on the axis its command runs on (``_axis()``)."""

    if TYPE_CHECKING:
        Execute: bool
        Done: bool
        Busy: bool
        Active: bool
        CommandAborted: bool
        InVelocity: bool
        Error: bool
        ErrorID: int
        PrevExecute: bool
        Shown: bool
        CmdNo: int

    def _axis(self) -> AXIS_REF:
        raise NotImplementedError

    def _set(self, pin: str, value: Any) -> None:
        if _has(type(self), pin):
            setattr(self, pin, value)

    def _edge(self, execute: bool) -> bool:
        """Advance the axis, drop outputs shown after Execute fell, and tell whether Execute rose (PLCopen)."""
        self._axis()._sync()
        if not execute and self.Shown and not self.Busy:
            self._clear()
        rising = execute and not self.PrevExecute
        self.PrevExecute = execute
        return rising

    def _clear(self) -> None:
        for pin in ("Done", "CommandAborted", "Error", "InVelocity", "InGear"):
            self._set(pin, False)
        self.ErrorID = 0
        self.Shown = False

    def _done_at_once(self, error: int = 0) -> None:
        """A command that completes at its call (MC_Reset, MC_SetPosition, homing without motion)."""
        self._clear()
        self.CmdNo = 0
        self._set("Busy", False)
        if error:
            self.Error, self.ErrorID = True, error
        else:
            self.Done = True
        self.Shown = True

    def _started(self, cmd: int, error: int) -> None:
        """A rising Execute was answered: command ``cmd`` runs, or ``error`` refused it."""
        self._clear()
        if error:
            self._set("Busy", False)
            self._set("Active", False)
            self.Error, self.ErrorID, self.Shown = True, error, True
            self.CmdNo = 0
            return
        self.CmdNo = cmd
        self._set("Busy", True)
        self._track()

    def _track(self) -> None:
        """Follow the block's command on the axis and set the outputs when it ends."""
        if not self.Busy:
            return
        outcome, code = self._axis()._result(self.CmdNo)
        if outcome in (_ACTIVE, _IN_VELOCITY):
            self._set("Active", True)
            if outcome == _IN_VELOCITY:
                self._set("InVelocity", True)
                self._set("InGear", True)
            return
        if outcome == _PENDING:
            return
        self._set("Busy", False)
        self._set("Active", False)
        self._set("InVelocity", False)
        self._set("InGear", False)
        if outcome == _DONE:
            self._set("Done", True)
        elif outcome == _ABORTED:
            self._set("CommandAborted", True)
        else:
            self.Error, self.ErrorID = True, code
        self.Shown = True


class _AxisBlock(_Handshake, abstract=True):
    """An MC block on one axis: ``Axis : AXIS_REF`` (VAR_IN_OUT)."""

    Axis: AXIS_REF = VAR_IN_OUT()

    def _axis(self) -> AXIS_REF:
        return self.Axis


class _Command(_AxisBlock, abstract=True):
    """An MC block started by a rising edge of Execute."""

    Execute: BOOL = VAR_INPUT(False)
    PrevExecute: BOOL = VAR(False)
    Shown: BOOL = VAR(False)
    CmdNo: UDINT = VAR(0)


class MC_Power(_AxisBlock):  # noqa: N801
    """MC_Power: controller enable of the axis (Disabled <-> Standstill); Status when it is on and healthy.

    ST: ``Power(Axis := Axis, Enable := TRUE, Enable_Positive := TRUE, Enable_Negative := TRUE, Override := 100);``
    """

    Enable: BOOL = VAR_INPUT(False)
    Enable_Positive: BOOL = VAR_INPUT(False)
    Enable_Negative: BOOL = VAR_INPUT(False)
    Override: LREAL = VAR_INPUT(100.0)
    BufferMode: MC_BufferMode = VAR_INPUT(MC_BufferMode.MC_Aborting)
    Options: ST_PowerOptions = VAR_INPUT()
    Status: BOOL = VAR_OUTPUT(False)
    Busy: BOOL = VAR_OUTPUT(False)
    Active: BOOL = VAR_OUTPUT(False)
    Error: BOOL = VAR_OUTPUT(False)
    ErrorID: UDINT = VAR_OUTPUT(0)

    def body(self) -> None:
        axis = self.Axis
        if not 0.0 <= self.Override <= 100.0:
            self.Error, self.ErrorID = True, ERR_PARAMETER
            return
        self.Error, self.ErrorID = False, 0
        control = (1 if self.Enable else 0) | (2 if self.Enable_Positive else 0) | (4 if self.Enable_Negative else 0)
        axis.PlcToNc.ControlDWord = (axis.PlcToNc.ControlDWord & ~7 & 0xFFFF_FFFF) | control
        axis.PlcToNc.Override = round(self.Override * 10_000)
        axis._sync()
        axis._apply_enable()
        axis._publish()
        self.Status = self.Enable and axis.Sim.ErrorId == 0 and axis.Sim.State != _STATES.MC_AXISSTATE_DISABLED
        self.Busy = self.Enable
        self.Active = self.Status


class MC_Reset(_Command):  # noqa: N801
    """MC_Reset: clear the axis error; ErrorStop -> Standstill (or Disabled without controller enable).

    ST: ``Reset(Axis := Axis, Execute := bReset);``
    """

    Done: BOOL = VAR_OUTPUT(False)
    Busy: BOOL = VAR_OUTPUT(False)
    Error: BOOL = VAR_OUTPUT(False)
    ErrorID: UDINT = VAR_OUTPUT(0)

    def body(self) -> None:
        if self._edge(self.Execute):
            self.Axis._reset()
            self._done_at_once()


class MC_SetPosition(_Command):  # noqa: N801
    """MC_SetPosition: the actual position becomes Position (Mode FALSE) or moves by it (Mode TRUE), without motion.

    ST: ``SetPos(Axis := Axis, Execute := TRUE, Position := 0, Mode := FALSE);``
    """

    Position: LREAL = VAR_INPUT(0.0)
    Mode: BOOL = VAR_INPUT(False)
    Done: BOOL = VAR_OUTPUT(False)
    Busy: BOOL = VAR_OUTPUT(False)
    Error: BOOL = VAR_OUTPUT(False)
    ErrorID: UDINT = VAR_OUTPUT(0)

    def body(self) -> None:
        if self._edge(self.Execute):
            if not math.isfinite(self.Position):
                self._done_at_once(ERR_PARAMETER)
                return
            self.Axis._set_position(self.Position, self.Mode)
            self._done_at_once()


class MC_MoveAbsolute(_Command):  # noqa: N801
    """MC_MoveAbsolute: move to Position with at most Velocity (DiscreteMotion); Done on the target.

    ST: ``Move(Axis := Axis, Execute := TRUE, Position := 100.0, Velocity := 50.0);``
    """

    Position: LREAL = VAR_INPUT(0.0)
    Velocity: LREAL = VAR_INPUT(0.0)
    Acceleration: LREAL = VAR_INPUT(0.0)
    Deceleration: LREAL = VAR_INPUT(0.0)
    Jerk: LREAL = VAR_INPUT(0.0)
    BufferMode: MC_BufferMode = VAR_INPUT(MC_BufferMode.MC_Aborting)
    Options: ST_MoveOptions = VAR_INPUT()
    Done: BOOL = VAR_OUTPUT(False)
    Busy: BOOL = VAR_OUTPUT(False)
    Active: BOOL = VAR_OUTPUT(False)
    CommandAborted: BOOL = VAR_OUTPUT(False)
    Error: BOOL = VAR_OUTPUT(False)
    ErrorID: UDINT = VAR_OUTPUT(0)

    def body(self) -> None:
        if self._edge(self.Execute):
            cmd, error = self.Axis._command(
                _MOVE, self.Position, self.Velocity, self.Acceleration, self.Deceleration, self.BufferMode,
            )
            self._started(cmd, error)
        else:
            self._track()


class MC_MoveRelative(_Command):  # noqa: N801
    """MC_MoveRelative: move by Distance from the set position at the start (DiscreteMotion).

    ST: ``Move(Axis := Axis, Execute := TRUE, Distance := 10.0, Velocity := 50.0);``
    """

    Distance: LREAL = VAR_INPUT(0.0)
    Velocity: LREAL = VAR_INPUT(0.0)
    Acceleration: LREAL = VAR_INPUT(0.0)
    Deceleration: LREAL = VAR_INPUT(0.0)
    Jerk: LREAL = VAR_INPUT(0.0)
    BufferMode: MC_BufferMode = VAR_INPUT(MC_BufferMode.MC_Aborting)
    Options: ST_MoveOptions = VAR_INPUT()
    Done: BOOL = VAR_OUTPUT(False)
    Busy: BOOL = VAR_OUTPUT(False)
    Active: BOOL = VAR_OUTPUT(False)
    CommandAborted: BOOL = VAR_OUTPUT(False)
    Error: BOOL = VAR_OUTPUT(False)
    ErrorID: UDINT = VAR_OUTPUT(0)

    def body(self) -> None:
        if self._edge(self.Execute):
            axis = self.Axis
            base = axis.Sim.Target if self._buffered() else axis.NcToPlc.SetPos
            cmd, error = axis._command(
                _MOVE, base + self.Distance, self.Velocity, self.Acceleration, self.Deceleration, self.BufferMode,
            )
            self._started(cmd, error)
        else:
            self._track()

    def _buffered(self) -> bool:
        # A buffered relative move starts where the running one ends.
        sim = self.Axis.Sim
        return self.BufferMode != MC_BufferMode.MC_Aborting and sim.ActiveKind == _MOVE and sim.ActiveCmd != 0


class MC_MoveModulo(_Command):  # noqa: N801
    """MC_MoveModulo: move to the modulo Position (0 <= Position < the axis' modulo factor) in Direction.

    ST: ``Move(Axis := Axis, Execute := TRUE, Position := 90.0, Velocity := 30.0, Direction := MC_Positive_Direction);``
    """

    Position: LREAL = VAR_INPUT(0.0)
    Velocity: LREAL = VAR_INPUT(0.0)
    Acceleration: LREAL = VAR_INPUT(0.0)
    Deceleration: LREAL = VAR_INPUT(0.0)
    Jerk: LREAL = VAR_INPUT(0.0)
    Direction: MC_Direction = VAR_INPUT(MC_Direction.MC_Positive_Direction)
    BufferMode: MC_BufferMode = VAR_INPUT(MC_BufferMode.MC_Aborting)
    Options: ST_MoveOptions = VAR_INPUT()
    Done: BOOL = VAR_OUTPUT(False)
    Busy: BOOL = VAR_OUTPUT(False)
    Active: BOOL = VAR_OUTPUT(False)
    CommandAborted: BOOL = VAR_OUTPUT(False)
    Error: BOOL = VAR_OUTPUT(False)
    ErrorID: UDINT = VAR_OUTPUT(0)

    def body(self) -> None:
        if self._edge(self.Execute):
            target, error = self._target()
            cmd = 0
            if not error:
                cmd, error = self.Axis._command(
                    _MOVE, target, self.Velocity, self.Acceleration, self.Deceleration, self.BufferMode,
                )
            self._started(cmd, error)
        else:
            self._track()

    def _target(self) -> tuple[float, int]:
        axis = self.Axis
        modulo = axis.Parameters.ModuloFactor
        if not 0.0 <= self.Position < modulo:
            return 0.0, ERR_PARAMETER
        direction = self.Direction
        if direction == MC_Direction.MC_Current_Direction:
            direction = (MC_Direction.MC_Negative_Direction if axis.NcToPlc.SetVelo < 0.0
                         else MC_Direction.MC_Positive_Direction)
        if direction not in (
            MC_Direction.MC_Positive_Direction, MC_Direction.MC_Negative_Direction, MC_Direction.MC_Shortest_Way,
        ):
            return 0.0, ERR_INVALID_MODE
        here = axis.NcToPlc.SetPos
        turn = math.floor(here / modulo) * modulo
        ahead = turn + self.Position if turn + self.Position >= here else turn + modulo + self.Position
        behind = ahead - modulo if ahead - modulo <= here else ahead
        if abs(ahead - here) <= _motion.EPSILON or abs(here - behind) <= _motion.EPSILON:
            return here, 0
        if direction == MC_Direction.MC_Positive_Direction:
            return ahead, 0
        if direction == MC_Direction.MC_Negative_Direction:
            return behind, 0
        return (ahead if ahead - here <= here - behind else behind), 0


class MC_MoveVelocity(_Command):  # noqa: N801
    """MC_MoveVelocity: run at Velocity in Direction (ContinuousMotion); InVelocity once reached, until aborted.

    ST: ``Jog(Axis := Axis, Execute := TRUE, Velocity := 20.0, Direction := MC_Positive_Direction);``
    """

    Velocity: LREAL = VAR_INPUT(0.0)
    Acceleration: LREAL = VAR_INPUT(0.0)
    Deceleration: LREAL = VAR_INPUT(0.0)
    Jerk: LREAL = VAR_INPUT(0.0)
    Direction: MC_Direction = VAR_INPUT(MC_Direction.MC_Positive_Direction)
    BufferMode: MC_BufferMode = VAR_INPUT(MC_BufferMode.MC_Aborting)
    Options: ST_MoveOptions = VAR_INPUT()
    InVelocity: BOOL = VAR_OUTPUT(False)
    Busy: BOOL = VAR_OUTPUT(False)
    Active: BOOL = VAR_OUTPUT(False)
    CommandAborted: BOOL = VAR_OUTPUT(False)
    Error: BOOL = VAR_OUTPUT(False)
    ErrorID: UDINT = VAR_OUTPUT(0)

    def body(self) -> None:
        if self._edge(self.Execute):
            if self.Direction == MC_Direction.MC_Positive_Direction:
                sign = 1.0
            elif self.Direction == MC_Direction.MC_Negative_Direction:
                sign = -1.0
            else:
                self._started(0, ERR_NOT_PERMITTED)
                return
            if not self.Velocity > 0.0:
                self._started(0, ERR_PARAMETER)
                return
            cmd, error = self.Axis._command(
                _VELOCITY, sign * self.Velocity, self.Velocity, self.Acceleration, self.Deceleration, self.BufferMode,
            )
            self._started(cmd, error)
        else:
            self._track()


class MC_Halt(_Command):  # noqa: N801
    """MC_Halt: brake to standstill with Deceleration (DiscreteMotion; another move may take over).

    ST: ``Halt(Axis := Axis, Execute := TRUE, Deceleration := 0);``
    """

    Deceleration: LREAL = VAR_INPUT(0.0)
    Jerk: LREAL = VAR_INPUT(0.0)
    BufferMode: MC_BufferMode = VAR_INPUT(MC_BufferMode.MC_Aborting)
    Options: ST_MoveOptions = VAR_INPUT()
    Done: BOOL = VAR_OUTPUT(False)
    Busy: BOOL = VAR_OUTPUT(False)
    Active: BOOL = VAR_OUTPUT(False)
    CommandAborted: BOOL = VAR_OUTPUT(False)
    Error: BOOL = VAR_OUTPUT(False)
    ErrorID: UDINT = VAR_OUTPUT(0)

    def body(self) -> None:
        if self._edge(self.Execute):
            cmd, error = self.Axis._command(_HALT, 0.0, 0.0, 0.0, self.Deceleration, self.BufferMode)
            self._started(cmd, error)
        else:
            self._track()


class MC_Stop(_Command):  # noqa: N801
    """MC_Stop: brake to standstill (Stopping); the axis refuses motion commands while Execute stays TRUE.

    ST: ``Stop(Axis := Axis, Execute := bStop, Deceleration := 0);``
    """

    Deceleration: LREAL = VAR_INPUT(0.0)
    Jerk: LREAL = VAR_INPUT(0.0)
    Options: ST_MoveOptions = VAR_INPUT()
    Done: BOOL = VAR_OUTPUT(False)
    Busy: BOOL = VAR_OUTPUT(False)
    Active: BOOL = VAR_OUTPUT(False)
    CommandAborted: BOOL = VAR_OUTPUT(False)
    Error: BOOL = VAR_OUTPUT(False)
    ErrorID: UDINT = VAR_OUTPUT(0)

    def body(self) -> None:
        if self._edge(self.Execute):
            cmd, error = self.Axis._command(_STOP, 0.0, 0.0, 0.0, self.Deceleration)
            self._started(cmd, error)
        else:
            self._track()
        if not self.Execute and self.CmdNo:
            self.Axis._release_stop(self.CmdNo)


class _SlaveCommand(_Handshake, abstract=True):
    """A coupling block: its command runs on ``Slave``, started by a rising edge of Execute."""

    Slave: AXIS_REF = VAR_IN_OUT()
    Execute: BOOL = VAR_INPUT(False)
    PrevExecute: BOOL = VAR(False)
    Shown: BOOL = VAR(False)
    CmdNo: UDINT = VAR(0)

    def _axis(self) -> AXIS_REF:
        return self.Slave


class MC_GearIn(_SlaveCommand):  # noqa: N801
    """MC_GearIn: couple Slave to Master with RatioNumerator / RatioDenominator (SynchronizedMotion); InGear at once.

    ST: ``GearIn(Master := Axis1, Slave := Axis2, Execute := TRUE, RatioNumerator := 2.0, RatioDenominator := 1);``

    As Tc2_MC2's, it couples at standstill only (a moving slave or master refuses with 0x4B01); the
    slave's set position is then the master's times the ratio, from where both stood, each cycle.
    Acceleration, Deceleration, Jerk and BufferMode are accepted and not used (so in Tc2_MC2 too).
    """

    Master: AXIS_REF = VAR_IN_OUT()
    RatioNumerator: LREAL = VAR_INPUT(1.0)
    RatioDenominator: UINT = VAR_INPUT(1)
    Acceleration: LREAL = VAR_INPUT(0.0)
    Deceleration: LREAL = VAR_INPUT(0.0)
    Jerk: LREAL = VAR_INPUT(0.0)
    BufferMode: MC_BufferMode = VAR_INPUT(MC_BufferMode.MC_Aborting)
    InGear: BOOL = VAR_OUTPUT(False)
    Busy: BOOL = VAR_OUTPUT(False)
    Active: BOOL = VAR_OUTPUT(False)
    CommandAborted: BOOL = VAR_OUTPUT(False)
    Error: BOOL = VAR_OUTPUT(False)
    ErrorID: UDINT = VAR_OUTPUT(0)

    def body(self) -> None:
        if self._edge(self.Execute):
            if self.RatioDenominator == 0:
                self._started(0, ERR_PARAMETER)
                return
            cmd, error = self.Slave._gear_in(self.Master, self.RatioNumerator / self.RatioDenominator)
            self._started(cmd, error)
        else:
            self._track()


class MC_GearOut(_SlaveCommand):  # noqa: N801
    """MC_GearOut: decouple Slave; a moving slave keeps its velocity (ContinuousMotion) until MC_Stop or MC_Halt.

    ST: ``GearOut(Slave := Axis2, Execute := TRUE);`` Done in the call of the edge; a slave that is
    not coupled refuses with 0x4B05.
    """

    Done: BOOL = VAR_OUTPUT(False)
    Busy: BOOL = VAR_OUTPUT(False)
    Error: BOOL = VAR_OUTPUT(False)
    ErrorID: UDINT = VAR_OUTPUT(0)

    def body(self) -> None:
        if self._edge(self.Execute):
            self._done_at_once(self.Slave._gear_out())


class MC_Home(_Command):  # noqa: N801
    """MC_Home: homing. MC_DefaultHoming moves towards the cam (negative, at the calibration velocity) until
    bCalibrationCam is TRUE, then takes Position; the other modes set the reference without motion.

    ST: ``Home(Axis := Axis, Execute := TRUE, Position := 0, HomingMode := MC_DefaultHoming, bCalibrationCam := bCam);``
    """

    Position: LREAL = VAR_INPUT(0.0)
    HomingMode: MC_HomingMode = VAR_INPUT(MC_HomingMode.MC_DefaultHoming)
    BufferMode: MC_BufferMode = VAR_INPUT(MC_BufferMode.MC_Aborting)
    bCalibrationCam: BOOL = VAR_INPUT(False)
    Done: BOOL = VAR_OUTPUT(False)
    Busy: BOOL = VAR_OUTPUT(False)
    Active: BOOL = VAR_OUTPUT(False)
    CommandAborted: BOOL = VAR_OUTPUT(False)
    Error: BOOL = VAR_OUTPUT(False)
    ErrorID: UDINT = VAR_OUTPUT(0)

    def body(self) -> None:
        axis = self.Axis
        if self._edge(self.Execute):
            mode = self.HomingMode
            if mode == MC_HomingMode.MC_DefaultHoming:
                cmd, error = axis._command(_HOME, -axis.Parameters.CalibrationVelocity, 0.0, 0.0, 0.0)
                self._started(cmd, error)
            else:
                refusal = axis._refusal(_HOME)
                if not refusal:
                    if mode == MC_HomingMode.MC_Direct:
                        axis._calibrate(True, self.Position)
                    else:
                        axis._calibrate(mode == MC_HomingMode.MC_ForceCalibration, None)
                self._done_at_once(refusal)
                return
        if self.Busy and self.bCalibrationCam:
            axis._homed(self.CmdNo, self.Position)
        self._track()


class MC_Jog(_AxisBlock):  # noqa: N801
    """MC_Jog: move while JogForward / JogBackwards is held (or a step of Position in the inching modes).

    ST: ``Jog(Axis := Axis, JogForward := bPlus, JogBackwards := bMinus, Mode := MC_JOGMODE_STANDARD_SLOW);``
    """

    JogForward: BOOL = VAR_INPUT(False)
    JogBackwards: BOOL = VAR_INPUT(False)
    Mode: E_JogMode = VAR_INPUT(E_JogMode.MC_JOGMODE_STANDARD_SLOW)
    Position: LREAL = VAR_INPUT(0.0)
    Velocity: LREAL = VAR_INPUT(0.0)
    Acceleration: LREAL = VAR_INPUT(0.0)
    Deceleration: LREAL = VAR_INPUT(0.0)
    Jerk: LREAL = VAR_INPUT(0.0)
    Done: BOOL = VAR_OUTPUT(False)
    Busy: BOOL = VAR_OUTPUT(False)
    Active: BOOL = VAR_OUTPUT(False)
    CommandAborted: BOOL = VAR_OUTPUT(False)
    Error: BOOL = VAR_OUTPUT(False)
    ErrorID: UDINT = VAR_OUTPUT(0)
    PrevExecute: BOOL = VAR(False)
    Shown: BOOL = VAR(False)
    CmdNo: UDINT = VAR(0)
    Stopping: BOOL = VAR(False)

    def body(self) -> None:
        axis = self.Axis
        held = self.JogForward != self.JogBackwards  # the handshake's Execute: one jog button held
        if self._edge(held):
            direction = 1.0 if self.JogForward else -1.0
            self.Stopping = False
            mode = self.Mode
            params = axis.Parameters
            if mode in (E_JogMode.MC_JOGMODE_INCHING, E_JogMode.MC_JOGMODE_INCHING_MODULO):
                velocity = self.Velocity if self.Velocity > 0.0 else params.ManualVelocitySlow
                cmd, error = axis._command(
                    _MOVE, axis.NcToPlc.SetPos + direction * abs(self.Position), velocity,
                    self.Acceleration, self.Deceleration,
                )
                self.Stopping = True  # a step ends by itself
            else:
                velocity = {
                    E_JogMode.MC_JOGMODE_STANDARD_SLOW: params.ManualVelocitySlow,
                    E_JogMode.MC_JOGMODE_STANDARD_FAST: params.ManualVelocityFast,
                }.get(mode, self.Velocity)
                if not velocity > 0.0:
                    self._started(0, ERR_PARAMETER)
                    return
                cmd, error = axis._command(
                    _VELOCITY, direction * velocity, velocity, self.Acceleration, self.Deceleration,
                )
            self._started(cmd, error)
            return
        if self.Busy and not self.Stopping and not held:
            # The button was released: brake; Done when the axis stands.
            self.Stopping = True
            cmd, error = axis._command(_HALT, 0.0, 0.0, 0.0, self.Deceleration)
            if error:
                self._started(0, error)
                return
            self.CmdNo = cmd
        self._track()


class _Reader(_AxisBlock, abstract=True):
    """An MC block that reads while Enable is TRUE: Valid, Busy, Error, ErrorID."""

    Enable: BOOL = VAR_INPUT(False)

    if TYPE_CHECKING:
        Valid: bool

    def _read(self) -> bool:
        """Advance the axis and set Valid / Busy from Enable; whether to read."""
        enable = self.Enable
        if enable:
            self.Axis._sync()
        self.Valid = self.Busy = enable
        if not enable:
            self.Error, self.ErrorID = False, 0
        return enable


class MC_ReadActualPosition(_Reader):  # noqa: N801
    """MC_ReadActualPosition: Position is the axis' actual position while Enable is TRUE.

    ST: ``ReadPos(Axis := Axis, Enable := TRUE);  x := ReadPos.Position;``
    """

    Valid: BOOL = VAR_OUTPUT(False)
    Busy: BOOL = VAR_OUTPUT(False)
    Error: BOOL = VAR_OUTPUT(False)
    ErrorID: UDINT = VAR_OUTPUT(0)
    Position: LREAL = VAR_OUTPUT(0.0)

    def body(self) -> None:
        self.Position = self.Axis.NcToPlc.ActPos if self._read() else 0.0


class MC_ReadActualVelocity(_Reader):  # noqa: N801
    """MC_ReadActualVelocity: ActualVelocity while Enable is TRUE.

    ST: ``ReadVelo(Axis := Axis, Enable := TRUE);  v := ReadVelo.ActualVelocity;``
    """

    Valid: BOOL = VAR_OUTPUT(False)
    Busy: BOOL = VAR_OUTPUT(False)
    Error: BOOL = VAR_OUTPUT(False)
    ErrorID: UDINT = VAR_OUTPUT(0)
    ActualVelocity: LREAL = VAR_OUTPUT(0.0)

    def body(self) -> None:
        self.ActualVelocity = self.Axis.NcToPlc.ActVelo if self._read() else 0.0


class MC_ReadAxisError(_Reader):  # noqa: N801
    """MC_ReadAxisError: AxisErrorID is the axis' NC error code while Enable is TRUE.

    ST: ``ReadErr(Axis := Axis, Enable := TRUE);  nErr := ReadErr.AxisErrorID;``
    """

    Valid: BOOL = VAR_OUTPUT(False)
    Busy: BOOL = VAR_OUTPUT(False)
    Error: BOOL = VAR_OUTPUT(False)
    ErrorID: UDINT = VAR_OUTPUT(0)
    AxisErrorID: UDINT = VAR_OUTPUT(0)

    def body(self) -> None:
        self.AxisErrorID = self.Axis.NcToPlc.ErrorCode if self._read() else 0


class MC_ReadStatus(_Reader):  # noqa: N801
    """MC_ReadStatus: the PLCopen state of the axis, and ``Axis.Status`` refreshed, while Enable is TRUE.

    ST: ``ReadStatus(Axis := Axis, Enable := TRUE);  IF ReadStatus.StandStill THEN ...``
    """

    Valid: BOOL = VAR_OUTPUT(False)
    Busy: BOOL = VAR_OUTPUT(False)
    Error: BOOL = VAR_OUTPUT(False)
    ErrorID: UDINT = VAR_OUTPUT(0)
    ErrorStop: BOOL = VAR_OUTPUT(False)
    Disabled: BOOL = VAR_OUTPUT(False)
    Stopping: BOOL = VAR_OUTPUT(False)
    StandStill: BOOL = VAR_OUTPUT(False)
    DiscreteMotion: BOOL = VAR_OUTPUT(False)
    ContinuousMotion: BOOL = VAR_OUTPUT(False)
    SynchronizedMotion: BOOL = VAR_OUTPUT(False)
    Homing: BOOL = VAR_OUTPUT(False)
    ConstantVelocity: BOOL = VAR_OUTPUT(False)
    Accelerating: BOOL = VAR_OUTPUT(False)
    Decelerating: BOOL = VAR_OUTPUT(False)
    Status: ST_AxisStatus = VAR_OUTPUT()

    def body(self) -> None:
        if not self._read():
            return
        self.Axis.ReadStatus()
        status = self.Axis.Status
        self.Status = status
        self.ErrorStop, self.Disabled, self.Stopping = status.ErrorStop, status.Disabled, status.Stopping
        self.StandStill, self.DiscreteMotion = status.StandStill, status.DiscreteMotion
        self.ContinuousMotion, self.SynchronizedMotion = status.ContinuousMotion, status.SynchronizedMotion
        self.Homing, self.ConstantVelocity = status.Homing, status.ConstantVelocity
        self.Accelerating, self.Decelerating = status.Accelerating, status.Decelerating


class MC_ReadParameter(_Reader):  # noqa: N801
    """MC_ReadParameter: Value is the axis parameter ParameterNumber (an MC_AxisParameter) while Enable is TRUE.

    ST: ``ReadPar(Axis := Axis, Enable := TRUE, ParameterNumber := MC_AxisParameter.AxisMaxVelocity);``
    """

    ParameterNumber: MC_AxisParameter = VAR_INPUT(MC_AxisParameter.CommandedPosition)
    ReadMode: E_ReadMode = VAR_INPUT(E_ReadMode.READMODE_ONCE)
    Valid: BOOL = VAR_OUTPUT(False)
    Busy: BOOL = VAR_OUTPUT(False)
    Error: BOOL = VAR_OUTPUT(False)
    ErrorID: UDINT = VAR_OUTPUT(0)
    Value: LREAL = VAR_OUTPUT(0.0)

    def body(self) -> None:
        if not self._read():
            self.Value = 0.0
            return
        value = _parameter(self.Axis, int(self.ParameterNumber))
        if value is None:
            self.Valid, self.Error, self.ErrorID, self.Value = False, True, ERR_NOT_PERMITTED, 0.0
        else:
            self.Error, self.ErrorID, self.Value = False, 0, value


_P = MC_AxisParameter

#: MC_AxisParameter -> how the simulated axis answers it (the "System" and "Appl" limits are one value here).
_PARAMETERS: dict[int, Any] = {
    _P.CommandedPosition: lambda a: a.NcToPlc.SetPos,
    _P.SWLimitPos: lambda a: a.Parameters.SWLimitPos,
    _P.SWLimitNeg: lambda a: a.Parameters.SWLimitNeg,
    _P.EnableLimitPos: lambda a: a.Parameters.EnableLimitPos,
    _P.EnableLimitNeg: lambda a: a.Parameters.EnableLimitNeg,
    _P.EnablePosLagMonitoring: lambda a: a.Parameters.EnablePosLagMonitoring,
    _P.MaxPositionLag: lambda a: a.Parameters.MaxPositionLag,
    _P.MaxVelocitySystem: lambda a: a.Parameters.MaxVelocity,
    _P.MaxVelocityAppl: lambda a: a.Parameters.MaxVelocity,
    _P.ActualVelocity: lambda a: a.NcToPlc.ActVelo,
    _P.CommandedVelocity: lambda a: a.NcToPlc.SetVelo,
    _P.MaxAccelerationSystem: lambda a: a.Parameters.Acceleration,
    _P.MaxAccelerationAppl: lambda a: a.Parameters.Acceleration,
    _P.MaxDecelerationSystem: lambda a: a.Parameters.Deceleration,
    _P.MaxDecelerationAppl: lambda a: a.Parameters.Deceleration,
    _P.MaxJerkSystem: lambda a: a.Parameters.Jerk,
    _P.MaxJerkAppl: lambda a: a.Parameters.Jerk,
    _P.AxisId: lambda a: a.Parameters.AxisId,
    _P.AxisVeloManSlow: lambda a: a.Parameters.ManualVelocitySlow,
    _P.AxisVeloManFast: lambda a: a.Parameters.ManualVelocityFast,
    _P.AxisVeloMax: lambda a: a.Parameters.MaxVelocity,
    _P.AxisAcc: lambda a: a.Parameters.Acceleration,
    _P.AxisDec: lambda a: a.Parameters.Deceleration,
    _P.AxisJerk: lambda a: a.Parameters.Jerk,
    _P.AxisMaxVelocity: lambda a: a.Parameters.MaxVelocity,
    _P.AxisManualVelocityFast: lambda a: a.Parameters.ManualVelocityFast,
    _P.AxisManualVelocitySlow: lambda a: a.Parameters.ManualVelocitySlow,
    _P.AxisCalibrationVelocityForward: lambda a: a.Parameters.CalibrationVelocity,
    _P.AxisCalibrationVelocityBackward: lambda a: a.Parameters.CalibrationVelocity,
    _P.AxisEnMinSoftPosLimit: lambda a: a.Parameters.EnableLimitNeg,
    _P.AxisMinSoftPosLimit: lambda a: a.Parameters.SWLimitNeg,
    _P.AxisEnMaxSoftPosLimit: lambda a: a.Parameters.EnableLimitPos,
    _P.AxisMaxSoftPosLimit: lambda a: a.Parameters.SWLimitPos,
    _P.AxisEnPositionLagMonitoring: lambda a: a.Parameters.EnablePosLagMonitoring,
    _P.AxisMaxPosLagValue: lambda a: a.Parameters.MaxPositionLag,
    _P.AxisEnTargetPositionMonitoring: lambda a: True,
    _P.AxisTargetPositionWindow: lambda a: a.Parameters.TargetPositionWindow,
}


def _parameter(axis: AXIS_REF, number: int) -> float | None:
    read = _PARAMETERS.get(number)
    return None if read is None else float(read(axis))
