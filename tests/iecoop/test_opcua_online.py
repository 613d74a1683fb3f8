"""TwinCAT's online write and force over OPC UA: off by default, ``OpcUaServer(online=True)``.

With it, a client writes any variable but a CONSTANT and calls
``Online.Force(path, value)`` / ``Online.Release(path, restore)``: the
force is the runtime's own (``rt.forced``), taken whole at the next cycle
start; a refused one forces nothing. The client is asyncua's synchronous
one; the runtime runs in the test's thread, a cycle at a time.
"""

from __future__ import annotations

import socket
import threading
import time
from collections.abc import Callable, Iterator
from typing import Any

import pytest

from iecoop import ARRAY, BOOL, INT, VAR, VAR_INPUT, VAR_OUTPUT, ExceptionCode, PlcException, Program, T
from iecoop.runtime import Runtime, Task

asyncua = pytest.importorskip("asyncua")
from asyncua import ua  # noqa: E402  (after the skip)
from asyncua.sync import Client  # noqa: E402

from iecoop.opcua import NAMESPACE, OpcUaServer  # noqa: E402

TIMEOUT = 30.0  # seconds: the bound of a wait for a published value


class UaOnlineMain(Program, st_name="MAIN"):
    bFill: BOOL = VAR_INPUT(False)
    bPump: BOOL = VAR_OUTPUT(False)
    nCount: INT = VAR(0)
    aLevels: ARRAY[INT] = VAR([1, 2, 3], bounds=(1, 3))
    nMax: INT = VAR(10, constant=True)
    nDivisor: INT = VAR_INPUT(1)
    nShare: INT = VAR(0)

    def body(self) -> None:
        self.bPump = self.bFill
        self.nCount += 1
        self.nShare = 100 // self.nDivisor


@pytest.fixture
def main() -> UaOnlineMain:
    return UaOnlineMain()


@pytest.fixture
def rt(main: UaOnlineMain) -> Iterator[Runtime]:
    runtime = Runtime(store=":memory:")
    runtime.add_task(Task("PlcTask", interval=T("10ms")), main)
    yield runtime
    runtime.stop()


def connected(server: OpcUaServer) -> tuple[Any, int]:
    client: Any = Client(server.endpoint, timeout=TIMEOUT)
    client.connect()
    return client, client.get_namespace_index(NAMESPACE)


def wait_for(condition: Callable[[], bool], what: str) -> None:
    deadline = time.monotonic() + TIMEOUT
    while not condition():
        assert time.monotonic() < deadline, f"not within {TIMEOUT} s: {what}"
        time.sleep(0.01)


def status(call: Callable[[], object]) -> str:
    with pytest.raises(ua.UaStatusCodeError) as info:
        call()
    return type(info.value).__name__


def test_online_is_off_by_default(rt: Runtime) -> None:
    with OpcUaServer(rt, endpoint="opc.tcp://127.0.0.1:0") as server:
        client, idx = connected(server)
        try:
            pump = client.get_node(ua.NodeId("PlcTask.MAIN.bPump", idx))
            assert status(lambda: pump.write_value(ua.Variant(True, ua.VariantType.Boolean))) == "BadNotWritable"
            assert status(lambda: client.get_node(ua.NodeId("Online", idx)).read_browse_name()) == "BadNodeIdUnknown"
        finally:
            client.disconnect()
        assert "PlcTask.MAIN.bPump" not in server.writable()


@pytest.fixture
def online(rt: Runtime) -> Iterator[tuple[OpcUaServer, Any, int]]:
    with OpcUaServer(rt, endpoint="opc.tcp://127.0.0.1:0", online=True) as server:
        client, idx = connected(server)
        try:
            yield server, client, idx
        finally:
            client.disconnect()


def test_online_a_client_writes_outputs_and_internals_never_a_constant(
        rt: Runtime, main: UaOnlineMain, online: tuple[OpcUaServer, Any, int]) -> None:
    server, client, idx = online
    assert {"PlcTask.MAIN.bPump", "PlcTask.MAIN.nCount"} <= set(server.writable())
    assert "PlcTask.MAIN.nMax" not in server.writable()
    client.get_node(ua.NodeId("PlcTask.MAIN.nCount", idx)).write_value(ua.Variant(100, ua.VariantType.Int64))
    rt.run(cycles=1)
    assert main.nCount == 101
    nmax = client.get_node(ua.NodeId("PlcTask.MAIN.nMax", idx))
    assert status(lambda: nmax.write_value(ua.Variant(1, ua.VariantType.Int64))) == "BadNotWritable"


