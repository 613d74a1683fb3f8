"""ST's ``VAR_IN_OUT aBuffer : ARRAY[*] OF T`` in a FUNCTION_BLOCK: loaded, run over cycles, written back and run the same.

TwinCAT 3 and CODESYS let a block take an array of any bounds by reference;
the block keeps it between calls, and its METHODs read it with
``LOWER_BOUND`` / ``UPPER_BOUND``. A ring buffer over a STRUCT array, the
shape of many real projects' logging and sample buffers.
"""

from __future__ import annotations

import pathlib

import pytest

from iecoop import ARRAY, DINT, INT, VAR, VAR_IN_OUT, VAR_OUTPUT, FunctionBlock, Program
from iecoop.runtime import Runtime, Task

st = pytest.importorskip("iecoop.st")

LOGGER = """TYPE ST_Sample :
STRUCT
    nCycle : UDINT;
    rValue : REAL;
END_STRUCT
END_TYPE
FUNCTION_BLOCK FB_Ring
VAR_INPUT
    rValue : REAL;
END_VAR
VAR_IN_OUT
    aBuffer : ARRAY[*] OF ST_Sample;
END_VAR
VAR_OUTPUT
    nCount : DINT;
    nNext : DINT;
END_VAR
VAR
    nCycles : UDINT;
END_VAR
nCycles := nCycles + 1;
IF nNext < LOWER_BOUND(aBuffer, 1) OR nNext > UPPER_BOUND(aBuffer, 1) THEN
    nNext := LOWER_BOUND(aBuffer, 1);
END_IF
aBuffer[nNext].nCycle := nCycles;
aBuffer[nNext].rValue := rValue;
nNext := nNext + 1;
nCount := MIN(nCount + 1, UPPER_BOUND(aBuffer, 1) - LOWER_BOUND(aBuffer, 1) + 1);
END_FUNCTION_BLOCK
METHOD Mean : REAL
VAR_INPUT
    nLast : DINT;
END_VAR
VAR
    i : DINT;
    rSum : REAL;
END_VAR
FOR i := LOWER_BOUND(aBuffer, 1) TO LOWER_BOUND(aBuffer, 1) + nLast - 1 DO
    rSum := rSum + aBuffer[i].rValue;
END_FOR
Mean := rSum / DINT_TO_REAL(nLast);
END_METHOD
VAR_GLOBAL
    aLog : ARRAY[0..3] OF ST_Sample;
END_VAR
PROGRAM MAIN
VAR
    aFast : ARRAY[1..8] OF ST_Sample;
    fbFast : FB_Ring;
    fbSlow : FB_Ring;
    rLevel : REAL;
    rMean : REAL;
END_VAR
rLevel := rLevel + 0.5;
fbFast(rValue := rLevel, aBuffer := aFast);
fbSlow(rValue := rLevel * 2.0, aBuffer := aLog);
rMean := fbSlow.Mean(4);
END_PROGRAM
"""


def _run(module: object, cycles: int) -> object:
    main = getattr(module, "MAIN")
    runtime = Runtime(store=":memory:")
    runtime.add_task(Task("PlcTask", interval=10_000_000), main)
    runtime.run(cycles=cycles)
    return main


def _trace(module: object, cycles: int) -> tuple[object, ...]:
    main: object = _run(module, cycles)
    fast = [(s.nCycle, s.rValue) for s in getattr(main, "aFast")]
    log = [(s.nCycle, s.rValue) for s in getattr(module, "GVL").aLog]
    return (getattr(main, "rMean"), getattr(main, "fbFast").nCount, getattr(main, "fbSlow").nNext, fast, log)


def test_each_block_fills_the_array_it_is_given_within_its_bounds() -> None:
    module = st.load(LOGGER)
    main = _run(module, 10)
    fast = [(s.nCycle, s.rValue) for s in getattr(main, "aFast")]
    # eight samples, then the ring wraps: cycles 9 and 10 overwrite the first two
    assert fast == [(9, 4.5), (10, 5.0), (3, 1.5), (4, 2.0), (5, 2.5), (6, 3.0), (7, 3.5), (8, 4.0)]
    assert getattr(main, "fbFast").nCount == 8
    log = [(s.nCycle, s.rValue) for s in module.GVL.aLog]
    assert log == [(9, 9.0), (10, 10.0), (7, 7.0), (8, 8.0)]  # ARRAY[0..3]: a ring of four
    assert getattr(main, "fbSlow").nNext == 2
    assert getattr(main, "rMean") == pytest.approx((9.0 + 10.0 + 7.0 + 8.0) / 4)


