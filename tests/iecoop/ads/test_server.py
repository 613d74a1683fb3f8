"""The ADS server, tested with pyads (Beckhoff's ADS library for Linux inside) on 127.0.0.1.

The runtime runs in the test's own thread, one ``rt.run(cycles=1)`` at a
time, so every value a test asserts is exact; the server answers from its
thread. On Linux ``pyads.Connection.open()`` opens an AMS port and adds the
route itself; ``"127.0.0.1:PORT"`` as the address picks the server's TCP
port (48898 otherwise), so each test's server takes a free one.
"""

from __future__ import annotations

import contextlib
import gc
import socket
import struct
import threading
import weakref
import time
from collections.abc import Callable, Iterator
from typing import Any

import pytest

from iecoop import (
    ARRAY, BOOL, INT, REAL, STRING, VAR, VAR_INPUT, VAR_OUTPUT, FunctionBlock, GlobalVariables, IecEnum, Program,
    Struct, T, gvl,
)
from iecoop.ads import AdsError, AdsServer
from iecoop.runtime import Runtime, Task

pyads = pytest.importorskip("pyads")

TIMEOUT = 10.0  # seconds: the bound of any wait for something the server sends


class E_AdsMode(IecEnum, base=INT):
    IDLE = 0
    RUN = 1
    JOG = 5


class FB_AdsStation(FunctionBlock):
    bRun: BOOL = VAR_INPUT(False)
    nBottles: INT = VAR_OUTPUT(0)

    def body(self) -> None:
        if self.bRun:
            self.nBottles += 1


class ST_AdsRecipe(Struct):
    rTarget: REAL = 0.0
    nSteps: INT = 0


@gvl
class GVL_AdsIO(GlobalVariables):
    bStart: BOOL = False
    stRecipe: ST_AdsRecipe = VAR()
    aLevels: ARRAY[INT] = VAR([10, 20, 30], bounds=(1, 3))
    nLimit: INT = VAR(100, constant=True)


class AdsMain(Program, st_name="MAIN"):
    bEnable: BOOL = VAR_INPUT(False)
    nSetpoint: INT = VAR_INPUT(0)
    rSpeed: REAL = VAR_INPUT(1.5)
    sName: STRING = VAR_INPUT("line", length=10)
    eMode: E_AdsMode = VAR_INPUT(E_AdsMode.IDLE)
    nCount: INT = VAR(0)
    fbStation: FB_AdsStation = VAR()

    def body(self) -> None:
        self.fbStation(bRun=self.bEnable or GVL_AdsIO.bStart)
        self.nCount = self.fbStation.nBottles


@pytest.fixture
def rt() -> Iterator[Runtime]:
    runtime = Runtime(store=":memory:")
    runtime.add_task(Task("PlcTask", interval=T("10ms")), AdsMain())
    GVL_AdsIO.bStart = False
    GVL_AdsIO.stRecipe.rTarget = 0.0
    yield runtime
    runtime.stop()


@pytest.fixture
def server(rt: Runtime) -> Iterator[AdsServer]:
    with AdsServer(rt, port=0, writable=["MAIN.fbStation.bRun"]) as found:
        yield found


@contextlib.contextmanager
def client(server: AdsServer) -> Iterator[Any]:
    """An open pyads connection to ``server``, closed after the block."""
    connection = pyads.Connection(server.net_id, 851, f"127.0.0.1:{server.port}")
    connection.open()
    try:
        yield connection
    finally:
        connection.close()


@pytest.fixture
def plc(server: AdsServer) -> Iterator[Any]:
    with client(server) as connection:
        yield connection


def ads_code(call: Callable[[], object]) -> int:
    with pytest.raises(pyads.ADSError) as info:
        call()
    return int(info.value.err_code)


def wait_for(condition: Callable[[], bool], what: str) -> None:
    deadline = time.monotonic() + TIMEOUT
    while not condition():
        if time.monotonic() > deadline:
            raise AssertionError(f"not within {TIMEOUT} s: {what}")
        time.sleep(0.005)


def test_device_info_and_state(plc: Any) -> None:
    name, version = plc.read_device_info()
    assert name == "iecoop" and (version.version, version.revision) == (3, 1)
    assert plc.read_state() == (pyads.ADSSTATE_RUN, 0)


def test_read_by_name_with_the_plc_type_from_the_symbol(rt: Runtime, plc: Any) -> None:
    rt.run(cycles=1)
    assert plc.read_by_name("MAIN.rSpeed") == 1.5
    assert plc.read_by_name("MAIN.sName") == "line"
    assert plc.read_by_name("MAIN.bEnable") is False
    assert plc.read_by_name("GVL_AdsIO.aLevels") == [10, 20, 30]
    assert plc.read_by_name("gvl_adsio.aLevels[2]") == 20  # names match case-insensitively, as in ST
    assert plc.read_by_name("GVL_AdsIO.stRecipe.nSteps") == 0
    # An enumeration's type name is its own: the client names the base type.
    assert plc.read_by_name("MAIN.eMode", pyads.PLCTYPE_INT) == 0
    info = pyads.pyads_ex.adsGetSymbolInfo(plc._port, plc._adr, "main.fbstation.nbottles")
    assert (info.symbol_type, info.size, info.dataType) == ("INT", 2, pyads.constants.ADST_INT16)


