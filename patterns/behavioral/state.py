"""State: the PackML unit state machine, one function block per state.

Intent
------

Let an object change its behaviour when its internal state changes: each
state is an object of its own that answers the events for that state, and
the context delegates to whichever state object is current. The object
appears to change its class.

The PLC problem
---------------

A packaging machine (a cartoner, a case packer, a labeller) is commanded by
the line controller and the HMI with the PackML commands Reset, Start, Stop,
Hold, Unhold, Suspend, Unsuspend, Abort and Clear, and it reports one of the
17 states of ISA-TR88.00.02. Whether a command is accepted depends on the
state (Start only from Idle, Unhold only from Held, Clear only from Aborted);
the *acting* states (the "-ing" states: Resetting, Starting, Completing,
Holding, ...) do their work and leave by themselves when it is done (the
"state complete", SC). The usual implementation is one CASE over the state
with a nested CASE over the command: it works, but the knowledge of one state
is scattered over the whole block, and a state's entry action, timing and
allowed commands are hard to review against the standard's diagram.

With State each PackML state is a small function block implementing
``I_PackMLState``. It knows which commands it accepts and where they lead;
an acting state completes on its TON. Abort and Stop, which the standard
allows from whole groups of states (superstates), are inherited from two
abstract bases. The machine holds the 17 instances, an ``ARRAY[1..17] OF
I_PackMLState`` indexed by the state number, and delegates to the current
one; a command no state accepts is refused, counted and reported, and the
state does not change. The allowed transitions are also given as data,
``TRANSITIONS``, from which the state diagram is drawn and against which the
tests check the function blocks. The optional Hold transitions from the
Suspend states (dashed in the 2015 diagram) are not part of this unit.

Roles
-----

- State → ``IPackMLState`` (``I_PackMLState``); the abstract bases
  ``PackMLStateBase`` (``FB_PackMLStateBase``, refuses everything),
  ``AbortableState`` (``FB_AbortableState``, accepts Abort) and
  ``StoppableState`` (``FB_StoppableState``, accepts Stop as well)
- Concrete states → ``Stopped`` (``FB_Stopped``), ``Resetting``
  (``FB_Resetting``), ``Idle``, ``Starting``, ``Execute``, ``Completing``,
  ``Complete``, ``Holding``, ``Held``, ``Unholding``, ``Suspending``,
  ``Suspended``, ``Unsuspending``, ``Stopping``, ``Aborting``, ``Aborted``,
  ``Clearing`` (each ``FB_<name>``)
- Context → ``PackMLMachine`` (``FB_PackMLMachine``), seen by the states as
  ``IPackMLContext`` (``I_PackMLContext``) and by the line as
  ``IPackMLUnit`` (``I_PackMLUnit``)
- State and command numbers → ``PackMLState`` (``E_PackMLState``) and
  ``PackMLCommand`` (``E_PackMLCommand``), the PackTags values
- Client → ``PackagingLine`` (``PRG_PackagingLine``)

IEC 61131-3 mapping
-------------------

::

    TYPE E_PackMLState : (CLEARING := 1, STOPPED := 2, ..., COMPLETE := 17) DINT; END_TYPE

    INTERFACE I_PackMLContext
        METHOD ChangeState     // VAR_INPUT target : E_PackMLState;

    INTERFACE I_PackMLState
        PROPERTY State : E_PackMLState           // Get
        METHOD Enter           // VAR_INPUT fromState : E_PackMLState;
        METHOD Cycle           // once per scan while current
        METHOD Command : BOOL  // VAR_INPUT cmd : E_PackMLCommand;

    FUNCTION_BLOCK ABSTRACT FB_PackMLStateBase IMPLEMENTS I_PackMLState
        VAR_INPUT duration : TIME; END_VAR      // acting states: time to SC
        VAR context : I_PackMLContext; timer : TON; END_VAR
        METHOD FB_init : BOOL  // VAR_INPUT context : I_PackMLContext;
        METHOD Attach          // the wiring step used by the machine
        METHOD PROTECTED Go : BOOL
        METHOD PROTECTED CompleteTo
    FUNCTION_BLOCK ABSTRACT FB_AbortableState EXTENDS FB_PackMLStateBase
    FUNCTION_BLOCK ABSTRACT FB_StoppableState EXTENDS FB_AbortableState
    FUNCTION_BLOCK FB_Resetting EXTENDS FB_StoppableState   // and 16 more

    FUNCTION_BLOCK FB_PackMLMachine IMPLEMENTS I_PackMLUnit, I_PackMLContext
        VAR stopped : FB_Stopped; resetting : FB_Resetting; (* ... *)
            states : ARRAY[E_PackMLState.CLEARING..E_PackMLState.COMPLETE] OF I_PackMLState;
            current : E_PackMLState := E_PackMLState.STOPPED; END_VAR
        VAR_OUTPUT refused : UDINT; lastRefused : E_PackMLCommand; END_VAR
        PROPERTY State : E_PackMLState          // Get only
        METHOD Command : BOOL

When not to use it on a PLC
---------------------------

For a sequence of four steps with one way through, a CASE on an enum reads
better online than seventeen blocks, and the maintenance electrician can
follow it in the editor. State pays off when the states have real behaviour
of their own (entry actions, timing, per-state command sets) and the machine
is reviewed against a diagram, as PackML is. Keep the transitions in one
place you can print, here ``TRANSITIONS``: with the behaviour spread over
blocks, a table checked by a test is what tells you the diagram and the code
still agree.

References
----------

- E. Gamma, R. Helm, R. Johnson, J. Vlissides, *Design Patterns: Elements of
  Reusable Object-Oriented Software*, Addison-Wesley 1994, "State".
- ANSI/ISA-TR88.00.02-2015, *Machine and Unit States: An Implementation
  Example of ANSI/ISA-88.00.01* (PackML), the base state model and PackTags.
- OMAC, *PackML Unit/Machine Implementation Guide*, Part 1: PackML
  Interface State Manager.
- IEC 61131-3:2013, *Programmable controllers - Part 3: Programming
  languages*, object-oriented function blocks (EXTENDS, IMPLEMENTS,
  ABSTRACT), interfaces, properties; the standard timer TON.
- Beckhoff InfoSys, TwinCAT 3 PLC: "Interface", "Property", "FB_init,
  FB_reinit, FB_exit", "Enumerations".
- CODESYS Online Help: "Object: Interface", "Method FB_Init, FB_Reinit,
  FB_Exit", "Data Type: Enumeration".
"""

