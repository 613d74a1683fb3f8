"""Chain of Responsibility: analog signal conditioning and start permissives.

Intent
------

Pass a request along a chain of handlers; each handler does its part (or
answers) and decides whether the next one sees it. The sender knows only the
first handler.

The PLC problem
---------------

Pressure transmitter PT205 delivers 4-20 mA. Before the value is usable it
goes through a fixed set of steps: a NAMUR NE 43 range check (below 3.6 mA
is a wire break, above 21 mA a short circuit), a spike filter (a single-scan
jump is held back for a few scans), scaling to bar, and the high / low alarm
limits. Written as one FB, every plant that needs one more step (a square-root
extraction for a flow, a second filter) edits that FB. As a chain, each step
is a small FB derived from ``FB_SignalStage``: it does its work on the
``ST_AnalogSignal`` it is handed (value + quality + first failing reason)
and calls ``SUPER^.Handle(signal)``, which forwards to the next stage.
A stage that sees BAD quality leaves the value alone and passes it on, so the
last good value is held and the alarm stage knows why.

The second chain is the textbook form: machine start permissives, where the
first check that fails answers with its reason and the rest are not asked.
The HMI shows "start blocked: guard door open" instead of a bare FALSE.

Both chains refuse a link that would close a loop or make the chain longer
than ``MAX_CHAIN_LENGTH``: ``SetNext`` asks the candidate to walk its own
tail with a depth counter (a bounded recursion, no allocation) while the
linking stage is marked, and answers FALSE with the verdict in
``linkStatus`` (``LOOP``, ``TOO_LONG``, ``NULL_LINK``) instead of making a
link that would end in a stack overflow. A chain that grows at its tail
after its head was checked is stopped at run time: the stage that would
pass the signal on beyond ``MAX_CHAIN_LENGTH`` marks it BAD with status
``CHAIN_TOO_LONG``.

Roles
-----

- Link rule shared by both chains → ``IChainLink`` (``I_ChainLink``),
  ``ChainLink`` (``FB_ChainLink``, ABSTRACT)
- Handler interface (``set_next`` and the request) → ``ISignalStage``
  (``I_SignalStage``), ``IPermissive`` (``I_Permissive``)
- Base handler with the link and the forwarding → ``SignalStage``
  (``FB_SignalStage``, ABSTRACT), ``Permissive`` (``FB_Permissive``, ABSTRACT)
- Concrete handlers → ``RangeCheck``, ``SpikeFilter``, ``Scaling``,
  ``AlarmLimits`` (``FB_RangeCheck`` ...); ``GuardDoorClosed``,
  ``EStopReleased``, ``SignalHealthy`` (``FB_GuardDoorClosed`` ...)
- Request → ``AnalogSignal`` (``ST_AnalogSignal``)
- Client → ``AnalogInput`` (``FB_AnalogInput``), ``PressureMain``
  (``PRG_PressureMain``)

IEC 61131-3 mapping
-------------------

::

    TYPE ST_AnalogSignal : STRUCT
        rawMa, currentMa, value : REAL; quality : E_Quality;
        status : E_SignalStatus; highAlarm, lowAlarm : BOOL;
        hops : USINT;   // stages entered, checked against MAX_CHAIN_LENGTH
    END_STRUCT END_TYPE

    INTERFACE I_ChainLink
        METHOD CheckChain : E_ChainCheck   VAR_INPUT depth : INT; END_VAR
    INTERFACE I_SignalStage EXTENDS I_ChainLink
        METHOD SetNext : BOOL   VAR_INPUT stage : I_SignalStage; END_VAR
        METHOD Handle   VAR_IN_OUT signal : ST_AnalogSignal; END_VAR

    FUNCTION_BLOCK ABSTRACT FB_ChainLink IMPLEMENTS I_ChainLink
    VAR_OUTPUT linkStatus : E_ChainCheck; END_VAR   // the verdict on the last SetNext
    VAR marked : BOOL; END_VAR
        METHOD PROTECTED ABSTRACT NextLink : I_ChainLink
        METHOD PROTECTED FINAL CheckLink : E_ChainCheck
        VAR_INPUT candidate : I_ChainLink; END_VAR

    FUNCTION_BLOCK ABSTRACT FB_SignalStage EXTENDS FB_ChainLink
        IMPLEMENTS I_SignalStage
    VAR nextStage : I_SignalStage; END_VAR
        METHOD FINAL SetNext : BOOL   VAR_INPUT stage : I_SignalStage; END_VAR
        METHOD Handle   // IF nextStage <> 0 THEN nextStage.Handle(signal); END_IF

    FUNCTION_BLOCK FB_SpikeFilter EXTENDS FB_SignalStage
    VAR_INPUT maxStepMa : REAL := 1.0; maxHeldScans : INT := 2; END_VAR
        METHOD Handle   // filter, then SUPER^.Handle(signal);

    FUNCTION_BLOCK FB_AnalogInput
    VAR_INPUT rawMa : REAL; END_VAR
    VAR_OUTPUT signal : ST_AnalogSignal; chainStatus : E_ChainCheck; END_VAR
    VAR first : I_SignalStage; END_VAR
        METHOD FB_init : BOOL   VAR_INPUT chain : I_SignalStage; END_VAR
        PROPERTY Chain : I_SignalStage

When not to use it on a PLC
---------------------------

When the steps are fixed for every instance and never reordered, a single
FB that calls four private methods in a row is shorter, faster and just as
readable online; a chain earns its keep when stages are chosen per channel
or added by plant engineering without editing the base. Each stage is a
nested call, so a long chain costs stack and scan time: keep it short and
bounded, and never let a stage link itself back.

References
----------

- Gamma, Helm, Johnson, Vlissides: *Design Patterns: Elements of Reusable
  Object-Oriented Software*, Addison-Wesley 1994, "Chain of Responsibility".
- IEC 61131-3:2013, 3rd edition: function block inheritance (EXTENDS,
  SUPER, ABSTRACT, FINAL), methods, interfaces (EXTENDS of interfaces),
  structured and enumerated data types.
- Beckhoff InfoSys, TwinCAT 3 PLC: "Extending a function block", "SUPER",
  "ABSTRACT concept", "FINAL", "Methods FB_init, FB_reinit and FB_exit".
- CODESYS Online Help: "Object: Method", "Extension of a function block",
  "Implementing interfaces".
- NAMUR NE 43, "Standardization of the signal level for the failure
  information of digital transmitters".
"""

