"""st.load: IEC evaluation rules the reader keeps (AND / OR evaluate both operands, the FOR variable after
the loop, values passed by value, method and function locals), one small ST program each, worked out by hand."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import pytest

from iecoop import ExceptionCode, PlcException, T, st
from iecoop.runtime import Runtime, Task
from tests.iecoop.st.test_load import prog, run

COUNTER = """
FUNCTION_BLOCK FB_Probe
VAR_OUTPUT nCalls : INT; END_VAR
END_FUNCTION_BLOCK
METHOD Hit : BOOL
VAR_INPUT bResult : BOOL; END_VAR
nCalls := nCalls + 1;
Hit := bResult;
END_METHOD
PROPERTY Ready : BOOL
nCalls := nCalls + 100;
Ready := TRUE;
END_PROPERTY
FUNCTION F_Tick : BOOL
VAR_INPUT bResult : BOOL; END_VAR
VAR_STAT nTicks : INT; END_VAR
nTicks := nTicks + 1;
F_Tick := bResult;
END_FUNCTION
"""

STRUCTS = """
TYPE ST_P : STRUCT x : INT; y : INT := 2; END_STRUCT END_TYPE
FUNCTION F_Sum : INT
VAR_INPUT a : ARRAY[1..3] OF INT; p : ST_P; END_VAR
VAR i : INT; t : ARRAY[0..1] OF INT := [10, 20]; END_VAR
FOR i := 1 TO 3 DO F_Sum := F_Sum + a[i]; a[i] := 0; END_FOR
F_Sum := F_Sum + p.x + p.y + t[0] + t[1];
p.x := 100; t[0] := 99;
END_FUNCTION
FUNCTION_BLOCK FB_Bump
VAR_INPUT pIn : ST_P; aIn : ARRAY[1..2] OF INT; END_VAR
VAR_OUTPUT nSeen : INT; END_VAR
pIn.x := pIn.x + 1; aIn[1] := aIn[1] + 1;
nSeen := pIn.x * 100 + aIn[1];
END_FUNCTION_BLOCK
METHOD Bump : INT
VAR_INPUT p : ST_P; END_VAR
VAR_STAT nShared : INT; END_VAR
VAR buf : ARRAY[1..2] OF ST_P; END_VAR
nShared := nShared + 1;
p.x := p.x + 1;
buf[1] := p;
Bump := buf[1].x * 100 + nShared;
END_METHOD
"""

# (id, ST source, cycles, what to read from MAIN, expected)
CASES: list[tuple[str, str, int, Callable[[Any], Any], Any]] = [
    ("and-or-evaluate-both-operands", COUNTER + prog(
        "fb : FB_Probe; bF : BOOL; bT : BOOL := TRUE; a : BOOL; b : BOOL; c : BOOL; d : BOOL; e : BOOL; f : BOOL; g : BOOL;",
        "a := bF AND fb.Hit(TRUE); b := bT OR fb.Hit(FALSE); c := bF AND (fb.Hit(TRUE) OR bF); "
        "d := bF AND F_Tick(TRUE) AND F_Tick(TRUE); e := (bT OR F_Tick(FALSE)) AND NOT F_Tick(FALSE);"
        "f := bT AND fb.Hit(TRUE) OR bF; g := bF AND fb.Ready;"), 1,
     # 4 calls of Hit and one read of the property Ready (its Get runs), 3 of F_Tick; each result as IEC combines the values
     lambda m: (m.fb.nCalls, m.a, m.b, m.c, m.d, m.e, m.f, m.g), (104, False, True, False, False, True, True, False)),
    ("and-then-or-else-stop-early", COUNTER + prog(
        "fb : FB_Probe; bF : BOOL; bT : BOOL := TRUE; a : BOOL; b : BOOL; c : BOOL;",
        "a := bF AND_THEN fb.Hit(TRUE); b := bT OR_ELSE fb.Hit(FALSE); c := bT AND_THEN fb.Hit(TRUE);"), 1,
     lambda m: (m.fb.nCalls, m.a, m.b, m.c), (1, False, True, True)),
    ("and-or-on-words-stay-bitwise", COUNTER + "FUNCTION F_Word : WORD\nF_Word := 16#00FF;\nEND_FUNCTION\n"
     + prog("w : WORD := 16#0F0F; v : WORD; x : WORD;", "v := w AND F_Word(); x := w OR F_Word() XOR 16#0001;"), 1,
     lambda m: (m.v, m.x), (0x000F, 0x0FFF)),  # XOR binds tighter than OR: 0F0F OR (00FF XOR 0001)
    ("for-variable-after-the-loop", prog(
        "i : INT; j : SINT; k : INT; m : INT; n : INT := 3; s : INT; nStep : INT := -2; q : INT; ",
        "FOR i := 1 TO 10 DO s := s + 1; END_FOR FOR j := 10 TO 1 BY -2 DO s := s + 1; END_FOR "
        "FOR m := 5 TO 1 DO s := s + 100; END_FOR FOR k := 1 TO 10 DO IF k = 4 THEN EXIT; END_IF END_FOR "
        "FOR q := n * 3 TO n BY nStep DO s := s + 1; END_FOR"), 1,
     # 10 + 5 + 0 + 4 (9, 7, 5, 3) runs; 1..10 leaves 11, 10..1 BY -2 leaves 0, 5 TO 1 never runs, EXIT at 4, 9..3 BY -2 leaves 1
     lambda m: (m.i, m.j, m.m, m.k, m.q, m.s), (11, 0, 5, 4, 1, 19)),
    ("for-in-a-function-leaves-the-local", "FUNCTION F_Last : INT\nVAR i : INT; END_VAR\n"
     "FOR i := 0 TO 20 BY 5 DO ; END_FOR\nF_Last := i;\nEND_FUNCTION\n" + prog("n : INT;", "n := F_Last();"), 1,
     lambda m: m.n, 25),
    ("function-inputs-by-value", STRUCTS + prog(
        "a : ARRAY[1..3] OF INT := [1, 2, 3]; p : ST_P := (x := 5); r1 : INT; r2 : INT;",
        "r1 := F_Sum(a, p); r2 := F_Sum(a := a, p := p);"), 1,
     # 1 + 2 + 3 + 5 + 2 + 10 + 20 both times: the function's writes reach neither the caller nor the next call
     lambda m: (m.r1, m.r2, list(m.a), m.p.x), (43, 43, [1, 2, 3], 5)),
    ("initialised-struct-local", STRUCTS + "FUNCTION F_Init : INT\nVAR s : ST_P := (x := 5); t : ST_P; END_VAR\n"
     "F_Init := s.x + s.y + t.y;\ns.x := 100;\nEND_FUNCTION\n" + prog("a : INT; b : INT;", "a := F_Init(); b := F_Init();"), 1,
     # 5 + 2 + 2 at every call: the locals start from their declared values each time
     lambda m: (m.a, m.b), (9, 9)),
    ("method-input-by-value-and-var-stat", STRUCTS + prog(
        "p : ST_P := (x := 5); fb1 : FB_Bump; fb2 : FB_Bump; b1 : INT; b2 : INT;",
        "b1 := fb1.Bump(p); b2 := fb2.Bump(p := p);"), 2,
     # (5 + 1) * 100 + the VAR_STAT count, shared by both instances: 1, 2, then 3, 4
     lambda m: (m.b1, m.b2, m.p.x), (603, 604, 5)),
    ("actions", """
