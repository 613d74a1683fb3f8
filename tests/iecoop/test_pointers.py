"""ADR, POINTER TO, REFERENCE TO, MEMCPY / MEMSET / MEMCMP and __VARINFO on checked memory.

Every fault a PLC program can provoke through an address (null pointer, an
address outside its block, deleted or collected memory) must surface as
PlcException RTSEXCPT_ACCESS_VIOLATION, and an index outside an ARRAY's
declared bounds as RTSEXCPT_ARRAYBOUNDS; never as a crash. Offsets are the
TwinCAT 3 x64 ones, worked out by hand next to each class.
"""

from __future__ import annotations

import ctypes
import dataclasses
import gc
import weakref
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any, cast

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.stateful import Bundle, MultipleResults, RuleBasedStateMachine, initialize, invariant, multiple, rule

from iecoop import (
    ARRAY, DINT, INT, LREAL, NULL, POINTER_TO, REFERENCE_TO, STRING, TYPE_CLASS, VAR, ExceptionCode, FunctionBlock,
    GlobalVariables, PlcException, Program, DefinitionError, Pointer, Struct, T, adr, adr_of, gvl, is_valid_ref, memcmp,
    memcpy, memset, ref_assign, sizeof, var_info,
)
from iecoop.memory._handles import allocation_of, free
from iecoop.runtime import Runtime, Task
from iecoop.testing.strategies import ANY_INTS, LATIN_1

AV = ExceptionCode.RTSEXCPT_ACCESS_VIOLATION
BOUNDS = ExceptionCode.RTSEXCPT_ARRAYBOUNDS


class Part(Struct):
    x: INT = 1  # 0
    y: LREAL = 2.0  # 8; size 16


class Cell(Struct):
    a: INT = 0  # 0
    b: DINT = 0  # 4
    arr: ARRAY[INT] = VAR(bounds=(1, 4))  # 8 .. 15
    grid: ARRAY[INT] = VAR(bounds=((0, 1), (0, 2)))  # 16 .. 27, row-major
    name: STRING = VAR("", length=7)  # 28 .. 35
    part: Part = VAR()  # 40 .. 55
    parts: ARRAY[Part] = VAR(bounds=(1, 2))  # 56 .. 87
    labels: ARRAY[STRING] = VAR(bounds=(0, 2), length=3)  # 88 .. 99
    zero: ARRAY[DINT] = VAR(bounds=(0, 2))  # 100 .. 111; size 112


CELL_SIZE = 112


class Holder(Struct):
    p: POINTER_TO[INT] = VAR()
    r: REFERENCE_TO[INT] = VAR()
    rp: REFERENCE_TO[Part] = VAR()
    rs: REFERENCE_TO[STRING] = VAR(length=7)


class Node(Struct):
    value: INT = 0
    following: POINTER_TO[Node] = VAR()


@contextmanager
def raises_plc(code: ExceptionCode, match: str) -> Iterator[None]:
    """Expect a PlcException with ``code`` whose message matches ``match``."""
    with pytest.raises(PlcException, match=match) as info:
        yield
    assert info.value.code == code


def deleted(obj: object) -> None:
    """``__DELETE``: release the block holding ``obj``."""
    free(allocation_of(obj)[0])


def raw(obj: object) -> bytes:
    return ctypes.string_at(ctypes.addressof(cast(Any, obj)), sizeof(obj))


def pointer_into_collected_cell() -> Pointer[Any]:
    """A bare handle (as MEMCPY copies it) into a Cell nothing keeps alive."""
    cell = Cell(a=5)
    p = adr(cell, "a")
    return Pointer(p.handle, p._target)


# ---------------------------------------------------------------------------
# ADR
# ---------------------------------------------------------------------------


def test_adr_of_an_instance_designates_the_instance() -> None:
    cell = Cell()
    p = adr(cell)
    assert p.deref is cell
    assert p == adr(cell)
    assert hash(p) == hash(adr(cell))
    assert p and not p.is_null


@pytest.mark.parametrize(
    ("member", "offset"),
    [("a", 0), ("b", 4), ("arr", 8), ("grid", 16), ("name", 28), ("part", 40), ("parts", 56), ("labels", 88),
     ("zero", 100)],
)
def test_adr_of_a_member_is_the_instance_address_plus_its_offset(member: str, offset: int) -> None:
    cell = Cell()
    assert adr(cell, member) - adr(cell) == offset
    info = var_info(cell, member)
    assert info.ByteOffset == offset
    assert info.ByteAddress == int(adr(cell, member))


def test_adr_of_array_elements_steps_by_the_element_size() -> None:
    cell = Cell()
    assert adr(cell, "arr", 1) == adr(cell, "arr")
    assert adr(cell, "arr", 3) - adr(cell, "arr", 1) == 2 * sizeof(INT)
    assert adr(cell.arr, 3) == adr(cell, "arr", 3)
    assert adr(cell, "zero", 2) - adr(cell) == 108
    assert adr(cell, "labels", 2) - adr(cell, "labels", 0) == 8  # STRING(3) is 4 bytes


@pytest.mark.parametrize(("index", "offset"), [((0, 0), 0), ((0, 1), 2), ((0, 2), 4), ((1, 0), 6), ((1, 2), 10)])
def test_adr_of_a_multi_dimensional_element_is_row_major(index: tuple[int, int], offset: int) -> None:
    cell = Cell()
    assert adr(cell, "grid", index) - adr(cell, "grid") == offset
    assert adr(cell.grid, index) == adr(cell, "grid", index)
    adr(cell, "grid", index).deref = 40 + offset
    assert cell.grid[index] == 40 + offset


def test_adr_of_struct_elements_and_nested_views() -> None:
    cell = Cell()
    assert adr(cell, "parts", 2) - adr(cell) == 72
    assert adr(cell.parts[2]) == adr(cell, "parts", 2)
    assert adr(cell.part) == adr(cell, "part")
    assert adr(cell.part, "y") - adr(cell) == 48
    # Two views of the same inline instance are equal and have one address.
    first, second = cell.part, cell.part
    assert first == second
    assert adr(first) == adr(second)


# ---------------------------------------------------------------------------
# Dereferencing
# ---------------------------------------------------------------------------


def test_deref_reads_and_writes_an_elementary_variable() -> None:
    cell = Cell()
    p = adr(cell, "a")
    p.deref = 5
    assert cell.a == 5
    cell.a = 7
    assert p.deref == 7
    p.deref = 40000  # stores wrap, through a pointer as anywhere else
    assert cell.a == -25536


def test_deref_of_a_string_truncates_to_the_declared_length() -> None:
    cell = Cell()
    p = adr(cell, "name")
    p.deref = "conveyor belt"
    assert cell.name == "conveyo"
    assert p.deref == "conveyo"
    label = adr(cell, "labels", 2)
    label.deref = "abcd"
    assert cell.labels[2] == "abc"
    assert [cell.labels[i] for i in range(3)] == ["", "", "abc"]


