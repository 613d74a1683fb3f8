"""The OPC UA server, tested with a real asyncua client on 127.0.0.1.

One server (and one connected client) serves most tests of this module:
starting asyncua takes about a second. Each test re-initialises the PLC
(reset origin) and runs it in virtual time unless it is about real time, so
the values it asserts are exact. The client runs its own event loop in a
thread; ``Client.call`` runs one of its coroutines and waits, bounded.
"""

from __future__ import annotations

import asyncio
import datetime
import importlib
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path
from collections.abc import Callable, Coroutine, Iterator
from typing import Any

import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from iecoop import (
    ARRAY, BOOL, DINT, DT, INT, LINT, LREAL, REAL, SINT, STRING, TIME, TOD, UDINT, UINT, ULINT, USINT, VAR,
    VAR_INPUT, VAR_OUTPUT, FunctionBlock, GlobalVariables, IecEnum, Program, Struct, T, gvl,
)
from iecoop.runtime import Runtime, Task
from iecoop.stdlib import TON

asyncua = pytest.importorskip("asyncua")
ua = asyncua.ua
from iecoop.opcua import NAMESPACE, OpcUaServer  # noqa: E402  (after the skip when asyncua is missing)

TIMEOUT = 10.0  # seconds: the bound of any one client call or wait
CLIENT_URI = "urn:iecoop:test-client"


class OpcState(IecEnum, base=INT):
    IDLE = 0
    RUNNING = 1
    FAULT = 2


class Sparse(IecEnum, base=USINT):
    LOW = 1
    HIGH = 10


class OpcPoint(Struct):
    x: REAL = 1.5
    y: LREAL = 2.5


class OpcAxis(FunctionBlock):
    target: LREAL = VAR_INPUT(0.0)
    position: LREAL = VAR_OUTPUT(0.0)

    def body(self) -> None:
        self.position = self.target


@gvl
class GVL_OpcPlant(GlobalVariables):
    speed: REAL = 0.5
    limit: INT = VAR(100, constant=True)


class OpcMain(Program):
    """Counts by ``step`` every cycle; ``half`` changes every other cycle; ``a`` and ``b`` are set apart."""

    step: INT = VAR_INPUT(1)
    mode: OpcState = VAR_INPUT(OpcState.IDLE)
    recipe: STRING = VAR_INPUT("bread", length=8)
    gains: ARRAY[INT] = VAR_INPUT(bounds=(1, 3))
    count: DINT = VAR_OUTPUT(0)
    half: DINT = VAR_OUTPUT(0)
    used: INT = VAR(0)
    a: DINT = VAR(0)
    b: DINT = VAR(0)
    flag: BOOL = VAR(True)
    small: SINT = VAR(-3)
    big: LINT = VAR(-(2**40))
    ubyte: USINT = VAR(200)
    uint: UINT = VAR(60000)
    udint: UDINT = VAR(4_000_000_000)
    ulint: ULINT = VAR(2**63)
    delay: TIME = VAR(T("1s500ms"))
    daytime: TOD = VAR(3_600_000)
    stamp: DT = VAR(86_400)
    level: Sparse = VAR(Sparse.HIGH)
    grid: ARRAY[INT] = VAR([1, 2, 3, 4, 5, 6], bounds=((1, 2), (0, 2)))
    where: OpcPoint = VAR()
    axes: ARRAY[OpcAxis] = VAR(bounds=(1, 2))
    timer: TON = VAR()

    def body(self) -> None:
        self.a = self.count
        self.used = self.step
        self.count += self.step
        self.half = self.count // 2
        self.timer(IN=True, PT=T("1s"))
        for i in (1, 2):
            self.axes[i](target=float(self.count))
        self.b = self.a


class OpcSecond(Program):
    """A second program of the task: copies ``OpcMain.count`` late in the cycle."""

    seen: DINT = VAR(0)

    def body(self) -> None:
        self.seen = MAIN.count


