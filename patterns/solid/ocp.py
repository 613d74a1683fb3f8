"""Open / closed: a new valve type joins through an interface, not through another CASE branch.

Principle
---------

Software entities should be open for extension but closed for modification
(Bertrand Meyer; Robert C. Martin). New behaviour arrives as new code; the code
that already works, and its tests, stay as they are.

The course example
------------------

The course's ``FB_Vehicle`` is extended by ``FB_Car`` and ``FB_Motorbike``
(``EXTENDS``): each adds what it needs, and ``FB_Vehicle`` is not edited when
the motorbike arrives.

The PLC problem
---------------

A manifold drives valves of several kinds; the I/O configuration table holds a
type code per valve. A single valve block with a ``CASE`` on that code handles
the solenoid and the motorised valve. When the plant buys proportional valves,
their code reaches the ``ELSE`` branch and the valve reports an error: the
only way in is to edit the ``CASE`` of the block every other valve runs on, and
re-test both kinds that already worked. (Both designs time the motorised
valve's travel with the same ``ValveTravel`` (``FB_ValveTravel``) block.)

Violating design
----------------

- ``ValveKind`` (``E_ValveKind``): the type codes of the configuration table.
- ``ValveByCase`` (``FB_ValveByCase``): one block; ``CASE eKind OF`` with a
  branch per known kind and an ``ELSE`` that sets ``bError`` with
  ``ERR_UNKNOWN_KIND``.

Compliant design
----------------

- ``IValve`` (``I_Valve``): ``Open``, ``Close``, ``Update`` (called once per
  scan), ``Position``, ``IsOpen``, ``IsClosed``.
- ``ValveBase`` (``FB_ValveBase``, ABSTRACT): the FINAL open / close commands and
  the end-position properties; ``Update`` is ABSTRACT.
- ``SolenoidValve``, ``MotorisedValve``, ``ProportionalValve``
  (``FB_SolenoidValve`` ...): each ``EXTENDS FB_ValveBase``, as the car and
  the motorbike extend the vehicle. A valve written later may implement
  ``I_Valve`` directly.
- ``ValveManifold`` (``FB_ValveManifold``): a static pool
  ``ARRAY[1..8] OF I_Valve``; it never names a concrete valve.

IEC 61131-3 mapping
-------------------

::

    TYPE E_ValveKind : (SOLENOID := 1, MOTORISED := 2, PROPORTIONAL := 3); END_TYPE

    FUNCTION_BLOCK FB_ValveByCase                       // violating
        VAR_INPUT  eKind : E_ValveKind; bOpen : BOOL; tTravel : TIME := T#300MS; END_VAR
        VAR_OUTPUT qOpen, qClose : BOOL; rPosition : REAL; bError : BOOL; nErrorId : UDINT; END_VAR
        CASE eKind OF
            SOLENOID:  ...
            MOTORISED: ...
        ELSE
            bError := TRUE; nErrorId := ERR_UNKNOWN_KIND;
        END_CASE

    INTERFACE I_Valve EXTENDS __SYSTEM.IQueryInterface  // compliant
        METHOD Open
        METHOD Close
        METHOD Update
        PROPERTY Position : REAL
        PROPERTY IsOpen : BOOL
        PROPERTY IsClosed : BOOL
    FUNCTION_BLOCK ABSTRACT FB_ValveBase IMPLEMENTS I_Valve
        METHOD FINAL Open
        METHOD ABSTRACT Update
    FUNCTION_BLOCK FB_ProportionalValve EXTENDS FB_ValveBase
        VAR_OUTPUT rAnalogOut : REAL; END_VAR
    FUNCTION_BLOCK FB_ValveManifold
        VAR aValves : ARRAY[1..8] OF I_Valve; nCount : INT; END_VAR
        METHOD Add : INT  VAR_INPUT itfValve : I_Valve; END_VAR   // the slot; 0: already in, or full

References
----------

- B. Meyer, *Object-Oriented Software Construction*, 2nd ed., Prentice Hall,
  1997, chapter 3 "Modularity": the open-closed principle.
- R. C. Martin, *Agile Software Development: Principles, Patterns, and
  Practices*, Prentice Hall, 2002, chapter 9 "OCP".
- IEC 61131-3:2013, 3rd edition: function blocks with EXTENDS, ABSTRACT and
  FINAL, interfaces, the CASE statement, the standard timer TON.
- Beckhoff InfoSys, TwinCAT 3 PLC: "Object-oriented programming",
  "Extending a function block", "Implementing an interface".
- CODESYS online help: "Extension of a function block", "Implementing an
  interface".
"""

