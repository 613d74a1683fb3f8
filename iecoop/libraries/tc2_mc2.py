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
from typing import TYPE_CHECKING, Any

from iecoop.declarations import VAR, VAR_IN_OUT, VAR_INPUT, VAR_OUTPUT
from iecoop.libraries import _motion
from iecoop.members import method
from iecoop.memory import ARRAY, IecEnum, Struct
from iecoop.pou import FunctionBlock
from iecoop.runtime.clock import task_clock
from iecoop.types import BOOL, BYTE, DINT, DWORD, LINT, LREAL, SINT, UDINT, UINT, WORD

__all__ = [
    "AXIS_REF", "E_JogMode", "E_ReadMode", "MC_AxisParameter", "MC_AxisStates", "MC_BufferMode", "MC_Direction",
    "MC_Halt", "MC_Home", "MC_HomingMode", "MC_Jog", "MC_MoveAbsolute", "MC_MoveModulo", "MC_MoveRelative",
    "MC_MoveVelocity", "MC_Power", "MC_ReadActualPosition", "MC_ReadActualVelocity", "MC_ReadAxisError",
    "MC_ReadParameter", "MC_ReadStatus", "MC_Reset", "MC_SetPosition", "MC_Stop", "NCTOPLC_AXIS_REF",
    "PLCTONC_AXIS_REF", "ST_AxisStatus",
]

_now = task_clock.get

# Beckhoff NC error codes the simulation raises (Infosys "NC error codes").
ERR_CANNOT_START = 0x4B01       # NC-PLC: axis cannot be started (error state, other command, protected, not ready)
ERR_INVALID_MODE = 0x4B04       # NC-PLC: invalid mode (invalid Direction at MC_MoveModulo)
ERR_NOT_PERMITTED = 0x4B05      # NC-PLC: command not permitted (continuous motion in an unspecified direction)
ERR_PARAMETER = 0x4B06          # NC-PLC: parameter is not correct
ERR_SOFT_MIN_START = 0x4460     # target below the minimum software end position (axis start)
ERR_SOFT_MAX_START = 0x4461     # target above the maximum software end position (axis start)
ERR_SOFT_MIN_MOVING = 0x4462    # minimum software end position crossed during motion
ERR_SOFT_MAX_MOVING = 0x4463    # maximum software end position crossed during motion
ERR_POSITION_LAG = 0x4550       # following error: maximum position lag exceeded


# ---------------------------------------------------------------------------
# Enumerations
# ---------------------------------------------------------------------------


class MC_AxisStates(IecEnum):  # noqa: N801 - Beckhoff's name
    """The PLCopen state of an axis (``ST_AxisStatus.MotionState``)."""

    MC_AXISSTATE_UNDEFINED = 0
    MC_AXISSTATE_DISABLED = 1
    MC_AXISSTATE_STANDSTILL = 2
    MC_AXISSTATE_ERRORSTOP = 3
    MC_AXISSTATE_STOPPING = 4
    MC_AXISSTATE_HOMING = 5
    MC_AXISSTATE_DISCRETEMOTION = 6
    MC_AXISSTATE_CONTINOUSMOTION = 7
    MC_AXISSTATE_SYNCHRONIZEDMOTION = 8


class MC_BufferMode(IecEnum):  # noqa: N801
    """When a command takes over: at once (``MC_Aborting``) or after the running one (the others)."""

    MC_Aborting = 0
    MC_Buffered = 1
    MC_BlendingLow = 2
    MC_BlendingPrevious = 3
    MC_BlendingNext = 4
    MC_BlendingHigh = 5


class MC_Direction(IecEnum):  # noqa: N801
    """Direction of MC_MoveVelocity and MC_MoveModulo."""

    MC_Positive_Direction = 1
    MC_Shortest_Way = 2
    MC_Negative_Direction = 3
    MC_Current_Direction = 4
    MC_Undefined_Direction = 128


class MC_HomingMode(IecEnum):  # noqa: N801
    """MC_Home: the NC's homing sequence, or setting the reference without motion."""

    MC_DefaultHoming = 0
    MC_Direct = 1
    MC_ForceCalibration = 2
    MC_ResetCalibration = 3


class E_JogMode(IecEnum):  # noqa: N801
    """MC_Jog: manual velocities of the axis, the Velocity input, or a step of Position."""

    MC_JOGMODE_STANDARD_SLOW = 0
    MC_JOGMODE_STANDARD_FAST = 1
    MC_JOGMODE_CONTINOUS = 2
    MC_JOGMODE_INCHING = 3
    MC_JOGMODE_INCHING_MODULO = 4


class E_ReadMode(IecEnum):  # noqa: N801
    """MC_ReadParameter: read once or at every call (the simulation reads at every call)."""

    READMODE_ONCE = 0
    READMODE_CYCLIC = 1