MAIN = OpcMain()
SECOND = OpcSecond()
#: Integer variables a client may write (``step`` an input, the others through ``writable=``) and their ranges.
INTEGERS = {
    "step": (-(2**15), 2**15 - 1), "small": (-128, 127), "big": (-(2**63), 2**63 - 1),
    "ubyte": (0, 255), "uint": (0, 2**16 - 1), "udint": (0, 2**32 - 1), "ulint": (0, 2**64 - 1),
}


class Client:
    """An asyncua client on its own event loop thread; ``call`` runs a coroutine there and waits for it."""

    def __init__(self, endpoint: str, *, security: tuple[Path, Path] | None = None, **login: str) -> None:
        self.loop = asyncio.new_event_loop()
        self.thread = threading.Thread(target=self.loop.run_forever, name="test OPC UA client")
        self.thread.start()
        self.client: Any = asyncua.Client(endpoint, timeout=TIMEOUT)
        if login:
            self.client.set_user(login["user"])
            self.client.set_password(login["password"])
        try:
            if security is not None:
                self.client.application_uri = CLIENT_URI
                policy = asyncua.crypto.security_policies.SecurityPolicyBasic256Sha256
                self.call(self.client.set_security(policy, certificate=str(security[0]), private_key=str(security[1])))
            self.call(self.client.connect())
            self.ns = self.call(self.client.get_namespace_index(NAMESPACE))
        except BaseException:
            self.close(connected=False)
            raise

    def call(self, coro: Coroutine[Any, Any, Any]) -> Any:
        return asyncio.run_coroutine_threadsafe(coro, self.loop).result(TIMEOUT)

    def node(self, path: str) -> Any:
        return self.client.get_node(ua.NodeId(path, self.ns))

    def read(self, path: str) -> Any:
        return self.call(self.node(path).read_value())

    def write(self, path: str, value: Any, vtype: Any) -> Any:
        """The status code of writing ``value`` as ``vtype`` to ``path``."""
        node = self.node(path)

        async def go() -> Any:
            datavalue = ua.DataValue(ua.Variant(value, vtype))
            params = ua.WriteParameters(NodesToWrite=[ua.WriteValue(node.nodeid, ua.AttributeIds.Value, Value=datavalue)])
            return (await self.client.uaclient.write(params))[0]

        return self.call(go())

    def close(self, connected: bool = True) -> None:
        if connected:
            self.call(self.client.disconnect())
        self.loop.call_soon_threadsafe(self.loop.stop)
        self.thread.join(TIMEOUT)
        self.loop.close()


def wait_until(condition: Callable[[], bool], what: str) -> None:
    deadline = time.monotonic() + TIMEOUT
    while not condition():
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out waiting for {what}")
        time.sleep(0.01)


@pytest.fixture(scope="module")
def served() -> Iterator[tuple[Runtime, OpcUaServer, Client]]:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), MAIN, SECOND)
    named = ["PlcTask.OpcMain.where.*", "PlcTask.OpcMain.stamp"]
    named += [f"PlcTask.OpcMain.{name}" for name in INTEGERS if name != "step"]
    # No program here uses GVL_OpcPlant: named, the server shows it too.
    with OpcUaServer(rt, endpoint="opc.tcp://127.0.0.1:0", writable=named, gvls=[GVL_OpcPlant]) as server:
        client = Client(server.endpoint)
        try:
            yield rt, server, client
        finally:
            client.close()


@pytest.fixture
def opc(served: tuple[Runtime, OpcUaServer, Client]) -> Iterator[tuple[Runtime, OpcUaServer, Client]]:
    rt, server, client = served
    rt.reset_origin()
    yield served


def cycles(rt: Runtime, server: OpcUaServer, n: int) -> None:
    rt.run(cycles=n)
    server.wait_published(TIMEOUT)


# -- the address space ----------------------------------------------------------


