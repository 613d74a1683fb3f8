"""Online access by symbol name: read, write and force any variable of a running application.

A symbol path is the dotted name TwinCAT's ADS symbol table and online view
use, independent of the task: the program instance's name, then the members
(``MAIN.fbStation.nBottles``, ``MAIN.aLevels[2]``), or a GVL's name then its
variable (``GVL_IO.bStart``). Names match case-insensitively, as in ST. The
program instance's name is its class name (``Main`` answers to ``MAIN``); the
task's instance path (``PlcTask.Main.count``) is accepted as well.

Like TwinCAT's online write, the access rules that bind code do not apply:
inputs, outputs and internal variables of any block can be written. A
symbol takes only the values its type can hold; anything else is refused at
the call with an ``AccessError`` naming the path and the rule.

>>> from iecoop import INT, VAR, Program
>>> class Main(Program):
...     count: INT = VAR(0)
...     def body(self) -> None:
...         self.count += 1
>>> main = Main()
>>> symbol = resolve_symbol({"Main": main}, "MAIN.count")
>>> symbol.store(41); main.count
41
>>> symbol.store(70_000)
Traceback (most recent call last):
...
iecoop.exceptions.AccessError: MAIN.count: 70000 is outside the range of INT (-32768..32767)
"""

from __future__ import annotations

import dataclasses
import math
import re
import threading
from collections.abc import Iterable, Mapping
from typing import Any

from iecoop.exceptions import AccessError
from iecoop.gvl import all_global_lists, global_lists, namespace_of
from iecoop.memory.layout import ClassLayout, FieldRecord
from iecoop.metadata import layout_of
from iecoop.memory.typeinfo import AggregateInfo, ArrayInfo, ElementaryInfo, EnumInfo, StringInfo, TypeInfo

__all__ = ["OnlineTable", "Symbol", "resolve_symbol", "symbol_roots"]

#: The largest finite REAL (IEEE 754 single precision).
_REAL_MAX = 3.4028234663852886e38

# One step of a path: a name, then any number of ``[i]`` / ``[i, j]`` indices.
_STEP = re.compile(r"\s*([A-Za-z_][A-Za-z0-9_]*)\s*((?:\[[^\]]*\]\s*)*)$")
_INDEX = re.compile(r"\[([^\]]*)\]")


@dataclasses.dataclass(frozen=True, eq=False)
class Symbol:
    """One elementary variable found by path: where it lives and how its values are stored.

    ``store`` checks the value first (type and range) and raises
    ``AccessError`` naming the path, so a refused value never reaches the PLC;
    ``check`` is that check alone, to refuse a value at the call and store it
    later in the PLC's thread.
    """

    path: str
    info: TypeInfo
    block: Any
    offset: int

    def load(self) -> Any:
        """The variable's current value."""
        return self.info.load(self.block, self.offset)

    def check(self, value: Any) -> None:
        """Raise ``AccessError`` if the variable's type cannot hold ``value``."""
        try:
            self.info.validate(value, self.path)
        except (TypeError, ValueError) as exc:
            raise AccessError(str(exc)) from None
        info = self.info
        if isinstance(info, ElementaryInfo) and info.record.kind == "real":
            # A REAL stores a larger finite number as infinity: not the value that was written.
            if info.record.size == 4 and math.isfinite(value) and abs(value) > _REAL_MAX:
                raise AccessError(f"{self.path}: {value} is outside the range of {info.name}")
        elif isinstance(info, ElementaryInfo) and info.record.kind != "bool":
            low, high = info.record.low, info.record.high
            if low is not None and high is not None and not low <= value <= high:
                raise AccessError(f"{self.path}: {value} is outside the range of {info.name} ({low}..{high})")
        elif isinstance(info, StringInfo):
            # An assignment in code truncates; an online write that does not fit is refused, not cut.
            if "\x00" in value:
                raise AccessError(f"{self.path}: {info.name} cannot hold the NUL character (it ends a PLC string)")
            if len(value) > info.length:
                raise AccessError(f"{self.path}: {len(value)} characters do not fit {info.name}")
        elif isinstance(info, EnumInfo):
            values = {int(member) for member in info.enum_cls}
            if int(value) not in values:
                raise AccessError(f"{self.path}: {value} is no value of {info.name}")

    def store(self, value: Any) -> None:
        """Write ``value`` now (checked first): the online write, whatever the variable's section."""
        self.check(value)
        self.info.store(self.block, self.offset, value, self.path)


