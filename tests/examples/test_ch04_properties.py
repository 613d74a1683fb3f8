"""Chapter 4: FB_Tank's properties: a checked Set, read-only and computed Gets, a PRIVATE Set."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from iecoop_examples.ch04_properties import Main, Tank, main
from iecoop import AccessError, T
from iecoop.runtime import Runtime, Task


def _model_level(level: float, setpoint: float) -> float:
    if level < setpoint:
        return min(level + 2.0, setpoint)
    if level > setpoint:
        return max(level - 2.0, setpoint)
    return level


def test_the_level_follows_the_setpoint_cycle_by_cycle() -> None:
    program = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    level = 0.0
    for cycle in range(1, 61):
        rt.run(cycles=1)
        setpoint = 100.0 if cycle < 30 else 40.0
        level = _model_level(level, setpoint)
        assert program.tank.setpoint == setpoint
        assert program.tank.level == level
        assert program.tank.volume == level * 2000.0 / 100.0
    assert (program.tank.level, program.tank.volume, rt.time_ms) == (40.0, 800.0, 600)


@given(st.floats(width=32, allow_nan=False, allow_infinity=False))
def test_the_set_accessor_clamps_any_setpoint_to_0_100(value: float) -> None:
    tank = Tank()
    tank.setpoint = value
    assert tank.setpoint == max(0.0, min(value, 100.0))
    assert 0.0 <= tank.setpoint <= 100.0


def test_the_get_accessor_runs_at_every_read() -> None:
    tank = Tank(capacity=500.0)
    readings = []
    for _ in range(3):
        tank()
        readings.append(tank.volume)
    assert readings == [10.0, 20.0, 30.0]


def test_a_property_without_set_is_read_only() -> None:
    tank = Tank()
    for name in ("level", "volume"):
        with pytest.raises(AttributeError, match=f"PROPERTY Tank\\.{name} has no Set accessor: it is read-only"):
            setattr(tank, name, 10.0)


def test_the_private_set_is_used_by_fb_init_only() -> None:
    assert Tank().capacity == 1000.0
    assert Tank(capacity=2000.0).capacity == 2000.0
    assert Tank(capacity=-5.0).capacity == 0.0
    assert Main().tank.capacity == 2000.0
    tank = Tank()
    with pytest.raises(
        AccessError,
        match=r"PRIVATE PROPERTY Tank\.capacity \(Set\) cannot be called from .*: PRIVATE members are callable only",
    ):
        tank.capacity = 5000.0
    assert tank.capacity == 1000.0


def test_main_prints_the_three_samples_and_both_refusals(capsys: pytest.CaptureFixture[str]) -> None:
    main()
    out = capsys.readouterr().out
    assert "t=500 ms  Setpoint=40.0 %  Level=40.0 %  Volume=800.0 l of 2000.0 l" in out
    assert "has no Set accessor" in out
    assert "AccessError: PRIVATE PROPERTY Tank.capacity (Set)" in out
