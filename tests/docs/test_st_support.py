"""The "What is not (yet)" list of docs/st.md agrees with the ST reader: every row is refused by ``st.load``."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

st = pytest.importorskip("iecoop.st")

ROOT = Path(__file__).resolve().parent.parent.parent
PAGE = ROOT / "docs" / "st.md"

_FB_A = "FUNCTION_BLOCK FB_A\nVAR n : INT; END_VAR\nEND_FUNCTION_BLOCK\n"

#: The start of each row of the list -> sources the row says are refused, one per construct it names.
REFUSED: dict[str, list[str]] = {
    "outputs (`=>`) and in-out arguments into a local variable of a PROPERTY accessor": [
        _FB_A + "METHOD Get : BOOL\nVAR_OUTPUT v : INT; END_VAR\nv := 3;\nGet := TRUE;\nEND_METHOD\n"
        "PROPERTY P : INT\nVAR q : INT; END_VAR\nGet(v => q);\nP := q;\nEND_PROPERTY",
        _FB_A + "METHOD Inc : BOOL\nVAR_IN_OUT v : INT; END_VAR\nv := v + 1;\nInc := TRUE;\nEND_METHOD\n"
        "PROPERTY P : INT\nVAR q : INT; END_VAR\nInc(v := q);\nP := q;\nEND_PROPERTY",
    ],
    "ARRAY locals and `VAR_STAT` in a PROPERTY accessor": [
        _FB_A + "PROPERTY P : INT\nVAR a : ARRAY[0..2] OF INT; END_VAR\nP := a[0];\nEND_PROPERTY",
        _FB_A + "PROPERTY P : INT\nVAR_STAT k : INT; END_VAR\nP := k;\nEND_PROPERTY",
    ],
    "a FUNCTION_BLOCK input passed by value to a METHOD or FUNCTION": [
        _FB_A + "FUNCTION F : INT\nVAR_INPUT a : FB_A; END_VAR\nF := a.n;\nEND_FUNCTION",
    ],
    "`REF= 0` of a local `REFERENCE TO` a STRUCT, UNION or FB": [
        "TYPE ST_P : STRUCT x : INT; END_STRUCT END_TYPE\n"
        "FUNCTION F : INT\nVAR r : REFERENCE TO ST_P; END_VAR\nr REF= 0;\nF := 0;\nEND_FUNCTION",
    ],
    "a label inside IF, CASE or a loop, and a JMP inside a FOR, WHILE or REPEAT loop": [
        "PROGRAM MAIN\nVAR i : INT; END_VAR\nIF i = 0 THEN\nL1: i := 1;\nEND_IF\nEND_PROGRAM",
        "PROGRAM MAIN\nVAR i : INT; END_VAR\nL1: i := 0;\nFOR i := 1 TO 3 DO\nJMP L1;\nEND_FOR\nEND_PROGRAM",
    ],
    "a located variable without a name (`AT %IX0.0 : BOOL`) and direct addresses in code": [
        "PROGRAM MAIN\nVAR\n    AT %IX0.0 : BOOL;\nEND_VAR\nEND_PROGRAM",
        "PROGRAM MAIN\nVAR b : BOOL; END_VAR\nb := %IX0.0;\nEND_PROGRAM",
    ],
    "`R_EDGE` / `F_EDGE` inputs, `ARRAY[*]` outside a VAR_IN_OUT": [
        "FUNCTION_BLOCK FB_E\nVAR_INPUT x : BOOL R_EDGE; END_VAR\nEND_FUNCTION_BLOCK",
        "FUNCTION_BLOCK FB_E\nVAR_INPUT x : BOOL F_EDGE; END_VAR\nEND_FUNCTION_BLOCK",
        "FUNCTION_BLOCK FB_E\nVAR a : ARRAY[*] OF INT; END_VAR\nEND_FUNCTION_BLOCK",
        "FUNCTION_BLOCK FB_E\nVAR_INPUT a : ARRAY[*] OF INT; END_VAR\nEND_FUNCTION_BLOCK",
    ],
    "generic types (`ANY_NUM` ...) outside a VAR_INPUT of a FUNCTION or METHOD": [
        "FUNCTION_BLOCK FB_G\nVAR_INPUT x : ANY_NUM; END_VAR\nEND_FUNCTION_BLOCK",
    ],
    "a METHOD, FUNCTION or PROPERTY result of type `REFERENCE TO` an elementary type": [
        _FB_A + "METHOD Cell : REFERENCE TO INT\nCell REF= n;\nEND_METHOD",
        _FB_A + "PROPERTY P : REFERENCE TO INT\nP REF= n;\nEND_PROPERTY\nPROPERTY P.Set : REFERENCE TO INT\nEND_PROPERTY",
    ],
    "`__NEW` of an array of STRUCTs, or of an elementary type without a count": [
        "TYPE ST_S : STRUCT x : INT; END_STRUCT END_TYPE\n"
        "FUNCTION_BLOCK FB_H\nVAR p : POINTER TO ST_S; END_VAR\np := __NEW(ST_S, 16);\nEND_FUNCTION_BLOCK",
        "FUNCTION_BLOCK FB_H\nVAR p : POINTER TO BYTE; END_VAR\np := __NEW(BYTE);\nEND_FUNCTION_BLOCK",
    ],
    "`__SYSTEM.AnyType` as the type of a variable or STRUCT member": [
        "FUNCTION F : DINT\nVAR a : __SYSTEM.AnyType; END_VAR\nF := a.diSize;\nEND_FUNCTION",
        "TYPE ST_Slot : STRUCT item : __SYSTEM.AnyType; END_STRUCT END_TYPE",
    ],
    "an inline enumeration in a GVL or a STRUCT": [
        "VAR_GLOBAL eMode : (MODE_A, MODE_B); END_VAR",
        "TYPE ST_X : STRUCT eMode : (MODE_A, MODE_B); END_STRUCT END_TYPE",
    ],
    "`SHL`, `SHR`, `ROL`, `ROR` of an untyped literal": [
        "FUNCTION F : LWORD\nVAR_INPUT n : DWORD; END_VAR\nF := SHL(32, n);\nEND_FUNCTION",
        "FUNCTION F : LWORD\nVAR_INPUT n : DWORD; END_VAR\nF := ROR(32, n);\nEND_FUNCTION",
    ],
    "an array literal assigned to a local ARRAY of a METHOD or FUNCTION": [
        "FUNCTION F : INT\nVAR a : ARRAY[0..1] OF INT; END_VAR\na := [1, 2];\nF := a[0];\nEND_FUNCTION",
    ],
    "a FUNCTION_BLOCK member of a STRUCT with an initialiser": [
        "TYPE ST_T : STRUCT t : TON := (PT := T#1S); END_STRUCT END_TYPE",
    ],
    "a FUNCTION_BLOCK local of a METHOD or FUNCTION with an initialiser": [
        _FB_A + "METHOD M : INT\nVAR fbLocal : FB_A := (n := 2); END_VAR\nM := fbLocal.n;\nEND_METHOD",
    ],
    "indexing a `POINTER TO` an ARRAY": [
        "FUNCTION F : INT\nVAR a : ARRAY[0..1] OF INT; p : POINTER TO ARRAY[0..1] OF INT; END_VAR\np := ADR(a);\nF := p[0];\nEND_FUNCTION",
    ],
    "a conversion into DATE, TOD or DT of a date or time type that counts in another unit": [
        "FUNCTION F : DT\nVAR_INPUT td : TOD; END_VAR\nF := TO_DT(td);\nEND_FUNCTION",
        "FUNCTION F : TOD\nVAR_INPUT d : DATE; END_VAR\nF := DATE_TO_TOD(d);\nEND_FUNCTION",
    ],
    "a `REFERENCE TO` or `POINTER TO` bound to a variable in an initialiser outside a block": [
        "FUNCTION_BLOCK FB_R\nVAR_INPUT r : REFERENCE TO INT; END_VAR\nEND_FUNCTION_BLOCK\n"
        "VAR_GLOBAL n : INT; fbR : FB_R := (r := n); END_VAR",
        "FUNCTION_BLOCK FB_P\nVAR_INPUT p : POINTER TO INT; END_VAR\nEND_FUNCTION_BLOCK\n"
        "VAR_GLOBAL n : INT; fbP : FB_P := (p := ADR(n)); END_VAR",
    ],
}

#: Rows the reader does not refuse yet: it loads them with a different meaning, so the row stays.
NOT_REFUSED_YET = {
    # The input is bound to the caller's instance (no copy), and its default instance is shared by all calls.
    "a FUNCTION_BLOCK input passed by value to a METHOD or FUNCTION",
}


def unsupported_rows() -> list[str]:
    """The bullets of the page's "What is not (yet)" section, as written."""
    text = PAGE.read_text(encoding="utf-8")
    section = re.search(r"^## What is not \(yet\)\n(.*?)(?=^#)", text, re.M | re.S)
    assert section is not None, "docs/st.md has no 'What is not (yet)' section"
    return [line[2:] for line in section.group(1).splitlines() if line.startswith("- ")]


