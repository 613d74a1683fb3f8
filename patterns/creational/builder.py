"""Builder: a motion profile assembled step by step, validated, then run segment by segment.

Intent
------

Separate the construction of a complex object from its representation: the
client states the steps (ramp, cruise, dwell, target) one call at a time, the
builder checks each step and assembles the product, and ``build()`` hands out
the finished product only when the whole of it is consistent.

The PLC problem
---------------

An indexing feed axis moves a web by a fixed length per cycle of the
machine, with a profile the process engineer tunes: accelerate, run, brake,
wait for the punch. The profile is a STRUCT holding an ARRAY of segments,
which the axis executes across PLC cycles. Filling that array by hand is
where the bugs are: a ramp longer than the axis can accelerate, a dwell while
the axis still moves, a segment too many for the array, a profile that does
not end at standstill or does not add up to the commanded length.

``ProfileBuilder`` offers a fluent interface: every step method returns
THIS^ (``self``), so a profile reads as one line,
``builder.begin("index").ramp(200.0, T("100ms")).cruise(T("400ms"))...``.
Each step is checked as it is given; the first error is latched with the
number of the step (later steps are ignored until ``begin``), as a PLCopen
block latches ``Error`` / ``ErrorID``. ``build`` then checks the whole
profile and returns an ``E_ProfileError``: ``NONE`` and a copy of the
product (``MEMCPY`` into the caller's VAR_IN_OUT), or the reason and a
product marked invalid. No exception is raised for a bad profile, because a
PLC program must keep scanning: the caller tests the code, as it tests
``ErrorID``. ``ProfileRunner`` refuses a product that ``build`` did not
validate, and runs a valid one with one TON per segment.

Roles
-----

- Builder: ``IProfileBuilder`` (``I_ProfileBuilder``), whose step methods
  return the builder itself
- Concrete builder: ``ProfileBuilder`` (``FB_ProfileBuilder``, FINAL)
- Product: ``MotionProfile`` (``ST_MotionProfile``) holding
  ``ARRAY[1..8] OF MotionSegment`` (``ST_MotionSegment``)
- Director: ``FeedAxisMain`` (``PROGRAM FeedAxisMain``), which knows the
  steps of the profiles the machine needs
- Consumer: ``ProfileRunner`` (``FB_ProfileRunner``) behind
  ``IProfileRunner`` (``I_ProfileRunner``)

IEC 61131-3 mapping
-------------------

::

    TYPE ST_MotionSegment : STRUCT eKind : E_SegmentKind; fVelocity : LREAL; tDuration : TIME; END_STRUCT END_TYPE
    TYPE ST_MotionProfile :
    STRUCT
        sName : STRING(20); aSegment : ARRAY[1..8] OF ST_MotionSegment; nCount : INT;
        fTarget : LREAL; bValid : BOOL;
    END_STRUCT END_TYPE

    INTERFACE I_ProfileBuilder
        METHOD Begin : I_ProfileBuilder    VAR_INPUT sName : STRING; END_VAR
        METHOD Ramp : I_ProfileBuilder     VAR_INPUT fVelocity : LREAL; tDuration : TIME; END_VAR
        METHOD Cruise : I_ProfileBuilder   VAR_INPUT tDuration : TIME; END_VAR
        METHOD Dwell : I_ProfileBuilder    VAR_INPUT tDuration : TIME; END_VAR
        METHOD Target : I_ProfileBuilder   VAR_INPUT fPosition : LREAL; END_VAR
        METHOD Build : E_ProfileError      VAR_IN_OUT stProfile : ST_MotionProfile; END_VAR
        PROPERTY PlannedDistance : LREAL

    FUNCTION_BLOCK FINAL FB_ProfileBuilder IMPLEMENTS I_ProfileBuilder
        VAR_INPUT  fMaxVelocity : LREAL := 500; fMaxAccel : LREAL := 5000; END_VAR
        VAR_OUTPUT eError : E_ProfileError; nErrorStep : INT; END_VAR
        METHOD Ramp : I_ProfileBuilder     // ...; Ramp := THIS^;

    FUNCTION_BLOCK FB_ProfileRunner IMPLEMENTS I_ProfileRunner
        VAR_INPUT  bExecute : BOOL; END_VAR
        VAR_OUTPUT bBusy : BOOL; eError : E_ProfileError; nStep : INT; fPosition, fVelocity : LREAL; END_VAR
        VAR aTimer : ARRAY[1..8] OF TON; stProfile : ST_MotionProfile; END_VAR
        METHOD Load : BOOL
            VAR_IN_OUT CONSTANT stProfile : ST_MotionProfile; END_VAR
        PROPERTY Done : BOOL

The step methods return ``I_ProfileBuilder``, so the director's chain
needs nothing but the interface; a builder with other rules (another axis
type's limits) implements the same interface instead of extending the FINAL
block.

When not to use it on a PLC
---------------------------

A profile with two fixed segments is clearer as a STRUCT literal in a VAR
CONSTANT. The builder is worth it when profiles are assembled at run time
(from an HMI recipe, per product) and the checks must live in one place.
Build during a standstill, not while the runner executes: ``Load`` copies the
product, and the runner refuses a new one while busy.

References
----------

- E. Gamma, R. Helm, R. Johnson, J. Vlissides, *Design Patterns: Elements of
  Reusable Object-Oriented Software*, Addison-Wesley 1994: "Builder".
- IEC 61131-3:2013, *Programmable controllers - Part 3: Programming
  languages*, 3rd edition: THIS, methods, STRUCT, ARRAY, TON.
- Beckhoff InfoSys, TwinCAT 3 PLC: "THIS", "Object Method", "MEMCPY".
- CODESYS Online Help: "THIS", "Object: Method".
- PLCopen, *Function blocks for motion control*, Part 1: the Execute / Busy
  / Done / Error / ErrorID behaviour.
"""

