"""Generic inputs (ANY, ANY_<type>) of Python FUNCTIONs and METHODs: what the body receives and what a family takes."""

from __future__ import annotations

import pytest

from iecoop import (
    ANY, ANY_BIT, ANY_DATE, ANY_ELEMENTARY, ANY_INT, ANY_NUM, ANY_REAL, ANY_STRING, BYTE, DINT, INT, LREAL, POINTER_TO,
    REAL, STRING, TYPE_CLASS, VAR, VAR_OUTPUT, AccessError, AnyType, FunctionBlock, Struct, adr, function, method,
)
from iecoop.generics import FAMILIES


class Point(Struct):
    x: INT = 1
    y: INT = 2


class Accumulator(FunctionBlock):
    total: LREAL = VAR(0.0)
    count: INT = VAR(3)
    ratio: REAL = VAR(1.5)

    @method
    def add(self, value: ANY_NUM, scale: INT = 1) -> DINT:
        """METHOD Add : DINT  VAR_INPUT value : ANY_NUM; scale : INT := 1; END_VAR"""
        if value.TypeClass == TYPE_CLASS.TYPE_INT:
            self.total += value.pValue.typed(INT).deref * scale
        elif value.TypeClass == TYPE_CLASS.TYPE_REAL:
            self.total += value.pValue.typed(REAL).deref * scale
        elif value.TypeClass == TYPE_CLASS.TYPE_LREAL:
            self.total += value.pValue.typed(LREAL).deref * scale
        return int(value.diSize)


@function
def size_of(value: ANY) -> DINT:
    return int(value.diSize)


@function
def clear(value: ANY_INT) -> None:
    value.pValue.typed(INT).deref = 0


@function
def described(value: ANY_ELEMENTARY, kind: POINTER_TO[DINT] = VAR_OUTPUT()) -> DINT:
    kind.deref = int(value.TypeClass)
    return int(value.diSize)


def test_a_method_reads_the_callers_variable_through_pvalue() -> None:
    acc = Accumulator()
    assert acc.add(AnyType.at(adr(acc, "count")), 2) == 2          # INT: 2 bytes
    assert acc.total == 6.0
    assert acc.add(AnyType.at(adr(acc, "ratio"))) == 4             # REAL: 4 bytes
    assert acc.total == 7.5
    assert acc.add(scale=10, value=0.25) == 8                       # a Python float is an LREAL copy
    assert acc.total == 10.0


def test_a_body_writes_the_callers_variable_and_not_a_copy() -> None:
    acc = Accumulator()
    clear(AnyType.at(adr(acc, "count")))
    assert acc.count == 0
    copy = AnyType.of(7, INT)
    clear(copy)
    assert copy.value == 0


def test_python_values_get_their_iec_type() -> None:
    assert (AnyType.of(True).TypeClass, AnyType.of(5).TypeClass, AnyType.of(2**40).TypeClass) == (
        TYPE_CLASS.TYPE_BOOL, TYPE_CLASS.TYPE_DINT, TYPE_CLASS.TYPE_LINT)
    assert AnyType.of(2**63).TypeClass == TYPE_CLASS.TYPE_ULINT
    assert (AnyType.of(1.5).TypeClass, AnyType.of("ab").TypeClass) == (TYPE_CLASS.TYPE_LREAL, TYPE_CLASS.TYPE_STRING)
    assert AnyType.of("ab").diSize == 81
    assert AnyType.of(300, BYTE).value == 44                         # stored as the type: BYTE wraps
    point = Point()
    given = AnyType.of(point)
    assert (given.TypeClass, given.diSize, size_of(point)) == (TYPE_CLASS.TYPE_USERDEF, 4, 4)
    given.pValue.typed(INT).deref = 40
    assert point.x == 40                                             # a STRUCT is passed as itself


def test_outputs_and_generic_inputs_together() -> None:
    class Holder(Struct):
        kind: DINT = 0

    holder = Holder()
    assert described(AnyType.of(3, INT), kind=adr(holder, "kind")) == 2
    assert holder.kind == TYPE_CLASS.TYPE_INT


@pytest.mark.parametrize(("family", "value", "admitted"), [
    (ANY_REAL, AnyType.of(1, INT), False), (ANY_REAL, 1.0, True), (ANY_INT, 1.0, False), (ANY_INT, 1, True),
    (ANY_BIT, True, True), (ANY_BIT, AnyType.of(1, BYTE), True), (ANY_BIT, 1, False),
    (ANY_STRING, "x", True), (ANY_STRING, 1, False), (ANY_NUM, True, False), (ANY_DATE, 1, False),
    (ANY_ELEMENTARY, Point(), False), (ANY, Point(), True), (ANY_ELEMENTARY, AnyType.of("s", STRING), True),
])
def test_the_family_restricts_the_argument(family: object, value: object, admitted: bool) -> None:
    @function
    def take(x: family) -> DINT:  # type: ignore[valid-type]
        return int(x.TypeClass)  # type: ignore[attr-defined]

    if admitted:
        take(value)
    else:
        with pytest.raises(AccessError, match=r"FUNCTION take: VAR_INPUT x : ANY_\w* takes .*, not a "):
            take(value)


def test_a_value_with_no_iec_type_is_refused_by_name() -> None:
    with pytest.raises(AccessError, match=r"VAR_INPUT value : ANY: a object has no IEC type"):
        size_of(object())
    with pytest.raises(AccessError, match="POINTER"):
        size_of(adr(Point()))


def test_string_annotations_name_the_family() -> None:
    @function
    def f(x: "ANY_REAL") -> None:
        pass

    with pytest.raises(AccessError, match="ANY_REAL takes a REAL or LREAL, not a DINT"):
        f(1)


def test_every_family_is_exported() -> None:
    import iecoop

    assert set(FAMILIES) <= set(iecoop.__all__) and "AnyType" in iecoop.__all__
