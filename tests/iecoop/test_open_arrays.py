"""A block's ``VAR_IN_OUT aData : ARRAY[*] OF T``: the array bound at each call, with its bounds, kept between calls."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as hs

from iecoop import (
    ARRAY, DINT, INT, POINTER_TO, REAL, REFERENCE_TO, FunctionBlock, Program, Struct, VAR, VAR_IN_OUT, VAR_INPUT, VAR_OUTPUT, adr, method,
)
from iecoop.exceptions import DefinitionError, ExceptionCode, PlcException


class Summer(FunctionBlock):
    """``VAR_IN_OUT aData : ARRAY[*] OF INT``: sums the array it is given and counts up its first element."""

    aData: ARRAY[INT] = VAR_IN_OUT(bounds="*")
    nSum: DINT = VAR_OUTPUT(0)
    nLow: DINT = VAR_OUTPUT(0)
    nHigh: DINT = VAR_OUTPUT(0)

    def body(self) -> None:
        self.nLow, self.nHigh = self.aData.bounds[0]
        self.nSum = 0
        for i in range(self.nLow, self.nHigh + 1):
            self.nSum += self.aData[i]
        self.aData[self.nLow] = self.aData[self.nLow] + 1

    @method
    def last(self) -> INT:
        """A METHOD reads the array of the last call: ``Last := aData[UPPER_BOUND(aData, 1)]``."""
        return self.aData[self.aData.bounds[0][1]]


class Line(Program):
    aShort: ARRAY[INT] = VAR_INPUT([10, 20, 30], bounds=(0, 2))
    aLong: ARRAY[INT] = VAR_INPUT([1, 2, 3, 4, 5], bounds=(1, 5))
    fbSum: Summer = VAR()
    nShort: DINT = VAR(0)
    nLong: DINT = VAR(0)

    def body(self) -> None:
        self.fbSum(aData=self.aShort)
        self.nShort = self.fbSum.nSum
        self.fbSum(aData=adr(self, "aLong"))
        self.nLong = self.fbSum.nSum


def test_each_call_binds_its_array_with_its_bounds_and_writes_go_through() -> None:
    line = Line()
    line()
    assert (line.nShort, line.nLong) == (60, 15)
    assert (line.fbSum.nLow, line.fbSum.nHigh) == (1, 5)  # the last call's array
    assert list(line.aShort) == [11, 20, 30] and list(line.aLong) == [2, 2, 3, 4, 5]
    line()
    line()
    assert (line.nShort, line.nLong) == (62, 17)
    assert list(line.aShort) == [13, 20, 30] and list(line.aLong) == [4, 2, 3, 4, 5]


def test_between_calls_the_block_keeps_the_array_it_was_given() -> None:
    line = Line()
    line()
    assert line.fbSum.last() == 5
    line.aLong[5] = 99  # an input written after the call: the block sees its variable itself
    assert line.fbSum.last() == 99
    assert line.fbSum.aData.bounds == ((1, 5),)


def test_a_block_never_bound_faults_as_an_unbound_reference() -> None:
    with pytest.raises(PlcException) as caught:
        Summer().last()
    assert caught.value.code is ExceptionCode.RTSEXCPT_ACCESS_VIOLATION
    assert "Summer.aData" in str(caught.value) and "not bound" in str(caught.value)


def test_a_call_must_give_it() -> None:
    with pytest.raises(TypeError, match=r"VAR_IN_OUT 'aData' must be assigned at every call"):
        Summer()()  # type: ignore[call-arg]  # a type checker sees it missing too


class Reals(Struct):
    values: ARRAY[REAL] = VAR(bounds=(1, 3))
    grid: ARRAY[INT] = VAR(bounds=((1, 2), (1, 2)))


@pytest.mark.parametrize("wrong, got", [("values", "ARRAY[1..3] OF REAL"), ("grid", "ARRAY[1..2, 1..2] OF INT")])
def test_an_array_of_another_element_or_shape_is_refused_at_the_call(wrong: str, got: str) -> None:
    data = Reals()
    with pytest.raises(TypeError) as caught:
        Summer()(aData=getattr(data, wrong))
    assert str(caught.value) == f"Summer.aData: ARRAY[*] OF INT takes an ARRAY of INT with 1 dimension, got {got}"


class GridTotal(FunctionBlock):
    """``VAR_IN_OUT aGrid : ARRAY[*, *] OF INT``."""

    aGrid: ARRAY[INT] = VAR_IN_OUT(bounds=("*", "*"))
    nTotal: DINT = VAR_OUTPUT(0)

    def body(self) -> None:
        (r0, r1), (c0, c1) = self.aGrid.bounds
        self.nTotal = 0
        for r in range(r0, r1 + 1):
            for c in range(c0, c1 + 1):
                self.nTotal += self.aGrid[r, c]


def test_two_open_dimensions_take_a_two_dimensional_array() -> None:
    data = Reals()
    data.grid[1, 1], data.grid[1, 2], data.grid[2, 1], data.grid[2, 2] = 1, 2, 3, 4
    block = GridTotal()
    block(aGrid=data.grid)
    assert block.nTotal == 10
    with pytest.raises(TypeError, match=r"ARRAY\[\*, \*\] OF INT takes an ARRAY of INT with 2 dimensions, got ARRAY\[1..3\] OF REAL"):
        block(aGrid=data.values)  # type: ignore[arg-type]  # as a type checker sees


def test_an_open_array_anywhere_but_a_blocks_in_out_is_refused_at_definition() -> None:
    with pytest.raises(DefinitionError, match=r"Bad\.aData: ARRAY\[\*\] OF INT \(bounds='\*'\) is the type of a block's VAR_IN_OUT only; a VAR "):
        class Bad(FunctionBlock):
            aData: ARRAY[INT] = VAR(bounds="*")
    with pytest.raises(DefinitionError, match=r"Rec\.aData: ARRAY\[\*\] OF INT \(bounds='\*'\) is the type of a block's VAR_IN_OUT only"):
        class Rec(Struct):
            aData: ARRAY[INT] = VAR(bounds="*")
    with pytest.raises(DefinitionError, match=r"Ptr\.p: POINTER TO ARRAY\[\*\] is not allowed"):
        class Ptr(FunctionBlock):
            p: POINTER_TO[ARRAY[INT]] = VAR(bounds="*")
    with pytest.raises(DefinitionError, match=r"Ref\.r: REFERENCE TO ARRAY\[\*\] OF INT is not allowed"):
        class Ref(FunctionBlock):
            r: REFERENCE_TO[ARRAY[INT]] = VAR(bounds="*")
    with pytest.raises(DefinitionError, match=r"Nest\.a: ARRAY\[\*\] OF ARRAY is not supported"):
        class Nest(FunctionBlock):
            a: ARRAY[ARRAY[INT]] = VAR_IN_OUT(bounds="*")


@settings(max_examples=60, deadline=None)
@given(low=hs.integers(-1000, 1000), values=hs.lists(hs.integers(-32768, 32767), min_size=1, max_size=40))
def test_any_bounds_are_read_as_the_array_declares_them(low: int, values: list[int]) -> None:
    high = low + len(values) - 1

    class Holder(Struct):
        items: ARRAY[INT] = VAR(bounds=(low, high))

    holder = Holder()
    for i, value in enumerate(values):
        holder.items[low + i] = value
    block = Summer()
    block(aData=holder.items)
    assert (block.nLow, block.nHigh, block.nSum) == (low, high, sum(values))
    first = ((values[0] + 1 + 32768) & 0xFFFF) - 32768  # INT wraps
    assert holder.items[low] == first
    with pytest.raises(PlcException) as caught:
        block.aData[high + 1]
    assert caught.value.code is ExceptionCode.RTSEXCPT_ARRAYBOUNDS


class Tick(FunctionBlock):
    n: DINT = VAR_OUTPUT(0)

    def body(self) -> None:
        self.n += 1


class TickAll(FunctionBlock):
    """``VAR_IN_OUT aBlocks : ARRAY[*] OF FB_Tick``: calls every block of the array it is given."""

    aBlocks: ARRAY[Tick] = VAR_IN_OUT(bounds="*")

    def body(self) -> None:
        low, high = self.aBlocks.bounds[0]
        for i in range(low, high + 1):
            self.aBlocks[i]()


class Cell(Program):
    aTicks: ARRAY[Tick] = VAR(bounds=(1, 3))
    aMore: ARRAY[Tick] = VAR(bounds=(0, 1))
    fbAll: TickAll = VAR()

    def body(self) -> None:
        self.fbAll(aBlocks=self.aTicks)
        self.fbAll(aBlocks=self.aMore)
        self.fbAll(aBlocks=self.aMore)


def test_an_array_of_blocks_is_called_element_by_element_in_place() -> None:
    cell = Cell()
    for _ in range(3):
        cell()
    assert [t.n for t in cell.aTicks] == [3, 3, 3]
    assert [t.n for t in cell.aMore] == [6, 6]
