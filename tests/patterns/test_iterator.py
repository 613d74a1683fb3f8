"""Iterator: the alarm history ring walked newest first, filtered and paged on the HMI, across cycles."""

from __future__ import annotations

from collections import deque

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import AccessError, ExceptionCode, PlcException, T, delete, new
from iecoop.runtime import Runtime, Task, default_clock
from patterns.behavioral.iterator import (
    ALARM_CAPACITY,
    DEMO_ALARMS,
    PAGE_ROWS,
    AlarmEntry,
    AlarmHistory,
    AlarmHmi,
    AlarmIterator,
    AlarmPager,
    IAlarmIterator,
    Severity,
    SeverityFilter,
)
from tests import checked_only


def _history(n: int) -> AlarmHistory:
    history = AlarmHistory()
    for i in range(1, n + 1):
        history.push(1000 + i, Severity((i % 4) + 1), f"alarm {i}")
    return history


def _walk(iterator: IAlarmIterator) -> list[int]:
    entry, seen = AlarmEntry(), []
    while iterator.has_next():
        iterator.next(entry)
        seen.append(entry.sequence)
    return seen


def _hmi() -> tuple[AlarmHmi, Runtime]:
    hmi = AlarmHmi()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), hmi)
    return hmi, rt


def _press(rt: Runtime, pager: AlarmPager, button: str, held: int = 3) -> list[int]:
    setattr(pager, button, True)
    rt.run(cycles=held)
    setattr(pager, button, False)
    rt.run(cycles=1)
    return [pager.rows[i].sequence for i in range(1, pager.row_count + 1)]


# ---------------------------------------------------------------------------
# The iterator over the ring
# ---------------------------------------------------------------------------


def test_a_wrapped_ring_is_walked_newest_first_with_every_field_copied() -> None:
    clock = default_clock()
    history = AlarmHistory()
    for i in range(1, ALARM_CAPACITY + 4):
        clock.set(i * 5_000_000)
        history.push(200 + i, Severity.WARNING, f"TT{i} high")
    iterator = AlarmIterator(history=history)
    entry = AlarmEntry()
    assert iterator.has_next()
    iterator.next(entry)
    newest = ALARM_CAPACITY + 3
    assert (entry.sequence, entry.code, entry.raised_at) == (newest, 200 + newest, 5 * newest)
    assert entry.text == f"TT{newest} high"
    assert Severity(entry.severity) is Severity.WARNING
    rest = _walk(iterator)
    assert rest == list(range(newest - 1, newest - ALARM_CAPACITY, -1))
    assert (iterator.position, iterator.overrun) == (ALARM_CAPACITY, False)


def test_next_past_the_end_answers_false_and_reset_starts_again_from_the_newest() -> None:
    history = _history(3)
    iterator = AlarmIterator(history=history)
    assert _walk(iterator) == [3, 2, 1]
    entry = AlarmEntry(sequence=99, text="untouched")
    assert iterator.next(entry) is False
    assert (entry.sequence, entry.text, iterator.position) == (99, "untouched", 3)
    history.push(7, Severity.ALARM, "new")
    assert _walk(iterator) == []
    iterator.reset()
    assert _walk(iterator) == [4, 3, 2, 1]


def test_an_empty_history_yields_nothing() -> None:
    history = AlarmHistory()
    iterator = AlarmIterator(history=history)
    assert iterator.has_next() is False
    assert (_walk(iterator), iterator.overrun) == ([], False)


def test_alarms_raised_while_walking_do_not_shift_the_walk() -> None:
    history = _history(5)
    iterator = AlarmIterator(history=history)
    entry = AlarmEntry()
    iterator.next(entry)
    iterator.next(entry)
    history.push(50, Severity.INFO, "later")
    assert _walk(iterator) == [3, 2, 1]
    assert iterator.overrun is False


def test_an_alarm_overwritten_while_walking_is_never_returned() -> None:
    history = _history(ALARM_CAPACITY)
    iterator = AlarmIterator(history=history)
    entry = AlarmEntry()
    for _ in range(3):
        iterator.next(entry)
    assert entry.sequence == ALARM_CAPACITY - 2
    for i in range(3):
        history.push(900 + i, Severity.INFO, "burst")
    # Alarms 1..3 were overwritten by the burst: the walk stops at 4 and says why.
    assert _walk(iterator) == list(range(ALARM_CAPACITY - 3, 3, -1))
    assert iterator.overrun is True