def test_programs_gvls_fbs_and_structs_are_objects_with_st_browse_names(opc: Any) -> None:
    rt, server, client = opc
    assert client.ns == server.namespace_index >= 1

    def children(node: Any) -> dict[str, Any]:
        found = client.call(node.get_children())
        return {client.call(n.read_browse_name()).Name: n for n in found}

    top = children(client.client.nodes.objects)
    assert {"PlcTask", "GVL_OpcPlant"} <= set(top)
    programs = children(top["PlcTask"])
    assert set(programs) == {"OpcMain", "OpcSecond"}
    main = children(programs["OpcMain"])
    assert {"step", "mode", "count", "half", "where", "axes", "timer", "grid", "ubyte"} <= set(main)
    assert client.call(main["where"].read_node_class()) == ua.NodeClass.Object
    assert client.call(main["count"].read_node_class()) == ua.NodeClass.Variable
    assert set(children(main["timer"])) >= {"IN", "PT", "Q", "ET"}
    assert set(children(main["axes"])) == {"axes[1]", "axes[2]"}
    axis = children(children(main["axes"])["axes[2]"])
    assert axis["position"].nodeid == ua.NodeId("PlcTask.OpcMain.axes[2].position", client.ns)
    assert main["count"].nodeid == ua.NodeId("PlcTask.OpcMain.count", client.ns)
    assert set(children(top["GVL_OpcPlant"])) == {"speed", "limit"}


@pytest.mark.parametrize(
    ("name", "vtype"),
    [
        ("flag", "Boolean"), ("small", "SByte"), ("used", "Int16"), ("count", "Int32"), ("big", "Int64"),
        ("ubyte", "Byte"), ("uint", "UInt16"), ("udint", "UInt32"), ("ulint", "UInt64"),
        ("where.x", "Float"), ("where.y", "Double"), ("recipe", "String"), ("delay", "Int64"),
        ("daytime", "UInt32"), ("stamp", "DateTime"), ("mode", "Int16"), ("level", "Byte"), ("gains", "Int16"),
    ],
)
def test_iec_types_map_to_opc_ua_types(opc: Any, name: str, vtype: str) -> None:
    rt, server, client = opc
    node = client.node(f"PlcTask.OpcMain.{name}")
    assert client.call(node.read_data_type_as_variant_type()) == ua.VariantType[vtype]
    assert client.call(node.read_data_value()).Value.VariantType == ua.VariantType[vtype]


def test_arrays_have_their_rank_and_dimensions_and_enums_their_names(opc: Any) -> None:
    rt, server, client = opc
    gains, grid = client.node("PlcTask.OpcMain.gains"), client.node("PlcTask.OpcMain.grid")
    assert client.call(gains.read_value_rank()) == 1
    assert client.call(gains.read_array_dimensions()) == [3]
    assert client.call(grid.read_value_rank()) == 2
    assert client.call(grid.read_array_dimensions()) == [2, 3]
    strings = client.call(client.node("PlcTask.OpcMain.mode").get_child("0:EnumStrings"))
    assert [t.Text for t in client.call(strings.read_value())] == ["IDLE", "RUNNING", "FAULT"]
    # 1 and 10 are not 0..n-1: the value / name pairs are EnumValues.
    pairs = client.call(client.call(client.node("PlcTask.OpcMain.level").get_child("0:EnumValues")).read_value())
    assert [(p.Value, p.DisplayName.Text) for p in pairs] == [(1, "LOW"), (10, "HIGH")]


