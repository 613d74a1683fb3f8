"""A Modbus TCP server for a running Runtime: the PLC's located variables as Modbus tables.

CODESYS-based controllers that act as a Modbus TCP slave (WAGO PFC and
750-8xx, for one: WAGO manual *Modbus TCP Mapping*) give a master their
process image: inputs as discrete inputs and input registers, outputs as
coils and holding registers, and the marker area as coils and holding
registers from 12288 (0x3000) on. ``ModbusServer`` does the same for an iecoop ``Runtime``
with pymodbus (install the extra: ``pip install "iecoop[modbus]"``)::

    located = {"MAIN.bStart": "%IX0.0", "MAIN.bLamp": "%QX0.0", "MAIN.nLevel": "%IW0", "MAIN.nSpeed": "%QW0"}
    with ModbusServer(rt, port=5020, located=located):
        rt.run(duration=T("1h"), realtime=True)

=======  =================  =====  =============================  =================================
address  table              first  address of                     a master may
=======  =================  =====  =============================  =================================
``%IX``  discrete inputs    0      ``%IXb.i`` is 8 b + i          read (FC 2)
``%QX``  coils              0      ``%QXb.i`` is 8 b + i          read, write (FC 1, 5, 15)
``%IW``  input registers    0      ``%IWn`` is n                  read (FC 4)
``%QW``  holding registers  0      ``%QWn`` is n                  read, write (FC 3, 6, 16, 22, 23)
``%MX``  coils              12288  ``%MXb.i`` is 12288 + 8 b + i  read, write
``%MW``  holding registers  12288  ``%MWn`` is 12288 + n          read, write
=======  =================  =====  =============================  =================================

A double word (``%ID``, ``%QD``, ``%MD``: DINT, UDINT, DWORD, REAL) takes
the two registers of its two words, the low word first, as it lies in the
PLC's memory (``%QD1`` is ``%QW2`` and ``%QW3``). ``tables=`` moves an area
to another table or first address (``{"IX": ("coils", 1024)}`` lets the
master write the inputs, a plant simulation's usual need);
``tables=CODESYS_DEVICE_TABLES`` maps them as CODESYS's own Modbus slave
device does, the master's writes to the inputs. An address past 65535 is
refused when the server is made.

Every request is answered from the values the PLC had at the end of its
last cycle. A request any of whose addresses holds no located variable, or
a write that covers only a part of a double word, answers exception 2
(illegal data address), and nothing of it is stored; a write taken is
stored at the start of the next cycle, the whole request in one.
"""

from __future__ import annotations

import asyncio
import collections
import dataclasses
import enum
import logging
import re
import struct
import threading
import typing
from collections.abc import Mapping, Sequence
from types import TracebackType
from typing import Any

try:
    from pymodbus.constants import ExcCodes
    from pymodbus.server import ModbusBaseServer, ModbusTcpServer
    from pymodbus.simulator import SimData, SimDevice
    from pymodbus.simulator.simcore import SimCore
except ImportError as exc:  # pragma: no cover - exercised without the extra installed
    raise ImportError(
        'iecoop.modbus needs the pymodbus library: install the extra with pip install "iecoop[modbus]"'
    ) from exc

from iecoop.exceptions import AccessError
from iecoop.memory.typeinfo import ElementaryInfo
from iecoop.runtime import Runtime, Symbol

__all__ = ["CODESYS_DEVICE_TABLES", "DEFAULT_TABLES", "ModbusServer", "Table", "parse_address"]

_log = logging.getLogger(__name__)


class Table(str, enum.Enum):
    """The four Modbus data tables."""

    DISCRETE_INPUTS = "discrete_inputs"
    COILS = "coils"
    INPUT_REGISTERS = "input_registers"
    HOLDING_REGISTERS = "holding_registers"


#: Where each area of located variables goes: area -> (table, first address).
DEFAULT_TABLES: Mapping[str, tuple[Table, int]] = {
    "IX": (Table.DISCRETE_INPUTS, 0),
    "QX": (Table.COILS, 0),
    "MX": (Table.COILS, 12288),
    "IW": (Table.INPUT_REGISTERS, 0),
    "QW": (Table.HOLDING_REGISTERS, 0),
    "MW": (Table.HOLDING_REGISTERS, 12288),
}

#: CODESYS's own *Modbus TCP Slave Device* (CODESYS Modbus help, "Modbus TCP Slave Device - General", with
#: separate bit areas): what the master writes is the PLC's input, holding registers to ``%IW`` and coils to
#: ``%IX``; what the PLC outputs the master reads, ``%QW`` as input registers and ``%QX`` as discrete inputs.
CODESYS_DEVICE_TABLES: Mapping[str, tuple[Table, int]] = {
    **DEFAULT_TABLES,
    "IX": (Table.COILS, 0),
    "QX": (Table.DISCRETE_INPUTS, 0),
    "IW": (Table.HOLDING_REGISTERS, 0),
    "QW": (Table.INPUT_REGISTERS, 0),
}