from __future__ import annotations

from iecoop import (
    ABSTRACT,
    ARRAY,
    BOOL,
    DINT,
    PROTECTED,
    TIME,
    UDINT,
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
from iecoop.runtime import Runtime, Task
from iecoop.stdlib import TON
from patterns.showcase.entry import Column, Showcase

__all__ = [
    "INITIAL_STATE",
    "TRANSITIONS",
    "AbortableState",
    "Aborted",
    "Aborting",
    "Clearing",
    "Complete",
    "Completing",
    "Execute",
    "Held",
    "Holding",
    "IPackMLContext",
    "IPackMLState",
    "IPackMLUnit",
    "Idle",
    "PackMLCommand",
    "PackMLMachine",
    "PackMLState",
    "PackMLStateBase",
    "PackagingLine",
    "Resetting",
    "Starting",
    "StoppableState",
    "Stopped",
    "Stopping",
    "Suspended",
    "Suspending",
    "Unholding",
    "Unsuspending",
    "main",
]


# ---------------------------------------------------------------------------
# The transition table: what the standard allows, as data
# ---------------------------------------------------------------------------

#: The state a PackML unit starts in.
INITIAL_STATE: str = "Stopped"

_ALL_STATES = (
    "Stopped", "Resetting", "Idle", "Starting", "Execute", "Completing", "Complete", "Holding", "Held",
    "Unholding", "Suspending", "Suspended", "Unsuspending", "Stopping", "Aborting", "Aborted", "Clearing",
)
#: The states Stop is accepted from: the Stopped superstate without Stopped, Stopping and the Abort branch.
_STOPPABLE = (
    "Resetting", "Idle", "Starting", "Execute", "Completing", "Complete", "Holding", "Held", "Unholding",
    "Suspending", "Suspended", "Unsuspending",
)

#: (from state, command or "SC", to state): the PackML base state model of ISA-TR88.00.02.
TRANSITIONS: tuple[tuple[str, str, str], ...] = (
    ("Stopped", "Reset", "Resetting"),
    ("Resetting", "SC", "Idle"),
    ("Idle", "Start", "Starting"),
    ("Starting", "SC", "Execute"),
    ("Execute", "SC", "Completing"),
    ("Completing", "SC", "Complete"),
    ("Complete", "Reset", "Resetting"),
    ("Execute", "Hold", "Holding"),
    ("Holding", "SC", "Held"),
    ("Held", "Unhold", "Unholding"),
    ("Unholding", "SC", "Execute"),
    ("Execute", "Suspend", "Suspending"),
    ("Suspending", "SC", "Suspended"),
    ("Suspended", "Unsuspend", "Unsuspending"),
    ("Unsuspending", "SC", "Execute"),
    ("Stopping", "SC", "Stopped"),
    ("Aborting", "SC", "Aborted"),
    ("Aborted", "Clear", "Clearing"),
    ("Clearing", "SC", "Stopped"),
    *((state, "Stop", "Stopping") for state in _STOPPABLE),
    *((state, "Abort", "Aborting") for state in _ALL_STATES if state not in ("Aborting", "Aborted")),
)


# ---------------------------------------------------------------------------
# Enumerations (PackTags numbers)
# ---------------------------------------------------------------------------


class PackMLState(IecEnum, base=DINT):
    """``E_PackMLState``: the state numbers of PackTags ``StateCurrent``."""

    CLEARING = 1
    STOPPED = 2
    STARTING = 3
    IDLE = 4
    SUSPENDED = 5
    EXECUTE = 6
    STOPPING = 7
    ABORTING = 8
    ABORTED = 9
    HOLDING = 10
    HELD = 11
    UNHOLDING = 12
    SUSPENDING = 13
    UNSUSPENDING = 14
    RESETTING = 15
    COMPLETING = 16
    COMPLETE = 17


class PackMLCommand(IecEnum, base=DINT):
    """``E_PackMLCommand``: the command numbers of PackTags ``CntrlCmd`` (0: no command)."""

    NONE = 0
    RESET = 1
    START = 2
    STOP = 3
    HOLD = 4
    UNHOLD = 5
    SUSPEND = 6
    UNSUSPEND = 7
    ABORT = 8
    CLEAR = 9


# ---------------------------------------------------------------------------
# Interfaces
# ---------------------------------------------------------------------------


class IPackMLContext(Interface):
    """``INTERFACE I_PackMLContext``: what a state sees of its machine."""

    @method
    def change_state(self, target: PackMLState) -> None: ...


class IPackMLState(Interface):
    """``INTERFACE I_PackMLState``: one state of the unit.

    ``enter`` is the entry action, ``cycle`` runs every scan while the state
    is current (an acting state completes there), ``command`` returns TRUE
    when the state accepts the command and has made the transition.
    """

    @prop
    def state(self) -> PackMLState:
        raise NotImplementedError

    @method
    def enter(self, from_state: PackMLState) -> None: ...

    @method
    def cycle(self) -> None: ...

    @method
    def command(self, cmd: PackMLCommand) -> BOOL:
        raise NotImplementedError


class IPackMLUnit(Interface):
    """``INTERFACE I_PackMLUnit``: what the line controller and the HMI see of a unit."""

    @prop
    def state(self) -> PackMLState:
        raise NotImplementedError

    @method
    def command(self, cmd: PackMLCommand) -> BOOL:
        raise NotImplementedError


# ---------------------------------------------------------------------------
# The state blocks
# ---------------------------------------------------------------------------


class PackMLStateBase(FunctionBlock, IPackMLState, abstract=True):
    """``FUNCTION_BLOCK ABSTRACT FB_PackMLStateBase IMPLEMENTS I_PackMLState``.

    Refuses every command. Holds the back-reference to the machine, given to
    FB_init (``Stopped(context=machine)``) or by the wiring step ``attach``
    (what the machine does for its nested states), and the TON an acting
    state completes on: ``complete_to(target)`` changes to ``target`` once
    ``duration`` has passed since the state was entered.
    """

    duration: TIME = VAR_INPUT(T("0ms"))
    context: IPackMLContext = VAR()
    timer: TON = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, context: IPackMLContext | None = None) -> BOOL:
        if context is not None:
            self.context = context
        return True

    @method
    def attach(self, context: IPackMLContext) -> None:
        """The wiring step: give the state its machine."""
        self.context = context

    @prop
    @method(ABSTRACT)
    def state(self) -> PackMLState:
        raise NotImplementedError

    @method
    def enter(self, from_state: PackMLState) -> None:
        # Restart the TON: the time of an acting state counts from the scan it was entered in.
        self.timer(IN=False, PT=self.duration)
        self.timer(IN=True)

    @method
    def cycle(self) -> None:
        """A wait state does nothing until a command arrives."""

    @method
    def command(self, cmd: PackMLCommand) -> BOOL:
        return False

    @method(PROTECTED)
    def go(self, target: PackMLState) -> BOOL:
        self.context.change_state(target)
        return True

    @method(PROTECTED)
    def complete_to(self, target: PackMLState) -> None:
        """The acting state's SC: ``target`` once ``duration`` has passed in this state."""
        self.timer(IN=True, PT=self.duration)
        if self.timer.Q:
            self.go(target)

    @prop
    def elapsed(self) -> TIME:
        """Time spent in an acting state so far (the TON's ET)."""
        return self.timer.ET


