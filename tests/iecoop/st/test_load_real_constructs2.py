"""More constructs public TwinCAT projects write: each loaded and run, the values worked by hand."""

from __future__ import annotations

import pathlib

import pytest

from iecoop.exceptions import DefinitionError
from iecoop.libraries import tc3_module

st = pytest.importorskip("iecoop.st")


# --- HRESULT and its constants, from Tc3_Module -----------------------------------------------------

RESULTS = """FUNCTION F_Worse : HRESULT
VAR_INPUT hrA : HRESULT; hrB : HRESULT; END_VAR
IF hrA.31 THEN F_Worse := hrA;
ELSIF hrB.31 THEN F_Worse := hrB;
ELSIF hrA >= hrB THEN F_Worse := hrA;
ELSE F_Worse := hrB;
END_IF
END_FUNCTION
FUNCTION_BLOCK FB_Step
VAR_INPUT nCycle : INT; END_VAR
VAR_OUTPUT hrLast : HRESULT; bFailed : BOOL; bOk : BOOL; nCode : DWORD; idObject : OTCID := 16#71010005; END_VAR
VAR hrNow : HRESULT; END_VAR
CASE nCycle OF
    1: hrNow := S_OK;
    2: hrNow := S_PENDING;
    3: hrNow := DWORD_TO_DINT(16#98110704);
ELSE hrNow := S_FALSE;
END_CASE
hrLast := F_Worse(hrLast, hrNow);
bFailed := FAILED(hrLast);
bOk := SUCCEEDED(hrNow) AND hrNow <> S_FALSE;
nCode := TO_DWORD(hrLast) AND 16#FFF;
END_FUNCTION_BLOCK
"""


def test_hresult_and_the_status_constants_of_tc3_module() -> None:
    # TYPE HRESULT : DINT; S_OK 0, S_FALSE 1, S_PENDING 16#203; SUCCEEDED(hr) is hr >= 0, FAILED(hr) hr < 0
    plc = st.load(RESULTS, libraries={"Tc3_Module": tc3_module})
    fb = plc.FB_Step()
    seen = []
    for cycle in (1, 2, 4, 3, 1):
        fb(nCycle=cycle)
        seen.append((fb.hrLast, fb.bFailed, fb.bOk, fb.nCode))
    assert seen == [
        (0, False, True, 0),  # S_OK
        (0x203, False, True, 0x203),  # S_PENDING outranks S_OK
        (0x203, False, False, 0x203),  # S_FALSE (1) is lower than S_PENDING, and not OK
        (0x98110704 - 2**32, True, False, 0x704),  # an error (bit 31 set) wins, as a negative DINT
        (0x98110704 - 2**32, True, True, 0x704),  # and stays: a later S_OK is not worse
    ]
    assert fb.idObject == 0x71010005  # OTCID is a UDINT


def test_hresult_is_a_name_of_tc3_module_only() -> None:
    with pytest.raises(DefinitionError, match=r"<st>:2: unknown type 'HRESULT'"):
        st.load(RESULTS)


# --- __POUNAME() ------------------------------------------------------------------------------------

POU_NAMES = """FUNCTION F_Tag : STRING
VAR_INPUT sWhat : STRING; END_VAR
F_Tag := CONCAT(CONCAT(__POUNAME(), ':'), sWhat);
END_FUNCTION
FUNCTION_BLOCK FB_Valve
VAR_OUTPUT sClass : STRING := __POUNAME(); sLast : STRING; nCalls : INT; END_VAR
nCalls := nCalls + 1;
sLast := CONCAT(__POUNAME(), INT_TO_STRING(nCalls));
END_FUNCTION_BLOCK
METHOD Describe : STRING
Describe := CONCAT(__POUNAME(), F_Tag('open'));
END_METHOD
PROGRAM P_Line
VAR sName : STRING(40) := __POUNAME(); fbValve : FB_Valve; sInfo : STRING; END_VAR
fbValve();
sInfo := fbValve.Describe();
END_PROGRAM
"""


