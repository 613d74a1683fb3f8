"""Template Method: axis homing as a FINAL step chain whose steps the variants fill in.

Intent
------

Define the skeleton of an algorithm in one operation and defer some of its
steps to subclasses, so that the subclasses redefine those steps without
changing the algorithm's structure.

The PLC problem
---------------

Every servo or stepper axis must be homed before it may run a program: the
controller has to learn where the slide is. How it learns that differs from
axis to axis: one drives onto a limit switch and creeps off it, one searches
the encoder's index (zero) pulse with the drive's touch probe, one has an
absolute encoder and needs no motion at all. What does not differ is the
sequence and its supervision: check the preconditions (drive powered, at
standstill), approach, find the reference edge, back off, set the position,
report done; every step must finish within its time or the sequence stops
with an error that names the step, so the maintenance technician knows
whether the switch, the index or the drive is at fault.

With Template Method the abstract ``FB_AxisHoming`` owns that sequence in
its FINAL method ``Run``, called once per scan: a step chain over an enum,
one TON restarted at every step, the error handling. The steps are methods
the variants override: ABSTRACT for the ones every variant must define
(approach, edge, set position), with a default for the hooks (preconditions:
powered and at standstill; back off: none). A variant cannot change the
sequence: overriding ``Run`` is refused when the class is defined.

Roles
-----

- Abstract class → ``AxisHoming`` (``FB_AxisHoming``, ABSTRACT, with the
  FINAL template method ``run``), behind ``IHoming`` (``I_Homing``)
- Concrete classes → ``HomeOnLimitSwitch`` (``FB_HomeOnLimitSwitch``),
  ``HomeOnIndexPulse`` (``FB_HomeOnIndexPulse``), ``HomeAbsolute``
  (``FB_HomeAbsolute``)
- The axis the steps drive → ``IAxis`` (``I_Axis``), simulated by
  ``SimAxis`` (``FB_SimAxis``)
- Steps → ``HomingStep`` (``E_HomingStep``)
- Client → ``HomingCell`` (``PRG_HomingCell``), homing four axes through an
  ``ARRAY[1..4] OF I_Homing``

IEC 61131-3 mapping
-------------------

::

    TYPE E_HomingStep : (IDLE, PRECONDITIONS, APPROACH, EDGE, BACK_OFF,
                         SET_POSITION, DONE, ERROR); END_TYPE

    INTERFACE I_Homing
        METHOD Start
        METHOD Run : BOOL                     // once per scan; TRUE when done
        PROPERTY Step : E_HomingStep          // Get

    FUNCTION_BLOCK ABSTRACT FB_AxisHoming IMPLEMENTS I_Homing
        VAR_INPUT  timeout : TIME := T#5S; homePosition : LREAL; END_VAR
        VAR_OUTPUT busy, done, error : BOOL; errorStep : E_HomingStep;
                   errorText : STRING(60); END_VAR
        VAR axis : I_Axis; current : E_HomingStep; stepTimer : TON; entry : BOOL; END_VAR
        METHOD FB_init : BOOL                 // VAR_INPUT axis : I_Axis;
        PROPERTY Axis : I_Axis                // Set: the wiring step
        METHOD FINAL Run : BOOL               // the template method
        METHOD PRIVATE EnterStep              // VAR_INPUT step : E_HomingStep;
        METHOD PROTECTED FINAL MoveUntil : BOOL     // VAR_INPUT reached : BOOL; velocity : LREAL;
        METHOD PROTECTED CheckPreconditions : BOOL  // hook: powered AND standstill
        METHOD PROTECTED ABSTRACT Approach : BOOL   // VAR_INPUT first : BOOL;
        METHOD PROTECTED ABSTRACT FindEdge : BOOL
        METHOD PROTECTED BackOff : BOOL             // hook: no back-off move
        METHOD PROTECTED ABSTRACT SetReference : BOOL

    FUNCTION_BLOCK FB_HomeOnLimitSwitch EXTENDS FB_AxisHoming
        VAR release : F_TRIG; edgePosition : LREAL; END_VAR
    FUNCTION_BLOCK FB_HomeOnIndexPulse EXTENDS FB_AxisHoming
    FUNCTION_BLOCK FB_HomeAbsolute EXTENDS FB_AxisHoming

When not to use it on a PLC
---------------------------

When the drive does the homing itself (PLCopen ``MC_Home`` with the drive's
homing modes, CiA 402 homing methods), the PLC only starts it and waits:
use the function block the motion library provides. When there is one kind
of axis and no second one in sight, a plain step chain is easier to read
online than a base block and a derived one. And a deep hierarchy of
variants that override a little each is harder to follow than a few
strategies plugged into one sequence.

References
----------

- E. Gamma, R. Helm, R. Johnson, J. Vlissides, *Design Patterns: Elements of
  Reusable Object-Oriented Software*, Addison-Wesley 1994, "Template Method".
- IEC 61131-3:2013, *Programmable controllers - Part 3: Programming
  languages*, object-oriented function blocks: EXTENDS, ABSTRACT, FINAL,
  access specifiers; the standard blocks TON and F_TRIG.
- PLCopen, *Function Blocks for Motion Control*, Part 1 (``MC_Home``) and
  Part 5 (homing procedures).
- Beckhoff InfoSys, TwinCAT 3 PLC: "Object Method" (ABSTRACT, FINAL),
  "Extending a function block", "FB_init, FB_reinit, FB_exit".
- CODESYS Online Help: "Object: Method", "Extension of a Function Block",
  "ABSTRACT keyword", "FINAL keyword".
"""

