"""Facade: a palletiser cell that the HMI drives with three buttons.

Intent
------

Provide a unified interface to a set of interfaces in a subsystem. Facade
defines a higher-level interface that makes the subsystem easier to use.

The PLC problem
---------------

An end-of-line palletiser cell holds a robot, a case infeed conveyor, an
empty-pallet infeed conveyor, a stretch wrapper and a safety relay. Starting
it is a sequence: the safety circuit must be healthy, the robot homed
(within a time limit), the pallet conveyor started, then the case conveyor
a moment later. Running it is a cycle: take a pallet, place cases on it,
send the full pallet to the wrapper. Stopping lets the robot and the wrapper
finish what they hold; a safety trip stops everything at once and needs a
reset with the cause gone.

The HMI and the line controller should not know any of that. The facade
``FB_PalletiserCell`` owns the subsystems (composition) and offers
``StartCell``, ``StopCell``, ``Reset``, a state and a status text. The
subsystems run inside it, one call per scan, and are INTERNAL to the
library: a project builds cells, not loose robots.

Roles
-----

- Facade → ``PalletiserCell`` (``FB_PalletiserCell``, FINAL), behind
  ``ICell`` (``I_Cell``), with ``CellState`` (``E_CellState``).
- Subsystems → ``Robot`` (``FB_Robot``, ``I_Robot``), ``Conveyor``
  (``FB_Conveyor``, ``I_Conveyor``; case infeed and pallet infeed),
  ``StretchWrapper`` (``FB_StretchWrapper``, ``I_Wrapper``),
  ``SafetyRelay`` (``FB_SafetyRelay``, ``I_Safety``); all INTERNAL.
- Client → ``CellMain`` (``PROGRAM CellMain``): HMI buttons through R_TRIG.

IEC 61131-3 mapping
-------------------

::

    INTERFACE I_Cell
        METHOD StartCell : BOOL    METHOD StopCell : BOOL    METHOD Reset : BOOL
        PROPERTY State : E_CellState    PROPERTY PalletsDone : UDINT
        PROPERTY Message : STRING

    FUNCTION_BLOCK FINAL FB_PalletiserCell IMPLEMENTS I_Cell
        VAR_INPUT bEstopOk, bGuardClosed : BOOL; END_VAR
        VAR
            fbSafety : FB_SafetyRelay;    fbRobot : FB_Robot;
            fbCaseInfeed : FB_Conveyor;   fbPalletInfeed : FB_Conveyor;
            fbWrapper : FB_StretchWrapper;
            eState : E_CellState;  tonHoming, tonStagger : TON;
        END_VAR
        METHOD PRIVATE AllStop    METHOD PRIVATE RunCycle

    FUNCTION_BLOCK INTERNAL FB_Robot IMPLEMENTS I_Robot
        METHOD Home    METHOD PickPlace : BOOL    METHOD Halt
        PROPERTY Homed : BOOL    PROPERTY Busy : BOOL    PROPERTY Done : BOOL

When not to use it on a PLC
---------------------------

When the client needs the subsystems' detail: a maintenance screen that jogs
the robot or runs one conveyor needs the subsystem interfaces, not a facade
that hides them (give it those, beside the facade). And a facade must not
grow into the one block that knows everything: the subsystems keep their own
logic (homing, wrap timing) and the facade only sequences them.

References
----------

- Gamma, Helm, Johnson, Vlissides: *Design Patterns*, Addison-Wesley 1994,
  "Facade".
- IEC 61131-3:2013 (3rd ed.), function blocks, methods, interfaces, access
  specifiers; TON, R_TRIG.
- ISA-TR88.00.02-2015, *Machine and Unit States* (PackML): Start / Stop /
  Reset commands and the Stopped, Starting, Execute, Stopping states.
- Beckhoff InfoSys, TwinCAT 3 PLC: "FINAL", "INTERNAL", "Object Method".
- CODESYS Online Help: "Access Specifier", "Object: Method".
"""

from __future__ import annotations