def test_pouname_is_the_name_of_the_pou_it_stands_in() -> None:
    # __POUNAME() is the name of the POU whose code it stands in, as a STRING: in a METHOD the block's
    # name with the method's (FB_Valve.Describe), as TwinCAT writes it
    plc = st.load(POU_NAMES)
    assert plc.F_Tag("x") == "F_Tag:x"
    valve = plc.FB_Valve()
    assert valve.sClass == "FB_Valve"
    valve()
    valve()
    assert (valve.sLast, valve.nCalls) == ("FB_Valve2", 2)
    plc.P_Line()
    assert plc.P_Line.sName == "P_Line"
    assert plc.P_Line.sInfo == "FB_Valve.DescribeF_Tag:open"


def test_pouname_takes_no_operands() -> None:
    with pytest.raises(DefinitionError, match=r"__POUNAME\(\) takes no operands"):
        st.load("FUNCTION F_Bad : STRING\nF_Bad := __POUNAME(1);\nEND_FUNCTION\n")


# --- PVOID -----------------------------------------------------------------------------------------

UNTYPED = """FUNCTION F_CopyInto : UDINT
VAR_INPUT pDest : PVOID; pSrc : PVOID; cb : UDINT; END_VAR
IF pDest = 0 OR pSrc = 0 THEN RETURN; END_IF
F_CopyInto := MEMCPY(pDest, pSrc, cb);
END_FUNCTION
FUNCTION_BLOCK FB_Register
VAR_OUTPUT nValue : UINT; nCopied : UDINT; END_VAR
VAR nRaw : UINT := 16#1234; pLast : PVOID; END_VAR
pLast := THIS^.pBuffer;
nCopied := F_CopyInto(pLast, ADR(nRaw), SIZEOF(nRaw));
nRaw := nRaw + 1;
END_FUNCTION_BLOCK
PROPERTY PROTECTED pBuffer : PVOID
pBuffer := ADR(nValue);
END_PROPERTY
"""


def test_pvoid_is_an_untyped_address() -> None:
    # PVOID holds any address (a PROPERTY gives it, a local keeps it, a FUNCTION takes it) for MEMCPY to use
    plc = st.load(UNTYPED)
    reg = plc.FB_Register()
    reg()
    assert (reg.nValue, reg.nCopied) == (0x1234, 2)
    reg()
    assert (reg.nValue, reg.nCopied) == (0x1235, 2)
    assert plc.F_CopyInto(cb=4) == 0  # null addresses (the inputs' default) copy nothing


# --- Tc2_Utilities' LREAL checks, called qualified ----------------------------------------------------

CLAMP = """FUNCTION_BLOCK FB_Clamp
VAR_INPUT fIn : LREAL; fMax : LREAL; END_VAR
VAR_OUTPUT fOut : LREAL; bNaN : BOOL; bFinite : BOOL; END_VAR
fOut := fIn;
bNaN := Tc2_Utilities.LrealIsNaN(fMax);
bFinite := LrealIsFinite(fIn);
IF NOT bNaN AND_THEN fOut > fMax THEN fOut := fMax; END_IF
END_FUNCTION_BLOCK
"""


def test_lrealisnan_and_lrealisfinite_of_tc2_utilities() -> None:
    # a NaN limit (the unset default of the block this comes from) clamps nothing; an infinite input is not finite
    from iecoop.libraries import tc2_utilities

    plc = st.load(CLAMP, libraries={"Tc2_Utilities": tc2_utilities})
    fb = plc.FB_Clamp()
    seen = []
    for value, limit in ((5.0, 3.0), (5.0, float("nan")), (float("inf"), 3.0), (float("-inf"), float("nan"))):
        fb(fIn=value, fMax=limit)
        seen.append((fb.fOut, fb.bNaN, fb.bFinite))
    assert seen == [(3.0, False, True), (5.0, True, True), (3.0, False, False), (float("-inf"), True, False)]


def test_a_qualified_name_a_library_lacks_is_named_with_its_library() -> None:
    from iecoop.libraries import tc2_utilities

    with pytest.raises(DefinitionError, match=r"<st>:4: unknown name 'Tc2_Utilities.LrealIsHuge': "
                                              r"library Tc2_Utilities declares no LrealIsHuge"):
        st.load(CLAMP.replace("Tc2_Utilities.LrealIsNaN", "Tc2_Utilities.LrealIsHuge").replace("fOut := fIn;\n", ""),
                libraries={"Tc2_Utilities": tc2_utilities})


