"""Thermocouples sharing calibration tables: memory, conversion and the shared references."""

from __future__ import annotations

import bisect
import struct

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import ExceptionCode, PlcException, T, adr, sizeof
from iecoop.runtime import Runtime, Task
from patterns.structural.flyweight import (
    MAX_POINTS,
    N_THERMOCOUPLES,
    CalibrationTable,
    FurnaceMain,
    GVL_Thermocouples,
    Thermocouple,
    ThermocoupleType,
    ThermocoupleWithTable,
    calibration_table,
    interpolate,
)

K, J = ThermocoupleType.TYPE_K, ThermocoupleType.TYPE_J
REFERENCE_SIZE = 8  # REFERENCE TO on a 64-bit target


def _runtime(prog: FurnaceMain) -> Runtime:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), prog)
    return rt


def _table_rows(sensor: ThermocoupleType) -> list[tuple[float, float]]:
    table = GVL_Thermocouples.TC_TYPE_K if sensor == K else GVL_Thermocouples.TC_TYPE_J
    return [(table.points[i].mv, table.points[i].deg_c) for i in range(1, table.count + 1)]


def _reference(rows: list[tuple[float, float]], mv: float) -> float:
    """Plain-Python linear interpolation, clamped at both ends."""
    xs = [x for x, _ in rows]
    if mv <= xs[0]:
        return rows[0][1]
    if mv >= xs[-1]:
        return rows[-1][1]
    i = bisect.bisect_right(xs, mv) - 1
    (x0, y0), (x1, y1) = rows[i], rows[i + 1]
    return y0 + (mv - x0) * (y1 - y0) / (x1 - x0)


def _real(x: float) -> float:
    return float(struct.unpack("f", struct.pack("f", x))[0])


# ---------------------------------------------------------------------------
# Memory: what the sharing saves
# ---------------------------------------------------------------------------


def test_a_flyweight_instance_holds_a_reference_where_the_copy_holds_the_table() -> None:
    assert sizeof(ThermocoupleWithTable) - sizeof(Thermocouple) >= sizeof(CalibrationTable) - REFERENCE_SIZE
    assert sizeof(Thermocouple) <= 24
    assert sizeof(CalibrationTable) >= MAX_POINTS * 2 * 4


def test_two_hundred_flyweights_take_less_than_a_fifth_of_the_copies() -> None:
    prog = FurnaceMain()
    shared = sizeof(prog, "thermocouples") + 2 * sizeof(CalibrationTable)
    copied = N_THERMOCOUPLES * sizeof(ThermocoupleWithTable)
    assert sizeof(prog, "thermocouples") == N_THERMOCOUPLES * sizeof(Thermocouple)
    assert shared * 5 < copied
    assert (shared, copied) == (5064, 30400)


def test_every_thermocouple_references_one_of_the_two_shared_tables() -> None:
    prog = FurnaceMain()
    k_table, j_table = adr(GVL_Thermocouples, "TC_TYPE_K"), adr(GVL_Thermocouples, "TC_TYPE_J")
    targets = [adr(prog.thermocouples[i], "table") for i in range(1, N_THERMOCOUPLES + 1)]
    assert targets.count(k_table) == 120
    assert targets.count(j_table) == 80
    assert prog.thermocouples[120].sensor == K and prog.thermocouples[121].sensor == J


def test_the_copying_design_owns_an_equal_but_separate_table() -> None:
    copy = ThermocoupleWithTable(sensor=J)
    assert copy.table == GVL_Thermocouples.TC_TYPE_J
    assert adr(copy, "table") != adr(GVL_Thermocouples, "TC_TYPE_J")


# ---------------------------------------------------------------------------
# Conversion
# ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("sensor", "raw_uv", "expected"),
    [(K, 0, 0.0), (K, 4096, 100.0), (K, 41276, 1000.0), (K, -3554, -100.0), (J, 5269, 100.0), (J, 69553, 1200.0)],
)
def test_at_a_table_point_the_temperature_is_the_points(sensor: ThermocoupleType, raw_uv: int, expected: float) -> None:
    tc = Thermocouple(sensor=sensor)
    tc.raw_uv = raw_uv
    assert tc.temperature == pytest.approx(expected, abs=1e-3)
    assert tc.in_range


def test_between_points_the_offset_is_added_and_outside_the_table_it_clamps() -> None:
    tc = Thermocouple(sensor=K)
    tc.raw_uv = 6117  # half-way between 100 and 200 degC
    tc.offset = 2.5
    assert tc.temperature == pytest.approx(150.0 + 2.5, abs=0.01)
    tc.raw_uv = 60000
    assert (tc.temperature, tc.in_range) == (1300.0 + 2.5, False)
    tc.raw_uv = -9000
    assert (tc.temperature, tc.in_range) == (-200.0 + 2.5, False)


