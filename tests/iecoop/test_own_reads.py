"""A block's compiled body reads its own STRUCT / ARRAY variables without the checked read's frame inspection.

Checked mode marks a view read from outside the block as read-only, which
needs a look at the reading frame. The block's own body may always write its
own variables, so its compiled call reads the view directly; reads from
other code keep the check and its message.
"""

from __future__ import annotations

from typing import Any

import pytest

from iecoop import ARRAY, BOOL, INT, VAR, VAR_INPUT, AccessError, FunctionBlock, Program, Struct, T, _config
from iecoop.memory._views import CheckedMemberField
from iecoop.runtime import Runtime, Task
from iecoop.stdlib import R_TRIG

pytestmark = pytest.mark.skipif(not _config.CHECKS, reason="checked mode checks who reads a STRUCT / ARRAY view")


class Pair(Struct):
    """ST: STRUCT a : INT; b : INT; END_STRUCT"""

    a: INT = VAR()
    b: INT = VAR()


class Edges(FunctionBlock):
    """Keeps an ARRAY OF FB, an ARRAY OF INT and a STRUCT, and reads all three from its body."""

    sensor: BOOL = VAR_INPUT()
    triggers: ARRAY[R_TRIG] = VAR(bounds=(1, 3))
    counts: ARRAY[INT] = VAR(bounds=(1, 3))
    pair: Pair = VAR()
    LIMITS: ARRAY[INT] = VAR([7, 8, 9], bounds=(1, 3), constant=True)

    def body(self) -> None:
        for i in range(1, 4):
            self.triggers[i](CLK=self.sensor)
            if self.triggers[i].Q:
                self.counts[i] = self.counts[i] + 1
        self.pair.a = self.counts[1] + self.LIMITS[1]


class Overwrite(FunctionBlock):
    """Its body writes an element of its CONSTANT ARRAY."""

    LIMITS: ARRAY[INT] = VAR([7, 8, 9], bounds=(1, 3), constant=True)

    def body(self) -> None:
        self.LIMITS[1] = 0


class Line(Program):
    """PROGRAM Line: calls its blocks in a loop, as users write it."""

    edges: ARRAY[Edges] = VAR(bounds=(1, 2))

    def body(self) -> None:
        for i in range(1, 3):
            self.edges[i](sensor=True)


def _count_rule_calls(monkeypatch: pytest.MonkeyPatch, cls: type, names: list[str]) -> list[str]:
    calls: list[str] = []
    for name in names:
        field = cls.__dict__[name]
        assert isinstance(field, CheckedMemberField)
        rule = field.rule
        assert rule is not None

        def counting(holder: Any, frame: Any, rule: Any = rule, name: str = name) -> str | None:
            calls.append(name)
            return rule(holder, frame)  # type: ignore[no-any-return]

        monkeypatch.setattr(field, "rule", counting)
    return calls


def test_the_body_reads_its_own_arrays_and_structs_without_the_rule_check(monkeypatch: pytest.MonkeyPatch) -> None:
    calls = _count_rule_calls(monkeypatch, Edges, ["triggers", "counts", "pair"])
    edges = Edges()
    edges(sensor=True)
    edges(sensor=False)
    edges(sensor=True)
    assert calls == []
    # A read from other code still asks the rule.
    assert list(edges.counts) == [2, 2, 2]
    assert edges.pair.a == 2 + 7
    assert calls == ["counts", "pair"]


def test_a_program_loop_over_its_array_of_blocks_makes_no_frame_inspection(monkeypatch: pytest.MonkeyPatch) -> None:
    calls = _count_rule_calls(monkeypatch, Line, ["edges"])
    calls += _count_rule_calls(monkeypatch, Edges, ["triggers", "counts", "pair"])
    line = Line()
    for _ in range(3):
        line()
    assert calls == []


def test_reads_from_outside_keep_the_read_only_view_after_the_body_read_its_own() -> None:
    edges = Edges()
    edges(sensor=True)
    with pytest.raises(AccessError, match="cannot be written from"):
        edges.counts[1] = 5
    with pytest.raises(AccessError, match="cannot be written from"):
        edges.pair.a = 5
    with pytest.raises(AccessError, match="cannot be written from"):
        edges.triggers[1] = R_TRIG()
    assert edges.counts[1] == 1


def test_the_body_still_cannot_write_its_constant_array() -> None:
    with pytest.raises(AccessError, match="CONSTANT"):
        Overwrite()()


def test_a_runtime_task_runs_the_program_through_its_compiled_call(monkeypatch: pytest.MonkeyPatch) -> None:
    calls = _count_rule_calls(monkeypatch, Line, ["edges"])
    line = Line()
    runtime = Runtime(store=":memory:")
    runtime.add_task(Task("PlcTask", interval=T("10ms"), priority=20), line)
    runtime.run(cycles=2)
    assert calls == []
    assert list(line.edges[1].counts) == [1, 1, 1]
