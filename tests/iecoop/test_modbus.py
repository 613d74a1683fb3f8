"""The Modbus TCP server, tested with pymodbus's own client on 127.0.0.1.

The runtime runs in the test's thread, one cycle at a time: a write is
taken by the server at once and stored at the next cycle start.
"""

from __future__ import annotations

import gc
import socket
import struct
import threading
import weakref
from collections.abc import Iterator
from typing import Any

import pytest

from iecoop import BOOL, DINT, INT, REAL, UINT, VAR, VAR_INPUT, VAR_OUTPUT, ExceptionCode, Program, T
from iecoop.exceptions import AccessError, PlcException
from iecoop.runtime import Runtime, Task

pytest.importorskip("pymodbus")
from pymodbus.client import ModbusTcpClient  # noqa: E402  (after the skip when pymodbus is missing)

from iecoop.modbus import ModbusServer, parse_address  # noqa: E402

ILLEGAL_ADDRESS = 2


class MbMain(Program, st_name="MAIN"):
    bStart: BOOL = VAR_INPUT(False)  # AT %IX0.0
    bStop: BOOL = VAR_INPUT(True)  # AT %IX0.3
    bMotor: BOOL = VAR_OUTPUT(False)  # AT %QX0.0
    bLamp: BOOL = VAR_OUTPUT(True)  # AT %QX1.2
    nLevel: INT = VAR_INPUT(-5)  # AT %IW0
    nSpeed: UINT = VAR_OUTPUT(1500)  # AT %QW1
    nCounter: DINT = VAR(-70_000)  # AT %MD2
    rFlow: REAL = VAR(1.5)  # AT %MD3
    nSetpoint: INT = VAR(0)  # AT %MW0

    def body(self) -> None:
        if self.bStart and self.bStop:
            self.bMotor = True
        if not self.bStop:
            self.bMotor = False


LOCATED = {
    "MAIN.bStart": "%IX0.0", "MAIN.bStop": "%IX0.3", "MAIN.bMotor": "%QX0.0", "MAIN.bLamp": "%QX1.2",
    "MAIN.nLevel": "%IW0", "MAIN.nSpeed": "%QW1", "MAIN.nCounter": "%MD2", "MAIN.rFlow": "%MD3",
    "MAIN.nSetpoint": "%MW0",
}


@pytest.fixture
def main() -> MbMain:
    return MbMain()


@pytest.fixture
def rt(main: MbMain) -> Iterator[Runtime]:
    runtime = Runtime(store=":memory:")
    runtime.add_task(Task("PlcTask", interval=T("10ms")), main)
    yield runtime
    runtime.stop()


@pytest.fixture
def client(rt: Runtime) -> Iterator[Any]:
    with ModbusServer(rt, port=0, located=LOCATED) as server:
        found = connect(server.port)
        yield found
        found.close()


def connect(port: int) -> Any:
    """A connected pymodbus client (typed Any: pymodbus leaves connect / close unannotated)."""
    client: Any = ModbusTcpClient("127.0.0.1", port=port, timeout=10)
    assert client.connect()
    return client


def exception_code(response: Any) -> int:
    assert response.isError(), response
    return int(response.exception_code)


def test_each_table_as_codesys_maps_the_process_image(rt: Runtime, client: Any) -> None:
    rt.run(cycles=1)
    assert client.read_discrete_inputs(0, count=1).bits[0] is False  # %IX0.0
    assert client.read_discrete_inputs(3, count=1).bits[0] is True  # %IX0.3
    assert client.read_coils(0, count=1).bits[0] is False  # %QX0.0
    assert client.read_coils(10, count=1).bits[0] is True  # %QX1.2 is coil 8 * 1 + 2
    assert client.read_input_registers(0, count=1).registers == [0xFFFB]  # -5 as a 16-bit register
    assert client.read_holding_registers(1, count=1).registers == [1500]  # %QW1
    assert client.read_holding_registers(12288, count=1).registers == [0]  # %MW0 at 0x3000
    # %MD2 (registers 12292, 12293) and %MD3 (12294, 12295): the low word first
    low, high, *flow = client.read_holding_registers(12292, count=4).registers
    assert (high << 16 | low) == -70_000 & 0xFFFF_FFFF
    assert struct.unpack("<f", struct.pack("<HH", *flow))[0] == 1.5


