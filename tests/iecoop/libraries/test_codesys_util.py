"""CODESYS Util: signals, monitors, ramps, characteristic curve, integral, derivative and controllers, by hand-worked values."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from iecoop import ARRAY, DINT, Program, Struct, T, VAR
from iecoop.libraries import codesys_util as cu
from iecoop.libraries import known, module_of
from iecoop.runtime import Runtime, Task
from iecoop.runtime.clock import VirtualClock, default_clock

MS = 1_000_000


@pytest.fixture
def clock() -> Iterator[VirtualClock]:
    clock = default_clock()
    clock.set(0)
    yield clock
    clock.set(0)


def test_the_module_is_the_known_library_and_exports_its_st_names() -> None:
    library = known("Util")
    assert library is not None and module_of(library) is cu
    for name in cu.__all__:
        assert hasattr(cu, name), name


def test_blink_starts_high_and_freezes_when_disabled(clock: VirtualClock) -> None:
    blink = cu.BLINK()
    seen = []
    for _ in range(8):  # 50 ms steps: high 150 ms, low 100 ms
        blink(ENABLE=True, TIMEHIGH=T("150ms"), TIMELOW=T("100ms"))
        seen.append(blink.OUT)
        clock.advance(50 * MS)
    assert seen == [True, True, True, False, False, True, True, True]
    blink(ENABLE=False)
    assert blink.OUT  # OUT keeps its value; OUT AND ENABLE is FALSE
    clock.advance(500 * MS)
    blink(ENABLE=False)
    assert blink.OUT
    blink(ENABLE=True)
    assert blink.OUT


def test_blink_in_a_runtime_follows_the_task_clock() -> None:
    class Main(Program):
        blink: cu.BLINK = VAR()
        ons: DINT = VAR(0)

        def body(self) -> None:
            self.blink(ENABLE=True, TIMEHIGH=T("20ms"), TIMELOW=T("30ms"))
            if self.blink.OUT:
                self.ons += 1

    main = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), main)
    rt.run(cycles=10)  # 100 ms: two periods of 50 ms, each 2 cycles high
    assert main.ons == 4


def test_hysteresis_switches_below_low_and_above_high() -> None:
    h = cu.HYSTERESIS()
    outs = []
    for value in (50, 19, 50, 80, 81, 50, 20, 19):
        h(IN=value, LOW=20, HIGH=80)
        outs.append(h.OUT)
    assert outs == [False, True, True, True, False, False, False, True]


def test_limitalarm() -> None:
    alarm = cu.LIMITALARM()
    rows = []
    for value in (-5, 0, 50, 100, 101):
        alarm(IN=value, LOW=0, HIGH=100)
        rows.append((alarm.O, alarm.U, alarm.IL))
    assert rows == [(False, True, False), (False, False, True), (False, False, True), (False, False, True), (True, False, False)]


def test_ramp_real_limits_the_slope_per_timebase(clock: VirtualClock) -> None:
    ramp = cu.RAMP_REAL()
    ramp(IN=0.0, ASCEND=10.0, DESCEND=20.0, TIMEBASE=T("1s"))
    assert ramp.OUT == 0.0  # the first call takes IN
    outs = []
    for target in (5.0, 5.0, 5.0, 5.0, 5.0, 5.0, 5.0, -1.0, -1.0):
        clock.advance(100 * MS)
        ramp(IN=target)
        outs.append(round(ramp.OUT, 4))
    assert outs == [1.0, 2.0, 3.0, 4.0, 5.0, 5.0, 5.0, 3.0, 1.0]
    ramp(IN=42.0, RESET=True)
    assert ramp.OUT == 42.0


def test_ramp_int_per_call_when_timebase_is_zero(clock: VirtualClock) -> None:
    ramp = cu.RAMP_INT()
    ramp(IN=0, ASCEND=3, DESCEND=5, TIMEBASE=0)
    outs = []
    for target in (10, 10, 10, 10, 0, 0):
        ramp(IN=target)
        outs.append(ramp.OUT)
    assert outs == [3, 6, 9, 10, 5, 0]


class Curve(Struct):
    points: ARRAY[cu.POINT] = VAR(bounds=(0, 10))


def curve() -> Curve:
    line = Curve()
    for i, (x, y) in enumerate([(0, 0), (250, 50), (500, 150), (750, 400), (1000, 1000)]):
        line.points[i] = cu.POINT(X=x, Y=y)
    return line


def test_charcurve_interpolates_between_points() -> None:
    line, fb = curve(), cu.CHARCURVE()
    results = []
    for value in (0, 125, 250, 600, 1000):
        fb(IN=value, N=5, P=line.points)
        results.append((fb.OUT, fb.ERR))
    assert results == [(0, 0), (25, 0), (50, 0), (250, 0), (1000, 0)]


def test_charcurve_errors() -> None:
    line, fb = curve(), cu.CHARCURVE()
    fb(IN=1200, N=5, P=line.points)
    assert (fb.OUT, fb.ERR) == (1000, 2)  # outside: the end point's Y
    fb(IN=-3, N=5, P=line.points)
    assert (fb.OUT, fb.ERR) == (0, 2)
    fb(IN=10, N=1, P=line.points)
    assert fb.ERR == 4
    fb(IN=10, N=12, P=line.points)
    assert fb.ERR == 4
    fb(IN=10, N=6, P=line.points)  # P[5] is (0, 0): not ascending
    assert fb.ERR == 1


def test_integral_sums_in_times_tm_and_locks_on_overflow() -> None:
    integral = cu.INTEGRAL()
    for _ in range(4):
        integral(IN=2.5, TM=100)
    assert integral.OUT == pytest.approx(1.0)
    integral(IN=3.0e38, TM=2000)
    assert integral.OVERFLOW
    integral(IN=1.0, TM=1000)
    assert integral.OVERFLOW and integral.OUT == pytest.approx(1.0)
    integral(RESET=True)
    assert (integral.OUT, integral.OVERFLOW) == (0.0, False)


def test_derivative_of_a_straight_line_is_its_slope() -> None:
    derivative = cu.DERIVATIVE()
    outs = []
    for k in range(6):
        derivative(IN=3.0 * k * 0.1, TM=100)  # 3 units per second, sampled every 100 ms
        outs.append(round(derivative.OUT, 6))
    assert outs[0] == 0.0
    assert outs[4:] == [3.0, 3.0]
    derivative(IN=0.0, TM=100, RESET=True)
    assert derivative.OUT == 0.0


def test_pd_is_proportional_plus_derivative(clock: VirtualClock) -> None:
    pd = cu.PD()
    pd(ACTUAL=0.0, SET_POINT=10.0, KP=2.0, TV=0.5, Y_OFFSET=1.0)
    assert pd.Y == pytest.approx(21.0)  # 2 * 10 + 1; no de/dt at the first call
    clock.advance(100 * MS)
    pd(ACTUAL=1.0)
    # e = 9, de/dt = -1 / 0.1 s = -10: 2 * (9 + 0.5 * -10) + 1
    assert pd.Y == pytest.approx(9.0)


def test_pid_integrates_and_stops_at_its_limits(clock: VirtualClock) -> None:
    pid = cu.PID()
    pid(ACTUAL=0.0, SET_POINT=1.0, KP=1.0, TN=2.0, TV=0.0, Y_MIN=-100.0, Y_MAX=100.0)
    assert pid.Y == pytest.approx(1.0)
    ys = []
    for _ in range(4):
        clock.advance(500 * MS)
        pid(ACTUAL=0.0)
        ys.append(pid.Y)
    # each call adds e * 0.5 s to the integral; Y = 1 + integral / TN
    assert ys == pytest.approx([1.25, 1.5, 1.75, 2.0])
    pid(Y_MAX=1.8, Y_MIN=0.0)
    clock.advance(500 * MS)
    pid()
    assert pid.LIMITS_ACTIVE
    assert pid.Y == pytest.approx(1.8)
    pid(Y_MAX=100.0)
    clock.advance(500 * MS)
    pid()
    assert pid.Y == pytest.approx(2.25)  # the integral stopped while limited: 1 + (2.0 + 0.5) / 2
    pid(MANUAL=True, Y_MANUAL=7.0)
    assert pid.Y == 7.0
    pid(MANUAL=False, RESET=True, Y_OFFSET=0.5)
    assert pid.Y == 0.5
    clock.advance(500 * MS)
    pid(RESET=False)
    assert pid.Y == pytest.approx(0.5 + 1.0 + 0.25)  # the integral restarted from 0