def _names(layout: ClassLayout) -> dict[str, FieldRecord]:
    return {record.name.casefold(): record for record in layout.fields}


def _root(roots: Mapping[str, Any], path: str, first: str) -> tuple[Any, int]:
    """The block a path starts at and how many dotted parts named it."""
    folded = {name.casefold(): block for name, block in roots.items()}
    parts = path.split(".")
    # The longest name that matches: an instance path ``PlcTask.Main`` is two parts.
    for count in range(len(parts), 0, -1):
        block = folded.get(".".join(parts[:count]).casefold())
        if block is not None:
            return block, count
    names = sorted(roots)
    known = ", ".join(names[:12]) + (f" and {len(names) - 12} more" if len(names) > 12 else "") or "none"
    raise AccessError(f"{path}: no program or GVL named {first!r} (known: {known})")


def symbol_roots(tasks: Iterable[Any]) -> dict[str, Any]:
    """Where a symbol path starts: each GVL by name, each task's program by name and by instance path."""
    tasks = list(tasks)
    roots: dict[str, Any] = dict(global_lists())
    # Of two lists of one name (two projects loaded in one process), the one of the programs' own project.
    spaces = {namespace_of(type(program).__module__) for task in tasks for _path, program in task.programs}
    for instance in all_global_lists():
        if namespace_of(type(instance).__module__) in spaces:
            roots[type(instance).__name__] = instance
    for task in tasks:
        for path, program in task.programs:
            roots[path[len(task.name) + 1 :]] = program
            roots[path] = program
    return roots


def resolve_symbol(roots: Mapping[str, Any], path: str) -> Symbol:
    """Find the elementary variable ``path`` names among ``roots`` (name -> program or GVL instance).

    Raises ``AccessError`` naming the path and the part that does not
    resolve; structured variables (an FB, a STRUCT, an ARRAY) are written
    member by member, and POINTER / REFERENCE / interface variables hold
    addresses, which are not written online.
    """
    if not isinstance(path, str) or not path.strip():
        raise AccessError(f"a symbol path is a dotted name such as 'MAIN.nCount', got {path!r}")
    parts = path.split(".")
    block, used = _root(roots, path, parts[0])
    layout = layout_of(type(block))
    owner = type(block).__name__
    info: TypeInfo | None = None
    offset = 0
    for part in parts[used:]:
        match = _STEP.match(part)
        if match is None:
            raise AccessError(f"{path}: {part!r} is not a member name (optionally indexed: aValues[2])")
        if layout is None:
            raise AccessError(f"{path}: {owner} is not a block or STRUCT, it has no member {match[1]!r}")
        record = _names(layout).get(match[1].casefold())
        if record is None:
            raise AccessError(f"{path}: {owner} has no member {match[1]!r}")
        info, offset = record.info, offset + record.offset
        for index in _INDEX.findall(match[2]):
            array = info
            if not isinstance(array, ArrayInfo):
                raise AccessError(f"{path}: {match[1]} is {array.name}, not an ARRAY; it takes no index")
            offset += _element(array, index, path) * array.elem.size
            info = array.elem
        layout = layout_of(info.cls) if isinstance(info, AggregateInfo) else None
        owner = info.name
    if info is None:
        raise AccessError(f"{path}: names a program or GVL, not a variable; add a member ('{path}.nCount')")
    if not isinstance(info, (ElementaryInfo, StringInfo, EnumInfo)):
        raise AccessError(f"{path}: is {info.name}; the online write and force take elementary variables "
                          f"(write a STRUCT, FB or ARRAY member by member)")
    return Symbol(path, info, block, offset)


