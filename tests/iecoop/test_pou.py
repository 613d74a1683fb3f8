"""Declaring and calling function blocks and programs, checked across several calls (cycles).

The blocks are written as a PLC programmer would write them; each test drives
them for a number of calls and compares with what the PLC would hold after
those cycles.
"""

from __future__ import annotations

from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from iecoop import (
    ARRAY,
    BOOL,
    DINT,
    INT,
    LREAL,
    POINTER_TO,
    REAL,
    REFERENCE_TO,
    STRING,
    VAR,
    VAR_IN_OUT,
    VAR_INPUT,
    VAR_INST,
    VAR_OUTPUT,
    VAR_STAT,
    VAR_TEMP,
    AccessError,
    ExceptionCode,
    FunctionBlock,
    PlcException,
    Program,
    Struct,
    adr,
    method,
    prop,
    ref_assign,
)
from iecoop.testing.strategies import BOOL_VALUES, DINT_VALUES, INT_VALUES, REAL_VALUES, string_values, wrap_int
from tests import checked_only


class Counter(FunctionBlock):
    """FB_Counter: ``IF enable THEN count := count + step; END_IF``; FB_init may preset the count."""

    enable: BOOL = VAR_INPUT(False)
    step: INT = VAR_INPUT(1)
    count: INT = VAR_OUTPUT(0)
    calls: DINT = VAR(0)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, start: INT = 0) -> BOOL:
        self.count = start
        return True

    def body(self) -> None:
        self.calls += 1
        if self.enable:
            self.count += self.step


# ---------------------------------------------------------------------------
# Inputs and outputs
# ---------------------------------------------------------------------------


def test_inputs_set_by_the_call_drive_the_outputs_cycle_after_cycle() -> None:
    counter = Counter()
    seen = []
    for enable in (True, True, False, True, False, False, True):
        counter(enable=enable)
        seen.append(counter.count)
    assert seen == [1, 2, 2, 3, 3, 3, 4]
    assert counter.calls == 7


def test_an_input_keeps_its_value_until_a_call_sets_it_again() -> None:
    counter = Counter()
    counter(enable=True, step=5)
    counter()
    counter()
    assert counter.count == 15
    assert counter.enable is True and counter.step == 5
    counter(enable=False)
    counter()
    assert counter.count == 15


def test_inputs_can_also_be_written_between_calls() -> None:
    counter = Counter()
    counter.enable = True
    counter.step = 3
    counter()
    counter()
    assert counter.count == 6


def test_the_output_wraps_like_an_int_on_the_plc() -> None:
    counter = Counter(start=32766)
    counter(enable=True)
    assert counter.count == 32767
    counter()
    assert counter.count == -32768
    counter(step=-1)
    assert counter.count == 32767


def test_unknown_input_name_is_a_type_error_naming_block_and_input() -> None:
    counter = Counter()
    with pytest.raises(TypeError, match=r"Counter.*'enabel'"):
        counter(enabel=True)  # type: ignore[call-arg]
    assert counter.calls == 0


@pytest.mark.parametrize(
    ("inputs", "pattern"),
    [
        ({"enable": 1}, r"Counter\.enable: cannot store int 1 in BOOL"),
        ({"enable": "yes"}, r"Counter\.enable: cannot store str 'yes' in BOOL"),
        ({"step": 1.5}, r"Counter\.step: cannot store float 1\.5 in INT"),
        ({"step": True}, r"Counter\.step: cannot store bool True in INT"),
        ({"step": "2"}, r"Counter\.step: cannot store str '2' in INT"),
    ],
)
@checked_only
def test_wrong_typed_input_is_a_type_error_and_the_body_does_not_run(inputs: dict[str, Any], pattern: str) -> None:
    counter = Counter()
    counter(enable=True)
    with pytest.raises(TypeError, match=pattern):
        counter(**inputs)
    assert counter.calls == 1
    assert counter.count == 1
    assert counter.enable is True and counter.step == 1


