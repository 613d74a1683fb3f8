"""Composite: a conveyor line made of zones made of sections, driven through one interface.

Intent
------

Compose objects into tree structures and let clients treat a single object
and a composition of objects in the same way.

The PLC problem
---------------

A packaging hall runs a conveyor line split into zones (infeed, transfer),
each made of belt sections driven by one motor. The HMI and the line
controller want the same four things from a section, a zone or the whole
line: start it, stop it, is it running, is it faulted, and how much power
does it draw. Writing those as nested loops over a fixed "line / zone /
section" hierarchy breaks as soon as a zone gets a sub-zone. With one
interface, a zone forwards start and stop to its children, ANDs their
``is_running``, ORs their ``is_faulted`` and sums their power; a section
answers for itself. A zone starts its children downstream first and
staggered in time, so the product never runs onto a stopped belt and the
motors' inrush currents do not add up.

A PLC has no heap and a small call stack, so the tree is built from
statically allocated blocks: each group holds a bounded ``ARRAY`` of child
interfaces and refuses, with a result code, an element that is null, itself,
already in a tree, an ancestor of the group (a cycle), one too many, or one
that would make the tree deeper than ``MAX_DEPTH`` (which bounds every
recursive call).

Roles
-----

- Component → ``IConveyorElement`` (``I_ConveyorElement``)
- Composite interface → ``IConveyorGroup`` (``I_ConveyorGroup``)
- Shared base → ``ConveyorElement`` (``FB_ConveyorElement``, ABSTRACT)
- Leaf → ``ConveyorSection`` (``FB_ConveyorSection``, FINAL)
- Composite → ``ConveyorGroup`` (``FB_ConveyorGroup``), used for zones and the line
- Client → ``ConveyorMain`` (``PRG_ConveyorMain``)

IEC 61131-3 mapping
-------------------

::

    INTERFACE I_ConveyorElement EXTENDS __SYSTEM.IQueryInterface
        METHOD Start; METHOD Stop; METHOD Reset; METHOD Scan
        PROPERTY IsRunning : BOOL; PROPERTY IsFaulted : BOOL; PROPERTY PowerKW : LREAL
        PROPERTY Name : STRING; PROPERTY Level : INT; PROPERTY Height : INT
        METHOD SetLevel  VAR_INPUT level : INT; END_VAR

    INTERFACE I_ConveyorGroup EXTENDS I_ConveyorElement
        METHOD Add : E_AddResult  VAR_INPUT element : I_ConveyorElement; END_VAR
        METHOD Contains : BOOL    VAR_INPUT element : I_ConveyorElement; END_VAR
        PROPERTY Count : INT

    FUNCTION_BLOCK ABSTRACT FB_ConveyorElement IMPLEMENTS I_ConveyorElement
        VAR sName : STRING(20); nLevel : INT := 1; END_VAR
        METHOD FB_init : BOOL  VAR_INPUT sName : STRING(20); END_VAR

    FUNCTION_BLOCK FINAL FB_ConveyorSection EXTENDS FB_ConveyorElement
        VAR_INPUT bMotorTrip : BOOL; fRatedKW : LREAL; tRunUp : TIME := T#300MS; END_VAR
        VAR_OUTPUT bContactor, bAtSpeed, bFault : BOOL; END_VAR
        VAR fbRunUp : TON; END_VAR

    FUNCTION_BLOCK FB_ConveyorGroup EXTENDS FB_ConveyorElement IMPLEMENTS I_ConveyorGroup
        VAR_INPUT tStagger : TIME := T#100MS; END_VAR
        VAR aChildren : ARRAY[1..MAX_CHILDREN] OF I_ConveyorElement;
            nCount, nNextStart : INT; fbStagger : TON; END_VAR

When not to use it on a PLC
---------------------------

When the plant hierarchy is fixed and flat (one line, a handful of drives),
a plain array of sections and one FOR loop is simpler to read online and
to debug. Do not build trees whose shape changes while the machine runs:
wire them once at initialisation. Keep every interlock that protects people
(emergency stop, guard doors) out of the composite: it belongs in the
safety PLC, not in method calls that a null reference can break.

References
----------

- Gamma, Helm, Johnson, Vlissides: *Design Patterns*, Addison-Wesley 1994, "Composite".
- IEC 61131-3:2013, 3rd ed., 6.6.5 (interfaces), 6.6.6 (methods), 6.6.7 (properties).
- Beckhoff InfoSys, TwinCAT 3 PLC: "Interface", "__QUERYINTERFACE", "Property", "TON".
- CODESYS Online Help: "Object: Interface", "Extending a function block", "Operator: __QUERYINTERFACE".
"""

