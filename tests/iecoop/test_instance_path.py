"""``VAR(instance_path=True)`` / ``{attribute 'instance-path'}``: a STRING holding its instance's path.

The path is set when the instance is initialised, before FB_init, for the blocks of a PROGRAM or GVL:
``<project>.MAIN.fbStation.fbLog``, an ARRAY element with its index; it is set again by a reset.
"""

from __future__ import annotations

import pathlib
import textwrap
import types

import pytest

from iecoop import (
    ARRAY, BOOL, INT, STRING, DefinitionError, FunctionBlock, GlobalVariables, Program, Struct, VAR, VAR_INPUT, gvl, new, st,
)
from iecoop.runtime import Runtime, Task
from iecoop.st.export import dump


class FB_Log(FunctionBlock):
    sPath: STRING = VAR(instance_path=True)
    sAtInit: STRING = VAR()
    nCalls: INT = VAR(0)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
        self.sAtInit = self.sPath  # FB_init already sees the path
        return True

    def body(self) -> None:
        self.nCalls += 1
        if self.nCalls == 2:
            self.sPath = "overwritten"  # the block's own code may write it, as any VAR


class FB_Short(FunctionBlock):
    sPath: STRING = VAR(length=12, instance_path=True)


class FB_Station(FunctionBlock):
    fbLog: FB_Log = VAR()
    aLogs: ARRAY[FB_Log] = VAR(bounds=((1, 2), (0, 1)))
    fbShort: FB_Short = VAR()

    def body(self) -> None:
        self.fbLog()


class MAIN(Program):
    fbStation: FB_Station = VAR()
    sSeen: STRING = VAR()

    def body(self) -> None:
        self.fbStation()
        self.sSeen = self.fbStation.fbLog.sPath


@gvl
class GVL_Cell(GlobalVariables):
    fbGlobalLog: FB_Log = VAR()


def test_every_block_of_a_program_holds_its_path_from_fb_init_on() -> None:
    main = MAIN()
    station = main.fbStation
    project = __name__.split(".")[0]  # Python code: the module's top package stands for the project
    assert station.fbLog.sPath == station.fbLog.sAtInit == f"{project}.MAIN.fbStation.fbLog"
    for i in (1, 2):
        for j in (0, 1):
            assert station.aLogs[i, j].sPath == f"{project}.MAIN.fbStation.aLogs[{i}, {j}]"
    assert station.fbShort.sPath == f"{project}.MAIN.fbStation.fbShort"[:12]  # STRING(12): its first 12 characters
    assert len(station.fbShort.sPath) == 12
    assert GVL_Cell.fbGlobalLog.sPath == f"{project}.GVL_Cell.fbGlobalLog"


def test_the_path_is_a_variable_the_block_writes_and_a_reset_sets_again() -> None:
    main = MAIN()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=10), main)
    path = main.fbStation.fbLog.sPath
    rt.run(cycles=1)
    assert main.sSeen == path
    rt.run(cycles=2)  # the second call overwrote it
    assert main.fbStation.fbLog.sPath == main.sSeen == "overwritten"
    rt.reset_cold()
    assert main.fbStation.fbLog.sPath == path and main.fbStation.fbLog.nCalls == 0


class ST_Slot(Struct):
    nId: INT = VAR(0)
    fbLog: FB_Log = VAR()


class ST_Rack(Struct):
    aSlots: ARRAY[ST_Slot] = VAR(bounds=(1, 2))


class RACKS(Program):
    stRack: ST_Rack = VAR()
    aRacks: ARRAY[ST_Rack] = VAR(bounds=(0, 1))


def test_a_block_inside_a_struct_holds_its_path_through_the_struct() -> None:
    racks = RACKS()
    project = __name__.split(".")[0]
    assert racks.stRack.aSlots[2].fbLog.sPath == f"{project}.RACKS.stRack.aSlots[2].fbLog"
    assert racks.aRacks[1].aSlots[1].fbLog.sAtInit == f"{project}.RACKS.aRacks[1].aSlots[1].fbLog"


