"""st.load: one small ST program per construct, expected values worked out by hand."""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies

from iecoop import PlcException, T
from iecoop.runtime import Runtime, Task
from iecoop import st
from tests import checked_only


def run(source: str, cycles: int = 1, program: str = "MAIN") -> Any:
    """Load ``source`` and call its PROGRAM ``cycles`` times; the program instance."""
    module = st.load(source)
    main = getattr(module, program)
    for _ in range(cycles):
        main()
    return main


def prog(decls: str, body: str) -> str:
    return f"PROGRAM MAIN\nVAR\n{decls}\nEND_VAR\n{body}\nEND_PROGRAM\n"


def _reference_results(fb: Any) -> tuple[int, int]:
    """Write through the references FB_R's Pick and First return: FB_R.s.n and FB_R.t.n after."""
    fb.Pick(b=True).n = 4
    fb.Pick(b=False).n = 5
    fb.First.n += 1
    return fb.s.n, fb.t.n


# (id, ST source, cycles, what to read from MAIN, expected)
CASES: list[tuple[str, str, int, Callable[[Any], Any], Any]] = [
    ("assign-and-wrap", prog("n : INT := 32767; b : BYTE := 255;", "n := n + 1; b := b + 1;"), 1,
     lambda m: (m.n, m.b), (-32768, 0)),
    ("integer-division-truncates", prog("a : INT; b : INT; c : DINT;", "a := -7 / 2; b := -7 MOD 2; c := 7 MOD -2;"), 1,
     lambda m: (m.a, m.b, m.c), (-3, -1, 1)),
    ("real-division", prog("r : REAL; l : LREAL;", "r := 7.0 / 2; l := 1.0 / 3.0;"), 1,
     lambda m: (m.r, round(m.l, 6)), (3.5, 0.333333)),
    ("real-is-32-bit", prog("r : REAL;", "r := 0.1;"), 1, lambda m: m.r == 0.1, False),
    ("precedence", prog("a : INT; b : BOOL;", "a := 2 + 3 * 4 - -1; b := 1 + 1 = 2 AND NOT (3 < 2);"), 1,
     lambda m: (m.a, m.b), (15, True)),
    ("typed-literals", prog("a : INT; b : BYTE; c : INT; d : DINT; t : TIME; e : LREAL;",
                             "a := 16#FF; b := 2#1010; c := INT#-5; d := 8#17; t := T#1s500ms; e := 1.5E3;"), 1,
     lambda m: (m.a, m.b, m.c, m.d, m.t, m.e), (255, 10, -5, 15, 1500, 1500.0)),
    ("bit-access", prog("w : WORD := 16#00F0; b3 : BOOL; b4 : BOOL;", "w.0 := TRUE; w.4 := FALSE; b3 := w.3; b4 := w.5;"), 1,
     lambda m: (m.w, m.b3, m.b4), (0x00E1, False, True)),
    ("bitwise-on-words", prog("w : WORD := 16#0F0F; v : WORD;", "v := (w AND 16#00FF) OR 16#F000; v := v XOR 16#0001;"), 1,
     lambda m: m.v, 0xF00E),
    ("if-elsif-else", prog("n : INT; s : INT;", "n := n + 1; IF n = 1 THEN s := 10; ELSIF n = 2 THEN s := 20; ELSE s := 30; END_IF"), 3,
     lambda m: m.s, 30),
    ("case-lists-ranges", prog("n : INT; a : INT; b : INT; c : INT;",
                               "FOR n := 0 TO 9 DO CASE n OF 1, 3: a := a + 1; 5..7: b := b + 1; ELSE c := c + 1; END_CASE END_FOR"), 1,
     lambda m: (m.a, m.b, m.c), (2, 3, 5)),
    ("for-by-negative", prog("i : INT; s : INT;", "FOR i := 10 TO 1 BY -3 DO s := s * 100 + i; END_FOR"), 1,
     lambda m: m.s, 10070401 % 65536 - 65536 if 10070401 % 65536 >= 32768 else 10070401 % 65536),
    ("while-exit-continue", prog("i : INT; s : INT;",
                                 "WHILE TRUE DO i := i + 1; IF i > 6 THEN EXIT; END_IF IF i MOD 2 = 0 THEN CONTINUE; END_IF s := s + i; END_WHILE"), 1,
     lambda m: (m.i, m.s), (7, 9)),
    ("repeat-until", prog("i : INT;", "REPEAT i := i + 2; UNTIL i >= 5 END_REPEAT"), 1, lambda m: m.i, 6),
    ("set-reset", prog("q : BOOL; s : BOOL; r : BOOL; n : INT;",
                       "n := n + 1; s := n = 1; r := n = 3; q S= s; q R= r;"), 2, lambda m: m.q, True),
    ("min-max-limit-sel-mux", prog("a : INT; b : INT; c : INT; d : INT; e : INT;",
                                   "a := MIN(4, 2, 9); b := MAX(4, 2); c := LIMIT(0, 150, 100); d := SEL(TRUE, 1, 2); e := MUX(2, 10, 20, 30);"), 1,
     lambda m: (m.a, m.b, m.c, m.d, m.e), (2, 4, 100, 2, 30)),
    ("shifts-rotates", prog("b : BYTE := 16#81; w : WORD := 16#8001; r1 : BYTE; r2 : WORD; s1 : BYTE; s2 : WORD;",
                            "r1 := ROL(b, 1); r2 := ROR(w, 4); s1 := SHL(b, 1); s2 := SHR(w, 15);"), 1,
     lambda m: (m.r1, m.r2, m.s1, m.s2), (0x03, 0x1800, 0x02, 1)),
    ("conversions", prog("i : INT; r : REAL := 2.5; w : WORD := 65535; d : DINT; b : BOOL;",
                         "i := REAL_TO_INT(r); d := WORD_TO_INT(w); b := INT_TO_BOOL(3); r := INT_TO_REAL(7);"), 1,
     lambda m: (m.i, m.d, m.b, m.r), (2, -1, True, 7.0)),
    ("string-functions", prog("s : STRING(20) := 'Hello'; a : STRING; n : INT; p : INT;",
                              "a := CONCAT(LEFT(s, 2), RIGHT(s, 2)); n := LEN(s); p := FIND(s, 'll'); s := MID(s, 3, 2);"), 1,
     lambda m: (m.a, m.n, m.p, m.s), ("Helo", 5, 3, "ell")),
    ("string-edit", prog("a : STRING := 'ABCDE'; b : STRING; c : STRING;",
                         "b := INSERT(a, 'xy', 2); c := REPLACE(a, 'z', 2, 3); a := DELETE(a, 2, 2);"), 1,
     lambda m: (m.a, m.b, m.c), ("ADE", "ABxyCDE", "ABzE")),
    ("string-escapes", prog("s : STRING;", "s := 'it$'s $$5';"), 1, lambda m: m.s, "it's $5"),
    ("arrays-and-repetition", prog("a : ARRAY[1..6] OF INT := [1, 2(7), 3(0)]; s : INT; i : INT;",
                                   "FOR i := 1 TO 6 DO s := s + a[i]; END_FOR a[6] := s;"), 1,
     lambda m: list(m.a), [1, 7, 7, 0, 0, 15]),
    ("array-2d", prog("a : ARRAY[0..1, 0..2] OF INT; i : INT; j : INT;",
                      "FOR i := 0 TO 1 DO FOR j := 0 TO 2 DO a[i, j] := i * 10 + j; END_FOR END_FOR"), 1,
     lambda m: (m.a[1, 2], m.a[0, 1]), (12, 1)),
    ("array-of-array", prog("a : ARRAY[0..4] OF ARRAY[0..2] OF INT; i : INT; j : INT; s : INT;",
                            "FOR i := 0 TO 4 DO FOR j := 0 TO 2 DO a[i][j] := i * 10 + j; END_FOR END_FOR s := a[3][2] + a[4][1];"), 1,
     lambda m: (m.s, list(m.a[2])), (73, [20, 21, 22])),
    ("alias-initial-value", "TYPE T_Index : DINT := -1; END_TYPE\n"
     + prog("a : T_Index; b : T_Index := 3; c : ARRAY[1..3] OF T_Index := [7]; n : INT;", "n := n + 1;"), 1,
     lambda m: (m.a, m.b, list(m.c)), (-1, 3, [7, -1, -1])),
    ("constant-bounds", "VAR_GLOBAL CONSTANT cMaxCb : INT := 4; END_VAR\n"
     + prog("a : ARRAY[1..cMaxCb * 2] OF INT; n : INT;", "n := UPPER_BOUND_FAKE;").replace("n := UPPER_BOUND_FAKE;", "a[8] := 3; n := a[8];"), 1,
     lambda m: m.n, 3),
    ("struct-and-array-copy", "TYPE ST_P : STRUCT x : INT; y : INT; END_STRUCT END_TYPE\n"
     + prog("a : ST_P := (x := 1, y := 2); b : ST_P; u : ARRAY[1..3] OF INT := [1, 2, 3]; v : ARRAY[1..3] OF INT;",
            "b := a; a.x := 5; v := u; u[1] := 9;"), 1,
     lambda m: (m.a.x, m.b.x, m.b.y, list(m.u), list(m.v)), (5, 1, 2, [9, 2, 3], [1, 2, 3])),
    ("one-element-initialisers",  # blark reads (x := 1) as a parenthesised assignment
     "TYPE ST_P : STRUCT x : INT; y : INT := 7; END_STRUCT END_TYPE\n"
     "FUNCTION_BLOCK FB_K\nVAR_INPUT k : INT; j : INT := 4; END_VAR\nVAR nStart : INT; END_VAR\nEND_FUNCTION_BLOCK\n"
     "METHOD FB_init : BOOL\nVAR_INPUT bInitRetains : BOOL; bInCopyCode : BOOL; nFrom : INT; END_VAR\n"
     "nStart := nFrom;\nEND_METHOD\n"
     + prog("a : ST_P := (x := 1); f : FB_K(nFrom := 3) := (k := 5); g : FB_K(nFrom := 6) := (k := 8, j := 9); "
            "h : ARRAY[1..3] OF ST_P := [(x := 2), (y := 3)]; n : INT;", "n := n + 1;"), 1,
     lambda m: (m.a.x, m.a.y, m.f.nStart, m.f.k, m.f.j, m.g.nStart, m.g.k, m.g.j, [(p.x, p.y) for p in m.h]),
     (1, 7, 3, 5, 4, 6, 8, 9, [(2, 7), (0, 3), (0, 7)])),
    ("array-of-structures-initialiser",  # blark may read (a := 1, b := 2, c := 3) as a := [1, b := 2], c := 3
     "TYPE ST_L : STRUCT low : REAL; high : REAL; step : REAL; END_STRUCT END_TYPE\n"
     "FUNCTION_BLOCK FB_P\nVAR CONSTANT\nLIMITS : ARRAY[1..2] OF ST_L := "
     "[(low := 150.0, high := 250.0, step := 10.0), (low := 100.0, high := 300.0, step := 50.0)];\nEND_VAR\n"
     "VAR x : REAL; END_VAR\nx := LIMITS[2].high + LIMITS[1].step;\nEND_FUNCTION_BLOCK\n"
     + prog("fb : FB_P;", "fb();"), 1,
     lambda m: (m.fb.x, [(p.low, p.high, p.step) for p in m.fb.LIMITS]), (310.0, [(150.0, 250.0, 10.0), (100.0, 300.0, 50.0)])),
    ("local-reference-to-a-struct",
     "TYPE ST_E : STRUCT n : INT; t : INT; END_STRUCT END_TYPE\n"
     "FUNCTION_BLOCK FB_Log\nVAR log : ARRAY[0..2] OF ST_E; nCount : INT; END_VAR\nEND_FUNCTION_BLOCK\n"
     "METHOD Add\nVAR_INPUT n : INT; END_VAR\nVAR e : REFERENCE TO ST_E; END_VAR\n"
     "e REF= log[nCount MOD 3];\ne.n := n;\ne.t := e.t + 1;\nnCount := nCount + 1;\nEND_METHOD\n"
     + prog("fb : FB_Log;", "fb.Add(n := 7); fb.Add(n := 8); fb.Add(n := 9); fb.Add(n := 10);"), 1,
     lambda m: [(e.n, e.t) for e in m.fb.log], [(10, 2), (8, 1), (9, 1)]),
    ("reference-results",  # the result name of a REFERENCE TO method or property is bound, by := or REF=
     "TYPE ST_R : STRUCT n : INT; END_STRUCT END_TYPE\n"
     "FUNCTION_BLOCK FB_R\nVAR s : ST_R; t : ST_R; END_VAR\nEND_FUNCTION_BLOCK\n"
     "METHOD Pick : REFERENCE TO ST_R\nVAR_INPUT b : BOOL; END_VAR\nIF b THEN Pick REF= t; ELSE Pick := s; END_IF\nEND_METHOD\n"
     "PROPERTY First : REFERENCE TO ST_R\nFirst := s;\nEND_PROPERTY\n"
     + prog("fb : FB_R;", "fb();"), 1,
     lambda m: _reference_results(m.fb), (6, 4)),
    ("interface-input-of-its-own-type",
     "INTERFACE I_Link\nEND_INTERFACE\nMETHOD SetNext\nVAR_INPUT next : I_Link; END_VAR\nEND_METHOD\n"
     "METHOD Depth : INT\nEND_METHOD\n"
     "FUNCTION_BLOCK FB_Link IMPLEMENTS I_Link\nVAR nextLink : I_Link; END_VAR\nEND_FUNCTION_BLOCK\n"
     "METHOD SetNext\nVAR_INPUT next : I_Link; END_VAR\nnextLink := next;\nEND_METHOD\n"
     "METHOD Depth : INT\nIF nextLink = 0 THEN Depth := 1; ELSE Depth := nextLink.Depth() + 1; END_IF\nEND_METHOD\n"
     + prog("a : FB_Link; b : FB_Link; c : FB_Link; n : INT; m2 : INT;",
            "a.SetNext(next := b); b.SetNext(next := c); n := a.Depth(); c.SetNext(); m2 := c.Depth();"), 1,
     lambda m: (m.n, m.m2), (3, 1)),
    ("struct-input-by-value",  # the callee works on its own copy
     "TYPE ST_V : STRUCT a : INT; b : INT; END_STRUCT END_TYPE\n"
     "FUNCTION F_Sum : INT\nVAR_INPUT k : INT; v : ST_V; END_VAR\nv.a := v.a * k;\nF_Sum := v.a + v.b;\nEND_FUNCTION\n"
     + prog("s : ST_V := (a := 2, b := 3); n : INT; m2 : INT;", "n := F_Sum(k := 10, v := s); m2 := F_Sum(v := s);"), 1,
     lambda m: (m.n, m.m2, m.s.a, m.s.b), (23, 3, 2, 3)),
    ("memory-functions", prog("a : ARRAY[1..3] OF INT := [1, 2, 3]; b : ARRAY[1..3] OF INT; n : UDINT; c : DINT; d : DINT;",
                              "n := MEMCPY(ADR(b), ADR(a), SIZEOF(a)); c := MEMCMP(ADR(a), ADR(b), 6); "
                              "MEMSET(ADR(b[2]), 0, 2); d := MEMCMP(ADR(a), ADR(b), 6);"), 1,
     lambda m: (m.n, list(m.b), m.c, m.d), (6, [1, 0, 3], 0, 1)),
    ("timer-stdlib", prog("fbT : TON; bQ : BOOL; tEt : TIME;", "fbT(IN := TRUE, PT := T#30ms, Q => bQ, ET => tEt);"), 1,
     lambda m: (m.bQ, m.tEt), (False, 0)),
    ("pointer-deref", prog("n : INT := 5; p : POINTER TO INT; m2 : INT;", "p := ADR(n); p^ := p^ + 1; m2 := p^;"), 1,
     lambda m: (m.n, m.m2), (6, 6)),
    ("pointer-compare", prog("a : ARRAY[0..4] OF INT := [1, 2, 3, 4, 5]; p : POINTER TO INT; pEnd : POINTER TO INT; s : INT; lt : BOOL;",
                             "p := ADR(a[0]); pEnd := ADR(a[4]); lt := p < pEnd AND pEnd >= p AND p > 0; "
                             "WHILE p <= pEnd DO s := s + p^; p := p + SIZEOF(INT); END_WHILE"), 1,
     lambda m: (m.s, m.lt), (15, True)),
    ("pointer-reference-initialised-with-a-sibling",
     "TYPE ST_C : STRUCT n : INT := 5; a : ARRAY[1..3] OF INT := [1, 2, 3]; p : POINTER TO INT := ADR(n); "
     "pa : POINTER TO INT := ADR(a[2]); END_STRUCT END_TYPE\n"
     + prog("c : ST_C; x : INT := 3; px : POINTER TO INT := ADR(x); r : REFERENCE TO INT := x;",
            "r := r + 1; px^ := px^ * 10; c.p^ := c.pa^;"), 2,
     lambda m: (m.x, m.c.n), (410, 2)),
    ("ref-assign-through-an-array-of-pointers",  # REF= p[i]^ and ADR(p[i]^) are the pointer p[i]
     prog("a : INT := 1; b : INT := 2; p : ARRAY[1..2] OF POINTER TO INT; q : POINTER TO INT; r : REFERENCE TO INT; "
          "i : INT; s : INT;",
          "p[1] := ADR(a); p[2] := ADR(b); FOR i := 1 TO 2 DO r REF= p[i]^; r := r * 10; s := s + r; END_FOR "
          "q := ADR(p[2]^); q^ := q^ + 1;"), 1,
     lambda m: (m.a, m.b, m.s), (10, 21, 30)),
    ("reference-ref-assign", prog("n : INT := 5; r : REFERENCE TO INT; ok : BOOL;", "ok := __ISVALIDREF(r); r REF= n; r := 9;"), 1,
     lambda m: (m.n, m.ok), (9, False)),
    ("try-catch-finally", prog("a : INT := 1; b : INT; exc : __SYSTEM.ExceptionCode; n : INT; bDiv : BOOL;",
                               "__TRY a := a / b; n := 1; __CATCH(exc) n := 2; __FINALLY n := n + 10; __ENDTRY "
                               "bDiv := exc = __SYSTEM.ExceptionCode.RTSEXCPT_DIVIDEBYZERO;"), 1,
     lambda m: (m.a, m.n, m.bDiv), (1, 12, True)),
    ("try-without-fault", prog("a : INT := 4; b : INT := 2; exc : __SYSTEM.ExceptionCode; n : INT;",
                               "__TRY a := a / b; __CATCH(exc) n := 2; __ENDTRY"), 1,
     lambda m: (m.a, m.n, m.exc), (2, 0, 0)),
    ("test-and-set", prog("bLock : BOOL; a : BOOL; b : BOOL;", "a := TEST_AND_SET(bLock); b := TEST_AND_SET(bLock);"), 1,
     lambda m: (m.a, m.b, m.bLock), (True, False, True)),
]


