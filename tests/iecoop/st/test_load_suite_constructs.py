"""Constructs public TwinCAT projects' TcUnit suites write that the reader refused: each loaded and run."""

from __future__ import annotations

import pytest

st = pytest.importorskip("iecoop.st")


def test_two_methods_may_each_keep_a_var_inst_of_the_same_name() -> None:
    # each METHOD's VAR_INST is its own: Up counts by 1, Down by -10, over three calls each
    plc = st.load("""FUNCTION_BLOCK FB_TwoCounters
VAR_OUTPUT nUp : INT; nDown : INT; END_VAR
END_FUNCTION_BLOCK
METHOD Up : INT
VAR_INST nCount : INT; tWait : TON := (PT := T#1S); END_VAR
nCount := nCount + 1;
tWait(IN := TRUE);
nUp := nCount;
Up := nCount;
END_METHOD
METHOD Down : INT
VAR_INST nCount : INT := 100; END_VAR
nCount := nCount - 10;
nDown := nCount;
Down := nCount;
END_METHOD""")
    fb = plc.FB_TwoCounters()
    for _ in range(3):
        fb.Up()
        fb.Down()
    assert (fb.nUp, fb.nDown) == (3, 70)
    assert fb.Up() == 4 and fb.Down() == 60


def test_a_var_inst_name_twice_in_one_method_is_still_refused() -> None:
    with pytest.raises(st.DefinitionError, match=r"VAR_INST nCount of METHOD FB_Twice.Up is declared twice"):
        st.load("""FUNCTION_BLOCK FB_Twice
END_FUNCTION_BLOCK
METHOD Up : INT
VAR_INST nCount : INT; nCount : DINT; END_VAR
Up := 1;
END_METHOD""")


def test_an_instance_declared_with_empty_parentheses_is_a_plain_instance() -> None:
    # bEdge : R_TRIG(); is an FB_init call without arguments: the edge still fires once per rising input
    plc = st.load("""FUNCTION_BLOCK FB_EdgeCount
VAR_INPUT bIn : BOOL; END_VAR
VAR_OUTPUT nEdges : INT; END_VAR
VAR bEdge : R_TRIG(); END_VAR
bEdge(CLK := bIn);
IF bEdge.Q THEN nEdges := nEdges + 1; END_IF
END_FUNCTION_BLOCK""")
    fb = plc.FB_EdgeCount()
    for value in (True, True, False, True, False, False, True):
        fb(bIn=value)
    assert fb.nEdges == 3


def test_a_local_array_may_start_from_the_locals_declared_before_it() -> None:
    # aBytes := [nHigh, nLow] and the STRUCT's field read the locals above them, at every call
    plc = st.load("""TYPE ST_Pair : STRUCT nFirst : INT; nSecond : INT; END_STRUCT END_TYPE
FUNCTION_BLOCK FB_Packer
VAR_INPUT nBase : BYTE; END_VAR
END_FUNCTION_BLOCK
METHOD Packed : UINT
VAR
    nHigh : BYTE := nBase;
    nLow : BYTE := 16#34;
    aBytes : ARRAY[1..4] OF BYTE := [nHigh, nLow, 2(7)];
    stPair : ST_Pair := (nFirst := nLow, nSecond := 5);
END_VAR
Packed := BYTE_TO_UINT(aBytes[1]) * 256 + BYTE_TO_UINT(aBytes[2]) + aBytes[3] + aBytes[4] + stPair.nFirst + stPair.nSecond;
END_METHOD""")
    fb = plc.FB_Packer()
    fb.nBase = 0x12
    assert fb.Packed() == 0x1234 + 14 + 0x34 + 5
    fb.nBase = 0x01
    assert fb.Packed() == 0x0134 + 14 + 0x34 + 5  # made again at the next call, from the new input


def test_this_is_the_instance_s_address_where_a_pointer_takes_it() -> None:
    # each block registers itself from FB_init (aKnown[n] := THIS), as a framework keeps its suites; the
    # pointers call the derived block's METHOD, and a pointer compares equal to THIS of its own block only
    plc = st.load("""{attribute 'qualified_only'}
VAR_GLOBAL
    nKnown : INT;
    aKnown : ARRAY[1..4] OF POINTER TO FB_Base;
END_VAR
FUNCTION_BLOCK FB_Base
VAR bIsFirst : BOOL; END_VAR
END_FUNCTION_BLOCK
METHOD FB_init : BOOL
VAR_INPUT bInitRetains : BOOL; bInCopyCode : BOOL; END_VAR
GVL.nKnown := GVL.nKnown + 1;
GVL.aKnown[GVL.nKnown] := THIS;
END_METHOD
METHOD Kind : INT
Kind := 1;
bIsFirst := GVL.aKnown[1] = THIS;
END_METHOD
METHOD Self : POINTER TO FB_Base
Self := THIS;
END_METHOD
FUNCTION_BLOCK FB_Derived EXTENDS FB_Base
END_FUNCTION_BLOCK
METHOD Kind : INT
Kind := 20;
bIsFirst := GVL.aKnown[1] = THIS;
END_METHOD
FUNCTION_BLOCK FB_Holder
VAR_INPUT pHeld : POINTER TO FB_Base; END_VAR
END_FUNCTION_BLOCK
PROGRAM P
VAR fbPlain : FB_Base; fbDerived : FB_Derived; fbHolder : FB_Holder; nSum : INT; END_VAR
nSum := GVL.aKnown[1]^.Kind() + GVL.aKnown[2]^.Kind();
fbHolder(pHeld := fbDerived.Self());
nSum := nSum + 100 * fbHolder.pHeld^.Kind();
END_PROGRAM""")
    plc.P()
    assert plc.GVL.nKnown == 2
    assert plc.P.nSum == 1 + 20 + 100 * 20
    assert (plc.P.fbPlain.bIsFirst, plc.P.fbDerived.bIsFirst) == (True, False)


def test_task_info_of_the_system_list_indexed_by_getcurtaskindex_is_the_running_task_s() -> None:
    from iecoop.exceptions import PlcException
    from iecoop.libraries import tc2_system
    from iecoop.testing import VirtualPlc

    # TwinCAT_SystemInfoVarList._TaskInfo[fbTask.index], as Beckhoff's GETCURTASKINDEX example reads the cycle count
    plc = st.load("""PROGRAM MAIN
VAR_INPUT nOther : BYTE; END_VAR
VAR fbTask : GETCURTASKINDEX; nCycles : UDINT; nFirst : INT; END_VAR
fbTask();
nCycles := TwinCAT_SystemInfoVarList._TaskInfo[fbTask.index].CycleCount;
IF _TaskInfo[fbTask.index].FirstCycle THEN nFirst := nFirst + 1; END_IF
IF nOther > 0 THEN nCycles := _TaskInfo[nOther].CycleCount; END_IF
END_PROGRAM""", libraries={"Tc2_System": tc2_system})
    virtual = VirtualPlc()
    virtual.add(plc.MAIN)
    virtual.run_cycles(3)
    counts = [plc.MAIN.nCycles]
    virtual.run_cycles(1)
    counts.append(plc.MAIN.nCycles)
    assert counts[1] == counts[0] + 1 and plc.MAIN.nFirst == 1
    plc.MAIN.nOther = plc.MAIN.fbTask.index + 1  # another task's index: iecoop knows the running one only
    with pytest.raises(PlcException, match=r"_TaskInfo\[\d+\]: iecoop knows the running task's information only"):
        virtual.run_cycles(1)