from __future__ import annotations

from operator import attrgetter

from iecoop import (
    ABSTRACT,
    ARRAY,
    BOOL,
    DINT,
    FINAL,
    LREAL,
    PRIVATE,
    PROTECTED,
    STRING,
    TIME,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    FunctionBlock,
    IecEnum,
    Interface,
    Program,
    T,
    method,
    prop,
)
from iecoop.conversions import TIME_TO_DINT, TRUNC
from iecoop.runtime import Runtime, Task
from iecoop.stdlib import F_TRIG, R_TRIG, TON
from patterns.showcase.entry import Column, Showcase

__all__ = [
    "AxisHoming",
    "HomeAbsolute",
    "HomeOnIndexPulse",
    "HomeOnLimitSwitch",
    "HomingCell",
    "HomingStep",
    "IAxis",
    "IHoming",
    "SimAxis",
    "main",
]


class HomingStep(IecEnum):
    """``E_HomingStep``: the steps of the chain, in the order they run."""

    IDLE = 0
    PRECONDITIONS = 1
    APPROACH = 2
    EDGE = 3
    BACK_OFF = 4
    SET_POSITION = 5
    DONE = 6
    ERROR = 7


def floor_dint(value: LREAL) -> DINT:
    """``FUNCTION F_FloorDint : DINT``: the largest whole number not above ``value`` (TRUNC rounds toward zero)."""
    whole: DINT = TRUNC(value)
    if whole > value:
        whole -= 1
    return whole


# ---------------------------------------------------------------------------
# The axis
# ---------------------------------------------------------------------------


class IAxis(Interface):
    """``INTERFACE I_Axis``: the motion commands and feedback a homing sequence uses."""

    @method
    def move_velocity(self, velocity: LREAL) -> None: ...

    @method
    def halt(self) -> None: ...

    @method
    def set_position(self, position: LREAL) -> None: ...

    @method
    def arm_index_latch(self) -> None: ...

    @prop
    def position(self) -> LREAL:
        raise NotImplementedError

    @prop
    def powered(self) -> BOOL:
        raise NotImplementedError

    @prop
    def standstill(self) -> BOOL:
        raise NotImplementedError

    @prop
    def home_switch(self) -> BOOL:
        raise NotImplementedError

    @prop
    def index_latched(self) -> BOOL:
        raise NotImplementedError

    @prop
    def index_position(self) -> LREAL:
        raise NotImplementedError

    @prop
    def encoder_valid(self) -> BOOL:
        raise NotImplementedError

    @prop
    def absolute_position(self) -> LREAL:
        raise NotImplementedError