def test_deref_of_a_struct_is_a_view_of_its_memory() -> None:
    cell = Cell()
    p = adr(cell, "part")
    view = p.deref
    view.x = 9
    assert cell.part.x == 9
    p.deref = Part(x=3, y=0.5)
    assert cell.part == Part(x=3, y=0.5)
    assert view.y == 0.5
    element = adr(cell, "parts", 1).deref
    element.y = 7.25
    assert cell.parts[1].y == 7.25


def test_deref_write_checks_the_kind() -> None:
    cell = Cell()
    with pytest.raises(TypeError, match=r"POINTER TO Part: cannot store int 5 in Part"):
        adr(cell, "part").deref = 5
    with pytest.raises(TypeError, match=r"POINTER TO INT: cannot store str 'x' in INT"):
        adr(cell, "a").deref = "x"


def test_an_untyped_pointer_cannot_be_dereferenced() -> None:
    with pytest.raises(TypeError, match=r"untyped pointer \(PVOID\) cannot be dereferenced"):
        Pointer().deref


def test_typed_reinterprets_the_same_address() -> None:
    cell = Cell(b=0x01020304)
    low = adr(cell, "b").typed(INT)
    assert low == adr(cell, "b")
    assert low.deref == 0x0304
    assert (low + 2).deref == 0x0102


def test_a_linked_list_through_pointers_to_its_own_type() -> None:
    first, second, third = Node(value=1), Node(value=2), Node(value=3)
    first.following = adr(second)
    second.following = adr(third)
    values = []
    p: Pointer[Node] = adr(first)
    while p:
        values.append(p.deref.value)
        p = p.deref.following
    assert values == [1, 2, 3]
    assert p.is_null


# ---------------------------------------------------------------------------
# Pointer arithmetic, comparison, hashing, null
# ---------------------------------------------------------------------------


def test_pointer_arithmetic_counts_bytes() -> None:
    cell = Cell()
    for i in range(1, 5):
        cell.arr[i] = 10 * i
    p = adr(cell, "arr", 1)
    assert (p + 2 * sizeof(INT)).deref == 30
    assert (sizeof(INT) + p).deref == 20
    walked = []
    q = p
    for _ in range(4):
        walked.append(q.deref)
        q = q + sizeof(INT)
    assert walked == [10, 20, 30, 40]
    assert q - p == 8
    assert p - q == -8
    assert q - 8 == p


def test_arithmetic_below_the_block_and_back_is_the_same_address() -> None:
    cell = Cell()
    p = adr(cell, "a")
    assert (p - 6) + 6 == p
    assert (p - 6) - p == -6  # a signed offset: below the block is negative, not wrapped
    with raises_plc(AV, "address -6 \\+ 2 bytes lies outside"):
        _ = (p - 6).deref


def test_pointer_difference_between_blocks_is_an_access_violation() -> None:
    with raises_plc(AV, "different memory blocks"):
        adr(Cell()) - adr(Cell())


def test_pointer_equality_and_hashing() -> None:
    cell = Cell()
    p, same, other = adr(cell, "arr", 2), adr(cell.arr, 2), adr(cell, "arr", 3)
    assert p == same
    assert p != other
    assert p == int(p)
    assert p != adr(Cell(), "arr", 2)
    assert hash(p) == hash(same)
    assert len({p, same, other}) == 2
    lookup = {p: "second"}
    assert lookup[same] == "second"


def test_null_pointer() -> None:
    holder = Holder()
    null = holder.p
    assert not null
    assert null.is_null
    assert null == 0
    assert null == Pointer()
    with raises_plc(AV, r"POINTER TO INT: null pointer \(0\) dereferenced"):
        null.deref
    with raises_plc(AV, "null pointer"):
        null.deref = 1
    with raises_plc(AV, "no longer exists"):
        (null + 4).deref  # 4 is no address of any block


def test_pointer_variables_hold_addresses_or_zero() -> None:
    cell, holder = Cell(), Holder()
    holder.p = adr(cell, "a")
    holder.p.deref = 3
    assert cell.a == 3
    assert holder.p == adr(cell, "a")
    holder.p = None  # type: ignore[assignment]  # ST: p := 0
    assert holder.p.is_null
    holder.p = adr(cell, "a")
    holder.p = 0  # type: ignore[assignment]
    assert holder.p.is_null
    holder.p = adr(cell, "a")
    holder.p = Pointer()
    assert holder.p.is_null
    with pytest.raises(TypeError, match=r"Holder\.p: cannot store int 5 in POINTER TO INT \(use adr\(\.\.\.\)\)"):
        holder.p = 5  # type: ignore[assignment]


# ---------------------------------------------------------------------------
# Faults: access violations
# ---------------------------------------------------------------------------


def test_address_past_the_end_of_the_block() -> None:
    cell = Cell()
    last = adr(cell, "zero", 2)
    last.deref = 1  # the last four bytes are inside
    with raises_plc(AV, r"address 112 \+ 2 bytes lies outside its 112-byte block"):
        (adr(cell, "a") + CELL_SIZE).deref
    with raises_plc(AV, r"address 109 \+ 4 bytes lies outside"):
        (last + 1).deref  # straddles the end
    with raises_plc(AV, "outside"):
        (last + 4).deref = 5
    assert cell.zero[2] == 1


def test_address_before_the_start_of_the_block() -> None:
    cell = Cell()
    with raises_plc(AV, "outside its 112-byte block"):
        (adr(cell, "a") - 2).deref
    with raises_plc(AV, "outside"):
        (adr(cell) - 1).deref


def test_wide_target_near_the_end_of_the_block() -> None:
    cell = Cell()
    as_lreal = adr(cell, "zero", 0).typed(LREAL)
    as_lreal.deref = 1.5  # 100 + 8 <= 112
    with raises_plc(AV, r"address 108 \+ 8 bytes"):
        (as_lreal + 8).deref


def test_freed_memory_is_an_access_violation() -> None:
    cell = Cell(a=5)
    p = adr(cell, "a")
    view_pointer = adr(cell, "part")
    deleted(cell)
    with raises_plc(AV, "deleted or no longer exists"):
        p.deref
    with raises_plc(AV, "deleted or no longer exists"):
        p.deref = 6
    with raises_plc(AV, "deleted"):
        view_pointer.deref


def test_adr_of_a_deleted_instance_does_not_revive_it() -> None:
    cell = Cell()
    view = cell.part
    deleted(cell)
    with raises_plc(AV, "deleted"):
        adr(cell, "a").deref
    with raises_plc(AV, "deleted"):
        adr(cell).deref
    with raises_plc(AV, "deleted"):
        adr(view).deref
    other = Cell()
    with raises_plc(AV, "MEMCPY source"):
        memcpy(adr(other), adr(cell), 4)


