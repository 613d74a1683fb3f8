"""TcUnit's assert family: how FB_TestSuite's asserts compare values and print them as TcUnit logs them.

``AssertEquals_<type>`` and ``AssertArray[2d|3d]Equals_<type>`` are METHODs made
here, one per TcUnit type (``iecoop.libraries.tcunit`` puts them on
``FB_TestSuite``); a failed one records its expected and actual values as ST
text (``TRUE``, ``16#FF``, ``T#1S``) with the suite's registry.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Sequence
from typing import TYPE_CHECKING, Any

from iecoop import ARRAY, STRING, method
from iecoop.exceptions import ExceptionCode, PlcException
from iecoop.generics import AnyType
from iecoop.literals import format_date, format_dt, format_ltime, format_time, format_tod
from iecoop.memory import TYPE_CLASS, Pointer
from iecoop import types
from iecoop.types import ELEMENTARY_TYPES, ElementaryType

if TYPE_CHECKING:
    from iecoop.libraries.tcunit import FB_TestSuite

__all__ = ["ELEMENTARY", "ELEMENTARY_CLASSES", "TEXT_CLASSES", "any_text", "array_equals", "equals", "typed_text"]


# --- comparing and printing values ------------------------------------------------------------

_BIT_STRINGS = frozenset({"BYTE", "WORD", "DWORD", "LWORD"})
_FORMATS = {"TIME": format_time, "LTIME": format_ltime, "DATE": format_date, "TIME_OF_DAY": format_tod,
            "TOD": format_tod, "DATE_AND_TIME": format_dt, "DT": format_dt}
#: The elementary type behind each TcUnit type suffix.
ELEMENTARY = {"TIME_OF_DAY": "TOD", "DATE_AND_TIME": "DT"}


def _stored(type_name: str, value: Any) -> Any:
    record = ELEMENTARY_TYPES[ELEMENTARY.get(type_name, type_name)]
    if isinstance(record, ElementaryType):
        return record.store(value)
    return str(value)


def _text(type_name: str, value: Any) -> str:
    """``value`` as TcUnit prints it: TRUE / FALSE, 16#.. for bit strings, ST literals for times and dates."""
    if type_name == "BOOL":
        return "TRUE" if value else "FALSE"
    if type_name in _BIT_STRINGS:
        return f"16#{value:X}"
    if type_name in _FORMATS:
        try:
            return _FORMATS[type_name](value)
        except ValueError:
            return str(value)
    if isinstance(value, float):
        return repr(value)
    return str(value)


TEXT_CLASSES = frozenset({TYPE_CLASS.TYPE_STRING, TYPE_CLASS.TYPE_WSTRING})
#: The type classes AssertEquals(ANY) compares by value; the others (STRUCT, ARRAY, blocks ...) byte by byte.
ELEMENTARY_CLASSES = frozenset(TYPE_CLASS(n) for n in range(0, 22)) | {TYPE_CLASS.TYPE_LTIME, TYPE_CLASS.TYPE_ENUM}


def any_text(value: AnyType) -> str:
    """An ANY argument's value as ST text."""
    if value.TypeClass in ELEMENTARY_CLASSES:
        return _text(value.type_name.split("(")[0], value.value)
    return f"{value.type_name} ({value.diSize} bytes)"


def typed_text(value: AnyType) -> str:
    return f"({value.type_name}) {any_text(value)}"


def _differs(expected: Any, actual: Any, delta: float | None) -> bool:
    if delta is not None:
        difference = abs(expected - actual)
        return not (difference <= abs(delta)) and not (math.isinf(expected) and expected == actual)
    return bool(expected != actual)


def _elements(values: Any, depth: int, where: str) -> tuple[list[int], list[tuple[tuple[int, ...], Any]]]:
    """The shape (elements per dimension) and (index, value) pairs of an ARRAY or nested sequence.

    ST indices are used for an iecoop ARRAY (its declared bounds), 0-based ones for a Python list.
    """
    if isinstance(values, Pointer):  # a VAR_IN_OUT passed by address: the array it points at
        values = values.deref
    bounds = getattr(values, "bounds", None)
    if bounds is not None:
        if len(bounds) != depth:
            raise PlcException(ExceptionCode.RTSEXCPT_ARRAYBOUNDS,
                               f"TcUnit.{where}: expects {depth}-dimensional arrays, got ARRAY[{bounds}]")
        shape = [hi - lo + 1 for lo, hi in bounds]
        pairs: list[tuple[tuple[int, ...], Any]] = []
        indices: list[tuple[int, ...]] = [()]
        for lo, hi in bounds:
            indices = [(*prefix, i) for prefix in indices for i in range(lo, hi + 1)]
        for index in indices:
            pairs.append((index, values[index if depth > 1 else index[0]]))
        return shape, pairs
    shape = []
    level: Any = values
    for _ in range(depth):
        if not isinstance(level, Sequence) or isinstance(level, str):
            raise PlcException(ExceptionCode.RTSEXCPT_ARRAYBOUNDS,
                               f"TcUnit.{where}: expects {depth}-dimensional arrays (lists or ARRAYs), got {values!r}")
        shape.append(len(level))
        level = level[0] if len(level) else []

    def walk(node: Any, prefix: tuple[int, ...], left: int) -> Iterator[tuple[tuple[int, ...], Any]]:
        if left == 0:
            yield prefix, node
            return
        if not isinstance(node, Sequence) or isinstance(node, str) or len(node) != shape[depth - left]:
            raise PlcException(ExceptionCode.RTSEXCPT_ARRAYBOUNDS,
                               f"TcUnit.{where}: the nested lists are not rectangular at index {list(prefix)}")
        for i, item in enumerate(node):
            yield from walk(item, (*prefix, i), left - 1)

    return shape, list(walk(values, (), depth))


