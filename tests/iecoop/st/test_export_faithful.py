"""A loaded ST project goes back out as the same project: unchanged objects byte for byte, changed ones written."""

from __future__ import annotations

import pathlib
import shutil
from typing import Any

import blark.parse
import pytest

from iecoop import st
from iecoop.cli import main
from iecoop.st.read.origin import fingerprint

PROJECT = pathlib.Path(__file__).parent / "data" / "projects" / "FillStation"
ORIGINALS = sorted(p for p in PROJECT.rglob("*") if p.suffix in (".TcPOU", ".TcDUT", ".TcGVL", ".TcIO"))


def test_load_records_file_text_id_and_line_ids() -> None:
    plc = st.load(PROJECT / "FillStation.plcproj")
    main_source = plc.__st_sources__["MAIN"]
    assert main_source.format == "twincat"
    assert main_source.text == (PROJECT / "POUs" / "MAIN.TcPOU").read_bytes()
    assert main_source.object_id.startswith("{5a1e")
    assert main_source.line_ids == ("MAIN",)
    assert main_source.fingerprint == fingerprint(plc.MAIN)
    assert sorted(plc.__st_sources__) == sorted(p.stem for p in ORIGINALS)
    assert plc.__st_project__ == "FillStation"


def test_unchanged_project_is_written_back_byte_identical(tmp_path: pathlib.Path) -> None:
    plc = st.load(PROJECT / "FillStation.plcproj")
    written = {p.name: p for p in st.export(plc, tmp_path, format="twincat")}
    for original in ORIGINALS:  # PROGRAM MAIN, FOR, CASE, AT %I*, pragmas, comments, Ids: all kept
        assert written[original.name].read_bytes() == original.read_bytes(), original.name
    assert "FillStation.plcproj" in written
    project = written["FillStation.plcproj"].read_text()
    assert all(original.name in project for original in ORIGINALS)
    again = st.load(tmp_path / "FillStation.plcproj")
    second = {p.name: p.read_bytes() for p in st.export(again, tmp_path / "again", format="twincat")}
    assert {name: path.read_bytes() for name, path in written.items()} == second


def test_a_method_replaced_in_python_is_written_and_parses(tmp_path: pathlib.Path) -> None:
    plc = st.load(PROJECT / "FillStation.plcproj")
    station = plc.FB_Alarms
    before = fingerprint(station)

    def Raise(self: object, nCode: int = 0) -> bool:  # noqa: N802 - ST name
        return True

    station.Raise = Raise
    assert fingerprint(station) != before
    written = {p.name: p for p in st.export(plc, tmp_path, format="twincat", lenient=True)}
    changed = written["FB_Alarms.TcPOU"].read_bytes()
    assert changed != (PROJECT / "POUs" / "FB_Alarms.TcPOU").read_bytes()
    assert b"METHOD" in changed and b"Raise" in changed
    blark.parse.parse_source_code(st.dump([station]))
    assert written["MAIN.TcPOU"].read_bytes() == (PROJECT / "POUs" / "MAIN.TcPOU").read_bytes()


def test_a_variable_added_changes_the_fingerprint() -> None:
    plc = st.load(PROJECT / "FillStation.plcproj")
    before = fingerprint(plc.FB_Station)
    plc.FB_Station.__annotations__ = {**plc.FB_Station.__annotations__, "nExtra": "INT"}
    assert fingerprint(plc.FB_Station) != before


ST_TEXT = """// the modes
TYPE E_Mode : (IDLE, RUN := 5) INT; END_TYPE

(* a counter, commented *)
FUNCTION_BLOCK FB_Count
VAR
    n : INT;   // counts
END_VAR
FOR n := 10 TO 0 BY -2 DO
    ;
END_FOR
END_FUNCTION_BLOCK

METHOD Reset : BOOL
n := 0;
END_METHOD
"""


def test_st_text_goes_back_out_as_its_text(tmp_path: pathlib.Path) -> None:
    plc = st.load(ST_TEXT)
    written = {p.name: p.read_text() for p in st.export(plc, tmp_path, format="st")}
    assert written["E_Mode.st"] == "// the modes\nTYPE E_Mode : (IDLE, RUN := 5) INT; END_TYPE\n"
    assert written["FB_Count.st"].startswith("\n(* a counter, commented *)\nFUNCTION_BLOCK FB_Count")
    assert "BY -2" in written["FB_Count.st"] and "END_METHOD" in written["FB_Count.st"]
    # the TwinCAT format is not the one it was read in: the writer makes those files
    assert {p.name for p in st.export(plc, tmp_path / "tc", format="twincat", lenient=True)} >= {"E_Mode.TcDUT"}