#: The last address of every Modbus table (addresses are 16 bits).
_LAST_ADDRESS = 0xFFFF

#: The table each Modbus function code reads or writes.
_FUNCTION_TABLES = {
    1: Table.COILS, 5: Table.COILS, 15: Table.COILS,
    2: Table.DISCRETE_INPUTS,
    4: Table.INPUT_REGISTERS,
    3: Table.HOLDING_REGISTERS, 6: Table.HOLDING_REGISTERS, 16: Table.HOLDING_REGISTERS,
    22: Table.HOLDING_REGISTERS, 23: Table.HOLDING_REGISTERS,
}
#: The writes whose response echoes what was taken (a mask write, 22, reads the register first instead).
_WRITES = frozenset({5, 6, 15, 16})
_ADDRESS = re.compile(r"^%([IQM])([XWD])(\d+)(?:\.(\d+))?$", re.IGNORECASE)
_BIT_TYPES = frozenset({"BOOL"})
_WORD_TYPES = frozenset({"INT", "UINT", "WORD"})
_DWORD_TYPES = frozenset({"DINT", "UDINT", "DWORD", "REAL"})


def parse_address(text: str) -> tuple[str, int, int]:
    """``"%IX1.3"`` -> ``("IX", 1, 3)``, ``"%QW2"`` -> ``("QW", 2, 0)``; ValueError for another form."""
    match = _ADDRESS.match(text.strip())
    if match is None:
        raise ValueError(f"{text!r} is no located address of the form %IX0.0, %QW2 or %MD1 (X, W or D of I, Q or M)")
    area = (match[1] + match[2]).upper()
    number, bit = int(match[3]), match[4]
    if (area[1] == "X") != (bit is not None) or (bit is not None and int(bit) > 7):
        raise ValueError(f"{text!r}: a bit address is %IXbyte.bit with bit 0..7; a word has no bit")
    return area, number, int(bit or 0)


@dataclasses.dataclass(frozen=True, eq=False)
class _Located:
    """One located variable: where it is in the PLC and which Modbus cells it takes."""

    path: str
    address: str
    symbol: Symbol
    table: Table
    first: int  # the first bit or register
    cells: int  # 1 bit, 1 or 2 registers
    real: bool

    def cell_values(self, value: Any) -> list[int]:
        """The bit or the registers of ``value``, the low word first."""
        if self.table in (Table.COILS, Table.DISCRETE_INPUTS):
            return [int(bool(value))]
        raw = struct.unpack("<I", struct.pack("<f", value))[0] if self.real else int(value) & 0xFFFF_FFFF
        return [raw & 0xFFFF, raw >> 16][: self.cells]

    def value_of(self, cells: Sequence[int]) -> Any:
        """The PLC value of the bit or registers a master wrote; AccessError if the type cannot hold it."""
        if self.table in (Table.COILS, Table.DISCRETE_INPUTS):
            return bool(cells[0])
        raw = cells[0] | (cells[1] << 16 if self.cells == 2 else 0)
        info = self.symbol.info
        assert isinstance(info, ElementaryInfo)
        if self.real:
            return struct.unpack("<f", struct.pack("<I", raw))[0]
        bits = 16 * self.cells
        if info.record.kind == "signed" and raw >= 1 << (bits - 1):
            raw -= 1 << bits
        return raw


class _PlcTables(SimCore):
    """pymodbus's datastore interface, answered from the PLC's cycle image and writes queued for the PLC."""

    def __init__(self, owner: ModbusServer) -> None:
        super().__init__(SimDevice(0, simdata=SimData(0)))
        self._owner = owner

    def device_ids(self) -> list[int]:
        return [0]

    async def async_getValues(self, device_id: int, func_code: int, address: int,
                              count: int = 1) -> list[int] | list[bool] | ExcCodes:
        table = _FUNCTION_TABLES.get(func_code)
        if table is None:
            return ExcCodes.ILLEGAL_FUNCTION
        if func_code in _WRITES:
            # The echo of a write: what was taken (the PLC stores it at its next cycle).
            echo = self._owner._echo
            return [echo[(table, a)] for a in range(address, address + count)] if all(
                (table, a) in echo for a in range(address, address + count)) else ExcCodes.ILLEGAL_ADDRESS
        return self._owner._read(table, address, count)

    async def async_setValues(self, device_id: int, func_code: int, address: int,
                              values: list[int] | list[bool]) -> ExcCodes | None:
        table = _FUNCTION_TABLES.get(func_code)
        if table is None or table in (Table.DISCRETE_INPUTS, Table.INPUT_REGISTERS):
            return ExcCodes.ILLEGAL_FUNCTION
        return self._owner._write(table, address, [int(v) for v in values])