class AbortableState(PackMLStateBase, abstract=True):
    """``FUNCTION_BLOCK ABSTRACT FB_AbortableState EXTENDS FB_PackMLStateBase``: Abort is accepted.

    Every state but Aborting and Aborted derives from it.
    """

    @method
    def command(self, cmd: PackMLCommand) -> BOOL:
        if cmd == PackMLCommand.ABORT:
            return self.go(PackMLState.ABORTING)
        return super().command(cmd)


class StoppableState(AbortableState, abstract=True):
    """``FUNCTION_BLOCK ABSTRACT FB_StoppableState EXTENDS FB_AbortableState``: Stop is accepted too.

    The Stopped superstate without Stopped, Stopping and Clearing.
    """

    @method
    def command(self, cmd: PackMLCommand) -> BOOL:
        if cmd == PackMLCommand.STOP:
            return self.go(PackMLState.STOPPING)
        return super().command(cmd)


class Stopped(AbortableState):
    """``FUNCTION_BLOCK FB_Stopped EXTENDS FB_AbortableState``: power on, waiting for Reset."""

    @prop
    def state(self) -> PackMLState:
        return PackMLState.STOPPED

    @method
    def command(self, cmd: PackMLCommand) -> BOOL:
        if cmd == PackMLCommand.RESET:
            return self.go(PackMLState.RESETTING)
        return super().command(cmd)