def test_cli_exports_an_st_project_strict_by_default(tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["export", str(PROJECT / "FillStation.plcproj"), "-o", str(tmp_path / "out")]) == 0
    for original in ORIGINALS:  # in the project's own layout (POUs/, DUTs/, GVLs/): diff -r finds nothing
        assert (tmp_path / "out" / original.relative_to(PROJECT)).read_bytes() == original.read_bytes()
    for other in ("FillStation.plcproj", "PlcTask.TcTTO"):  # nothing changed: the project file as read too
        assert (tmp_path / "out" / other).read_bytes() == (PROJECT / other).read_bytes()
    assert main(["export", str(PROJECT), "-o", str(tmp_path / "folder")]) == 0
    assert (tmp_path / "folder" / "POUs" / "MAIN.TcPOU").read_bytes() == (PROJECT / "POUs" / "MAIN.TcPOU").read_bytes()
    capsys.readouterr()


UNSUPPORTED = """from iecoop import INT, VAR, FunctionBlock


class FB_Odd(FunctionBlock):
    n: INT = VAR()

    def body(self) -> None:
        self.n = 1
        raise ValueError("no ST form")
"""


def test_cli_is_strict_by_default_and_lenient_lists_every_comment(tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]) -> None:
    module = tmp_path / "odd.py"
    module.write_text(UNSUPPORTED)
    assert main(["export", str(module), "-o", str(tmp_path / "strict")]) == 1
    assert "raise" in capsys.readouterr().err
    assert not (tmp_path / "strict" / "FB_Odd.TcPOU").exists()
    assert main(["export", str(module), "-o", str(tmp_path / "lenient"), "--lenient"]) == 0
    err = capsys.readouterr().err
    assert "written as a comment" in err and "raise" in err
    assert (tmp_path / "lenient" / "FB_Odd.TcPOU").exists()


LOOPS = """FUNCTION F : INT
VAR_INPUT a : INT; END_VAR
F := a;
END_FUNCTION
FUNCTION_BLOCK FB_Loops
VAR
    n : INT; s : INT := 2; k : INT;
END_VAR
VAR_TEMP i : DINT; END_VAR
FOR n := F(a := 1) TO F(a := 5) DO
    k := k + n;
END_FOR
FOR i := 1 TO 5 BY s DO
    k := k + 1;
END_FOR
FOR n := 1 TO 10 DO
    IF n > 3 THEN EXIT; END_IF
END_FOR
FOR n := 10 TO 0 BY -2 DO
    k := k - 1;
END_FOR
END_FUNCTION_BLOCK
"""


def test_for_loops_as_the_reader_makes_them_are_written_as_for() -> None:
    loaded = st.load(LOOPS)
    text = st.dump([loaded.FB_Loops])  # strict: every FOR has its ST form
    for line in ("FOR i := 1 TO 5 BY s DO", "FOR n := 1 TO 10 DO", "FOR n := 10 TO 0 BY -2 DO"):
        assert line in text
    # An end bound that calls a FUNCTION is checked before every pass (as TwinCAT and CODESYS do): the
    # reader writes that loop as a while, and the writer gives it back as the equivalent WHILE.
    assert "n := F(a := 1);" in text and "IF NOT (n <= F(a := 5)) THEN" in text
    blark.parse.parse_source_code(text)
    again = st.load(text)
    first, second = loaded.FB_Loops(), again.FB_Loops()
    trace = []
    for _ in range(4):
        first()
        second()
        trace.append(((first.k, first.n), (second.k, second.n)))
    assert all(a == b for a, b in trace), trace


def test_copy_of_project_loads_from_anywhere(tmp_path: pathlib.Path) -> None:
    shutil.copytree(PROJECT, tmp_path / "FillStation")
    plc = st.load(tmp_path / "FillStation")
    assert plc.__st_sources__["FB_Station"].file.startswith(str(tmp_path))


