"""Chapter 15: ExST S= and R=, the latch of FB_MotorControl, and chained assignments."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from iecoop_examples.ch15_exst import SEQUENCE, Main, MotorControl, main
from iecoop import BOOL, INT, AccessError, Struct, T
from iecoop.runtime import Runtime, Task
from iecoop.stdlib import R, S
from tests import checked_only

BUTTONS = st.fixed_dictionaries({name: st.booleans() for name in ("start", "stop", "fault", "ack")})


class Flags(Struct):
    a: BOOL = False
    b: BOOL = True
    count: INT = 0


def _model(state: dict[str, bool], start: bool, stop: bool, fault: bool, ack: bool) -> dict[str, bool]:
    """The same FB written with plain IF statements, as the S= / R= lines expand."""
    running, alarm = state["running"], state["alarm"]
    if start and not alarm:
        running = True
    if stop:
        running = False
    if fault:
        running = False
        alarm = True
    if ack:
        alarm = False
    return {"follow": start, "running": running, "alarm": alarm}


def test_main_plays_the_sequence_cycle_by_cycle() -> None:
    program = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    expected_running = [False, True, True, False, True, False, False, False, True]
    expected_alarm = [False, False, False, False, False, True, True, False, False]
    for button, running, alarm in zip(SEQUENCE, expected_running, expected_alarm, strict=True):
        for name in ("start", "stop", "fault", "ack"):
            setattr(program, name, name == button)
        rt.run(cycles=1)
        assert program.motor.follow is (button == "start")
        assert (program.motor.running, program.motor.alarm) == (running, alarm)


@given(st.lists(BUTTONS, max_size=40))
def test_s_and_r_behave_like_the_if_statements_they_replace(cycles: list[dict[str, bool]]) -> None:
    motor = MotorControl()
    state = {"follow": False, "running": False, "alarm": False}
    for buttons in cycles:
        motor(**buttons)
        state = _model(state, **buttons)
        assert {"follow": motor.follow, "running": motor.running, "alarm": motor.alarm} == state


def test_a_set_variable_stays_set_while_the_condition_is_false() -> None:
    flags = Flags()
    assert S(flags, "a", True) is True
    for _ in range(5):
        assert S(flags, "a", False) is False
        assert flags.a is True
    R(flags, "a", True)
    assert flags.a is False


def test_a_chain_acts_on_the_operand_at_the_end_of_the_line() -> None:
    flags = Flags()  # a S= b R= TRUE: a set and b reset, both by TRUE
    S(flags, "a", R(flags, "b", True))
    assert (flags.a, flags.b) == (True, False)
    flags = Flags()  # with FALSE at the end neither moves
    S(flags, "a", R(flags, "b", False))
    assert (flags.a, flags.b) == (False, True)


def test_s_and_r_assign_bool_variables_only() -> None:
    with pytest.raises(TypeError, match=r"S=: Flags\.count is not a BOOL variable"):
        S(Flags(), "count", True)
    with pytest.raises(TypeError, match=r"R=: Flags\.count is not a BOOL variable"):
        R(Flags(), "count", True)


@checked_only
def test_an_output_is_set_only_by_its_own_block() -> None:
    motor = MotorControl()
    with pytest.raises(AccessError, match=r"VAR_OUTPUT MotorControl\.running cannot be written from"):
        S(motor, "running", True)
    assert motor.running is False


def test_main_prints_nine_cycles(capsys: pytest.CaptureFixture[str]) -> None:
    main()
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == len(SEQUENCE)
    assert lines[5] == "t= 50 ms  button fault  bFollow=False  bRunning=False  bAlarm=True"