def test_use_rebinds_the_reference_to_the_other_type_at_run_time() -> None:
    tc = Thermocouple(sensor=K)
    tc.raw_uv = 41276
    assert tc.temperature == pytest.approx(1000.0, abs=1e-3)
    tc.use(J)
    assert tc.sensor == J
    assert tc.temperature == pytest.approx(733.7, abs=0.05)
    assert adr(tc, "table") == adr(GVL_Thermocouples, "TC_TYPE_J")


def test_the_program_tracks_the_hottest_sensor_cycle_after_cycle() -> None:
    prog = FurnaceMain()
    rt = _runtime(prog)
    hottest = []
    # Type K at 200, 400, 700, 800, 1000 degC against type J at 1000, 800, 600, 400, 200 degC.
    for k_uv, j_uv in zip((8138, 16397, 29129, 33275, 41276), (57953, 45494, 33102, 21848, 10779)):
        prog.thermocouples[10].raw_uv = k_uv
        prog.thermocouples[190].raw_uv = j_uv
        rt.run(cycles=1)
        hottest.append((prog.hottest_at, round(prog.hottest)))
    assert hottest == [(190, 1000), (190, 800), (10, 700), (10, 800), (10, 1000)]
    assert prog.out_of_range == 0
    prog.thermocouples[10].raw_uv = 99999
    rt.run(cycles=1)
    assert (prog.out_of_range, prog.hottest_at) == (1, 190)
    assert rt.time_ms == 60


def test_a_thermocouple_whose_type_was_never_chosen_faults_on_first_use() -> None:
    tc = Thermocouple()
    tc.raw_uv = 1000
    with pytest.raises(PlcException, match="not bound") as info:
        _ = tc.temperature
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


@pytest.mark.parametrize("points", [1, MAX_POINTS + 1])
def test_a_table_needs_two_to_max_points(points: int) -> None:
    rows = tuple((float(i), float(i)) for i in range(points))
    with pytest.raises(ValueError, match="2 .. 16 points"):
        calibration_table(K, rows)


# ---------------------------------------------------------------------------
# Invariants of the interpolation
# ---------------------------------------------------------------------------

RAW = st.integers(-9000, 75000)


@settings(max_examples=100, deadline=None)
@given(sensor=st.sampled_from([K, J]), a=RAW, b=RAW, offset=st.sampled_from([0.0, -1.5, 3.25]))
def test_temperature_is_monotonic_in_the_raw_value(sensor: ThermocoupleType, a: int, b: int, offset: float) -> None:
    low, high = Thermocouple(sensor=sensor), Thermocouple(sensor=sensor)
    low.raw_uv, high.raw_uv = min(a, b), max(a, b)
    low.offset = high.offset = offset
    assert low.temperature <= high.temperature


@settings(max_examples=100, deadline=None)
@given(sensor=st.sampled_from([K, J]), raw_uv=RAW)
def test_temperature_matches_a_plain_python_reference_and_the_copying_design(
    sensor: ThermocoupleType, raw_uv: int
) -> None:
    shared, copied = Thermocouple(sensor=sensor), ThermocoupleWithTable(sensor=sensor)
    shared.raw_uv = copied.raw_uv = raw_uv
    rows = [(_real(mv), _real(deg)) for mv, deg in _table_rows(sensor)]
    assert shared.temperature == pytest.approx(_reference(rows, raw_uv / 1000.0), rel=1e-12, abs=1e-9)
    assert shared.temperature == copied.temperature
    assert shared.in_range == copied.in_range == (rows[0][0] <= raw_uv / 1000.0 <= rows[-1][0])


@settings(max_examples=50, deadline=None)
@given(sensor=st.sampled_from([K, J]), segment=st.integers(1, 14), fractions=st.lists(st.floats(0.0, 1.0), min_size=2))
def test_between_two_points_the_curve_stays_between_their_temperatures(
    sensor: ThermocoupleType, segment: int, fractions: list[float]
) -> None:
    table = GVL_Thermocouples.TC_TYPE_K if sensor == K else GVL_Thermocouples.TC_TYPE_J
    low, high = table.points[segment], table.points[segment + 1]
    temperatures = [interpolate(table, low.mv + f * (high.mv - low.mv)) for f in sorted(fractions)]
    assert temperatures == sorted(temperatures)
    assert all(low.deg_c <= t <= high.deg_c for t in temperatures)
