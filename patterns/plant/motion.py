"""A servo axis behind PLCopen motion blocks, simulated: ``AXIS_REF``, the motion kernel and MC_* blocks.

Each command is an Execute edge followed by Busy, then Done (or InVelocity)
or Error, several cycles later, as PLCopen *Function blocks for motion
control* Part 1 describes; the kernel ramps the velocity and trips on demand.
"""

from __future__ import annotations

from iecoop import BOOL, LREAL, PROTECTED, UDINT, VAR, VAR_IN_OUT, VAR_INPUT, VAR_OUTPUT, FunctionBlock, Struct, T, method
from iecoop.runtime import now_ms
from iecoop.stdlib import R_TRIG, TON
from patterns.plant.functions import ramp

__all__ = [
    "ERR_AXIS_NOT_READY", "ERR_DRIVE_TRIP", "ERR_VELOCITY_RANGE", "AxisRef", "AxisSim", "MC_MoveVelocity",
    "MC_Power", "MC_Reset", "MC_Stop",
]

# Simulated error IDs of the motion blocks (ErrorID : UDINT).
ERR_AXIS_NOT_READY = 0x4221
ERR_VELOCITY_RANGE = 0x4358
ERR_DRIVE_TRIP = 0x4550


class AxisRef(Struct):
    """Stands in for ``AXIS_REF``: the commands the motion blocks post and the state the axis reports."""

    cmd_power: BOOL = False
    cmd_move: BOOL = False
    cmd_stop: BOOL = False
    cmd_reset: BOOL = False
    cmd_velocity: LREAL = 0.0
    command: UDINT = 0
    powered: BOOL = False
    act_velocity: LREAL = 0.0
    error: BOOL = False
    error_id: UDINT = 0
    max_velocity: LREAL = 3000.0
    accel: LREAL = 6000.0


class AxisSim(FunctionBlock):
    """The motion kernel's side: ``FUNCTION_BLOCK FB_AxisSim`` (``VAR_IN_OUT Axis : AXIS_REF``).

    The power stage is ready 30 ms after enable; the velocity ramps at
    ``Axis.accel`` rpm/s. ``trip`` raises a drive error that MC_Reset clears
    once ``trip`` is gone.
    """

    Axis: AxisRef = VAR_IN_OUT()
    trip: BOOL = VAR_INPUT(False)
    power_on: TON = VAR()
    last_ms: UDINT = VAR(0)

    def body(self) -> None:
        axis = self.Axis
        now = now_ms()
        step = axis.accel * (now - self.last_ms) / 1000.0
        self.last_ms = now
        if self.trip and not axis.error:
            axis.error = True
            axis.error_id = ERR_DRIVE_TRIP
        if axis.cmd_reset and axis.error and not self.trip:
            axis.error = False
            axis.error_id = 0
        self.power_on(IN=axis.cmd_power and not axis.error, PT=T("30ms"))
        axis.powered = self.power_on.Q
        if axis.error or not axis.powered:
            axis.cmd_move = False
            axis.act_velocity = 0.0
            return
        target = axis.cmd_velocity if axis.cmd_move and not axis.cmd_stop else 0.0
        axis.act_velocity = ramp(axis.act_velocity, target, step)


class MC_Power(FunctionBlock):
    """PLCopen ``MC_Power`` (level-triggered): ``Status`` follows the power stage."""

    Axis: AxisRef = VAR_IN_OUT()
    Enable: BOOL = VAR_INPUT(False)
    Status: BOOL = VAR_OUTPUT(False)
    Error: BOOL = VAR_OUTPUT(False)
    ErrorID: UDINT = VAR_OUTPUT(0)

    def body(self) -> None:
        self.Axis.cmd_power = self.Enable
        self.Status = self.Enable and self.Axis.powered
        self.Error = self.Enable and self.Axis.error
        self.ErrorID = self.Axis.error_id if self.Error else 0


