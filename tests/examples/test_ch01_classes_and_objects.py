"""Chapter 1: the FB_Car class and its three objects, cycle by cycle."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop_examples.ch01_classes_and_objects import Car, Main, main
from iecoop import T, adr, sizeof
from iecoop.runtime import Runtime, Task

COMMANDS = ("accelerate", "drive", "brake")


def _runtime(program: Main) -> Runtime:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    return rt


def test_the_first_cycle_sets_every_objects_properties() -> None:
    program = Main()
    assert [car.brand for car in (program.mercedes, program.bmw, program.audi)] == ["", "", ""]
    _runtime(program).run(cycles=1)
    assert [(car.brand, car.color) for car in (program.mercedes, program.bmw, program.audi)] == [
        ("Mercedes", "black"),
        ("BMW", "white"),
        ("Audi", "red"),
    ]
    assert program.color == "black"


@pytest.mark.parametrize("command", COMMANDS)
def test_a_command_reaches_the_mercedes_only_and_is_reset(command: str) -> None:
    program = Main()
    rt = _runtime(program)
    setattr(program, command, True)
    rt.run(cycles=1)
    assert program.mercedes.last_action == command
    assert (program.bmw.last_action, program.audi.last_action) == ("", "")
    assert getattr(program, command) is False
    rt.run(cycles=5)
    assert program.mercedes.last_action == command  # the object keeps its state between cycles


@settings(max_examples=50)
@given(st.lists(st.sets(st.sampled_from(COMMANDS)), max_size=20))
def test_the_last_command_executed_is_the_action(cycles: list[set[str]]) -> None:
    program = Main()
    rt = _runtime(program)
    expected = ""
    for commands in cycles:
        for command in commands:
            setattr(program, command, True)
        rt.run(cycles=1)
        # MAIN tests the flags in the order Accelerate, Drive, Brake: the last one given wins.
        for command in COMMANDS:
            if command in commands:
                expected = command
        assert program.mercedes.last_action == expected
        assert not (program.accelerate or program.drive or program.brake)
    assert (program.bmw.last_action, program.audi.last_action) == ("", "")


def test_the_properties_read_and_write_the_objects_own_data() -> None:
    first, second = Car(), Car()
    first.brand, first.color = "Seat", "blue"
    assert (first.brand, first.color, first.brand_internal) == ("Seat", "blue", "Seat")
    assert (second.brand, second.color) == ("", "")


def test_each_object_is_its_own_block_of_memory() -> None:
    program = Main()
    assert sizeof(Car) == 256  # three STRING(80) of 81 bytes after the 8-byte header, rounded up
    assert adr(program.bmw) - adr(program.mercedes) == sizeof(Car)
    assert adr(program.audi) - adr(program.bmw) == sizeof(Car)
    assert program.mercedes != program.bmw


def test_main_prints_the_three_commands(capsys: pytest.CaptureFixture[str]) -> None:
    main()
    out = capsys.readouterr().out
    assert "t=40 ms  bBrake       Mercedes black: 'brake'  BMW white: ''  Audi red: ''" in out
    assert "the command flags are FALSE again: True" in out
