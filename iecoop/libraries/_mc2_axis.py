"""The simulated NC axis behind ``iecoop.libraries.tc2_mc2``: AXIS_REF, its records and enumerations.

The MC blocks of ``tc2_mc2`` command an ``AXIS_REF`` through its private
methods (``_command``, ``_result``...); everything the simulation keeps lives
in the axis' memory (``AXIS_REF.Sim``), so a reset re-initialises it with the
rest of the PLC's data. See ``tc2_mc2`` for what is simulated.
"""

from __future__ import annotations

import math

from iecoop.declarations import VAR, VAR_INPUT, VAR_OUTPUT
from iecoop.libraries import _motion
from iecoop.members import method
from iecoop.memory import ARRAY, IecEnum, Struct, adr
from iecoop.pou import FunctionBlock
from iecoop.runtime.clock import task_clock
from iecoop.types import BOOL, BYTE, DINT, DWORD, LINT, LREAL, SINT, UDINT, UINT, WORD

__all__ = [
    "AXIS_REF", "E_JogMode", "E_ReadMode", "MC_AxisParameter", "MC_AxisStates", "MC_BufferMode", "MC_Direction",
    "MC_HomingMode", "NCTOPLC_AXIS_REF", "PLCTONC_AXIS_REF", "ST_AxisStatus", "ST_MoveOptions", "ST_SimAxisParameters",
    "ST_SimAxisState", "ST_SimSegment",
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


class ST_MoveOptions(Struct):  # noqa: N801
    """Rarely used settings of a motion command (Beckhoff's ST_MoveOptions); accepted, not simulated."""

    EnableBlendingPosition: BOOL = False
    BlendingPosition: LREAL = 0.0
    IgnorePositionMonitoring: BOOL = False
    EnableStopPositionMonitoring: BOOL = False


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
_MOVE, _VELOCITY, _HALT, _STOP, _HOME, _GEAR = 1, 2, 3, 4, 5, 6
# What a block learns of its command (``AXIS_REF._result``).
_PENDING, _ACTIVE, _IN_VELOCITY, _DONE, _ABORTED, _FAILED = 0, 1, 2, 3, 4, 5
_ABORTED_CODE = 0xFFFF_FFFF
_RESULTS = 8

_STATES = MC_AxisStates


def _dint(value: int) -> int:
    """``value`` wrapped into DINT, as the PLC's integer arithmetic would store it."""
    return (value + 0x8000_0000) % 0x1_0000_0000 - 0x8000_0000


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
    GearRatio: LREAL = 0.0
    GearMasterStart: LREAL = 0.0
    GearSlaveStart: LREAL = 0.0


_MOTION_STATES = frozenset({
    _STATES.MC_AXISSTATE_STANDSTILL, _STATES.MC_AXISSTATE_DISCRETEMOTION, _STATES.MC_AXISSTATE_CONTINOUSMOTION,
    _STATES.MC_AXISSTATE_SYNCHRONIZEDMOTION,
})
_KIND_STATE = {
    _MOVE: _STATES.MC_AXISSTATE_DISCRETEMOTION, _HALT: _STATES.MC_AXISSTATE_DISCRETEMOTION,
    _VELOCITY: _STATES.MC_AXISSTATE_CONTINOUSMOTION, _STOP: _STATES.MC_AXISSTATE_STOPPING,
    _HOME: _STATES.MC_AXISSTATE_HOMING, _GEAR: _STATES.MC_AXISSTATE_SYNCHRONIZEDMOTION,
}
#: The master each geared slave follows (MC_GearIn), by the slave's address: a VAR_IN_OUT hands a block a
#: view of the axis, a new Python object at each access, so only the address names the axis.
_masters: dict[int, AXIS_REF] = {}


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
        status.SynchronizedMotion = state == _STATES.MC_AXISSTATE_SYNCHRONIZEDMOTION
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
        self._sync()
        self.Sim.Lag = float(lag)
        self.NcToPlc.ActPos = self.NcToPlc.SetPos - self.Sim.Lag
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
        if now <= sim.LastNs:
            return  # this instant is done (or a clock behind the axis' own time: the axis does not go back)
        sim.LastNs = now
        sim.CycleCounter += 1
        if sim.ActiveKind == _GEAR:
            self._follow()
        elif sim.Running:
            self._advance(now)
        self._apply_enable()
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
        if self._crossed_limit(sample.position, sample.velocity):
            return
        if not ended:
            return
        if sim.ProfileEndless:
            sim.InVelocity = True
            return
        self._end_profile(sample.position)
        self._finish_active()

    def _crossed_limit(self, position: float, velocity: float) -> bool:
        """A set position moving past an enabled software limit: ErrorStop (0x4462 / 0x4463)."""
        p = self.Parameters
        if self.Sim.State == _STATES.MC_AXISSTATE_ERRORSTOP:
            return False
        if p.EnableLimitPos and position > p.SWLimitPos and velocity > 0.0:
            self._fault(ERR_SOFT_MAX_MOVING, immediate=False)
            return True
        if p.EnableLimitNeg and position < p.SWLimitNeg and velocity < 0.0:
            self._fault(ERR_SOFT_MIN_MOVING, immediate=False)
            return True
        return False

    def _follow(self) -> None:
        """A geared slave: the master's set position (this instant) times the ratio, from where both were coupled."""
        sim, nc = self.Sim, self.NcToPlc
        master = _masters.get(int(adr(self)))
        if master is None:
            return
        master._sync()
        source = master.NcToPlc
        nc.SetPos = sim.GearSlaveStart + sim.GearRatio * (source.SetPos - sim.GearMasterStart)
        nc.SetVelo, nc.SetAcc = sim.GearRatio * source.SetVelo, sim.GearRatio * source.SetAcc
        nc.ActPos = nc.SetPos - sim.Lag
        nc.ActVelo, nc.ActAcc = nc.SetVelo, nc.SetAcc
        self._crossed_limit(nc.SetPos, nc.SetVelo)

    def _gear_in(self, master: AXIS_REF, ratio: float) -> tuple[int, int]:
        """MC_GearIn: couple this axis (the slave, at standstill) to ``master`` (at standstill) with ``ratio``."""
        if master is self or not math.isfinite(ratio):
            return 0, ERR_PARAMETER
        master._sync()
        # Tc2_MC2's MC_GearIn couples at standstill only; it cannot synchronize to a moving master.
        if self.Sim.State != _STATES.MC_AXISSTATE_STANDSTILL or master.NcToPlc.SetVelo != 0.0:
            return 0, ERR_CANNOT_START
        sim = self.Sim
        self._abort_commands()
        sim.NextCmd += 1
        sim.ActiveCmd, sim.ActiveKind = sim.NextCmd, _GEAR
        sim.State = _STATES.MC_AXISSTATE_SYNCHRONIZEDMOTION
        sim.GearRatio, sim.GearMasterStart, sim.GearSlaveStart = ratio, master.NcToPlc.SetPos, self.NcToPlc.SetPos
        sim.InVelocity, sim.HasTarget = True, False  # InGear at once
        _masters[int(adr(self))] = master
        self._publish()
        return sim.ActiveCmd, 0

    def _gear_out(self) -> int:
        """MC_GearOut: decouple; a moving slave keeps its velocity (ContinuousMotion) until MC_Stop / MC_Halt. 0 or an error."""
        sim, nc = self.Sim, self.NcToPlc
        if sim.ActiveKind != _GEAR:
            return ERR_NOT_PERMITTED
        self._record(sim.ActiveCmd, 0)
        sim.ActiveCmd = sim.ActiveKind = 0
        sim.InVelocity = False
        _masters.pop(int(adr(self)), None)
        velocity = nc.SetVelo
        if velocity == 0.0:
            self._end_profile(nc.SetPos)
            sim.State = _STATES.MC_AXISSTATE_STANDSTILL
            self._publish()
            return 0
        sim.NextCmd += 1
        self._begin(sim.NextCmd, _VELOCITY, velocity, abs(velocity), self.Parameters.Acceleration,
                    self.Parameters.Deceleration)
        return 0

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
        if sim.ActiveKind == _GEAR:
            _masters.pop(int(adr(self)), None)
        for cmd in (sim.ActiveCmd, sim.PendingCmd):
            if cmd:
                self._record(cmd, _ABORTED_CODE)
        sim.ActiveCmd = sim.ActiveKind = sim.PendingCmd = sim.PendingKind = 0
        sim.InVelocity = False

    def _fault(self, error_id: int, *, immediate: bool) -> None:
        """ErrorStop with ``error_id``: the running command fails with it, a buffered one is aborted."""
        sim, nc = self.Sim, self.NcToPlc
        if sim.ActiveKind == _GEAR:
            _masters.pop(int(adr(self)), None)
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
        act_turns = math.floor(nc.ActPos / modulo)
        set_turns = math.floor(nc.SetPos / modulo)
        nc.ModuloActPos = nc.ActPos - act_turns * modulo
        nc.ModuloSetPos = nc.SetPos - set_turns * modulo
        nc.ModuloActTurns = _dint(act_turns)
        nc.ModuloSetTurns = _dint(set_turns)
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
        """MC_Reset: leave ErrorStop (to Standstill when enabled, else Disabled); also lifts MC_Stop's lock."""
        sim = self.Sim
        if sim.StopLocked:
            sim.StopLocked = False
            if sim.State == _STATES.MC_AXISSTATE_STOPPING and not sim.Running:
                sim.State = _STATES.MC_AXISSTATE_STANDSTILL
        if sim.State != _STATES.MC_AXISSTATE_ERRORSTOP:
            self._publish()
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