@pytest.mark.parametrize("source, cycles, read, expected", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_construct(source: str, cycles: int, read: Callable[[Any], Any], expected: Any) -> None:
    assert read(run(source, cycles)) == expected


OOP = """
TYPE E_Gear : (LOW := 1, HIGH := 2) USINT; END_TYPE
TYPE T_Speed : REAL; END_TYPE
TYPE ST_Base : STRUCT nId : INT := 7; END_STRUCT END_TYPE
TYPE ST_Item EXTENDS ST_Base : STRUCT rWeight : T_Speed := 2.5; END_STRUCT END_TYPE
TYPE U_Split : UNION wWhole : WORD; aBytes : ARRAY[0..1] OF BYTE; END_UNION END_TYPE

INTERFACE I_Vehicle EXTENDS __SYSTEM.IQueryInterface
END_INTERFACE
METHOD Accelerate : REAL
VAR_INPUT rDelta : REAL; END_VAR
END_METHOD
PROPERTY Gear : E_Gear
END_PROPERTY

INTERFACE I_Other EXTENDS __SYSTEM.IQueryInterface
END_INTERFACE

FUNCTION_BLOCK ABSTRACT FB_Vehicle IMPLEMENTS I_Vehicle
VAR
    rSpeed : REAL;
    eGear : E_Gear := E_Gear.LOW;
    nCalls : INT;
END_VAR
nCalls := nCalls + 1;
END_FUNCTION_BLOCK

METHOD ABSTRACT MaxSpeed : REAL
END_METHOD

METHOD Accelerate : REAL
VAR_INPUT rDelta : REAL; END_VAR
rSpeed := Clamp(rSpeed + rDelta);
Accelerate := rSpeed;
END_METHOD

METHOD PROTECTED FINAL Clamp : REAL
VAR_INPUT rValue : REAL; END_VAR
Clamp := MIN(rValue, THIS^.MaxSpeed());
END_METHOD

PROPERTY Gear.Get : E_Gear
Gear := eGear;
END_PROPERTY

PROPERTY PRIVATE Gear.Set : E_Gear
eGear := Gear;
END_PROPERTY

FUNCTION_BLOCK FB_Car EXTENDS FB_Vehicle
VAR_INPUT nAxle : INT; END_VAR
VAR nInit : INT; END_VAR
SUPER^();
SUPER^();
END_FUNCTION_BLOCK

METHOD FB_init : BOOL
VAR_INPUT
    bInitRetains : BOOL;
    bInCopyCode : BOOL;
    nStart : INT := 3;
END_VAR
nInit := nStart;
END_METHOD

METHOD MaxSpeed : REAL
MaxSpeed := 120.0;
END_METHOD

METHOD Accelerate : REAL
VAR_INPUT rDelta : REAL; END_VAR
Accelerate := SUPER^.Accelerate(rDelta * 2);
END_METHOD

FUNCTION F_Square : DINT
VAR_INPUT n : DINT; END_VAR
F_Square := n * n;
END_FUNCTION

PROGRAM MAIN
VAR
    fbCar : FB_Car(nStart := 5);
    fbCar2 : FB_Car := (nAxle := 2);
    itf : I_Vehicle;
    itfOther : I_Other;
    pCar : POINTER TO FB_Car;
    stItem : ST_Item := (rWeight := 4.0);
    uSplit : U_Split;
    rResult : REAL;
    bNull : BOOL;
    bOther : BOOL;
    bFound : BOOL;
    nSq : DINT;
    eGear : E_Gear;
    nGear : USINT;
END_VAR
bNull := itf = 0;
itf := fbCar;
rResult := itf.Accelerate(rDelta := 50.0);
rResult := itf.Accelerate(50.0);
fbCar();
eGear := itf.Gear;
nGear := E_Gear.HIGH;
bOther := __QUERYINTERFACE(itf, itfOther);
bFound := __QUERYPOINTER(itf, pCar);
nSq := F_Square(n := 12) + F_Square(3);
uSplit.wWhole := 16#1234;
END_PROGRAM
"""


@pytest.fixture(scope="module")
def oop() -> Any:
    return st.load(OOP)


def test_methods_properties_inheritance_interfaces(oop: Any) -> None:
    main = oop.MAIN
    main()
    assert main.bNull is True
    assert main.rResult == 120.0  # 2 * 50 = 100, then clamped to MaxSpeed 120
    assert main.fbCar.nCalls == 2  # SUPER^() twice
    assert main.fbCar.nInit == 5 and main.fbCar2.nInit == 3 and main.fbCar2.nAxle == 2
    assert main.eGear == oop.E_Gear.LOW and main.nGear == 2
    assert main.bOther is False and main.bFound is True
    assert main.pCar.deref.nInit == 5
    assert main.nSq == 153
    assert (main.stItem.nId, main.stItem.rWeight) == (7, 4.0)
    assert (main.uSplit.aBytes[0], main.uSplit.aBytes[1]) == (0x34, 0x12)


def test_access_and_abstract_rules_hold(oop: Any) -> None:
    from iecoop import AccessError, DefinitionError

    with pytest.raises(DefinitionError, match="ABSTRACT"):
        oop.FB_Vehicle()
    car = oop.FB_Car()
    with pytest.raises(AccessError, match="PROTECTED"):
        car.Clamp(1.0)
    with pytest.raises(AccessError, match="PRIVATE"):
        car.Gear = oop.E_Gear.HIGH


def test_case_insensitive_names(oop: Any) -> None:
    assert oop.main is oop.MAIN and oop.f_square(4) == 16


def test_program_runs_on_a_runtime() -> None:
    module = st.load(prog("fbT : TON; bStart : BOOL := TRUE; nDone : INT;",
                          "fbT(IN := bStart, PT := T#50ms); IF fbT.Q THEN nDone := nDone + 1; END_IF"))
    runtime = Runtime(store=":memory:")
    runtime.add_task(Task("PlcTask", interval=T("10ms")), module.MAIN)
    runtime.run(cycles=5)
    assert module.MAIN.nDone == 0
    runtime.run(cycles=3)  # at 50, 60, 70 ms the timer is done
    assert module.MAIN.nDone == 3


def test_division_by_zero_faults_the_runtime() -> None:
    module = st.load(prog("a : INT := 1; b : INT;", "a := a / b;"))
    runtime = Runtime(store=":memory:")
    runtime.add_task(Task("PlcTask", interval=T("10ms")), module.MAIN)
    with pytest.raises(PlcException, match="DIVIDEBYZERO"):
        runtime.run(cycles=1)


def test_sections_stat_temp_inst_retain() -> None:
    module = st.load("""
FUNCTION_BLOCK FB_S
VAR_STAT nShared : INT; END_VAR
VAR_TEMP nTemp : INT; END_VAR
VAR RETAIN nKept : INT; END_VAR
VAR CONSTANT cStep : INT := 2; END_VAR
nShared := nShared + 1; nTemp := nTemp + 1; nKept := nKept + nTemp * cStep;
END_FUNCTION_BLOCK
METHOD Dose : INT
VAR_INST nDoses : INT; END_VAR
nDoses := nDoses + 1;
Dose := nDoses;
END_METHOD
""")
    a, b = module.FB_S(), module.FB_S()
    a(); a(); b()
    assert (a.nShared, a.nTemp, a.nKept, b.nKept) == (3, 1, 4, 2)
    assert (a.Dose(), a.Dose(), b.Dose()) == (1, 2, 1)


def test_new_and_delete() -> None:
    module = st.load("""
FUNCTION_BLOCK FB_Dyn
VAR nId : INT := 4; END_VAR
END_FUNCTION_BLOCK
PROGRAM MAIN
VAR p : POINTER TO FB_Dyn; nSeen : INT; bNull : BOOL; END_VAR
p := __NEW(FB_Dyn);
nSeen := p^.nId;
__DELETE(p);
bNull := p = 0;
END_PROGRAM
""")
    module.MAIN()
    assert (module.MAIN.nSeen, module.MAIN.bNull) == (4, True)


NEW_WITH_INPUTS = """
FUNCTION_BLOCK FB_Axis
VAR nId : INT; rScale : REAL := 1.0; END_VAR
END_FUNCTION_BLOCK
METHOD FB_init : BOOL
VAR_INPUT bInitRetains : BOOL; bInCopyCode : BOOL; nAxis : INT; rGear : REAL := 2.0; END_VAR
nId := nAxis;
rScale := rGear;
END_METHOD
PROGRAM MAIN
VAR p : POINTER TO FB_Axis; q : POINTER TO FB_Axis; END_VAR
p := __NEW(FB_Axis, NAXIS := 3);
q := __NEW(FB_Axis, rGear := 0.5, nAxis := 7);
END_PROGRAM
"""


def test_new_passes_fb_init_inputs_by_name() -> None:
    module = st.load(NEW_WITH_INPUTS)
    module.MAIN()
    p, q = module.MAIN.p.deref, module.MAIN.q.deref
    assert (p.nId, p.rScale, q.nId, q.rScale) == (3, 2.0, 7, 0.5)


@pytest.mark.parametrize("new, construct", [
    ("__NEW(FB_Axis, nAxle := 3)", "<st>:12: __NEW of FB_Axis: FB_init has no input 'nAxle'"),
    ("__NEW(FB_Axis, 4)", "<st>:12: __NEW of FB_Axis with a length"),
])
def test_new_refuses_what_fb_init_does_not_take(new: str, construct: str) -> None:
    with pytest.raises(st.StUnsupportedError, match=construct):
        st.load(NEW_WITH_INPUTS.replace("__NEW(FB_Axis, NAXIS := 3)", new))


def test_globals_and_external_functions() -> None:
    module = st.load("""
VAR_GLOBAL
    gnExtCount : INT := 10;
END_VAR
FUNCTION F_Scale : REAL
VAR_INPUT x : REAL; END_VAR
END_FUNCTION
PROGRAM MAIN
VAR r : REAL; END_VAR
gnExtCount := gnExtCount + 1;
GVL.gnExtCount := GVL.gnExtCount + 1;
r := F_Scale(x := 2.0);
END_PROGRAM
""", externals={"F_Scale": lambda x: x * 10})
    module.MAIN()
    assert module.GVL.gnExtCount == 12 and module.MAIN.r == 20.0


def test_external_function_must_be_bound() -> None:
    with pytest.raises(st.StUnsupportedError, match="F_Missing"):
        st.load("FUNCTION F_Missing : INT\nVAR_INPUT x : INT; END_VAR\nEND_FUNCTION\n")


_INTERNAL_METHOD = """
FUNCTION_BLOCK FB_Valve
VAR nOpened : INT; END_VAR
END_FUNCTION_BLOCK
METHOD INTERNAL Service : INT
nOpened := nOpened + 1;
Service := nOpened;
END_METHOD
"""


def test_internal_members_are_reached_only_from_the_loaded_package() -> None:
    from iecoop import AccessError

    own = st.load(_INTERNAL_METHOD)
    with pytest.raises(AccessError, match=r"INTERNAL members are callable only inside the package 'iecoop_st_\d+'"):
        own.FB_Valve().Service()
    shared = st.load(_INTERNAL_METHOD, package="tests")
    valve = shared.FB_Valve()
    assert (valve.Service(), valve.Service()) == (1, 2)
    assert shared.__name__.startswith("tests.")
    outside = st.load(_INTERNAL_METHOD, package="plant")
    with pytest.raises(AccessError, match="inside the package 'plant'"):
        outside.FB_Valve().Service()


def test_package_must_be_a_dotted_name() -> None:
    with pytest.raises(ValueError, match="package must be a dotted Python name"):
        st.load(_INTERNAL_METHOD, package="my plant")


def test_syntax_error_names_file_and_line(tmp_path: Any) -> None:
    path = tmp_path / "broken.st"
    path.write_text("PROGRAM MAIN\nVAR x : INT; END_VAR\nx := := 1;\nEND_PROGRAM\n")
    with pytest.raises(st.StSyntaxError, match=r"broken\.st:3: .*syntax error"):
        st.load(path)


def test_unknown_type_is_named() -> None:
    with pytest.raises(st.StUnsupportedError, match=r"<st>:2: unknown type 'FB_Nowhere'"):
        st.load("PROGRAM MAIN\nVAR x : FB_Nowhere; END_VAR\nEND_PROGRAM\n")


def test_super_variable_is_the_same_variable() -> None:
    module = st.load("""
FUNCTION_BLOCK FB_A
VAR nX : INT; END_VAR
END_FUNCTION_BLOCK
FUNCTION_BLOCK FB_B EXTENDS FB_A
SUPER^.nX := SUPER^.nX + 2;
END_FUNCTION_BLOCK
""")
    block = module.FB_B()
    block(); block()
    assert block.nX == 4


SUPER_PROPERTY = """
FUNCTION_BLOCK FB_A
VAR _n : INT; END_VAR
END_FUNCTION_BLOCK
PROPERTY N.Get : INT
N := _n;
END_PROPERTY
PROPERTY N.Set : INT
_n := N;
END_PROPERTY
FUNCTION_BLOCK FB_B EXTENDS FB_A
SUPER^.N := 1;
END_FUNCTION_BLOCK
"""


def test_super_property_write_runs_the_base_setter() -> None:
    module = st.load(SUPER_PROPERTY.replace("SUPER^.N := 1;", "SUPER^.N := SUPER^.N + 5;").replace(
        "FUNCTION_BLOCK FB_B EXTENDS FB_A\n", "FUNCTION_BLOCK FB_B EXTENDS FB_A\nVAR nSets : INT; END_VAR\n")
        + "PROPERTY N.Set : INT\nnSets := nSets + 1;\nSUPER^.N := N * 2;\nEND_PROPERTY\n"
        + "PROPERTY N.Get : INT\nN := SUPER^.N;\nEND_PROPERTY\n")
    block = module.FB_B()
    block(); block()
    assert (block.st_n_, block.nSets) == (10, 0)  # the body writes the base's N, not FB_B's
    block.N = 4
    assert (block.st_n_, block.nSets, block.N) == (8, 1, 8)
    assert 'super_set(super(), "N", ' in st.to_python(SUPER_PROPERTY)


MARKED_ACCESSORS = """
FUNCTION_BLOCK FB_Tank
VAR _rSetpoint : REAL; END_VAR
END_FUNCTION_BLOCK
// Set
PROPERTY PUBLIC Setpoint : REAL
VAR
END_VAR
_rSetpoint := LIMIT(0.0, Setpoint, 100.0);
END_PROPERTY
// Get
PROPERTY PUBLIC Setpoint : REAL
VAR
END_VAR
Setpoint := _rSetpoint * 2.0;
END_PROPERTY
// the level, read-only
PROPERTY PUBLIC Level : REAL
Level := _rSetpoint;
END_PROPERTY
"""


def test_accessors_marked_get_and_set_as_dump_writes_them() -> None:
    tank = st.load(MARKED_ACCESSORS).FB_Tank()
    tank.Setpoint = 150.0
    assert (tank.st_rSetpoint_, tank.Setpoint, tank.Level) == (100.0, 200.0, 100.0)
    with pytest.raises(AttributeError, match="Level has no Set accessor"):
        tank.Level = 1.0
    python = st.to_python(MARKED_ACCESSORS)
    assert "# the level, read-only" in python and "# Get" not in python and "# Set" not in python  # marks, not comments
    unmarked = MARKED_ACCESSORS.replace("// Set\n", "").replace("// Get\n", "")
    with pytest.raises(st.StUnsupportedError, match=r"<st>:10: PROPERTY Setpoint has two Get accessors .*// Set"):
        st.load(unmarked)


def test_time_reads_the_task_clock() -> None:
    main = st.load(prog("t : TIME; n : INT;", "t := TIME(); n := n + 1;")).MAIN
    runtime = Runtime(store=":memory:")
    runtime.add_task(Task("PlcTask", interval=T("10ms"), priority=20), main)
    runtime.run(cycles=3)
    assert (main.t, main.n) == (20, 3)


def test_a_var_external_declared_before_its_global_binds_to_it() -> None:
    module = st.load("PROGRAM MAIN\nVAR_EXTERNAL gOrderCount : INT; END_VAR\ngOrderCount := gOrderCount + 1;\nEND_PROGRAM\n"
                     "VAR_GLOBAL gOrderCount : INT := 40; END_VAR\n")
    module.MAIN()
    module.MAIN()
    assert module.GVL.gOrderCount == 42


LOCAL_REFERENCE = (
    "TYPE ST_E : STRUCT n : INT; END_STRUCT END_TYPE\nTYPE ST_F : STRUCT n : INT; END_STRUCT END_TYPE\n"
    "FUNCTION_BLOCK FB_L\nVAR a : ST_E; f : ST_F; END_VAR\nEND_FUNCTION_BLOCK\n"
    "METHOD M\nVAR e : REFERENCE TO ST_E; END_VAR\n{statement}\nEND_METHOD\n"
)


@pytest.mark.parametrize("statement, construct", [
    ("e := a;", "<st>:8: assignment to the whole REFERENCE TO local e"),
    ("e REF= f;", "<st>:8: REF= of e needs a ST_E variable, got self.f"),
])
def test_a_local_reference_is_bound_by_ref_assign_only(statement: str, construct: str) -> None:
    with pytest.raises(st.StUnsupportedError, match=construct):
        st.load(LOCAL_REFERENCE.format(statement=statement))


@pytest.mark.parametrize("source, construct", [
    (prog("x : INT;", "IF x = 0 THEN lbl: x := 1; END_IF"), "label lbl inside IF, CASE or a loop"),
    (prog("x : INT;", "y := 1;"), "unknown variable 'y'"),
    (prog("t : TIME;", "t := TIME(t);"), r"<st>:5: TIME\(\) takes no input"),
    ("FUNCTION_BLOCK FB_O\nEND_FUNCTION_BLOCK\nMETHOD M\nVAR_OUTPUT o : INT; END_VAR\nEND_METHOD\n"
     "PROPERTY N : INT\nVAR x : INT; END_VAR\nM(o => x);\nN := x;\nEND_PROPERTY\n", "a local variable of a PROPERTY accessor has no address"),
    ("PROGRAM MAIN\nVAR AT %IX0.0 : BOOL; END_VAR\nEND_PROGRAM\n", "located variable without a name"),
])
def test_unsupported_constructs_raise(source: str, construct: str) -> None:
    with pytest.raises(st.StUnsupportedError, match=construct):
        st.load(source)


def test_traceback_shows_st_line() -> None:
    import traceback

    module = st.load(prog("a : INT; b : INT;", "a := a / b;"))
    with pytest.raises(PlcException) as info:
        module.MAIN()
    shown = "".join(traceback.format_tb(info.tb))
    assert "a := a / b;" in shown and '<st text #' in shown
    assert "self.a = DIV(self.a, self.b)" in module.__python__


def test_to_python_keeps_names_and_comments() -> None:
    text = st.to_python(prog("nCount : INT; // parts seen", "(* count up *)\nnCount := nCount + 1;"))
    assert "class MAIN(Program):" in text
    assert "# count up" in text and "# parts seen" in text
    assert "self.nCount = self.nCount + 1" in text


def test_importing_iecoop_does_not_import_blark() -> None:
    import subprocess
    import sys

    code = "import sys, iecoop, iecoop.st; print('blark' in sys.modules, 'lark' in sys.modules)"
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert result.stdout.split() == ["False", "False"]


def test_without_blark_load_and_to_python_name_the_extra() -> None:
    import subprocess
    import sys

    # A None entry in sys.modules makes "import blark" fail, as when the package is not installed.
    code = (
        "import sys; sys.modules['blark'] = None\n"
        "from iecoop import st\n"
        "for call in (st.to_python, st.load):\n"
        "    try:\n"
        "        call('TYPE E_Mode : (IDLE, RUN) INT; END_TYPE')\n"
        "    except ImportError as exc:\n"
        "        print(exc)\n"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    lines = result.stdout.splitlines()
    assert len(lines) == 2
    assert all('needs the blark parser' in line and 'pip install "iecoop[st]"' in line for line in lines)


ARITHMETIC = st.load("""
FUNCTION F_DivMod : DINT
VAR_INPUT a : DINT; b : DINT; END_VAR
F_DivMod := a / b * 1000 + a MOD b;
END_FUNCTION
FUNCTION F_AddInt : INT
VAR_INPUT a : INT; b : INT; END_VAR
VAR s : INT; END_VAR
s := a + b;           // a method or function local wraps like the INT it is
F_AddInt := s;
END_FUNCTION
""")


@given(strategies.integers(-30000, 30000), strategies.integers(1, 999))
def test_integer_division_truncates_and_mod_follows_the_dividend(a: int, b: int) -> None:
    quotient = abs(a) // b * (1 if a >= 0 else -1)  # toward zero
    remainder = a - b * quotient                      # sign of the dividend
    assert ARITHMETIC.F_DivMod(a=a, b=b) == quotient * 1000 + remainder
    assert ARITHMETIC.F_DivMod(a=a, b=-b) == -quotient * 1000 + remainder


@given(strategies.integers(-32768, 32767), strategies.integers(-32768, 32767))
def test_function_locals_wrap_like_their_type(a: int, b: int) -> None:
    assert ARITHMETIC.F_AddInt(a=a, b=b) == (a + b + 32768) % 65536 - 32768


def test_external_pragma_and_call_after_init() -> None:
    module = st.load("""
{external}
FUNCTION F_Ext : INT
VAR_INPUT x : INT; END_VAR
F_Ext := x;             // the ST body stands in for a PLC library; Python replaces it
END_FUNCTION
FUNCTION_BLOCK FB_X
VAR n : INT; END_VAR
END_FUNCTION_BLOCK
{attribute 'call_after_init'}
METHOD Init
n := 7;
END_METHOD
PROGRAM MAIN
VAR r : INT; fb : FB_X; END_VAR
r := F_Ext(3);
END_PROGRAM
""", externals={"F_Ext": lambda x: x * 100})
    module.MAIN()
    assert (module.MAIN.r, module.MAIN.fb.n) == (300, 7)


def test_real_locals_are_32_bit() -> None:
    import struct

    module = st.load("FUNCTION F_Tenth : REAL\nVAR r : REAL; END_VAR\nr := 0.1;\nF_Tenth := r * 3;\nEND_FUNCTION\n")
    tenth = struct.unpack("<f", struct.pack("<f", 0.1))[0]
    assert module.F_Tenth() == struct.unpack("<f", struct.pack("<f", tenth * 3))[0] != 0.1 * 3


STANDARD = st.load("""
FUNCTION F_Strings : STRING(80)
VAR_INPUT s : STRING(40); t : STRING(40); n : INT; p : INT; END_VAR
F_Strings := CONCAT(CONCAT(MID(s, n, p), '|'), CONCAT(LEFT(s, n), '|'));
F_Strings := CONCAT(F_Strings, CONCAT(CONCAT(RIGHT(s, n), '|'), CONCAT(DELETE(s, n, p), '|')));
F_Strings := CONCAT(F_Strings, CONCAT(CONCAT(INSERT(s, t, p), '|'), REPLACE(s, t, n, p)));
END_FUNCTION
FUNCTION F_Find : INT
VAR_INPUT s : STRING(40); t : STRING(40); END_VAR
F_Find := FIND(s, t) * 100 + LEN(t);
END_FUNCTION
FUNCTION F_Shifts : LWORD
VAR_INPUT i : INT; n : INT; END_VAR
VAR w : WORD; END_VAR
w := i;
F_Shifts := SHL(i, n) * 16#1000000000000 + SHR(i, n) * 16#100000000 + ROL(w, n) * 16#10000 + ROR(w, n);
END_FUNCTION
FUNCTION F_Bits : WORD
VAR_INPUT w : WORD; n : INT; b : BOOL; END_VAR
CASE n OF
0: w.0 := b; 5: w.5 := b; 15: w.15 := b;
END_CASE
F_Bits := w;
IF w.15 THEN F_Bits := F_Bits OR 16#1; END_IF
END_FUNCTION
""")

_TEXT = strategies.text("ab", max_size=6)


@given(_TEXT, _TEXT, strategies.integers(-2, 8), strategies.integers(-2, 8))
def test_string_functions_match_the_python_forms(s: str, t: str, n: int, p: int) -> None:
    from iecoop.functions import DELETE, FIND, INSERT, LEFT, LEN, MID, REPLACE, RIGHT

    expected = "|".join([MID(s, n, p), LEFT(s, n), RIGHT(s, n), DELETE(s, n, p), INSERT(s, t, p), REPLACE(s, t, n, p)])
    assert STANDARD.F_Strings(s=s, t=t, n=n, p=p) == expected
    assert STANDARD.F_Find(s=s, t=t) == FIND(s, t) * 100 + LEN(t)


def test_string_function_edges_follow_iec() -> None:
    # FIND of an empty string is 0; MID from a position below 1 starts at the first character
    assert STANDARD.F_Find(s="abc", t="") == 0
    assert STANDARD.F_Strings(s="abc", t="", n=2, p=0).split("|")[0] == "ab"


@given(strategies.integers(-32768, 32767), strategies.integers(0, 20))
def test_shifts_match_the_python_forms(i: int, n: int) -> None:
    from iecoop import INT, WORD
    from iecoop.functions import ROL, ROR, SHL, SHR

    w = i & 0xFFFF
    expected = (SHL(i, n, INT) << 48) + (SHR(i, n, INT) << 32) + (ROL(w, n, WORD) << 16) + ROR(w, n, WORD)
    assert STANDARD.F_Shifts(i=i, n=n) == expected


def test_shr_of_a_negative_int_shifts_in_zeros() -> None:
    assert STANDARD.F_Shifts(i=-1, n=4) >> 32 & 0xFFFF == 0x0FFF


@given(strategies.integers(0, 0xFFFF), strategies.sampled_from([0, 5, 15]), strategies.booleans())
def test_bit_access_matches_get_bit_and_set_bit(w: int, n: int, b: bool) -> None:
    from iecoop.functions import get_bit, set_bit

    written = set_bit(w, n, b)
    assert STANDARD.F_Bits(w=w, n=n, b=b) == (written | 1 if get_bit(written, 15) else written)


def test_generated_python_calls_the_standard_functions() -> None:
    code = st.to_python(prog("w : WORD; b : BOOL; s : STRING; n : INT;",
                             "w.3 := TRUE; b := w.3; w := ROL(w, 2); n := FIND(s, 'x'); s := MID(s, 2, 1);"))
    for form in ("set_bit(self.w, 3, True)", "get_bit(self.w, 3)", "ROL(self.w, 2, WORD)",
                 'FIND(self.s, "x")', "MID(self.s, 2, 1)", "from iecoop.functions import"):
        assert form in code, form


TWO_PROGRAMS = """
PROGRAM P_Count
VAR_INPUT nStep : INT := 1; END_VAR
VAR counter : INT; END_VAR
counter := counter + nStep;
END_PROGRAM
PROGRAM MAIN
VAR seen : INT; END_VAR
seen := P_Count.counter * 10;
P_Count.nStep := 5;
END_PROGRAM
"""


def test_a_program_reads_another_programs_variables_through_its_instance() -> None:
    module = st.load(TWO_PROGRAMS)
    module.P_Count(); module.MAIN(); module.P_Count(); module.MAIN()
    assert (module.P_Count.counter, module.MAIN.seen) == (6, 60)
    code = st.to_python(TWO_PROGRAMS)
    assert "self.seen = P_Count.counter * 10" in code and "@_program_instance\nclass P_Count(Program):" in code


@checked_only
def test_writing_another_programs_local_variable_is_refused_at_the_write() -> None:
    from iecoop import AccessError

    module = st.load(TWO_PROGRAMS.replace("P_Count.nStep := 5;", "P_Count.counter := 0;"))
    with pytest.raises(AccessError, match=r"VAR P_Count\.counter cannot be written from MAIN\.body"):
        module.MAIN()


@pytest.mark.slow  # seconds each: once, in the slow gate
def test_loading_the_same_design_again_and_again_never_crashes_the_interpreter() -> None:
    # Block classes are built, run and collected 30 times in a child process: a class record replaced
    # after ctypes set the class up once left a dangling reference that crashed the garbage collector.
    script = (
        "import gc\n"
        "from tests.iecoop.st.test_load import OOP\n"
        "from iecoop import st\n"
        "for _ in range(30):\n"
        "    module = st.load(OOP)\n"
        "    module.MAIN()\n"
        "    del module\n"
        "    gc.collect()\n"
        "print('ok')\n"
    )
    root = Path(__file__).resolve().parents[3]
    done = subprocess.run([sys.executable, "-c", script], cwd=root, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.strip() == "ok"