from __future__ import annotations

from typing import Any

from iecoop import (
    ARRAY,
    BOOL,
    INT,
    LREAL,
    PRIVATE,
    STRING,
    TIME,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    FunctionBlock,
    IecEnum,
    IQueryInterface,
    Program,
    T,
    call_after_init,
    method,
    prop,
    query_interface,
)
from iecoop.runtime import Runtime, Task
from iecoop.stdlib import R_TRIG, TON
from patterns.showcase.entry import Column, Showcase, press, steps

__all__ = [
    "MAX_CHILDREN",
    "MAX_DEPTH",
    "AddResult",
    "ConveyorElement",
    "ConveyorGroup",
    "ConveyorMain",
    "ConveyorSection",
    "IConveyorElement",
    "IConveyorGroup",
    "main",
]

#: ``VAR_GLOBAL CONSTANT MAX_CHILDREN : INT := 8;``: children per group.
MAX_CHILDREN = 8
#: ``VAR_GLOBAL CONSTANT MAX_DEPTH : INT := 4;``: levels in a tree, the root included.
MAX_DEPTH = 4


class AddResult(IecEnum):
    """``TYPE E_AddResult : (ADDED, NULL_ELEMENT, SELF, ALREADY_IN_TREE, CYCLE, FULL, TOO_DEEP) INT;``"""

    ADDED = 0
    NULL_ELEMENT = 1
    SELF = 2
    ALREADY_IN_TREE = 3
    CYCLE = 4
    FULL = 5
    TOO_DEEP = 6


class IConveyorElement(IQueryInterface):
    """``INTERFACE I_ConveyorElement EXTENDS __SYSTEM.IQueryInterface``: a section, a zone or a line."""

    @method
    def start(self) -> None: ...

    @method
    def stop(self) -> None: ...

    @method
    def reset(self) -> None: ...

    @method
    def scan(self) -> None: ...

    @prop
    def is_running(self) -> BOOL:
        raise NotImplementedError

    @prop
    def is_faulted(self) -> BOOL:
        raise NotImplementedError

    @prop
    def power_kw(self) -> LREAL:
        raise NotImplementedError

    @prop
    def name(self) -> STRING:
        raise NotImplementedError

    @prop
    def level(self) -> INT:
        raise NotImplementedError

    @prop
    def height(self) -> INT:
        raise NotImplementedError

    @method
    def set_level(self, level: INT) -> None: ...


class IConveyorGroup(IConveyorElement):
    """``INTERFACE I_ConveyorGroup EXTENDS I_ConveyorElement``: an element that holds children."""

    @method
    def add(self, element: IConveyorElement) -> AddResult:
        raise NotImplementedError

    @method
    def contains(self, element: IConveyorElement) -> BOOL:
        raise NotImplementedError

    @prop
    def count(self) -> INT:
        raise NotImplementedError


class ConveyorElement(FunctionBlock, IConveyorElement, abstract=True):
    """``FUNCTION_BLOCK ABSTRACT FB_ConveyorElement IMPLEMENTS I_ConveyorElement``: name and tree level."""

    element_name: STRING = VAR("", length=20)
    tree_level: INT = VAR(1)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, name: STRING = "") -> None:
        self.element_name = name

    @prop
    def name(self) -> STRING:
        return self.element_name

    @prop
    def level(self) -> INT:
        """1 for a root; a group sets its children's level when it adopts them."""
        return self.tree_level

    @method
    def set_level(self, level: INT) -> None:
        self.tree_level = level


