"""Mediator: the filling and capping cell, bottle by bottle, across PLC cycles."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import DINT, VAR, VAR_OUTPUT, ExceptionCode, FunctionBlock, PlcException, Program, T, method
from iecoop.runtime import Runtime, Task
from patterns.behavioral.mediator import (
    LOG_SIZE,
    Capper,
    CellCommand,
    CellEvent,
    CellMain,
    CellStation,
    Filler,
    FillingCell,
    ICellMediator,
    Infeed,
    RejectGate,
    StationState,
)


class SpyMediator(FunctionBlock, ICellMediator):
    """Stands in for the cell: records the last event a station reported."""

    events: DINT = VAR_OUTPUT(0)
    last_sender: CellStation = VAR_OUTPUT(CellStation.INFEED)
    last_event: CellEvent = VAR_OUTPUT(CellEvent.BOTTLE_ARRIVED)
    last_bottle: DINT = VAR_OUTPUT(0)

    @method
    def notify(self, sender: CellStation, event: CellEvent, bottle: DINT) -> None:
        self.events += 1
        self.last_sender, self.last_event, self.last_bottle = sender, event, bottle


class LoneFiller(Program):
    """A filler with a spy (or nothing) as its mediator, run cyclically."""

    filler: Filler = VAR()
    spy: SpyMediator = VAR()

    def body(self) -> None:
        self.filler.execute()


class ThreeStations(Program):
    """A cell whose capper was never registered."""

    infeed: Infeed = VAR()
    filler: Filler = VAR()
    gate: RejectGate = VAR()
    cell: FillingCell = VAR()

    def fb_init(self, init_retains: bool, in_copy_code: bool) -> None:
        self.cell.register(self.infeed)
        self.cell.register(self.filler)
        self.cell.register(self.gate)

    def body(self) -> None:
        self.cell()


def _runtime(program: Program) -> Runtime:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    return rt


def _events(cell: FillingCell) -> list[tuple[int, CellStation, CellEvent, int]]:
    first = max(1, cell.log_count - LOG_SIZE + 1)
    return [
        (e.time_ms, e.sender, e.event, e.bottle)
        for e in (cell.entry(n) for n in range(first, cell.log_count + 1))
    ]


def _bottles_inside(main: CellMain) -> list[int]:
    return [s.bottle for s in (main.gate, main.capper, main.filler, main.infeed) if s.bottle]


# ---------------------------------------------------------------------------
# Bottles through the cell
# ---------------------------------------------------------------------------


def test_the_first_bottle_goes_through_every_station_with_its_timings() -> None:
    main = CellMain()
    rt = _runtime(main)
    rt.run(cycles=89)
    first_bottle = [(t, s, e) for t, s, e, b in _events(main.cell) if b == 1]
    assert first_bottle == [
        (200, CellStation.INFEED, CellEvent.BOTTLE_ARRIVED),
        (510, CellStation.FILLER, CellEvent.FILL_DONE),       # 300 ms fill, started the scan after arrival
        (770, CellStation.CAPPER, CellEvent.CAP_OK),          # 250 ms capping
        (880, CellStation.REJECT_GATE, CellEvent.BOTTLE_PASSED),  # 100 ms gate stroke
    ]
    assert (main.cell.good_count, main.cell.reject_count, rt.time_ms) == (1, 0, 890)


def test_the_filler_valve_is_open_only_while_a_bottle_is_filling() -> None:
    main = CellMain()
    rt = _runtime(main)
    opened = []
    for _ in range(60):
        rt.run(cycles=1)
        opened.append(main.filler.valve_open)
    # Bottle 1 arrives at 200 ms; the valve opens at 210 ms and closes at 510 ms.
    assert opened.index(True) == 21
    assert opened[21:51] == [True] * 30 and opened[51] is False


def test_a_failed_cap_sends_the_bottle_to_the_reject_gate() -> None:
    main = CellMain()
    rt = _runtime(main)
    diverted = set()
    for _ in range(200):
        rt.run(cycles=1)
        if main.gate.divert:
            diverted.add(main.gate.bottle)
    assert diverted == {4}
    rejected = [(t, s, e) for t, s, e, b in _events(main.cell) if b == 4][-2:]
    assert rejected == [(1700, CellStation.CAPPER, CellEvent.CAP_FAILED), (1810, CellStation.REJECT_GATE, CellEvent.BOTTLE_REJECTED)]


def test_good_and_rejected_bottles_over_many_cycles() -> None:
    main = CellMain()
    rt = _runtime(main)
    rt.run(cycles=3000)
    cell = main.cell
    finished = cell.good_count + cell.reject_count
    # The filler is the bottleneck: one bottle every 300 ms fill + one scan to hand over.
    assert (main.infeed.arrived, cell.good_count, cell.reject_count) == (97, 71, 23)
    assert finished + len(_bottles_inside(main)) == main.infeed.arrived
    assert cell.reject_count == finished // 4
    # With the capping head repaired, every further bottle is good.
    main.bad_cap_every = 0
    rt.run(cycles=1000)
    assert (cell.good_count, cell.reject_count) == (71 + 33, 23)     # 10 s at 310 ms a bottle


def test_switching_the_supply_off_drains_the_cell() -> None:
    main = CellMain()
    rt = _runtime(main)
    rt.run(cycles=300)
    main.infeed.supply_on = False
    rt.run(cycles=200)
    arrived = main.infeed.arrived
    assert arrived == main.cell.good_count + main.cell.reject_count == 10
    assert [s.state for s in (main.infeed, main.filler, main.capper, main.gate)] == [StationState.EMPTY] * 4
    rt.run(cycles=100)
    assert main.infeed.arrived == arrived


@settings(max_examples=100, deadline=None)
@given(
    spacing=st.integers(1, 40).map(lambda n: n * 10),
    fill=st.integers(1, 40).map(lambda n: n * 10),
    cap=st.integers(1, 40).map(lambda n: n * 10),
    stroke=st.integers(1, 20).map(lambda n: n * 10),
    bad_every=st.integers(0, 5),
    cycles=st.integers(1, 400),
)
def test_no_bottle_is_lost_duplicated_or_overtaken(
    spacing: int, fill: int, cap: int, stroke: int, bad_every: int, cycles: int
) -> None:
    main = CellMain()
    main.infeed.spacing, main.filler.fill_time, main.capper.cap_time, main.gate.stroke_time = spacing, fill, cap, stroke
    main.bad_cap_every = bad_every
    rt = _runtime(main)
    for _ in range(cycles):
        rt.run(cycles=1)
        cell = main.cell
        finished = cell.good_count + cell.reject_count
        inside = _bottles_inside(main)
        # Conservation: every bottle that came in is out (good or rejected) or at exactly one station.
        assert finished + len(inside) == main.infeed.arrived
        # First in, first out: the bottles downstream are the older ones, and they leave in order.
        assert inside == list(range(finished + 1, finished + 1 + len(inside)))
        # Exactly the bottles that failed the torque check were rejected.
        assert cell.reject_count == (finished // bad_every if bad_every else 0)


# ---------------------------------------------------------------------------
# Stations talk only to the mediator
# ---------------------------------------------------------------------------


def test_a_station_reports_to_whatever_mediator_it_was_given() -> None:
    lone = LoneFiller()
    lone.filler.set_mediator(lone.spy)
    lone.filler.receive(CellCommand.START_FILL, 42)
    rt = _runtime(lone)
    rt.run(cycles=30)
    assert (lone.spy.events, lone.filler.state) == (0, StationState.WORKING)
    rt.run(cycles=1)
    assert (lone.spy.events, lone.spy.last_sender, lone.spy.last_event, lone.spy.last_bottle) == (
        1, CellStation.FILLER, CellEvent.FILL_DONE, 42,
    )
    assert (lone.filler.state, lone.filler.bottle) == (StationState.DONE, 42)
    lone.filler.receive(CellCommand.RELEASE, 42)
    assert (lone.filler.state, lone.filler.bottle) == (StationState.EMPTY, 0)


def test_a_station_without_a_mediator_faults_when_it_reports() -> None:
    lone = LoneFiller()
    lone.filler.receive(CellCommand.START_FILL, 1)
    rt = _runtime(lone)
    with pytest.raises(PlcException, match="null interface reference") as exc:
        rt.run(cycles=40)
    assert exc.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION
    assert rt.time_ms == 300      # the fill started in the first scan and ended 300 ms later


def test_a_second_colleague_for_a_taken_station_is_refused() -> None:
    cell, filler, other = FillingCell(), Filler(), Filler()
    assert cell.register(filler) is True
    assert cell.register(filler) is False
    assert cell.register(other) is False
    assert cell.registered == 1
    assert cell.stations[2] == filler and cell.stations[2] != other


def test_registering_a_null_colleague_is_refused() -> None:
    cell = FillingCell()
    assert cell.register(cell.stations[1]) is False
    assert cell.registered == 0 and not cell.stations[CellStation.INFEED]
    assert cell.register(Infeed()) is True and cell.registered == 1


def test_a_cell_with_a_station_missing_does_not_run_and_names_the_station() -> None:
    three = ThreeStations()
    rt = _runtime(three)
    rt.run(cycles=50)
    assert (three.cell.error, three.cell.missing) == (True, CellStation.CAPPER)
    # Nothing runs: the infeed never brings a bottle, no event is logged.
    assert (three.infeed.arrived, three.cell.log_count, three.cell.good_count) == (0, 0, 0)


def test_registering_the_missing_station_lets_the_cell_run() -> None:
    three = ThreeStations()
    rt = _runtime(three)
    rt.run(cycles=5)
    assert (three.cell.error, three.infeed.arrived) == (True, 0)
    capper = Capper()
    assert three.cell.register(capper) is True
    rt.run(cycles=89)
    assert not three.cell.error
    assert three.cell.good_count == 1


def test_events_older_than_the_log_ring_read_as_an_empty_entry() -> None:
    main = CellMain()
    rt = _runtime(main)
    rt.run(cycles=1000)
    count = main.cell.log_count
    assert count > LOG_SIZE
    assert main.cell.entry(count - LOG_SIZE + 1).time_ms < main.cell.entry(count).time_ms
    assert main.cell.entry(count - LOG_SIZE + 1).bottle > 0
    for number in (count - LOG_SIZE, 0, -1, count + 1):
        gone = main.cell.entry(number)
        assert (gone.time_ms, gone.bottle) == (0, 0)
    assert not main.cell.error


def test_a_cold_reset_registers_the_stations_again() -> None:
    main = CellMain()
    rt = _runtime(main)
    rt.run(cycles=500)
    rt.reset_cold()
    assert (main.cell.registered, main.cell.good_count, main.infeed.arrived) == (4, 0, 0)
    rt.run(cycles=89)
    assert main.cell.good_count == 1
