"""Constructs public TwinCAT libraries write: each loaded and run across cycles, values worked by hand."""

from __future__ import annotations

import pytest

st = pytest.importorskip("iecoop.st")


def test_a_block_initialiser_binds_a_reference_and_a_pointer_to_variables_beside_it() -> None:
    # fbWatch := (bRef := bFlag, pCount := ADR(nCount)): each cycle it reads bFlag, inverts it and adds 5 to nCount;
    # a VAR_INST of a METHOD is bound the same way (to the block's nCount): it adds 1 at each call
    plc = st.load("""FUNCTION_BLOCK FB_Watch
VAR_INPUT bRef : REFERENCE TO BOOL; pCount : POINTER TO DINT; nStep : DINT := 5; END_VAR
VAR_OUTPUT bSeen : BOOL; END_VAR
IF __ISVALIDREF(bRef) THEN bSeen := bRef; bRef := NOT bRef; END_IF
IF pCount <> 0 THEN pCount^ := pCount^ + nStep; END_IF
END_FUNCTION_BLOCK
FUNCTION_BLOCK FB_Owner
VAR_OUTPUT bOut : BOOL; bFlag : BOOL := TRUE; nCount : DINT; END_VAR
VAR fbWatch : FB_Watch := (bRef := bFlag, pCount := ADR(nCount)); fbIdle : FB_Watch := (pCount := 0); END_VAR
fbWatch();
fbIdle();
bOut := fbWatch.bSeen;
Bump();
END_FUNCTION_BLOCK
METHOD Bump
VAR_INST fbOne : FB_Watch := (pCount := ADR(nCount), nStep := 1); END_VAR
fbOne();
END_METHOD""")
    fb = plc.FB_Owner()
    fb()
    assert (fb.bOut, fb.bFlag, fb.nCount) == (True, False, 6)
    fb()
    assert (fb.bOut, fb.bFlag, fb.nCount) == (False, True, 12)
    assert not fb.fbIdle.bSeen


def test_a_reference_in_an_initialiser_outside_a_block_is_refused_by_name() -> None:
    # a STRUCT type's default cannot name a variable: the error says where and what to write instead
    with pytest.raises(st.StUnsupportedError, match=r"<st>:6: bRef := \.\.\.: a REFERENCE TO or POINTER TO .* not supported outside a block's VAR \(bind it in code"):
        st.load("""FUNCTION_BLOCK FB_Watch
VAR_INPUT bRef : REFERENCE TO BOOL; END_VAR
END_FUNCTION_BLOCK
VAR_GLOBAL
bFlag : BOOL;
fbGlobal : FB_Watch := (bRef := bFlag);
END_VAR""")


def test_an_alias_of_the_system_any_type_is_a_generic_input() -> None:
    # TYPE T_Any : __SYSTEM.AnyType: an input of that type takes any value as ANY does (TypeClass, pValue,
    # diSize); F_SizeOf reads diSize, F_FirstByte reads through pValue, F_Kind hands it on to another function
    plc = st.load("""TYPE T_Any : __SYSTEM.AnyType; END_TYPE
FUNCTION F_SizeOf : DINT
VAR_INPUT aValue : T_Any; END_VAR
F_SizeOf := aValue.diSize;
END_FUNCTION
FUNCTION F_FirstByte : BYTE
VAR_INPUT aValue : __SYSTEM.AnyType; END_VAR
F_FirstByte := aValue.pValue^;
END_FUNCTION
FUNCTION F_IsReal : BOOL
VAR_INPUT aValue : T_Any; END_VAR
F_IsReal := aValue.TypeClass = __SYSTEM.TYPE_CLASS.TYPE_LREAL;
END_FUNCTION
FUNCTION F_Kind : BOOL
VAR_INPUT aAnything : ANY; END_VAR
F_Kind := F_IsReal(aAnything);
END_FUNCTION
FUNCTION_BLOCK FB_Probe
VAR_OUTPUT nSize : DINT; nByte : BYTE; bReal : BOOL; bIntReal : BOOL; END_VAR
VAR nWord : WORD := 16#1234; fValue : LREAL := 2.5; nStep : WORD := 16#0101; END_VAR
nSize := F_SizeOf(nWord) + F_SizeOf(fValue);
nByte := F_FirstByte(nWord);
bReal := F_Kind(fValue);
bIntReal := F_Kind(nWord);
nWord := nWord + nStep;
END_FUNCTION_BLOCK""")
    fb = plc.FB_Probe()
    fb()
    assert (fb.nSize, fb.nByte, fb.bReal, fb.bIntReal) == (10, 0x34, True, False)
    fb()
    assert fb.nByte == 0x35  # 16#1335: the low byte comes first


