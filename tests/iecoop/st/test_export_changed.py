"""A loaded POU changed in Python goes through the writer: CASE stays CASE, FOR stays FOR, a PROGRAM instance is written."""

from __future__ import annotations

import pathlib
from typing import Any

import blark.parse
import pytest

from iecoop import ARRAY, BOOL, INT, REAL, VAR, FunctionBlock, GlobalVariables, Program, gvl, st
from iecoop.st.export import StExportError
from iecoop.st.write.recorded import Bound, recorded

CASES = """{attribute 'qualified_only'}
TYPE E_Mode : (IDLE, RUN, STOP, FAULT) INT; END_TYPE
{attribute 'qualified_only'}
VAR_GLOBAL CONSTANT
    cLimit : INT := 40;
END_VAR
PROGRAM MAIN
VAR
    eMode : E_Mode;
    n : INT;
    nSeen : INT;
    nOut : INT;
END_VAR
n := n + 1;
CASE eMode OF
    E_Mode.IDLE:
        eMode := E_Mode.RUN;
    E_Mode.RUN, E_Mode.STOP:
        nSeen := nSeen + 1;
        IF n MOD 3 = 0 THEN eMode := E_Mode.FAULT; END_IF
ELSE
    eMode := E_Mode.IDLE;
END_CASE
CASE n MOD 7 OF
    0: nOut := 1;
    1..3: nOut := 2;
    GVL_Limits.cLimit: nOut := 3;
END_CASE
END_PROGRAM
"""


def _run(plc: Any, cycles: int) -> list[tuple[object, ...]]:
    rows: list[tuple[object, ...]] = []
    for _ in range(cycles):
        plc.MAIN()
        rows.append((str(plc.MAIN.eMode), plc.MAIN.nSeen, plc.MAIN.nOut))
    return rows


def test_case_read_as_an_if_chain_is_written_as_case_and_runs_the_same() -> None:
    plc = st.load(CASES.replace("VAR_GLOBAL CONSTANT", "// GVL GVL_Limits\nVAR_GLOBAL CONSTANT", 1))
    text = st.dump(plc, lenient=False)
    assert "CASE eMode OF" in text and "E_Mode.RUN, E_Mode.STOP:" in text and "ELSIF" not in text
    assert "CASE n MOD 7 OF" in text and "1..3:" in text  # the reader's temporary selector folded back
    assert "_case" not in text
    blark.parse.parse_source_code(text)
    assert _run(st.load(text), 30) == _run(plc, 30)


class TwoTests(Program):
    x: INT = VAR(0)
    y: INT = VAR(0)
    r: REAL = VAR(0.0)

    def body(self) -> None:
        if self.x == 1:
            self.y = 1
        elif self.x == 1:  # never runs in Python; ST refuses a label twice
            self.y = 2
        if self.r == 1:
            self.y = 3
        elif self.r == 2:  # CASE takes no REAL
            self.y = 4
        if self.x == 2:
            self.y = 5
        elif self.x == 3 or self.x == 4:
            self.y = 6
        else:
            self.y = 7


def test_a_python_chain_is_case_only_where_case_means_the_same() -> None:
    text = st.dump([TwoTests])
    assert text.count("ELSIF") == 2  # the repeated label and the REAL stay IF chains
    assert "CASE x OF\n    2:\n        y := 5;\n    3, 4:\n        y := 6;\nELSE\n    y := 7;\nEND_CASE" in text


class ForElse(FunctionBlock):
    n: INT = VAR(0)

    def body(self) -> None:
        for self.n in range(3):
            pass
        else:
            self.n = 99  # not where FOR leaves the variable (3): no FOR form


def test_a_for_else_that_sets_another_value_is_refused() -> None:
    with pytest.raises(StExportError, match="for ... else"):
        st.dump([ForElse])


def test_a_made_range_read_after_its_loop_is_not_folded_away() -> None:
    class Made(FunctionBlock):
        n: INT = VAR(0)
        k: INT = VAR(4)

        def body(self) -> None:
            _for1 = range(1, self.k)
            for i in _for1:
                self.n += i
            self.n += len(_for1)  # the range is read again: not the reader's form

    with pytest.raises(StExportError, match="_for1"):
        st.dump([Made])


