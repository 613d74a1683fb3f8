"""Tc2_MC2's simulated axis, driven by a PROGRAM on a 10 ms task, against hand-worked profiles.

Unless a test says otherwise the axis has MaxVelocity 100, Acceleration and
Deceleration 1000 (units/s, units/s^2). A command given in cycle 0 (task
time 0) moves the axis from cycle 1 on; cycle k is task time 10 k ms. So a
move from rest reaches ``500 t^2`` after ``t`` seconds of acceleration.
"""

from __future__ import annotations

import math
import pathlib
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import BOOL, LREAL, VAR, VAR_INPUT, Program, T
from iecoop.libraries import _motion
from iecoop.libraries.tc2_mc2 import (
    AXIS_REF,
    E_JogMode,
    MC_AxisParameter,
    MC_AxisStates,
    MC_BufferMode,
    MC_Direction,
    MC_Halt,
    MC_Home,
    MC_HomingMode,
    MC_Jog,
    MC_MoveAbsolute,
    MC_MoveModulo,
    MC_MoveRelative,
    MC_MoveVelocity,
    MC_Power,
    MC_ReadActualPosition,
    MC_ReadActualVelocity,
    MC_ReadAxisError,
    MC_ReadParameter,
    MC_ReadStatus,
    MC_Reset,
    MC_SetPosition,
    MC_Stop,
)
from iecoop.runtime import Runtime, Task
from iecoop.runtime.clock import VirtualClock, use_clock

S = MC_AxisStates


class Cell(Program):
    """One axis and one instance of each MC block; the test drives their inputs between cycles."""

    axis: AXIS_REF = VAR()
    power: MC_Power = VAR()
    move: MC_MoveAbsolute = VAR()
    move2: MC_MoveAbsolute = VAR()
    rel: MC_MoveRelative = VAR()
    modulo: MC_MoveModulo = VAR()
    velo: MC_MoveVelocity = VAR()
    halt: MC_Halt = VAR()
    stop: MC_Stop = VAR()
    reset: MC_Reset = VAR()
    home: MC_Home = VAR()
    setpos: MC_SetPosition = VAR()
    jog: MC_Jog = VAR()
    read_pos: MC_ReadActualPosition = VAR()
    read_velo: MC_ReadActualVelocity = VAR()
    read_error: MC_ReadAxisError = VAR()
    read_status: MC_ReadStatus = VAR()
    read_param: MC_ReadParameter = VAR()

    enable: BOOL = VAR_INPUT(True)
    do_move: BOOL = VAR_INPUT(False)
    do_move2: BOOL = VAR_INPUT(False)
    do_rel: BOOL = VAR_INPUT(False)
    do_modulo: BOOL = VAR_INPUT(False)
    do_velo: BOOL = VAR_INPUT(False)
    do_halt: BOOL = VAR_INPUT(False)
    do_stop: BOOL = VAR_INPUT(False)
    do_reset: BOOL = VAR_INPUT(False)
    do_home: BOOL = VAR_INPUT(False)
    do_setpos: BOOL = VAR_INPUT(False)
    jog_forward: BOOL = VAR_INPUT(False)
    jog_backwards: BOOL = VAR_INPUT(False)
    cam: BOOL = VAR_INPUT(False)
    target: LREAL = VAR_INPUT(0.0)
    target2: LREAL = VAR_INPUT(0.0)
    velocity: LREAL = VAR_INPUT(100.0)
    distance: LREAL = VAR_INPUT(0.0)
    set_to: LREAL = VAR_INPUT(0.0)
    relative_set: BOOL = VAR_INPUT(False)
    direction: MC_Direction = VAR_INPUT(MC_Direction.MC_Positive_Direction)
    buffer_mode: MC_BufferMode = VAR_INPUT(MC_BufferMode.MC_Aborting)
    homing_mode: MC_HomingMode = VAR_INPUT(MC_HomingMode.MC_DefaultHoming)
    jog_mode: E_JogMode = VAR_INPUT(E_JogMode.MC_JOGMODE_STANDARD_SLOW)
    parameter: MC_AxisParameter = VAR_INPUT(MC_AxisParameter.AxisMaxVelocity)

    def body(self) -> None:
        axis = self.axis
        self.power(Axis=axis, Enable=self.enable, Enable_Positive=True, Enable_Negative=True)
        self.move(Axis=axis, Execute=self.do_move, Position=self.target, Velocity=self.velocity)
        self.move2(Axis=axis, Execute=self.do_move2, Position=self.target2, Velocity=self.velocity,
                   BufferMode=self.buffer_mode)
        self.rel(Axis=axis, Execute=self.do_rel, Distance=self.distance, Velocity=self.velocity)
        self.modulo(Axis=axis, Execute=self.do_modulo, Position=self.target, Velocity=self.velocity,
                    Direction=self.direction)
        self.velo(Axis=axis, Execute=self.do_velo, Velocity=self.velocity, Direction=self.direction)
        self.halt(Axis=axis, Execute=self.do_halt)
        self.stop(Axis=axis, Execute=self.do_stop)
        self.reset(Axis=axis, Execute=self.do_reset)
        self.home(Axis=axis, Execute=self.do_home, Position=self.set_to, HomingMode=self.homing_mode,
                  bCalibrationCam=self.cam)
        self.setpos(Axis=axis, Execute=self.do_setpos, Position=self.set_to, Mode=self.relative_set)
        self.jog(Axis=axis, JogForward=self.jog_forward, JogBackwards=self.jog_backwards, Mode=self.jog_mode)
        self.read_pos(Axis=axis, Enable=True)
        self.read_velo(Axis=axis, Enable=True)
        self.read_error(Axis=axis, Enable=True)
        self.read_status(Axis=axis, Enable=True)
        self.read_param(Axis=axis, Enable=True, ParameterNumber=self.parameter)