from iecoop import (
    BOOL,
    PRIVATE,
    STRING,
    TIME,
    UDINT,
    UINT,
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
from iecoop.stdlib import R_TRIG, TON
from patterns.showcase.entry import Column, Scenario, Showcase

__all__ = [
    "CASES_PER_PALLET",
    "CellMain",
    "CellState",
    "Conveyor",
    "ICell",
    "IConveyor",
    "IRobot",
    "ISafety",
    "IWrapper",
    "PalletiserCell",
    "Robot",
    "SafetyRelay",
    "StretchWrapper",
    "main",
]

#: Cases on a full pallet (small, so the example runs in a few seconds of PLC time).
CASES_PER_PALLET = 4


# ---------------------------------------------------------------------------
# Subsystem interfaces
# ---------------------------------------------------------------------------


class IRobot(Interface):
    """``INTERFACE I_Robot``"""

    @method
    def home(self) -> None: ...

    @method
    def pick_place(self) -> BOOL:
        raise NotImplementedError

    @method
    def halt(self) -> None: ...

    @prop
    def homed(self) -> BOOL:
        raise NotImplementedError

    @prop
    def busy(self) -> BOOL:
        raise NotImplementedError

    @prop
    def done(self) -> BOOL:
        """TRUE for one scan when a pick-and-place has finished."""
        raise NotImplementedError


class IConveyor(Interface):
    """``INTERFACE I_Conveyor``"""

    @method
    def start(self) -> None: ...

    @method
    def stop(self) -> None: ...

    @method
    def take(self) -> BOOL:
        """Remove the item at the end photo-eye; FALSE if there is none."""
        raise NotImplementedError

    @prop
    def running(self) -> BOOL:
        raise NotImplementedError

    @prop
    def item_ready(self) -> BOOL:
        raise NotImplementedError


class IWrapper(Interface):
    """``INTERFACE I_Wrapper``"""

    @method
    def wrap(self) -> BOOL:
        raise NotImplementedError

    @method
    def abort(self) -> None: ...

    @prop
    def busy(self) -> BOOL:
        raise NotImplementedError

    @prop
    def done(self) -> BOOL:
        """TRUE for one scan when a pallet is wrapped."""
        raise NotImplementedError


class ISafety(Interface):
    """``INTERFACE I_Safety``"""

    @method
    def reset(self) -> BOOL:
        raise NotImplementedError

    @prop
    def safe(self) -> BOOL:
        raise NotImplementedError

    @prop
    def cause(self) -> STRING:
        raise NotImplementedError


# ---------------------------------------------------------------------------
# Subsystems (each simulates its own equipment)
# ---------------------------------------------------------------------------


class Robot(FunctionBlock, IRobot, internal=True):
    """``FUNCTION_BLOCK INTERNAL FB_Robot IMPLEMENTS I_Robot``.

    Homing takes 300 ms and a pick-and-place 200 ms. A halt drops the servos,
    so the robot must home again. ``stuck`` simulates an axis that never
    reaches its home switch.
    """

    stuck: BOOL = VAR_INPUT(False)
    homed_flag: BOOL = VAR(False)
    homing: BOOL = VAR(False)
    moving: BOOL = VAR(False)
    done_pulse: BOOL = VAR(False)
    placed: UDINT = VAR_OUTPUT(0)
    home_time: TON = VAR()
    motion_time: TON = VAR()

    @method
    def home(self) -> None:
        self.homing = not self.homed_flag

    @method
    def pick_place(self) -> BOOL:
        if not self.homed_flag or self.moving:
            return False
        self.moving = True
        return True

    @method
    def halt(self) -> None:
        self.homing = self.moving = self.homed_flag = False

    @prop
    def homed(self) -> BOOL:
        return self.homed_flag

    @prop
    def busy(self) -> BOOL:
        return self.homing or self.moving

    @prop
    def done(self) -> BOOL:
        return self.done_pulse

    def body(self) -> None:
        self.done_pulse = False
        self.home_time(IN=self.homing and not self.stuck, PT=T("300ms"))
        if self.home_time.Q:
            self.homing = False
            self.homed_flag = True
        self.motion_time(IN=self.moving, PT=T("200ms"))
        if self.motion_time.Q:
            self.moving = False
            self.done_pulse = True
            self.placed += 1


class Conveyor(FunctionBlock, IConveyor, internal=True):
    """``FUNCTION_BLOCK INTERNAL FB_Conveyor IMPLEMENTS I_Conveyor``.

    While running and not blocked, an item reaches the end photo-eye every
    ``interval`` (given to FB_init); an item at the end blocks the next one.
    """

    interval: TIME = VAR(T("250ms"))
    running_flag: BOOL = VAR(False)
    at_end: BOOL = VAR(False)
    arrival: TON = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, interval: TIME = T("250ms")) -> None:
        self.interval = interval

    @method
    def start(self) -> None:
        self.running_flag = True

    @method
    def stop(self) -> None:
        self.running_flag = False

    @method
    def take(self) -> BOOL:
        if not self.at_end:
            return False
        self.at_end = False
        return True

    @prop
    def running(self) -> BOOL:
        return self.running_flag

    @prop
    def item_ready(self) -> BOOL:
        return self.at_end

    def body(self) -> None:
        self.arrival(IN=self.running_flag and not self.at_end, PT=self.interval)
        if self.arrival.Q:
            self.at_end = True