FUNCTION_BLOCK FB_Station
VAR_OUTPUT nParts : INT; nResets : INT; END_VAR
Count();
END_FUNCTION_BLOCK
ACTION Count:
nParts := nParts + 1;
END_ACTION
ACTION Reset:
nParts := 0; nResets := nResets + 1;
END_ACTION
""" + prog("fb : FB_Station; n : INT;", "fb(); n := n + 1; IF n = 3 THEN fb.Reset(); END_IF"), 4,
     # parts 1, 2, 3 -> reset to 0, then 1
     lambda m: (m.fb.nParts, m.fb.nResets), (1, 1)),
    ("subranges", "TYPE T_Pct : INT(0..100); END_TYPE\n"
     "FUNCTION_BLOCK FB_V\nVAR_INPUT nIn : T_Pct; END_VAR\nVAR_OUTPUT nOut : INT(-5..5) := 2; END_VAR\n"
     "nOut := nIn - 50;\nEND_FUNCTION_BLOCK\n"
     + prog("a : T_Pct; b : INT(5..10); c : UINT(5..10) := 7; fb : FB_V; n : INT := 150; a0 : T_Pct; b0 : INT; c0 : UINT;",
            "a0 := a; b0 := b; c0 := c; a := n; b := b - 10; c := c + 1; fb(nIn := n * 2);"), 1,
     # a subrange starts at its lower limit; a store is held to the limits (150 -> 100, -5 -> 5, 300 -> 100, 50 -> 5)
     lambda m: (m.a0, m.b0, m.c0, m.a, m.b, m.c, m.fb.nIn, m.fb.nOut), (0, 5, 7, 100, 5, 8, 100, 5)),
    ("subrange-arguments", "FUNCTION F_Pct : INT\nVAR_INPUT nPct : INT(0..100); END_VAR\nF_Pct := nPct;\nEND_FUNCTION\n"
     "FUNCTION_BLOCK FB_Valve\nVAR nLast : INT; END_VAR\nEND_FUNCTION_BLOCK\n"
     "METHOD Open : INT\nVAR_INPUT nPct : INT(0..100); END_VAR\nnLast := nPct;\nOpen := nPct;\nEND_METHOD\n"
     + prog("fb : FB_Valve; n : INT := 250; a : INT; b : INT; c : INT; d : INT;",
            "a := F_Pct(nPct := n); b := F_Pct(n - 300); c := fb.Open(nPct := n - 200); d := fb.Open(n);"), 1,
     # a METHOD's or FUNCTION's subrange input is held to the limits at the call, named or by position
     lambda m: (m.a, m.b, m.c, m.d, m.fb.nLast), (100, 0, 50, 100, 100)),
    ("located-variables", prog(
        "bSensor AT %IX0.1 : BOOL; bLamp AT %Q* : BOOL; wWord AT %MW10 : WORD := 5; nCount : INT;",
        "bLamp := bSensor; wWord := wWord + 1; IF bSensor THEN nCount := nCount + 1; END_IF"), 2,
     lambda m: (m.bLamp, m.wWord, m.nCount), (False, 7, 0)),
    ("string-to-conversions", prog(
        "sNum : STRING := ' 34abc'; a : WORD; b : BYTE; c : INT; d : REAL; e : BOOL; f : TIME; g : DINT; h : INT;",
        "a := STRING_TO_WORD(sNum); b := STRING_TO_BYTE('500'); c := STRING_TO_INT('abc34'); "
        "d := STRING_TO_REAL('1.5E3'); e := STRING_TO_BOOL('TRUE'); f := STRING_TO_TIME('T#1s127ms'); "
        "g := STRING_TO_DINT('16#FF'); h := STRING_TO_INT('-2_000');"), 1,
     # text after the number is dropped, text before it gives 0, the value wraps to the type (500 -> 244)
     lambda m: (m.a, m.b, m.c, m.d, m.e, m.f, m.g, m.h), (34, 244, 0, 1500.0, True, 1127, 255, -2000)),
    ("jmp-and-labels", prog("x : INT; n : INT;",
                            "x := 0;\nlbl: x := x + 1;\nIF x < 3 THEN JMP lbl; END_IF\nn := n + 1;\n"
                            "IF n > 1 THEN JMP done; END_IF\nx := x * 2;\ndone:\nn := n + 10;"), 2,
     # cycle 1: x counts to 3, doubled to 6, n = 11; cycle 2: x to 3, n = 12 > 1 skips the doubling, n = 22
     lambda m: (m.x, m.n), (3, 22)),
    ("jmp-to-a-label-that-opens-the-body", prog("x : INT; n : INT;",
                                                "again: x := x + 1;\nIF x MOD 3 <> 0 THEN JMP again; END_IF\nn := n + 1;"), 2,
     # the body starts at its first statement though it carries a label: x counts to 3, then to 6
     lambda m: (m.x, m.n), (6, 2)),
    ("continue-in-repeat-goes-on-at-until", prog("i : INT; n : INT; k : INT; j : INT;",
                                                 "REPEAT i := i + 1; IF i = 3 THEN CONTINUE; END_IF n := n + 1; UNTIL i >= 3 END_REPEAT\n"
                                                 "REPEAT k := k + 1; FOR j := 1 TO 2 DO CONTINUE; END_FOR UNTIL k >= 2 END_REPEAT"), 1,
     # i = 3 continues to UNTIL, which ends the loop (i 3, n 2); a nested loop's CONTINUE is its own
     lambda m: (m.i, m.n, m.k, m.j), (3, 2, 2, 3)),
    ("function-calls-itself", "FUNCTION F_Fact : LINT\nVAR_INPUT n : INT; END_VAR\n"
                              "IF n <= 1 THEN F_Fact := 1; ELSE F_Fact := n * F_Fact(n - 1); END_IF\nEND_FUNCTION\n"
     + prog("x : LINT; y : LINT;", "x := F_Fact(10); y := F_Fact(n := 1);"), 1,
     # in its own body F_Fact is the result where it is read or written and the FUNCTION where it is called
     lambda m: (m.x, m.y), (3628800, 1)),
    ("jmp-in-a-method-and-case", """
