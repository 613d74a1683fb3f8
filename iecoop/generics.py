"""Generic inputs: ``ANY`` and ``ANY_<type>`` parameters of a FUNCTION or METHOD, received as an ``AnyType``.

ST::

    FUNCTION F_Describe : DINT
    VAR_INPUT value : ANY_NUM; END_VAR
    F_Describe := value.diSize;          (* value is a __SYSTEM.AnyType *)

Python::

    @function
    def F_Describe(value: ANY_NUM) -> DINT:
        return value.diSize

As in TwinCAT and CODESYS, the body does not get the value itself but an
``AnyType`` describing it: ``TypeClass`` (a ``TYPE_CLASS``), ``pValue`` (a
``POINTER TO BYTE`` to the value) and ``diSize`` (its size in bytes).
``pValue`` points at the caller's variable when the caller names one (ST
``F(nCount)``; Python ``F(AnyType.at(adr(self, "count")))``), so the body may
read it through a typed pointer (``pInt := value.pValue; pInt^``); for
any other argument (an expression, a literal, a Python value) it points at a
copy made for the call. Beckhoff and CODESYS document that only a variable may
be passed; iecoop also takes an expression and gives its copy.

The family restricts the argument: an INT given to an ``ANY_REAL`` input is
refused (a DefinitionError when ST is loaded, an AccessError at a Python call).
A Python value gets an IEC type by its kind: ``bool`` is BOOL, ``int`` DINT (LINT
when it does not fit, ULINT above LINT), ``float`` LREAL, ``str`` STRING; a
Struct or block instance is passed as itself. ``AnyType.of(5, INT)`` gives a
value an IEC type of your choice.

>>> from iecoop import DINT, INT, LREAL, function, TYPE_CLASS
>>> @function
... def scaled(value: ANY_NUM) -> LREAL:
...     if value.TypeClass == TYPE_CLASS.TYPE_INT:
...         return value.pValue.typed(INT).deref * 10.0
...     return -1.0
>>> scaled(AnyType.of(7, INT)), scaled(2.5)
(70.0, -1.0)
>>> scaled("text")
Traceback (most recent call last):
...
iecoop.exceptions.AccessError: FUNCTION scaled: VAR_INPUT value : ANY_NUM takes a number (ANY_INT or ANY_REAL), not a STRING(80)

Sources: Beckhoff Infosys TwinCAT 3 "ANY and ANY_<Type>"
(https://infosys.beckhoff.com/content/1033/tc3_plc_intro/2529426571.html);
CODESYS Online Help "Data Type: ANY, ANY_<type>"
(https://content.helpme-codesys.com/en/CODESYS%20Development%20System/_cds_datatype_any.html);
IEC 61131-3 (the generic type families).
"""

from __future__ import annotations

import dataclasses
import enum
import functools
import inspect
from collections.abc import Callable
from typing import Annotated, Any, TypeAlias, TypeVar

from iecoop.metadata import layout_of
from iecoop.exceptions import AccessError
from iecoop.memory._aggregates import AggregateInfo
from iecoop.memory._handles import handle_of
from iecoop.memory._infos import TypeInfo
from iecoop.memory._resolve import resolve_type
from iecoop.memory.operators import TYPE_CLASS, _type_class, adr
from iecoop.memory.pointers import Pointer

__all__ = [
    "ANY", "ANY_BIT", "ANY_DATE", "ANY_ELEMENTARY", "ANY_INT", "ANY_NUM", "ANY_REAL", "ANY_STRING", "AnyFamily", "AnyType",
    "generic_family", "generic_parameters", "with_generics",
]

_F = TypeVar("_F", bound=Callable[..., Any])

_C = TYPE_CLASS
_INT = frozenset({_C.TYPE_SINT, _C.TYPE_INT, _C.TYPE_DINT, _C.TYPE_LINT, _C.TYPE_USINT, _C.TYPE_UINT, _C.TYPE_UDINT, _C.TYPE_ULINT})
_REAL = frozenset({_C.TYPE_REAL, _C.TYPE_LREAL})
_BIT = frozenset({_C.TYPE_BOOL, _C.TYPE_BIT, _C.TYPE_BYTE, _C.TYPE_WORD, _C.TYPE_DWORD, _C.TYPE_LWORD})
_STRING = frozenset({_C.TYPE_STRING, _C.TYPE_WSTRING})
_DATE = frozenset({_C.TYPE_DATE, _C.TYPE_DATEANDTIME, _C.TYPE_TIMEOFDAY})
_DURATION = frozenset({_C.TYPE_TIME, _C.TYPE_LTIME})


