"""SRP: what a wording change costs the drive in each design, and that both run the motor alike."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import BOOL, PROTECTED, STRING, VAR, VAR_INPUT, ExceptionCode, PlcException, Program, T, adr, method, sizeof
from iecoop.runtime import Runtime, Task
from patterns.solid.srp import (
    MAX_EVENTS,
    Drive,
    DriveEventLog,
    DriveHmiFormatter,
    DriveState,
    DriveWithHmi,
    HmiMain,
    IDriveStatus,
    MotionMain,
    ViolatingCell,
    state_word,
)


def _plant() -> tuple[Runtime, ViolatingCell, MotionMain, HmiMain]:
    violating, motion, hmi = ViolatingCell(), MotionMain(), HmiMain()
    hmi.drive = motion.drive
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), violating, motion)
    rt.add_task(Task("HmiTask", interval=T("100ms"), priority=30), hmi)
    return rt, violating, motion, hmi


def _set(cells: tuple[ViolatingCell, MotionMain], **inputs: object) -> None:
    for cell in cells:
        for name, value in inputs.items():
            setattr(cell, name, value)


# ---------------------------------------------------------------------------
# What goes wrong in the violating design
# ---------------------------------------------------------------------------


def test_every_violating_drive_instance_carries_the_hmi_buffers() -> None:
    fat, lean = DriveWithHmi(), Drive()
    hmi_bytes = sizeof(fat, "status_text") + sizeof(fat, "events") + sizeof(fat, "name")
    assert hmi_bytes == 41 + MAX_EVENTS * 41 + 9
    assert sizeof(DriveWithHmi) >= sizeof(Drive) + hmi_bytes
    assert sizeof(lean) == sizeof(Drive) <= 32
    # The split-off text lives once, in the HMI program's formatter.
    assert sizeof(DriveHmiFormatter(), "status_text") == 41


def test_the_violating_drive_rebuilds_its_text_in_every_motion_cycle() -> None:
    rt, violating, motion, hmi = _plant()
    rt.run(cycles=100)  # the motor stays stopped: nothing changes
    assert rt.time_ms == 1000
    assert violating.drive.format_count == 100
    assert hmi.formatter.format_count == 10
    assert violating.drive.status_text == hmi.formatter.status_text == "M1 STOP 0.0 %"
    assert motion.drive.state == DriveState.STOPPED


class DriveWithHmiDe(DriveWithHmi):
    """The HMI team's new wording: in the violating design it can only be a new drive block."""

    @method(PROTECTED)
    def compose(self) -> STRING:
        return f"{self.name} LAEUFT {self.speed_ref:.0f}%" if self.current == DriveState.RUNNING else f"{self.name} AUS"


class ViolatingCellDe(Program):
    overload: BOOL = VAR_INPUT(False)
    drive: DriveWithHmiDe = VAR()

    def body(self) -> None:
        self.drive(overload=self.overload)


class FormatterDe(DriveHmiFormatter):
    """The same new wording in the compliant design: a new formatter, the drive untouched."""

    @method(PROTECTED)
    def compose(self) -> STRING:
        if self.source.state == DriveState.RUNNING:
            return f"{self.name} LAEUFT {self.source.speed:.0f}%"
        return f"{self.name} AUS"


class HmiMainDe(Program):
    drive: IDriveStatus = VAR_INPUT()
    formatter: FormatterDe = VAR()

    def body(self) -> None:
        self.formatter(source=self.drive)


def test_a_new_wording_replaces_the_motor_block_in_the_violating_design() -> None:
    rt, violating, motion, hmi = _plant()
    _set((violating, motion), start_button=True)
    rt.run(cycles=10)
    changed = ViolatingCellDe()
    rt.online_change(replace={"PlcTask.ViolatingCell": changed})
    # The block that runs the motor is a new instance of a new type: FB_exit / FB_init / copy for a text change.
    assert rt.programs()["PlcTask.ViolatingCell"] is changed
    assert type(changed.drive) is DriveWithHmiDe and adr(changed.drive) != adr(violating.drive)
    rt.run(cycles=1)
    assert changed.drive.status_text == "M1 LAEUFT 75%"
    assert changed.drive.speed_ref == 75.0 and changed.drive.state == DriveState.RUNNING