class MC_AxisParameter(IecEnum, base=DINT):  # noqa: N801
    """Axis parameters for MC_ReadParameter, numbered as Tc2_MC2 declares them."""

    CommandedPosition = 1
    SWLimitPos = 2
    SWLimitNeg = 3
    EnableLimitPos = 4
    EnableLimitNeg = 5
    EnablePosLagMonitoring = 6
    MaxPositionLag = 7
    MaxVelocitySystem = 8
    MaxVelocityAppl = 9
    ActualVelocity = 10
    CommandedVelocity = 11
    MaxAccelerationSystem = 12
    MaxAccelerationAppl = 13
    MaxDecelerationSystem = 14
    MaxDecelerationAppl = 15
    MaxJerkSystem = 16
    MaxJerkAppl = 17
    AxisId = 1000
    AxisVeloManSlow = 1001
    AxisVeloManFast = 1002
    AxisVeloMax = 1003
    AxisAcc = 1004
    AxisDec = 1005
    AxisJerk = 1006
    AxisMaxVelocity = 1007
    AxisRapidTraverseVelocity = 1008
    AxisManualVelocityFast = 1009
    AxisManualVelocitySlow = 1010
    AxisCalibrationVelocityForward = 1011
    AxisCalibrationVelocityBackward = 1012
    AxisJogIncrementForward = 1013
    AxisJogIncrementBackward = 1014
    AxisEnMinSoftPosLimit = 1015
    AxisMinSoftPosLimit = 1016
    AxisEnMaxSoftPosLimit = 1017
    AxisMaxSoftPosLimit = 1018
    AxisEnPositionLagMonitoring = 1019
    AxisMaxPosLagValue = 1020
    AxisMaxPosLagFilterTime = 1021
    AxisEnPositionRangeMonitoring = 1022
    AxisPositionRangeWindow = 1023
    AxisEnTargetPositionMonitoring = 1024
    AxisTargetPositionWindow = 1025


# ---------------------------------------------------------------------------
# The axis interface records
# ---------------------------------------------------------------------------


class NCTOPLC_AXIS_REF(Struct):  # noqa: N801
    """What the NC reports every cycle (the leading members of Beckhoff's NCTOPLC_AXIS_REF)."""

    StateDWord: DWORD = 0
    ErrorCode: DWORD = 0
    AxisState: DWORD = 0
    AxisModeConfirmation: DWORD = 0
    HomingState: DWORD = 0
    CoupleState: DWORD = 0
    SvbEntries: DWORD = 0
    SafEntries: DWORD = 0
    AxisId: DWORD = 0
    OpModeDWord: DWORD = 0
    ActPos: LREAL = 0.0
    ModuloActPos: LREAL = 0.0
    ActiveControlLoopIndex: WORD = 0
    ControlLoopIndex: WORD = 0
    ModuloActTurns: DINT = 0
    ActVelo: LREAL = 0.0
    PosDiff: LREAL = 0.0
    SetPos: LREAL = 0.0
    SetVelo: LREAL = 0.0
    SetAcc: LREAL = 0.0
    TargetPos: LREAL = 0.0
    ModuloSetPos: LREAL = 0.0
    ModuloSetTurns: DINT = 0
    CmdNo: UINT = 0
    CmdState: UINT = 0
    ActAcc: LREAL = 0.0


class PLCTONC_AXIS_REF(Struct):  # noqa: N801
    """What the PLC sends the NC: the controller and feed enables (ControlDWord bits 0-2) and the override."""

    ControlDWord: DWORD = 0
    Override: UDINT = 0
    AxisModeRequest: DWORD = 0
    AxisModeDWord: DWORD = 0
    AxisModeLReal: LREAL = 0.0
    PositionCorrection: LREAL = 0.0
    ExtSetPos: LREAL = 0.0
    ExtSetVelo: LREAL = 0.0
    ExtSetAcc: LREAL = 0.0
    ExtSetDirection: DINT = 0


class ST_AxisStatus(Struct):  # noqa: N801
    """The axis state as ``Axis.ReadStatus()`` / MC_ReadStatus prepare it (Beckhoff's ST_AxisStatus)."""

    UpdateTaskIndex: BYTE = 0
    UpdateCycleTime: LREAL = 0.0
    CycleCounter: UDINT = 0
    NcCycleCounter: UDINT = 0
    MotionState: MC_AxisStates = MC_AxisStates.MC_AXISSTATE_UNDEFINED
    Error: BOOL = False
    ErrorID: UDINT = 0
    ErrorStop: BOOL = False
    Disabled: BOOL = False
    Stopping: BOOL = False
    StandStill: BOOL = False
    DiscreteMotion: BOOL = False
    ContinuousMotion: BOOL = False
    SynchronizedMotion: BOOL = False
    Homing: BOOL = False
    ConstantVelocity: BOOL = False
    Accelerating: BOOL = False
    Decelerating: BOOL = False
    Operational: BOOL = False
    ControlLoopClosed: BOOL = False
    HasJob: BOOL = False
    HasBeenStopped: BOOL = False
    NewTargetPosition: BOOL = False
    InPositionArea: BOOL = False
    InTargetPosition: BOOL = False
    ProtectedMode: BOOL = False
    Homed: BOOL = False
    HomingBusy: BOOL = False
    MotionCommandsLocked: BOOL = False
    SoftLimitMinExceeded: BOOL = False
    SoftLimitMaxExceeded: BOOL = False
    Moving: BOOL = False
    PositiveDirection: BOOL = False
    NegativeDirection: BOOL = False
    NotMoving: BOOL = False


