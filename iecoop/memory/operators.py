"""Memory operators: ADR, SIZEOF, MEMCPY / MEMSET / MEMCMP, REF=, __ISVALIDREF, __VARINFO.

Every address is checked: a null pointer, an address outside its block or
into deleted memory raises PlcException RTSEXCPT_ACCESS_VIOLATION.

>>> from iecoop import INT, REAL, Struct, adr, sizeof, memcpy
>>> class Point(Struct):
...     x: REAL = 0.0
...     y: REAL = 0.0
>>> a, b = Point(x=1.0, y=2.0), Point()
>>> memcpy(adr(b), adr(a), sizeof(Point))
8
>>> b
Point(x=1.0, y=2.0)
"""

from __future__ import annotations

import ctypes
import dataclasses
import enum
import typing
from collections.abc import Callable
from typing import Any, TypeVar, overload

from iecoop.exceptions import DefinitionError
from iecoop.memory._aggregates import AggregateInfo, ArrayInfo
from iecoop.memory._handles import (
    access_violation,
    allocation_for_handle,
    allocation_of,
    handle_of,
    hold,
    resolve,
    table_lock,
    target_root,
)
from iecoop.memory._infos import ElementaryInfo, EnumInfo, StringInfo, TypeInfo
from iecoop.memory._resolve import class_info, resolve_type
from iecoop.memory.interface_references import InterfaceInfo
from iecoop.memory.pointers import Pointer, PointerInfo
from iecoop.memory.references import ReferenceInfo
from iecoop.memory.layout import BlockArgument, ClassLayout, FieldRecord, LateInitial
from iecoop.metadata import Kind, kind_of

__all__ = [
    "TYPE_CLASS",
    "VarInfo",
    "adr",
    "adr_of",
    "is_valid_ref",
    "memcmp",
    "memcpy",
    "memset",
    "ref_assign",
    "sibling",
    "sizeof",
    "type_info_of",
    "var_info",
]

_T = TypeVar("_T")


def _layout(obj: Any, op: str) -> ClassLayout:
    layout = getattr(type(obj), "_iec_layout_", None)
    if layout is None:
        raise TypeError(f"{op} needs a struct, union, array or POU instance, got {type(obj).__name__}")
    return typing.cast(ClassLayout, layout)


def _record(obj: Any, field: str, op: str) -> FieldRecord:
    record = _layout(obj, op).by_name.get(field)
    if record is None:
        raise AttributeError(f"{op}: {type(obj).__name__} has no variable {field!r}")
    return record


def _class_record(cls: type, field: str, op: str) -> FieldRecord:
    """The field record of a class (``SIZEOF(ST_Recipe.nSteps)`` needs no instance)."""
    layout = getattr(cls, "_iec_layout_", None)
    if not isinstance(layout, ClassLayout):
        raise TypeError(f"{op}: {cls.__name__} is not a struct, union or POU class with a layout")
    record = layout.by_name.get(field)
    if record is None:
        raise AttributeError(f"{op}: {cls.__name__} has no variable {field!r}")
    return record


def type_info_of(obj: Any) -> TypeInfo:
    """The TypeInfo of an instance (struct, union, POU or array)."""
    info = getattr(type(obj), "_iec_info_", None)
    if isinstance(info, TypeInfo):
        return info
    found = class_info(type(obj))
    if found is None and kind_of(type(obj)) is Kind.PROGRAM and getattr(type(obj), "_iec_layout_", None):
        # ADR(PRG_Main): a program instance is a memory block too (it is never a member's type).
        found = AggregateInfo(type(obj))
    if found is None:
        raise TypeError(f"{type(obj).__name__} is not an IEC data instance")
    return found


@overload
def adr(obj: Any) -> Pointer[Any]: ...


@overload
def adr(obj: Any, member: str | int | tuple[int, ...], index: int | tuple[int, ...] | None = None) -> Pointer[Any]: ...