def test_inputs_are_passed_by_name_only() -> None:
    counter = Counter()
    with pytest.raises(TypeError, match="positional"):
        counter(True)  # type: ignore[call-arg]
    assert counter.calls == 0


def test_an_fb_without_inputs_is_still_callable_and_rejects_any_input() -> None:
    class Ticker(FunctionBlock):
        ticks: DINT = VAR_OUTPUT(0)

        def body(self) -> None:
            self.ticks += 1

    ticker = Ticker()
    for _ in range(4):
        ticker()
    assert ticker.ticks == 4
    with pytest.raises(TypeError, match=r"Ticker.*'start'"):
        ticker(start=True)  # type: ignore[call-arg]


# ---------------------------------------------------------------------------
# VAR_IN_OUT and REFERENCE_TO inputs: bound at the call
# ---------------------------------------------------------------------------


class Recipe(Struct):
    temperature: REAL = 20.0
    steps: INT = 0


class Accumulate(FunctionBlock):
    """``VAR_IN_OUT values : ARRAY[1..4] OF INT; recipe : ST_Recipe;``: both read and written through."""

    values: ARRAY[INT] = VAR_IN_OUT(bounds=(1, 4))
    recipe: Recipe = VAR_IN_OUT()
    total: DINT = VAR_OUTPUT(0)
    heat: REAL = VAR_OUTPUT(0.0)

    def body(self) -> None:
        self.total = sum(self.values)
        self.values[1] += 1
        self.recipe.steps += 1
        self.heat = self.recipe.temperature


class Cell(FunctionBlock):
    # VAR()'s overloads type a list / dict initial value as itself, not as the ARRAY / struct it fills.
    data: ARRAY[INT] = VAR([0, 10, 20, 30], bounds=(1, 4))
    recipe: Recipe = VAR({"temperature": 180.0})
    worker: Accumulate = VAR()

    def body(self) -> None:
        self.worker(values=adr(self, "data"), recipe=self.recipe)


def test_var_in_out_bound_with_adr_and_a_struct_reads_and_writes_the_callers_data() -> None:
    cell = Cell()
    totals = []
    for _ in range(3):
        cell()
        totals.append(cell.worker.total)
    assert totals == [60, 61, 62]
    assert list(cell.data) == [3, 10, 20, 30]
    assert cell.recipe.steps == 3
    assert cell.worker.heat == 180.0


def test_var_in_out_from_outside_with_a_standalone_struct_and_array_holder() -> None:
    class Buffer(Struct):
        items: ARRAY[INT] = VAR([1, 2, 3, 4], bounds=(1, 4))

    buffer, recipe = Buffer(), Recipe(temperature=55.5)
    acc = Accumulate()
    acc(values=adr(buffer, "items"), recipe=recipe)
    acc(values=adr(buffer, "items"), recipe=recipe)
    assert acc.total == 11
    assert list(buffer.items) == [3, 2, 3, 4]
    assert recipe.steps == 2
    assert acc.heat == 55.5


def test_var_in_out_is_rebound_at_every_call() -> None:
    first, second = Recipe(), Recipe(temperature=99.0)
    buffer = Cell()
    acc = Accumulate()
    acc(values=adr(buffer, "data"), recipe=first)
    acc(values=adr(buffer, "data"), recipe=second)
    acc(values=adr(buffer, "data"), recipe=second)
    assert (first.steps, second.steps) == (1, 2)
    assert acc.heat == 99.0


def test_var_in_out_missing_at_a_call_is_an_error_even_after_an_earlier_binding() -> None:
    cell = Cell()
    acc = Accumulate()
    acc(values=adr(cell, "data"), recipe=cell.recipe)
    with pytest.raises(TypeError, match=r"Accumulate: VAR_IN_OUT 'recipe' must be assigned at every call"):
        acc(values=adr(cell, "data"))  # type: ignore[call-arg]
    with pytest.raises(TypeError, match=r"Accumulate: VAR_IN_OUT 'values' must be assigned at every call"):
        acc(recipe=cell.recipe)  # type: ignore[call-arg]
    assert cell.recipe.steps == 1
    assert list(cell.data) == [1, 10, 20, 30]


