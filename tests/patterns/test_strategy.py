"""Strategy: a heater zone with swappable control strategies, checked scan by scan on the virtual clock."""

from __future__ import annotations

from typing import cast

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import BOOL, REAL, VAR, VAR_INPUT, Program, T
from iecoop.runtime import Runtime, Task
from patterns.behavioral.strategy import (
    ControlMode,
    HeaterZone,
    IControlStrategy,
    OnOffControl,
    PidControl,
    PwmControl,
    ThermalProcess,
    ZoneMain,
)

SETPOINT = 60.0


def start(program: Program) -> Runtime:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    return rt


def trace(rt: Runtime, program: ZoneMain, cycles: int) -> list[float]:
    temperatures = []
    for _ in range(cycles):
        rt.run(cycles=1)
        temperatures.append(program.process.temperature)
    return temperatures


# ---------------------------------------------------------------------------
# Each strategy reaches and holds the setpoint
# ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("mode", "settle_cycles", "band"),
    [(ControlMode.ON_OFF, 3000, 1.2), (ControlMode.PID, 3000, 0.1), (ControlMode.PWM, 4000, 1.5)],
)
def test_each_strategy_reaches_and_holds_the_setpoint(mode: ControlMode, settle_cycles: int, band: float) -> None:
    program = ZoneMain()
    program.mode = mode
    rt = start(program)
    rt.run(cycles=settle_cycles)
    held = trace(rt, program, 1000)
    assert rt.time_ms == (settle_cycles + 1000) * 10
    assert program.zone.strategy == {
        ControlMode.ON_OFF: program.on_off, ControlMode.PID: program.pid, ControlMode.PWM: program.pwm,
    }[mode]
    assert all(abs(t - SETPOINT) <= band for t in held), (min(held), max(held))
    assert abs(sum(held) / len(held) - SETPOINT) < 0.5


def test_the_process_stays_at_ambient_until_a_strategy_heats_it() -> None:
    program = ZoneMain()
    program.setpoint = 15.0
    rt = start(program)
    rt.run(cycles=200)
    assert program.process.temperature == pytest.approx(20.0)
    assert program.zone.power == 0.0
    program.setpoint = SETPOINT
    rt.run(cycles=100)
    assert program.process.temperature > 23.0
    assert program.zone.power == 100.0


def test_on_off_switches_at_the_edges_of_the_hysteresis_band() -> None:
    program = ZoneMain()
    program.mode = ControlMode.ON_OFF
    rt = start(program)
    rt.run(cycles=3000)
    switches: list[tuple[bool, float]] = []
    relay = program.on_off.relay
    for _ in range(1500):
        rt.run(cycles=1)
        if program.on_off.relay != relay:
            relay = program.on_off.relay
            switches.append((relay, program.zone.actual))
    assert len(switches) >= 4
    for switched_on, actual in switches:
        if switched_on:
            assert actual < SETPOINT - 1.0
        else:
            assert actual > SETPOINT + 1.0


# ---------------------------------------------------------------------------
# Bumpless transfer at the swap
# ---------------------------------------------------------------------------


@pytest.mark.parametrize(("first", "second"), [(ControlMode.PID, ControlMode.PWM), (ControlMode.PWM, ControlMode.PID)])
def test_a_swap_while_hot_does_not_bump_the_output(first: ControlMode, second: ControlMode) -> None:
    program = ZoneMain()
    program.mode = first
    rt = start(program)
    rt.run(cycles=4000)
    before = program.zone.output
    assert 30.0 < before < 50.0
    swaps = program.zone.swaps
    program.mode = second
    rt.run(cycles=1)
    assert program.selected == second
    assert program.zone.swaps == swaps + 1
    assert abs(program.zone.output - before) < 1.0
    after = trace(rt, program, 500)
    assert all(abs(t - SETPOINT) < 1.5 for t in after)


def test_a_cold_strategy_would_jump_where_the_takeover_does_not() -> None:
    program = ZoneMain()
    rt = start(program)
    rt.run(cycles=3000)
    before = program.zone.output
    actual = program.process.temperature
    cold = PidControl()
    cold_output = cold.execute(SETPOINT, actual, T("10ms"))
    assert abs(cold_output - before) > 30.0
    warm = PidControl()
    warm.takeover(before, SETPOINT, actual)
    assert abs(warm.execute(SETPOINT, actual, T("10ms")) - before) < 0.1