from __future__ import annotations

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
    Interface,
    Program,
    Struct,
    T,
    adr,
    memcpy,
    memset,
    method,
    prop,
    sizeof,
)
from iecoop.runtime import Runtime, Task
from iecoop.stdlib import R_TRIG, TON
from patterns.showcase.entry import Column, Showcase

__all__ = [
    "DISTANCE_TOLERANCE",
    "FeedAxisMain",
    "IProfileBuilder",
    "IProfileRunner",
    "MAX_SEGMENTS",
    "MotionProfile",
    "MotionSegment",
    "ProfileBuilder",
    "ProfileError",
    "ProfileRunner",
    "SegmentKind",
    "main",
]

#: Segments a profile holds (``ARRAY[1..MAX_SEGMENTS]``).
MAX_SEGMENTS = 8
#: How far (mm) the segments may travel from the target.
DISTANCE_TOLERANCE = 0.01


class SegmentKind(IecEnum):
    """``E_SegmentKind``."""

    NONE = 0
    RAMP = 1
    CRUISE = 2
    DWELL = 3


class ProfileError(IecEnum):
    """``E_ProfileError``: the first reason a profile is not valid."""

    NONE = 0
    NEGATIVE_VELOCITY = 1
    VELOCITY_LIMIT = 2
    ACCEL_LIMIT = 3
    ZERO_DURATION = 4
    DWELL_WHILE_MOVING = 5
    TOO_MANY_SEGMENTS = 6
    NO_TARGET = 7
    ENDS_MOVING = 8
    DISTANCE_MISMATCH = 9
    NOT_BUILT = 10
    BUSY = 11


class MotionSegment(Struct):
    """``ST_MotionSegment``: velocity at the end of the segment (mm/s) and its duration."""

    kind: SegmentKind = SegmentKind.NONE
    velocity: LREAL = 0.0
    duration: TIME = 0