@dataclasses.dataclass(frozen=True)
class AnyFamily:
    """One generic type family: its ST name and the type classes it admits (None: every type)."""

    name: str
    classes: frozenset[TYPE_CLASS] | None
    #: what the family takes, in words, for messages
    takes: str

    def admits(self, type_class: TYPE_CLASS) -> bool:
        return self.classes is None or type_class in self.classes


#: The families, by ST name (IEC 61131-3: ANY_NUM = ANY_INT | ANY_REAL; ANY_ELEMENTARY = numbers, durations,
#: bit strings, character strings and dates).
FAMILIES = {
    family.name: family
    for family in (
        AnyFamily("ANY", None, "any type"),
        AnyFamily("ANY_ELEMENTARY", _INT | _REAL | _BIT | _STRING | _DATE | _DURATION, "an elementary type"),
        AnyFamily("ANY_NUM", _INT | _REAL, "a number (ANY_INT or ANY_REAL)"),
        AnyFamily("ANY_INT", _INT, "an integer (SINT ... ULINT)"),
        AnyFamily("ANY_REAL", _REAL, "a REAL or LREAL"),
        AnyFamily("ANY_BIT", _BIT, "a bit string (BOOL, BYTE, WORD, DWORD, LWORD)"),
        AnyFamily("ANY_STRING", _STRING, "a STRING or WSTRING"),
        AnyFamily("ANY_DATE", _DATE, "a DATE, TOD or DT"),
    )
}

#: ``x: ANY_NUM`` declares a generic input; inside the body ``x`` is an ``AnyType`` (typed ``Any`` for a type checker,
#: which cannot see that the argument a caller passes arrives as its description).
ANY: TypeAlias = Annotated[Any, FAMILIES["ANY"]]
ANY_ELEMENTARY: TypeAlias = Annotated[Any, FAMILIES["ANY_ELEMENTARY"]]
ANY_NUM: TypeAlias = Annotated[Any, FAMILIES["ANY_NUM"]]
ANY_INT: TypeAlias = Annotated[Any, FAMILIES["ANY_INT"]]
ANY_REAL: TypeAlias = Annotated[Any, FAMILIES["ANY_REAL"]]
ANY_BIT: TypeAlias = Annotated[Any, FAMILIES["ANY_BIT"]]
ANY_STRING: TypeAlias = Annotated[Any, FAMILIES["ANY_STRING"]]
ANY_DATE: TypeAlias = Annotated[Any, FAMILIES["ANY_DATE"]]


class AnyType:
    """``__SYSTEM.AnyType``: what a generic input receives (``TypeClass``, ``pValue``, ``diSize``).

    ST: ``TYPE AnyType : STRUCT pValue : POINTER TO BYTE; diSize : DINT; TypeClass : __SYSTEM.TYPE_CLASS; END_STRUCT``.
    """

    __slots__ = ("TypeClass", "diSize", "pValue", "_info")

    def __init__(self, pointer: Pointer[Any], info: TypeInfo) -> None:
        self.TypeClass: TYPE_CLASS = _type_class(info)
        self.diSize: int = info.size
        self.pValue: Pointer[Any] = Pointer(pointer.handle, _BYTE_INFO(), keep=pointer._keep)
        self._info = info

    @staticmethod
    def at(pointer: Pointer[Any]) -> AnyType:
        """The caller's variable itself: ``AnyType.at(adr(self, "count"))`` (ST passes ``nCount``)."""
        target = pointer._target
        if target is None:
            raise AccessError("a generic input needs a typed variable; an untyped pointer (PVOID) has no type to pass")
        return AnyType(pointer, target)

    @staticmethod
    def of(value: Any, type_: Any = None) -> AnyType:
        """A copy of ``value`` as the IEC type ``type_`` (inferred from the value when None), for an expression."""
        if isinstance(value, AnyType):
            return value
        if type_ is None:
            if isinstance(value, Pointer):
                raise AccessError("a POINTER passed to a generic input: pass AnyType.at(p) for what it points to")
            if layout_of(type(value)) is not None or getattr(type(value), "_iec_info_", None) is not None:
                return AnyType.at(adr(value))  # a STRUCT, block or ARRAY instance: its memory is the variable
            type_ = _python_type(value)
        info = resolve_type(type_, "generic input")
        holder = info.cls() if isinstance(info, AggregateInfo) else info.ctype()
        info.store(holder, 0, value, "generic input")
        return AnyType(Pointer(handle_of(holder), info, keep=holder), info)

    @property
    def value(self) -> Any:
        """The value ``pValue`` points at, read as its own type (Python's shortcut for a typed pointer's ``^``)."""
        return self._info.load_handle(self.pValue.handle, "AnyType.pValue")

    @property
    def type_name(self) -> str:
        """The IEC name of the argument's type (``INT``, ``STRING(80)``, ``ST_Point``)."""
        return self._info.name

    def __repr__(self) -> str:
        return f"AnyType(TypeClass={self.TypeClass.name}, diSize={self.diSize}, value={self.value!r})"


