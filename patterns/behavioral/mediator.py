"""Mediator: a filling and capping cell whose stations talk only to the cell.

Intent
------

Define an object that encapsulates how a set of objects interact, so that
they do not refer to each other and their interaction can be changed in one
place.

The PLC problem
---------------

A bottling cell has four stations in a row: an infeed star wheel, a filler,
a capper and a reject gate. Each station has its own timing (spacing, fill
time, capping time, gate stroke) and a bottle may only move on when the next
station is free; a bottle whose capping torque check fails must be pushed out
at the reject gate. If each station's FB reads the others' states ("filler
done AND capper empty"), the four FBs are knotted together: a fifth station
(a labeller) means editing three of them.

With Mediator every station FB knows only ``I_CellMediator``: it reports what
happened (``BOTTLE_ARRIVED``, ``FILL_DONE``, ``CAP_FAILED`` ...) and obeys the
commands it receives (``START_FILL``, ``RELEASE``, ``REJECT_BOTTLE`` ...). The
cell FB holds the stations in an ``ARRAY[E_CellStation] OF I_CellColleague``
and owns the one rule of the cell: a bottle moves on when its station is done
and the next one is empty, starting from the end of the line so that space
frees up in the same scan.

Roles
-----

- Mediator interface → ``ICellMediator`` (``I_CellMediator``)
- Colleague interface → ``ICellColleague`` (``I_CellColleague``)
- Concrete mediator → ``FillingCell`` (``FB_FillingCell``)
- Colleague base → ``CellColleague`` (``FB_CellColleague``, ABSTRACT)
- Concrete colleagues → ``Infeed``, ``Filler``, ``Capper``, ``RejectGate``
  (``FB_Infeed``, ``FB_Filler``, ``FB_Capper``, ``FB_RejectGate``)
- Messages → ``CellEvent`` (``E_CellEvent``, station to cell) and
  ``CellCommand`` (``E_CellCommand``, cell to station)
- Client → ``CellMain`` (``PRG_CellMain``)

IEC 61131-3 mapping
-------------------

::

    TYPE E_CellStation : (INFEED := 1, FILLER, CAPPER, REJECT_GATE) USINT; END_TYPE
    TYPE E_CellEvent : (BOTTLE_ARRIVED, FILL_DONE, CAP_OK, CAP_FAILED,
                        BOTTLE_PASSED, BOTTLE_REJECTED) USINT; END_TYPE

    INTERFACE I_CellMediator
        METHOD Notify
        VAR_INPUT sender : E_CellStation; event : E_CellEvent; bottle : DINT; END_VAR

    INTERFACE I_CellColleague
        PROPERTY Station : E_CellStation      PROPERTY State : E_StationState
        PROPERTY Bottle : DINT
        METHOD SetMediator   VAR_INPUT mediator : I_CellMediator; END_VAR
        METHOD Receive       VAR_INPUT command : E_CellCommand; bottle : DINT; END_VAR
        METHOD Execute       // the station's cyclic part

    FUNCTION_BLOCK FB_FillingCell IMPLEMENTS I_CellMediator
    VAR_OUTPUT goodCount, rejectCount : DINT;
               error : BOOL; missing : E_CellStation; END_VAR  // a station not registered
    VAR stations : ARRAY[E_CellStation.INFEED..E_CellStation.REJECT_GATE]
                   OF I_CellColleague; END_VAR
        METHOD Register : BOOL   VAR_INPUT colleague : I_CellColleague; END_VAR
        // FALSE for a null colleague or a station already taken

    FUNCTION_BLOCK ABSTRACT FB_CellColleague IMPLEMENTS I_CellColleague
    VAR mediator : I_CellMediator; state : E_StationState; END_VAR
        PROPERTY ABSTRACT Station : E_CellStation
        METHOD PROTECTED FINAL Send
        VAR_INPUT event : E_CellEvent; bottle : DINT; END_VAR

    FUNCTION_BLOCK FB_Capper EXTENDS FB_CellColleague
    VAR_INPUT capTime : TIME := T#250MS; torqueOk : BOOL := TRUE; END_VAR
    VAR capTimer : TON; END_VAR

When not to use it on a PLC
---------------------------

A cell with two stations and one interlock does not need a mediator; an
``IF`` in the cell's program is clearer. The mediator concentrates the cell's
logic in one FB, which is the point, but it can grow into a god object:
keep the station behaviour (timers, outputs) in the colleagues and only the
coordination in the mediator. Safety interlocks do not belong here at all:
they stay hard-wired or in the safety PLC, never routed through a
mediator's method calls.

References
----------

- Gamma, Helm, Johnson, Vlissides: *Design Patterns: Elements of Reusable
  Object-Oriented Software*, Addison-Wesley 1994, "Mediator".
- IEC 61131-3:2013, 3rd edition: interfaces, methods and properties,
  ABSTRACT and FINAL, enumerated and structured data types, arrays, and the
  standard timer TON.
- Beckhoff InfoSys, TwinCAT 3 PLC: "Interface", "Property", "ABSTRACT
  concept", "Enumerations", "TON".
- CODESYS Online Help: "Object: Interface", "Object: Property",
  "Implementing interfaces".
- ISA-TR88.00.02 (PackML): unit / machine modes, for where a cell like this
  sits in a packaging line.
"""

