"""TON / TOF / TP and their LTIME forms against their IEC state machines (docs/reference/stdlib.md), and the task clock."""

from __future__ import annotations

import dataclasses
import threading
import time
from collections.abc import Iterator
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import LTIME, T, use_profile
from iecoop.profiles import CODESYS, TWINCAT
from iecoop.runtime.clock import (
    Clock,
    VirtualClock,
    WallClock,
    current_clock,
    default_clock,
    now_ms,
    use_clock,
)
from iecoop.stdlib import LTOF, LTON, LTP, TOF, TON, TP

MS = 1_000_000
HOLD = dataclasses.replace(TWINCAT, tp_et_after_pulse="hold_until_next_pulse")


@pytest.fixture
def clock() -> Iterator[VirtualClock]:
    """The default clock, at 0 whatever earlier tests or doctests left in it."""
    clock = default_clock()
    clock.set(0)
    yield clock
    clock.set(0)


def ms(clock: VirtualClock, amount: int) -> None:
    clock.advance(amount * MS)


# ---------------------------------------------------------------------------
# The task clock
# ---------------------------------------------------------------------------


def test_virtual_clock_starts_at_zero_and_moves_only_when_told() -> None:
    c = VirtualClock()
    assert c.now_ns() == 0
    c.advance(1_500_000)
    assert (c.now_ns(), c.now_ms()) == (1_500_000, 1)
    c.set(LTIME("2s"))
    assert c.now_ms() == 2000
    assert VirtualClock(start_ns=7).now_ns() == 7


def test_virtual_clock_rejects_negative_time() -> None:
    c = VirtualClock()
    with pytest.raises(ValueError, match="backwards"):
        c.advance(-1)
    with pytest.raises(ValueError, match="starts at 0"):
        c.set(-5)
    with pytest.raises(ValueError, match="starts at 0"):
        VirtualClock(start_ns=-1)


def test_wall_clock_counts_from_its_creation_and_never_decreases() -> None:
    wall = WallClock()
    first = wall.now_ns()
    time.sleep(0.002)
    second = wall.now_ns()
    assert 0 <= first < second
    assert second >= 2 * MS
    assert second < 10 * 1_000 * MS


def test_default_clock_is_current_outside_a_task(clock: VirtualClock) -> None:
    assert current_clock() is clock is default_clock()
    ms(clock, 42)
    assert now_ms() == 42


def test_use_clock_installs_and_restores_in_nested_blocks(clock: VirtualClock) -> None:
    outer, inner = VirtualClock(start_ns=10 * MS), VirtualClock(start_ns=20 * MS)
    with use_clock(outer) as installed:
        assert installed is outer and current_clock() is outer and now_ms() == 10
        with use_clock(inner):
            assert now_ms() == 20
        assert current_clock() is outer
    assert current_clock() is clock


def test_use_clock_restores_after_an_exception(clock: VirtualClock) -> None:
    with pytest.raises(KeyError), use_clock(VirtualClock(start_ns=MS)):
        raise KeyError("fault in the cycle")
    assert current_clock() is clock


def test_use_clock_left_out_of_order_is_an_error(clock: VirtualClock) -> None:
    first, second = use_clock(VirtualClock()), use_clock(VirtualClock())
    first.__enter__()
    second.__enter__()
    with pytest.raises(RuntimeError, match="out of order"):
        first.__exit__(None, None, None)
    second.__exit__(None, None, None)
    first.__exit__(None, None, None)
    assert current_clock() is clock


def test_use_clock_needs_a_clock() -> None:
    with pytest.raises(TypeError, match="needs a Clock"):
        use_clock(123)  # type: ignore[arg-type]


def test_a_user_clock_subclass_drives_timers(clock: VirtualClock) -> None:
    class Fixed(Clock):
        def __init__(self, ns: int) -> None:
            self.ns = ns

        def now_ns(self) -> int:
            return self.ns

    source = Fixed(0)
    timer = TON()
    with use_clock(source):
        timer(IN=True, PT=T("1s"))
        source.ns = LTIME("1s")
        timer(IN=True)
    assert timer.Q and timer.ET == 1000
    with pytest.raises(TypeError):
        Clock()  # type: ignore[abstract]


def test_timers_read_the_installed_clock_not_the_default(clock: VirtualClock) -> None:
    task_clock = VirtualClock()
    timer = TON()
    with use_clock(task_clock):
        timer(IN=True, PT=100)
    ms(clock, 1000)
    with use_clock(task_clock):
        timer(IN=True)
        assert (timer.Q, timer.ET) == (False, 0)
        ms(task_clock, 100)
        timer(IN=True)
    assert timer.Q


