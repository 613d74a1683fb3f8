"""Axis homing: the FINAL step chain and its three variants, scan by scan on a simulated axis."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import BOOL, PROTECTED, VAR, AccessError, DefinitionError, ExceptionCode, PlcException, Program, T, method
from iecoop.runtime import Runtime, Task
from patterns.behavioral.template_method import (
    AxisHoming,
    HomeAbsolute,
    HomeOnIndexPulse,
    HomeOnLimitSwitch,
    HomingCell,
    HomingStep,
    IHoming,
    SimAxis,
    floor_dint,
)

CHAIN = [
    HomingStep.PRECONDITIONS, HomingStep.APPROACH, HomingStep.EDGE, HomingStep.BACK_OFF,
    HomingStep.SET_POSITION, HomingStep.DONE,
]


class SwitchRig(Program):
    axis: SimAxis = VAR({"switch_at": -10.0}, fb_init={"start_at": 35.0})
    homing: HomeOnLimitSwitch = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
        self.homing.axis = self.axis
        return True

    def body(self) -> None:
        self.axis()
        self.homing.run()


class IndexRig(Program):
    axis: SimAxis = VAR(fb_init={"start_at": 3.0})
    homing: HomeOnIndexPulse = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
        self.homing.axis = self.axis
        return True

    def body(self) -> None:
        self.axis()
        self.homing.run()


class AbsoluteRig(Program):
    axis: SimAxis = VAR({"encoder_offset": 700.0}, fb_init={"start_at": -4.25})
    homing: HomeAbsolute = VAR({"encoder_at_home": 690.0, "home_position": 100.0})

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
        self.homing.axis = self.axis
        return True

    def body(self) -> None:
        self.axis()
        self.homing.run()


Rig = SwitchRig | IndexRig | AbsoluteRig


def place(rt: Runtime, axis: SimAxis, at: float) -> None:
    """Jog the slide to ``at`` in one scan (the rigs' FB_init start positions are fixed)."""
    axis.move_velocity((at - axis.mechanical) * 100.0)
    rt.run(cycles=1)
    axis.halt()


def on_task(rig: Rig) -> Runtime:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), rig)
    return rt


def home(rt: Runtime, rig: Rig, limit: int = 2000) -> list[tuple[int, HomingStep]]:
    """Start the homing, run scans until it is no longer busy; (time, step) at every step change."""
    rig.homing.start()
    trace: list[tuple[int, HomingStep]] = []
    for _ in range(limit):
        now = rt.time_ms
        rt.run(cycles=1)
        if not trace or trace[-1][1] != rig.homing.step:
            trace.append((now, rig.homing.step))
        if not rig.homing.busy:
            return trace
    raise AssertionError(f"homing still busy in {rig.homing.step.name} after {limit} scans")


# ---------------------------------------------------------------------------
# The three variants, across scans
# ---------------------------------------------------------------------------


def test_limit_switch_homing_runs_the_whole_chain_and_references_the_switch_edge() -> None:
    rig = SwitchRig()
    rt = on_task(rig)
    trace = home(rt, rig)
    assert [step for _t, step in trace] == CHAIN
    # 45 mm at 50 mm/s, two creep scans off the switch, 2 mm back off at 5 mm/s.
    assert [t for t, _s in trace] == [0, 10, 920, 940, 1350, 1360]
    assert (rig.homing.done, rig.homing.error, rig.axis.velocity) == (True, False, 0.0)
    assert rig.axis.position == pytest.approx(2.0, abs=1e-9)
    # The switch releases at mechanical -10 mm; that point is now home_position (within one creep scan).
    assert -0.05 - 1e-9 <= -10.0 + rig.axis.offset - rig.homing.home_position <= 0.0


def test_index_pulse_homing_latches_the_mark_exactly_and_does_not_back_off() -> None:
    rig = IndexRig()
    rig.homing.home_position = 25.0
    rt = on_task(rig)
    trace = home(rt, rig)
    assert [step for _t, step in trace] == CHAIN
    times = dict((s, t) for t, s in trace)
    assert times[HomingStep.SET_POSITION] - times[HomingStep.BACK_OFF] == 10
    # The mark at mechanical 10 mm (the first one after clearing 2 mm) reads home_position.
    assert rig.axis.offset + 10.0 == pytest.approx(25.0, abs=1e-9)
    assert rig.homing.mark_position == pytest.approx(10.0, abs=1e-9)


def test_absolute_homing_moves_nothing_and_takes_one_scan_per_step() -> None:
    rig = AbsoluteRig()
    rt = on_task(rig)
    trace = home(rt, rig)
    assert trace == list(zip(range(0, 60, 10), CHAIN))
    assert rig.axis.mechanical == -4.25
    assert rig.axis.position == pytest.approx(-4.25 + 700.0 - 690.0 + 100.0)


