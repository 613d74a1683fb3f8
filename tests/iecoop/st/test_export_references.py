"""What a design hands out and what it uses from elsewhere: REFERENCE TO results, names that differ only in case, and the
user-defined blocks of other modules an export brings along."""

from __future__ import annotations

from pathlib import Path
import typing
from typing import Any

import pytest

from iecoop import (
    ARRAY,
    BOOL,
    INT,
    REFERENCE_TO,
    VAR,
    VAR_INPUT,
    VAR_IN_OUT,
    VAR_OUTPUT,
    FunctionBlock,
    GlobalVariables,
    Program,
    Struct,
    adr,
    gvl,
    method,
    ref_assign,
)
from iecoop import st
from iecoop.st import StUnsupportedError
from iecoop.st.export import StExportError, dump, export
from iecoop.testing.round_trip import FORMATS, load_back
from patterns.plant.motion import MC_Power
from patterns.structural.adapter import AxisStep

# ---------------------------------------------------------------------------
# A METHOD or FUNCTION that hands out a variable returns REFERENCE TO it
# ---------------------------------------------------------------------------


class Slot(Struct):
    level: INT = 0


class Pool(FunctionBlock):
    """Hands out its slots, as FB_Plant hands out its areas."""

    slots: ARRAY[Slot] = VAR(bounds=(1, 3))
    count: INT = VAR_OUTPUT(0)

    @method
    def take(self) -> Slot:
        slot = self.slots[self.count + 1]
        self.count += 1
        return slot

    @method
    def first(self) -> Slot:
        return self.slots[1]

    @method
    def blank(self) -> Slot:
        """A new value: the result is a copy, as before."""
        fresh: Slot
        fresh.level = -1
        return fresh


@gvl
class GVL_Tables(GlobalVariables):
    LOW: Slot = VAR(Slot(level=10))
    HIGH: Slot = VAR(Slot(level=90))


def table_for(high: BOOL) -> Slot:
    """``FUNCTION table_for : REFERENCE TO Slot``: the shared table, never a copy."""
    if high:
        return GVL_Tables.HIGH
    return GVL_Tables.LOW


class Filler(Program):
    pool: Pool = VAR()
    high: BOOL = VAR_INPUT(False)
    table: REFERENCE_TO[Slot] = VAR()
    copied: Slot = VAR()
    taken: INT = VAR_OUTPUT(0)
    seen: INT = VAR_OUTPUT(0)

    def body(self) -> None:
        slot = self.pool.take()
        slot.level = 7 * self.pool.count
        self.pool.first().level += 1
        self.taken = slot.level
        ref_assign(self, "table", table_for(self.high))
        self.copied = table_for(self.high)
        self.seen = self.table.level + self.copied.level


def test_a_method_handing_out_an_element_returns_a_reference_bound_with_ref() -> None:
    text = dump([Slot, Pool])
    assert "METHOD PUBLIC take : REFERENCE TO Slot\n" in text
    assert "take REF= slot;\nEND_METHOD" in text
    assert "METHOD PUBLIC first : REFERENCE TO Slot\n" in text and "first REF= slots[1];" in text
    # a new value is no variable of the block: a copy, as ST returns a STRUCT
    assert "METHOD PUBLIC blank : Slot\n" in text and "blank := fresh;" in text


def test_the_caller_keeps_the_variable_and_copies_only_into_a_variable() -> None:
    text = dump([Slot, GVL_Tables, Pool, Filler])
    assert "FUNCTION table_for : REFERENCE TO Slot\n" in text
    assert "table_for REF= GVL_Tables.HIGH;" in text and "table_for REF= GVL_Tables.LOW;" in text
    assert "    slot : REFERENCE TO Slot;\n" in text
    assert "slot REF= pool.take();\n" in text
    assert "first_result REF= pool.first();\nfirst_result.level := first_result.level + 1;" in text
    assert "table REF= table_for(high);\ncopied := table_for(high);" in text