def equals(type_name: str, with_delta: bool = False) -> Any:
    """``METHOD AssertEquals_<type>(Expected, Actual[, Delta], Message)``: one per TcUnit type."""
    annotation = getattr(types, ELEMENTARY.get(type_name, type_name))
    name = f"AssertEquals_{type_name}"

    def assert_equals(self: FB_TestSuite, Expected: Any, Actual: Any, Delta: Any = 0.0, Message: Any = "") -> None:
        expected, actual = _stored(type_name, Expected), _stored(type_name, Actual)
        if _differs(expected, actual, _stored(type_name, Delta) if with_delta else None):
            self._registry().record(self, name, str(Message), _text(type_name, expected), _text(type_name, actual))

    function: Callable[..., None]
    if not with_delta:
        def assert_equals_plain(self: FB_TestSuite, Expected: Any, Actual: Any, Message: Any = "") -> None:
            assert_equals(self, Expected, Actual, 0.0, Message)

        function = assert_equals_plain
    else:
        function = assert_equals
    function.__name__ = function.__qualname__ = name
    function.__doc__ = (
        f"``{name}(Expected, Actual{', Delta' if with_delta else ''}, Message)``: fails when the two "
        f"{type_name} values differ{' by more than Delta' if with_delta else ''}."
    )
    function.__annotations__ = {"Expected": annotation, "Actual": annotation, "Message": STRING, "return": None}
    if with_delta:
        function.__annotations__["Delta"] = annotation
    return method(function)


def array_equals(type_name: str, depth: int = 1, with_delta: bool = False) -> Any:
    """``METHOD AssertArray[2d|3d]Equals_<type>(Expecteds, Actuals : ARRAY[*] OF <type> (VAR_IN_OUT), [Delta,] Message)``."""
    dims = {1: "", 2: "2d", 3: "3d"}[depth]
    name = f"AssertArray{dims}Equals_{type_name}"

    def assert_array_equals(self: FB_TestSuite, Expecteds: Any, Actuals: Any, Delta: Any = 0.0, Message: Any = "") -> None:
        registry = self._registry()
        expected_shape, expecteds = _elements(Expecteds, depth, name)
        actual_shape, actuals = _elements(Actuals, depth, name)
        if expected_shape != actual_shape:
            registry.record(self, name, str(Message), "SIZE " + " x ".join(map(str, expected_shape)),
                            "SIZE " + " x ".join(map(str, actual_shape)))
            return
        tolerance = _stored(type_name, Delta) if with_delta else None
        for (index, expected), (actual_index, actual) in zip(expecteds, actuals):
            expected, actual = _stored(type_name, expected), _stored(type_name, actual)
            if _differs(expected, actual, tolerance):
                where = ", ".join(map(str, actual_index))
                registry.record(self, name, str(Message), _text(type_name, expected), _text(type_name, actual), f"[{where}]")
                return

    function: Callable[..., None]
    if not with_delta:
        def assert_array_plain(self: FB_TestSuite, Expecteds: Any, Actuals: Any, Message: Any = "") -> None:
            assert_array_equals(self, Expecteds, Actuals, 0.0, Message)

        function = assert_array_plain
    else:
        function = assert_array_equals
    function.__name__ = function.__qualname__ = name
    function.__doc__ = (
        f"``{name}(Expecteds, Actuals{', Delta' if with_delta else ''}, Message)``: fails when the "
        f"{type_name} arrays differ in size or in an element (the first differing index is reported)."
    )
    element = getattr(types, type_name)
    array: Any = ARRAY  # ARRAY[*] OF <type>: the element type is only known here
    function.__annotations__ = {"Expecteds": array[element], "Actuals": array[element], "Message": STRING, "return": None}
    if with_delta:
        function.__annotations__["Delta"] = element
    return method(function)
