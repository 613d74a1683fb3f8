"""Prototype: cloning a tuned axis parameter set from a static pool, shallow and deep."""

from __future__ import annotations

import gc

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import (
    AccessError,
    ExceptionCode,
    PlcException,
    VAR,
    Program,
    T,
    adr,
    memcmp,
    query_interface,
    sizeof,
)
from iecoop.runtime import Runtime, Task
from patterns.creational.prototype import (
    AxisParams,
    AxisStation,
    CommissioningMain,
    CompTable,
    CopyMode,
    IAxisPrototype,
    ParameterPool,
    ParameterSet,
    PoolError,
)


def tuned(table: CompTable) -> tuple[ParameterPool, ParameterSet]:
    pool = ParameterPool()
    master = ParameterSet(pool=pool)
    master.tune(8.0, 200.0, adr(table))
    return pool, master


def table_of(*points: float) -> CompTable:
    table = CompTable(name="screw")
    for index, value in enumerate(points, start=1):
        table.error_um[index] = value
    return table


def running_cell() -> tuple[CommissioningMain, Runtime]:
    cell = CommissioningMain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), cell)
    rt.run(cycles=1)
    return cell, rt


def test_a_clone_is_a_byte_copy_and_only_a_deep_one_repoints_its_table() -> None:
    table = table_of(0.0, 4.0, 12.0, 9.0, 15.0)
    pool, master = tuned(table)
    shallow, deep = master.clone(CopyMode.SHALLOW), master.clone(CopyMode.DEEP)
    assert memcmp(adr(shallow.params), adr(master.params), sizeof(AxisParams)) == 0
    assert memcmp(adr(deep.params), adr(master.params), sizeof(AxisParams)) != 0
    assert (deep.params.kp, deep.params.max_velocity) == (8.0, 200.0)
    assert shallow.params.comp == adr(table)
    assert deep.params.comp == adr(pool.slots[2], "own_table")
    assert memcmp(deep.params.comp, adr(table), sizeof(CompTable)) == 0
    assert pool.used == 2


def test_the_shared_table_is_seen_by_shallow_clones_only() -> None:
    table = table_of(0.0, 4.0, 12.0, 9.0, 15.0)
    _pool, master = tuned(table)
    shallow, deep = master.clone(CopyMode.SHALLOW), master.clone(CopyMode.DEEP)
    master.set_compensation(3, 30.0)
    assert [s.compensation(200.0) for s in (master, shallow, deep)] == [0.030, 0.030, 0.012]
    deep.set_compensation(3, -5.0)  # the replacement screw, corrected on its own
    assert table.error_um[3] == 30.0
    assert [s.compensation(200.0) for s in (master, shallow, deep)] == [0.030, 0.030, -0.005]


def test_retuning_the_master_leaves_its_clones_alone() -> None:
    first, second = table_of(0.0, 0.0, 0.0, 0.0, 0.0), table_of(1.0, 1.0, 1.0, 1.0, 1.0)
    _pool, master = tuned(first)
    clone = master.clone(CopyMode.SHALLOW)
    master.tune(2.0, 50.0, adr(second))
    assert (clone.params.kp, clone.params.max_velocity) == (8.0, 200.0)
    assert clone.compensation(100.0) == 0.0


def test_a_clone_clones_from_the_pool_too_and_shares_what_it_points_at() -> None:
    table = table_of(0.0, 4.0, 12.0, 9.0, 15.0)
    pool, master = tuned(table)
    deep = master.clone(CopyMode.DEEP)
    grandchild = deep.clone(CopyMode.SHALLOW)
    assert grandchild.params.comp == deep.params.comp != adr(table)
    deep.set_compensation(2, 7.0)
    assert grandchild.compensation(100.0) == pytest.approx(0.007)
    assert pool.used == 2


def test_a_station_s_parameters_give_their_prototype_back_through_query_interface() -> None:
    cell, _rt = running_cell()
    parameters = cell.stations[3].parameters
    prototype = query_interface(parameters, IAxisPrototype)
    assert prototype is not None
    copy = prototype.clone(CopyMode.SHALLOW)
    assert copy.params.comp == parameters.params.comp != adr(cell, "screw_table")
    assert cell.pool.used == 3


