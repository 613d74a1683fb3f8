"""OCP: a new valve kind breaks the CASE block, and joins the I_Valve manifold without an edit."""

from __future__ import annotations

from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import (
    BOOL,
    REAL,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    DefinitionError,
    ExceptionCode,
    FunctionBlock,
    PlcException,
    Program,
    T,
    method,
    prop,
    query_interface,
)
from iecoop.runtime import Runtime, Task
from patterns.solid.ocp import (
    ERR_UNKNOWN_KIND,
    SLOTS,
    IValve,
    MotorisedValve,
    ProportionalValve,
    SolenoidValve,
    ValveBase,
    ValveByCase,
    ValveCell,
    ValveKind,
    ValveManifold,
)


class DoubleSeatValve(FunctionBlock, IValve):
    """A kind written after the manifold: it implements I_Valve directly and nothing else changes.

    Both seats lift one after the other; the valve is open when both feedbacks are made.
    """

    cmd_open: BOOL = VAR(False)
    q_upper: BOOL = VAR_OUTPUT(False)
    q_lower: BOOL = VAR_OUTPUT(False)
    seats_lifted: REAL = VAR(0.0)

    @method
    def open(self) -> None:
        self.cmd_open = True

    @method
    def close(self) -> None:
        self.cmd_open = False

    @method
    def update(self) -> None:
        self.q_lower = self.cmd_open
        self.q_upper = self.cmd_open and self.seats_lifted >= 1.0
        self.seats_lifted = float(self.q_lower) + float(self.q_upper)

    @prop
    def position(self) -> REAL:
        return self.seats_lifted * 50.0

    @prop
    def is_open(self) -> BOOL:
        return self.seats_lifted >= 2.0

    @prop
    def is_closed(self) -> BOOL:
        return self.seats_lifted <= 0.0


class Bench(Program):
    cmd_open: BOOL = VAR_INPUT(False)
    solenoid: SolenoidValve = VAR()
    motorised: MotorisedValve = VAR()
    proportional: ProportionalValve = VAR()
    double_seat: DoubleSeatValve = VAR()
    manifold: ValveManifold = VAR()
    solenoid_case: ValveByCase = VAR({"kind": ValveKind.SOLENOID})
    motorised_case: ValveByCase = VAR({"kind": ValveKind.MOTORISED})
    proportional_case: ValveByCase = VAR({"kind": ValveKind.PROPORTIONAL})

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
        for valve in (self.solenoid, self.motorised, self.proportional, self.double_seat):
            self.manifold.add(valve)
        return True

    def body(self) -> None:
        for case in (self.solenoid_case, self.motorised_case, self.proportional_case):
            case(cmd_open=self.cmd_open)
        if self.cmd_open:
            self.manifold.open_all()
        else:
            self.manifold.close_all()
        self.manifold()


def _bench() -> tuple[Runtime, Bench]:
    bench = Bench()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), bench)
    return rt, bench


# ---------------------------------------------------------------------------
# What goes wrong in the violating design
# ---------------------------------------------------------------------------


def test_a_type_code_without_a_case_branch_ends_in_the_else_error() -> None:
    rt, bench = _bench()
    bench.cmd_open = True
    for _ in range(50):
        rt.run(cycles=1)
        valve = bench.proportional_case
        assert (valve.error, valve.error_id) == (True, ERR_UNKNOWN_KIND)
        assert (valve.q_open, valve.q_close, valve.position) == (False, False, 0.0)
    assert rt.time_ms == 500
    # The two kinds the CASE knows work: the block is fine until the plant grows.
    assert bench.solenoid_case.position == bench.motorised_case.position == 100.0
    assert not bench.solenoid_case.error and not bench.motorised_case.error


def test_the_case_block_runs_its_known_kinds_on_time() -> None:
    rt, bench = _bench()
    bench.cmd_open = True
    rt.run(cycles=1)
    assert bench.solenoid_case.q_open and bench.solenoid_case.position == 100.0
    rt.run(cycles=29)  # t = 0 .. 290 ms: the motor runs
    assert (bench.motorised_case.q_open, bench.motorised_case.position) == (True, 50.0)
    rt.run(cycles=1)  # t = 300 ms: the travel time has elapsed
    assert (bench.motorised_case.q_open, bench.motorised_case.position) == (False, 100.0)


# ---------------------------------------------------------------------------
# What holds in the compliant design
# ---------------------------------------------------------------------------


def test_a_new_valve_class_joins_the_manifold_without_an_edit() -> None:
    rt, bench = _bench()
    assert (bench.manifold.count, bench.manifold.all_closed) == (4, True)
    bench.cmd_open = True
    rt.run(cycles=2)
    assert (bench.double_seat.q_lower, bench.double_seat.q_upper) == (True, True)
    # The new valve is open; the motorised one still travels.
    assert (bench.manifold.valve(4).is_open, bench.manifold.all_open) == (True, False)
    rt.run(cycles=29)
    assert (bench.manifold.all_open, rt.time_ms) == (True, 310)
    bench.cmd_open = False
    rt.run(cycles=31)
    assert (bench.manifold.all_closed, bench.double_seat.q_lower, bench.double_seat.q_upper) == (True, False, False)


