"""The PackML unit: the state blocks checked against the transition table, across cycles."""

from __future__ import annotations

from collections import deque

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import BOOL, INT, VAR, VAR_INPUT, VAR_OUTPUT, AccessError, ExceptionCode, FunctionBlock, PlcException, Program, T, method
from iecoop.runtime import Runtime, Task
from patterns.behavioral.state import (
    INITIAL_STATE,
    TRANSITIONS,
    IPackMLContext,
    PackagingLine,
    PackMLCommand,
    PackMLMachine,
    PackMLState,
    Resetting,
    Stopped,
    state_name,
)
from tests import checked_only

STATES = {state_name(s): s for s in PackMLState}
COMMANDS = {c.name.capitalize(): c for c in PackMLCommand if c != PackMLCommand.NONE}
TABLE = {(source, cause): target for source, cause, target in TRANSITIONS}
ACTING = (
    "resetting", "starting", "completing", "holding", "unholding", "suspending", "unsuspending", "stopping",
    "aborting", "clearing",
)


class Harness(Program):
    """Runs the unit; a command put in ``request`` is given to it inside the next scan, as a PLC does."""

    unit: PackMLMachine = VAR()
    request: PackMLCommand = VAR_INPUT(PackMLCommand.NONE)
    accepted: BOOL = VAR_OUTPUT(False)

    def body(self) -> None:
        if self.request != PackMLCommand.NONE:
            self.accepted = self.unit.command(self.request)
            self.request = PackMLCommand.NONE
        self.unit()


class Plc:
    """One harness on a 10 ms task; ``fast`` shortens every acting state to 20 ms and the batch to 3 packs."""

    def __init__(self, fast: bool = True) -> None:
        self.harness = Harness()
        self.rt = Runtime(store=":memory:")
        self.rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), self.harness)
        self.unit = self.harness.unit
        if fast:
            for name in ACTING:
                getattr(self.unit, name).duration = T("20ms")
            self.unit.execute.batch_size = 3
            self.unit.execute.pack_time = T("20ms")

    def send(self, cmd: PackMLCommand) -> bool:
        """Give ``cmd`` to the unit in one scan; whether it was accepted."""
        self.harness.request = cmd
        self.rt.run(cycles=1)
        return self.harness.accepted

    def wait_for_sc(self, limit: int = 50) -> int:
        """Run scans until the state changes by itself; the number of scans it took."""
        before = self.unit.state
        for cycle in range(1, limit + 1):
            self.rt.run(cycles=1)
            if self.unit.state != before:
                return cycle
        raise AssertionError(f"{state_name(before)} did not complete within {limit} scans")

    def drive(self, target: str) -> None:
        """Follow the table's shortest path from the initial state to ``target``."""
        for cause, state in path_to(target):
            if cause == "SC":
                self.wait_for_sc()
            else:
                assert self.send(COMMANDS[cause])
            assert state_name(self.unit.state) == state


def path_to(target: str) -> list[tuple[str, str]]:
    """The shortest (cause, state) path from the initial state, found in the table."""
    paths: dict[str, list[tuple[str, str]]] = {INITIAL_STATE: []}
    queue = deque([INITIAL_STATE])
    while queue:
        source = queue.popleft()
        for (from_state, cause), to_state in TABLE.items():
            if from_state == source and to_state not in paths:
                paths[to_state] = [*paths[source], (cause, to_state)]
                queue.append(to_state)
    return paths[target]


# ---------------------------------------------------------------------------
# The table itself
# ---------------------------------------------------------------------------


def test_the_table_speaks_of_the_17_states_and_9_commands_of_the_standard() -> None:
    named = {s for s, _c, _t in TRANSITIONS} | {t for _s, _c, t in TRANSITIONS}
    assert named == set(STATES) and len(STATES) == 17
    assert {c for _s, c, _t in TRANSITIONS} == set(COMMANDS) | {"SC"}
    assert INITIAL_STATE == "Stopped"
    assert len(TABLE) == len(TRANSITIONS), "one (state, command) pair leads to one state only"
    acting = {s for s, c, _t in TRANSITIONS if c == "SC"}
    assert acting == {s for s in STATES if s.endswith("ing")} | {"Execute"}
    assert {s for s, c, _t in TRANSITIONS if c == "Abort"} == set(STATES) - {"Aborting", "Aborted"}
    assert {s for s, c, _t in TRANSITIONS if c == "Stop"} == set(STATES) - {
        "Stopping", "Stopped", "Aborting", "Aborted", "Clearing"
    }
    assert all(path_to(state) or state == INITIAL_STATE for state in STATES)


