"""OPC UA server for a running Runtime: HMIs, SCADA and test scripts connect to the PLC.

TwinCAT 3 (TF6100) and CODESYS expose PLC variables through an OPC UA server
in the controller; ``OpcUaServer`` does the same for an iecoop ``Runtime``,
with the asyncua library (install the extra: ``pip install "iecoop[opcua]"``)::

    with OpcUaServer(rt, endpoint="opc.tcp://127.0.0.1:4840"):
        rt.run(duration=T("1h"), realtime=True)     # the PLC runs in this thread

The server runs its own thread and event loop. After every cycle the PLC
thread copies the exposed blocks in one go (one consistent image, never half
a cycle) and hands the copy to the server, which publishes the values that
changed. A client write is checked at once (a refusal stores nothing), queued,
and applied at the start of the next cycle, before the tasks run.

The address space, the type table and the write rules are in docs/opcua.md.
"""

from __future__ import annotations

import asyncio
import collections
import contextlib
import ctypes
import dataclasses
import datetime
import enum
import fnmatch
import hmac
import logging
import operator
import os
import socket
import threading
import time
import types
import typing
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from types import TracebackType
from typing import Any
from urllib.parse import urlsplit

try:
    from asyncua import Server, ua
    from asyncua.crypto.permission_rules import User, UserRole
    from asyncua.server.address_space import AttributeService, NodeManagementService
except ImportError as exc:  # pragma: no cover - exercised without the extra installed
    raise ImportError(
        'iecoop.opcua needs the asyncua library: install the extra with pip install "iecoop[opcua]"'
    ) from exc

from iecoop.exceptions import AccessError
from iecoop.gvl import GlobalVariables, global_lists
from iecoop.memory.typeinfo import AggregateInfo, ArrayInfo, ElementaryInfo, EnumInfo, StringInfo, TypeInfo
from iecoop.runtime import Runtime, Symbol
from iecoop.sections import SECTION_RULES, AtCall, Section, Storage
from iecoop.metadata import Kind, fields_of, iec_class, kind_of, layout_of, st_name

__all__ = ["NAMESPACE", "OpcUaServer"]

#: The namespace URI of every node iecoop adds.
NAMESPACE = "urn:iecoop"

_log = logging.getLogger(__name__)
_RAW = operator.attrgetter("raw")

_VT = ua.VariantType
#: Seconds between two looks for a fault that stopped the PLC mid-cycle.
_FAULT_POLL = 0.05
_INTEGERS = frozenset({_VT.SByte, _VT.Byte, _VT.Int16, _VT.UInt16, _VT.Int32, _VT.UInt32, _VT.Int64, _VT.UInt64})
_NUMBERS = _INTEGERS | {_VT.Float, _VT.Double}
_SIGNED = {1: _VT.SByte, 2: _VT.Int16, 4: _VT.Int32, 8: _VT.Int64}
_UNSIGNED = {1: _VT.Byte, 2: _VT.UInt16, 4: _VT.UInt32, 8: _VT.UInt64}
_EPOCH = datetime.datetime(1970, 1, 1, tzinfo=datetime.timezone.utc)
_REAL_MAX = 3.4028234663852886e38
_INT64_MAX = 2**63 - 1
#: Sections that are no value of the instance between cycles (VAR_TEMP) or a reference to another one (VAR_IN_OUT).
_HIDDEN_SECTIONS = frozenset(
    s for s, rule in SECTION_RULES.items() if rule.at_call is AtCall.REINITIALISED or rule.storage is Storage.CALLER
)
#: The images the server may fall behind by before it drops the oldest (a client far too slow for the PLC).
_BACKLOG = 10_000


class _Refused(Exception):
    """A client write the PLC does not take: the OPC UA status code and why."""

    def __init__(self, code: int, why: str) -> None:
        super().__init__(why)
        self.code = code


def _out_of_range(why: str) -> _Refused:
    return _Refused(ua.StatusCodes.BadOutOfRange, why)


@dataclasses.dataclass(frozen=True, eq=False)
class _Codec:
    """How one scalar IEC type appears in OPC UA: its VariantType, how a PLC value reads and a client value is taken."""

    vtype: ua.VariantType
    accepts: frozenset[ua.VariantType]
    read: Callable[[Any], Any]
    take: Callable[[Any], Any]  # a client's value -> the PLC value; raises _Refused(BadOutOfRange)


def _int_range(low: int, high: int, name: str) -> Callable[[Any], Any]:
    def take(value: Any) -> Any:
        if not low <= value <= high:
            raise _out_of_range(f"{value} is outside the range of {name} ({low}..{high})")
        return int(value)

    return take


def _real(name: str, single: bool) -> Callable[[Any], Any]:
    def take(value: Any) -> Any:
        number = float(value)
        if single and abs(number) > _REAL_MAX and number not in (float("inf"), float("-inf")):
            raise _out_of_range(f"{value} is outside the range of {name}")
        return number

    return take