def test_the_proportional_valve_the_case_refused_opens_in_slew_steps() -> None:
    rt, bench = _bench()
    bench.cmd_open = True
    positions = []
    for _ in range(5):
        rt.run(cycles=1)
        positions.append(bench.proportional.position)
    assert positions == [25.0, 50.0, 75.0, 100.0, 100.0]
    assert bench.proportional.ao_position == 100.0 and bench.proportional.is_open


def test_the_main_cell_shows_the_else_branch_beside_the_open_manifold() -> None:
    cell = ValveCell()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), cell)
    cell.cmd_open = True
    rt.run(duration=T("400ms"))
    assert [cell.by_case[slot].error for slot in (1, 2, 3)] == [False, False, True]
    assert cell.manifold.all_open


commands = st.lists(st.booleans(), min_size=1, max_size=80)


@settings(max_examples=50, deadline=None)
@given(commands)
def test_the_valve_classes_match_the_case_branches_they_replace(script: list[bool]) -> None:
    rt, bench = _bench()
    for cmd_open in script:
        bench.cmd_open = cmd_open
        rt.run(cycles=1)
        assert bench.solenoid.position == bench.solenoid_case.position
        assert bench.motorised.position == bench.motorised_case.position
        assert (bench.motorised.q_open, bench.motorised.q_close) == (
            bench.motorised_case.q_open,
            bench.motorised_case.q_close,
        )
        every = [bench.manifold.valve(slot) for slot in range(1, 5)]
        assert bench.manifold.all_open == all(v.is_open for v in every)
        assert bench.manifold.all_closed == all(v.is_closed for v in every)
        assert all(0.0 <= v.position <= 100.0 for v in every)


def test_a_reversal_mid_travel_restarts_the_motor_run() -> None:
    rt = Runtime(store=":memory:")

    class Single(Program):
        cmd_open: BOOL = VAR_INPUT(False)
        target: MotorisedValve = VAR()

        def body(self) -> None:
            if self.cmd_open:
                self.target.open()
            else:
                self.target.close()
            self.target.update()

    single = Single()
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), single)
    single.cmd_open = True
    rt.run(cycles=20)
    single.cmd_open = False
    rt.run(cycles=30)  # a full travel time closing, counted from the reversal
    assert (single.target.q_close, single.target.position) == (True, 50.0)
    rt.run(cycles=1)
    assert (single.target.is_closed, single.target.q_close) == (True, False)


def test_the_manifold_pool_is_bounded_and_refuses_duplicates() -> None:
    manifold = ValveManifold()
    valves = [SolenoidValve() for _ in range(SLOTS + 1)]
    assert [manifold.add(v) for v in valves[:SLOTS]] == list(range(1, SLOTS + 1))
    assert manifold.add(valves[SLOTS]) == 0  # refused: the caller checks for 0
    assert manifold.count == SLOTS and not manifold.valve(SLOTS).is_open
    other = ValveManifold()
    assert other.add(valves[0]) == 1
    assert (other.add(valves[0]), other.count) == (0, 1)  # already in slot 1
    assert other.valve(1) == valves[0]
    free = other.valve(2)
    assert not free  # a free slot holds the null interface; calling through it is the PLC's own fault
    with pytest.raises(PlcException, match=r"IValve\.open called through a null interface") as info:
        free.open()
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION
    for slot in (0, SLOTS + 1):
        with pytest.raises(PlcException, match=rf"index {slot} outside ARRAY\[1\.\.8\] OF IValve") as info:
            other.valve(slot)
        assert info.value.code == ExceptionCode.RTSEXCPT_ARRAYBOUNDS


def test_the_manifold_takes_only_valves() -> None:
    manifold = ValveManifold()
    not_a_valve: Any = ValveCell()
    with pytest.raises(TypeError, match=r"ValveCell does not implement IValve"):
        manifold.add(not_a_valve)
    assert manifold.count == 0
    assert query_interface(ProportionalValve(), IValve) is not None
    assert query_interface(ValveByCase(), IValve) is None


def test_the_base_is_abstract_and_its_commands_final() -> None:
    with pytest.raises(DefinitionError, match="ABSTRACT FUNCTION_BLOCK ValveBase cannot be instantiated"):
        ValveBase()
    with pytest.raises(DefinitionError, match="FINAL"):

        class SneakyValve(ValveBase):
            @method
            def open(self) -> None:
                self.cmd_open = False

            @method
            def update(self) -> None:
                self.actual = 0.0