FUNCTION_BLOCK FB_J
END_FUNCTION_BLOCK
METHOD Steps : INT
VAR_INPUT nFrom : INT; END_VAR
VAR i : INT; END_VAR
i := nFrom;
again:
CASE i OF
    0: Steps := Steps + 1; i := 1; JMP again;
    1: Steps := Steps + 10;
END_CASE
RETURN;
never:
Steps := -1;
END_METHOD
""" + prog("fb : FB_J; a : INT; b : INT;", "a := fb.Steps(0); b := fb.Steps(1);"), 1,
     lambda m: (m.a, m.b), (11, 10)),
    ("struct-and-block-locals-are-copies", STRUCTS + """
FUNCTION_BLOCK FB_Keep
VAR stKept : ST_P := (x := 1); fbInner : FB_Bump; END_VAR
END_FUNCTION_BLOCK
METHOD Copied : INT
VAR stLocal : ST_P; fbLocal : FB_Bump; END_VAR
stLocal := stKept; stLocal.x := 50;     // the block's stKept stays 1
fbLocal := fbInner; fbLocal(pIn := stLocal);
Copied := stKept.x * 1000 + fbLocal.nSeen;
END_METHOD
METHOD Direct : INT
VAR_INPUT n : INT; END_VAR
Mine.x := n;                            // through the REFERENCE TO property: the block's own struct
Direct := stKept.x;
END_METHOD
PROPERTY Mine : REFERENCE TO ST_P
Mine REF= stKept;
END_PROPERTY
""" + prog("fb : FB_Keep; a : INT; b : INT; c : INT;", "a := fb.Copied(); b := fb.Direct(7); c := fb.fbInner.nSeen;"), 1,
     # 1 * 1000 + (50 + 1) * 100 + (0 + 1); the inner block was never called
     lambda m: (m.a, m.b, m.c), (6101, 7, 0)),
    ("fb-inputs-by-value", STRUCTS + prog(
        "p : ST_P := (x := 5); a : ARRAY[1..2] OF INT := [7, 8]; fb : FB_Bump;",
        "fb(pIn := p, aIn := a);"), 2,
     lambda m: (m.fb.nSeen, m.p.x, list(m.a)), (608, 5, [7, 8])),
]


@pytest.mark.parametrize("source, cycles, read, expected", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_construct(source: str, cycles: int, read: Callable[[Any], Any], expected: Any) -> None:
    assert read(run(source, cycles)) == expected


def test_a_function_that_calls_itself_for_ever_is_a_stack_overflow() -> None:
    module = st.load("FUNCTION F : INT\nVAR_INPUT n : INT; END_VAR\nF := F(n + 1);\nEND_FUNCTION\n" + prog("x : INT;", "x := F(0);"))
    runtime = Runtime(store=":memory:")
    runtime.add_task(Task("PlcTask", interval=T("10ms")), module.MAIN)
    with pytest.raises(PlcException) as caught:
        runtime.run(cycles=1)
    assert caught.value.code == ExceptionCode.RTSEXCPT_STACK_OVERFLOW


def test_function_var_stat_counts_every_call() -> None:
    module = st.load(COUNTER)
    for result in (True, False, True):
        assert module.F_Tick(bResult=result) is result
    assert module.F_Tick.__globals__["_F_Tick_static"].nTicks == 3


@pytest.mark.parametrize("source, construct", [
    (prog("i : INT;", "FOR i := 1 TO 3 DO IF i = 2 THEN JMP out; END_IF END_FOR\nout: i := 0;"), "JMP inside a FOR, WHILE or REPEAT"),
    (prog("i : INT;", "JMP nowhere;"), "JMP nowhere: no label nowhere"),
    (prog("i : INT;", "FOR i := 1 TO 10 DO IF i = 2 THEN i := 5; END_IF END_FOR"), "the FOR loop writes its control variable i"),
    (prog("i : INT;", "a: i := 1; a: i := 2;"), "label a is declared twice"),
    (prog("i : INT;", "i := 1;\nEXIT;"), r"^<st>:\d+: EXIT outside a FOR, WHILE or REPEAT loop"),
    # a number where a compiler wants a string or a BOOL: at load, where a cycle raised a TypeError (RTSEXCPT_UNKNOWN)
    (prog("s : STRING(20);", "s := 5;"), r"^<st>:5: the number 5 cannot be stored in a STRING \(a string literal or a conversion"),
    (prog("w : WSTRING;", "w := 2.5;"), r"^<st>:5: the number 2.5 cannot be stored in a WSTRING"),
    (prog("i : INT; n : INT; r : REAL := 2;", "FOR i := 1 TO r DO n := n + 1; END_FOR"),
     r"^<st>:5: FOR i: its end is a REAL; a FOR counts in integers"),
    (prog("i : INT; n : INT;", "FOR i := 1 TO 5 BY 0.5 DO n := i; END_FOR"), r"^<st>:5: FOR i: its step is a REAL"),
    (prog("r : REAL := 7.5; n : INT := 2;", "r := r MOD n;"), r"^<st>:5: MOD of a REAL: MOD is defined for integers"),
    (prog("b : BOOL;", "b := 32767;"), r"^<st>:5: the number 32767 cannot be stored in a BOOL \(TRUE or FALSE\)"),
    (prog("i : INT;", "IF i = 0 THEN CONTINUE; END_IF"), r"^<st>:\d+: CONTINUE outside a FOR, WHILE or REPEAT loop"),
    # the loop a body with labels runs in is no ST loop: EXIT there would end the body silently
    (prog("i : INT;", "a: i := i + 1;\nIF i > 2 THEN EXIT; END_IF\nJMP a;"), "EXIT outside a FOR, WHILE or REPEAT loop"),
    (prog("i : INT(0..10);", "i := 11;"), "11 is outside the subrange INT[(]0..10[)]"),
    (prog("i : INT(0..10) := -1;", "i := 1;"), "-1 is outside the subrange"),
    ("FUNCTION F : INT\nVAR_INPUT n : INT(0..10); END_VAR\nF := n;\nEND_FUNCTION\n" + prog("i : INT;", "i := F(n := 11);"),
     "11 is outside the subrange INT[(]0..10[)]"),
    ("PROGRAM MAIN\nVAR x : INT; END_VAR\nEND_PROGRAM\nACTION A:\nx := 1;\nEND_ACTION\nACTION A2:\nEND_ACTION\n"
     "FUNCTION F : INT\nF := 1;\nEND_FUNCTION\nACTION B:\nEND_ACTION\n", "ACTION B does not follow a FUNCTION_BLOCK or PROGRAM"),
    ("FUNCTION_BLOCK FB_A\nVAR _n : INT; END_VAR\nEND_FUNCTION_BLOCK\nPROPERTY N : INT\nVAR a : ARRAY[1..2] OF INT; END_VAR\n"
     "N := _n;\nEND_PROPERTY\n", "ARRAY local a"),
    ("FUNCTION_BLOCK FB_A\nVAR _n : INT; END_VAR\nEND_FUNCTION_BLOCK\nPROPERTY N : INT\nVAR_STAT s : INT; END_VAR\n"
     "N := _n;\nEND_PROPERTY\n", "VAR_STAT in a getter"),
    ("FUNCTION_BLOCK FB_A\nVAR M_n : INT; END_VAR\nEND_FUNCTION_BLOCK\nMETHOD M\nVAR_STAT n : INT; END_VAR\n"
     "n := 1;\nEND_METHOD\n", "VAR_STAT n of METHOD FB_A.M clashes with the member M_n"),
])
def test_unsupported_forms_raise(source: str, construct: str) -> None:
    with pytest.raises(st.StUnsupportedError, match=construct):
        st.load(source)


TYPES = """TYPE ST_Pos : STRUCT x : INT; END_STRUCT END_TYPE
TYPE T_Name : STRING(40); END_TYPE
FUNCTION F_Twice : INT
VAR_INPUT n : INT; END_VAR
F_Twice := n * 2;
END_FUNCTION
FUNCTION_BLOCK FB_Scale
VAR_INPUT rIn : REAL; END_VAR
VAR_OUTPUT sText : STRING; END_VAR
END_FUNCTION_BLOCK
"""


@pytest.mark.parametrize("declarations, statement, message", [
    ("s : STRING := '12'; n : INT;", "n := s;",
     r"^<st>:15: n := \.\.\.: cannot convert type STRING to type INT \(ST converts no STRING implicitly: convert it with "
     r"STRING_TO_INT or TO_INT\)"),
    ("s : STRING; n : DINT := 3;", "s := n;", r"s := \.\.\.: cannot convert type DINT to type STRING \(.*DINT_TO_STRING"),
    ("s : T_Name; r : LREAL;", "s := r;", r"cannot convert type LREAL to type STRING .*LREAL_TO_STRING"),  # an alias of STRING
    ("s : STRING; t : TIME;", "s := t;", "cannot convert type TIME to type STRING"),
    ("p : ST_Pos; n : INT;", "p := n;", r"p := \.\.\.: cannot convert type INT to type ST_Pos \(a STRUCT\)"),
    ("p : ST_Pos; n : INT;", "n := p;", r"cannot convert type ST_Pos \(a STRUCT\) to type INT"),
    ("a : ARRAY[0..2] OF INT; n : INT;", "a := n;", "cannot convert type INT to type ARRAY OF INT"),
    ("fb : FB_Scale; n : INT;", "n := fb;", r"cannot convert type FB_Scale \(a FUNCTION_BLOCK\) to type INT"),
    ("s : STRING := 'a'; n : INT;", "n := F_Twice(s);", r"input n: cannot convert type STRING to type INT"),
    ("s : STRING := 'a'; n : INT;", "n := F_Twice(n := s);", r"input n: cannot convert type STRING to type INT"),
    ("fb : FB_Scale; s : STRING := '1.5';", "fb(rIn := s);", r"input rIn: cannot convert type STRING to type REAL"),
    ("fb : FB_Scale; n : INT;", "n := fb.sText;", "cannot convert type STRING to type INT"),
    ("s : STRING; n : INT; b : BOOL;", "b := s = n;", r"cannot compare type STRING with type INT \(a STRING compares"),
    ("s : STRING; t : TIME; b : BOOL;", "b := t < s;", "cannot compare type TIME with type STRING"),
])
def test_a_value_st_does_not_convert_implicitly_is_refused_at_its_line(declarations: str, statement: str, message: str) -> None:
    with pytest.raises(st.StUnsupportedError, match=message):
        st.load(TYPES + prog(declarations, statement))


def test_what_st_converts_implicitly_loads_and_runs() -> None:
    """Numbers into numbers, TIME and integers, aliases of STRING, STRING into STRING: converted as ST does."""
    main = run(TYPES + prog(
        "n : INT := 7; r : LREAL; t : TIME; d : DINT; s : STRING := 'ab'; name : T_Name; b : BOOL; p : ST_Pos; q : ST_Pos;",
        "r := n; t := n; d := t; name := s; s := name; b := name = s; p.x := 3; q := p; n := F_Twice(d);"), 1)
    assert (main.r, main.t, main.d, main.name, main.b, main.q.x, main.n) == (7.0, 7, 7, "ab", True, 3, 14)


def test_generated_python_reads_as_the_rules() -> None:
    code = st.to_python(COUNTER + prog("fb : FB_Probe; a : BOOL; i : INT;",
                                       "a := a AND fb.Hit(TRUE); a := a AND_THEN fb.Hit(TRUE); a := a AND TRUE; "
                                       "FOR i := 1 TO 3 DO ; END_FOR"))
    assert "self.a = self.a & self.fb.Hit(True)" in code
    assert "self.a = self.a and self.fb.Hit(True)" in code and "self.a = self.a and True" in code
    assert "else:  # the first value past the end, as ST leaves it\n            self.i = 4" in code


def test_located_inputs_are_written_from_outside_and_keep_their_address() -> None:
    source = prog("bSensor AT %I* : BOOL;\nbLamp AT %QX0.0 : BOOL; // lamp", "bLamp := bSensor;")
    main = st.load(source).MAIN
    main.bSensor = True  # what the I/O image would write
    main()
    assert main.bLamp is True
    code = st.to_python(source)
    assert "bSensor: BOOL = VAR_INPUT()  # AT %I*" in code and "bLamp: BOOL = VAR()  # AT %QX0.0: lamp" in code


def test_twincat_action_joins_its_block(tmp_path: Any) -> None:
    (tmp_path / "FB_Act.TcPOU").write_text("""<?xml version="1.0" encoding="utf-8"?>
