"""Adapter: three device protocols behind IDrive, each handshake taking several cycles."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import T
from iecoop.runtime import Runtime, Task
from patterns.plant.vfd import CW_FAULT_RESET, CW_RUN, SW_FAULT, SW_RUNNING
from patterns.structural.adapter import (
    ERR_AXIS_NOT_READY,
    ERR_DRIVE_TRIP,
    ERR_VELOCITY_RANGE,
    AxisDrive,
    AxisRef,
    AxisStep,
    ContactorDrive,
    DriveLine,
    IDrive,
    MC_MoveVelocity,
    MC_Power,
    MC_Stop,
    VfdDrive,
)


def _line() -> tuple[DriveLine, Runtime]:
    line = DriveLine()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), line)
    return line, rt


def _start(line: DriveLine, rt: Runtime, speed: float = 1200.0) -> None:
    line.speed = speed
    line.cmd_start = True
    rt.run(cycles=1)
    line.cmd_start = False


def _first_running_cycle(line: DriveLine, rt: Runtime, drive: IDrive, limit: int = 50) -> int:
    for cycle in range(1, limit + 1):
        rt.run(cycles=1)
        if drive.running:
            return cycle
    raise AssertionError("never running")


# ---------------------------------------------------------------------------
# One interface, three handshakes
# ---------------------------------------------------------------------------


def test_the_line_holds_three_different_adapters_behind_one_interface() -> None:
    line, _ = _line()
    kinds = [type(line.drives[i]) for i in range(1, 4)]
    assert kinds == [VfdDrive, AxisDrive, ContactorDrive]
    assert all(isinstance(line.drives[i], IDrive) for i in range(1, 4))


def test_start_through_the_interface_takes_a_different_number_of_cycles_per_device() -> None:
    line, rt = _line()
    _start(line, rt)
    assert not any(line.drives[i].running for i in range(1, 4))  # nothing runs in the scan that commands it
    running_at: dict[str, int] = {}
    for _ in range(10):
        rt.run(cycles=1)
        for name, i in (("vfd", 1), ("axis", 2), ("dol", 3)):
            if line.drives[i].running and name not in running_at:
                running_at[name] = rt.time_ms - 10
    # DOL: contactor pull-in 20 ms; axis: power stage 30 ms then an Execute edge; VFD: 50 ms magnetising.
    assert running_at == {"dol": 30, "axis": 40, "vfd": 60}


def test_all_drives_reach_their_speed_and_the_dol_refuses_a_setpoint() -> None:
    line, rt = _line()
    _start(line, rt, speed=900.0)
    assert list(line.accepted) == [True, True, False]
    rt.run(cycles=50)
    assert line.all_running
    assert [line.drives[i].actual_speed for i in range(1, 4)] == [900.0, 900.0, 1450.0]
    assert line.vfd.speed_ref == 300  # 30.0 Hz in 0.1 Hz units


def test_a_stop_through_the_interface_stops_every_drive_after_its_own_ramp() -> None:
    line, rt = _line()
    _start(line, rt)
    rt.run(cycles=60)
    line.cmd_stop = True
    stopped_at: dict[int, int] = {}
    for cycle in range(1, 60):
        rt.run(cycles=1)
        for i in range(1, 4):
            if not line.drives[i].running and i not in stopped_at:
                stopped_at[i] = cycle
    # DOL: the aux contact opens at once, read one scan later; the axis decelerates 1200 rpm at
    # 6000 rpm/s; the VFD ramps 40 Hz down at 100 Hz/s.
    assert stopped_at == {3: 2, 2: 21, 1: 41}
    assert not line.any_fault
    assert line.axis.step == AxisStep.IDLE


# ---------------------------------------------------------------------------
# (a) the Modbus VFD: bits in WORDs
# ---------------------------------------------------------------------------


@settings(max_examples=100, deadline=None)
@given(status=st.integers(0, 0xFFFF))
def test_vfd_properties_are_the_status_word_bits(status: int) -> None:
    vfd = VfdDrive()
    vfd.status_word = status
    assert vfd.running == bool(status >> 1 & 1)  # wStatus.1
    assert vfd.fault == bool(status >> 3 & 1)  # wStatus.3


def test_vfd_control_word_run_bit_follows_start_and_stop() -> None:
    vfd = VfdDrive()
    vfd.start()
    vfd.cyclic()
    assert vfd.control_word == CW_RUN
    vfd.stop()
    vfd.cyclic()
    assert vfd.control_word == 0


def test_vfd_set_speed_scales_to_tenths_of_hertz_and_refuses_out_of_range() -> None:
    vfd = VfdDrive()
    assert vfd.set_speed(1500.0) is True
    assert vfd.speed_ref == 500
    assert vfd.set_speed(1801.0) is False
    assert vfd.set_speed(-1.0) is False
    assert vfd.speed_ref == 500


def test_vfd_trip_then_reset_pulses_bit_7_for_one_scan_and_does_not_restart() -> None:
    line, rt = _line()
    _start(line, rt)
    rt.run(cycles=20)
    line.vfd_sim.trip = True
    rt.run(cycles=1)
    line.vfd_sim.trip = False
    rt.run(cycles=1)
    assert (line.vfd.fault, line.vfd.status_word & SW_FAULT) == (True, SW_FAULT)
    assert line.vfd.control_word & CW_RUN == 0  # a fault drops the run command
    line.cmd_reset = True
    rt.run(cycles=1)
    assert line.vfd.control_word == CW_FAULT_RESET
    rt.run(cycles=1)
    assert line.vfd.control_word == 0  # the reset bit was high for exactly one scan
    assert line.vfd.fault is False
    rt.run(cycles=10)
    assert (line.vfd.running, line.vfd.status_word & SW_RUNNING) == (False, 0)


# ---------------------------------------------------------------------------
# (b) the PLCopen axis: Execute / Busy / Done / Error
# ---------------------------------------------------------------------------


def test_axis_goes_through_power_and_move_handshakes_cycle_by_cycle() -> None:
    line, rt = _line()
    axis = line.axis
    _start(line, rt)
    steps = [axis.step]
    busy = [axis.move.Busy]
    for _ in range(4):
        rt.run(cycles=1)
        steps.append(axis.step)
        busy.append(axis.move.Busy)
    assert steps == [AxisStep.POWERING] * 4 + [AxisStep.MOVING]
    assert busy == [False] * 4 + [True]
    assert axis.move.InVelocity is False
    rt.run(cycles=20)
    assert (axis.move.InVelocity, axis.move.Busy, axis.actual_speed) == (True, True, 1200.0)


def test_a_new_setpoint_retriggers_execute_with_one_low_scan() -> None:
    line, rt = _line()
    axis = line.axis
    _start(line, rt)
    rt.run(cycles=30)
    assert axis.set_speed(600.0) is True
    rt.run(cycles=1)
    assert (axis.move.Execute, axis.move.Busy) == (False, True)  # the low scan; the move goes on
    rt.run(cycles=1)
    assert (axis.move.Execute, axis.move.Busy, axis.move.InVelocity) == (True, True, False)
    rt.run(cycles=10)
    assert (axis.move.InVelocity, axis.actual_speed) == (True, 600.0)
    assert axis.set_speed(3001.0) is False


def test_axis_trip_faults_with_the_error_id_and_reset_needs_the_cause_gone() -> None:
    line, rt = _line()
    axis = line.axis
    _start(line, rt)
    rt.run(cycles=30)
    line.axis_sim.trip = True
    rt.run(cycles=2)
    assert (axis.fault, axis.error_id, axis.running, axis.actual_speed) == (True, ERR_DRIVE_TRIP, False, 0.0)
    line.cmd_reset = True
    rt.run(cycles=1)
    assert axis.step == AxisStep.RESETTING
    rt.run(cycles=100)  # the cause is still there: MC_Reset never gets Done; the watchdog gives up
    assert (axis.step, axis.fault) == (AxisStep.FAULTED, True)
    line.axis_sim.trip = False
    line.cmd_reset = False
    rt.run(cycles=1)
    line.cmd_reset = True
    rt.run(cycles=3)
    assert (axis.step, axis.fault, axis.error_id) == (AxisStep.IDLE, False, 0)


def test_mc_move_velocity_refuses_an_unpowered_axis_and_a_velocity_out_of_range() -> None:
    ref = AxisRef()
    move = MC_MoveVelocity()
    move(Axis=ref, Execute=True, Velocity=100.0)
    assert (move.Busy, move.Error, move.ErrorID) == (False, True, ERR_AXIS_NOT_READY)
    move(Axis=ref, Execute=False)
    assert (move.Error, move.ErrorID) == (False, 0)  # outputs are held only while Execute is TRUE
    ref.powered = True
    move(Axis=ref, Execute=True, Velocity=5000.0)
    assert (move.Error, move.ErrorID) == (True, ERR_VELOCITY_RANGE)


def test_mc_stop_aborts_a_move_and_holds_the_axis_while_execute_is_true() -> None:
    ref = AxisRef(powered=True)
    move, halt = MC_MoveVelocity(), MC_Stop()
    move(Axis=ref, Execute=True, Velocity=100.0)
    assert move.Busy and ref.cmd_move
    ref.act_velocity = 50.0
    halt(Axis=ref, Execute=True)
    move(Axis=ref, Execute=True)
    assert (move.CommandAborted, move.Busy) == (True, False)
    assert (halt.Busy, halt.Done) == (True, False)
    ref.act_velocity = 0.0
    halt(Axis=ref, Execute=True)
    assert (halt.Done, halt.Busy, ref.cmd_stop) == (True, False, True)
    retry = MC_MoveVelocity()
    retry(Axis=ref, Execute=True, Velocity=10.0)
    assert retry.Error  # Stopping refuses moves while MC_Stop.Execute is TRUE
    halt(Axis=ref, Execute=False)
    assert not ref.cmd_stop and not halt.Done


def test_mc_power_status_follows_the_power_stage() -> None:
    ref = AxisRef()
    power = MC_Power()
    power(Axis=ref, Enable=True)
    assert ref.cmd_power and not power.Status
    ref.powered = True
    power(Axis=ref, Enable=True)
    assert power.Status


# ---------------------------------------------------------------------------
# (c) the DOL contactor motor
# ---------------------------------------------------------------------------


def test_dol_overload_trips_and_reset_is_refused_while_the_relay_is_open() -> None:
    line, rt = _line()
    _start(line, rt)
    rt.run(cycles=5)
    assert line.dol.running
    line.dol_sim.overload = True
    rt.run(cycles=2)
    assert (line.dol.fault, line.dol.reason, line.dol.coil_k1) == (True, "overload relay tripped", False)
    line.dol.reset()
    assert line.dol.fault is True
    line.dol.start()
    rt.run(cycles=1)
    assert line.dol.coil_k1 is False  # start refused while faulted
    line.dol_sim.overload = False
    rt.run(cycles=2)  # the relay's contact closes in the device, then reaches %I the next scan
    line.dol.reset()
    assert (line.dol.fault, line.dol.reason) == (False, "")


def test_dol_missing_feedback_faults_after_200_ms() -> None:
    line, rt = _line()
    line.dol_sim.aux_wire_broken = True
    _start(line, rt)
    for _ in range(19):
        rt.run(cycles=1)
        assert not line.dol.fault
    rt.run(cycles=2)
    assert line.dol.fault and line.dol.reason == "contactor feedback missing"
    assert not line.dol.running and line.dol.actual_speed == 0.0


@pytest.mark.parametrize("index", [1, 2, 3])
def test_every_adapter_reports_stopped_and_healthy_before_any_command(index: int) -> None:
    line, rt = _line()
    rt.run(cycles=10)
    drive = line.drives[index]
    assert (drive.running, drive.fault, drive.actual_speed) == (False, False, 0.0)