@functools.cache
def _BYTE_INFO() -> TypeInfo:
    from iecoop.types import BYTE

    return resolve_type(BYTE, "AnyType.pValue")


def _python_type(value: Any) -> Any:
    """The IEC type a plain Python value is passed as (see the module docstring)."""
    from iecoop import types as t

    if isinstance(value, bool):
        return t.BOOL
    if isinstance(value, enum.Enum) and getattr(type(value), "_iec_info_", None) is not None:
        return type(value)
    if isinstance(value, int):
        if -(2**31) <= value < 2**31:
            return t.DINT
        return t.LINT if -(2**63) <= value < 2**63 else t.ULINT
    if isinstance(value, float):
        return t.LREAL
    if isinstance(value, str):
        return t.STRING
    raise AccessError(f"a {type(value).__name__} has no IEC type to pass to a generic input; use AnyType.of(value, <type>)")


def generic_family(annotation: Any, resolve: Callable[[str], Any] | None = None) -> AnyFamily | None:
    """The family an annotation declares (``ANY_NUM``, or its text ``"ANY_NUM"``), else None."""
    if isinstance(annotation, str):
        named = FAMILIES.get(annotation.strip().strip("\"'").rsplit(".", 1)[-1])
        if named is not None or resolve is None:
            return named
        try:
            annotation = resolve(annotation)
        except Exception:  # noqa: BLE001 - a name defined later is no generic family; the annotation is the user's own text
            return None
    for meta in getattr(annotation, "__metadata__", ()):
        if isinstance(meta, AnyFamily):
            return meta
    return None


def generic_parameters(func: Callable[..., Any], resolve: Callable[[str], Any] | None = None) -> dict[str, AnyFamily]:
    """The generic inputs of ``func`` (or of the function it wraps), by name."""
    try:
        params = inspect.signature(inspect.unwrap(func)).parameters.values()
    except (TypeError, ValueError):
        return {}
    return {p.name: family for p in params if (family := generic_family(p.annotation, resolve)) is not None}


def _received(value: Any, family: AnyFamily, label: str, name: str) -> AnyType:
    """What the body gets for ``value``: its AnyType, once the family admits its type."""
    if value is None:
        raise AccessError(f"{label}: VAR_INPUT {name} : {family.name} must be given at every call")
    try:
        given = AnyType.of(value)
    except AccessError as exc:
        raise AccessError(f"{label}: VAR_INPUT {name} : {family.name}: {exc}") from None
    if not family.admits(given.TypeClass):
        raise AccessError(f"{label}: VAR_INPUT {name} : {family.name} takes {family.takes}, not a {given.type_name}")
    return given


def with_generics(func: _F, label: str, resolve: Callable[[str], Any] | None = None) -> _F:
    """``func`` itself without generic inputs, else a wrapper that hands each one an ``AnyType``."""
    families = generic_parameters(func, resolve)
    if not families:
        return func
    params = list(inspect.signature(func).parameters.values())
    kinds = (inspect.Parameter.POSITIONAL_ONLY, inspect.Parameter.POSITIONAL_OR_KEYWORD)
    positions = [(i, p.name, families[p.name]) for i, p in enumerate(params) if p.name in families and p.kind in kinds]
    keywords = [(p.name, families[p.name]) for p in params if p.name in families and p.kind is not inspect.Parameter.POSITIONAL_ONLY]

    @functools.wraps(func)
    def generic(*args: Any, **kwargs: Any) -> Any:
        if positions:
            args_ = list(args)
            for index, name, family in positions:
                if index < len(args_):
                    args_[index] = _received(args_[index], family, label, name)
            args = tuple(args_)
        for name, family in keywords:
            if name in kwargs:
                kwargs[name] = _received(kwargs[name], family, label, name)
        return func(*args, **kwargs)

    setattr(generic, "_iec_generics_", families)
    return generic  # type: ignore[return-value]
