"""What an OPC UA client may do, tested with real asyncua clients on 127.0.0.1.

No client changes the address space, whoever it logs in as; a write stores
exactly the text a STRING or WSTRING holds, or nothing; a server shows the
programs its runtime runs, the global lists they use and the lists named to
it, never every list the process happens to hold.
"""

from __future__ import annotations

import secrets
import sys
from collections.abc import Iterator
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import (
    INT, STRING, WSTRING, VAR, VAR_EXTERNAL, VAR_INPUT, VAR_OUTPUT, FunctionBlock, GlobalVariables, Program, T, gvl,
    method,
)
from iecoop import st as iec_st
from iecoop.runtime import Runtime, Task

asyncua = pytest.importorskip("asyncua")
ua = asyncua.ua
from iecoop.opcua import OpcUaServer  # noqa: E402  (after the skip when asyncua is missing)
from tests.iecoop.test_opcua import TIMEOUT, Client  # noqa: E402

LENGTH = 8


@gvl
class GVL_SecCell(GlobalVariables):
    sec_cell_speed: INT = 5


@gvl
class GVL_SecLine(GlobalVariables):
    sec_line_jams: INT = 0


@gvl
class GVL_SecUnused(GlobalVariables):
    sec_unused_flag: INT = 0


class SecFeeder(FunctionBlock):
    """Counts jams in a global list its body names."""

    def body(self) -> None:
        GVL_SecLine.sec_line_jams += 1


class Guarded(Program):
    """Adds ``inflow`` to ``level`` every cycle; reads a global through VAR_EXTERNAL."""

    inflow: INT = VAR_INPUT(1)
    label: STRING = VAR_INPUT("tank", length=LENGTH)
    wlabel: WSTRING = VAR_INPUT("tank", length=LENGTH)
    level: INT = VAR_OUTPUT(0)
    sec_cell_speed: INT = VAR_EXTERNAL()
    feeder: SecFeeder = VAR()

    def body(self) -> None:
        self.level += self.inflow
        self.feeder()


GUARDED = Guarded()


@gvl
class GVL_SecModule(GlobalVariables):
    sec_module_total: INT = 0


this = sys.modules[__name__]


class ByModule(Program):
    """Names its global list through the module that holds it, in a METHOD."""

    @method
    def add(self) -> None:
        this.GVL_SecModule.sec_module_total += 1

    def body(self) -> None:
        self.add()


@pytest.fixture(scope="module")
def served() -> Iterator[tuple[Runtime, OpcUaServer]]:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), GUARDED)
    with OpcUaServer(rt, endpoint="opc.tcp://127.0.0.1:0") as server:
        yield rt, server


@pytest.fixture(scope="module")
def anonymous(served: tuple[Runtime, OpcUaServer]) -> Iterator[Client]:
    client = Client(served[1].endpoint)
    try:
        yield client
    finally:
        client.close()


def cycle(rt: Runtime, server: OpcUaServer) -> None:
    rt.run(cycles=1)
    server.wait_published(TIMEOUT)


# -- no client changes the address space -----------------------------------------


def children(client: Client, path: str) -> set[str]:
    found = client.call(client.node(path).get_children())
    return {client.call(n.read_browse_name()).Name for n in found}


def statuses(results: list[Any]) -> list[str]:
    return [getattr(r, "StatusCode", r).name for r in results]


def refusal(client: Client, request: Any) -> str:
    """The status of a one-item node-management request: of the whole service, or of the one item."""
    try:
        results = client.call(request)
    except ua.UaStatusCodeError as refused:
        return type(refused).__name__
    (status,) = statuses(results)
    return status