def test_the_values_of_an_enumeration_are_named_through_an_alias_of_it() -> None:
    # TYPE T_Order : E_Order: T_Order.Before is E_Order.Before; F_Order gives Before, Same, After for 1-2, 2-2, 3-2
    plc = st.load("""{attribute 'qualified_only'}
TYPE E_Order : (Unknown := 0, Before, Same, After) BYTE; END_TYPE
TYPE T_Order : E_Order; END_TYPE
FUNCTION F_Order : T_Order
VAR_INPUT a : INT; b : INT; END_VAR
F_Order := SEL(a = b, SEL(a > b, T_Order.Before, T_Order.After), T_Order.Same);
END_FUNCTION
FUNCTION_BLOCK FB_Sorter
VAR_OUTPUT eLast : T_Order; nAfter : INT; END_VAR
VAR n : INT := 1; END_VAR
eLast := F_Order(n, 2);
CASE eLast OF T_Order.After: nAfter := nAfter + 1; E_Order.Before: nAfter := nAfter + 10; END_CASE
n := n + 1;
END_FUNCTION_BLOCK""")
    fb = plc.FB_Sorter()
    fb()
    assert (fb.eLast, fb.nAfter) == (plc.E_Order.Before, 10)
    fb()
    assert (fb.eLast, fb.nAfter) == (plc.E_Order.Same, 10)
    fb()
    assert (fb.eLast, fb.nAfter) == (plc.E_Order.After, 11)


def test_the_platform_types_pvoid_uxint_xint_and_xword_are_declared() -> None:
    # TwinCAT's pseudo types on a 64-bit target: PVOID an untyped address (here POINTER TO BYTE), UXINT ULINT,
    # XINT LINT, XWORD LWORD; pAny walks aSrc, nCount counts cycles in all three widths
    plc = st.load("""FUNCTION_BLOCK FB_Walk
VAR_OUTPUT nFirst : INT; nSecond : INT; bNull : BOOL; nBig : UXINT; nSigned : __XINT; wMask : XWORD; END_VAR
VAR aSrc : ARRAY[0..1] OF INT := [7, 9]; pAny : PVOID; pNone : PVOID; pInt : POINTER TO INT; END_VAR
pAny := ADR(aSrc);
MEMCPY(ADR(nFirst), pAny, SIZEOF(nFirst));
bNull := pNone = 0 AND pAny <> 0;
pInt := pAny + SIZEOF(INT);
nSecond := pInt^;
aSrc[1] := aSrc[1] * 2;
nBig := nBig + 16#1_0000_0000;
nSigned := nSigned - 1;
wMask := SHL(wMask, 1) OR 1;
END_FUNCTION_BLOCK""")
    fb = plc.FB_Walk()
    fb()
    assert (fb.nFirst, fb.nSecond, fb.bNull, fb.nBig, fb.nSigned, fb.wMask) == (7, 9, True, 2**32, -1, 1)
    fb()
    assert (fb.nSecond, fb.nBig, fb.nSigned, fb.wMask) == (18, 2**33, -2, 3)