def test_read_gives_the_values_of_the_last_cycle(opc: Any) -> None:
    rt, server, client = opc
    cycles(rt, server, 7)
    assert client.read("PlcTask.OpcMain.count") == MAIN.count == 7
    assert client.read("PlcTask.OpcSecond.seen") == 7
    assert client.read("PlcTask.OpcMain.grid") == [[1, 2, 3], [4, 5, 6]]
    assert client.read("PlcTask.OpcMain.gains") == [0, 0, 0]
    assert client.read("PlcTask.OpcMain.where.x") == 1.5
    assert client.read("PlcTask.OpcMain.axes[2].position") == 7.0
    assert client.read("PlcTask.OpcMain.timer.ET") == 60  # ms: TIME is Int64 milliseconds
    assert client.read("PlcTask.OpcMain.delay") == 1500
    assert client.read("PlcTask.OpcMain.ulint") == 2**63
    assert client.read("PlcTask.OpcMain.recipe") == "bread"
    assert client.read("PlcTask.OpcMain.stamp") == datetime.datetime(1970, 1, 2, tzinfo=datetime.timezone.utc)
    assert client.read("PlcTask.OpcMain.mode") == 0
    assert client.read("GVL_OpcPlant.speed") == 0.5
    assert client.read("GVL_OpcPlant.limit") == 100


def test_reads_never_see_half_a_cycle(opc: Any) -> None:
    rt, server, client = opc
    paths = ["PlcTask.OpcMain.a", "PlcTask.OpcMain.b", "PlcTask.OpcMain.count", "PlcTask.OpcSecond.seen"]
    nodes = [client.node(p) for p in paths]
    samples: list[list[int]] = []
    stop = threading.Event()

    async def sample() -> None:
        while not stop.is_set():
            samples.append(await client.client.read_values(nodes))

    reader = asyncio.run_coroutine_threadsafe(sample(), client.loop)
    rt.run(cycles=30, realtime=True)  # 300 ms while the client reads as fast as it can
    for _ in range(300):  # a busy machine serves fewer reads: run on (at most 30 s) until enough came
        if len(samples) > 10 and len({tuple(s) for s in samples}) > 5:
            break
        rt.run(cycles=10, realtime=True)
    stop.set()
    reader.result(TIMEOUT)
    assert len(samples) > 10
    # In every image b equals a (set at the two ends of OpcMain), and OpcSecond saw the count OpcMain left.
    assert all(a == b and c == seen for a, b, c, seen in samples)
    assert len({tuple(s) for s in samples}) > 5


# -- subscriptions ------------------------------------------------------------


class Changes:
    """asyncua subscription handler: the values of each data change, by node."""

    def __init__(self) -> None:
        self.values: dict[str, list[Any]] = {}

    def datachange_notification(self, node: Any, value: Any, data: Any) -> None:
        self.values.setdefault(node.nodeid.Identifier, []).append(value)


def test_a_data_change_arrives_for_each_cycle_in_which_a_value_changes(opc: Any) -> None:
    rt, server, client = opc
    handler = Changes()
    paths = ["PlcTask.OpcMain.count", "PlcTask.OpcMain.half", "PlcTask.OpcMain.recipe"]
    cycles(rt, server, 1)
    subscription = client.call(client.client.create_subscription(10, handler))
    try:
        client.call(subscription.subscribe_data_change([client.node(p) for p in paths], queuesize=100))
        # The first notification of each item is its current value.
        wait_until(lambda: all(len(handler.values.get(p, [])) == 1 for p in paths), "the initial values")
        cycles(rt, server, 9)  # in virtual time: nine cycles in far less than one publishing interval
        wait_until(lambda: len(handler.values["PlcTask.OpcMain.count"]) == 10, "nine changes of count")
        wait_until(lambda: len(handler.values["PlcTask.OpcMain.half"]) == 6, "five changes of half")
        time.sleep(0.1)  # anything more would come within this
        assert handler.values["PlcTask.OpcMain.count"] == list(range(1, 11))
        assert handler.values["PlcTask.OpcMain.half"] == [0, 1, 2, 3, 4, 5]  # only the cycles where it changed
        assert handler.values["PlcTask.OpcMain.recipe"] == ["bread"]  # never changed: nothing after the first
    finally:
        client.call(subscription.delete())


# -- writes -------------------------------------------------------------------