def test_the_state_numbers_are_the_packtags_values() -> None:
    assert [int(PackMLState[n]) for n in ("CLEARING", "STOPPED", "IDLE", "EXECUTE", "ABORTED", "COMPLETE")] == [
        1, 2, 4, 6, 9, 17
    ]
    assert [int(COMMANDS[n]) for n in ("Reset", "Start", "Stop", "Abort", "Clear")] == [1, 2, 3, 8, 9]


# ---------------------------------------------------------------------------
# The blocks against the table
# ---------------------------------------------------------------------------


@pytest.mark.parametrize(("source", "cause", "target"), TRANSITIONS, ids=lambda x: str(x))
def test_every_table_row_is_reachable_and_performs_its_transition(source: str, cause: str, target: str) -> None:
    plc = Plc()
    plc.drive(source)
    count = plc.unit.transitions
    if cause == "SC":
        plc.wait_for_sc()
    else:
        assert plc.send(COMMANDS[cause]) is True
    assert state_name(plc.unit.state) == target
    assert state_name(plc.unit.previous_state) == source
    assert (plc.unit.transitions, plc.unit.refused) == (count + 1, 0)


REFUSED = [(s, c) for s in STATES for c in COMMANDS if (s, c) not in TABLE]


@pytest.mark.parametrize(("source", "cause"), REFUSED, ids=lambda x: str(x))
def test_every_command_the_table_does_not_allow_is_refused(source: str, cause: str) -> None:
    plc = Plc()
    plc.drive(source)
    count = plc.unit.transitions
    assert plc.send(COMMANDS[cause]) is False
    assert state_name(plc.unit.state) == source
    assert (plc.unit.transitions, plc.unit.refused, plc.unit.last_refused) == (count, 1, COMMANDS[cause])


def test_no_command_is_refused_everywhere() -> None:
    plc = Plc()
    assert plc.unit.command(PackMLCommand.NONE) is False
    assert (plc.unit.state, plc.unit.refused, plc.unit.last_refused) == (PackMLState.STOPPED, 1, PackMLCommand.NONE)


@pytest.mark.parametrize("source", [s for s in STATES if (s, "SC") not in TABLE])
def test_a_wait_state_never_leaves_by_itself(source: str) -> None:
    plc = Plc()
    plc.drive(source)
    count = plc.unit.transitions
    plc.rt.run(cycles=200)
    assert (state_name(plc.unit.state), plc.unit.transitions) == (source, count)


# ---------------------------------------------------------------------------
# Timing, production, properties, wiring
# ---------------------------------------------------------------------------


def test_an_acting_state_completes_after_its_configured_time() -> None:
    plc = Plc(fast=False)
    assert plc.unit.resetting.duration == 200
    plc.unit.resetting.duration = T("350ms")
    plc.rt.run(cycles=3)
    entered = plc.rt.time_ms
    assert plc.send(PackMLCommand.RESET)
    assert plc.wait_for_sc() == 35
    # Entered in the scan at t=30 ms, complete in the scan at t=30 + 350 ms.
    assert (plc.rt.time_ms - 10 - entered, plc.unit.state) == (350, PackMLState.IDLE)
    assert plc.unit.resetting.elapsed == 350


def test_execute_makes_the_batch_keeps_the_count_over_a_hold_and_restarts_it_on_start() -> None:
    plc = Plc()
    execute = plc.unit.execute
    execute.batch_size = 4
    execute.pack_time = T("50ms")
    plc.drive("Execute")
    plc.rt.run(cycles=10)
    assert execute.packs == 2
    assert plc.send(PackMLCommand.HOLD)
    plc.rt.run(cycles=30)
    assert (plc.unit.state, execute.packs) == (PackMLState.HELD, 2)
    assert plc.send(PackMLCommand.UNHOLD)
    plc.wait_for_sc()
    assert plc.unit.state == PackMLState.EXECUTE
    # Two more packs of 50 ms, counted from the scan Execute was entered in again.
    assert plc.wait_for_sc() == 10
    assert (plc.unit.state, execute.packs) == (PackMLState.COMPLETING, 4)
    plc.wait_for_sc()
    assert plc.send(PackMLCommand.RESET)
    plc.wait_for_sc()
    assert plc.send(PackMLCommand.START)
    plc.wait_for_sc()
    assert (plc.unit.state, execute.packs) == (PackMLState.EXECUTE, 0)


