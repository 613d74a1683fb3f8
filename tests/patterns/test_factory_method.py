"""Factory Method: valves created from the I/O configuration table, checked across cycles."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import ARRAY, VAR, AccessError, DefinitionError, ExceptionCode, PlcException, Program, Struct, T, adr
from iecoop.runtime import Runtime, Task
from patterns.creational.factory_method import (
    IO_CONFIG,
    MAX_VALVES,
    FactoryError,
    IValve,
    MotorisedValve,
    PinchValve,
    PinchValveFactory,
    ProportionalValve,
    SolenoidValve,
    ValveBase,
    ValveCellMain,
    ValveConfig,
    ValveFactory,
    ValveType,
)
from tests import checked_only


class Table(Struct):
    """A configuration table as a test builds it: ``ARRAY[1..8] OF ST_ValveConfig``."""

    rows: ARRAY[ValveConfig] = VAR(bounds=(1, MAX_VALVES))


def table_of(*codes: ValveType) -> Table:
    table = Table()
    for row, code in enumerate(codes, start=1):
        table.rows[row] = ValveConfig(tag=f"V{100 + row}", type_code=code)
    return table


def is_open(valve: IValve) -> bool:
    """Read the end position afresh (mypy would otherwise keep a narrowed property across cycles)."""
    return valve.is_open


def started_cell() -> tuple[ValveCellMain, Runtime]:
    cell = ValveCellMain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), cell)
    rt.run(cycles=1)
    return cell, rt


def test_each_row_gets_the_block_its_type_code_names() -> None:
    cell, _rt = started_cell()
    factory = cell.factory
    kinds = [type(factory.valve(row)) for row in range(1, 5)]
    assert kinds == [SolenoidValve, MotorisedValve, ProportionalValve, PinchValve]
    assert [factory.valve(row).tag for row in range(1, 5)] == ["V101", "V102", "V103", "V104"]
    assert [factory.valve(row).type_code for row in range(1, 5)] == [config.type_code for config in IO_CONFIG[:4]]
    assert factory.created == 4
    # BUTTERFLY has no factory; the unused rows stay 0 without being an error.
    assert (factory.error, factory.error_row) == (FactoryError.UNKNOWN_TYPE, 5)
    assert not any(factory.valve(row) for row in range(5, MAX_VALVES + 1))


def test_the_base_factory_refuses_the_kind_only_the_subclass_knows() -> None:
    table = table_of(ValveType.SOLENOID, ValveType.PINCH, ValveType.MOTORISED)
    base, extended = ValveFactory(), PinchValveFactory()
    assert base.configure(adr(table, "rows", 1), MAX_VALVES) == 2
    assert (base.error, base.error_row) == (FactoryError.UNKNOWN_TYPE, 2)
    assert not base.valve(2)
    assert extended.configure(adr(table, "rows", 1), MAX_VALVES) == 3
    assert extended.error == FactoryError.NONE
    assert isinstance(extended.valve(2), PinchValve)


def test_the_factory_method_is_protected_and_the_client_goes_through_configure() -> None:
    factory = PinchValveFactory()
    with pytest.raises(AccessError, match=r"PROTECTED METHOD PinchValveFactory\.create_valve cannot be called from"):
        factory.create_valve(ValveConfig(tag="V101", type_code=ValveType.SOLENOID))
    assert factory.created == 0


def test_an_exhausted_pool_leaves_the_row_null_and_a_call_through_it_faults() -> None:
    factory = PinchValveFactory()
    table = table_of(*[ValveType.SOLENOID] * 5, ValveType.MOTORISED)
    assert factory.configure(adr(table, "rows", 1), MAX_VALVES) == 5
    assert (factory.error, factory.error_row) == (FactoryError.POOL_FULL, 5)
    assert isinstance(factory.valve(6), MotorisedValve)
    with pytest.raises(PlcException, match=r"IValve\.open called through a null interface") as info:
        factory.valve(5).open()
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


def test_configure_runs_once() -> None:
    factory = PinchValveFactory()
    table = table_of(ValveType.SOLENOID)
    assert factory.configure(adr(table, "rows", 1), MAX_VALVES) == 1
    assert factory.configure(adr(table, "rows", 1), MAX_VALVES) == 0
    assert factory.error == FactoryError.ALREADY_CONFIGURED
    assert factory.created == 1


def test_a_row_outside_the_table_is_an_array_bounds_fault() -> None:
    with pytest.raises(PlcException, match="outside ARRAY") as info:
        PinchValveFactory().valve(MAX_VALVES + 1)
    assert info.value.code == ExceptionCode.RTSEXCPT_ARRAYBOUNDS


def test_the_motorised_valve_travels_for_its_stroke_time_across_cycles() -> None:
    cell, rt = started_cell()
    valve = cell.factory.valve(2)
    rt.run(cycles=50)  # the cycle at t=500 ms has run
    assert valve.position == pytest.approx(50.0)
    assert not is_open(valve)
    rt.run(cycles=49)
    assert not is_open(valve)
    rt.run(cycles=1)  # the cycle at t=1000 ms has run
    assert is_open(valve) and valve.position == 100.0
    valve.close()
    rt.run(cycles=26)  # closing started at t=1010 ms, now t=1260 ms
    assert valve.position == pytest.approx(75.0)
    rt.run(cycles=75)
    assert valve.position == 0.0


class ProportionalCell(Program):
    """A cell that only runs a factory configured by the test."""

    factory: PinchValveFactory = VAR()

    def body(self) -> None:
        self.factory.execute_all()


def test_a_proportional_valve_without_a_table_stroke_uses_its_rated_250_ms() -> None:
    cell = ProportionalCell()
    table = table_of(ValveType.PROPORTIONAL)
    cell.factory.configure(adr(table, "rows", 1), MAX_VALVES)
    valve = cell.factory.valve(1)
    valve.open()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), cell)
    rt.run(cycles=25)  # t = 0 .. 240 ms
    assert not is_open(valve) and valve.position == pytest.approx(96.0)
    rt.run(cycles=1)
    assert is_open(valve) and rt.time_ms == 260


def test_the_pinch_valve_needs_its_50_ms_air_delay() -> None:
    cell, rt = started_cell()
    valve = cell.factory.valve(4)
    rt.run(cycles=4)
    assert not is_open(valve)
    rt.run(cycles=1)
    assert is_open(valve)


def test_only_the_package_configures_a_valve() -> None:
    cell, _rt = started_cell()
    valve = cell.factory.solenoids[1]
    with pytest.raises(AccessError, match=r"INTERNAL METHOD ValveBase\.setup cannot be called from .*package 'patterns'"):
        valve.setup(ValveConfig(tag="X", type_code=ValveType.MOTORISED))
    assert valve.tag == "V101"


@checked_only
def test_the_configuration_table_is_constant() -> None:
    cell = ValveCellMain()
    with pytest.raises(AccessError, match=r"ValveCellMain\.io_config is CONSTANT"):
        setattr(cell, "io_config", [ValveConfig()])
    assert cell.io_config[1].tag == "V101"


def test_the_valve_base_is_abstract() -> None:
    with pytest.raises(DefinitionError, match=r"ABSTRACT FUNCTION_BLOCK ValveBase cannot be instantiated"):
        ValveBase()


POOL_SIZE = {ValveType.SOLENOID: 4, ValveType.MOTORISED: 2, ValveType.PROPORTIONAL: 2, ValveType.PINCH: 2}


@settings(max_examples=60, deadline=None)
@given(st.lists(st.sampled_from(list(ValveType)), max_size=MAX_VALVES))
def test_every_row_gets_a_distinct_block_of_its_kind_or_a_reason(codes: list[ValveType]) -> None:
    factory = PinchValveFactory()
    table = table_of(*codes)
    created = factory.configure(adr(table, "rows", 1), MAX_VALVES)
    used = {kind: 0 for kind in POOL_SIZE}
    blocks = []
    first_failure = None
    for row, code in enumerate(codes, start=1):
        valve = factory.valve(row)
        if code in POOL_SIZE and used[code] < POOL_SIZE[code]:
            used[code] += 1
            assert valve and valve.type_code == code and valve.tag == f"V{100 + row}"
            blocks.append(valve)
        else:
            assert not valve
            if code != ValveType.NONE and first_failure is None:
                reason = FactoryError.POOL_FULL if code in POOL_SIZE else FactoryError.UNKNOWN_TYPE
                first_failure = (reason, row)
    assert created == len(blocks) == sum(used.values())
    assert len(set(blocks)) == len(blocks)  # FB equality is the instance address: no block handed out twice
    assert (factory.error, factory.error_row) == (first_failure or (FactoryError.NONE, 0))