# ---------------------------------------------------------------------------
# TON
# ---------------------------------------------------------------------------


def test_ton_initial_state() -> None:
    timer = TON()
    assert (timer.IN, timer.PT, timer.Q, timer.ET) == (False, 0, False, 0)
    assert (timer.STATE, timer.PREV_IN, timer.START_TIME) == (0, False, 0)


def test_ton_stays_off_while_in_is_false(clock: VirtualClock) -> None:
    timer = TON()
    for _ in range(5):
        timer(IN=False, PT=100)
        ms(clock, 1000)
        assert (timer.Q, timer.ET, timer.STATE) == (False, 0, 0)


def test_ton_rising_edge_starts_timing_and_et_counts_up_to_pt(clock: VirtualClock) -> None:
    timer = TON()
    ms(clock, 5000)  # the start time is the edge's, not the clock's origin
    timer(IN=True, PT=300)
    assert (timer.Q, timer.ET, timer.STATE, timer.START_TIME, timer.PREV_IN) == (False, 0, 1, 5000, True)
    for elapsed in (100, 200, 299):
        clock.set((5000 + elapsed) * MS)
        timer(IN=True, PT=300)
        assert (timer.Q, timer.ET, timer.STATE) == (False, elapsed, 1)
    clock.set(5300 * MS)
    timer(IN=True, PT=300)
    assert (timer.Q, timer.ET, timer.STATE) == (True, 300, 2)
    ms(clock, 10_000)
    timer(IN=True, PT=300)
    assert (timer.Q, timer.ET) == (True, 300)


def test_ton_expiry_overshoot_reports_pt_not_the_elapsed_time(clock: VirtualClock) -> None:
    timer = TON()
    timer(IN=True, PT=100)
    ms(clock, 250)
    timer(IN=True)
    assert (timer.Q, timer.ET) == (True, 100)


def test_ton_false_in_resets_at_once_from_any_state(clock: VirtualClock) -> None:
    timer = TON()
    timer(IN=True, PT=100)
    ms(clock, 50)
    timer(IN=True)
    timer(IN=False)
    assert (timer.Q, timer.ET, timer.STATE, timer.PREV_IN) == (False, 0, 0, False)
    timer(IN=True)
    ms(clock, 100)
    timer(IN=True)
    assert timer.Q
    timer(IN=False)
    assert (timer.Q, timer.ET, timer.STATE) == (False, 0, 0)


def test_ton_restart_times_from_the_new_edge(clock: VirtualClock) -> None:
    timer = TON()
    timer(IN=True, PT=100)
    ms(clock, 90)
    timer(IN=False)
    ms(clock, 5)
    timer(IN=True)
    ms(clock, 90)
    timer(IN=True)
    assert (timer.Q, timer.ET) == (False, 90)
    ms(clock, 10)
    timer(IN=True)
    assert timer.Q


def test_ton_first_call_with_in_true_is_an_edge(clock: VirtualClock) -> None:
    timer = TON()
    timer(IN=True, PT=0)
    assert not timer.Q and timer.STATE == 1


def test_ton_pt_zero_gives_q_one_call_after_the_edge(clock: VirtualClock) -> None:
    timer = TON()
    timer(IN=True, PT=0)
    assert (timer.Q, timer.ET) == (False, 0)
    timer(IN=True, PT=0)  # no time has passed
    assert (timer.Q, timer.ET) == (True, 0)


def test_ton_pt_is_read_at_every_call(clock: VirtualClock) -> None:
    timer = TON()
    timer(IN=True, PT=1000)
    ms(clock, 400)
    timer(IN=True, PT=1000)
    assert not timer.Q
    timer(IN=True, PT=300)  # lowered below the elapsed time: expires now
    assert (timer.Q, timer.ET) == (True, 300)
    timer(IN=True, PT=5000)  # raised after expiry: STATE 2 is kept
    assert (timer.Q, timer.ET, timer.STATE) == (True, 300, 2)


def test_ton_repeated_calls_in_one_instant_change_nothing(clock: VirtualClock) -> None:
    timer = TON()
    timer(IN=True, PT=100)
    ms(clock, 40)
    for _ in range(3):
        timer(IN=True, PT=100)
        assert (timer.Q, timer.ET) == (False, 40)


def test_ton_truncates_the_clock_to_milliseconds(clock: VirtualClock) -> None:
    clock.set(999_999)  # 0.999999 ms: still T#0ms
    timer = TON()
    timer(IN=True, PT=2)
    assert timer.START_TIME == 0
    clock.set(1_999_999)
    timer(IN=True)
    assert timer.ET == 1


