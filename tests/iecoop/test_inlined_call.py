"""The generated call with the body compiled into it: the same behaviour as calling the body, in one frame.

Each block is driven over several calls; where the body cannot be compiled
into the call (no source, a name it shares with an input, a value returned),
the call still runs the body, and both forms must give the same results.
"""

from __future__ import annotations

import enum
import inspect
import linecache
import traceback
from typing import Any

import pytest

from iecoop import (
    ARRAY,
    BOOL,
    DINT,
    INT,
    PRIVATE,
    TIME,
    VAR,
    VAR_IN_OUT,
    VAR_INPUT,
    VAR_OUTPUT,
    AccessError,
    FunctionBlock,
    PlcException,
    T,
    _config,
    adr,
    delete,
    method,
    new,
)
from iecoop.stdlib import R_TRIG, TON

LIMIT = 3


class Counter(FunctionBlock):
    """FB_Counter: counts the calls with enable, wraps as an INT."""

    enable: BOOL = VAR_INPUT(False)
    step: INT = VAR_INPUT(1)
    count: INT = VAR_OUTPUT(0)
    calls: INT = VAR(0)

    def body(self) -> None:
        """The docstring is no statement of the call."""
        self.calls += 1
        if self.enable:
            self.count += self.step


def _is_one_frame(cls: type) -> bool:
    call: Any = cls.__dict__["__call__"]
    body: Any = next(k.__dict__["body"] for k in cls.__mro__ if "body" in k.__dict__)
    return bool(call.__code__.co_filename == body.__code__.co_filename and call.__code__.co_firstlineno == body.__code__.co_firstlineno)


def test_the_body_runs_in_the_call_frame_with_the_inputs_kept_between_calls() -> None:
    assert _is_one_frame(Counter)
    counter = Counter()
    for enable in (True, True, False, True):
        counter(enable=enable)
    counter(step=10)  # enable is kept from the last call
    assert (counter.count, counter.calls, counter.enable, counter.step) == (13, 5, True, 10)
    counter(enable=True, step=32767)
    assert counter.count == 13 + 32767 - 65536  # INT wrap-around at the store


def test_the_call_keeps_its_name_and_refuses_unknown_inputs() -> None:
    assert Counter.__call__.__qualname__ == "Counter.__call__"
    assert Counter.__call__.__name__ == "__call__"
    with pytest.raises(TypeError, match=r"Counter\.__call__\(\) got an unexpected keyword argument 'speed'"):
        Counter()(speed=1)  # type: ignore[call-arg]


def test_a_traceback_shows_the_body_line() -> None:
    class Divider(FunctionBlock):
        divisor: INT = VAR_INPUT(1)
        quotient: INT = VAR_OUTPUT(0)

        def body(self) -> None:
            self.quotient = 100 // self.divisor  # the failing line

    divider = Divider()
    divider(divisor=4)
    assert divider.quotient == 25
    with pytest.raises(ZeroDivisionError) as caught:
        divider(divisor=0)
    last = traceback.extract_tb(caught.value.__traceback__)[-1]
    assert (last.filename, last.name, last.line) == (__file__, "body", "self.quotient = 100 // self.divisor  # the failing line")


def test_closure_variables_are_the_bodys_own_cells() -> None:
    scale = 2

    class Scaler(FunctionBlock):
        value: INT = VAR_INPUT(0)
        result: INT = VAR_OUTPUT(0)

        def body(self) -> None:
            self.result = self.value * scale

    scaler = Scaler()
    scaler(value=5)
    assert scaler.result == 10
    scale = 3  # rebinding the variable is seen by the next call, as by the body itself
    scaler(value=5)
    assert scaler.result == 15
    assert _is_one_frame(Scaler)


def test_super_body_and_a_private_method_of_the_base() -> None:
    class Base(FunctionBlock):
        trips: INT = VAR_OUTPUT(0)

        def body(self) -> None:
            self.bump()

        @method(PRIVATE)
        def bump(self) -> None:
            self.trips += 1

    class Derived(Base):
        extra: INT = VAR_OUTPUT(0)

        def body(self) -> None:
            super().body()
            self.extra += 2

    class Inheriting(Base):
        other: INT = VAR(0)

        @method
        def touch(self) -> None:
            self.other += 1

    derived, inheriting = Derived(), Inheriting()
    for _ in range(LIMIT):
        derived()
        inheriting()
    assert (derived.trips, derived.extra, inheriting.trips) == (LIMIT, 2 * LIMIT, LIMIT)
    assert all(_is_one_frame(c) for c in (Base, Derived, Inheriting))
    with pytest.raises(AccessError, match=r"PRIVATE METHOD Base\.bump"):
        inheriting.bump()


