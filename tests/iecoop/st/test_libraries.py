"""Libraries in the ST reader: references in a .plcproj, names plain and qualified, and how they are found."""

from __future__ import annotations

import pathlib
import sys
import types

import pytest

from iecoop import BOOL, INT, VAR_INPUT, VAR_OUTPUT, FunctionBlock, T, st
from iecoop.exceptions import DefinitionError
from iecoop.libraries import KNOWN, Library, tc2_standard
from iecoop.st.write import references
from iecoop.runtime import Runtime, Task
from iecoop.st.read.parse import LibraryReference, library_references
from tests.iecoop.st import fs_pylib

PROJECTS = pathlib.Path(__file__).parent / "data" / "projects"
LINE = PROJECTS / "LineCtrl" / "LineCtrl.plcproj"


def test_a_plcproj_s_references_are_read_with_title_namespace_version_and_company() -> None:
    references = library_references(LINE)
    assert [(r.name, r.namespace, r.version, r.company) for r in references] == [
        ("Tc2_Standard", "Tc2_Standard", "*", "Beckhoff Automation GmbH"),
        ("FsUtil", "FSU", "1.2.0.0", "Fs Tools"),
    ]
    assert all(isinstance(r, LibraryReference) and r.where.startswith(str(LINE)) for r in references)
    assert library_references(LINE.parent) == references  # the folder holding the one .plcproj
    assert library_references("PROGRAM P END_PROGRAM") == []


def test_a_reference_without_namespace_uses_its_title_and_a_bad_one_names_its_line(tmp_path: pathlib.Path) -> None:
    project = tmp_path / "P.plcproj"
    project.write_text('<?xml version="1.0" encoding="utf-8"?>\n<Project xmlns="http://schemas.microsoft.com/developer/msbuild/2003">'
                       '<ItemGroup>\n<LibraryReference Include="Tc2_MC2, 3.3.52.0 (Beckhoff Automation GmbH)" />\n'
                       '</ItemGroup></Project>\n')
    assert [(r.name, r.namespace, r.version, r.company) for r in library_references(project)] == [
        ("Tc2_MC2", "Tc2_MC2", "3.3.52.0", "Beckhoff Automation GmbH")]
    project.write_text(project.read_text().replace("Tc2_MC2, 3.3.52.0", "Tc2 MC2; 3.3"))
    with pytest.raises(DefinitionError, match=r"P.plcproj:3: library reference 'Tc2 MC2; 3.3 \(Beckhoff Automation GmbH\)' names no library"):
        library_references(project)


def test_the_project_runs_with_its_libraries_over_several_cycles() -> None:
    plc = st.load(LINE, library_path=[PROJECTS])
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), plc.MAIN)
    seen = []
    for _ in range(5):
        rt.run(cycles=1)
        main = plc.MAIN
        seen.append((main.nCycle, main.fbPulses.nCount, main.stTotal.nGood, main.stTotal.nBad, main.stLast.nBad,
                     main.nClamped, main.nLimit, int(main.eState), main.sName))
    # bTick rises on cycles 1, 3, 5 (FSU.FB_EdgeCounter, which uses Tc2_Standard.R_TRIG inside the library);
    # FB_Station.Run (FSU.I_Runnable) is TRUE every second run; F_Clamp(2 * nCycle, 0, cMaxParts = 5);
    # fbStart (TON, 20 ms) is Q from t = 20 ms (cycle 3), fbDelay (Tc2_Standard.TON) 20 ms later (cycle 5).
    assert seen == [
        (1, 1, 0, 1, 1, 2, 5, 0, "cycle 1"),
        (2, 1, 1, 1, 1, 4, 5, 0, "cycle 2"),
        (3, 2, 1, 2, 2, 5, 5, 1, "cycle 3"),
        (4, 2, 2, 2, 2, 5, 5, 1, "cycle 4"),
        (5, 3, 2, 3, 3, 5, 5, 2, "cycle 5"),
    ]


def test_the_generated_python_imports_library_names_from_their_modules() -> None:
    plc = st.load(LINE, library_path=[PROJECTS])
    text = plc.__python__
    assert "from iecoop.stdlib import TON" in text
    assert "F_Clamp, GVL_Util, I_Runnable, ST_Count" in text
    assert "class FB_Station(FunctionBlock, I_Runnable):" in text
    assert "class F_Clamp" not in text and "class ST_Count" not in text  # the library's body is not copied