class StretchWrapper(FunctionBlock, IWrapper, internal=True):
    """``FUNCTION_BLOCK INTERNAL FB_StretchWrapper IMPLEMENTS I_Wrapper``: a 600 ms wrap cycle."""

    wrapping: BOOL = VAR(False)
    done_pulse: BOOL = VAR(False)
    wrapped: UDINT = VAR_OUTPUT(0)
    cycle_time: TON = VAR()

    @method
    def wrap(self) -> BOOL:
        if self.wrapping:
            return False
        self.wrapping = True
        return True

    @method
    def abort(self) -> None:
        self.wrapping = False

    @prop
    def busy(self) -> BOOL:
        return self.wrapping

    @prop
    def done(self) -> BOOL:
        return self.done_pulse

    def body(self) -> None:
        self.done_pulse = False
        self.cycle_time(IN=self.wrapping, PT=T("600ms"))
        if self.cycle_time.Q:
            self.wrapping = False
            self.done_pulse = True
            self.wrapped += 1


class SafetyRelay(FunctionBlock, ISafety, internal=True):
    """``FUNCTION_BLOCK INTERNAL FB_SafetyRelay IMPLEMENTS I_Safety``.

    Latches a trip when the e-stop or the guard door opens; ``Reset`` clears
    it only once both are healthy again (no automatic restart).
    """

    estop_ok: BOOL = VAR_INPUT(True)
    guard_closed: BOOL = VAR_INPUT(True)
    tripped: BOOL = VAR_OUTPUT(False)
    first_cause: STRING = VAR("", length=20)

    @method
    def reset(self) -> BOOL:
        if self.estop_ok and self.guard_closed:
            self.tripped = False
            self.first_cause = ""
        return not self.tripped

    @prop
    def safe(self) -> BOOL:
        return not self.tripped

    @prop
    def cause(self) -> STRING:
        return self.first_cause

    def body(self) -> None:
        if not self.tripped and not (self.estop_ok and self.guard_closed):
            self.tripped = True
            self.first_cause = "e-stop" if not self.estop_ok else "guard door open"


# ---------------------------------------------------------------------------
# The facade
# ---------------------------------------------------------------------------


class CellState(IecEnum):
    """``TYPE E_CellState : (STOPPED, STARTING, RUNNING, STOPPING, TRIPPED, FAULTED) INT; END_TYPE``"""

    STOPPED = 0
    STARTING = 1
    RUNNING = 2
    STOPPING = 3
    TRIPPED = 4
    FAULTED = 5


class ICell(Interface):
    """``INTERFACE I_Cell``: everything the HMI and the line controller need."""

    @method
    def start_cell(self) -> BOOL:
        raise NotImplementedError

    @method
    def stop_cell(self) -> BOOL:
        raise NotImplementedError

    @method
    def reset(self) -> BOOL:
        raise NotImplementedError

    @prop
    def state(self) -> CellState:
        raise NotImplementedError

    @prop
    def pallets_done(self) -> UDINT:
        raise NotImplementedError

    @prop
    def message(self) -> STRING:
        raise NotImplementedError


