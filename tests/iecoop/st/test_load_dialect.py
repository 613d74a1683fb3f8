"""The TwinCAT / CODESYS dialect real projects write: each construct loaded and run over cycles, values worked by hand."""

from __future__ import annotations

import pathlib

import pytest

from iecoop.exceptions import AccessError, DefinitionError

st = pytest.importorskip("iecoop.st")


# --- errors named instead of internal ones ---------------------------------------------------------


def test_a_struct_extending_an_undeclared_one_is_named() -> None:
    with pytest.raises(st.StUnsupportedError, match=r"<st>:1: STRUCT ST_B EXTENDS ST_Nope, which is no declared STRUCT"):
        st.load("TYPE ST_B EXTENDS ST_Nope : STRUCT x : INT; END_STRUCT END_TYPE")


def test_an_empty_struct_is_named_with_its_line() -> None:
    with pytest.raises(DefinitionError, match=r"<st>:2: STRUCT ST_E has no members"):
        st.load("\nTYPE ST_E : STRUCT END_STRUCT END_TYPE")


def test_a_positional_argument_after_a_named_one_takes_the_parameter_of_its_place() -> None:
    source = """FUNCTION F : INT
VAR_INPUT a : INT; b : INT; c : INT; END_VAR
F := a * 100 + b * 10 + c;
END_FUNCTION
PROGRAM P
VAR x : INT; y : INT; END_VAR
x := F(a := 5, 2, c := 1);
y := F(b := 5, a := 2, 3);
END_PROGRAM"""
    plc = st.load(source)
    plc.P()
    assert (plc.P.x, plc.P.y) == (521, 253)


def test_a_positional_argument_after_a_named_one_is_refused_where_its_place_is_taken() -> None:
    source = """FUNCTION F : INT
VAR_INPUT a : INT; b : INT; END_VAR
F := a + b;
END_FUNCTION
PROGRAM P
VAR x : INT; END_VAR
x := F(b := 5, 2);
END_PROGRAM"""
    with pytest.raises(st.StUnsupportedError, match=r"<st>:7: argument 2 is b by its place, which a named argument sets too"):
        st.load(source)
    with pytest.raises(st.StUnsupportedError, match=r"<st>:7: a positional argument follows the named argument a and has no "
                                                     r"parameter at its place \(3\)"):
        st.load(source.replace("F(b := 5, 2)", "F(a := 5, b := 2, 3)"))


def test_an_interface_named_with_its_descendant_loads() -> None:
    plc = st.load("""INTERFACE I_A
END_INTERFACE
METHOD M : INT
END_METHOD
INTERFACE I_B EXTENDS I_A
END_INTERFACE
FUNCTION_BLOCK FB IMPLEMENTS I_A, I_B
VAR n : INT; END_VAR
END_FUNCTION_BLOCK
METHOD M : INT
n := n + 3;
M := n;
END_METHOD
""")
    fb = plc.FB()
    assert (fb.M(), fb.M()) == (3, 6)
    assert isinstance(fb, plc.I_A) and isinstance(fb, plc.I_B)


def test_a_class_the_builder_refuses_is_named_at_its_declaration() -> None:
    source = "INTERFACE I_Drive\nEND_INTERFACE\nMETHOD Move : BOOL\nEND_METHOD\n\nFUNCTION_BLOCK FB_Motor IMPLEMENTS I_Drive\nEND_FUNCTION_BLOCK\n"
    with pytest.raises(DefinitionError, match=r"<st>:6: FUNCTION_BLOCK FB_Motor: there is no implementation for method 'Move'"):
        st.load(source)


def test_a_program_that_cannot_be_made_is_named_at_its_declaration() -> None:
    source = "FUNCTION_BLOCK FB_X\nVAR n : INT; END_VAR\nEND_FUNCTION_BLOCK\nPROGRAM P\nVAR fb : FB_X(n := 5); END_VAR\nEND_PROGRAM"
    with pytest.raises(st.StUnsupportedError, match=r"<st>:4: PROGRAM P cannot be made: TypeError: FB_X: FB_init has no input 'n'"):
        st.load(source)