from __future__ import annotations

from iecoop import (
    ABSTRACT,
    ARRAY,
    BOOL,
    FINAL,
    INT,
    REAL,
    TIME,
    UDINT,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    FunctionBlock,
    IecEnum,
    IQueryInterface,
    Program,
    T,
    method,
    prop,
)
from iecoop.runtime import Runtime, Task
from iecoop.stdlib import TON
from patterns.plant import ramp
from patterns.showcase.entry import Column, Getter, Showcase, hex_word, steps

#: ``ERR_UNKNOWN_KIND : UDINT := 16#8001``: the CASE met a type code it has no branch for.
ERR_UNKNOWN_KIND = 0x8001
#: Slots of the manifold's pool: ``ARRAY[1..SLOTS] OF I_Valve``.
SLOTS = 8


class ValveKind(IecEnum):
    """``TYPE E_ValveKind : (SOLENOID := 1, MOTORISED := 2, PROPORTIONAL := 3);``: the configuration's type codes."""

    SOLENOID = 1
    MOTORISED = 2
    PROPORTIONAL = 3


class ValveTravel(FunctionBlock):
    """``FUNCTION_BLOCK FB_ValveTravel``: a valve motor runs until ``travel_time`` has elapsed in one direction.

    Without position feedback the valve counts as half open while it moves.
    """

    want_open: BOOL = VAR_INPUT(False)
    travel_time: TIME = VAR_INPUT(T("300ms"))
    q_open: BOOL = VAR_OUTPUT(False)
    q_close: BOOL = VAR_OUTPUT(False)
    position: REAL = VAR_OUTPUT(0.0)
    timer: TON = VAR()
    direction: BOOL = VAR(False)

    def body(self) -> None:
        if self.want_open != self.direction:
            self.timer(IN=False)  # reversed mid-travel: the run starts again
            self.direction = self.want_open
        target = 100.0 if self.want_open else 0.0
        moving = self.position != target
        self.timer(IN=moving, PT=self.travel_time)
        if self.timer.Q:
            self.position = target
            moving = False
        elif moving:
            self.position = 50.0
        self.q_open = moving and self.want_open
        self.q_close = moving and not self.want_open


# ---------------------------------------------------------------------------
# Violating design: a CASE on the type code
# ---------------------------------------------------------------------------


class ValveByCase(FunctionBlock):
    """``FUNCTION_BLOCK FB_ValveByCase``: every kind in one block, chosen by ``CASE eKind OF``.

    A kind without a branch ends in ``ELSE``: ``error`` with ``ERR_UNKNOWN_KIND``.
    """

    kind: ValveKind = VAR_INPUT(ValveKind.SOLENOID)
    cmd_open: BOOL = VAR_INPUT(False)
    travel_time: TIME = VAR_INPUT(T("300ms"))
    q_open: BOOL = VAR_OUTPUT(False)
    q_close: BOOL = VAR_OUTPUT(False)
    position: REAL = VAR_OUTPUT(0.0)
    error: BOOL = VAR_OUTPUT(False)
    error_id: UDINT = VAR_OUTPUT(0)
    travel: ValveTravel = VAR()

    def body(self) -> None:
        match self.kind:  # CASE eKind OF
            case ValveKind.SOLENOID:
                self.q_open = self.cmd_open
                self.position = 100.0 if self.cmd_open else 0.0
            case ValveKind.MOTORISED:
                self.travel(want_open=self.cmd_open, travel_time=self.travel_time)
                self.q_open, self.q_close = self.travel.q_open, self.travel.q_close
                self.position = self.travel.position
            case _:  # ELSE
                self.q_open = self.q_close = False
                self.error = True
                self.error_id = ERR_UNKNOWN_KIND


