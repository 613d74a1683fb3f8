"""METHOD and FUNCTION VAR_OUTPUT / VAR_IN_OUT through the ST bridge: load, dump, round trip, mypy."""

from __future__ import annotations

import pathlib
from xml.etree import ElementTree

import pytest

from iecoop import BOOL, DINT, INT, POINTER_TO, VAR, VAR_IN_OUT, VAR_OUTPUT, FunctionBlock, Program, adr, function, method, st
from tests.typing.test_typing import run_mypy

SPLIT = """
FUNCTION_BLOCK FB_Word
VAR nHi : BYTE; nLo : BYTE; nCalls : DINT; bOk : BOOL; END_VAR
bOk := Split(nValue := 1000, nHigh => nHi, nLow => nLo, nCount := nCalls);
END_FUNCTION_BLOCK

METHOD Split : BOOL
VAR_INPUT nValue : UINT; END_VAR
VAR_OUTPUT nHigh : BYTE; nLow : BYTE := 7; END_VAR
VAR_IN_OUT nCount : DINT; END_VAR
nHigh := nValue / 256;
nLow := nLow + nValue MOD 256;
nCount := nCount + 1;
Split := nValue <> 0;
END_METHOD

METHOD HighOf
VAR_INPUT nValue : UINT; END_VAR
VAR_OUTPUT nHigh : BYTE; END_VAR
Split(nValue := nValue, nHigh => nHigh, nCount := nCalls);
END_METHOD

FUNCTION F_Divide : INT
VAR_INPUT a : INT; b : INT; END_VAR
VAR_OUTPUT nRest : INT; END_VAR
VAR_IN_OUT nCalls : INT; END_VAR
nRest := a MOD b;
nCalls := nCalls + 1;
F_Divide := a / b;
END_FUNCTION

PROGRAM MAIN
VAR fbWord : FB_Word; n : INT; r : INT := 99; c : INT; h : BYTE; k : BOOL; END_VAR
fbWord();
n := F_Divide(17, 5, nRest => r, nCalls := c);
fbWord.HighOf(nValue := 16#1234, nHigh => h);
k := fbWord.Split(nValue := 0, nCount := c);
END_PROGRAM
"""


def test_st_methods_and_functions_with_outputs_and_in_outs_load_and_run() -> None:
    module = st.load(SPLIT)
    main = module.MAIN
    main()
    main()
    word = main.fbWord
    # per cycle: the body's Split and HighOf's Split count on nCalls; the last Split counts on c with F_Divide
    # nHi = 1000 / 256 = 3; nLo = 7 (its initial value, at every call) + 1000 MOD 256 = 239
    assert (word.nHi, word.nLo, word.nCalls) == (3, 239, 4)
    # 17 / 5 = 3 rest 2; h = 16#1234 / 256 = 16#12; Split(0) is FALSE; its outputs, not bound, are dropped
    assert (main.n, main.r, main.c, main.h, main.k) == (3, 2, 4, 0x12, False)


def test_the_generated_python_uses_the_public_forms() -> None:
    text = st.to_python(SPLIT)
    assert "nHigh: POINTER_TO[BYTE] = VAR_OUTPUT()" in text
    assert "nCount: POINTER_TO[DINT] = VAR_IN_OUT()" in text
    assert "nLow.deref = 7" in text  # an output's initial value, set at every call
    assert 'self.Split(nValue=1000, nHigh=adr(self, "nHi"), nLow=adr(self, "nLo"), nCount=adr(self, "nCalls"))' in text
    assert "self.Split(nValue=nValue, nHigh=nHigh, " in text  # an output passed on to another call
    assert "@function\ndef F_Divide(" in text


def test_the_generated_python_passes_mypy_strict(tmp_path: pathlib.Path) -> None:
    path = tmp_path / "st_method_outputs.py"
    path.write_text(st.to_python(SPLIT))
    assert run_mypy([path]) == ("", 0)


@pytest.mark.parametrize("body, construct", [
    ("Split(nValue := 1, nHgh => nHi, nCount := nCalls);", "call has no output 'nHgh'"),
    ("Split(nValue := 1, nHigh := nHi, nCount := nCalls);", "output 'nHigh' is assigned with =>, not :="),
])
def test_wrong_outputs_in_st_are_named(body: str, construct: str) -> None:
    source = SPLIT.replace("bOk := Split(nValue := 1000, nHigh => nHi, nLow => nLo, nCount := nCalls);", body)
    with pytest.raises(st.StUnsupportedError, match=construct):
        st.load(source)


# A class written in Python, dumped to ST and loaded back: the same results.