<TcPlcObject Version="1.1.0.1" ProductVersion="3.1.4024.12">
  <POU Name="FB_Act" Id="{5a0e3c57-0000-4000-8000-000000000108}" SpecialFunc="None">
    <Declaration><![CDATA[FUNCTION_BLOCK FB_Act
VAR_OUTPUT
    nCount : INT;
END_VAR
]]></Declaration>
    <Implementation>
      <ST><![CDATA[Bump();]]></ST>
    </Implementation>
    <Action Name="Bump" Id="{5a0e3c57-0000-4000-8000-000000000109}">
      <Implementation>
        <ST><![CDATA[nCount := nCount + 1;
nCount := nCount + undefined;]]></ST>
      </Implementation>
    </Action>
  </POU>
</TcPlcObject>
""")
    # the error names the action's own line in the file
    with pytest.raises(st.StUnsupportedError, match=r"FB_Act\.TcPOU:\d+: unknown variable 'undefined'"):
        st.load(tmp_path)
    path = tmp_path / "FB_Act.TcPOU"
    path.write_text(path.read_text().replace("nCount := nCount + undefined;", ""))
    block = st.load(tmp_path).FB_Act()
    block(); block.Bump()
    assert block.nCount == 2


def test_subrange_declarations_read_as_their_base_type() -> None:
    code = st.to_python("TYPE T_Pct : INT(0..100); END_TYPE\n" + prog("b : INT(5..10);", "b := b + 1;"))
    assert 'T_Pct = Annotated[INT, Alias("T_Pct", initial=0, limits=(0, 100))]' in code
    assert "b: INT = VAR(5)  # INT(5..10)" in code and "self.b = LIMIT(5, self.b + 1, 10)" in code


def test_an_action_of_a_program_runs_on_its_instance() -> None:
    module = st.load("PROGRAM P_Line\nVAR nStops : INT; END_VAR\nEND_PROGRAM\nACTION Halt:\nnStops := nStops + 1;\nEND_ACTION\n"
                     + prog("n : INT;", "P_Line.Halt(); n := P_Line.nStops * 10;"))
    module.MAIN(); module.MAIN()
    assert (module.MAIN.n, module.P_Line.nStops) == (20, 2)


def test_to_string_conversions_write_the_vendor_text() -> None:
    """REAL_TO_STRING, TIME_TO_STRING and the rest load as iecoop's conversions, TO_STRING by the declared type."""
    main = run(prog(
        "r : REAL := 1.5; lr : LREAL := 0.25; t : TIME := T#1S500MS; b : BOOL := TRUE; w : WORD := 16#FFFF;\n"
        "d : DATE := D#2024-01-28; s1, s2, s3, s4, s5, s6, s7 : STRING; ws : WSTRING;",
        "s1 := REAL_TO_STRING(r * 2.0 + 0.1); s2 := TIME_TO_STRING(t); s3 := BOOL_TO_STRING(b);\n"
        "s4 := TO_STRING(t); s5 := WORD_TO_STRING(w); s6 := CONCAT('x=', LREAL_TO_STRING(lr));\n"
        "s7 := DATE_TO_STRING(d); ws := REAL_TO_WSTRING(r);",
    ))
    assert (main.s1, main.s2, main.s3, main.s4, main.s5, main.s6, main.s7, main.ws) == (
        "3.1", "T#1s500ms", "TRUE", "T#1s500ms", "65535", "x=0.25", "D#2024-01-28", "1.5",
    )


def test_to_string_of_an_enumeration_is_its_name() -> None:
    source = "{attribute 'to_string'}\nTYPE E_Mode : (IDLE := 0, AUTO := 1) INT; END_TYPE\n" + prog(
        "eMode : E_Mode := E_Mode.AUTO; s : STRING;", "s := TO_STRING(eMode);"
    )
    assert run(source).s == "AUTO"
