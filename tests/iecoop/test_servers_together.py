"""OPC UA, ADS and Modbus TCP served at once by a runtime running in the background with a plant model.

The PLC fills a tank with a pump; the plant model (an ``on_cycle_end``
hook) raises the level while the pump runs. A force of the pump, made
online, is what all three clients read, and so is one a client makes (over
ADS, released over OPC UA); a stop leaves no thread and no port.
"""

from __future__ import annotations

import socket
import threading
import time
from collections.abc import Callable
from typing import Any

import pytest

from iecoop import BOOL, INT, VAR, VAR_INPUT, Program, T
from iecoop.runtime import Runtime, Task

asyncua = pytest.importorskip("asyncua")
pyads = pytest.importorskip("pyads")
pytest.importorskip("pymodbus")
from asyncua.sync import Client as OpcUaClient  # noqa: E402  (after the skips)
from pymodbus.client import ModbusTcpClient  # noqa: E402

from iecoop.ads import AdsServer  # noqa: E402
from iecoop.ads.protocol import IndexGroup  # noqa: E402
from iecoop.modbus import ModbusServer  # noqa: E402
from iecoop.opcua import NAMESPACE, OpcUaServer  # noqa: E402

TIMEOUT = 30.0  # seconds: the bound of any wait for the PLC or a server


class TankMain(Program, st_name="MAIN"):
    bFill: BOOL = VAR_INPUT(False)  # AT %IX0.0
    nLevel: INT = VAR_INPUT(0)  # AT %IW0: the plant's level sensor
    bPump: BOOL = VAR(False)  # AT %QX0.0

    def body(self) -> None:
        self.bPump = self.bFill and self.nLevel < 100


def wait_for(condition: Callable[[], bool], what: str) -> None:
    deadline = time.monotonic() + TIMEOUT
    while not condition():
        assert time.monotonic() < deadline, f"not within {TIMEOUT} s: {what}"
        time.sleep(0.01)


def test_three_servers_one_force_and_a_clean_stop() -> None:
    before = set(threading.enumerate())
    main = TankMain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), main)

    def plant() -> None:  # the tank: the pump raises the level by one a cycle
        if main.bPump:
            main.nLevel += 1

    rt.on_cycle_end.append(plant)
    located = {"MAIN.bFill": "%IX0.0", "MAIN.nLevel": "%IW0", "MAIN.bPump": "%QX0.0"}
    opcua = OpcUaServer(rt, endpoint="opc.tcp://127.0.0.1:0", online=True)
    ads = AdsServer(rt, port=0, online=True)
    modbus = ModbusServer(rt, port=0, located=located)
    ports = []
    with opcua, ads, modbus, rt.running():
        ports = [opcua.port, ads.port, modbus.port]
        ua_client: Any = OpcUaClient(opcua.endpoint)
        ua_client.connect()
        plc = pyads.Connection(ads.net_id, 851, f"127.0.0.1:{ads.port}")
        plc.open()
        mb: Any = ModbusTcpClient("127.0.0.1", port=modbus.port, timeout=10)
        assert mb.connect()
        try:
            index = ua_client.get_namespace_index(NAMESPACE)
            pump = ua_client.get_node(asyncua.ua.NodeId("PlcTask.MAIN.bPump", index))
            assert pump.read_value() is False and plc.read_by_name("MAIN.bPump") is False
            rt.force("MAIN.bPump", True)  # the pump forced on: the plant fills, every client sees it
            wait_for(lambda: plc.read_by_name("MAIN.bPump") is True, "ADS sees the force")
            wait_for(lambda: pump.read_value() is True, "OPC UA sees the force")
            wait_for(lambda: mb.read_coils(0, count=1).bits[0] is True, "Modbus sees the force")
            wait_for(lambda: mb.read_input_registers(0, count=1).registers[0] > 3, "the plant fills the tank")
            rt.release("MAIN.bPump")  # bFill is FALSE: the program switches the pump off
            wait_for(lambda: plc.read_by_name("MAIN.bPump") is False, "ADS sees the release")
            wait_for(lambda: mb.read_coils(0, count=1).bits[0] is False, "Modbus sees the release")
            wait_for(lambda: pump.read_value() is False, "OPC UA sees the release")
            # A force made by a client is the runtime's: forced over ADS, released over OPC UA.
            plc.write(IndexGroup.FORCE_BYHND, plc.get_handle("MAIN.bPump"), True, pyads.PLCTYPE_BOOL)
            wait_for(lambda: mb.read_coils(0, count=1).bits[0] is True, "Modbus sees the ADS client's force")
            wait_for(lambda: pump.read_value() is True, "OPC UA sees the ADS client's force")
            assert rt.forced == {"MAIN.bPump": True}
            online = ua_client.get_node(asyncua.ua.NodeId("Online", index))
            online.call_method(asyncua.ua.NodeId("Online.Release", index), "PlcTask.MAIN.bPump", False)
            wait_for(lambda: plc.read_by_name("MAIN.bPump") is False, "ADS sees the OPC UA client's release")
            assert rt.forced == {}
        finally:
            mb.close()
            plc.close()
            ua_client.disconnect()
    assert rt.on_cycle_start == [] and rt.on_cycle_end == [plant]
    left = [t for t in set(threading.enumerate()) - before if t.is_alive()]
    assert left == [], left
    for port in ports:
        with socket.socket() as probe:
            probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            probe.bind(("127.0.0.1", port))
            probe.listen()
    rt.stop()
