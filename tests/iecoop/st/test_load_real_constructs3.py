"""Constructs a fourth set of public TwinCAT projects writes: each loaded and run, the values worked by hand."""

from __future__ import annotations

import pytest

st = pytest.importorskip("iecoop.st")


# --- __ISVALIDREF of a METHOD's REFERENCE TO input and local ----------------------------------------

JOG = """TYPE ST_Drive :
STRUCT
    nOverride : UDINT;
    nMoves : INT;
END_STRUCT
END_TYPE
FUNCTION_BLOCK FB_Move
VAR_IN_OUT
    Drive : ST_Drive;
END_VAR
VAR_INPUT
    bGo : BOOL;
END_VAR
IF bGo THEN
    Drive.nMoves := Drive.nMoves + 1;
END_IF
END_FUNCTION_BLOCK
FUNCTION_BLOCK FB_Jogger
VAR
    _move : FB_Move;
    _nSaved : UDINT;
    _bLocalSeen : BOOL;
END_VAR
METHOD Jog : BOOL
VAR_INPUT
    Drive : REFERENCE TO ST_Drive;
    bButton : BOOL;
END_VAR
VAR
    rKeep : REFERENCE TO ST_Drive;
END_VAR
_bLocalSeen := __ISVALIDREF(rKeep);
IF __ISVALIDREF(Drive) THEN
    THIS^._nSaved := Drive.nOverride;
    rKeep REF= Drive;
    IF __ISVALIDREF(rKeep) AND bButton THEN
        rKeep.nOverride := 50;
    END_IF
    THIS^._move(Drive := Drive, bGo := bButton);
    Jog := TRUE;
END_IF
END_METHOD
END_FUNCTION_BLOCK
PROGRAM MAIN
VAR_INPUT
    bPressed : BOOL;
END_VAR
VAR
    fbJog : FB_Jogger;
    stDrive : ST_Drive := (nOverride := 100);
    bDone : BOOL;
END_VAR
bDone := fbJog.Jog(Drive := stDrive, bButton := bPressed);
END_PROGRAM
"""


def test_isvalidref_of_a_methods_reference_input_and_local() -> None:
    plc = st.load(JOG)
    main = plc.MAIN
    main()
    assert (main.bDone, main.stDrive.nMoves, main.stDrive.nOverride) == (True, 0, 100)
    assert main.fbJog._nSaved == 100 and main.fbJog._bLocalSeen is False  # a fresh local REFERENCE is not bound
    main(bPressed=True)
    main(bPressed=True)
    assert (main.stDrive.nMoves, main.stDrive.nOverride, main.fbJog._nSaved) == (2, 50, 50)
    assert main.fbJog._bLocalSeen is False  # unbound again at every call


# --- an FB_init argument that is a variable of the same block: passed from each instance ----------------------

INJECTED = """FUNCTION_BLOCK FB_Counter
VAR
    nCount : UINT;
END_VAR
nCount := nCount + 1;
END_FUNCTION_BLOCK
FUNCTION_BLOCK FB_User
VAR
    _counter : REFERENCE TO FB_Counter;
END_VAR
METHOD FB_init : BOOL
VAR_INPUT
    bInitRetains : BOOL;
    bInCopyCode : BOOL;
    counter : REFERENCE TO FB_Counter;
END_VAR
_counter REF= counter;
END_METHOD
_counter();
END_FUNCTION_BLOCK
PROGRAM Runner
VAR
    counter : FB_Counter;
    user : FB_User(counter);
END_VAR
user();
END_PROGRAM
"""


def test_an_fb_init_argument_naming_a_variable_of_the_same_block_is_that_variable() -> None:
    runner = st.load(INJECTED).Runner
    for _ in range(3):
        runner()
    assert runner.counter.nCount == 3


# --- a STRUCT initialiser of four or more elements (blark reads the tail as nested bare arrays) --------

VERSIONED = """TYPE ST_Release :
STRUCT
    iMajor : UINT;
    iMinor : UINT;
    iBuild : UINT;
    iRevision : UINT;
    nFlags : DWORD;
    sText : STRING(23);
END_STRUCT
END_TYPE
VAR_GLOBAL CONSTANT
    stRelease : ST_Release := (iMajor := 1, iMinor := 4, iBuild := 7, iRevision := 2, nFlags := 1, sText := '1.4.7');
END_VAR
PROGRAM MAIN
VAR
    stLocal : ST_Release := (iRevision := 9, iBuild := 8, iMinor := 6, iMajor := 5);
    nSum : UDINT;
    sSeen : STRING;
END_VAR
nSum := stRelease.iMajor * 1000 + stRelease.iMinor * 100 + stRelease.iBuild * 10 + stRelease.iRevision + stRelease.nFlags;
sSeen := stRelease.sText;
END_PROGRAM
"""


def test_a_struct_initialiser_of_six_elements_sets_each_member() -> None:
    plc = st.load(VERSIONED)
    plc.MAIN()
    assert (plc.MAIN.nSum, plc.MAIN.sSeen) == (1473, "1.4.7")
    local = plc.MAIN.stLocal
    assert (local.iMajor, local.iMinor, local.iBuild, local.iRevision, local.nFlags) == (5, 6, 8, 9, 0)