from __future__ import annotations

from iecoop import (
    ABSTRACT,
    ARRAY,
    BOOL,
    DINT,
    FINAL,
    INT,
    PROTECTED,
    TIME,
    USINT,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    FunctionBlock,
    IecEnum,
    Interface,
    Program,
    Struct,
    T,
    method,
    prop,
)
from iecoop.runtime import Runtime, Task, now_ms
from iecoop.stdlib import TON
from patterns.showcase.entry import Column, Showcase

__all__ = [
    "LOG_SIZE",
    "STATION_COUNT",
    "Capper",
    "CellColleague",
    "CellCommand",
    "CellEvent",
    "CellLogEntry",
    "CellMain",
    "CellStation",
    "FillingCell",
    "Filler",
    "ICellColleague",
    "ICellMediator",
    "Infeed",
    "RejectGate",
    "StationState",
    "main",
]

#: ``LOG_SIZE``: a GVL's VAR_GLOBAL CONSTANT, the depth of the cell's event ring.
LOG_SIZE = 32
#: ``STATION_COUNT``: a VAR_GLOBAL CONSTANT too, how many stations the cell must have registered before it runs.
STATION_COUNT = 4


class CellStation(IecEnum, base=USINT):
    """``TYPE E_CellStation : (INFEED := 1, FILLER, CAPPER, REJECT_GATE) USINT; END_TYPE``: also the array index."""

    INFEED = 1
    FILLER = 2
    CAPPER = 3
    REJECT_GATE = 4


class StationState(IecEnum, base=USINT):
    """``TYPE E_StationState : (EMPTY, WORKING, DONE) USINT; END_TYPE``; DONE holds a finished bottle."""

    EMPTY = 0
    WORKING = 1
    DONE = 2


class CellEvent(IecEnum, base=USINT):
    """``TYPE E_CellEvent``: what a station reports to the cell."""

    BOTTLE_ARRIVED = 1
    FILL_DONE = 2
    CAP_OK = 3
    CAP_FAILED = 4
    BOTTLE_PASSED = 5
    BOTTLE_REJECTED = 6


class CellCommand(IecEnum, base=USINT):
    """``TYPE E_CellCommand``: what the cell tells a station."""

    RELEASE = 1
    START_FILL = 2
    START_CAP = 3
    PASS_BOTTLE = 4
    REJECT_BOTTLE = 5


class CellLogEntry(Struct):
    """``TYPE ST_CellLogEntry : STRUCT timeMs : TIME; sender : E_CellStation; event : E_CellEvent; bottle : DINT;``."""

    time_ms: TIME = 0
    sender: CellStation = CellStation.INFEED
    event: CellEvent = CellEvent.BOTTLE_ARRIVED
    bottle: DINT = 0


class ICellMediator(Interface):
    """``INTERFACE I_CellMediator``: the only thing a station knows about the cell."""

    @method
    def notify(self, sender: CellStation, event: CellEvent, bottle: DINT) -> None: ...


class ICellColleague(Interface):
    """``INTERFACE I_CellColleague``: what the cell knows about a station."""

    @prop
    def station(self) -> CellStation:
        raise NotImplementedError

    @prop
    def state(self) -> StationState:
        raise NotImplementedError

    @prop
    def bottle(self) -> DINT:
        raise NotImplementedError

    @method
    def set_mediator(self, mediator: ICellMediator) -> None: ...

    @method
    def receive(self, command: CellCommand, bottle: DINT) -> None: ...

    @method
    def execute(self) -> None: ...