def test_writes_are_stored_at_the_next_cycle(rt: Runtime, main: MbMain, client: Any) -> None:
    assert not client.write_register(12288, 0xFFFF).isError()  # %MW0 := -1
    assert not client.write_registers(12292, [0x2345, 0x0001]).isError()  # %MD2 := 16#12345
    flow = struct.unpack("<HH", struct.pack("<f", -2.25))
    assert not client.write_registers(12294, list(flow)).isError()
    response = client.write_coil(10, False)
    assert response.bits[0] is False  # the echo of what was taken
    assert main.nSetpoint == 0  # not before the cycle
    rt.run(cycles=1)
    assert (main.nSetpoint, main.nCounter, main.rFlow, main.bLamp) == (-1, 0x12345, -2.25, False)
    assert client.read_holding_registers(12288, count=1).registers == [0xFFFF]


def test_refusals_are_exception_2_and_store_nothing(rt: Runtime, main: MbMain, client: Any) -> None:
    assert exception_code(client.read_holding_registers(2, count=1)) == ILLEGAL_ADDRESS  # nothing at %QW2
    assert exception_code(client.read_holding_registers(0, count=2)) == ILLEGAL_ADDRESS  # %QW0 is free
    assert exception_code(client.read_input_registers(1, count=1)) == ILLEGAL_ADDRESS
    assert exception_code(client.read_discrete_inputs(0, count=4)) == ILLEGAL_ADDRESS  # %IX0.1 and 0.2 are free
    assert exception_code(client.write_register(7, 1)) == ILLEGAL_ADDRESS
    # Half a double word, and a request whose second register is free: nothing of either is stored.
    assert exception_code(client.write_register(12292, 1)) == ILLEGAL_ADDRESS
    assert exception_code(client.write_registers(12288, [5, 6])) == ILLEGAL_ADDRESS
    assert exception_code(client.write_coils(9, [True, True])) == ILLEGAL_ADDRESS
    rt.run(cycles=1)
    assert (main.nSetpoint, main.nCounter, main.bLamp) == (0, -70_000, True)


def test_a_table_moved_lets_the_master_write_the_inputs(rt: Runtime, main: MbMain) -> None:
    located = {"MAIN.bStart": "%IX0.0", "MAIN.bMotor": "%QX0.0"}
    with ModbusServer(rt, port=0, located=located, tables={"IX": ("coils", 1024)}) as server:
        client = connect(server.port)
        try:
            assert not client.write_coil(1024, True).isError()
            rt.run(cycles=2)
            assert client.read_coils(0, count=1).bits[0] is True
            assert main.bMotor is True
        finally:
            client.close()


@pytest.mark.parametrize(("located", "words"), [
    ({"MAIN.bStart": "%IX0.8"}, "bit 0..7"),
    ({"MAIN.bStart": "%IW0.1"}, "a word has no bit"),
    ({"MAIN.bStart": "I0.0"}, "no located address"),
    ({"MAIN.nLevel": "%IX0.0"}, "MAIN.nLevel is INT; at %IX0.0 it must be BOOL"),
    ({"MAIN.rFlow": "%MW0"}, "it must be INT or UINT or WORD"),
    ({"MAIN.nSpeed": "%QW1", "MAIN.nSetpoint": "%QW1"}, "are both at holding_registers 1"),
    ({"MAIN.nCounter": "%MD0", "MAIN.nSetpoint": "%MW1"}, "are both at holding_registers 12289"),
])
def test_a_bad_mapping_is_refused_at_construction(rt: Runtime, located: dict[str, str], words: str) -> None:
    with pytest.raises(ValueError, match=words):
        ModbusServer(rt, port=0, located=located)