class ConveyorSection(ConveyorElement, final=True):
    """``FUNCTION_BLOCK FINAL FB_ConveyorSection EXTENDS FB_ConveyorElement``: one belt, one motor.

    ``motor_trip`` is the motor protection contact; a trip latches ``fault``
    and drops the contactor until ``reset()`` with the trip cleared.
    """

    motor_trip: BOOL = VAR_INPUT(False)
    rated_kw: LREAL = VAR_INPUT(0.75)
    run_up_time: TIME = VAR_INPUT(T("300ms"))
    contactor: BOOL = VAR_OUTPUT(False)
    at_speed: BOOL = VAR_OUTPUT(False)
    fault: BOOL = VAR_OUTPUT(False)
    run_up: TON = VAR()

    @method
    def start(self) -> None:
        if not self.fault:
            self.contactor = True

    @method
    def stop(self) -> None:
        self.contactor = False

    @method
    def reset(self) -> None:
        if not self.motor_trip:
            self.fault = False

    @method
    def scan(self) -> None:
        if self.motor_trip:
            self.fault = True
        if self.fault:
            self.contactor = False
        self.run_up(IN=self.contactor, PT=self.run_up_time)
        self.at_speed = self.run_up.Q

    @prop
    def is_running(self) -> BOOL:
        return self.at_speed

    @prop
    def is_faulted(self) -> BOOL:
        return self.fault

    @prop
    def power_kw(self) -> LREAL:
        return self.rated_kw if self.contactor else 0.0

    @prop
    def height(self) -> INT:
        return 1


class ConveyorGroup(ConveyorElement, IConveyorGroup):
    """``FUNCTION_BLOCK FB_ConveyorGroup EXTENDS FB_ConveyorElement IMPLEMENTS I_ConveyorGroup``.

    A zone or a line. ``start()`` starts the last (most downstream) child at
    once and one more child every ``stagger_time``; ``stop()`` stops every
    child at once, upstream first.
    """

    stagger_time: TIME = VAR_INPUT(T("100ms"))
    children: ARRAY[IConveyorElement] = VAR(bounds=(1, MAX_CHILDREN))
    child_count: INT = VAR(0)
    next_start: INT = VAR(0)
    stagger: TON = VAR()

    @method
    def add(self, element: IConveyorElement) -> AddResult:
        """Adopt ``element`` as the most downstream child, or say why not."""
        if not element:
            return AddResult.NULL_ELEMENT
        if element == self:
            return AddResult.SELF
        if element.level > 1:
            return AddResult.ALREADY_IN_TREE
        group = query_interface(element, IConveyorGroup)
        if group is not None and group.contains(self):
            return AddResult.CYCLE
        if self.child_count >= MAX_CHILDREN:
            return AddResult.FULL
        if self.tree_level + element.height > MAX_DEPTH:
            return AddResult.TOO_DEEP
        self.child_count += 1
        self.children[self.child_count] = element
        element.set_level(self.tree_level + 1)
        return AddResult.ADDED

    @method
    def contains(self, element: IConveyorElement) -> BOOL:
        """Whether ``element`` is this group or anywhere below it."""
        if element == self:
            return True
        for i in range(1, self.child_count + 1):
            child = self.children[i]
            if child == element:
                return True
            group = query_interface(child, IConveyorGroup)
            if group is not None and group.contains(element):
                return True
        return False

    @method
    def set_level(self, level: INT) -> None:
        super().set_level(level)
        for i in range(1, self.child_count + 1):
            self.children[i].set_level(level + 1)

    @method
    def start(self) -> None:
        if self.child_count == 0:
            return
        self.children[self.child_count].start()
        self.next_start = self.child_count - 1
        self.stagger(IN=False)

    @method
    def stop(self) -> None:
        self.next_start = 0
        self.stagger(IN=False)
        for i in range(1, self.child_count + 1):
            self.children[i].stop()

    @method
    def reset(self) -> None:
        for i in range(1, self.child_count + 1):
            self.children[i].reset()

    @method
    def scan(self) -> None:
        if self.next_start > 0:
            self.stagger(IN=True, PT=self.stagger_time)
            if self.stagger.Q:
                self.children[self.next_start].start()
                self.next_start -= 1
                self.stagger(IN=False)
                self.stagger(IN=self.next_start > 0, PT=self.stagger_time)
        for i in range(1, self.child_count + 1):
            self.children[i].scan()

    @prop
    def is_running(self) -> BOOL:
        """AND of the children; an empty group is not running."""
        if self.child_count == 0:
            return False
        for i in range(1, self.child_count + 1):
            if not self.children[i].is_running:
                return False
        return True

    @prop
    def is_faulted(self) -> BOOL:
        """OR of the children."""
        for i in range(1, self.child_count + 1):
            if self.children[i].is_faulted:
                return True
        return False

    @prop
    def power_kw(self) -> LREAL:
        """Sum of the children, in child order."""
        total = 0.0
        for i in range(1, self.child_count + 1):
            total += self.children[i].power_kw
        return total

    @prop
    def height(self) -> INT:
        tallest = 0
        for i in range(1, self.child_count + 1):
            tallest = max(tallest, self.children[i].height)
        return tallest + 1

    @prop
    def count(self) -> INT:
        return self.child_count