class ST_SimAxisParameters(Struct):  # noqa: N801
    """The simulated axis' parameters (iecoop's; MC_ReadParameter reads them), set with ``AXIS_REF.configure``."""

    AxisId: UDINT = 1
    MaxVelocity: LREAL = 2000.0
    Acceleration: LREAL = 10000.0
    Deceleration: LREAL = 10000.0
    Jerk: LREAL = 0.0
    ManualVelocitySlow: LREAL = 100.0
    ManualVelocityFast: LREAL = 600.0
    CalibrationVelocity: LREAL = 30.0
    EnableLimitNeg: BOOL = False
    SWLimitNeg: LREAL = 0.0
    EnableLimitPos: BOOL = False
    SWLimitPos: LREAL = 0.0
    EnablePosLagMonitoring: BOOL = True
    MaxPositionLag: LREAL = 5.0
    TargetPositionWindow: LREAL = 0.02
    ModuloFactor: LREAL = 360.0


class ST_SimSegment(Struct):  # noqa: N801
    """One segment of constant acceleration of the running profile."""

    Duration: LREAL = 0.0
    Acceleration: LREAL = 0.0


# Command kinds of the simulation (what the active command does to the state machine).
_MOVE, _VELOCITY, _HALT, _STOP, _HOME = 1, 2, 3, 4, 5
# What a block learns of its command (``AXIS_REF._result``).
_PENDING, _ACTIVE, _IN_VELOCITY, _DONE, _ABORTED, _FAILED = 0, 1, 2, 3, 4, 5
_ABORTED_CODE = 0xFFFF_FFFF
_RESULTS = 8

_STATES = MC_AxisStates


class ST_SimAxisState(Struct):  # noqa: N801
    """The simulation's own state of an axis (iecoop's): state machine, commands, running profile."""

    State: MC_AxisStates = MC_AxisStates.MC_AXISSTATE_DISABLED
    ErrorId: UDINT = 0
    Homed: BOOL = False
    LastNs: LINT = -1
    NextCmd: UDINT = 0
    ActiveCmd: UDINT = 0
    ActiveKind: SINT = 0
    InVelocity: BOOL = False
    StopLocked: BOOL = False
    StopCmd: UDINT = 0
    PendingCmd: UDINT = 0
    PendingKind: SINT = 0
    PendingTarget: LREAL = 0.0
    PendingVelocity: LREAL = 0.0
    PendingAcc: LREAL = 0.0
    PendingDec: LREAL = 0.0
    ResultCmd: ARRAY[UDINT] = VAR(bounds=(1, _RESULTS))
    ResultCode: ARRAY[UDINT] = VAR(bounds=(1, _RESULTS))
    ResultNext: SINT = 1
    Running: BOOL = False
    ProfileStartNs: LINT = 0
    ProfileStart: LREAL = 0.0
    ProfileVelocity: LREAL = 0.0
    ProfileTarget: LREAL = 0.0
    ProfileEndless: BOOL = False
    SegmentCount: SINT = 0
    Segments: ARRAY[ST_SimSegment] = VAR(bounds=(1, 4))
    HasTarget: BOOL = False
    Target: LREAL = 0.0
    Lag: LREAL = 0.0
    CycleCounter: UDINT = 0


_MOTION_STATES = frozenset({
    _STATES.MC_AXISSTATE_STANDSTILL, _STATES.MC_AXISSTATE_DISCRETEMOTION, _STATES.MC_AXISSTATE_CONTINOUSMOTION,
})
_KIND_STATE = {
    _MOVE: _STATES.MC_AXISSTATE_DISCRETEMOTION, _HALT: _STATES.MC_AXISSTATE_DISCRETEMOTION,
    _VELOCITY: _STATES.MC_AXISSTATE_CONTINOUSMOTION, _STOP: _STATES.MC_AXISSTATE_STOPPING,
    _HOME: _STATES.MC_AXISSTATE_HOMING,
}


