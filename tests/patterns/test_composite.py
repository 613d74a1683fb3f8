"""The conveyor composite, run cycle after cycle on the virtual clock."""

from __future__ import annotations

from typing import Union

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import (
    ARRAY,
    BOOL,
    VAR,
    VAR_INPUT,
    DefinitionError,
    ExceptionCode,
    PlcException,
    Program,
    T,
)
from iecoop.runtime import Runtime, Task
from patterns.structural.composite import (
    MAX_CHILDREN,
    MAX_DEPTH,
    AddResult,
    ConveyorElement,
    ConveyorGroup,
    ConveyorMain,
    ConveyorSection,
    IConveyorElement,
)


def _runtime(prog: Program) -> Runtime:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), prog)
    return rt


def _on(prog: ConveyorMain) -> list[str]:
    return [s.name for s in (prog.s1, prog.s2, prog.s3, prog.s4, prog.s5) if s.contactor]


def _started(prog: ConveyorMain) -> Runtime:
    rt = _runtime(prog)
    prog.cmd_start = True
    rt.run(cycles=1)
    prog.cmd_start = False
    return rt


# ---------------------------------------------------------------------------
# The line program
# ---------------------------------------------------------------------------


def test_wiring_builds_line_zones_sections_with_levels_and_heights() -> None:
    prog = ConveyorMain()
    assert prog.wired
    assert (prog.line.count, prog.infeed.count, prog.transfer.count) == (2, 2, 3)
    assert (prog.line.level, prog.transfer.level, prog.s5.level) == (1, 2, 3)
    assert (prog.line.height, prog.infeed.height, prog.s1.height) == (3, 2, 1)
    assert prog.line.contains(prog.s4) and prog.transfer.contains(prog.s4)
    assert not prog.infeed.contains(prog.s4)


def test_start_is_staggered_downstream_first_across_cycles() -> None:
    prog = ConveyorMain()
    rt = _started(prog)
    seen = {rt.time_ms: _on(prog)}
    for _ in range(25):
        rt.run(cycles=1)
        seen[rt.time_ms] = _on(prog)
    assert seen[10] == ["S5"]
    assert seen[100] == ["S5"]
    assert seen[110] == ["S2", "S4", "S5"]
    assert seen[210] == ["S1", "S2", "S3", "S4", "S5"]
    assert prog.power_kw == pytest.approx(4.8)


def test_line_is_running_only_when_every_section_is_at_speed() -> None:
    prog = ConveyorMain()
    rt = _started(prog)
    rt.run(cycles=49)
    assert rt.time_ms == 500
    # S1 and S3 got their contactor in the scan at 200 ms; the run-up takes 300 ms.
    assert (prog.s5.is_running, prog.s2.is_running, prog.infeed.is_running, prog.running) == (True, True, False, False)
    rt.run(cycles=1)
    assert (prog.transfer.is_running, prog.infeed.is_running, prog.running) == (True, True, True)


def test_stop_drops_every_contactor_in_the_same_cycle_and_cancels_pending_starts() -> None:
    prog = ConveyorMain()
    rt = _started(prog)
    rt.run(cycles=5)
    assert _on(prog) == ["S5"]
    prog.cmd_stop = True
    rt.run(cycles=1)
    assert _on(prog) == [] and prog.power_kw == 0.0
    prog.cmd_stop = False
    rt.run(cycles=40)
    assert _on(prog) == [] and not prog.running


def test_a_trip_faults_and_stops_the_line_and_reset_needs_the_trip_cleared() -> None:
    prog = ConveyorMain()
    rt = _started(prog)
    rt.run(cycles=60)
    assert prog.running
    prog.s3.motor_trip = True
    rt.run(cycles=1)
    assert prog.faulted and prog.transfer.is_faulted and not prog.infeed.is_faulted
    assert _on(prog) == [] and prog.power_kw == 0.0
    prog.cmd_reset = True
    rt.run(cycles=2)
    assert prog.faulted, "reset is refused while the motor protection is still tripped"
    prog.cmd_reset = False
    prog.s3.motor_trip = False
    rt.run(cycles=1)
    assert prog.faulted, "the fault is latched"
    prog.cmd_reset = True
    rt.run(cycles=1)
    assert (prog.faulted, prog.running) == (False, False)
    prog.cmd_reset = False
    prog.cmd_start = True
    rt.run(cycles=60)
    assert prog.running and prog.power_kw == pytest.approx(4.8)


def test_cold_reset_rewires_the_tree() -> None:
    prog = ConveyorMain()
    rt = _started(prog)
    rt.run(cycles=60)
    rt.reset_cold()
    assert prog.wired and prog.line.count == 2 and not prog.running
    prog.cmd_start = False
    rt.run(cycles=1)
    prog.cmd_start = True
    rt.run(cycles=60)
    assert prog.running


# ---------------------------------------------------------------------------
# Building trees: what add() refuses
# ---------------------------------------------------------------------------


class Pool(Program):
    """Statically allocated elements for building trees in tests."""

    sections: ARRAY[ConveyorSection] = VAR(bounds=(1, 30))
    groups: ARRAY[ConveyorGroup] = VAR(bounds=(1, 15))
    root: IConveyorElement = VAR_INPUT()
    nothing: IConveyorElement = VAR()
    cmd_start: BOOL = VAR_INPUT(False)

    def body(self) -> None:
        if self.cmd_start:
            self.root.start()
            self.cmd_start = False
        self.root.scan()