class MotionProfile(Struct):
    """``ST_MotionProfile``: the product; ``valid`` is set only by a successful ``build``."""

    name: STRING = VAR("", length=20)
    segments: ARRAY[MotionSegment] = VAR(bounds=(1, MAX_SEGMENTS))
    count: INT = 0
    target: LREAL = 0.0
    valid: BOOL = False


class IProfileBuilder(Interface):
    """``INTERFACE I_ProfileBuilder``: the steps, each returning the builder, and the finished product."""

    @method
    def begin(self, name: STRING) -> IProfileBuilder:
        raise NotImplementedError

    @method
    def ramp(self, velocity: LREAL, duration: TIME) -> IProfileBuilder:
        raise NotImplementedError

    @method
    def cruise(self, duration: TIME) -> IProfileBuilder:
        raise NotImplementedError

    @method
    def dwell(self, duration: TIME) -> IProfileBuilder:
        raise NotImplementedError

    @method
    def target(self, position: LREAL) -> IProfileBuilder:
        raise NotImplementedError

    @method
    def build(self, profile: MotionProfile) -> ProfileError:
        raise NotImplementedError

    @prop
    def planned_distance(self) -> LREAL:
        raise NotImplementedError


class ProfileBuilder(FunctionBlock, IProfileBuilder, final=True):
    """``FUNCTION_BLOCK FINAL FB_ProfileBuilder``: each step returns THIS^; the first error latches."""

    max_velocity: LREAL = VAR_INPUT(500.0)
    max_accel: LREAL = VAR_INPUT(5000.0)
    error: ProfileError = VAR_OUTPUT(ProfileError.NONE)
    error_step: INT = VAR_OUTPUT(0)
    draft: MotionProfile = VAR()
    velocity: LREAL = VAR(0.0)
    distance: LREAL = VAR(0.0)
    steps: INT = VAR(0)
    has_target: BOOL = VAR(False)

    @method
    def begin(self, name: STRING) -> IProfileBuilder:
        """Start a new profile at standstill; clears a latched error."""
        memset(adr(self, "draft"), 0, sizeof(MotionProfile))
        self.draft.name = name
        self.error = ProfileError.NONE
        self.error_step = 0
        self.velocity = 0.0
        self.distance = 0.0
        self.steps = 0
        self.has_target = False
        return self

    @method
    def ramp(self, velocity: LREAL, duration: TIME) -> IProfileBuilder:
        """Change the velocity linearly to ``velocity`` (mm/s) in ``duration``."""
        if not self.accept():
            return self
        if velocity < 0.0:
            return self.reject(ProfileError.NEGATIVE_VELOCITY)
        if velocity > self.max_velocity:
            return self.reject(ProfileError.VELOCITY_LIMIT)
        if duration <= 0:
            return self.reject(ProfileError.ZERO_DURATION)
        if abs(velocity - self.velocity) / (duration / 1000) > self.max_accel:
            return self.reject(ProfileError.ACCEL_LIMIT)
        return self.append(SegmentKind.RAMP, velocity, duration)

    @method
    def cruise(self, duration: TIME) -> IProfileBuilder:
        """Keep the present velocity for ``duration``."""
        if not self.accept():
            return self
        if duration <= 0:
            return self.reject(ProfileError.ZERO_DURATION)
        return self.append(SegmentKind.CRUISE, self.velocity, duration)

    @method
    def dwell(self, duration: TIME) -> IProfileBuilder:
        """Stand still for ``duration``; only allowed at standstill."""
        if not self.accept():
            return self
        if self.velocity != 0.0:
            return self.reject(ProfileError.DWELL_WHILE_MOVING)
        if duration <= 0:
            return self.reject(ProfileError.ZERO_DURATION)
        return self.append(SegmentKind.DWELL, 0.0, duration)

    @method
    def target(self, position: LREAL) -> IProfileBuilder:
        """Where the move must end (mm from its start); ``build`` checks the segments reach it."""
        if self.accept():
            self.draft.target = position
            self.has_target = True
        return self

    @method
    def build(self, profile: MotionProfile) -> ProfileError:
        """Check the whole profile; on success copy it into ``profile`` (VAR_IN_OUT) marked valid."""
        if self.error == ProfileError.NONE:
            if not self.has_target:
                self.error = ProfileError.NO_TARGET
            elif self.velocity != 0.0:
                self.error = ProfileError.ENDS_MOVING
            elif abs(self.distance - self.draft.target) > DISTANCE_TOLERANCE:
                self.error = ProfileError.DISTANCE_MISMATCH
        if self.error != ProfileError.NONE:
            profile.valid = False
            return self.error
        self.draft.valid = True
        memcpy(adr(profile), adr(self, "draft"), sizeof(MotionProfile))
        return ProfileError.NONE

    @prop
    def planned_distance(self) -> LREAL:
        """The distance the segments given so far travel (mm)."""
        return self.distance

    @method(PRIVATE)
    def accept(self) -> BOOL:
        """Count the step; FALSE when an earlier step already failed."""
        self.steps += 1
        return self.error == ProfileError.NONE

    @method(PRIVATE)
    def reject(self, error: ProfileError) -> IProfileBuilder:
        self.error = error
        self.error_step = self.steps
        return self

    @method(PRIVATE)
    def append(self, kind: SegmentKind, velocity: LREAL, duration: TIME) -> IProfileBuilder:
        if self.draft.count >= MAX_SEGMENTS:
            return self.reject(ProfileError.TOO_MANY_SEGMENTS)
        self.draft.count += 1
        self.draft.segments[self.draft.count].kind = kind
        self.draft.segments[self.draft.count].velocity = velocity
        self.draft.segments[self.draft.count].duration = duration
        self.distance += (self.velocity + velocity) / 2 * duration / 1000
        self.velocity = velocity
        return self