class PalletiserCell(FunctionBlock, ICell, final=True):
    """The facade: ``FUNCTION_BLOCK FINAL FB_PalletiserCell IMPLEMENTS I_Cell``.

    Call it once per scan with the safety inputs; command it with the three
    methods, each answering whether the command was accepted in the current
    state.
    """

    estop_ok: BOOL = VAR_INPUT(True)
    guard_closed: BOOL = VAR_INPUT(True)
    safety: SafetyRelay = VAR()
    robot: Robot = VAR()
    case_infeed: Conveyor = VAR(fb_init={"interval": T("250ms")})
    pallet_infeed: Conveyor = VAR(fb_init={"interval": T("300ms")})
    wrapper: StretchWrapper = VAR()
    state_now: CellState = VAR(CellState.STOPPED)
    text: STRING = VAR("stopped", length=40)
    pallet_in_place: BOOL = VAR(False)
    cases: UINT = VAR(0)
    done_count: UDINT = VAR(0)
    homing_watchdog: TON = VAR()
    stagger: TON = VAR()

    @method
    def start_cell(self) -> BOOL:
        if self.state_now != CellState.STOPPED or not self.safety.safe:
            return False
        self.robot.home()
        self.state_now = CellState.STARTING
        self.text = "homing robot"
        return True

    @method
    def stop_cell(self) -> BOOL:
        if self.state_now not in (CellState.STARTING, CellState.RUNNING):
            return False
        self.case_infeed.stop()
        self.pallet_infeed.stop()
        self.state_now = CellState.STOPPING
        self.text = "stopping: finishing the cycle"
        return True

    @method
    def reset(self) -> BOOL:
        if self.state_now == CellState.TRIPPED:
            if not self.safety.reset():
                self.text = f"reset refused: {self.safety.cause}"
                return False
        elif self.state_now != CellState.FAULTED:
            return False
        self.state_now = CellState.STOPPED
        self.text = "stopped"
        return True

    @prop
    def state(self) -> CellState:
        return self.state_now

    @prop
    def pallets_done(self) -> UDINT:
        return self.done_count

    @prop
    def message(self) -> STRING:
        return self.text

    def body(self) -> None:
        self.safety(estop_ok=self.estop_ok, guard_closed=self.guard_closed)
        self.robot()
        self.case_infeed()
        self.pallet_infeed()
        self.wrapper()
        if not self.safety.safe and self.state_now != CellState.TRIPPED:
            self.all_stop()
            self.state_now = CellState.TRIPPED
            self.text = f"safety trip: {self.safety.cause}"
        starting = self.state_now == CellState.STARTING
        self.homing_watchdog(IN=starting and not self.robot.homed, PT=T("2s"))
        self.stagger(IN=starting and self.robot.homed, PT=T("200ms"))
        if starting:
            if self.homing_watchdog.Q:
                self.all_stop()
                self.state_now = CellState.FAULTED
                self.text = "fault: robot homing timeout"
            elif self.robot.homed and not self.pallet_infeed.running:
                self.pallet_infeed.start()
                self.text = "starting conveyors"
            elif self.stagger.Q:
                self.case_infeed.start()
                self.state_now = CellState.RUNNING
                self.text = "running"
        elif self.state_now == CellState.RUNNING:
            self.run_cycle(feed=True)
        elif self.state_now == CellState.STOPPING:
            self.run_cycle(feed=False)
            if not self.robot.busy and not self.wrapper.busy:
                self.state_now = CellState.STOPPED
                self.text = "stopped"

    @method(PRIVATE)
    def run_cycle(self, feed: BOOL) -> None:
        """One scan of production: count placed cases, swap pallets, start the next pick."""
        if self.robot.done:
            self.cases += 1
        if self.wrapper.done:
            self.done_count += 1
            self.text = f"pallet {self.done_count} wrapped"
        if not self.pallet_in_place and feed and self.pallet_infeed.take():
            self.pallet_in_place = True
            self.cases = 0
        if not self.pallet_in_place or self.robot.busy:
            return
        if self.cases >= CASES_PER_PALLET:
            if self.wrapper.wrap():
                self.pallet_in_place = False
                self.text = f"wrapping pallet {self.done_count + 1}"
        elif feed and self.case_infeed.item_ready:
            self.case_infeed.take()
            self.robot.pick_place()

    @method(PRIVATE)
    def all_stop(self) -> None:
        self.robot.halt()
        self.case_infeed.stop()
        self.pallet_infeed.stop()
        self.wrapper.abort()


# ---------------------------------------------------------------------------
# The client: an HMI with three buttons
# ---------------------------------------------------------------------------