def assert_address_space_fixed(client: Client) -> None:
    """Every node-management service is refused, and the program's nodes are all still there."""
    level = client.node("PlcTask.Guarded.level")
    before = children(client, "PlcTask.Guarded")
    uaclient = client.client.uaclient
    ns = client.ns

    deleted = refusal(client, uaclient.delete_nodes(ua.DeleteNodesParameters(
        NodesToDelete=[ua.DeleteNodesItem(NodeId=level.nodeid, DeleteTargetReferences=True)])))
    item = ua.AddNodesItem(
        ParentNodeId=client.node("PlcTask.Guarded").nodeid,
        ReferenceTypeId=ua.NodeId(ua.ObjectIds.HasComponent),
        RequestedNewNodeId=ua.NodeId("PlcTask.Guarded.intruder", ns),
        BrowseName=ua.QualifiedName("intruder", ns),
        NodeClass=ua.NodeClass.Variable,
        NodeAttributes=ua.VariableAttributes(Value=ua.Variant(1, ua.VariantType.Int16)),
        TypeDefinition=ua.NodeId(ua.ObjectIds.BaseDataVariableType),
    )
    added = refusal(client, uaclient.add_nodes([item]))
    reference = ua.AddReferencesItem(
        SourceNodeId=client.node("PlcTask").nodeid, ReferenceTypeId=ua.NodeId(ua.ObjectIds.Organizes),
        IsForward=True, TargetNodeId=level.nodeid, TargetNodeClass=ua.NodeClass.Variable,
    )
    referenced = refusal(client, uaclient.add_references([reference]))
    unreferenced = refusal(client, uaclient.delete_references([ua.DeleteReferencesItem(
        SourceNodeId=client.node("PlcTask.Guarded").nodeid, ReferenceTypeId=ua.NodeId(ua.ObjectIds.HasComponent),
        IsForward=True, TargetNodeId=level.nodeid, DeleteBidirectional=True,
    )]))
    assert [deleted, added, referenced, unreferenced] == ["BadUserAccessDenied"] * 4
    with pytest.raises(ua.UaStatusCodeError, match="BadUserAccessDenied"):
        client.call(client.client.nodes.objects.add_object(ua.NodeId("Intruder", ns), ua.QualifiedName("Intruder", ns)))
    with pytest.raises(ua.UaStatusCodeError, match="BadUserAccessDenied"):
        client.call(client.node("PlcTask").add_variable(ua.NodeId("PlcTask.extra", ns), "extra", 0))
    # The nodes are all still there, unchanged.
    assert children(client, "PlcTask.Guarded") == before
    assert "level" in before and "intruder" not in before
    assert isinstance(client.read("PlcTask.Guarded.level"), int)
    assert children(client, "PlcTask") == {"Guarded"}


@pytest.mark.parametrize("user", [None, "admin", "Admin", "operator"], ids=["anonymous", "admin", "Admin", "any name"])
def test_no_client_changes_the_address_space_whatever_it_logs_in_as(
    served: tuple[Runtime, OpcUaServer], user: str | None
) -> None:
    rt, server = served
    if user is None:
        client = Client(server.endpoint)
    else:
        client = Client(server.endpoint, user=user, password=secrets.token_urlsafe(12))  # any password at all
    try:
        assert_address_space_fixed(client)
        # Its rights are the documented ones: a program input is writable, an output is not.
        assert client.write("PlcTask.Guarded.inflow", 2, ua.VariantType.Int16).is_good()
        assert client.write("PlcTask.Guarded.level", 0, ua.VariantType.Int16).name == "BadNotWritable"
        # No attribute but the Value is written, of a PLC variable or of any other node.
        text = ua.DataValue(ua.Variant(ua.LocalizedText("hacked"), ua.VariantType.LocalizedText))
        for node in (client.node("PlcTask.Guarded.inflow"), client.node("PlcTask")):
            params = ua.WriteParameters(NodesToWrite=[ua.WriteValue(node.nodeid, ua.AttributeIds.DisplayName, Value=text)])
            (code,) = client.call(client.client.uaclient.write(params))
            assert not code.is_good()
            assert client.call(node.read_display_name()).Text != "hacked"
        cycle(rt, server)
        assert GUARDED.inflow == 2
    finally:
        GUARDED.inflow = 1
        client.close()


def test_a_configured_user_changes_no_node_and_admin_is_no_user_of_its_own() -> None:
    password = secrets.token_urlsafe(12)
    rt = Runtime(store=":memory:")
    guarded = Guarded()
    rt.add_task(Task("PlcTask", interval=T("10ms")), guarded)
    with OpcUaServer(rt, endpoint="opc.tcp://127.0.0.1:0", users={"operator": password}) as server:
        for name in ("admin", "Admin"):
            with pytest.raises(Exception, match="BadUserAccessDenied"):
                Client(server.endpoint, user=name, password=secrets.token_urlsafe(12))
        client = Client(server.endpoint, user="operator", password=password)
        try:
            assert_address_space_fixed(client)
            assert client.write("PlcTask.Guarded.inflow", 3, ua.VariantType.Int16).is_good()
            rt.run(cycles=1)
            assert guarded.level == 3
        finally:
            client.close()