@pytest.mark.parametrize(("source", "line", "name"), [
    ("FUNCTION F_Size : DINT\nVAR vAny : __SYSTEM.AnyType; END_VAR\nF_Size := vAny.diSize;\nEND_FUNCTION", 2, "vAny"),
    ("FUNCTION_BLOCK FB_Box\nVAR vHeld : __SYSTEM.AnyType; END_VAR\nEND_FUNCTION_BLOCK", 2, "vHeld"),
    ("TYPE ST_Cell :\nSTRUCT\n  vItem : __SYSTEM.AnyType;\nEND_STRUCT\nEND_TYPE", 3, "vItem"),
])
def test_anytype_as_a_stored_type_is_refused_naming_the_generic_input(source: str, line: int, name: str) -> None:
    # only a generic input of a FUNCTION or METHOD receives an AnyType; a local, member or STRUCT field of it is refused
    with pytest.raises(st.StUnsupportedError, match=rf"<st>:{line}: VAR\w* {name} : ANY: a generic type is not supported "
                                                    r"outside a VAR_INPUT of a FUNCTION or METHOD"):
        st.load(source)


# --- a body in a graphical language -------------------------------------------------------------------

def _pou_file(folder: pathlib.Path, name: str, implementation: str, extra: str = "") -> pathlib.Path:
    path = folder / f"{name}.TcPOU"
    path.write_text('<?xml version="1.0" encoding="utf-8"?>\n<TcPlcObject Version="1.1.0.1">\n'
                    f'  <POU Name="{name}" Id="{{00000000-0000-0000-0000-000000000001}}" SpecialFunc="None">\n'
                    f"    <Declaration><![CDATA[PROGRAM {name}\nVAR nCount : INT; END_VAR\n]]></Declaration>\n"
                    f"    <Implementation>\n{implementation}\n    </Implementation>\n{extra}  </POU>\n</TcPlcObject>\n")
    return path


NETWORK = ('      <NWL>\n        <XmlArchive>\n          <Data>\n            <o xml:space="preserve" t="NWLImplementationObject">\n'
           '              <v n="DefaultViewMode">"{mode}"</v>\n            </o>\n          </Data>\n        </XmlArchive>\n      </NWL>')


@pytest.mark.parametrize(("mode", "language"), [("Fbd", "FBD"), ("Ld", "LD"), ("IL", "IL")])
def test_a_body_in_a_network_language_is_refused_not_read_as_empty(tmp_path: pathlib.Path, mode: str, language: str) -> None:
    # TwinCAT keeps FBD, LD and IL bodies as an XML network list; iecoop reads ST only, and an empty body in its place
    # would run as doing nothing
    path = _pou_file(tmp_path, "P_Pump", NETWORK.format(mode=mode))
    with pytest.raises(DefinitionError, match=rf"P_Pump.TcPOU:8: PROGRAM P_Pump: its body is written in {language}, "
                                              r"not Structured Text: iecoop reads ST only \(write the body in ST\)"):
        st.load(path)


def test_a_method_in_sfc_is_refused_naming_the_method(tmp_path: pathlib.Path) -> None:
    method = ('    <Method Name="Step" Id="{00000000-0000-0000-0000-000000000002}">\n'
              "      <Declaration><![CDATA[METHOD Step : BOOL\n]]></Declaration>\n"
              "      <Implementation>\n        <SFC />\n      </Implementation>\n    </Method>\n")
    path = _pou_file(tmp_path, "P_Fill", "      <ST><![CDATA[nCount := nCount + 1;]]></ST>", extra=method)
    with pytest.raises(DefinitionError, match=r"P_Fill.TcPOU:14: METHOD P_Fill.Step: its body is written in SFC"):
        st.load(path)
    path.write_text(path.read_text().replace("<SFC />", "<ST><![CDATA[Step := TRUE;]]></ST>"))
    plc = st.load(path)  # the same POU in ST loads and runs
    plc.P_Fill()
    plc.P_Fill()
    assert plc.P_Fill.nCount == 2 and plc.P_Fill.Step() is True