def test_add_refuses_null_self_and_elements_already_in_a_tree() -> None:
    pool = Pool()
    zone, other = pool.groups[1], pool.groups[2]
    assert zone.add(pool.nothing) == AddResult.NULL_ELEMENT
    assert zone.add(zone) == AddResult.SELF
    assert zone.add(pool.sections[1]) == AddResult.ADDED
    assert zone.add(pool.sections[1]) == AddResult.ALREADY_IN_TREE
    assert other.add(pool.sections[1]) == AddResult.ALREADY_IN_TREE
    assert (zone.count, other.count) == (1, 0)


def test_add_refuses_a_cycle_through_a_subtree() -> None:
    pool = Pool()
    line, zone, sub = pool.groups[1], pool.groups[2], pool.groups[3]
    assert zone.add(sub) == AddResult.ADDED
    assert line.add(zone) == AddResult.ADDED
    assert sub.add(line) == AddResult.CYCLE
    assert sub.count == 0 and line.level == 1


def test_add_refuses_the_child_after_the_array_is_full() -> None:
    pool = Pool()
    zone = pool.groups[1]
    for i in range(1, MAX_CHILDREN + 1):
        assert zone.add(pool.sections[i]) == AddResult.ADDED
    assert zone.add(pool.sections[MAX_CHILDREN + 1]) == AddResult.FULL
    assert zone.count == MAX_CHILDREN
    assert pool.sections[MAX_CHILDREN + 1].level == 1


def test_add_refuses_a_tree_deeper_than_max_depth_at_any_level() -> None:
    pool = Pool()
    chain = [pool.groups[i] for i in range(1, MAX_DEPTH + 1)]
    for parent, child in zip(chain, chain[1:]):
        assert parent.add(child) == AddResult.ADDED
    assert [g.level for g in chain] == list(range(1, MAX_DEPTH + 1))
    assert chain[-1].add(pool.sections[1]) == AddResult.TOO_DEEP
    assert chain[-2].add(pool.sections[1]) == AddResult.ADDED
    # A two-level subtree fits under level 2 but not under level 3.
    sub = pool.groups[MAX_DEPTH + 1]
    assert sub.add(pool.sections[2]) == AddResult.ADDED
    assert chain[2].add(sub) == AddResult.TOO_DEEP
    assert chain[1].add(sub) == AddResult.ADDED
    assert (sub.level, pool.sections[2].level) == (3, 4)
    assert chain[0].height == MAX_DEPTH


def test_adding_a_built_subtree_moves_all_its_levels() -> None:
    pool = Pool()
    line, zone = pool.groups[1], pool.groups[2]
    zone.add(pool.sections[1])
    assert pool.sections[1].level == 2
    line.add(zone)
    assert (zone.level, pool.sections[1].level) == (2, 3)


def test_an_empty_group_is_neither_running_nor_faulted_and_draws_nothing() -> None:
    zone = ConveyorGroup(name="Empty")
    zone.start()
    zone.scan()
    assert (zone.is_running, zone.is_faulted, zone.power_kw, zone.height) == (False, False, 0.0, 1)


def test_the_abstract_element_cannot_be_instantiated() -> None:
    with pytest.raises(DefinitionError, match="ConveyorElement"):
        ConveyorElement()


def test_a_program_scanning_an_unwired_root_faults_with_an_access_violation() -> None:
    pool = Pool()
    rt = _runtime(pool)
    with pytest.raises(PlcException, match="ACCESS_VIOLATION") as info:
        rt.run(cycles=1)
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


# ---------------------------------------------------------------------------
# The invariant: a group is the AND / OR / sum of its leaves
# ---------------------------------------------------------------------------

Leaf = tuple[bool, float]
Node = Union[Leaf, list["Node"]]


def _nodes(depth: int) -> st.SearchStrategy[Node]:
    leaf: st.SearchStrategy[Node] = st.tuples(st.booleans(), st.sampled_from([0.37, 0.55, 1.1, 2.2, 7.5]))
    if depth == 1:
        return leaf
    return st.one_of(leaf, st.lists(_nodes(depth - 1), max_size=3))


def _build(pool: Pool, node: Node, used: list[int]) -> IConveyorElement:
    if isinstance(node, tuple):
        used[0] += 1
        section = pool.sections[used[0]]
        section.motor_trip, section.rated_kw = node
        return section
    used[1] += 1
    group = pool.groups[used[1]]
    group.stagger_time = 0
    for child in node:
        assert group.add(_build(pool, child, used)) == AddResult.ADDED
    return group


def _model(node: Node) -> tuple[bool, bool, float]:
    if isinstance(node, tuple):
        tripped, kw = node
        return (not tripped, tripped, 0.0 if tripped else kw)
    kids = [_model(child) for child in node]
    power = 0.0
    for _running, _faulted, kw in kids:
        power += kw
    return (bool(kids) and all(k[0] for k in kids), any(k[1] for k in kids), power)


@settings(max_examples=60, deadline=None)
@given(tree=_nodes(MAX_DEPTH))
def test_group_state_is_and_or_and_sum_of_its_leaves(tree: Node) -> None:
    pool = Pool()
    pool.root = _build(pool, tree, [0, 0])
    assert pool.root.height <= MAX_DEPTH
    pool.cmd_start = True
    rt = _runtime(pool)
    rt.run(cycles=70)
    running, faulted, power = _model(tree)
    assert pool.root.is_faulted == faulted
    assert pool.root.power_kw == power
    assert pool.root.is_running == running


def test_wiring_twice_refuses_every_element_and_clears_wired() -> None:
    prog = ConveyorMain()
    first = prog.wired
    prog.wire()  # every element is in the tree already: each add answers ALREADY_IN_TREE
    assert (first, prog.wired) == (True, False)
    assert (prog.line.count, prog.infeed.count, prog.transfer.count) == (2, 2, 3)