class AXIS_REF(FunctionBlock):  # noqa: N801
    """AXIS_REF: one simulated NC axis, passed to every MC block as ``Axis``.

    ST: ``Axis1 : AXIS_REF;  Axis1.ReadStatus();  x := Axis1.NcToPlc.ActPos;``

    From Python a test configures it (``configure``), reads ``NcToPlc``,
    ``Status`` and ``Sim`` (the simulation's state), and injects faults
    (``inject_fault``, ``simulate_position_lag``).
    """

    PlcToNc: PLCTONC_AXIS_REF = VAR_INPUT()
    NcToPlc: NCTOPLC_AXIS_REF = VAR_OUTPUT()
    Status: ST_AxisStatus = VAR_OUTPUT()
    Parameters: ST_SimAxisParameters = VAR()
    Sim: ST_SimAxisState = VAR()

    @method
    def ReadStatus(self) -> None:
        """Refresh ``Status`` from the axis (ST: ``Axis.ReadStatus();``)."""
        self._sync()
        sim, status, nc = self.Sim, self.Status, self.NcToPlc
        state = sim.State
        sim.CycleCounter += 1
        status.CycleCounter = sim.CycleCounter
        status.NcCycleCounter = sim.CycleCounter
        status.MotionState = state
        status.Error = sim.ErrorId != 0
        status.ErrorID = sim.ErrorId
        status.ErrorStop = state == _STATES.MC_AXISSTATE_ERRORSTOP
        status.Disabled = state == _STATES.MC_AXISSTATE_DISABLED
        status.Stopping = state == _STATES.MC_AXISSTATE_STOPPING
        status.StandStill = state == _STATES.MC_AXISSTATE_STANDSTILL
        status.DiscreteMotion = state == _STATES.MC_AXISSTATE_DISCRETEMOTION
        status.ContinuousMotion = state == _STATES.MC_AXISSTATE_CONTINOUSMOTION
        status.Homing = state == _STATES.MC_AXISSTATE_HOMING
        moving = nc.SetVelo != 0.0
        speeding_up = nc.SetAcc * nc.SetVelo > 0.0
        status.ConstantVelocity = moving and nc.SetAcc == 0.0
        status.Accelerating = moving and speeding_up
        status.Decelerating = moving and nc.SetAcc != 0.0 and not speeding_up
        status.Operational = self._enabled() and sim.ErrorId == 0
        status.ControlLoopClosed = self._enabled()
        status.HasJob = sim.Running
        status.HasBeenStopped = sim.ActiveKind in (_HALT, _STOP) and sim.ActiveCmd != 0
        status.InTargetPosition = self._in_target()
        status.InPositionArea = status.InTargetPosition
        status.Homed = sim.Homed
        status.HomingBusy = state == _STATES.MC_AXISSTATE_HOMING
        status.MotionCommandsLocked = sim.StopLocked
        status.SoftLimitMinExceeded = self.Parameters.EnableLimitNeg and nc.SetPos < self.Parameters.SWLimitNeg
        status.SoftLimitMaxExceeded = self.Parameters.EnableLimitPos and nc.SetPos > self.Parameters.SWLimitPos
        status.Moving = moving
        status.PositiveDirection = nc.SetVelo > 0.0
        status.NegativeDirection = nc.SetVelo < 0.0
        status.NotMoving = not moving

    # -- Python-side test API ------------------------------------------------

    def configure(
        self, *, max_velocity: float | None = None, acceleration: float | None = None,
        deceleration: float | None = None, soft_limit_min: float | None = None, soft_limit_max: float | None = None,
        max_position_lag: float | None = None, position_lag_monitoring: bool | None = None,
        target_position_window: float | None = None, manual_velocity_slow: float | None = None,
        manual_velocity_fast: float | None = None, calibration_velocity: float | None = None,
        modulo_factor: float | None = None, axis_id: int | None = None,
    ) -> None:
        """Set the simulated axis' parameters; a software limit given as a number is enabled, as None left as it is.

        ``disable_soft_limits()`` switches both limits off again.
        """
        p = self.Parameters
        for name, value in (
            ("MaxVelocity", max_velocity), ("Acceleration", acceleration), ("Deceleration", deceleration),
            ("ManualVelocitySlow", manual_velocity_slow), ("ManualVelocityFast", manual_velocity_fast),
            ("CalibrationVelocity", calibration_velocity), ("ModuloFactor", modulo_factor),
        ):
            if value is not None:
                if not value > 0.0 or math.isinf(value):
                    raise ValueError(f"AXIS_REF.configure: {name} must be a positive number, got {value!r}")
                setattr(p, name, float(value))
        if soft_limit_min is not None:
            p.EnableLimitNeg, p.SWLimitNeg = True, float(soft_limit_min)
        if soft_limit_max is not None:
            p.EnableLimitPos, p.SWLimitPos = True, float(soft_limit_max)
        if max_position_lag is not None:
            p.MaxPositionLag = float(max_position_lag)
        if position_lag_monitoring is not None:
            p.EnablePosLagMonitoring = position_lag_monitoring
        if target_position_window is not None:
            p.TargetPositionWindow = float(target_position_window)
        if axis_id is not None:
            p.AxisId = axis_id
            self.NcToPlc.AxisId = axis_id

    def disable_soft_limits(self) -> None:
        """Switch both software end position monitors off."""
        self.Parameters.EnableLimitNeg = False
        self.Parameters.EnableLimitPos = False

    def inject_fault(self, error_id: int) -> None:
        """An NC error on the axis: ErrorStop with ``error_id``; the axis brakes with its deceleration."""
        if error_id <= 0:
            raise ValueError(f"AXIS_REF.inject_fault: an NC error code is > 0, got {error_id!r}")
        self._sync()
        self._fault(error_id, immediate=False)
        self._publish()

    def simulate_position_lag(self, lag: float) -> None:
        """Let the actual position trail the set position by ``lag`` (``PosDiff``) from now on."""
        self.Sim.Lag = float(lag)
        self._sync()
        self._check_lag()
        self._publish()

    # -- the simulation (called by the MC blocks) ----------------------------

    def _enabled(self) -> bool:
        return bool(self.PlcToNc.ControlDWord & 1)

    def _in_target(self) -> bool:
        sim = self.Sim
        return (not sim.Running and sim.HasTarget
                and abs(self.NcToPlc.ActPos - sim.Target) <= self.Parameters.TargetPositionWindow)

    def _sync(self) -> None:
        """Move the axis to the task clock's instant, once per instant."""
        sim = self.Sim
        now = _now().now_ns()
        if now == sim.LastNs:
            return
        sim.LastNs = now
        self._apply_enable()
        if sim.Running:
            self._advance(now)
        self._check_lag()
        self._publish()

    def _apply_enable(self) -> None:
        sim = self.Sim
        state = sim.State
        if self._enabled():
            if state == _STATES.MC_AXISSTATE_DISABLED:
                sim.State = _STATES.MC_AXISSTATE_STANDSTILL
        elif state != _STATES.MC_AXISSTATE_DISABLED:
            # Controller enable removed: the drive stops where it is; a running command is aborted.
            self._end_profile(self.NcToPlc.SetPos)
            self._abort_commands()
            sim.StopLocked = False
            if state != _STATES.MC_AXISSTATE_ERRORSTOP:
                sim.State = _STATES.MC_AXISSTATE_DISABLED

    def _profile(self) -> _motion.Profile:
        sim = self.Sim
        segments = tuple(
            (sim.Segments[i].Duration, sim.Segments[i].Acceleration) for i in range(1, sim.SegmentCount + 1)
        )
        return _motion.Profile(sim.ProfileStart, sim.ProfileVelocity, segments, sim.ProfileTarget, sim.ProfileEndless)

    def _run(self, profile: _motion.Profile) -> None:
        sim = self.Sim
        sim.ProfileStartNs = sim.LastNs
        sim.ProfileStart = profile.start
        sim.ProfileVelocity = profile.velocity
        sim.ProfileTarget = 0.0 if profile.endless else profile.target
        sim.ProfileEndless = profile.endless
        sim.SegmentCount = len(profile.segments)
        for index, (duration, acceleration) in enumerate(profile.segments, start=1):
            sim.Segments[index].Duration = duration
            sim.Segments[index].Acceleration = acceleration
        sim.Running = True
        sim.InVelocity = False
        if not profile.endless:
            sim.HasTarget, sim.Target = True, profile.target
            self.NcToPlc.TargetPos = profile.target

    def _end_profile(self, position: float) -> None:
        sim, nc = self.Sim, self.NcToPlc
        sim.Running = False
        nc.SetPos = position
        nc.SetVelo = nc.SetAcc = 0.0
        nc.ActPos = position - sim.Lag
        nc.ActVelo = nc.ActAcc = 0.0

    def _advance(self, now: int) -> None:
        sim, nc, p = self.Sim, self.NcToPlc, self.Parameters
        sample, ended = _motion.evaluate(self._profile(), (now - sim.ProfileStartNs) / 1e9)
        nc.SetPos, nc.SetVelo, nc.SetAcc = sample
        nc.ActPos = sample.position - sim.Lag
        nc.ActVelo, nc.ActAcc = sample.velocity, sample.acceleration
        if sim.State != _STATES.MC_AXISSTATE_ERRORSTOP:
            if p.EnableLimitPos and sample.position > p.SWLimitPos and sample.velocity > 0.0:
                self._fault(ERR_SOFT_MAX_MOVING, immediate=False)
                return
            if p.EnableLimitNeg and sample.position < p.SWLimitNeg and sample.velocity < 0.0:
                self._fault(ERR_SOFT_MIN_MOVING, immediate=False)
                return
        if not ended:
            return
        if sim.ProfileEndless:
            sim.InVelocity = True
            return
        self._end_profile(sample.position)
        self._finish_active()

    def _finish_active(self) -> None:
        """The running profile reached its end: the command is done, the state machine moves on."""
        sim = self.Sim
        kind, cmd = sim.ActiveKind, sim.ActiveCmd
        if sim.State == _STATES.MC_AXISSTATE_ERRORSTOP:
            return
        if cmd:
            self._record(cmd, 0)
        sim.ActiveCmd, sim.ActiveKind = 0, 0
        if kind == _STOP and sim.StopLocked:
            return  # MC_Stop holds the axis in Stopping until its Execute falls
        sim.State = _STATES.MC_AXISSTATE_STANDSTILL
        if sim.PendingCmd:
            self._start_pending()

    def _record(self, cmd: int, code: int) -> None:
        sim = self.Sim
        slot = sim.ResultNext
        sim.ResultCmd[slot] = cmd
        sim.ResultCode[slot] = code
        sim.ResultNext = slot % _RESULTS + 1

    def _abort_commands(self) -> None:
        sim = self.Sim
        for cmd in (sim.ActiveCmd, sim.PendingCmd):
            if cmd:
                self._record(cmd, _ABORTED_CODE)
        sim.ActiveCmd = sim.ActiveKind = sim.PendingCmd = sim.PendingKind = 0
        sim.InVelocity = False

    def _fault(self, error_id: int, *, immediate: bool) -> None:
        """ErrorStop with ``error_id``: the running command fails with it, a buffered one is aborted."""
        sim, nc = self.Sim, self.NcToPlc
        if sim.ActiveCmd:
            self._record(sim.ActiveCmd, error_id)
            sim.ActiveCmd = sim.ActiveKind = 0
        if sim.PendingCmd:
            self._record(sim.PendingCmd, _ABORTED_CODE)
            sim.PendingCmd = sim.PendingKind = 0
        sim.ErrorId = error_id
        sim.State = _STATES.MC_AXISSTATE_ERRORSTOP
        sim.StopLocked = False
        sim.InVelocity = False
        if immediate or nc.SetVelo == 0.0:
            self._end_profile(nc.SetPos)
        else:
            self._run(_motion.plan_stop(nc.SetPos, nc.SetVelo, self.Parameters.Deceleration))

    def _check_lag(self) -> None:
        sim, p = self.Sim, self.Parameters
        if (p.EnablePosLagMonitoring and abs(sim.Lag) > p.MaxPositionLag
                and sim.State not in (_STATES.MC_AXISSTATE_ERRORSTOP, _STATES.MC_AXISSTATE_DISABLED)):
            # Beckhoff: the axis is stopped at once by direct shutdown, error 0x4550.
            self._fault(ERR_POSITION_LAG, immediate=True)

    def _publish(self) -> None:
        """Write the NC's cyclic report (NcToPlc) from the simulation's state."""
        sim, nc, p = self.Sim, self.NcToPlc, self.Parameters
        nc.ErrorCode = sim.ErrorId
        nc.PosDiff = nc.SetPos - nc.ActPos
        modulo = p.ModuloFactor
        nc.ModuloActTurns = math.floor(nc.ActPos / modulo)
        nc.ModuloActPos = nc.ActPos - nc.ModuloActTurns * modulo
        nc.ModuloSetTurns = math.floor(nc.SetPos / modulo)
        nc.ModuloSetPos = nc.SetPos - nc.ModuloSetTurns * modulo
        nc.CmdNo = sim.ActiveCmd & 0xFFFF
        nc.HomingState = 1 if sim.Homed else 0
        velocity = nc.SetVelo
        word = 0
        if self._enabled() and sim.ErrorId == 0:
            word |= 1 << 0                      # Operational
        if sim.Homed:
            word |= 1 << 1                      # Homed
        if velocity == 0.0:
            word |= 1 << 2                      # NotMoving
        if self._in_target():
            word |= (1 << 3) | (1 << 4)         # InPositionArea, InTargetPosition
        if sim.ActiveKind in (_HALT, _STOP) and sim.ActiveCmd:
            word |= 1 << 7                      # HasBeenStopped
        if sim.Running:
            word |= 1 << 8                      # HasJob
        if velocity > 0.0:
            word |= 1 << 9                      # PositiveDirection
        if velocity < 0.0:
            word |= 1 << 10                     # NegativeDirection
        if sim.State == _STATES.MC_AXISSTATE_HOMING:
            word |= 1 << 11                     # HomingBusy
        if velocity != 0.0 and nc.SetAcc == 0.0:
            word |= 1 << 12                     # ConstantVelocity
        nc.StateDWord = word

    def _result(self, cmd: int) -> tuple[int, int]:
        """What became of command ``cmd``: one of _PENDING ... _FAILED, and the error code."""
        sim = self.Sim
        if cmd == sim.ActiveCmd:
            return (_IN_VELOCITY if sim.InVelocity else _ACTIVE), 0
        if cmd == sim.PendingCmd:
            return _PENDING, 0
        for slot in range(1, _RESULTS + 1):
            if sim.ResultCmd[slot] == cmd:
                code = sim.ResultCode[slot]
                if code == 0:
                    return _DONE, 0
                return (_ABORTED, 0) if code == _ABORTED_CODE else (_FAILED, code)
        return _ABORTED, 0

    def _refusal(self, kind: int) -> int:
        """The error code that refuses a new command of ``kind`` in the axis' present state, or 0 (PLCopen's diagram)."""
        state = self.Sim.State
        if state in (_STATES.MC_AXISSTATE_DISABLED, _STATES.MC_AXISSTATE_ERRORSTOP):
            return ERR_CANNOT_START
        if kind == _STOP:
            return 0
        if state not in _MOTION_STATES or (kind == _HOME and state != _STATES.MC_AXISSTATE_STANDSTILL):
            return ERR_CANNOT_START
        return 0

    def _command(
        self, kind: int, target: float, velocity: float, acc: float, dec: float,
        buffer_mode: int = MC_BufferMode.MC_Aborting,
    ) -> tuple[int, int]:
        """Start (or buffer) a command; returns (command number, 0) or (0, error code).

        ``target`` is a position for _MOVE, a signed velocity for _VELOCITY; ``acc`` / ``dec`` <= 0
        mean the axis' own.
        """
        refusal = self._refusal(kind)
        if refusal:
            return 0, refusal
        sim, p = self.Sim, self.Parameters
        if kind == _MOVE:
            if not math.isfinite(target) or not velocity > 0.0:
                return 0, ERR_PARAMETER
            if p.EnableLimitPos and target > p.SWLimitPos:
                self._fault(ERR_SOFT_MAX_START, immediate=False)
                self._publish()
                return 0, ERR_SOFT_MAX_START
            if p.EnableLimitNeg and target < p.SWLimitNeg:
                self._fault(ERR_SOFT_MIN_START, immediate=False)
                self._publish()
                return 0, ERR_SOFT_MIN_START
        acc = acc if acc > 0.0 else p.Acceleration
        dec = dec if dec > 0.0 else p.Deceleration
        sim.NextCmd += 1
        cmd = sim.NextCmd
        busy = sim.ActiveCmd != 0 and sim.ActiveKind != _STOP
        if buffer_mode != MC_BufferMode.MC_Aborting and busy and kind in (_MOVE, _VELOCITY, _HALT):
            if sim.PendingCmd:
                self._record(sim.PendingCmd, _ABORTED_CODE)
            sim.PendingCmd, sim.PendingKind = cmd, kind
            sim.PendingTarget, sim.PendingVelocity, sim.PendingAcc, sim.PendingDec = target, velocity, acc, dec
            return cmd, 0
        self._abort_commands()
        self._begin(cmd, kind, target, velocity, acc, dec)
        return cmd, 0

    def _start_pending(self) -> None:
        sim = self.Sim
        cmd, kind = sim.PendingCmd, sim.PendingKind
        sim.PendingCmd = sim.PendingKind = 0
        self._begin(cmd, kind, sim.PendingTarget, sim.PendingVelocity, sim.PendingAcc, sim.PendingDec)

    def _begin(self, cmd: int, kind: int, target: float, velocity: float, acc: float, dec: float) -> None:
        sim, nc, p = self.Sim, self.NcToPlc, self.Parameters
        vmax = min(velocity, p.MaxVelocity) if velocity > 0.0 else p.MaxVelocity
        if kind == _MOVE:
            profile = _motion.plan_move(nc.SetPos, nc.SetVelo, target, vmax, acc, dec)
        elif kind in (_VELOCITY, _HOME):
            commanded = math.copysign(min(abs(target), p.MaxVelocity), target)
            profile = _motion.plan_velocity(nc.SetPos, nc.SetVelo, commanded, acc, dec)
        else:
            profile = _motion.plan_stop(nc.SetPos, nc.SetVelo, dec)
        sim.ActiveCmd, sim.ActiveKind = cmd, kind
        sim.State = _KIND_STATE[kind]
        if kind == _STOP:
            sim.StopLocked, sim.StopCmd = True, cmd
        if kind == _HOME:
            sim.Homed = False
        self._run(profile)
        self._publish()

    def _release_stop(self, cmd: int) -> None:
        """MC_Stop's Execute fell: the axis leaves Stopping once it stands still."""
        sim = self.Sim
        if not sim.StopLocked or sim.StopCmd != cmd:
            return
        sim.StopLocked = False
        if sim.State == _STATES.MC_AXISSTATE_STOPPING and not sim.Running:
            sim.State = _STATES.MC_AXISSTATE_STANDSTILL
        self._publish()

    def _reset(self) -> None:
        """MC_Reset: leave ErrorStop (to Standstill when enabled, else Disabled) once the axis stands."""
        sim = self.Sim
        if sim.State != _STATES.MC_AXISSTATE_ERRORSTOP:
            return
        self._end_profile(self.NcToPlc.SetPos)
        sim.ErrorId = 0
        sim.Lag = 0.0
        sim.State = _STATES.MC_AXISSTATE_STANDSTILL if self._enabled() else _STATES.MC_AXISSTATE_DISABLED
        self._publish()

    def _set_position(self, position: float, relative: bool) -> None:
        """MC_SetPosition: shift the axis' coordinates; a running profile is shifted with them."""
        sim, nc = self.Sim, self.NcToPlc
        offset = position if relative else position - nc.ActPos
        sim.ProfileStart += offset
        sim.ProfileTarget += offset
        sim.Target += offset
        nc.SetPos += offset
        nc.ActPos += offset
        nc.TargetPos += offset
        self._publish()

    def _homed(self, cmd: int, position: float) -> None:
        """The homing of ``cmd`` found its reference: the axis stops there and takes ``position``."""
        sim, nc = self.Sim, self.NcToPlc
        if sim.ActiveCmd != cmd or sim.ActiveKind != _HOME:
            return
        self._end_profile(nc.SetPos)
        self._set_position(position, relative=False)
        sim.Homed = True
        sim.HasTarget, sim.Target = True, position
        self._finish_active()
        self._publish()

    def _calibrate(self, homed: bool, position: float | None) -> None:
        """MC_Home without motion: MC_Direct (set the position), MC_ForceCalibration, MC_ResetCalibration."""
        if position is not None:
            self._set_position(position, relative=False)
        self.Sim.Homed = homed
        self._publish()


