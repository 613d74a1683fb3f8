"""Fast mode: a loop of the block's own code that calls nothing keeps the block's variables in locals.

Each block is driven over several calls and its variables checked against
the values each store would have left (INT and UDINT wrap-around, BOOL and
LREAL conversion), by every way out of the loop: its end, ``break``,
``return`` and an error in the middle, whose memory holds what the passes
before it stored. A loop that calls a METHOD, or reads through a REFERENCE,
reads and writes the block's memory on every pass. The property at the end
runs random loops compiled from their source against the same source run as
written: the same variables, the same errors. In checked mode every loop
reads and writes its variables where the code has them.
"""

from __future__ import annotations

import ctypes
import dis
import itertools
import linecache
import traceback
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import (
    BOOL, DINT, INT, LREAL, REAL, REFERENCE_TO, UDINT, USINT, VAR, FunctionBlock, Program, _config, adr, method,
    ref_assign,
)

fast_only = pytest.mark.skipif(_config.CHECKS, reason="fast mode keeps variables in locals through a loop")


class Totals(FunctionBlock):
    """Sums and counts in METHOD loops, as a block computing statistics over its passes writes them."""

    total: INT = VAR(0)
    passes: UDINT = VAR(0)
    level: LREAL = VAR(0.0)
    full: BOOL = VAR(False)
    seen: DINT = VAR(0)
    i: DINT = VAR(0)

    @method
    def add(self, n: DINT) -> None:
        for _ in range(n):
            self.total = self.total + 1000  # INT: wraps at 32767
            self.passes -= 1  # UDINT: 0 - 1 wraps to 4294967295
            self.level = self.level + 0.5
            self.full = self.total != 0

    @method
    def first_over(self, limit: DINT) -> DINT:
        """``FOR i := 0 TO 99 DO IF i * i > limit THEN RETURN i; END_IF; seen := seen + 1; END_FOR``."""
        for self.i in range(100):
            if self.i * self.i > limit:
                return self.i
            self.seen = self.seen + 1
        return -1

    @method
    def until(self, limit: DINT) -> None:
        while self.seen < limit:
            self.seen += 3
            if self.seen % 7 == 0:
                break

    @method
    def divide(self, divisors: DINT) -> None:
        for k in range(divisors, -3, -1):
            self.seen = self.seen + 100 // k  # k reaches 0: the pass before it has stored

    @method
    def restart(self, level: LREAL) -> None:
        self.seen = 0
        self.level = level

    @method
    def wrong_kind(self) -> None:
        for k in range(5):
            self.seen = self.seen + 1
            if k == 3:
                self.total = self.level  # type: ignore[assignment]  # an LREAL in an INT: refused


def _wrap(value: int, bits: int, signed: bool) -> int:
    value &= (1 << bits) - 1
    return value - (1 << bits) if signed and value >> (bits - 1) else value


def test_the_values_each_store_leaves_over_several_calls() -> None:
    fb = Totals()
    total = 0
    for n in (3, 40, 0, 7):
        fb.add(n)
        for _ in range(n):
            total = _wrap(total + 1000, 16, True)
        assert fb.total == total
        assert fb.full is (total != 0)  # the last pass's
    assert fb.passes == _wrap(-50, 32, False)
    assert fb.level == 25.0


def test_a_return_from_the_loop_stores_what_the_passes_wrote() -> None:
    fb = Totals()
    assert fb.first_over(50) == 8
    assert (fb.i, fb.seen) == (8, 8)
    assert fb.first_over(10_000) == -1
    assert (fb.i, fb.seen) == (99, 108)  # a FOR's variable keeps the last value it took, as in Python


def test_a_while_loop_and_its_break() -> None:
    fb = Totals()
    fb.until(100)  # 3, 6, ..., 21: 21 % 7 == 0 ends it
    assert fb.seen == 21
    fb.until(30)  # 24, 27, 30: the test ends it
    assert fb.seen == 30


def test_an_error_in_a_pass_leaves_what_the_passes_before_it_stored() -> None:
    fb = Totals()
    with pytest.raises(ZeroDivisionError) as raised:
        fb.divide(3)
    assert fb.seen == 100 // 3 + 100 // 2 + 100 // 1
    # the traceback points at the line written, not at generated code
    assert "self.seen = self.seen + 100 // k" in "".join(traceback.format_tb(raised.value.__traceback__))
    fb.restart(1.5)
    with pytest.raises(TypeError, match="float"):
        fb.wrong_kind()
    assert (fb.seen, fb.total) == (4, 0)


