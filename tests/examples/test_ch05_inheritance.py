"""Chapter 5: FB_NewEngine EXTENDS FB_Engine, run by MAIN through I_Engine."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from iecoop_examples.ch05_inheritance import Engine, IEngine, Main, NewEngine, main
from iecoop import BOOL, FINAL, INT, LREAL, PROTECTED, VAR, VAR_INPUT, AccessError, DefinitionError, Program, T, method
from iecoop.runtime import Runtime, Task


def test_both_engines_cycle_by_cycle() -> None:
    program = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    for cycle in range(1, 11):
        rt.run(cycles=1)
        # Start(1, 7.5) in cycle 1; Stop() at cycle 6 comes before the body.
        expected = 7.5 * min(cycle, 5)
        for engine in (program.engine, program.new_engine):
            assert engine.odometer == expected
            assert engine.running is (cycle < 6)
    assert (program.engine.ramp_steps, program.new_engine.ramp_steps) == (1, 2)
    assert program.new_engine.gear == 1


def test_the_interface_call_reaches_the_most_derived_start() -> None:
    program = Main()
    program()
    assert isinstance(program.engines[2], NewEngine)
    assert program.engines[2] == program.new_engine
    assert program.new_engine.gear == 1  # only FB_NewEngine.Start sets the gear


def test_new_engine_extends_start_with_the_gear_property() -> None:
    engine = NewEngine()
    assert engine.gear == 0
    engine.start()
    assert (engine.gear, engine.velocity_internal, engine.running, engine.ramp_steps) == (2, 8.0, True, 2)
    engine.start(gear=4, velocity=9.5)
    assert (engine.gear, engine.velocity_internal, engine.ramp_steps) == (4, 9.5, 4)
    engine.start(5)  # the velocity keeps its default
    assert (engine.gear, engine.velocity_internal, engine.ramp_steps) == (5, 8.0, 6)
    engine.gear = 1
    assert (engine.gear, engine.gear_internal) == (1, 1)


def test_the_base_start_defaults_to_velocity_8_and_stop_halts_the_odometer() -> None:
    engine = Engine()
    engine.start()
    for _ in range(5):
        engine()
    assert (engine.running, engine.velocity_internal, engine.odometer) == (True, 8.0, 40.0)
    engine.stop()
    engine()
    assert (engine.running, engine.velocity_internal, engine.odometer) == (False, 0.0, 40.0)


def test_the_base_alone_has_no_gear_and_ramps_once() -> None:
    engine = Engine()
    engine.start(gear=5, velocity=3.0)
    assert (engine.velocity_internal, engine.ramp_steps) == (3.0, 1)
    assert not hasattr(engine, "gear")


@given(st.floats(min_value=0.0, max_value=1000.0), st.floats(min_value=0.0, max_value=1000.0))
def test_start_clamps_to_max_velocity_in_base_and_derived(velocity: float, max_velocity: float) -> None:
    for engine in (Engine(), NewEngine()):
        engine(max_velocity=max_velocity)
        engine.start(velocity=velocity)
        assert engine.velocity_internal == min(velocity, max_velocity)


def test_the_protected_ramp_is_refused_from_outside() -> None:
    engine = NewEngine()
    with pytest.raises(
        AccessError,
        match=r"PROTECTED METHOD Engine\.ramp cannot be called from .*only inside Engine and its derived blocks",
    ):
        engine.ramp()
    assert engine.ramp_steps == 0


def test_a_derived_block_may_call_the_protected_method() -> None:
    class TunedEngine(NewEngine):
        @method
        def warm_up(self) -> INT:
            self.ramp()
            return self.ramp_steps

    assert TunedEngine().warm_up() == 1


def test_an_override_must_keep_the_signature() -> None:
    with pytest.raises(
        DefinitionError,
        match=r"interface of overridden method 'start' of base 'Engine' doesn't match declaration \(C0094\)",
    ):

        class BadEngine(Engine):
            @method
            def start(self, gear: LREAL = 2.0, velocity: LREAL = 8.0) -> None: ...


def test_an_override_may_not_narrow_the_access() -> None:
    with pytest.raises(DefinitionError, match=r"start narrows the access of PUBLIC METHOD Engine\.start to PROTECTED"):

        class HiddenEngine(Engine):
            @method(PROTECTED)
            def start(self, gear: INT = 2, velocity: LREAL = 8.0) -> None: ...


def test_a_final_method_cannot_be_overridden() -> None:
    class SafeEngine(Engine):
        @method(FINAL)
        def stop(self) -> None:
            super().stop()

    with pytest.raises(DefinitionError, match=r"FINAL PUBLIC METHOD SafeEngine\.stop cannot be overridden"):

        class QuietEngine(SafeEngine):
            @method
            def stop(self) -> None: ...


def test_engines_are_interchangeable_through_the_interface() -> None:
    engines: list[IEngine] = [Engine(), NewEngine()]
    for engine in engines:
        engine.start(velocity=6.0)
    assert [e.velocity_internal for e in engines if isinstance(e, Engine)] == [6.0, 6.0]


class Driver(Program):
    """``PROGRAM Driver``: gets an engine through ``VAR_INPUT engine : I_Engine`` and starts it once."""

    engine: IEngine = VAR_INPUT()
    cmd_start: BOOL = VAR_INPUT(False)
    started: BOOL = VAR(False)

    def body(self) -> None:
        if self.cmd_start and not self.started:
            self.engine.start()
            self.started = True


def test_a_program_starts_the_new_engine_through_an_interface_input() -> None:
    engine = NewEngine()
    driver = Driver()
    driver(engine=engine)
    assert engine.running is False
    for _ in range(3):
        driver(cmd_start=True)
        engine()
    assert (engine.gear, engine.running, engine.odometer, engine.ramp_steps) == (2, True, 24.0, 2)


def test_main_prints_both_engines_and_the_three_errors(capsys: pytest.CaptureFixture[str]) -> None:
    main()
    out = capsys.readouterr().out
    assert "FB_NewEngine  Running=False  Odometer=37.5  RampSteps=2  Gear=1" in out
    assert "AccessError: PROTECTED METHOD Engine.ramp" in out
    assert "(C0094)" in out
    assert "FINAL PUBLIC METHOD SafeEngine.stop cannot be overridden" in out