def test_unknown_names_and_areas_are_refused(rt: Runtime) -> None:
    with pytest.raises(AccessError, match="MAIN has no member 'nothing'|no member 'nothing'"):
        ModbusServer(rt, port=0, located={"MAIN.nothing": "%IX0.0"})
    with pytest.raises(ValueError, match="the area 'ZX'"):
        ModbusServer(rt, port=0, located={}, tables={"ZX": ("coils", 0)})
    assert parse_address("%qx1.7") == ("QX", 1, 7)


def test_a_stop_leaves_no_thread_and_no_port(rt: Runtime) -> None:
    before = set(threading.enumerate())
    server = ModbusServer(rt, port=0, located=LOCATED)
    server.start()
    port = server.port
    client = connect(port)
    assert client.read_input_registers(0, count=1).registers == [0xFFFB]
    client.close()
    server.stop()
    assert [t.name for t in set(threading.enumerate()) - before] == []
    with socket.socket() as probe:
        probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        probe.bind(("127.0.0.1", port))
        probe.listen()
    assert rt.on_cycle_start == [] and rt.on_cycle_end == []


def test_a_stopped_server_keeps_nothing_alive() -> None:
    """Nothing of pymodbus holds the server, its runtime or the GVLs that runtime reaches once it is stopped."""
    runtime = Runtime(store=":memory:")
    runtime.add_task(Task("PlcTask", interval=T("10ms")), MbMain())
    server = ModbusServer(runtime, port=0, located={"MAIN.bStart": "%IX0.0"})
    server.start()
    runtime.run(cycles=1)
    server.stop()
    runtime.stop()
    gone = weakref.ref(runtime)
    del runtime, server
    gc.collect()
    assert gone() is None


class MbMarkers(Program, st_name="MAIN"):
    bFlag: BOOL = VAR(False)  # AT %MX1.3
    bIn: BOOL = VAR_INPUT(False)  # AT %IX0.0
    bOut: BOOL = VAR_OUTPUT(False)  # AT %QX0.0
    nIn: INT = VAR_INPUT(0)  # AT %IW0
    nOut: INT = VAR_OUTPUT(0)  # AT %QW0
    nMask: UINT = VAR(0x0F0F)  # AT %MW1
    nDivisor: INT = VAR_INPUT(1)  # AT %QW2

    def body(self) -> None:
        self.bOut = self.bIn
        self.nOut = self.nIn * 2 // self.nDivisor


@pytest.fixture
def markers() -> Iterator[tuple[Runtime, MbMarkers]]:
    main = MbMarkers()
    runtime = Runtime(store=":memory:")
    runtime.add_task(Task("PlcTask", interval=T("10ms")), main)
    yield runtime, main
    runtime.stop()


def test_marker_bits_are_coils_from_12288_and_a_mask_write_changes_a_register(
        markers: tuple[Runtime, MbMarkers]) -> None:
    rt, main = markers
    with ModbusServer(rt, port=0, located={"MAIN.bFlag": "%MX1.3", "MAIN.nMask": "%MW1"}) as server:
        assert [(v.table.value, v.first) for v in server.variables] == [("coils", 12288 + 11),
                                                                         ("holding_registers", 12289)]
        client = connect(server.port)
        try:
            rt.run(cycles=1)
            assert client.read_coils(12299, count=1).bits[0] is False
            assert not client.write_coil(12299, True).isError()
            # FC 22: (0x0F0F AND 0x00FF) OR (0x1000 AND NOT 0x00FF), on the value of the last cycle
            assert not client.mask_write_register(address=12289, and_mask=0x00FF, or_mask=0x1000).isError()
            rt.run(cycles=1)
            assert (main.bFlag, main.nMask) == (True, 0x100F)
            assert client.read_coils(12299, count=1).bits[0] is True
        finally:
            client.close()