def test_garbage_collected_memory_is_an_access_violation() -> None:
    p = pointer_into_collected_cell()
    gc.collect()
    with raises_plc(AV, "deleted or no longer exists"):
        p.deref
    with raises_plc(AV, "deleted or no longer exists"):
        p.deref = 1


def test_a_new_block_at_a_reused_address_is_not_the_old_one() -> None:
    stale = pointer_into_collected_cell()
    gc.collect()
    # CPython often reuses the freed memory for the next objects of the same size.
    fresh = [Cell(a=i) for i in range(20)]
    for i, cell in enumerate(fresh):
        assert adr(cell, "a").deref == i
        assert adr(cell, "a") != stale
    with raises_plc(AV, "deleted or no longer exists"):
        stale.deref


def test_memory_of_a_deleted_instance_is_usable_again_once_collected() -> None:
    def delete_and_drop() -> None:
        cell = Cell()
        deleted(cell)

    for _ in range(20):
        delete_and_drop()
    gc.collect()
    # New instances often land where the deleted ones were; they must be fresh, valid blocks.
    fresh = [Cell(a=i) for i in range(40)]
    for i, cell in enumerate(fresh):
        assert adr(cell, "a").deref == i
        assert adr(cell).deref is cell


# ---------------------------------------------------------------------------
# Faults: array bounds
# ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("member", "index"),
    [
        ("arr", 0), ("arr", 5), ("arr", -1), ("arr", -4),
        ("zero", -1), ("zero", 3),
        ("grid", (2, 0)), ("grid", (0, 3)), ("grid", (-1, 0)), ("grid", (0, -1)),
        ("grid", 0), ("grid", (0,)), ("grid", (0, 0, 0)), ("arr", (1, 1)),
        ("labels", 3), ("labels", -1), ("parts", 0), ("parts", 3),
    ],
    ids=repr,
)
def test_index_outside_the_bounds(member: str, index: int | tuple[int, ...]) -> None:
    cell = Cell()
    array: Any = getattr(cell, member)
    value = {"labels": "x", "parts": Part()}.get(member, 0)
    with raises_plc(BOUNDS, r"index .* outside ARRAY\["):
        array[index]
    with raises_plc(BOUNDS, "outside ARRAY"):
        array[index] = value
    with raises_plc(BOUNDS, "outside ARRAY"):
        adr(cell, member, index)
    with raises_plc(BOUNDS, "outside ARRAY"):
        adr(array, index)


def test_bounds_error_names_the_declared_bounds() -> None:
    cell = Cell()
    with raises_plc(BOUNDS, r"index 5 outside ARRAY\[1\.\.4\] OF INT"):
        cell.arr[5]
    with raises_plc(BOUNDS, r"index \(2, 0\) outside ARRAY\[0\.\.1, 0\.\.2\] OF INT"):
        cell.grid[2, 0]


def test_non_integer_indices_are_outside_the_bounds() -> None:
    cell = Cell()
    for index in (1.0, "1", True, slice(1, 3)):
        with raises_plc(BOUNDS, r"outside ARRAY\[1\.\.4\] OF INT"):
            cell.arr[index]  # type: ignore[index]


# ---------------------------------------------------------------------------
# MEMCPY / MEMSET / MEMCMP
# ---------------------------------------------------------------------------


def test_memcpy_copies_a_whole_instance() -> None:
    source = Cell(a=1, b=2, name="seven")
    source.arr[4] = 44
    source.parts[2].y = 1.25
    target = Cell()
    assert memcpy(adr(target), adr(source), sizeof(Cell)) == CELL_SIZE
    assert target == source
    assert raw(target) == raw(source)


def test_memcpy_copies_part_of_an_array() -> None:
    source, target = Cell(), Cell()
    for i in range(1, 5):
        source.arr[i] = i
    memcpy(adr(target, "arr", 2), adr(source, "arr", 1), 2 * sizeof(INT))
    assert list(target.arr) == [0, 1, 2, 0]


def test_memcpy_checks_both_ranges() -> None:
    source, target = Cell(), Cell()
    with raises_plc(AV, r"MEMCPY destination: address 8 \+ 112 bytes lies outside"):
        memcpy(adr(target, "arr"), adr(source), CELL_SIZE)
    with raises_plc(AV, "MEMCPY source"):
        memcpy(adr(target), adr(source, "zero"), 16)
    with raises_plc(AV, "MEMCPY destination: null pointer"):
        memcpy(Holder().p, adr(source), 2)
    assert raw(target) == raw(Cell())


def test_memcpy_of_zero_bytes_touches_nothing() -> None:
    assert memcpy(Pointer(), Pointer(), 0) == 0
    assert memset(Pointer(), 0, 0) == 0
    assert memcmp(Pointer(), Pointer(), 0) == 0


def test_memory_operators_reject_bad_arguments() -> None:
    cell = Cell()
    with pytest.raises(TypeError, match=r"MEMCPY: the byte count must be a non-negative integer, got -1"):
        memcpy(adr(cell), adr(cell), -1)
    with pytest.raises(TypeError, match=r"MEMCPY destination needs a pointer from adr\(\.\.\.\), got Cell"):
        memcpy(cell, adr(cell), 2)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=r"MEMSET: the byte count"):
        memset(adr(cell), 0, True)
    with pytest.raises(TypeError, match=r"MEMCMP second buffer needs a pointer from adr\(\.\.\.\), got int"):
        memcmp(adr(cell), 0, 0)  # type: ignore[arg-type]  # checked even for 0 bytes


@settings(max_examples=200, deadline=None)
@given(
    fill=st.one_of(st.integers(-300, 600), st.floats(allow_nan=True), st.booleans(), st.none(), st.text(max_size=2)),
    n=st.one_of(st.integers(-4, CELL_SIZE + 4), st.booleans(), st.floats(0, 8)),
    offset=st.integers(0, CELL_SIZE),
)
def test_memset_writes_a_byte_in_bounds_or_nothing(fill: Any, n: Any, offset: int) -> None:
    cell = Cell()
    before = raw(cell)
    target = adr(cell) + offset
    good_n = isinstance(n, int) and not isinstance(n, bool) and n >= 0
    good_fill = isinstance(fill, int) and not isinstance(fill, bool) and 0 <= fill <= 255
    if not good_n:
        with pytest.raises(TypeError, match=r"MEMSET: the byte count must be a non-negative integer"):
            memset(target, fill, n)
    elif not good_fill:
        with pytest.raises(TypeError, match=r"MEMSET: the fill value is a BYTE, an int 0\.\.255"):
            memset(target, fill, n)
    elif n and offset + n > CELL_SIZE:
        with raises_plc(AV, r"MEMSET destination: .* lies outside its"):
            memset(target, fill, n)
    else:
        assert memset(target, fill, n) == n
        expected = before[:offset] + bytes([fill]) * n + before[offset + n:]
        assert raw(cell) == expected
        return
    assert raw(cell) == before  # a refused MEMSET writes nothing