class SimAxis(FunctionBlock, IAxis):
    """``FUNCTION_BLOCK FB_SimAxis IMPLEMENTS I_Axis``: a simulated linear axis, one step per scan.

    ``mechanical`` is where the slide really is (mm); ``position`` is what
    the controller believes, ``mechanical + offset``, and ``set_position``
    moves the offset. The home switch is on for ``mechanical <= switch_at``;
    an index mark sits every ``index_pitch`` mm and, once the latch is armed,
    the first mark passed is latched exactly, as a drive's touch probe does;
    the absolute encoder reads ``mechanical + encoder_offset``. Call it once
    per scan before the homing, so the homing sees this scan's feedback.
    """

    cycle_time: TIME = VAR_INPUT(T("10ms"))
    enable: BOOL = VAR_INPUT(True)
    switch_at: LREAL = VAR_INPUT(-50.0)
    switch_broken: BOOL = VAR_INPUT(False)
    index_pitch: LREAL = VAR_INPUT(10.0)
    encoder_offset: LREAL = VAR_INPUT(0.0)
    encoder_ok: BOOL = VAR_INPUT(True)
    mechanical: LREAL = VAR_OUTPUT(0.0)
    velocity: LREAL = VAR_OUTPUT(0.0)
    offset: LREAL = VAR(0.0)
    latch_armed: BOOL = VAR(False)
    latched: BOOL = VAR(False)
    latched_at: LREAL = VAR(0.0)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, start_at: LREAL = 0.0) -> BOOL:
        self.mechanical = start_at
        return True

    def body(self) -> None:
        if not self.enable:
            self.velocity = 0.0
        before = self.mechanical
        self.mechanical = before + self.velocity * TIME_TO_DINT(self.cycle_time) / 1000.0
        if self.latch_armed and not self.latched:
            mark_before: DINT = floor_dint(before / self.index_pitch)
            mark_after: DINT = floor_dint(self.mechanical / self.index_pitch)
            if mark_before != mark_after:
                self.latched = True
                self.latched_at = max(mark_before, mark_after) * self.index_pitch

    @method
    def move_velocity(self, velocity: LREAL) -> None:
        self.velocity = velocity if self.enable else 0.0

    @method
    def halt(self) -> None:
        self.velocity = 0.0

    @method
    def set_position(self, position: LREAL) -> None:
        self.offset = position - self.mechanical

    @method
    def arm_index_latch(self) -> None:
        self.latch_armed = True
        self.latched = False

    @prop
    def position(self) -> LREAL:
        return self.mechanical + self.offset

    @prop
    def powered(self) -> BOOL:
        return self.enable

    @prop
    def standstill(self) -> BOOL:
        return self.velocity == 0.0

    @prop
    def home_switch(self) -> BOOL:
        return self.mechanical <= self.switch_at and not self.switch_broken

    @prop
    def index_latched(self) -> BOOL:
        return self.latched

    @prop
    def index_position(self) -> LREAL:
        return self.latched_at + self.offset

    @prop
    def encoder_valid(self) -> BOOL:
        return self.encoder_ok

    @prop
    def absolute_position(self) -> LREAL:
        return self.mechanical + self.encoder_offset


# ---------------------------------------------------------------------------
# The template
# ---------------------------------------------------------------------------


class IHoming(Interface):
    """``INTERFACE I_Homing``: start a homing, advance it once per scan, see its step."""

    @method
    def start(self) -> None: ...

    @method
    def run(self) -> BOOL:
        raise NotImplementedError

    @prop
    def step(self) -> HomingStep:
        raise NotImplementedError


