"""R_TRIG / F_TRIG against their IEC definition (docs/reference/stdlib.md), including the first-call behaviour."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from iecoop.stdlib import F_TRIG, R_TRIG


def outputs(trigger: R_TRIG | F_TRIG, clks: list[bool]) -> list[bool]:
    found = []
    for clk in clks:
        trigger(CLK=clk)
        found.append(trigger.Q)
    return found


def test_r_trig_initial_state() -> None:
    trigger = R_TRIG()
    assert (trigger.CLK, trigger.Q, trigger.M) == (False, False, False)


def test_r_trig_q_for_one_call_per_rising_edge() -> None:
    assert outputs(R_TRIG(), [False, True, True, True, False, False, True, False]) == [
        False, True, False, False, False, False, True, False,
    ]


def test_r_trig_first_call_with_clk_true_is_an_edge() -> None:
    trigger = R_TRIG()
    trigger(CLK=True)
    assert trigger.Q and trigger.M


def test_r_trig_first_call_with_clk_false_is_not() -> None:
    trigger = R_TRIG()
    trigger(CLK=False)
    assert not trigger.Q and not trigger.M


def test_r_trig_a_call_without_inputs_reuses_the_last_clk() -> None:
    trigger = R_TRIG()
    trigger(CLK=True)
    trigger()
    assert not trigger.Q


def test_f_trig_initial_state() -> None:
    trigger = F_TRIG()
    assert (trigger.CLK, trigger.Q, trigger.M) == (False, False, False)


def test_f_trig_first_call_with_clk_false_is_a_falling_edge() -> None:
    trigger = F_TRIG()
    trigger(CLK=False)
    assert trigger.Q and trigger.M
    trigger(CLK=False)
    assert not trigger.Q


def test_f_trig_first_call_with_clk_true_is_not() -> None:
    assert outputs(F_TRIG(), [True, True, False, False, True, False]) == [False, False, True, False, False, True]


@given(st.lists(st.booleans(), max_size=80))
def test_r_trig_is_true_exactly_on_rising_edges(clks: list[bool]) -> None:
    previous = [False, *clks[:-1]]
    assert outputs(R_TRIG(), clks) == [clk and not before for clk, before in zip(clks, previous)]


@given(st.lists(st.booleans(), max_size=80))
def test_f_trig_is_true_exactly_on_falling_edges_after_an_implicit_true(clks: list[bool]) -> None:
    # M starts FALSE, which is "CLK was TRUE before the first call".
    previous = [True, *clks[:-1]]
    assert outputs(F_TRIG(), clks) == [before and not clk for clk, before in zip(clks, previous)]


@given(st.lists(st.booleans(), max_size=80))
def test_triggers_mirror_each_other(clks: list[bool]) -> None:
    rising, falling = R_TRIG(), F_TRIG()
    for clk in clks:
        rising(CLK=clk)
        falling(CLK=not clk)
        assert rising.Q == falling.Q
