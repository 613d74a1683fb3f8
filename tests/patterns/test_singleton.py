"""Singleton: the plant log is really one log; the injected logger is the one that is easy to test."""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import BOOL, VAR, VAR_INPUT, AccessError, DefinitionError, ExceptionCode, PlcException, Program, T
from iecoop.runtime import Runtime, Task
from patterns.creational.singleton import (
    CAPACITY,
    Conveyor,
    Event,
    GVL_PlantEvents,
    LineMain,
    LogBuffer,
    PlantLog,
    Pump,
    RingLogger,
    Severity,
    log_copy,
    log_push,
)
from tests import checked_only


@pytest.fixture(autouse=True)
def _clear_plant_log() -> Iterator[None]:
    # The Singleton's cost, paid by every test: shared state must be cleared by hand.
    GVL_PlantEvents.plant_events.clear()
    yield
    GVL_PlantEvents.plant_events.clear()


def _runtime(program: Program) -> Runtime:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    return rt


def _newest(log: PlantLog | RingLogger, age: int) -> Event:
    """The event ``age`` places before the newest, as a caller on the PLC reads it: into its own ST_Event."""
    event = Event()
    assert log.newest(age, event) is True
    return event


def _texts(log: PlantLog | RingLogger) -> list[str]:
    """Held events, oldest first, as 'SOURCE text'."""
    out = []
    for age in reversed(range(log.held)):
        event = _newest(log, age)
        out.append(f"{event.source} {event.text}")
    return out


# ---------------------------------------------------------------------------
# The Singleton really is one log
# ---------------------------------------------------------------------------


def test_every_plant_log_instance_is_the_same_log() -> None:
    first, second = PlantLog(), PlantLog()
    first.log(Severity.INFO, "A", "one")
    second.log(Severity.ALARM, "B", "two")
    for log in (first, second, GVL_PlantEvents.plant_events):
        assert log.count == 2
        assert _texts(log) == ["A one", "B two"]


def test_conveyors_in_any_program_write_into_the_global_log_stamped_with_the_task_clock() -> None:
    line = LineMain()
    rt = _runtime(line)
    rt.run(cycles=3)
    assert GVL_PlantEvents.plant_events.count == 0
    line.cmd_run = True
    rt.run(cycles=2)
    assert rt.time_ms == 50
    log = GVL_PlantEvents.plant_events
    assert _texts(log) == ["CV101 started", "CV102 started", "P101 started"]
    assert [_newest(log, age).stamp for age in range(3)] == [30, 30, 30]
    line.overload_cv102 = True
    rt.run(cycles=4)
    assert _texts(log)[-2:] == ["CV102 overload trip", "CV102 stopped"]
    assert _newest(log, 1).severity == Severity.ALARM
    assert _newest(log, 0).stamp == 50


def test_two_separate_lines_cannot_have_separate_logs() -> None:
    """The criticism made concrete: line A's events end up in line B's log."""
    line_a, line_b = LineMain(), LineMain()
    rt_a, rt_b = _runtime(line_a), _runtime(line_b)
    line_a.cmd_run = True
    rt_a.run(cycles=1)
    rt_b.run(cycles=1)
    assert GVL_PlantEvents.plant_events.count == 3
    assert PlantLog().count == 3  # whichever log line B looks at, A's events are in it


def test_the_shared_buffer_is_a_ring_that_overwrites_the_oldest() -> None:
    log = PlantLog()
    for n in range(1, CAPACITY + 4):
        log.log(Severity.INFO, "T", f"event {n}")
    assert (log.count, log.held) == (CAPACITY + 3, CAPACITY)
    assert _newest(log, 0).text == f"event {CAPACITY + 3}"
    assert _newest(log, CAPACITY - 1).text == "event 4"


def test_an_age_past_the_events_held_is_refused_and_leaves_the_callers_event_alone() -> None:
    log = RingLogger()
    kept = Event(source="HMI", text="kept")
    assert log.newest(0, kept) is False  # an empty log holds no newest event
    log.log(Severity.WARNING, "P1", "dry running")
    assert log.newest(1, kept) is False and (kept.source, kept.text) == ("HMI", "kept")
    assert log.newest(0, kept) is True and (kept.severity, kept.source, kept.text) == (
        Severity.WARNING, "P1", "dry running"
    )
    kept.text = "changed"  # a copy: the log is not written through the caller's event
    assert _newest(log, 0).text == "dry running"


