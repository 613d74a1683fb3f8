"""The access-level setpoint proxy and the caching remote-I/O proxy, run on the virtual clock."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import (
    BOOL,
    LREAL,
    VAR,
    VAR_INPUT,
    ExceptionCode,
    FunctionBlock,
    PlcException,
    Program,
    T,
    method,
    prop,
)
from iecoop.runtime import Runtime, Task
from patterns.structural.proxy import (
    AccessLevel,
    CachedAnalogInput,
    ISetpoint,
    OvenMain,
    OvenSetpoint,
    Quality,
    Refusal,
    RemoteAnalogInput,
    SetpointAccessProxy,
)

OP, MAINT, ENG = AccessLevel.OPERATOR, AccessLevel.MAINTENANCE, AccessLevel.ENGINEER
#: The table the proxy must enforce: (low, high, max_step) per level.
LIMITS = {OP: (150.0, 250.0, 10.0), MAINT: (100.0, 300.0, 50.0), ENG: (0.0, 400.0, 400.0)}


def _runtime(prog: Program) -> Runtime:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), prog)
    return rt


def _proxy() -> tuple[SetpointAccessProxy, OvenSetpoint]:
    oven = OvenSetpoint()
    return SetpointAccessProxy(subject=oven), oven


# ---------------------------------------------------------------------------
# Protection proxy
# ---------------------------------------------------------------------------


def test_the_proxy_and_the_oven_share_the_setpoint_interface() -> None:
    proxy, oven = _proxy()
    clients: list[ISetpoint] = [proxy, oven]
    assert [c.setpoint for c in clients] == [180.0, 180.0]
    assert proxy.write(185.0) and proxy.setpoint == oven.setpoint == 185.0
    assert oven.write(350.0) and proxy.setpoint == 350.0


@pytest.mark.parametrize("level", [OP, MAINT, ENG])
def test_each_level_may_write_up_to_its_limits_and_not_beyond(level: AccessLevel) -> None:
    low, high, step = LIMITS[level]
    proxy, oven = _proxy()
    proxy.login(ENG)
    assert proxy.write(low)
    proxy.login(level)
    refusals = [proxy.write(low - 0.5), proxy.last_refusal]
    proxy.login(ENG)
    assert proxy.write(high)
    proxy.login(level)
    refusals += [proxy.write(high + 0.5), proxy.last_refusal]
    assert refusals == [False, Refusal.BELOW_LIMIT, False, Refusal.ABOVE_LIMIT]
    assert proxy.write(high - step) and oven.setpoint == high - step
    assert proxy.last_refusal == Refusal.NONE
    assert (proxy.refused, oven.writes) == (2, 3)


def test_an_operator_may_only_nudge_the_setpoint() -> None:
    proxy, oven = _proxy()
    assert proxy.write(190.0)
    assert proxy.write(200.5) is False
    assert proxy.last_refusal == Refusal.STEP_TOO_LARGE
    assert proxy.message == "OPERATOR write 200.5 refused: step over 10.0"
    assert oven.setpoint == 190.0 and proxy.refused == 1


class LockedSetpoint(FunctionBlock, ISetpoint):
    """Another subject: refuses every write while a batch runs."""

    locked: BOOL = VAR_INPUT(False)
    value: LREAL = VAR(200.0)

    @method
    def write(self, value: LREAL) -> BOOL:
        if self.locked:
            return False
        self.value = value
        return True

    @prop
    def setpoint(self) -> LREAL:
        return self.value


def test_a_write_the_subject_refuses_is_counted_as_refused() -> None:
    subject = LockedSetpoint()
    proxy = SetpointAccessProxy(subject=subject)
    subject.locked = True
    assert proxy.write(205.0) is False
    assert (proxy.last_refusal, proxy.refused, subject.setpoint) == (Refusal.SUBJECT_REFUSED, 1, 200.0)
    assert "refused by the oven" in proxy.message
    subject.locked = False
    assert proxy.write(205.0) and subject.setpoint == 205.0


def test_a_higher_level_falls_back_to_operator_after_idle_time_and_a_write_restarts_it() -> None:
    prog = OvenMain()
    prog.access.logout_after = T("2s")
    rt = _runtime(prog)
    prog.access.login(ENG)
    rt.run(cycles=150)
    assert prog.hmi_setpoint.write(320.0)
    rt.run(cycles=199)
    assert prog.access.level == ENG
    rt.run(cycles=2)
    assert prog.access.level == OP
    assert prog.hmi_setpoint.write(330.0) is False
    assert prog.access.last_refusal == Refusal.ABOVE_LIMIT


def test_the_oven_setpoint_is_persistent() -> None:
    prog = OvenMain()
    rt = _runtime(prog)
    assert prog.hmi_setpoint.write(185.0)
    rt.run(cycles=2)
    rt.reset_cold()
    assert prog.oven_setpoint.setpoint == 185.0
    rt.reset_origin()
    assert prog.oven_setpoint.setpoint == 180.0


def test_a_proxy_without_a_subject_faults_on_a_write_it_would_forward() -> None:
    proxy = SetpointAccessProxy()
    assert proxy.write(500.0) is False, "refused by the table before the subject is needed"
    with pytest.raises(PlcException, match="null interface") as info:
        proxy.write(190.0)
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


WRITES = st.lists(st.tuples(st.sampled_from([OP, MAINT, ENG]), st.integers(-100, 500).map(float)), max_size=30)


@settings(max_examples=100, deadline=None)
@given(writes=WRITES)
def test_every_write_obeys_the_writers_limits(writes: list[tuple[AccessLevel, float]]) -> None:
    proxy, oven = _proxy()
    model, refused = 180.0, 0
    for level, value in writes:
        proxy.login(level)
        low, high, step = LIMITS[level]
        allowed = low <= value <= high and abs(value - model) <= step
        assert proxy.write(value) == allowed
        if allowed:
            model = value
        else:
            refused += 1
        assert oven.setpoint == model
    assert (proxy.refused, oven.writes) == (refused, len(writes) - refused)


# ---------------------------------------------------------------------------
# Remote proxy with a cache
# ---------------------------------------------------------------------------


class Remote(Program):
    """A station read through the cache; the test drives the station's inputs."""

    station: RemoteAnalogInput = VAR()
    cached: CachedAnalogInput = VAR()
    answered: BOOL = VAR(False)

    def body(self) -> None:
        if not self.cached.station:
            self.cached.station = self.station
        self.cached()
        self.answered = self.cached.read()