def test_to_python_binds_libraries_as_load_does() -> None:
    text = st.to_python(LINE, library_path=[PROJECTS])
    assert "class FB_Station(FunctionBlock, I_Runnable):" in text
    assert "nLimit = F_Clamp(nValue=100, nLow=0, nHigh=GVL_Util.cMaxParts)" in text


def test_the_environment_variable_finds_a_library(monkeypatch: pytest.MonkeyPatch, tmp_path: pathlib.Path) -> None:
    monkeypatch.setenv("IECOOP_LIBRARY_PATH", f"{tmp_path}{__import__('os').pathsep}{PROJECTS}")
    plc = st.load(LINE)
    plc.MAIN()
    assert plc.MAIN.nLimit == 5


def test_a_missing_reference_is_one_error_saying_how_to_resolve_it(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("IECOOP_LIBRARY_PATH", raising=False)
    with pytest.raises(DefinitionError) as caught:
        st.load(LINE)
    message = str(caught.value)
    assert "LineCtrl.plcproj:" in message
    for words in ("library FsUtil", "version 1.2.0.0", "(Fs Tools)", "not found", "libraries=", "library_path=",
                  "IECOOP_LIBRARY_PATH"):
        assert words in message


def test_libraries_maps_a_reference_to_its_folder_by_title_or_namespace() -> None:
    for key in ("FsUtil", "fsu"):
        plc = st.load(LINE, libraries={key: PROJECTS / "FsUtil"})
        plc.MAIN()
        assert plc.MAIN.nClamped == 2


def test_the_namespace_not_the_title_qualifies_names() -> None:
    source = """
    PROGRAM P
    VAR n : INT; END_VAR
    n := FsUtil.F_Clamp(7, 0, 3);
    END_PROGRAM
    """
    with pytest.raises(DefinitionError, match="unknown variable 'FsUtil'"):
        st.load(source, libraries={"FSU": PROJECTS / "FsUtil"})
    plc = st.load(source.replace("FsUtil.", "FSU."), libraries={"FSU": PROJECTS / "FsUtil"})
    plc.P()
    assert plc.P.n == 3


def test_a_type_qualified_by_an_unknown_namespace_names_file_line_and_namespace() -> None:
    source = "PROGRAM P\nVAR\n  t : Nowhere.TON;\nEND_VAR\nEND_PROGRAM\n"
    with pytest.raises(DefinitionError, match=r"<st>:3: unknown type 'Nowhere.TON': 'Nowhere' is no namespace"):
        st.load(source, libraries={"Tc2_Standard": tc2_standard})
    with pytest.raises(DefinitionError, match=r"library Tc2_Standard declares no NOTHING"):
        st.load(source.replace("Nowhere.TON", "Tc2_Standard.NOTHING"), libraries={"Tc2_Standard": tc2_standard})


# --- a library written in Python -------------------------------------------------------------------

PY_PROJECT = """
FUNCTION_BLOCK FB_Named IMPLEMENTS FsPy.I_Named
END_FUNCTION_BLOCK

METHOD Name : STRING
Name := 'named';
END_METHOD

PROGRAM MAIN
VAR
    fbScaled : FsPy.FB_Scaler;
    fbPlain : FB_Scaler;
    stRange : FsPy.ST_Range;
    stCopy : ST_Range;
    eQualified : FsPy.E_Dir := FsPy.E_Dir.FORWARD;
    ePlain : E_Dir := BACKWARD;
    fSpeed : FsPy.T_Speed := 3.5;
    fDouble : T_Speed;
    nTens, nRest, nRest2 : INT;
    nTwice : DINT;
    fSum : REAL;
    nCalls : UDINT;
    sName : STRING;
    fbNamed : FB_Named;
    itfNamed : FsPy.I_Named;
END_VAR
fbScaled(rGain := FsPy.GVL_Py.cScale, rIn := 2.0);
fbPlain(rGain := cScale, rIn := 1.0);
fSum := fbScaled.rOut + fbPlain.rOut;
nCalls := fbScaled.Calls;
fbPlain.Reset();
stRange.rHigh := 10.0;
stCopy := stRange;
nTens := FsPy.F_Split(47, nRest => nRest);
nTens := nTens + F_Split(nValue := 123, nRest => nRest2);
nTwice := FsPy.F_Twice(21) + F_Twice(1);
itfNamed := fbNamed;
sName := itfNamed.Name();
fDouble := fSpeed * 2;
END_PROGRAM
"""


def test_a_python_module_library_binds_plain_and_qualified_names() -> None:
    plc = st.load(PY_PROJECT, libraries={"FsPy": fs_pylib})
    main = plc.MAIN
    main()
    assert main.fSum == 7.5  # 2.0 * cScale (2.5) + 1.0 * 2.5
    assert (main.nCalls, main.fbPlain.nCalls) == (1, 0)  # PROPERTY Calls; METHOD Reset
    assert main.stCopy.rHigh == 10.0
    assert (main.nTens, main.nRest, main.nRest2) == (4 + 12, 7, 3)  # F_Split's VAR_OUTPUT nRest
    assert main.nTwice == 44
    assert main.sName == "named"  # an INTERFACE of the library implemented by the project
    assert main.fDouble == 7.0
    assert (int(main.eQualified), int(main.ePlain)) == (1, 2)
    assert "from tests.iecoop.st.fs_pylib import" in plc.__python__


def test_a_python_module_s_constant_is_a_global_plain_and_qualified() -> None:
    plc = st.load("PROGRAM P VAR n, m : LINT; END_VAR n := FsPy.cMaxAxes + 1; m := cMaxAxes * 2; END_PROGRAM",
                  libraries={"FsPy": fs_pylib})
    plc.P()
    assert (plc.P.n, plc.P.m) == (9, 16)
    assert "from tests.iecoop.st import fs_pylib as lib_FsPy" in plc.__python__


def test_qualified_only_in_a_python_module_refuses_the_plain_name(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(fs_pylib, "QUALIFIED_ONLY", True, raising=False)
    with pytest.raises(DefinitionError, match=r"FB_Scaler needs its namespace: library FsPy is qualified_only"):
        st.load(PY_PROJECT, libraries={"FsPy": fs_pylib})
    with pytest.raises(DefinitionError, match=r"cMaxAxes needs its namespace: library FsPy is qualified_only"):
        st.load("PROGRAM P VAR n : LINT; END_VAR n := cMaxAxes; END_PROGRAM", libraries={"FsPy": fs_pylib})
    plc = st.load("PROGRAM P VAR n : DINT; END_VAR n := FsPy.F_Twice(4) + FsPy.cMaxAxes; END_PROGRAM",
                  libraries={"FsPy": fs_pylib})
    plc.P()
    assert plc.P.n == 16


def test_qualified_only_gvl_and_enumeration_of_an_st_library_need_their_names() -> None:
    gvl = "PROGRAM P VAR n : INT; END_VAR n := cMaxParts; END_PROGRAM"
    with pytest.raises(DefinitionError, match=r"<st>:1: cMaxParts needs its GVL's name: GVL FSU.GVL_Util is qualified_only"):
        st.load(gvl, libraries={"FSU": PROJECTS / "FsUtil"})
    enum = "PROGRAM P VAR e : E_Station; END_VAR e := RUNNING; END_PROGRAM"
    with pytest.raises(DefinitionError, match=r"RUNNING needs its enumeration's name: enumeration FSU.E_Station is qualified_only"):
        st.load(enum, libraries={"FSU": PROJECTS / "FsUtil"})
    plc = st.load(gvl.replace("cMaxParts", "GVL_Util.cMaxParts"), libraries={"FSU": PROJECTS / "FsUtil"})
    plc.P()
    assert plc.P.n == 5


def test_a_name_two_libraries_declare_is_ambiguous_when_used_plain() -> None:
    other = types.ModuleType("fs_other")
    other.__all__ = ["F_Twice"]  # type: ignore[attr-defined]
    other.F_Twice = lambda nValue: nValue  # type: ignore[attr-defined]
    other.F_Twice.__annotations__ = {"nValue": "DINT", "return": "DINT"}
    sys.modules["fs_other"] = other
    try:
        source = "PROGRAM P VAR n : DINT; END_VAR n := F_Twice(4); END_PROGRAM"
        with pytest.raises(DefinitionError) as caught:
            st.load(source, libraries={"FsPy": fs_pylib, "Other": other})
        assert "F_Twice is ambiguous: FsPy.F_Twice and Other.F_Twice both declare it" in str(caught.value)
        assert str(caught.value).startswith("<st>:1:")
        plc = st.load(source.replace("F_Twice(4)", "FsPy.F_Twice(4) + Other.F_Twice(4)"),
                      libraries={"FsPy": fs_pylib, "Other": other})
        plc.P()
        assert plc.P.n == 12
    finally:
        del sys.modules["fs_other"]


def test_the_project_s_own_name_hides_a_library_s_plain_name() -> None:
    source = """
    FUNCTION F_Twice : DINT
    VAR_INPUT nValue : DINT; END_VAR
    F_Twice := nValue * 3;
    END_FUNCTION

    TYPE E_Local : (FORWARD := 7, AHEAD := 8) INT; END_TYPE

    PROGRAM P
    VAR nOwn, nLibrary : DINT; eOwn : E_Local; eLibrary : E_Dir; END_VAR
    nOwn := F_Twice(5);
    nLibrary := FsPy.F_Twice(5);
    eOwn := FORWARD;
    eLibrary := FsPy.E_Dir.FORWARD;
    END_PROGRAM
    """
    plc = st.load(source, libraries={"FsPy": fs_pylib})
    plc.P()
    assert (plc.P.nOwn, plc.P.nLibrary) == (15, 10)
    assert (int(plc.P.eOwn), int(plc.P.eLibrary)) == (7, 1)  # the project's enumeration value FORWARD first
    assert "F_Twice as FsPy_F_Twice" in plc.__python__


def test_a_project_gvl_named_like_a_library_s_leaves_the_library_s_globals_reachable() -> None:
    source = """
    // GVL GVL_Py
    VAR_GLOBAL
        nLocal : INT := 3;
    END_VAR

    PROGRAM P
    VAR fQualified, fPlain : REAL; nOwn : INT; END_VAR
    fQualified := FsPy.GVL_Py.cScale;
    fPlain := cScale * 2.0;
    nOwn := GVL_Py.nLocal;
    END_PROGRAM
    """
    plc = st.load(source, libraries={"FsPy": fs_pylib})
    plc.P()
    assert (plc.P.fQualified, plc.P.fPlain, plc.P.nOwn) == (2.5, 5.0, 3)
    assert "GVL_Py as FsPy_GVL_Py" in plc.__python__


# --- ST libraries that reference others ------------------------------------------------------------


def _library(folder: pathlib.Path, name: str, references: list[str], body: str) -> None:
    """A library ``name`` of one FUNCTION ``<name>_F : INT`` whose body is ``body``."""
    folder.mkdir()
    (folder / f"{name}.TcPOU").write_text(
        f'<?xml version="1.0" encoding="utf-8"?>\n<TcPlcObject><POU Name="{name}_F"><Declaration><![CDATA['
        f"FUNCTION {name}_F : INT\n]]></Declaration><Implementation><ST><![CDATA[{body}]]></ST></Implementation>"
        "</POU></TcPlcObject>\n")
    items = "".join(f'<PlaceholderReference Include="{r}"><DefaultResolution>{r}, * (Fs Tools)</DefaultResolution>'
                    f"<Namespace>{r}</Namespace></PlaceholderReference>" for r in references)
    (folder / f"{name}.plcproj").write_text(
        '<?xml version="1.0" encoding="utf-8"?>\n<Project xmlns="http://schemas.microsoft.com/developer/msbuild/2003">'
        f'<ItemGroup><Compile Include="{name}.TcPOU" /></ItemGroup><ItemGroup>{items}</ItemGroup></Project>\n')


def test_libraries_referencing_each_other_in_a_cycle_are_refused(tmp_path: pathlib.Path) -> None:
    _library(tmp_path / "LibA", "LibA", ["LibB"], "LibA_F := 1;")
    _library(tmp_path / "LibB", "LibB", ["LibA"], "LibB_F := 2;")
    with pytest.raises(DefinitionError, match=r"libraries reference each other in a cycle: LibA.plcproj -> LibB.plcproj -> LibA.plcproj"):
        st.load(tmp_path / "LibA" / "LibA.plcproj", library_path=[tmp_path])


def test_an_st_library_s_own_references_are_bound(tmp_path: pathlib.Path) -> None:
    _library(tmp_path / "LibB", "LibB", [], "LibB_F := 2;")
    _library(tmp_path / "LibA", "LibA", ["LibB"], "LibA_F := LibB.LibB_F() + 1;")
    plc = st.load("PROGRAM P VAR n : INT; END_VAR n := LibA.LibA_F(); END_PROGRAM",
                  libraries={"LibA": tmp_path / "LibA"}, library_path=[tmp_path])
    plc.P()
    assert plc.P.n == 3


def test_libraries_maps_a_name_to_a_folder_module_or_nothing_else() -> None:
    with pytest.raises(DefinitionError, match=r"library X: .*nowhere.* does not exist"):
        st.load("PROGRAM P END_PROGRAM", libraries={"X": "nowhere"})
    with pytest.raises(DefinitionError, match=r"library X: libraries= maps a name to a folder, .plcproj or module, got int"):
        st.load("PROGRAM P END_PROGRAM", libraries={"X": 5})  # type: ignore[dict-item]


# --- export -----------------------------------------------------------------------------------------


class FB_Axis(FunctionBlock):
    """A block of a library iecoop ships (the table of shipped libraries is given one for the test)."""

    __module__ = "iecoop.libraries.fs_axes"
    bEnable: BOOL = VAR_INPUT()
    nSteps: INT = VAR_OUTPUT()

    def body(self) -> None:
        if self.bEnable:
            self.nSteps += 1


FS_AXES = Library("Fs_Axes", "iecoop.libraries.fs_axes", "Fs Tools", "1.0.0.0", "https://example.invalid/fs_axes", "FSA")


def test_an_export_references_the_libraries_its_classes_use_and_loads_again(
    tmp_path: pathlib.Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(references, "KNOWN", (*KNOWN, FS_AXES))
    axes = types.ModuleType("iecoop.libraries.fs_axes")
    axes.__all__ = ["FB_Axis"]  # type: ignore[attr-defined]
    axes.FB_Axis = FB_Axis  # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, "iecoop.libraries.fs_axes", axes)
    plc = st.load("""
    FUNCTION_BLOCK FB_Cell
    VAR_OUTPUT nSteps : INT; END_VAR
    VAR fbAxis : FSA.FB_Axis; fbDelay : TON; END_VAR
    fbAxis(bEnable := TRUE);
    fbDelay(IN := TRUE, PT := T#1S);
    nSteps := fbAxis.nSteps;
    END_FUNCTION_BLOCK
    """, libraries={"FSA": axes})
    files = st.export([plc.FB_Cell], tmp_path)
    assert [f.name for f in files] == ["FB_Cell.TcPOU", "FB_Cell.plcproj"]
    project = (tmp_path / "FB_Cell.plcproj").read_text()
    assert '<Compile Include="FB_Cell.TcPOU">' in project
    assert "FB_Axis" not in project and not (tmp_path / "FB_Axis.TcPOU").exists()  # referenced, never written
    assert [(r.name, r.namespace, r.version, r.company) for r in library_references(tmp_path)] == [
        ("Fs_Axes", "FSA", "*", "Fs Tools"), ("Tc2_Standard", "Tc2_Standard", "*", "Beckhoff Automation GmbH")]
    back = st.load(tmp_path, libraries={"Fs_Axes": axes})
    cell = back.FB_Cell()
    cell()
    cell()
    assert cell.nSteps == 2 and type(cell.fbAxis) is FB_Axis


def test_an_export_that_uses_only_the_standard_blocks_writes_no_project_file(tmp_path: pathlib.Path) -> None:
    plc = st.load("FUNCTION_BLOCK FB_Plain VAR fbDelay : Tc2_Standard.TON; END_VAR fbDelay(IN := TRUE); END_FUNCTION_BLOCK",
                  libraries={"Tc2_Standard": tc2_standard})
    assert [f.name for f in st.export([plc.FB_Plain], tmp_path)] == ["FB_Plain.TcPOU"]