def test_var_in_out_bound_to_the_wrong_type_is_rejected() -> None:
    cell = Cell()
    acc = Accumulate()
    with pytest.raises(TypeError, match=r"Accumulate\.recipe: cannot store Cell"):
        acc(values=adr(cell, "data"), recipe=cell)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=r"Accumulate\.recipe: REF= to INT does not fit REFERENCE TO Recipe"):
        acc(values=adr(cell, "data"), recipe=adr(cell, "data", 1))
    assert cell.recipe.steps == 0


class Tally(FunctionBlock):
    """``VAR_INPUT target : REFERENCE TO INT; END_VAR  target := target + amount;``"""

    target: REFERENCE_TO[INT] = VAR_INPUT()
    amount: INT = VAR_INPUT(1)

    def body(self) -> None:
        self.target = self.target + self.amount


class Box(Struct):
    a: INT = 0
    b: INT = 0


def test_reference_input_is_bound_by_the_call_and_writes_through() -> None:
    box = Box()
    tally = Tally()
    tally(target=adr(box, "a"))
    tally()
    tally(amount=10)
    assert (box.a, box.b) == (12, 0)
    tally(target=adr(box, "b"), amount=5)
    tally()
    assert (box.a, box.b) == (12, 10)
    assert tally.target == 10


def test_reference_input_never_bound_is_an_access_violation_when_used() -> None:
    tally = Tally()
    with pytest.raises(PlcException, match="not bound") as info:
        tally()
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


# ---------------------------------------------------------------------------
# VAR_TEMP, VAR_STAT, VAR_INST, CONSTANT
# ---------------------------------------------------------------------------


def test_var_temp_is_reinitialised_at_every_call() -> None:
    class Scratch(FunctionBlock):
        t: INT = VAR_TEMP(5)
        buf: ARRAY[INT] = VAR_TEMP(bounds=(0, 2))
        text: STRING = VAR_TEMP("abc", length=10)
        seen: INT = VAR_OUTPUT(0)
        seen_text: STRING = VAR_OUTPUT("", length=10)

        def body(self) -> None:
            self.seen = self.t + self.buf[1]
            self.seen_text = self.text
            self.t += 100
            self.buf[1] = 7
            self.text = "changed"

    scratch = Scratch()
    for _ in range(3):
        scratch()
        assert scratch.seen == 5
        assert scratch.seen_text == "abc"


def test_var_stat_is_shared_by_every_instance_of_the_class_and_separate_per_class() -> None:
    class Station(FunctionBlock):
        created: INT = VAR_STAT(0)
        ticket: INT = VAR_OUTPUT(0)

        def body(self) -> None:
            self.created += 1
            self.ticket = self.created

    class Other(FunctionBlock):
        created: INT = VAR_STAT(100)

        def body(self) -> None:
            self.created += 1

    a, b, other = Station(), Station(), Other()
    a()
    b()
    a()
    other()
    assert (a.ticket, b.ticket) == (3, 2)
    assert a.created == b.created == 3
    assert other.created == 101
    Station()()
    assert a.created == 4


@checked_only
def test_var_stat_is_not_writable_from_outside() -> None:
    class Station(FunctionBlock):
        created: INT = VAR_STAT(0)

    station = Station()
    with pytest.raises(AccessError, match=r"VAR_STAT Station\.created cannot be written from"):
        station.created = 5
    assert station.created == 0


class Doser(FunctionBlock):
    doses: INT = VAR_INST(0, method="dose")
    volume: LREAL = VAR_OUTPUT(0.0)

    @method
    def dose(self, amount: LREAL) -> INT:
        self.doses += 1
        self.volume += amount
        return self.doses

    @method
    def reset_from_other_method(self) -> None:
        self.doses = 0

    def body(self) -> None:
        self.doses = 0