class AxisHoming(FunctionBlock, IHoming, abstract=True):
    """``FUNCTION_BLOCK ABSTRACT FB_AxisHoming IMPLEMENTS I_Homing``: the homing sequence.

    ``start()`` requests a homing (ignored while one runs); ``run()``, the
    FINAL template method, advances it by one scan and returns ``done``. Each
    step method runs from the scan after its step is entered, gets ``first``
    (TRUE in that first scan) and returns TRUE when the step is finished; a step still unfinished after
    ``timeout`` halts the axis and ends in ERROR with ``error_step`` and
    ``error_text`` naming it. The axis is given to FB_init
    (``HomeAbsolute(axis=drive)``) or through the ``axis`` property.
    """

    timeout: TIME = VAR_INPUT(T("5s"))
    home_position: LREAL = VAR_INPUT(0.0)
    busy: BOOL = VAR_OUTPUT(False)
    done: BOOL = VAR_OUTPUT(False)
    error: BOOL = VAR_OUTPUT(False)
    error_step: HomingStep = VAR_OUTPUT(HomingStep.IDLE)
    error_text: STRING = VAR_OUTPUT("", length=60)
    drive: IAxis = VAR()
    current: HomingStep = VAR(HomingStep.IDLE)
    requested: BOOL = VAR(False)
    entry: BOOL = VAR(False)
    step_timer: TON = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, axis: IAxis | None = None) -> BOOL:
        if axis is not None:
            self.drive = axis
        return True

    @prop
    def axis(self) -> IAxis:
        return self.drive

    @axis.setter
    def axis(self, value: IAxis) -> None:
        self.drive = value

    @prop
    def step(self) -> HomingStep:
        return self.current

    @method
    def start(self) -> None:
        self.requested = True

    @method(FINAL)
    def run(self) -> BOOL:
        if self.requested and not self.busy:
            self.requested = False
            self.busy, self.done, self.error = True, False, False
            self.error_step, self.error_text = HomingStep.IDLE, ""
            self.enter_step(HomingStep.PRECONDITIONS)
            return False
        self.requested = False
        if not self.busy:
            return self.done
        first = self.entry
        self.entry = False
        self.step_timer(IN=True, PT=self.timeout)
        step = self.current
        # Each step names the one that follows it: the chain runs in the order of E_HomingStep.
        if step == HomingStep.PRECONDITIONS:
            finished, following = self.check_preconditions(first), HomingStep.APPROACH
        elif step == HomingStep.APPROACH:
            finished, following = self.approach(first), HomingStep.EDGE
        elif step == HomingStep.EDGE:
            finished, following = self.find_edge(first), HomingStep.BACK_OFF
        elif step == HomingStep.BACK_OFF:
            finished, following = self.back_off(first), HomingStep.SET_POSITION
        else:  # SET_POSITION: the only other step while busy
            finished, following = self.set_reference(first), HomingStep.DONE
        if finished:
            self.enter_step(following)
            if self.current == HomingStep.DONE:
                self.busy, self.done = False, True
        elif self.step_timer.Q:
            self.drive.halt()
            self.busy, self.error, self.error_step = False, True, step
            self.error_text = f"{step.name} timed out after {TIME_TO_DINT(self.timeout)} ms"
            self.current = HomingStep.ERROR
        return self.done

    @method(PRIVATE)
    def enter_step(self, step: HomingStep) -> None:
        """The step is entered in this scan; its method runs from the next scan, its time counts from now."""
        self.current = step
        self.entry = True
        self.step_timer(IN=False)
        self.step_timer(IN=True, PT=self.timeout)

    @method(PROTECTED | FINAL)
    def move_until(self, reached: BOOL, velocity: LREAL) -> BOOL:
        """For a moving step: halt and return TRUE once ``reached``, until then move at ``velocity``."""
        if reached:
            self.drive.halt()
            return True
        self.drive.move_velocity(velocity)
        return False

    # The steps: called only by run() and by the variants' overrides.

    @method(PROTECTED)
    def check_preconditions(self, first: BOOL) -> BOOL:
        """Hook: the drive is powered and at standstill."""
        return self.drive.powered and self.drive.standstill

    @method(PROTECTED | ABSTRACT)
    def approach(self, first: BOOL) -> BOOL:
        raise NotImplementedError

    @method(PROTECTED | ABSTRACT)
    def find_edge(self, first: BOOL) -> BOOL:
        raise NotImplementedError

    @method(PROTECTED)
    def back_off(self, first: BOOL) -> BOOL:
        """Hook: no back-off move."""
        return True

    @method(PROTECTED | ABSTRACT)
    def set_reference(self, first: BOOL) -> BOOL:
        raise NotImplementedError