def _element(info: ArrayInfo, index: str, path: str) -> int:
    """The position of ``[index]`` in the array's storage (row-major), bounds checked."""
    try:
        numbers = [int(text) for text in index.split(",")]
    except ValueError:
        raise AccessError(f"{path}: the index [{index}] is not a list of integers") from None
    if len(numbers) != len(info.bounds):
        raise AccessError(f"{path}: {info.name} takes {len(info.bounds)} indices, got [{index}]")
    position = 0
    for number, (low, high) in zip(numbers, info.bounds):
        if not low <= number <= high:
            raise AccessError(f"{path}: index {number} is outside the bounds {low}..{high} of {info.name}")
        position = position * (high - low + 1) + number - low
    return position


#: No value recorded (a force released before any cycle applied it).
_UNSET = object()


class OnlineTable:
    """A runtime's online writes waiting for the next cycle start, and its forced variables.

    Any thread adds and removes; the PLC's thread reads ``active`` once per
    cycle and, when it is set, ``take`` s what to store. Forces are keyed by
    location, so two spellings of one path are one force.
    """

    __slots__ = ("lock", "writes", "forces", "before", "forced_now", "active")

    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.writes: list[tuple[Symbol, Any]] = []
        self.forces: dict[tuple[int, int], tuple[Symbol, Any]] = {}
        #: Each forced variable's value before its first forced cycle: what a release with restore puts back.
        self.before: dict[tuple[int, int], Any] = {}
        #: The forces as a cycle stores them: replaced whole under the lock, read without it.
        self.forced_now: tuple[tuple[Symbol, Any], ...] = ()
        #: Writes are waiting or variables are forced: the one test a cycle makes.
        self.active = False

    def _changed(self) -> None:
        self.forced_now = tuple(self.forces.values())
        self.active = bool(self.writes or self.forced_now)

    def write(self, symbol: Symbol, value: Any) -> None:
        with self.lock:
            self.writes.append((symbol, value))
            self.active = True

    def force(self, symbol: Symbol, value: Any) -> None:
        key = (id(symbol.block), symbol.offset)
        with self.lock:
            previous = self.forces.get(key)
            # A force of an already forced variable keeps the path it was first forced by.
            self.forces[key] = (symbol if previous is None else previous[0], value)
            self._changed()

    def release(self, symbol: Symbol, restore: bool = False) -> None:
        key = (id(symbol.block), symbol.offset)
        with self.lock:
            found = self.forces.pop(key, None)
            if found is None:
                forced = ", ".join(path for path in self.forced()) or "none"
                raise AccessError(f"{symbol.path}: is not forced (forced: {forced})")
            self._restore(key, found[0], restore)
            self._changed()

    def release_all(self, restore: bool = False) -> None:
        with self.lock:
            for key, (symbol, _value) in self.forces.items():
                self._restore(key, symbol, restore)
            self.forces.clear()
            self._changed()

    def _restore(self, key: tuple[int, int], symbol: Symbol, restore: bool) -> None:
        # Under the lock: the value from before the force goes back with the next cycle start, as a write.
        before = self.before.pop(key, _UNSET)
        if restore and before is not _UNSET:
            self.writes.append((symbol, before))

    def forced(self) -> dict[str, Any]:
        return {symbol.path: value for symbol, value in self.forced_now}

    def is_forced(self, symbol: Symbol) -> bool:
        return (id(symbol.block), symbol.offset) in self.forces

    def apply(self) -> None:
        """At a cycle start: the writes queued since the last one, in order, then the forces."""
        with self.lock:
            writes, self.writes = self.writes, []
            self.active = bool(self.forced_now)
            forced, before = self.forced_now, self.before
            for symbol, _value in forced:
                key = (id(symbol.block), symbol.offset)
                if key not in before and key in self.forces:
                    before[key] = symbol.load()
        for symbol, value in (*writes, *forced):
            symbol.info.store(symbol.block, symbol.offset, value, symbol.path)

    def hold(self) -> None:
        """After the cycle's code: the forces again, so readers between cycles see them."""
        for symbol, value in self.forced_now:
            symbol.info.store(symbol.block, symbol.offset, value, symbol.path)
