"""The course's chapter 5 (inheritance, THIS^ / SUPER^, access specifiers) run as the PLC runs it.

Each block carries its ST listing; the tests call them cycle after cycle from a
PROGRAM, as the task would, and compare with the values the PLC shows online.
"""

from __future__ import annotations

import importlib
import sys
import uuid
from collections.abc import Callable, Iterator
from types import ModuleType

import pytest

from iecoop import (
    BOOL,
    INT,
    INTERNAL,
    LREAL,
    PRIVATE,
    PROTECTED,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    AccessError,
    FunctionBlock,
    Interface,
    Program,
    method,
    prop,
)
from iecoop.testing.strategies import wrap_int


# ---------------------------------------------------------------------------
# THIS^ and SUPER^
# ---------------------------------------------------------------------------


class FB_Base(FunctionBlock):
    """ST::

        FUNCTION_BLOCK FB_Base
        VAR_OUTPUT iCnt : INT; END_VAR
        iCnt := iCnt + 1;

        METHOD METH_DoIt : BOOL
        iCnt := iCnt + 10;
        METH_DoIt := TRUE;

        METHOD METH_DoTwice : BOOL
        THIS^.METH_DoIt();
        THIS^.METH_DoIt();
    """

    i_cnt: INT = VAR_OUTPUT(0)

    def body(self) -> None:
        self.i_cnt += 1

    @method
    def meth_do_it(self) -> BOOL:
        self.i_cnt += 10
        return True

    @method
    def meth_do_twice(self) -> BOOL:
        self.meth_do_it()
        self.meth_do_it()
        return True


class FB_1(FB_Base):
    """ST::

        FUNCTION_BLOCK FB_1 EXTENDS FB_Base
        VAR_OUTPUT iThis : INT; iBase : INT; END_VAR
        SUPER^();                 // FB_Base's body
        THIS^.METH_DoIt();        // FB_1's METH_DoIt
        iThis := iCnt;
        SUPER^.METH_DoIt();       // FB_Base's METH_DoIt only
        iBase := iCnt;

        METHOD METH_DoIt : BOOL
        SUPER^.METH_DoIt();
        iCnt := iCnt + 100;
        METH_DoIt := TRUE;
    """

    i_this: INT = VAR_OUTPUT(0)
    i_base: INT = VAR_OUTPUT(0)

    def body(self) -> None:
        super().body()
        self.meth_do_it()
        self.i_this = self.i_cnt
        super().meth_do_it()
        self.i_base = self.i_cnt

    @method
    def meth_do_it(self) -> BOOL:
        super().meth_do_it()
        self.i_cnt += 100
        return True


class MAIN(Program):
    """ST::

        PROGRAM MAIN
        VAR fbBase : FB_Base; fb1 : FB_1; iBaseCnt : INT; iFb1Cnt : INT; END_VAR
        fbBase();
        fb1();
        iBaseCnt := fbBase.iCnt;
        iFb1Cnt := fb1.iCnt;
    """

    fb_base: FB_Base = VAR()
    fb1: FB_1 = VAR()
    i_base_cnt: INT = VAR(0)
    i_fb1_cnt: INT = VAR(0)

    def body(self) -> None:
        self.fb_base()
        self.fb1()
        self.i_base_cnt = self.fb_base.i_cnt
        self.i_fb1_cnt = self.fb1.i_cnt


def test_this_and_super_values_after_each_cycle() -> None:
    main = MAIN()
    for cycle in range(1, 6):
        main()
        # One FB_1 cycle: +1 (SUPER^()), +10 +100 (THIS^.METH_DoIt), +10 (SUPER^.METH_DoIt).
        assert main.i_base_cnt == cycle
        assert main.i_fb1_cnt == 121 * cycle
        assert main.fb1.i_this == 121 * (cycle - 1) + 111
        assert main.fb1.i_base == 121 * cycle


def test_the_base_alone_runs_only_its_own_code() -> None:
    base = FB_Base()
    base()
    base.meth_do_it()
    base()
    assert base.i_cnt == 12


def test_this_in_base_code_dispatches_to_the_derived_override() -> None:
    base, derived = FB_Base(), FB_1()
    base.meth_do_twice()
    derived.meth_do_twice()
    assert (base.i_cnt, derived.i_cnt) == (20, 220)


def test_a_reference_typed_as_the_base_calls_the_derived_method() -> None:
    blocks: list[FB_Base] = [FB_Base(), FB_1()]
    for block in blocks:
        block.meth_do_it()
    assert [b.i_cnt for b in blocks] == [10, 110]