def adr(obj: Any, member: str | int | tuple[int, ...] | None = None, index: int | tuple[int, ...] | None = None) -> Pointer[Any]:
    """``ADR(x)``: a typed pointer to an instance, one of its variables, or an array element.

    ``adr(motor)`` is ``ADR(motor)``, ``adr(motor, "speed")`` is
    ``ADR(motor.speed)``, ``adr(values, 3)`` is ``ADR(values[3])`` and
    ``adr(self, "data", 3)`` is ``ADR(data[3])``. For a REFERENCE TO or
    VAR_IN_OUT variable it is the address of what the reference designates.
    """
    if member is None:
        return _pointer_into(obj, 0, type_info_of(obj))
    if isinstance(member, str):
        record = _record(obj, member, "ADR")
        if isinstance(record.info, ReferenceInfo):
            handle = record.raw.__get__(obj)
            target: TypeInfo = record.info.target
            if index is not None:
                array = target.load_handle(handle, record.where)
                return adr(array, index)
            return Pointer(handle, target, keep=target_root(handle))
        if index is not None:
            return adr(record.raw.__get__(obj), index)
        return _pointer_into(obj, record.offset, record.info)
    info = getattr(type(obj), "_iec_info_", None)
    if not isinstance(info, ArrayInfo):
        raise TypeError(f"ADR with an index needs an ARRAY, got {type(obj).__name__}")
    position = obj._flat(member)
    return _pointer_into(obj, position * info.elem.size, info.elem)


def adr_of(member: str, index: int | tuple[int, ...] | None = None) -> Any:
    """The initial value ``ADR(member)`` of a POINTER, or ``REF= member`` of a REFERENCE, declared beside it.

    ST: ``pValue : POINTER TO INT := ADR(nValue);`` is
    ``value_ptr: POINTER_TO[INT] = VAR(adr_of("value"))``;
    ``adr_of("values", 3)`` is ``ADR(aValues[3])``. Each instance binds it to
    its own member when it is created, after the other initial values and
    before FB_init. The member must exist and have the pointed-to type.

    >>> from iecoop import INT, POINTER_TO, REFERENCE_TO, Struct, VAR
    >>> class Counter(Struct):
    ...     value: INT = 5
    ...     value_ptr: POINTER_TO[INT] = VAR(adr_of("value"))
    ...     value_ref: REFERENCE_TO[INT] = VAR(adr_of("value"))
    >>> counter = Counter()
    >>> counter.value_ptr.deref, counter.value_ref
    (5, 5)
    """
    return AddressOf(member, index)


class _NamedMember(BlockArgument):
    """A variable of the block being declared, by name (and index into it): what ``adr_of`` and ``sibling`` say."""

    __slots__ = ("member", "index")
    #: the function that makes it, in messages and its repr
    word: typing.ClassVar[str] = ""

    def __init__(self, member: str, index: int | tuple[int, ...] | None = None) -> None:
        if not isinstance(member, str):
            raise TypeError(f"{self.word}: the member is a variable name (a str), got {member!r}")
        self.member = member
        self.index = index

    def __repr__(self) -> str:
        return f"{self.word}({self.member!r})" if self.index is None else f"{self.word}({self.member!r}, {self.index!r})"

    def check_argument(self, record: FieldRecord, layout: ClassLayout) -> None:
        """Refuse, at definition, an FB_init argument of ``record`` naming a variable the block does not declare
        (or an index into one that is no ARRAY, or the member itself)."""
        target = layout.by_name.get(self.member)
        if target is None:
            raise DefinitionError(f"{record.where}: FB_init argument {self!r} names no variable of the block")
        if self.index is not None and not isinstance(target.info, ArrayInfo):
            raise DefinitionError(
                f"{record.where}: FB_init argument {self!r} needs an ARRAY, {self.member} is {target.info.name}"
            )
        if self.member == record.name:
            raise DefinitionError(f"{record.where}: FB_init argument {self!r} names the member it initialises")


class AddressOf(LateInitial, _NamedMember):
    """The initial value ``ADR(x)`` / ``REF= x`` of a POINTER or REFERENCE: a sibling variable (see ``adr_of``)."""

    __slots__ = ()
    word = "adr_of"

    def check(self, record: FieldRecord, layout: ClassLayout) -> None:
        """Refuse, at definition, a member that is not there or whose type the pointer does not point to."""
        target = layout.by_name.get(self.member)
        if target is None:
            raise DefinitionError(f"{record.where}: adr_of({self.member!r}) names no variable of {record.owner}")
        assert isinstance(record.info, (PointerInfo, ReferenceInfo))
        points_to = record.info.target
        designated = target.info
        if self.index is not None:
            if not isinstance(designated, ArrayInfo):
                raise DefinitionError(f"{record.where}: adr_of({self.member!r}, {self.index!r}) needs an ARRAY, {self.member} is {designated.name}")
            designated = designated.elem
        if isinstance(designated, ReferenceInfo):
            designated = designated.target
        if points_to is not None and points_to.signature != designated.signature:
            raise DefinitionError(
                f"{record.where}: {record.info.name} cannot be initialised with the address of {self.member} "
                f"({designated.name}): the types must match"
            )

    def op(self, record: FieldRecord) -> Callable[[Any], None]:
        member, index, field, offset, where = self.member, self.index, record.name, record.offset, record.where
        if isinstance(record.info, ReferenceInfo):
            return lambda obj: ref_assign(obj, field, adr(obj, member, index))
        store = record.info.store
        return lambda obj: store(obj, offset, adr(obj, member, index), where)

    def resolve(self, obj: Any) -> Any:
        """The argument passed to a member's FB_init: ``ADR(member)`` of ``obj``, the instance being made."""
        return adr(obj, self.member, self.index)