class Rig:
    """A Cell on a 10 ms task; ``cycle()`` runs one cycle and returns (SetPos, SetVelo) after it."""

    def __init__(self, **configure: Any) -> None:
        self.cell = Cell()
        self.axis = self.cell.axis
        self.axis.configure(**{"max_velocity": 100.0, "acceleration": 1000.0, "deceleration": 1000.0, **configure})
        self.runtime = Runtime(store=":memory:")
        self.runtime.add_task(Task("PlcTask", interval=T("10ms")), self.cell)

    def cycle(self, count: int = 1) -> tuple[float, float]:
        self.runtime.run(cycles=count)
        return self.axis.NcToPlc.SetPos, self.axis.NcToPlc.SetVelo

    def trace(self, count: int) -> list[tuple[float, float]]:
        return [self.cycle() for _ in range(count)]

    @property
    def state(self) -> int:
        return int(self.axis.Sim.State)


def pins(block: object, *names: str) -> dict[str, object]:
    """The named outputs of ``block`` (read afresh: a type checker does not carry an earlier value over)."""
    return {name: getattr(block, name) for name in names}


class approx:  # noqa: N801 - reads like pytest.approx
    """``approx(trace) == [(position, velocity), ...]``, each value within 1e-9."""

    def __init__(self, values: list[tuple[float, float]]) -> None:
        self.values = [value for pair in values for value in pair]

    def __eq__(self, other: object) -> bool:
        assert isinstance(other, list)
        return [value for pair in other for value in pair] == pytest.approx(self.values, abs=1e-9)

    def __repr__(self) -> str:
        return repr(self.values)


def test_move_absolute_trapezoid_accelerates_cruises_and_brakes_onto_the_target() -> None:
    rig = Rig()
    rig.cell.target, rig.cell.do_move = 100.0, True
    rig.cycle()  # cycle 0: power on, the move starts
    assert rig.state == S.MC_AXISSTATE_DISCRETEMOTION
    assert pins(rig.cell.move, "Busy", "Active", "Done") == {"Busy": True, "Active": True, "Done": False}
    trace = rig.trace(110)  # cycles 1..110
    # Acceleration 0.1 s to 100 (5 units), cruise 0.9 s (90 units), braking 0.1 s (5 units).
    assert approx([trace[k - 1] for k in (1, 2, 5, 10, 20, 100, 105, 109)]) == [
        (0.05, 10.0), (0.2, 20.0), (1.25, 50.0), (5.0, 100.0), (15.0, 100.0), (95.0, 100.0), (98.75, 50.0),
        (99.95, 10.0),
    ]
    assert trace[109] == (100.0, 0.0)
    assert pins(rig.cell.move, "Done", "Busy", "Active") == {"Done": True, "Busy": False, "Active": False}
    assert rig.state == S.MC_AXISSTATE_STANDSTILL
    assert rig.axis.NcToPlc.ActPos == 100.0 and rig.axis.NcToPlc.PosDiff == 0.0


def test_move_absolute_triangle_when_the_distance_is_too_short_for_the_velocity() -> None:
    rig = Rig()
    rig.cell.target, rig.cell.do_move = 2.5, True
    rig.cycle()
    trace = rig.trace(10)
    # The ramps meet at 50 after 0.05 s: never at the commanded 100.
    assert approx(trace) == [
        (0.05, 10.0), (0.2, 20.0), (0.45, 30.0), (0.8, 40.0), (1.25, 50.0),
        (1.7, 40.0), (2.05, 30.0), (2.3, 20.0), (2.45, 10.0), (2.5, 0.0),
    ]
    assert rig.cell.move.Done


def test_move_relative_moves_by_the_distance_from_where_the_axis_stands() -> None:
    rig = Rig()
    rig.cell.target, rig.cell.do_move = 2.5, True
    rig.cycle(11)
    rig.cell.distance, rig.cell.do_rel = -2.5, True
    rig.cycle()
    trace = rig.trace(10)
    assert approx([trace[k] for k in (0, 4, 9)]) == [(2.45, -10.0), (1.25, -50.0), (0.0, 0.0)]
    assert pins(rig.cell.rel, "Done", "Busy") == {"Done": True, "Busy": False}


def test_move_velocity_reaches_in_velocity_and_halt_brakes_it_to_standstill() -> None:
    rig = Rig()
    rig.cell.velocity, rig.cell.do_velo = 50.0, True
    rig.cycle()
    assert rig.state == S.MC_AXISSTATE_CONTINOUSMOTION
    trace = rig.trace(5)
    assert approx(trace[-1:]) == [(1.25, 50.0)]
    assert pins(rig.cell.velo, "InVelocity", "Busy", "Active") == {"InVelocity": True, "Busy": True, "Active": True}
    trace = rig.trace(5)  # cycles 6..10 at 50 units/s
    assert approx(trace[-1:]) == [(3.75, 50.0)]
    rig.cell.do_halt = True  # cycle 11 commands the halt
    rig.cycle()
    assert rig.state == S.MC_AXISSTATE_DISCRETEMOTION
    assert rig.cell.halt.Busy
    trace = rig.trace(5)
    # 50 -> 0 at 1000 units/s^2: 0.05 s and 1.25 units.
    assert approx([trace[0], trace[-1]]) == [(4.25 + 0.45, 40.0), (4.25 + 1.25, 0.0)]
    assert rig.cell.halt.Done
    assert pins(rig.cell.velo, "CommandAborted", "Busy", "InVelocity") == {"CommandAborted": True, "Busy": False, "InVelocity": False}
    assert rig.state == S.MC_AXISSTATE_STANDSTILL


