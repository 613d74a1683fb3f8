"""The ADS symbol table of a runtime: TwinCAT symbol names, types, sizes and addresses, read from the class layouts.

Every program instance and global variable list is one block of the PLC's
data area (index group ``0x4040``), laid one after the other; a variable's
index offset is its block's base plus its offset in the block, so a read by
index group / offset and a read by name see the same bytes. Names are the
TwinCAT symbol paths ``MAIN.fbStation.nBottles``, ``GVL_IO.bStart``,
``MAIN.aLevels[2]``, matched case-insensitively as in ST.

Who may write what follows the OPC UA server: a program's VAR_INPUTs and
every GVL variable (and the members of a STRUCT among them); the members of
an FB instance only when named in ``writable``; a CONSTANT never.
"""

from __future__ import annotations

import bisect
import ctypes
import dataclasses
import fnmatch
import re
import struct
from collections.abc import Iterable, Iterator
from typing import Any

from iecoop.exceptions import AccessError
from iecoop.gvl import global_lists
from iecoop.memory.layout import ClassLayout, FieldRecord
from iecoop.memory.typeinfo import AggregateInfo, ArrayInfo, ElementaryInfo, EnumInfo, StringInfo, TypeInfo
from iecoop.metadata import Kind, kind_of, layout_of, st_name
from iecoop.runtime import Runtime, Symbol
from iecoop.sections import SECTION_RULES, AtCall, Section, Storage
from iecoop.ads.protocol import AdsError, IndexGroup

__all__ = ["AdsSymbol", "Refused", "SymbolTable"]

#: ADS data type ids (``ADST_*``, Infosys: *ADS Datatypes*).
_ADST_SIGNED = {1: 16, 2: 2, 4: 3, 8: 20}
_ADST_UNSIGNED = {1: 17, 2: 18, 4: 19, 8: 21}
_ADST_REAL = {4: 4, 8: 5}
_ADST_STRING, _ADST_WSTRING, _ADST_BIT, _ADST_BIGTYPE = 30, 31, 33, 65
#: ADSSYMBOLFLAG_PERSISTENT, _READONLY (the entry's flags)
_FLAG_PERSISTENT, _FLAG_READONLY = 0x1, 0x10

_HIDDEN_SECTIONS = frozenset(
    s for s, rule in SECTION_RULES.items() if rule.at_call is AtCall.REINITIALISED or rule.storage is Storage.CALLER
)
_STEP = re.compile(r"\s*([A-Za-z_][A-Za-z0-9_]*)\s*((?:\[[^\]]*\]\s*)*)$")
_INDEX = re.compile(r"\[([^\]]*)\]")
_ENTRY = struct.Struct("<IIIIIIHHH")
#: Blocks start at multiples of this in the data area (the largest elementary alignment).
_ALIGN = 8


class Refused(Exception):
    """A request the PLC does not take: the ADS return code and why."""

    def __init__(self, code: AdsError, why: str) -> None:
        super().__init__(why)
        self.code = code


@dataclasses.dataclass(frozen=True, eq=False)
class AdsSymbol:
    """One variable as ADS shows it: name, type, size, address, and whether a client may write it."""

    name: str
    type_name: str
    ads_type: int
    info: TypeInfo
    root: int  # which block of the data area
    block_offset: int
    offset: int  # the index offset in PLC_DATA
    writable: bool
    persistent: bool = False
    comment: str = ""

    @property
    def size(self) -> int:
        return self.info.size

    @property
    def group(self) -> int:
        return int(IndexGroup.PLC_DATA)

    def entry(self) -> bytes:
        """The symbol's ``AdsSymbolEntry`` (the upload's and INFOBYNAMEEX's record)."""
        name, type_name, comment = (text.encode("latin-1", "replace") for text in (self.name, self.type_name, self.comment))
        flags = (_FLAG_PERSISTENT if self.persistent else 0) | (0 if self.writable else _FLAG_READONLY)
        body = name + b"\x00" + type_name + b"\x00" + comment + b"\x00"
        length = _ENTRY.size + len(body)
        return _ENTRY.pack(length, self.group, self.offset, self.size, self.ads_type, flags,
                           len(name), len(type_name), len(comment)) + body

    def decode(self, data: bytes, block: Any) -> list[tuple[Symbol, Any]]:
        """The stores a client's bytes make, each checked: Refused with the ADS code if the PLC cannot take them."""
        if not self.writable:
            raise Refused(AdsError.ACCESSDENIED, f"{self.name} is read-only for ADS clients")
        info = self.info
        if isinstance(info, StringInfo) and len(data) < self.size:
            data += bytes(self.size - len(data))  # a STRING written up to its terminator, as pyads writes one
        if len(data) != self.size:
            raise Refused(AdsError.INVALIDSIZE, f"{self.name} is {self.type_name} of {self.size} bytes, got {len(data)}")
        buffer = bytearray(data)
        stores = []
        for where, scalar, offset in _leaves(self.name, info, 0):
            symbol = Symbol(where, scalar, block, self.block_offset + offset)
            try:
                value = scalar.load(buffer, offset)
                symbol.check(value)
            except (AccessError, ValueError, TypeError) as exc:
                raise Refused(AdsError.INVALIDDATA, str(exc)) from None
            stores.append((symbol, value))
        return stores


    def leaves(self, block: Any) -> list[Symbol]:
        """The elementary variables this symbol is made of (itself, an ARRAY's elements, a STRUCT's members)."""
        if not self.writable:
            raise Refused(AdsError.ACCESSDENIED, f"{self.name} is read-only for ADS clients")
        return [Symbol(where, scalar, block, self.block_offset + offset)
                for where, scalar, offset in _leaves(self.name, self.info, 0)]