def test_a_library_function_named_like_a_conversion_is_an_unknown_function_without_its_library() -> None:
    source = "PROGRAM MAIN\nVAR fRad : LREAL; END_VAR\nfRad := DEG_TO_RAD(90.0);\nEND_PROGRAM\n"
    with pytest.raises(st.StUnsupportedError, match=r":3: unknown function DEG_TO_RAD \(not a conversion: RAD is not an elementary type\)"):
        st.load(source)


# --- __NEW(BYTE, n): a buffer whose size is known at run time -----------------------------------------

PAYLOAD = """TYPE ST_Sample :
STRUCT
    nId : UINT;
END_STRUCT
END_TYPE
FUNCTION_BLOCK FB_Payload
VAR_INPUT
    nSize : UDINT;
    bRelease : BOOL;
END_VAR
VAR_OUTPUT
    bAllocated : BOOL;
    nSum : UDINT;
    nSecond : WORD;
END_VAR
VAR
    pBuffer : POINTER TO BYTE;
    pWords : POINTER TO WORD;
    i : UDINT;
END_VAR
IF pBuffer = 0 AND nSize > 0 THEN
    pBuffer := __NEW(BYTE, nSize);
    pWords := __NEW(WORD, 3);
    IF pBuffer <> 0 THEN
        FOR i := 0 TO nSize - 1 DO
            pBuffer[i] := UDINT_TO_BYTE(i + 1);
        END_FOR
        pWords[1] := 16#BEEF;
    END_IF
END_IF
bAllocated := pBuffer <> 0;
nSum := 0;
IF bAllocated THEN
    FOR i := 0 TO nSize - 1 DO
        nSum := nSum + pBuffer[i];
    END_FOR
    nSecond := pWords[1];
END_IF
IF bRelease AND bAllocated THEN
    __DELETE(pBuffer);
    __DELETE(pWords);
END_IF
END_FUNCTION_BLOCK
FUNCTION_BLOCK FB_Samples
VAR
    pSamples : POINTER TO ST_Sample;
END_VAR
pSamples := __NEW(ST_Sample, 3);
END_FUNCTION_BLOCK
FUNCTION_BLOCK FB_Overrun
VAR_OUTPUT
    nLast : BYTE;
END_VAR
VAR
    pBuffer : POINTER TO BYTE;
END_VAR
pBuffer := __NEW(BYTE, 4);
nLast := pBuffer[4];
END_FUNCTION_BLOCK
"""


def test_new_of_an_elementary_type_or_struct_with_a_count_allocates_a_buffer() -> None:
    from iecoop.exceptions import ExceptionCode, PlcException

    plc = st.load(PAYLOAD.replace(SAMPLES, ""))
    fb = plc.FB_Payload()
    fb(nSize=0)
    assert (fb.bAllocated, fb.nSum) == (False, 0)
    fb(nSize=5)
    assert (fb.bAllocated, fb.nSum, fb.nSecond) == (True, 15, 0xBEEF)  # 1 + 2 + 3 + 4 + 5; the second WORD
    fb(nSize=5, bRelease=True)
    released = (fb.bAllocated, fb.nSum)
    fb(nSize=0)
    assert released == (True, 15) and fb.bAllocated is False  # __DELETE set the pointer to 0
    with pytest.raises(PlcException) as raised:
        plc.FB_Overrun()()
    assert raised.value.code is ExceptionCode.RTSEXCPT_ACCESS_VIOLATION  # the fifth byte of four


SAMPLES = PAYLOAD[PAYLOAD.index("FUNCTION_BLOCK FB_Samples"):PAYLOAD.index("FUNCTION_BLOCK FB_Overrun")]


def test_new_of_a_struct_with_a_count_is_refused_by_name() -> None:
    with pytest.raises(st.StUnsupportedError, match=r"__NEW\(ST_Sample, n\): an array of a STRUCT or block is not supported"):
        st.load(PAYLOAD)


# --- STRING_TO_DT, STRING_TO_DATE, STRING_TO_TOD: the literal the text starts with ------------------

STAMPS = """PROGRAM MAIN
VAR_INPUT
    sStamp : STRING := 'DT#2024-02-29-13:45:07.250';
END_VAR
VAR
    dtStamp : DT;
    dDay : DATE;
    tdShift : TOD;
    dtBad : DT;
    sBack : STRING;
    nSeconds : UDINT;
END_VAR
dtStamp := STRING_TO_DT(sStamp);
dDay := STRING_TO_DATE('  D#2024-02-29 (leap day)');
tdShift := TO_TOD('TOD#06:30:15.5');
dtBad := STRING_TO_DT('2024-02-30-00:00:00');
sBack := DT_TO_STRING(dtStamp);
nSeconds := DT_TO_UDINT(dtStamp) - DATE_TO_UDINT(dDay);
END_PROGRAM
"""