class ModbusServer:
    """A Modbus TCP server for ``runtime``'s located variables, in a background thread.

    ``located`` maps symbol paths to addresses (``{"MAIN.bStart": "%IX0.0"}``,
    as ``AT %IX0.0`` declares them in ST); ``tables`` overrides where an area
    goes (see ``DEFAULT_TABLES``). ``port`` 0 picks a free port, which
    ``.port`` then names; ``host`` is 127.0.0.1 (this machine only) unless
    given. Use it as a context manager.
    """

    def __init__(
        self,
        runtime: Runtime,
        port: int = 502,
        *,
        located: Mapping[str, str],
        host: str = "127.0.0.1",
        tables: Mapping[str, tuple[Table | str, int]] | None = None,
        start_timeout: float = 30.0,
    ) -> None:
        self.runtime = runtime
        self.host = host
        self.port = port
        self._start_timeout = start_timeout
        areas = dict(DEFAULT_TABLES)
        for area, (table, first) in (tables or {}).items():
            if area.upper() not in DEFAULT_TABLES:
                raise ValueError(f"ModbusServer: tables names the area {area!r}; the areas are {', '.join(DEFAULT_TABLES)}")
            if not isinstance(first, int) or not 0 <= first <= _LAST_ADDRESS:
                raise ValueError(f"ModbusServer: tables puts {area!r} at {first!r}; a first address is 0..{_LAST_ADDRESS}")
            areas[area.upper()] = (Table(table), first)
        self.tables = areas
        self.variables: list[_Located] = [self._locate(path, address) for path, address in located.items()]
        self._cells: dict[tuple[Table, int], tuple[_Located, int]] = {}
        for variable in self.variables:
            for part in range(variable.cells):
                key = (variable.table, variable.first + part)
                if key in self._cells:
                    other = self._cells[key][0]
                    raise ValueError(f"ModbusServer: {variable.path} ({variable.address}) and {other.path} "
                                     f"({other.address}) are both at {key[0].value} {key[1]}")
                self._cells[key] = (variable, part)
        self._loads = [variable.symbol.load for variable in self.variables]
        self._index = {id(variable): index for index, variable in enumerate(self.variables)}
        self._values: tuple[Any, ...] = self._capture()
        self._pending: collections.deque[list[tuple[Symbol, Any]]] = collections.deque()
        self._echo: dict[tuple[Table, int], int] = {}
        self._fault: object = None  # the fault the values were last refreshed for
        self._thread: threading.Thread | None = None
        self._loop: asyncio.AbstractEventLoop | None = None
        self._stop: asyncio.Event | None = None
        self._ready = threading.Event()
        self._error: BaseException | None = None

    def _locate(self, path: str, address: str) -> _Located:
        try:
            area, number, bit = parse_address(address)
        except ValueError as exc:
            raise ValueError(f"ModbusServer: {path}: {exc}") from None
        symbol = self.runtime.symbol(path)
        name = symbol.info.name if isinstance(symbol.info, ElementaryInfo) else ""
        size = area[1]
        allowed = {"X": _BIT_TYPES, "W": _WORD_TYPES, "D": _DWORD_TYPES}[size]
        if name not in allowed:
            raise ValueError(f"ModbusServer: {path} is {symbol.info.name}; at {address} it must be "
                             f"{' or '.join(sorted(allowed))}")
        table, base = self.tables[area[0] + ("X" if size == "X" else "W")]
        if size == "X":
            first, cells = base + 8 * number + bit, 1
        elif size == "W":
            first, cells = base + number, 1
        else:
            first, cells = base + 2 * number, 2
        if first + cells - 1 > _LAST_ADDRESS:
            raise ValueError(f"ModbusServer: {path} at {address} would be {table.value} {first + cells - 1}; "
                             f"Modbus addresses end at {_LAST_ADDRESS}")
        return _Located(path, address.strip().upper(), symbol, table, first, cells, name == "REAL")

    # -- the PLC thread ----------------------------------------------------------

    def _capture(self) -> tuple[Any, ...]:
        # The values only: the PLC's thread pays one load a variable; the server makes the cells.
        return tuple(load() for load in self._loads)

    def _cycle_end(self) -> None:
        self._values = self._capture()

    def _cycle_start(self) -> None:
        pending = self._pending
        while pending:
            for symbol, value in pending.popleft():
                symbol.store(value)

    # -- the server thread (pymodbus's datastore calls) -----------------------------

    def _read(self, table: Table, address: int, count: int) -> list[int] | list[bool] | ExcCodes:
        fault = self.runtime.fault
        if fault is not None and fault is not self._fault:
            # A faulted cycle has no cycle end: the PLC stands still where it stopped, which the master then reads.
            self._fault, self._values = fault, self._capture()
        values, cells, index = self._values, self._cells, self._index
        found = [cells.get((table, a)) for a in range(address, address + count)]
        if any(cell is None for cell in found):
            return ExcCodes.ILLEGAL_ADDRESS
        words = [variable.cell_values(values[index[id(variable)]])[part]
                 for variable, part in typing.cast(list[tuple[_Located, int]], found)]
        if table in (Table.COILS, Table.DISCRETE_INPUTS):
            return [bool(word) for word in words]
        return words

    def _write(self, table: Table, address: int, values: list[int]) -> ExcCodes | None:
        cells = {(table, address + i): value for i, value in enumerate(values)}
        written: dict[_Located, list[int]] = {}
        for key, value in cells.items():
            found = self._cells.get(key)
            if found is None:
                _log.info("Modbus write refused: no variable at %s %d", key[0].value, key[1])
                return ExcCodes.ILLEGAL_ADDRESS
            variable, part = found
            written.setdefault(variable, [0] * variable.cells)[part] = value
        stores = []
        for variable in written:
            if any((variable.table, variable.first + p) not in cells for p in range(variable.cells)):
                _log.info("Modbus write refused: %s (%s) written in part", variable.path, variable.address)
                return ExcCodes.ILLEGAL_ADDRESS
            value = variable.value_of(written[variable])
            try:
                variable.symbol.check(value)
            except AccessError as exc:
                _log.info("Modbus write refused: %s", exc)
                return ExcCodes.ILLEGAL_VALUE
            stores.append((variable.symbol, value))
        self._echo = cells
        self._pending.append(stores)
        return None

    async def _serve(self) -> None:
        self._loop = asyncio.get_running_loop()
        self._stop = asyncio.Event()
        server = _Server(self, address=(self.host, self.port))
        await server.serve_forever(background=True)
        try:
            sockets = getattr(server.transport, "sockets", None) or ()
            if sockets:
                self.port = sockets[0].getsockname()[1]
            self._ready.set()
            await self._stop.wait()
        finally:
            self._loop = None
            await server.shutdown()  # type: ignore[no-untyped-call]  # unannotated in pymodbus
            # pymodbus keeps the last server started in a class attribute: let this one, and the runtime
            # it reaches, go.
            if ModbusBaseServer.active_server is server:
                ModbusBaseServer.active_server = None

    def _thread_main(self) -> None:
        try:
            asyncio.run(self._serve())
        except BaseException as exc:  # handed to the thread that called start()
            self._error = exc
        finally:
            self._ready.set()

    # -- start and stop ------------------------------------------------------------

    def start(self) -> None:
        """Listen and serve (``__enter__`` calls it); raises what kept the server from listening."""
        if self._thread is not None:
            raise RuntimeError("ModbusServer: already started")
        self._error = None
        self._ready.clear()
        self._values = self._capture()
        self._thread = threading.Thread(target=self._thread_main, name=f"iecoop Modbus {self.host}:{self.port}",
                                        daemon=True)
        self._thread.start()
        if not self._ready.wait(self._start_timeout) or self._error is not None:
            error = self._error
            self.stop()
            if error is not None:
                raise error
            raise TimeoutError(f"ModbusServer: the server did not start within {self._start_timeout} s")
        self.runtime.on_cycle_start.append(self._cycle_start)
        self.runtime.on_cycle_end.append(self._cycle_end)

    def stop(self) -> None:
        """Stop serving and close the port (``__exit__`` calls it); queued writes are dropped."""
        for hooks, hook in ((self.runtime.on_cycle_start, self._cycle_start), (self.runtime.on_cycle_end, self._cycle_end)):
            if hook in hooks:
                hooks.remove(hook)
        thread, self._thread = self._thread, None
        if thread is None:
            return
        while thread.is_alive():
            loop, stop = self._loop, self._stop
            if loop is not None and stop is not None:
                try:
                    loop.call_soon_threadsafe(stop.set)
                except RuntimeError:
                    pass  # the loop has just closed
            thread.join(0.05)
        self._pending.clear()

    def __enter__(self) -> ModbusServer:
        self.start()
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None) -> None:
        self.stop()

    def __repr__(self) -> str:
        state = "serving" if self._thread is not None else "stopped"
        return f"<ModbusServer {self.host}:{self.port} {state}, {len(self.variables)} variables>"


class _Server(ModbusTcpServer):
    """pymodbus's TCP server with the PLC's tables as its datastore."""

    def __init__(self, owner: ModbusServer, address: tuple[str, int]) -> None:
        super().__init__(SimDevice(0, simdata=SimData(0)), address=address)
        self.context = _PlcTables(owner)
