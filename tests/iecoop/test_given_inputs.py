"""A BOOL input given to a call: the body's first reads of it take the argument, with the same results.

The compiled call stores each given input before the body; up to the body's
first statement that could change anything, ``self.IN`` is the argument when
it is an exact ``bool`` and the stored variable otherwise. Each block is
driven over several calls with inputs given and left out.
"""

from __future__ import annotations

import dis
from typing import Any

import pytest

from iecoop import BOOL, INT, VAR, VAR_INPUT, VAR_OUTPUT, FunctionBlock, _config, method
from iecoop.stdlib import TON


class Gate(FunctionBlock):
    """``IF bEnable THEN nCount := nCount + 1; END_IF`` and the input copied to an output."""

    enable: BOOL = VAR_INPUT()
    count: INT = VAR_OUTPUT()
    seen: BOOL = VAR_OUTPUT()

    def body(self) -> None:
        now = self.enable
        if self.enable:
            self.count += 1
        self.seen = now


def _loads(cls: type, opname: str, name: str) -> int:
    """How many instructions of the compiled call are ``opname`` (LOAD_ATTR, LOAD_FAST) of ``name``."""
    call: Any = cls.__dict__["__call__"]
    return sum(1 for i in dis.get_instructions(call) if i.opname.startswith(opname) and i.argval == name)


def test_a_given_bool_is_read_from_the_argument_and_a_left_out_one_from_the_variable() -> None:
    gate = Gate()
    gate(enable=True)
    gate()  # left out: keeps TRUE
    assert (gate.count, gate.seen) == (2, True)
    gate(enable=False)
    gate()
    assert (gate.count, gate.seen) == (2, False)
    gate(enable=True)
    assert (gate.count, gate.seen) == (3, True)
    # both reads test the argument (the input lines use it twice), each keeping the variable's read for a call
    # that leaves the input out; the input lines read the variable once, to store only a changed value
    assert _loads(Gate, "LOAD_FAST", "enable") >= 2 + 2 * 2
    assert _loads(Gate, "LOAD_ATTR", "enable") == 1 + 2


@pytest.mark.skipif(_config.CHECKS, reason="checked mode refuses a BOOL input that is not a bool")
def test_fast_mode_a_value_that_is_not_a_bool_is_read_back_as_the_bool_stored() -> None:
    gate = Gate()
    gate(enable=5)  # type: ignore[arg-type]  # the BOOL holds TRUE
    assert (gate.count, gate.seen) == (1, True)
    assert gate.seen is True
    gate(enable=0)  # type: ignore[arg-type]
    assert (gate.count, gate.seen) == (1, False)


class Latch(FunctionBlock):
    """A METHOD called first may write the input: every read after it reads the variable."""

    start: BOOL = VAR_INPUT()
    block: BOOL = VAR_INPUT()
    running: BOOL = VAR_OUTPUT()

    def body(self) -> None:
        self.interlock()
        self.running = self.start

    @method
    def interlock(self) -> None:
        if self.block:
            self.start = False


def test_a_read_after_a_call_that_may_write_the_input_reads_the_variable() -> None:
    latch = Latch()
    latch(start=True)
    assert latch.running is True
    latch(start=True, block=True)  # the METHOD clears start before the body reads it
    assert (latch.running, latch.start) == (False, False)
    latch(start=True, block=False)
    assert latch.running is True


class Delay(FunctionBlock):
    """A member call's arguments read the given input (evaluated before the member runs)."""

    go: BOOL = VAR_INPUT()
    timer: TON = VAR()
    done: BOOL = VAR_OUTPUT()

    def body(self) -> None:
        self.timer(IN=self.go, PT=20)
        self.done = self.timer.Q and self.go


def test_a_member_calls_arguments_take_the_given_input() -> None:
    from iecoop.runtime.clock import default_clock

    clock = default_clock()
    clock.set(0)
    delay = Delay()
    delay(go=True)
    assert (delay.done, delay.timer.Q) == (False, False)
    clock.advance(30_000_000)  # 30 ms
    delay(go=True)
    assert (delay.done, delay.timer.Q) == (True, True)
    delay(go=False)
    assert (delay.done, delay.timer.Q) == (False, False)
    clock.advance(30_000_000)
    delay()  # left out: FALSE kept
    assert (delay.done, delay.timer.Q) == (False, False)


class Interlock(FunctionBlock):
    """``IF bRun AND NOT bStop OR bJog THEN nCount := nCount + 1; END_IF``: the inputs only tested for truth."""

    run: BOOL = VAR_INPUT()
    stop: BOOL = VAR_INPUT()
    jog: BOOL = VAR_INPUT()
    count: INT = VAR_OUTPUT()

    def body(self) -> None:
        if self.run and not self.stop or self.jog:
            self.count += 1


def test_inputs_tested_for_truth_take_the_argument_given_and_the_variable_left_out() -> None:
    fb = Interlock()
    held = {"run": False, "stop": False, "jog": False}
    expected = 0
    cases: list[dict[str, Any]] = [
        {"run": True}, {}, {"stop": True}, {"jog": True}, {"jog": False}, {"stop": False}, {"run": False, "jog": True},
        {"run": True, "stop": True, "jog": False}, {}, {"stop": False},
    ]
    if not _config.CHECKS:
        cases += [{"run": 0, "stop": 0}, {"run": 3}, {}]  # fast mode: other values held as the BOOL stored
    for given in cases:
        fb(**given)
        held.update({name: bool(value) for name, value in given.items()})
        expected += held["run"] and not held["stop"] or held["jog"]
        assert fb.count == expected, given
    # each input's read is kept for a call that leaves it out, the argument tested first
    assert all(_loads(Interlock, "LOAD_ATTR", name) >= 1 for name in held)