def test_var_inst_is_kept_between_calls_of_its_method_per_instance() -> None:
    a, b = Doser(), Doser()
    assert [a.dose(1.0), a.dose(2.0), a.dose(0.5)] == [1, 2, 3]
    assert b.dose(4.0) == 1
    assert (a.doses, a.volume, b.doses) == (3, 3.5, 1)


@checked_only
def test_var_inst_is_written_only_by_its_method() -> None:
    doser = Doser()
    doser.dose(1.0)
    with pytest.raises(AccessError, match=r"VAR_INST Doser\.doses belongs to METHOD dose \(C0576\)"):
        doser.reset_from_other_method()
    with pytest.raises(AccessError, match=r"VAR_INST Doser\.doses belongs to METHOD dose"):
        doser()
    with pytest.raises(AccessError, match=r"VAR_INST Doser\.doses cannot be written from"):
        doser.doses = 7
    assert doser.doses == 1


@checked_only
def test_constant_is_readable_and_never_writable() -> None:
    class Limiter(FunctionBlock):
        LIMIT: INT = VAR(10, constant=True)
        request: INT = VAR_INPUT(0)
        out: INT = VAR_OUTPUT(0)

        def body(self) -> None:
            self.out = min(self.request, self.LIMIT)

        @method
        def raise_limit(self) -> None:
            self.LIMIT = 20

    limiter = Limiter()
    limiter(request=5)
    assert limiter.out == 5
    limiter(request=50)
    assert limiter.out == 10
    with pytest.raises(AccessError, match=r"Limiter\.LIMIT is CONSTANT and cannot be written"):
        limiter.raise_limit()
    with pytest.raises(AccessError, match=r"Limiter\.LIMIT is CONSTANT"):
        limiter.LIMIT = 30
    limiter(request=50)
    assert limiter.out == 10 and limiter.LIMIT == 10


@checked_only
def test_var_in_out_constant_is_read_only_inside() -> None:
    class Reader(FunctionBlock):
        limit: INT = VAR_IN_OUT(constant=True)
        seen: INT = VAR_OUTPUT(0)
        write: BOOL = VAR_INPUT(False)

        def body(self) -> None:
            self.seen = self.limit
            if self.write:
                self.limit = 0

    box = Box(a=42)
    reader = Reader()
    reader(limit=adr(box, "a"))
    assert reader.seen == 42
    with pytest.raises(AccessError, match=r"Reader\.limit is CONSTANT"):
        reader(limit=adr(box, "a"), write=True)
    assert box.a == 42


# ---------------------------------------------------------------------------
# Composition: nested FBs and ARRAY OF FB live inline in the parent
# ---------------------------------------------------------------------------


class Line(FunctionBlock):
    feeder: Counter = VAR()
    stations: ARRAY[Counter] = VAR(bounds=(1, 3))
    preset: Counter = VAR({"enable": True, "step": 2})

    def body(self) -> None:
        self.feeder(enable=True)
        for i in range(1, 4):
            self.stations[i](enable=i != 2, step=i)
        self.preset()


def test_nested_blocks_and_arrays_of_blocks_keep_their_state_across_calls() -> None:
    line = Line()
    for _ in range(4):
        line()
    assert line.feeder.count == 4
    assert [s.count for s in line.stations] == [4, 0, 12]
    assert [s.calls for s in line.stations] == [4, 4, 4]
    assert line.preset.count == 8


def test_views_of_the_same_nested_instance_are_equal_and_share_the_address() -> None:
    line = Line()
    first, second = line.feeder, line.feeder
    assert first == second
    assert adr(first) == adr(second) == adr(line, "feeder")
    assert line.stations[2] == line.stations[2]
    assert adr(line.stations[2]) == adr(line.stations, 2)
    assert line.stations[1] != line.stations[2]
    assert line.feeder != line.preset
    assert hash(first) == hash(second)
    first(enable=True)
    assert second.count == 1
    assert line.feeder.count == 1


