"""Constructs public TwinCAT projects write that the reader refused: each loaded and run, values worked by hand."""

from __future__ import annotations

import math
import pathlib

import pytest

from iecoop import T
from iecoop.exceptions import AccessError, DefinitionError
from iecoop.runtime import Runtime, Task
from iecoop.st.read.parse import library_references

st = pytest.importorskip("iecoop.st")


# --- locals of a FUNCTION or METHOD that need an address --------------------------------------------


def test_an_array_local_of_a_function_is_passed_as_an_in_out() -> None:
    # F_Fill writes 0, 7, 14, 21 into the caller's local array; the caller sums them: 42
    plc = st.load("""TYPE ST_Item : STRUCT nWeight : DINT; fArea : LREAL; END_STRUCT END_TYPE
FUNCTION F_Fill
VAR_INPUT nLast : INT; END_VAR
VAR_IN_OUT aItems : ARRAY[0..3] OF ST_Item; END_VAR
VAR i : INT; END_VAR
FOR i := 0 TO nLast DO aItems[i].nWeight := i * 7; END_FOR
END_FUNCTION
FUNCTION F_Total : DINT
VAR aWork : ARRAY[0..3] OF ST_Item; i : INT; END_VAR
F_Fill(nLast := 3, aItems := aWork);
FOR i := 0 TO 3 DO F_Total := F_Total + aWork[i].nWeight; END_FOR
END_FUNCTION
FUNCTION_BLOCK FB_Tally
VAR_OUTPUT nTotal : DINT; END_VAR
nTotal := nTotal + F_Total();
END_FUNCTION_BLOCK""")
    fb = plc.FB_Tally()
    fb()
    fb()
    assert fb.nTotal == 84  # 42 per call: the local array starts from zero every call


def test_a_method_array_local_is_passed_by_position_as_an_in_out() -> None:
    plc = st.load("""FUNCTION F_Swap
VAR_IN_OUT a : ARRAY[1..2] OF INT; END_VAR
VAR t : INT; END_VAR
t := a[1]; a[1] := a[2]; a[2] := t;
END_FUNCTION
FUNCTION_BLOCK FB_Pair
VAR_OUTPUT nFirst : INT; END_VAR
END_FUNCTION_BLOCK
METHOD Swapped : INT
VAR aPair : ARRAY[1..2] OF INT := [3, 9]; END_VAR
F_Swap(aPair);
nFirst := aPair[1];
Swapped := aPair[1] * 10 + aPair[2];
END_METHOD""")
    fb = plc.FB_Pair()
    assert fb.Swapped() == 93 and fb.nFirst == 9


def test_adr_of_a_constant_reads_its_bits_as_another_type() -> None:
    # 16#7FF0000000000000 is the IEEE-754 pattern of +infinity; 16#3FF0000000000000 is 1.0
    plc = st.load("""FUNCTION F_Inf : LREAL
VAR CONSTANT cInfBits : ULINT := ULINT#16#7FF0000000000000; END_VAR
VAR pInf : POINTER TO LREAL := ADR(cInfBits); END_VAR
F_Inf := pInf^;
END_FUNCTION
FUNCTION F_One : LREAL
VAR CONSTANT cBits : ULINT := ULINT#16#3FF0000000000000; END_VAR
VAR p : POINTER TO LREAL; END_VAR
p := ADR(cBits);
F_One := p^ * 2;
END_FUNCTION""")
    assert math.isinf(plc.F_Inf()) and plc.F_Inf() > 0
    assert plc.F_One() == 2.0


def test_a_constant_whose_address_is_taken_is_still_refused_a_write() -> None:
    with pytest.raises(st.StUnsupportedError, match=r"<st>:4: assignment to CONSTANT cBits"):
        st.load("""FUNCTION F : LREAL
VAR CONSTANT cBits : ULINT := 1; END_VAR
VAR p : POINTER TO ULINT := ADR(cBits); END_VAR
cBits := 2;
END_FUNCTION""")