def test_a_second_move_aborts_the_first_brakes_reverses_and_reaches_its_own_target() -> None:
    rig = Rig()
    rig.cell.target, rig.cell.do_move = 100.0, True
    rig.cycle(21)  # cycles 0..20: at 15.0, cruising at 100
    assert rig.axis.NcToPlc.SetPos == pytest.approx(15.0)
    rig.cell.target2, rig.cell.do_move2 = 10.0, True  # cycle 21 (t = 0.21 s, at 16.0)
    rig.cycle()
    assert pins(rig.cell.move2, "Busy", "Active") == {"Busy": True, "Active": True}
    # The first move's block is called before the second's: it sees the abort at its next call.
    assert pins(rig.cell.move, "Busy", "CommandAborted") == {"Busy": True, "CommandAborted": False}
    trace = rig.trace(30)  # cycles 22..51
    assert pins(rig.cell.move, "CommandAborted", "Busy", "Done") == {"CommandAborted": True, "Busy": False, "Done": False}
    # Braking 100 -> 0 takes 0.1 s and 5 units (stop at 21.0, cycle 31); back 11 units from rest: peak
    # 100, 0.21 s, arrival at cycle 52.
    assert approx([trace[4], trace[9]]) == [(19.75, 50.0), (21.0, 0.0)]
    assert trace[-1][0] > 10.0
    assert approx([rig.cycle()]) == [(10.0, 0.0)]
    assert rig.cell.move2.Done and not rig.cell.move.Done
    assert rig.cell.move.CommandAborted  # held while its Execute stays TRUE


def test_mc_stop_holds_the_axis_in_stopping_and_refuses_moves_until_execute_falls() -> None:
    rig = Rig()
    rig.cell.velocity, rig.cell.do_velo = 50.0, True
    rig.cycle(11)
    rig.cell.do_stop = True
    rig.cycle()
    assert rig.state == S.MC_AXISSTATE_STOPPING
    trace = rig.trace(5)
    assert trace[-1][1] == 0.0 and rig.cell.stop.Done
    assert rig.state == S.MC_AXISSTATE_STOPPING  # Execute still TRUE
    rig.cell.target, rig.cell.do_move = 0.0, True
    rig.cycle()
    assert rig.cell.move.Error and rig.cell.move.ErrorID == 0x4B01 and not rig.cell.move.Busy
    assert rig.axis.NcToPlc.SetVelo == 0.0
    rig.cell.do_stop, rig.cell.do_move = False, False
    rig.cycle()
    assert rig.state == S.MC_AXISSTATE_STANDSTILL
    assert pins(rig.cell.stop, "Done") == {"Done": False}
    assert pins(rig.cell.move, "Error", "ErrorID") == {"Error": False, "ErrorID": 0}
    rig.cell.do_move = True
    rig.cycle()
    assert pins(rig.cell.move, "Busy") == {"Busy": True}
    assert rig.state == S.MC_AXISSTATE_DISCRETEMOTION


def test_reset_lifts_the_lock_of_mc_stop() -> None:
    rig = Rig()
    rig.cell.do_stop = True
    rig.cycle(2)
    assert rig.state == S.MC_AXISSTATE_STOPPING and rig.axis.Sim.StopLocked
    rig.cell.do_reset = True
    rig.cycle()
    assert rig.state == S.MC_AXISSTATE_STANDSTILL
    rig.cell.target, rig.cell.do_move = 1.0, True
    rig.cycle()
    assert pins(rig.cell.move, "Busy", "Error") == {"Busy": True, "Error": False}


def test_power_off_during_motion_stops_the_axis_disables_it_and_aborts_the_move() -> None:
    rig = Rig()
    rig.cell.target, rig.cell.do_move = 100.0, True
    rig.cycle(21)
    rig.cell.enable = False  # cycle 21: at 16.0 the controller enable drops
    assert approx([rig.cycle()]) == [(16.0, 0.0)]
    assert rig.state == S.MC_AXISSTATE_DISABLED
    assert not rig.cell.power.Status
    assert pins(rig.cell.move, "CommandAborted", "Busy") == {"CommandAborted": True, "Busy": False}
    assert approx([rig.cycle(5)]) == [(16.0, 0.0)]
    rig.cell.do_move = False
    rig.cycle()
    rig.cell.do_move = True
    rig.cycle()
    assert rig.cell.move.Error and rig.cell.move.ErrorID == 0x4B01