def test_a_written_input_is_used_from_the_next_cycle(opc: Any) -> None:
    rt, server, client = opc
    cycles(rt, server, 2)
    assert client.write("PlcTask.OpcMain.step", 5, ua.VariantType.Int16).is_good()
    assert MAIN.step == 1  # queued: the PLC's memory changes at the start of the next cycle
    cycles(rt, server, 1)
    assert (MAIN.used, MAIN.count) == (5, 7)
    assert client.read("PlcTask.OpcMain.step") == 5
    assert client.read("PlcTask.OpcMain.count") == 7


def test_any_integer_type_within_range_a_gvl_variable_an_array_and_named_writables(opc: Any) -> None:
    rt, server, client = opc
    writes = [
        ("PlcTask.OpcMain.step", -7, ua.VariantType.Int64),
        ("PlcTask.OpcMain.mode", 2, ua.VariantType.Int32),
        ("PlcTask.OpcMain.recipe", "rye", ua.VariantType.String),
        ("PlcTask.OpcMain.gains", [3, 2, 1], ua.VariantType.Int16),
        ("GVL_OpcPlant.speed", 0.25, ua.VariantType.Double),
        ("PlcTask.OpcMain.where.y", 9.5, ua.VariantType.Double),  # writable through the writable= option
        ("PlcTask.OpcMain.stamp", datetime.datetime(2024, 5, 6, 7, 8, 9, 500_000, tzinfo=datetime.timezone.utc),
         ua.VariantType.DateTime),
    ]
    for path, value, vtype in writes:
        assert client.write(path, value, vtype).is_good(), path
    cycles(rt, server, 1)
    assert (MAIN.step, MAIN.mode, MAIN.recipe, list(MAIN.gains)) == (-7, OpcState.FAULT, "rye", [3, 2, 1])
    assert (GVL_OpcPlant.speed, MAIN.where.y) == (0.25, 9.5)
    # DT holds whole seconds since 1970-01-01 (UTC): the half second is cut, as DT_TO_DATE cuts the day.
    assert MAIN.stamp == int(datetime.datetime(2024, 5, 6, 7, 8, 9, tzinfo=datetime.timezone.utc).timestamp())
    assert client.read("PlcTask.OpcMain.gains") == [3, 2, 1]
    assert "PlcTask.OpcMain.where.x" in server.writable()
    assert "PlcTask.OpcMain.count" not in server.writable()


@st.composite
def integer_writes(draw: st.DrawFn) -> tuple[str, int]:
    """An integer variable and a value for it: in its range, or just outside, or far outside."""
    name = draw(st.sampled_from(sorted(INTEGERS)))
    low, high = INTEGERS[name]
    value = draw(st.one_of(st.integers(low, high), st.integers(high + 1, high + 2**20), st.integers(low - 2**20, low - 1)))
    return name, value


@settings(max_examples=40, deadline=None)
@given(write=integer_writes())
def test_an_integer_write_is_stored_exactly_when_in_range_and_refused_otherwise(
    served: tuple[Runtime, OpcUaServer, Client], write: tuple[str, int]
) -> None:
    rt, server, client = served
    name, value = write
    low, high = INTEGERS[name]
    assume(-(2**63) <= value < 2**64)  # beyond, no OPC UA integer holds it: a client cannot send it
    vtype = ua.VariantType.Int64 if value < 2**63 else ua.VariantType.UInt64
    before = getattr(MAIN, name)
    status = client.write(f"PlcTask.OpcMain.{name}", value, vtype)
    cycles(rt, server, 1)
    if low <= value <= high:
        assert status.is_good() and getattr(MAIN, name) == value == client.read(f"PlcTask.OpcMain.{name}")
    else:
        assert status.name == "BadOutOfRange" and getattr(MAIN, name) == before