# --- VAR blocks ------------------------------------------------------------------------------------


def test_an_empty_var_block_of_a_program_loads() -> None:
    # blark reads an empty VAR ... END_VAR of a PROGRAM as a block of located variables: it has none
    plc = st.load("""PROGRAM MAIN
VAR
\t
END_VAR
END_PROGRAM
PROGRAM P_Count
VAR
END_VAR
VAR n : INT; END_VAR
n := n + 2;
END_PROGRAM""")
    plc.P_Count()
    plc.P_Count()
    assert plc.P_Count.n == 4


def test_a_program_var_of_located_inputs_alone_loads() -> None:
    plc = st.load("""PROGRAM MAIN
VAR
    bStart AT %I* : BOOL;
    nRaw AT %IW4 : INT;
END_VAR
VAR
    bLamp AT %Q* : BOOL;
END_VAR
VAR
    nCount : INT;
END_VAR
bLamp := bStart;
IF bStart THEN nCount := nCount + nRaw; END_IF
END_PROGRAM""")
    plc.MAIN.bStart = True
    plc.MAIN.nRaw = 5
    plc.MAIN()
    plc.MAIN()
    assert (plc.MAIN.bLamp, plc.MAIN.nCount) == (True, 10)
    plc.MAIN.bStart = False
    plc.MAIN()
    assert (plc.MAIN.bLamp, plc.MAIN.nCount) == (False, 10)


# --- inline enumerations ----------------------------------------------------------------------------


def test_an_inline_enumeration_steps_a_state_machine() -> None:
    # IDLE=0, FILL=5, DRAIN=6; starts at FILL: FILL->DRAIN (+1), DRAIN->IDLE (+10), IDLE->FILL, FILL->DRAIN (+1)
    plc = st.load("""FUNCTION_BLOCK FB_Tank
VAR_OUTPUT nLog : INT; END_VAR
VAR
    eStep : (IDLE, FILL := 5, DRAIN) := FILL;
END_VAR
CASE eStep OF
    IDLE: eStep := FILL;
    FILL: eStep := DRAIN; nLog := nLog + 1;
    DRAIN: eStep := IDLE; nLog := nLog + 10;
END_CASE
END_FUNCTION_BLOCK""")
    fb = plc.FB_Tank()
    seen = []
    for _ in range(4):
        fb()
        seen.append((int(fb.eStep), fb.nLog))
    assert seen == [(6, 1), (0, 11), (5, 11), (6, 12)]
    assert plc.FB_Tank_eStep.DRAIN == 6


def test_two_blocks_with_inline_enumerations_of_the_same_variable_name_load() -> None:
    plc = st.load("""FUNCTION_BLOCK FB_A
VAR eState : (A_OFF, A_ON); END_VAR
eState := A_ON;
END_FUNCTION_BLOCK
FUNCTION_BLOCK FB_B
VAR eState : (B_OFF, B_HALF, B_ON) := B_HALF; END_VAR
IF eState = B_HALF THEN eState := B_ON; END_IF
END_FUNCTION_BLOCK""")
    a, b = plc.FB_A(), plc.FB_B()
    assert (int(a.eState), int(b.eState)) == (0, 1)
    a()
    b()
    assert (int(a.eState), int(b.eState)) == (1, 2)


def test_an_inline_enumeration_local_to_a_method_starts_anew_every_call() -> None:
    # CLOSED=0, OPENING=1, OPEN=2: each call starts at OPENING and moves to OPEN, counting one opening
    plc = st.load("""FUNCTION_BLOCK FB_Door
VAR_OUTPUT nOpened : INT; END_VAR
END_FUNCTION_BLOCK
METHOD Cycle : INT
VAR eLocal : (CLOSED, OPENING, OPEN) := OPENING; END_VAR
IF eLocal = OPENING THEN eLocal := OPEN; nOpened := nOpened + 1; END_IF
Cycle := eLocal;
END_METHOD""")
    door = plc.FB_Door()
    assert (door.Cycle(), door.Cycle(), door.nOpened) == (2, 2, 2)
    assert plc.FB_Door_Cycle_eLocal.OPEN == 2