def test_reset_leaves_error_stop_after_an_injected_fault() -> None:
    rig = Rig()
    rig.cycle()
    rig.axis.inject_fault(0x4650)
    rig.cycle()
    assert rig.state == S.MC_AXISSTATE_ERRORSTOP
    assert rig.cell.read_error.AxisErrorID == 0x4650 and rig.cell.read_status.ErrorStop
    assert not rig.cell.power.Status
    rig.cell.target, rig.cell.do_move = 10.0, True
    rig.cycle()
    assert rig.cell.move.Error and rig.cell.move.ErrorID == 0x4B01
    rig.cell.do_reset, rig.cell.do_move = True, False
    rig.cycle()
    assert rig.cell.reset.Done and rig.state == S.MC_AXISSTATE_STANDSTILL
    assert rig.axis.NcToPlc.ErrorCode == 0
    rig.cycle()  # MC_Power is called before MC_Reset: its Status comes back a cycle later
    assert pins(rig.cell.power, "Status") == {"Status": True}
    rig.cell.do_move = True
    rig.cycle(12)
    assert rig.cell.move.Busy and rig.axis.NcToPlc.SetPos > 0.0


def test_a_target_beyond_the_software_limit_is_refused_with_the_nc_start_code() -> None:
    rig = Rig(soft_limit_max=50.0, soft_limit_min=-5.0)
    rig.cell.target, rig.cell.do_move = 60.0, True
    rig.cycle()
    assert rig.cell.move.Error and rig.cell.move.ErrorID == 0x4461
    assert rig.state == S.MC_AXISSTATE_ERRORSTOP and rig.axis.NcToPlc.ErrorCode == 0x4461
    assert rig.axis.NcToPlc.SetPos == 0.0
    rig.cell.do_move, rig.cell.do_reset = False, True
    rig.cycle()
    rig.cell.target, rig.cell.do_move = -6.0, True
    rig.cycle()
    assert rig.cell.move.ErrorID == 0x4460


def test_crossing_the_software_limit_during_a_velocity_move_stops_the_axis_in_error_stop() -> None:
    rig = Rig(soft_limit_max=20.0)
    rig.cell.do_velo = True
    rig.cycle()
    trace = rig.trace(25)  # 5 units of acceleration, then 1 unit a cycle: 20.0 at cycle 25
    assert approx(trace[-1:]) == [(20.0, 100.0)]
    assert rig.state == S.MC_AXISSTATE_CONTINOUSMOTION
    rig.cycle()  # cycle 26: 21.0 is beyond the limit
    assert rig.state == S.MC_AXISSTATE_ERRORSTOP
    assert rig.cell.velo.Error and rig.cell.velo.ErrorID == 0x4463
    trace = rig.trace(10)
    # The axis brakes with its deceleration from where the fault was seen: 5 units in 0.1 s.
    assert approx(trace[-1:]) == [(26.0, 0.0)]
    assert rig.axis.NcToPlc.ErrorCode == 0x4463


def test_a_position_lag_beyond_the_maximum_stops_the_axis_at_once_with_0x4550() -> None:
    rig = Rig(max_position_lag=5.0)
    rig.cell.do_velo = True
    rig.cycle(11)
    rig.axis.simulate_position_lag(4.0)
    assert rig.axis.NcToPlc.PosDiff == pytest.approx(4.0)  # at once, not only from the next cycle
    rig.cycle()
    assert rig.axis.NcToPlc.PosDiff == pytest.approx(4.0) and rig.state == S.MC_AXISSTATE_CONTINOUSMOTION
    rig.axis.simulate_position_lag(6.0)
    assert rig.state == S.MC_AXISSTATE_ERRORSTOP and rig.axis.NcToPlc.SetVelo == 0.0
    assert rig.axis.NcToPlc.PosDiff == pytest.approx(6.0)
    rig.cycle()
    assert rig.cell.velo.Error and rig.cell.velo.ErrorID == 0x4550
    assert rig.cell.read_error.AxisErrorID == 0x4550


def test_default_homing_moves_to_the_cam_and_takes_the_home_position() -> None:
    rig = Rig(calibration_velocity=10.0)
    rig.cell.set_to, rig.cell.do_home = 5.0, True
    rig.cycle()
    assert rig.state == S.MC_AXISSTATE_HOMING and rig.cell.home.Busy
    trace = rig.trace(10)
    # Towards the cam (negative) at the calibration velocity: 0.05 units of ramp, then 0.1 a cycle.
    assert approx(trace[-1:]) == [(-0.95, -10.0)]
    rig.cell.target, rig.cell.do_move = 0.0, True
    rig.cycle()
    assert rig.cell.move.Error and rig.cell.move.ErrorID == 0x4B01  # no move while homing
    rig.cell.cam = True
    rig.cycle()
    assert rig.cell.home.Done and rig.axis.Sim.Homed
    assert rig.axis.NcToPlc.ActPos == 5.0 and rig.axis.NcToPlc.SetVelo == 0.0
    assert rig.state == S.MC_AXISSTATE_STANDSTILL
    assert rig.axis.NcToPlc.StateDWord & 0b10  # Homed


def test_homing_modes_without_motion() -> None:
    rig = Rig()
    rig.cell.homing_mode, rig.cell.set_to, rig.cell.do_home = MC_HomingMode.MC_Direct, 42.0, True
    rig.cycle()
    assert rig.cell.home.Done and rig.axis.Sim.Homed and rig.axis.NcToPlc.ActPos == 42.0
    rig.cell.do_home = False
    rig.cycle()
    assert pins(rig.cell.home, "Done") == {"Done": False}
    rig.cell.homing_mode, rig.cell.do_home = MC_HomingMode.MC_ResetCalibration, True
    rig.cycle()
    assert rig.cell.home.Done and not rig.axis.Sim.Homed