def test_ton_times_across_the_time_wrap(clock: VirtualClock) -> None:
    wrap_ms = 1 << 32
    clock.set((wrap_ms - 30) * MS)
    timer = TON()
    timer(IN=True, PT=100)
    assert timer.START_TIME == wrap_ms - 30
    ms(clock, 60)  # past T#49d17h2m47s295ms: the clock's TIME value is 30
    timer(IN=True)
    assert (timer.Q, timer.ET) == (False, 60)
    ms(clock, 40)
    timer(IN=True)
    assert (timer.Q, timer.ET) == (True, 100)


def test_lton_works_in_nanoseconds(clock: VirtualClock) -> None:
    timer = LTON()
    clock.set(123)
    timer(IN=True, PT=LTIME("1us"))
    assert timer.START_TIME == 123
    clock.advance(999)
    timer(IN=True)
    assert (timer.Q, timer.ET) == (False, 999)
    clock.advance(1)
    timer(IN=True)
    assert (timer.Q, timer.ET) == (True, 1000)
    timer(IN=False)
    assert (timer.Q, timer.ET, timer.STATE) == (False, 0, 0)


def test_lton_times_across_the_ltime_wrap(clock: VirtualClock) -> None:
    timer = LTON()
    clock.set((1 << 64) - 10)
    timer(IN=True, PT=100)
    clock.advance(60)
    timer(IN=True)
    assert timer.ET == 60
    clock.advance(40)
    timer(IN=True)
    assert (timer.Q, timer.ET) == (True, 100)


# ---------------------------------------------------------------------------
# TOF
# ---------------------------------------------------------------------------


def test_tof_first_call_with_in_false_is_no_falling_edge(clock: VirtualClock) -> None:
    timer = TOF()
    timer(IN=False, PT=100)
    assert (timer.Q, timer.ET, timer.STATE) == (False, 0, 0)
    ms(clock, 500)
    timer(IN=False)
    assert not timer.Q


def test_tof_q_follows_in_and_holds_pt_after_the_fall(clock: VirtualClock) -> None:
    timer = TOF()
    timer(IN=True, PT=200)
    assert (timer.Q, timer.ET, timer.STATE) == (True, 0, 0)
    ms(clock, 1000)
    timer(IN=True)
    assert (timer.Q, timer.ET) == (True, 0)
    timer(IN=False)
    assert (timer.Q, timer.ET, timer.STATE, timer.START_TIME) == (True, 0, 1, 1000)
    ms(clock, 199)
    timer(IN=False)
    assert (timer.Q, timer.ET) == (True, 199)
    ms(clock, 1)
    timer(IN=False)
    assert (timer.Q, timer.ET, timer.STATE) == (False, 200, 2)
    ms(clock, 5000)
    timer(IN=False)
    assert (timer.Q, timer.ET) == (False, 200)


def test_tof_rising_edge_while_timing_resets_et_and_keeps_q(clock: VirtualClock) -> None:
    timer = TOF()
    timer(IN=True, PT=200)
    timer(IN=False)
    ms(clock, 150)
    timer(IN=False)
    timer(IN=True)
    assert (timer.Q, timer.ET, timer.STATE) == (True, 0, 0)
    ms(clock, 100)
    timer(IN=False)  # a new fall starts a new full PT
    ms(clock, 150)
    timer(IN=False)
    assert (timer.Q, timer.ET) == (True, 150)


def test_tof_rising_edge_after_expiry_resets_et(clock: VirtualClock) -> None:
    timer = TOF()
    timer(IN=True, PT=10)
    timer(IN=False)
    ms(clock, 10)
    timer(IN=False)
    assert timer.ET == 10
    timer(IN=True)
    assert (timer.Q, timer.ET) == (True, 0)


def test_tof_pt_zero_keeps_q_for_the_falling_call_only(clock: VirtualClock) -> None:
    timer = TOF()
    timer(IN=True, PT=0)
    timer(IN=False)
    assert timer.Q
    timer(IN=False)
    assert (timer.Q, timer.ET) == (False, 0)


def test_ltof_works_in_nanoseconds(clock: VirtualClock) -> None:
    timer = LTOF()
    timer(IN=True, PT=500)
    timer(IN=False)
    clock.advance(499)
    timer(IN=False)
    assert (timer.Q, timer.ET) == (True, 499)
    clock.advance(1)
    timer(IN=False)
    assert (timer.Q, timer.ET) == (False, 500)
    timer(IN=True)
    assert (timer.Q, timer.ET) == (True, 0)


# ---------------------------------------------------------------------------
# TP
# ---------------------------------------------------------------------------


