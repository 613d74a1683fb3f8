"""Observer: the TT101 transmitter and its alarm, trend and logger, across PLC cycles."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import BOOL, DINT, NULL, REAL, VAR, VAR_INPUT, VAR_OUTPUT, FunctionBlock, Program, T, method
from iecoop.runtime import Runtime, Task
from patterns.behavioral.observer import (
    LOG_SIZE,
    MAX_OBSERVERS,
    TREND_SIZE,
    AttachRefusal,
    EventLogger,
    HighTemperatureAlarm,
    IObserver,
    LogReason,
    Quality,
    ReactorMain,
    TemperatureTransmitter,
    TrendBuffer,
)


class CountingObserver(FunctionBlock, IObserver):
    updates: DINT = VAR_OUTPUT(0)
    last_value: REAL = VAR_OUTPUT(0.0)
    last_quality: Quality = VAR_OUTPUT(Quality.GOOD)

    @method
    def update(self, value: REAL, quality: Quality) -> None:
        self.updates += 1
        self.last_value, self.last_quality = value, quality


class Bench(Program):
    """TT101 fed from the test between cycles, with the three real observers attached."""

    temperature: REAL = VAR_INPUT(20.0)
    wire_break: BOOL = VAR_INPUT(False)
    tt: TemperatureTransmitter = VAR()
    alarm: HighTemperatureAlarm = VAR()
    trend: TrendBuffer = VAR()
    logger: EventLogger = VAR()

    def fb_init(self, init_retains: bool, in_copy_code: bool) -> None:
        self.tt.attach(self.alarm)
        self.tt.attach(self.trend)
        self.tt.attach(self.logger)

    def body(self) -> None:
        self.tt(raw_temperature=self.temperature, wire_break=self.wire_break)


class Subscribers(Program):
    """Four counting observers; the test flags attach / detach requests served in the next cycle."""

    tt: TemperatureTransmitter = VAR()
    a: CountingObserver = VAR()
    b: CountingObserver = VAR()
    c: CountingObserver = VAR()
    d: CountingObserver = VAR()
    e: CountingObserver = VAR()
    spare: IObserver = VAR()
    detach_b: BOOL = VAR_INPUT(False)
    attach_e: BOOL = VAR_INPUT(False)
    attach_spare: BOOL = VAR_INPUT(False)
    last_result: BOOL = VAR(False)

    def body(self) -> None:
        if self.detach_b:
            self.detach_b = False
            self.last_result = self.tt.detach(self.b)
        if self.attach_e:
            self.attach_e = False
            self.last_result = self.tt.attach(self.e)
        if self.attach_spare:
            self.attach_spare = False
            self.last_result = self.tt.attach(self.spare)
        self.tt(raw_temperature=50.0)


def _runtime(program: Program) -> Runtime:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    return rt


def _feed(rt: Runtime, bench: Bench, values: list[float]) -> list[bool]:
    states = []
    for value in values:
        bench.temperature = value
        rt.run(cycles=1)
        states.append(bench.alarm.active)
    return states


# ---------------------------------------------------------------------------
# The high-temperature alarm
# ---------------------------------------------------------------------------


def test_the_alarm_waits_for_the_on_delay_then_clears_only_below_the_hysteresis_band() -> None:
    bench = Bench()
    rt = _runtime(bench)
    bench.alarm.delay = T("50ms")
    # Above 90 from t=10 ms: the 50 ms on-delay expires at t=60 ms, the 7th scan.
    states = _feed(rt, bench, [85.0] + [95.0] * 6)
    assert states == [False] * 6 + [True]
    assert rt.time_ms == 70
    # 86 and 89 are inside the band (85..90): the alarm stays; 84.5 clears it.
    assert _feed(rt, bench, [89.0, 86.0, 85.0, 84.5]) == [True, True, True, False]


def test_a_dip_below_the_limit_restarts_the_on_delay() -> None:
    bench = Bench()
    rt = _runtime(bench)
    bench.alarm.delay = T("30ms")
    states = _feed(rt, bench, [95.0, 95.0, 95.0, 90.0, 95.0, 95.0, 95.0, 95.0])
    assert states == [False, False, False, False, False, False, False, True]


def test_a_wire_break_sets_sensor_fault_and_holds_the_alarm_as_it_was() -> None:
    bench = Bench()
    rt = _runtime(bench)
    bench.alarm.delay = T("20ms")
    _feed(rt, bench, [95.0] * 3)
    assert bench.alarm.active
    bench.wire_break = True
    assert _feed(rt, bench, [20.0] * 5) == [True] * 5
    assert (bench.tt.quality, bench.alarm.sensor_fault) == (Quality.BAD, True)
    bench.wire_break = False
    assert _feed(rt, bench, [20.0]) == [False]
    assert (bench.tt.quality, bench.alarm.sensor_fault) == (Quality.GOOD, False)


def test_a_wire_break_restarts_a_running_on_delay() -> None:
    bench = Bench()
    rt = _runtime(bench)
    bench.alarm.delay = T("30ms")
    _feed(rt, bench, [95.0, 95.0])
    bench.wire_break = True
    _feed(rt, bench, [95.0])
    bench.wire_break = False
    # Timing starts again at the first GOOD sample after the break, so 30 ms later, not 10.
    assert _feed(rt, bench, [95.0] * 4) == [False, False, False, True]


def test_a_value_outside_the_calibrated_range_is_clamped_and_uncertain() -> None:
    bench = Bench()
    rt = _runtime(bench)
    _feed(rt, bench, [400.0])
    assert (bench.tt.value, bench.tt.quality) == (250.0, Quality.UNCERTAIN)
    _feed(rt, bench, [-80.0])
    assert (bench.tt.value, bench.tt.quality) == (-50.0, Quality.UNCERTAIN)


def _alarm_model(samples: list[tuple[float, bool]], limit: float, hysteresis: float, delay: int) -> list[bool]:
    """The alarm in plain Python: one sample every 10 ms, from t = 0."""
    active, above_since, states = False, -1, []
    for scan, (value, bad) in enumerate(samples):
        now = scan * 10
        if bad:
            above_since = -1
        else:
            if value > limit:
                above_since = now if above_since < 0 else above_since
            else:
                above_since = -1
            if active:
                active = not value < limit - hysteresis
            else:
                active = above_since >= 0 and now - above_since >= delay
        states.append(active)
    return states


#: Offsets from the high limit, in 0.5 degree steps; None stands for "exactly limit - hysteresis".
_LEVELS = (-10.0, None, -0.5, 0.0, 0.5, 6.0)


@settings(max_examples=100, deadline=None)
@given(
    runs=st.lists(
        # (level, scans at that level, wire break): the boundaries and the on-delay are both hit often.
        st.tuples(st.sampled_from(_LEVELS), st.integers(1, 6), st.integers(0, 7).map(lambda n: n == 0)),
        min_size=4,
        max_size=20,
    ),
    limit=st.integers(80, 100),
    hysteresis=st.integers(0, 6).map(lambda n: n / 2),
    delay=st.integers(1, 5).map(lambda n: n * 10),
)
def test_the_alarm_matches_the_plain_python_model(
    runs: list[tuple[float | None, int, bool]], limit: int, hysteresis: float, delay: int
) -> None:
    bench = Bench()
    rt = _runtime(bench)
    bench.alarm.high_limit, bench.alarm.hysteresis, bench.alarm.delay = limit, hysteresis, delay
    values = [
        (limit - hysteresis if offset is None else limit + offset, bad)
        for offset, scans, bad in runs
        for _ in range(scans)
    ]
    states = []
    for value, bad in values:
        bench.temperature, bench.wire_break = value, bad
        rt.run(cycles=1)
        states.append(bench.alarm.active)
    assert states == _alarm_model(values, float(limit), hysteresis, delay)


# ---------------------------------------------------------------------------
# The trend buffer and the event logger
# ---------------------------------------------------------------------------


def test_the_trend_keeps_the_newest_samples_and_decimates() -> None:
    bench = Bench()
    rt = _runtime(bench)
    _feed(rt, bench, [float(n) for n in range(1, 4)])
    assert bench.trend.stored == 3
    assert [bench.trend.value_at(age) for age in range(3)] == [3.0, 2.0, 1.0]
    _feed(rt, bench, [float(n) for n in range(4, 21)])
    assert bench.trend.stored == TREND_SIZE
    assert [bench.trend.value_at(age) for age in range(TREND_SIZE)] == [float(n) for n in range(20, 12, -1)]
    bench.trend.decimation = 5
    _feed(rt, bench, [float(n) for n in range(21, 31)])
    assert [bench.trend.value_at(age) for age in range(3)] == [30.0, 25.0, 20.0]


def test_reading_the_trend_past_its_stored_samples_gives_zero() -> None:
    bench = Bench()
    rt = _runtime(bench)
    _feed(rt, bench, [1.0, 2.0])
    assert [bench.trend.value_at(age) for age in (-1, 0, 1, 2, TREND_SIZE)] == [0.0, 2.0, 1.0, 0.0, 0.0]
    _feed(rt, bench, [float(n) for n in range(3, 3 + TREND_SIZE)])
    # Full: the oldest sample is the last one readable, the ring does not wrap round to the newest.
    assert (bench.trend.value_at(TREND_SIZE - 1), bench.trend.value_at(TREND_SIZE)) == (3.0, 0.0)


def test_the_logger_records_first_sample_deadband_moves_and_quality_changes_with_task_time() -> None:
    bench = Bench()
    rt = _runtime(bench)
    _feed(rt, bench, [50.0, 52.0, 54.9, 55.0, 49.0])
    bench.wire_break = True
    _feed(rt, bench, [10.0, 90.0])
    bench.wire_break = False
    _feed(rt, bench, [60.0])
    seen = [
        (e.time_ms, e.value, e.quality, e.reason)
        for e in (bench.logger.entry(n) for n in range(1, bench.logger.total + 1))
    ]
    assert seen == [
        (0, 50.0, Quality.GOOD, LogReason.FIRST_SAMPLE),
        (30, 55.0, Quality.GOOD, LogReason.DEADBAND),
        (40, 49.0, Quality.GOOD, LogReason.DEADBAND),
        (50, 49.0, Quality.BAD, LogReason.QUALITY_CHANGED),
        (70, 60.0, Quality.GOOD, LogReason.QUALITY_CHANGED),
    ]


def test_logger_entries_overwritten_by_the_ring_are_refused() -> None:
    bench = Bench()
    rt = _runtime(bench)
    bench.logger.deadband = 1.0
    _feed(rt, bench, [float(n * 2) for n in range(LOG_SIZE + 3)])
    assert bench.logger.total == LOG_SIZE + 3
    assert bench.logger.entry(4).value == 6.0
    for number in (3, 0, LOG_SIZE + 4):
        gone = bench.logger.entry(number)
        assert (gone.time_ms, gone.value, gone.quality) == (0, 0.0, Quality.BAD)
    assert bench.logger.entry(LOG_SIZE + 3).quality == Quality.GOOD


# ---------------------------------------------------------------------------
# Attach and detach
# ---------------------------------------------------------------------------


def test_every_attached_observer_is_told_once_per_scan_and_a_duplicate_attach_is_refused() -> None:
    subs = Subscribers()
    assert subs.tt.attach(subs.a) is True
    assert subs.tt.attach(subs.a) is False
    assert subs.tt.observer_count == 1
    rt = _runtime(subs)
    rt.run(cycles=5)
    assert (subs.a.updates, subs.a.last_value, subs.a.last_quality) == (5, 50.0, Quality.GOOD)


def test_detach_at_run_time_compacts_the_array_and_keeps_the_order() -> None:
    subs = Subscribers()
    for observer in (subs.a, subs.b, subs.c):
        subs.tt.attach(observer)
    rt = _runtime(subs)
    rt.run(cycles=3)
    subs.detach_b = True
    rt.run(cycles=4)
    assert (subs.last_result, subs.tt.observer_count) == (True, 2)
    assert (subs.a.updates, subs.b.updates, subs.c.updates) == (7, 3, 7)
    assert subs.tt.observers[1] == subs.a and subs.tt.observers[2] == subs.c
    assert subs.tt.observers[3] == NULL
    subs.detach_b = True
    rt.run(cycles=1)
    assert (subs.last_result, subs.tt.observer_count) == (False, 2)
    # The freed slot is reused at the end.
    subs.attach_e = True
    rt.run(cycles=2)
    assert (subs.last_result, subs.tt.observer_count) == (True, 3)
    assert subs.tt.observers[3] == subs.e
    assert (subs.a.updates, subs.e.updates) == (10, 2)


def test_attaching_past_max_observers_is_refused_as_list_full() -> None:
    subs = Subscribers()
    for observer in (subs.a, subs.b, subs.c, subs.d):
        assert subs.tt.attach(observer) is True
    assert (subs.tt.observer_count, subs.tt.refusal) == (MAX_OBSERVERS, AttachRefusal.NONE)
    rt = _runtime(subs)
    rt.run(cycles=2)
    subs.attach_e = True
    rt.run(cycles=3)
    assert (subs.last_result, subs.tt.refusal) == (False, AttachRefusal.LIST_FULL)
    assert subs.tt.observer_count == MAX_OBSERVERS
    assert (subs.a.updates, subs.e.updates) == (5, 0)
    # Detaching one makes room; the next attach is accepted and clears the refusal.
    subs.detach_b = True
    subs.attach_e = True
    rt.run(cycles=1)
    assert (subs.last_result, subs.tt.refusal, subs.tt.observer_count) == (True, AttachRefusal.NONE, MAX_OBSERVERS)
    assert subs.e.updates == 1


def test_a_duplicate_attach_is_refused_as_already_attached() -> None:
    subs = Subscribers()
    subs.tt.attach(subs.a)
    assert subs.tt.attach(subs.a) is False
    assert (subs.tt.refusal, subs.tt.observer_count) == (AttachRefusal.ALREADY_ATTACHED, 1)


def test_attaching_a_null_observer_is_refused_and_the_scan_goes_on() -> None:
    subs = Subscribers()
    assert subs.tt.attach(subs.spare) is False
    assert subs.tt.refusal == AttachRefusal.NULL_OBSERVER
    subs.tt.attach(subs.a)
    rt = _runtime(subs)
    subs.attach_spare = True
    rt.run(cycles=2)
    assert (subs.last_result, subs.tt.refusal) == (False, AttachRefusal.NULL_OBSERVER)
    assert (subs.tt.observer_count, subs.a.updates) == (1, 2)


# ---------------------------------------------------------------------------
# The reactor program
# ---------------------------------------------------------------------------


def test_the_reactor_program_detaches_the_trend_and_survives_a_cold_reset() -> None:
    reactor = ReactorMain()
    rt = _runtime(reactor)
    rt.run(cycles=70)
    assert (reactor.tt101.observer_count, reactor.trend.stored) == (2, TREND_SIZE)
    frozen = reactor.trend.value_at(0)
    rt.run(cycles=10)
    assert reactor.trend.value_at(0) == frozen
    rt.reset_cold()
    # FB_init runs again on the re-initialised memory: all three observers are wired once more.
    assert (reactor.tt101.observer_count, reactor.trend.stored, reactor.logger.total, reactor.high_alarm.active) == (3, 0, 0, False)
    rt.run(cycles=1)
    assert reactor.logger.total == 1 and reactor.trend.stored == 1