def test_the_node_management_service_refuses_every_session_but_the_servers_own() -> None:
    from asyncua.crypto.permission_rules import User, UserRole
    from asyncua.server.address_space import AddressSpace

    from iecoop.opcua import _FixedNodes

    server_user = User(role=UserRole.Admin)
    service = _FixedNodes(AddressSpace(), server_user)
    admin = User(role=UserRole.Admin, name="admin")
    item = ua.DeleteNodesItem(NodeId=ua.NodeId(ua.ObjectIds.Server))
    assert statuses(service.delete_nodes(ua.DeleteNodesParameters(NodesToDelete=[item]), admin)) == ["BadUserAccessDenied"]
    assert statuses(service.add_nodes([ua.AddNodesItem()], admin)) == ["BadUserAccessDenied"]
    assert statuses(service.add_references([ua.AddReferencesItem()], admin)) == ["BadUserAccessDenied"]
    assert statuses(service.delete_references([ua.DeleteReferencesItem()], admin)) == ["BadUserAccessDenied"]
    # The server's own session builds the address space: its requests go through.
    assert statuses(service.delete_nodes(ua.DeleteNodesParameters(NodesToDelete=[item]), server_user)) == ["BadNodeIdUnknown"]


# -- a STRING holds what it is given, or is not written --------------------------


@pytest.mark.parametrize(
    ("name", "text"),
    [
        ("label", "ab\x00cd"), ("wlabel", "ab\x00cd"), ("label", "\x00"),  # NUL ends a PLC string
        ("label", "pain \u20ac"), ("wlabel", "emoji \U0001f600"),  # no Latin-1 / no UCS-2 code
        ("label", "x" * (LENGTH + 1)), ("wlabel", "\u00e9" * (LENGTH + 1)),
    ],
)
def test_a_text_the_plc_string_cannot_hold_is_refused_and_nothing_stored(
    served: tuple[Runtime, OpcUaServer], anonymous: Client, name: str, text: str
) -> None:
    rt, server = served
    setattr(GUARDED, name, "tank")
    cycle(rt, server)
    code = anonymous.write(f"PlcTask.Guarded.{name}", text, ua.VariantType.String)
    cycle(rt, server)
    assert code.name == "BadOutOfRange"
    assert getattr(GUARDED, name) == "tank" == anonymous.read(f"PlcTask.Guarded.{name}")


#: Texts of characters a STRING holds, a WSTRING holds, neither holds (NUL among them: it ends a PLC string).
TEXTS = st.text(alphabet=st.sampled_from("aZ 9\u00e9\u00ff\x00\x01\u0100\u20ac\uffff\U0001f600"), max_size=LENGTH + 1)


@settings(max_examples=40, deadline=None)
@given(text=TEXTS, wide=st.booleans())
def test_a_text_is_stored_exactly_when_the_string_holds_it_and_refused_otherwise(
    served: tuple[Runtime, OpcUaServer], anonymous: Client, text: str, wide: bool
) -> None:
    rt, server = served
    name = "wlabel" if wide else "label"
    highest = 0xFFFF if wide else 0xFF
    holds = len(text) <= LENGTH and "\x00" not in text and all(ord(ch) <= highest for ch in text)
    setattr(GUARDED, name, "tank")
    code = anonymous.write(f"PlcTask.Guarded.{name}", text, ua.VariantType.String)
    cycle(rt, server)
    if holds:
        assert code.is_good() and getattr(GUARDED, name) == text == anonymous.read(f"PlcTask.Guarded.{name}")
    else:
        assert code.name == "BadOutOfRange" and getattr(GUARDED, name) == "tank"
    setattr(GUARDED, name, "tank")


# -- a server shows what its runtime runs ----------------------------------------