def _leaves(name: str, info: TypeInfo, offset: int) -> Iterator[tuple[str, ElementaryInfo | StringInfo | EnumInfo, int]]:
    """The elementary variables a write of ``info`` at ``offset`` stores: itself, an ARRAY's elements, a STRUCT's members.

    Refused(ACCESSDENIED) for what a client cannot write whole: an FB instance, a UNION (its members share
    bytes), an address (POINTER, REFERENCE, interface), a CONSTANT member.
    """
    if isinstance(info, (ElementaryInfo, StringInfo, EnumInfo)):
        yield name, info, offset
    elif isinstance(info, ArrayInfo):
        for index in range(info.count):
            label = ",".join(map(str, _indices(info, index)))
            yield from _leaves(f"{name}[{label}]", info.elem, offset + index * info.elem.size)
    elif isinstance(info, AggregateInfo) and kind_of(info.cls) is Kind.STRUCT:
        layout = _layout_of(info)
        assert layout is not None
        for record in layout.fields:
            if record.spec.constant:
                raise Refused(AdsError.ACCESSDENIED, f"{name}.{record.st_name} is a CONSTANT: write the others one by one")
            yield from _leaves(f"{name}.{record.st_name}", record.info, offset + record.offset)
    else:
        raise Refused(AdsError.ACCESSDENIED, f"{name} is {_type_name(info)}: write its members one by one")


def _ads_type(info: TypeInfo) -> int:
    scalar = info.elem if isinstance(info, ArrayInfo) else info
    if isinstance(scalar, StringInfo):
        return _ADST_WSTRING if scalar.record.name == "WSTRING" else _ADST_STRING
    record = scalar.base if isinstance(scalar, EnumInfo) else scalar.record if isinstance(scalar, ElementaryInfo) else None
    if record is None:
        return _ADST_BIGTYPE
    if record.kind == "bool":
        return _ADST_BIT
    if record.kind == "real":
        return _ADST_REAL[record.size]
    return (_ADST_SIGNED if record.kind == "signed" else _ADST_UNSIGNED)[record.size]


def _type_name(info: TypeInfo) -> str:
    """The type as TwinCAT's symbol table writes it: ``INT``, ``STRING(80)``, ``ARRAY [1..5] OF INT``, ``FB_Station``."""
    if isinstance(info, ArrayInfo):
        dims = ",".join(f"{lo}..{hi}" for lo, hi in info.bounds)
        return f"ARRAY [{dims}] OF {_type_name(info.elem)}"
    if isinstance(info, AggregateInfo):
        return st_name(info.cls)
    if isinstance(info, EnumInfo):
        return st_name(info.enum_cls) if kind_of(info.enum_cls) is Kind.ENUM else info.name
    return info.name


def _shown(info: TypeInfo) -> bool:
    """Whether ADS shows a variable of this type (addresses, references and interfaces it does not)."""
    scalar = info.elem if isinstance(info, ArrayInfo) else info
    return isinstance(scalar, (ElementaryInfo, StringInfo, EnumInfo, AggregateInfo))


@dataclasses.dataclass(frozen=True)
class _Root:
    name: str
    block: Any
    base: int
    program: bool