class CellColleague(FunctionBlock, ICellColleague, abstract=True):
    """``FUNCTION_BLOCK ABSTRACT FB_CellColleague IMPLEMENTS I_CellColleague``.

    Holds the mediator reference and the station state; ``RELEASE`` (the
    bottle moved on) is the same for every station. A derived station
    reports through ``send`` as the last thing it does, because the cell may
    answer at once with the next command.
    """

    mediator: ICellMediator = VAR()
    station_state: StationState = VAR(StationState.EMPTY)
    held_bottle: DINT = VAR(0)

    @prop
    @method(ABSTRACT)
    def station(self) -> CellStation:
        raise NotImplementedError

    @prop
    def state(self) -> StationState:
        return self.station_state

    @prop
    def bottle(self) -> DINT:
        return self.held_bottle

    @method(FINAL)
    def set_mediator(self, mediator: ICellMediator) -> None:
        self.mediator = mediator

    @method
    def receive(self, command: CellCommand, bottle: DINT) -> None:
        if command == CellCommand.RELEASE:
            self.station_state, self.held_bottle = StationState.EMPTY, 0

    @method(PROTECTED | FINAL)
    def send(self, event: CellEvent, bottle: DINT) -> None:
        self.mediator.notify(self.station, event, bottle)

    @method(PROTECTED | FINAL)
    def start(self, bottle: DINT) -> None:
        self.station_state, self.held_bottle = StationState.WORKING, bottle


class Infeed(CellColleague):
    """``FUNCTION_BLOCK FB_Infeed EXTENDS FB_CellColleague``: a bottle every ``spacing`` while supply is on."""

    supply_on: BOOL = VAR_INPUT(True)
    spacing: TIME = VAR_INPUT(T("200ms"))
    arrived: DINT = VAR_OUTPUT(0)
    spacing_timer: TON = VAR()

    @prop
    def station(self) -> CellStation:
        return CellStation.INFEED

    @method
    def execute(self) -> None:
        self.spacing_timer(IN=self.supply_on and self.station_state == StationState.EMPTY, PT=self.spacing)
        if self.spacing_timer.Q:
            self.spacing_timer(IN=False)
            self.arrived += 1
            self.station_state, self.held_bottle = StationState.DONE, self.arrived
            self.send(CellEvent.BOTTLE_ARRIVED, self.arrived)


class Filler(CellColleague):
    """``FUNCTION_BLOCK FB_Filler EXTENDS FB_CellColleague``: the valve is open for ``fill_time``."""

    fill_time: TIME = VAR_INPUT(T("300ms"))
    valve_open: BOOL = VAR_OUTPUT(False)
    fill_timer: TON = VAR()

    @prop
    def station(self) -> CellStation:
        return CellStation.FILLER

    @method
    def receive(self, command: CellCommand, bottle: DINT) -> None:
        if command == CellCommand.START_FILL:
            self.start(bottle)
        else:
            super().receive(command, bottle)

    @method
    def execute(self) -> None:
        working = self.station_state == StationState.WORKING
        self.fill_timer(IN=working, PT=self.fill_time)
        self.valve_open = working and not self.fill_timer.Q
        if self.fill_timer.Q:
            self.fill_timer(IN=False)
            self.station_state = StationState.DONE
            self.send(CellEvent.FILL_DONE, self.held_bottle)


class Capper(CellColleague):
    """``FUNCTION_BLOCK FB_Capper EXTENDS FB_CellColleague``: caps for ``cap_time``, then checks the torque."""

    cap_time: TIME = VAR_INPUT(T("250ms"))
    torque_ok: BOOL = VAR_INPUT(True)
    cap_timer: TON = VAR()

    @prop
    def station(self) -> CellStation:
        return CellStation.CAPPER

    @method
    def receive(self, command: CellCommand, bottle: DINT) -> None:
        if command == CellCommand.START_CAP:
            self.start(bottle)
        else:
            super().receive(command, bottle)

    @method
    def execute(self) -> None:
        self.cap_timer(IN=self.station_state == StationState.WORKING, PT=self.cap_time)
        if self.cap_timer.Q:
            self.cap_timer(IN=False)
            self.station_state = StationState.DONE
            self.send(CellEvent.CAP_OK if self.torque_ok else CellEvent.CAP_FAILED, self.held_bottle)


