"""st.load: qualified enumeration values, enumerations as text, globals inside a FUNCTION, names used before
their declaration, STRUCT ARRAY initial values, __SYSTEM.IQueryInterface as a type, REF= 0, one small ST program each,
expected values worked out by hand."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import pytest

from iecoop import ExceptionCode, PlcException, T, st
from iecoop.runtime import Runtime, Task
from tests.iecoop.st.test_load import prog, run

MODES = "TYPE E_Mode : (IDLE, AUTO := 5, MANUAL) INT; END_TYPE\n"

# (id, ST source, cycles, what to read from MAIN, expected)
CASES: list[tuple[str, str, int, Callable[[Any], Any], Any]] = [
    ("qualified-enum-case-labels",  # cycle 1: AUTO -> 2, then MANUAL -> 3, then IDLE -> 1 (n = 0 + 2, 2 * 10 + 3, 23 * 10 + 1)
     MODES + "VAR_GLOBAL CONSTANT cIdle : E_Mode := E_Mode.IDLE; END_VAR\n"
     + prog("eMode : E_Mode := E_Mode.AUTO; n : INT; a : ARRAY[0..1] OF E_Mode := [E_Mode.MANUAL, E_Mode.IDLE]; i : INT;",
            "CASE eMode OF GVL.cIdle: n := n * 10 + 1; E_Mode.AUTO: n := n * 10 + 2; eMode := a[0];\n"
            "E_Mode.MANUAL, E_Mode.IDLE: n := n * 10 + 3; eMode := a[1]; END_CASE"), 3,
     lambda m: (m.n, m.eMode), (231, 0)),
    ("qualified-enum-in-expressions-and-structs",
     MODES + "TYPE ST_Cfg : STRUCT eMode : E_Mode := E_Mode.MANUAL; n : INT; END_STRUCT END_TYPE\n"
     + prog("c : ST_Cfg; d : ST_Cfg := (eMode := E_Mode.AUTO, n := 1); b : BOOL; k : INT;",
            "b := c.eMode = E_Mode.MANUAL AND d.eMode <> E_Mode.IDLE; k := E_Mode.MANUAL - d.eMode;"), 1,
     lambda m: (m.c.eMode, m.d.eMode, m.b, m.k), (6, 5, True, 1)),
    ("globals-in-a-function",  # F_Inc: n 0 -> 1; F_Add: GVL.n 1 -> 11, then VAR_EXTERNAL written through a call
     "VAR_GLOBAL n : INT; END_VAR\n"
     "FUNCTION F_Inc : INT\nVAR_EXTERNAL n : INT; END_VAR\nn := n + 1; F_Inc := n;\nEND_FUNCTION\n"
     "FUNCTION F_Add : INT\nVAR_INPUT d : INT; END_VAR\nGVL.n := GVL.n + d; F_Add := GVL.n;\nEND_FUNCTION\n"
     "FUNCTION F_Out\nVAR_OUTPUT o : INT; END_VAR\no := 100;\nEND_FUNCTION\n"
     "FUNCTION F_Twice\nVAR_EXTERNAL n : INT; END_VAR\nF_Out(o => n);\nEND_FUNCTION\n"
     + prog("a : INT; b : INT; c : INT;", "a := F_Inc(); b := F_Add(10); F_Twice(); c := GVL.n;"), 2,
     lambda m: (m.a, m.b, m.c), (101, 111, 100)),
    ("enum-to-string",  # {attribute 'to_string'}: the component's name; without it: the number's text
     "{attribute 'qualified_only'}\n{attribute 'to_string'}\nTYPE E_Named : (IDLE, AUTO := 5, MANUAL) INT; END_TYPE\n"
     "TYPE E_Plain : (A, B := 7) INT; END_TYPE\n"
     + prog("e : E_Named := E_Named.AUTO; p : E_Plain := E_Plain.B; s1 : STRING; s2 : STRING; s3 : STRING; s4 : WSTRING; s5 : STRING;",
            "s1 := TO_STRING(e); s2 := E_Named_TO_STRING(E_Named.MANUAL); s3 := TO_STRING(p); s4 := E_Plain_TO_WSTRING(E_Plain.A);\n"
            "s5 := CONCAT(TO_STRING(E_Named.IDLE), TO_STRING(e));"), 1,
     lambda m: (m.s1, m.s2, m.s3, m.s4, m.s5), ("AUTO", "MANUAL", "7", "0", "IDLEAUTO")),
    ("names-used-before-their-declaration",  # MAIN, then the FB, its base, the interface and the types it uses
     "PROGRAM MAIN\nVAR fb : FB_Pump; i : I_Pump; n : INT; s : ST_Pair; END_VAR\n"
     "i := fb; n := i.Speed(s) + fb.nBase;\nEND_PROGRAM\n"
     "FUNCTION_BLOCK FB_Pump EXTENDS FB_Base IMPLEMENTS I_Pump\nVAR p : ST_Pair := (a := 3, b := 4); END_VAR\nEND_FUNCTION_BLOCK\n"
     "METHOD Speed : INT\nVAR_INPUT q : ST_Pair; END_VAR\nSpeed := p.a * 10 + p.b + q.a;\nEND_METHOD\n"
     "INTERFACE I_Pump\nEND_INTERFACE\nMETHOD Speed : INT\nVAR_INPUT q : ST_Pair; END_VAR\nEND_METHOD\n"
     "FUNCTION_BLOCK FB_Base\nVAR_OUTPUT nBase : INT := 100; END_VAR\nEND_FUNCTION_BLOCK\n"
     "TYPE ST_Pair : STRUCT a : INT; b : E_Unit := E_Unit.MM; END_STRUCT END_TYPE\n"
     "TYPE E_Unit : (MM := 1, CM := 10) INT; END_TYPE\n", 1,
     lambda m: (m.n, m.s.b), (134, 1)),
    ("struct-array-initial-values",  # a[1].low + a[2].high * 10 + cR[1].low * 100 + cR[0].high * 1000
     "TYPE ST_Range : STRUCT low : INT; high : INT := 9; END_STRUCT END_TYPE\n"
     "VAR_GLOBAL CONSTANT cR : ARRAY[0..1] OF ST_Range := [(low := 1, high := 2), (low := 3, high := 4)]; END_VAR\n"
     + prog("a : ARRAY[1..3] OF ST_Range := [(low := 1, high := 2), (low := 3, high := 4)]; s : INT; t : INT;",
            "s := a[1].low + a[2].high * 10 + cR[1].low * 100 + cR[0].high * 1000; t := a[3].low + a[3].high;"), 1,
     lambda m: (m.s, m.t), (2341, 9)),
    ("struct-array-initial-values-of-locals-and-members",  # F: c[1].high = 4; M: c[0].high = 2; t.r[1].low = 7, t.r[0].high = 6
     "TYPE ST_R : STRUCT low : INT; high : INT; END_STRUCT END_TYPE\n"
     "TYPE ST_T : STRUCT r : ARRAY[0..1] OF ST_R := [(low := 5, high := 6), (low := 7)]; END_STRUCT END_TYPE\n"
     "FUNCTION F : INT\nVAR CONSTANT c : ARRAY[0..1] OF ST_R := [(low := 1, high := 2), (low := 3, high := 4)]; END_VAR\n"
     "F := c[1].high;\nEND_FUNCTION\n"
     "FUNCTION_BLOCK FB\nEND_FUNCTION_BLOCK\n"
     "METHOD M : INT\nVAR c : ARRAY[0..1] OF ST_R := [(low := 1, high := 2), (low := 3, high := 4)]; END_VAR\n"
     "M := c[0].high; c[0].high := 0;\nEND_METHOD\n"
     + prog("n : INT; t : ST_T; fb : FB; m : INT;", "n := F(); m := fb.M() * 100 + t.r[1].low * 10 + t.r[0].high;"), 2,
     lambda m: (m.n, m.m), (4, 276)),
    ("elementary-reference-local",  # n 5 -> +2 = 7 -> *2 through ADR(r) = 14 -> +1 through q = 15; s 'ab' -> 'abc'
     "FUNCTION_BLOCK FB\nVAR n : INT := 5; s : STRING := 'ab'; END_VAR\nVAR_OUTPUT b : BOOL; c : BOOL; t : STRING; END_VAR\n"
     "END_FUNCTION_BLOCK\n"
     "METHOD Bump : INT\nVAR_INPUT x : INT; END_VAR\n"
     "VAR r : REFERENCE TO INT; q : REFERENCE TO INT; p : POINTER TO INT; rs : REFERENCE TO STRING; END_VAR\n"
     "b := __ISVALIDREF(r);\nr REF= n; r := r + x; p := ADR(r); p^ := p^ * 2;\nq REF= r; q := q + 1;\n"
     "rs REF= s; rs := CONCAT(rs, 'c'); t := rs;\nc := __ISVALIDREF(q);\nBump := r;\nEND_METHOD\n"
     + prog("fb : FB; k : INT;", "k := fb.Bump(2);"), 1,
     lambda m: (m.k, m.fb.b, m.fb.c, m.fb.t), (15, False, True, "abc")),
    ("another-program-by-name",  # MAIN calls P_Count, then reads it: 1, 2; FB_Seen reads it from a block: 20
     "PROGRAM P_Count\nVAR counter : INT; END_VAR\ncounter := counter + 1;\nEND_PROGRAM\n"
     "FUNCTION_BLOCK FB_Seen\nVAR_OUTPUT n : INT; END_VAR\nn := P_Count.counter * 10;\nEND_FUNCTION_BLOCK\n"
     + prog("n : INT; fb : FB_Seen;", "P_Count(); n := P_Count.counter; fb();"), 2,
     lambda m: (m.n, m.fb.n), (2, 20)),
    ("varinfo-in-a-method",  # ST_AB: a INT at 0, b LREAL aligned to 8: offset 8, 64 bits
     "TYPE ST_AB : STRUCT a : INT; b : LREAL; END_STRUCT END_TYPE\n"
     "FUNCTION_BLOCK FB\nVAR s : ST_AB; END_VAR\nVAR_OUTPUT nOff : UDINT; nBits : UDINT; sType : STRING; END_VAR\nEND_FUNCTION_BLOCK\n"
     "METHOD Inspect : BOOL\nVAR info : __SYSTEM.VAR_INFO; END_VAR\n"
     "info := __VARINFO(s.b); nOff := info.ByteOffset; nBits := info.BitSize; sType := info.TypeName;\n"
     "Inspect := info.NumElements = 1;\nEND_METHOD\n"
     + prog("fb : FB; b : BOOL;", "b := fb.Inspect();"), 1,
     lambda m: (m.b, m.fb.nOff, m.fb.nBits, m.fb.sType), (True, 8, 64, "LREAL")),
    ("varinfo-in-a-var-temp",  # as above, from a PROGRAM's VAR_TEMP
     "TYPE ST_AB : STRUCT a : INT; b : LREAL; END_STRUCT END_TYPE\n"
     "PROGRAM MAIN\nVAR s : ST_AB; nOff : UDINT; sType : STRING; END_VAR\nVAR_TEMP info : __SYSTEM.VAR_INFO; END_VAR\n"
     "info := __VARINFO(s.b); nOff := info.ByteOffset; sType := info.TypeName;\nEND_PROGRAM\n", 1,
     lambda m: (m.nOff, m.sType), (8, "LREAL")),
    ("iqueryinterface-as-a-type",  # FB_Rack holds FB_Lamp and FB_Pump as __SYSTEM.IQueryInterface; per cycle only the pump
     # answers I_Start: through Pick's result (Start's count, 2 in cycle 2), through POINTER TO (+100), a STRUCT member (+1000)
     "INTERFACE I_Start EXTENDS __SYSTEM.IQueryInterface\nEND_INTERFACE\nMETHOD Start : INT\nEND_METHOD\n"
     "INTERFACE I_Other EXTENDS __SYSTEM.IQueryInterface\nEND_INTERFACE\n"
     "FUNCTION_BLOCK FB_Pump IMPLEMENTS I_Start\nVAR_OUTPUT nStarts : INT; END_VAR\nEND_FUNCTION_BLOCK\n"
     "METHOD Start : INT\nnStarts := nStarts + 1; Start := nStarts;\nEND_METHOD\n"
     "FUNCTION_BLOCK FB_Lamp IMPLEMENTS I_Other\nEND_FUNCTION_BLOCK\n"
     "TYPE ST_Slot : STRUCT itf : __SYSTEM.IQueryInterface; END_STRUCT END_TYPE\n"
     "FUNCTION_BLOCK FB_Rack\nVAR_INPUT itfFirst : __SYSTEM.IQueryInterface; END_VAR\n"
     "VAR aItems : ARRAY[0..1] OF __SYSTEM.IQueryInterface; pItem : POINTER TO __SYSTEM.IQueryInterface; stSlot : ST_Slot; END_VAR\n"
     "VAR_OUTPUT nStarted : INT; bFirstSet : BOOL; END_VAR\nEND_FUNCTION_BLOCK\n"
     "METHOD Put\nVAR_INPUT n : INT; itf : __SYSTEM.IQueryInterface; END_VAR\naItems[n] := itf;\nEND_METHOD\n"
     "METHOD Pick : __SYSTEM.IQueryInterface\nVAR_INPUT n : INT; END_VAR\nPick := aItems[n];\nEND_METHOD\n"
     "PROPERTY First : __SYSTEM.IQueryInterface\nFirst := itfFirst;\nEND_PROPERTY\n"
     "METHOD StartAll : INT\nVAR i : INT; itfStart : I_Start; itf : __SYSTEM.IQueryInterface; END_VAR\n"
     "bFirstSet := First <> 0; stSlot.itf := First; pItem := ADR(aItems[1]);\n"
     "FOR i := 0 TO 1 DO itf := Pick(i); __QUERYINTERFACE(itf, itfStart);\n"
     "IF itfStart <> 0 THEN StartAll := StartAll + itfStart.Start(); END_IF END_FOR\n"
     "__QUERYINTERFACE(pItem^, itfStart); IF itfStart <> 0 THEN nStarted := nStarted + 100; END_IF\n"
     "__QUERYINTERFACE(stSlot.itf, itfStart); IF itfStart <> 0 THEN nStarted := nStarted + 1000; END_IF\nEND_METHOD\n"
     + prog("fbPump : FB_Pump; fbLamp : FB_Lamp; fbRack : FB_Rack; n : INT;",
            "fbRack.Put(0, fbLamp); fbRack.Put(n := 1, itf := fbPump); fbRack.itfFirst := fbPump; n := fbRack.StartAll();"), 2,
     lambda m: (m.n, m.fbPump.nStarts, m.fbRack.nStarted, m.fbRack.bFirstSet), (2, 2, 2200, True)),
    ("ref-zero-unbinds",  # a block's REFERENCE TO and a METHOD's elementary one: bound to n (5), then REF= 0 (16#0 too)
     "FUNCTION_BLOCK FB\nVAR n : INT := 5; r : REFERENCE TO INT; END_VAR\n"
     "VAR_OUTPUT bBound : BOOL; nRead : INT; bAfter : BOOL := TRUE; bLocal : BOOL; bLocalAfter : BOOL := TRUE; END_VAR\n"
     "r REF= n; bBound := __ISVALIDREF(r); nRead := r; r REF= 0; bAfter := __ISVALIDREF(r);\nEND_FUNCTION_BLOCK\n"
     "METHOD M : INT\nVAR q : REFERENCE TO INT; END_VAR\n"
     "q REF= n; bLocal := __ISVALIDREF(q); M := q; q REF= 16#0; bLocalAfter := __ISVALIDREF(q);\nEND_METHOD\n"
     + prog("fb : FB; m : INT;", "fb(); m := fb.M();"), 2,
     lambda m: (m.fb.bBound, m.fb.nRead, m.fb.bAfter, m.m, m.fb.bLocal, m.fb.bLocalAfter), (True, 5, False, 5, True, False)),
    ("outputs-and-in-outs-into-locals",  # F_Use(16#0304): h 3, l 4, k 10 + 1 + 1 = 12, e MANUAL (6): 3000 + 4 + 12 + 6
     MODES + "FUNCTION F_Split\nVAR_INPUT w : WORD; END_VAR\nVAR_OUTPUT nHigh : BYTE; nLow : BYTE; eMode : E_Mode; END_VAR\n"
     "nHigh := WORD_TO_BYTE(SHR(w, 8)); nLow := WORD_TO_BYTE(w); eMode := E_Mode.MANUAL;\nEND_FUNCTION\n"
     "FUNCTION F_Inc\nVAR_IN_OUT n : INT; END_VAR\nn := n + 1;\nEND_FUNCTION\n"
     "FUNCTION F_Use : INT\nVAR_INPUT w : WORD; END_VAR\nVAR h : BYTE; l : BYTE; k : INT := 10; e : E_Mode; END_VAR\n"
     "F_Split(w := w, nHigh => h, nLow => l, eMode => e);\nF_Inc(k); F_Inc(n := k);\nF_Use := h * 1000 + l + k + e;\nEND_FUNCTION\n"
     "FUNCTION_BLOCK FB\nEND_FUNCTION_BLOCK\n"
     "METHOD Pair : INT\nVAR a : BYTE; b : BYTE; END_VAR\nF_Split(w := 16#0102, nHigh => a, nLow => b);\nPair := a * 10 + b;\nEND_METHOD\n"
     + prog("n : INT; fb : FB; m : INT;", "n := F_Use(16#0304); m := fb.Pair();"), 2,
     lambda m: (m.n, m.m), (3022, 12)),
]

TASK_INFO = prog("t : UDINT; n : UDINT; bFirst : BOOL; s : STRING; nFirst : INT;",
                 "t := _TaskInfo[GETCURTASKINDEXEX()].CycleTime; n := _TaskInfo[GETCURTASKINDEXEX()].cyclecount;\n"
                 "bFirst := _TaskInfo[GETCURTASKINDEXEX()].FirstCycle; s := _TaskInfo[GETCURTASKINDEXEX()].TaskName;\n"
                 "IF _TaskInfo[GETCURTASKINDEXEX()].FirstCycle THEN nFirst := nFirst + 1; END_IF")


@pytest.mark.parametrize("source, cycles, read, expected", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_construct(source: str, cycles: int, read: Callable[[Any], Any], expected: Any) -> None:
    assert read(run(source, cycles)) == expected


@pytest.mark.parametrize("source, construct", [
    (MODES + prog("e : E_Mode; n : INT;", "CASE e OF E_Mode.OFF: n := 1; END_CASE"), "<st>:6: enumeration E_Mode has no value 'OFF'"),
    (MODES + prog("e : E_Mode;", "e := E_Mode.OFF;"), "E_Mode has no value 'OFF'"),
    ("FUNCTION F : INT\nVAR_EXTERNAL nMissing : INT; END_VAR\nF := nMissing;\nEND_FUNCTION\n",
     "<st>:2: VAR_EXTERNAL nMissing of F names no VAR_GLOBAL"),
    ("FUNCTION F : INT\nVAR_INPUT x : INT; END_VAR\nVAR r : REFERENCE TO INT; END_VAR\nr REF= x;\nEND_FUNCTION\n",
     "<st>:4: x is a local variable; ADR / REF= need a variable of a block, struct or GVL"),
    (prog("t : UDINT; i : DINT;", "t := _TaskInfo[i, 2].CycleTime;"), r"<st>:5: _TaskInfo takes one index, the task's"),
    (prog("t : UDINT;", "t := _TaskInfo[GETCURTASKINDEXEX()].AdsPort;"), r"_TaskInfo\[...\].AdsPort: iecoop's TaskInfo has CycleTime"),
    (prog("t : UDINT;", "_TaskInfo[GETCURTASKINDEXEX()].CycleTime := t;"), "assignment to _TaskInfo"),
    (prog("info : __SYSTEM.VAR_INFO;", ""), "<st>:3: VAR info : __SYSTEM.VAR_INFO .declare it as a local of a METHOD or FUNCTION."),
    ("TYPE ST_A : STRUCT n : INT; END_STRUCT END_TYPE\nFUNCTION F : INT\nVAR s : ST_A; r : REFERENCE TO ST_A; END_VAR\n"
     "r REF= s; r REF= 0;\nEND_FUNCTION\n",
     "<st>:4: REF= 0 of r: a local REFERENCE TO a STRUCT, UNION or FB cannot be unbound"),
])
def test_unsupported_or_wrong_names_raise(source: str, construct: str) -> None:
    with pytest.raises(st.StUnsupportedError, match=construct):
        st.load(source)


def test_enum_to_string_of_a_value_without_a_component_is_its_number() -> None:
    main = st.load("{attribute 'to_string'}\nTYPE E_Named : (IDLE, AUTO := 5) INT; END_TYPE\n"
                   "PROGRAM MAIN\nVAR_INPUT e : E_Named; END_VAR\nVAR s : STRING; END_VAR\ns := TO_STRING(e);\nEND_PROGRAM\n").MAIN
    main.e = 5
    main()
    assert main.s == "AUTO"
    main.e = 3
    main()
    assert main.s == "3"


def test_an_unbound_reference_local_faults_when_read() -> None:
    module = st.load("FUNCTION F : INT\nVAR r : REFERENCE TO INT; END_VAR\nF := r;\nEND_FUNCTION\n")
    with pytest.raises(PlcException) as caught:
        module.F()
    assert caught.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


def test_a_reference_unbound_by_ref_zero_faults_when_read() -> None:
    fb = st.load("FUNCTION_BLOCK FB\nVAR n : INT; r : REFERENCE TO INT; END_VAR\nVAR_OUTPUT nRead : INT; END_VAR\n"
                 "r REF= n; nRead := r + 1; r REF= 0; nRead := r;\nEND_FUNCTION_BLOCK\n").FB()
    with pytest.raises(PlcException) as caught:
        fb()
    assert caught.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION
    assert fb.nRead == 1  # the read through the bound reference ran; the one after REF= 0 faulted


def test_task_info_is_the_running_tasks() -> None:
    main = st.load(TASK_INFO).MAIN
    rt = Runtime(store=":memory:")
    rt.add_task(Task("Fast", interval=T("5ms")), main)
    rt.run(cycles=1)
    assert (main.t, main.bFirst, main.s, main.nFirst) == (50_000, True, "Fast", 1)  # 5 ms in 100 ns units
    rt.run(cycles=2)
    assert (main.bFirst, main.nFirst, main.n) == (False, 1, 2)  # the third cycle: 2 cycles counted before it
