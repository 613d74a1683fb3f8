"""FB_init, FB_exit, FB_reinit and dynamic instances (``__NEW`` / ``__DELETE``).

The call orders follow docs/concepts/lifecycle.md: nested members are
initialised first, in declaration order, each completely (FB_init, then the
inputs set at its declaration, then call_after_init); then the block's own
FB_init, base before derived. FB_exit runs derived before base, then the
members in reverse. FB_reinit is not chained unless the derived block calls
``super().fb_reinit()``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import pytest

from iecoop import (
    ARRAY,
    BOOL,
    INT,
    POINTER_TO,
    REFERENCE_TO,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    DefinitionError,
    ExceptionCode,
    FunctionBlock,
    Interface,
    PlcException,
    Pointer,
    Struct,
    adr,
    call_after_init,
    delete,
    method,
    new,
)
from iecoop.lifecycle import finalise, reinitialise

Log = list[tuple[Any, ...]]
log: Log = []


@pytest.fixture(autouse=True)
def _clear_log() -> None:
    log.clear()


class Part(FunctionBlock):
    tag: INT = VAR_INPUT(0)
    tag_in_fb_init: INT = VAR_OUTPUT(-1)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, ident: INT = 0) -> BOOL:
        log.append(("Part.fb_init", ident, self.tag, init_retains, in_copy_code))
        self.tag_in_fb_init = self.tag
        return True

    @call_after_init
    def ready(self) -> None:
        log.append(("Part.after_init", self.tag))

    def fb_exit(self, in_copy_code: BOOL) -> BOOL:
        log.append(("Part.fb_exit", self.tag, in_copy_code))
        return True

    def fb_reinit(self) -> BOOL:
        log.append(("Part.fb_reinit", self.tag))
        return True


class Base(FunctionBlock):
    first: Part = VAR({"tag": 1}, fb_init={"ident": 11})
    speed: INT = VAR(0)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, speed: INT = 5) -> BOOL:
        log.append(("Base.fb_init", speed, self.first.tag))
        self.speed = speed
        return True

    def fb_exit(self, in_copy_code: BOOL) -> BOOL:
        log.append(("Base.fb_exit", in_copy_code))
        return True

    def fb_reinit(self) -> BOOL:
        log.append(("Base.fb_reinit",))
        return True


class Derived(Base):
    second: Part = VAR({"tag": 2}, fb_init={"ident": 22})
    mode: INT = VAR(0)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, speed: INT = 5, mode: INT = 0) -> BOOL:
        log.append(("Derived.fb_init", speed, mode, self.speed))
        self.mode = mode
        return True

    def fb_exit(self, in_copy_code: BOOL) -> BOOL:
        log.append(("Derived.fb_exit", in_copy_code))
        return True

    def fb_reinit(self) -> BOOL:
        log.append(("Derived.fb_reinit",))
        return True


class ChainedDerived(Base):
    def fb_reinit(self) -> BOOL:
        log.append(("ChainedDerived.fb_reinit",))
        return super().fb_reinit()


# ---------------------------------------------------------------------------
# FB_init
# ---------------------------------------------------------------------------


def test_fb_init_order_members_first_then_base_then_derived() -> None:
    block = Derived(speed=7, mode=2)
    assert log == [
        ("Part.fb_init", 11, 0, True, False),
        ("Part.after_init", 1),
        ("Part.fb_init", 22, 0, True, False),
        ("Part.after_init", 2),
        ("Base.fb_init", 7, 1),
        ("Derived.fb_init", 7, 2, 7),
    ]
    assert (block.speed, block.mode) == (7, 2)


def test_declaration_site_inputs_are_set_after_fb_init_and_before_call_after_init() -> None:
    block = Derived()
    assert (block.first.tag, block.second.tag) == (1, 2)
    assert (block.first.tag_in_fb_init, block.second.tag_in_fb_init) == (0, 0)
    assert ("Part.after_init", 1) in log and ("Part.after_init", 2) in log


def test_a_declaration_site_input_overrides_what_fb_init_wrote() -> None:
    class Valve(FunctionBlock):
        opening: INT = VAR_INPUT(0)

        def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
            self.opening = 50
            return True

    class Manifold(FunctionBlock):
        declared: Valve = VAR({"opening": 80})
        plain: Valve = VAR()

    manifold = Manifold()
    assert (manifold.declared.opening, manifold.plain.opening) == (80, 50)


def test_array_of_blocks_declaration_inputs_hold_after_each_fb_init() -> None:
    class Valve(FunctionBlock):
        opening: INT = VAR_INPUT(0)

        def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
            self.opening = 50
            return True

        @call_after_init
        def ready(self) -> None:
            log.append(("Valve.after_init", self.opening))

    class Manifold(FunctionBlock):
        valves: ARRAY[Valve] = VAR([{"opening": 10}, {"opening": 20}], bounds=(1, 3))

    manifold = Manifold()
    assert [v.opening for v in manifold.valves] == [10, 20, 50]
    assert log == [("Valve.after_init", 10), ("Valve.after_init", 20), ("Valve.after_init", 50)]


def test_an_array_of_blocks_is_initialised_element_by_element_in_order() -> None:
    class Rack(FunctionBlock):
        slots: ARRAY[Part] = VAR(bounds=(1, 3))

    Rack()
    assert log == [("Part.fb_init", 0, 0, True, False), ("Part.after_init", 0)] * 3


def test_an_array_of_blocks_is_finalised_last_element_first() -> None:
    class Rack(FunctionBlock):
        slots: ARRAY[Part] = VAR([{"tag": 1}, {"tag": 2}, {"tag": 3}], bounds=(1, 3))

    rack = Rack()
    log.clear()
    finalise(rack, in_copy_code=False)
    assert log == [("Part.fb_exit", 3, False), ("Part.fb_exit", 2, False), ("Part.fb_exit", 1, False)]


def test_call_after_init_runs_after_the_blocks_own_fb_init() -> None:
    class Station(FunctionBlock):
        ready_flag: BOOL = VAR_OUTPUT(False)
        station_id: INT = VAR(0)

        def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, station_id: INT = 1) -> BOOL:
            log.append(("Station.fb_init", station_id))
            self.station_id = station_id
            return True

        @call_after_init
        def announce(self) -> None:
            log.append(("Station.after_init", self.station_id))
            self.ready_flag = True

    station = Station(station_id=4)
    assert log == [("Station.fb_init", 4), ("Station.after_init", 4)]
    assert station.ready_flag is True


def test_extra_fb_init_inputs_are_the_constructor_keywords_defaults_apply() -> None:
    assert Derived().speed == 5
    assert Derived(mode=3).mode == 3
    block = Derived(speed=-2)
    assert (block.speed, block.mode) == (-2, 0)


def test_unknown_fb_init_argument_is_a_type_error() -> None:
    with pytest.raises(TypeError, match=r"Derived: FB_init has no input 'velocity' \(its extra inputs: mode, speed\)"):
        Derived(velocity=3)


def test_missing_required_fb_init_argument_is_a_type_error() -> None:
    class Axis(FunctionBlock):
        axis_id: INT = VAR(0)

        def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, axis_id: INT) -> BOOL:
            self.axis_id = axis_id
            return True

    with pytest.raises(TypeError, match=r"Axis: FB_init input 'axis_id' has no value; pass it as Axis\(axis_id=\.\.\.\)"):
        Axis()
    assert Axis(axis_id=3).axis_id == 3


def test_fb_init_arguments_for_members_errors_name_the_member_type() -> None:
    class Axis(FunctionBlock):
        def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, axis_id: INT) -> BOOL:
            return True

    class Gantry(FunctionBlock):
        x: Axis = VAR(fb_init={"axis_id": 1})

    Gantry()

    class BadGantry(FunctionBlock):
        x: Axis = VAR(fb_init={"axis": 1})

    with pytest.raises(TypeError, match=r"Axis: FB_init has no input 'axis'"):
        BadGantry()

    class ForgetfulGantry(FunctionBlock):
        x: Axis = VAR()

    with pytest.raises(TypeError, match=r"Axis: FB_init input 'axis_id' has no value"):
        ForgetfulGantry()


def test_fb_init_for_a_member_that_is_not_a_block_is_rejected() -> None:
    with pytest.raises(DefinitionError, match=r"Gantry\.count: fb_init= applies to function block members \(or ARRAYs of them\) only"):

        class Gantry(FunctionBlock):
            count: INT = VAR(0, fb_init={"x": 1})


array_init_log: list[tuple[int, int]] = []


class NumberedAxis(FunctionBlock):
    speed: INT = VAR_INPUT(0)
    ident: INT = VAR(0)

    def fb_init(self, init_retains: bool, in_copy_code: bool, ident: INT = 0) -> None:
        array_init_log.append((ident, self.speed))
        self.ident = ident


def test_an_array_of_blocks_takes_fb_init_inputs_per_element_then_declared_inputs() -> None:
    class Gantry(FunctionBlock):
        # ST: aAxes : ARRAY[1..3] OF FB_Axis[(ident := 1), (ident := 2), (ident := 3)] := [(speed := 5), (speed := 6)];
        axes: ARRAY[NumberedAxis] = VAR([{"speed": 5}, {"speed": 6}], bounds=(1, 3), fb_init=[{"ident": 1}, {"ident": 2}, {"ident": 3}])
        spares: ARRAY[NumberedAxis] = VAR(bounds=(1, 2), fb_init={"ident": 9})

    array_init_log.clear()
    gantry = Gantry()
    # FB_init runs first (the declared inputs are not set yet), in element order
    assert array_init_log == [(1, 0), (2, 0), (3, 0), (9, 0), (9, 0)]
    assert [(a.ident, a.speed) for a in gantry.axes] == [(1, 5), (2, 6), (3, 0)]
    assert [a.ident for a in gantry.spares] == [9, 9]


def test_fb_init_lists_must_fit_their_array() -> None:
    with pytest.raises(DefinitionError, match=r"Gantry\.axes: 3 fb_init= entries for 2 elements"):

        class Gantry(FunctionBlock):
            axes: ARRAY[NumberedAxis] = VAR(bounds=(1, 2), fb_init=[{"ident": 1}, {"ident": 2}, {"ident": 3}])

    with pytest.raises(DefinitionError, match=r"Single\.axis: a list of fb_init= inputs is for an ARRAY OF function blocks"):

        class Single(FunctionBlock):
            axis: NumberedAxis = VAR(fb_init=[{"ident": 1}])


def test_an_instance_is_usable_with_the_values_fb_init_set() -> None:
    class Counter(FunctionBlock):
        count: INT = VAR_OUTPUT(0)
        step: INT = VAR(1)

        def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, start: INT = 0, step: INT = 1) -> BOOL:
            self.count = start
            self.step = step
            return True

        def body(self) -> None:
            self.count += self.step

    counter = Counter(start=100, step=-3)
    for _ in range(4):
        counter()
    assert counter.count == 88


class Tagged(FunctionBlock):
    """A block that numbers itself in FB_init, so each instance shows in the log."""

    counter = [0]
    tag: INT = VAR_OUTPUT(0)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
        Tagged.counter[0] += 1
        self.tag = Tagged.counter[0]
        log.append(("Tagged.fb_init", self.tag))
        return True

    @call_after_init
    def ready(self) -> None:
        log.append(("Tagged.after_init", self.tag))

    def fb_exit(self, in_copy_code: BOOL) -> BOOL:
        log.append(("Tagged.fb_exit", self.tag))
        return True

    def fb_reinit(self) -> BOOL:
        log.append(("Tagged.fb_reinit", self.tag))
        return True


class Station(Struct):
    """ST: STRUCT nId : INT; fbPart : FB_Part; END_STRUCT: a block inside a STRUCT."""

    ident: INT = VAR(5)
    part: Tagged = VAR()


class Bay(Struct):
    """A STRUCT holding a STRUCT that holds a block, and an ARRAY of blocks."""

    station: Station = VAR()
    spares: ARRAY[Tagged] = VAR(bounds=(1, 2))


class Cell(FunctionBlock):
    bays: ARRAY[Bay] = VAR(bounds=(1, 2))
    station: Station = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
        log.append(("Cell.fb_init", self.station.part.tag, self.bays[2].spares[2].tag))
        return True


def test_blocks_inside_struct_members_get_fb_init_first_in_declaration_order() -> None:
    Tagged.counter[0] = 0
    cell = Cell()
    # each block's FB_init ran once, in declaration order through the STRUCTs and ARRAYs, before the holder's
    assert log == [entry for tag in range(1, 8) for entry in (("Tagged.fb_init", tag), ("Tagged.after_init", tag))] + [
        ("Cell.fb_init", 7, 6)
    ]
    assert (cell.bays[1].station.part.tag, cell.bays[1].spares[1].tag, cell.bays[2].spares[2].tag) == (1, 2, 6)
    assert cell.station.ident == 5 and cell.bays[2].station.ident == 5


def test_blocks_inside_struct_members_get_fb_exit_in_reverse_and_fb_reinit() -> None:
    Tagged.counter[0] = 0
    cell = Cell()
    log.clear()
    finalise(cell, in_copy_code=False)
    assert log == [("Tagged.fb_exit", tag) for tag in range(7, 0, -1)]
    log.clear()
    reinitialise(cell)
    assert log == [("Tagged.fb_reinit", tag) for tag in range(1, 8)]


# ---------------------------------------------------------------------------
# FB_exit and FB_reinit
# ---------------------------------------------------------------------------


def test_fb_exit_order_derived_then_base_then_members_in_reverse() -> None:
    block = Derived()
    log.clear()
    finalise(block, in_copy_code=True)
    assert log == [
        ("Derived.fb_exit", True),
        ("Base.fb_exit", True),
        ("Part.fb_exit", 2, True),
        ("Part.fb_exit", 1, True),
    ]


def test_fb_reinit_runs_only_the_most_derived_unless_chained() -> None:
    block = Derived()
    log.clear()
    reinitialise(block)
    assert log == [("Part.fb_reinit", 1), ("Part.fb_reinit", 2), ("Derived.fb_reinit",)]
    chained = ChainedDerived()
    log.clear()
    reinitialise(chained)
    assert log == [("Part.fb_reinit", 1), ("ChainedDerived.fb_reinit",), ("Base.fb_reinit",)]


def test_fb_reinit_inherited_when_the_derived_block_declares_none() -> None:
    class Plain(Base):
        pass

    block = Plain()
    log.clear()
    reinitialise(block)
    assert log == [("Part.fb_reinit", 1), ("Base.fb_reinit",)]


# ---------------------------------------------------------------------------
# new / delete
# ---------------------------------------------------------------------------


class IRunnable(Interface):
    @method
    def run(self) -> INT: ...


class Job(FunctionBlock, IRunnable):
    priority: INT = VAR_INPUT(0)
    runs: INT = VAR_OUTPUT(0)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, priority: INT = 1) -> BOOL:
        log.append(("Job.fb_init", priority, init_retains, in_copy_code))
        self.priority = priority
        return True

    def fb_exit(self, in_copy_code: BOOL) -> BOOL:
        log.append(("Job.fb_exit", self.priority, in_copy_code))
        return True

    @method
    def run(self) -> INT:
        self.runs += 1
        return self.runs


class UrgentJob(Job):
    def fb_exit(self, in_copy_code: BOOL) -> BOOL:
        log.append(("UrgentJob.fb_exit",))
        return True


class Scheduler(FunctionBlock):
    job: POINTER_TO[Job] = VAR()
    alias: POINTER_TO[Job] = VAR_INPUT()
    current: IRunnable = VAR_INPUT()
    view: REFERENCE_TO[Job] = VAR_INPUT()
    priority: REFERENCE_TO[INT] = VAR_INPUT()
    total: INT = VAR_OUTPUT(0)

    @method
    def create(self, priority: INT) -> None:
        self.job = new(Job, priority=priority)

    @method
    def drop(self) -> None:
        delete(self.job)

    def body(self) -> None:
        self.total += self.current.run()


def test_new_runs_fb_init_with_the_keyword_inputs_and_delete_runs_fb_exit() -> None:
    p = new(Job, priority=4)
    assert log == [("Job.fb_init", 4, True, False)]
    job = p.deref
    assert job.run() == 1 and p.deref.run() == 2
    assert p.deref.priority == 4
    delete(p)
    assert log[-1] == ("Job.fb_exit", 4, False)
    assert not p and p == 0 and p.is_null
    with pytest.raises(PlcException, match="null pointer") as info:
        _ = p.deref
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


def test_a_heap_block_called_across_cycles_through_its_pointer() -> None:
    p = new(Job)
    for _ in range(3):
        p.deref.run()
    assert p.deref.runs == 3
    delete(p)


def test_delete_through_a_pointer_field_zeroes_the_field() -> None:
    scheduler = Scheduler()
    scheduler.create(3)
    assert scheduler.job
    assert scheduler.job.deref.priority == 3
    scheduler.drop()
    assert log[-1] == ("Job.fb_exit", 3, False)
    assert scheduler.job == 0 and not scheduler.job


def test_every_other_pointer_reference_and_interface_into_a_deleted_block_faults() -> None:
    scheduler = Scheduler()
    scheduler.create(2)
    p = scheduler.job
    copy: Pointer[Job] = Pointer(p.handle, p._target)
    scheduler(alias=p, current=p.deref, view=p, priority=adr(p.deref, "priority"))
    scheduler()
    assert scheduler.total == 3
    assert scheduler.view.runs == 2 and scheduler.priority == 2
    scheduler.drop()
    assert not scheduler.job
    faults: list[PlcException] = []
    uses: list[Callable[[], object]] = [
        lambda: p.deref,
        lambda: copy.deref,
        lambda: scheduler.alias.deref,
        lambda: scheduler.current,
        lambda: scheduler.view,
        lambda: scheduler.view.runs,
        lambda: scheduler.priority,
        lambda: setattr(scheduler, "priority", 1),
        lambda: scheduler(),
    ]
    for use in uses:
        with pytest.raises(PlcException, match="deleted or no longer exists") as info:
            use()
        faults.append(info.value)
    assert {f.code for f in faults} == {ExceptionCode.RTSEXCPT_ACCESS_VIOLATION}
    assert scheduler.total == 3


def test_delete_through_a_base_type_pointer_runs_only_the_base_fb_exit() -> None:
    p = new(UrgentJob, priority=9)
    log.clear()
    delete(p.typed(Job))
    assert log == [("Job.fb_exit", 9, False)]
    exact = new(UrgentJob, priority=8)
    log.clear()
    delete(exact)
    assert log == [("UrgentJob.fb_exit",), ("Job.fb_exit", 8, False)]


def test_delete_runs_the_fb_exit_of_the_heap_blocks_members() -> None:
    p = new(Derived)
    log.clear()
    delete(p)
    assert log == [
        ("Derived.fb_exit", False),
        ("Base.fb_exit", False),
        ("Part.fb_exit", 2, False),
        ("Part.fb_exit", 1, False),
    ]


def test_double_delete_through_a_copy_is_an_access_violation() -> None:
    p = new(Job)
    copy: Pointer[Job] = Pointer(p.handle, p._target)
    delete(p)
    log.clear()
    with pytest.raises(PlcException, match=r"__DELETE of memory that new\(\) did not create \(or already deleted\)") as info:
        delete(copy)
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION
    assert log == []


def test_deleting_the_nulled_pointer_again_does_nothing() -> None:
    p = new(Job)
    delete(p)
    log.clear()
    delete(p)
    assert log == [] and not p


def test_deleting_memory_new_did_not_create_is_an_access_violation() -> None:
    job = Job()
    log.clear()
    with pytest.raises(PlcException, match=r"__DELETE of memory that new\(\) did not create") as info:
        delete(adr(job))
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION
    assert log == []
    assert job.run() == 1


def test_deleting_through_a_pointer_inside_the_block_is_an_access_violation() -> None:
    p = new(Job, priority=6)
    with pytest.raises(PlcException, match="not one inside the block") as info:
        delete(adr(p.deref, "runs"))
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION
    assert p.deref.priority == 6
    delete(p)


def test_new_of_a_struct_and_of_things_that_are_not_types() -> None:
    class Recipe(Struct):
        steps: INT = 3

    p = new(Recipe)
    assert p.deref.steps == 3
    delete(p)
    with pytest.raises(PlcException):
        _ = p.deref
    with pytest.raises(TypeError, match="__NEW needs a function block or struct type"):
        new(INT)
    with pytest.raises(TypeError, match="__DELETE needs a pointer from new"):
        delete(5)  # type: ignore[arg-type]


def test_new_with_an_unknown_fb_init_argument_fails_without_running_fb_init() -> None:
    with pytest.raises(TypeError, match=r"Job: FB_init has no input 'urgency'"):
        new(Job, urgency=1)
    assert log == []
