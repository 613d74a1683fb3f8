"""A block's own code writes its variables without the checked ``__setattr__``: the same checks, written out.

In checked mode a write runs the class's ``__setattr__``, which asks the
writing frame whether the block's own code is writing. The block's own code
always may (unless CONSTANT or a METHOD's VAR_INST), so when the class is
built its compiled call, its METHODs and its FOR counters write their
variables as that ``__setattr__`` would, without calling it: the value's
class checked (left out when the code shows the class), then the store.
Writes from outside keep the rules and their messages.
"""

from __future__ import annotations

import copy
import inspect
import os
import pathlib
import subprocess
import sys
from collections.abc import Iterator
from typing import Any

import pytest

from iecoop import (
    BOOL,
    DINT,
    INT,
    PRIVATE,
    PROTECTED,
    REAL,
    VAR,
    VAR_INPUT,
    VAR_INST,
    VAR_OUTPUT,
    AccessError,
    FunctionBlock,
    Program,
    _config,
    method,
)

pytestmark = pytest.mark.skipif(not _config.CHECKS, reason="checked mode installs the write-checking __setattr__")


class Accumulator(FunctionBlock):
    """FB_Accumulator: METHOD Run adds n to x, one at a time (x wraps as an INT)."""

    x: INT = VAR(0)
    total: DINT = VAR_OUTPUT(0)
    level: REAL = VAR_OUTPUT(0.0)
    busy: BOOL = VAR_OUTPUT(False)

    @method
    def run(self, n: DINT) -> None:
        for _ in range(n):
            self.x = self.x + 1
        self.total += n
        self.level = self.x  # an INT into a REAL: the value is checked (an int is no float) and stored
        self.busy = not self.busy

    @method
    def put(self, value: Any) -> None:
        self.x = value

    @method(PRIVATE)
    def bump(self) -> None:
        self.x += 1

    @method(PROTECTED)
    def nudge(self) -> None:
        self.total = self.total - 1

    def body(self) -> None:
        self.bump()
        self.nudge()


class Loop(Program):
    """PROGRAM Loop: ``FOR i := 1 TO 3 DO seen := seen + Peek(); END_FOR`` (Peek returns i)."""

    i: DINT = VAR(0)
    seen: DINT = VAR(0)
    flag: BOOL = VAR(False)
    last: INT = VAR_INST(0, method="peek")

    def body(self) -> None:
        for self.i in range(1, 4):
            self.seen += self.peek()

    @method
    def peek(self) -> DINT:
        self.last = self.i
        return self.i

    @method
    def toggle(self, values: list[Any]) -> None:
        for self.flag in values:
            pass


#: The tests that count ``__setattr__`` runs with a profile function run in a process of their own: a profile
#: function switched on late in a long process (after the whole suite's earlier tests) stalled CPython 3.11.
_PROFILED = "IECOOP_PROFILED_TESTS"
profiled = pytest.mark.skipif(os.environ.get(_PROFILED) != "1", reason="run in a fresh process by test_profiled_tests")


def test_profiled_tests() -> None:
    env = {**os.environ, _PROFILED: "1"}
    root = pathlib.Path(__file__).resolve().parents[2]
    done = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
         *(f"{__file__}::{name}" for name in ("test_a_methods_own_writes_call_no_setattr",
                                               "test_guarded_methods_are_compiled_and_still_guarded",
                                               "test_the_for_counter_is_written_each_pass_without_setattr"))],
        cwd=root, env=env, capture_output=True, text=True, timeout=600, check=False,
    )
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-2000:]
    assert "\n3 passed in " in done.stdout, done.stdout[-2000:]


@pytest.fixture
def setattr_calls() -> Iterator[list[tuple[str, str]]]:
    """Every run of the checked ``__setattr__`` of Accumulator and Loop, as (class, variable).

    Seen by a profile function, so no frame stands between the writer and ``__setattr__``.
    """
    calls: list[tuple[str, str]] = []
    codes = {cls.__dict__["__setattr__"].__code__ for cls in (Accumulator, Loop)}

    def profile(frame: Any, event: str, _arg: Any) -> None:
        if event == "call" and frame.f_code in codes:
            calls.append((type(frame.f_locals["self"]).__name__, frame.f_locals["field"]))

    sys.setprofile(profile)
    try:
        yield calls
    finally:
        sys.setprofile(None)


@profiled
def test_a_methods_own_writes_call_no_setattr(setattr_calls: list[tuple[str, str]]) -> None:
    acc = Accumulator()
    acc.run(40_000)
    assert (acc.x, acc.total, acc.level, acc.busy) == (40_000 - 65_536, 40_000, float(40_000 - 65_536), True)
    acc.run(1)
    assert (acc.x, acc.busy) == (40_001 - 65_536, False)
    assert setattr_calls == []