def test_a_block_of_no_program_or_gvl_has_an_empty_path() -> None:
    assert FB_Log().sPath == "" and FB_Station().fbLog.sPath == ""
    pointer = new(FB_Log)
    assert pointer.deref.sPath == ""


@pytest.mark.parametrize(
    ("annotation", "spec", "message"),
    [
        (INT, VAR(instance_path=True), "instance_path= is for a STRING or WSTRING VAR of a FUNCTION_BLOCK or PROGRAM"),
        (STRING, VAR_INPUT(), None),
        (STRING, VAR("x", instance_path=True), "takes no initial value"),
    ],
)
def test_instance_path_on_anything_but_a_local_string_is_refused(annotation: object, spec: object, message: str | None) -> None:
    namespace = {"__annotations__": {"sPath": annotation}, "sPath": spec}
    if message is None:  # VAR_INPUT has no instance_path= at all: the specifier refuses it
        with pytest.raises(TypeError, match="instance_path"):
            VAR_INPUT(instance_path=True)  # type: ignore[call-overload]
        return
    with pytest.raises(DefinitionError, match=message) as info:
        types.new_class("FB_Bad", (FunctionBlock,), exec_body=lambda ns: ns.update(namespace))
    assert "FB_Bad.sPath" in str(info.value)


def test_instance_path_in_a_struct_is_refused() -> None:
    with pytest.raises(DefinitionError, match=r"ST_Bad\.sPath: instance_path= is for a STRING .* VAR of a FUNCTION_BLOCK or PROGRAM"):
        class ST_Bad(Struct):
            sPath: STRING = VAR(instance_path=True)


SOURCE = """\
{attribute 'reflection'}
FUNCTION_BLOCK FB_Log
VAR
    nCount : INT;
    {attribute 'instance-path'}
    {attribute 'noinit'}
    sPath : STRING;
    sOther : STRING;
END_VAR
nCount := nCount + 1;
END_FUNCTION_BLOCK

FUNCTION_BLOCK FB_Plain
VAR
    {attribute 'instance-path'}
    {attribute 'noinit'}
    sPath : STRING;
END_VAR
END_FUNCTION_BLOCK

FUNCTION_BLOCK FB_Station
VAR
    fbLog : FB_Log;
    aLogs : ARRAY[0..1] OF FB_Log;
    fbPlain : FB_Plain;
END_VAR
fbLog();
END_FUNCTION_BLOCK

PROGRAM MAIN
VAR
    fbStation : FB_Station;
    sSeen : STRING;
    nLength : INT;
END_VAR
fbStation();
sSeen := fbStation.fbLog.sPath;
nLength := LEN(sSeen);
END_PROGRAM
"""


def _project(tmp_path: pathlib.Path) -> pathlib.Path:
    folder = tmp_path / "CellCtrl"
    folder.mkdir()
    (folder / "cell.st").write_text(SOURCE)
    return folder


def test_st_instance_path_of_a_reflection_pou_runs_over_cycles(tmp_path: pathlib.Path) -> None:
    plc = st.load(_project(tmp_path))
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=10), plc.MAIN)
    for cycle in range(1, 4):
        rt.run(cycles=1)
        assert plc.MAIN.sSeen == "CellCtrl.MAIN.fbStation.fbLog" and plc.MAIN.nLength == 29
        assert plc.MAIN.fbStation.fbLog.nCount == cycle
    station = plc.MAIN.fbStation
    assert [log.sPath for log in station.aLogs] == ["CellCtrl.MAIN.fbStation.aLogs[0]", "CellCtrl.MAIN.fbStation.aLogs[1]"]
    assert station.fbLog.sOther == ""  # only the STRING the attribute marks
    assert station.fbPlain.sPath == ""  # no {attribute 'reflection'} on its POU: the PLC leaves it empty too