def test_st_run_takes_the_tcTTO_task_set_and_trace(capsys: pytest.CaptureFixture[str]) -> None:
    argv = [
        "st", "run", str(PROJECT / "FillStation.plcproj"), "--set", "GVL_IO.bStartButton=TRUE@10ms",
        "--trace", "MAIN.eState,MAIN.fbStation.nBottles", "--duration", "60ms",
    ]
    assert main(argv) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("MAIN on PlcTask (5 ms)") and "12 cycles" in out[0]  # <CycleTime>5000</CycleTime>: 5 ms
    assert out[1].split()[-2:] == ["MAIN.eState", "MAIN.fbStation.nBottles"]
    rows = [line.split() for line in out[2:]]
    assert rows[0][2:] == ["IDLE", "0"]
    assert rows[1][:3] == ["10", "3", "FILLING"]  # the write lands at the cycle starting at 10 ms
    assert rows[-1][-1] == "3"


def test_st_run_refuses_a_bad_set_or_trace(capsys: pytest.CaptureFixture[str]) -> None:
    source = str(PROJECT / "FillStation.plcproj")
    assert main(["st", "run", source, "--set", "GVL_IO.bStartButton", "--cycles", "2"]) == 2
    assert "PATH=VALUE@TIME" in capsys.readouterr().err
    assert main(["st", "run", source, "--trace", "MAIN.nope", "--cycles", "2"]) == 2
    assert "MAIN.nope" in capsys.readouterr().err


def test_a_loaded_program_and_an_uncalled_function_are_written() -> None:
    loaded = st.load("FUNCTION F_Add : INT\nVAR_INPUT a : INT; END_VAR\nF_Add := a + 1;\nEND_FUNCTION\n"
                     "PROGRAM MAIN\nVAR n : INT; END_VAR\nn := n + 1;\nEND_PROGRAM\n")
    text = st.dump(loaded)
    assert "FUNCTION F_Add : INT" in text and "PROGRAM MAIN" in text and "n := n + 1;" in text
    again = st.load(text)
    assert again.F_Add(2) == 3
    again.MAIN()
    assert again.MAIN.n == 1


def _trace(plc: object, cycles: int) -> list[tuple[object, ...]]:
    rows: list[tuple[object, ...]] = []
    program: Any = getattr(plc, "MAIN")
    io: Any = getattr(plc, "GVL_IO")
    for cycle in range(cycles):
        io.bStartButton = cycle >= 2
        program()
        rows.append((str(program.eState), program.fbStation.nBottles, program.sState, io.bValveOpen, program.fDone))
    return rows


def test_the_project_written_as_plain_st_runs_the_same(tmp_path: pathlib.Path) -> None:
    plc = st.load(PROJECT / "FillStation.plcproj")
    # another format: every object goes through the writer, strictly (CASE, FOR BY -5, TO_STRING, MAIN, F_Percent)
    written = {p.name: p for p in st.export(plc, tmp_path, format="st")}
    assert "sState := TO_STRING(eState);" in written["MAIN.st"].read_text()
    assert "FOR nStep := 10 TO 0 BY -5 DO" in written["MAIN.st"].read_text()
    for path in written.values():
        blark.parse.parse_source_code(path.read_text())
    again = st.load(tmp_path)
    assert _trace(again, 12) == _trace(st.load(PROJECT / "FillStation.plcproj"), 12)


PROJECTS = PROJECT.parent


@pytest.mark.parametrize("name", ["FillStation", "FsUtil", "LineCtrl"])
def test_each_project_round_trips_byte_identical(name: str, tmp_path: pathlib.Path) -> None:
    folder = PROJECTS / name
    plc = st.load(folder / f"{name}.plcproj", library_path=[PROJECTS])
    written = {p.name: p.read_bytes() for p in st.export(plc, tmp_path / "one", format="twincat")}
    originals = [p for p in folder.rglob("*") if p.suffix in (".TcPOU", ".TcDUT", ".TcGVL", ".TcIO")]
    assert originals
    for original in originals:
        assert written[original.name] == original.read_bytes(), original.name
    again = st.load(tmp_path / "one" / f"{name}.plcproj", library_path=[PROJECTS])
    assert {p.name: p.read_bytes() for p in st.export(again, tmp_path / "two", format="twincat")} == written