def test_set_position_moves_the_coordinates_not_the_axis() -> None:
    rig = Rig()
    rig.cell.target, rig.cell.do_move = 2.5, True
    rig.cycle(11)
    rig.cell.set_to, rig.cell.do_setpos = 100.0, True
    rig.cycle()
    assert rig.cell.setpos.Done
    assert (rig.axis.NcToPlc.ActPos, rig.axis.NcToPlc.SetPos, rig.axis.NcToPlc.SetVelo) == (100.0, 100.0, 0.0)
    rig.cell.do_setpos = False
    rig.cycle()
    rig.cell.set_to, rig.cell.relative_set, rig.cell.do_setpos = -10.0, True, True
    rig.cycle()
    assert rig.axis.NcToPlc.ActPos == 90.0
    rig.cell.distance, rig.cell.do_rel = 2.5, True
    rig.cycle(11)
    assert rig.axis.NcToPlc.SetPos == pytest.approx(92.5) and rig.cell.rel.Done


def test_jog_moves_while_the_button_is_held_and_brakes_when_released() -> None:
    rig = Rig(manual_velocity_slow=20.0)
    rig.cell.jog_forward = True
    rig.cycle()
    assert rig.state == S.MC_AXISSTATE_CONTINOUSMOTION and rig.cell.jog.Busy
    trace = rig.trace(9)
    assert approx([trace[1], trace[8]]) == [(0.2, 20.0), (1.6, 20.0)]
    rig.cell.jog_forward = False  # cycle 10, at 1.8
    rig.cycle()
    trace = rig.trace(2)
    assert approx(trace[-1:]) == [(2.0, 0.0)]
    assert pins(rig.cell.jog, "Done", "Busy") == {"Done": True, "Busy": False}
    assert rig.state == S.MC_AXISSTATE_STANDSTILL
    rig.cycle()
    assert not rig.cell.jog.Done  # shown for one cycle: the button was already released


def test_done_is_shown_for_one_cycle_when_execute_fell_before_the_end() -> None:
    rig = Rig()
    rig.cell.target, rig.cell.do_move = 2.5, True
    rig.cycle(2)
    rig.cell.do_move = False
    rig.cycle(8)
    assert rig.cell.move.Busy and not rig.cell.move.Done  # the move goes on without Execute
    rig.cycle()
    assert pins(rig.cell.move, "Done", "Busy") == {"Done": True, "Busy": False}
    rig.cycle()
    assert not rig.cell.move.Done


def test_done_is_held_while_execute_stays_true_and_reset_when_it_falls() -> None:
    rig = Rig()
    rig.cell.target, rig.cell.do_move = 2.5, True
    rig.cycle(30)
    assert rig.cell.move.Done
    rig.cell.do_move = False
    rig.cycle()
    assert pins(rig.cell.move, "Done", "Busy") == {"Done": False, "Busy": False}


def test_buffered_move_starts_when_the_running_one_is_done() -> None:
    rig = Rig()
    rig.cell.target, rig.cell.do_move = 2.5, True
    rig.cycle()
    rig.cell.target2, rig.cell.buffer_mode, rig.cell.do_move2 = 0.0, MC_BufferMode.MC_Buffered, True
    rig.cycle()
    assert pins(rig.cell.move2, "Busy", "Active") == {"Busy": True, "Active": False}
    assert rig.cell.move.Active
    rig.cycle(9)  # the first move arrives at cycle 10
    assert pins(rig.cell.move, "Done") == {"Done": True}
    assert pins(rig.cell.move2, "Active") == {"Active": True}
    trace = rig.trace(10)
    assert approx(trace[-1:]) == [(0.0, 0.0)]
    assert rig.cell.move2.Done and not rig.cell.move.CommandAborted


def test_move_modulo_chooses_the_turn_by_direction() -> None:
    rig = Rig(max_velocity=1000.0, acceleration=100000.0, deceleration=100000.0)
    rig.cell.set_to, rig.cell.do_setpos = 350.0, True
    rig.cycle()
    results = []
    for direction in (MC_Direction.MC_Positive_Direction, MC_Direction.MC_Negative_Direction,
                      MC_Direction.MC_Shortest_Way):
        rig.cell.set_to, rig.cell.do_setpos = 350.0, True
        rig.cycle()
        rig.cell.do_setpos = False
        rig.cell.target, rig.cell.velocity, rig.cell.direction, rig.cell.do_modulo = 10.0, 1000.0, direction, True
        rig.cycle(60)
        assert rig.cell.modulo.Done
        results.append(rig.axis.NcToPlc.SetPos)
        assert rig.axis.NcToPlc.ModuloActPos == pytest.approx(10.0)
        rig.cell.do_modulo = False
        rig.cycle()
    assert results == pytest.approx([370.0, 10.0, 370.0])
    rig.cell.direction, rig.cell.do_modulo = MC_Direction.MC_Undefined_Direction, True
    rig.cycle()
    assert rig.cell.modulo.Error and rig.cell.modulo.ErrorID == 0x4B04


def test_refused_inputs_report_the_nc_plc_codes() -> None:
    rig = Rig()
    rig.cell.direction, rig.cell.do_velo = MC_Direction.MC_Shortest_Way, True
    rig.cycle()
    assert rig.cell.velo.Error and rig.cell.velo.ErrorID == 0x4B05
    rig.cell.velocity, rig.cell.do_move = 0.0, True
    rig.cycle()
    assert rig.cell.move.Error and rig.cell.move.ErrorID == 0x4B06
    rig.cell.power(Axis=rig.axis, Enable=True, Override=150.0)
    assert rig.cell.power.Error and rig.cell.power.ErrorID == 0x4B06


