"""SR / RS against their IEC definition (docs/reference/stdlib.md): every input combination from both previous states."""

from __future__ import annotations

import itertools

import pytest
from hypothesis import given
from hypothesis import strategies as st

from iecoop.stdlib import RS, SR

BOOLS = (False, True)


def sr_at(q1: bool) -> SR:
    latch = SR()
    latch(SET1=q1, RESET=not q1)
    assert latch.Q1 == q1
    return latch


def rs_at(q1: bool) -> RS:
    latch = RS()
    latch(SET=q1, RESET1=not q1)
    assert latch.Q1 == q1
    return latch


@pytest.mark.parametrize(("q1", "set1", "reset"), list(itertools.product(BOOLS, BOOLS, BOOLS)))
def test_sr_truth_table(q1: bool, set1: bool, reset: bool) -> None:
    latch = sr_at(q1)
    latch(SET1=set1, RESET=reset)
    assert latch.Q1 == (set1 or (not reset and q1))


@pytest.mark.parametrize(("q1", "set_", "reset1"), list(itertools.product(BOOLS, BOOLS, BOOLS)))
def test_rs_truth_table(q1: bool, set_: bool, reset1: bool) -> None:
    latch = rs_at(q1)
    latch(SET=set_, RESET1=reset1)
    assert latch.Q1 == (not reset1 and (set_ or q1))


def test_sr_set_dominates_and_rs_reset_dominates() -> None:
    sr, rs = SR(), RS()
    sr(SET1=True, RESET=True)
    rs(SET=True, RESET1=True)
    assert (sr.Q1, rs.Q1) == (True, False)


def test_initial_state_is_reset() -> None:
    assert not SR().Q1 and not RS().Q1


def test_level_sensitive_a_held_set_keeps_acting() -> None:
    latch = SR()
    found = []
    latch(SET1=True)
    latch(SET1=True, RESET=True)  # no edge needed: SET1 still TRUE wins
    found.append(latch.Q1)
    latch(SET1=False)  # RESET still TRUE
    found.append(latch.Q1)
    latch(SET1=True)
    found.append(latch.Q1)
    assert found == [True, False, True]


@given(st.lists(st.tuples(st.booleans(), st.booleans()), max_size=60))
def test_sr_and_rs_follow_their_equations(inputs: list[tuple[bool, bool]]) -> None:
    sr, rs = SR(), RS()
    sr_q = rs_q = False
    for set_, reset in inputs:
        sr(SET1=set_, RESET=reset)
        rs(SET=set_, RESET1=reset)
        sr_q = set_ or (not reset and sr_q)
        rs_q = not reset and (set_ or rs_q)
        assert (sr.Q1, rs.Q1) == (sr_q, rs_q)
        if set_ != reset:
            assert sr.Q1 == rs.Q1 == set_