class IProfileRunner(Interface):
    """``INTERFACE I_ProfileRunner``: load a built profile, then run it with ``execute``."""

    @method
    def load(self, profile: MotionProfile) -> BOOL:
        raise NotImplementedError

    @prop
    def done(self) -> BOOL:
        raise NotImplementedError


class ProfileRunner(FunctionBlock, IProfileRunner):
    """``FUNCTION_BLOCK FB_ProfileRunner``: a rising ``execute`` runs the loaded profile, one TON per segment."""

    execute: BOOL = VAR_INPUT(False)
    busy: BOOL = VAR_OUTPUT(False)
    finished: BOOL = VAR_OUTPUT(False)
    error: ProfileError = VAR_OUTPUT(ProfileError.NONE)
    step: INT = VAR_OUTPUT(0)
    position: LREAL = VAR_OUTPUT(0.0)
    velocity: LREAL = VAR_OUTPUT(0.0)
    profile: MotionProfile = VAR()
    timers: ARRAY[TON] = VAR(bounds=(1, MAX_SEGMENTS))
    start: R_TRIG = VAR()
    entry_velocity: LREAL = VAR(0.0)
    last_et: TIME = VAR(0)

    @method
    def load(self, profile: MotionProfile) -> BOOL:
        """Copy a built profile; refused (FALSE, ``error``) when not valid or while busy."""
        if self.busy:
            self.error = ProfileError.BUSY
            return False
        if not profile.valid:
            self.error = ProfileError.NOT_BUILT
            return False
        self.profile = profile
        self.error = ProfileError.NONE
        return True

    @prop
    def done(self) -> BOOL:
        return self.finished

    def body(self) -> None:
        self.start(CLK=self.execute)
        if self.start.Q and not self.busy:
            if not self.profile.valid:
                self.error = ProfileError.NOT_BUILT
            else:
                self.busy, self.finished, self.step = True, False, 1
                self.entry_velocity, self.last_et = 0.0, 0
        if not self.busy:
            return
        segment = self.profile.segments[self.step]
        timer = self.timers[self.step]
        timer(IN=True, PT=segment.duration)
        goal = segment.velocity
        velocity = self.entry_velocity + (goal - self.entry_velocity) * timer.ET / segment.duration
        # Trapezoidal integration over the time the segment's TON measured since the last scan.
        self.position += (self.velocity + velocity) / 2 * (timer.ET - self.last_et) / 1000
        self.velocity = velocity
        self.last_et = timer.ET
        if timer.Q:
            timer(IN=False)
            self.entry_velocity, self.last_et = goal, 0
            if self.step == self.profile.count:
                self.busy, self.finished, self.step = False, True, 0
            else:
                self.step += 1
                self.timers[self.step](IN=True, PT=self.profile.segments[self.step].duration)