def test_readers_and_read_status_report_the_axis() -> None:
    rig = Rig()
    rig.cell.target, rig.cell.do_move = 100.0, True
    rig.cycle(6)
    assert rig.cell.read_pos.Valid and rig.cell.read_pos.Position == pytest.approx(1.25)
    assert rig.cell.read_velo.ActualVelocity == pytest.approx(50.0)
    status = rig.cell.read_status
    assert status.DiscreteMotion and status.Accelerating and not status.StandStill
    assert status.Status.MotionState == S.MC_AXISSTATE_DISCRETEMOTION and status.Status.Moving
    assert rig.axis.Status.HasJob and rig.axis.Status.PositiveDirection
    assert rig.cell.read_param.Value == 100.0
    rig.cell.parameter = MC_AxisParameter.AxisAcc
    rig.cycle()
    assert rig.cell.read_param.Value == 1000.0
    rig.cycle(120)
    assert rig.cell.read_status.StandStill and rig.axis.Status.InTargetPosition and rig.axis.Status.NotMoving
    assert rig.axis.NcToPlc.StateDWord & 0b11101 == 0b11101  # Operational, NotMoving, InPositionArea, InTarget


def test_read_parameter_answers_the_configured_values_and_refuses_an_unknown_number() -> None:
    rig = Rig(soft_limit_max=250.0, max_position_lag=2.5, target_position_window=0.1)
    expected = {
        MC_AxisParameter.SWLimitPos: 250.0, MC_AxisParameter.EnableLimitPos: 1.0,
        MC_AxisParameter.EnableLimitNeg: 0.0, MC_AxisParameter.MaxPositionLag: 2.5,
        MC_AxisParameter.AxisTargetPositionWindow: 0.1, MC_AxisParameter.MaxDecelerationAppl: 1000.0,
    }
    for number, value in expected.items():
        rig.cell.parameter = number
        rig.cycle()
        assert pins(rig.cell.read_param, "Valid", "Error", "Value") == {"Valid": True, "Error": False, "Value": value}
    rig.cell.read_param(Axis=rig.axis, Enable=True, ParameterNumber=MC_AxisParameter.AxisPositionRangeWindow)
    assert pins(rig.cell.read_param, "Valid", "Error", "ErrorID") == {"Valid": False, "Error": True, "ErrorID": 0x4B05}


def test_power_off_at_standstill_is_the_disabled_state() -> None:
    rig = Rig()
    rig.cycle()
    assert rig.cell.read_status.StandStill and rig.cell.power.Status
    rig.cell.enable = False
    rig.cycle(2)
    assert pins(rig.cell.read_status, "Disabled", "StandStill") == {"Disabled": True, "StandStill": False}
    assert rig.axis.NcToPlc.StateDWord & 1 == 0  # not Operational


def test_the_axis_is_integrated_once_per_cycle_however_many_blocks_call_it() -> None:
    rig = Rig()
    rig.cell.target, rig.cell.do_move = 100.0, True
    rig.cycle(6)
    before = (rig.axis.NcToPlc.SetPos, rig.axis.Sim.LastNs)
    assert before[0] == pytest.approx(1.25) and before[1] == 50_000_000
    with use_clock(VirtualClock(start_ns=rig.axis.Sim.LastNs)):  # more calls at the same task instant
        for _ in range(5):
            rig.cell.read_pos(Axis=rig.axis, Enable=True)
            rig.axis.ReadStatus()
    assert (rig.axis.NcToPlc.SetPos, rig.axis.Sim.LastNs) == before
    with use_clock(VirtualClock(start_ns=10_000_000)):  # an earlier instant: the axis does not go back
        rig.axis.ReadStatus()
    assert (rig.axis.NcToPlc.SetPos, rig.axis.Sim.LastNs) == before
    with use_clock(VirtualClock(start_ns=60_000_000)):
        rig.axis.ReadStatus()
        rig.axis.ReadStatus()
    assert rig.axis.NcToPlc.SetPos == pytest.approx(1.8)


def test_configure_rejects_a_non_positive_velocity() -> None:
    with pytest.raises(ValueError, match="MaxVelocity must be a positive number"):
        AXIS_REF().configure(max_velocity=0.0)
    with pytest.raises(ValueError, match="NC error code"):
        AXIS_REF().inject_fault(0)


# ---------------------------------------------------------------------------
# The profile, as a property
# ---------------------------------------------------------------------------

_position = st.floats(-1000.0, 1000.0, allow_nan=False)
_rate = st.floats(1.0, 10000.0, allow_nan=False)


@given(start=_position, target=_position, fraction=st.floats(-1.0, 1.0), vmax=_rate, acc=_rate, dec=_rate)
@settings(max_examples=300, deadline=None)
def test_a_move_keeps_its_limits_is_continuous_and_ends_on_the_target(
    start: float, target: float, fraction: float, vmax: float, acc: float, dec: float,
) -> None:
    velocity = fraction * vmax  # a move may start while the axis is moving, either way
    profile = _motion.plan_move(start, velocity, target, vmax, acc, dec)
    steps = 400
    dt = profile.duration / steps if profile.duration else 0.0
    previous = _motion.evaluate(profile, 0.0)[0]
    assert previous.position == pytest.approx(start, abs=1e-9)
    for step in range(1, steps + 1):
        sample, _ = _motion.evaluate(profile, step * dt)
        assert abs(sample.velocity) <= vmax * (1 + 1e-9) + 1e-9
        assert abs(sample.acceleration) <= max(acc, dec) * (1 + 1e-12)
        assert abs(sample.position - previous.position) <= vmax * dt * (1 + 1e-9) + 1e-6
        previous = sample
    final, ended = _motion.evaluate(profile, profile.duration + 1e-3)
    assert ended and final == (target, 0.0, 0.0)
    end = _motion.evaluate(profile, max(0.0, profile.duration - 1e-12))[0]
    assert end.position == pytest.approx(target, abs=1e-6 * max(1.0, abs(target)))
    assert math.isclose(end.velocity, 0.0, abs_tol=1e-6 * max(vmax, 1.0))


