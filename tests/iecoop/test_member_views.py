"""Reading a block member or an ARRAY OF FB element: one kept view, the same memory semantics.

A member block (``jam : TON``) or an element of an ``ARRAY OF FB`` is read as a
view of the holder's memory. The view is made at the first read and kept, so a
scan does not build one per read; writing the member still copies memory and
keeps the member's type, and a deleted block's views are not kept.
"""

from __future__ import annotations

import copy

import pytest
from hypothesis import given
from hypothesis import strategies as st

from iecoop import ARRAY, BOOL, INT, VAR, VAR_INPUT, VAR_OUTPUT, FunctionBlock, PlcException, Program, T, delete, method, new
from iecoop.exceptions import ExceptionCode
from iecoop.memory._views import CACHE_PREFIX, VIEW_PREFIX
from iecoop.stdlib import TON


class Base(FunctionBlock):
    n: INT = VAR_OUTPUT()

    def body(self) -> None:
        self.n += 1


class Derived(Base):
    def body(self) -> None:
        self.n += 10


class Holder(FunctionBlock):
    go: BOOL = VAR_INPUT()
    part: Base = VAR_INPUT()
    timer: TON = VAR()

    def body(self) -> None:
        self.timer(IN=self.go, PT=T("20ms"))
        self.part()


class Cell(Program):
    holders: ARRAY[Holder] = VAR(bounds=(1, 3))

    def body(self) -> None:
        for i in range(1, 4):
            self.holders[i](go=True)

    @method
    def same_element_view(self) -> BOOL:
        """The program's own reads of one element give one view."""
        return self.holders[2] is self.holders[2] and self.holders[1] != self.holders[2]


def test_two_reads_of_a_member_are_one_view_of_the_same_memory() -> None:
    holder = Holder()
    first, second = holder.timer, holder.timer
    assert first is second and first == second
    holder(go=True)
    assert holder.timer.IN is True and first.IN is True
    other = Holder()
    assert other.timer != holder.timer  # another instance: another view, other memory


def test_writing_a_member_copies_memory_and_keeps_its_type() -> None:
    holder, source = Holder(), Derived()
    view = holder.part
    source()
    holder.part = source
    assert holder.part is view and holder.part is not source
    assert view.n == 10
    source()
    assert source.n == 20 and view.n == 10  # a copy, not an alias of the source
    holder()
    assert type(holder.part) is Base and holder.part.n == 11  # still a Base: Base's body ran


def test_array_of_fb_elements_are_kept_views_and_bounds_still_fault() -> None:
    cell = Cell()
    assert cell.same_element_view()
    assert cell.holders[2] == cell.holders[2]  # read from outside (checked mode: a read-only view), same memory
    for _ in range(3):
        cell.body()
    assert [cell.holders[i].part.n for i in range(1, 4)] == [3, 3, 3]
    indexes: tuple[object, ...] = (0, 4, True, "1", 2.0, -1, None)
    for index in indexes:
        with pytest.raises(PlcException) as info:
            _ = cell.holders[index]  # type: ignore[index]
        assert info.value.code == ExceptionCode.RTSEXCPT_ARRAYBOUNDS


class Index(int):
    """An int subclass (as a numpy integer or an enumeration value is): it indexes like its number."""