def _date(name: str, resolution: int) -> Callable[[Any], Any]:
    def take(value: Any) -> Any:
        moment = value if value.tzinfo is not None else value.replace(tzinfo=datetime.timezone.utc)
        seconds = int((moment - _EPOCH).total_seconds() // 1)
        seconds -= seconds % resolution
        if not 0 <= seconds <= 0xFFFF_FFFF:
            raise _out_of_range(f"{value} is outside the range of {name} (1970-01-01 .. 2106-02-07)")
        return seconds

    return take


def _read_date(seconds: Any) -> Any:
    return _EPOCH + datetime.timedelta(seconds=int(seconds))


def _string(info: StringInfo) -> Callable[[Any], Any]:
    def take(value: Any) -> Any:
        text = "" if value is None else value
        if "\x00" in text:
            # The PLC's string ends at its first NUL: storing the rest would store less than was written.
            raise _out_of_range(f"{info.name} cannot hold the NUL character (it ends a PLC string)")
        if len(text) > info.length:
            raise _out_of_range(f"{len(text)} characters do not fit {info.name}")
        try:
            info.validate(text, info.name)
        except ValueError as exc:
            raise _out_of_range(str(exc)) from None
        return text

    return take


def _enum(info: EnumInfo) -> Callable[[Any], Any]:
    values = {int(member) for member in typing.cast(Iterable[enum.IntEnum], info.enum_cls)}

    def take(value: Any) -> Any:
        if value not in values:
            raise _out_of_range(f"{value} is no value of {info.name} ({', '.join(map(str, sorted(values)))})")
        return int(value)

    return take


def _codec(info: TypeInfo) -> _Codec | None:
    """The OPC UA form of a scalar IEC type, or None for what OPC UA cannot show (pointers, references, interfaces)."""
    if isinstance(info, StringInfo):
        return _Codec(_VT.String, frozenset({_VT.String}), str, _string(info))
    if isinstance(info, EnumInfo):
        table = _SIGNED if info.base.kind == "signed" else _UNSIGNED
        return _Codec(table[info.base.size], _INTEGERS, int, _enum(info))
    if not isinstance(info, ElementaryInfo):
        return None
    record = info.record
    name, kind = record.name, record.kind
    if kind == "bool":
        return _Codec(_VT.Boolean, frozenset({_VT.Boolean}), bool, bool)
    if kind == "real":
        single = record.size == 4
        return _Codec(_VT.Float if single else _VT.Double, _NUMBERS, float, _real(name, single))
    low, high = int(record.low or 0), int(record.high or 0)
    if kind == "time":
        # PLCopen / TwinCAT: TIME and LTIME are Int64, in the unit iecoop stores (ms, ns).
        return _Codec(_VT.Int64, _INTEGERS, lambda v: min(int(v), _INT64_MAX), _int_range(low, high, name))
    if name in ("DATE", "DT"):
        resolution = 86_400 if name == "DATE" else 1
        return _Codec(_VT.DateTime, frozenset({_VT.DateTime}), _read_date, _date(name, resolution))
    table = _SIGNED if kind == "signed" else _UNSIGNED
    return _Codec(table[record.size], _INTEGERS, int, _int_range(low, high, name))


@dataclasses.dataclass(frozen=True, eq=False)
class _Object:
    """An object node: a task, program, GVL, FB instance, STRUCT, or an ARRAY of them."""

    path: str
    name: str
    parent: str | None  # the parent's path; None: the Objects folder


@dataclasses.dataclass(frozen=True, eq=False)
class _Variable:
    """A variable node: a value of elementary, STRING or enum type, or an ARRAY of one of them."""

    path: str
    name: str
    parent: str
    root: int  # which block of the image
    offset: int  # in that block
    info: TypeInfo  # what stores the whole value (the ARRAY's info for an ARRAY)
    scalar: TypeInfo  # the element type
    codec: _Codec
    shape: tuple[int, ...] | None  # None: a scalar
    writable: bool

    def variant(self, block: bytearray) -> ua.Variant:
        """The value in ``block`` (a copy of the variable's root block) as an OPC UA Variant."""
        if self.shape is None:
            return ua.Variant(self.codec.read(self.info.load(block, self.offset)), self.codec.vtype)
        size, read, load = self.scalar.size, self.codec.read, self.scalar.load
        flat = [read(load(block, self.offset + i * size)) for i in range(_count(self.shape))]
        return ua.Variant(_nest(flat, self.shape), self.codec.vtype, Dimensions=list(self.shape))

    def take(self, variant: ua.Variant) -> Any:
        """The PLC value for a client's Variant; raises _Refused (nothing is stored)."""
        if variant.VariantType not in self.codec.accepts:
            raise _Refused(
                ua.StatusCodes.BadTypeMismatch,
                f"{self.path} takes {self.codec.vtype.name}, got {variant.VariantType.name}",
            )
        value = variant.Value
        if self.shape is None:
            if isinstance(value, (list, tuple)):
                raise _Refused(ua.StatusCodes.BadTypeMismatch, f"{self.path} takes a scalar, got an array")
            return self.codec.take(value)
        flat = _flatten(value, self.shape, self.path)
        return [self.codec.take(item) for item in flat]


def _count(shape: tuple[int, ...]) -> int:
    total = 1
    for n in shape:
        total *= n
    return total


def _nest(flat: list[Any], shape: tuple[int, ...]) -> list[Any]:
    """Row-major nesting of a flat list (the last index varies fastest, as in IEC ARRAY memory)."""
    for n in reversed(shape[1:]):
        flat = [flat[i : i + n] for i in range(0, len(flat), n)]
    return flat


def _flatten(value: Any, shape: tuple[int, ...], path: str) -> list[Any]:
    if not isinstance(value, (list, tuple)) or len(value) != shape[0]:
        got = f"{len(value)} elements" if isinstance(value, (list, tuple)) else "a scalar"
        raise _Refused(ua.StatusCodes.BadTypeMismatch, f"{path} takes an array of {'x'.join(map(str, shape))}, got {got}")
    if len(shape) == 1:
        if any(isinstance(item, (list, tuple)) for item in value):
            raise _Refused(ua.StatusCodes.BadTypeMismatch, f"{path} takes a one-dimensional array")
        return list(value)
    return [item for row in value for item in _flatten(row, shape[1:], path)]


def _indices(bounds: tuple[tuple[int, int], ...]) -> list[tuple[int, ...]]:
    result: list[tuple[int, ...]] = [()]
    for lo, hi in bounds:
        result = [prefix + (i,) for prefix in result for i in range(lo, hi + 1)]
    return result


def _code_names(code: types.CodeType) -> Iterator[str]:
    """The global and attribute names a function's code uses, its nested functions' and comprehensions' included."""
    yield from code.co_names
    for const in code.co_consts:
        if isinstance(const, types.CodeType):
            yield from _code_names(const)


def _user_code(obj: Any) -> bool:
    # The library's own blocks and functions (TON, SEL...) name no global list of the user's.
    module = getattr(obj, "__module__", None) or ""
    return module != "iecoop" and not module.startswith("iecoop.")


class _ListFinder:
    """The global variable lists some programs use, as the PLC links them: found in their classes, once.

    A list is used when a class the programs are made of (their own, their
    bases, the FBs and STRUCTs they hold, the functions and blocks their code
    names) declares a VAR_EXTERNAL of it or its code names it (``GVL_Plant.speed``,
    ``plant.GVL_Plant.speed``).
    """

    def __init__(self) -> None:
        self.found: dict[int, Any] = {}
        self._seen: set[int] = set()

    def _first(self, obj: Any) -> bool:
        if id(obj) in self._seen:
            return False
        self._seen.add(id(obj))
        return True

    def block_class(self, cls: type) -> None:
        for klass in cls.__mro__:
            if iec_class(klass) is None or not _user_code(klass) or not self._first(klass):
                continue
            layout = layout_of(klass)
            for record in layout.fields if layout is not None else ():
                info = record.info.elem if isinstance(record.info, ArrayInfo) else record.info
                if isinstance(info, AggregateInfo):
                    self.block_class(info.cls)
            for name, value in vars(klass).items():
                if name.startswith(("_iec", "__")):
                    continue  # what the builders generate: no code of the user's
                static = getattr(value, "block", None)  # a VAR_EXTERNAL's global list, a VAR_STAT's block
                if static is not None and layout_of(type(static)) is not None:
                    self.value(static)
                # Its body and METHODs, its PROPERTYs' accessors.
                for attribute in ("fget", "fset", "__func__"):
                    self.function(getattr(value, attribute, None))
                self.function(value)

    def function(self, func: Any) -> None:
        if not isinstance(func, types.FunctionType) or not _user_code(func) or not self._first(func):
            return
        names = set(_code_names(func.__code__))
        values = [func.__globals__[n] for n in names if n in func.__globals__]
        values += [cell.cell_contents for cell in func.__closure__ or () if _filled(cell)]
        for value in values:
            if isinstance(value, types.ModuleType):  # plant.GVL_Plant.speed: the list is an attribute of a module
                for name in names:
                    if isinstance(getattr(value, name, None), GlobalVariables):
                        self.value(getattr(value, name))
            else:
                self.value(value)

    def value(self, value: Any) -> None:
        if isinstance(value, GlobalVariables):
            self.found.setdefault(id(value), value)
            self.block_class(type(value))
        elif isinstance(value, types.FunctionType):
            self.function(value)
        elif isinstance(value, type):
            self.block_class(value)
        elif layout_of(type(value)) is not None:
            self.block_class(type(value))


def _filled(cell: types.CellType) -> bool:
    try:
        cell.cell_contents
    except ValueError:  # a closure variable not yet bound
        return False
    return True


def _served_lists(
    runtime: Runtime, named: Iterable[GlobalVariables | type[GlobalVariables] | str]
) -> list[tuple[str, Any]]:
    """The global lists a server shows: those the runtime's programs use, then those named, by their names."""
    finder = _ListFinder()
    for task in runtime.tasks:
        for _path, program in task.programs:
            finder.block_class(type(program))
    registry = global_lists()
    for item in named:
        block = registry.get(item) if isinstance(item, str) else item
        if not isinstance(block, GlobalVariables):
            known = ", ".join(registry) or "none"
            raise ValueError(f"OpcUaServer: gvls names {item!r}, which is no global variable list (known: {known})")
        finder.found.setdefault(id(block), block)
    names = {id(block): name for name, block in registry.items()}
    # The registry's order (the order of definition), then lists a program holds that another took the name of.
    ordered = [block for block in registry.values() if id(block) in finder.found]
    ordered += [block for key, block in finder.found.items() if key not in names]
    return [(names.get(id(block), type(block).__name__), block) for block in ordered]


class _AddressSpace:
    """The nodes of a runtime's programs and GVLs, read once from their class layouts."""

    def __init__(self, runtime: Runtime, lists: Iterable[tuple[str, Any]], writable: Iterable[str],
                 online: bool = False) -> None:
        self.online = online
        self.objects: list[_Object] = []
        self.variables: dict[str, _Variable] = {}
        self.blocks: list[Any] = []
        self._paths: set[str] = set()
        patterns = list(writable)
        self._patterns = patterns
        matched: set[str] = set()
        self._matched = matched
        for task in runtime.tasks:
            self._add_object(task.name, task.name, None)
            for path, program in task.programs:
                self._add_block(path, path[len(task.name) + 1 :], task.name, program, inputs_writable=True)
        for name, block in lists:
            self._add_block(name, name, None, block, inputs_writable=False)
        if online:
            self._claim("Online")  # the object of the Force and Release methods
        for pattern in patterns:
            if pattern not in matched:
                raise ValueError(f"OpcUaServer: writable pattern {pattern!r} matches no variable of the runtime")

    def _claim(self, path: str) -> None:
        if path in self._paths:
            raise ValueError(f"OpcUaServer: two nodes would have the instance path {path!r}")
        self._paths.add(path)

    def _add_object(self, path: str, name: str, parent: str | None) -> None:
        self._claim(path)
        self.objects.append(_Object(path, name, parent))

    def _add_block(self, path: str, name: str, parent: str | None, block: Any, *, inputs_writable: bool) -> None:
        self._add_object(path, name, parent)
        self.blocks.append(block)
        root = len(self.blocks) - 1
        layout = layout_of(type(block))
        if layout is None:
            return
        for record in layout.fields:
            if record.section in _HIDDEN_SECTIONS:
                continue
            # Program inputs and GVL variables are what an HMI sets; the rest is the PLC's own.
            writable = record.section is Section.VAR_INPUT if inputs_writable else True
            self._add(f"{path}.{record.st_name}", record.st_name, path, record.info, root, record.offset,
                      writable, record.spec.constant)

    def _add_members(self, cls: type, path: str, root: int, base: int, writable: bool, constant: bool) -> None:
        # The members of an FB instance follow the FB's own rules: read-only unless named writable.
        data = kind_of(cls) in (Kind.STRUCT, Kind.UNION)
        for record in fields_of(cls):
            if record.section in _HIDDEN_SECTIONS:
                continue
            self._add(f"{path}.{record.st_name}", record.st_name, path, record.info, root, base + record.offset,
                      writable and data, constant or record.spec.constant)

    def _add(self, path: str, name: str, parent: str, info: TypeInfo, root: int, offset: int,
             writable: bool, constant: bool) -> None:
        if isinstance(info, AggregateInfo):
            self._add_object(path, name, parent)
            self._add_members(info.cls, path, root, offset, writable, constant)
            return
        if isinstance(info, ArrayInfo) and isinstance(info.elem, AggregateInfo):
            self._add_object(path, name, parent)
            for index, position in enumerate(_indices(info.bounds)):
                label = f"{name}[{','.join(map(str, position))}]"
                element = f"{parent}.{label}"
                self._add_object(element, label, path)
                self._add_members(info.elem.cls, element, root, offset + index * info.elem.size, writable, constant)
            return
        scalar = info.elem if isinstance(info, ArrayInfo) else info
        codec = _codec(scalar)
        if codec is None:
            return
        shape = tuple(hi - lo + 1 for lo, hi in info.bounds) if isinstance(info, ArrayInfo) else None
        named = False
        for pattern in self._patterns:
            if fnmatch.fnmatchcase(path, pattern):
                self._matched.add(pattern)
                named = True
        self._claim(path)
        self.variables[path] = _Variable(
            path, name, parent, root, offset, info, scalar, codec, shape,
            (writable or named or self.online) and not constant,
        )


class _Users:
    """asyncua user manager: who may open a session, never as an administrator.

    With a table, the configured names and passwords and nobody else; without
    one, every client (anonymous or any name) as an ordinary user. asyncua's
    default manager makes a client that calls itself ``admin`` an
    administrator, whatever its password: this one never does.
    """

    def __init__(self, users: Mapping[str, str] | None) -> None:
        self._users = None if users is None else {name: password.encode() for name, password in users.items()}

    def get_user(self, iserver: Any, username: str | None = None, password: str | None = None,
                 certificate: Any = None) -> User | None:
        if self._users is None:
            return User(role=UserRole.User, name=username)
        known = self._users.get(username or "")
        if known is None or password is None or not hmac.compare_digest(known, password.encode()):
            return None
        return User(role=UserRole.User, name=username)


#: The user of a call that names none: refused, where asyncua's default would be an administrator.
_NOBODY = User(role=UserRole.Anonymous)


def _denied(count: int) -> list[ua.StatusCode]:
    return [ua.StatusCode(ua.StatusCodes.BadUserAccessDenied) for _ in range(count)]


class _FixedNodes(NodeManagementService):  # type: ignore[misc]  # asyncua is not followed (see pyproject.toml)
    """The node management services (AddNodes, DeleteNodes, AddReferences, DeleteReferences) for the server alone.

    The address space is the runtime's layout: a client that removed a
    variable's node would leave the HMI blind, one that added nodes would
    show variables the PLC has not got. Every client request is refused,
    whatever its user's role; the server's own session builds the nodes.
    """

    def __init__(self, aspace: Any, server_user: User) -> None:
        super().__init__(aspace)
        self._server_user = server_user

    def add_nodes(self, addnodeitems: list[ua.AddNodesItem], user: User = _NOBODY) -> list[ua.AddNodesResult]:
        if user is self._server_user:
            return typing.cast(list[ua.AddNodesResult], super().add_nodes(addnodeitems, user))
        return [ua.AddNodesResult(StatusCode=code) for code in _denied(len(addnodeitems))]

    def delete_nodes(self, deletenodeitems: ua.DeleteNodesParameters, user: User = _NOBODY) -> list[ua.StatusCode]:
        if user is self._server_user:
            return typing.cast(list[ua.StatusCode], super().delete_nodes(deletenodeitems, user))
        return _denied(len(deletenodeitems.NodesToDelete))

    def add_references(self, refs: list[ua.AddReferencesItem], user: User = _NOBODY) -> list[ua.StatusCode]:
        if user is self._server_user:
            return typing.cast(list[ua.StatusCode], super().add_references(refs, user))
        return _denied(len(refs))

    def delete_references(self, refs: list[ua.DeleteReferencesItem], user: User = _NOBODY) -> list[ua.StatusCode]:
        if user is self._server_user:
            return typing.cast(list[ua.StatusCode], super().delete_references(refs, user))
        return _denied(len(refs))


class _PlcAttributeService(AttributeService):  # type: ignore[misc]  # asyncua is not followed (see pyproject.toml)
    """Client writes: to PLC variables checked here and queued for the next cycle; to any other node refused.

    The server's own session (its clock) writes the other nodes as asyncua does.
    """

    def __init__(self, aspace: Any, owner: OpcUaServer, server_user: User) -> None:
        super().__init__(aspace)
        self._owner = owner
        self._server_user = server_user

    async def write(self, params: ua.WriteParameters, user: User = _NOBODY) -> list[ua.StatusCode]:
        results: list[ua.StatusCode] = []
        for item in params.NodesToWrite:
            nodeid = item.NodeId
            variable = self._owner._variable_for(nodeid)
            if variable is not None:
                results.append(ua.StatusCode(self._owner._client_write(variable, item)))
            elif user is self._server_user:
                results.extend(await super().write(ua.WriteParameters(NodesToWrite=[item]), user))
            else:
                results.extend(_denied(1))
        return results


class OpcUaServer:
    """An OPC UA server for ``runtime`` (TwinCAT TF6100, the CODESYS OPC UA server), in a background thread.

    ``endpoint`` is where it listens (``opc.tcp://127.0.0.1:4840``; port 0
    picks a free port, which ``.endpoint`` then names). ``writable`` adds
    variables a client may write, as instance paths or ``fnmatch`` patterns
    (``"PlcTask.Main.setpoint"``, ``"PlcTask.Main.axis.*"``). The server
    shows the runtime's programs and the global variable lists they use
    (VAR_EXTERNAL, or named in their code); ``gvls`` adds lists, by name or
    instance (``gvls=["GVL_Plant"]``). No client adds, deletes or relinks a
    node. ``users`` maps user names to passwords (anonymous clients are then
    refused; without it every client may connect, none as an administrator);
    ``certificate`` and ``private_key`` enable the ``security`` policies
    (asyncua ``SecurityPolicyType`` names). ``online=True`` gives clients
    TwinCAT's online write and force: every variable but a CONSTANT is
    writable, and the methods ``Online.Force(path, value)`` and
    ``Online.Release(path, restore)`` force as ``rt.force`` does. Use it as a
    context manager::

        with OpcUaServer(rt, endpoint="opc.tcp://127.0.0.1:4840"):
            rt.run(duration=T("10s"), realtime=True)
    """

    def __init__(
        self,
        runtime: Runtime,
        endpoint: str = "opc.tcp://127.0.0.1:4840",
        *,
        writable: Iterable[str] = (),
        gvls: Iterable[GlobalVariables | type[GlobalVariables] | str] = (),
        users: Mapping[str, str] | None = None,
        certificate: str | os.PathLike[str] | None = None,
        private_key: str | os.PathLike[str] | None = None,
        security: Sequence[str] | None = None,
        name: str = "iecoop",
        start_timeout: float = 30.0,
        online: bool = False,
    ) -> None:
        parts = urlsplit(endpoint)
        if parts.scheme != "opc.tcp" or not parts.hostname:
            raise ValueError(f"OpcUaServer: endpoint must look like opc.tcp://127.0.0.1:4840, got {endpoint!r}")
        try:
            port = parts.port
        except ValueError:
            raise ValueError(f"OpcUaServer: endpoint {endpoint!r} has no valid port") from None
        if (certificate is None) != (private_key is None):
            raise ValueError("OpcUaServer: certificate and private_key go together")
        if security is None:
            security = ("NoSecurity",) if certificate is None else ("Basic256Sha256_SignAndEncrypt",)
        policies = []
        for policy in security:
            try:
                policies.append(ua.SecurityPolicyType[policy])
            except KeyError:
                known = ", ".join(ua.SecurityPolicyType.__members__)
                raise ValueError(f"OpcUaServer: unknown security policy {policy!r} (known: {known})") from None
        if certificate is None and any(p != ua.SecurityPolicyType.NoSecurity for p in policies):
            raise ValueError("OpcUaServer: a signing or encrypting security policy needs certificate= and private_key=")
        self.runtime = runtime
        self.host = parts.hostname
        self.port = 4840 if port is None else port
        self._path = parts.path
        self._users = dict(users) if users is not None else None
        self._certificate = certificate
        self._private_key = private_key
        self._policies = policies
        self._name = name
        self._start_timeout = start_timeout
        self._space = _AddressSpace(runtime, _served_lists(runtime, gvls), writable, online)
        # A byte view of each exposed block: `.raw` copies it in one C call (the whole per-cycle cost).
        self._views = [(ctypes.c_char * ctypes.sizeof(b)).from_buffer(b) for b in self._space.blocks]
        self._nodeids: dict[ua.NodeId, _Variable] = {}
        self._namespace = 0
        # What clients asked for, done by the PLC's thread at the next cycle start: a write, a force, a release.
        self._pending: collections.deque[tuple[Callable[[Any, Any], None], Any, Any]] = collections.deque()
        self._images: collections.deque[tuple[tuple[bytes, ...], float]] = collections.deque(maxlen=_BACKLOG)
        self._last: tuple[bytes, ...] = ()
        # Images handed to the server / published (or dropped) by it, for wait_published().
        self._sent = 0
        self._done = 0
        self._progress = threading.Condition()
        self._thread: threading.Thread | None = None
        self._loop: asyncio.AbstractEventLoop | None = None
        self._stop: asyncio.Event | None = None
        self._wake: asyncio.Event | None = None
        self._ready = threading.Event()
        self._error: BaseException | None = None

    @property
    def endpoint(self) -> str:
        """The URL clients connect to (with the port actually bound)."""
        return f"opc.tcp://{self.host}:{self.port}{self._path}"

    @property
    def namespace_index(self) -> int:
        """The index of ``urn:iecoop`` in the server's namespace array."""
        return self._namespace

    def writable(self) -> list[str]:
        """The instance paths a client may write."""
        return [path for path, v in self._space.variables.items() if v.writable]

    def wait_published(self, timeout: float = 5.0) -> None:
        """Block until every cycle run so far is published (a client reading now sees the last cycle's values).

        Raises TimeoutError if the server has not caught up within ``timeout`` seconds.
        """
        target = self._sent
        with self._progress:
            if not self._progress.wait_for(lambda: self._done >= target or self._thread is None, timeout):
                raise TimeoutError(f"OpcUaServer: {target - self._done} cycle images not published after {timeout} s")

    # -- the PLC thread ----------------------------------------------------------

    def _capture(self) -> tuple[bytes, ...]:
        return tuple(map(_RAW, self._views))

    def _cycle_end(self) -> None:
        """After every cycle: one copy of the exposed blocks, handed to the server if anything changed."""
        image = self._capture()
        if image == self._last:
            return
        self._last = image
        loop = self._loop
        if loop is not None:
            try:
                loop.call_soon_threadsafe(self._receive, image, time.time())
            except RuntimeError:
                return  # the server is shutting down; nobody reads this image
            self._sent += 1

    def _cycle_start(self) -> None:
        """Before every cycle: the client writes taken since the last one, in the order they came."""
        pending = self._pending
        while pending:
            change, target, value = pending.popleft()
            try:
                change(target, value)
            except (TypeError, ValueError, OverflowError, AccessError) as exc:  # pragma: no cover - checked before
                _log.warning("OPC UA change of %s not applied: %s", target.path, exc)

    def _store(self, variable: _Variable, value: Any) -> None:
        variable.info.store(self._space.blocks[variable.root], variable.offset, value, variable.path)

    def _release(self, symbol: Symbol, restore: bool) -> None:
        with contextlib.suppress(AccessError):  # an element that is not forced: nothing to release
            self.runtime.release(symbol, restore=restore)

    def _symbols(self, variable: _Variable) -> list[Symbol]:
        """The elementary variables a node is: itself, or an ARRAY's elements (forced one by one, in one cycle)."""
        block = self._space.blocks[variable.root]
        if variable.shape is None or not isinstance(variable.info, ArrayInfo):
            return [Symbol(variable.path, variable.info, block, variable.offset)]
        size = variable.scalar.size
        return [Symbol(f"{variable.path}[{','.join(map(str, position))}]", variable.scalar, block,
                       variable.offset + index * size) for index, position in enumerate(_indices(variable.info.bounds))]

    async def _force_method(self, parent: ua.NodeId, path: ua.Variant, value: ua.Variant) -> Any:
        """``Online.Force(Path, Value)``: the node's variable forced from the next cycle, whole; a refusal forces nothing."""
        variable = self._space.variables.get(path.Value) if isinstance(path.Value, str) else None
        if variable is None or not variable.writable:
            return ua.StatusCode(ua.StatusCodes.BadNodeIdUnknown if variable is None else ua.StatusCodes.BadNotWritable)
        try:
            taken = variable.take(value)
        except _Refused as refusal:
            _log.info("OPC UA force of %s refused: %s", variable.path, refusal)
            return ua.StatusCode(refusal.code)
        values = taken if variable.shape is not None else [taken]
        self._pending.extend((self.runtime.force, symbol, item) for symbol, item in zip(self._symbols(variable), values))
        return []

    async def _release_method(self, parent: ua.NodeId, path: ua.Variant, restore: ua.Variant) -> Any:
        """``Online.Release(Path, Restore)``: the force ended, keeping the value or restoring the one before it."""
        variable = self._space.variables.get(path.Value) if isinstance(path.Value, str) else None
        if variable is None or not isinstance(restore.Value, bool):
            return ua.StatusCode(ua.StatusCodes.BadNodeIdUnknown if variable is None else ua.StatusCodes.BadTypeMismatch)
        self._pending.extend((self._release, symbol, restore.Value) for symbol in self._symbols(variable))
        return []

    # -- the server thread -------------------------------------------------------

    def _variable_for(self, nodeid: ua.NodeId) -> _Variable | None:
        return self._nodeids.get(nodeid)

    def _client_write(self, variable: _Variable, item: ua.WriteValue) -> int:
        if item.AttributeId != ua.AttributeIds.Value or item.IndexRange:
            return int(ua.StatusCodes.BadNotWritable if item.AttributeId != ua.AttributeIds.Value
                       else ua.StatusCodes.BadWriteNotSupported)
        if not variable.writable:
            return int(ua.StatusCodes.BadNotWritable)
        datavalue = item.Value
        variant = datavalue.Value if datavalue is not None else None
        if variant is None:
            return int(ua.StatusCodes.BadTypeMismatch)
        try:
            value = variable.take(variant)
        except _Refused as refusal:
            _log.info("OPC UA write to %s refused: %s", variable.path, refusal)
            return refusal.code
        self._pending.append((self._store, variable, value))
        return int(ua.StatusCodes.Good)

    def _receive(self, image: tuple[bytes, ...], stamp: float) -> None:
        if len(self._images) == self._images.maxlen:
            self._count_done()  # the oldest image is dropped
        self._images.append((image, stamp))
        assert self._wake is not None
        self._wake.set()

    async def _publisher(self, server: Server, first: tuple[bytes, ...]) -> None:
        previous = first
        assert self._wake is not None
        while True:
            await self._wake.wait()
            self._wake.clear()
            while self._images:
                image, stamp = self._images.popleft()
                try:
                    await self._publish(server, previous, image, stamp)
                except Exception:  # one bad image must not end publishing for good
                    _log.exception("OPC UA: publishing a cycle's values failed")
                previous = image
                self._count_done()

    async def _watch_faults(self) -> None:
        """A faulted cycle has no cycle end: publish where the PLC stopped, so clients read its state."""
        seen = self.runtime.fault
        while True:
            await asyncio.sleep(_FAULT_POLL)
            fault = self.runtime.fault
            if fault is not None and fault is not seen:
                self._cycle_end()
            seen = fault

    def _count_done(self) -> None:
        with self._progress:
            self._done += 1
            self._progress.notify_all()

    async def _publish(self, server: Server, old: tuple[bytes, ...], new: tuple[bytes, ...], stamp: float) -> None:
        when = datetime.datetime.fromtimestamp(stamp, datetime.timezone.utc)
        changed = {root for root in range(len(new)) if new[root] != old[root]}
        blocks: dict[int, bytearray] = {root: bytearray(new[root]) for root in changed}
        for variable in self._space.variables.values():
            root = variable.root
            if root not in changed:
                continue
            start, end = variable.offset, variable.offset + variable.info.size
            if old[root][start:end] == new[root][start:end]:
                continue
            value = ua.DataValue(variable.variant(blocks[root]), SourceTimestamp=when, ServerTimestamp=when)
            await server.write_attribute_value(ua.NodeId(variable.path, self._namespace), value)

    async def _build(self, server: Server, image: tuple[bytes, ...]) -> None:
        idx = self._namespace
        nodes: dict[str | None, Any] = {None: server.nodes.objects}
        for obj in self._space.objects:
            parent = nodes[obj.parent]
            nodes[obj.path] = await parent.add_object(ua.NodeId(obj.path, idx), ua.QualifiedName(obj.name, idx))
        blocks = [bytearray(block) for block in image]
        for variable in self._space.variables.values():
            parent = nodes[variable.parent]
            nodeid = ua.NodeId(variable.path, idx)
            node = await parent.add_variable(nodeid, ua.QualifiedName(variable.name, idx),
                                             variable.variant(blocks[variable.root]), variable.codec.vtype)
            if variable.shape is not None:
                # asyncua leaves a one-dimensional array's rank open; a client sizes its buffers from these two.
                await node.write_attribute(ua.AttributeIds.ValueRank, ua.DataValue(ua.Variant(len(variable.shape), _VT.Int32)))
                dims = ua.Variant(list(variable.shape), _VT.UInt32)
                await node.write_attribute(ua.AttributeIds.ArrayDimensions, ua.DataValue(dims))
            if variable.writable:
                await node.set_writable(True)
            if isinstance(variable.scalar, EnumInfo):
                await self._add_enum_strings(node, variable, idx)
            self._nodeids[nodeid] = variable

    @staticmethod
    async def _add_enum_strings(node: Any, variable: _Variable, idx: int) -> None:
        assert isinstance(variable.scalar, EnumInfo)
        enum_cls = variable.scalar.enum_cls
        members = list(typing.cast(Iterable[enum.IntEnum], enum_cls))
        values = sorted(int(m) for m in members)
        # the values' ST names (an enumeration iecoop did not build has only its Python names)
        shown = {m.name: st_name(enum_cls, m.name) if iec_class(enum_cls) else m.name for m in members}
        if values == list(range(len(values))):
            texts = [ua.LocalizedText(shown[m.name]) for m in sorted(members, key=int)]
            await node.add_property(ua.NodeId(f"{variable.path}#EnumStrings", idx), ua.QualifiedName("EnumStrings", 0),
                                    texts, _VT.LocalizedText)
        else:
            # Values that are not 0..n-1 need EnumValues (value and name pairs), as OPC UA Part 3 says.
            pairs = [ua.EnumValueType(Value=int(m), DisplayName=ua.LocalizedText(shown[m.name]),
                                      Description=ua.LocalizedText(shown[m.name]))
                     for m in sorted(members, key=int)]
            await node.add_property(ua.NodeId(f"{variable.path}#EnumValues", idx), ua.QualifiedName("EnumValues", 0),
                                    pairs, _VT.ExtensionObject)

    async def _serve(self, first: tuple[bytes, ...]) -> None:
        self._loop = asyncio.get_running_loop()
        self._stop = asyncio.Event()
        self._wake = asyncio.Event()
        server = Server(user_manager=_Users(self._users))
        server.allow_remote_admin(False)
        await server.init()
        iserver = server.iserver
        builder = iserver.isession.user
        iserver.node_mgt_service = _FixedNodes(iserver.aspace, builder)
        # asyncua's own clock task sleeps a second between updates and is awaited on stop; ours is cancelled.
        server.disable_clock()
        server.set_endpoint(self.endpoint)
        server.set_server_name(self._name)
        await server.set_application_uri(f"{NAMESPACE}:server")
        server.set_security_policy(self._policies)
        if self._certificate is not None and self._private_key is not None:
            await server.load_certificate(str(self._certificate))
            await server.load_private_key(str(self._private_key))
        if self._users is not None:
            server.set_identity_tokens([ua.UserNameIdentityToken])
        self._namespace = await server.register_namespace(NAMESPACE)
        await self._build(server, first)
        if self._space.online:
            idx = self._namespace
            online = await server.nodes.objects.add_object(ua.NodeId("Online", idx), ua.QualifiedName("Online", idx))
            await online.add_method(ua.NodeId("Online.Force", idx), ua.QualifiedName("Force", idx), self._force_method,
                                    [_VT.String, _VT.Variant], [])
            await online.add_method(ua.NodeId("Online.Release", idx), ua.QualifiedName("Release", idx),
                                    self._release_method, [_VT.String, _VT.Boolean], [])
        iserver.attribute_service = _PlcAttributeService(iserver.aspace, self, builder)
        await server.start()
        helpers = [asyncio.create_task(self._publisher(server, first)), asyncio.create_task(_clock(server)),
                   asyncio.create_task(self._watch_faults())]
        try:
            self._ready.set()
            await self._stop.wait()
        finally:
            self._loop = None
            for task in helpers:
                task.cancel()
            await asyncio.gather(*helpers, return_exceptions=True)
            await server.stop()

    def _thread_main(self, first: tuple[bytes, ...]) -> None:
        try:
            asyncio.run(self._serve(first))
        except BaseException as exc:  # handed to the thread that called start()
            self._error = exc
        finally:
            self._ready.set()

    # -- start and stop ----------------------------------------------------------

    def start(self) -> None:
        """Start serving (``__enter__`` calls it); raises what kept the server from listening."""
        if self._thread is not None:
            raise RuntimeError("OpcUaServer: already started")
        # Fail fast on a port already taken, before a second of asyncua start-up.
        self.port = _probe_port(self.host, self.port)
        self._error = None
        self._sent = self._done = 0
        self._ready.clear()
        first = self._last = self._capture()
        self._thread = threading.Thread(target=self._thread_main, args=(first,), name=f"iecoop OPC UA {self.endpoint}")
        self._thread.start()
        if not self._ready.wait(self._start_timeout) or self._error is not None:
            error = self._error
            self.stop()
            if error is not None:
                raise error
            raise TimeoutError(f"OpcUaServer: the server did not start within {self._start_timeout} s")
        self.runtime.on_cycle_start.append(self._cycle_start)
        self.runtime.on_cycle_end.append(self._cycle_end)

    def stop(self) -> None:
        """Stop serving and close the port (``__exit__`` calls it); queued writes not yet applied are dropped."""
        for hooks, hook in ((self.runtime.on_cycle_start, self._cycle_start), (self.runtime.on_cycle_end, self._cycle_end)):
            if hook in hooks:
                hooks.remove(hook)
        thread, self._thread = self._thread, None
        if thread is None:
            return
        while thread.is_alive():
            # The loop and its stop event exist once the thread has begun; ask until it has ended.
            loop, stop = self._loop, self._stop
            if loop is not None and stop is not None:
                try:
                    loop.call_soon_threadsafe(stop.set)
                except RuntimeError:
                    pass  # the loop has just closed
            thread.join(0.05)
        self._pending.clear()
        self._images.clear()

    def __enter__(self) -> OpcUaServer:
        self.start()
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None) -> None:
        self.stop()

    def __repr__(self) -> str:
        state = "serving" if self._thread is not None else "stopped"
        return f"<OpcUaServer {self.endpoint} {state}, {len(self._space.variables)} variables>"


async def _clock(server: Server) -> None:
    """The server's ServerStatus.CurrentTime, once a second (OPC UA Part 5), until cancelled."""
    status = server.get_node(ua.ObjectIds.Server_ServerStatus)
    current = server.get_node(ua.ObjectIds.Server_ServerStatus_CurrentTime)
    while True:
        now = datetime.datetime.now(datetime.timezone.utc)
        value = await status.read_value()
        value.CurrentTime = now
        await status.write_value(value)
        await current.write_value(now)
        await asyncio.sleep(1)


def _probe_port(host: str, port: int) -> int:
    """``port`` if it can be bound on ``host`` now (for 0, the free port the OS picks); OSError if it is taken."""
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    with socket.socket(family, socket.SOCK_STREAM) as probe:
        # As asyncio's server does: a port in TIME_WAIT may be bound again, one with a listener may not.
        probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        probe.bind((host, port))
        return int(probe.getsockname()[1])