class CellMain(Program):
    """``PROGRAM CellMain``: HMI buttons (edge-triggered) and the safety inputs into the facade.

    ST::

        rtStart(CLK := bBtnStart);  IF rtStart.Q THEN bAccepted := fbCell.StartCell(); END_IF
        rtStop(CLK := bBtnStop);    IF rtStop.Q  THEN bAccepted := fbCell.StopCell();  END_IF
        rtReset(CLK := bBtnReset);  IF rtReset.Q THEN bAccepted := fbCell.Reset();     END_IF
        fbCell(bEstopOk := bEstopOk, bGuardClosed := bGuardClosed);
    """

    btn_start: BOOL = VAR_INPUT(False)
    btn_stop: BOOL = VAR_INPUT(False)
    btn_reset: BOOL = VAR_INPUT(False)
    estop_ok: BOOL = VAR_INPUT(True)
    guard_closed: BOOL = VAR_INPUT(True)
    accepted: BOOL = VAR_OUTPUT(False)
    cell: PalletiserCell = VAR()
    start_edge: R_TRIG = VAR()
    stop_edge: R_TRIG = VAR()
    reset_edge: R_TRIG = VAR()

    def body(self) -> None:
        self.start_edge(CLK=self.btn_start)
        self.stop_edge(CLK=self.btn_stop)
        self.reset_edge(CLK=self.btn_reset)
        if self.start_edge.Q:
            self.accepted = self.cell.start_cell()
        if self.stop_edge.Q:
            self.accepted = self.cell.stop_cell()
        if self.reset_edge.Q:
            self.accepted = self.cell.reset()
        self.cell(estop_ok=self.estop_ok, guard_closed=self.guard_closed)


def main() -> None:
    """Run the cell through a pallet, an e-stop, a refused and an accepted reset, a restart and a stop.

    >>> main()
    t=   0 ms  start button      STARTING  homing robot
    t= 300 ms                    STARTING  starting conveyors
    t= 500 ms                    RUNNING   running
    t=1450 ms                    RUNNING   wrapping pallet 1
    t=2060 ms                    RUNNING   pallet 1 wrapped
    t=2100 ms  e-stop pressed    TRIPPED   safety trip: e-stop
    t=2200 ms  reset button      TRIPPED   reset refused: e-stop
    t=2300 ms  e-stop released   TRIPPED   reset refused: e-stop
    t=2400 ms  reset button      STOPPED   stopped
    t=2500 ms  start button      STARTING  homing robot
    t=2800 ms                    STARTING  starting conveyors
    t=3000 ms                    RUNNING   running
    t=3300 ms  stop button       STOPPING  stopping: finishing the cycle
    t=3470 ms                    STOPPED   stopped
    pallets done: 1, cases placed: 7
    """
    hmi = CellMain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), hmi)
    script = {
        0: "start button",
        2100: "e-stop pressed",
        2200: "reset button",
        2300: "e-stop released",
        2400: "reset button",
        2500: "start button",
        3300: "stop button",
    }
    shown = ""
    for _ in range(380):
        t = rt.time_ms
        action = script.get(t, "")
        hmi.estop_ok = hmi.estop_ok != action.startswith("e-stop")
        hmi.btn_start = action == "start button"
        hmi.btn_stop = action == "stop button"
        hmi.btn_reset = action == "reset button"
        rt.run(cycles=1)
        status = f"{hmi.cell.state.name:<9} {hmi.cell.message}"
        if action or status != shown:
            print(f"t={t:4d} ms  {action:<17} {status}")
            shown = status
    print(f"pallets done: {hmi.cell.pallets_done}, cases placed: {hmi.cell.robot.placed}")


_FACADE = {1: "start", 211: "estop", 221: "reset", 231: "estop", 241: "reset", 251: "start", 331: "stop"}


def _cell_buttons(scenario: Scenario, cycle: int) -> None:
    hmi = scenario.program
    action = _FACADE.get(cycle, "")
    hmi.estop_ok = hmi.estop_ok != (action == "estop")
    hmi.btn_start = action == "start"
    hmi.btn_stop = action == "stop"
    hmi.btn_reset = action == "reset"


SHOWCASE = Showcase(
    use_when="an HMI or a line controller needs a few buttons, not the detail of every subsystem of a cell",
    columns=(
        Column("state", lambda p: p.cell.state),
        Column("message", lambda p: p.cell.message),
        Column("pallets", lambda p: p.cell.pallets_done),
        Column("cases", lambda p: p.cell.robot.placed, watch=False),
    ),
    script=_cell_buttons,
    cycles=380,
    tour_cycles=250,
    expected=(("TRIPPED, reset refused", "the e-stop is pressed in cycle 211, a reset tried while it is still pressed"),),
)