class Logger(FunctionBlock):
    """A loop calling a METHOD that reads the variable: every pass stores it first."""

    x: INT = VAR(0)
    sum_seen: DINT = VAR(0)
    y: INT = VAR(0)
    ref: REFERENCE_TO[INT] = VAR()

    @method
    def count(self, n: DINT) -> None:
        for _ in range(n):
            self.x = self.x + 1
            self.log()

    @method
    def log(self) -> None:
        self.sum_seen = self.sum_seen + self.x

    @method
    def through_reference(self, n: DINT) -> None:
        """``ref`` designates ``x``: a write of ``x`` is seen by the next read of ``ref``."""
        for _ in range(n):
            self.x = self.x + 1
            self.y = self.y + self.ref


def test_a_loop_calling_a_method_reads_and_writes_memory_on_every_pass() -> None:
    fb = Logger()
    fb.count(5)
    assert (fb.x, fb.sum_seen) == (5, 1 + 2 + 3 + 4 + 5)


def test_a_loop_reading_through_a_reference_reads_memory_on_every_pass() -> None:
    fb = Logger()
    ref_assign(fb, "ref", adr(fb, "x"))
    fb.through_reference(4)
    assert (fb.x, fb.y) == (4, 1 + 2 + 3 + 4)


class Nested(Program):
    """An outer loop calling a METHOD, an inner one calling nothing: the inner one keeps its variables."""

    acc: DINT = VAR(0)
    rounds: USINT = VAR(0)
    ratio: REAL = VAR(0.0)

    def body(self) -> None:
        for _ in range(3):
            for j in range(100):
                self.acc = self.acc + j
            self.step()

    @method
    def step(self) -> None:
        self.rounds = self.rounds + self.acc  # USINT: wraps at 256
        self.ratio = self.ratio + 0.1  # REAL: never kept in a local (each store rounds)


def _attribute_ops(function: Any, name: str) -> list[str]:
    return [i.opname for i in dis.get_instructions(function) if i.argval == name and "ATTR" in i.opname]


def test_an_inner_loop_keeps_its_variables_while_the_outer_one_calls() -> None:
    prog = Nested()
    for cycle in range(1, 4):
        prog()
        assert prog.acc == cycle * 3 * 4950
    rounds = 0
    acc = 0
    for _ in range(9):
        acc += 4950
        rounds = (rounds + acc) & 0xFF
    assert prog.rounds == rounds
    assert prog.ratio == pytest.approx(0.9, abs=1e-5)
    call = type(prog).__dict__["__call__"]
    if _config.CHECKS:
        # checked mode: the inner loop reads and writes acc on every pass
        assert "LOAD_ATTR" in _attribute_ops(call, "acc")
    else:
        # one read before the inner loop, one store after it, on each of its ways out (the finally's two copies)
        ops = _attribute_ops(call, "acc")
        assert ops.count("LOAD_ATTR") == 1 and 1 <= ops.count("STORE_ATTR") <= 2


@fast_only
def test_the_method_loop_reads_its_variable_once_and_stores_it_once() -> None:
    ops = _attribute_ops(Totals.__dict__["add"], "total")
    assert ops.count("LOAD_ATTR") == 1 and 1 <= ops.count("STORE_ATTR") <= 2


@pytest.mark.skipif(not _config.CHECKS, reason="checked mode keeps every read and write where the code has it")
def test_checked_mode_loops_read_and_write_the_block_on_every_pass() -> None:
    assert "LOAD_ATTR" in _attribute_ops(Totals.__dict__["add"], "passes")


class Named(FunctionBlock):
    """Variables named as the rewrite's own names might be: each keeps its own value."""

    value: INT = VAR(0)
    int: DINT = VAR(0)
    float: LREAL = VAR(0.0)
    t_value: INT = VAR(0)

    @method
    def run(self, n: DINT) -> None:
        for k in range(n):
            self.value = self.value + 2
            self.int = k
            self.t_value = self.value + 1
            self.float = self.float + 0.5


def test_variables_named_as_the_rewrites_names_keep_their_own_values() -> None:
    fb = Named()
    fb.run(10)
    assert (fb.value, fb.int, fb.t_value, fb.float) == (20, 9, 21, 5.0)


# -- random loops: compiled from their source, and run as written ---------------------------------

FIELDS = {"a": ("INT", 16, True), "b": ("USINT", 8, False), "c": ("DINT", 32, True)}
_INT_FIELDS = [f"self.{name}" for name in FIELDS]
_ints = st.one_of(
    st.sampled_from([*_INT_FIELDS, "k", "1", "3", "-7", "250", "70000"]),
    st.builds(lambda a, op, b: f"({a} {op} {b})", st.sampled_from([*_INT_FIELDS, "k"]),
              st.sampled_from(["+", "-", "*", "//", "%"]), st.sampled_from([*_INT_FIELDS, "k", "2", "0", "1000"])),
)
_floats = st.one_of(
    st.sampled_from(["self.d", "0.5", "-0.0", "1e308"]),
    st.builds(lambda a, op, b: f"({a} {op} {b})", st.sampled_from(["self.d", *_INT_FIELDS]),
              st.sampled_from(["+", "-", "*", "/"]), st.sampled_from(["self.d", "0.25", "k", "10.0"])),
)
_bools = st.one_of(
    st.sampled_from(["self.e", "True", "not self.e"]),
    st.builds(lambda a, op, b: f"{a} {op} {b}", _ints, st.sampled_from(["<", ">=", "==", "!="]), _ints),
)


