"""Builder: fluent motion profiles, validation before build(), and the runner across cycles."""

from __future__ import annotations

from collections.abc import Callable

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import BOOL, VAR, VAR_INPUT, DefinitionError, Program, T
from iecoop.runtime import Runtime, Task
from patterns.creational.builder import (
    MAX_SEGMENTS,
    FeedAxisMain,
    IProfileBuilder,
    MotionProfile,
    ProfileBuilder,
    ProfileError,
    ProfileRunner,
    SegmentKind,
)


class RunnerCell(Program):
    """A task program around one runner; the test loads profiles and toggles ``execute``."""

    runner: ProfileRunner = VAR()
    execute: BOOL = VAR_INPUT(False)

    def body(self) -> None:
        self.runner(execute=self.execute)


def runtime_for(program: Program) -> Runtime:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    return rt


def index_move(builder: IProfileBuilder) -> IProfileBuilder:
    return builder.begin("index").ramp(200.0, T("100ms")).cruise(T("400ms")).ramp(0.0, T("100ms")).target(100.0)


def test_the_fluent_chain_builds_the_product() -> None:
    builder, profile = ProfileBuilder(), MotionProfile()
    chained = builder.begin("index").ramp(200.0, T("100ms"))
    assert chained is builder  # THIS^
    assert index_move(builder).build(profile) == ProfileError.NONE
    assert (profile.name, profile.count, profile.target, profile.valid) == ("index", 3, 100.0, True)
    kinds = [profile.segments[i].kind for i in range(1, 4)]
    assert kinds == [SegmentKind.RAMP, SegmentKind.CRUISE, SegmentKind.RAMP]
    assert [profile.segments[i].velocity for i in range(1, 4)] == [200.0, 200.0, 0.0]
    assert profile.segments[4].kind == SegmentKind.NONE
    assert builder.planned_distance == pytest.approx(100.0)


Steps = Callable[[IProfileBuilder], IProfileBuilder]

STEP_ERRORS: list[tuple[Steps, ProfileError, int]] = [
    (lambda b: b.begin("x").ramp(-5.0, T("100ms")), ProfileError.NEGATIVE_VELOCITY, 1),
    (lambda b: b.begin("x").ramp(100.0, T("100ms")).ramp(600.0, T("1s")), ProfileError.VELOCITY_LIMIT, 2),
    (lambda b: b.begin("x").ramp(400.0, T("50ms")), ProfileError.ACCEL_LIMIT, 1),
    (lambda b: b.begin("x").ramp(100.0, T("100ms")).cruise(T("0ms")), ProfileError.ZERO_DURATION, 2),
    (lambda b: b.begin("x").ramp(100.0, T("100ms")).dwell(T("1s")), ProfileError.DWELL_WHILE_MOVING, 2),
    (lambda b: b.begin("x").dwell(T("0ms")), ProfileError.ZERO_DURATION, 1),
]


@pytest.mark.parametrize(("steps", "error", "step"), STEP_ERRORS)
def test_a_bad_step_is_reported_with_its_number_and_build_refuses(steps: Steps, error: ProfileError, step: int) -> None:
    builder, profile = ProfileBuilder(), MotionProfile(valid=True)
    steps(builder)
    assert (builder.error, builder.error_step) == (error, step)
    assert builder.target(0.0).build(profile) == error
    assert not profile.valid


def test_the_ninth_segment_does_not_fit_the_array() -> None:
    builder = ProfileBuilder()
    builder.begin("long")
    for _ in range(MAX_SEGMENTS + 1):
        builder.dwell(T("10ms"))
    assert (builder.error, builder.error_step) == (ProfileError.TOO_MANY_SEGMENTS, MAX_SEGMENTS + 1)


@pytest.mark.parametrize(
    ("steps", "error"),
    [
        (lambda b: b.begin("x").ramp(200.0, T("100ms")).ramp(0.0, T("100ms")), ProfileError.NO_TARGET),
        (lambda b: b.begin("x").ramp(200.0, T("100ms")).target(10.0), ProfileError.ENDS_MOVING),
        (lambda b: b.begin("x").ramp(200.0, T("100ms")).ramp(0.0, T("100ms")).target(25.0), ProfileError.DISTANCE_MISMATCH),
    ],
)
def test_build_checks_the_whole_profile(steps: Steps, error: ProfileError) -> None:
    builder, profile = ProfileBuilder(), MotionProfile()
    assert steps(builder).build(profile) == error
    assert builder.error_step == 0 and not profile.valid