def test_a_methods_written_out_write_still_checks_the_value() -> None:
    acc = Accumulator()
    with pytest.raises(TypeError, match=r"Accumulator\.x: cannot store float 2\.5 in INT"):
        acc.put(2.5)
    with pytest.raises(TypeError, match=r"Accumulator\.x: cannot store bool True in INT"):
        acc.put(True)
    acc.put(70_000)  # an int out of range wraps, as ctypes stores it
    assert acc.x == 70_000 - 65_536


@profiled
def test_guarded_methods_are_compiled_and_still_guarded(setattr_calls: list[tuple[str, str]]) -> None:
    acc = Accumulator()
    acc()
    acc()
    assert (acc.x, acc.total) == (2, -2)
    assert setattr_calls == []
    with pytest.raises(AccessError, match=r"PRIVATE METHOD Accumulator\.bump cannot be called from"):
        acc.bump()
    with pytest.raises(AccessError, match=r"PROTECTED METHOD Accumulator\.nudge cannot be called from"):
        acc.nudge()


def test_a_compiled_method_keeps_its_source_signature_and_code_ownership() -> None:
    run = Accumulator.__dict__["run"]
    assert inspect.getsource(run).lstrip().startswith("@method\n    def run(self, n: DINT) -> None:")
    assert list(inspect.signature(run).parameters) == ["self", "n"]
    assert run.__code__ in Accumulator._iec_codes_
    assert "_iec_w_store_x" in run.__code__.co_freevars  # the write written out


def test_writes_from_outside_keep_their_rules() -> None:
    acc = Accumulator()
    with pytest.raises(AccessError, match=r"VAR_OUTPUT Accumulator\.total cannot be written from"):
        acc.total = 5
    with pytest.raises(AccessError, match=r"VAR Accumulator\.x cannot be written from"):
        acc.x = 5


@profiled
def test_the_for_counter_is_written_each_pass_without_setattr(setattr_calls: list[tuple[str, str]]) -> None:
    loop = Loop()
    loop()
    # Each pass stores the counter before its statements run: the METHOD reads the current value.
    assert (loop.i, loop.seen, loop.last) == (3, 1 + 2 + 3, 3)
    # Only the VAR_INST takes the general path (its METHOD alone may write it), once a pass; the call's
    # first statement makes the instance's __dict__ a plain one, once.
    assert [call for call in setattr_calls if call[1] != "__dict__"] == [("Loop", "last")] * 3


def test_a_for_counter_of_the_wrong_kind_is_refused() -> None:
    loop = Loop()
    loop.toggle([True, False])
    assert loop.flag is False
    with pytest.raises(TypeError, match=r"Loop\.flag: cannot store int 1 in BOOL"):
        loop.toggle([True, 1])
    assert loop.flag is True  # the passes before the refused value were stored


class Pump(FunctionBlock):
    """FB_Pump: its compiled call writes its inputs and outputs with the checks written out."""

    run: BOOL = VAR_INPUT(False)
    speed: INT = VAR_INPUT(0)
    running: BOOL = VAR_OUTPUT(False)
    starts: DINT = VAR_OUTPUT(0)

    def body(self) -> None:
        if self.run and not self.running:
            self.starts += 1
        self.running = self.run


class BigPump(Pump):
    flow: REAL = VAR_OUTPUT(0.0)

    def body(self) -> None:
        super().body()
        self.flow = self.speed * 0.5


def test_a_copy_writes_its_own_memory_not_the_originals() -> None:
    pump = Pump()
    pump(run=True, speed=3)
    other = copy.copy(pump)
    other(run=False, speed=7)
    assert (pump.run, pump.speed, pump.running, pump.starts) == (True, 3, True, 1)
    assert (other.run, other.speed, other.running, other.starts) == (False, 7, False, 1)


def test_a_base_call_on_a_derived_instance_writes_the_derived_instances_memory() -> None:
    big = BigPump()
    Pump.__call__(big, run=True, speed=4)  # the base's compiled call, run on a derived block
    assert (big.run, big.speed, big.running, big.starts, big.flow) == (True, 4, True, 1, 0.0)
    big(run=True, speed=6)
    assert (big.running, big.starts, big.flow) == (True, 1, 3.0)


def test_an_input_of_the_wrong_kind_is_refused_before_anything_is_stored() -> None:
    pump = Pump()
    with pytest.raises(TypeError, match=r"Pump\.speed: cannot store float 1\.5 in INT"):
        pump(run=True, speed=1.5)  # type: ignore[arg-type]
    assert (pump.run, pump.speed, pump.starts) == (True, 0, 0)  # inputs are stored in order, as before