class HomeOnLimitSwitch(AxisHoming):
    """``FUNCTION_BLOCK FB_HomeOnLimitSwitch EXTENDS FB_AxisHoming``: home on the switch's release edge.

    Approach: drive towards the switch at ``approach_velocity`` until it
    closes. Edge: creep off it; the F_TRIG of the switch is the reference
    (``home_position`` there). Back off: creep ``back_off_distance`` further.
    """

    approach_velocity: LREAL = VAR_INPUT(50.0)
    creep_velocity: LREAL = VAR_INPUT(5.0)
    back_off_distance: LREAL = VAR_INPUT(2.0)
    edge_position: LREAL = VAR_OUTPUT(0.0)
    release: F_TRIG = VAR()

    @method(PROTECTED)
    def approach(self, first: BOOL) -> BOOL:
        return self.move_until(self.drive.home_switch, -self.approach_velocity)

    @method(PROTECTED)
    def find_edge(self, first: BOOL) -> BOOL:
        self.release(CLK=self.drive.home_switch)
        found = self.move_until(self.release.Q and not first, self.creep_velocity)
        if found:
            self.edge_position = self.drive.position
        return found

    @method(PROTECTED)
    def back_off(self, first: BOOL) -> BOOL:
        return self.move_until(self.drive.position >= self.edge_position + self.back_off_distance, self.creep_velocity)

    @method(PROTECTED)
    def set_reference(self, first: BOOL) -> BOOL:
        self.drive.set_position(self.home_position + self.drive.position - self.edge_position)
        return True


class HomeOnIndexPulse(AxisHoming):
    """``FUNCTION_BLOCK FB_HomeOnIndexPulse EXTENDS FB_AxisHoming``: home on the encoder's index mark.

    Approach: travel ``clear_distance`` at ``approach_velocity``, off the
    mark the axis may stand on. Edge: arm the drive's latch and creep to the
    next mark; its latched position is ``home_position``. No back off.
    """

    approach_velocity: LREAL = VAR_INPUT(20.0)
    creep_velocity: LREAL = VAR_INPUT(5.0)
    clear_distance: LREAL = VAR_INPUT(2.0)
    start_position: LREAL = VAR(0.0)
    mark_position: LREAL = VAR_OUTPUT(0.0)

    @method(PROTECTED)
    def approach(self, first: BOOL) -> BOOL:
        if first:
            self.start_position = self.drive.position
        return self.move_until(self.drive.position >= self.start_position + self.clear_distance, self.approach_velocity)

    @method(PROTECTED)
    def find_edge(self, first: BOOL) -> BOOL:
        if first:
            self.drive.arm_index_latch()
        found = self.move_until(self.drive.index_latched, self.creep_velocity)
        if found:
            self.mark_position = self.drive.index_position
        return found

    @method(PROTECTED)
    def set_reference(self, first: BOOL) -> BOOL:
        self.drive.set_position(self.home_position + self.drive.position - self.mark_position)
        return True


class HomeAbsolute(AxisHoming):
    """``FUNCTION_BLOCK FB_HomeAbsolute EXTENDS FB_AxisHoming``: an absolute encoder, no motion.

    Preconditions add a valid encoder; approach and edge finish at once; the
    position is the encoder reading minus ``encoder_at_home`` (the reading
    stored at commissioning) plus ``home_position``.
    """

    encoder_at_home: LREAL = VAR_INPUT(0.0)

    @method(PROTECTED)
    def check_preconditions(self, first: BOOL) -> BOOL:
        return super().check_preconditions(first) and self.drive.encoder_valid

    @method(PROTECTED)
    def approach(self, first: BOOL) -> BOOL:
        return True

    @method(PROTECTED)
    def find_edge(self, first: BOOL) -> BOOL:
        return True

    @method(PROTECTED)
    def set_reference(self, first: BOOL) -> BOOL:
        self.drive.set_position(self.home_position + self.drive.absolute_position - self.encoder_at_home)
        return True


# ---------------------------------------------------------------------------
# The client
# ---------------------------------------------------------------------------