class Resetting(StoppableState):
    """``FUNCTION_BLOCK FB_Resetting EXTENDS FB_StoppableState``: acting, SC to Idle."""

    @prop
    def state(self) -> PackMLState:
        return PackMLState.RESETTING

    @method
    def cycle(self) -> None:
        self.complete_to(PackMLState.IDLE)


class Idle(StoppableState):
    """``FUNCTION_BLOCK FB_Idle EXTENDS FB_StoppableState``: ready, waiting for Start."""

    @prop
    def state(self) -> PackMLState:
        return PackMLState.IDLE

    @method
    def command(self, cmd: PackMLCommand) -> BOOL:
        if cmd == PackMLCommand.START:
            return self.go(PackMLState.STARTING)
        return super().command(cmd)


class Starting(StoppableState):
    """``FUNCTION_BLOCK FB_Starting EXTENDS FB_StoppableState``: acting, SC to Execute."""

    @prop
    def state(self) -> PackMLState:
        return PackMLState.STARTING

    @method
    def cycle(self) -> None:
        self.complete_to(PackMLState.EXECUTE)


class Execute(StoppableState):
    """``FUNCTION_BLOCK FB_Execute EXTENDS FB_StoppableState``: producing; SC to Completing.

    Makes one pack every ``pack_time``; the batch is complete (SC) after
    ``batch_size`` packs. Hold and Suspend interrupt it; the count carries
    on when Execute is entered again from Unholding or Unsuspending and
    starts from zero when it is entered from Starting.
    """

    batch_size: UDINT = VAR_INPUT(5)
    pack_time: TIME = VAR_INPUT(T("100ms"))
    packs: UDINT = VAR_OUTPUT(0)
    pack_timer: TON = VAR()

    @prop
    def state(self) -> PackMLState:
        return PackMLState.EXECUTE

    @method
    def enter(self, from_state: PackMLState) -> None:
        super().enter(from_state)
        if from_state == PackMLState.STARTING:
            self.packs = 0
        self.pack_timer(IN=False, PT=self.pack_time)
        self.pack_timer(IN=True)

    @method
    def cycle(self) -> None:
        self.pack_timer(IN=True, PT=self.pack_time)
        if self.pack_timer.Q:
            self.packs += 1
            self.pack_timer(IN=False)
            self.pack_timer(IN=True)
        if self.packs >= self.batch_size:
            self.go(PackMLState.COMPLETING)

    @method
    def command(self, cmd: PackMLCommand) -> BOOL:
        if cmd == PackMLCommand.HOLD:
            return self.go(PackMLState.HOLDING)
        if cmd == PackMLCommand.SUSPEND:
            return self.go(PackMLState.SUSPENDING)
        return super().command(cmd)