def _statements(depth: int) -> st.SearchStrategy[list[str]]:
    simple = st.one_of(
        st.builds(lambda t, v: [f"{t} = {v}"], st.sampled_from(_INT_FIELDS), _ints),
        st.builds(lambda t, op, v: [f"{t} {op} {v}"], st.sampled_from(_INT_FIELDS), st.sampled_from(["+=", "-=", "*="]), _ints),
        st.builds(lambda v: [f"self.d = {v}"], _floats),
        st.builds(lambda v: [f"self.e = {v}"], st.one_of(_bools, _ints)),
        st.builds(lambda t: [f"{t} = self.d"], st.sampled_from(_INT_FIELDS)),  # refused: a float in an integer
        st.builds(lambda v: [f"t = {v}", "self.c = self.c + t"], _ints),
        st.builds(lambda b: [f"if {b}:", "    break"], _bools),
        st.builds(lambda b: [f"if {b}:", "    continue"], _bools),
    )
    if depth == 0:
        return simple
    inner = st.lists(_statements(depth - 1), min_size=1, max_size=3).map(lambda parts: [s for p in parts for s in p])
    return st.one_of(
        simple,
        st.builds(lambda b, x, y: [f"if {b}:", *("    " + s for s in x), "else:", *("    " + s for s in y)], _bools, inner, inner),
        st.builds(lambda n, x: [f"for j in range({n}):", *("    " + s for s in x)], st.integers(0, 4), inner),
    )


def _block(name: str, body: list[str], filename: str | None) -> type:
    """An FB with the loop as a METHOD, from source registered with linecache (``filename``) or none."""
    lines = [
        f"class {name}(FunctionBlock):",
        "    a: INT = VAR(0)", "    b: USINT = VAR(0)", "    c: DINT = VAR(0)", "    d: LREAL = VAR(0.0)", "    e: BOOL = VAR(False)",
        "    @method",
        "    def run(self, n: DINT) -> None:",
        "        for k in range(n):",
        *("            " + s for s in body),
    ]
    source = "\n".join(lines) + "\n"
    where = filename or f"<loop {name} as written>"
    if filename is not None:
        linecache.cache[filename] = (len(source), None, source.splitlines(True), filename)
    namespace: dict[str, Any] = {"FunctionBlock": FunctionBlock, "VAR": VAR, "method": method, "INT": INT, "USINT": USINT,
                                 "DINT": DINT, "LREAL": LREAL, "BOOL": BOOL, "__name__": "tests.loops"}
    exec(compile(source, where, "exec"), namespace)
    return namespace[name]  # type: ignore[no-any-return]


def _memory(fb: Any) -> list[bytes]:
    return [ctypes.string_at(ctypes.addressof(fb) + getattr(type(fb), f).offset, getattr(type(fb), f).size) for f in "abcde"]


def _outcome(fb: Any, passes: int) -> tuple[str, list[bytes]]:
    try:
        fb.run(passes)
        error = ""
    except (ArithmeticError, TypeError) as exc:
        # checked mode's refusals name the class: the same words for both blocks
        error = f"{type(exc).__name__}: {exc}".replace(type(fb).__name__, "Loop")
    return error, _memory(fb)


_names = itertools.count()


@settings(max_examples=120, deadline=None)
@given(body=st.lists(_statements(2), min_size=1, max_size=4).map(lambda parts: [s for p in parts for s in p]),
       calls=st.lists(st.integers(0, 30), min_size=1, max_size=3))
def test_a_loop_compiled_from_its_source_does_what_it_does_as_written(body: list[str], calls: list[int]) -> None:
    number = next(_names)
    filename = f"<iecoop test loop {number}>"
    try:
        compiled = _block(f"Compiled{number}", body, filename)
    finally:
        linecache.cache.pop(filename, None)
    as_written = _block(f"AsWritten{number}", body, None)
    if not _config.CHECKS:
        assert compiled.__dict__["run"].__code__ is not as_written.__dict__["run"].__code__
    one, other = compiled(), as_written()
    for passes in calls:
        assert _outcome(one, passes) == _outcome(other, passes), "\n".join(body)