def test_numbers_convert_to_date_time_of_day_and_date_and_time() -> None:
    # TO_DT / UDINT_TO_DT take seconds since 1970, TO_DATE too, TO_TOD milliseconds; DT_TO_DATE and DT_TO_TOD
    # split a DT into its day and its time of day; a DATE is a DT at midnight
    plc = st.load("""FUNCTION_BLOCK FB_Clock
VAR_OUTPUT dtNow : DT; dDay : DATE; tdNow : TOD; dtMidnight : DT; tdLate : TOD; END_VAR
VAR nSeconds : UDINT := 86400 + 3600; fMs : LREAL := 1500.4; END_VAR
dtNow := UDINT_TO_DT(nSeconds);
dDay := DT_TO_DATE(dtNow);
tdNow := DT_TO_TOD(dtNow);
dtMidnight := TO_DT(dDay);
tdLate := TO_TOD(fMs);
nSeconds := nSeconds + 60;
END_FUNCTION_BLOCK""")
    fb = plc.FB_Clock()
    fb()
    assert (fb.dtNow, fb.dDay, fb.tdNow, fb.dtMidnight, fb.tdLate) == (90000, 86400, 3_600_000, 86400, 1500)
    fb()
    assert (fb.dtNow, fb.dDay, fb.tdNow) == (90060, 86400, 3_660_000)


def test_a_conversion_between_date_and_time_types_of_other_units_is_refused() -> None:
    with pytest.raises(st.StUnsupportedError, match=r"<st>:4: TO_DT of a TOD is not supported \(write DT_TO_TOD"):
        st.load("""FUNCTION F_Bad : DT
VAR_INPUT td : TOD; END_VAR
VAR p : POINTER TO TOD; END_VAR
F_Bad := TO_DT(td);
END_FUNCTION""")


def test_a_var_info_is_an_input_of_a_method() -> None:
    # Describe(info, ...) reads the symbol and type name of the variable __VARINFO described; not given, the
    # input is the zero VAR_INFO (an empty symbol)
    plc = st.load("""FUNCTION_BLOCK FB_Log
VAR_OUTPUT sLine : STRING; sEmpty : STRING; END_VAR
VAR nSpeed : INT := 3; END_VAR
METHOD Describe : STRING
VAR_INPUT stInfo : __SYSTEM.VAR_INFO; nValue : INT; END_VAR
Describe := CONCAT(CONCAT(stInfo.Symbol, CONCAT(':', stInfo.TypeName)), CONCAT('=', INT_TO_STRING(nValue)));
END_METHOD
METHOD Run
VAR stSpeed : __SYSTEM.VAR_INFO; END_VAR
stSpeed := __VARINFO(nSpeed);
sLine := Describe(stSpeed, nSpeed);
sEmpty := Describe(nValue := 0);
nSpeed := nSpeed * 2;
END_METHOD
END_FUNCTION_BLOCK""")
    fb = plc.FB_Log()
    fb.Run()
    assert fb.sLine.endswith("nSpeed:INT=3") and fb.sEmpty == ":=0"
    fb.Run()
    assert fb.sLine.endswith("nSpeed:INT=6")


def test_the_values_of_the_type_class_are_named_through_an_alias_of_it() -> None:
    # TYPE T_Kind : __SYSTEM.TYPE_CLASS: T_Kind.TYPE_LREAL is __SYSTEM.TYPE_CLASS.TYPE_LREAL, compared with an ANY's
    plc = st.load("""TYPE T_Kind : __SYSTEM.TYPE_CLASS; END_TYPE
FUNCTION F_IsReal : BOOL
VAR_INPUT aValue : ANY; END_VAR
VAR eKind : T_Kind; END_VAR
eKind := aValue.TypeClass;
F_IsReal := eKind = T_Kind.TYPE_LREAL OR eKind = T_Kind.TYPE_REAL;
END_FUNCTION
FUNCTION_BLOCK FB_Probe
VAR_OUTPUT nReals : INT; END_VAR
VAR fValue : LREAL := 1.5; nValue : INT; rValue : REAL; END_VAR
IF F_IsReal(fValue) THEN nReals := nReals + 1; END_IF
IF F_IsReal(nValue) THEN nReals := nReals + 10; END_IF
IF F_IsReal(rValue) THEN nReals := nReals + 100; END_IF
END_FUNCTION_BLOCK""")
    fb = plc.FB_Probe()
    fb()
    assert fb.nReals == 101
    fb()
    assert fb.nReals == 202