@pytest.mark.parametrize(
    ("path", "value", "vtype", "status"),
    [
        ("PlcTask.OpcMain.count", 1, "Int32", "BadNotWritable"),  # an output
        ("PlcTask.OpcMain.used", 1, "Int16", "BadNotWritable"),  # an internal
        ("PlcTask.OpcMain.timer.PT", 100, "Int64", "BadNotWritable"),  # an FB's input: the FB's own
        ("PlcTask.OpcSecond.seen", 1, "Int32", "BadNotWritable"),
        ("GVL_OpcPlant.limit", 1, "Int16", "BadNotWritable"),  # a CONSTANT
        ("PlcTask.OpcMain.step", "7", "String", "BadTypeMismatch"),
        ("PlcTask.OpcMain.step", 7.0, "Double", "BadTypeMismatch"),  # no silent truncation
        ("PlcTask.OpcMain.step", True, "Boolean", "BadTypeMismatch"),
        ("PlcTask.OpcMain.step", [1, 2], "Int16", "BadTypeMismatch"),
        ("PlcTask.OpcMain.gains", [1, 2], "Int16", "BadTypeMismatch"),  # 2 values for 3 elements
        ("PlcTask.OpcMain.recipe", 5, "Int32", "BadTypeMismatch"),
        ("PlcTask.OpcMain.stamp", 86_400, "UInt32", "BadTypeMismatch"),  # a DT is a DateTime
        ("PlcTask.OpcMain.stamp", datetime.datetime(1969, 12, 31, tzinfo=datetime.timezone.utc), "DateTime",
         "BadOutOfRange"),
        ("PlcTask.OpcMain.step", 40000, "Int32", "BadOutOfRange"),
        ("PlcTask.OpcMain.step", -40000, "Int64", "BadOutOfRange"),
        ("PlcTask.OpcMain.mode", 3, "Int16", "BadOutOfRange"),  # no value of OpcState
        ("PlcTask.OpcMain.recipe", "sourdough", "String", "BadOutOfRange"),  # 9 characters for STRING(8)
        ("PlcTask.OpcMain.recipe", "pain \u20ac", "String", "BadOutOfRange"),  # no Latin-1 code
        ("PlcTask.OpcMain.gains", [1, 2, 99999], "Int32", "BadOutOfRange"),
        ("GVL_OpcPlant.speed", 1e39, "Double", "BadOutOfRange"),  # beyond REAL
    ],
)
def test_refused_writes_store_nothing(opc: Any, path: str, value: Any, vtype: str, status: str) -> None:
    rt, server, client = opc
    cycles(rt, server, 1)
    before = client.read(path)
    code = client.write(path, value, ua.VariantType[vtype])
    assert code.name == status
    cycles(rt, server, 1)
    if path not in ("PlcTask.OpcMain.count", "PlcTask.OpcSecond.seen", "PlcTask.OpcMain.timer.PT"):
        assert client.read(path) == before  # these do not change by themselves
    assert MAIN.step == 1 and MAIN.recipe == "bread" and list(MAIN.gains) == [0, 0, 0]
    assert MAIN.mode == OpcState.IDLE and GVL_OpcPlant.speed == 0.5 and MAIN.stamp == 86_400


# -- real time, start and stop ------------------------------------------------


def test_the_plc_runs_in_real_time_in_the_callers_thread_while_a_client_writes(opc: Any) -> None:
    rt, server, client = opc

    def timed() -> None:
        time.sleep(0.05)
        client.write("PlcTask.OpcMain.step", 3, ua.VariantType.Int16)

    writer = threading.Thread(target=timed)
    writer.start()
    began = time.monotonic()
    rt.run(cycles=20, realtime=True)
    assert time.monotonic() - began >= 0.19  # paced: 20 cycles of 10 ms take at least 190 ms
    for _ in range(1000):  # a busy machine may deliver the write after those 20 cycles: run on until it lands
        if MAIN.step == 3:
            break
        rt.run(cycles=5, realtime=True)
    writer.join(TIMEOUT)
    assert MAIN.step == 3 and MAIN.used == 3
    before = MAIN.count
    rt.run(cycles=2)
    assert MAIN.count == before + 6  # the written step is what every later cycle counts by