def test_a_body_using_an_input_name_runs_as_its_own_function() -> None:
    class Shadow(FunctionBlock):
        limit: INT = VAR_INPUT(0)
        hits: INT = VAR_OUTPUT(0)

        def body(self) -> None:
            limit = self.limit + 1  # a local named like the input: the call cannot take the body in
            self.hits += limit

    assert not _is_one_frame(Shadow)
    shadow = Shadow()
    shadow(limit=1)
    shadow()
    assert shadow.hits == 4


def test_a_body_returning_a_value_or_without_source_runs_as_its_own_function() -> None:
    class Returning(FunctionBlock):
        count: INT = VAR_OUTPUT(0)

        def body(self) -> Any:
            self.count += 1
            return self.count

    returning = Returning()
    call: Any = returning
    assert call() is None  # the call returns nothing, whatever the body returns
    assert returning.count == 1 and not _is_one_frame(Returning)

    source = "class NoSource(FunctionBlock):\n    count: INT = VAR_OUTPUT(0)\n    def body(self) -> None:\n        self.count += 1\n"
    namespace: dict[str, Any] = {"FunctionBlock": FunctionBlock, "INT": INT, "VAR_OUTPUT": VAR_OUTPUT, "__name__": __name__}
    exec(compile(source, "<iecoop test: no source>", "exec"), namespace)  # noqa: S102 - a class without source
    no_source = namespace["NoSource"]()
    no_source()
    no_source()
    assert no_source.count == 2 and not _is_one_frame(namespace["NoSource"])


def test_source_that_no_longer_matches_the_running_code_is_not_compiled_in() -> None:
    filename = "<iecoop test: edited source>"
    source = "class Edited(FunctionBlock):\n    count: INT = VAR_OUTPUT(0)\n    def body(self) -> None:\n        self.count += 1\n"
    namespace: dict[str, Any] = {"FunctionBlock": FunctionBlock, "INT": INT, "VAR_OUTPUT": VAR_OUTPUT, "__name__": __name__}
    # The source linecache holds says "+= 5": the class's real code adds 1, so the call keeps the real body.
    edited = source.replace("+= 1", "+= 5")
    linecache.cache[filename] = (len(edited), None, edited.splitlines(True), filename)
    try:
        exec(compile(source, filename, "exec"), namespace)  # noqa: S102 - code whose registered source differs
    finally:
        del linecache.cache[filename]
    block = namespace["Edited"]()
    block()
    assert block.count == 1 and not _is_one_frame(namespace["Edited"])


def test_the_call_code_counts_as_the_blocks_own() -> None:
    code = Counter.__call__.__code__
    assert code in Counter._iec_codes_
    assert inspect.getsource(Counter.__call__).lstrip().startswith("def body(self) -> None:")


@pytest.mark.skipif(not _config.CHECKS, reason="checked mode checks the kind of a written value")
def test_checked_mode_writes_in_the_body_keep_their_checks() -> None:
    class Writer(FunctionBlock):
        value: INT = VAR_INPUT(0)
        kept: INT = VAR_OUTPUT(0)
        flag: BOOL = VAR(False)
        limit: INT = VAR(10, constant=True)

        def body(self) -> None:
            self.kept = self.value * 1000  # wraps as an INT
            self.flag = self.value > 0
            if self.value < 0:
                self.kept = "text"  # type: ignore[assignment]
            if self.value > 100:
                self.limit = 3

    writer = Writer()
    writer(value=40)
    assert (writer.kept, writer.flag) == (40000 - 65536, True)
    with pytest.raises(TypeError, match=r"Writer\.kept: cannot store str 'text' in INT"):
        writer(value=-1)
    with pytest.raises(AccessError, match=r"Writer\.limit is CONSTANT"):
        writer(value=101)
    with pytest.raises(AccessError, match=r"VAR_OUTPUT Writer\.kept cannot be written from"):
        writer.kept = 1