def test_homing_can_be_repeated_and_a_start_while_busy_is_ignored() -> None:
    rig = SwitchRig()
    rt = on_task(rig)
    rig.homing.start()
    rt.run(cycles=50)
    rig.homing.start()
    rt.run(cycles=1)
    assert (rig.homing.step, rig.homing.busy) == (HomingStep.APPROACH, True)
    rt.run(cycles=200)
    assert rig.homing.done
    first_offset = rig.axis.offset
    trace = home(rt, rig)
    assert [step for _t, step in trace] == CHAIN
    assert rig.axis.offset == pytest.approx(first_offset, abs=0.05)


# ---------------------------------------------------------------------------
# Failure paths: timeouts name the step
# ---------------------------------------------------------------------------


def test_a_broken_switch_times_out_in_approach_and_halts_the_axis() -> None:
    rig = SwitchRig()
    rig.axis.switch_broken = True
    rig.homing.timeout = T("800ms")
    rt = on_task(rig)
    trace = home(rt, rig)
    assert trace[-1] == (810, HomingStep.ERROR)
    assert (rig.homing.error, rig.homing.done, rig.homing.error_step) == (True, False, HomingStep.APPROACH)
    assert rig.homing.error_text == "APPROACH timed out after 800 ms"
    assert rig.axis.velocity == 0.0
    stopped_at = rig.axis.mechanical
    rt.run(cycles=20)
    assert rig.axis.mechanical == stopped_at
    assert rig.homing.run() is False


def test_an_unpowered_drive_fails_the_preconditions_and_a_new_start_recovers() -> None:
    rig = SwitchRig()
    rig.axis.enable = False
    rig.homing.timeout = T("300ms")
    rt = on_task(rig)
    home(rt, rig)
    assert (rig.homing.step, rig.homing.error_step) == (HomingStep.ERROR, HomingStep.PRECONDITIONS)
    assert "PRECONDITIONS timed out after 300 ms" in rig.homing.error_text
    assert rig.axis.mechanical == 35.0
    rig.axis.enable = True
    rig.homing.timeout = T("5s")
    home(rt, rig)
    assert (rig.homing.done, rig.homing.error, rig.homing.error_text) == (True, False, "")


@given(st.floats(min_value=-1e6, max_value=1e6, allow_nan=False))
def test_floor_dint_is_the_floor_for_both_signs(value: float) -> None:
    assert floor_dint(value) == math.floor(value)


def test_floor_dint_rounds_towards_minus_infinity() -> None:
    assert (floor_dint(-0.5), floor_dint(-10.0), floor_dint(9.99)) == (-1, -10, 9)


def test_an_invalid_absolute_encoder_fails_the_variants_extra_precondition() -> None:
    rig = AbsoluteRig()
    rig.axis.encoder_ok = False
    rig.homing.timeout = T("100ms")
    rt = on_task(rig)
    trace = home(rt, rig)
    # PRECONDITIONS is entered in the start scan at t=0 and its time counts from there.
    assert trace[-1] == (100, HomingStep.ERROR)
    assert rig.homing.error_step == HomingStep.PRECONDITIONS


def test_a_homing_without_its_axis_is_an_access_violation() -> None:
    homing = HomeAbsolute()
    homing.start()
    assert homing.run() is False
    with pytest.raises(PlcException) as info:
        homing.run()
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


def test_fb_init_injects_the_axis_outside_any_program() -> None:
    axis = SimAxis(start_at=7.0)
    homing = HomeAbsolute(axis=axis)
    homing.start()
    scans = 0
    while not homing.run():
        scans += 1
        assert scans < 10
    assert (scans, axis.position, homing.axis.position) == (5, 7.0, 7.0)


# ---------------------------------------------------------------------------
# Definition-time rules: FINAL, ABSTRACT
# ---------------------------------------------------------------------------


def test_overriding_the_final_template_method_is_a_definition_error() -> None:
    with pytest.raises(DefinitionError, match=r"FINAL PUBLIC METHOD AxisHoming\.run cannot be overridden"):

        class Shortcut(HomeAbsolute):
            @method
            def run(self) -> BOOL:
                return True


def test_the_abstract_base_cannot_be_instantiated() -> None:
    with pytest.raises(DefinitionError, match=r"ABSTRACT FUNCTION_BLOCK AxisHoming cannot be instantiated"):
        AxisHoming()