# --- a POINTER indexed like an ARRAY -----------------------------------------------------------------

BYTES = """TYPE ST_Slot : STRUCT nId : INT; fLoad : REAL; END_STRUCT END_TYPE
FUNCTION F_Digits : STRING
VAR_INPUT sIn : STRING; END_VAR
VAR pIn : POINTER TO BYTE; pOut : POINTER TO BYTE; sOut : STRING; i : INT; k : INT; END_VAR
pIn := ADR(sIn);
pOut := ADR(sOut);
WHILE pIn[i] <> 0 DO
    IF pIn[i] >= 16#30 AND pIn[i] <= 16#39 THEN pOut[k] := pIn[i]; k := k + 1; END_IF
    i := i + 1;
END_WHILE
pOut[k] := 0;
F_Digits := sOut;
END_FUNCTION
FUNCTION_BLOCK FB_Slots
VAR_INPUT nReach : INT; END_VAR
VAR_OUTPUT nIds : INT; fTotal : REAL; END_VAR
VAR aSlots : ARRAY[1..3] OF ST_Slot; pSlot : POINTER TO ST_Slot; i : INT; END_VAR
pSlot := ADR(aSlots);
FOR i := 0 TO nReach DO
    pSlot[i].nId := (i + 1) * 10;
    pSlot[i].fLoad := pSlot[i].fLoad + 0.5;
END_FOR
nIds := aSlots[1].nId + aSlots[2].nId + aSlots[3].nId;
fTotal := aSlots[1].fLoad + aSlots[2].fLoad + aSlots[3].fLoad;
END_FUNCTION_BLOCK
"""


def test_a_pointer_indexed_like_an_array_reads_and_writes_the_element_at_its_offset() -> None:
    # p[i] is the element i * SIZEOF(T) bytes past p: a byte scan of a STRING, and the members of STRUCTs
    from iecoop import ExceptionCode, PlcException

    plc = st.load(BYTES)
    assert plc.F_Digits("a1b22c3") == "1223"
    assert plc.F_Digits("none") == ""
    slots = plc.FB_Slots()
    slots(nReach=2)
    slots(nReach=2)
    assert (slots.nIds, slots.fTotal) == (60, 3.0)  # 10 + 20 + 30; each load 0.5 twice
    with pytest.raises(PlcException) as fault:
        slots(nReach=3)  # pSlot[3] is past the ARRAY
    assert fault.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


def test_a_pointer_takes_one_index() -> None:
    with pytest.raises(DefinitionError, match=r"<st>:4: .*a pointer is indexed with one index"):
        st.load("FUNCTION F : BYTE\nVAR_INPUT n : INT; END_VAR\nVAR p : POINTER TO BYTE; END_VAR\nF := p[n, 1];\nEND_FUNCTION\n")


# --- POUs for implicit checks ---------------------------------------------------------------------------

CHECKED = """FUNCTION CheckBounds : DINT
VAR_INPUT index, lower, upper : DINT; END_VAR
{noflow}
IF index < lower THEN CheckBounds := lower;
ELSIF index > upper THEN CheckBounds := upper;
ELSE CheckBounds := index;
END_IF
{flow}
END_FUNCTION
FUNCTION CheckDivDInt : DINT
VAR_INPUT divisor : DINT; END_VAR
IF divisor = 0 THEN CheckDivDInt := 1; ELSE CheckDivDInt := divisor; END_IF
END_FUNCTION
FUNCTION CheckDivLReal : LREAL
VAR_INPUT divisor : LREAL; END_VAR
IF divisor = 0 THEN CheckDivLReal := 1; ELSE CheckDivLReal := divisor; END_IF
END_FUNCTION
FUNCTION_BLOCK FB_Table
VAR_INPUT nAt : INT; nDiv : DINT; fDiv : LREAL; END_VAR
VAR_OUTPUT nRead : INT; nQuot : DINT; fQuot : LREAL; END_VAR
VAR aCells : ARRAY[1..4] OF INT := [10, 20, 30, 40]; aGrid : ARRAY[0..1, 0..2] OF INT; END_VAR
nRead := aCells[nAt];
aCells[nAt] := aCells[nAt] + 1;
aGrid[nAt, nAt] := nAt;
nQuot := 100 / nDiv;
fQuot := 7.5 / fDiv;
END_FUNCTION_BLOCK
"""