def test_a_program_instance_is_written_as_its_program() -> None:
    plc = st.load("PROGRAM MAIN\nVAR n : INT; END_VAR\nn := n + 1;\nEND_PROGRAM\n")
    text = st.dump([plc.MAIN])
    assert text.startswith("PROGRAM MAIN") and "n := n + 1;" in text


FILL_STATION = pathlib.Path(__file__).parent / "data" / "projects" / "FillStation" / "FillStation.plcproj"


def test_written_objects_keep_pragmas_addresses_and_bounds_by_name(tmp_path: pathlib.Path) -> None:
    plc = st.load(FILL_STATION)
    # another format than the one read: every object goes through the writer
    written = {p.stem: p.read_text() for p in st.export(plc, tmp_path, format="st")}
    assert written["E_FillState"].startswith(
        "{attribute 'qualified_only'}\n{attribute 'strict'}\n{attribute 'to_string'}\n// States of the filling station\nTYPE E_FillState :")
    assert "bStartButton AT %I* : BOOL;" in written["GVL_IO"] and "bValveOpen AT %Q* : BOOL;" in written["GVL_IO"]
    assert "qualified_only" not in written["GVL_IO"]  # the list had none: GVL_IO.bStartButton and bStartButton both work
    assert written["GVL_Param"].count("{attribute 'qualified_only'}") == 1
    assert "aAlarms : ARRAY[1..GVL_Param.cMaxAlarms] OF ST_Alarm;" in written["FB_Alarms"]
    assert "CASE eState OF" in written["MAIN"] and "ELSIF" not in written["MAIN"]
    for text in written.values():
        blark.parse.parse_source_code(text)


def test_a_changed_block_keeps_its_bounds_by_name_while_they_hold(tmp_path: pathlib.Path) -> None:
    plc = st.load(FILL_STATION)
    source = (FILL_STATION.parent / "POUs" / "FB_Alarms.TcPOU").read_bytes()

    def Raise(self: Any, nCode: INT = 0) -> BOOL:  # noqa: N802 - ST name
        self.nCount = nCode
        return True

    plc.FB_Alarms.Raise = Raise
    written = {p.name: p.read_bytes() for p in st.export(plc, tmp_path, format="twincat")}
    assert written["FB_Alarms.TcPOU"] != source
    assert b"aAlarms : ARRAY[1..GVL_Param.cMaxAlarms] OF ST_Alarm;" in written["FB_Alarms.TcPOU"]
    assert b"nCount := nCode;" in written["FB_Alarms.TcPOU"]
    assert written["MAIN.TcPOU"] == (FILL_STATION.parent / "POUs" / "MAIN.TcPOU").read_bytes()


def test_bounds_by_name_are_written_only_while_they_give_the_class_bounds() -> None:
    plc = st.load("""// GVL GVL_P
{attribute 'qualified_only'}
VAR_GLOBAL CONSTANT
    cN : INT := 4;
END_VAR
FUNCTION_BLOCK FB_A
VAR
    a : ARRAY[0..GVL_P.cN - 1] OF INT;
END_VAR
END_FUNCTION_BLOCK
""")
    (declared,) = recorded(plc, ["FB_A"]).values()
    assert declared.dimensions("A", ((0, 3),)) == (Bound("0", "GVL_P.cN - 1", (0, 3)),)
    assert declared.dimensions("a", ((0, 4),)) is None  # the class says otherwise: its numbers are written
    assert "a : ARRAY[0..GVL_P.cN - 1] OF INT;" in st.dump(plc)


def test_a_flat_global_list_goes_back_out_as_written(tmp_path: pathlib.Path) -> None:
    source = "// GVL GVL_A\n{attribute 'qualified_only'}\nVAR_GLOBAL\n  x AT %QX0.1 : BOOL;   // the lamp\nEND_VAR\n"
    plc = st.load(source)
    assert [p.read_text() for p in st.export(plc, tmp_path / "st", format="st")] == [source]
    tc = st.export(plc, tmp_path / "tc", format="twincat")[0].read_text()
    assert "x AT %QX0.1 : BOOL;" in tc and tc.count("qualified_only") == 1