def test_log_push_reports_when_the_oldest_event_is_overwritten() -> None:
    buffer, event = LogBuffer(), Event()
    assert [log_push(buffer, Severity.INFO, "T", f"e{n}") for n in range(CAPACITY + 2)] == (
        [False] * CAPACITY + [True, True]
    )
    assert (buffer.held, buffer.total) == (CAPACITY, CAPACITY + 2)
    assert log_copy(buffer, CAPACITY - 1, event) and event.text == "e2"
    assert not log_copy(buffer, CAPACITY, event) and event.text == "e2"


@checked_only
def test_the_buffer_is_var_stat_and_not_writable_from_outside() -> None:
    log = PlantLog()
    log.log(Severity.INFO, "T", "kept")
    with pytest.raises(AccessError, match=r"VAR_STAT PlantLog\.buffer"):
        log.buffer = RingLogger().buffer
    assert log.count == 1


def test_the_singleton_cannot_be_extended_into_a_second_log() -> None:
    with pytest.raises(DefinitionError, match="PlantLog is FINAL"):

        class SecondLog(PlantLog):
            pass


# ---------------------------------------------------------------------------
# The injected alternative
# ---------------------------------------------------------------------------


class PumpRig(Program):
    """A test program: one pump, its logger injected by the test."""

    run: BOOL = VAR_INPUT(False)
    dry: BOOL = VAR_INPUT(False)
    pump: Pump = VAR(fb_init={"tag": "P1"})

    def body(self) -> None:
        self.pump(run=self.run, dry_run=self.dry)


def test_an_injected_logger_is_fresh_and_private_to_each_test() -> None:
    rig, logger = PumpRig(), RingLogger()
    rig.pump.logger = logger
    rt = _runtime(rig)
    rig.run = True
    rt.run(cycles=2)
    rig.dry = True
    rt.run(cycles=1)
    assert _texts(logger) == ["P1 started", "P1 dry running", "P1 stopped"]
    assert _newest(logger, 1).severity == Severity.WARNING
    assert _newest(logger, 0).stamp == 20
    assert GVL_PlantEvents.plant_events.count == 0  # nothing leaked into the plant log


def test_two_rigs_with_their_own_loggers_do_not_see_each_other() -> None:
    rigs, loggers = (PumpRig(), PumpRig()), (RingLogger(), RingLogger())
    for rig, logger in zip(rigs, loggers):
        rig.pump.logger = logger
    runtimes = [_runtime(rig) for rig in rigs]
    rigs[0].run = True
    for rt in runtimes:
        rt.run(cycles=3)
    assert (loggers[0].count, loggers[1].count) == (1, 0)


def test_the_program_can_inject_the_plant_log_itself() -> None:
    line = LineMain()
    assert line.p101.logger == GVL_PlantEvents.plant_events
    pump = Pump(tag="P9", logger=GVL_PlantEvents.plant_events)
    pump(run=True)
    assert _texts(GVL_PlantEvents.plant_events) == ["P9 started"]


def test_a_pump_without_a_logger_faults_with_an_access_violation_in_its_cycle() -> None:
    rig = PumpRig()
    rt = _runtime(rig)
    rt.run(cycles=2)  # nothing to log yet, nothing fails
    rig.run = True
    with pytest.raises(PlcException, match=r"Pump\.logger_ref: ILogger\.log called through a null interface") as info:
        rt.run(cycles=1)
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


def test_the_conveyor_depends_on_the_global_even_without_saying_so() -> None:
    conveyor = Conveyor(tag="CV9")
    conveyor(run=True)
    assert conveyor.motor_on is True
    assert _texts(GVL_PlantEvents.plant_events) == ["CV9 started"]


@settings(max_examples=60, deadline=None)
@given(texts=st.lists(st.text(alphabet="abcxyz ", max_size=12), max_size=3 * CAPACITY))
def test_ring_logger_holds_the_newest_events_in_order(texts: list[str]) -> None:
    logger = RingLogger()  # injected: a fresh log per example, no clearing needed
    for text in texts:
        logger.log(Severity.INFO, "X", text)
    assert logger.count == len(texts)
    assert logger.held == min(len(texts), CAPACITY)
    assert [_newest(logger, age).text for age in range(logger.held)] == texts[::-1][:CAPACITY]
    assert logger.newest(logger.held, Event()) is False