def test_a_variant_that_leaves_a_step_abstract_is_a_definition_error() -> None:
    with pytest.raises(DefinitionError, match=r"must be ABSTRACT or implement .*AxisHoming\.set_reference"):

        class Incomplete(AxisHoming):
            @method(PROTECTED)
            def approach(self, first: BOOL) -> BOOL:
                return True

            @method(PROTECTED)
            def find_edge(self, first: BOOL) -> BOOL:
                return True


def test_the_steps_are_callable_only_by_the_chain_and_the_variants() -> None:
    homing = HomeAbsolute(axis=SimAxis())
    with pytest.raises(AccessError, match=r"PROTECTED METHOD HomeAbsolute\.approach cannot be called from"):
        homing.approach(True)
    with pytest.raises(AccessError, match=r"only inside AxisHoming and its derived blocks"):
        homing.check_preconditions(True)


def test_a_new_variant_overrides_steps_and_keeps_the_chain() -> None:
    class HomeOnHardStop(HomeOnLimitSwitch):
        """Drive into the hard stop (no switch): the approach ends after a fixed travel."""

        @method(PROTECTED)
        def approach(self, first: BOOL) -> BOOL:
            return self.move_until(self.drive.position <= -5.0, -self.approach_velocity)

        @method(PROTECTED)
        def find_edge(self, first: BOOL) -> BOOL:
            self.edge_position = self.drive.position
            return True

    axis = SimAxis(start_at=0.0)
    homing = HomeOnHardStop(axis=axis)
    assert isinstance(homing, IHoming)
    homing.start()
    steps: list[HomingStep] = []
    for _ in range(200):
        axis()
        homing.run()
        if not steps or steps[-1] != homing.step:
            steps.append(homing.step)
    assert steps == CHAIN
    assert homing.edge_position == -5.0
    assert axis.position == pytest.approx(2.0, abs=0.05)


# ---------------------------------------------------------------------------
# The cell and the invariants
# ---------------------------------------------------------------------------


def on_task_cell(cell: HomingCell) -> Runtime:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), cell)
    return rt


def test_the_cell_homes_three_axes_through_the_interface_array_and_reports_the_fourth() -> None:
    cell = HomingCell()
    rt = on_task_cell(cell)
    rt.run(cycles=200)
    assert [h.step for h in (cell.x_homing, cell.y_homing, cell.z_homing, cell.w_homing)] == [
        HomingStep.DONE, HomingStep.DONE, HomingStep.DONE, HomingStep.ERROR
    ]
    assert cell.all_done is False
    assert cell.w_homing.error_step == HomingStep.APPROACH


@settings(max_examples=60, deadline=None)
@given(
    start=st.floats(-40.0, 60.0),
    switch_at=st.floats(-30.0, -21.0),
    back_off=st.floats(0.5, 5.0),
    home_position=st.floats(-100.0, 100.0),
)
def test_limit_switch_homing_always_ends_done_with_the_edge_at_home_position(
    start: float, switch_at: float, back_off: float, home_position: float
) -> None:
    rig = SwitchRig()
    rig.axis.switch_at = switch_at
    rig.homing.back_off_distance = back_off
    rig.homing.home_position = home_position
    rig.homing.timeout = T("10s")
    rt = on_task(rig)
    place(rt, rig.axis, start)
    trace = home(rt, rig)
    assert [step for _t, step in trace] == CHAIN
    assert [t for t, _s in trace] == sorted(t for t, _s in trace)
    creep = rig.homing.creep_velocity * 0.01
    assert rig.axis.position == pytest.approx(home_position + back_off, abs=creep + 1e-9)
    # The switch point reads home_position, less at most one creep scan of overshoot past the edge.
    assert -creep - 1e-9 <= switch_at + rig.axis.offset - home_position <= 1e-9


@settings(max_examples=60, deadline=None)
@given(start=st.floats(-50.0, 50.0), pitch=st.sampled_from([5.0, 10.0, 20.0]))
def test_index_homing_always_puts_home_position_on_the_first_mark_past_the_clearing_move(
    start: float, pitch: float
) -> None:
    rig = IndexRig()
    rig.axis.index_pitch = pitch
    rt = on_task(rig)
    place(rt, rig.axis, start)
    cleared = rig.axis.mechanical + rig.homing.clear_distance
    trace = home(rt, rig)
    assert [step for _t, step in trace] == CHAIN
    mark = rig.axis.latched_at
    assert mark / pitch == pytest.approx(round(mark / pitch), abs=1e-9)
    # The first mark after the clearing move, which may overshoot by one approach scan.
    assert cleared <= mark <= cleared + rig.homing.approach_velocity * 0.01 + pitch
    assert mark + rig.axis.offset == pytest.approx(rig.homing.home_position, abs=1e-9)