class Commented(FunctionBlock):
    n: INT = VAR(0)

    def body(self) -> None:
        # count the parts
        self.n += 1  # a note after a statement stays in Python
        if self.n > 3:
            # start again
            self.n = 0


def test_comments_on_lines_of_their_own_are_written_before_their_statement() -> None:
    assert "// count the parts\nn := n + 1;\nIF n > 3 THEN\n    // start again\n    n := 0;\nEND_IF" in st.dump([Commented])
    plc = st.load(FILL_STATION)
    assert "// the station's state machine\nipStation := fbStation;" in st.dump([plc.MAIN])


REFUSED = """FUNCTION F_First : REAL
VAR_IN_OUT
    a : ARRAY[*] OF REAL;
END_VAR
F_First := a[0];
END_FUNCTION

PROGRAM MAIN
VAR
    x : ARRAY[0..1] OF REAL;
    y : REAL;
END_VAR
x[0] := 1.5;
y := F_First(a := x);
END_PROGRAM
"""


def test_strict_export_of_a_loaded_pou_names_the_st_file_and_line(tmp_path: pathlib.Path) -> None:
    source = tmp_path / "main.st"
    source.write_text(REFUSED)
    plc = st.load(source)
    with pytest.raises(StExportError) as refused:
        st.export(plc, tmp_path / "out", format="twincat")
    assert f"{source}:14: a call of F_First()" in str(refused.value)  # y := F_First(a := x); is line 14
    report: list[str] = []
    st.export(plc, tmp_path / "lenient", format="twincat", lenient=True, report=report)
    assert any(f"{source}:14" in line for line in report)
    assert not (tmp_path / "out").exists()  # strict: nothing written


@gvl
class GVL_Size(GlobalVariables):
    cMax: INT = VAR(4, constant=True)


class FB_Buffer(FunctionBlock):
    aItems: ARRAY[INT] = VAR(bounds=(1, GVL_Size.cMax))
    aOther: ARRAY[INT] = VAR(bounds=(0, 3))

    def body(self) -> None:
        self.aItems[1] = GVL_Size.cMax


def test_a_python_class_bounded_by_a_gvl_constant_keeps_the_name() -> None:
    text = st.dump([FB_Buffer])
    assert "aItems : ARRAY[1..GVL_Size.cMax] OF INT;" in text and "aOther : ARRAY[0..3] OF INT;" in text
    again = st.load(text)
    assert again.FB_Buffer().aItems.bounds == ((1, 4),)


@gvl
class GVL_Table(GlobalVariables):
    aRows: ARRAY[INT] = VAR(bounds=(1, GVL_Size.cMax))


def test_a_python_list_bounded_by_name_keeps_its_qualified_only() -> None:
    text = st.dump([GVL_Table, GVL_Size])
    assert "// GVL GVL_Table\n{attribute 'qualified_only'}\nVAR_GLOBAL\n    aRows : ARRAY[1..GVL_Size.cMax] OF INT;" in text


LINKED = """// GVL GVL_Links
VAR_GLOBAL
    {attribute 'TcLinkTo' := 'TIIB[Term 2]^Channel 1'}
    bIn AT %I* : BOOL;   // the input
    // the lamp
    bOut AT %Q* : BOOL;
END_VAR
"""


def test_a_variables_pragmas_and_comments_stay_with_it(tmp_path: pathlib.Path) -> None:
    plc = st.load(LINKED)
    written = st.export(plc, tmp_path, format="twincat")[0].read_text()  # read as ST: the writer writes it
    assert "<![CDATA[" + LINKED.split("\n", 1)[1] + "]]>" in written
    again = st.load(tmp_path)
    assert st.export(again, tmp_path / "again", format="twincat")[0].read_text() == written
