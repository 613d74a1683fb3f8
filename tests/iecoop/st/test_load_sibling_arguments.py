"""ST declarations handing a member a variable of the same block through FB_init: ``fbUser : FB_User(fbCounter);``.

The dependency injection TwinCAT and CODESYS projects write: a REFERENCE TO,
an interface, ``ADR(x)`` for a POINTER TO, an ARRAY element, the value of an
elementary variable; by position or by name. Loaded, run over cycles, written
back as ST and as PLCopen XML and run again the same.
"""

from __future__ import annotations

import pathlib

import pytest

from iecoop import BOOL, INT, REFERENCE_TO, VAR, VAR_OUTPUT, FunctionBlock, Program, adr, ref_assign, sibling

st = pytest.importorskip("iecoop.st")

CELL = """INTERFACE I_Log
METHOD Write : BOOL
VAR_INPUT
    nCode : INT;
END_VAR
END_METHOD
END_INTERFACE
FUNCTION_BLOCK FB_Log IMPLEMENTS I_Log
VAR_OUTPUT
    nLast : INT;
    nLines : UDINT;
END_VAR
END_FUNCTION_BLOCK
METHOD Write : BOOL
VAR_INPUT
    nCode : INT;
END_VAR
nLast := nCode;
nLines := nLines + 1;
Write := TRUE;
END_METHOD
FUNCTION_BLOCK FB_Axis
VAR_OUTPUT
    nMoves : UDINT;
END_VAR
nMoves := nMoves + 1;
END_FUNCTION_BLOCK
FUNCTION_BLOCK FB_Mover
VAR
    _axis : REFERENCE TO FB_Axis;
    _log : I_Log;
    _pSpare : POINTER TO FB_Axis;
    _nCode : INT;
END_VAR
IF __ISVALIDREF(_axis) THEN
    _axis();
    _log.Write(_nCode);
END_IF
IF _pSpare <> 0 THEN
    _pSpare^();
END_IF
END_FUNCTION_BLOCK
METHOD FB_init : BOOL
VAR_INPUT
    bInitRetains : BOOL;
    bInCopyCode : BOOL;
    axis : REFERENCE TO FB_Axis;
    log : I_Log;
    pSpare : POINTER TO FB_Axis;
    nCode : INT;
END_VAR
_axis REF= axis;
_log := log;
_pSpare := pSpare;
_nCode := nCode;
END_METHOD
PROGRAM MAIN
VAR
    fbLog : FB_Log;
    aAxes : ARRAY[1..3] OF FB_Axis;
    fbSpare : FB_Axis;
    nBase : INT := 40;
    fbFirst : FB_Mover(aAxes[1], fbLog, ADR(fbSpare), nBase);
    fbThird : FB_Mover(axis := aAxes[3], log := fbLog, pSpare := 0, nCode := 7);
END_VAR
fbFirst();
fbThird();
fbThird();
END_PROGRAM
"""


def _trace(main: object, cycles: int) -> list[tuple[int, ...]]:
    rows = []
    for _ in range(cycles):
        main()  # type: ignore[operator]
        rows.append((
            main.fbLog.nLast, main.fbLog.nLines, main.fbSpare.nMoves,  # type: ignore[attr-defined]
            *(main.aAxes[i].nMoves for i in (1, 2, 3)),  # type: ignore[attr-defined]
        ))
    return rows


def test_each_form_of_argument_reaches_the_variable_beside_it() -> None:
    main = st.load(CELL).MAIN
    rows = _trace(main, 3)
    # the third mover logs last (its code 7), twice a cycle; the first logs 40 and moves the spare too
    assert rows == [(7, 3, 1, 1, 0, 2), (7, 6, 2, 2, 0, 4), (7, 9, 3, 3, 0, 6)]


def test_the_python_says_sibling_and_adr_of() -> None:
    source = st.to_python(CELL)
    assert 'fbFirst: FB_Mover = VAR(fb_init={"axis": sibling("aAxes", 1), "log": sibling("fbLog"), ' \
        '"pSpare": adr_of("fbSpare"), "nCode": sibling("nBase")})' in source


def test_written_back_as_st_it_declares_the_same_and_runs_the_same(tmp_path: pathlib.Path) -> None:
    text = st.dump(st.load(CELL))
    assert "fbFirst : FB_Mover(axis := aAxes[1], log := fbLog, pSpare := ADR(fbSpare), nCode := nBase);" in text
    path = tmp_path / "cell.st"
    path.write_text(text)
    assert _trace(st.load(path).MAIN, 4) == _trace(st.load(CELL).MAIN, 4)


def test_written_as_plcopen_xml_and_read_back_it_runs_the_same(tmp_path: pathlib.Path) -> None:
    (xml,) = st.export(st.load(CELL), tmp_path, format="plcopen")
    assert _trace(st.load(xml).MAIN, 4) == _trace(st.load(CELL).MAIN, 4)


def test_an_argument_computed_from_the_blocks_variables_is_refused_by_name() -> None:
    computed = CELL.replace("nBase);", "nBase + 1);")
    with pytest.raises(st.StUnsupportedError) as caught:
        st.load(computed)
    message = str(caught.value)
    assert ":63:" in message and "FB_init argument nCode of FB_Mover computes with variables of the same block" in message


def test_an_argument_naming_no_variable_is_refused_by_name() -> None:
    with pytest.raises(st.StUnsupportedError, match=r":63: unknown variable .fbSpar."):
        st.load(CELL.replace("ADR(fbSpare)", "ADR(fbSpar)"))


# --- a design born in Python: sibling() written as ST and read back ---------------------------------

class Tally(FunctionBlock):
    n: INT = VAR_OUTPUT(0)

    def body(self) -> None:
        self.n = self.n + 1


class Tallier(FunctionBlock):
    tally: REFERENCE_TO[Tally] = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, tally: REFERENCE_TO[Tally]) -> BOOL:
        ref_assign(self, "tally", adr(tally))
        return True

    def body(self) -> None:
        self.tally()


class Station(Program):
    tally: Tally = VAR()
    tallier: Tallier = VAR(fb_init={"tally": sibling("tally")})

    def body(self) -> None:
        self.tallier()
        self.tallier()


def test_a_design_born_in_python_round_trips_through_st(tmp_path: pathlib.Path) -> None:
    text = st.dump([Tally, Tallier, Station])
    assert "tallier : Tallier(tally := tally);" in text
    path = tmp_path / "station.st"
    path.write_text(text)
    station = st.load(path).Station
    station()
    station()
    assert station.tally.n == 4


def test_a_global_list_hands_one_global_to_another(tmp_path: pathlib.Path) -> None:
    source = CELL.split("PROGRAM MAIN")[0] + """VAR_GLOBAL
    gAxis : FB_Axis;
    gLog : FB_Log;
    gMover : FB_Mover(gAxis, gLog, 0, 5);
END_VAR
PROGRAM MAIN
gMover();
END_PROGRAM
"""
    path = tmp_path / "plant.st"
    path.write_text(source)
    plc = st.load(path)
    for _ in range(3):
        plc.MAIN()
    assert (plc.plant.gAxis.nMoves, plc.plant.gLog.nLast, plc.plant.gLog.nLines) == (3, 5, 3)
    assert 'sibling("gAxis")' in st.to_python(path)