# ---------------------------------------------------------------------------
# Compliant design: the manifold depends on I_Valve; kinds are added as classes
# ---------------------------------------------------------------------------


class IValve(IQueryInterface):
    """``INTERFACE I_Valve``: what the manifold needs from any valve."""

    @method
    def open(self) -> None: ...

    @method
    def close(self) -> None: ...

    @method
    def update(self) -> None:
        """Once per scan, from the owner: drive the outputs towards the command."""

    @prop
    def position(self) -> REAL:
        raise NotImplementedError

    @prop
    def is_open(self) -> BOOL:
        raise NotImplementedError

    @prop
    def is_closed(self) -> BOOL:
        raise NotImplementedError


class ValveBase(FunctionBlock, IValve, abstract=True):
    """``FUNCTION_BLOCK ABSTRACT FB_ValveBase IMPLEMENTS I_Valve``: the command and end positions, once."""

    cmd_open: BOOL = VAR(False)
    actual: REAL = VAR_OUTPUT(0.0)

    @method(FINAL)
    def open(self) -> None:
        self.cmd_open = True

    @method(FINAL)
    def close(self) -> None:
        self.cmd_open = False

    @method(ABSTRACT)
    def update(self) -> None: ...

    @prop
    def position(self) -> REAL:
        return self.actual

    @prop
    def is_open(self) -> BOOL:
        return self.actual >= 100.0

    @prop
    def is_closed(self) -> BOOL:
        return self.actual <= 0.0


class SolenoidValve(ValveBase):
    """``FUNCTION_BLOCK FB_SolenoidValve EXTENDS FB_ValveBase``: one coil, spring return."""

    q_open: BOOL = VAR_OUTPUT(False)

    @method
    def update(self) -> None:
        self.q_open = self.cmd_open
        self.actual = 100.0 if self.cmd_open else 0.0


class MotorisedValve(ValveBase):
    """``FUNCTION_BLOCK FB_MotorisedValve EXTENDS FB_ValveBase``: open / close motor, timed travel."""

    travel_time: TIME = VAR_INPUT(T("300ms"))
    q_open: BOOL = VAR_OUTPUT(False)
    q_close: BOOL = VAR_OUTPUT(False)
    travel: ValveTravel = VAR()

    @method
    def update(self) -> None:
        self.travel(want_open=self.cmd_open, travel_time=self.travel_time)
        self.q_open, self.q_close = self.travel.q_open, self.travel.q_close
        self.actual = self.travel.position


class ProportionalValve(ValveBase):
    """``FUNCTION_BLOCK FB_ProportionalValve EXTENDS FB_ValveBase``: an analog output its positioner follows.

    The kind the ``CASE`` block could not take, added without editing any
    existing block.
    """

    slew: REAL = VAR_INPUT(25.0)
    ao_position: REAL = VAR_OUTPUT(0.0)

    @method
    def update(self) -> None:
        self.ao_position = 100.0 if self.cmd_open else 0.0
        self.actual = ramp(self.actual, self.ao_position, self.slew)


