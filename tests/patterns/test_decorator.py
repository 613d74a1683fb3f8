"""Sensor decorators stacked in any order, run cycle after cycle on the virtual clock."""

from __future__ import annotations

import itertools

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import VAR, VAR_INPUT, DefinitionError, ExceptionCode, PlcException, Program, T
from iecoop.runtime import Runtime, Task
from patterns.structural.decorator import (
    MAX_WINDOW,
    RAW_FULL_SCALE,
    ISensor,
    MaintenanceCounter,
    MovingAverage,
    PressureMain,
    PressureTransmitter,
    SensorDecorator,
    SimulationOverride,
)


def _runtime(prog: Program, profile: str = "twincat") -> Runtime:
    rt = Runtime(store=":memory:", profile=profile)
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), prog)
    return rt


def _bar(raw: int) -> float:
    return 10.0 * raw / RAW_FULL_SCALE


class Bench(Program):
    """One transmitter and one of each decorator; the test wires them and sets ``pv``."""

    pt: PressureTransmitter = VAR(fb_init={"low": 0.0, "high": 10.0})
    average: MovingAverage = VAR()
    override: SimulationOverride = VAR()
    counter: MaintenanceCounter = VAR()
    pv: ISensor = VAR_INPUT()

    def body(self) -> None:
        self.pv.scan()


def _stack(bench: Bench, order: tuple[SensorDecorator, ...]) -> None:
    below: ISensor = bench.pt
    for layer in order:
        layer.inner = below
        below = layer
    bench.pv = below


# ---------------------------------------------------------------------------
# The program: PT101 → counter → average → override
# ---------------------------------------------------------------------------


