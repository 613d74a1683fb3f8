"""Facade: three HMI commands sequence five subsystems across cycles; a safety trip stops everything."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import AccessError, DefinitionError, T
from iecoop.runtime import Runtime, Task
from patterns.structural.facade import (
    CASES_PER_PALLET,
    CellMain,
    CellState,
    ICell,
    PalletiserCell,
    Robot,
    SafetyRelay,
)


def _cell() -> tuple[CellMain, Runtime]:
    hmi = CellMain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), hmi)
    return hmi, rt


def _press(hmi: CellMain, rt: Runtime, button: str) -> bool:
    """Press for one scan and release for one (R_TRIG needs to see the release); was it accepted?"""
    setattr(hmi, button, True)
    rt.run(cycles=1)
    accepted = hmi.accepted
    setattr(hmi, button, False)
    rt.run(cycles=1)
    return accepted


def _idle(cell: PalletiserCell) -> bool:
    """Every subsystem at rest."""
    return not (
        cell.robot.busy or cell.case_infeed.running or cell.pallet_infeed.running or cell.wrapper.busy
    )


def _run_until(hmi: CellMain, rt: Runtime, state: CellState, limit: int = 1000) -> int:
    """Run until the cell is in ``state``; return the time it got there."""
    for _ in range(limit):
        t = rt.time_ms
        rt.run(cycles=1)
        if hmi.cell.state == state:
            return t
    raise AssertionError(f"never reached {state.name}")


def test_start_homes_the_robot_then_starts_the_conveyors_in_order() -> None:
    hmi, rt = _cell()
    cell = hmi.cell
    assert _press(hmi, rt, "btn_start") is True
    assert (cell.state, cell.message) == (CellState.STARTING, "homing robot")
    started: dict[str, int] = {}
    for _ in range(60):
        t = rt.time_ms
        rt.run(cycles=1)
        for name, running in (
            ("homed", cell.robot.homed),
            ("pallet", cell.pallet_infeed.running),
            ("case", cell.case_infeed.running),
            ("running", cell.state == CellState.RUNNING),
        ):
            if running and name not in started:
                started[name] = t
    assert started == {"homed": 300, "pallet": 300, "case": 500, "running": 500}


def test_the_cell_fills_a_pallet_and_wraps_it() -> None:
    hmi, rt = _cell()
    _press(hmi, rt, "btn_start")
    _run_until(hmi, rt, CellState.RUNNING)
    max_cases = 0
    for _ in range(200):
        rt.run(cycles=1)
        max_cases = max(max_cases, hmi.cell.cases)
        if hmi.cell.pallets_done == 1:
            break
    assert hmi.cell.pallets_done == 1 and hmi.cell.wrapper.wrapped == 1
    assert max_cases == CASES_PER_PALLET
    assert hmi.cell.message == "pallet 1 wrapped"
    assert hmi.cell.robot.placed >= CASES_PER_PALLET


def test_a_safety_trip_stops_every_subsystem_in_the_same_scan() -> None:
    hmi, rt = _cell()
    _press(hmi, rt, "btn_start")
    _run_until(hmi, rt, CellState.RUNNING)
    rt.run(cycles=25)
    assert hmi.cell.case_infeed.running and hmi.cell.robot.homed
    hmi.guard_closed = False
    rt.run(cycles=1)
    cell = hmi.cell
    assert (cell.state, cell.message) == (CellState.TRIPPED, "safety trip: guard door open")
    assert _idle(cell)
    assert cell.robot.homed is False  # the servos dropped: the next start homes again


def test_a_trip_while_wrapping_aborts_the_wrapper_too() -> None:
    hmi, rt = _cell()
    _press(hmi, rt, "btn_start")
    _run_until(hmi, rt, CellState.RUNNING)
    while not hmi.cell.wrapper.busy:
        rt.run(cycles=1)
    hmi.estop_ok = False
    rt.run(cycles=1)
    assert hmi.cell.state == CellState.TRIPPED and _idle(hmi.cell)
    rt.run(cycles=100)
    assert (hmi.cell.wrapper.wrapped, hmi.cell.pallets_done) == (0, 0)


def test_reset_is_refused_until_the_cause_is_gone_and_never_restarts_by_itself() -> None:
    hmi, rt = _cell()
    _press(hmi, rt, "btn_start")
    rt.run(cycles=10)
    hmi.estop_ok = False
    rt.run(cycles=1)
    assert _press(hmi, rt, "btn_start") is False
    assert _press(hmi, rt, "btn_reset") is False
    assert hmi.cell.message == "reset refused: e-stop"
    hmi.estop_ok = True
    rt.run(cycles=5)
    assert hmi.cell.state == CellState.TRIPPED  # releasing the e-stop is not a reset
    assert _press(hmi, rt, "btn_reset") is True
    rt.run(cycles=20)
    assert (hmi.cell.state, hmi.cell.message) == (CellState.STOPPED, "stopped")
    assert _idle(hmi.cell)
    assert _press(hmi, rt, "btn_start") is True
    assert _run_until(hmi, rt, CellState.RUNNING) > 0


def test_stop_lets_the_robot_finish_its_case_then_stops() -> None:
    hmi, rt = _cell()
    _press(hmi, rt, "btn_start")
    _run_until(hmi, rt, CellState.RUNNING)
    while not hmi.cell.robot.busy:
        rt.run(cycles=1)
    placed = hmi.cell.robot.placed
    assert _press(hmi, rt, "btn_stop") is True
    assert hmi.cell.state == CellState.STOPPING
    assert not hmi.cell.case_infeed.running and not hmi.cell.pallet_infeed.running
    _run_until(hmi, rt, CellState.STOPPED, limit=30)
    assert hmi.cell.robot.placed == placed + 1
    assert _idle(hmi.cell) and hmi.cell.robot.homed  # a controlled stop keeps the robot homed


def test_commands_are_refused_in_the_wrong_state() -> None:
    hmi, rt = _cell()
    assert _press(hmi, rt, "btn_stop") is False
    assert _press(hmi, rt, "btn_reset") is False
    assert _press(hmi, rt, "btn_start") is True
    assert _press(hmi, rt, "btn_start") is False
    assert _press(hmi, rt, "btn_reset") is False
    assert hmi.cell.state == CellState.STARTING


def test_a_robot_that_never_homes_faults_the_cell_after_two_seconds() -> None:
    hmi, rt = _cell()
    hmi.cell.robot.stuck = True
    _press(hmi, rt, "btn_start")
    faulted_at = _run_until(hmi, rt, CellState.FAULTED, limit=300)
    assert faulted_at == 2000
    assert hmi.cell.message == "fault: robot homing timeout"
    assert _idle(hmi.cell) and not hmi.cell.pallet_infeed.running
    assert _press(hmi, rt, "btn_reset") is True
    assert hmi.cell.state == CellState.STOPPED


def test_the_hmi_needs_only_the_cell_interface() -> None:
    hmi, rt = _cell()
    cell: ICell = hmi.cell
    assert cell.start_cell() is True
    rt.run(cycles=60)
    assert (cell.state, cell.pallets_done) == (CellState.RUNNING, 0)
    assert cell.stop_cell() is True


def test_subsystems_are_internal_and_the_cycle_logic_private() -> None:
    with pytest.raises(AccessError, match=r"INTERNAL FUNCTION_BLOCK Robot cannot be instantiated from .*'patterns'"):
        Robot()
    with pytest.raises(AccessError, match="INTERNAL FUNCTION_BLOCK SafetyRelay"):
        SafetyRelay()
    cell = CellMain().cell
    with pytest.raises(AccessError, match=r"PRIVATE METHOD PalletiserCell\.run_cycle cannot be called"):
        cell.run_cycle(True)


def test_the_facade_is_final() -> None:
    with pytest.raises(DefinitionError, match="PalletiserCell is FINAL"):

        class BiggerCell(PalletiserCell):
            pass


ACTIONS = st.sampled_from(["btn_start", "btn_stop", "btn_reset", "estop", "guard", "wait", "wait", "wait"])


@settings(max_examples=40, deadline=None)
@given(actions=st.lists(st.tuples(ACTIONS, st.sampled_from([1, 5, 20, 100, 200])), min_size=1, max_size=12))
def test_invariants_hold_for_any_button_and_safety_sequence(actions: list[tuple[str, int]]) -> None:
    hmi, rt = _cell()
    cell = hmi.cell
    for action, scans in actions:
        if action == "estop":
            hmi.estop_ok = not hmi.estop_ok
        elif action == "guard":
            hmi.guard_closed = not hmi.guard_closed
        elif action != "wait":
            setattr(hmi, action, True)
        for _ in range(scans):
            rt.run(cycles=1)
            for button in ("btn_start", "btn_stop", "btn_reset"):
                setattr(hmi, button, False)
            assert cell.cases <= CASES_PER_PALLET
            assert cell.pallets_done <= cell.wrapper.wrapped
            if not (hmi.estop_ok and hmi.guard_closed):
                # An open safety circuit always means a stopped cell.
                assert cell.state == CellState.TRIPPED and _idle(cell)
            if cell.state in (CellState.STOPPED, CellState.TRIPPED, CellState.FAULTED):
                assert _idle(cell)
            if cell.state == CellState.RUNNING:
                assert cell.robot.homed