@pytest.mark.parametrize("source", ["", "   \n", "FUNCTION_BLOCK A\nVAR x : INT;"])
def test_empty_and_cut_sources(source: str) -> None:
    if not source.strip():
        assert "<iecoop.st st #" in str(st.load(source).__file__)  # empty text, not the current folder
        return
    with pytest.raises(st.StSyntaxError, match=r"<st>:2: .*the source ends before"):
        st.load(source)


# --- generics ---------------------------------------------------------------------------------------

GENERIC = """
FUNCTION F_Kind : INT
VAR_INPUT x : ANY_NUM; END_VAR
VAR pInt : POINTER TO INT; pReal : POINTER TO REAL; END_VAR
CASE x.TypeClass OF
__SYSTEM.TYPE_CLASS.TYPE_INT:
    pInt := x.pValue;
    F_Kind := pInt^ * 10;
__SYSTEM.TYPE_CLASS.TYPE_REAL:
    pReal := x.pValue;
    F_Kind := REAL_TO_INT(pReal^);
ELSE
    F_Kind := -x.diSize;
END_CASE
END_FUNCTION

FUNCTION F_Clear : BOOL
VAR_INPUT x : ANY_INT; END_VAR
VAR p : POINTER TO INT; END_VAR
IF x.TypeClass = __SYSTEM.TYPE_CLASS.TYPE_INT THEN
    p := x.pValue;
    p^ := 0;
    F_Clear := TRUE;
END_IF
END_FUNCTION

FUNCTION_BLOCK FB_Sum
VAR_OUTPUT rTotal : LREAL; END_VAR
END_FUNCTION_BLOCK
METHOD Add : DINT
VAR_INPUT value : ANY_REAL; END_VAR
VAR pR : POINTER TO REAL; pL : POINTER TO LREAL; END_VAR
IF value.TypeClass = __SYSTEM.TYPE_CLASS.TYPE_REAL THEN
    pR := value.pValue;
    rTotal := rTotal + pR^;
ELSE
    pL := value.pValue;
    rTotal := rTotal + pL^;
END_IF
Add := value.diSize;
END_METHOD

PROGRAM MAIN
VAR
    n : INT := 4; r : REAL := 2.5; d : DINT := 7; l : LREAL := 0.25;
    a : INT; b : INT; c : INT; e : INT; k : INT := 9; s1 : DINT; s2 : DINT;
    fbSum : FB_Sum;
END_VAR
a := F_Kind(n);
b := F_Kind(r);
c := F_Kind(x := d);
e := F_Kind(n + 1);
s1 := fbSum.Add(r);
s2 := fbSum.Add(value := l);
F_Clear(k);
n := n + 1;
k := k + 2;
END_PROGRAM
"""


def test_generic_inputs_from_st_over_cycles() -> None:
    plc = st.load(GENERIC)
    main = plc.MAIN
    main()
    # n=4: 4*10; r=2.5 rounds to 2 (REAL_TO_INT rounds half to even); DINT: -4 bytes; n+1=5 (a copy): 50
    assert (main.a, main.b, main.c, main.e) == (40, 2, -4, 50)
    assert (main.s1, main.s2, main.fbSum.rTotal) == (4, 8, 2.75)
    assert main.k == 2                       # F_Clear wrote the caller's k through pValue, then k := k + 2
    main()
    assert (main.a, main.e, main.k, main.fbSum.rTotal) == (50, 60, 2, 5.5)


def test_a_generic_input_refuses_a_type_outside_its_family_at_load() -> None:
    source = GENERIC.replace("s1 := fbSum.Add(r);", "s1 := fbSum.Add(n);")
    with pytest.raises(DefinitionError, match=r"<st>:\d+: VAR_INPUT value : ANY_REAL takes a REAL or LREAL, not INT"):
        st.load(source)


