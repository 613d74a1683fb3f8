"""VAR_OUTPUT and VAR_IN_OUT of METHODs and FUNCTIONs, driven over several calls.

ST of the block most tests use::

    FUNCTION_BLOCK FB_Word
    VAR nHi, nLo : BYTE; nCalls : DINT; nLast : INT; END_VAR
    METHOD Split : BOOL
    VAR_INPUT nValue : UINT; END_VAR
    VAR_OUTPUT nHigh : BYTE; nLow : BYTE; END_VAR
    VAR_IN_OUT nCalls : DINT; END_VAR
    nHigh := nValue / 256; nLow := nValue MOD 256; nCalls := nCalls + 1; Split := nValue <> 0;
"""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from iecoop import (
    BOOL,
    BYTE,
    DINT,
    INT,
    POINTER_TO,
    PRIVATE,
    STRING,
    UINT,
    VAR,
    VAR_IN_OUT,
    VAR_OUTPUT,
    AccessError,
    DefinitionError,
    ExceptionCode,
    FunctionBlock,
    Interface,
    PlcException,
    Struct,
    adr,
    function,
    method,
)


class Word(FunctionBlock):
    hi: BYTE = VAR(0)
    lo: BYTE = VAR(0)
    calls: DINT = VAR(0)
    last: INT = VAR(0)

    @method
    def split(
        self, value: UINT, high: POINTER_TO[BYTE] = VAR_OUTPUT(), low: POINTER_TO[BYTE] = VAR_OUTPUT(),
        calls: POINTER_TO[DINT] = VAR_IN_OUT(),
    ) -> BOOL:
        high.deref = value // 256
        low.deref = value % 256
        calls.deref += 1
        return value != 0

    @method
    def count(self, seen: POINTER_TO[INT] = VAR_OUTPUT()) -> None:
        seen.deref += 1  # an output starts at 0 at every call: this is always 1

    @method
    def plain(self, value: INT) -> INT:
        return value + 1


def test_outputs_are_written_to_the_callers_variables_at_every_call() -> None:
    word = Word()
    results = [word.split(v, high=adr(word, "hi"), low=adr(word, "lo"), calls=adr(word, "calls")) for v in (1000, 0, 65535)]
    assert results == [True, False, True]
    assert (word.hi, word.lo, word.calls) == (255, 255, 3)


def test_an_output_starts_at_zero_at_every_call_an_in_out_keeps_the_callers_value() -> None:
    word = Word()
    for _ in range(4):
        word.count(seen=adr(word, "last"))
        word.split(1, calls=adr(word, "calls"))
    assert (word.last, word.calls) == (1, 4)


def test_an_output_left_out_is_computed_and_dropped() -> None:
    class Pair(Struct):
        hi: BYTE = 7
        lo: BYTE = 9
        calls: DINT = 0

    pair = Pair()
    assert Word().split(1000, low=adr(pair, "lo"), calls=adr(pair, "calls"))
    assert (pair.hi, pair.lo, pair.calls) == (7, 232, 1)


def test_a_method_that_raises_writes_no_output_but_its_in_out_writes_stay() -> None:
    class Checked(FunctionBlock):
        result: INT = VAR(5)
        calls: INT = VAR(0)

        @method
        def divide(self, a: INT, b: INT, quotient: POINTER_TO[INT] = VAR_OUTPUT(), calls: POINTER_TO[INT] = VAR_IN_OUT()) -> None:
            calls.deref += 1
            quotient.deref = 99
            quotient.deref = a // b

    block = Checked()
    block.divide(9, 2, quotient=adr(block, "result"), calls=adr(block, "calls"))
    with pytest.raises(ZeroDivisionError):
        block.divide(9, 0, quotient=adr(block, "result"), calls=adr(block, "calls"))
    assert (block.result, block.calls) == (4, 2)


