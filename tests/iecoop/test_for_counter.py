"""A FOR over a block's own integer variable: each pass reads the counter from the loop, with the same results.

``for self.i in range(1, 5):`` (ST: ``FOR i := 1 TO 4 DO``) compiled into the
block's call stores ``i`` at the start of each pass, as before, and the pass's
own statements read it from the loop; ``MOD(i, 2)`` of a counter that is never
negative is ``i % 2``, and ``cells[i]`` of a counter that stays in the ARRAY's
bounds reads the element in place. Each block is driven over several calls,
against values worked by hand; where the rule does not hold (the pass stores
the counter, the range leaves the type, the counter leaves the bounds, it goes
negative) the loop runs as written.
"""

from __future__ import annotations

from typing import Any

import pytest

from iecoop import ARRAY, BOOL, DINT, INT, SINT, VAR, VAR_INPUT, VAR_OUTPUT, FunctionBlock, PlcException, method
from iecoop.conversions import MOD

st = pytest.importorskip("iecoop.st")


class Cell(FunctionBlock):
    go: BOOL = VAR_INPUT()
    count: INT = VAR_OUTPUT()

    def body(self) -> None:
        if self.go:
            self.count += 1


class Tally(FunctionBlock):
    """Even cells counted; a METHOD the pass calls records the counter it reads."""

    cells: ARRAY[Cell] = VAR(bounds=(1, 4))
    seen: ARRAY[DINT] = VAR(bounds=(1, 4))
    i: DINT = VAR()
    total: DINT = VAR_OUTPUT()

    def body(self) -> None:
        for self.i in range(1, 4 + 1):
            self.total += self.i
            if MOD(self.i, 2) == 0:
                self.cells[self.i](go=True)
            self.note()

    @method
    def note(self) -> None:
        self.seen[self.i] = self.seen[self.i] + self.i * 10


def _locals(cls: type) -> tuple[str, ...]:
    call: Any = cls.__dict__["__call__"]
    return tuple(call.__code__.co_varnames)


def test_a_pass_reads_the_counter_from_the_loop_and_a_method_sees_it_stored() -> None:
    tally = Tally()
    for cycle in range(1, 4):
        tally()
        assert tally.i == 4  # Python's for leaves the last value (the ST reader adds ST's `else`)
        assert tally.total == 10 * cycle
        assert [cell.count for cell in tally.cells] == [0, cycle, 0, cycle]
        assert list(tally.seen) == [10 * cycle, 20 * cycle, 30 * cycle, 40 * cycle]  # the METHOD read the stored i
    names = _locals(Tally)
    assert any(name.startswith("_iec_c_") for name in names)  # the pass's reads come from the loop
    call: Any = Tally.__dict__["__call__"]
    assert "MOD" not in call.__code__.co_names  # MOD(i, 2) of a counter 1..4 is i % 2
    assert "_iec_w_type" not in call.__code__.co_freevars  # cells[i] of a counter 1..4 needs no bounds check


class Search(FunctionBlock):
    """``break`` (ST: EXIT) leaves the counter where it was."""

    limit: DINT = VAR_INPUT()
    i: DINT = VAR()
    passes: DINT = VAR_OUTPUT()

    def body(self) -> None:
        for self.i in range(1, 10 + 1):
            if self.i >= self.limit:
                break
            self.passes += 1


def test_exit_keeps_the_counter_it_stopped_at() -> None:
    search = Search()
    search(limit=3)
    assert (search.i, search.passes) == (3, 2)
    search(limit=20)
    assert (search.i, search.passes) == (10, 12)


class Negative(FunctionBlock):
    """MOD of a counter that goes negative keeps IEC's sign (truncated toward zero): -5 MOD 3 = -2."""

    i: INT = VAR()
    acc: DINT = VAR_OUTPUT()

    def body(self) -> None:
        for self.i in range(-5, 5 + 1):
            self.acc += MOD(self.i, 3)