def test_the_state_is_a_read_only_property() -> None:
    unit = Plc().unit
    with pytest.raises(AttributeError, match="state"):
        unit.state = PackMLState.EXECUTE  # type: ignore[misc]
    assert unit.state == PackMLState.STOPPED


@checked_only
def test_the_current_state_is_not_writable_from_outside() -> None:
    unit = Plc().unit
    with pytest.raises(AccessError, match=r"VAR PackMLMachine\.current cannot be written"):
        unit.current = PackMLState.EXECUTE
    assert unit.state == PackMLState.STOPPED


class Recorder(FunctionBlock, IPackMLContext):
    """A test double for the machine: records the state it was asked to change to."""

    target: PackMLState = VAR(PackMLState.STOPPED)
    calls: INT = VAR(0)

    @method
    def change_state(self, target: PackMLState) -> None:
        self.target = target
        self.calls += 1


def test_fb_init_injects_the_machine_into_a_state() -> None:
    recorder = Recorder()
    stopped = Stopped(context=recorder)
    assert stopped.command(PackMLCommand.START) is False
    assert recorder.calls == 0
    assert stopped.command(PackMLCommand.RESET) is True
    assert (recorder.target, recorder.calls) == (PackMLState.RESETTING, 1)
    assert stopped.command(PackMLCommand.ABORT) is True
    assert recorder.target == PackMLState.ABORTING


def test_a_state_without_its_machine_faults_when_it_accepts_a_command() -> None:
    orphan = Resetting()
    assert orphan.command(PackMLCommand.START) is False
    with pytest.raises(PlcException) as info:
        orphan.command(PackMLCommand.STOP)
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


def test_reset_cold_returns_to_the_initial_state_with_the_states_wired_again() -> None:
    plc = Plc()
    plc.drive("Held")
    plc.rt.reset_cold()
    assert (state_name(plc.unit.state), plc.unit.transitions, plc.unit.refused) == (INITIAL_STATE, 0, 0)
    plc.drive("Execute")
    assert plc.unit.transitions == 4


def test_the_line_program_runs_a_batch_and_stops_the_unit() -> None:
    line = PackagingLine()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), line)
    rt.run(cycles=100)
    assert (line.unit.state, line.unit.execute.packs) == (PackMLState.SUSPENDED, 3)
    rt.run(cycles=200)
    assert (line.unit.state, line.unit.execute.packs, line.batches) == (PackMLState.STOPPED, 5, 1)
    assert (line.unit.refused, line.unit.last_refused, line.unit.transitions) == (1, PackMLCommand.START, 14)


# ---------------------------------------------------------------------------
# Invariant
# ---------------------------------------------------------------------------

ALL_COMMANDS = sorted(COMMANDS)


def commands_for(state: str) -> st.SearchStrategy[str]:
    """Any command, with a bias towards the ones that lead on from ``state`` (so runs get deep)."""
    allowed = sorted(c for (s, c) in TABLE if s == state and c != "SC")
    ahead = [c for c in allowed if c not in ("Abort", "Stop")]
    return st.sampled_from(ahead or ALL_COMMANDS) | st.sampled_from(allowed or ALL_COMMANDS) | st.sampled_from(
        ALL_COMMANDS
    )


@settings(max_examples=100, deadline=None)
@given(data=st.data(), fast=st.booleans(), batch=st.integers(1, 30))
def test_random_commands_and_cycles_only_make_transitions_the_table_allows(
    data: st.DataObject, fast: bool, batch: int
) -> None:
    plc = Plc(fast)
    plc.unit.execute.batch_size = batch
    refused = 0
    for _ in range(data.draw(st.integers(0, 40), label="commands")):
        before = state_name(plc.unit.state)
        name = data.draw(commands_for(before), label="command")
        count = plc.unit.transitions
        accepted = plc.send(COMMANDS[name])
        after = state_name(plc.unit.state)
        if accepted:
            assert (TABLE.get((before, name)), plc.unit.transitions) == (after, count + 1), (before, name)
        else:
            # Refused; the scan it was given in may still complete an acting state.
            refused += 1
            assert (before, name) not in TABLE
            assert after == before or TABLE.get((before, "SC")) == after, (before, after)
        for _ in range(data.draw(st.integers(0, 3) | st.integers(0, 30), label="scans")):
            before = state_name(plc.unit.state)
            plc.rt.run(cycles=1)
            after = state_name(plc.unit.state)
            assert after == before or TABLE.get((before, "SC")) == after, (before, after)
    assert plc.unit.refused == refused