def test_codesys_device_tables_let_the_master_write_the_inputs_and_read_the_outputs(
        markers: tuple[Runtime, MbMarkers]) -> None:
    from iecoop.modbus import CODESYS_DEVICE_TABLES

    rt, main = markers
    located = {"MAIN.bIn": "%IX0.0", "MAIN.bOut": "%QX0.0", "MAIN.nIn": "%IW0", "MAIN.nOut": "%QW0"}
    with ModbusServer(rt, port=0, located=located, tables=CODESYS_DEVICE_TABLES) as server:
        client = connect(server.port)
        try:
            assert not client.write_register(0, 21).isError()  # a holding register: the PLC's %IW0
            assert not client.write_coil(0, True).isError()  # a coil: the PLC's %IX0.0
            rt.run(cycles=2)
            assert (main.nIn, main.bIn, main.nOut, main.bOut) == (21, True, 42, True)
            assert client.read_input_registers(0, count=1).registers == [42]  # %QW0
            assert client.read_discrete_inputs(0, count=1).bits[0] is True  # %QX0.0
            assert client.read_holding_registers(0, count=1).registers == [21]
        finally:
            client.close()


@pytest.mark.parametrize(("located", "tables", "words"), [
    ({"MAIN.nIn": "%QW65536"}, None, "would be holding_registers 65536; Modbus addresses end at 65535"),
    ({"MAIN.nMask": "%MW53248"}, None, "would be holding_registers 65536"),
    ({"MAIN.bFlag": "%MX6656.0"}, None, "would be coils 65536"),
    ({"MAIN.nIn": "%IW0"}, {"IW": ("input_registers", 70_000)}, "a first address is 0..65535"),
])
def test_an_address_past_the_modbus_tables_is_refused_at_construction(
        markers: tuple[Runtime, MbMarkers], located: dict[str, str], tables: Any, words: str) -> None:
    with pytest.raises(ValueError, match=words):
        ModbusServer(markers[0], port=0, located=located, tables=tables)


def test_the_top_of_the_address_space_and_a_request_beyond_the_protocol_limits(
        markers: tuple[Runtime, MbMarkers]) -> None:
    rt, _ = markers
    with ModbusServer(rt, port=0, located={"MAIN.nMask": "%MW53247"}) as server:  # register 65535
        rt.run(cycles=1)
        client = connect(server.port)
        try:
            assert client.read_holding_registers(65535, count=1).registers == [0x0F0F]
            assert exception_code(client.read_holding_registers(65534, count=2)) == ILLEGAL_ADDRESS
            # 124 registers in one write is beyond Modbus's 123: exception 3, illegal data value, nothing stored
            assert exception_code(client.write_registers(65412, [1] * 124)) == 3
            rt.run(cycles=1)
            assert client.read_holding_registers(65535, count=1).registers == [0x0F0F]
        finally:
            client.close()
        # 126 registers in one read is beyond Modbus's 125: an exception, and the server goes on serving.
        with socket.create_connection(("127.0.0.1", server.port), timeout=10) as sock:
            sock.sendall(struct.pack(">HHHBBHH", 1, 0, 6, 1, 3, 65535, 126))
            reply = sock.recv(64)
            assert reply[7] & 0x80 and len(reply) == 9
            sock.sendall(struct.pack(">HHHBBHH", 2, 0, 6, 1, 3, 65535, 1))
            assert sock.recv(64)[7:] == bytes([3, 2, 0x0F, 0x0F])


def test_after_a_fault_the_master_reads_where_the_plc_stopped(markers: tuple[Runtime, MbMarkers]) -> None:
    rt, _ = markers
    located = {"MAIN.nIn": "%QW0", "MAIN.nOut": "%QW1", "MAIN.nDivisor": "%QW2"}
    with ModbusServer(rt, port=0, located=located) as server:
        client = connect(server.port)
        try:
            rt.run(cycles=1)
            assert not client.write_registers(0, [21, 0, 0]).isError()  # nDivisor := 0
            with pytest.raises(PlcException) as fault:
                rt.run(cycles=1)
            assert fault.value.code is ExceptionCode.RTSEXCPT_DIVIDEBYZERO
            assert client.read_holding_registers(0, count=3).registers == [21, 0, 0]  # the state the fault left
        finally:
            client.close()