def test_a_generic_input_called_from_python() -> None:
    plc = st.load(GENERIC)
    assert plc.F_Kind(7) == -4               # a Python int is a DINT
    with pytest.raises(AccessError, match="ANY_NUM takes a number"):
        plc.F_Kind("x")


def test_a_generic_type_outside_a_function_input_is_refused() -> None:
    with pytest.raises(st.StUnsupportedError, match="<st>:2: VAR x : ANY_NUM: a generic type is not supported outside a VAR_INPUT"):
        st.load("PROGRAM P\nVAR x : ANY_NUM; END_VAR\nEND_PROGRAM")


# --- grammar blark does not read -------------------------------------------------------------------

NESTED = """
TYPE ST_P : STRUCT a : INT := 5; b : INT; END_STRUCT END_TYPE
FUNCTION_BLOCK FB_Counter EXTENDS FB_Base,
VAR n : INT; stP : ST_P := (); END_VAR
METHOD PUBLIC Inc : INT
VAR_INPUT d : INT; END_VAR
n := n + d;
Inc := n;
END_METHOD
PROPERTY Count : INT
GET
    Count := n * 10;
END_GET
SET
    n := Count;
END_SET
END_PROPERTY
Inc(2);
END_FUNCTION_BLOCK
FUNCTION_BLOCK FB_Base
VAR_OUTPUT t : LTIME := LTIME#1US5NS; tLong : LTIME := LTIME#1MS2US3NS; END_VAR
END_FUNCTION_BLOCK
CLASS C_Acc
VAR total : DINT; END_VAR
METHOD Add : DINT
VAR_INPUT x : DINT; END_VAR
VAR_TEMP y : DINT; END_VAR
y := x * 2;
total := total + y;
Add := total;
END_METHOD
END_CLASS
FUNCTION F_Twice : INT
VAR_INPUT x : INT; END_VAR
VAR_TEMP t : INT; END_VAR
t := x * 2;
F_Twice := t;
END_FUNCTION
PROGRAM INTERNAL MAIN
VAR fb : FB_Counter; acc : C_Acc; r : REF_TO INT; n : INT; k : INT; END_VAR
fb();
acc.Add(3);
r REF= n;
r := F_Twice(r + 1);
k := fb.Count;
END_PROGRAM
"""


def test_members_inside_their_block_class_and_the_small_forms() -> None:
    plc = st.load(NESTED)
    main = plc.MAIN
    main()
    # Inc(2) per cycle; Add(3) adds 6; r is n: n := (0 + 1) * 2; Count's GET is n * 10
    assert (main.fb.n, main.acc.total, main.n, main.k) == (2, 6, 2, 20)
    main()
    assert (main.fb.n, main.acc.total, main.n, main.k) == (4, 12, 6, 40)
    assert (main.fb.t, main.fb.tLong) == (1_005, 1_002_003)   # nanoseconds
    assert (main.fb.stP.a, main.fb.stP.b) == (5, 0)          # := () keeps the declared values
    main.fb.Count = 7                                          # SET ... END_SET
    assert main.fb.Count == 70
    assert isinstance(main.fb, plc.FB_Base)                    # EXTENDS FB_Base, (trailing comma)


def test_return_after_a_parenthesised_condition() -> None:
    plc = st.load("""FUNCTION F : INT
VAR_INPUT x : BOOL; END_VAR
F := 1;
IF (x) THEN RETURN; END_IF
F := 2;
END_FUNCTION""")
    assert (plc.F(True), plc.F(False)) == (1, 2)


# --- declarations -----------------------------------------------------------------------------------