def test_a_full_pool_returns_0_and_says_why() -> None:
    table = table_of(0.0, 0.0, 0.0, 0.0, 0.0)
    pool, master = tuned(table)
    clones = [master.clone(CopyMode.DEEP) for _ in range(5)]
    assert all(clones[:4]) and not clones[4]
    assert (pool.used, pool.error) == (4, PoolError.POOL_FULL)
    with pytest.raises(PlcException, match=r"IAxisPrototype\.params called through a null interface") as info:
        _ = clones[4].params
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


def test_a_parameter_set_without_its_pool_cannot_clone() -> None:
    orphan = ParameterSet()
    with pytest.raises(PlcException, match=r"IParameterPool\.clone_of called through a null interface") as info:
        orphan.clone(CopyMode.SHALLOW)
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


def test_a_deep_clone_of_a_set_without_a_table_has_none() -> None:
    pool = ParameterPool()
    clone = ParameterSet(pool=pool).clone(CopyMode.DEEP)
    assert not clone.params.comp and clone.compensation(150.0) == 0.0


def test_only_the_pool_loads_a_parameter_set() -> None:
    table = table_of(0.0, 0.0, 0.0, 0.0, 0.0)
    pool, master = tuned(table)
    with pytest.raises(AccessError, match=r"INTERNAL METHOD ParameterSet\.load cannot be called from .*package 'patterns'"):
        pool.slots[1].load(master.params, CopyMode.DEEP)
    assert pool.slots[1].params.kp == 1.0


def test_the_stations_move_identically_and_follow_their_tables_across_cycles() -> None:
    cell, rt = running_cell()
    stations = [cell.stations[n] for n in (1, 2, 3)]
    for _ in range(199):
        rt.run(cycles=1)
        positions = {s.position for s in stations}
        assert len(positions) == 1  # same parameters, same trajectory, every cycle
    assert rt.time_ms == 2000
    assert all(s.in_position for s in stations)
    assert stations[0].position == pytest.approx(250.0, abs=0.1)
    cell.master.set_compensation(4, 19.0)
    rt.run(cycles=1)
    offsets = [round((s.load_position - s.position) * 1000, 1) for s in stations]
    assert offsets == [15.5, 15.5, 10.5]


class BareStation(Program):
    """A station nobody gave a parameter set."""

    station: AxisStation = VAR()

    def body(self) -> None:
        self.station(setpoint=10.0)


def test_a_station_without_parameters_faults_the_task() -> None:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), BareStation())
    with pytest.raises(PlcException, match=r"AxisStation\.parameters: IAxisParameters\.params called through a null interface") as info:
        rt.run(cycles=1)
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


def test_a_pointer_to_a_table_that_no_longer_exists_faults_instead_of_reading_stale_data() -> None:
    table = table_of(0.0, 4.0, 12.0, 9.0, 15.0)
    _pool, master = tuned(table)
    shallow = master.clone(CopyMode.SHALLOW)
    del table
    gc.collect()
    # The master's POINTER keeps the table alive, as a Python reference would ...
    assert shallow.compensation(100.0) == master.compensation(100.0)
    # ... until it points elsewhere: the shallow copy's pointer is copied bytes and keeps nothing.
    other = table_of(1.0, 1.0, 1.0, 1.0, 1.0)
    master.tune(8.0, 200.0, adr(other))
    gc.collect()
    with pytest.raises(PlcException, match="target memory was deleted or no longer exists") as info:
        shallow.compensation(100.0)
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


error_um = st.floats(min_value=-50.0, max_value=50.0, width=32)


@settings(max_examples=60, deadline=None)
@given(
    st.lists(error_um, min_size=5, max_size=5),
    st.integers(min_value=1, max_value=5),
    error_um,
    st.floats(min_value=-10.0, max_value=410.0),
)
def test_shallow_clones_track_the_shared_table_and_deep_ones_keep_their_snapshot(
    points: list[float], edited: int, value: float, position: float
) -> None:
    table = table_of(*points)
    _pool, master = tuned(table)
    shallow, deep = master.clone(CopyMode.SHALLOW), master.clone(CopyMode.DEEP)
    before = master.compensation(position)
    master.set_compensation(edited, value)
    assert shallow.compensation(position) == master.compensation(position)
    assert deep.compensation(position) == before