class RejectGate(CellColleague):
    """``FUNCTION_BLOCK FB_RejectGate EXTENDS FB_CellColleague``: lets a bottle pass or pushes it out.

    The gate never waits for anything downstream: after ``stroke_time`` the
    bottle is gone and the gate is empty again.
    """

    stroke_time: TIME = VAR_INPUT(T("100ms"))
    divert: BOOL = VAR_OUTPUT(False)
    stroke_timer: TON = VAR()

    @prop
    def station(self) -> CellStation:
        return CellStation.REJECT_GATE

    @method
    def receive(self, command: CellCommand, bottle: DINT) -> None:
        if command == CellCommand.PASS_BOTTLE or command == CellCommand.REJECT_BOTTLE:
            self.start(bottle)
            self.divert = command == CellCommand.REJECT_BOTTLE
        else:
            super().receive(command, bottle)

    @method
    def execute(self) -> None:
        self.stroke_timer(IN=self.station_state == StationState.WORKING, PT=self.stroke_time)
        if self.stroke_timer.Q:
            self.stroke_timer(IN=False)
            gone, event = self.held_bottle, CellEvent.BOTTLE_REJECTED if self.divert else CellEvent.BOTTLE_PASSED
            self.station_state, self.held_bottle, self.divert = StationState.EMPTY, 0, False
            self.send(event, gone)


class FillingCell(FunctionBlock, ICellMediator):
    """``FUNCTION_BLOCK FB_FillingCell IMPLEMENTS I_CellMediator``: the cell's one coordination rule.

    Each call runs every station's cyclic part, from the reject gate back to
    the infeed. Every event moves whatever bottles can move, starting at the
    end of the line, and is kept in a ring of ``LOG_SIZE`` entries.
    """

    good_count: DINT = VAR_OUTPUT(0)
    reject_count: DINT = VAR_OUTPUT(0)
    stations: ARRAY[ICellColleague] = VAR(bounds=(CellStation.INFEED, CellStation.REJECT_GATE))
    registered: INT = VAR(0)
    cap_failed: BOOL = VAR(False)
    log: ARRAY[CellLogEntry] = VAR(bounds=(0, LOG_SIZE - 1))
    log_count: DINT = VAR(0)
    no_entry: CellLogEntry = VAR()
    error: BOOL = VAR_OUTPUT(False)
    missing: CellStation = VAR_OUTPUT(CellStation.INFEED)

    @method
    def register(self, colleague: ICellColleague) -> BOOL:
        """Take ``colleague`` at its station and give it this cell as its mediator.

        FALSE, and nothing changes, if ``colleague`` is a null reference or its place is taken.
        """
        if not colleague:
            return False
        station = colleague.station
        if self.stations[station]:
            return False
        self.stations[station] = colleague
        self.registered += 1
        colleague.set_mediator(self)
        return True

    def body(self) -> None:
        # With a station missing the cell does not run (calling it would fault on the
        # null reference): ``error`` is set and ``missing`` names the first empty place.
        self.error = self.registered < STATION_COUNT
        if self.error:
            if not self.stations[CellStation.REJECT_GATE]:
                self.missing = CellStation.REJECT_GATE
            if not self.stations[CellStation.CAPPER]:
                self.missing = CellStation.CAPPER
            if not self.stations[CellStation.FILLER]:
                self.missing = CellStation.FILLER
            if not self.stations[CellStation.INFEED]:
                self.missing = CellStation.INFEED
            return
        for index in range(CellStation.REJECT_GATE, CellStation.INFEED - 1, -1):
            self.stations[index].execute()

    @method
    def notify(self, sender: CellStation, event: CellEvent, bottle: DINT) -> None:
        entry = self.log[self.log_count % LOG_SIZE]
        entry.time_ms, entry.sender, entry.event, entry.bottle = now_ms(), sender, event, bottle
        self.log_count += 1
        if event == CellEvent.CAP_OK or event == CellEvent.CAP_FAILED:
            self.cap_failed = event == CellEvent.CAP_FAILED
        elif event == CellEvent.BOTTLE_PASSED:
            self.good_count += 1
        elif event == CellEvent.BOTTLE_REJECTED:
            self.reject_count += 1
        self.move_bottles()

    @method
    def entry(self, number: DINT) -> CellLogEntry:
        """Log entry ``number`` (1 = the first event); an empty entry (bottle 0) once the ring no longer holds it."""
        if not (number >= 1 and self.log_count - LOG_SIZE < number <= self.log_count):
            return self.no_entry
        found: CellLogEntry = self.log[(number - 1) % LOG_SIZE]
        return found

    @method(PROTECTED)
    def move_bottles(self) -> None:
        infeed, filler = self.stations[CellStation.INFEED], self.stations[CellStation.FILLER]
        capper, gate = self.stations[CellStation.CAPPER], self.stations[CellStation.REJECT_GATE]
        if capper.state == StationState.DONE and gate.state == StationState.EMPTY:
            bottle = capper.bottle
            capper.receive(CellCommand.RELEASE, bottle)
            gate.receive(CellCommand.REJECT_BOTTLE if self.cap_failed else CellCommand.PASS_BOTTLE, bottle)
        if filler.state == StationState.DONE and capper.state == StationState.EMPTY:
            bottle = filler.bottle
            filler.receive(CellCommand.RELEASE, bottle)
            capper.receive(CellCommand.START_CAP, bottle)
        if infeed.state == StationState.DONE and filler.state == StationState.EMPTY:
            bottle = infeed.bottle
            infeed.receive(CellCommand.RELEASE, bottle)
            filler.receive(CellCommand.START_FILL, bottle)