def test_two_separate_parents_do_not_share_their_members() -> None:
    a, b = Line(), Line()
    a()
    a()
    b()
    assert (a.feeder.count, b.feeder.count) == (2, 1)
    assert a.feeder != b.feeder


@checked_only
def test_a_nested_block_cannot_be_replaced_from_outside() -> None:
    line = Line()
    with pytest.raises(AccessError, match=r"VAR Line\.feeder cannot be written from"):
        line.feeder = Counter()


# ---------------------------------------------------------------------------
# Inheritance of the body: super().body() is SUPER^()
# ---------------------------------------------------------------------------


class Axis(FunctionBlock):
    moves: INT = VAR_OUTPUT(0)

    def body(self) -> None:
        self.moves += 1


class ServoAxis(Axis):
    ticks: INT = VAR_OUTPUT(0)

    def body(self) -> None:
        super().body()
        self.ticks = self.moves * 10


class QuietAxis(Axis):
    pass


def test_super_body_runs_the_base_body_every_cycle() -> None:
    servo = ServoAxis()
    for cycle in range(1, 5):
        servo()
        assert (servo.moves, servo.ticks) == (cycle, cycle * 10)


def test_a_derived_block_without_a_body_runs_the_base_body() -> None:
    quiet = QuietAxis()
    quiet()
    quiet()
    assert quiet.moves == 2


# ---------------------------------------------------------------------------
# Properties and methods
# ---------------------------------------------------------------------------


class Gearbox(FunctionBlock):
    gear_internal: INT = VAR(1)
    changes: INT = VAR_OUTPUT(0)
    ratio_table: ARRAY[REAL] = VAR([3.5, 2.0, 1.25, 1.0], bounds=(1, 4))

    @prop
    def gear(self) -> INT:
        return self.gear_internal

    @gear.setter
    def gear(self, value: INT) -> None:
        self.gear_internal = max(1, min(4, value))
        self.changes += 1

    @prop
    def ratio(self) -> REAL:
        return self.ratio_table[self.gear_internal]

    @method
    def shift(self, up: BOOL = True, steps: INT = 1) -> INT:
        self.gear = self.gear + (steps if up else -steps)
        return self.gear

    @method
    def output_speed(self, input_speed: LREAL) -> LREAL:
        return input_speed / self.ratio


def test_property_get_and_set_across_calls() -> None:
    box = Gearbox()
    assert box.gear == 1 and box.ratio == 3.5
    box.gear = 3
    assert box.gear == 3 and box.ratio == 1.25
    box.gear = 9
    assert box.gear == 4
    assert box.changes == 2


def test_read_only_property_cannot_be_set() -> None:
    box = Gearbox()
    with pytest.raises(AttributeError, match="ratio"):
        box.ratio = 2.0  # type: ignore[misc]
    assert box.ratio == 3.5


@checked_only
def test_property_setter_writes_the_typed_variable_with_its_checks() -> None:
    box = Gearbox()
    with pytest.raises(TypeError, match=r"Gearbox\.gear_internal: cannot store float"):
        box.gear = 2.5  # type: ignore[assignment]
    assert box.gear == 1


def test_methods_with_defaults_positional_and_named_arguments_and_return_values() -> None:
    box = Gearbox()
    assert box.shift() == 2
    assert box.shift(True, 2) == 4
    assert box.shift(up=False) == 3
    assert box.shift(steps=2, up=False) == 1
    assert box.shift(False) == 1
    assert box.changes == 5
    assert box.output_speed(700.0) == 200.0
    assert box.output_speed(input_speed=350.0) == 100.0


def test_method_called_with_too_many_or_unknown_arguments() -> None:
    box = Gearbox()
    with pytest.raises(TypeError, match="positional argument"):
        box.shift(True, 1, 3)  # type: ignore[call-arg]
    with pytest.raises(TypeError, match="'gear'"):
        box.shift(gear=2)  # type: ignore[call-arg]
    assert box.gear == 1