def test_the_body_runs_one_frame_below_the_caller() -> None:
    frame_count: list[int] = []

    class Depth(FunctionBlock):
        depth: INT = VAR_OUTPUT(0)

        def body(self) -> None:
            frame_count.append(len(inspect.stack(0)))
            self.depth = 1

    depth = Depth()
    depth()
    here = len(inspect.stack(0))
    assert frame_count == [here + 1]  # the body runs one frame below the caller


_LITERAL_SOURCE = '''
class Delay(FunctionBlock):
    run: BOOL = VAR_INPUT(False)
    preset: TIME = VAR_OUTPUT(0)
    timer: TON = VAR()

    def body(self) -> None:
        self.timer(IN=self.run, PT=T("200ms"))
        self.preset = self.timer.PT
'''


def _module_with_source(source: str, filename: str) -> dict[str, Any]:
    """Run ``source`` as a module whose lines linecache knows (as a file's would be)."""
    linecache.cache[filename] = (len(source), None, source.splitlines(True), filename)
    namespace: dict[str, Any] = {
        "FunctionBlock": FunctionBlock, "BOOL": BOOL, "TIME": TIME, "VAR_INPUT": VAR_INPUT, "VAR_OUTPUT": VAR_OUTPUT,
        "VAR": VAR, "TON": TON, "T": T, "__name__": "literal_module",
    }
    exec(compile(source, filename, "exec"), namespace)  # noqa: S102 - a module whose source linecache holds
    return namespace


def test_a_time_literal_in_the_body_is_read_once_and_follows_its_name() -> None:
    filename = "<iecoop test: literal module>"
    try:
        module = _module_with_source(_LITERAL_SOURCE, filename)
        delay = module["Delay"]()
        assert _is_one_frame(module["Delay"])
        assert "_iec_w_literal_T" in module["Delay"].__call__.__code__.co_freevars
        delay(run=True)
        assert (delay.preset, delay.timer.PT) == (200, 200)
        module["T"] = lambda text: 7  # the module rebinds T: the call uses the module's T, as the body would
        delay(run=True)
        assert delay.preset == 7
    finally:
        del linecache.cache[filename]


def test_a_refused_literal_still_fails_at_the_call() -> None:
    filename = "<iecoop test: bad literal module>"
    try:
        module = _module_with_source(_LITERAL_SOURCE.replace('"200ms"', '"200 parsecs"'), filename)
        with pytest.raises(ValueError, match="200 parsecs"):
            module["Delay"]()(run=True)
    finally:
        del linecache.cache[filename]


def test_a_member_read_in_the_body_and_after_delete() -> None:
    class Edge(FunctionBlock):
        clk: BOOL = VAR_INPUT(False)
        rising: INT = VAR_OUTPUT(0)
        trig: R_TRIG = VAR()

        def body(self) -> None:
            self.trig(CLK=self.clk)
            if self.trig.Q:
                self.rising += 1

    edge = Edge()
    for clk in (True, False, True, True, False, True):
        edge(clk=clk)
    assert (edge.rising, edge.trig.M) == (3, True)
    assert "_iec_m_0trig" in Edge.__call__.__code__.co_names  # the member's kept view, an instance attribute
    assert edge.__dict__["_iec_m_0trig"] is edge.trig  # the view the member's property returns
    pointer = new(Edge)
    block = pointer.deref
    block(clk=True)
    delete(pointer)
    for key in ("_iec_m_0trig", "_iec_m_trig"):  # what the compiled call reads for self.trig, and the alias
        with pytest.raises(PlcException, match=r"'trig' read of a deleted Edge") as caught:
            getattr(block, key)
        assert caught.value.code.name == "RTSEXCPT_ACCESS_VIOLATION"


_SHADOW_SOURCE = """
AttributeError = None  # the module's own name: the call must still catch the builtin


class Pulse(FunctionBlock):
    run: BOOL = VAR_INPUT(False)
    timer: TON = VAR()

    def body(self) -> None:
        self.timer(IN=self.run, PT=T("20ms"))
"""


def test_member_views_are_kept_at_the_first_call_whatever_the_module_names() -> None:
    filename = "<iecoop test: shadowing module>"
    try:
        module = _module_with_source(_SHADOW_SOURCE, filename)
        pulse = module["Pulse"]()
        assert "_iec_m_0timer" not in pulse.__dict__
        pulse(run=True)  # the first call keeps the view, although the module's AttributeError is None
        assert pulse.__dict__["_iec_m_0timer"] is pulse.timer and pulse.timer.IN is True
        pulse(run=False)
        assert pulse.timer.IN is False
    finally:
        del linecache.cache[filename]


