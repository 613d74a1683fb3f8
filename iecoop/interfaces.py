"""INTERFACE: method and property prototypes, implemented by function blocks.

``class ISensor(Interface)`` is ``INTERFACE I_Sensor``; ``class IAB(IA, IB)``
is ``INTERFACE I_AB EXTENDS I_A, I_B``. An interface holds no state and no
bodies, and cannot be instantiated. A variable typed with an interface is a
reference: it starts as 0 (a falsy ``NullInterface``), and calling through it
raises RTSEXCPT_ACCESS_VIOLATION.

>>> from iecoop import BOOL, FunctionBlock, Interface, method, query_interface
>>> class IStartable(IQueryInterface):
...     @method
...     def start(self) -> BOOL: ...
>>> class IDiagnosable(IQueryInterface):
...     @method
...     def healthy(self) -> BOOL: ...
>>> class Pump(FunctionBlock, IStartable, IDiagnosable):
...     @method
...     def start(self) -> BOOL:
...         return True
...     @method
...     def healthy(self) -> BOOL:
...         return True
>>> diag = query_interface(Pump(), IDiagnosable)
>>> diag.healthy()
True
"""

from __future__ import annotations

import typing
from typing import Any, ClassVar, TypeVar

from iecoop.exceptions import DefinitionError
from iecoop.memory._handles import handle_of
from iecoop.memory._resolve import class_info
from iecoop.memory.interface_references import NullInterface
from iecoop.memory.pointers import Pointer
from iecoop.memory.layout import DefinitionScope, class_st_name, register_builder
from iecoop.members import Member, has_body, members_of_namespace
from iecoop.metadata import IecClass, iec_class, kind_of
from iecoop.sections import Kind

register_builder(__file__)

__all__ = ["NULL", "IQueryInterface", "null", "Interface", "interface_members", "query_interface", "query_pointer"]

#: The null reference, for clearing an interface or pointer variable and comparing with it
#: (ST ``itfSensor := 0;``, ``IF itfSensor = 0 THEN``). Typed ``Any`` so that
#: ``self.sensor = NULL`` and ``self.sensor == NULL`` type-check for a field of any interface type.
NULL: Any = None

_I = TypeVar("_I")


def null(iface: type[_I]) -> _I:
    """The null reference of one interface type, typed as that interface (ST: ``RETURN 0`` for ``: I_Valve``).

    ``return null(IValve)`` type-checks in a method declared ``-> IValve``;
    calling through it raises RTSEXCPT_ACCESS_VIOLATION, as on the PLC.

    >>> from iecoop import INT, method
    >>> class IValve(Interface):
    ...     @method
    ...     def open(self) -> INT:
    ...         raise NotImplementedError
    >>> valve = null(IValve)
    >>> bool(valve), valve == NULL
    (False, True)
    >>> valve.open()
    Traceback (most recent call last):
    ...
    iecoop.exceptions.PlcException: RTSEXCPT_ACCESS_VIOLATION (16#...): null(IValve): IValve.open called through a null interface reference
    """
    if not (isinstance(iface, type) and kind_of(iface) is Kind.INTERFACE):
        raise TypeError(f"null() takes an interface type, got {iface!r}")
    return typing.cast(_I, NullInterface(iface.__name__, f"null({iface.__name__})"))


_ALLOWED_CLASS_ATTRS = frozenset({"__dict__", "__weakref__", "__module__", "__qualname__", "__doc__", "__annotations__", "__firstlineno__", "__static_attributes__", "__orig_bases__", "__parameters__"})