def test_outputs_wrap_and_truncate_to_their_declared_type() -> None:
    class Texts(FunctionBlock):
        name: STRING = VAR("")
        small: BYTE = VAR(0)

        @method
        # VAR_OUTPUT(7) runs; mypy reads it as a default of the wrong type, so typed code sets 7 in the body instead
        def fill(self, text: POINTER_TO[STRING] = VAR_OUTPUT(length=4), wide: POINTER_TO[BYTE] = VAR_OUTPUT(7)) -> None:  # type: ignore[arg-type]
            assert wide.deref == 7  # the declared initial value, at every call
            text.deref = "conveyor"
            wide.deref = wide.deref + 300

    block = Texts()
    block.fill(text=adr(block, "name"), wide=adr(block, "small"))
    assert (block.name, block.small) == ("conv", (7 + 300) % 256)


def test_a_method_passes_its_own_output_on_to_another_call() -> None:
    class Relay(Word):
        @method
        def high_of(self, value: UINT, high: POINTER_TO[BYTE] = VAR_OUTPUT()) -> None:
            self.split(value, high=high, calls=adr(self, "calls"))  # nHigh => nHigh

    relay = Relay()
    relay.high_of(0x1234, high=adr(relay, "hi"))
    assert (relay.hi, relay.calls) == (0x12, 1)


def test_an_override_reaches_the_base_outputs_through_super() -> None:
    class Doubled(Word):
        @method
        def split(
            self, value: UINT, high: POINTER_TO[BYTE] = VAR_OUTPUT(), low: POINTER_TO[BYTE] = VAR_OUTPUT(),
            calls: POINTER_TO[DINT] = VAR_IN_OUT(),
        ) -> BOOL:
            ok = super().split(value, high=high, low=low, calls=calls)
            low.deref = low.deref * 2
            return ok

    block = Doubled()
    assert block.split(0x0203, high=adr(block, "hi"), low=adr(block, "lo"), calls=adr(block, "calls"))
    assert (block.hi, block.lo, block.calls) == (2, 6, 1)


def test_calls_through_an_interface_and_a_private_method_keeps_its_rule() -> None:
    class ICount(Interface):
        @method
        def count(self, seen: POINTER_TO[INT] = VAR_OUTPUT()) -> None: ...

    class Secret(FunctionBlock, ICount):
        last: INT = VAR(0)

        @method
        def count(self, seen: POINTER_TO[INT] = VAR_OUTPUT()) -> None:
            self._peek(seen=seen)

        @method(PRIVATE)
        def _peek(self, seen: POINTER_TO[INT] = VAR_OUTPUT()) -> None:
            seen.deref = 42

    block = Secret()
    through: ICount = block
    through.count(seen=adr(block, "last"))
    assert block.last == 42
    with pytest.raises(AccessError, match=r"PRIVATE METHOD Secret\._peek cannot be called from"):
        block._peek(seen=adr(block, "last"))


def test_wrong_names_and_wrong_arguments_name_the_class_the_member_and_the_rule() -> None:
    word = Word()
    with pytest.raises(TypeError, match=r"METHOD Word\.split has no VAR_INPUT, VAR_OUTPUT or VAR_IN_OUT 'hgh'"):
        word.split(1, hgh=adr(word, "hi"), calls=adr(word, "calls"))  # type: ignore[call-arg]
    with pytest.raises(TypeError, match=r"METHOD Word\.split: VAR_IN_OUT 'calls' must be assigned at every call"):
        word.split(1, high=adr(word, "hi"))  # type: ignore[call-arg]
    with pytest.raises(TypeError, match=r"METHOD Word\.split: VAR_OUTPUT 'high' is bound to a variable of the caller .*high=adr"):
        word.split(1, high=5, calls=adr(word, "calls"))  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=r"VAR_IN_OUT 'calls' is bound to a variable of the caller"):
        word.split(1, calls=word.calls)  # type: ignore[arg-type]
    assert (word.hi, word.calls) == (0, 0)  # refused before the method ran