def test_the_ring_is_read_only_from_outside_the_library() -> None:
    history = _history(2)
    with pytest.raises(AccessError, match=r"INTERNAL METHOD AlarmHistory\.copy_out cannot be called"):
        history.copy_out(1, AlarmEntry())
    assert _walk(AlarmIterator(history=history)) == [2, 1]


@checked_only
def test_the_ring_and_its_count_cannot_be_assigned_from_outside() -> None:
    history = _history(2)
    with pytest.raises(AccessError, match=r"VAR AlarmHistory\.ring cannot be written from"):
        history.ring = _history(1).ring
    with pytest.raises(AccessError, match=r"VAR_OUTPUT AlarmHistory\.total cannot be written from"):
        history.total = 0
    assert _walk(AlarmIterator(history=history)) == [2, 1]


def test_an_iterator_without_a_live_history_yields_nothing() -> None:
    unbound = AlarmIterator()
    unbound.reset()
    assert (unbound.bound, unbound.has_next(), unbound.next(AlarmEntry())) == (False, False, False)
    p_history = new(AlarmHistory)
    p_history.deref.push(1, Severity.INFO, "x")
    p_history.deref.push(2, Severity.INFO, "y")
    iterator = AlarmIterator(history=p_history.deref)
    entry = AlarmEntry()
    assert (iterator.bound, iterator.next(entry), entry.sequence) == (True, True, 2)
    delete(p_history)
    # The history is gone mid-walk: the iterator stops instead of reading freed memory.
    assert (iterator.bound, iterator.has_next(), iterator.next(entry), entry.sequence) == (False, False, False, 2)
    iterator.reset()
    assert _walk(iterator) == []
    iterator.bind(_history(2))
    assert _walk(iterator) == [2, 1]


# ---------------------------------------------------------------------------
# The filter and the pager
# ---------------------------------------------------------------------------


def test_the_severity_filter_keeps_the_order_and_skips_low_severities() -> None:
    history = _history(ALARM_CAPACITY + 2)
    cursor = AlarmIterator(history=history)
    critical = SeverityFilter(source=cursor, minimum=Severity.CRITICAL)
    expected = [i for i in range(ALARM_CAPACITY + 2, 2, -1) if (i % 4) + 1 == Severity.CRITICAL]
    assert _walk(critical) == expected
    critical.reset()
    assert critical.has_next() and critical.has_next()  # looking ahead twice reads no further
    assert _walk(critical) == expected
    assert critical.next(AlarmEntry()) is False
    cursor.reset()
    entries = []
    entry = AlarmEntry()
    while critical.next(entry):          # the ST idiom: WHILE it.Next(entry) DO
        entries.append(entry.sequence)
    assert entries == expected


def test_a_filter_or_pager_without_its_iterator_faults_on_use() -> None:
    with pytest.raises(PlcException, match="null interface") as info:
        SeverityFilter().reset()
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION
    pager = AlarmPager()
    with pytest.raises(PlcException, match="null interface"):
        pager(first_page=True)


def test_the_page_buttons_page_through_the_history_across_cycles() -> None:
    hmi, rt = _hmi()
    hmi.simulate = True
    rt.run(cycles=len(DEMO_ALARMS))
    hmi.simulate = False
    pager = hmi.all_pager
    assert _press(rt, pager, "first_page") == [10, 9, 8, 7]
    assert _press(rt, pager, "next_page", held=6) == [6, 5, 4, 3]  # held for 6 cycles: one page only
    assert (pager.page, pager.more) == (2, False)
    assert _press(rt, pager, "next_page") == [6, 5, 4, 3]
    assert _press(rt, pager, "prev_page") == [10, 9, 8, 7]
    assert _press(rt, hmi.alarm_pager, "first_page") == [10, 8, 5, 3]
    assert hmi.alarm_pager.more is False