@settings(max_examples=150, deadline=None)
@given(n=st.integers(-2, CELL_SIZE + 4), at=st.integers(0, CELL_SIZE), frm=st.integers(0, CELL_SIZE))
def test_memcpy_and_memcmp_stay_inside_both_blocks(n: int, at: int, frm: int) -> None:
    source, target = Cell(a=3, b=4, name="x"), Cell()
    before = raw(target)
    if n < 0:
        for op in (memcpy, memcmp):
            with pytest.raises(TypeError, match="the byte count must be a non-negative integer"):
                op(adr(target) + at, adr(source) + frm, n)
        return
    if n and max(at, frm) + n > CELL_SIZE:
        with raises_plc(AV, r"lies outside its"):
            memcpy(adr(target) + at, adr(source) + frm, n)
        with raises_plc(AV, r"MEMCMP .* lies outside its"):
            memcmp(adr(target) + at, adr(source) + frm, n)
        assert raw(target) == before
        return
    left, right = raw(target)[at:at + n], raw(source)[frm:frm + n]
    assert memcmp(adr(target) + at, adr(source) + frm, n) == (left > right) - (left < right)
    assert memcpy(adr(target) + at, adr(source) + frm, n) == n
    assert raw(target)[at:at + n] == raw(source)[frm:frm + n]


def test_memcpy_copies_pointers_and_references_as_handles() -> None:
    cell, original, copy = Cell(), Holder(), Holder()
    original.p = adr(cell, "a")
    ref_assign(original, "r", adr(cell, "arr", 1))
    memcpy(adr(copy), adr(original), sizeof(Holder))
    assert copy.p == original.p
    copy.p.deref = 4
    copy.r = 8
    assert (cell.a, cell.arr[1]) == (4, 8)
    deleted(cell)
    with raises_plc(AV, "deleted"):
        copy.p.deref
    assert not is_valid_ref(copy, "r")


def test_memset_fills_bytes() -> None:
    cell = Cell()
    assert memset(adr(cell, "arr"), 0xFF, 4 * sizeof(INT)) == 8
    assert list(cell.arr) == [-1, -1, -1, -1]
    memset(adr(cell, "arr", 2), 0x01, 2)
    assert cell.arr[2] == 0x0101
    memset(adr(cell, "name"), ord("A"), 3)
    assert cell.name == "AAA"
    with raises_plc(AV, "MEMSET destination"):
        memset(adr(cell, "zero", 2), 0, 5)


def test_memcmp_compares_unsigned_bytes() -> None:
    left, right = Cell(), Cell()
    assert memcmp(adr(left), adr(right), sizeof(Cell)) == 0
    left.a, right.a = -1, 1  # first bytes 0xFF and 0x01
    assert memcmp(adr(left), adr(right), 2) == 1
    assert memcmp(adr(right), adr(left), 2) == -1
    right.a = -1
    right.b = 1
    assert memcmp(adr(left), adr(right), 4) == 0
    assert memcmp(adr(left), adr(right), 8) == -1
    with raises_plc(AV, "MEMCMP second buffer"):
        memcmp(adr(left), adr(right, "zero"), 16)


# ---------------------------------------------------------------------------
# REFERENCE TO
# ---------------------------------------------------------------------------


def test_an_unbound_reference_is_an_access_violation() -> None:
    holder = Holder()
    assert not is_valid_ref(holder, "r")
    with raises_plc(AV, r"Holder\.r: reference is not bound \(REF= missing\)"):
        holder.r
    with raises_plc(AV, r"Holder\.r: reference is not bound"):
        holder.r = 1
    with raises_plc(AV, r"Holder\.rp: reference is not bound"):
        holder.rp.x


def test_ref_assign_with_a_pointer_writes_through() -> None:
    cell, holder = Cell(a=5), Holder()
    ref_assign(holder, "r", adr(cell, "a"))
    assert is_valid_ref(holder, "r")
    assert holder.r == 5
    holder.r = 9
    assert cell.a == 9
    cell.a = 3
    assert holder.r == 3
    holder.r += 1
    assert cell.a == 4
    assert adr(holder, "r") == adr(cell, "a")
    ref_assign(holder, "r", adr(cell, "arr", 3))
    holder.r = 33
    assert cell.arr[3] == 33
    assert cell.a == 4


def test_ref_assign_with_a_struct_instance() -> None:
    cell, holder = Cell(), Holder()
    ref_assign(holder, "rp", cell.part)
    assert is_valid_ref(holder, "rp")
    holder.rp.x = 8
    assert cell.part.x == 8
    holder.rp = Part(x=1, y=0.25)  # := through a reference copies the value
    assert cell.part == Part(x=1, y=0.25)
    ref_assign(holder, "rp", cell.parts[2])
    holder.rp.y = 3.5
    assert cell.parts[2].y == 3.5
    assert cell.part.y == 0.25


def test_ref_assign_to_a_string() -> None:
    cell, holder = Cell(), Holder()
    ref_assign(holder, "rs", adr(cell, "name"))
    holder.rs = "abcdefghij"
    assert cell.name == "abcdefg"
    assert holder.rs == "abcdefg"


def test_ref_assign_none_unbinds() -> None:
    cell, holder = Cell(), Holder()
    ref_assign(holder, "r", adr(cell, "a"))
    ref_assign(holder, "r", None)
    assert not is_valid_ref(holder, "r")
    with raises_plc(AV, "not bound"):
        holder.r


def test_ref_assign_rejects_what_does_not_fit() -> None:
    cell, holder = Cell(), Holder()
    with pytest.raises(TypeError, match=r"Holder\.rs: REF= to STRING\(3\) does not fit REFERENCE TO STRING\(7\)"):
        ref_assign(holder, "rs", adr(cell, "labels", 0))
    with pytest.raises(TypeError, match=r"Holder\.r: REF= needs adr\(\.\.\.\), a struct / FB instance or an ARRAY, got Part"):
        ref_assign(holder, "r", cell.part)
    with pytest.raises(TypeError, match=r"Holder\.rp: cannot store Cell .* in Part"):
        ref_assign(holder, "rp", cell)
    with pytest.raises(TypeError, match=r"REF=: Holder\.p is POINTER TO INT, not a REFERENCE TO"):
        ref_assign(holder, "p", adr(cell, "a"))
    with pytest.raises(TypeError, match=r"__ISVALIDREF works on REFERENCE TO only; Holder\.p is POINTER TO INT"):
        is_valid_ref(holder, "p")
    with pytest.raises(AttributeError, match=r"REF=: Holder has no variable 'missing'"):
        ref_assign(holder, "missing", adr(cell, "a"))
    assert not is_valid_ref(holder, "r")