class Completing(StoppableState):
    """``FUNCTION_BLOCK FB_Completing EXTENDS FB_StoppableState``: acting, SC to Complete."""

    @prop
    def state(self) -> PackMLState:
        return PackMLState.COMPLETING

    @method
    def cycle(self) -> None:
        self.complete_to(PackMLState.COMPLETE)


class Complete(StoppableState):
    """``FUNCTION_BLOCK FB_Complete EXTENDS FB_StoppableState``: batch done, waiting for Reset."""

    @prop
    def state(self) -> PackMLState:
        return PackMLState.COMPLETE

    @method
    def command(self, cmd: PackMLCommand) -> BOOL:
        if cmd == PackMLCommand.RESET:
            return self.go(PackMLState.RESETTING)
        return super().command(cmd)


class Holding(StoppableState):
    """``FUNCTION_BLOCK FB_Holding EXTENDS FB_StoppableState``: acting, SC to Held."""

    @prop
    def state(self) -> PackMLState:
        return PackMLState.HOLDING

    @method
    def cycle(self) -> None:
        self.complete_to(PackMLState.HELD)


class Held(StoppableState):
    """``FUNCTION_BLOCK FB_Held EXTENDS FB_StoppableState``: held by the operator, waiting for Unhold."""

    @prop
    def state(self) -> PackMLState:
        return PackMLState.HELD

    @method
    def command(self, cmd: PackMLCommand) -> BOOL:
        if cmd == PackMLCommand.UNHOLD:
            return self.go(PackMLState.UNHOLDING)
        return super().command(cmd)


