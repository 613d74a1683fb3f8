"""Chapter 8: three blocks behind I_Actuator, driven by MAIN through one array."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop_examples.ch08_interfaces import IActuator, Lamp, Main, Motor, Valve, main
from iecoop import VAR_INPUT, DefinitionError, ExceptionCode, FunctionBlock, Interface, PlcException, Program, T, method
from iecoop.runtime import Runtime, Task


def _runtime(program: Main) -> Runtime:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    return rt


def _press(rt: Runtime, program: Main, start: bool = False, stop: bool = False) -> None:
    program.start_all, program.stop_all = start, stop
    rt.run(cycles=1)


def test_start_all_stop_all_cycle_by_cycle() -> None:
    program = Main()
    rt = _runtime(program)
    _press(rt, program, start=True)
    assert program.running == 2
    for cycle in range(2, 51):
        _press(rt, program)
        # The valve's TON started at t=0; cycle n runs at t=(n-1)*10 ms.
        assert program.valve.running is ((cycle - 1) * 10 >= 200)
        assert program.running == (3 if program.valve.running else 2)
    _press(rt, program, stop=True)
    assert program.running == 0
    assert [a.running for a in (program.motor, program.valve, program.lamp)] == [False, False, False]
    assert program.motor.run_cycles == 50


def test_the_array_holds_the_three_blocks_and_one_free_slot() -> None:
    program = Main()
    program()
    assert [program.actuators[i] == b for i, b in enumerate((program.motor, program.valve, program.lamp), 1)] == [
        True,
        True,
        True,
    ]
    assert isinstance(program.actuators[2], Valve)
    assert not program.actuators[4]
    assert [a.name for a in program.actuators if a] == ["motor", "valve", "lamp"]


def test_a_call_through_a_null_interface_is_an_access_violation() -> None:
    program = Main()
    null_call = r"RTSEXCPT_ACCESS_VIOLATION.*called through a null interface reference"
    with pytest.raises(PlcException, match=null_call) as info:
        program.actuators[4].start()
    assert info.value.code is ExceptionCode.RTSEXCPT_ACCESS_VIOLATION
    with pytest.raises(PlcException, match="RTSEXCPT_ACCESS_VIOLATION"):
        _ = program.actuators[1].running


def test_each_block_keeps_the_contract_its_own_way() -> None:
    actuators: list[IActuator] = [Motor(), Valve(), Lamp()]
    for actuator in actuators:
        actuator.start()
    assert [a.running for a in actuators] == [True, False, True]  # the valve is still travelling
    for actuator in actuators:
        actuator.stop()
    assert [a.running for a in actuators] == [False, False, False]


def test_only_an_implementing_block_fits_an_interface_variable() -> None:
    class Horn(FunctionBlock):
        @method
        def start(self) -> None: ...

    class Panel(Program):
        slot: IActuator = VAR_INPUT()

    panel, motor = Panel(), Motor()
    panel(slot=motor)
    assert isinstance(panel.slot, Motor)
    with pytest.raises(TypeError, match="Horn does not implement IActuator"):
        panel(slot=Horn())  # type: ignore[arg-type]


def test_an_interface_has_no_instances_no_state_and_no_bodies() -> None:
    with pytest.raises(TypeError, match="INTERFACE IActuator cannot be instantiated"):
        IActuator()
    with pytest.raises(DefinitionError, match="interfaces hold no state"):

        class IStateful(Interface):
            count: int

    with pytest.raises(DefinitionError, match="start has a body; an interface declares prototypes only"):

        class IBodied(Interface):
            @method
            def start(self) -> None:
                print("started")


@settings(max_examples=40)
@given(st.lists(st.sampled_from(["none", "start", "stop", "both"]), max_size=60))
def test_n_running_matches_a_model_of_the_three_actuators(presses: list[str]) -> None:
    program = Main()
    rt = _runtime(program)
    on, opened_at = False, None
    for cycle, press in enumerate(presses):
        start, stop = press in ("start", "both"), press in ("stop", "both")
        _press(rt, program, start, stop)
        if start:
            on = True
        if stop:
            on = False
        opened_at = (opened_at if opened_at is not None else cycle) if on else None
        valve_open = opened_at is not None and (cycle - opened_at) * 10 >= 200
        assert program.running == (2 if on else 0) + (1 if valve_open else 0)


def test_main_prints_the_changes_and_the_fault(capsys: pytest.CaptureFixture[str]) -> None:
    main()
    out = capsys.readouterr().out
    assert "t=200 ms  nRunning=3  motor valve lamp" in out
    assert "aActuators[4].Start(): RTSEXCPT_ACCESS_VIOLATION" in out