def test_a_new_wording_replaces_only_the_hmi_program_in_the_compliant_design() -> None:
    rt, violating, motion, hmi = _plant()
    _set((violating, motion), start_button=True)
    rt.run(cycles=3)
    drive = motion.drive
    speed_before, events_before = drive.speed_ref, motion.log.event_total
    changed = HmiMainDe()
    changed.drive = motion.drive
    rt.online_change(replace={"HmiTask.HmiMain": changed})
    assert rt.programs()["PlcTask.MotionMain"] is motion
    assert adr(motion.drive) == adr(drive) and type(motion.drive) is Drive
    assert (drive.speed_ref, motion.log.event_total) == (speed_before, events_before) == (37.5, 1)
    assert changed.formatter.status_text == "M1 RUN  12.5 %"  # copied by the online change, until its next cycle
    rt.run(cycles=8)  # the HMI task runs again at t = 100 ms
    assert changed.formatter.status_text == "M1 LAEUFT 75%"
    assert drive.speed_ref == 75.0 and drive.state == DriveState.RUNNING


# ---------------------------------------------------------------------------
# What both designs share: the motor behaves the same
# ---------------------------------------------------------------------------

commands = st.lists(
    st.tuples(
        st.sampled_from(["none", "start", "stop", "reset"]),
        st.booleans(),
        st.sampled_from([0.0, 25.0, 60.0, 100.0, 150.0]),
    ),
    min_size=1,
    max_size=40,
)


@settings(max_examples=60, deadline=None)
@given(commands)
def test_both_designs_run_the_motor_and_log_events_identically(script: list[tuple[str, bool, float]]) -> None:
    rt, violating, motion, _hmi = _plant()
    cells = (violating, motion)
    for command, overload, setpoint in script:
        _set(cells, start_button=command == "start", stop_button=command == "stop", reset_button=command == "reset")
        _set(cells, overload=overload, setpoint=setpoint)
        rt.run(cycles=1)
        fat, lean = violating.drive, motion.drive
        assert (fat.state, fat.q_run, fat.speed_ref) == (lean.state, lean.q_run, lean.speed_ref)
        assert 0.0 <= lean.speed_ref <= 100.0
        assert fat.event_total == motion.log.event_total
    kept = min(motion.log.event_total, MAX_EVENTS)
    assert [violating.drive.event(age) for age in range(kept)] == [motion.log.event(age) for age in range(kept)]


def test_the_drive_ramps_to_its_setpoint_in_steps_of_the_ramp_rate() -> None:
    rt, _violating, motion, _hmi = _plant()
    motion.start_button = True
    speeds = []
    for _ in range(8):
        rt.run(cycles=1)
        speeds.append(motion.drive.speed_ref)
    assert speeds == [12.5, 25.0, 37.5, 50.0, 62.5, 75.0, 75.0, 75.0]
    motion.stop_button = True
    rt.run(cycles=6)
    assert (motion.drive.speed_ref, motion.drive.q_run, rt.time_ms) == (0.0, False, 140)


def test_a_tripped_drive_refuses_start_until_reset_without_overload() -> None:
    drive = Drive()
    states: list[DriveState] = []
    assert drive.start(50.0) is True
    drive(overload=True)
    states.append(drive.state)
    assert drive.speed_ref == 0.0 and not drive.q_run
    assert drive.start(50.0) is False
    assert drive.reset() is True
    drive(overload=True)  # the overload persists: it trips again
    states.append(drive.state)
    assert drive.reset() is True
    drive(overload=False)
    states.append(drive.state)
    assert states == [DriveState.TRIPPED, DriveState.TRIPPED, DriveState.STOPPED]
    assert drive.start(50.0) is True
    assert drive.reset() is False


def test_the_event_log_keeps_the_newest_eight_changes() -> None:
    rt, _violating, motion, _hmi = _plant()
    for _ in range(5):
        motion.start_button = True
        rt.run(cycles=1)
        motion.start_button, motion.stop_button = False, True
        rt.run(cycles=1)
        motion.stop_button = False
    assert motion.log.event_total == 10
    assert [motion.log.event(age) for age in range(MAX_EVENTS)] == ["M1 STOPPED", "M1 RUNNING"] * 4
    # An age past the changes kept reads as an empty row, as an HMI event list shows it.
    assert (motion.log.event(MAX_EVENTS), motion.log.event(-1)) == ("", "")
    assert DriveEventLog().event(0) == ""


def test_the_status_word_of_each_state() -> None:
    assert [state_word(s) for s in DriveState] == ["STOP", "RUN ", "TRIP"]


def test_an_hmi_program_without_a_drive_faults_with_an_access_violation() -> None:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("HmiTask", interval=T("100ms"), priority=30), HmiMain())
    with pytest.raises(PlcException, match="null interface reference") as info:
        rt.run(cycles=1)
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


def test_the_setpoint_is_clamped_to_the_drive_range() -> None:
    drive = Drive()
    drive.start(250.0)
    for _ in range(10):
        drive()
    assert drive.speed_ref == 100.0
    drive.start(-5.0)
    for _ in range(10):
        drive()
    assert (drive.speed, drive.state) == (0.0, DriveState.RUNNING)