def test_st_instance_path_goes_back_out_as_the_attributes_it_came_from(tmp_path: pathlib.Path) -> None:
    text = dump(st.load(_project(tmp_path)))
    assert text.count("{attribute 'instance-path'}") == 2 and text.count("{attribute 'reflection'}") == 1


def test_a_python_block_exports_its_instance_path_as_the_plc_declares_it(tmp_path: pathlib.Path) -> None:
    module = tmp_path / "loglib.py"
    module.write_text(textwrap.dedent("""\
        from iecoop import INT, STRING, FunctionBlock, Program, VAR

        class FB_Note(FunctionBlock):
            sWhere: STRING = VAR(instance_path=True)
            nCount: INT = VAR(0)

            def body(self) -> None:
                self.nCount += 1

        class MAIN(Program):
            fbNote: FB_Note = VAR()

            def body(self) -> None:
                self.fbNote()
        """))
    import importlib.util

    spec = importlib.util.spec_from_file_location("loglib", module)
    assert spec is not None and spec.loader is not None
    loaded = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(loaded)
    text = dump(loaded)
    assert "{attribute 'reflection'}\nFUNCTION_BLOCK FB_Note" in text
    assert "    {attribute 'instance-path'}\n    {attribute 'noinit'}\n    sWhere : STRING;" in text
    folder = tmp_path / "NoteCell"
    folder.mkdir()
    (folder / "note.st").write_text(text)
    assert st.load(folder).MAIN.fbNote.sWhere == "NoteCell.MAIN.fbNote"  # read back: the path again


APP_SOURCE = """\
{attribute 'reflection'}
FUNCTION_BLOCK FB_Suite
VAR
    {attribute 'instance-path'}
    {attribute 'noinit'}
    sPath : STRING(255);
END_VAR
END_FUNCTION_BLOCK

PROGRAM MAIN
VAR
    fbSuite : FB_Suite;
    sProject : STRING;
    sApp : STRING;
    nPort : UINT;
    nAt : INT;
    sShort : STRING;
END_VAR
sProject := TwinCAT_SystemInfoVarList._AppInfo.ProjectName;
sApp := _AppInfo.AppName;
nPort := _AppInfo.AdsPort;
// a test suite's name: its instance path without the project's name and the dot after it
nAt := FIND(fbSuite.sPath, CONCAT(sProject, '.'));
sShort := DELETE(fbSuite.sPath, LEN(sProject) + 1, nAt);
END_PROGRAM
"""


def test_app_info_names_the_project_instance_paths_start_with(tmp_path: pathlib.Path) -> None:
    folder = tmp_path / "Conveyor"
    folder.mkdir()
    (folder / "main.st").write_text(APP_SOURCE)
    plc = st.load(folder)
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=10), plc.MAIN)
    rt.run(cycles=2)
    main = plc.MAIN
    assert (main.sProject, main.sApp, main.nPort) == ("Conveyor", "Port_851", 851)
    assert main.fbSuite.sPath == "Conveyor.MAIN.fbSuite" and main.nAt == 1 and main.sShort == "MAIN.fbSuite"


@pytest.mark.parametrize(
    ("line", "message"),
    [
        ("n := _AppInfo.OnlineChangeCnt;", r"_AppInfo\.OnlineChangeCnt: iecoop's AppInfo has ProjectName, AppName, AdsPort"),
        ("_AppInfo.AdsPort := 852;", r"_AppInfo: assignment to AdsPort \(the PLC's application information is read-only\)"),
    ],
)
def test_app_info_refuses_what_it_does_not_have_at_the_line(line: str, message: str) -> None:
    source = f"PROGRAM MAIN\nVAR n : UDINT; END_VAR\n{line}\nEND_PROGRAM\n"
    with pytest.raises(st.StUnsupportedError, match=rf"<st>:3: {message}"):
        st.load(source)