@given(distance=st.floats(-20.0, 20.0, allow_nan=False), velocity=st.floats(10.0, 200.0))
@settings(max_examples=25, deadline=None)
def test_the_simulated_axis_never_exceeds_its_limits_and_reaches_the_target(distance: float, velocity: float) -> None:
    rig = Rig()
    rig.cell.target, rig.cell.velocity, rig.cell.do_move = distance, velocity, True
    rig.cycle()
    previous = 0.0
    for _ in range(400):  # at most 2.2 s of motion
        position, speed = rig.cycle()
        assert abs(speed) <= min(velocity, 100.0) + 1e-9
        assert abs(position - previous) <= min(velocity, 100.0) * 0.01 + 1e-9
        previous = position
        if rig.cell.move.Done:
            break
    assert rig.cell.move.Done and rig.axis.NcToPlc.SetPos == pytest.approx(distance, abs=1e-9)


# ---------------------------------------------------------------------------
# A TwinCAT project that references Tc2_MC2
# ---------------------------------------------------------------------------

MOTION_CELL = pathlib.Path(__file__).parent / "data" / "MotionCell" / "MotionCell.plcproj"


def _motion_cell(**configure: Any) -> tuple[Any, Runtime]:
    from iecoop import st

    project = st.load(MOTION_CELL)
    main = project.MAIN
    main.Axis1.configure(max_velocity=100.0, acceleration=1000.0, deceleration=1000.0, **configure)
    runtime = Runtime(store=":memory:")
    runtime.add_task(Task("PlcTask", interval=T("10ms")), main)
    return main, runtime


def test_an_st_project_referencing_tc2_mc2_shuttles_its_axis_between_two_stations() -> None:
    main, runtime = _motion_cell()
    trace = []
    for _ in range(26):
        runtime.run(cycles=1)
        trace.append((main.fActPos, main.fSetVelo))
    # Cycles 0-2: the TON delays the enable; 3: Status shows StandStill; 4: the move to 2.5 starts;
    # 5-14: the triangle to 2.5 (peak 50 at cycle 9); 15: back to 0.0, reached at cycle 25.
    assert approx(trace[4:15]) == [
        (0.0, 0.0), (0.05, 10.0), (0.2, 20.0), (0.45, 30.0), (0.8, 40.0), (1.25, 50.0),
        (1.7, 40.0), (2.05, 30.0), (2.3, 20.0), (2.45, 10.0), (2.5, 0.0),
    ]
    assert approx(trace[20:26]) == [(1.25, -50.0), (0.8, -40.0), (0.45, -30.0), (0.2, -20.0), (0.05, -10.0), (0.0, 0.0)]
    assert main.fbShuttle.nTrips == 2
    assert main.eState == S.MC_AXISSTATE_STANDSTILL


def test_an_st_project_sees_the_software_limit_refusal_as_the_nc_error_code() -> None:
    main, runtime = _motion_cell(soft_limit_max=2.0)
    runtime.run(cycles=6)
    assert pins(main.fbShuttle, "bError", "nErrorId", "nTrips") == {"bError": True, "nErrorId": 0x4461, "nTrips": 0}
    assert main.eState == S.MC_AXISSTATE_ERRORSTOP


# --- gearing: MC_GearIn / MC_GearOut (Infosys Tc2_MC2 "MC_GearIn", "MC_GearOut") -------------------

_GEAR_CELL = """
PROGRAM MAIN
VAR_INPUT
    bCouple, bDecouple, bRunMaster, bMoveSlave, bStopSlave : BOOL;
    fNumerator : MC_LREAL := 2.0;
    nDenominator : UINT := 1;
END_VAR
VAR
    Master, Slave : AXIS_REF;
    fbPowerM, fbPowerS : MC_Power;
    fbGearIn : MC_GearIn;
    fbGearOut : MC_GearOut;
    fbRun : MC_MoveVelocity;
    fbMoveSlave : MC_MoveAbsolute;
    fbStopSlave : MC_Stop;
END_VAR
fbPowerM(Axis := Master, Enable := TRUE, Enable_Positive := TRUE, Enable_Negative := TRUE);
fbPowerS(Axis := Slave, Enable := TRUE, Enable_Positive := TRUE, Enable_Negative := TRUE);
fbGearIn(Master := Master, Slave := Slave, Execute := bCouple, RatioNumerator := fNumerator,
         RatioDenominator := nDenominator);
fbRun(Axis := Master, Execute := bRunMaster, Velocity := 10.0);
fbMoveSlave(Axis := Slave, Execute := bMoveSlave, Position := 50.0, Velocity := 100.0);
fbStopSlave(Axis := Slave, Execute := bStopSlave);
fbGearOut(Slave := Slave, Execute := bDecouple);
END_PROGRAM
"""