def test_a_pointer_is_indexed_as_the_elements_it_points_to() -> None:
    # pWord[i] is the i-th WORD from pWord (its address + i * 2), pText[i] the i-th character's byte of a STRING;
    # a store through pWord[0] changes aWords[0]: 10, 11, 12 over the cycles
    plc = st.load("""FUNCTION_BLOCK FB_Walk
VAR_OUTPUT nSum : WORD; nLetter : BYTE; nFirst : WORD; END_VAR
VAR aWords : ARRAY[0..2] OF WORD := [10, 20, 30]; pWord : POINTER TO WORD; sText : STRING := 'AZ';
    pText : POINTER TO STRING; i : INT; END_VAR
pWord := ADR(aWords);
nSum := 0;
FOR i := 0 TO 2 DO nSum := nSum + pWord[i]; END_FOR
pText := ADR(sText);
nLetter := pText[1];
nFirst := aWords[0];
pWord[0] := pWord[0] + 1;
END_FUNCTION_BLOCK""")
    fb = plc.FB_Walk()
    fb()
    assert (fb.nSum, fb.nLetter, fb.nFirst) == (60, ord("Z"), 10)
    fb()
    assert (fb.nSum, fb.nFirst, fb.aWords[0]) == (61, 11, 12)


def test_indexing_a_pointer_to_an_array_is_refused_by_name() -> None:
    with pytest.raises(st.StUnsupportedError, match=r"<st>:4: indexing a POINTER TO ARRAY.* is not supported \(index the variable"):
        st.load("""FUNCTION F_Bad : INT
VAR aRow : ARRAY[0..1] OF INT; pRow : POINTER TO ARRAY[0..1] OF INT; END_VAR
pRow := ADR(aRow);
F_Bad := pRow[0];
END_FUNCTION""")


def test_a_method_implements_its_prototype_whatever_the_case_of_its_input_names() -> None:
    # ST names are case-insensitive: I_Sink.Put(Text) and I_Small.Put(TEXT) are implemented by Put(text); called
    # through either interface and on the block, with the input named in any case: 'abb', then 'c' and 'd' added
    plc = st.load("""INTERFACE I_Sink
END_INTERFACE
METHOD Put : I_Sink
VAR_INPUT Text : STRING; Times : INT; END_VAR
END_METHOD
INTERFACE I_Small
END_INTERFACE
METHOD Put : I_Sink
VAR_INPUT TEXT : STRING; TIMES : INT; END_VAR
END_METHOD
FUNCTION_BLOCK FB_Base
VAR_OUTPUT sAll : STRING; END_VAR
END_FUNCTION_BLOCK
METHOD Clear : BOOL
VAR_INPUT bKeepLast : BOOL; END_VAR
sAll := '';
END_METHOD
FUNCTION_BLOCK FB_Sink EXTENDS FB_Base IMPLEMENTS I_Sink, I_Small
END_FUNCTION_BLOCK
METHOD Put : I_Sink
VAR_INPUT text : STRING; times : INT; END_VAR
VAR i : INT; END_VAR
FOR i := 1 TO times DO sAll := CONCAT(sAll, text); END_FOR
Put := THIS^;
END_METHOD
METHOD Clear : BOOL
VAR_INPUT BKEEPLAST : BOOL; END_VAR
IF NOT BKEEPLAST THEN sAll := ''; END_IF
END_METHOD
FUNCTION_BLOCK FB_User
VAR_OUTPUT sOut : STRING; END_VAR
VAR fbSink : FB_Sink; itf : I_Sink; itfSmall : I_Small; nCycle : INT; END_VAR
itf := fbSink;
itfSmall := fbSink;
nCycle := nCycle + 1;
IF nCycle = 1 THEN itf.Put(TEXT := 'a', times := 1).Put('b', 2);
ELSE fbSink.Put(Text := 'c', TIMES := 1); fbSink.Clear(bKeepLast := TRUE); itfSmall.Put(text := 'd', Times := 1);
END_IF
sOut := fbSink.sAll;
END_FUNCTION_BLOCK""")
    fb = plc.FB_User()
    fb()
    assert fb.sOut == "abb"
    fb()
    assert fb.sOut == "abbcd"


