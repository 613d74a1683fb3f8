"""DIP: the fixed controller can only be tested through its real hardware blocks; the injected one with fakes."""

from __future__ import annotations

from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import (
    BOOL,
    INT,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    AccessError,
    ExceptionCode,
    FunctionBlock,
    PlcException,
    T,
    delete,
    method,
    prop,
)
from iecoop.runtime import Runtime, Task
from patterns.solid.dip import (
    CW_ENABLE_OPERATION,
    CW_FAULT_RESET,
    CW_SHUTDOWN,
    SW_FAULT,
    SW_OPERATION_ENABLED,
    ConveyorController,
    ConveyorControllerFixed,
    DipCell,
    IDrive,
    ILamp,
    LampMode,
    TowerLamp,
    VfdDrive,
)
from tests import checked_only


class FakeLamp(FunctionBlock, ILamp):
    """A test double: remembers the mode and counts the changes."""

    wanted: LampMode = VAR(LampMode.OFF)
    changes: INT = VAR_OUTPUT(0)

    @method
    def set_mode(self, mode: LampMode) -> None:
        self.wanted = mode
        self.changes += 1

    @prop
    def mode(self) -> LampMode:
        return self.wanted


class FakeDrive(FunctionBlock, IDrive):
    """A test double: the test sets what the drive reports and counts the commands."""

    is_running: BOOL = VAR_INPUT(False)
    is_faulted: BOOL = VAR_INPUT(False)
    starts: INT = VAR_OUTPUT(0)
    stops: INT = VAR_OUTPUT(0)
    resets: INT = VAR_OUTPUT(0)

    @method
    def start(self) -> BOOL:
        self.starts += 1
        return not self.is_faulted

    @method
    def stop(self) -> None:
        self.stops += 1

    @method
    def reset(self) -> None:
        self.resets += 1

    @prop
    def running(self) -> BOOL:
        return self.is_running

    @prop
    def faulted(self) -> BOOL:
        return self.is_faulted


def _cell() -> tuple[Runtime, DipCell]:
    cell = DipCell()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), cell)
    return rt, cell


# ---------------------------------------------------------------------------
# What goes wrong in the violating design
# ---------------------------------------------------------------------------


def test_the_fixed_controller_cannot_be_given_a_fake() -> None:
    with pytest.raises(TypeError, match=r"ConveyorControllerFixed: FB_init has no input 'lamp'"):
        ConveyorControllerFixed(lamp=FakeLamp())


@checked_only
def test_the_fixed_controller_members_refuse_a_fake() -> None:
    controller = ConveyorControllerFixed()
    # Its members are typed with the concrete blocks: mypy rejects a fake as well (warn_unused_ignores checks it).
    with pytest.raises(AccessError, match=r"VAR ConveyorControllerFixed\.lamp cannot be written"):
        controller.lamp = FakeLamp()  # type: ignore[assignment]
    with pytest.raises(AccessError, match=r"VAR ConveyorControllerFixed\.drive cannot be written"):
        controller.drive = FakeDrive()  # type: ignore[assignment]


def test_a_test_of_the_fixed_start_policy_runs_into_the_contactor_supervision() -> None:
    """'A start request runs the belt' cannot be checked without simulating the auxiliary contact."""
    rt, cell = _cell()
    cell.start_request = True  # no contact feedback wired in the test
    rt.run(cycles=1)
    assert (cell.fixed.drive.q_contactor, cell.fixed.lamp.mode) == (True, LampMode.OFF)
    rt.run(cycles=31)  # t = 310 ms: 300 ms after the first cycle without feedback, the real supervision trips
    assert (cell.fixed.drive.q_contactor, cell.fixed.drive.fault) == (False, True)
    assert cell.fixed.lamp.mode == LampMode.BLINK
    # ... and seeing the blink needs the real lamp's 500 ms timer.
    outputs = []
    for _ in range(101):
        rt.run(cycles=1)
        outputs.append(cell.fixed.lamp.q_lamp)
    assert outputs.index(True) == 49 and outputs[49:] == [True] * 50 + [False] * 2


# ---------------------------------------------------------------------------
# What holds in the compliant design
# ---------------------------------------------------------------------------


def test_the_policy_is_tested_with_fakes_cycle_by_cycle() -> None:
    lamp, drive = FakeLamp(), FakeDrive()
    controller = ConveyorController(lamp=lamp, drive=drive)
    for _ in range(5):
        controller(start_request=True)
    assert (drive.starts, drive.stops, lamp.mode, lamp.changes) == (1, 0, LampMode.OFF, 0)
    drive.is_running = True
    controller(start_request=False)
    assert (lamp.mode, lamp.changes) == (LampMode.STEADY, 1)
    for _ in range(5):
        controller(jam=True)
    assert (drive.stops, lamp.mode, lamp.changes) == (1, LampMode.BLINK, 2)
    controller(jam=True, start_request=True)  # no start into a jam
    assert drive.starts == 1
    drive.is_running = False
    controller(jam=False, start_request=False)
    assert (lamp.mode, lamp.changes) == (LampMode.OFF, 3)
    drive.is_faulted = True
    controller()
    assert lamp.mode == LampMode.BLINK
    controller(reset_request=True)
    controller(reset_request=True)
    assert drive.resets == 1
    controller(stop_request=True)
    assert drive.stops == 2


