"""METHOD and FUNCTION outputs and in-outs misused: mypy reports each. Never run."""

from __future__ import annotations

from iecoop import BOOL, BYTE, DINT, INT, POINTER_TO, UINT, VAR, VAR_IN_OUT, VAR_OUTPUT, FunctionBlock, adr, function, method


class Word(FunctionBlock):
    hi: BYTE = VAR(0)
    calls: DINT = VAR(0)

    @method
    def split(self, value: UINT, high: POINTER_TO[BYTE] = VAR_OUTPUT(), calls: POINTER_TO[DINT] = VAR_IN_OUT()) -> BOOL:
        high.deref = "high"  # E: Incompatible types in assignment
        high = 3  # E: Incompatible types in assignment
        return calls.deref > 0


@function
def divide(a: INT, b: INT, rest: POINTER_TO[INT] = VAR_OUTPUT()) -> INT:
    rest.deref = a % b
    return a // b


@function
def count(seen: POINTER_TO[BYTE], *, calls: POINTER_TO[DINT] = VAR_IN_OUT()) -> None:
    calls.deref += seen.deref


def misuse(word: Word) -> None:
    word.split(1, high=word.hi, calls=adr(word, "calls"))  # E: Argument "high" to "split" of "Word" has incompatible type "int"
    word.split(1, hgh=adr(word, "hi"), calls=adr(word, "calls"))  # E: Unexpected keyword argument "hgh"
    word.split(1, high=adr(word, "hi"))  # E: Too few arguments for "split" of "Word"
    word.split(1, calls=5)  # E: Argument "calls" to "split" of "Word" has incompatible type "int"
    flag: str = divide(1, 2)  # E: Incompatible types in assignment
    divide(1, 2, rest=3)  # E: Argument "rest" to "divide" has incompatible type "int"
    count(adr(word, "hi"), calls=adr(word, "calls"))
    count(adr(word, "hi"))  # E: Missing named argument "calls" for "count"