@pytest.mark.parametrize("first", [True, 1.0, 0, 4, Index(2), 2])
def test_array_of_fb_indexes_only_with_an_int_whatever_was_indexed_first(first: object) -> None:
    cell = Cell()  # a fresh array: its element views are made by the first index, whatever that index is
    holders = cell.holders
    if type(first) is int and not 1 <= first <= 3:
        with pytest.raises(PlcException, match=r"index -?\d+ outside ARRAY\[1\.\.3\]"):
            _ = holders[first]
    elif type(first) in (bool, float):
        with pytest.raises(PlcException, match=r"outside ARRAY\[1\.\.3\]") as info:
            _ = holders[first]  # type: ignore[index]
        assert info.value.code == ExceptionCode.RTSEXCPT_ARRAYBOUNDS
    else:
        assert holders[first] is holders[2]  # type: ignore[index]
    for index in (True, 1.0, 3.0, False):  # True == 1 and 1.0 == 1, yet neither is an index
        with pytest.raises(PlcException) as info:
            _ = holders[index]  # type: ignore[index]
        assert info.value.code == ExceptionCode.RTSEXCPT_ARRAYBOUNDS
    assert holders[Index(3)] is holders[3] and holders[Index(3)] is not holders[2]
    holders[Index(1)](go=True)
    assert [holders[i].go for i in (1, 2, 3)] == [True, False, False]


_CELL = Cell()


@given(st.one_of(st.integers(-3, 7), st.booleans(), st.floats(-3, 7), st.integers(-3, 7).map(Index)))
def test_an_array_of_fb_index_is_an_int_in_bounds_whatever_its_value_equals(index: object) -> None:
    holders = _CELL.holders
    if isinstance(index, int) and not isinstance(index, bool) and 1 <= index <= 3:
        assert holders[index] is holders[int(index)]
    else:
        with pytest.raises(PlcException) as info:
            _ = holders[index]  # type: ignore[index]
        assert info.value.code == ExceptionCode.RTSEXCPT_ARRAYBOUNDS


def test_the_compiled_call_reads_the_views_its_members_return() -> None:
    holder = Holder()
    assert not [key for key in holder.__dict__ if key.startswith(VIEW_PREFIX)]  # nothing made before a call
    holder(go=True)
    kept = {key: view for key, view in holder.__dict__.items() if key.startswith(VIEW_PREFIX)}
    assert kept == {f"{VIEW_PREFIX}part": holder.part, f"{VIEW_PREFIX}timer": holder.timer}
    assert all(kept[f"{VIEW_PREFIX}{name}"] is getattr(holder, name) for name in ("part", "timer"))
    source = Base()
    for _ in range(5):
        source()
    holder.part = source  # a write copies memory into the member: the kept view sees it
    assert kept[f"{VIEW_PREFIX}part"].n == 5
    holder(go=False)
    assert holder.part.n == 6 and source.n == 5 and holder.timer.IN is False


class Extended(Holder):
    """A derived block with a member of its own: one key present means every key of the class is."""

    spare: TON = VAR()

    def body(self) -> None:
        super().body()
        self.spare(IN=self.timer.IN, PT=T("10ms"))


def test_a_base_call_on_a_derived_instance_keeps_every_members_view() -> None:
    extended = Extended()
    Holder.__call__(extended, go=True)  # the base's compiled call, on a derived instance
    assert {f"{VIEW_PREFIX}{n}" for n in ("part", "timer", "spare")} <= set(extended.__dict__)
    extended(go=True)
    assert extended.spare.IN is True and extended.part.n == 2


def test_a_deleted_block_does_not_keep_its_member_views() -> None:
    p = new(Holder)
    holder = p.deref
    before = holder.timer
    assert holder.timer is before
    delete(p)
    kept = object.__getattribute__(holder, "__dict__")
    assert not [key for key in kept if key.startswith(CACHE_PREFIX)]  # no cached view survives the delete
    for read in (lambda: holder.timer, lambda: p.deref):  # and the instance Python still holds faults
        with pytest.raises(PlcException) as info:
            read()
        assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


def test_a_copy_has_its_own_member_views() -> None:
    holder = Holder()
    kept = holder.timer
    holder(go=True)
    twin = copy.copy(holder)
    assert twin.timer is not kept and twin.timer.IN is True  # the memory is copied, the views are not
    twin(go=False)
    assert [twin.timer.IN, holder.timer.IN] == [False, True]
    cell = Cell()
    cell.body()
    other = copy.copy(cell.holders)
    other[1](go=False)
    assert [other[1].go, cell.holders[1].go] == [False, True]