class HomingCell(Program):
    """``PROGRAM PRG_HomingCell``: homes four axes together on a rising edge of ``start``.

    X homes on its limit switch, Y on the index pulse, Z reads its absolute
    encoder, W homes on a limit switch whose wire is broken. The homings are
    wired to their axes in FB_init and run through ``ARRAY[1..4] OF I_Homing``.
    """

    start: BOOL = VAR_INPUT(True)
    all_done: BOOL = VAR_OUTPUT(False)
    x_axis: SimAxis = VAR({"switch_at": -10.0}, fb_init={"start_at": 35.0})
    y_axis: SimAxis = VAR(fb_init={"start_at": 3.0})
    z_axis: SimAxis = VAR({"encoder_offset": 500.0}, fb_init={"start_at": 12.5})
    w_axis: SimAxis = VAR({"switch_at": -10.0, "switch_broken": True}, fb_init={"start_at": 20.0})
    x_homing: HomeOnLimitSwitch = VAR()
    y_homing: HomeOnIndexPulse = VAR()
    z_homing: HomeAbsolute = VAR({"encoder_at_home": 500.0})
    w_homing: HomeOnLimitSwitch = VAR({"timeout": T("1s")})
    homings: ARRAY[IHoming] = VAR(bounds=(1, 4))
    start_edge: R_TRIG = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
        self.x_homing.axis = self.x_axis
        self.y_homing.axis = self.y_axis
        self.z_homing.axis = self.z_axis
        self.w_homing.axis = self.w_axis
        self.homings[1] = self.x_homing
        self.homings[2] = self.y_homing
        self.homings[3] = self.z_homing
        self.homings[4] = self.w_homing
        return True

    def body(self) -> None:
        self.x_axis()
        self.y_axis()
        self.z_axis()
        self.w_axis()
        self.start_edge(CLK=self.start)
        all_done = True
        for i in range(1, 5):
            if self.start_edge.Q:
                self.homings[i].start()
            all_done = self.homings[i].run() and all_done
        self.all_done = all_done


def main() -> None:
    """Home four axes on a 10 ms task and print when each entered each step.

    >>> main()
    step            X switch   Y index  Z absolute  W switch
    PRECONDITIONS       0 ms      0 ms        0 ms      0 ms
    APPROACH           10 ms     10 ms       10 ms     10 ms
    EDGE              920 ms    120 ms       20 ms         -
    BACK_OFF          940 ms   1130 ms       30 ms         -
    SET_POSITION     1350 ms   1140 ms       40 ms         -
    DONE             1360 ms   1150 ms       50 ms         -
    ERROR                  -         -           -   1010 ms
    position           2.000     0.000      12.500
    W: APPROACH timed out after 1000 ms
    """
    cell = HomingCell()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), cell)
    homings = (cell.x_homing, cell.y_homing, cell.z_homing, cell.w_homing)
    entered: dict[tuple[int, HomingStep], int] = {}
    for _ in range(150):
        now = rt.time_ms
        rt.run(cycles=1)
        for column, homing in enumerate(homings):
            entered.setdefault((column, homing.step), now)
    print(f"{'step':<14}{'X switch':>10}{'Y index':>10}{'Z absolute':>12}{'W switch':>10}")
    for step in list(HomingStep)[1:]:
        cells = [f"{entered[(c, step)]} ms" if (c, step) in entered else "-" for c in range(4)]
        print(f"{step.name:<14}{cells[0]:>10}{cells[1]:>10}{cells[2]:>12}{cells[3]:>10}")
    axes = (cell.x_axis, cell.y_axis, cell.z_axis)
    print(f"{'position':<14}" + "".join(f"{a.position:>{w}.3f}" for a, w in zip(axes, (10, 10, 12))))
    print(f"W: {cell.w_homing.error_text}")


SHOWCASE = Showcase(
    use_when="axis variants share one fixed homing sequence and differ only in its steps",
    columns=(
        *(Column(f"{axis} {method}", attrgetter(f"{axis.lower()}_homing.step"))
          for axis, method in (("X", "switch"), ("Y", "index"), ("Z", "absolute"), ("W", "switch"))),
        Column("all done", lambda p: p.all_done),
    ),
    cycles=150,
    tour_cycles=150,
)