# ---------------------------------------------------------------------------
# PROGRAM
# ---------------------------------------------------------------------------


class Shape(FunctionBlock):
    @method
    def kind(self) -> STRING:
        return "shape"


class Circle(Shape):
    @method
    def kind(self) -> STRING:
        return "circle"


class Drawing(FunctionBlock):
    p: POINTER_TO[Shape] = VAR_INPUT()
    r: REFERENCE_TO[Shape] = VAR_INPUT()
    circle: Circle = VAR()
    shape: Shape = VAR()


def test_pointer_and_reference_to_a_base_block_call_the_derived_method() -> None:
    """POINTER TO / REFERENCE TO FB_Shape aimed at an FB_Circle: p^.Kind() is the circle's (virtual call)."""
    drawing = Drawing()
    drawing.p = adr(drawing, "circle")
    ref_assign(drawing, "r", drawing.circle)
    assert type(drawing.p.deref) is Circle
    assert drawing.p.deref.kind() == "circle"
    assert drawing.r.kind() == "circle"
    drawing.p = adr(drawing, "shape")
    ref_assign(drawing, "r", drawing.shape)
    assert drawing.p.deref.kind() == "shape"
    assert drawing.r.kind() == "shape"


class Main(Program):
    cycle: DINT = VAR(0)
    line: Line = VAR()
    box: Gearbox = VAR()
    log: ARRAY[INT] = VAR(bounds=(1, 5))

    def body(self) -> None:
        self.cycle += 1
        self.line()
        if self.cycle % 2 == 0:
            self.box.shift()
        self.log[self.cycle] = self.line.feeder.count * 100 + self.box.gear


def test_a_program_runs_its_body_and_its_members_every_cycle() -> None:
    main = Main()
    for _ in range(5):
        main()
    assert main.cycle == 5
    assert list(main.log) == [101, 202, 302, 403, 503]
    assert main.line.stations[3].count == 15


@checked_only
def test_a_program_variable_is_not_writable_from_outside() -> None:
    main = Main()
    with pytest.raises(AccessError, match=r"VAR Main\.cycle cannot be written from"):
        main.cycle = 4


def test_program_log_index_outside_its_bounds_faults_in_cycle_six() -> None:
    main = Main()
    for _ in range(5):
        main()
    with pytest.raises(PlcException) as info:
        main()
    assert info.value.code == ExceptionCode.RTSEXCPT_ARRAYBOUNDS


# ---------------------------------------------------------------------------
# Property tests of the call semantics
# ---------------------------------------------------------------------------


@given(start=INT_VALUES, enables=st.lists(BOOL_VALUES, max_size=60))
def test_counter_matches_a_model_with_int_wrap_around(start: int, enables: list[bool]) -> None:
    counter = Counter(start=start)
    model = start
    for enable in enables:
        counter(enable=enable)
        if enable:
            model = wrap_int(model + 1)
        assert counter.count == model
    assert counter.calls == len(enables)


@given(start=st.integers(32700, 32767), enables=st.lists(BOOL_VALUES, min_size=60, max_size=120))
def test_counter_near_the_top_of_int_wraps_to_the_bottom(start: int, enables: list[bool]) -> None:
    counter = Counter(start=start)
    for enable in enables:
        counter(enable=enable)
    assert counter.count == wrap_int(start + sum(enables))


@given(steps=st.lists(st.tuples(BOOL_VALUES, INT_VALUES), max_size=40))
def test_counter_with_any_step_matches_the_model(steps: list[tuple[bool, int]]) -> None:
    counter = Counter()
    model = 0
    for enable, step in steps:
        counter(enable=enable, step=step)
        if enable:
            model = wrap_int(model + step)
        assert counter.count == model