def test_the_counter_wraps_after_enough_cycles_like_an_int() -> None:
    main = MAIN()
    for _ in range(300):
        main()
    assert main.i_fb1_cnt == wrap_int(121 * 300)
    assert main.i_fb1_cnt < 0
    assert main.i_base_cnt == 300


# ---------------------------------------------------------------------------
# FB_Engine and FB_NewEngine
# ---------------------------------------------------------------------------


class I_Engine(Interface):
    """ST::

        INTERFACE I_Engine
        METHOD Start
        VAR_INPUT gear : INT := 2; velocity : LREAL := 8.0; END_VAR
    """

    @method
    def start(self, gear: INT = 2, velocity: LREAL = 8.0) -> None: ...


class FB_Engine(FunctionBlock, I_Engine):
    """ST::

        FUNCTION_BLOCK FB_Engine IMPLEMENTS I_Engine
        VAR_INPUT  MaxVelocity : LREAL := 10.0; END_VAR
        VAR_OUTPUT Running : BOOL; Odometer : LREAL; END_VAR
        VAR        VelocityInternal : LREAL; RampSteps : INT; END_VAR
        IF Running THEN Odometer := Odometer + VelocityInternal; END_IF

        METHOD Start
        VelocityInternal := MIN(velocity, MaxVelocity);
        Running := TRUE;
        Ramp();

        METHOD Stop
        Running := FALSE;
        VelocityInternal := 0;

        METHOD PROTECTED Ramp
        RampSteps := RampSteps + 1;
    """

    max_velocity: LREAL = VAR_INPUT(10.0)
    running: BOOL = VAR_OUTPUT(False)
    odometer: LREAL = VAR_OUTPUT(0.0)
    velocity_internal: LREAL = VAR(0.0)
    ramp_steps: INT = VAR(0)

    def body(self) -> None:
        if self.running:
            self.odometer += self.velocity_internal

    @method
    def start(self, gear: INT = 2, velocity: LREAL = 8.0) -> None:
        self.velocity_internal = min(velocity, self.max_velocity)
        self.running = True
        self.ramp()

    @method
    def stop(self) -> None:
        self.running = False
        self.velocity_internal = 0.0

    @method(PROTECTED)
    def ramp(self) -> None:
        self.ramp_steps += 1


class FB_NewEngine(FB_Engine):
    """ST::

        FUNCTION_BLOCK FB_NewEngine EXTENDS FB_Engine
        VAR GearInternal : INT; END_VAR

        PROPERTY Gear : INT
          Get: Gear := GearInternal;
          Set: GearInternal := Gear;

        METHOD Start
        SUPER^.Start(gear := gear, velocity := velocity);
        THIS^.Gear := gear;
        Ramp();
    """

    gear_internal: INT = VAR(0)

    @prop
    def gear(self) -> INT:
        return self.gear_internal

    @gear.setter
    def gear(self, value: INT) -> None:
        self.gear_internal = value

    @method
    def start(self, gear: INT = 2, velocity: LREAL = 8.0) -> None:
        super().start(gear, velocity)
        self.gear = gear
        self.ramp()


class Driver(Program):
    """ST::

        PROGRAM Driver
        VAR_INPUT engine : I_Engine; cmdStart : BOOL; END_VAR
        VAR started : BOOL; END_VAR
        IF cmdStart AND NOT started THEN engine.Start(); started := TRUE; END_IF
    """

    engine: I_Engine = VAR_INPUT()
    cmd_start: BOOL = VAR_INPUT(False)
    started: BOOL = VAR(False)

    def body(self) -> None:
        if self.cmd_start and not self.started:
            self.engine.start()
            self.started = True


def test_engine_start_with_default_inputs_runs_at_8() -> None:
    engine = FB_Engine()
    engine.start()
    for _ in range(5):
        engine()
    assert engine.running is True
    assert engine.velocity_internal == 8.0
    assert engine.odometer == 40.0
    engine.stop()
    engine()
    assert (engine.running, engine.odometer) == (False, 40.0)


def test_engine_velocity_is_clamped_to_max_velocity() -> None:
    engine = FB_Engine()
    engine.start(velocity=25.0)
    assert engine.velocity_internal == 10.0
    engine(max_velocity=30.0)
    engine.start(3, 25.0)
    assert engine.velocity_internal == 25.0
    engine()
    assert engine.odometer == 10.0 + 25.0


def test_new_engine_extends_start_with_the_gear_property() -> None:
    engine = FB_NewEngine()
    assert engine.gear == 0
    engine.start()
    assert (engine.gear, engine.velocity_internal, engine.running) == (2, 8.0, True)
    engine.start(gear=4, velocity=9.5)
    assert (engine.gear, engine.velocity_internal) == (4, 9.5)
    engine.start(5)
    assert (engine.gear, engine.velocity_internal) == (5, 8.0)
    engine.gear = 1
    assert engine.gear == 1
    assert engine.ramp_steps == 6