def listening(port: int) -> bool:
    with socket.socket() as probe:
        probe.settimeout(1)
        return probe.connect_ex(("127.0.0.1", port)) == 0


def server_threads() -> list[threading.Thread]:
    return [t for t in threading.enumerate() if t.name.startswith("iecoop OPC UA")]


def test_a_port_in_use_raises_and_leaves_no_thread(served: Any) -> None:
    rt, server, client = served
    before = len(server_threads())
    with pytest.raises(OSError):
        with OpcUaServer(rt, endpoint=server.endpoint, start_timeout=TIMEOUT):
            pass  # pragma: no cover
    assert len(server_threads()) == before
    assert rt.on_cycle_start.count(server._cycle_start) == 1


def test_bad_configuration_is_refused_with_the_reason(served: Any) -> None:
    rt = served[0]
    with pytest.raises(ValueError, match="endpoint must look like opc.tcp"):
        OpcUaServer(rt, endpoint="http://127.0.0.1:4840")
    with pytest.raises(ValueError, match="'PlcTask.OpcMain.nothing' matches no variable"):
        OpcUaServer(rt, writable=["PlcTask.OpcMain.nothing"])
    with pytest.raises(ValueError, match="unknown security policy 'Basic1'"):
        OpcUaServer(rt, security=["Basic1"])
    with pytest.raises(ValueError, match="needs certificate= and private_key="):
        OpcUaServer(rt, security=["Basic256Sha256_SignAndEncrypt"])
    with pytest.raises(ValueError, match="certificate and private_key go together"):
        OpcUaServer(rt, certificate="server.der")
    clash = Runtime(store=":memory:")
    clash.add_task(Task("GVL_OpcPlant", interval=T("10ms")), OpcSecond())
    with pytest.raises(ValueError, match="two nodes would have the instance path 'GVL_OpcPlant'"):
        OpcUaServer(clash, gvls=["GVL_OpcPlant"])


def certificate(folder: Path, name: str, uri: str, usage: Any) -> tuple[Path, Path]:
    """A self-signed certificate (DER) and its private key (PEM) for an OPC UA application."""
    from asyncua.crypto import cert_gen
    from cryptography import x509
    from cryptography.hazmat.primitives.serialization import Encoding

    key = cert_gen.generate_private_key()
    alt_names = [x509.UniformResourceIdentifier(uri), x509.DNSName("localhost")]
    cert = cert_gen.generate_self_signed_app_certificate(key, name, {}, alt_names, [usage])
    cert_path, key_path = folder / f"{name}-cert.der", folder / f"{name}-key.pem"
    cert_path.write_bytes(cert.public_bytes(Encoding.DER))
    key_path.write_bytes(cert_gen.dump_private_key_as_pem(key))
    return cert_path, key_path