class ConveyorMain(Program):
    """``PROGRAM PRG_ConveyorMain``: a line of two zones and five sections, run from three HMI buttons.

    A fault anywhere stops the whole line; ``cmd_reset`` acknowledges it once
    the motor protection has been reset in the field.
    """

    cmd_start: BOOL = VAR_INPUT(False)
    cmd_stop: BOOL = VAR_INPUT(False)
    cmd_reset: BOOL = VAR_INPUT(False)
    line: ConveyorGroup = VAR(fb_init={"name": "Line"})
    infeed: ConveyorGroup = VAR(fb_init={"name": "Infeed"})
    transfer: ConveyorGroup = VAR(fb_init={"name": "Transfer"})
    s1: ConveyorSection = VAR({"rated_kw": 0.55}, fb_init={"name": "S1"})
    s2: ConveyorSection = VAR({"rated_kw": 0.55}, fb_init={"name": "S2"})
    s3: ConveyorSection = VAR({"rated_kw": 1.1}, fb_init={"name": "S3"})
    s4: ConveyorSection = VAR({"rated_kw": 1.1}, fb_init={"name": "S4"})
    s5: ConveyorSection = VAR({"rated_kw": 1.5}, fb_init={"name": "S5"})
    start_edge: R_TRIG = VAR()
    stop_edge: R_TRIG = VAR()
    reset_edge: R_TRIG = VAR()
    wired: BOOL = VAR_OUTPUT(False)
    running: BOOL = VAR_OUTPUT(False)
    faulted: BOOL = VAR_OUTPUT(False)
    power_kw: LREAL = VAR_OUTPUT(0.0)

    @call_after_init
    def wire(self) -> None:
        """Build the tree once; ``wired`` tells the HMI every element was accepted."""
        self.wired = True
        self.accept(self.infeed.add(self.s1))
        self.accept(self.infeed.add(self.s2))
        self.accept(self.transfer.add(self.s3))
        self.accept(self.transfer.add(self.s4))
        self.accept(self.transfer.add(self.s5))
        self.accept(self.line.add(self.infeed))
        self.accept(self.line.add(self.transfer))

    @method(PRIVATE)
    def accept(self, result: AddResult) -> None:
        """``wired`` stays TRUE only while every element is ADDED; every add runs either way."""
        if result != AddResult.ADDED:
            self.wired = False

    def body(self) -> None:
        self.start_edge(CLK=self.cmd_start)
        self.stop_edge(CLK=self.cmd_stop)
        self.reset_edge(CLK=self.cmd_reset)
        if self.reset_edge.Q:
            self.line.reset()
        if self.stop_edge.Q:
            self.line.stop()
        elif self.start_edge.Q and not self.line.is_faulted:
            self.line.start()
        self.line.scan()
        if self.line.is_faulted:
            self.line.stop()
        self.running = self.line.is_running
        self.faulted = self.line.is_faulted
        self.power_kw = self.line.power_kw