def test_a_null_in_out_faults_as_an_access_violation() -> None:
    word = Word()
    with pytest.raises(PlcException) as info:
        word.split(1, calls=POINTER_TO[DINT]())
    assert info.value.code is ExceptionCode.RTSEXCPT_ACCESS_VIOLATION
    assert "METHOD Word.split: VAR_IN_OUT 'calls' is bound to 0" in str(info.value)


def test_bad_declarations_are_refused_at_class_definition() -> None:
    with pytest.raises(DefinitionError, match=r"METHOD Bad\.m: VAR_OUTPUT 'out'.*annotate it POINTER_TO\[<type>\] \(got INT\)"):

        class Bad(FunctionBlock):
            @method
            def m(self, out: INT = VAR_OUTPUT()) -> None: ...

    with pytest.raises(DefinitionError, match=r"METHOD Const\.m: VAR_IN_OUT CONSTANT 'ref' is not supported"):

        class Const(FunctionBlock):
            @method
            def m(self, ref: POINTER_TO[INT] = VAR_IN_OUT(constant=True)) -> None: ...

    with pytest.raises(DefinitionError, match=r"FUNCTION spread: \*more cannot stand beside"):

        @function
        def spread(*more: INT, out: POINTER_TO[INT] = VAR_OUTPUT()) -> None: ...


def test_an_output_does_not_implement_or_override_an_input_of_the_same_type() -> None:
    class ISeen(Interface):
        @method
        def count(self, seen: POINTER_TO[INT] = VAR_OUTPUT()) -> None: ...

    with pytest.raises(DefinitionError, match=r"count.*\(seen: POINTER_TO\[INT\] = VAR_OUTPUT\(\)\) -> None"):

        class Plain(FunctionBlock, ISeen):
            @method
            def count(self, seen: POINTER_TO[INT] = POINTER_TO[INT]()) -> None: ...

    with pytest.raises(DefinitionError, match=r"C0094.*base \(seen: POINTER_TO\[INT\] = VAR_OUTPUT\(\)\)"):

        class InOut(Word):
            @method
            def count(self, seen: POINTER_TO[INT] = VAR_IN_OUT()) -> None: ...


def test_only_methods_with_outputs_or_in_outs_get_a_wrapper() -> None:
    assert Word.__dict__["plain"].__code__.co_filename == __file__
    assert Word.__dict__["split"].__code__.co_filename.startswith("<iecoop generated METHOD Word.split")
    assert Word.__dict__["split"].__wrapped__.__code__.co_filename == __file__

    def undecorated(a: INT) -> INT:
        return a

    assert function(undecorated) is undecorated


class Remainder(Struct):
    rest: INT = 0
    calls: INT = 0


@function
def divide(a: INT, b: INT, rest: POINTER_TO[INT] = VAR_OUTPUT(), calls: POINTER_TO[INT] = VAR_IN_OUT()) -> INT:
    rest.deref = a % b
    calls.deref += 1
    return a // b


def test_a_function_with_an_output_and_an_in_out() -> None:
    r = Remainder()
    assert [divide(a, 4, rest=adr(r, "rest"), calls=adr(r, "calls")) for a in (9, 10, 3)] == [2, 2, 0]
    assert (r.rest, r.calls) == (3, 3)
    with pytest.raises(TypeError, match=r"FUNCTION divide: VAR_IN_OUT 'calls' must be assigned at every call"):
        divide(1, 1, rest=adr(r, "rest"))  # type: ignore[call-arg]


@given(st.integers(min_value=0, max_value=65535))
def test_split_outputs_rebuild_the_input(value: int) -> None:
    word = Word()
    word.split(value, high=adr(word, "hi"), low=adr(word, "lo"), calls=adr(word, "calls"))
    assert word.hi * 256 + word.lo == value and word.calls == 1