DECLARATIONS = """
TYPE T_MaxString : STRING(255); END_TYPE
TYPE T_Trio : ARRAY[1..3] OF INT; END_TYPE
TYPE E_Mode : (Idle, Run) := Run; END_TYPE
TYPE ST_Flags : STRUCT bReady : BIT; bBusy : BIT; eMode : E_Mode; nCount : INT; END_STRUCT END_TYPE
FUNCTION F_Sum : INT
VAR_IN_OUT arr : ARRAY[*] OF INT; END_VAR
VAR i : DINT; END_VAR
FOR i := LOWER_BOUND(arr, 1) TO UPPER_BOUND(arr, 1) DO
    F_Sum := F_Sum + arr[i];
    arr[i] := arr[i] + 1;
END_FOR
END_FUNCTION
FUNCTION F_Mode : E_Mode
VAR x : E_Mode; END_VAR
F_Mode := x;
END_FUNCTION
PROGRAM MAIN
VAR
    sText : T_MaxString; nLen : INT; aTrio : T_Trio;
    a : ARRAY[2..4] OF INT := [1, 2, 3]; b : ARRAY[0..1] OF INT := [10, 20]; s : INT; t : INT;
    eMode : E_Mode; eIdle : E_Mode := E_Mode.Idle; stFlags : ST_Flags; eFromF : E_Mode; nRuns : INT;
END_VAR
sText := CONCAT(sText, '0123456789');
nLen := LEN(sText);
aTrio[3] := nLen;
s := F_Sum(a);
t := F_Sum(arr := b);
eFromF := F_Mode();
IF eMode = E_Mode.Run THEN nRuns := nRuns + 1; eMode := E_Mode.Idle; END_IF
stFlags.bBusy := NOT stFlags.bBusy;
END_PROGRAM
"""


def test_declarations_real_projects_write() -> None:
    plc = st.load(DECLARATIONS)
    main = plc.MAIN
    main()
    assert (main.s, main.t, list(main.a), list(main.b)) == (6, 30, [2, 3, 4], [11, 21])   # sums, then each +1
    assert (main.eMode, main.eIdle, main.stFlags.eMode, main.eFromF, main.nRuns) == (0, 0, 1, 1, 1)  # Run is 1
    assert (main.nLen, main.aTrio[3], main.stFlags.bBusy, main.stFlags.bReady) == (10, 10, True, False)
    main()
    assert (main.s, main.t, main.nRuns, main.stFlags.bBusy) == (9, 32, 1, False)
    for _ in range(30):
        main()
    assert main.nLen == 255                          # STRING(255) through the alias, not STRING(80)


def test_array_star_outside_an_in_out_is_refused() -> None:
    with pytest.raises(st.StUnsupportedError, match=r"<st>:2: VAR a : ARRAY\[\*\] is not supported outside a VAR_IN_OUT"):
        st.load("PROGRAM P\nVAR a : ARRAY[*] OF INT; END_VAR\nEND_PROGRAM")


def test_a_function_without_body_names_its_line() -> None:
    with pytest.raises(st.StUnsupportedError, match=r"<st>:2: FUNCTION F has no body"):
        st.load("\nFUNCTION F : INT\nEND_FUNCTION")


def test_an_enum_default_that_is_no_value_is_named() -> None:
    with pytest.raises(st.StUnsupportedError, match="the default 'Stop' of enumeration E_Mode is none of its values"):
        st.load("TYPE E_Mode : (Idle, Run) := Stop; END_TYPE")


# --- calls ------------------------------------------------------------------------------------------

FOR_BOUNDS = """
FUNCTION_BLOCK FB_Bounds
VAR_OUTPUT nEndCalls : INT; nStepCalls : INT; END_VAR
END_FUNCTION_BLOCK
METHOD getEnd : INT
nEndCalls := nEndCalls + 1;
getEnd := 6;
END_METHOD
METHOD getStep : INT
nStepCalls := nStepCalls + 1;
getStep := 2;
END_METHOD
PROGRAM MAIN
VAR fb : FB_Bounds; i : INT; j : INT; n : INT; nPasses : INT; nShrinking : INT; END_VAR
nPasses := 0;
FOR i := 0 TO fb.getEnd() BY fb.getStep() DO
    nPasses := nPasses + 1;
END_FOR
n := 5;
nShrinking := 0;
FOR j := 1 TO n DO
    n := n - 1;
    nShrinking := nShrinking + 1;
END_FOR
END_PROGRAM
"""