class FeedAxisMain(Program):
    """``PROGRAM FeedAxisMain``: the director; builds the index move and a jog move, runs the index."""

    builder: ProfileBuilder = VAR()
    runner: ProfileRunner = VAR()
    index_move: MotionProfile = VAR()
    jog_move: MotionProfile = VAR()
    index_result: ProfileError = VAR_OUTPUT(ProfileError.NONE)
    jog_result: ProfileError = VAR_OUTPUT(ProfileError.NONE)
    jog_step: INT = VAR_OUTPUT(0)
    first_scan: BOOL = VAR(True)

    def body(self) -> None:
        if self.first_scan:
            self.first_scan = False
            self.index_result = (
                self.builder.begin("index")
                .ramp(200.0, T("100ms"))
                .cruise(T("400ms"))
                .ramp(0.0, T("100ms"))
                .dwell(T("200ms"))
                .target(100.0)
                .build(self.index_move)
            )
            self.jog_result = (
                self.builder.begin("jog")
                .ramp(300.0, T("100ms"))
                .ramp(900.0, T("200ms"))
                .ramp(0.0, T("100ms"))
                .target(50.0)
                .build(self.jog_move)
            )
            self.jog_step = self.builder.error_step
            self.runner.load(self.index_move)
        self.runner(execute=self.index_result == ProfileError.NONE)


def main() -> None:
    """Build two profiles on the first scan, run the valid one and trace its segments.

    >>> main()
    jog:   VELOCITY_LIMIT at step 2
    index: NONE, 4 segments, 100.0 mm
    t=   0 ms  segment 1 RAMP     v=  0.0 mm/s  x=  0.0 mm
    t= 100 ms  segment 2 CRUISE   v=200.0 mm/s  x= 10.0 mm
    t= 500 ms  segment 3 RAMP     v=200.0 mm/s  x= 90.0 mm
    t= 600 ms  segment 4 DWELL    v=  0.0 mm/s  x=100.0 mm
    t= 800 ms  done               v=  0.0 mm/s  x=100.0 mm
    """
    axis = FeedAxisMain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), axis)
    runner = axis.runner
    last_step = -1
    while rt.time_ms <= 1000:
        cycle_start = rt.time_ms
        rt.run(cycles=1)
        if cycle_start == 0:
            print(f"jog:   {axis.jog_result.name} at step {axis.jog_step}")
            move = axis.index_move
            print(f"index: {axis.index_result.name}, {move.count} segments, {move.target:.1f} mm")
        if runner.step != last_step:
            last_step = runner.step
            what = f"segment {runner.step} {axis.index_move.segments[runner.step].kind.name:<8}" if runner.step else "done"
            print(f"t={cycle_start:4d} ms  {what:<17}  v={runner.velocity:5.1f} mm/s  x={runner.position:5.1f} mm")
        if runner.done:
            break


SHOWCASE = Showcase(
    use_when="motion profiles or recipes assembled at run time from HMI or product data, checked in one place",
    columns=(
        Column("jog build", lambda p: p.jog_result),
        Column("step", lambda p: p.runner.step),
        Column("v mm/s", lambda p: p.runner.velocity, ".1f", watch=False),
        Column("x mm", lambda p: p.runner.position, ".1f", watch=False),
        Column("busy", lambda p: p.runner.busy),
        Column("finished", lambda p: p.runner.finished),
    ),
    cycles=100,
    tour_cycles=90,
)