def _gear_cell() -> tuple[Any, Runtime]:
    from iecoop import st as iecoop_st
    from iecoop.libraries import tc2_mc2

    plc = iecoop_st.load(_GEAR_CELL, libraries={"Tc2_MC2": tc2_mc2})
    runtime = Runtime(store=":memory:")
    runtime.add_task(Task("PlcTask", interval=T("10ms")), plc.MAIN)
    runtime.run(cycles=1)  # both axes enabled: Standstill
    return plc.MAIN, runtime


def test_gear_in_makes_the_slave_follow_the_master_times_the_ratio() -> None:
    main, runtime = _gear_cell()
    main.bCouple = True
    runtime.run(cycles=1)
    assert (main.fbGearIn.InGear, main.fbGearIn.Busy, main.fbGearIn.Active) == (True, True, True)
    assert main.Slave.Sim.State == S.MC_AXISSTATE_SYNCHRONIZEDMOTION
    main.bRunMaster = True
    positions = []
    for _ in range(10):
        runtime.run(cycles=1)
        positions.append((main.Master.NcToPlc.SetPos, main.Slave.NcToPlc.SetPos, main.Slave.NcToPlc.SetVelo))
    for master, slave, _velocity in positions:
        assert slave == pytest.approx(2.0 * master)
    assert positions[-1][2] == pytest.approx(20.0)  # the master at 10 units/s, the slave at twice that
    main.Slave.ReadStatus()
    assert main.Slave.Status.SynchronizedMotion


def test_gear_out_while_moving_keeps_the_velocity_until_a_stop() -> None:
    main, runtime = _gear_cell()
    main.bCouple = True
    runtime.run(cycles=1)
    main.bRunMaster = True
    runtime.run(cycles=5)
    main.bDecouple = True
    runtime.run(cycles=1)
    assert (main.fbGearOut.Done, main.fbGearOut.Error) == (True, False)
    runtime.run(cycles=1)  # MC_GearIn, called before MC_GearOut, sees the decoupling in the next cycle
    assert (main.fbGearIn.InGear, main.fbGearIn.Busy, main.fbGearIn.CommandAborted) == (False, False, False)
    assert main.Slave.Sim.State == S.MC_AXISSTATE_CONTINOUSMOTION
    before = main.Slave.NcToPlc.SetPos
    main.bRunMaster = False
    runtime.run(cycles=10)
    # decoupled: 10 cycles at 20 units/s more, whatever the master does
    assert main.Slave.NcToPlc.SetVelo == pytest.approx(20.0)
    assert main.Slave.NcToPlc.SetPos == pytest.approx(before + 10 * 0.2)
    main.bStopSlave = True
    runtime.run(cycles=5)
    assert main.fbStopSlave.Done and main.Slave.NcToPlc.SetVelo == 0.0


def test_gear_in_is_refused_on_a_moving_master_a_zero_denominator_and_gear_out_uncoupled() -> None:
    main, runtime = _gear_cell()
    main.bDecouple = True
    runtime.run(cycles=1)
    assert (main.fbGearOut.Error, main.fbGearOut.ErrorID) == (True, 0x4B05)
    main.nDenominator = 0
    main.bCouple = True
    runtime.run(cycles=1)
    assert (main.fbGearIn.Error, main.fbGearIn.ErrorID, main.fbGearIn.InGear) == (True, 0x4B06, False)
    main.bCouple, main.nDenominator, main.bRunMaster = False, 1, True
    runtime.run(cycles=3)
    main.bCouple = True
    runtime.run(cycles=1)  # Tc2_MC2 couples at standstill only
    assert (main.fbGearIn.Error, main.fbGearIn.ErrorID) == (True, 0x4B01)
    assert main.Slave.Sim.State == S.MC_AXISSTATE_STANDSTILL


def test_a_move_of_the_slave_aborts_the_coupling() -> None:
    main, runtime = _gear_cell()
    main.bCouple = True
    runtime.run(cycles=1)
    main.bMoveSlave = True
    runtime.run(cycles=2)  # the move starts in the first; MC_GearIn, called before it, shows it in the second
    assert (main.fbGearIn.CommandAborted, main.fbGearIn.InGear, main.fbGearIn.Busy) == (True, False, False)
    assert main.fbMoveSlave.Busy and main.Slave.Sim.State == S.MC_AXISSTATE_DISCRETEMOTION
    main.bRunMaster = True
    runtime.run(cycles=100)
    assert main.fbMoveSlave.Done and main.Slave.NcToPlc.SetPos == pytest.approx(50.0)  # no longer the master's


def test_mc_power_takes_its_options_as_a_project_passes_them() -> None:
    from iecoop import st as iecoop_st
    from iecoop.libraries import tc2_mc2

    plc = iecoop_st.load("""
    PROGRAM MAIN
    VAR Axis : AXIS_REF; fbPower : MC_Power; stOptions : ST_PowerOptions; fSpeed : MC_LREAL := 50.0; END_VAR
    fbPower.Options := stOptions;
    fbPower(Axis := Axis, Enable := TRUE, Enable_Positive := TRUE, Enable_Negative := TRUE, Override := fSpeed);
    END_PROGRAM
    """, libraries={"Tc2_MC2": tc2_mc2})
    runtime = Runtime(store=":memory:")
    runtime.add_task(Task("PlcTask", interval=T("10ms")), plc.MAIN)
    runtime.run(cycles=2)
    assert plc.MAIN.fbPower.Status and plc.MAIN.Axis.Sim.State == S.MC_AXISSTATE_STANDSTILL