def test_tp_pulse_lasts_pt_whatever_in_does(clock: VirtualClock) -> None:
    timer = TP()
    timer(IN=True, PT=100)
    assert (timer.Q, timer.ET, timer.STATE) == (True, 0, 1)
    for step, in_ in ((30, False), (30, True), (30, False)):
        ms(clock, step)
        timer(IN=in_)
        assert timer.Q
    assert timer.ET == 90
    ms(clock, 10)
    timer(IN=False)
    assert (timer.Q, timer.STATE) == (False, 0)


def test_tp_is_not_retriggerable(clock: VirtualClock) -> None:
    timer = TP()
    timer(IN=True, PT=100)
    ms(clock, 60)
    timer(IN=False)
    timer(IN=True)  # an edge during the pulse is ignored
    ms(clock, 40)
    timer(IN=True)
    assert (timer.Q, timer.ET, timer.STATE) == (False, 100, 2)


def test_tp_in_held_true_after_the_pulse_gives_no_new_pulse(clock: VirtualClock) -> None:
    timer = TP()
    timer(IN=True, PT=10)
    ms(clock, 10)
    timer(IN=True)
    for _ in range(3):
        ms(clock, 100)
        timer(IN=True)
        assert (timer.Q, timer.ET, timer.STATE) == (False, 10, 2)


def test_tp_et_after_the_pulse_iec_reference(clock: VirtualClock) -> None:
    assert TWINCAT.tp_et_after_pulse == CODESYS.tp_et_after_pulse == "reset_when_in_false"
    timer = TP()
    timer(IN=True, PT=10)
    ms(clock, 10)
    timer(IN=True)
    assert timer.ET == 10
    timer(IN=False)
    assert (timer.Q, timer.ET, timer.STATE) == (False, 0, 0)


def test_tp_pulse_ending_while_in_is_false_resets_et_in_the_same_call(clock: VirtualClock) -> None:
    timer = TP()
    timer(IN=True, PT=10)
    timer(IN=False)
    ms(clock, 10)
    timer(IN=False)
    assert (timer.Q, timer.ET, timer.STATE) == (False, 0, 0)
    timer(IN=True)  # immediately ready for the next pulse
    assert (timer.Q, timer.STATE) == (True, 1)


def test_tp_et_held_until_the_next_pulse_with_the_hold_profile(clock: VirtualClock) -> None:
    timer = TP()
    with use_profile(HOLD):
        timer(IN=True, PT=10)
        ms(clock, 10)
        timer(IN=False)
        assert (timer.Q, timer.ET, timer.STATE) == (False, 10, 0)
        ms(clock, 1000)
        timer(IN=False)
        assert timer.ET == 10
        timer(IN=True)  # the next pulse starts: ET from 0
        assert (timer.Q, timer.ET) == (True, 0)
        ms(clock, 4)
        timer(IN=True)
        assert timer.ET == 4


def test_tp_profile_is_read_at_the_call(clock: VirtualClock) -> None:
    timer = TP()
    with use_profile(HOLD):
        timer(IN=True, PT=10)
        ms(clock, 10)
        timer(IN=True)
    timer(IN=False)  # the pulse is cleared under the default profile
    assert timer.ET == 0


def test_tp_pt_zero_pulses_for_one_call(clock: VirtualClock) -> None:
    timer = TP()
    timer(IN=True, PT=0)
    assert timer.Q
    timer(IN=True, PT=0)
    assert (timer.Q, timer.ET) == (False, 0)


def test_tp_first_call_with_in_true_starts_a_pulse(clock: VirtualClock) -> None:
    timer = TP()
    timer(IN=True, PT=5)
    assert timer.Q


def test_ltp_works_in_nanoseconds(clock: VirtualClock) -> None:
    timer = LTP()
    timer(IN=True, PT=1000)
    clock.advance(999)
    timer(IN=False)
    assert (timer.Q, timer.ET) == (True, 999)
    clock.advance(1)
    timer(IN=True)
    assert (timer.Q, timer.ET, timer.STATE) == (False, 1000, 2)
    with use_profile(HOLD):
        timer(IN=False)
        assert timer.ET == 1000
    timer(IN=True)
    assert (timer.Q, timer.ET) == (True, 0)


# ---------------------------------------------------------------------------
# Properties: random IN sequences with random time steps
# ---------------------------------------------------------------------------

# (time step in ns, IN): steps cover "same instant", sub-millisecond and long gaps.
STEPS = st.lists(
    st.tuples(
        st.one_of(st.just(0), st.integers(0, 3 * MS), st.integers(0, 400 * MS)),
        st.booleans(),
    ),
    max_size=60,
)
PTS = st.one_of(st.just(0), st.integers(0, 300))