# ---------------------------------------------------------------------------
# The function blocks
# ---------------------------------------------------------------------------


@functools.cache
def _has(cls: type, pin: str) -> bool:
    return hasattr(cls, pin)


class _AxisBlock(FunctionBlock, abstract=True):
    """What every MC block shares: ``Axis : AXIS_REF`` (VAR_IN_OUT) and the PLCopen output handshake."""

    Axis: AXIS_REF = VAR_IN_OUT()

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

    def _set(self, pin: str, value: Any) -> None:
        if _has(type(self), pin):
            setattr(self, pin, value)

    def _edge(self, execute: bool) -> bool:
        """Advance the axis, drop outputs shown after Execute fell, and tell whether Execute rose (PLCopen)."""
        self.Axis._sync()
        if not execute and self.Shown and not self.Busy:
            self._clear()
        rising = execute and not self.PrevExecute
        self.PrevExecute = execute
        return rising

    def _clear(self) -> None:
        for pin in ("Done", "CommandAborted", "Error", "InVelocity"):
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
        outcome, code = self.Axis._result(self.CmdNo)
        if outcome in (_ACTIVE, _IN_VELOCITY):
            self._set("Active", True)
            if outcome == _IN_VELOCITY:
                self._set("InVelocity", True)
            return
        if outcome == _PENDING:
            return
        self._set("Busy", False)
        self._set("Active", False)
        self._set("InVelocity", False)
        if outcome == _DONE:
            self._set("Done", True)
        elif outcome == _ABORTED:
            self._set("CommandAborted", True)
        else:
            self.Error, self.ErrorID = True, code
        self.Shown = True


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
        here = axis.NcToPlc.SetPos
        turn = math.floor(here / modulo) * modulo
        ahead = turn + self.Position if turn + self.Position >= here else turn + modulo + self.Position
        behind = ahead - modulo if ahead - modulo <= here else ahead
        if abs(ahead - here) <= _motion.EPSILON or abs(here - behind) <= _motion.EPSILON:
            return here, 0
        direction = self.Direction
        if direction == MC_Direction.MC_Current_Direction:
            direction = (MC_Direction.MC_Negative_Direction if axis.NcToPlc.SetVelo < 0.0
                         else MC_Direction.MC_Positive_Direction)
        if direction == MC_Direction.MC_Positive_Direction:
            return ahead, 0
        if direction == MC_Direction.MC_Negative_Direction:
            return behind, 0
        if direction == MC_Direction.MC_Shortest_Way:
            return (ahead if ahead - here <= here - behind else behind), 0
        return 0.0, ERR_INVALID_MODE


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
    Direction: SINT = VAR(0)
    Stopping: BOOL = VAR(False)

    def body(self) -> None:
        axis = self.Axis
        held = self.JogForward != self.JogBackwards  # the handshake's Execute: one jog button held
        if self._edge(held):
            direction = 1.0 if self.JogForward else -1.0
            self.Direction = int(direction)
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