def test_a_project_s_implicit_checks_are_called_as_twincat_calls_them() -> None:
    # CheckBounds gets every ARRAY index with the dimension's bounds, and the index it gives is used;
    # CheckDivDInt and CheckDivLReal get the divisor of every integer and LREAL division
    plc = st.load(CHECKED)
    table = plc.FB_Table()
    table(nAt=2, nDiv=7, fDiv=2.5)
    assert (table.nRead, table.nQuot, table.fQuot) == (20, 14, 3.0)
    table(nAt=9, nDiv=0, fDiv=0.0)  # index 9 is held to 4 (and to 1 and 2 in the grid), the divisors 0 made 1
    assert (table.nRead, table.nQuot, table.fQuot) == (40, 100, 7.5)
    table(nAt=-3, nDiv=-5, fDiv=-0.5)
    assert (table.nRead, table.nQuot, table.fQuot) == (10, -20, -15.0)
    table(nAt=4, nDiv=1, fDiv=1.0)
    assert table.nRead == 41  # 40, plus one from the call whose index 9 was held to 4 (-3 was held to 1)


def test_without_check_functions_an_index_out_of_bounds_faults() -> None:
    from iecoop import ExceptionCode, PlcException

    plc = st.load(CHECKED.replace("FUNCTION CheckBounds", "FUNCTION NoCheckBounds").replace("CheckBounds :=", "NoCheckBounds :="))
    table = plc.FB_Table()
    with pytest.raises(PlcException) as fault:
        table(nAt=9, nDiv=1, fDiv=1.0)
    assert fault.value.code == ExceptionCode.RTSEXCPT_ARRAYBOUNDS


# --- a standard block as a local of a FUNCTION ----------------------------------------------------------

def test_a_standard_block_local_of_a_function_is_new_at_every_call() -> None:
    # a FUNCTION's locals live for one call: its R_TRIG has seen no earlier CLK, so a TRUE input is an edge every
    # call, and its CTU has counted that one edge only
    plc = st.load("""FUNCTION F_Edge : BOOL
VAR_INPUT bIn : BOOL; END_VAR
VAR rt : R_TRIG; ctEdges : CTU; END_VAR
rt(CLK := bIn);
ctEdges(CU := rt.Q, PV := 1);
F_Edge := rt.Q AND ctEdges.Q AND ctEdges.CV = 1;
END_FUNCTION
FUNCTION_BLOCK FB_Count
VAR_INPUT bIn : BOOL; END_VAR
VAR_OUTPUT nEdges : INT; END_VAR
IF F_Edge(bIn) THEN nEdges := nEdges + 1; END_IF
END_FUNCTION_BLOCK""")
    fb = plc.FB_Count()
    for value in (True, True, False, True):
        fb(bIn=value)
    assert fb.nEdges == 3  # every TRUE call, the held ones too
    assert plc.F_Edge(False) is False


# --- a body whose first statement has a label -------------------------------------------------------------

def test_a_body_that_starts_with_a_label_runs_from_it() -> None:
    # the first part of the body is the labelled one: it runs on entry, and the JMP runs it again until i is 3
    plc = st.load("""FUNCTION F_Retry : INT
VAR i : INT; END_VAR
lblTry: i := i + 1;
IF i < 3 THEN JMP lblTry; END_IF
F_Retry := i * 10;
END_FUNCTION
PROGRAM P_Loop
VAR n : INT; nRuns : INT; END_VAR
lblStart: n := n + 1;
IF n MOD 4 <> 0 THEN JMP lblStart; END_IF
nRuns := nRuns + 1;
END_PROGRAM""")
    assert plc.F_Retry() == 30
    plc.P_Loop()
    assert (plc.P_Loop.n, plc.P_Loop.nRuns) == (4, 1)
    plc.P_Loop()
    assert (plc.P_Loop.n, plc.P_Loop.nRuns) == (8, 2)


# --- TO_<type> of a STRING -------------------------------------------------------------------------------