def test_a_controller_without_its_dependencies_cannot_be_built() -> None:
    with pytest.raises(TypeError, match=r"ConveyorController: FB_init input 'drive' has no value"):
        ConveyorController(lamp=FakeLamp())
    hint = r"FB_init input 'drive' has no value; pass it as ConveyorController\(drive=\.\.\.\)"
    with pytest.raises(TypeError, match=hint):
        ConveyorController()
    not_a_lamp: Any = FakeDrive()
    with pytest.raises(TypeError, match=r"ConveyorController\.lamp: FakeDrive does not implement ILamp"):
        ConveyorController(lamp=not_a_lamp, drive=FakeDrive())


def test_the_same_controller_drives_a_frequency_converter() -> None:
    lamp, vfd = TowerLamp(), VfdDrive()
    controller = ConveyorController(lamp=lamp, drive=vfd)
    assert vfd.control_word == CW_SHUTDOWN
    controller(start_request=True)
    assert (vfd.control_word, lamp.mode) == (CW_ENABLE_OPERATION, LampMode.OFF)
    modes = []
    vfd(status_word=SW_OPERATION_ENABLED)
    controller(start_request=True)
    modes.append(lamp.mode)
    vfd(status_word=SW_FAULT)
    controller(start_request=False)
    modes.append(lamp.mode)
    assert modes == [LampMode.STEADY, LampMode.BLINK]
    controller(reset_request=True)
    assert vfd.control_word == CW_SHUTDOWN | CW_FAULT_RESET
    controller(start_request=True)
    assert vfd.control_word == CW_SHUTDOWN | CW_FAULT_RESET  # a faulted converter refuses the start


def test_the_cell_owns_the_controller_and_no_pointer_outlives_it() -> None:
    rt, cell = _cell()
    cell.start_request = cell.contactor_feedback = True
    rt.run(cycles=2)
    old = cell.controller
    assert old.deref.lamp.mode == LampMode.STEADY
    rt.reset_origin()  # FB_exit deletes the controller, FB_init creates a new one
    with pytest.raises(PlcException) as info:
        _ = old.deref.start_request
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION
    assert cell.controller and cell.controller != old
    assert (cell.drive.q_contactor, cell.lamp.mode, cell.start_request) == (False, LampMode.OFF, False)
    cell.start_request = cell.contactor_feedback = True
    rt.run(cycles=1)
    assert (cell.drive.q_contactor, cell.lamp.mode) == (True, LampMode.STEADY)


def test_an_online_change_hands_the_controller_over_and_reconnects_it() -> None:
    rt, cell = _cell()
    cell.start_request = cell.contactor_feedback = True
    rt.run(cycles=2)
    owned = cell.controller
    changed = DipCell()
    # Constructing it ran FB_init(bInCopyCode := FALSE), which made a controller; the online change
    # runs FB_init again with bInCopyCode := TRUE on zeroed memory, so this one would have no owner.
    delete(changed.controller)
    rt.online_change(replace={"PlcTask.DipCell": changed})
    assert changed.controller == owned and owned.deref.start_request is True  # taken over, state kept
    assert owned.deref.lamp == changed.lamp and owned.deref.drive == changed.drive  # FB_reinit reconnected it
    del cell
    rt.run(cycles=1)
    changed.jam = True
    rt.run(cycles=1)
    assert (changed.drive.q_contactor, changed.lamp.mode) == (False, LampMode.BLINK)


steps = st.lists(
    st.tuples(st.booleans(), st.booleans(), st.booleans(), st.booleans(), st.booleans(), st.integers(1, 40)),
    min_size=1,
    max_size=12,
)


@settings(max_examples=40, deadline=None)
@given(steps)
def test_fixed_and_injected_controllers_behave_identically(
    script: list[tuple[bool, bool, bool, bool, bool, int]],
) -> None:
    rt, cell = _cell()
    for start, stop, reset, jam, feedback, cycles in script:
        cell.start_request, cell.stop_request, cell.reset_request = start, stop, reset
        cell.jam, cell.contactor_feedback = jam, feedback
        for _ in range(cycles):
            rt.run(cycles=1)
            fixed = (cell.fixed.drive.q_contactor, cell.fixed.drive.fault, cell.fixed.lamp.mode, cell.fixed.lamp.q_lamp)
            injected = (cell.drive.q_contactor, cell.drive.fault, cell.lamp.mode, cell.lamp.q_lamp)
            assert fixed == injected
            if jam:
                assert not cell.drive.q_contactor and cell.lamp.mode == LampMode.BLINK