def test_writes_land_at_the_next_cycle_start(rt: Runtime, plc: Any) -> None:
    plc.write_by_name("MAIN.bEnable", True)
    plc.write_by_name("MAIN.sName", "filler")
    plc.write_by_name("GVL_AdsIO.stRecipe.rTarget", 2.5)
    assert plc.read_by_name("MAIN.bEnable") is False  # queued: the PLC has not run a cycle since
    rt.run(cycles=3)
    assert plc.read_by_name("MAIN.nCount") == 3
    assert plc.read_by_name("MAIN.sName") == "filler"
    assert GVL_AdsIO.stRecipe.rTarget == 2.5
    plc.write_by_name("MAIN.fbStation.bRun", True)  # an FB's member, named writable
    rt.run(cycles=1)
    assert plc.read_by_name("MAIN.fbStation.bRun") is True


def test_refusals_carry_ads_error_codes_and_store_nothing(rt: Runtime, plc: Any) -> None:
    assert ads_code(lambda: plc.read_by_name("MAIN.nMissing", pyads.PLCTYPE_INT)) == 1808 == int(AdsError.SYMBOLNOTFOUND)
    assert ads_code(lambda: plc.read_by_name("NOPE.x", pyads.PLCTYPE_INT)) == AdsError.SYMBOLNOTFOUND
    assert ads_code(lambda: plc.read_by_name("MAIN.aLevels[9]", pyads.PLCTYPE_INT)) == AdsError.SYMBOLNOTFOUND
    # read-only: a program's own variable, an FB's output, a CONSTANT
    assert ads_code(lambda: plc.write_by_name("MAIN.nCount", 5, pyads.PLCTYPE_INT)) == 1827 == int(AdsError.ACCESSDENIED)
    assert ads_code(lambda: plc.write_by_name("MAIN.fbStation.nBottles", 5, pyads.PLCTYPE_INT)) == AdsError.ACCESSDENIED
    assert ads_code(lambda: plc.write_by_name("GVL_AdsIO.nLimit", 5, pyads.PLCTYPE_INT)) == AdsError.ACCESSDENIED
    # the wrong size: a DINT into an INT, a STRING longer than STRING(10)
    assert ads_code(lambda: plc.write_by_name("MAIN.nSetpoint", 5, pyads.PLCTYPE_DINT)) == 1797 == int(AdsError.INVALIDSIZE)
    assert ads_code(lambda: plc.write_by_name("MAIN.sName", "x" * 20)) == AdsError.INVALIDSIZE
    # a value the type cannot hold: 3 is no E_AdsMode
    assert ads_code(lambda: plc.write_by_name("MAIN.eMode", 3, pyads.PLCTYPE_INT)) == 1798 == int(AdsError.INVALIDDATA)
    assert ads_code(lambda: plc.read(0x1234, 0, pyads.PLCTYPE_INT)) == AdsError.INVALIDGRP
    assert ads_code(lambda: plc.write_control(pyads.ADSSTATE_STOP, 0, 0, pyads.PLCTYPE_INT)) == AdsError.SRVNOTSUPP
    rt.run(cycles=1)
    assert plc.read_by_name("MAIN.nSetpoint") == 0 and plc.read_by_name("MAIN.eMode", pyads.PLCTYPE_INT) == 0
    assert plc.read_by_name("MAIN.sName") == "line"


def test_handles(rt: Runtime, plc: Any) -> None:
    handle = plc.get_handle("MAIN.nSetpoint")
    plc.write_by_name("", 42, pyads.PLCTYPE_INT, handle=handle)
    rt.run(cycles=1)
    assert plc.read_by_name("", pyads.PLCTYPE_INT, handle=handle) == 42
    plc.release_handle(handle)
    assert ads_code(lambda: plc.read_by_name("", pyads.PLCTYPE_INT, handle=handle)) == AdsError.SYMBOLNOTFOUND
    assert ads_code(lambda: plc.release_handle(handle)) == AdsError.SYMBOLNOTFOUND