def test_an_inline_enumeration_local_to_a_property_accessor_loads() -> None:
    # LOW=0, MID=4, HIGH=5: a level of 7 is above MID, so the Get returns HIGH
    plc = st.load("""FUNCTION_BLOCK FB_Level
VAR_INPUT nLevel : INT; END_VAR
END_FUNCTION_BLOCK
PROPERTY Band : INT
VAR eBand : (LOW, MID := 4, HIGH); END_VAR
IF nLevel > MID THEN eBand := HIGH; ELSIF nLevel > 0 THEN eBand := MID; END_IF
Band := eBand;
END_PROPERTY""")
    fb = plc.FB_Level()
    assert fb.Band == 0
    fb.nLevel = 7
    assert fb.Band == 5
    fb.nLevel = 2
    assert fb.Band == 4


# --- a POU's own constants in its declarations -----------------------------------------------------


def test_array_bounds_name_constants_declared_after_them() -> None:
    # cSize = 4, cBytes = 4 * 2 = 8: aBuf is [1..4], aBytes [0..7]
    plc = st.load("""FUNCTION_BLOCK FB_Log
VAR
    aBuf : ARRAY[1..cSize] OF INT;
    aBytes : ARRAY[0..cBytes - 1] OF BYTE;
    nShape : INT;
END_VAR
VAR CONSTANT
    cSize : INT := 4;
    cBytes : UDINT := cSize * 2;
END_VAR
nShape := UPPER_BOUND(aBuf, 1) * 100 + UPPER_BOUND(aBytes, 1);
aBuf[cSize] := nShape;
END_FUNCTION_BLOCK""")
    fb = plc.FB_Log()
    fb()
    assert (fb.nShape, fb.aBuf[4], fb.cBytes) == (407, 407, 8)


def test_a_function_local_array_is_bounded_by_its_own_constant() -> None:
    plc = st.load("""FUNCTION F_Sum : INT
VAR CONSTANT cLast : INT := 3; END_VAR
VAR a : ARRAY[0..cLast] OF INT := [1, 2, 3, 4]; i : INT; END_VAR
FOR i := 0 TO cLast DO F_Sum := F_Sum + a[i]; END_FOR
END_FUNCTION""")
    assert plc.F_Sum() == 10


def test_an_unknown_interface_is_named_by_its_st_name() -> None:
    with pytest.raises(st.StUnsupportedError, match=r"IMPLEMENTS unknown interface 'Lib\.I_Run'$"):
        st.load("FUNCTION_BLOCK FB_X IMPLEMENTS Lib.I_Run\nEND_FUNCTION_BLOCK")


# --- a TwinCAT project using them, loaded through its .plcproj and run ------------------------------

PALLETIZER = pathlib.Path(__file__).parent / "data" / "projects" / "Palletizer" / "Palletizer.plcproj"


