"""Memory layouts match a TwinCAT 3 x64 target with the default alignment (pack mode 8).

Every expected size and offset below was worked out by hand from the C rules
the target follows: each member starts at a multiple of its own alignment
(BOOL, BYTE, SINT, USINT, STRING: 1; INT, UINT, WORD, WSTRING: 2; DINT,
UDINT, DWORD, REAL, TIME, TOD, DATE, DT: 4; LINT, ULINT, LWORD, LREAL, LTIME,
POINTER, REFERENCE: 8; an ARRAY or STRUCT: that of its widest member), and a
STRUCT's size is rounded up to a multiple of its alignment. A UNION is as large
as its largest member, rounded up to the largest alignment.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Annotated

import pytest

from tests import checked_only

from iecoop import (
    ARRAY, BOOL, BYTE, DATE, DINT, DT, DWORD, INT, LINT, LREAL, LTIME, LWORD, POINTER_TO, REAL, REFERENCE_TO, SINT,
    STRING, TIME, TOD, UDINT, UINT, ULINT, USINT, VAR, VAR_INPUT, WORD, WSTRING, Alias, DefinitionError, FunctionBlock, IecEnum, Struct,
    PlcException, Union, adr, ref_assign, sizeof, var_info,
)


class BoolLreal(Struct):
    flag: BOOL = False
    value: LREAL = 0.0


class ByteIntDint(Struct):
    b: BYTE = 0
    i: INT = 0
    d: DINT = 0


class String80(Struct):
    text: STRING = VAR()


class BoolString10Dint(Struct):
    flag: BOOL = False
    text: STRING = VAR("", length=10)
    count: DINT = 0


class WString80(Struct):
    text: WSTRING = VAR()


class BoolWString5(Struct):
    flag: BOOL = False
    text: WSTRING = VAR("", length=5)


class RealString3(Struct):
    r: REAL = 0.0
    s: STRING = VAR("", length=3)


class IntArray20(Struct):
    fifo: ARRAY[INT] = VAR(bounds=(1, 20))


class ByteLrealArray(Struct):
    b: BYTE = 0
    values: ARRAY[LREAL] = VAR(bounds=(1, 3))


class DintGridBool(Struct):
    grid: ARRAY[DINT] = VAR(bounds=((1, 2), (1, 3)))
    flag: BOOL = False


class StringArrayDint(Struct):
    names: ARRAY[STRING] = VAR(bounds=(1, 3), length=4)
    d: DINT = 0


class MixedWidths(Struct):
    a: SINT = 0
    b: LINT = 0
    c: USINT = 0
    d: UDINT = 0
    e: BOOL = False
    f: WORD = 0


class Unsigned(Struct):
    a: USINT = 0
    b: UINT = 0
    c: ULINT = 0
    d: DWORD = 0
    e: LWORD = 0


class Inner16(Struct):
    flag: BOOL = False
    value: LREAL = 0.0


class OuterAligned8(Struct):
    head: BYTE = 0
    inner: Inner16 = VAR()
    tail: BYTE = 0


class Inner4(Struct):
    i: INT = 0
    b: BYTE = 0


class OuterAligned2(Struct):
    head: BYTE = 0
    inner: Inner4 = VAR()
    tail: BYTE = 0


class InnerArray(Struct):
    flag: BOOL = False
    items: ARRAY[Inner4] = VAR(bounds=(0, 1))


class BaseBoolDint(Struct):
    flag: BOOL = False
    count: DINT = 0


class DerivedLreal(BaseBoolDint):
    value: LREAL = 0.0


class BaseTwoInts(Struct):
    x: INT = 0
    y: INT = 0


class DerivedDint(BaseTwoInts):
    z: DINT = 0


class DerivedTwice(DerivedDint):
    w: LREAL = 0.0


class UnionByteLrealString(Union):
    b: BYTE = 0
    value: LREAL = 0.0
    text: STRING = VAR("", length=10)


class UnionByteStringWord(Union):
    b: BYTE = 0
    text: STRING = VAR("", length=10)
    w: WORD = 0


class UnionDintInts(Union):
    whole: DINT = 0
    halves: ARRAY[INT] = VAR(bounds=(0, 1))


class ModeInt(IecEnum):
    IDLE = 0
    RUN = 1


class ModeUdint(IecEnum, base=UDINT):
    IDLE = 0
    RUN = 100_000


class ByteEnumInt(Struct):
    b: BYTE = 0
    mode: ModeInt = ModeInt.IDLE


class ByteEnumUdint(Struct):
    b: BYTE = 0
    mode: ModeUdint = ModeUdint.IDLE


class BoolPointer(Struct):
    flag: BOOL = False
    p: POINTER_TO[INT] = VAR()


class BoolReference(Struct):
    flag: BOOL = False
    r: REFERENCE_TO[INT] = VAR()


class BoolLtime(Struct):
    flag: BOOL = False
    t: LTIME = 0


class TimesAndDates(Struct):
    flag: BOOL = False
    t: TIME = 0
    tod: TOD = 0
    d: DATE = 0
    dt: DT = 0


# class, SIZEOF, {member: byte offset}
LAYOUTS: list[tuple[type[Struct] | type[Union], int, dict[str, int]]] = [
    (BoolLreal, 16, {"flag": 0, "value": 8}),
    (ByteIntDint, 8, {"b": 0, "i": 2, "d": 4}),
    (String80, 81, {"text": 0}),
    (BoolString10Dint, 16, {"flag": 0, "text": 1, "count": 12}),
    (WString80, 162, {"text": 0}),
    (BoolWString5, 14, {"flag": 0, "text": 2}),
    (RealString3, 8, {"r": 0, "s": 4}),
    (IntArray20, 40, {"fifo": 0}),
    (ByteLrealArray, 32, {"b": 0, "values": 8}),
    (DintGridBool, 28, {"grid": 0, "flag": 24}),
    (StringArrayDint, 20, {"names": 0, "d": 16}),
    (MixedWidths, 32, {"a": 0, "b": 8, "c": 16, "d": 20, "e": 24, "f": 26}),
    (Unsigned, 32, {"a": 0, "b": 2, "c": 8, "d": 16, "e": 24}),
    (Inner16, 16, {"flag": 0, "value": 8}),
    (OuterAligned8, 32, {"head": 0, "inner": 8, "tail": 24}),
    (Inner4, 4, {"i": 0, "b": 2}),
    (OuterAligned2, 8, {"head": 0, "inner": 2, "tail": 6}),
    (InnerArray, 10, {"flag": 0, "items": 2}),
    (DerivedLreal, 16, {"flag": 0, "count": 4, "value": 8}),
    (DerivedDint, 8, {"x": 0, "y": 2, "z": 4}),
    (DerivedTwice, 16, {"x": 0, "y": 2, "z": 4, "w": 8}),
    (UnionByteLrealString, 16, {"b": 0, "value": 0, "text": 0}),
    (UnionByteStringWord, 12, {"b": 0, "text": 0, "w": 0}),
    (UnionDintInts, 4, {"whole": 0, "halves": 0}),
    (ByteEnumInt, 4, {"b": 0, "mode": 2}),
    (ByteEnumUdint, 8, {"b": 0, "mode": 4}),
    (BoolPointer, 16, {"flag": 0, "p": 8}),
    (BoolReference, 16, {"flag": 0, "r": 8}),
    (BoolLtime, 16, {"flag": 0, "t": 8}),
    (TimesAndDates, 20, {"flag": 0, "t": 4, "tod": 8, "d": 12, "dt": 16}),
]


@pytest.mark.parametrize(("cls", "size", "offsets"), LAYOUTS, ids=[row[0].__name__ for row in LAYOUTS])
def test_layout_matches_twincat_x64(cls: type[Struct] | type[Union], size: int, offsets: dict[str, int]) -> None:
    instance = cls()
    assert sizeof(cls) == size
    assert sizeof(instance) == size
    assert {name: var_info(instance, name).ByteOffset for name in offsets} == offsets


SIZES: list[tuple[str, object, int]] = [
    ("BOOL", BOOL, 1), ("SINT", SINT, 1), ("USINT", USINT, 1), ("BYTE", BYTE, 1),
    ("INT", INT, 2), ("UINT", UINT, 2), ("WORD", WORD, 2),
    ("DINT", DINT, 4), ("UDINT", UDINT, 4), ("DWORD", DWORD, 4), ("REAL", REAL, 4),
    ("LINT", LINT, 8), ("ULINT", ULINT, 8), ("LWORD", LWORD, 8), ("LREAL", LREAL, 8),
    ("TIME", TIME, 4), ("TOD", TOD, 4), ("DATE", DATE, 4), ("DT", DT, 4), ("LTIME", LTIME, 8),
    ("STRING", STRING, 81), ("WSTRING", WSTRING, 162),
    ("POINTER TO INT", POINTER_TO[INT], 8), ("POINTER TO LREAL", POINTER_TO[LREAL], 8),
    ("REFERENCE TO BYTE", REFERENCE_TO[BYTE], 8),
    ("enum INT", ModeInt, 2), ("enum UDINT", ModeUdint, 4),
]


@pytest.mark.parametrize(("annotation", "size"), [row[1:] for row in SIZES], ids=[row[0] for row in SIZES])
def test_sizeof_types(annotation: object, size: int) -> None:
    assert sizeof(annotation) == size


def test_sizeof_declared_variables() -> None:
    assert sizeof(BoolString10Dint(), "text") == 11
    assert sizeof(BoolWString5(), "text") == 12
    assert sizeof(DintGridBool(), "grid") == 24
    assert sizeof(StringArrayDint(), "names") == 15
    assert sizeof(OuterAligned8(), "inner") == 16


def test_sizeof_a_declared_variable_of_a_class_needs_no_instance() -> None:
    for cls, field, size in [(BoolString10Dint, "text", 11), (BoolWString5, "text", 12), (DintGridBool, "grid", 24),
                             (StringArrayDint, "names", 15), (OuterAligned8, "inner", 16), (Grid, "b", 12)]:
        assert sizeof(cls, field) == sizeof(cls(), field) == size


def test_sizeof_of_a_class_names_the_class_and_the_missing_variable() -> None:
    with pytest.raises(AttributeError, match=r"SIZEOF: BoolString10Dint has no variable 'txt'"):
        sizeof(BoolString10Dint, "txt")
    with pytest.raises(TypeError, match=r"SIZEOF: int is not a struct, union or POU class with a layout"):
        sizeof(int, "real")


def test_union_members_share_their_bytes() -> None:
    u = UnionDintInts(whole=0x12345678)
    assert list(u.halves) == [0x5678, 0x1234]  # little endian: the low half first
    u.halves[1] = -1
    assert u.whole == 0xFFFF5678 - (1 << 32)


def test_derived_struct_puts_base_members_first_and_is_a_base() -> None:
    d = DerivedTwice(x=1, y=2, z=3, w=4.5)
    assert isinstance(d, BaseTwoInts)
    assert (d.x, d.y, d.z, d.w) == (1, 2, 3, 4.5)
    assert var_info(d, "x").Symbol == "BaseTwoInts.x"
    assert var_info(d, "w").Symbol == "DerivedTwice.w"


# ---------------------------------------------------------------------------
# Definition errors: the analog of compile errors, raised by the class statement
# ---------------------------------------------------------------------------


def duplicate_member_in_derived_struct() -> None:
    class Base(Struct):
        speed: INT = 0

    class Derived(Base):
        speed: INT = 0


def array_bounds_reversed() -> None:
    class Reversed(Struct):
        items: ARRAY[INT] = VAR(bounds=(5, 1))


def array_without_bounds() -> None:
    class Unbounded(Struct):
        items: ARRAY[INT] = VAR()


def array_bounds_not_in_pairs() -> None:
    class Odd(Struct):
        items: ARRAY[INT] = VAR(bounds=(1, 2, 3))


def array_bounds_not_integers() -> None:
    class Floats(Struct):
        items: ARRAY[INT] = VAR(bounds=(1.0, 2.0))


def array_bounds_beyond_dint() -> None:
    class Huge(Struct):
        items: ARRAY[INT] = VAR(bounds=(0, 2**31))


def string_length_zero() -> None:
    class Empty(Struct):
        text: STRING = VAR("", length=0)


def wstring_length_too_large() -> None:
    class Large(Struct):
        text: WSTRING = VAR("", length=65536)


def length_on_an_int() -> None:
    class Lengthy(Struct):
        count: INT = VAR(0, length=3)


def bounds_on_an_int() -> None:
    class Bounded(Struct):
        count: INT = VAR(0, bounds=(1, 3))


def plain_python_int() -> None:
    class Plain(Struct):
        count: int = 0


def plain_python_str() -> None:
    class Plain(Struct):
        text: str = ""


def unknown_type_name() -> None:
    class Unknown(Struct):
        count: Nonexistent = 0  # type: ignore[name-defined]


def initial_str_for_int() -> None:
    class Wrong(Struct):
        count: INT = "five"  # type: ignore[assignment]


def initial_int_for_bool() -> None:
    class Wrong(Struct):
        flag: BOOL = 1  # type: ignore[assignment]


def initial_non_latin_1_for_string() -> None:
    class Wrong(Struct):
        text: STRING = "20 €"


def initial_too_many_array_values() -> None:
    class Wrong(Struct):
        items: ARRAY[INT] = VAR([1, 2, 3], bounds=(1, 2))


def initial_pointer_not_null() -> None:
    class Wrong(Struct):
        p: POINTER_TO[INT] = VAR(5)  # type: ignore[arg-type]


def empty_struct() -> None:
    class Nothing(Struct):
        pass


def empty_union() -> None:
    class Nothing(Union):
        pass


def union_extending_a_union() -> None:
    class Base(Union):
        whole: DWORD = 0

    class Derived(Base):
        low: WORD = 0


def enum_value_out_of_base_range() -> None:
    class Small(IecEnum, base=SINT):
        BIG = 200


def enum_value_out_of_default_int_range() -> None:
    class Wide(IecEnum):
        FAR = 40_000


def enum_negative_in_unsigned_base() -> None:
    class Signed(IecEnum, base=UDINT):
        BELOW = -1


def enum_base_not_an_integer() -> None:
    class Floating(IecEnum, base=REAL):
        A = 1


def struct_containing_itself() -> None:
    class Loop(Struct):
        again: Loop = VAR()


def input_section_in_a_struct() -> None:
    class Sectioned(Struct):
        speed: INT = VAR_INPUT(0)


def array_of_references() -> None:
    class Refs(Struct):
        items: ARRAY[REFERENCE_TO[INT]] = VAR(bounds=(1, 2))


def reserved_member_name() -> None:
    class Reserved(Struct):
        _iec_secret: INT = 0


DEFINITION_ERRORS: list[tuple[Callable[[], None], str]] = [
    (duplicate_member_in_derived_struct, r"Derived\.speed: speed is already declared in Base"),
    (array_bounds_reversed, r"Reversed\.items: ARRAY\[5\.\.1\] is empty"),
    (array_without_bounds, r"Unbounded\.items: ARRAY needs bounds"),
    (array_bounds_not_in_pairs, r"Odd\.items: ARRAY bounds come in \(lo, hi\) pairs"),
    (array_bounds_not_integers, r"Floats\.items: ARRAY bounds must be \(lo, hi\) integer pairs"),
    (array_bounds_beyond_dint, r"Huge\.items: ARRAY bounds 0\.\.2147483648 are outside the DINT range"),
    (string_length_zero, r"Empty\.text: STRING length must be an integer 1\.\.65535, got 0"),
    (wstring_length_too_large, r"Large\.text: WSTRING length must be an integer 1\.\.65535, got 65536"),
    (length_on_an_int, r"Lengthy\.count: length= applies to STRING / WSTRING, not INT"),
    (bounds_on_an_int, r"Bounded\.count: bounds= applies to ARRAY, not INT"),
    (plain_python_int, r"Plain\.count: plain int is not an IEC type"),
    (plain_python_str, r"Plain\.text: plain str is not an IEC type"),
    (unknown_type_name, r"Unknown\.count: cannot resolve the annotation 'Nonexistent'"),
    (initial_str_for_int, r"Wrong\.count: initial value of the wrong type: cannot store str 'five' in INT"),
    (initial_int_for_bool, r"Wrong\.flag: initial value of the wrong type: cannot store int 1 in BOOL"),
    (initial_non_latin_1_for_string, r"Wrong\.text: initial value of the wrong type: character '€' has no Latin-1"),
    (initial_too_many_array_values, r"Wrong\.items: initial value of the wrong type: 3 initial values for 2 elements"),
    (initial_pointer_not_null, r"Wrong\.p: initial value of the wrong type: POINTER TO INT starts as 0"),
    (empty_struct, r"STRUCT Nothing has no members"),
    (empty_union, r"UNION Nothing has no members"),
    (union_extending_a_union, r"UNION Derived: a union cannot extend another union"),
    (enum_value_out_of_base_range, r"enumeration Small: BIG := 200 does not fit the base type SINT"),
    (enum_value_out_of_default_int_range, r"enumeration Wide: FAR := 40000 does not fit the base type INT"),
    (enum_negative_in_unsigned_base, r"enumeration Signed: BELOW := -1 does not fit the base type UDINT"),
    (enum_base_not_an_integer, r"enumeration Floating: base type must be an integer type"),
    (struct_containing_itself, r"Loop: a type cannot contain itself inline; use POINTER_TO\[Loop\]"),
    (input_section_in_a_struct, r"Sectioned\.speed: VAR_INPUT is not allowed in a STRUCT"),
    (array_of_references, r"Refs\.items: ARRAY OF REFERENCE is not allowed"),
    (reserved_member_name, r"Reserved\._iec_secret: names starting with '_iec' or '__' are reserved"),
]


@pytest.mark.parametrize(("define", "message"), DEFINITION_ERRORS, ids=[d.__name__ for d, _ in DEFINITION_ERRORS])
def test_definition_errors(define: Callable[[], None], message: str) -> None:
    with pytest.raises(DefinitionError, match=message):
        define()


def test_definition_error_is_a_type_error() -> None:
    with pytest.raises(TypeError):
        plain_python_int()


def test_the_base_classes_cannot_be_instantiated() -> None:
    with pytest.raises(DefinitionError, match=r"Struct is the base class; declare a subclass with members"):
        Struct()
    with pytest.raises(DefinitionError, match=r"Union is the base class"):
        Union()


def test_a_struct_may_point_to_its_own_type() -> None:
    class Link(Struct):
        value: INT = 0
        following: POINTER_TO[Link] = VAR()

    assert sizeof(Link) == 16
    assert var_info(Link(), "following").ByteOffset == 8


# ---------------------------------------------------------------------------
# Lists fill ARRAYs and dicts fill STRUCTs, also nested
# ---------------------------------------------------------------------------


class CalPoint(Struct):
    uv: REAL = 0.0
    celsius: REAL = 0.0


class CalTable(Struct):
    count: INT = 0
    points: ARRAY[CalPoint] = VAR(bounds=(1, 4))
    gains: ARRAY[REAL] = VAR(bounds=(1, 3))


def test_a_struct_is_built_from_lists_and_dicts_for_its_array_and_struct_members() -> None:
    table = CalTable(count=2, gains=[1.0, 2.0], points=[{"uv": 0.0, "celsius": 0.0}, {"uv": 4096.0, "celsius": 100.0}])
    assert table.count == 2
    assert list(table.gains) == [1.0, 2.0, 0.0]  # the rest keeps its initial value
    assert (table.points[2].uv, table.points[2].celsius, table.points[3].uv) == (4096.0, 100.0, 0.0)


def test_declaration_initialisers_nest_lists_and_dicts() -> None:
    class Sensor(FunctionBlock):
        table: CalTable = VAR({"count": 1, "points": [{"celsius": 25.0}], "gains": [0.5]})
        tables: ARRAY[CalTable] = VAR([{"count": 3, "gains": [9.0, 8.0]}, {"count": 4}], bounds=(1, 3))

    sensor = Sensor()
    assert (sensor.table.count, sensor.table.points[1].celsius, sensor.table.gains[1]) == (1, 25.0, 0.5)
    assert [t.count for t in sensor.tables] == [3, 4, 0]
    assert list(sensor.tables[1].gains) == [9.0, 8.0, 0.0]


def test_wrong_lists_and_dicts_name_the_member() -> None:
    with pytest.raises(TypeError, match=r"CalTable\.gains: 4 values for ARRAY\[1\.\.3\] OF REAL, which has 3 elements"):
        CalTable(gains=[1.0, 2.0, 3.0, 4.0])
    with pytest.raises(TypeError, match=r"CalTable\.points\[1\]: CalPoint has no member 'kelvin'"):
        CalTable(points=[{"kelvin": 1.0}])
    with pytest.raises(TypeError, match=r"CalTable\.gains\[2\]: cannot store str 'x' in REAL"):
        CalTable(gains=[1.0, "x"])


def test_references_and_pointers_to_arrays_take_the_arrays_bounds() -> None:
    from iecoop import adr, method, ref_assign

    class Owner(FunctionBlock):
        points: ARRAY[CalPoint] = VAR([{"uv": 1.0}, {"uv": 2.0}], bounds=(1, 4))
        counts: ARRAY[INT] = VAR([5, 6, 7], bounds=(1, 3))

    class User(FunctionBlock):
        table: REFERENCE_TO[ARRAY[CalPoint]] = VAR(bounds=(1, 4))
        counts: POINTER_TO[ARRAY[INT]] = VAR(bounds=(1, 3))

        @method
        def second(self) -> REAL:
            return self.table[2].uv

        @method
        def use(self, counts: POINTER_TO[ARRAY[INT]]) -> None:
            self.counts = counts

        @method
        def last_count(self) -> INT:
            return self.counts.deref[3]

    owner, user = Owner(), User()
    ref_assign(user, "table", adr(owner, "points"))
    user.use(adr(owner, "counts"))
    assert (user.second(), user.last_count()) == (2.0, 7)


class Grid(Struct):
    """ST: ``a : ARRAY[0..4] OF ARRAY[0..2] OF INT; b : ARRAY[1..2] OF ARRAY[1..2, 1..3] OF BYTE``."""

    flag: BOOL = False
    a: ARRAY[ARRAY[INT]] = VAR(bounds=((0, 4), (0, 2)))
    b: ARRAY[ARRAY[BYTE]] = VAR([[1, 2, 3, 4, 5, 6], [7]], bounds=((1, 2), ((1, 2), (1, 3))))


def test_an_array_of_arrays_has_one_bounds_entry_per_level_and_is_laid_out_row_by_row() -> None:
    grid = Grid()
    assert sizeof(Grid) == 2 + 5 * 3 * 2 + 2 * 6
    assert var_info(grid, "a").TypeName == "ARRAY[0..4] OF ARRAY[0..2] OF INT"
    grid.a[4][2] = 42
    assert list(grid.a[4]) == [0, 0, 42]
    assert grid.b[1][2, 3] == 6 and grid.b[2][1, 1] == 7 and grid.b[2][2, 3] == 0


def test_an_element_array_is_a_view_that_takes_an_array_or_a_list() -> None:
    grid = Grid()
    row = grid.a[1]
    row[0] = 5
    assert grid.a[1][0] == 5
    grid.a[2] = row
    grid.a[3] = [7, 8]  # type: ignore[assignment]  # a list stores element by element
    assert [list(r) for r in grid.a] == [[0, 0, 0], [5, 0, 0], [5, 0, 0], [7, 8, 0], [0, 0, 0]]
    with pytest.raises(PlcException, match="RTSEXCPT_ARRAYBOUNDS"):
        grid.a[5][0] = 1
    with pytest.raises(PlcException, match="RTSEXCPT_ARRAYBOUNDS"):
        grid.a[0][3] = 1


@pytest.mark.parametrize("bounds, message", [
    (None, r"Nested\.a: ARRAY needs bounds=, e\.g\. VAR\(bounds=\(\(0, 4\), \(0, 9\)\), one \(lo, hi\) per ARRAY level\)"),
    ((0, 4), r"Nested\.a: an ARRAY of ARRAY nests 2 levels and takes one bounds entry per level"),
    (((0, 4), (0, 4), (0, 4)), r"Nested\.a: an ARRAY of ARRAY nests 2 levels"),
    (((0, 4), (4, 0)), r"Nested\.a: ARRAY\[4\.\.0\] is empty"),
])
def test_an_array_of_arrays_names_what_is_wrong_with_its_bounds(bounds: object, message: str) -> None:
    with pytest.raises(DefinitionError, match=message):
        class Nested(Struct):
            a: ARRAY[ARRAY[INT]] = VAR(bounds=bounds)


def test_an_array_of_arrays_of_blocks_is_refused_with_the_multi_dimensional_form() -> None:
    class FB_Cell(FunctionBlock):
        n: INT = VAR()

    with pytest.raises(DefinitionError, match=r"Board\.cells: ARRAY OF ARRAY OF a function block .* ARRAY\[a\.\.b, c\.\.d\]"):
        class Board(Struct):
            cells: ARRAY[ARRAY[FB_Cell]] = VAR(bounds=((0, 1), (0, 1)))


@checked_only
def test_an_array_of_arrays_takes_a_list_of_lists_all_or_nothing() -> None:
    grid = Grid()
    grid.a = [[1], [2, 3]]  # type: ignore[assignment]
    assert [list(r) for r in grid.a][:2] == [[1, 0, 0], [2, 3, 0]]
    with pytest.raises(TypeError, match=r"Grid\.a\[1\]: 4 values for ARRAY\[0\.\.2\] OF INT, which has 3 elements"):
        grid.a = [[9], [1, 2, 3, 4]]  # type: ignore[assignment]
    assert grid.a[0][0] == 1


Index = Annotated[DINT, Alias("T_Index", initial=-1)]


class Cursor(Struct):
    """ST: ``TYPE T_Index : DINT := -1; END_TYPE`` and fields of that type."""

    unset: Index = VAR()
    given: Index = 4
    many: ARRAY[Index] = VAR([7], bounds=(1, 3))
    plain: DINT = VAR()


class FB_Cursor(FunctionBlock):
    at: Index = VAR_INPUT()


def test_a_field_of_an_alias_type_starts_with_the_alias_initial_value_unless_it_gives_its_own() -> None:
    cursor = Cursor()
    assert (cursor.unset, cursor.given, list(cursor.many), cursor.plain) == (-1, 4, [7, -1, -1], 0)
    assert FB_Cursor().at == -1
    assert var_info(cursor, "unset").TypeName == "T_Index"
    assert repr(Alias("T_Index", initial=-1)) == "Alias('T_Index', initial=-1)"


def test_an_alias_initial_value_of_the_wrong_type_names_the_field() -> None:
    with pytest.raises(DefinitionError, match=r"Bad\.flag: initial value of the wrong type: cannot store str 'x' in BOOL"):
        class Bad(Struct):
            flag: Annotated[BOOL, Alias("T_Flag", initial="x")] = VAR()


def test_a_reference_to_an_alias_type_resolves_whether_the_alias_stands_inside_or_outside() -> None:
    """ST: ``rIndex : REFERENCE TO T_Index;`` written either way round in Python."""

    class Holder(Struct):
        target: Index = VAR()
        inside: REFERENCE_TO[Index] = VAR()
        outside: Annotated[REFERENCE_TO[DINT], Alias("T_Index")] = VAR()

    holder = Holder()
    assert var_info(holder, "inside").TypeName == var_info(holder, "outside").TypeName == "REFERENCE TO T_Index"
    ref_assign(holder, "inside", adr(holder, "target"))
    ref_assign(holder, "outside", adr(holder, "target"))
    holder.inside = 3
    assert (holder.target, holder.outside) == (3, 3)


def test_a_reference_to_an_interface_is_refused_at_definition() -> None:
    from iecoop import Interface

    class I_Probe(Interface):
        pass

    with pytest.raises(DefinitionError, match=r"ToInterface\.r: REFERENCE TO I_Probe is not allowed; declare the variable as I_Probe itself"):
        class ToInterface(Struct):
            r: REFERENCE_TO[I_Probe] = VAR()



def test_a_reference_to_a_reference_is_refused_at_definition_however_it_nests() -> None:
    """CODESYS and TwinCAT reject ``REFERENCE TO REFERENCE TO INT``."""
    with pytest.raises(DefinitionError, match=r"Twice\.r: REFERENCE TO REFERENCE TO INT is not allowed"):
        class Twice(Struct):
            r: REFERENCE_TO[REFERENCE_TO[INT]] = VAR()
    with pytest.raises(DefinitionError, match=r"Named\.r: REFERENCE TO REFERENCE TO INT is not allowed"):
        class Named(Struct):
            r: REFERENCE_TO["REFERENCE_TO[INT]"] = VAR()


def test_a_pointer_to_a_reference_is_refused_at_definition() -> None:
    """CODESYS: a reference type is never the base type of an array, a pointer or a reference."""
    with pytest.raises(DefinitionError, match=r"Pointing\.p: POINTER TO REFERENCE is not allowed"):
        class Pointing(Struct):
            p: POINTER_TO[REFERENCE_TO[INT]] = VAR()

    class Late(Struct):
        p: POINTER_TO["REFERENCE_TO[INT]"] = VAR()  # a target named by a string is resolved at first use

    late = Late()
    with pytest.raises(DefinitionError, match=r"Late\.p: POINTER TO REFERENCE is not allowed"):
        late.p.deref


def test_a_block_member_of_a_struct_with_declared_inputs_is_refused_not_left_at_its_defaults() -> None:
    from iecoop import ARRAY, INT, FunctionBlock, Struct, VAR, VAR_INPUT

    class FB_Gain(FunctionBlock):
        k: INT = VAR_INPUT(1)

    class ST_Plain(Struct):
        gain: FB_Gain = VAR()

    assert ST_Plain().gain.k == 1  # without inputs it is the block's own initial values
    for spec in (VAR({"k": 5}), VAR(fb_init={"k": 5})):
        with pytest.raises(DefinitionError, match=r"ST_Gains\.gain: a FUNCTION_BLOCK member of a STRUCT takes no inputs "
                                                  r"or fb_init= at its declaration .* make ST_Gains a FUNCTION_BLOCK"):
            type("ST_Gains", (Struct,), {"__annotations__": {"gain": FB_Gain}, "gain": spec})
    with pytest.raises(DefinitionError, match=r"ST_Row\.gains: a FUNCTION_BLOCK member of a STRUCT"):
        type("ST_Row", (Struct,), {"__annotations__": {"gains": ARRAY[FB_Gain]}, "gains": VAR([{"k": 2}], bounds=(1, 2))})