def test_the_first_error_latches_until_begin() -> None:
    builder, profile = ProfileBuilder(), MotionProfile()
    builder.begin("x").ramp(-1.0, T("100ms")).ramp(100.0, T("100ms")).ramp(0.0, T("100ms")).target(10.0)
    assert (builder.error, builder.error_step) == (ProfileError.NEGATIVE_VELOCITY, 1)
    assert builder.build(profile) == ProfileError.NEGATIVE_VELOCITY
    assert index_move(builder).build(profile) == ProfileError.NONE
    assert builder.error == ProfileError.NONE and profile.valid


def test_the_builder_is_final() -> None:
    with pytest.raises(DefinitionError, match=r"cannot EXTEND ProfileBuilder: ProfileBuilder is FINAL"):

        class LooseBuilder(ProfileBuilder):
            pass


def test_the_director_runs_the_index_move_segment_by_segment() -> None:
    axis = FeedAxisMain()
    rt = runtime_for(axis)
    rt.run(cycles=1)
    assert (axis.index_result, axis.jog_result, axis.jog_step) == (ProfileError.NONE, ProfileError.VELOCITY_LIMIT, 2)
    assert not axis.jog_move.valid
    runner = axis.runner
    expected = {
        50: (1, 100.0, 2.5),  # the cycle at t=50 ms: half-way up the first ramp
        100: (2, 200.0, 10.0),
        300: (2, 200.0, 50.0),
        550: (3, 100.0, 97.5),
        600: (4, 0.0, 100.0),
    }
    while rt.time_ms <= 790:
        at = rt.time_ms
        rt.run(cycles=1)
        if at in expected:
            step, velocity, position = expected[at]
            assert runner.step == step
            assert runner.velocity == pytest.approx(velocity)
            assert runner.position == pytest.approx(position)
        assert runner.busy
    rt.run(cycles=1)  # t=800 ms: the dwell ends
    assert runner.done and not runner.busy and runner.step == 0
    assert runner.position == pytest.approx(100.0)
    rt.run(cycles=20)
    assert runner.position == pytest.approx(100.0)  # execute stays TRUE: no restart without an edge


def test_the_runner_refuses_a_profile_that_was_not_built() -> None:
    cell = RunnerCell()
    rt = runtime_for(cell)
    assert not cell.runner.load(MotionProfile(count=1))
    assert cell.runner.error == ProfileError.NOT_BUILT
    cell.execute = True
    rt.run(cycles=5)
    assert not cell.runner.busy and cell.runner.error == ProfileError.NOT_BUILT


def test_the_runner_refuses_a_new_profile_while_busy_and_restarts_on_an_edge() -> None:
    cell, profile = RunnerCell(), MotionProfile()
    rt = runtime_for(cell)
    index_move(ProfileBuilder()).build(profile)
    assert cell.runner.load(profile)
    cell.execute = True
    rt.run(cycles=10)
    assert cell.runner.busy
    assert not cell.runner.load(profile) and cell.runner.error == ProfileError.BUSY
    rt.run(cycles=51)  # 600 ms of segments: the cycles at t=0 .. 600 ms
    assert cell.runner.done and cell.runner.position == pytest.approx(100.0)
    cell.execute = False
    rt.run(cycles=1)
    cell.execute = True
    rt.run(cycles=61)
    assert cell.runner.done and cell.runner.position == pytest.approx(200.0)


move = st.tuples(
    st.integers(min_value=1, max_value=50).map(lambda n: n * 10.0),  # cruise velocity, mm/s
    st.integers(min_value=10, max_value=30).map(lambda n: n * 10),  # ramp time, ms (accel <= 5000)
    st.integers(min_value=0, max_value=30).map(lambda n: n * 10),  # cruise time, ms (0: none)
    st.integers(min_value=0, max_value=20).map(lambda n: n * 10),  # dwell time, ms (0: none)
)


@settings(max_examples=40, deadline=None)
@given(st.lists(move, min_size=1, max_size=2))
def test_a_valid_profile_ends_at_its_target_after_the_sum_of_its_segments(moves: list[tuple[float, int, int, int]]) -> None:
    builder, profile = ProfileBuilder(), MotionProfile()
    builder.begin("random")
    total_ms = 0
    for velocity, ramp_ms, cruise_ms, dwell_ms in moves:
        builder.ramp(velocity, ramp_ms)
        if cruise_ms:
            builder.cruise(cruise_ms)
        builder.ramp(0.0, ramp_ms)
        if dwell_ms:
            builder.dwell(dwell_ms)
        total_ms += 2 * ramp_ms + cruise_ms + dwell_ms
    assert builder.target(builder.planned_distance).build(profile) == ProfileError.NONE
    cell = RunnerCell()
    rt = runtime_for(cell)
    cell.runner.load(profile)
    cell.execute = True
    rt.run(cycles=total_ms // 10)
    assert cell.runner.busy and cell.runner.velocity >= 0.0
    rt.run(cycles=1)
    assert cell.runner.done
    assert cell.runner.position == pytest.approx(profile.target, abs=1e-6)