def test_string_to_dt_date_and_tod_read_the_literal_the_text_starts_with() -> None:
    plc = st.load(STAMPS)
    main = plc.MAIN
    main()
    assert (main.sBack, main.nSeconds) == ("DT#2024-02-29-13:45:07", 13 * 3600 + 45 * 60 + 7)  # the fraction dropped
    assert main.tdShift == ((6 * 60 + 30) * 60 + 15) * 1000 + 500  # TOD: milliseconds since midnight
    assert main.dtBad == 0  # no prefix, and no 30th of February: no value
    main(sStamp="DT#2024-13-01-00:00:00")
    assert main.dtStamp == 0


# --- a variable named as its type, and a METHOD's VAR_INST named as a variable of its block -----------

NAMESAKES = """TYPE zone :
STRUCT
    nLux : UINT;
END_STRUCT
END_TYPE
TYPE floor :
STRUCT
    zone : zone;
    nLevel : INT := 2;
END_STRUCT
END_TYPE
FUNCTION_BLOCK room
VAR_INPUT
    bOccupied : BOOL;
END_VAR
VAR
    heating_on : BOOL;
    nCalls : UINT;
END_VAR
METHOD PRIVATE heating : BOOL
VAR_INST
    heating_on : BOOL;
    nSeen : UINT;
END_VAR
nSeen := nSeen + 1;
heating_on := bOccupied AND nSeen > 1;
heating := heating_on;
END_METHOD
heating_on := heating();
nCalls := nCalls + 1;
END_FUNCTION_BLOCK
PROGRAM MAIN
VAR
    room : room;
    rooms : ARRAY[0..1] OF room;
    zone : zone := (nLux := 300);
    floor : floor;
    bWarm : BOOL;
END_VAR
room(bOccupied := TRUE);
rooms[1](bOccupied := TRUE);
bWarm := room.heating_on;
zone.nLux := zone.nLux + 1;
floor.zone.nLux := floor.zone.nLux + UINT#10 * INT_TO_UINT(floor.nLevel);
END_PROGRAM
"""


def test_a_variable_named_as_its_type_and_a_var_inst_named_as_a_variable_of_its_block() -> None:
    plc = st.load(NAMESAKES)
    main = plc.MAIN
    main()
    assert (main.bWarm, main.room.nCalls, main.zone.nLux) == (False, 1, 301)
    main()
    assert (main.bWarm, main.room.nCalls, main.zone.nLux) == (True, 2, 302)  # the METHOD's own heating_on, returned
    assert main.rooms[1].nCalls == 2 and main.rooms[0].nCalls == 0
    assert main.floor.zone.nLux == 40  # a STRUCT member named as its type, too


# --- a Get-only PROPERTY of type REFERENCE TO an elementary type or STRING -----------------------------

PAD = """FUNCTION_BLOCK FB_Pad
VAR_INPUT
    bConnected : BOOL;
    fRaw : REAL;
END_VAR
VAR
    _fTrigger : REAL;
    _sName : STRING := 'pad 1';
END_VAR
PROPERTY P_Trigger : REFERENCE TO REAL
VAR
END_VAR
IF bConnected THEN
    _fTrigger := fRaw;
ELSE
    _fTrigger := 0;
END_IF
P_Trigger REF= THIS^._fTrigger;
END_PROPERTY
PROPERTY P_Name : REFERENCE TO STRING
P_Name REF= _sName;
END_PROPERTY
PROPERTY P_Unbound : REFERENCE TO INT
END_PROPERTY
END_FUNCTION_BLOCK
PROGRAM MAIN
VAR_INPUT
    bOn : BOOL;
END_VAR
VAR
    pad : FB_Pad;
    fTwice : REAL;
    sName : STRING;
END_VAR
pad(bConnected := bOn, fRaw := 0.75);
fTwice := pad.P_Trigger * 2;
sName := pad.P_Name;
END_PROGRAM
"""


def test_a_get_only_property_of_type_reference_to_an_elementary_type_reads_its_target() -> None:
    from iecoop.exceptions import ExceptionCode, PlcException

    plc = st.load(PAD)
    plc.MAIN(bOn=True)
    assert (plc.MAIN.fTwice, plc.MAIN.sName) == (1.5, "pad 1")
    plc.MAIN(bOn=False)
    assert plc.MAIN.fTwice == 0.0  # the Get ran again: the variable it aims at was set to 0 first
    with pytest.raises(PlcException) as raised:
        _ = plc.MAIN.pad.P_Unbound  # a Get that never binds its result: a null reference
    assert raised.value.code is ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


def test_a_property_of_type_reference_to_an_elementary_type_with_a_set_stays_refused() -> None:
    setter = ("FUNCTION_BLOCK FB_Pad2\nVAR n : INT; END_VAR\nPROPERTY P : REFERENCE TO INT\nP REF= n;\nEND_PROPERTY\n"
              "PROPERTY P.Set : REFERENCE TO INT\nEND_PROPERTY\nEND_FUNCTION_BLOCK\n")
    with pytest.raises(st.StUnsupportedError, match=r"a result of type REFERENCE TO INT is not supported"):
        st.load(setter)