class Unholding(StoppableState):
    """``FUNCTION_BLOCK FB_Unholding EXTENDS FB_StoppableState``: acting, SC to Execute."""

    @prop
    def state(self) -> PackMLState:
        return PackMLState.UNHOLDING

    @method
    def cycle(self) -> None:
        self.complete_to(PackMLState.EXECUTE)


class Suspending(StoppableState):
    """``FUNCTION_BLOCK FB_Suspending EXTENDS FB_StoppableState``: acting, SC to Suspended."""

    @prop
    def state(self) -> PackMLState:
        return PackMLState.SUSPENDING

    @method
    def cycle(self) -> None:
        self.complete_to(PackMLState.SUSPENDED)


class Suspended(StoppableState):
    """``FUNCTION_BLOCK FB_Suspended EXTENDS FB_StoppableState``: starved or blocked, waiting for Unsuspend."""

    @prop
    def state(self) -> PackMLState:
        return PackMLState.SUSPENDED

    @method
    def command(self, cmd: PackMLCommand) -> BOOL:
        if cmd == PackMLCommand.UNSUSPEND:
            return self.go(PackMLState.UNSUSPENDING)
        return super().command(cmd)


class Unsuspending(StoppableState):
    """``FUNCTION_BLOCK FB_Unsuspending EXTENDS FB_StoppableState``: acting, SC to Execute."""

    @prop
    def state(self) -> PackMLState:
        return PackMLState.UNSUSPENDING

    @method
    def cycle(self) -> None:
        self.complete_to(PackMLState.EXECUTE)


class Stopping(AbortableState):
    """``FUNCTION_BLOCK FB_Stopping EXTENDS FB_AbortableState``: acting, SC to Stopped."""

    @prop
    def state(self) -> PackMLState:
        return PackMLState.STOPPING

    @method
    def cycle(self) -> None:
        self.complete_to(PackMLState.STOPPED)


class Aborting(PackMLStateBase):
    """``FUNCTION_BLOCK FB_Aborting EXTENDS FB_PackMLStateBase``: acting, SC to Aborted; refuses every command."""

    @prop
    def state(self) -> PackMLState:
        return PackMLState.ABORTING

    @method
    def cycle(self) -> None:
        self.complete_to(PackMLState.ABORTED)


class Aborted(PackMLStateBase):
    """``FUNCTION_BLOCK FB_Aborted EXTENDS FB_PackMLStateBase``: waiting for Clear, nothing else."""

    @prop
    def state(self) -> PackMLState:
        return PackMLState.ABORTED

    @method
    def command(self, cmd: PackMLCommand) -> BOOL:
        if cmd == PackMLCommand.CLEAR:
            return self.go(PackMLState.CLEARING)
        return super().command(cmd)


class Clearing(AbortableState):
    """``FUNCTION_BLOCK FB_Clearing EXTENDS FB_AbortableState``: acting, SC to Stopped."""

    @prop
    def state(self) -> PackMLState:
        return PackMLState.CLEARING

    @method
    def cycle(self) -> None:
        self.complete_to(PackMLState.STOPPED)


# ---------------------------------------------------------------------------
# The context: the machine
# ---------------------------------------------------------------------------