def test_for_evaluates_the_step_once_and_the_end_before_every_pass() -> None:
    plc = st.load(FOR_BOUNDS)
    main = plc.MAIN
    main()
    # passes at i = 0, 2, 4, 6; the end is checked before each and once more at i = 8; BY runs once
    assert (main.nPasses, main.i, main.fb.nEndCalls, main.fb.nStepCalls) == (4, 8, 5, 1)
    # j = 1, 2, 3 run (n falls to 2): the check at j = 4 reads the new end
    assert (main.nShrinking, main.j, main.n) == (3, 4, 2)
    main()
    assert (main.fb.nEndCalls, main.fb.nStepCalls) == (10, 2)


def test_a_block_called_with_its_inputs_by_position() -> None:
    plc = st.load("""FUNCTION_BLOCK FB_Mix
VAR_INPUT a : INT; b : INT; END_VAR
VAR_OUTPUT s : INT; END_VAR
s := a * 10 + b;
END_FUNCTION_BLOCK
FUNCTION_BLOCK FB_Mix3 EXTENDS FB_Mix
VAR_INPUT c : INT; END_VAR
s := s + c * 100;
END_FUNCTION_BLOCK
PROGRAM MAIN
VAR fb : FB_Mix; fb3 : FB_Mix3; t : TON; x : INT; y : INT; n : INT; END_VAR
n := n + 1;
fb(n, 2);
x := fb.s;
fb3(1, 2, n);
y := fb3.s;
t(TRUE, T#5MS);
END_PROGRAM""")
    main = plc.MAIN
    main()
    assert (main.x, main.y, main.fb3.a, main.t.PT) == (12, 100, 1, 5)  # inputs in declaration order, the base's first
    main()
    assert (main.x, main.y) == (22, 300)                              # FB_Mix3's body adds to its s
    with pytest.raises(st.StUnsupportedError, match="FB_Mix takes 2 inputs by position, the call gives 3"):
        st.load("FUNCTION_BLOCK FB_Mix\nVAR_INPUT a : INT; b : INT; END_VAR\nEND_FUNCTION_BLOCK\n"
                "PROGRAM P\nVAR fb : FB_Mix; END_VAR\nfb(1, 2, 3);\nEND_PROGRAM")


# --- addresses of locals and type punning ---------------------------------------------------------

PUNNING = """
FUNCTION F_Bits : ULINT
VAR_INPUT lrealVar : LREAL; END_VAR
VAR pBits : POINTER TO ULINT := ADR(lrealVar); n : INT := 3; pN : POINTER TO INT := ADR(n); END_VAR
pN^ := pN^ + 1;
F_Bits := pBits^ + n;
END_FUNCTION
FUNCTION_BLOCK FB_Raw
VAR_OUTPUT nBits : ULINT; END_VAR
END_FUNCTION_BLOCK
METHOD Raw : ULINT
VAR_INPUT v : LREAL; END_VAR
VAR p : POINTER TO ULINT; END_VAR
p := ADR(v);
nBits := p^;
Raw := nBits;
END_METHOD
PROGRAM MAIN
VAR fb : FB_Raw; b : ULINT; c : ULINT; f : LREAL := 1.0; END_VAR
b := F_Bits(f);
c := fb.Raw(-2.0);
f := f * 2;
END_PROGRAM
"""


def test_adr_of_a_local_or_an_input_and_the_bits_of_an_lreal() -> None:
    plc = st.load(PUNNING)
    main = plc.MAIN
    main()
    assert main.b == 0x3FF0_0000_0000_0000 + 4          # 1.0's bits, plus n after pN^ := pN^ + 1
    assert main.c == main.fb.nBits == 0xC000_0000_0000_0000  # -2.0
    main()
    assert main.b == 0x4000_0000_0000_0000 + 4          # 2.0: the input was copied where it has an address


