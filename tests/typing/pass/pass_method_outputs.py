"""METHOD and FUNCTION outputs and in-outs that ``mypy --strict`` accepts, and that run.

ST::

    FUNCTION_BLOCK FB_Word
    VAR nHi : BYTE; nLo : BYTE; nCalls : DINT; sName : STRING; END_VAR
    METHOD Split : BOOL
    VAR_INPUT nValue : UINT; END_VAR
    VAR_OUTPUT nHigh : BYTE; nLow : BYTE; END_VAR
    VAR_IN_OUT nCalls : DINT; END_VAR

    FUNCTION F_Divide : INT
    VAR_INPUT a : INT; b : INT; END_VAR
    VAR_OUTPUT nRest : INT; END_VAR
"""

from __future__ import annotations

from iecoop import (
    BOOL,
    BYTE,
    DINT,
    INT,
    POINTER_TO,
    STRING,
    UINT,
    VAR,
    VAR_IN_OUT,
    VAR_OUTPUT,
    FunctionBlock,
    Interface,
    adr,
    function,
    method,
)


class ISplit(Interface):
    @method
    def split(
        self, value: UINT, high: POINTER_TO[BYTE] = VAR_OUTPUT(), low: POINTER_TO[BYTE] = VAR_OUTPUT(),
        calls: POINTER_TO[DINT] = VAR_IN_OUT(),
    ) -> BOOL: ...


class Word(FunctionBlock, ISplit):
    hi: BYTE = VAR(0)
    lo: BYTE = VAR(0)
    calls: DINT = VAR(0)
    name: STRING = VAR("")

    @method
    def split(
        self, value: UINT, high: POINTER_TO[BYTE] = VAR_OUTPUT(), low: POINTER_TO[BYTE] = VAR_OUTPUT(),
        calls: POINTER_TO[DINT] = VAR_IN_OUT(),
    ) -> BOOL:
        high.deref = value // 256
        low.deref = value % 256
        calls.deref += 1
        return True

    @method
    def label(self, text: POINTER_TO[STRING] = VAR_OUTPUT(length=20)) -> None:
        text.deref = "word"

    def body(self) -> None:
        ok: bool = self.split(1000, high=adr(self, "hi"), low=adr(self, "lo"), calls=adr(self, "calls"))
        assert ok
        self.split(7, calls=adr(self, "calls"))      # outputs left out
        self.label(text=adr(self, "name"))


@function
def divide(a: INT, b: INT, rest: POINTER_TO[INT] = VAR_OUTPUT()) -> INT:
    rest.deref = a % b
    return a // b


def through_interface(word: ISplit, target: Word) -> bool:
    return word.split(3, low=adr(target, "lo"), calls=adr(target, "calls"))


def main() -> None:
    word = Word()
    word()
    assert (word.hi, word.lo, word.calls, word.name) == (3, 232, 2, "word")
    assert through_interface(word, word) and (word.lo, word.calls) == (3, 3)
    quotient: int = divide(17, 5, rest=adr(word, "calls"))
    assert (quotient, word.calls) == (3, 2)