def test_the_real_subject_answers_after_its_response_time_or_times_out() -> None:
    class Direct(Program):
        station: RemoteAnalogInput = VAR()
        answers: LREAL = VAR(0.0)

        def body(self) -> None:
            if self.station.read():
                self.answers += 1.0

    prog = Direct()
    prog.station.remote_value = 1.25
    rt = _runtime(prog)
    rt.run(cycles=4)
    assert (prog.station.quality, prog.station.busy) == (Quality.NO_DATA, True)
    rt.run(cycles=1)
    assert (prog.station.quality, prog.station.value, prog.answers) == (Quality.GOOD, 1.25, 1.0)
    rt.run(cycles=95)
    assert (prog.station.requests, prog.answers) == (20, 20.0)
    prog.station.link_ok = False
    rt.run(cycles=21)
    assert prog.station.quality == Quality.BAD
    assert prog.station.value == 1.25


def test_the_cache_answers_every_cycle_and_polls_the_station_at_its_interval() -> None:
    prog = Remote()
    prog.station.remote_value = 3.5
    rt = _runtime(prog)
    rt.run(cycles=1)
    assert prog.answered and prog.cached.quality == Quality.NO_DATA
    rt.run(cycles=4)
    assert (prog.cached.quality, prog.cached.value) == (Quality.GOOD, 3.5)
    prog.station.remote_value = 4.0
    rt.run(cycles=50)
    assert prog.cached.value == 3.5, "the cache changes only at the next poll"
    rt.run(cycles=5)
    assert prog.cached.value == 4.0
    rt.run(cycles=940)
    assert rt.time_ms == 10_000
    # One poll per 500 ms interval plus the 40 ms answer: 10 s / 550 ms, not 10 s / 50 ms.
    assert prog.station.requests == 19
    assert prog.cached.refreshes == 19


def test_a_lost_link_keeps_the_last_value_and_turns_it_stale_then_good_again() -> None:
    prog = Remote()
    prog.station.remote_value = 2.0
    rt = _runtime(prog)
    rt.run(cycles=5)
    last_answer = rt.time_ms - 10
    prog.station.link_ok = False
    prog.station.remote_value = 9.0
    rt.run(cycles=199)
    assert (prog.cached.quality, prog.cached.value) == (Quality.GOOD, 2.0)
    assert rt.time_ms - 10 - last_answer == 1990
    rt.run(cycles=1)
    assert (prog.cached.quality, prog.cached.value) == (Quality.STALE, 2.0)
    prog.station.link_ok = True
    rt.run(cycles=60)
    assert (prog.cached.quality, prog.cached.value) == (Quality.GOOD, 9.0)


def test_a_cache_without_a_station_faults_in_the_first_cycle() -> None:
    class Unwired(Program):
        cached: CachedAnalogInput = VAR()

        def body(self) -> None:
            self.cached()

    rt = _runtime(Unwired())
    with pytest.raises(PlcException, match="ACCESS_VIOLATION") as info:
        rt.run(cycles=1)
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


@settings(max_examples=40, deadline=None)
@given(link=st.lists(st.booleans(), min_size=1, max_size=40))
def test_stale_exactly_when_no_good_answer_for_stale_after(link: list[bool]) -> None:
    prog = Remote()
    rt = _runtime(prog)
    last_answer, answered_value, refreshes = -1, 0.0, 0
    for step, up in enumerate(link):
        prog.station.link_ok = up
        for _ in range(10):  # 100 ms per step
            prog.station.remote_value = float(step)
            rt.run(cycles=1)
            scan = rt.time_ms - 10
            if prog.cached.refreshes != refreshes:
                refreshes, last_answer, answered_value = prog.cached.refreshes, scan, float(step)
            if last_answer < 0:
                assert prog.cached.quality == Quality.NO_DATA
                continue
            stale = scan - last_answer >= 2000
            assert prog.cached.quality == (Quality.STALE if stale else Quality.GOOD)
            assert prog.cached.value == answered_value