def test_the_protected_ramp_is_not_callable_from_outside() -> None:
    engine = FB_NewEngine()
    with pytest.raises(AccessError, match=r"PROTECTED METHOD FB_Engine\.ramp cannot be called from"):
        engine.ramp()
    assert engine.ramp_steps == 0


def test_a_program_starts_the_new_engine_through_the_interface() -> None:
    engine = FB_NewEngine()
    driver = Driver()
    driver(engine=engine)
    assert engine.running is False
    for _ in range(3):
        driver(cmd_start=True)
        engine()
    assert (engine.gear, engine.running, engine.odometer) == (2, True, 24.0)
    assert engine.ramp_steps == 2


# ---------------------------------------------------------------------------
# The access-specifier table
# ---------------------------------------------------------------------------


class FB_Access(FunctionBlock):
    """ST::

        FUNCTION_BLOCK FB_Access
        METHOD PUBLIC    M_Public    : INT   M_Public    := 1;
        METHOD PRIVATE   M_Private   : INT   M_Private   := 2;
        METHOD PROTECTED M_Protected : INT   M_Protected := 3;
        METHOD INTERNAL  M_Internal  : INT   M_Internal  := 4;
    """

    @method
    def m_public(self) -> INT:
        return 1

    @method(PRIVATE)
    def m_private(self) -> INT:
        return 2

    @method(PROTECTED)
    def m_protected(self) -> INT:
        return 3

    @method(INTERNAL)
    def m_internal(self) -> INT:
        return 4

    @method
    def call_from_inside(self, name: str) -> INT:
        member: Callable[[], INT] = getattr(self, name)
        return member()


class FB_AccessChild(FB_Access):
    @method
    def call_from_subclass(self, name: str) -> INT:
        member: Callable[[], INT] = getattr(self, name)
        return member()


_OTHER_NAMESPACE = '''
from iecoop import FunctionBlock, method


def call(block, name):
    return getattr(block, name)()


def derive(base):
    class ForeignChild(base):
        @method
        def call_from_subclass(self, name: str):
            return getattr(self, name)()

    return ForeignChild
'''


@pytest.fixture(scope="module")
def other_namespace(tmp_path_factory: pytest.TempPathFactory) -> Iterator[ModuleType]:
    """A second top-level package: INTERNAL's namespace is the top-level package."""
    root = tmp_path_factory.mktemp("namespace")
    name = f"otherlib_{uuid.uuid4().hex[:8]}"
    (root / name).mkdir()
    (root / name / "__init__.py").write_text(_OTHER_NAMESPACE)
    sys.path.insert(0, str(root))
    try:
        yield importlib.import_module(name)
    finally:
        sys.path.remove(str(root))
        sys.modules.pop(name, None)


MEMBERS = {"PUBLIC": "m_public", "PRIVATE": "m_private", "PROTECTED": "m_protected", "INTERNAL": "m_internal"}
RESULTS = {"m_public": 1, "m_private": 2, "m_protected": 3, "m_internal": 4}

#: The course's table: may the member be called from ...?
ACCESS_TABLE = {
    #             inside  subclass  outside  subclass elsewhere  other namespace
    "PUBLIC":    (True,   True,     True,    True,               True),
    "PRIVATE":   (True,   False,    False,   False,              False),
    "PROTECTED": (True,   True,     False,   True,               False),
    "INTERNAL":  (True,   True,     True,    False,              False),
}
PLACES = ("inside", "subclass", "outside", "subclass elsewhere", "other namespace")


def _caller(place: str, other: ModuleType) -> Callable[[str], INT]:
    if place == "inside":
        return FB_Access().call_from_inside
    if place == "subclass":
        return FB_AccessChild().call_from_subclass
    if place == "outside":
        return lambda name: int(getattr(FB_Access(), name)())
    if place == "subclass elsewhere":
        return lambda name: int(other.derive(FB_Access)().call_from_subclass(name))
    return lambda name: int(other.call(FB_Access(), name))


@pytest.mark.parametrize("specifier", list(ACCESS_TABLE))
@pytest.mark.parametrize("place", PLACES)
def test_access_specifier_table(specifier: str, place: str, other_namespace: ModuleType) -> None:
    name = MEMBERS[specifier]
    call = _caller(place, other_namespace)
    if ACCESS_TABLE[specifier][PLACES.index(place)]:
        assert call(name) == RESULTS[name]
    else:
        with pytest.raises(AccessError, match=rf"{specifier} METHOD FB_Access\.{name} cannot be called from"):
            call(name)