def test_a_method_or_property_spelt_in_another_case_overrides_and_implements() -> None:
    # FB_Fast.STEP overrides FB_Slow.Step: Run (in the base) calls the override, +10 a cycle; LEVEL and doIt
    # implement I_Level's Level and DoIt, read through the interface
    plc = st.load("""INTERFACE I_Level
END_INTERFACE
METHOD DoIt : INT
END_METHOD
PROPERTY Level : INT
END_PROPERTY
FUNCTION_BLOCK FB_Slow
VAR_OUTPUT n : INT; END_VAR
END_FUNCTION_BLOCK
METHOD Step : INT
n := n + 1;
END_METHOD
METHOD Run
Step();
END_METHOD
FUNCTION_BLOCK FB_Fast EXTENDS FB_Slow IMPLEMENTS I_Level
END_FUNCTION_BLOCK
METHOD STEP : INT
n := n + 10;
END_METHOD
METHOD doIt : INT
doIt := n + 1;
END_METHOD
PROPERTY LEVEL : INT
LEVEL := n * 2;
END_PROPERTY
FUNCTION_BLOCK FB_User
VAR_OUTPUT nDone : INT; nLevel : INT; END_VAR
VAR fbFast : FB_Fast; itf : I_Level; END_VAR
fbFast.Run();
itf := fbFast;
nDone := itf.DoIt();
nLevel := itf.Level;
END_FUNCTION_BLOCK""")
    fb = plc.FB_User()
    fb()
    assert (fb.fbFast.n, fb.nDone, fb.nLevel) == (10, 11, 20)
    fb()
    assert (fb.fbFast.n, fb.nDone, fb.nLevel) == (20, 21, 40)


def test_the_wstring_functions_work_on_characters() -> None:
    # WCONCAT, WLEN, WLEFT, WMID, WFIND, WREPLACE of Tc2_Standard on a WSTRING that grows by one 'ü' a cycle
    plc = st.load("""FUNCTION_BLOCK FB_Wide
VAR_OUTPUT wsAll : WSTRING; nLen : INT; wsHead : WSTRING; wsMid : WSTRING; nAt : INT; wsSwap : WSTRING; END_VAR
VAR wsGrow : WSTRING := "Grö"; END_VAR
wsGrow := WCONCAT(wsGrow, "ü");
wsAll := wsGrow;
nLen := WLEN(wsAll);
wsHead := WLEFT(wsAll, 2);
wsMid := WMID(wsAll, 2, 3);
nAt := WFIND(wsAll, "ü");
wsSwap := WREPLACE(wsAll, "o", 1, 3);
END_FUNCTION_BLOCK""")
    fb = plc.FB_Wide()
    fb()
    assert (fb.wsAll, fb.nLen, fb.wsHead, fb.wsMid, fb.nAt, fb.wsSwap) == ("Gröü", 4, "Gr", "öü", 4, "Groü")
    fb()
    assert (fb.wsAll, fb.nLen, fb.wsMid) == ("Gröüü", 5, "öü")


_SUM_INTERFACES = {
    # TwinCAT's form: the prototypes after their INTERFACE (an access specifier on each: INTERNAL, PUBLIC)
    "after": """INTERFACE INTERNAL I_Sum
END_INTERFACE
METHOD Add : DINT
VAR_INPUT nBy : DINT; END_VAR
END_METHOD
PROPERTY Total : DINT
END_PROPERTY
INTERFACE PUBLIC I_Labelled EXTENDS I_Sum
END_INTERFACE
METHOD Label : STRING
END_METHOD
""",
    # the IEC form: the prototypes inside INTERFACE ... END_INTERFACE
    "inside": """INTERFACE I_Sum
METHOD Add : DINT
VAR_INPUT nBy : DINT; END_VAR
END_METHOD
PROPERTY Total : DINT
END_PROPERTY
END_INTERFACE
INTERFACE INTERNAL I_Labelled EXTENDS I_Sum
METHOD Label : STRING
END_METHOD
END_INTERFACE
""",
}