class SymbolTable:
    """The symbols of ``runtime``'s programs and of every global variable list, by name and by address."""

    def __init__(self, runtime: Runtime, writable: Iterable[str] = (), online: bool = False) -> None:
        self._patterns = list(writable)
        self._online = online
        found: list[tuple[str, Any, bool]] = []
        for task in runtime.tasks:
            for path, program in task.programs:
                found.append((path[len(task.name) + 1 :], program, True))
        found += [(name, block, False) for name, block in global_lists().items()]
        self.roots: list[_Root] = []
        base = 0
        for name, block, program in found:
            self.roots.append(_Root(name, block, base, program))
            base += -(-ctypes.sizeof(block) // _ALIGN) * _ALIGN
        self.area_size = base
        self._bases = [root.base for root in self.roots]
        self._by_root = {root.name.casefold(): index for index, root in enumerate(self.roots)}
        self._cache: dict[str, AdsSymbol] = {}
        self.top = [symbol for index in range(len(self.roots)) for symbol in self._top(index)]
        self._upload = b"".join(symbol.entry() for symbol in self.top)
        matched = {pattern for pattern in self._patterns if any(self._named(s.name, pattern) for s in self._walk_all())}
        for pattern in self._patterns:
            if pattern not in matched:
                raise ValueError(f"AdsServer: writable pattern {pattern!r} matches no variable of the runtime")

    @staticmethod
    def _named(name: str, pattern: str) -> bool:
        return fnmatch.fnmatchcase(name.casefold(), pattern.casefold())

    # -- by name -----------------------------------------------------------------

    def find(self, name: str) -> AdsSymbol:
        """The symbol ``name`` names; Refused(SYMBOLNOTFOUND) naming the part that does not resolve."""
        key = name.strip().rstrip("\x00").casefold()
        found = self._cache.get(key)
        if found is None:
            found = self._resolve(name.strip().rstrip("\x00"))
            if len(self._cache) < 100_000:
                self._cache[key] = found
        return found

    def _resolve(self, name: str) -> AdsSymbol:
        parts = name.split(".")
        index = self._by_root.get(parts[0].casefold())
        if index is None or len(parts) < 2:
            known = ", ".join(root.name for root in self.roots[:12]) or "none"
            raise Refused(AdsError.SYMBOLNOTFOUND, f"{name}: no program or GVL named {parts[0]!r} (known: {known})"
                          if index is None else f"{name}: names a program or GVL, not a variable")
        root = self.roots[index]
        layout = _layout(root.block)
        shown = [root.name]
        writable = not root.program
        constant = False
        info: TypeInfo | None = None
        offset = 0
        for depth, part in enumerate(parts[1:]):
            match = _STEP.match(part)
            if match is None or layout is None:
                raise Refused(AdsError.SYMBOLNOTFOUND, f"{name}: {'.'.join(shown)} has no member {part!r}")
            record = _field(layout, match[1])
            if record is None or record.section in _HIDDEN_SECTIONS or not _shown(record.info):
                raise Refused(AdsError.SYMBOLNOTFOUND, f"{name}: {'.'.join(shown)} has no member {match[1]!r}")
            writable = self._step_writable(writable, info, record, root.program and depth == 0)
            constant = constant or record.spec.constant
            info, offset = record.info, offset + record.offset
            label = record.st_name
            for text in _INDEX.findall(match[2]):
                if not isinstance(info, ArrayInfo):
                    raise Refused(AdsError.SYMBOLNOTFOUND, f"{name}: {label} is {info.name}, not an ARRAY")
                position = _element(info, text, name)
                offset += position * info.elem.size
                label += f"[{text.replace(' ', '')}]"
                info = info.elem
            shown.append(label)
            layout = _layout_of(info)
        assert info is not None
        return self._symbol(".".join(shown), info, index, offset, writable, constant)

    def _step_writable(self, writable: bool, parent: TypeInfo | None, record: FieldRecord, program_field: bool) -> bool:
        if record.spec.constant:
            return False
        if program_field:
            return record.section is Section.VAR_INPUT
        if isinstance(parent, ArrayInfo):
            parent = parent.elem
        if isinstance(parent, AggregateInfo) and kind_of(parent.cls) not in (Kind.STRUCT, Kind.UNION):
            return False  # an FB instance's members are the FB's own
        return writable

    def _symbol(self, name: str, info: TypeInfo, index: int, offset: int, writable: bool, constant: bool,
                persistent: bool = False) -> AdsSymbol:
        named = any(self._named(name, pattern) for pattern in self._patterns)
        return AdsSymbol(name, _type_name(info), _ads_type(info), info, index, offset, self.roots[index].base + offset,
                         (writable or named or self._online) and not constant, persistent)

    # -- the upload ----------------------------------------------------------------

    def _top(self, index: int) -> Iterator[AdsSymbol]:
        root = self.roots[index]
        layout = _layout(root.block)
        for record in layout.fields if layout is not None else ():
            if record.section in _HIDDEN_SECTIONS or not _shown(record.info):
                continue
            writable = self._step_writable(not root.program, None, record, root.program)
            persistent = record.spec.persistent or record.spec.retain
            yield self._symbol(f"{root.name}.{record.st_name}", record.info, index, record.offset, writable,
                               record.spec.constant, persistent)

    def _walk_all(self) -> Iterator[AdsSymbol]:
        """Every top-level symbol and every member under it (array elements not expanded)."""
        stack = list(self.top)
        while stack:
            symbol = stack.pop()
            yield symbol
            info = symbol.info.elem if isinstance(symbol.info, ArrayInfo) else symbol.info
            layout = _layout_of(info)
            if layout is not None and not isinstance(symbol.info, ArrayInfo):
                stack += [self.find(f"{symbol.name}.{r.st_name}") for r in layout.fields
                          if r.section not in _HIDDEN_SECTIONS and _shown(r.info)]

    def upload(self) -> bytes:
        """The symbol upload (SYM_UPLOAD): every top-level variable's entry."""
        return self._upload

    # -- by address ----------------------------------------------------------------

    def locate(self, offset: int, size: int) -> tuple[int, int]:
        """The block holding ``size`` bytes at data-area ``offset`` and the offset in it; Refused if none does."""
        index = bisect.bisect_right(self._bases, offset) - 1
        if index < 0 or size < 0:
            raise Refused(AdsError.INVALIDOFFSET, f"no variable at index offset {offset:#x}")
        root = self.roots[index]
        inner = offset - root.base
        block_size = ctypes.sizeof(root.block)
        if inner >= block_size and size:
            raise Refused(AdsError.INVALIDOFFSET, f"no variable at index offset {offset:#x}")
        if inner + size > block_size:
            raise Refused(AdsError.INVALIDSIZE, f"{size} bytes at {offset:#x} run past the end of {root.name}")
        return index, inner

    def at(self, offset: int, size: int) -> AdsSymbol:
        """The variable starting at data-area ``offset`` that is ``size`` bytes long (a write by address)."""
        index, inner = self.locate(offset, size)
        root = self.roots[index]
        layout = _layout(root.block)
        parts = [root.name]
        position = 0
        while layout is not None:
            record = next((r for r in layout.fields if r.offset <= inner - position < r.offset + r.size), None)
            if record is None or record.section in _HIDDEN_SECTIONS or not _shown(record.info):
                break
            position += record.offset
            parts.append(record.st_name)
            if position == inner and record.size == size:
                return self.find(".".join(parts))
            info = record.info
            if isinstance(info, ArrayInfo):
                element = (inner - position) // info.elem.size
                parts[-1] += "[" + ",".join(map(str, _indices(info, element))) + "]"
                position += element * info.elem.size
                if position == inner and info.elem.size == size:
                    return self.find(".".join(parts))
                info = info.elem
            layout = _layout_of(info)
        raise Refused(AdsError.INVALIDACCESS, f"{size} bytes at index offset {offset:#x} are no one variable of {root.name}")


def _layout(block: Any) -> ClassLayout | None:
    return layout_of(type(block))


def _layout_of(info: TypeInfo) -> ClassLayout | None:
    return layout_of(info.cls) if isinstance(info, AggregateInfo) else None


def _field(layout: ClassLayout, name: str) -> FieldRecord | None:
    folded = name.casefold()
    return next((r for r in layout.fields if r.st_name.casefold() == folded or r.name.casefold() == folded), None)


def _element(info: ArrayInfo, index: str, path: str) -> int:
    """The position of ``[index]`` in the array's storage (row-major), bounds checked."""
    try:
        numbers = [int(text) for text in index.split(",")]
    except ValueError:
        raise Refused(AdsError.SYMBOLNOTFOUND, f"{path}: the index [{index}] is not a list of integers") from None
    if len(numbers) != len(info.bounds):
        raise Refused(AdsError.SYMBOLNOTFOUND, f"{path}: {info.name} takes {len(info.bounds)} indices, got [{index}]")
    position = 0
    for number, (low, high) in zip(numbers, info.bounds):
        if not low <= number <= high:
            raise Refused(AdsError.SYMBOLNOTFOUND, f"{path}: index {number} is outside the bounds {low}..{high} of {info.name}")
        position = position * (high - low + 1) + number - low
    return position


def _indices(info: ArrayInfo, position: int) -> list[int]:
    """The ``[i, j]`` of the element at ``position`` (row-major)."""
    numbers = []
    for low, high in reversed(info.bounds):
        span = high - low + 1
        numbers.append(low + position % span)
        position //= span
    return numbers[::-1]