def sibling(member: str, index: int | tuple[int, ...] | None = None) -> Any:
    """An FB_init argument naming a variable declared beside the block that takes it.

    ST: ``fbUser : FB_User(fbCounter);`` (an interface, ``REFERENCE TO`` or
    value input of FB_User's FB_init given the variable ``fbCounter`` of the
    same block) is ``user: FB_User = VAR(fb_init={"counter": sibling("counter")})``;
    ``sibling("values", 2)`` is ``aValues[2]``. Each instance passes its own
    variable, read when the member's FB_init runs (members in declaration
    order, after every initial value); ``adr_of("counter")`` passes
    ``ADR(fbCounter)`` to a ``POINTER TO`` input.

    >>> from iecoop import BOOL, INT, REFERENCE_TO, VAR, VAR_OUTPUT, FunctionBlock, Program, ref_assign
    >>> class Counter(FunctionBlock):
    ...     count: INT = VAR_OUTPUT(0)
    ...     def body(self) -> None:
    ...         self.count = self.count + 1
    >>> class User(FunctionBlock):
    ...     counter: REFERENCE_TO[Counter] = VAR()
    ...     def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, counter: REFERENCE_TO[Counter]) -> BOOL:
    ...         ref_assign(self, "counter", adr(counter))
    ...         return True
    ...     def body(self) -> None:
    ...         self.counter()
    >>> class Cell(Program):
    ...     counter: Counter = VAR()
    ...     user: User = VAR(fb_init={"counter": sibling("counter")})
    ...     def body(self) -> None:
    ...         self.user()
    >>> cell = Cell()
    >>> cell(); cell()
    >>> cell.counter.count
    2
    """
    return Sibling(member, index)


class Sibling(_NamedMember):
    """An FB_init argument that is a variable of the block declaring the member (see ``sibling``)."""

    __slots__ = ()
    word = "sibling"

    def resolve(self, obj: Any) -> Any:
        """The argument passed to a member's FB_init: the variable of ``obj``, the instance being made."""
        value = getattr(obj, self.member)
        return value if self.index is None else value[self.index]


def _pointer_into(obj: Any, extra: int, target: TypeInfo) -> Pointer[Any]:
    # The pointer holds the block, so ADR of an object only Python refers to stays valid.
    alloc, offset = allocation_of(obj)
    return Pointer((alloc.id << 32) | (offset + extra), target, keep=alloc.ref())


def sizeof(x: Any, member: str | None = None) -> int:
    """``SIZEOF(x)``: bytes of a type (``sizeof(INT)``, ``sizeof(Recipe)``) or of a variable.

    ``sizeof(STRING)`` is 81 (STRING(80) plus its terminator). For a declared
    variable of non-default length use ``sizeof(obj, "name")`` or, without an
    instance, ``sizeof(Recipe, "name")``.
    """
    if member is not None:
        if isinstance(x, type):
            return _class_record(x, member, "SIZEOF").info.size
        return _record(x, member, "SIZEOF").info.size
    if isinstance(x, Pointer):
        return 8
    if isinstance(x, ctypes._SimpleCData) or isinstance(x, (ctypes.Structure, ctypes.Union, ctypes.Array)):
        return ctypes.sizeof(x)
    if isinstance(x, type) and issubclass(x, (ctypes.Structure, ctypes.Union, ctypes.Array)):
        if getattr(x, "_iec_layout_", "absent") is None:
            raise TypeError(f"{x.__name__} is a base class without a layout")
        return ctypes.sizeof(x)
    return resolve_type(x, "SIZEOF").size


_stored_handle = typing.cast(Any, Pointer).__dict__["_handle"].__get__