def test_a_reference_to_freed_memory_is_invalid() -> None:
    cell, holder = Cell(), Holder()
    ref_assign(holder, "r", adr(cell, "a"))
    ref_assign(holder, "rp", cell.part)
    deleted(cell)
    assert not is_valid_ref(holder, "r")
    assert not is_valid_ref(holder, "rp")
    with raises_plc(AV, r"Holder\.r: the target memory was deleted"):
        holder.r
    with raises_plc(AV, "deleted"):
        holder.r = 1
    with raises_plc(AV, "deleted"):
        holder.rp.x


def test_a_reference_to_collected_memory_is_invalid() -> None:
    holder = Holder()
    ref_assign(holder, "r", pointer_into_collected_cell())
    gc.collect()
    assert not is_valid_ref(holder, "r")
    with raises_plc(AV, "deleted or no longer exists"):
        holder.r


# ---------------------------------------------------------------------------
# __VARINFO
# ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("member", "expected"),
    [
        ("a", (0, 16, TYPE_CLASS.TYPE_INT, "INT", 1, 16, TYPE_CLASS.TYPE_INT)),
        ("b", (4, 32, TYPE_CLASS.TYPE_DINT, "DINT", 1, 32, TYPE_CLASS.TYPE_DINT)),
        ("grid", (16, 96, TYPE_CLASS.TYPE_ARRAY, "ARRAY[0..1, 0..2] OF INT", 6, 16, TYPE_CLASS.TYPE_INT)),
        ("name", (28, 64, TYPE_CLASS.TYPE_STRING, "STRING(7)", 1, 64, TYPE_CLASS.TYPE_STRING)),
        ("part", (40, 128, TYPE_CLASS.TYPE_USERDEF, "Part", 1, 128, TYPE_CLASS.TYPE_USERDEF)),
        ("parts", (56, 256, TYPE_CLASS.TYPE_ARRAY, "ARRAY[1..2] OF Part", 2, 128, TYPE_CLASS.TYPE_USERDEF)),
        ("labels", (88, 96, TYPE_CLASS.TYPE_ARRAY, "ARRAY[0..2] OF STRING(3)", 3, 32, TYPE_CLASS.TYPE_STRING)),
    ],
)
def test_var_info(member: str, expected: tuple[int, int, TYPE_CLASS, str, int, int, TYPE_CLASS]) -> None:
    cell = Cell()
    info = var_info(cell, member)
    assert info.Symbol == f"Cell.{member}"
    assert info.ByteAddress == int(adr(cell, member))
    assert info.Area == -1
    assert info.BitNr == -1
    got = (info.ByteOffset, info.BitSize, info.TypeClass, info.TypeName, info.NumElements, info.ElemBitSize,
           info.BaseTypeClass)
    assert got == expected


def test_var_info_of_pointers_and_references() -> None:
    holder = Holder()
    p, r = var_info(holder, "p"), var_info(holder, "r")
    assert (p.ByteOffset, p.BitSize, p.TypeClass, p.TypeName) == (0, 64, TYPE_CLASS.TYPE_POINTER, "POINTER TO INT")
    assert (r.ByteOffset, r.BitSize, r.TypeClass, r.TypeName) == (8, 64, TYPE_CLASS.TYPE_REFERENCE, "REFERENCE TO INT")
    with pytest.raises(AttributeError, match=r"__VARINFO: Holder has no variable 'q'"):
        var_info(holder, "q")


# ---------------------------------------------------------------------------
# Random sequences of memory operations
# ---------------------------------------------------------------------------


class Rec(Struct):
    a: INT = 0  # 0
    b: DINT = 0  # 4
    arr: ARRAY[INT] = VAR(bounds=(1, 4))  # 8 .. 15
    grid: ARRAY[INT] = VAR(bounds=((0, 1), (0, 2)))  # 16 .. 27
    name: STRING = VAR("", length=7)  # 28 .. 35; size 36


class NullSource(Struct):
    p: POINTER_TO[INT] = VAR()


REC_SIZE = 36
WIDTH = {"INT": 2, "DINT": 4, "STRING": 8, "Rec": REC_SIZE}

# Where the machine may take an address: (member, index) -> (byte offset, target kind),
# or None when the index is outside the bounds.
ADDRESSES: dict[tuple[str, object], tuple[int, str] | None] = {
    ("*", None): (0, "Rec"),
    ("a", None): (0, "INT"),
    ("b", None): (4, "DINT"),
    ("name", None): (28, "STRING"),
    **{("arr", i): ((8 + 2 * (i - 1), "INT") if 1 <= i <= 4 else None) for i in range(-1, 7)},
    **{
        ("grid", (i, j)): ((16 + 2 * (3 * i + j), "INT") if 0 <= i <= 1 and 0 <= j <= 2 else None)
        for i in range(-1, 3)
        for j in range(-1, 4)
    },
    ("grid", 0): None,
    ("grid", (0, 0, 0)): None,
}

_VALID = sorted((place for place, where in ADDRESSES.items() if where is not None), key=repr)
_INVALID = sorted((place for place, where in ADDRESSES.items() if where is None), key=repr)
# Mostly addresses inside the bounds, so that most pointers start valid.
PLACES = st.sampled_from(_VALID) | st.sampled_from(_VALID) | st.sampled_from(_INVALID)
# Mostly element-sized steps that stay inside a 36-byte block, some that leave it.
DELTAS = (
    st.sampled_from([0, 1, 2, 4, 8, 16, 28, -2, -4, -8])
    | st.integers(-40, 40)
    | st.sampled_from([2**32, -(2**32), 2**31, -(2**31), 2**64])  # never wraps back into the block
)
#: The offset of an address moved outside the 32-bit range: outside every block, for good.
WILD = 2**31 - 1
COUNTS = st.integers(0, 12) | st.integers(0, 40)


def _arr(i: int) -> Callable[[Rec], int]:
    return lambda r: r.arr[i]


def _grid(i: int, j: int) -> Callable[[Rec], int]:
    return lambda r: r.grid[i, j]


# The member each INT-sized offset belongs to, read through the member itself.
INT_MEMBERS: dict[int, Callable[[Rec], int]] = {
    0: lambda r: r.a,
    **{8 + 2 * (i - 1): _arr(i) for i in range(1, 5)},
    **{16 + 2 * (3 * i + j): _grid(i, j) for i in range(2) for j in range(3)},
}


@dataclasses.dataclass(eq=False)
class Block:
    """One Rec instance and the bytes the model says it holds."""

    obj: Rec | None
    memory: bytearray
    alive: bool = True


@dataclasses.dataclass(eq=False)
class Ref:
    """A pointer and what the model expects of it."""

    pointer: Pointer[Any]
    block: Block | None  # None: derived from the null pointer
    offset: int  # signed; WILD once moved outside the 32-bit range
    kind: str

    def valid(self, size: int | None = None) -> bool:
        width = WIDTH[self.kind] if size is None else size
        return self.block is not None and self.block.alive and 0 <= self.offset and self.offset + width <= REC_SIZE