def run_filler(filler: Any, tables: Any) -> list[tuple[int, ...]]:
    tables.LOW.level, tables.HIGH.level = 10, 90
    out = []
    for cycle in range(3):
        filler.high = cycle == 2
        filler()
        tables.LOW.level += 100  # seen through the reference, not in the copy
        drift = filler.table.level - filler.copied.level
        out.append((filler.taken, filler.seen, drift, filler.pool.count, *(filler.pool.slots[i].level for i in (1, 2, 3))))
    return out


@pytest.mark.parametrize("fmt", FORMATS)
def test_references_handed_out_loaded_back_run_as_python(fmt: str) -> None:
    import tests.iecoop.st.test_export_references as this

    python = run_filler(Filler(), GVL_Tables)
    # slot 1 written through the caller's name, then +1 through first(), which the caller's name sees
    assert python[0] == (8, 20, 100, 1, 8, 0, 0)  # LOW moved on: the reference sees it, the copy does not
    assert python[2] == (21, 180, 0, 3, 10, 14, 21)  # HIGH, which did not move
    loaded = load_back(this, fmt)
    try:
        assert run_filler(loaded.Filler, loaded.GVL_Tables) == python  # st.load gives a PROGRAM's instance
    finally:
        from iecoop.gvl import register_global_list

        register_global_list(typing.cast(GlobalVariables, GVL_Tables))  # the loaded list took its name


class Station(FunctionBlock):
    """Hands out a nested block, and names it in a local: both are the block itself."""

    counter: Pool = VAR()
    seen: INT = VAR_OUTPUT(0)

    @method
    def pool(self) -> Pool:
        return self.counter

    def body(self) -> None:
        shared = self.counter
        shared.take().level = 5
        self.seen = self.pool().count


def test_a_nested_block_handed_out_or_named_by_a_local_is_a_reference_not_a_copy() -> None:
    text = dump([Slot, Pool, Station])
    assert "METHOD PUBLIC pool : REFERENCE TO Pool\n" in text and "pool REF= counter;" in text
    assert "    shared : REFERENCE TO Pool;\n" in text
    assert "shared REF= counter;\ntake_result REF= shared.take();\ntake_result.level := 5;\n" in text
    station, loaded = Station(), st.load(text).Station()
    for block in (station, loaded):
        block()
        block()
    assert (station.seen, station.counter.slots[2].level) == (loaded.seen, loaded.counter.slots[2].level) == (2, 5)


def test_an_override_must_hand_out_a_variable_where_its_first_definition_does() -> None:
    class Base(FunctionBlock):
        kept: Slot = VAR()

        @method
        def get(self) -> Slot:
            return self.kept

    class Derived(Base):
        @method
        def get(self) -> Slot:
            other: Slot
            other.level = self.kept.level
            return other

    assert "METHOD PUBLIC get : REFERENCE TO Slot" in dump([Slot, Base])
    with pytest.raises(StExportError, match=r"test_export_references\.py:\d+: a return of a value that ends with the call, where the result is REFERENCE TO Slot.*\(in .*Derived\.get\)"):
        dump([Slot, Base, Derived])


def test_the_reader_binds_a_reference_to_a_call_that_returns_one() -> None:
    module = st.load("""
TYPE ST_Cell : STRUCT n : INT; END_STRUCT END_TYPE
FUNCTION_BLOCK FB_Store
VAR cells : ARRAY[1..2] OF ST_Cell; END_VAR
END_FUNCTION_BLOCK
METHOD Cell : REFERENCE TO ST_Cell
VAR_INPUT i : INT; END_VAR
Cell REF= cells[i];
END_METHOD
PROGRAM MAIN
VAR store : FB_Store; r : REFERENCE TO ST_Cell; c : ST_Cell; END_VAR
VAR_TEMP t : REFERENCE TO ST_Cell; END_VAR
r REF= store.Cell(2);
r.n := r.n + 5;
t REF= store.Cell(1);
t.n := 3;
c := store.Cell(2);
c.n := 100;
END_PROGRAM
""")
    main = module.MAIN
    main()
    main()
    assert [main.store.cells[i].n for i in (1, 2)] == [3, 10]
    assert main.c.n == 100 and main.r.n == 10