def _handle(pointer: Pointer[Any], what: str) -> int:
    # Read through the slot itself: no code of a Pointer subclass runs between the checks and the C call.
    if not isinstance(pointer, Pointer):
        raise TypeError(f"{what} needs a pointer from adr(...), got {type(pointer).__name__}")
    return int(_stored_handle(pointer))


def _count(n: int, what: str) -> int:
    if isinstance(n, bool) or not isinstance(n, int) or n < 0:
        raise TypeError(f"{what}: the byte count must be a non-negative integer, got {n!r}")
    return n


def _fill_byte(value: int) -> int:
    # ST's fillByte is a BYTE: a float, a BOOL or a wider number is a type error there, not a truncation.
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= 0xFF:
        raise TypeError(f"MEMSET: the fill value is a BYTE, an int 0..255; got {value!r} (nothing was written)")
    return int(value)


def memcpy(dest: Pointer[Any], src: Pointer[Any], n: int) -> int:
    """``MEMCPY(destAddr, srcAddr, n)``: copy n bytes, both ranges checked; returns n."""
    _count(n, "MEMCPY")
    target, source = _handle(dest, "MEMCPY destination"), _handle(src, "MEMCPY source")
    if n == 0:
        return 0
    # The roots stay referenced and the table locked until the copy ends: no thread can free
    # or delete either block between the check and the C call.
    with table_lock:
        target_block, target_offset = resolve(target, n, "MEMCPY destination")
        source_block, source_offset = resolve(source, n, "MEMCPY source")
        ctypes.memmove(
            ctypes.addressof(target_block) + target_offset, ctypes.addressof(source_block) + source_offset, n
        )
    return n


def memset(dest: Pointer[Any], value: int, n: int) -> int:
    """``MEMSET(destAddr, fillByte, n)``: fill n bytes with the BYTE ``value`` (0..255); returns n."""
    _count(n, "MEMSET")
    fill = _fill_byte(value)
    target = _handle(dest, "MEMSET destination")
    if n:
        with table_lock:
            block, offset = resolve(target, n, "MEMSET destination")
            ctypes.memset(ctypes.addressof(block) + offset, fill, n)
    return n


def memcmp(a: Pointer[Any], b: Pointer[Any], n: int) -> int:
    """``MEMCMP(pBuf1, pBuf2, n)``: 0 when equal, 1 when the first differing byte of a is greater, else -1."""
    _count(n, "MEMCMP")
    first, second = _handle(a, "MEMCMP first buffer"), _handle(b, "MEMCMP second buffer")
    if n == 0:
        return 0
    with table_lock:
        left_block, left_offset = resolve(first, n, "MEMCMP first buffer")
        right_block, right_offset = resolve(second, n, "MEMCMP second buffer")
        left = ctypes.string_at(ctypes.addressof(left_block) + left_offset, n)
        right = ctypes.string_at(ctypes.addressof(right_block) + right_offset, n)
    return (left > right) - (left < right)


def ref_assign(holder: Any, field: str, target: Any) -> None:
    """``holder.field REF= target``: bind a REFERENCE TO (or VAR_IN_OUT) to ``target``.

    ``target`` is a pointer from ``adr(...)``, a struct / FB instance, or None
    (``REF= 0``) to unbind.

    >>> from iecoop import INT, REFERENCE_TO, Struct, VAR, adr, ref_assign
    >>> class Counter(Struct):
    ...     value: INT = 5
    >>> class Holder(Struct):
    ...     r: REFERENCE_TO[INT] = VAR()
    >>> c, h = Counter(), Holder()
    >>> ref_assign(h, "r", adr(c, "value"))
    >>> h.r += 1
    >>> c.value
    6
    """
    record = _record(holder, field, "REF=")
    if not isinstance(record.info, ReferenceInfo):
        raise TypeError(f"REF=: {record.where} is {record.info.name}, not a REFERENCE TO")
    handle = record.info.bind_handle(target, record.where)
    record.raw.__set__(holder, handle)
    # A block holding a reference keeps its target alive, as Python does.
    kept = getattr(target, "_keep", None) if isinstance(target, Pointer) else None
    hold(holder, record.offset, (kept if kept is not None else target_root(handle)) if handle else None)


def is_valid_ref(holder: Any, field: str) -> bool:
    """``__ISVALIDREF(holder.field)``: TRUE when the reference is bound to live memory.

    A PLC only compares with 0; here a reference into deleted memory is
    reported as invalid too, since using it would be an access violation.
    """
    record = _record(holder, field, "__ISVALIDREF")
    if not isinstance(record.info, ReferenceInfo):
        raise TypeError(f"__ISVALIDREF works on REFERENCE TO only; {record.where} is {record.info.name}")
    handle = record.raw.__get__(holder)
    if handle == 0:
        return False
    alloc = allocation_for_handle(handle)
    return alloc is not None and alloc.ref() is not None and (handle & 0xFFFFFFFF) + record.info.target.size <= alloc.size


