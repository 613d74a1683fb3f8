"""Chain of Responsibility: PT205 signal conditioning and start permissives, across PLC cycles."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import NULL, REAL, USINT, VAR, AccessError, VAR_INPUT, VAR_OUTPUT, ExceptionCode, PlcException, Program, T, method
from iecoop.runtime import Runtime, Task
from patterns.behavioral.chain_of_responsibility import (
    MAX_CHAIN_LENGTH,
    AlarmLimits,
    AnalogInput,
    AnalogSignal,
    ChainCheck,
    EStopReleased,
    GuardDoorClosed,
    ISignalStage,
    PressureMain,
    Quality,
    RangeCheck,
    Scaling,
    SignalHealthy,
    SignalStage,
    SignalStatus,
    SpikeFilter,
)


class Probe(SignalStage):
    """A stage that only records what reached it, then forwards."""

    seen_hops: USINT = VAR_OUTPUT(0)
    seen_ma: REAL = VAR_OUTPUT(0.0)
    calls: USINT = VAR_OUTPUT(0)

    @method
    def handle(self, signal: AnalogSignal) -> None:
        self.seen_hops, self.seen_ma = signal.hops, signal.current_ma
        self.calls += 1
        super().handle(signal)


class Conditioning(Program):
    """The four standard stages behind one analog input, fed from the test."""

    loop_ma: REAL = VAR_INPUT(12.0)
    ai: AnalogInput = VAR()
    range_check: RangeCheck = VAR()
    spike_filter: SpikeFilter = VAR()
    scaling: Scaling = VAR()
    limits: AlarmLimits = VAR()

    def fb_init(self, init_retains: bool, in_copy_code: bool) -> None:
        self.range_check.set_next(self.spike_filter)
        self.spike_filter.set_next(self.scaling)
        self.scaling.set_next(self.limits)
        self.ai.chain = self.range_check

    def body(self) -> None:
        self.ai(raw_ma=self.loop_ma)


class Unwired(Program):
    ai: AnalogInput = VAR()

    def body(self) -> None:
        self.ai(raw_ma=12.0)


def _runtime(program: Program) -> Runtime:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    return rt


def _feed(rt: Runtime, cell: Conditioning, currents: list[float]) -> list[tuple[float, Quality, SignalStatus]]:
    seen = []
    for ma in currents:
        cell.loop_ma = ma
        rt.run(cycles=1)
        signal = cell.ai.signal
        seen.append((signal.value, signal.quality, signal.status))
    return seen


def _probes(n: int) -> list[Probe]:
    return [Probe() for _ in range(n)]


# ---------------------------------------------------------------------------
# The conditioning chain
# ---------------------------------------------------------------------------


def test_each_stage_sees_the_signal_once_in_link_order() -> None:
    first, second, third = _probes(3)
    first.set_next(second)
    second.set_next(third)
    ai = AnalogInput(chain=first)
    ai(raw_ma=9.5)
    ai(raw_ma=10.0)
    assert [(p.seen_hops, p.calls) for p in (first, second, third)] == [(1, 2), (2, 2), (3, 2)]
    assert (third.seen_ma, ai.signal.hops) == (10.0, 3)


def test_a_client_links_the_stages_through_i_signal_stage_alone() -> None:
    range_check, scaling, limits = RangeCheck(), Scaling(), AlarmLimits()
    stages: list[ISignalStage] = [range_check, scaling, limits]
    for before, after in zip(stages, stages[1:]):
        before.set_next(after)
    ai = AnalogInput(chain=stages[0])
    ai(raw_ma=20.0)
    assert (ai.signal.value, ai.signal.high_alarm, ai.signal.hops) == (16.0, True, 3)
    with pytest.raises(AccessError, match=r"PROTECTED METHOD SignalStage\.next_link cannot be called from"):
        range_check.next_link()


@pytest.mark.parametrize(
    ("ma", "quality", "status"),
    [
        (3.5, Quality.BAD, SignalStatus.WIRE_BREAK),
        (3.6, Quality.UNCERTAIN, SignalStatus.UNDER_RANGE),
        (3.7, Quality.UNCERTAIN, SignalStatus.UNDER_RANGE),
        (4.0, Quality.GOOD, SignalStatus.OK),
        (20.5, Quality.GOOD, SignalStatus.OK),
        (20.7, Quality.UNCERTAIN, SignalStatus.OVER_RANGE),
        (21.0, Quality.UNCERTAIN, SignalStatus.OVER_RANGE),
        (21.5, Quality.BAD, SignalStatus.SHORT_CIRCUIT),
    ],
)
def test_the_range_check_follows_namur_ne43(ma: float, quality: Quality, status: SignalStatus) -> None:
    check = RangeCheck()
    ai = AnalogInput(chain=check)
    ai(raw_ma=ma)
    assert (ai.signal.quality, ai.signal.status) == (quality, status)


def test_scaling_maps_4_to_20_ma_onto_the_engineering_range() -> None:
    scaling = Scaling()
    scaling.eu_low, scaling.eu_high = -1.0, 15.0
    ai = AnalogInput(chain=scaling)
    values = []
    for ma in (4.0, 12.0, 20.0):
        ai(raw_ma=ma)
        values.append(ai.signal.value)
    assert values == [-1.0, 7.0, 15.0]


def test_a_one_scan_spike_is_held_and_a_lasting_step_is_taken() -> None:
    cell = Conditioning()
    rt = _runtime(cell)
    assert _feed(rt, cell, [8.0, 16.0, 8.0]) == [
        (4.0, Quality.GOOD, SignalStatus.OK),
        (4.0, Quality.UNCERTAIN, SignalStatus.SPIKE_HELD),
        (4.0, Quality.GOOD, SignalStatus.OK),
    ]
    # The step persists beyond max_held_scans = 2: taken on the third scan.
    assert _feed(rt, cell, [16.0, 16.0, 16.0, 16.5]) == [
        (4.0, Quality.UNCERTAIN, SignalStatus.SPIKE_HELD),
        (4.0, Quality.UNCERTAIN, SignalStatus.SPIKE_HELD),
        (12.0, Quality.GOOD, SignalStatus.OK),
        (12.5, Quality.GOOD, SignalStatus.OK),
    ]


def test_a_wire_break_holds_the_last_good_value_and_the_alarms_and_reaches_every_stage() -> None:
    cell = Conditioning()
    rt = _runtime(cell)
    _feed(rt, cell, [16.0 + n * 0.5 for n in range(3)])     # 12, 12.5, 13 bar: HIGH
    assert cell.ai.signal.high_alarm
    assert _feed(rt, cell, [1.0, 0.0]) == [(13.0, Quality.BAD, SignalStatus.WIRE_BREAK)] * 2
    assert (cell.ai.signal.high_alarm, cell.ai.signal.hops) == (True, 4)
    # After the break the spike filter starts afresh: no SPIKE_HELD on the jump back.
    assert _feed(rt, cell, [8.0]) == [(4.0, Quality.GOOD, SignalStatus.OK)]
    assert not cell.ai.signal.high_alarm


def test_the_alarm_limits_use_their_hysteresis_across_scans() -> None:
    cell = Conditioning()
    rt = _runtime(cell)
    highs, lows = [], []
    # 12.5, 11.75, 11.25 bar, then 1.5, 2.25, 2.75 bar (the filter is opened wide for the jumps).
    cell.spike_filter.max_step_ma = 20.0
    for ma in (16.5, 15.75, 15.25, 5.5, 6.25, 6.75):
        _feed(rt, cell, [ma])
        highs.append(cell.ai.signal.high_alarm)
        lows.append(cell.ai.signal.low_alarm)
    assert highs == [True, True, False, False, False, False]
    assert lows == [False, False, False, True, True, False]


@settings(max_examples=80, deadline=None)
@given(st.lists(st.integers(0, 46).map(lambda n: n / 2), min_size=1, max_size=40))
def test_conditioning_invariants_over_random_loop_currents(currents: list[float]) -> None:
    cell = Conditioning()
    rt = _runtime(cell)
    last_value, held_run = 0.0, 0
    for ma in currents:
        cell.loop_ma = ma
        rt.run(cycles=1)
        signal = cell.ai.signal
        # Every stage saw the signal exactly once.
        assert signal.hops == 4
        # BAD exactly when NE 43 says the loop has failed, and then the value is held.
        assert (signal.quality == Quality.BAD) == (ma < 3.6 or ma > 21.0)
        if signal.quality == Quality.BAD:
            assert signal.value == last_value
        # The spike filter never holds for more than max_held_scans in a row.
        held_run = held_run + 1 if signal.status == SignalStatus.SPIKE_HELD else 0
        assert held_run <= cell.spike_filter.max_held_scans
        # The alarms agree with the value and the hysteresis band.
        if signal.quality != Quality.BAD:
            assert not signal.high_alarm or signal.value >= 11.5
            assert not (signal.value > 12.0) or signal.high_alarm
        last_value = signal.value


# ---------------------------------------------------------------------------
# Refused links and missing injection
# ---------------------------------------------------------------------------


def test_a_link_that_closes_a_loop_is_refused_and_leaves_the_chain_as_it_was() -> None:
    a, b, c = _probes(3)
    assert a.set_next(b) is True and b.set_next(c) is True
    assert (a.link_status, b.link_status) == (ChainCheck.OK, ChainCheck.OK)
    assert (c.set_next(a), c.link_status) == (False, ChainCheck.LOOP)
    assert (a.set_next(a), a.link_status) == (False, ChainCheck.LOOP)
    assert not c.next_stage and a.next_stage == b
    ai = AnalogInput(chain=a)
    assert ai.chain_status == ChainCheck.OK
    ai(raw_ma=12.0)
    assert ai.signal.hops == 3
    # The refused link left no mark behind: a later valid link is accepted.
    d = _probes(1)[0]
    assert (c.set_next(d), c.link_status) == (True, ChainCheck.OK)
    ai(raw_ma=12.0)
    assert (ai.signal.hops, d.calls) == (4, 1)


def test_a_chain_longer_than_max_chain_length_is_refused() -> None:
    stages = _probes(MAX_CHAIN_LENGTH + 1)
    for before, after in zip(stages[1:-1], stages[2:]):
        assert before.set_next(after) is True
    # stages[1..] already hold MAX_CHAIN_LENGTH links; one more in front is one too many.
    assert stages[0].set_next(stages[1]) is False
    assert stages[0].link_status == ChainCheck.TOO_LONG
    assert not stages[0].next_stage


def test_a_chain_grown_at_its_tail_after_the_head_was_checked_stops_at_run_time() -> None:
    stages = _probes(MAX_CHAIN_LENGTH + 1)
    stages[0].set_next(stages[1])
    ai = AnalogInput(chain=stages[0])
    for before, after in zip(stages[1:-1], stages[2:]):
        before.set_next(after)     # each link checks only its own tail
    for _ in range(3):
        ai(raw_ma=12.0)
        assert (ai.signal.quality, ai.signal.status) == (Quality.BAD, SignalStatus.CHAIN_TOO_LONG)
    assert [p.calls for p in stages] == [3] * MAX_CHAIN_LENGTH + [0]
    # Handing the grown chain to an input is refused up front; the input keeps the chain it had.
    other = AnalogInput(chain=stages[0])
    assert other.chain_status == ChainCheck.TOO_LONG
    assert not other.chain
    short = _probes(1)[0]
    ai.chain = short
    assert (ai.chain_status, ai.chain == short) == (ChainCheck.OK, True)
    ai.chain = stages[0]
    assert (ai.chain_status, ai.chain == short) == (ChainCheck.TOO_LONG, True)
    ai(raw_ma=12.0)
    assert (ai.signal.quality, ai.signal.status, short.calls) == (Quality.GOOD, SignalStatus.OK, 1)


def test_linking_a_null_stage_is_refused() -> None:
    ai = AnalogInput()
    assert (ai.chain_status, ai.chain) == (ChainCheck.OK, NULL)
    scaling = Scaling()
    assert (scaling.set_next(ai.chain), scaling.link_status) == (False, ChainCheck.NULL_LINK)
    assert not scaling.next_stage
    ai.chain = scaling.next_stage
    assert ai.chain_status == ChainCheck.NULL_LINK


def test_an_input_without_a_chain_faults_the_cycle_with_an_access_violation() -> None:
    rt = _runtime(Unwired())
    with pytest.raises(PlcException, match="null interface reference") as exc:
        rt.run(cycles=1)
    assert exc.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


# ---------------------------------------------------------------------------
# Start permissives
# ---------------------------------------------------------------------------


def test_the_first_failing_permissive_answers_and_the_rest_are_not_asked() -> None:
    door, estop, signal = GuardDoorClosed(), EStopReleased(), SignalHealthy()
    door.set_next(estop)
    estop.set_next(signal)
    assert door.first_failing() == "guard door open"
    door(closed=True)
    assert door.first_failing() == "emergency stop pressed"
    estop(released=True)
    assert door.first_failing() == "PT205 signal BAD"
    signal(quality=Quality.UNCERTAIN, high_alarm=True)
    assert door.first_failing() == "PT205 pressure high"
    signal(high_alarm=False)
    assert door.first_failing() == ""
    door(closed=False)
    assert door.first_failing() == "guard door open"
    assert signal.set_next(door) is False
    assert signal.link_status == ChainCheck.LOOP
    assert door.first_failing() == "guard door open"


def test_the_pressure_program_blocks_start_while_the_signal_is_bad_or_high() -> None:
    main = PressureMain()
    rt = _runtime(main)
    rt.run(cycles=19)
    assert (main.start_permitted, main.blocked_by) == (True, "")
    rt.run(cycles=1)
    assert (main.start_permitted, main.blocked_by) == (False, "PT205 signal BAD")
    main.door_closed = False
    rt.run(cycles=1)
    assert main.blocked_by == "guard door open"
    main.door_closed = True
    rt.run(cycles=5)
    assert (main.start_permitted, rt.time_ms) == (True, 260)
    rt.run(cycles=20)
    assert (main.pt205.signal.value, main.blocked_by) == (12.5, "PT205 pressure high")