def test_the_reader_refuses_ref_to_a_call_that_returns_a_value() -> None:
    with pytest.raises(StUnsupportedError, match=r"<st>:10: the address of a call's result \(self\.Make\(\)\).*REFERENCE TO"):
        st.load("""
TYPE ST_Cell : STRUCT n : INT; END_STRUCT END_TYPE
FUNCTION_BLOCK FB_Maker
VAR r : REFERENCE TO ST_Cell; END_VAR
END_FUNCTION_BLOCK
METHOD Make : ST_Cell
Make.n := 1;
END_METHOD
METHOD Bind
r REF= Make();
END_METHOD
""")


# ---------------------------------------------------------------------------
# ST ignores case: a local axis is the variable Axis
# ---------------------------------------------------------------------------


class Counter(FunctionBlock):
    Cell: Slot = VAR_IN_OUT()
    Total: INT = VAR_OUTPUT(0)

    def body(self) -> None:
        cell = self.Cell
        cell.level += 1
        self.Total += cell.level

    @method
    def add(self, n: INT) -> INT:
        total = self.Total + n
        self.Total = total
        return total


def test_a_local_named_like_a_variable_but_for_case_is_kept_apart() -> None:
    text = dump([Slot, Counter])
    assert "VAR_TEMP\n    cell_temp : REFERENCE TO Slot;\nEND_VAR\ncell_temp REF= Cell;\n" in text
    assert "total := THIS^.Total + n;\nTHIS^.Total := total;\nadd := total;" in text
    counter = st.load(text).Counter()
    slot = st.load(text).Slot()
    counter(Cell=adr(slot))
    counter(Cell=adr(slot))
    assert (slot.level, counter.Total, counter.add(10)) == (2, 3, 13)


# ---------------------------------------------------------------------------
# The blocks a design uses from other modules go with it
# ---------------------------------------------------------------------------


class Lift(FunctionBlock):
    """Uses MC_Power (whose VAR_IN_OUT is an AxisRef) and names AxisStep in its body only."""

    power: MC_Power = VAR()
    enable: BOOL = VAR_INPUT(False)
    stepping: BOOL = VAR_OUTPUT(False)

    def body(self) -> None:
        step: INT = AxisStep.MOVING
        self.stepping = self.enable and step > 0


def test_an_export_brings_the_user_blocks_it_uses_and_leaves_the_library_out() -> None:
    text = dump([Lift])
    assert "FUNCTION_BLOCK MC_Power\n" in text  # a variable's type
    assert "TYPE AxisRef :\nSTRUCT\n" in text  # through MC_Power's VAR_IN_OUT
    assert "TYPE AxisStep :\n" in text  # named in the body only
    assert "FUNCTION_BLOCK MC_MoveVelocity" not in text and "FUNCTION_BLOCK AxisSim" not in text
    assert "FUNCTION_BLOCK TON" not in text and "FUNCTION_BLOCK R_TRIG" not in text
    # types first, then the blocks: the order a project lists them
    assert text.index("TYPE AxisStep") < text.index("TYPE AxisRef") < text.index("FUNCTION_BLOCK Lift") < text.index("FUNCTION_BLOCK MC_Power")
    lift = st.load(text).Lift()
    lift(enable=True)
    assert lift.stepping is True


def test_exporting_a_module_with_its_dependencies_twice_writes_the_same_bytes(tmp_path: Path) -> None:
    import patterns.structural.adapter as adapter

    first = export(adapter, tmp_path / "a")
    second = export(adapter, tmp_path / "b")
    assert [p.name for p in first] == [p.name for p in second]
    assert {"AxisRef.TcDUT", "MC_Power.TcPOU", "MC_MoveVelocity.TcPOU", "VfdSim.TcPOU"} <= {p.name for p in first}
    assert all(a.read_bytes() == b.read_bytes() for a, b in zip(first, second))


def test_two_objects_of_one_name_in_an_export_are_refused_naming_both() -> None:
    class AxisRef(Struct):
        x: INT = 0

    with pytest.raises(StExportError, match=r"two objects are named AxisRef in one export: .*test_export_references.*AxisRef and patterns\.plant\.motion\.AxisRef"):
        dump([AxisRef, Lift])