def test_symbol_upload_names_types_sizes_and_addresses(rt: Runtime, plc: Any) -> None:
    rt.run(cycles=1)
    symbols = {symbol.name: symbol for symbol in plc.get_all_symbols()}
    assert [name for name in symbols if name.startswith("MAIN.")] == [
        "MAIN.bEnable", "MAIN.nSetpoint", "MAIN.rSpeed", "MAIN.sName", "MAIN.eMode", "MAIN.nCount", "MAIN.fbStation"]
    assert {name: symbols[name].symbol_type for name in ("MAIN.sName", "MAIN.eMode", "MAIN.fbStation",
                                                         "GVL_AdsIO.aLevels", "GVL_AdsIO.stRecipe")} == {
        "MAIN.sName": "STRING(10)", "MAIN.eMode": "E_AdsMode", "MAIN.fbStation": "FB_AdsStation",
        "GVL_AdsIO.aLevels": "ARRAY [1..3] OF INT", "GVL_AdsIO.stRecipe": "ST_AdsRecipe"}
    levels = symbols["GVL_AdsIO.aLevels"]
    assert levels.index_group == 0x4040
    # The address is the variable: a read by index group / offset gives what a read by name gives.
    assert plc.read(levels.index_group, levels.index_offset, pyads.PLCTYPE_INT * 3) == [10, 20, 30]
    speed = symbols["MAIN.rSpeed"]
    assert plc.read(speed.index_group, speed.index_offset, pyads.PLCTYPE_REAL) == 1.5
    plc.write(speed.index_group, speed.index_offset, 4.0, pyads.PLCTYPE_REAL)
    rt.run(cycles=1)
    assert plc.read_by_name("MAIN.rSpeed") == 4.0
    # By address too, the bytes must be one whole writable variable.
    assert ads_code(lambda: plc.write(speed.index_group, speed.index_offset + 1, 1, pyads.PLCTYPE_INT)) \
        == AdsError.INVALIDACCESS


def test_sum_read_and_sum_write_all_or_nothing(rt: Runtime, plc: Any) -> None:
    rt.run(cycles=1)
    names = ["MAIN.rSpeed", "MAIN.sName", "GVL_AdsIO.aLevels", "MAIN.nCount"]
    assert plc.read_list_by_name(names) == {
        "MAIN.rSpeed": 1.5, "MAIN.sName": "line", "GVL_AdsIO.aLevels": [10, 20, 30], "MAIN.nCount": 0}
    assert plc.write_list_by_name({"MAIN.rSpeed": 3.0, "GVL_AdsIO.aLevels": [1, 2, 3]}) == {
        "MAIN.rSpeed": "no error", "GVL_AdsIO.aLevels": "no error"}
    # One refused sub-write: none is stored, and the others say they were aborted.
    result = plc.write_list_by_name({"MAIN.nSetpoint": 7, "MAIN.nCount": 9, "MAIN.sName": "batch"})
    assert result == {"MAIN.nSetpoint": "request is aborted", "MAIN.nCount": "access denied",
                      "MAIN.sName": "request is aborted"}
    rt.run(cycles=1)
    assert plc.read_list_by_name(["MAIN.rSpeed", "GVL_AdsIO.aLevels", "MAIN.nSetpoint", "MAIN.sName"]) == {
        "MAIN.rSpeed": 3.0, "GVL_AdsIO.aLevels": [1, 2, 3], "MAIN.nSetpoint": 0, "MAIN.sName": "line"}


def test_a_sum_read_is_one_cycle(rt: Runtime, server: AdsServer, plc: Any) -> None:
    """Every sub-read of one sum read comes from the same cycle, while the PLC runs in the background."""
    plc.write_by_name("MAIN.bEnable", True)
    with rt.running(realtime=False):
        for _ in range(50):
            values = plc.read_list_by_name(["MAIN.nCount", "MAIN.fbStation.nBottles"])
            assert values["MAIN.nCount"] == values["MAIN.fbStation.nBottles"]


def test_notifications_on_change_and_cyclic(rt: Runtime, plc: Any) -> None:
    changes: list[int] = []
    ticks: list[int] = []
    arrived = threading.Condition()

    def keep(into: list[int]) -> Callable[[Any, str], None]:
        def callback(notification: Any, name: str) -> None:
            with arrived:
                into.append(plc.parse_notification(notification, pyads.PLCTYPE_INT)[2])
                arrived.notify_all()
        return callback

    def wait(what: list[int], count: int) -> None:
        with arrived:
            assert arrived.wait_for(lambda: len(what) >= count, TIMEOUT), f"{len(what)} notifications of {count}"

    on_change = plc.add_device_notification("MAIN.nCount", pyads.NotificationAttrib(2), keep(changes))
    try:
        rt.run(cycles=1)
        wait(changes, 1)  # the first sample is the value at the next cycle
        plc.write_by_name("MAIN.bEnable", True)
        for count in range(2, 6):
            rt.run(cycles=1)
            wait(changes, count)
        rt.run(cycles=1)
        plc.write_by_name("MAIN.bEnable", False)
        rt.run(cycles=3)  # the count stops at 5: no sample for cycles that change nothing
        wait(changes, 6)
    finally:
        plc.del_device_notification(*on_change)
    assert changes == [0, 1, 2, 3, 4, 5]
    # Cyclic: every 10 ms whether the value changed or not.
    attrib = pyads.NotificationAttrib(2, trans_mode=pyads.ADSTRANS_SERVERCYCLE, cycle_time=10)
    cyclic = plc.add_device_notification("MAIN.nSetpoint", attrib, keep(ticks))
    try:
        wait(ticks, 3)
    finally:
        plc.del_device_notification(*cyclic)
    assert set(ticks) == {0} and changes == [0, 1, 2, 3, 4, 5]