def test_to_type_of_a_string_reads_the_text_as_string_to_type_does() -> None:
    plc = st.load("""FUNCTION_BLOCK FB_Parse
VAR_INPUT sIn : STRING; END_VAR
VAR_OUTPUT fValue : REAL; nValue : DINT; fLit : LREAL; END_VAR
fValue := TO_REAL(sIn);
nValue := TO_DINT(sIn) + STRING_TO_DINT(sIn);
fLit := TO_LREAL('2.5E2');
END_FUNCTION_BLOCK""")
    fb = plc.FB_Parse()
    fb(sIn="-17")
    assert (fb.fValue, fb.nValue, fb.fLit) == (-17.0, -34, 250.0)
    fb(sIn="1.5")
    assert fb.fValue == 1.5


# --- arithmetic on TOD, DT and DATE --------------------------------------------------------------------------

def test_tod_dt_and_date_take_time_and_give_time_as_iec_61131_3_defines() -> None:
    plc = st.load("""FUNCTION_BLOCK FB_Shift
VAR_INPUT tStep : TIME; END_VAR
VAR_OUTPUT todEnd : TOD; dtEnd : DT; tLeft : TIME; tSpan : TIME; tDays : TIME; todBack : TOD; END_VAR
VAR todStart : TOD := TOD#06:00:00; dtStart : DT := DT#2024-02-28-22:00:00; END_VAR
todEnd := todStart + tStep;
todBack := T#30M + todStart - T#1H;
dtEnd := dtStart + tStep;
tLeft := TOD#22:00:00 - todEnd;
tSpan := dtEnd - dtStart;
tDays := D#2024-03-01 - D#2024-02-28;
END_FUNCTION_BLOCK""")
    fb = plc.FB_Shift()
    fb(tStep=8 * 3600_000 + 1500)  # T#8H1S500MS: the DT keeps the whole seconds
    assert fb.todEnd == (14 * 3600 + 1) * 1000 + 500
    assert fb.todBack == 5 * 3600_000 + 30 * 60_000
    assert fb.dtEnd == fb.dtStart + 8 * 3600 + 1  # DT#2024-02-29-06:00:01
    assert fb.tLeft == (8 * 3600 - 1) * 1000 - 500
    assert fb.tSpan == (8 * 3600 + 1) * 1000
    assert fb.tDays == 2 * 86_400_000  # 2024 is a leap year


def test_other_arithmetic_on_a_date_type_is_refused_naming_what_iec_defines() -> None:
    with pytest.raises(DefinitionError, match=r"<st>:3: DT \+ DT is not supported: IEC 61131-3 defines TOD \+ TIME"):
        st.load("FUNCTION F : DT\nVAR a, b : DT; END_VAR\nF := a + b;\nEND_FUNCTION\n")


# --- SIZEOF of a local, an input or an ARRAY element -------------------------------------------------------

def test_sizeof_of_a_local_an_input_and_an_array_element() -> None:
    plc = st.load("""TYPE ST_Pair : STRUCT a : INT; b : LREAL; END_STRUCT END_TYPE
FUNCTION F_Sizes : UDINT
VAR_INPUT sName : STRING(20); END_VAR
VAR aValues : ARRAY[1..10] OF LREAL; n : DINT; aGrid : ARRAY[0..1, 1..3] OF WORD; stPair : ST_Pair; aPairs : ARRAY[1..2] OF ST_Pair; END_VAR
F_Sizes := SIZEOF(aValues) * 1000000 + SIZEOF(n) * 10000 + SIZEOF(sName) * 100 + SIZEOF(aGrid);
END_FUNCTION
FUNCTION F_Count : UDINT
VAR aPairs : ARRAY[1..4] OF ST_Pair; aBuf : ARRAY[0..7] OF BYTE; END_VAR
MEMSET(ADR(aBuf), 3, SIZEOF(aBuf));
F_Count := SIZEOF(aPairs) / SIZEOF(aPairs[1]) + aBuf[7];
END_FUNCTION
FUNCTION_BLOCK FB_Table
VAR aCells : ARRAY[1..6] OF INT; END_VAR
VAR_OUTPUT nCells : UDINT; END_VAR
nCells := SIZEOF(aCells) / SIZEOF(aCells[1]);
END_FUNCTION_BLOCK""")
    # 10 LREALs, a DINT, STRING(20) with its 0, 2 x 3 WORDs
    assert plc.F_Sizes() == 80 * 1000000 + 4 * 10000 + 21 * 100 + 12
    assert plc.F_Count() == 4 + 3  # ST_Pair is 16 bytes (INT, padding, LREAL)
    table = plc.FB_Table()
    table()
    assert table.nCells == 6