def test_the_palletizer_project_stacks_three_layers_over_cycles() -> None:
    # 100 ms cycles, the grip TON 200 ms: a layer takes 5 cycles (wait, grip started, 2 cycles gripping, place)
    plc = st.load(PALLETIZER)
    runtime = Runtime(store=":memory:")
    runtime.add_task(Task("PlcTask", interval=T("100ms")), plc.MAIN)
    stacker = plc.MAIN.fbStacker
    runtime.run(cycles=1)  # the start button is off: MAIN does not call the stacker
    assert (int(stacker.eStep), plc.P_Io.bRunLamp) == (0, False)
    plc.P_Io.bStartButton = True  # %I* in a PROGRAM's VAR: an input the I/O update (here the test) writes
    plc.GVL_IO.bBoxAtGripper = True
    seen, texts = [], []
    for raw in [125] * 5 + [310] * 5 + [88] * 6:  # the scale reads 12.5 kg, then 31.0 kg, then 8.8 kg
        plc.GVL_IO.nScaleRaw = raw
        runtime.run(cycles=1)
        seen.append((int(stacker.eStep), stacker.nLayer, plc.GVL_IO.bGripperClose, plc.MAIN.fHeaviest))
        texts.append(plc.MAIN.sLayers)

    def grip(layers: int, heaviest: float) -> list[tuple[int, int, bool, float]]:
        """GRIP (1) with the gripper closing, closed, closed, then PLACE (2) once the TON is done."""
        return [(1, layers, False, heaviest), (1, layers, True, heaviest), (1, layers, True, heaviest), (2, layers, True, heaviest)]

    assert seen[0:4] == grip(0, 0.0)
    assert seen[4] == (0, 1, False, 12.5)  # placed: WAIT_BOX again, the gripper open
    assert seen[5:9] == grip(1, 12.5)
    assert seen[9] == (0, 2, False, 31.0)
    assert seen[10:14] == grip(2, 31.0)
    assert seen[14] == (10, 3, False, 31.0)  # FULL := 10
    assert seen[15] == (10, 3, False, 31.0) and stacker.bFull and plc.P_Io.bRunLamp
    # F_HeaviestLayer sorted its own copy: the stacker's layers keep their order
    assert [stacker.aLayers[i].fWeight for i in range(1, 5)] == [12.5, 31.0, 8.8, 0.0]
    assert math.isinf(plc.MAIN.fInfinity) and plc.MAIN.bNaNSeen
    # F_LayerText's CASE labels are its own constants (0, 3); the GripTime PROPERTY has a Set only
    assert (texts[0], texts[4], texts[9], texts[14]) == ("empty", "1 of 3", "2 of 3", "full")
    with pytest.raises(AccessError, match="PROPERTY FB_Stacker.GripTime has no Get accessor"):
        stacker.GripTime


def test_a_library_whose_title_has_a_space_is_bound_by_its_namespace(tmp_path: pathlib.Path) -> None:
    # TwinCAT's own system library is titled "Base Interfaces"; projects reach it as IBaseLibrary
    library = tmp_path / "base"
    library.mkdir()
    (library / "F_Twice.st").write_text("FUNCTION F_Twice : INT\nVAR_INPUT n : INT; END_VAR\nF_Twice := 2 * n;\nEND_FUNCTION\n")
    (tmp_path / "MAIN.TcPOU").write_text(
        '<?xml version="1.0" encoding="utf-8"?>\n<TcPlcObject Version="1.1.0.1">\n  <POU Name="MAIN">\n'
        '    <Declaration><![CDATA[PROGRAM MAIN\nVAR n : INT := 4; END_VAR]]></Declaration>\n'
        '    <Implementation><ST><![CDATA[n := IBaseLibrary.F_Twice(n);]]></ST></Implementation>\n  </POU>\n</TcPlcObject>\n')
    (tmp_path / "P.plcproj").write_text(
        '<?xml version="1.0" encoding="utf-8"?>\n<Project xmlns="http://schemas.microsoft.com/developer/msbuild/2003">\n'
        '<ItemGroup><Compile Include="MAIN.TcPOU" /></ItemGroup>\n'
        '<ItemGroup><LibraryReference Include="Base Interfaces,newest,System"><Namespace>IBaseLibrary</Namespace>'
        '</LibraryReference></ItemGroup>\n</Project>\n')
    [reference] = library_references(tmp_path / "P.plcproj")
    assert (reference.name, reference.namespace, reference.version) == ("Base Interfaces", "IBaseLibrary", "newest,System")
    with pytest.raises(DefinitionError, match=r"P.plcproj:4: library Base Interfaces, version newest,System is not found: pass libraries="):
        st.load(tmp_path / "P.plcproj")
    plc = st.load(tmp_path / "P.plcproj", libraries={"IBaseLibrary": library})
    plc.MAIN()
    plc.MAIN()
    assert plc.MAIN.n == 16