OTHER_ST = """
// GVL GVL_SecOther
VAR_GLOBAL
    sec_other_count : INT;
END_VAR
PROGRAM PRG_SecOther
sec_other_count := sec_other_count + 1;
END_PROGRAM
"""

USER_ST = """
// GVL GVL_SecUsed
VAR_GLOBAL
    sec_used_count : INT;
END_VAR
// GVL GVL_SecExternal
VAR_GLOBAL
    sec_external_limit : INT := 7;
END_VAR
// GVL GVL_SecScale
VAR_GLOBAL
    sec_scale_gain : INT := 1;
END_VAR
FUNCTION F_SecStep : INT
F_SecStep := GVL_SecScale.sec_scale_gain;
END_FUNCTION
PROGRAM PRG_SecUser
VAR_EXTERNAL
    sec_external_limit : INT;
END_VAR
IF GVL_SecUsed.sec_used_count < sec_external_limit THEN
    GVL_SecUsed.sec_used_count := GVL_SecUsed.sec_used_count + F_SecStep();
END_IF
END_PROGRAM
"""


@pytest.fixture(scope="module")
def loaded() -> Iterator[tuple[Any, Any]]:
    yield iec_st.load(OTHER_ST), iec_st.load(USER_ST)  # held: a GVL lives while something holds it


def exposed_lists(server: OpcUaServer) -> set[str]:
    return {path.split(".", 1)[0] for path in server.writable() if path.startswith("GVL_")}


def test_a_server_shows_the_global_lists_its_programs_use_and_no_other(
    served: tuple[Runtime, OpcUaServer], loaded: tuple[Any, Any]
) -> None:
    other, user = loaded
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), user.PRG_SecUser)
    server = OpcUaServer(rt, endpoint="opc.tcp://127.0.0.1:0")
    # Named in the body, a VAR_EXTERNAL, named in a FUNCTION the body calls.
    assert exposed_lists(server) == {"GVL_SecUsed", "GVL_SecExternal", "GVL_SecScale"}
    # Python blocks: a VAR_EXTERNAL, and a global list the body of a nested block names.
    assert exposed_lists(served[1]) == {"GVL_SecCell", "GVL_SecLine"}


def test_a_global_list_a_method_names_through_its_module_is_shown() -> None:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), ByModule())
    assert exposed_lists(OpcUaServer(rt, endpoint="opc.tcp://127.0.0.1:0")) == {"GVL_SecModule"}


def test_a_global_list_named_to_the_server_is_shown_too(loaded: tuple[Any, Any]) -> None:
    other, user = loaded
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), user.PRG_SecUser)
    server = OpcUaServer(rt, endpoint="opc.tcp://127.0.0.1:0", gvls=["GVL_SecOther", GVL_SecUnused])
    assert exposed_lists(server) == {"GVL_SecUsed", "GVL_SecExternal", "GVL_SecScale", "GVL_SecOther", "GVL_SecUnused"}
    with pytest.raises(ValueError, match="gvls names 'GVL_SecNothing', which is no global variable list"):
        OpcUaServer(rt, gvls=["GVL_SecNothing"])
    with pytest.raises(ValueError, match="gvls names 42, which is no global variable list"):
        OpcUaServer(rt, gvls=[42])  # type: ignore[list-item]


def test_a_client_browses_no_global_list_the_runtime_does_not_use(loaded: tuple[Any, Any]) -> None:
    other, user = loaded
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), user.PRG_SecUser)
    with OpcUaServer(rt, endpoint="opc.tcp://127.0.0.1:0") as server:
        client = Client(server.endpoint)
        try:
            top = {client.call(n.read_browse_name()).Name for n in client.call(client.client.nodes.objects.get_children())}
            assert {"PlcTask", "GVL_SecUsed", "GVL_SecExternal"} <= top
            assert not top & {"GVL_SecOther", "GVL_SecUnused", "GVL_SecCell"}
            with pytest.raises(ua.UaStatusCodeError, match="BadNodeIdUnknown"):
                client.read("GVL_SecOther.sec_other_count")
            assert client.write("GVL_SecUsed.sec_used_count", 5, ua.VariantType.Int16).is_good()
            rt.run(cycles=3)
            assert user.GVL_SecUsed.sec_used_count == 7  # 5, then counted up to the limit
        finally:
            client.close()