def test_force_and_release_through_the_online_methods(
        rt: Runtime, main: UaOnlineMain, online: tuple[OpcUaServer, Any, int]) -> None:
    server, client, idx = online
    methods = client.get_node(ua.NodeId("Online", idx))
    force, release = ua.NodeId("Online.Force", idx), ua.NodeId("Online.Release", idx)
    methods.call_method(force, "PlcTask.MAIN.bPump", ua.Variant(True, ua.VariantType.Boolean))
    methods.call_method(force, "PlcTask.MAIN.aLevels", ua.Variant([7, 8, 9], ua.VariantType.Int64))
    assert rt.forced == {}  # taken; forced from the next cycle start
    rt.run(cycles=2)
    assert main.bPump is True  # bFill is FALSE: the program writes FALSE, the force holds TRUE
    assert rt.forced == {"PlcTask.MAIN.bPump": True, "PlcTask.MAIN.aLevels[1]": 7, "PlcTask.MAIN.aLevels[2]": 8,
                         "PlcTask.MAIN.aLevels[3]": 9}
    server.wait_published(TIMEOUT)
    pump = client.get_node(ua.NodeId("PlcTask.MAIN.bPump", idx))
    wait_for(lambda: pump.read_value() is True, "the client reads the forced value")
    methods.call_method(release, "PlcTask.MAIN.bPump", False)  # <Unforce>: the program's FALSE comes back
    methods.call_method(release, "PlcTask.MAIN.aLevels", True)  # <Unforce and restore>: 1, 2, 3 again
    rt.run(cycles=1)
    assert (rt.forced, main.bPump) == ({}, False)
    assert [rt.symbol(f"MAIN.aLevels[{i}]").load() for i in (1, 2, 3)] == [1, 2, 3]


def test_a_refused_force_forces_nothing(rt: Runtime, online: tuple[OpcUaServer, Any, int]) -> None:
    _server, client, idx = online
    methods = client.get_node(ua.NodeId("Online", idx))
    force = ua.NodeId("Online.Force", idx)
    refused = [
        ("PlcTask.MAIN.nCount", ua.Variant(70_000, ua.VariantType.Int64), "BadOutOfRange"),
        ("PlcTask.MAIN.aLevels", ua.Variant([1, 2], ua.VariantType.Int64), "BadTypeMismatch"),
        ("PlcTask.MAIN.bPump", ua.Variant(1, ua.VariantType.Int64), "BadTypeMismatch"),
        ("PlcTask.MAIN.nMax", ua.Variant(1, ua.VariantType.Int64), "BadNotWritable"),
        ("PlcTask.MAIN.nothing", ua.Variant(1, ua.VariantType.Int64), "BadNodeIdUnknown"),
    ]
    for path, value, code in refused:
        assert status(lambda: methods.call_method(force, path, value)) == code, path
    rt.run(cycles=1)
    assert rt.forced == {}


def test_a_stop_after_a_force_leaves_no_thread_and_no_port(rt: Runtime) -> None:
    before = set(threading.enumerate())
    with OpcUaServer(rt, endpoint="opc.tcp://127.0.0.1:0", online=True) as server:
        port = server.port
        client, idx = connected(server)
        try:
            methods = client.get_node(ua.NodeId("Online", idx))
            methods.call_method(ua.NodeId("Online.Force", idx), "PlcTask.MAIN.bPump", True)
            rt.run(cycles=1)  # taken at this cycle's start (a stop drops what no cycle has taken yet)
        finally:
            client.disconnect()
    rt.run(cycles=1)
    assert rt.forced == {"PlcTask.MAIN.bPump": True}  # the force is the runtime's: it outlives the server
    assert [t.name for t in set(threading.enumerate()) - before if t.is_alive()] == []
    with socket.socket() as probe:
        probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        probe.bind(("127.0.0.1", port))


def test_after_a_fault_clients_read_where_the_plc_stopped(rt: Runtime) -> None:
    with OpcUaServer(rt, endpoint="opc.tcp://127.0.0.1:0") as server:
        client, idx = connected(server)
        try:
            rt.run(cycles=1)
            divisor = client.get_node(ua.NodeId("PlcTask.MAIN.nDivisor", idx))
            count = client.get_node(ua.NodeId("PlcTask.MAIN.nCount", idx))
            wait_for(lambda: count.read_value() == 1, "the first cycle published")
            divisor.write_value(ua.Variant(0, ua.VariantType.Int64))  # an input: writable by default
            with pytest.raises(PlcException) as fault:
                rt.run(cycles=1)
            assert fault.value.code is ExceptionCode.RTSEXCPT_DIVIDEBYZERO
            # The faulted cycle never ended, yet its state is what a client now reads: the cause, and the count.
            wait_for(lambda: divisor.read_value() == 0 and count.read_value() == 2, "the faulted cycle published")
        finally:
            client.disconnect()