def test_on_off_takes_over_the_relay_state_nearest_the_output() -> None:
    thermostat = OnOffControl()
    thermostat.takeover(80.0, SETPOINT, SETPOINT)
    assert thermostat.relay is True and thermostat.output == 100.0
    assert thermostat.execute(SETPOINT, SETPOINT, T("10ms")) == 100.0
    thermostat.takeover(20.0, SETPOINT, SETPOINT)
    assert thermostat.execute(SETPOINT, SETPOINT, T("10ms")) == 0.0


def test_selecting_the_active_strategy_again_is_not_a_swap() -> None:
    pid, pwm = PidControl(), PwmControl()
    zone = HeaterZone(strategy=pid)
    assert zone.strategy == pid and zone.swaps == 1
    zone.strategy = pid
    assert zone.swaps == 1
    zone.strategy = pwm
    zone.strategy = pwm
    assert zone.strategy == pwm and zone.swaps == 2


def test_the_first_strategy_of_a_zone_starts_cold_at_full_power() -> None:
    program = ZoneMain()
    rt = start(program)
    rt.run(cycles=1)
    assert program.zone.output == 100.0
    assert program.zone.power == 100.0


# ---------------------------------------------------------------------------
# PID details
# ---------------------------------------------------------------------------


def test_anti_windup_lets_the_output_leave_saturation_at_once() -> None:
    pid = PidControl(kp=12.0, ti=6.0)
    for _ in range(2000):
        assert pid.execute(SETPOINT, 20.0, T("10ms")) == 100.0
    assert pid.integral == 0.0
    # The measurement overshoots by 2 K: the output drops off the limit in the same scan.
    assert pid.execute(SETPOINT, SETPOINT + 2.0, T("10ms")) == 0.0
    assert pid.execute(SETPOINT, SETPOINT - 2.0, T("10ms")) == pytest.approx(24.0, abs=0.1)


def test_derivative_acts_on_the_measurement_so_a_setpoint_step_gives_no_kick() -> None:
    pid = PidControl(kp=2.0, ti=0.0, td=1.0)
    assert pid.execute(50.0, 40.0, T("10ms")) == pytest.approx(20.0)
    assert pid.execute(60.0, 40.0, T("10ms")) == pytest.approx(40.0)
    # A measurement rising by 0.1 K in 10 ms is 10 K/s: kp * td * 10 = 20 % less.
    assert pid.execute(60.0, 40.1, T("10ms")) == pytest.approx(2.0 * (19.9 - 10.0), abs=0.01)


@settings(max_examples=100, deadline=None)
@given(
    output=st.floats(0.0, 100.0),
    setpoint=st.floats(20.0, 200.0),
    actual=st.floats(20.0, 200.0),
)
def test_takeover_then_one_scan_moves_the_output_only_by_one_integral_step(
    output: float, setpoint: float, actual: float
) -> None:
    pid = PidControl(kp=12.0, ti=6.0)
    pid.takeover(output, setpoint, actual)
    assert pid.output == pytest.approx(output, abs=1e-3)
    after = pid.execute(setpoint, actual, T("10ms"))
    step = 12.0 * abs(setpoint - actual) * 0.01 / 6.0
    assert abs(after - output) <= step + 0.01


@settings(max_examples=50, deadline=None)
@given(actuals=st.lists(st.floats(-50.0, 300.0), min_size=1, max_size=200))
def test_pid_output_stays_within_0_and_100_percent(actuals: list[float]) -> None:
    pid = PidControl(kp=12.0, ti=6.0, td=0.5)
    for actual in actuals:
        output = pid.execute(SETPOINT, actual, T("10ms"))
        assert 0.0 <= output <= 100.0
        assert output == pid.output


# ---------------------------------------------------------------------------
# Time-proportional output: TON period, TP on-time
# ---------------------------------------------------------------------------


class PwmBench(Program):
    """Drives a PwmControl at a constant duty: setpoint = actual, so only the integral acts."""

    pwm: PwmControl = VAR()
    duty: REAL = VAR_INPUT(25.0)
    armed: BOOL = VAR(False)
    relay: BOOL = VAR(False)

    def body(self) -> None:
        if not self.armed:
            self.pwm.takeover(self.duty, SETPOINT, SETPOINT)
            self.armed = True
        self.relay = self.pwm.execute(SETPOINT, SETPOINT, T("10ms")) == 100.0