def test_the_program_filters_a_step_over_four_cycles() -> None:
    prog = PressureMain()
    rt = _runtime(prog)
    prog.pt101.raw = 0
    rt.run(cycles=4)
    prog.pt101.raw = RAW_FULL_SCALE // 2
    seen = []
    for _ in range(5):
        rt.run(cycles=1)
        seen.append(round(prog.pressure, 3))
    half = round(_bar(RAW_FULL_SCALE // 2), 3)
    assert seen == [round(half / 4, 3), round(half / 2, 3), round(3 * half / 4, 3), half, half]
    assert prog.pressure_ok


def test_a_wire_break_holds_the_average_and_flags_the_value_bad() -> None:
    prog = PressureMain()
    rt = _runtime(prog)
    raw = 9830
    prog.pt101.raw = raw
    rt.run(cycles=5)
    held = prog.pressure
    prog.pt101.error = True
    prog.pt101.raw = 0
    rt.run(cycles=3)
    assert (prog.pressure, prog.pressure_ok) == (held, False)
    assert held == pytest.approx(_bar(raw))
    prog.pt101.error = False
    rt.run(cycles=1)
    assert prog.pressure_ok and prog.pressure == pytest.approx(3 * held / 4)


def test_simulation_reaches_the_logic_unfiltered_while_the_counter_keeps_counting() -> None:
    prog = PressureMain()
    rt = _runtime(prog)
    prog.override.sim_value = 4.5
    prog.override.simulate = True
    prog.pt101.error = True
    rt.run(cycles=1)
    assert (prog.pressure, prog.pressure_ok) == (4.5, True)
    prog.pt101.error = False
    for bar in (7.0, 2.0, 7.0, 2.0):
        prog.pt101.raw = round(bar / 10.0 * RAW_FULL_SCALE)
        rt.run(cycles=1)
        assert prog.pressure == 4.5
    assert prog.counter.switchings == 2
    prog.override.simulate = False
    rt.run(cycles=1)
    assert prog.pressure == pytest.approx((2.0 + 7.0 + 2.0 + 2.0) / 4, abs=1e-3)


# ---------------------------------------------------------------------------
# Each decorator
# ---------------------------------------------------------------------------


def test_maintenance_counter_counts_whole_seconds_in_service_on_the_task_clock() -> None:
    bench = Bench()
    _stack(bench, (bench.counter,))
    rt = _runtime(bench)
    rt.run(cycles=350)
    assert (rt.time_ms, bench.counter.operating_s) == (3500, 3)
    bench.pt.error = True
    rt.run(cycles=100)
    assert bench.counter.operating_s == 3, "nothing counts while the sensor is bad"
    bench.pt.error = False
    rt.run(cycles=100)
    assert bench.counter.operating_s == 3, "the half second before the outage was dropped"
    rt.run(cycles=1)
    assert bench.counter.operating_s == 4
    assert bench.counter.operating_hours == pytest.approx(4 / 3600)


def test_maintenance_counter_counts_switchings_with_hysteresis_and_flags_service() -> None:
    bench = Bench()
    _stack(bench, (bench.counter,))
    bench.counter.switch_point = 6.0
    bench.counter.hysteresis = 0.5
    bench.counter.max_switchings = 2
    rt = _runtime(bench)
    counts = []
    for bar in (2.0, 6.1, 5.8, 6.2, 5.4, 6.05, 6.5, 1.0, 7.0):
        bench.pt.raw = round(bar / 10.0 * RAW_FULL_SCALE)
        rt.run(cycles=1)
        counts.append(bench.counter.switchings)
    assert counts == [0, 1, 1, 1, 1, 2, 2, 2, 3]
    assert bench.counter.service_due
    bench.counter.reset_counters()
    assert (bench.counter.switchings, bench.counter.operating_s, bench.counter.service_due) == (0, 0, False)


def test_maintenance_counters_are_retain_and_survive_a_cold_reset_on_twincat() -> None:
    bench = Bench()
    _stack(bench, (bench.counter,))
    rt = _runtime(bench)
    bench.pt.raw = RAW_FULL_SCALE
    rt.run(cycles=250)
    assert (bench.counter.operating_s, bench.counter.switchings) == (2, 1)
    rt.reset_cold()
    assert (bench.counter.operating_s, bench.counter.switchings) == (2, 1)
    rt.reset_origin()
    assert (bench.counter.operating_s, bench.counter.switchings) == (0, 0)


@pytest.mark.parametrize(("window", "effective"), [(0, 1), (-3, 1), (1, 1), (MAX_WINDOW + 5, MAX_WINDOW)])
def test_moving_average_window_is_clamped(window: int, effective: int) -> None:
    bench = Bench()
    _stack(bench, (bench.average,))
    bench.average.window = window
    rt = _runtime(bench)
    values = list(range(0, 3000, 100))
    for raw in values:
        bench.pt.raw = raw
        rt.run(cycles=1)
    expected = sum(_bar(r) for r in values[-effective:]) / effective
    assert bench.pv.value == pytest.approx(expected)


def test_a_decorator_with_nothing_wrapped_is_an_access_violation() -> None:
    lone = MovingAverage()
    with pytest.raises(PlcException, match="null interface") as info:
        lone.scan()
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION
    bench = Bench()
    bench.pv = bench.override
    rt = _runtime(bench)
    with pytest.raises(PlcException, match="ACCESS_VIOLATION"):
        rt.run(cycles=1)


def test_fb_init_injection_and_the_property_wire_the_same_way() -> None:
    pt = PressureTransmitter(low=0.0, high=16.0)
    injected = SimulationOverride(inner=pt)
    assert injected.inner == pt
    wired = SimulationOverride()
    assert not wired.inner
    wired.inner = injected
    pt.raw = RAW_FULL_SCALE
    wired.scan()
    assert (wired.value, wired.ok) == (16.0, True)


def test_the_abstract_decorator_cannot_be_instantiated() -> None:
    with pytest.raises(DefinitionError, match="SensorDecorator"):
        SensorDecorator()


# ---------------------------------------------------------------------------
# Any order: the contract holds for every stacking
# ---------------------------------------------------------------------------

ORDERS = list(itertools.permutations(range(3)))


def _layers(bench: Bench, order: tuple[int, ...]) -> tuple[SensorDecorator, ...]:
    layers: tuple[SensorDecorator, ...] = (bench.average, bench.override, bench.counter)
    return tuple(layers[i] for i in order)


@settings(max_examples=60, deadline=None)
@given(
    order=st.sampled_from(ORDERS),
    window=st.integers(1, MAX_WINDOW),
    raws=st.lists(st.integers(0, RAW_FULL_SCALE), min_size=1, max_size=40),
)
def test_any_order_without_simulation_gives_the_moving_average_of_the_transmitter(
    order: tuple[int, ...], window: int, raws: list[int]
) -> None:
    bench = Bench()
    _stack(bench, _layers(bench, order))
    bench.average.window = window
    bench.counter.switch_point = 5.0
    rt = _runtime(bench)
    crossings, above = 0, False
    for i, raw in enumerate(raws):
        bench.pt.raw = raw
        rt.run(cycles=1)
        last = [_bar(r) for r in raws[max(0, i + 1 - window) : i + 1]]
        assert bench.pv.value == pytest.approx(sum(last) / len(last), rel=1e-12, abs=1e-12)
        assert bench.pv.ok
        # The counter sees the average when it is stacked above it.
        seen = bench.pv.value if order.index(2) > order.index(0) else _bar(raw)
        if seen >= 5.0 and not above:
            crossings += 1
        above = seen >= 5.0 or (above and seen >= 4.5)
    assert bench.counter.switchings == crossings


@settings(max_examples=30, deadline=None)
@given(order=st.sampled_from(ORDERS), window=st.integers(1, MAX_WINDOW), sim=st.floats(-5.0, 50.0))
def test_any_order_with_simulation_settles_on_the_simulated_value_within_the_window(
    order: tuple[int, ...], window: int, sim: float
) -> None:
    bench = Bench()
    _stack(bench, _layers(bench, order))
    bench.average.window = window
    bench.override.sim_value = sim
    bench.override.simulate = True
    bench.pt.error = True
    rt = _runtime(bench)
    rt.run(cycles=window)
    assert bench.pv.value == pytest.approx(sim)
    assert bench.pv.ok