def test_a_member_call_runs_the_members_call_as_python_finds_it() -> None:
    class Pulse(FunctionBlock):
        go: BOOL = VAR_INPUT(False)
        count: INT = VAR_OUTPUT(0)

        def body(self) -> None:
            if self.go:
                self.count += 1

    class Holder(FunctionBlock):
        go: BOOL = VAR_INPUT(False)
        inner: Pulse = VAR()

        def body(self) -> None:
            self.inner(go=self.go)
            self.inner(**{"go": self.go})

    holder = Holder()
    holder(go=True)
    assert holder.inner.count == 2
    assert "_iec_w_call_inner" in Holder.__call__.__code__.co_freevars
    original = Pulse.__call__
    seen: list[bool] = []

    def replaced(self: Any, *, go: bool = False) -> None:
        seen.append(go)

    Pulse.__call__ = replaced  # type: ignore[method-assign, assignment]
    try:
        holder(go=True)  # the class's __call__ is no longer the one found at build: Python's call finds the new one
    finally:
        Pulse.__call__ = original  # type: ignore[method-assign]
    assert seen == [True, True] and holder.inner.count == 2
    holder(go=True)
    assert holder.inner.count == 4
    del Pulse.__call__  # no __call__ left on the class: a view of it is not callable, as Python says
    with pytest.raises(TypeError, match="'Pulse' object is not callable"):
        holder(go=True)
    setattr(Pulse, "__call__", replaced)  # rebound before a holder is built: that holder calls the new one too

    class Later(FunctionBlock):
        inner: Pulse = VAR()

        def body(self) -> None:
            self.inner(go=True)

    later = Later()
    later()
    assert seen == [True, True, True] and later.inner.count == 0
    Pulse.__call__ = original  # type: ignore[method-assign]
    later()
    holder(go=False)
    assert later.inner.count == 1 and holder.inner.count == 4 and holder.inner.go is False


class Mixer(FunctionBlock):
    """Three inputs and an in-out: a member call may give any of the inputs, in any order."""

    a: INT = VAR_INPUT(0)
    b: INT = VAR_INPUT(0)
    c: INT = VAR_INPUT(0)
    total: INT = VAR_IN_OUT()

    def body(self) -> None:
        self.total = self.a * 100 + self.b * 10 + self.c


class Station(FunctionBlock):
    """Calls its Mixer with the keywords in the declared order, with gaps, and out of order."""

    step: INT = VAR_INPUT(0)
    total: INT = VAR_OUTPUT(0)
    mixer: Mixer = VAR()

    def body(self) -> None:
        if self.step == 1:
            self.mixer(a=1, c=3, total=adr(self, "total"))  # in order, b not given: kept from the last call
        elif self.step == 2:
            self.mixer(c=note(7), a=note(5), total=adr(self, "total"))  # out of order: evaluated as written
        elif self.step == 3:
            self.mixer(b=2)  # type: ignore[call-arg]  # no in-out: refused as the call refuses it


_noted: list[int] = []


def note(value: int) -> int:
    _noted.append(value)
    return value


def test_member_call_inputs_by_position_or_as_written() -> None:
    station = Station()
    code = Station.__call__.__code__
    assert {"_iec_w_position_mixer", "_iec_w_call_mixer"} <= set(code.co_freevars)
    station.mixer(b=4, total=adr(station, "total"))
    station(step=1)
    assert (station.total, station.mixer.b) == (143, 4)
    _noted.clear()
    station(step=2)
    assert (station.total, _noted) == (547, [7, 5])
    with pytest.raises(TypeError, match=r"Mixer: VAR_IN_OUT 'total' must be assigned at every call"):
        station(step=3)
    seen: list[dict[str, Any]] = []
    original = Mixer.__call__

    def replaced(self: Any, **inputs: Any) -> None:
        seen.append(inputs)

    Mixer.__call__ = replaced  # type: ignore[method-assign]
    try:
        station(step=1)
        station(step=3)
    finally:
        Mixer.__call__ = original  # type: ignore[method-assign]
    # Rebound: the new __call__ gets the inputs given, by name, and nothing for those not given.
    assert [sorted(inputs) for inputs in seen] == [["a", "c", "total"], ["b"]]
    station(step=1)
    assert station.total == 123 and station.mixer.b == 2