class ValveManifold(FunctionBlock):
    """``FUNCTION_BLOCK FB_ValveManifold``: up to ``SLOTS`` valves of any kind, through ``I_Valve`` only."""

    valves: ARRAY[IValve] = VAR(bounds=(1, SLOTS))
    count: INT = VAR_OUTPUT(0)

    @method
    def add(self, valve: IValve) -> INT:
        """Put ``valve`` in the next free slot and return the slot number; 0 when it is already in or all are used."""
        for slot in range(1, self.count + 1):
            if self.valves[slot] == valve:
                return 0
        if self.count >= SLOTS:
            return 0
        self.valves[self.count + 1] = valve  # fails on a non-valve before the count moves
        self.count += 1
        return self.count

    @method
    def valve(self, slot: INT) -> IValve:
        """The valve in ``slot``: 0 for a free slot; a slot outside 1..SLOTS faults with RTSEXCPT_ARRAYBOUNDS."""
        return self.valves[slot]

    @method
    def open_all(self) -> None:
        for slot in range(1, self.count + 1):
            self.valves[slot].open()

    @method
    def close_all(self) -> None:
        for slot in range(1, self.count + 1):
            self.valves[slot].close()

    @prop
    def all_open(self) -> BOOL:
        if self.count == 0:
            return False
        for slot in range(1, self.count + 1):
            if not self.valves[slot].is_open:
                return False
        return True

    @prop
    def all_closed(self) -> BOOL:
        for slot in range(1, self.count + 1):
            if not self.valves[slot].is_closed:
                return False
        return True

    def body(self) -> None:
        for slot in range(1, self.count + 1):
            self.valves[slot].update()


class ValveCell(Program):
    """``PROGRAM PRG_ValveCell``: the same three configured valves, in both designs, on one command."""

    cmd_open: BOOL = VAR_INPUT(False)
    by_case: ARRAY[ValveByCase] = VAR(
        [{"kind": ValveKind.SOLENOID}, {"kind": ValveKind.MOTORISED}, {"kind": ValveKind.PROPORTIONAL}], bounds=(1, 3)
    )
    solenoid: SolenoidValve = VAR()
    motorised: MotorisedValve = VAR()
    proportional: ProportionalValve = VAR()
    manifold: ValveManifold = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
        self.manifold.add(self.solenoid)
        self.manifold.add(self.motorised)
        self.manifold.add(self.proportional)
        return True

    def body(self) -> None:
        for slot in range(1, 4):
            self.by_case[slot](cmd_open=self.cmd_open)
        if self.cmd_open:
            self.manifold.open_all()
        else:
            self.manifold.close_all()
        self.manifold()


def main() -> None:
    """Open the three configured valves in both designs and show each one after 400 ms.

    >>> main()
    slot  kind          FB_ValveByCase (CASE)        I_Valve manifold
    1     SOLENOID      open                         open
    2     MOTORISED     open                         open
    3     PROPORTIONAL  error 16#8001, closed        open
    manifold all open: True
    """
    cell = ValveCell()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), cell)
    cell.cmd_open = True
    rt.run(duration=T("400ms"))
    print("slot  kind          FB_ValveByCase (CASE)        I_Valve manifold")
    for slot in range(1, 4):
        old = cell.by_case[slot]
        new = cell.manifold.valve(slot)
        before = f"error 16#{old.error_id:04X}, " if old.error else ""
        before += "open" if old.position >= 100.0 else "closed" if old.position <= 0.0 else "moving"
        after = "open" if new.is_open else "closed" if new.is_closed else "moving"
        print(f"{slot:<5} {old.kind.name:<13} {before:<28} {after}")
    print(f"manifold all open: {cell.manifold.all_open}")


def _position(index: int) -> Getter:
    return lambda prog: prog.by_case[index].position


SHOWCASE = Showcase(
    use_when="new device types must join without editing a CASE in code that is already commissioned",
    columns=(
        *(Column(f"CASE {k}", _position(i), ".0f") for i, k in ((1, "sol"), (2, "mot"), (3, "prop"))),
        Column("CASE errors", lambda p: " ".join(hex_word(p.by_case[i].error_id) for i in range(1, 4)
                                             if p.by_case[i].error) or "-"),
        Column("manifold all open", lambda p: p.manifold.all_open),
    ),
    script=steps((1, "cmd_open", True)),
    cycles=40,
    tour_cycles=40,
)