def test_names_from_other_files_gvl_constant_bound_and_later_bases(tmp_path: pathlib.Path) -> None:
    folder = tmp_path
    files = {
        "A_Main.st": "PROGRAM MAIN\nVAR aBuf : ARRAY[1..GVL_Param.cMax] OF INT; stD : ST_Derived; fb : FB_Derived; i : INT; END_VAR\n"
                     "FOR i := 1 TO GVL_Param.cMax DO aBuf[i] := aBuf[i] + i; END_FOR\nstD.x := stD.x + 1;\nfb();\nEND_PROGRAM\n",
        "B_Derived.st": "TYPE ST_Derived EXTENDS ST_Base : STRUCT y : INT := 7; END_STRUCT END_TYPE\n"
                        "FUNCTION_BLOCK FB_Derived EXTENDS FB_Base\nEND_FUNCTION_BLOCK\n",
        "GVL_Param.st": "VAR_GLOBAL CONSTANT\n    cMax : INT := 3;\nEND_VAR\n",
        "Z_Base.st": "TYPE ST_Base : STRUCT x : INT; END_STRUCT END_TYPE\n"
                     "FUNCTION_BLOCK FB_Base\nVAR_OUTPUT n : INT; END_VAR\nn := n + 2;\nEND_FUNCTION_BLOCK\n",
    }
    for name, text in files.items():
        (folder / name).write_text(text, encoding="utf-8")
    plc = st.load(folder)
    main = plc.MAIN
    main()
    main()
    assert (list(main.aBuf), main.stD.x, main.stD.y, main.fb.n) == ([2, 4, 6], 2, 7, 4)


def test_an_array_literal_assigned_in_code() -> None:
    plc = st.load("""TYPE ST_P : STRUCT a : INT; b : INT; END_STRUCT END_TYPE
PROGRAM MAIN
VAR arr : ARRAY[0..1] OF ST_P; n : ARRAY[1..3] OF INT; k : INT; END_VAR
k := k + 1;
arr := [(a := k, b := 2), (a := 3, b := 4)];
n := [k, 2 * k, 1(7)];
END_PROGRAM""")
    plc.MAIN()
    plc.MAIN()
    assert [(p.a, p.b) for p in plc.MAIN.arr] == [(2, 2), (3, 4)]
    assert list(plc.MAIN.n) == [2, 4, 7]


def test_a_member_of_what_a_call_returns_a_pointer_to() -> None:
    plc = st.load("""TYPE ST_P : STRUCT y : INT; z : INT; END_STRUCT END_TYPE
FUNCTION_BLOCK FB_Store
VAR aItems : ARRAY[0..2] OF ST_P; END_VAR
END_FUNCTION_BLOCK
METHOD Item : POINTER TO ST_P
VAR_INPUT i : INT; END_VAR
aItems[i].y := aItems[i].y + i;
Item := ADR(aItems[i]);
END_METHOD
PROGRAM MAIN
VAR fb : FB_Store; v : INT; w : INT; END_VAR
v := fb.Item(2)^.y;
w := v + fb.Item(1)^.y;
END_PROGRAM""")
    plc.MAIN()
    assert (plc.MAIN.v, plc.MAIN.w) == (2, 3)   # each call adds i to its item's y first
    plc.MAIN()
    assert (plc.MAIN.v, plc.MAIN.w) == (4, 6)


def test_an_accessors_access_specifier_on_its_own_line() -> None:
    plc = st.load("""FUNCTION_BLOCK FB_Tank
VAR n : INT := 4; END_VAR
END_FUNCTION_BLOCK
PROPERTY PUBLIC Capacity : INT
PRIVATE
Capacity := n * 2;
END_PROPERTY
METHOD Report : INT
n := n + 1;
Report := Capacity + 1;
END_METHOD
""")
    tank = plc.FB_Tank()
    assert (tank.Report(), tank.Report()) == (11, 13)     # (4 + 1) * 2 + 1, then (5 + 1) * 2 + 1
    with pytest.raises(AccessError, match=r"PRIVATE PROPERTY FB_Tank.Capacity \(Get\)"):
        tank.Capacity