def bare(pointer: Pointer[Any]) -> Pointer[Any]:
    """The pointer as a block stores it: the handle alone, which does not keep its block alive."""
    return Pointer(pointer.handle, pointer._target)


def expect(valid: bool, code: ExceptionCode = AV) -> Callable[[Callable[[], Any]], Any]:
    """Run an operation: it must succeed when ``valid``, else raise PlcException ``code``."""

    def run(operation: Callable[[], Any]) -> Any:
        try:
            result = operation()
        except PlcException as exc:
            assert not valid, f"unexpected {exc}"
            assert exc.code == code, str(exc)
            return None
        assert valid, f"expected {code.name}"
        return result

    return run


def int_at(memory: bytes | bytearray, offset: int, size: int) -> int:
    return int.from_bytes(memory[offset : offset + size], "little", signed=True)


def text_at(memory: bytes | bytearray, offset: int) -> str:
    return bytes(memory[offset : offset + 8]).split(b"\x00", 1)[0].decode("latin-1")


@settings(max_examples=200, stateful_step_count=50, deadline=None, suppress_health_check=[HealthCheck.too_slow])
class MemoryMachine(RuleBasedStateMachine):
    """Random ADR / arithmetic / deref / write / MEMCPY / MEMSET / MEMCMP / delete / collect.

    Each step's outcome is predicted from a byte model of every block: success
    (and then the exact bytes), ACCESS_VIOLATION or ARRAYBOUNDS; any other
    exception fails the test, and a crash would take the test process down.
    """

    pointers: Bundle[Ref] = Bundle("pointers")

    def __init__(self) -> None:
        super().__init__()
        # Three live instances, and the deleted ones, whose Python objects stay reachable
        # (as a user's variable would) so ADR of a deleted instance is exercised too.
        self.blocks: list[Block] = []
        self.deleted: list[Block] = []

    @initialize(target=pointers)
    def start(self) -> MultipleResults[Ref]:
        self.blocks = [Block(Rec(), bytearray(REC_SIZE)) for _ in range(3)]
        # Bundle draws favour the first entries, so those are valid pointers and the
        # null pointer comes last.
        # Bare handles, so that collect() can free a block a pointer designates.
        starts = [Ref(bare(adr(block.obj, "arr", 1)), block, 8, "INT") for block in self.blocks]
        starts += [Ref(bare(adr(block.obj)), block, 0, "Rec") for block in self.blocks]
        return multiple(*starts, Ref(NullSource().p, None, 0, "INT"))

    @rule(target=pointers, which=st.integers(0, 4), place=PLACES, through_array=st.booleans())
    def take_address(self, which: int, place: tuple[str, Any], through_array: bool) -> MultipleResults[Ref]:
        candidates = self.blocks + self.deleted[-2:]
        block = candidates[which % len(candidates)]
        obj = block.obj
        assert obj is not None
        member, index = place
        expected = ADDRESSES[place]

        def take() -> Pointer[Any]:
            if member == "*":
                return adr(obj)
            if index is None:
                return adr(obj, member)
            if through_array:
                return adr(getattr(obj, member), index)
            return adr(obj, member, index)

        pointer = expect(expected is not None, BOUNDS)(take)
        if expected is None:
            return multiple()
        offset, kind = expected
        return multiple(Ref(bare(pointer), block, offset, kind))

    @rule(target=pointers, ref=pointers, delta=DELTAS, subtract=st.booleans())
    def move(self, ref: Ref, delta: int, subtract: bool) -> Ref:
        moved = ref.pointer - delta if subtract else ref.pointer + delta
        offset = ref.offset + (-delta if subtract else delta)
        if ref.offset == WILD or not -(2**31) <= offset < WILD:
            offset = WILD
        assert moved - ref.pointer == offset - ref.offset
        return Ref(moved, ref.block, offset, ref.kind)

    @rule(left=pointers, right=pointers)
    def compare_pointers(self, left: Ref, right: Ref) -> None:
        same_block = left.block is right.block
        equal = same_block and left.offset == right.offset
        assert (left.pointer == right.pointer) is equal
        if equal:
            assert hash(left.pointer) == hash(right.pointer)
        difference = expect(same_block)(lambda: left.pointer - right.pointer)
        if same_block:
            assert difference == left.offset - right.offset
        assert bool(left.pointer) == (left.block is not None or left.offset != 0)

    @rule(ref=pointers)
    def read(self, ref: Ref) -> None:
        value = expect(ref.valid())(lambda: ref.pointer.deref)
        if not ref.valid():
            return
        assert ref.block is not None
        memory, offset = ref.block.memory, ref.offset
        if ref.kind in ("INT", "DINT"):
            assert value == int_at(memory, offset, WIDTH[ref.kind])
        elif ref.kind == "STRING":
            assert value == text_at(memory, offset)
        else:
            assert ctypes.string_at(ctypes.addressof(value), REC_SIZE) == bytes(memory[offset : offset + REC_SIZE])
            assert (value.a, value.b, value.name) == (
                int_at(memory, offset, 2), int_at(memory, offset + 4, 4), text_at(memory, offset + 28)
            )

    @rule(ref=pointers, number=ANY_INTS, text=st.text(LATIN_1, max_size=10))
    def write(self, ref: Ref, number: int, text: str) -> None:
        data: bytes
        value: Any
        if ref.kind in ("INT", "DINT"):
            size = WIDTH[ref.kind]
            value = number
            data = (number % (1 << (8 * size))).to_bytes(size, "little")
        elif ref.kind == "STRING":
            value = text
            encoded = text.encode("latin-1")[:7]
            data = encoded + b"\x00" * (8 - len(encoded))
        else:
            value = Rec(a=number % 2**15, b=-(number % 2**31), name=text)
            data = raw(value)

        def store() -> None:
            ref.pointer.deref = value

        expect(ref.valid())(store)
        if not ref.valid():
            return
        block = ref.block
        assert block is not None and block.obj is not None
        block.memory[ref.offset : ref.offset + len(data)] = data
        # The write is visible through the member itself, not only through the pointer.
        obj = block.obj
        if ref.kind == "INT" and ref.offset in INT_MEMBERS:
            assert INT_MEMBERS[ref.offset](obj) == int_at(data, 0, 2)
        elif ref.kind == "DINT" and ref.offset == 4:
            assert obj.b == int_at(data, 0, 4)
        elif ref.kind == "STRING" and ref.offset == 28:
            assert obj.name == text[:7].split("\x00", 1)[0]
        elif ref.kind == "Rec" and ref.offset == 0:
            assert (obj.a, obj.b, obj.name) == (value.a, value.b, value.name)

    @rule(target_ref=pointers, source_ref=pointers, n=COUNTS)
    def copy(self, target_ref: Ref, source_ref: Ref, n: int) -> None:
        valid = n == 0 or (target_ref.valid(n) and source_ref.valid(n))
        copied = expect(valid)(lambda: memcpy(target_ref.pointer, source_ref.pointer, n))
        if valid:
            assert copied == n
        if valid and n:
            assert target_ref.block is not None and source_ref.block is not None
            chunk = bytes(source_ref.block.memory[source_ref.offset : source_ref.offset + n])
            target_ref.block.memory[target_ref.offset : target_ref.offset + n] = chunk

    @rule(ref=pointers, fill=st.integers(0, 255), n=COUNTS)
    def fill(self, ref: Ref, fill: int, n: int) -> None:
        valid = n == 0 or ref.valid(n)
        expect(valid)(lambda: memset(ref.pointer, fill, n))
        if valid and n:
            assert ref.block is not None
            ref.block.memory[ref.offset : ref.offset + n] = bytes([fill]) * n

    @rule(left=pointers, right=pointers, n=COUNTS)
    def compare_memory(self, left: Ref, right: Ref, n: int) -> None:
        valid = n == 0 or (left.valid(n) and right.valid(n))
        result = expect(valid)(lambda: memcmp(left.pointer, right.pointer, n))
        if valid and n:
            assert left.block is not None and right.block is not None
            a = bytes(left.block.memory[left.offset : left.offset + n])
            b = bytes(right.block.memory[right.offset : right.offset + n])
            assert result == (a > b) - (a < b)

    @rule(slot=st.integers(0, 2))
    def delete(self, slot: int) -> None:
        block = self.blocks[slot]
        assert block.obj is not None
        deleted(block.obj)
        block.alive = False
        self.deleted.append(block)
        self.blocks[slot] = Block(Rec(), bytearray(REC_SIZE))

    @rule(slot=st.integers(0, 2))
    def collect(self, slot: int) -> None:
        block = self.blocks[slot]
        assert block.obj is not None
        watch = weakref.ref(block.obj)
        block.obj = None
        block.alive = False
        # Reference counting frees the instance here; a full gc.collect() per step would
        # dominate the run time, and the weak reference proves the memory is gone.
        assert watch() is None, "the machine itself kept the instance alive"
        self.blocks[slot] = Block(Rec(), bytearray(REC_SIZE))

    @invariant()
    def memory_matches_the_model(self) -> None:
        # Deleted blocks are checked too: nothing may have written into them.
        for block in self.blocks + self.deleted:
            obj = block.obj
            assert obj is not None
            assert raw(obj) == bytes(block.memory)
            assert obj.a == int_at(block.memory, 0, 2)
            assert obj.b == int_at(block.memory, 4, 4)
            assert list(obj.arr) == [int_at(block.memory, 8 + 2 * k, 2) for k in range(4)]
            assert obj.name == text_at(block.memory, 28)