def test_page_one_follows_new_alarms_and_a_page_past_the_end_is_empty() -> None:
    hmi, rt = _hmi()
    hmi.simulate = True
    rt.run(cycles=3)
    hmi.simulate = False
    pager = hmi.all_pager
    assert _press(rt, pager, "first_page") == [3, 2, 1]
    hmi.simulate = True
    rt.run(cycles=2)
    hmi.simulate = False
    assert _press(rt, pager, "first_page") == [5, 4, 3, 2]
    assert (pager.show(3), pager.page, pager.more) == (0, 3, False)
    assert pager.show(1) == PAGE_ROWS
    assert [pager.show(0), pager.show(-2)] == [0, 0]
    assert (pager.page, pager.row_count, pager.rows[1].sequence) == (1, PAGE_ROWS, 5)


def test_a_reset_cold_empties_the_history_and_keeps_the_wiring() -> None:
    hmi, rt = _hmi()
    hmi.simulate = True
    rt.run(cycles=4)
    rt.reset_cold()
    assert (hmi.history.total, hmi.simulate) == (0, False)
    assert _press(rt, hmi.all_pager, "first_page") == []
    hmi.simulate = True
    rt.run(cycles=2)
    hmi.simulate = False
    assert _press(rt, hmi.all_pager, "first_page") == [2, 1]
    assert _press(rt, hmi.alarm_pager, "first_page") == []  # the demo's first two alarms are below ALARM


# ---------------------------------------------------------------------------
# Invariants against a Python deque
# ---------------------------------------------------------------------------


@settings(max_examples=60, deadline=None)
@given(n=st.integers(0, 3 * ALARM_CAPACITY))
def test_the_iterator_matches_a_bounded_deque_newest_first(n: int) -> None:
    reference: deque[tuple[int, int, str]] = deque(maxlen=ALARM_CAPACITY)
    history = AlarmHistory()
    for i in range(1, n + 1):
        history.push(1000 + i, Severity.INFO, f"alarm {i}")
        reference.append((i, 1000 + i, f"alarm {i}"))
    iterator = AlarmIterator(history=history)
    entry, seen = AlarmEntry(), []
    while iterator.has_next():
        iterator.next(entry)
        seen.append((entry.sequence, entry.code, entry.text))
    assert seen == list(reversed(reference))
    assert len(seen) == min(n, ALARM_CAPACITY) == history.count


@settings(max_examples=40, deadline=None)
@given(n=st.integers(0, 3 * ALARM_CAPACITY), minimum=st.sampled_from(list(Severity)))
def test_pages_put_together_are_the_filtered_walk(n: int, minimum: Severity) -> None:
    history = _history(n)
    cursor = AlarmIterator(history=history)
    source = SeverityFilter(source=cursor, minimum=minimum)
    pager = AlarmPager(iterator=source)
    pages: list[list[int]] = []
    page = 1
    while pager.show(page) > 0:
        pages.append([pager.rows[i].sequence for i in range(1, pager.row_count + 1)])
        if not pager.more:
            break
        page += 1
    source.reset()
    walk = _walk(source)
    assert [seq for rows in pages for seq in rows] == walk
    assert all(len(rows) == PAGE_ROWS for rows in pages[:-1])
    assert walk == [s for s in range(n, max(n - ALARM_CAPACITY, 0), -1) if (s % 4) + 1 >= minimum]


@settings(max_examples=60, deadline=None)
@given(
    before=st.integers(0, 2 * ALARM_CAPACITY),
    read=st.integers(0, ALARM_CAPACITY),
    burst=st.integers(0, 2 * ALARM_CAPACITY),
)
def test_a_walk_interrupted_by_new_alarms_never_returns_a_wrong_entry(before: int, read: int, burst: int) -> None:
    history = _history(before)
    iterator = AlarmIterator(history=history)
    entry, seen = AlarmEntry(), []
    for _ in range(read):
        if not iterator.has_next():
            break
        iterator.next(entry)
        seen.append((entry.sequence, entry.text))
    for i in range(burst):
        history.push(1, Severity.INFO, f"burst {i}")
    while iterator.has_next():
        iterator.next(entry)
        seen.append((entry.sequence, entry.text))
    sequences = [s for s, _ in seen]
    assert sequences == list(range(before, before - len(seen), -1))
    assert all(text == f"alarm {s}" for s, text in seen)
    # Either the walk got every alarm the ring held when it was anchored, or it says it was overrun,
    # and then the alarm it stopped at really was overwritten.
    assert iterator.overrun == (len(seen) < min(before, ALARM_CAPACITY))
    if iterator.overrun:
        assert history.total - (before - len(seen)) >= ALARM_CAPACITY