def test_a_member_call_refuses_what_the_call_refuses() -> None:
    class Inner(FunctionBlock):
        go: BOOL = VAR_INPUT(False)

    class Bad(FunctionBlock):
        inner: Inner = VAR()
        positional: BOOL = VAR_INPUT(False)

        def body(self) -> None:
            if self.positional:
                self.inner(True)  # type: ignore[call-arg]
            else:
                self.inner(speed=1)  # type: ignore[call-arg]

    with pytest.raises(TypeError, match=r"Inner\.__call__\(\) got an unexpected keyword argument 'speed'"):
        Bad()()
    with pytest.raises(TypeError, match=r"Inner\.__call__\(\) takes 1 positional argument but 2 were given"):
        Bad()(positional=True)


@pytest.mark.skipif(not _config.CHECKS, reason="checked mode checks the kind of a written value")
def test_checked_mode_chained_writes_assign_every_target() -> None:
    class Chain(FunctionBlock):
        value: INT = VAR_INPUT(0)
        first: INT = VAR_OUTPUT(0)
        second: INT = VAR_OUTPUT(0)
        copy: INT = VAR_OUTPUT(0)

        def body(self) -> None:
            self.first = local = self.second = self.value * 2
            self.copy = local
            if self.value < 0:
                self.first = kept = "text"  # type: ignore[assignment]
                self.copy = len(kept)

    chain = Chain()
    chain(value=20000)
    assert (chain.first, chain.second, chain.copy) == (40000 - 65536,) * 3
    with pytest.raises(TypeError, match=r"Chain\.first: cannot store str 'text' in INT"):
        chain(value=-1)
    assert (chain.first, chain.second) == (-2, -2)  # the targets before the refused one were written


class Cell(FunctionBlock):
    """One cell of a Grid: counts its calls with go."""

    go: BOOL = VAR_INPUT(False)
    count: INT = VAR_OUTPUT(0)

    def body(self) -> None:
        if self.go:
            self.count += 1


class Slot(enum.IntEnum):
    FIRST = 2
    LAST = 4


class Grid(FunctionBlock):
    """``cells : ARRAY[2..4] OF Cell;`` called and read in a loop from the body, indexed by ``at``."""

    at: DINT = VAR_INPUT(2)
    cells: ARRAY[Cell] = VAR(bounds=(2, 4))
    total: DINT = VAR_OUTPUT(0)

    def body(self) -> None:
        for i in range(2, 5):
            self.cells[i](go=i >= self.at)
        self.total = self.cells[2].count + self.cells[3].count + self.cells[4].count
        for index in _grid_index:
            self.cells[index](go=True)


#: An index of another kind than an int the body also uses, set by the test.
_grid_index: list[Any] = []


def test_an_array_of_blocks_is_indexed_in_place_with_the_bounds_checked() -> None:
    grid = Grid()
    grid(at=3)
    grid(at=2)
    assert [cell.count for cell in grid.cells] == [1, 2, 2]
    assert grid.total == 5
    assert "_iec_m_elements" in Grid.__call__.__code__.co_names  # the element views read in place
    cells = grid.cells
    assert all(cell is cells[i] for i, cell in zip(range(2, 5), cells))  # iterating gives the kept element views
    try:
        _grid_index[:] = [Slot.LAST]  # an enumeration value indexes by its number
        grid(at=5)
        assert grid.cells[4].count == 3
        for bad in (1, 5, True, 3.0):
            _grid_index[:] = [bad]
            with pytest.raises(PlcException, match=r"index .* outside ARRAY\[2\.\.4\] OF Cell") as caught:
                grid(at=5)
            assert caught.value.code.name == "RTSEXCPT_ARRAYBOUNDS"
    finally:
        _grid_index.clear()
    assert [cell.count for cell in grid.cells] == [1, 2, 3]


def test_an_array_element_call_evaluates_the_index_before_the_inputs() -> None:
    order: list[str] = []

    def seen(label: str, value: Any) -> Any:
        order.append(label)
        return value

    class Caller(FunctionBlock):
        cells: ARRAY[Cell] = VAR(bounds=(1, 2))

        def body(self) -> None:
            self.cells[seen("index", 2)](go=seen("input", True))

    caller = Caller()
    caller()
    assert order == ["index", "input"]
    assert [cell.count for cell in caller.cells] == [0, 1]