test_random_memory_operations = MemoryMachine.TestCase


# ---------------------------------------------------------------------------
# Enumerations as ARRAY indexes; NULL
# ---------------------------------------------------------------------------


def test_an_enumeration_value_indexes_an_array_like_its_number() -> None:
    from iecoop import IecEnum

    class Station(IecEnum):
        INFEED = 1
        FILLER = 2

    class Counts(Struct):
        per_station: ARRAY[INT] = VAR(bounds=(Station.INFEED, Station.FILLER))
        grid: ARRAY[INT] = VAR(bounds=((1, 2), (1, 2)))

    counts = Counts()
    counts.per_station[Station.FILLER] = 7
    counts.grid[Station.FILLER, Station.INFEED] = 3
    assert counts.per_station[2] == 7 and counts.grid[2, 1] == 3
    with pytest.raises(PlcException, match=r"index True outside ARRAY\[1\.\.2\] OF INT") as exc:
        counts.per_station[True] = 1  # a BOOL is not an index
    assert exc.value.code == ExceptionCode.RTSEXCPT_ARRAYBOUNDS


def test_null_clears_and_compares_with_interfaces_and_pointers() -> None:
    from iecoop import NULL, REAL, FunctionBlock, Interface, method

    class ISensor(Interface):
        @method
        def read(self) -> REAL:
            raise NotImplementedError

    class Sensor(FunctionBlock, ISensor):
        @method
        def read(self) -> REAL:
            return 2.5

    class Holder(FunctionBlock):
        sensor: ISensor = VAR()
        target: POINTER_TO[Sensor] = VAR()

        @method
        def wire(self, sensor: Sensor) -> None:
            self.sensor = sensor
            self.target = adr(sensor)

        @method
        def unwire(self) -> None:
            self.sensor = NULL  # ST: itfSensor := 0;
            self.target = NULL

    sensor, holder = Sensor(), Holder()
    assert holder.sensor == NULL and holder.target == NULL
    holder.wire(sensor)
    assert holder.sensor != NULL and holder.target != NULL and holder.sensor.read() == 2.5
    holder.unwire()
    assert holder.sensor == NULL and holder.target == NULL and holder.target.is_null
    with pytest.raises(PlcException, match="null interface reference") as exc:
        holder.sensor.read()
    assert exc.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


def test_a_derived_block_copied_into_a_base_variable_stays_the_base_type() -> None:
    from iecoop import FunctionBlock, method

    class Motor(FunctionBlock):
        speed: INT = VAR(0)

        @method
        def kind(self) -> STRING:
            return "motor"

        @method
        def set_speed(self, speed: INT) -> None:
            self.speed = speed

    class Servo(Motor):
        axis: DINT = VAR(0)

        @method
        def kind(self) -> STRING:
            return "servo"

    class Cell(FunctionBlock):
        spare: Motor = VAR()

        @method
        def load(self, other: Motor) -> None:
            self.spare = other  # fbSpare := fbOther; copies the base part

    servo = Servo()
    servo.set_speed(5)
    cell = Cell()
    cell.load(servo)
    assert type(cell.spare) is Motor and cell.spare.speed == 5 and cell.spare.kind() == "motor"
    pointer = adr(cell, "spare")
    assert type(pointer.deref) is Motor  # the type tag still says Motor


class Samples(Struct):
    values: ARRAY[INT] = VAR(bounds=(0, 9))


@given(st.integers(-4, 30), st.integers(-4, 30))
def test_pointers_into_one_block_compare_by_offset(i: int, j: int) -> None:
    samples = Samples()
    p, q = adr(samples) + i, adr(samples) + j
    assert (p < q, p <= q, p > q, p >= q, p == q) == (i < j, i <= j, i > j, i >= j, i == j)


def test_null_is_below_every_address_and_blocks_compare_in_allocation_order() -> None:
    first, second = Samples(), Samples()
    p, q = adr(first, "values", 9), adr(second, "values", 0)
    assert p > 0 and 0 < p and p > NULL and not p <= 0 and Pointer() <= 0 and Pointer() < p
    assert p < q and q > p and not q <= p  # first allocated, first in order, whatever the offsets
    assert sorted([q, p, Pointer()]) == [Pointer(), p, q]


