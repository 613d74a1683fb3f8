"""A loaded project written back as flat ST keeps what its source said, and the text runs the same.

The constructs are those of public TwinCAT projects the writer used to refuse or rename: a block as a
METHOD's local, a PROGRAM named in its own METHODs, names starting with ``_``, a METHOD's POINTER TO input,
DT and TOD literals, a shipped library's FUNCTION, a METHOD written inside its FUNCTION_BLOCK.
"""

from __future__ import annotations

import pathlib

import pytest

pytest.importorskip("blark")

from iecoop import INT, VAR, FunctionBlock, method, st  # noqa: E402
from iecoop.libraries import tc2_utilities  # noqa: E402
from iecoop.runtime import Runtime, Task  # noqa: E402

SOURCE = """
TYPE ST_Reading :
STRUCT
    _rRaw : LREAL := 1.5;
    tsTaken : DT := DT#2024-03-01-12:00;
END_STRUCT
END_TYPE

FUNCTION_BLOCK FB_Edge
VAR_INPUT _bIn : BOOL; END_VAR
VAR_OUTPUT _bRise : BOOL; END_VAR
VAR _bLast : BOOL; END_VAR
_bRise := _bIn AND NOT _bLast;
_bLast := _bIn;
END_FUNCTION_BLOCK

FUNCTION_BLOCK FB_Station
VAR
    _nParts : INT;
    _tPeriod : TON;
    _stLast : ST_Reading := (_rRaw := 2.5);
    todShift : TOD := TOD#06:30:00;
    bNaN : BOOL;
END_VAR
METHOD M_Count : INT
VAR_INPUT pTimer : POINTER TO TON; bPart : BOOL; END_VAR
VAR fbEdge : FB_Edge; END_VAR
fbEdge(_bIn := bPart);
IF pTimer <> 0 THEN
    pTimer^(IN := TRUE, PT := T#50MS);
END_IF
M_Count := _nParts + 1;
END_METHOD
_nParts := M_Count(ADR(_tPeriod), TRUE);
bNaN := LrealIsNaN(_stLast._rRaw);
IF _stLast.tsTaken = DT#2024-03-01-12:00 THEN
    _stLast._rRaw := _stLast._rRaw + 1.0;
END_IF
END_FUNCTION_BLOCK

FUNCTION F_Rate : UDINT
VAR_INPUT nParts : UDINT; nMs : UDINT; END_VAR
F_Rate := nParts * 60000 / nMs;
END_FUNCTION

PROGRAM PRG_Counter
VAR _nNext : INT; END_VAR
END_PROGRAM
METHOD Next : INT
_nNext := _nNext + 1;
Next := _nNext;
END_METHOD
METHOD Twice : INT
Twice := PRG_Counter.Next() + PRG_Counter.Next();
END_METHOD

PROGRAM MAIN
VAR
    fbStation : FB_Station;
    nTwice : INT;
    nRate : UDINT;
END_VAR
fbStation();
nTwice := PRG_Counter.Twice();
nRate := F_Rate(nParts := 30, nMs := 1000);
END_PROGRAM
"""


def _project(tmp_path: pathlib.Path) -> pathlib.Path:
    (tmp_path / "station.st").write_text(SOURCE)
    return tmp_path / "station.st"


def _state(module: object) -> tuple[object, ...]:
    main, counter = getattr(module, "MAIN"), getattr(module, "PRG_Counter")
    station = main.fbStation
    return (station.st_nParts_, station.st_stLast_.st_rRaw_, station.todShift, station.bNaN, main.nTwice, main.nRate,
            counter.st_nNext_, station.st_tPeriod_.Q)


def test_a_loaded_project_written_as_flat_st_keeps_its_names_and_forms(tmp_path: pathlib.Path) -> None:
    text = st.dump(st.load(_project(tmp_path), libraries={"Tc2_Utilities": tc2_utilities}))
    for line in ("    _nParts : INT;", "    _stLast : ST_Reading := (_rRaw := 2.5);", "    _rRaw : LREAL := 1.5;",
                 "_nParts := M_Count(ADR(_tPeriod), TRUE);", "bNaN := LrealIsNaN(_stLast._rRaw);", "fbEdge(_bIn := bPart);",
                 "    fbEdge : FB_Edge;", "    pTimer : POINTER TO TON;", "todShift : TOD := TOD#06:30:00;",
                 "tsTaken : DT := DT#2024-03-01-12:00:00;", "Twice := TO_INT(PRG_Counter.Next() + PRG_Counter.Next());",
                 "F_Rate := nParts * 60000 / nMs;"):
        assert line in text, line
    assert "st_" not in text  # no Python name of an ST name Python could not take


def test_the_flat_text_of_a_loaded_project_runs_as_the_project_does(tmp_path: pathlib.Path) -> None:
    libraries = {"Tc2_Utilities": tc2_utilities}
    loaded = st.load(_project(tmp_path), libraries=libraries)
    again = st.load(st.dump(loaded), libraries=libraries)
    states = []
    for module in (loaded, again):
        runtime = Runtime(store=":memory:")
        runtime.add_task(Task("PlcTask", interval=10), getattr(module, "PRG_Counter"), getattr(module, "MAIN"))
        runtime.run(cycles=8)
        states.append(_state(module))
    assert states[0] == states[1]
    assert states[0][:3] == (8, 10.5, 6 * 3_600_000 + 30 * 60_000) and states[0][4:7] == (31, 1800, 16)
    assert states[0][7] is True  # the timer the METHOD called through its pointer ran out after 50 ms


def test_a_method_written_inside_its_block_is_written_after_it() -> None:
    source = ("FUNCTION_BLOCK FB_T\nVAR n : INT; END_VAR\nMETHOD M_Add\nVAR_INPUT k : INT; END_VAR\nn := n + k;\nEND_METHOD\n"
              "M_Add(2);\nEND_FUNCTION_BLOCK\n")
    text = st.dump(st.load(source))
    assert text.index("END_FUNCTION_BLOCK") < text.index("METHOD PUBLIC M_Add")
    block = st.load(text).FB_T()
    block()
    block()
    assert block.n == 4


def test_global_lists_dumped_into_one_file_keep_their_names(tmp_path: pathlib.Path) -> None:
    source = ("VAR_GLOBAL\n    nA : INT := 1;\nEND_VAR\n// GVL GVL_Two\nVAR_GLOBAL\n    nB : INT := 2;\nEND_VAR\n"
              "PROGRAM MAIN\nVAR n : INT; END_VAR\nn := GVL.nA + GVL_Two.nB;\nEND_PROGRAM\n")
    path = tmp_path / "plant.st"
    path.write_text(st.dump(st.load(source)))
    again = st.load(path)  # a `// GVL name` line names its list in a file too, not only the file's own name
    again.MAIN()
    assert again.MAIN.n == 3 and again.GVL_Two.nB == 2 and again.GVL.nA == 1


def test_an_input_named_as_a_keyword_variable_still_hides_it() -> None:
    """``word`` is an ST keyword: the input and the variable are both ``word_`` in ST, so the variable is THIS^.word_."""
    class Module(FunctionBlock):
        word: INT = VAR(-1)

        @method
        def bind(self, word: INT) -> None:
            self.word = word

    text = st.dump([Module])
    assert "THIS^.word_ := word_;" in text
    loaded = st.load(text).Module()
    loaded.bind(word=3)
    assert loaded.word_ == 3