class PackMLMachine(FunctionBlock, IPackMLUnit, IPackMLContext):
    """``FUNCTION_BLOCK FB_PackMLMachine IMPLEMENTS I_PackMLUnit, I_PackMLContext``.

    Holds one instance of each state, wires them to itself in FB_init and
    files them in ``states``, indexed by their PackTags number. ``command``
    and the body delegate to the current state; a command the current state
    does not accept is refused: ``refused`` counts it, ``last_refused`` names
    it and the state stays. ``state`` is read-only. The acting times are the
    ``duration`` inputs of the state instances (``machine.resetting.duration``).
    """

    stopped: Stopped = VAR()
    resetting: Resetting = VAR({"duration": T("200ms")})
    idle: Idle = VAR()
    starting: Starting = VAR({"duration": T("300ms")})
    execute: Execute = VAR()
    completing: Completing = VAR({"duration": T("200ms")})
    complete: Complete = VAR()
    holding: Holding = VAR({"duration": T("100ms")})
    held: Held = VAR()
    unholding: Unholding = VAR({"duration": T("100ms")})
    suspending: Suspending = VAR({"duration": T("100ms")})
    suspended: Suspended = VAR()
    unsuspending: Unsuspending = VAR({"duration": T("100ms")})
    stopping: Stopping = VAR({"duration": T("200ms")})
    aborting: Aborting = VAR({"duration": T("100ms")})
    aborted: Aborted = VAR()
    clearing: Clearing = VAR({"duration": T("200ms")})

    states: ARRAY[IPackMLState] = VAR(bounds=(PackMLState.CLEARING, PackMLState.COMPLETE))
    current: PackMLState = VAR(PackMLState.STOPPED)
    previous_state: PackMLState = VAR_OUTPUT(PackMLState.STOPPED)
    transitions: UDINT = VAR_OUTPUT(0)
    refused: UDINT = VAR_OUTPUT(0)
    last_refused: PackMLCommand = VAR_OUTPUT(PackMLCommand.NONE)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
        # ST has no list of instances to loop over: each state is wired and filed by name.
        self.stopped.attach(self)
        self.resetting.attach(self)
        self.idle.attach(self)
        self.starting.attach(self)
        self.execute.attach(self)
        self.completing.attach(self)
        self.complete.attach(self)
        self.holding.attach(self)
        self.held.attach(self)
        self.unholding.attach(self)
        self.suspending.attach(self)
        self.suspended.attach(self)
        self.unsuspending.attach(self)
        self.stopping.attach(self)
        self.aborting.attach(self)
        self.aborted.attach(self)
        self.clearing.attach(self)
        self.states[PackMLState.STOPPED] = self.stopped
        self.states[PackMLState.RESETTING] = self.resetting
        self.states[PackMLState.IDLE] = self.idle
        self.states[PackMLState.STARTING] = self.starting
        self.states[PackMLState.EXECUTE] = self.execute
        self.states[PackMLState.COMPLETING] = self.completing
        self.states[PackMLState.COMPLETE] = self.complete
        self.states[PackMLState.HOLDING] = self.holding
        self.states[PackMLState.HELD] = self.held
        self.states[PackMLState.UNHOLDING] = self.unholding
        self.states[PackMLState.SUSPENDING] = self.suspending
        self.states[PackMLState.SUSPENDED] = self.suspended
        self.states[PackMLState.UNSUSPENDING] = self.unsuspending
        self.states[PackMLState.STOPPING] = self.stopping
        self.states[PackMLState.ABORTING] = self.aborting
        self.states[PackMLState.ABORTED] = self.aborted
        self.states[PackMLState.CLEARING] = self.clearing
        self.states[self.current].enter(self.current)
        return True

    @prop
    def state(self) -> PackMLState:
        return self.current

    @method
    def command(self, cmd: PackMLCommand) -> BOOL:
        if self.states[self.current].command(cmd):
            return True
        self.refused += 1
        self.last_refused = cmd
        return False

    @method
    def change_state(self, target: PackMLState) -> None:
        self.previous_state = self.current
        self.current = target
        self.transitions += 1
        self.states[target].enter(self.previous_state)

    def body(self) -> None:
        self.states[self.current].cycle()


# ---------------------------------------------------------------------------
# The client: a line controller running one batch
# ---------------------------------------------------------------------------