class Panel(FunctionBlock):
    """Many inputs of different types; the body copies what it sees to outputs."""

    run: BOOL = VAR_INPUT(False)
    speed: INT = VAR_INPUT(10)
    target: DINT = VAR_INPUT(-5)
    gain: REAL = VAR_INPUT(0.5)
    label: STRING = VAR_INPUT("idle", length=12)
    seen_run: BOOL = VAR_OUTPUT(False)
    seen_speed: INT = VAR_OUTPUT(0)
    seen_target: DINT = VAR_OUTPUT(0)
    seen_gain: REAL = VAR_OUTPUT(0.0)
    seen_label: STRING = VAR_OUTPUT("", length=12)

    def body(self) -> None:
        self.seen_run = self.run
        self.seen_speed = self.speed
        self.seen_target = self.target
        self.seen_gain = self.gain
        self.seen_label = self.label


PANEL_INPUTS: dict[str, st.SearchStrategy[Any]] = {
    "run": BOOL_VALUES,
    "speed": INT_VALUES,
    "target": DINT_VALUES,
    "gain": REAL_VALUES,
    "label": string_values(12),
}


@given(calls=st.lists(st.fixed_dictionaries({}, optional=PANEL_INPUTS), max_size=25))
def test_each_call_sets_exactly_the_inputs_given_and_leaves_the_others(calls: list[dict[str, Any]]) -> None:
    panel = Panel()
    model: dict[str, Any] = {"run": False, "speed": 10, "target": -5, "gain": 0.5, "label": "idle"}
    for inputs in calls:
        panel(**inputs)
        model.update(inputs)
        for name, expected in model.items():
            assert getattr(panel, name) == expected, name
            assert getattr(panel, f"seen_{name}") == expected, name


# ---------------------------------------------------------------------------
# Aggregate inputs from lists / dicts; VAR_IN_OUT CONSTANT with a literal; an ARRAY bound to VAR_IN_OUT
# ---------------------------------------------------------------------------


class Point2(Struct):
    x: REAL = 0.0
    y: REAL = 0.0


class Summer(FunctionBlock):
    values: ARRAY[INT] = VAR_INPUT(bounds=(1, 3))
    origin: Point2 = VAR_INPUT()
    offset: INT = VAR_IN_OUT(constant=True)
    log: ARRAY[INT] = VAR_IN_OUT(bounds=(1, 3))
    total: DINT = VAR_OUTPUT()

    def body(self) -> None:
        self.total = self.values[1] + self.values[2] + self.values[3] + self.offset
        self.log[1] += 1


class LogOwner(FunctionBlock):
    entries: ARRAY[INT] = VAR([0, 0, 0], bounds=(1, 3))


def test_array_and_struct_inputs_take_lists_and_dicts() -> None:
    owner, summer = LogOwner(), Summer()
    summer(values=[1, 2, 3], origin={"x": 1.5}, offset=10, log=owner.entries)
    assert (summer.total, summer.origin.x, summer.origin.y, owner.entries[1]) == (16, 1.5, 0.0, 1)
    summer(values=[4], offset=20, log=adr(owner, "entries"))  # the rest of the array input keeps its value
    assert (summer.total, owner.entries[1]) == (29, 2)
    with pytest.raises(TypeError, match=r"Summer\.values: 4 values for ARRAY\[1\.\.3\] OF INT"):
        summer(values=[1, 2, 3, 4], offset=0, log=owner.entries)
    with pytest.raises(TypeError, match=r"Summer\.origin: Point2 has no member 'z'"):
        summer(origin={"z": 1.0}, offset=0, log=owner.entries)


def test_var_in_out_constant_takes_a_literal_or_an_expression() -> None:
    owner, summer = LogOwner(), Summer()
    for offset in (5, 7 * 6):  # ST: fbSummer(offset := 5, ...); a literal passed through a temporary
        summer(values=[0, 0, 0], offset=offset, log=owner.entries)
        assert summer.total == offset
    with pytest.raises(TypeError, match=r"Summer\.offset: cannot store str 'x' in INT"):
        summer(offset="x", log=owner.entries)  # type: ignore[arg-type]