def _trace(rt: Runtime, prog: ConveyorMain, event: str) -> None:
    sections = (prog.s1, prog.s2, prog.s3, prog.s4, prog.s5)
    on = " ".join(s.name for s in sections if s.contactor) or "-"
    state = "FAULT" if prog.faulted else "running" if prog.running else "stopped"
    print(f"t={rt.time_ms:5d} ms  {event:<13} {state:<8} {prog.power_kw:4.2f} kW  on: {on}")


def main() -> None:
    """Start the line, trip a motor, reset and restart; print the line after each step.

    >>> main()
    t=    0 ms  wired         stopped  0.00 kW  on: -
    t=   10 ms  start         stopped  1.50 kW  on: S5
    t=  110 ms  staggering    stopped  3.15 kW  on: S2 S4 S5
    t=  210 ms  staggering    stopped  4.80 kW  on: S1 S2 S3 S4 S5
    t=  600 ms  at speed      running  4.80 kW  on: S1 S2 S3 S4 S5
    t=  800 ms  S4 trips      FAULT    0.00 kW  on: -
    t= 1000 ms  reset, trip   FAULT    0.00 kW  on: -
    t= 1200 ms  reset         stopped  0.00 kW  on: -
    t= 1800 ms  restarted     running  4.80 kW  on: S1 S2 S3 S4 S5
    """
    prog = ConveyorMain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), prog)
    _trace(rt, prog, "wired" if prog.wired else "NOT WIRED")
    prog.cmd_start = True
    rt.run(cycles=1)
    _trace(rt, prog, "start")
    prog.cmd_start = False
    rt.run(cycles=10)
    _trace(rt, prog, "staggering")
    rt.run(cycles=10)
    _trace(rt, prog, "staggering")
    rt.run(cycles=39)
    _trace(rt, prog, "at speed")
    prog.s4.motor_trip = True
    rt.run(cycles=20)
    _trace(rt, prog, "S4 trips")
    prog.cmd_reset = True
    rt.run(cycles=20)
    _trace(rt, prog, "reset, trip")
    prog.cmd_reset = False
    prog.s4.motor_trip = False
    rt.run(cycles=1)
    prog.cmd_reset = True
    rt.run(cycles=19)
    _trace(rt, prog, "reset")
    prog.cmd_reset = False
    prog.cmd_start = True
    rt.run(cycles=60)
    _trace(rt, prog, "restarted")


def _sections_on(prog: Any) -> object:
    return " ".join(s.name for s in (prog.s1, prog.s2, prog.s3, prog.s4, prog.s5) if s.contactor) or "-"


SHOWCASE = Showcase(
    use_when="a line of zones of sections is commanded and queried through one interface, wired once at start-up",
    columns=(
        Column("running", lambda p: p.running),
        Column("faulted", lambda p: p.faulted),
        Column("kW", lambda p: p.power_kw, ".2f"),
        Column("contactors on", _sections_on),
    ),
    script=steps(
        *press("cmd_start", 1), (62, "s4.motor_trip", True), *press("cmd_reset", 82, hold=20),
        (102, "s4.motor_trip", False), *press("cmd_reset", 103), *press("cmd_start", 122),
    ),
    cycles=190,
    tour_cycles=190,
    expected=(("faulted", "the motor of section S4 trips in cycle 62"),),
)


if __name__ == "__main__":
    main()