# A 624 ms pulse is seen by the 10 ms scans as 63 scans: TP's Q drops at the first scan after PT.
@pytest.mark.parametrize(("duty", "on_scans"), [(25.0, 25), (0.0, 0), (100.0, 100), (62.4, 63)])
def test_pwm_gives_duty_times_period_of_on_time_in_every_period(duty: float, on_scans: int) -> None:
    bench = PwmBench()
    bench.duty = duty
    rt = start(bench)
    per_period = []
    for _ in range(4):
        ons = 0
        for _ in range(100):
            rt.run(cycles=1)
            ons += bench.relay
        per_period.append(ons)
    assert per_period == [on_scans] * 4
    assert bench.pwm.periods == 4
    assert bench.pwm.on_time == round(duty * 10)
    assert bench.pwm.output == pytest.approx(duty)


def test_pwm_on_pulse_starts_at_the_beginning_of_each_period() -> None:
    bench = PwmBench()
    bench.duty = 30.0
    rt = start(bench)
    relay = []
    for _ in range(200):
        rt.run(cycles=1)
        relay.append(bench.relay)
    assert relay == ([True] * 30 + [False] * 70) * 2


def test_pwm_period_is_a_property_with_a_lower_limit() -> None:
    pwm = PwmControl(period=T("2s"))
    assert pwm.period == 2000
    pwm.period = T("500ms")
    assert pwm.period == 500
    pwm.period = T("50ms")
    assert pwm.period == 100
    pwm.period = T("100ms")
    assert pwm.period == 100
    assert PwmControl(period=T("10ms")).period == 100


# ---------------------------------------------------------------------------
# The simulated process: first-order lag in REAL
# ---------------------------------------------------------------------------


def test_the_process_is_a_first_order_lag() -> None:
    process = ThermalProcess(ambient=20.0, gain=1.0, tau=10.0)
    for _ in range(1000):
        process(power=50.0, cycle_time=T("10ms"))
    # One time constant: 63.2 % of the 50 K step (Euler at dt = tau / 1000).
    assert process.temperature == pytest.approx(20.0 + 50.0 * 0.632, abs=0.05)
    for _ in range(9000):
        process()
    assert process.temperature == pytest.approx(70.0, abs=0.01)


# ---------------------------------------------------------------------------
# Failure paths
# ---------------------------------------------------------------------------


class BareZone(Program):
    zone: HeaterZone = VAR()

    def body(self) -> None:
        self.zone(setpoint=SETPOINT, actual=20.0)


def test_a_zone_without_a_strategy_keeps_the_heater_off_and_says_so() -> None:
    bare = BareZone()
    rt = start(bare)
    rt.run(cycles=5)
    assert (bare.zone.no_strategy, bare.zone.power, bare.zone.output) == (True, 0.0, 0.0)
    pid = PidControl()
    bare.zone.strategy = pid
    rt.run(cycles=1)
    assert (bare.zone.no_strategy, bare.zone.power) == (False, 100.0)   # 40 K below the setpoint


def test_a_null_strategy_is_refused_and_the_active_one_kept() -> None:
    pid = PidControl()
    zone = HeaterZone(strategy=pid)
    zone.strategy = cast(IControlStrategy, None)
    assert (zone.strategy == pid, zone.swaps) == (True, 1)
    zone(setpoint=SETPOINT, actual=20.0)
    assert (zone.no_strategy, zone.power) == (False, 100.0)


def test_bad_gains_are_refused_and_the_gains_before_stay() -> None:
    assert PidControl(kp=0.0).tune_error is True
    assert (PidControl(kp=0.0).kp, PidControl(ti=-1.0).ti) == (12.0, 6.0)
    pid = PidControl()
    assert pid.tune_error is False
    assert pid.tune(5.0, 1.0, -0.1) is False
    assert (pid.kp, pid.ti, pid.td, pid.tune_error) == (12.0, 6.0, 0.0, True)
    assert pid.tune(-1.0, 1.0) is False
    assert pid.tune(5.0, 0.0, 0.5) is True
    assert (pid.kp, pid.ti, pid.td, pid.tune_error) == (5.0, 0.0, 0.5, False)


def test_a_time_constant_of_zero_keeps_the_default() -> None:
    process = ThermalProcess(ambient=25.0, tau=0.0)
    assert (process.tau, process.ambient, process.temperature) == (20.0, 25.0, 25.0)
    for _ in range(2000):
        process(power=50.0, cycle_time=T("10ms"))
    assert process.temperature == pytest.approx(25.0 + 50.0 * 0.632, abs=0.05)