def test_a_type_class_input_names_the_class_a_generic_input_had() -> None:
    # TcUnit's way to print what type an ANY input was: a __SYSTEM.TYPE_CLASS input, cased on its values
    plc = st.load("""FUNCTION F_Name : STRING
VAR_INPUT c : __SYSTEM.TYPE_CLASS; END_VAR
CASE c OF
    __SYSTEM.TYPE_CLASS.TYPE_INT: F_Name := 'INT';
    __SYSTEM.TYPE_CLASS.TYPE_LREAL: F_Name := 'LREAL';
ELSE F_Name := 'OTHER';
END_CASE
END_FUNCTION
FUNCTION F_Kind : STRING
VAR_INPUT x : ANY; END_VAR
F_Kind := F_Name(x.TypeClass);
END_FUNCTION
PROGRAM MAIN
VAR a : INT; b : LREAL; t : BOOL; sA, sB, sT : STRING; END_VAR
sA := F_Kind(a); sB := F_Kind(b); sT := F_Kind(t);
END_PROGRAM""")
    plc.MAIN()
    assert (plc.MAIN.sA, plc.MAIN.sB, plc.MAIN.sT) == ("INT", "LREAL", "OTHER")


# --- what TwinCAT accepts in calls and BOOL values ---------------------------------------------------


def test_arguments_written_without_a_value_are_not_passed() -> None:
    # fb(nStep := , bDone => ) keeps the input's value and reads no output, as TwinCAT's call assistant writes them
    plc = st.load("""FUNCTION_BLOCK FB_Count
VAR_INPUT nStep : INT := 2; END_VAR
VAR_OUTPUT nTotal : INT; bOdd : BOOL; END_VAR
nTotal := nTotal + nStep;
bOdd := (nTotal MOD 2) = 1;
END_FUNCTION_BLOCK
PROGRAM MAIN
VAR fbCount : FB_Count; bOdd : BOOL := TRUE; nSeen : INT; END_VAR
fbCount(nStep := , bOdd => , nTotal => nSeen);
fbCount(nStep := 3, bOdd => bOdd, );
fbCount(nStep := , nTotal => nSeen);
END_PROGRAM""")
    plc.MAIN()
    # 0 + 2 = 2 (seen), + 3 = 5 (odd), + 3 (the input kept its value) = 8 (seen)
    assert (plc.MAIN.nSeen, plc.MAIN.bOdd, plc.MAIN.fbCount.nTotal) == (8, True, 8)


def test_bool_takes_the_literals_zero_and_one() -> None:
    plc = st.load("""TYPE ST_Flags : STRUCT bEnable : BOOL := 1; bLatch : BOOL := 0; END_STRUCT END_TYPE
FUNCTION_BLOCK FB_Latch
VAR_INPUT bSet : BOOL := 0; END_VAR
VAR_OUTPUT bQ : BOOL; END_VAR
VAR stFlags : ST_Flags; END_VAR
IF bSet = 1 AND stFlags.bEnable THEN stFlags.bLatch := 1; END_IF
bQ := stFlags.bLatch;
END_FUNCTION_BLOCK""")
    fb = plc.FB_Latch()
    fb()
    assert (fb.bQ, fb.stFlags.bEnable) == (False, True)
    fb(bSet=True)
    assert (fb.bQ, fb.stFlags.bLatch) == (True, True)