from __future__ import annotations

from iecoop import (
    ABSTRACT,
    BOOL,
    FINAL,
    INT,
    PROTECTED,
    REAL,
    STRING,
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
from iecoop.runtime import Runtime, Task
from patterns.showcase.entry import Column, Showcase, steps

__all__ = [
    "MAX_CHAIN_LENGTH",
    "AlarmLimits",
    "AnalogInput",
    "AnalogSignal",
    "ChainCheck",
    "ChainLink",
    "EStopReleased",
    "GuardDoorClosed",
    "IChainLink",
    "IPermissive",
    "ISignalStage",
    "Permissive",
    "PressureMain",
    "Quality",
    "RangeCheck",
    "Scaling",
    "SignalHealthy",
    "SignalStage",
    "SignalStatus",
    "SpikeFilter",
    "main",
]

#: ``MAX_CHAIN_LENGTH``: a GVL's VAR_GLOBAL CONSTANT bounding every chain.
MAX_CHAIN_LENGTH = 6


class Quality(IecEnum, base=USINT):
    """``TYPE E_Quality : (GOOD := 0, UNCERTAIN := 1, BAD := 2) USINT; END_TYPE``; higher is worse."""

    GOOD = 0
    UNCERTAIN = 1
    BAD = 2


class SignalStatus(IecEnum, base=USINT):
    """``TYPE E_SignalStatus``: the first reason the quality is not GOOD."""

    OK = 0
    WIRE_BREAK = 1
    SHORT_CIRCUIT = 2
    UNDER_RANGE = 3
    OVER_RANGE = 4
    SPIKE_HELD = 5
    CHAIN_TOO_LONG = 6


class ChainCheck(IecEnum, base=USINT):
    """``TYPE E_ChainCheck : (OK, LOOP, TOO_LONG, NULL_LINK) USINT; END_TYPE``: the verdict on a link."""

    OK = 0
    LOOP = 1
    TOO_LONG = 2
    NULL_LINK = 3


class AnalogSignal(Struct):
    """``TYPE ST_AnalogSignal``: the request handed down the conditioning chain."""

    raw_ma: REAL = 0.0
    current_ma: REAL = 0.0
    value: REAL = 0.0
    quality: Quality = Quality.GOOD
    status: SignalStatus = SignalStatus.OK
    high_alarm: BOOL = False
    low_alarm: BOOL = False
    hops: USINT = 0


class IChainLink(Interface):
    """``INTERFACE I_ChainLink``: lets a stage check the tail it is about to be linked to."""

    @method
    def check_chain(self, depth: INT) -> ChainCheck:
        raise NotImplementedError


class ISignalStage(IChainLink):
    """``INTERFACE I_SignalStage EXTENDS I_ChainLink``: one conditioning step."""

    @method
    def set_next(self, stage: ISignalStage) -> BOOL:
        raise NotImplementedError

    @method
    def handle(self, signal: AnalogSignal) -> None: ...


class IPermissive(IChainLink):
    """``INTERFACE I_Permissive EXTENDS I_ChainLink``: one start condition."""

    @method
    def set_next(self, check: IPermissive) -> BOOL:
        raise NotImplementedError

    @method
    def first_failing(self) -> STRING:
        raise NotImplementedError


class ChainLink(FunctionBlock, IChainLink, abstract=True):
    """``FUNCTION_BLOCK ABSTRACT FB_ChainLink IMPLEMENTS I_ChainLink``: the no-loop, bounded-length rule."""

    link_status: ChainCheck = VAR_OUTPUT(ChainCheck.OK)
    marked: BOOL = VAR(False)

    @method(PROTECTED | ABSTRACT)
    def next_link(self) -> IChainLink:
        """The next link as seen by the check (each chain keeps its own typed reference)."""
        raise NotImplementedError

    @method(FINAL)
    def check_chain(self, depth: INT) -> ChainCheck:
        """Walk the tail from here; ``depth`` is this link's position counted from the linking stage."""
        if self.marked:
            return ChainCheck.LOOP
        if depth > MAX_CHAIN_LENGTH:
            return ChainCheck.TOO_LONG
        following = self.next_link()
        if not following:
            return ChainCheck.OK
        return following.check_chain(depth + 1)

    @method(PROTECTED | FINAL)
    def check_link(self, candidate: IChainLink) -> ChainCheck:
        """Whether linking ``candidate`` after this stage keeps the chain loop-free and short; kept in ``link_status``."""
        if not candidate:
            self.link_status = ChainCheck.NULL_LINK
        else:
            self.marked = True
            self.link_status = candidate.check_chain(2)
            self.marked = False
        return self.link_status


class SignalStage(ChainLink, ISignalStage, abstract=True):
    """``FUNCTION_BLOCK ABSTRACT FB_SignalStage EXTENDS FB_ChainLink IMPLEMENTS I_SignalStage``.

    ``handle`` forwards to the next stage; a derived stage does its work and
    then calls ``super().handle(signal)`` (``SUPER^.Handle(signal)``).
    """

    next_stage: ISignalStage = VAR()

    @method(FINAL)
    def set_next(self, stage: ISignalStage) -> BOOL:
        """Link ``stage`` after this one; FALSE, and the link stays as it was, for a refused one (see ``link_status``)."""
        if self.check_link(stage) != ChainCheck.OK:
            return False
        self.next_stage = stage
        return True

    @method(PROTECTED)
    def next_link(self) -> IChainLink:
        return self.next_stage

    @method
    def handle(self, signal: AnalogSignal) -> None:
        if not self.next_stage:
            return
        if signal.hops >= MAX_CHAIN_LENGTH:
            # A chain grown at its tail after its head was checked: stop before the stack does.
            self.degrade(signal, Quality.BAD, SignalStatus.CHAIN_TOO_LONG)
            return
        signal.hops += 1
        self.next_stage.handle(signal)

    @method(PROTECTED | FINAL)
    def degrade(self, signal: AnalogSignal, quality: Quality, status: SignalStatus) -> None:
        """Lower the quality (never raise it) and keep the first failing reason."""
        if quality > signal.quality:
            signal.quality = quality
        if signal.status == SignalStatus.OK:
            signal.status = status


class RangeCheck(SignalStage):
    """``FUNCTION_BLOCK FB_RangeCheck EXTENDS FB_SignalStage``: NAMUR NE 43 limits on the loop current."""

    wire_break_ma: REAL = VAR_INPUT(3.6)
    short_circuit_ma: REAL = VAR_INPUT(21.0)
    under_range_ma: REAL = VAR_INPUT(3.8)
    over_range_ma: REAL = VAR_INPUT(20.5)

    @method
    def handle(self, signal: AnalogSignal) -> None:
        ma = signal.current_ma
        if ma < self.wire_break_ma:
            self.degrade(signal, Quality.BAD, SignalStatus.WIRE_BREAK)
        elif ma > self.short_circuit_ma:
            self.degrade(signal, Quality.BAD, SignalStatus.SHORT_CIRCUIT)
        elif ma < self.under_range_ma:
            self.degrade(signal, Quality.UNCERTAIN, SignalStatus.UNDER_RANGE)
        elif ma > self.over_range_ma:
            self.degrade(signal, Quality.UNCERTAIN, SignalStatus.OVER_RANGE)
        super().handle(signal)


class SpikeFilter(SignalStage):
    """``FUNCTION_BLOCK FB_SpikeFilter EXTENDS FB_SignalStage``.

    A jump of more than ``max_step_ma`` from the last accepted current is held
    back for up to ``max_held_scans`` scans (the previous current is passed on,
    quality UNCERTAIN); a jump that persists longer is a real step and is taken.
    """

    max_step_ma: REAL = VAR_INPUT(1.0)
    max_held_scans: INT = VAR_INPUT(2)
    last_ma: REAL = VAR(0.0)
    primed: BOOL = VAR(False)
    held: INT = VAR(0)

    @method
    def handle(self, signal: AnalogSignal) -> None:
        if signal.quality == Quality.BAD:
            self.primed = False
        elif not self.primed or abs(signal.current_ma - self.last_ma) <= self.max_step_ma:
            self.accept(signal.current_ma)
        elif self.held < self.max_held_scans:
            self.held += 1
            signal.current_ma = self.last_ma
            self.degrade(signal, Quality.UNCERTAIN, SignalStatus.SPIKE_HELD)
        else:
            self.accept(signal.current_ma)
        super().handle(signal)

    @method(PROTECTED)
    def accept(self, ma: REAL) -> None:
        self.last_ma, self.primed, self.held = ma, True, 0


class Scaling(SignalStage):
    """``FUNCTION_BLOCK FB_Scaling EXTENDS FB_SignalStage``: 4-20 mA to ``eu_low``..``eu_high``.

    With BAD quality the value is left as it was: the last good value is held.
    """

    eu_low: REAL = VAR_INPUT(0.0)
    eu_high: REAL = VAR_INPUT(16.0)

    @method
    def handle(self, signal: AnalogSignal) -> None:
        if signal.quality != Quality.BAD:
            span = self.eu_high - self.eu_low
            signal.value = self.eu_low + (signal.current_ma - 4.0) * span / 16.0
        super().handle(signal)


class AlarmLimits(SignalStage):
    """``FUNCTION_BLOCK FB_AlarmLimits EXTENDS FB_SignalStage``: high / low limits with hysteresis.

    With BAD quality both alarms keep their state: a dead sensor neither raises
    nor clears a process alarm (the quality itself is the sensor alarm).
    """

    high_limit: REAL = VAR_INPUT(12.0)
    low_limit: REAL = VAR_INPUT(2.0)
    hysteresis: REAL = VAR_INPUT(0.5)
    high: BOOL = VAR(False)
    low: BOOL = VAR(False)

    @method
    def handle(self, signal: AnalogSignal) -> None:
        if signal.quality != Quality.BAD:
            value = signal.value
            if value > self.high_limit:
                self.high = True
            elif value < self.high_limit - self.hysteresis:
                self.high = False
            if value < self.low_limit:
                self.low = True
            elif value > self.low_limit + self.hysteresis:
                self.low = False
        signal.high_alarm, signal.low_alarm = self.high, self.low
        super().handle(signal)


class AnalogInput(FunctionBlock):
    """``FUNCTION_BLOCK FB_AnalogInput``: the client; it knows only the first stage.

    The chain comes through FB_init (``AnalogInput(chain=head)``) or, for a
    nested instance wired to its siblings, through the ``chain`` property,
    which checks the whole chain before taking it: a chain longer than
    ``MAX_CHAIN_LENGTH`` is refused, the old one kept, and ``chain_status``
    says why.
    """

    raw_ma: REAL = VAR_INPUT(0.0)
    signal: AnalogSignal = VAR_OUTPUT()
    chain_status: ChainCheck = VAR_OUTPUT(ChainCheck.OK)
    first: ISignalStage = VAR()

    def fb_init(self, init_retains: bool, in_copy_code: bool, chain: ISignalStage | None = None) -> None:
        if chain is not None:
            self.chain = chain

    @prop
    def chain(self) -> ISignalStage:
        return self.first

    @chain.setter
    def chain(self, head: ISignalStage) -> None:
        if head:
            self.chain_status = head.check_chain(1)
            if self.chain_status != ChainCheck.OK:
                return
        else:
            self.chain_status = ChainCheck.NULL_LINK
        self.first = head

    def body(self) -> None:
        signal = self.signal
        signal.raw_ma = signal.current_ma = self.raw_ma
        signal.quality, signal.status, signal.hops = Quality.GOOD, SignalStatus.OK, 1
        self.first.handle(signal)


class Permissive(ChainLink, IPermissive, abstract=True):
    """``FUNCTION_BLOCK ABSTRACT FB_Permissive EXTENDS FB_ChainLink IMPLEMENTS I_Permissive``.

    ``first_failing`` returns '' when this and every later permissive is met;
    a derived check returns its own reason or ``SUPER^.FirstFailing()``.
    """

    next_check: IPermissive = VAR()

    @method(FINAL)
    def set_next(self, check: IPermissive) -> BOOL:
        """Link ``check`` after this one; FALSE, and the link stays as it was, for a refused one (see ``link_status``)."""
        if self.check_link(check) != ChainCheck.OK:
            return False
        self.next_check = check
        return True

    @method(PROTECTED)
    def next_link(self) -> IChainLink:
        return self.next_check

    @method
    def first_failing(self) -> STRING:
        if self.next_check:
            return self.next_check.first_failing()
        return ""


class GuardDoorClosed(Permissive):
    """``FUNCTION_BLOCK FB_GuardDoorClosed EXTENDS FB_Permissive``."""

    closed: BOOL = VAR_INPUT(False)

    @method
    def first_failing(self) -> STRING:
        if not self.closed:
            return "guard door open"
        return super().first_failing()


class EStopReleased(Permissive):
    """``FUNCTION_BLOCK FB_EStopReleased EXTENDS FB_Permissive``."""

    released: BOOL = VAR_INPUT(False)

    @method
    def first_failing(self) -> STRING:
        if not self.released:
            return "emergency stop pressed"
        return super().first_failing()


class SignalHealthy(Permissive):
    """``FUNCTION_BLOCK FB_SignalHealthy EXTENDS FB_Permissive``: the conditioned signal is usable."""

    quality: Quality = VAR_INPUT(Quality.BAD)
    high_alarm: BOOL = VAR_INPUT(False)

    @method
    def first_failing(self) -> STRING:
        if self.quality == Quality.BAD:
            return "PT205 signal BAD"
        if self.high_alarm:
            return "PT205 pressure high"
        return super().first_failing()


class PressureMain(Program):
    """``PROGRAM PRG_PressureMain``: PT205 conditioning and the start permissives.

    The loop current is simulated from the scan count (a ramp with one
    spike, a wire break and a pressure excursion) so the run is repeatable.
    """

    pt205: AnalogInput = VAR()
    range_check: RangeCheck = VAR()
    spike_filter: SpikeFilter = VAR()
    scaling: Scaling = VAR()
    limits: AlarmLimits = VAR()
    guard_door: GuardDoorClosed = VAR()
    estop: EStopReleased = VAR()
    signal_ok: SignalHealthy = VAR()
    door_closed: BOOL = VAR_INPUT(True)
    estop_released: BOOL = VAR_INPUT(True)
    start_permitted: BOOL = VAR_OUTPUT(False)
    blocked_by: STRING = VAR_OUTPUT("", length=40)
    loop_ma: REAL = VAR(8.0)
    scan: INT = VAR(0)

    def fb_init(self, init_retains: bool, in_copy_code: bool) -> None:
        self.range_check.set_next(self.spike_filter)
        self.spike_filter.set_next(self.scaling)
        self.scaling.set_next(self.limits)
        self.pt205.chain = self.range_check
        self.guard_door.set_next(self.estop)
        self.estop.set_next(self.signal_ok)

    def body(self) -> None:
        self.scan += 1
        self.simulate()
        self.pt205(raw_ma=self.loop_ma)
        self.guard_door(closed=self.door_closed)
        self.estop(released=self.estop_released)
        self.signal_ok(quality=self.pt205.signal.quality, high_alarm=self.pt205.signal.high_alarm)
        self.blocked_by = self.guard_door.first_failing()
        self.start_permitted = self.blocked_by == ""

    @method(PROTECTED)
    def simulate(self) -> None:
        scan = self.scan
        if scan == 10:
            self.loop_ma = 16.0      # one-scan spike from a contactor switching nearby
        elif scan == 11:
            self.loop_ma = 8.0
        elif 20 <= scan < 25:
            self.loop_ma = 2.0       # terminal loose: wire break
        elif scan == 25:
            self.loop_ma = 8.0
        elif 30 <= scan < 50:
            self.loop_ma += 0.5      # pressure rising to 18 mA = 14 bar
        elif scan >= 50 and self.loop_ma > 8.0:
            self.loop_ma -= 0.5


def main() -> None:
    """Run PT205 for 1 s of PLC time and print each change of quality, alarm or permissive.

    >>> main()
    t=   0 ms   8.00 mA   4.00 bar  GOOD      OK         alarm -    start: permitted
    t=  90 ms  16.00 mA   4.00 bar  UNCERTAIN SPIKE_HELD alarm -    start: permitted
    t= 100 ms   8.00 mA   4.00 bar  GOOD      OK         alarm -    start: permitted
    t= 190 ms   2.00 mA   4.00 bar  BAD       WIRE_BREAK alarm -    start: blocked, PT205 signal BAD
    t= 240 ms   8.00 mA   4.00 bar  GOOD      OK         alarm -    start: permitted
    t= 450 ms  16.50 mA  12.50 bar  GOOD      OK         alarm HIGH start: blocked, PT205 pressure high
    t= 540 ms  15.00 mA  11.00 bar  GOOD      OK         alarm -    start: permitted
    t= 750 ms   8.00 mA   4.00 bar  GOOD      OK         alarm -    start: blocked, guard door open
    t= 850 ms   8.00 mA   4.00 bar  GOOD      OK         alarm -    start: blocked, emergency stop pressed
    t= 900 ms   8.00 mA   4.00 bar  GOOD      OK         alarm -    start: permitted
    """
    program = PressureMain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    shown = ""
    for _ in range(100):
        now = rt.time_ms
        program.door_closed = not 750 <= now < 850        # the operator opens the guard door
        program.estop_released = not 800 <= now < 900     # ... and presses the E-stop meanwhile
        rt.run(cycles=1)
        signal = program.pt205.signal
        alarm = "HIGH" if signal.high_alarm else ("LOW" if signal.low_alarm else "-")
        state = f"{signal.quality.name:9} {signal.status.name:10} alarm {alarm:4} "
        state += "start: " + ("permitted" if program.start_permitted else f"blocked, {program.blocked_by}")
        if state != shown:
            shown = state
            print(f"t={now:4d} ms  {signal.raw_ma:5.2f} mA  {signal.value:5.2f} bar  {state}")


SHOWCASE = Showcase(
    use_when="stages (signal conditioning, permissives) are chosen per channel or added without editing the base",
    columns=(
        Column("mA", lambda p: p.pt205.signal.raw_ma, ".2f", watch=False),
        Column("bar", lambda p: p.pt205.signal.value, ".2f", watch=False),
        Column("quality", lambda p: p.pt205.signal.quality),
        Column("status", lambda p: p.pt205.signal.status),
        Column("high", lambda p: p.pt205.signal.high_alarm),
        Column("blocked by", lambda p: p.blocked_by or "- (start permitted)"),
    ),
    script=steps((76, "door_closed", False), (81, "estop_released", False), (86, "door_closed", True),
                 (91, "estop_released", True)),
    cycles=100,
    tour_cycles=100,
    expected=(
        ("SPIKE_HELD, WIRE_BREAK", "the simulated transmitter sends a spike and a broken-wire current"),
        ("blocked by", "the guard door opens in cycle 76 and the e-stop is pressed in cycle 81"),
    ),
)