def test_a_pointer_compares_with_a_pointer_or_with_0_only() -> None:
    p = adr(Samples())
    for value in (5, 1.5, "x", True):
        with pytest.raises(TypeError, match=r"POINTER <: a pointer compares with a pointer or with 0 \(NULL\)"):
            p < value  # noqa: B015 - the comparison is the test


class SelfPointing(Struct):
    """ST: ``pValue : POINTER TO INT := ADR(nValue); refValue : REFERENCE TO INT := nValue;`` in a STRUCT."""

    value: INT = 5
    values: ARRAY[INT] = VAR([1, 2, 3], bounds=(1, 3))
    value_ptr: POINTER_TO[INT] = VAR(adr_of("value"))
    third: POINTER_TO[INT] = VAR(adr_of("values", 3))
    value_ref: REFERENCE_TO[INT] = VAR(adr_of("value"))


def test_a_pointer_or_reference_initialised_with_a_sibling_address_is_bound_in_each_instance() -> None:
    first, second = SelfPointing(), SelfPointing()
    assert (first.value_ptr.deref, first.third.deref, first.value_ref) == (5, 3, 5)
    first.value_ref = 9
    first.third.deref = 30
    assert (first.value, first.values[3], second.value, second.values[3]) == (9, 30, 5, 3)
    assert first.value_ptr == adr(first, "value") and second.value_ptr == adr(second, "value")
    assert is_valid_ref(second, "value_ref")


def test_a_block_pointer_to_its_own_variable_is_bound_before_fb_init_and_survives_cycles() -> None:
    from iecoop import FunctionBlock

    seen: list[int] = []

    class FB_Count(FunctionBlock):
        n: INT = VAR(10)
        p: POINTER_TO[INT] = VAR(adr_of("n"))

        def fb_init(self, init_retains: bool, in_copy_code: bool) -> bool:
            seen.append(self.p.deref)
            return True

        def body(self) -> None:
            self.p.deref += 1

    block = FB_Count()
    block(); block()
    assert (seen, block.n) == ([10], 12)


def test_an_instance_whose_pointer_points_into_itself_is_collected() -> None:
    cell = weakref.ref(SelfPointing())
    gc.collect()
    assert cell() is None


@pytest.mark.parametrize("declaration, message", [
    ('x: POINTER_TO[LREAL] = VAR(adr_of("value"))', r"Bad\.x: POINTER TO LREAL cannot be initialised with the address of value \(INT\): the types must match"),
    ('x: POINTER_TO[INT] = VAR(adr_of("nope"))', r"Bad\.x: adr_of\('nope'\) names no variable of Bad"),
    ('x: POINTER_TO[INT] = VAR(adr_of("value", 1))', r"Bad\.x: adr_of\('value', 1\) needs an ARRAY, value is INT"),
    ('x: REFERENCE_TO[LREAL] = VAR(adr_of("value"))', r"Bad\.x: REFERENCE TO LREAL cannot be initialised with the address of value"),
    ('x: POINTER_TO[INT] = VAR(adr(SelfPointing(), "value"))', r"Bad\.x: .*POINTER TO INT starts as 0, or as adr_of\(member\)"),
])
def test_a_sibling_address_initial_value_is_checked_at_definition(declaration: str, message: str) -> None:
    with pytest.raises(DefinitionError, match=message):
        exec(f"class Bad(Struct):\n    value: INT = 0\n    {declaration}\n", globals())


# ---------------------------------------------------------------------------
# A POINTER initialised with the address of a global: p : POINTER TO DINT := ADR(foo);
# ---------------------------------------------------------------------------


@gvl
class GVL_PointerTargets(GlobalVariables):
    foo: DINT = 7
    ratio: LREAL = 0.5


class PointsAtGlobal(Struct):
    p: POINTER_TO[DINT] = VAR(adr(GVL_PointerTargets, "foo"))


class BlockPointsAtGlobal(FunctionBlock):
    p: POINTER_TO[DINT] = VAR(adr(GVL_PointerTargets, "foo"))

    def body(self) -> None:
        self.p.deref += 1


class ProgramPointsAtGlobal(Program):
    p: POINTER_TO[DINT] = VAR(adr(GVL_PointerTargets, "foo"))
    block: BlockPointsAtGlobal = VAR()

    def body(self) -> None:
        self.p.deref += 10
        self.block()


def test_a_pointer_starts_aimed_at_a_global_in_a_struct_block_and_program() -> None:
    GVL_PointerTargets.foo = 7
    assert PointsAtGlobal().p.deref == 7 and PointsAtGlobal().p == adr(GVL_PointerTargets, "foo")
    main = ProgramPointsAtGlobal()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), main)
    rt.run(cycles=2)
    assert GVL_PointerTargets.foo == 7 + 2 * 11  # both pointers write the global
    memset(adr(main, "p"), 0, sizeof(main, "p"))  # aimed elsewhere at run time ...
    assert not main.p
    rt.reset_cold()
    assert main.p == adr(GVL_PointerTargets, "foo")  # ... and at the global again after a re-initialisation
    rt.stop()


@gvl
class GVL_Transient(GlobalVariables):
    value: DINT = 1


class HoldsTransient(Struct):
    p: POINTER_TO[DINT] = VAR(adr(GVL_Transient, "value"))


def test_a_pointer_to_a_global_list_that_is_gone_faults_when_used() -> None:
    global GVL_Transient
    value = HoldsTransient().p.deref
    assert value == 1
    del GVL_Transient  # the list goes (a module unloaded): the declaration does not keep it
    gc.collect()
    with raises_plc(ExceptionCode.RTSEXCPT_ACCESS_VIOLATION, "deleted or no longer exists"):
        HoldsTransient().p.deref


def test_a_pointer_initialiser_must_be_a_global_of_the_pointed_type() -> None:
    with pytest.raises(DefinitionError, match=r"Wrong\.p: POINTER TO DINT cannot be initialised with the address of a LREAL"):
        class Wrong(Struct):
            p: POINTER_TO[DINT] = VAR(adr(GVL_PointerTargets, "ratio"))
    local = Cell()
    with pytest.raises(DefinitionError, match=r"Local\.p: POINTER TO INT starts as 0, .*adr\(GVL, member\) of a "
                                              r"global variable; this address is into a Cell instance"):
        class Local(Struct):
            p: POINTER_TO[INT] = VAR(adr(local, "a"))


def test_st_load_reads_a_pointer_initialised_with_the_address_of_a_global() -> None:
    from iecoop import st

    module = st.load(
        """
        VAR_GLOBAL
            globalFoo : DINT := 7;
        END_VAR
        PROGRAM PRG_Reader
        VAR
            p : POINTER TO DINT := ADR(globalFoo);
            n : DINT;
        END_VAR
        n := p^;
        p^ := n + 1;
        END_PROGRAM
        """
    )
    reader = module.PRG_Reader
    reader()
    assert reader.n == 7 and module.GVL.globalFoo == 8