def test_users_passwords_an_encrypting_policy_and_a_stop_that_leaves_nothing_behind(tmp_path: Path) -> None:
    from cryptography.x509.oid import ExtendedKeyUsageOID

    server_cert, server_key = certificate(tmp_path, "server", "urn:iecoop:server", ExtendedKeyUsageOID.SERVER_AUTH)
    secure = certificate(tmp_path, "client", CLIENT_URI, ExtendedKeyUsageOID.CLIENT_AUTH)
    main = OpcMain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("Secure", interval=T("10ms")), main)
    before = len(server_threads())
    with OpcUaServer(rt, endpoint="opc.tcp://127.0.0.1:0", users={"operator": "s3cret"},
                     certificate=server_cert, private_key=server_key) as server:
        port = int(server.endpoint.rsplit(":", 1)[1])
        assert listening(port) and len(server_threads()) == before + 1
        with pytest.raises(Exception, match="No matching endpoints.*SecurityPolicy#None"):
            Client(server.endpoint, user="operator", password="s3cret")  # no encryption: not offered
        with pytest.raises(Exception, match="BadIdentityTokenRejected"):
            Client(server.endpoint, security=secure)  # anonymous
        with pytest.raises(Exception, match="BadUserAccessDenied"):
            Client(server.endpoint, security=secure, user="operator", password="guess")
        client = Client(server.endpoint, security=secure, user="operator", password="s3cret")
        try:
            assert client.write("Secure.OpcMain.step", 4, ua.VariantType.Int16).is_good()
            rt.run(cycles=1)
            assert main.count == 4
            server.wait_published(TIMEOUT)
            assert client.read("Secure.OpcMain.count") == 4
        finally:
            client.close()
    # The thread has ended, the port is closed, the runtime's hooks are gone, and the PLC goes on.
    assert len(server_threads()) == before
    assert not listening(port)
    assert rt.on_cycle_start == [] and rt.on_cycle_end == []
    rt.run(cycles=2)
    assert main.count == 12  # 4 + two cycles of the step the client wrote
    assert "stopped" in repr(server)


# -- the optional dependency ----------------------------------------------------


def test_iecoop_imports_without_asyncua_and_iecoop_opcua_names_the_extra(monkeypatch: pytest.MonkeyPatch) -> None:
    code = "import sys; sys.modules['asyncua'] = None; import iecoop, iecoop.runtime, iecoop.stdlib; print('ok')"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert done.stdout.strip() == "ok", done.stderr
    monkeypatch.setitem(sys.modules, "asyncua", None)  # what import sees when the package is missing
    monkeypatch.delitem(sys.modules, "iecoop.opcua")
    with pytest.raises(ImportError, match=r'pip install "iecoop\[opcua\]"'):
        importlib.import_module("iecoop.opcua")


# -- iecoop serve ---------------------------------------------------------------


def test_serve_runs_a_pattern_in_real_time_behind_opc_ua() -> None:
    import io

    from patterns.showcase.serve import serve

    out, err = io.StringIO(), io.StringIO()
    status: list[int] = []
    runner = threading.Thread(
        target=lambda: status.append(serve(["state", "--endpoint", "opc.tcp://127.0.0.1:0", "--duration", "2s"], out, err))
    )
    runner.start()
    try:
        wait_until(lambda: "OPC UA server at" in out.getvalue() or not runner.is_alive(), "the server to start")
        endpoint = out.getvalue().split("OPC UA server at ", 1)[1].split(",", 1)[0]
        client = Client(endpoint)
        try:
            transitions = "PlcTask.PackagingLine.unit.transitions"
            wait_until(lambda: client.read(transitions) >= 2, "the line to go through its first states")
            assert client.write("PlcTask.PackagingLine.infeed_gap", 300, ua.VariantType.Int64).is_good()
            assert client.write("PlcTask.PackagingLine.batches", 1, ua.VariantType.UInt32).name == "BadNotWritable"
            wait_until(lambda: client.read("PlcTask.PackagingLine.infeed_gap") == 300, "the write to be applied")
        finally:
            client.close()
    finally:
        runner.join(TIMEOUT)
    assert status == [0], err.getvalue()
    assert not any(endpoint in t.name for t in server_threads())
    assert not listening(int(endpoint.rsplit(":", 1)[1]))
    assert "writable: PlcTask.PackagingLine.infeed_gap" in out.getvalue()
    assert "stopped after 2000 ms of PLC time" in out.getvalue()


def test_serve_refuses_an_unknown_name_and_a_bad_duration(capsys: pytest.CaptureFixture[str]) -> None:
    from patterns.showcase.serve import serve

    assert serve(["no_such_pattern"]) == 2
    assert "unknown name 'no_such_pattern'" in capsys.readouterr().err
    assert serve(["state", "--duration", "soon"]) == 2
    assert "bad TIME literal 'soon'" in capsys.readouterr().err