@pytest.mark.parametrize("form", sorted(_SUM_INTERFACES))
def test_an_interface_with_an_access_specifier_and_its_prototypes_after_or_inside_it(form: str) -> None:
    # the block adds 2 a call through the interface; Total is ten times the sum
    plc = st.load(_SUM_INTERFACES[form] + """FUNCTION_BLOCK FB_Sum IMPLEMENTS I_Labelled
VAR n : DINT; END_VAR
METHOD Add : DINT
VAR_INPUT nBy : DINT; END_VAR
n := n + nBy;
Add := n;
END_METHOD
METHOD Label : STRING
Label := 'sum';
END_METHOD
PROPERTY Total : DINT
GET
Total := n * 10;
END_GET
END_PROPERTY
END_FUNCTION_BLOCK
FUNCTION_BLOCK FB_Reader
VAR_OUTPUT nLast : DINT; nTotal : DINT; sLabel : STRING; END_VAR
VAR fbSum : FB_Sum; itf : I_Labelled; END_VAR
itf := fbSum;
nLast := itf.Add(2);
nTotal := itf.Total;
sLabel := itf.Label();
END_FUNCTION_BLOCK""")
    fb = plc.FB_Reader()
    fb()
    assert (fb.nLast, fb.nTotal, fb.sLabel) == (2, 20, "sum")
    fb()
    assert (fb.nLast, fb.nTotal) == (4, 40)


def test_a_block_local_of_a_method_with_an_initialiser_is_refused_at_load() -> None:
    # it used to load and fail when the METHOD ran; a VAR_INST with the same initialiser is the way
    source = """FUNCTION_BLOCK FB_Twice
VAR_INPUT k : INT; END_VAR
VAR_OUTPUT d : INT; END_VAR
d := k * 2;
END_FUNCTION_BLOCK
FUNCTION_BLOCK FB_Host
VAR_OUTPUT n : INT; END_VAR
METHOD Run
VAR{section} fbTwice : FB_Twice := (k := 5); END_VAR
fbTwice();
n := fbTwice.d;
END_METHOD
END_FUNCTION_BLOCK"""
    with pytest.raises(st.StUnsupportedError, match=r"<st>:9: fbTwice : FB_Twice := \(\.\.\.\): a FUNCTION_BLOCK local of a method .*not supported \(declare it in the block's VAR or the METHOD's VAR_INST\)"):
        st.load(source.format(section=""))
    fb = st.load(source.format(section="_INST")).FB_Host()
    fb.Run()
    assert fb.n == 10


@pytest.mark.parametrize("member", ["fbTwice : FB_Twice := (k := 5);", "tDelay : TON := (PT := T#1S);"])
def test_a_block_member_of_a_struct_with_an_initialiser_is_refused_at_load(member: str) -> None:
    # it loaded with the block's own values (k 0, PT 0), the initialiser silently left out
    with pytest.raises(st.StUnsupportedError, match=r"<st>:5: STRUCT member \w+ : \w+ := \(\.\.\.\): a FUNCTION_BLOCK member of a STRUCT with an initialiser is not supported"):
        st.load(f"""FUNCTION_BLOCK FB_Twice
VAR_INPUT k : INT; END_VAR
END_FUNCTION_BLOCK
TYPE ST_Holder : STRUCT
{member}
nPlain : INT := 3;
END_STRUCT END_TYPE""")
    plc = st.load("""TYPE ST_Plain : STRUCT tDelay : TON; nPlain : INT := 3; END_STRUCT END_TYPE
FUNCTION_BLOCK FB_Use
VAR_OUTPUT n : INT; END_VAR
VAR s : ST_Plain; END_VAR
n := s.nPlain + TIME_TO_INT(s.tDelay.PT);
END_FUNCTION_BLOCK""")
    fb = plc.FB_Use()
    fb()
    assert fb.n == 3