def test_mod_of_a_counter_that_goes_negative_keeps_its_sign() -> None:
    negative = Negative()
    negative()
    # -2 -1 0 -2 -1 0 1 2 0 1 2: Python's % would give 1 2 0 1 2 ... and a sum of 12
    assert negative.acc == 0
    negative()
    assert negative.acc == 0
    call: Any = Negative.__dict__["__call__"]
    assert "MOD" in call.__code__.co_names


class Rewrites(FunctionBlock):
    """A pass that stores its own counter (Python allows it; ST does not): the loop runs as written."""

    i: DINT = VAR()
    acc: DINT = VAR_OUTPUT()

    def body(self) -> None:
        for self.i in range(1, 3 + 1):
            self.i = self.i * 2
            self.acc += self.i


def test_a_pass_that_stores_its_counter_reads_what_it_stored() -> None:
    rewrites = Rewrites()
    rewrites()
    assert (rewrites.acc, rewrites.i) == (2 + 4 + 6, 6)
    assert not any(name.startswith("_iec_c_") for name in _locals(Rewrites))


class Overrun(FunctionBlock):
    """A counter past the ARRAY's bounds: the element read checks the bounds, as before."""

    cells: ARRAY[Cell] = VAR(bounds=(1, 4))
    i: DINT = VAR()

    def body(self) -> None:
        for self.i in range(1, 5 + 1):
            self.cells[self.i](go=True)


def test_a_counter_past_the_bounds_is_refused_at_the_pass_that_leaves_them() -> None:
    overrun = Overrun()
    with pytest.raises(PlcException, match=r"index 5 .*outside ARRAY\[1\.\.4\] OF Cell") as caught:
        overrun()
    assert caught.value.code.name == "RTSEXCPT_ARRAYBOUNDS"
    assert [cell.count for cell in overrun.cells] == [1, 1, 1, 1]
    assert overrun.i == 5


class Wide(FunctionBlock):
    """A range beyond the counter's type (SINT holds -128..127): the loop runs as written."""

    n: SINT = VAR()
    passes: DINT = VAR_OUTPUT()

    def body(self) -> None:
        for self.n in range(120, 130):
            self.passes += 1


def test_a_range_beyond_the_counters_type_runs_as_written() -> None:
    assert not any(name.startswith("_iec_c_") for name in _locals(Wide))
    wide = Wide()
    wide()
    assert (wide.passes, wide.n) == (10, -127)  # the store wraps as the PLC's SINT does: 128 is -128, 129 is -127
    wide()
    assert (wide.passes, wide.n) == (20, -127)


_LINE = """
FUNCTION_BLOCK FB_Cell
VAR_INPUT bGo : BOOL; END_VAR
VAR_OUTPUT nCount : INT; END_VAR
IF bGo THEN nCount := nCount + 1; END_IF
END_FUNCTION_BLOCK

PROGRAM MAIN
VAR
    aCells : ARRAY[1..6] OF FB_Cell;
    aSeen : ARRAY[1..6] OF DINT;
    i : INT;
    nLast : INT := 6;
    nTotal : DINT;
END_VAR
FOR i := 1 TO 6 DO
    aCells[i](bGo := i MOD 3 = 0);
    nTotal := nTotal + i MOD 4;
    Note();
END_FOR
END_PROGRAM

METHOD Note
aSeen[i] := aSeen[i] + i;
END_METHOD
"""


def test_a_loaded_for_loop_counts_and_a_method_reads_the_counter() -> None:
    plc = st.load(_LINE)
    for cycle in range(1, 4):
        plc.MAIN()
        assert plc.MAIN.i == 7
        assert [cell.nCount for cell in plc.MAIN.aCells] == [0, 0, cycle, 0, 0, cycle]
        assert plc.MAIN.nTotal == (1 + 2 + 3 + 0 + 1 + 2) * cycle
        assert list(plc.MAIN.aSeen) == [n * cycle for n in range(1, 7)]
    assert any(name.startswith("_iec_c_") for name in _locals(type(plc.MAIN)))