def test_a_stop_leaves_no_thread_and_no_port(rt: Runtime) -> None:
    before = set(threading.enumerate())
    server = AdsServer(rt, port=0)
    server.start()
    port = server.port
    plc = pyads.Connection(server.net_id, 851, f"127.0.0.1:{port}")
    plc.open()
    assert plc.read_by_name("MAIN.nSetpoint") == 0
    plc.close()
    server.stop()
    assert [t.name for t in set(threading.enumerate()) - before if t.name.startswith("iecoop ADS")] == []
    with socket.socket() as probe:
        probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        probe.bind(("127.0.0.1", port))
        probe.listen()
    assert rt.on_cycle_start == [] and rt.on_cycle_end == []
    with AdsServer(rt, port=port):  # and a server can serve there again
        pass


def _frame(command: int, data: bytes, invoke: int = 1, port: int = 851) -> bytes:
    header = bytes([127, 0, 0, 1, 1, 1]) + struct.pack("<H", port) + bytes([10, 0, 0, 9, 1, 1]) + struct.pack(
        "<HHHIII", 30000, command, 4, len(data), 0, invoke)
    return struct.pack("<HI", 0, len(header) + len(data)) + header + data


class _Replies:
    """The frames a raw socket receives, one at a time, however TCP cut them."""

    def __init__(self, sock: socket.socket) -> None:
        self.sock = sock
        self.buffer = b""

    def next(self) -> tuple[int, int, bytes]:
        """(invoke id, AMS error, ADS data) of the next frame the server sends."""
        while len(self.buffer) < 6 or len(self.buffer) < 6 + struct.unpack_from("<I", self.buffer, 2)[0]:
            chunk = self.sock.recv(65536)
            assert chunk, "the server closed the connection"
            self.buffer += chunk
        _t, _tp, _s, _sp, _cmd, flags, length, error, invoke = struct.unpack_from("<6sH6sHHHIII", self.buffer, 6)
        assert flags == 5
        data = self.buffer[38 : 38 + length]
        self.buffer = self.buffer[38 + length :]
        return invoke, error, data


def test_the_stream_is_framed_whatever_the_segments(server: AdsServer) -> None:
    """A frame split across segments, two in one, a wrong port; a frame too long drops the connection."""
    with socket.create_connection(("127.0.0.1", server.port), timeout=TIMEOUT) as sock:
        replies = _Replies(sock)
        state = _frame(4, b"", invoke=7)
        sock.sendall(state[:10])
        time.sleep(0.01)
        sock.sendall(state[10:] + _frame(4, b"", invoke=8) + _frame(4, b"", invoke=9, port=852))
        assert replies.next() == (7, 0, struct.pack("<IHH", 0, 5, 0))
        assert replies.next()[0] == 8
        assert replies.next()[:2] == (9, AdsError.TARGET_PORT_NOT_FOUND)
        sock.sendall(_frame(0x77, b"", invoke=10))
        assert replies.next()[:2] == (10, AdsError.UNKNOWN_COMMAND)
        sock.sendall(_frame(2, b"\x00\x40", invoke=11))  # a READ cut short
        assert replies.next() == (11, 0, struct.pack("<II", AdsError.INVALIDSIZE, 0))
        sock.sendall(struct.pack("<HI", 0, 1 << 30))
        assert sock.recv(10) == b""  # dropped, not waiting for a gigabyte


def test_the_symbol_table_rejects_a_pattern_matching_nothing(rt: Runtime) -> None:
    with pytest.raises(ValueError, match="'MAIN.nope' matches no variable"):
        AdsServer(rt, writable=["MAIN.nope"])


def test_a_stopped_server_keeps_nothing_alive() -> None:
    runtime = Runtime(store=":memory:")
    runtime.add_task(Task("PlcTask", interval=T("10ms")), AdsMain())
    with AdsServer(runtime, port=0) as server:
        plc = pyads.Connection(server.net_id, 851, f"127.0.0.1:{server.port}")
        plc.open()
        assert plc.read_by_name("MAIN.nSetpoint") == 0
        plc.close()
    runtime.stop()
    gone = weakref.ref(runtime)
    del runtime, server
    gc.collect()
    assert gone() is None