class Interface:
    """Base of every INTERFACE. Subclass it with method / property prototypes only."""

    __slots__ = ()
    __iec__: ClassVar[IecClass] = IecClass(Kind.INTERFACE, root=True)

    def __init_subclass__(cls, st_name: str | None = None, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        own = cls.__dict__.get("__iec__")
        if isinstance(own, IecClass) and own.kind.is_pou:
            return  # a block that IMPLEMENTS interfaces
        # The first base with a record decides: class IBad(Interface, Recipe) declares an interface.
        inherited = next(b.__dict__["__iec__"].kind for b in cls.__mro__[1:] if "__iec__" in b.__dict__)
        if inherited is Kind.INTERFACE:
            _build_interface(cls, class_st_name(st_name, f"INTERFACE {cls.__name__}"))

    def __new__(cls, *args: Any, **kwargs: Any) -> Any:
        if kind_of(cls) is Kind.INTERFACE:
            raise TypeError(f"INTERFACE {cls.__name__} cannot be instantiated; implement it in a FunctionBlock")
        return super().__new__(cls)


def _build_interface(cls: type, st_name: str = "") -> None:
    name = st_name or cls.__name__
    for base in cls.__bases__:
        if base is object or base is Interface:
            continue
        if not (isinstance(base, type) and issubclass(base, Interface)) or kind_of(base) is not Kind.INTERFACE:
            raise DefinitionError(f"INTERFACE {name}: an interface can only EXTEND interfaces, not {base.__name__}")
    namespace = dict(cls.__dict__)
    annotations = namespace.get("__annotations__", {})
    if annotations:
        field = next(iter(annotations))
        raise DefinitionError(f"INTERFACE {name}: interfaces hold no state, but {field!r} is declared as a variable")
    for attr, value in namespace.items():
        if attr in _ALLOWED_CLASS_ATTRS or attr.startswith("_iec") or attr == "__slots__":
            continue
        if not (callable(value) or isinstance(value, property)):
            raise DefinitionError(f"INTERFACE {name}: interfaces hold no state, but {attr!r} is a class variable")
    scope = DefinitionScope(namespace)
    own = members_of_namespace(cls, namespace, lambda text: scope.eval(text), frozenset())
    for member in own.values():
        funcs = [cls.__dict__[member.name]]
        if member.kind == "property":
            prop = funcs[0]
            funcs = [f for f in (prop.fget, prop.fset) if f is not None]
        if any(has_body(f) for f in funcs):
            raise DefinitionError(
                f"INTERFACE {name}: {member.name} has a body; an interface declares prototypes only (write '...' or 'raise NotImplementedError')"
            )
    members: dict[str, Member] = {}
    for base in reversed(cls.__mro__[1:]):
        record = iec_class(base)
        if record is not None:
            members.update(record.members)
    members.update(own)
    record = IecClass(Kind.INTERFACE, st_name=st_name)
    record.complete(members=members)
    type.__setattr__(cls, "__iec__", record)


def interface_members(iface: type) -> dict[str, Member]:
    """Every method and property an interface declares, its EXTENDS included."""
    record = iec_class(iface)
    return dict(record.members) if record is not None else {}


class IQueryInterface(Interface):
    """``__SYSTEM.IQueryInterface``: interfaces usable with query_interface / query_pointer."""


def _check_queryable(iface: type, op: str) -> None:
    if not (isinstance(iface, type) and issubclass(iface, Interface)) or kind_of(iface) is not Kind.INTERFACE:
        raise TypeError(f"{op}: {iface!r} is not an INTERFACE")
    if not issubclass(iface, IQueryInterface):
        raise DefinitionError(f"{op}: Interface {iface.__name__} does not extend __System.IQueryInterface (C0239)")


def query_interface(source: Any, target: type[_I]) -> _I | None:
    """``__QUERYINTERFACE(itfSource, itfDest)``: the same object seen as ``target``, or None.

    The dynamic object decides (cross-casts between sibling interfaces work);
    a null source gives None.
    """
    _check_queryable(target, "__QUERYINTERFACE")
    if source is None or isinstance(source, NullInterface):
        return None
    if isinstance(source, Interface) and not isinstance(source, IQueryInterface):
        raise DefinitionError(
            f"__QUERYINTERFACE: the source {type(source).__name__} does not implement __System.IQueryInterface (C0239)"
        )
    return source if isinstance(source, target) else None


def query_pointer(source: Any) -> Pointer[Any]:
    """``__QUERYPOINTER(itfSource, pDest)``: a pointer to the FB instance behind an interface.

    ST returns an untyped pointer; here it carries the instance's dynamic type,
    and a null source gives a null pointer.
    """
    if source is None or isinstance(source, NullInterface):
        return Pointer(0, None)
    if not isinstance(source, IQueryInterface):
        raise DefinitionError(
            f"__QUERYPOINTER: {type(source).__name__} does not implement __System.IQueryInterface (C0239)"
        )
    return Pointer(handle_of(source), class_info(type(source)))