class Counter(FunctionBlock):
    total: DINT = VAR(0)
    last: INT = VAR(0)
    seen: BOOL = VAR(False)

    @method
    def step(self, amount: INT, before: POINTER_TO[INT] = VAR_OUTPUT(), total: POINTER_TO[DINT] = VAR_IN_OUT()) -> BOOL:
        before.deref = total.deref
        total.deref = total.deref + amount
        return total.deref > 10

    @method
    def relay(self, amount: INT, before: POINTER_TO[INT] = VAR_OUTPUT()) -> None:
        self.seen = self.step(amount, before=before, total=adr(self, "total"))

    def body(self) -> None:
        self.relay(4, before=adr(self, "last"))


@function
def clamp(value: INT, limit: INT, cut: POINTER_TO[BOOL] = VAR_OUTPUT()) -> INT:
    cut.deref = value > limit
    if value > limit:
        return limit
    return value


class Main(Program):
    counter: Counter = VAR()
    low: INT = VAR(0)
    cut: BOOL = VAR(False)

    def body(self) -> None:
        self.counter()
        self.low = clamp(self.counter.last, 5, cut=adr(self, "cut"))


def test_a_python_class_with_outputs_dumps_to_st_and_loads_back_the_same() -> None:
    text = st.dump([Counter, Main])
    assert "VAR_OUTPUT\n    before : INT;\nEND_VAR\nVAR_IN_OUT\n    total : DINT;\nEND_VAR" in text
    assert "step(amount := amount, before => before, total := total)" in text
    assert "relay(amount := 4, before => last)" in text
    assert "clamp(value := counter.last, limit := 5, cut => cut)" in text
    loaded = st.load(text)
    python, plc = Main(), loaded.Main
    for _ in range(4):
        python()
        plc()
        assert (plc.counter.total, plc.counter.last, plc.counter.seen, plc.low, plc.cut) == (
            python.counter.total, python.counter.last, python.counter.seen, python.low, python.cut)
    assert (python.counter.total, python.counter.last, python.counter.seen, python.low, python.cut) == (16, 12, True, 5, True)


INTERFACE = """
INTERFACE I_Split
END_INTERFACE
METHOD Split : BOOL
VAR_INPUT nValue : INT; END_VAR
VAR_OUTPUT nDouble : INT; sName : STRING(4); END_VAR
END_METHOD

FUNCTION_BLOCK FB_A IMPLEMENTS I_Split
END_FUNCTION_BLOCK
METHOD Split : BOOL
VAR_INPUT nValue : INT; END_VAR
VAR_OUTPUT nDouble : INT; sName : STRING(4); END_VAR
nDouble := nValue * 2;
sName := 'conveyor';
Split := TRUE;
END_METHOD

PROGRAM MAIN
VAR fbA : FB_A; itf : I_Split; n : INT; s : STRING; ok : BOOL; END_VAR
itf := fbA;
ok := itf.Split(21, nDouble => n, sName => s);
END_PROGRAM
"""


def test_outputs_through_an_interface_keep_their_string_length_both_ways() -> None:
    module = st.load(INTERFACE)
    module.MAIN()
    assert (module.MAIN.n, module.MAIN.s, module.MAIN.ok) == (42, "conv", True)  # STRING(4) cuts 'conveyor'
    text = st.dump([module.I_Split, module.FB_A, type(module.MAIN)])
    assert text.count("sName : STRING(4);") == 2 and "Split(nValue := 21, nDouble => n, sName => s)" in text
    again = st.load(text)
    again.MAIN()
    assert (again.MAIN.n, again.MAIN.s, again.MAIN.ok) == (42, "conv", True)


def test_twincat_and_plcopen_files_carry_the_outputs_and_in_outs(tmp_path: pathlib.Path) -> None:
    from tests.iecoop.st.test_export import validate_plcopen

    files = st.export([Counter, Main], tmp_path / "twincat", format="twincat")
    counter = next(p for p in files if p.name == "Counter.TcPOU").read_text()
    assert "VAR_OUTPUT\n    before : INT;\nEND_VAR\nVAR_IN_OUT\n    total : DINT;\nEND_VAR" in counter
    (project,) = st.export([Counter, Main], tmp_path / "plcopen", format="plcopen")
    parsed = validate_plcopen(project)
    assert {pou.name for pou in parsed.types.pous.pou} >= {"Counter", "Main", "clamp"}
    tree = ElementTree.parse(project)
    step = next(e for e in tree.iter() if e.tag.endswith("Method") and e.get("name") == "step")
    interface = step.find("{*}interface")
    assert interface is not None
    sections = {child.tag.rsplit("}", 1)[-1]: [v.get("name") for v in child] for child in interface}
    assert (sections["inputVars"], sections["outputVars"], sections["inOutVars"]) == (["amount"], ["before"], ["total"])