def _sample_of(row: str) -> str:
    found = [start for start in REFUSED if row.startswith(start)]
    assert found, f"docs/st.md lists {row!r} as unsupported, and this test has no ST source to check it with"
    return found[0]


def test_every_row_of_the_list_has_sources_to_check_it_with() -> None:
    rows = unsupported_rows()
    assert len(rows) >= 8
    assert sorted(_sample_of(row) for row in rows) == sorted(REFUSED)


@pytest.mark.parametrize(
    ("row", "source"),
    [
        pytest.param(
            row, source, id=f"{row[:40]}-{number}",
            marks=[pytest.mark.xfail(reason="the reader loads it", strict=True)] if row in NOT_REFUSED_YET else [],
        )
        for row, sources in REFUSED.items()
        for number, source in enumerate(sources)
    ],
)
def test_each_row_is_refused_by_the_reader(row: str, source: str) -> None:
    with pytest.raises(st.StUnsupportedError, match=r"^<st>:\d+: .*(not supported|no address|cannot be unbound)"):
        st.load(source)


def test_real_to_string_is_listed_as_supported_and_loads() -> None:
    rows = "\n".join(unsupported_rows())
    assert "REAL_TO_STRING" not in rows
    assert "REAL and LREAL `*_TO_STRING`" in PAGE.read_text(encoding="utf-8")
    plc = st.load(
        "FUNCTION F_Label : STRING\nVAR r : REAL := 12.5; END_VAR\n"
        "F_Label := CONCAT('Volume ', REAL_TO_STRING(r));\nEND_FUNCTION"
    )
    assert plc.F_Label() == "Volume 12.5"


def test_the_exponent_operator_is_named_as_not_read_and_expt_loads() -> None:
    page = PAGE.read_text(encoding="utf-8")
    assert "The exponent operator `**` of IEC 61131-3 is not read" in page
    assert "MOD, EXPT;" in page
    with pytest.raises(st.StSyntaxError, match=r"^<st>:3: .*cannot parse 'y := 2\.0 \*\* 3;'"):
        st.load("FUNCTION_BLOCK FB_P\nVAR_OUTPUT y : LREAL; END_VAR\ny := 2.0 ** 3;\nEND_FUNCTION_BLOCK\n", cache=False)
    plc = st.load("FUNCTION F_Cube : LREAL\nVAR_INPUT x : LREAL; END_VAR\nF_Cube := EXPT(x, 3);\nEND_FUNCTION\n", cache=False)
    assert plc.F_Cube(2.0) == 8.0
    assert plc.F_Cube(x=-1.5) == -3.375