class TYPE_CLASS(enum.IntEnum):
    """``__SYSTEM.TYPE_CLASS`` (the CODESYS numbering)."""

    TYPE_BOOL = 0
    TYPE_BIT = 1
    TYPE_BYTE = 2
    TYPE_WORD = 3
    TYPE_DWORD = 4
    TYPE_LWORD = 5
    TYPE_SINT = 6
    TYPE_INT = 7
    TYPE_DINT = 8
    TYPE_LINT = 9
    TYPE_USINT = 10
    TYPE_UINT = 11
    TYPE_UDINT = 12
    TYPE_ULINT = 13
    TYPE_REAL = 14
    TYPE_LREAL = 15
    TYPE_STRING = 16
    TYPE_WSTRING = 17
    TYPE_TIME = 18
    TYPE_DATE = 19
    TYPE_DATEANDTIME = 20
    TYPE_TIMEOFDAY = 21
    TYPE_POINTER = 22
    TYPE_REFERENCE = 23
    TYPE_SUBRANGE = 24
    TYPE_ENUM = 25
    TYPE_ARRAY = 26
    TYPE_PARAMS = 27
    TYPE_USERDEF = 28
    TYPE_NONE = 29
    TYPE_ANY = 30
    TYPE_LTIME = 37
    TYPE_INTERFACE = 39


_CLASS_BY_NAME = {
    "DT": TYPE_CLASS.TYPE_DATEANDTIME,
    "TOD": TYPE_CLASS.TYPE_TIMEOFDAY,
}


def _type_class(info: TypeInfo) -> TYPE_CLASS:
    if isinstance(info, ElementaryInfo):
        name = info.record.name
        return _CLASS_BY_NAME.get(name) or TYPE_CLASS[f"TYPE_{name}"]
    if isinstance(info, StringInfo):
        return TYPE_CLASS[f"TYPE_{info.record.name}"]
    if isinstance(info, PointerInfo):
        return TYPE_CLASS.TYPE_POINTER
    if isinstance(info, ReferenceInfo):
        return TYPE_CLASS.TYPE_REFERENCE
    if isinstance(info, EnumInfo):
        return TYPE_CLASS.TYPE_ENUM
    if isinstance(info, ArrayInfo):
        return TYPE_CLASS.TYPE_ARRAY
    if isinstance(info, InterfaceInfo):
        return TYPE_CLASS.TYPE_INTERFACE
    return TYPE_CLASS.TYPE_USERDEF


@dataclasses.dataclass(frozen=True)
class VarInfo:
    """``__SYSTEM.VAR_INFO``: what ``__VARINFO(x)`` reports about a variable."""

    Symbol: str
    ByteAddress: int
    ByteOffset: int
    Area: int
    BitNr: int
    BitSize: int
    TypeClass: TYPE_CLASS
    TypeName: str
    NumElements: int
    ElemBitSize: int
    BaseTypeClass: TYPE_CLASS


def var_info(obj: Any, field: str) -> VarInfo:
    """``__VARINFO(obj.field)``: address, offset in the instance, size and type of a variable.

    >>> from iecoop import INT, LREAL, Struct, var_info
    >>> class Axis(Struct):
    ...     mode: INT = 0
    ...     position: LREAL = 0.0
    >>> info = var_info(Axis(), "position")
    >>> info.ByteOffset, info.BitSize, info.TypeName, info.TypeClass.name
    (8, 64, 'LREAL', 'TYPE_LREAL')
    """
    record = _record(obj, field, "__VARINFO")
    info = record.info
    elements, elem_bits, base_class = 1, info.size * 8, _type_class(info)
    if isinstance(info, ArrayInfo):
        elements, elem_bits, base_class = info.count, info.elem.size * 8, _type_class(info.elem)
    return VarInfo(
        Symbol=record.where,
        ByteAddress=handle_of(obj, record.offset),
        ByteOffset=record.offset,
        Area=-1,
        BitNr=-1,
        BitSize=info.size * 8,
        TypeClass=_type_class(info),
        TypeName=info.name,
        NumElements=elements,
        ElemBitSize=elem_bits,
        BaseTypeClass=base_class,
    )