class PackagingLine(Program):
    """``PROGRAM PRG_PackagingLine``: the line controller commanding one unit through a batch.

    Resets and starts the unit, suspends it when the infeed runs dry after
    three packs, unsuspends it once the infeed is back (after ``infeed_gap``),
    and when the batch is complete resets it and stops it. The HMI's Start
    pressed a second time while producing is refused by the unit.
    """

    unit: PackMLMachine = VAR()
    infeed_gap: TIME = VAR_INPUT(T("200ms"))
    batches: UDINT = VAR(0)
    starved: BOOL = VAR(False)
    pressed_again: BOOL = VAR(False)
    wait: TON = VAR()

    def body(self) -> None:
        state = self.unit.state
        self.wait(IN=state in (PackMLState.SUSPENDED, PackMLState.COMPLETE), PT=self.infeed_gap)
        if state == PackMLState.STOPPED and self.batches == 0:
            self.unit.command(PackMLCommand.RESET)
        elif state == PackMLState.IDLE:
            self.unit.command(PackMLCommand.START if self.batches == 0 else PackMLCommand.STOP)
        elif state == PackMLState.EXECUTE:
            if self.unit.execute.packs == 1 and not self.pressed_again:
                self.pressed_again = True
                self.unit.command(PackMLCommand.START)
            elif self.unit.execute.packs == 3 and not self.starved:
                self.starved = True
                self.unit.command(PackMLCommand.SUSPEND)
        elif state == PackMLState.SUSPENDED and self.wait.Q:
            self.unit.command(PackMLCommand.UNSUSPEND)
        elif state == PackMLState.COMPLETE and self.wait.Q:
            self.batches += 1
            self.unit.command(PackMLCommand.RESET)
        self.unit()


def state_name(state: PackMLState) -> str:
    """The table's spelling of a state: ``PackMLState.EXECUTE`` -> ``"Execute"``."""
    return state.name.capitalize()


def main() -> None:
    """Run one production batch on a 10 ms task and print the state trace.

    >>> main()
    t=    0 ms  Stopped      Reset     -> Resetting
    t=  200 ms  Resetting    SC        -> Idle
    t=  210 ms  Idle         Start     -> Starting
    t=  510 ms  Starting     SC        -> Execute
    t=  820 ms  Execute      Suspend   -> Suspending
    t=  920 ms  Suspending   SC        -> Suspended
    t= 1130 ms  Suspended    Unsuspend -> Unsuspending
    t= 1230 ms  Unsuspending SC        -> Execute
    t= 1430 ms  Execute      SC        -> Completing
    t= 1630 ms  Completing   SC        -> Complete
    t= 1840 ms  Complete     Reset     -> Resetting
    t= 2040 ms  Resetting    SC        -> Idle
    t= 2050 ms  Idle         Stop      -> Stopping
    t= 2250 ms  Stopping     SC        -> Stopped
    packs=5  refused=1 (last: Start)
    """
    line = PackagingLine()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), line)
    causes = {(source, target): cause for source, cause, target in TRANSITIONS}
    seen = line.unit.transitions
    for _ in range(250):
        now = rt.time_ms
        rt.run(cycles=1)
        if line.unit.transitions != seen:
            seen = line.unit.transitions
            source, target = state_name(line.unit.previous_state), state_name(line.unit.state)
            print(f"t={now:5d} ms  {source:<12} {causes[(source, target)]:<9} -> {target}")
    print(
        f"packs={line.unit.execute.packs}  refused={line.unit.refused} "
        f"(last: {line.unit.last_refused.name.capitalize()})"
    )


SHOWCASE = Showcase(
    use_when="states have behaviour of their own (entry actions, timing, commands) reviewed against a diagram, as in PackML",
    columns=(
        Column("state", lambda p: p.unit.state),
        Column("packs", lambda p: p.unit.execute.packs),
        Column("transitions", lambda p: p.unit.transitions),
        Column("refused", lambda p: p.unit.refused),
        Column("batches", lambda p: p.batches),
    ),
    cycles=250,
    tour_cycles=250,
    expected=(("refused", "Start is pressed again while the unit is already in EXECUTE"),),
)