class MC_MoveVelocity(FunctionBlock):
    """PLCopen ``MC_MoveVelocity``: an Execute edge starts the move; Busy until aborted or failed.

    ``InVelocity`` is the Done of a continuous move. A later command on the
    same axis (another move, MC_Stop) sets ``CommandAborted``. Error and
    CommandAborted are held while Execute is TRUE.
    """

    Axis: AxisRef = VAR_IN_OUT()
    Execute: BOOL = VAR_INPUT(False)
    Velocity: LREAL = VAR_INPUT(0.0)
    InVelocity: BOOL = VAR_OUTPUT(False)
    Busy: BOOL = VAR_OUTPUT(False)
    CommandAborted: BOOL = VAR_OUTPUT(False)
    Error: BOOL = VAR_OUTPUT(False)
    ErrorID: UDINT = VAR_OUTPUT(0)
    edge: R_TRIG = VAR()
    my_command: UDINT = VAR(0)

    def body(self) -> None:
        axis = self.Axis
        self.edge(CLK=self.Execute)
        if self.edge.Q:
            self.InVelocity = self.CommandAborted = self.Error = False
            self.ErrorID = 0
            if not axis.powered or axis.error or axis.cmd_stop:
                self.fail(ERR_AXIS_NOT_READY)
            elif abs(self.Velocity) > axis.max_velocity:
                self.fail(ERR_VELOCITY_RANGE)
            else:
                axis.command += 1
                self.my_command = axis.command
                axis.cmd_velocity = self.Velocity
                axis.cmd_move = True
                self.Busy = True
        if self.Busy:
            if axis.error:
                self.fail(axis.error_id)
            elif axis.command != self.my_command:
                self.Busy = False
                self.InVelocity = False
                self.CommandAborted = True
            else:
                self.InVelocity = abs(axis.act_velocity - axis.cmd_velocity) < 1.0
        if not self.Execute and not self.Busy:
            self.InVelocity = self.CommandAborted = self.Error = False
            self.ErrorID = 0

    @method(PROTECTED)
    def fail(self, error_id: UDINT) -> None:
        self.Busy = False
        self.InVelocity = False
        self.Error = True
        self.ErrorID = error_id


class MC_Stop(FunctionBlock):
    """PLCopen ``MC_Stop``: decelerate to standstill; Done at zero velocity.

    While Execute stays TRUE the axis is held in Stopping and refuses moves.
    """

    Axis: AxisRef = VAR_IN_OUT()
    Execute: BOOL = VAR_INPUT(False)
    Done: BOOL = VAR_OUTPUT(False)
    Busy: BOOL = VAR_OUTPUT(False)
    Error: BOOL = VAR_OUTPUT(False)
    ErrorID: UDINT = VAR_OUTPUT(0)
    edge: R_TRIG = VAR()
    holding: BOOL = VAR(False)

    def body(self) -> None:
        axis = self.Axis
        self.edge(CLK=self.Execute)
        if self.edge.Q:
            self.Done = self.Error = False
            self.ErrorID = 0
            axis.command += 1
            axis.cmd_stop = True
            axis.cmd_move = False
            self.holding = True
            self.Busy = True
        if self.Busy:
            if axis.error:
                self.Busy = False
                self.Error = True
                self.ErrorID = axis.error_id
            elif axis.act_velocity == 0.0:
                self.Busy = False
                self.Done = True
        if not self.Execute:
            if self.holding and not self.Busy:
                axis.cmd_stop = False
                self.holding = False
            if not self.Busy:
                self.Done = self.Error = False
                self.ErrorID = 0


class MC_Reset(FunctionBlock):
    """PLCopen ``MC_Reset``: clear an axis error; Done once the axis reports none."""

    Axis: AxisRef = VAR_IN_OUT()
    Execute: BOOL = VAR_INPUT(False)
    Done: BOOL = VAR_OUTPUT(False)
    Busy: BOOL = VAR_OUTPUT(False)
    Error: BOOL = VAR_OUTPUT(False)
    edge: R_TRIG = VAR()

    def body(self) -> None:
        self.edge(CLK=self.Execute)
        if self.edge.Q:
            self.Done = self.Error = False
            self.Axis.cmd_reset = True
            self.Busy = True
        elif self.Busy and not self.Axis.error:
            self.Axis.cmd_reset = False
            self.Busy = False
            self.Done = True
        if not self.Execute and not self.Busy:
            self.Done = False