# --- {attribute 'pack_mode'} ------------------------------------------------------------------------------

def test_pack_mode_lays_a_struct_out_without_its_alignment_gaps() -> None:
    # pack_mode 1 (and 0): no gaps, as a fieldbus or ADS telegram lays its bytes; 2: members on even offsets
    plc = st.load("""{attribute 'pack_mode' := '1'}
TYPE ST_Telegram : STRUCT nCmd : BYTE; nValue : DINT; fSpeed : LREAL; END_STRUCT END_TYPE
{attribute 'pack_mode' := '2'}
TYPE ST_Even : STRUCT nCmd : BYTE; nValue : DINT; END_STRUCT END_TYPE
TYPE ST_Aligned : STRUCT nCmd : BYTE; nValue : DINT; END_STRUCT END_TYPE
FUNCTION F_Decode : DINT
VAR aRaw : ARRAY[0..12] OF BYTE := [7, 16#04, 16#03, 16#02, 16#01]; stT : ST_Telegram; END_VAR
MEMCPY(ADR(stT), ADR(aRaw), SIZEOF(stT));
F_Decode := stT.nValue;
END_FUNCTION
FUNCTION F_Sizes : UDINT
VAR a : ST_Telegram; b : ST_Even; c : ST_Aligned; END_VAR
F_Sizes := SIZEOF(a) * 10000 + SIZEOF(b) * 100 + SIZEOF(c);
END_FUNCTION""")
    assert plc.F_Sizes() == 13 * 10000 + 6 * 100 + 8
    assert plc.F_Decode() == 0x01020304  # the DINT right after the command byte, as the telegram has it


def test_a_pack_mode_twincat_does_not_know_is_refused() -> None:
    with pytest.raises(DefinitionError, match=r"<st>:2: \{attribute 'pack_mode' := '3'\}: pack_mode is 0, 1, 2, 4 or 8"):
        st.load("{attribute 'pack_mode' := '3'}\nTYPE ST_X : STRUCT a : BYTE; END_STRUCT END_TYPE\n")


# --- a block inside a STRUCT gets its FB_init, as every instance on the PLC does --------------------

STRUCT_BLOCKS = """TYPE ST_Channel :
STRUCT
    nId : INT := 4;
    fbFilter : FB_Filter;
END_STRUCT
END_TYPE
FUNCTION_BLOCK FB_Filter
VAR_INPUT rIn : REAL; END_VAR
VAR_OUTPUT rOut : REAL; nInits : INT; END_VAR
VAR rFactor : REAL; END_VAR
METHOD FB_init : BOOL
VAR_INPUT bInitRetains : BOOL; bInCopyCode : BOOL; END_VAR
rFactor := 0.5;
nInits := nInits + 1;
END_METHOD
rOut := rOut + (rIn - rOut) * rFactor;
END_FUNCTION_BLOCK
PROGRAM MAIN
VAR
    stChannel : ST_Channel;
    aChannels : ARRAY[1..2] OF ST_Channel;
END_VAR
stChannel.fbFilter(rIn := 8.0);
aChannels[2].fbFilter(rIn := 4.0);
END_PROGRAM
"""


def test_a_block_inside_a_struct_runs_with_what_its_fb_init_set() -> None:
    main = st.load(STRUCT_BLOCKS).MAIN
    for expected in (4.0, 6.0, 7.0):
        main()
        assert main.stChannel.fbFilter.rOut == expected  # rFactor 0.5 from FB_init: without it the filter stays at 0
    assert main.aChannels[2].fbFilter.rOut == 3.5 and main.aChannels[1].fbFilter.rOut == 0.0
    assert [main.stChannel.fbFilter.nInits, *(channel.fbFilter.nInits for channel in main.aChannels)] == [1, 1, 1]
    assert main.stChannel.nId == 4