class CellMain(Program):
    """``PROGRAM PRG_CellMain``: registers the four stations with the cell and runs it.

    The capping head's torque check is simulated: every ``bad_cap_every``-th
    bottle (by number) fails it.
    """

    infeed: Infeed = VAR()
    filler: Filler = VAR()
    capper: Capper = VAR()
    gate: RejectGate = VAR()
    cell: FillingCell = VAR()
    bad_cap_every: DINT = VAR_INPUT(4)

    def fb_init(self, init_retains: bool, in_copy_code: bool) -> None:
        self.cell.register(self.infeed)
        self.cell.register(self.filler)
        self.cell.register(self.capper)
        self.cell.register(self.gate)

    def body(self) -> None:
        bottle = self.capper.bottle
        # Not one OR: ST evaluates both sides, and MOD 0 faults.
        if self.bad_cap_every > 0:
            self.capper.torque_ok = bottle % self.bad_cap_every != 0
        else:
            self.capper.torque_ok = True
        self.cell()


def main() -> None:
    """Run the cell for 2 s of PLC time: bottle 1's journey, the first reject, the totals.

    >>> main()
    t= 200 ms  INFEED      -> BOTTLE_ARRIVED  bottle 1
    t= 510 ms  FILLER      -> FILL_DONE       bottle 1
    t= 770 ms  CAPPER      -> CAP_OK          bottle 1
    t= 880 ms  REJECT_GATE -> BOTTLE_PASSED   bottle 1
    t=1020 ms  INFEED      -> BOTTLE_ARRIVED  bottle 4
    t=1440 ms  FILLER      -> FILL_DONE       bottle 4
    t=1700 ms  CAPPER      -> CAP_FAILED      bottle 4
    t=1810 ms  REJECT_GATE -> BOTTLE_REJECTED bottle 4
    after 2000 ms: 7 bottles in, 3 good, 1 rejected, 3 still in the cell
    """
    program = CellMain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    rt.run(cycles=200)
    cell = program.cell
    for number in range(1, cell.log_count + 1):
        entry = cell.entry(number)
        if entry.bottle in (1, 4):
            print(f"t={entry.time_ms:4d} ms  {entry.sender.name:11} -> {entry.event.name:15} bottle {entry.bottle}")
    inside = program.infeed.arrived - cell.good_count - cell.reject_count
    print(f"after {rt.time_ms} ms: {program.infeed.arrived} bottles in, {cell.good_count} good, "
          f"{cell.reject_count} rejected, {inside} still in the cell")


SHOWCASE = Showcase(
    use_when="the stations of a cell must coordinate without knowing each other",
    columns=(
        Column("arrived", lambda p: p.infeed.arrived),
        Column("filling", lambda p: p.filler.valve_open, watch=False),
        Column("divert", lambda p: p.gate.divert, watch=False),
        Column("good", lambda p: p.cell.good_count),
        Column("rejected", lambda p: p.cell.reject_count),
    ),
    cycles=200,
    tour_cycles=200,
)