def test_case_labels_and_input_defaults_name_the_blocks_constants() -> None:
    # cStart = 1, cStop = 2; SetEffect's default nEffect is cPulse = 2
    plc = st.load("""FUNCTION_BLOCK FB_Button
VAR_INPUT nType : USINT; END_VAR
VAR_OUTPUT nRed, nEffect : BYTE; END_VAR
VAR CONSTANT cStart : USINT := 1; cStop : USINT := 2; cPulse : BYTE := 2; END_VAR
CASE nType OF
    cStart: nRed := 0;
    cStop: nRed := 255;
ELSE nRed := 128;
END_CASE
END_FUNCTION_BLOCK
METHOD SetEffect
VAR_INPUT nNew : BYTE := cPulse; END_VAR
nEffect := nNew;
END_METHOD""")
    button = plc.FB_Button()
    seen = []
    for kind in (1, 2, 7):
        button(nType=kind)
        seen.append(button.nRed)
    assert seen == [0, 255, 128]
    button.SetEffect()
    assert button.nEffect == 2
    button.SetEffect(nNew=5)
    assert button.nEffect == 5


def test_a_property_with_a_set_accessor_only_is_written_and_refuses_a_read(tmp_path: pathlib.Path) -> None:
    (tmp_path / "FB_Led.TcPOU").write_text("""<?xml version="1.0" encoding="utf-8"?>
<TcPlcObject Version="1.1.0.1">
  <POU Name="FB_Led">
    <Declaration><![CDATA[FUNCTION_BLOCK FB_Led
VAR_OUTPUT nRed, nGreen : BYTE; END_VAR]]></Declaration>
    <Implementation><ST><![CDATA[]]></ST></Implementation>
    <Property Name="Color">
      <Declaration><![CDATA[PROPERTY Color : INT]]></Declaration>
      <Set Name="Set">
        <Declaration><![CDATA[VAR
END_VAR]]></Declaration>
        <Implementation><ST><![CDATA[CASE Color OF
    0: nRed := 255; nGreen := 0;
    1: nRed := 0; nGreen := 255;
END_CASE]]></ST></Implementation>
      </Set>
    </Property>
  </POU>
</TcPlcObject>
""")
    plc = st.load(tmp_path / "FB_Led.TcPOU")
    led = plc.FB_Led()
    led.Color = 1
    assert (led.nRed, led.nGreen) == (0, 255)
    led.Color = 0
    assert (led.nRed, led.nGreen) == (255, 0)
    with pytest.raises(AccessError, match=r"PROPERTY FB_Led.Color has no Get accessor: it can only be written"):
        led.Color


# --- date and time literals ----------------------------------------------------------------------------


def test_a_date_and_time_literal_may_leave_out_the_seconds() -> None:
    from iecoop.literals import format_dt, format_tod

    plc = st.load("""PROGRAM MAIN
VAR dtStart : DT := DT#2000-01-01-00:00; todShift : TOD; nPasses : INT; END_VAR
todShift := TOD#6:30;
IF dtStart = DT#2000-01-01-00:00:00 THEN nPasses := nPasses + 1; END_IF
END_PROGRAM""")
    plc.MAIN()
    plc.MAIN()
    assert format_dt(plc.MAIN.dtStart) == "DT#2000-01-01-00:00:00"
    assert format_tod(plc.MAIN.todShift) == "TOD#06:30:00"
    assert plc.MAIN.nPasses == 2


@pytest.mark.parametrize(
    ("literal", "why"),
    [("DT#2023-02-29-10:00", "day out of range"), ("TOD#24:00:00", "hour out of range"), ("D#1969-12-31", "out of range")],
)
def test_a_bad_date_or_time_literal_is_refused_at_load_at_its_line(tmp_path: pathlib.Path, literal: str, why: str) -> None:
    source = tmp_path / "MAIN.st"
    source.write_text(f"PROGRAM MAIN\nVAR nCount : INT; bLate : BOOL; END_VAR\nnCount := nCount + 1;\nIF nCount > 5 THEN nCount := 0; END_IF\nbLate := {literal} > {literal};\nEND_PROGRAM\n")
    with pytest.raises(DefinitionError, match=rf"MAIN\.st:5: .*{why}"):  # before: a ValueError in the cycle that read it
        st.load(source, cache=False)
