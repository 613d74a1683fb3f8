"""Chapter 13: the FB_Device family (inheritance) next to I_Switchable (interface)."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop_examples.ch13_interface_vs_inheritance import (
    Device,
    DimmableLamp,
    Fan,
    IDimmable,
    ISwitchable,
    Lamp,
    Main,
    Valve,
    ValveDriver,
    main,
)
from iecoop import DefinitionError, T
from iecoop.runtime import Runtime, Task


def _runtime(program: Main) -> Runtime:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    return rt


def _step(rt: Runtime, program: Main, all_on: bool = False, all_off: bool = False, dim: int = 100) -> None:
    program.all_on, program.all_off, program.dim = all_on, all_off, dim
    rt.run(cycles=1)


def test_main_switches_all_four_and_counts_the_family() -> None:
    program = Main()
    rt = _runtime(program)
    _step(rt, program, all_on=True)
    assert (program.count_on, program.switchings, program.fan.rpm, program.valve.open) == (4, 3, 1400, True)
    _step(rt, program, dim=30)
    assert (program.count_on, program.dimmer.brightness) == (4, 30)
    _step(rt, program, all_off=True, dim=30)
    assert (program.count_on, program.dimmer.brightness, program.fan.rpm, program.valve.open) == (0, 0, 0, False)
    _step(rt, program, all_on=True, dim=30)
    assert (program.count_on, program.switchings, program.dimmer.brightness) == (4, 6, 30)
    # The valve's own switchings are nowhere: it is not an FB_Device.
    assert [program.lamp.switchings, program.dimmer.switchings, program.fan.switchings] == [2, 2, 2]


def test_the_family_and_the_contract() -> None:
    lamp, dimmer, fan, valve = Lamp(), DimmableLamp(), Fan(), Valve()
    assert all(isinstance(block, Device) for block in (lamp, dimmer, fan))
    assert all(isinstance(block, ISwitchable) for block in (lamp, dimmer, fan, valve))
    assert isinstance(valve, ValveDriver) and Device not in type(valve).__mro__
    assert isinstance(dimmer, IDimmable) and not isinstance(lamp, IDimmable)


def test_the_derived_blocks_reuse_the_base_code_unchanged() -> None:
    lamp = Lamp()
    for _ in range(3):
        lamp.turn_on()
        lamp.turn_on()  # already on: not counted again
        lamp.turn_off()
    assert (lamp.switchings, lamp.is_on) == (3, False)


def test_the_pointers_to_fb_device_designate_the_derived_blocks() -> None:
    program = Main()
    program()
    assert [type(program.devices[i].deref) for i in range(1, 4)] == [Lamp, DimmableLamp, Fan]


@given(st.integers(min_value=-1000, max_value=1000))
def test_the_brightness_set_accessor_clamps_to_0_100(value: int) -> None:
    dimmer = DimmableLamp()
    dimmer.turn_on()
    dimmer.brightness = value
    assert dimmer.brightness == max(0, min(value, 100))


@settings(max_examples=40)
@given(st.lists(st.sampled_from(["on", "off", "both", "none"]), max_size=30))
def test_all_four_always_move_together_and_each_off_on_counts_once(commands: list[str]) -> None:
    program = Main()
    rt = _runtime(program)
    on, turned_on = False, 0
    for command in commands:
        _step(rt, program, all_on=command in ("on", "both"), all_off=command in ("off", "both"))
        if command in ("on", "both"):
            turned_on += not on
            on = True
        if command in ("off", "both"):
            on = False
        assert program.count_on == (4 if on else 0)
        assert program.switchings == 3 * turned_on


def test_a_block_extends_one_base_only() -> None:
    with pytest.raises(DefinitionError, match=r"EXTENDS allows one function block, got ValveDriver, Device"):

        class DeviceValve(ValveDriver, Device):
            pass


def test_main_prints_the_four_steps_and_the_error(capsys: pytest.CaptureFixture[str]) -> None:
    main()
    out = capsys.readouterr().out
    assert "t=30 ms  all on again  nOn=4" in out
    assert "EXTENDS allows one function block" in out