KINDS: dict[str, tuple[type[Any], type[Any], type[Any], int]] = {
    "TIME": (TON, TOF, TP, MS),
    "LTIME": (LTON, LTOF, LTP, 1),
}


def run(timer_cls: type[Any], unit: int, pt: int, steps: list[tuple[int, bool]]) -> Iterator[tuple[int, bool, bool, int]]:
    """Drive a fresh timer on its own clock; yields (time in units, IN, Q, ET) after each call."""
    clock = VirtualClock()
    timer = timer_cls()
    with use_clock(clock):
        for dt, in_ in steps:
            clock.advance(dt)
            timer(IN=in_, PT=pt)
            yield clock.now_ns() // unit, in_, timer.Q, timer.ET


@settings(max_examples=150, deadline=None)
@given(steps=STEPS, pt=PTS, kind=st.sampled_from(sorted(KINDS)))
def test_ton_matches_the_continuous_on_model(steps: list[tuple[int, bool]], pt: int, kind: str) -> None:
    """Q is TRUE iff IN has been TRUE at every call since an earlier call (the edge) at least PT ago."""
    ton_cls, _, _, unit = KINDS[kind]
    pt = pt if unit == MS else pt * MS
    since: int | None = None
    for now, in_, q, et in run(ton_cls, unit, pt, steps):
        assert 0 <= et <= pt
        if not in_:
            since = None
            assert (q, et) == (False, 0)
        elif since is None:
            since = now
            assert (q, et) == (False, 0)
        else:
            elapsed = now - since
            assert q == (elapsed >= pt)
            assert et == min(elapsed, pt)


@settings(max_examples=150, deadline=None)
@given(steps=STEPS, pt=PTS, kind=st.sampled_from(sorted(KINDS)))
def test_tof_q_is_in_or_within_pt_after_the_last_fall(steps: list[tuple[int, bool]], pt: int, kind: str) -> None:
    _, tof_cls, _, unit = KINDS[kind]
    pt = pt if unit == MS else pt * MS
    fall: int | None = None
    prev = False
    for now, in_, q, et in run(tof_cls, unit, pt, steps):
        assert 0 <= et <= pt
        if in_:
            fall = None
            assert (q, et) == (True, 0)
        elif prev:
            fall = now
            assert (q, et) == (True, 0)
        elif fall is None:
            assert (q, et) == (False, 0)
        else:
            elapsed = now - fall
            assert q == (elapsed < pt)
            assert et == min(elapsed, pt)
        prev = in_


@settings(max_examples=150, deadline=None)
@given(steps=STEPS, pt=PTS, kind=st.sampled_from(sorted(KINDS)), hold=st.booleans())
def test_tp_pulses_follow_the_pulse_model(steps: list[tuple[int, bool]], pt: int, kind: str, hold: bool) -> None:
    """A rising edge outside a pulse starts one; the pulse lasts PT whatever IN does."""
    _, _, tp_cls, unit = KINDS[kind]
    pt = pt if unit == MS else pt * MS
    start: int | None = None  # start time of the running pulse
    expired = False  # the pulse has ended and IN has not been FALSE since
    held_et = 0
    prev = False
    with use_profile(HOLD if hold else TWINCAT):
        for now, in_, q, et in run(tp_cls, unit, pt, steps):
            assert 0 <= et <= pt
            if start is not None:
                if now - start >= pt:
                    start, expired = None, True
                    expected = (False, pt)
                else:
                    expected = (True, now - start)
            elif in_ and not prev:
                start, held_et = now, 0
                expected = (True, 0)
            else:
                expected = (False, pt if expired else held_et)
            if expired and not in_:
                expired = False
                held_et = pt if hold else 0
                expected = (False, held_et)
            assert (q, et) == expected
            prev = in_


def test_timer_instances_are_independent(clock: VirtualClock) -> None:
    """Timers hold no state outside their instance: two instances, or instances in threads, never interfere."""
    a, b = TON(), TON()
    a(IN=True, PT=10)
    ms(clock, 5)
    b(IN=True, PT=10)
    ms(clock, 5)
    a(IN=True)
    b(IN=True)
    assert (a.Q, b.Q, b.ET) == (True, False, 5)
    errors: list[BaseException] = []

    def worker() -> None:
        try:
            local = TON()
            local(IN=True, PT=0)
            local(IN=True, PT=0)
            assert local.Q
        except BaseException as exc:  # surfaced below
            errors.append(exc)

    threads = [threading.Thread(target=worker) for _ in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert not errors
