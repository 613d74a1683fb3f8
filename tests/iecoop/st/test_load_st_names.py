"""A loaded name the naming rule changed (in -> in_) is shown by its ST name: messages, var_info, getattr, OPC UA, trace."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from iecoop import T, _config, var_info
from iecoop.cli import main as iecoop_main
from iecoop.exceptions import AccessError
from iecoop.metadata import st_name
from iecoop.runtime import Runtime, Task

st = pytest.importorskip("iecoop.st")

SOURCE = """
TYPE E_Opt : (None, Some := 2) INT; END_TYPE
FUNCTION_BLOCK FB_Names
VAR_INPUT T : INT; END_VAR
VAR_OUTPUT in : INT; END_VAR
VAR _x : INT; mode : E_Opt := E_Opt.None; END_VAR
_x := T * 2;
in := _x + 1;
END_FUNCTION_BLOCK
METHOD body : INT
body := in;
END_METHOD
FUNCTION_BLOCK in
VAR_OUTPUT done : BOOL; END_VAR
END_FUNCTION_BLOCK
PROGRAM MAIN
VAR in : INT := 3; fb : FB_Names; mode : E_Opt; END_VAR
in := in + 1;
fb(T := in);
END_PROGRAM
"""


@pytest.fixture(scope="module")
def plc() -> Any:
    return st.load(SOURCE)


def test_the_generated_python_carries_each_changed_st_name(plc: Any) -> None:
    text = plc.__python__
    assert 'T_: INT = VAR_INPUT(st_name="T")' in text and 'in_: INT = VAR_OUTPUT(st_name="in")' in text
    assert 'st_x_: INT = VAR(st_name="_x")' in text and '@method(st_name="body")' in text
    assert 'class in_(FunctionBlock, st_name="in")' in text and 'st_names={"None_": "None"}' in text
    assert "mode: E_Opt = VAR(E_Opt.None_)" in text  # an unchanged name gets no st_name=


@pytest.mark.skipif(not _config.CHECKS, reason="checked mode refuses the write")
def test_writing_an_output_from_outside_names_the_st_variable(plc: Any) -> None:
    block = plc.FB_Names()
    with pytest.raises(AccessError) as info:
        block.in_ = 1
    assert str(info.value).startswith("VAR_OUTPUT FB_Names.in cannot be written") and "in_" not in str(info.value)
    with pytest.raises(AccessError, match="VAR FB_Names._x cannot be written"):
        block.st_x_ = 1


def test_var_info_and_the_accessor_give_the_st_names(plc: Any) -> None:
    block = plc.FB_Names()
    assert [var_info(block, name).Symbol for name in ("T_", "in_", "st_x_")] == [
        "FB_Names.T", "FB_Names.in", "FB_Names._x",
    ]
    assert st_name(plc.FB_Names, "body_") == "body" and st_name(plc.E_Opt, "None_") == "None"
    assert st_name(plc.in_) == "in"


def test_getattr_by_st_name_on_the_module_its_program_and_a_block(plc: Any) -> None:
    assert getattr(plc, "in") is plc.in_ and getattr(plc, "IN") is plc.in_  # ST names ignore case
    main = getattr(plc, "main")
    main.body()
    assert getattr(main, "in") == 4 and getattr(main.fb, "in") == 9 and getattr(main.fb, "_x") == 8
    assert getattr(main.fb, "body") != getattr(main.fb, "body_")  # the block's own body stays the body
    assert main.fb.body_() == 9
    with pytest.raises(AttributeError, match="declares no 'out'"):
        getattr(plc, "out")


def test_the_trace_of_st_run_heads_its_columns_with_st_names(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    source = tmp_path / "names.st"
    source.write_text(SOURCE)
    assert iecoop_main(["st", "run", str(source), "--cycles", "2"]) == 0
    out = capsys.readouterr().out
    header = next(line for line in out.splitlines() if line.startswith("time ms"))
    assert header.split() == ["time", "ms", "cycle", "in", "mode", "fb.in"]
    assert "None" in out.splitlines()[2].split()  # an enumeration value by its ST name
    assert "in_" not in out


@pytest.fixture
def served(plc: Any) -> Iterator[Any]:
    pytest.importorskip("asyncua")
    from iecoop.opcua import OpcUaServer
    from tests.iecoop.test_opcua import Client

    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), plc.MAIN)
    with OpcUaServer(rt, endpoint="opc.tcp://127.0.0.1:0") as server:
        client = Client(server.endpoint)
        try:
            yield client
        finally:
            client.close()


def test_opc_ua_browse_names_and_node_ids_are_the_st_names(plc: Any, served: Any) -> None:
    client = served
    ua = pytest.importorskip("asyncua").ua

    def children(node: Any) -> dict[str, Any]:
        return {client.call(n.read_browse_name()).Name: n for n in client.call(node.get_children())}

    main = children(client.node("PlcTask.MAIN"))
    assert {"in", "fb", "mode"} <= set(main) and "in_" not in main
    block = children(main["fb"])
    assert {"T", "in", "_x"} <= set(block)
    assert block["in"].nodeid == ua.NodeId("PlcTask.MAIN.fb.in", client.ns)
    assert client.read("PlcTask.MAIN.fb._x") == plc.MAIN.fb.st_x_
    strings = client.call(client.call(client.node("PlcTask.MAIN.mode").get_child("0:EnumValues")).read_value())
    assert [pair.DisplayName.Text for pair in strings] == ["None", "Some"]


def test_a_global_variable_named_like_a_python_keyword_loads_and_is_reached_by_its_st_name() -> None:
    plc = st.load("VAR_GLOBAL\n    in : INT := 4;\nEND_VAR\nPROGRAM MAIN\nVAR n : INT; END_VAR\nn := in + 1;\nEND_PROGRAM\n")
    plc.MAIN.body()
    assert plc.MAIN.n == 5 and getattr(plc.GVL, "in") == 4 and plc.GVL.in_ == 4
    assert var_info(plc.GVL, "in_").Symbol == "GVL.in"


@pytest.mark.skipif(not _config.CHECKS, reason="checked mode refuses the write")
def test_a_renamed_program_and_method_are_named_in_st_by_the_runtime_and_the_refusal() -> None:
    plc = st.load("""
FUNCTION_BLOCK FB_Out
VAR_OUTPUT in : INT; END_VAR
END_FUNCTION_BLOCK
PROGRAM in
VAR fb : FB_Out; END_VAR
END_PROGRAM
FUNCTION_BLOCK FB_Writer
VAR fb : FB_Out; END_VAR
END_FUNCTION_BLOCK
METHOD pass : INT
fb.in := 1;
END_METHOD
""")
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), getattr(plc, "in"))
    assert [path for path, _ in rt.tasks[0].programs] == ["PlcTask.in"]
    with pytest.raises(AccessError, match="VAR_OUTPUT FB_Out.in cannot be written from FB_Writer.pass: only FB_Out's"):
        plc.FB_Writer().pass_()