def test_the_python_declares_the_open_array_in_out() -> None:
    text = st.to_python(LOGGER)
    assert 'aBuffer: ARRAY[ST_Sample] = VAR_IN_OUT(bounds="*")' in text
    assert "self.aBuffer.bounds[1 - 1][0]" in text


def test_written_back_as_st_and_as_plcopen_it_runs_the_same(tmp_path: pathlib.Path) -> None:
    expected = _trace(st.load(LOGGER), 12)
    text = st.dump(st.load(LOGGER))
    assert "aBuffer : ARRAY[*] OF ST_Sample;" in text and "UPPER_BOUND(aBuffer, 1)" in text
    assert _trace(st.load(text), 12) == expected
    (xml,) = st.export(st.load(LOGGER), tmp_path / "xml", format="plcopen")
    from_xml = st.load(xml)
    assert _trace(from_xml, 12) == expected
    # the PLCopen-loaded project written as ST files is ST, and runs the same again
    files = st.export(from_xml, tmp_path / "st", format="st")
    assert all(not f.read_text().startswith("<?xml") for f in files)
    assert _trace(st.load(tmp_path / "st"), 12) == expected


REFUSED = """FUNCTION_BLOCK FB_Sum
VAR_IN_OUT
    aData : ARRAY[*] OF INT;
END_VAR
VAR_OUTPUT
    nHigh : DINT;
END_VAR
nHigh := UPPER_BOUND(aData, 1);
END_FUNCTION_BLOCK
PROGRAM MAIN
VAR
    aWrong : {declared};
    fbSum : FB_Sum;
END_VAR
fbSum(aData := aWrong);
END_PROGRAM
"""


@pytest.mark.parametrize("declared, got", [
    ("ARRAY[1..4] OF REAL", "of REAL, 1 dimension(s)"),
    ("ARRAY[1..4, 1..2] OF INT", "of INT, 2 dimension(s)"),
])
def test_an_array_of_another_element_or_shape_is_refused_at_load_with_its_line(declared: str, got: str) -> None:
    with pytest.raises(st.StUnsupportedError) as caught:
        st.load(REFUSED.format(declared=declared))
    message = str(caught.value)
    assert ":15: VAR_IN_OUT aData : ARRAY[*] OF INT takes an ARRAY of INT with 1 dimension(s), not aWrong" in message
    assert got in message


def test_an_open_array_outside_an_in_out_is_refused_with_its_line() -> None:
    source = REFUSED.format(declared="ARRAY[*] OF INT")
    with pytest.raises(st.StUnsupportedError, match=r":12: VAR aWrong : ARRAY\[\*\] is not supported outside a VAR_IN_OUT \(of a block, METHOD or FUNCTION\)"):
        st.load(source)
    with pytest.raises(st.StUnsupportedError, match=r":15: VAR_IN_OUT aData : ARRAY\[\*\] takes an ARRAY variable, not fbSum.nHigh"):
        st.load(REFUSED.format(declared="DINT").replace("aData := aWrong", "aData := fbSum.nHigh"))


class Total(FunctionBlock):
    aData: ARRAY[INT] = VAR_IN_OUT(bounds="*")
    nSum: DINT = VAR_OUTPUT(0)

    def body(self) -> None:
        self.nSum = 0
        for i in range(self.aData.low, self.aData.high + 1):
            self.nSum += self.aData[i]


class Tally(Program):
    aFew: ARRAY[INT] = VAR([1, 2, 3], bounds=(0, 2))
    aMany: ARRAY[INT] = VAR([5] * 6, bounds=(-2, 3))
    fbTotal: Total = VAR()
    nFew: DINT = VAR(0)
    nMany: DINT = VAR(0)

    def body(self) -> None:
        self.fbTotal(aData=self.aFew)
        self.nFew = self.fbTotal.nSum
        self.fbTotal(aData=self.aMany)
        self.nMany = self.fbTotal.nSum


def test_a_design_born_in_python_is_written_with_lower_and_upper_bound() -> None:
    text = st.dump([Total, Tally])
    assert "aData : ARRAY[*] OF INT;" in text
    assert "FOR i := LOWER_BOUND(aData, 1) TO UPPER_BOUND(aData, 1) DO" in text
    loaded = st.load(text).Tally
    loaded()
    assert (loaded.nFew, loaded.nMany) == (6, 30)
