"""Bridge: any device on any channel; the channel decides latency and health, the device its logic."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import VAR, DefinitionError, ExceptionCode, PlcException, Program, T, adr
from iecoop.runtime import Runtime, Task
from patterns.structural.bridge import Device, LocalIo, ModbusTcp, Pump, SimChannel, SkidMain, Valve


def _skid() -> tuple[SkidMain, Runtime]:
    skid = SkidMain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), skid)
    return skid, rt


COMBINATIONS = [
    ("p_loc", "local I/O"),
    ("p_mb", "Modbus TCP"),
    ("p_sim", "simulated"),
    ("v_loc", "local I/O"),
    ("v_mb", "Modbus TCP"),
    ("v_sim", "simulated"),
]


@pytest.mark.parametrize(("name", "kind"), COMBINATIONS)
def test_every_device_kind_works_on_every_channel_kind(name: str, kind: str) -> None:
    skid, rt = _skid()
    device: Pump | Valve = getattr(skid, name)
    assert device.channel.kind == kind
    skid.cmd_run = True
    rt.run(cycles=30)
    if isinstance(device, Pump):
        assert device.at_speed and device.running and abs(device.feedback - 60.0) < 0.5
    else:
        assert device.is_open and not device.fault
    assert device.comm_ok
    skid.cmd_run = False
    rt.run(cycles=30)
    if isinstance(device, Pump):
        assert (device.running, device.feedback) == (False, 0.0)
    else:
        assert device.is_closed


def test_the_command_reaches_the_field_through_the_device_s_own_channel_and_point() -> None:
    skid, rt = _skid()
    skid.speed = 42.0
    skid.cmd_run = True
    rt.run(cycles=5)
    assert (skid.local.image.q[1], skid.local.image.q[2]) == (42.0, 100.0)
    assert (skid.sim.image.q[1], skid.sim.image.q[2]) == (42.0, 100.0)
    assert (skid.modbus.remote.q[1], skid.modbus.remote.q[2]) == (42.0, 100.0)
    assert list(skid.modbus.request) == [420, 1000, 0, 0]  # registers in 0.1 %


def test_modbus_latency_delays_the_command_by_whole_transactions() -> None:
    skid, rt = _skid()
    skid.cmd_run = True
    arrived = []
    for _ in range(4):
        rt.run(cycles=1)
        arrived.append((skid.local.image.q[1], skid.modbus.remote.q[1]))
    # Local I/O has the value in the first scan; the Modbus transaction completes in the third.
    assert arrived == [(60.0, 0.0), (60.0, 0.0), (60.0, 60.0), (60.0, 60.0)]
    rt.run(cycles=26)
    assert skid.p_loc.at_speed and skid.p_mb.at_speed


def test_a_lost_modbus_link_faults_only_the_devices_on_that_channel_and_recovers() -> None:
    skid, rt = _skid()
    skid.cmd_run = True
    rt.run(cycles=30)
    skid.modbus.link_up = False
    rt.run(cycles=9)
    assert not any(skid.devices[k].fault for k in range(1, 7))  # under 100 ms without an answer
    rt.run(cycles=2)
    faulted = [skid.devices[k].tag for k in range(1, 7) if skid.devices[k].fault]
    assert faulted == ["P-MB", "V-MB"]
    skid.modbus.link_up = True
    rt.run(cycles=4)
    assert not any(skid.devices[k].fault for k in range(1, 7))


def test_a_stuck_valve_latches_a_travel_fault_after_one_second_whatever_the_channel() -> None:
    skid, rt = _skid()
    skid.field_local.rate = 0.0  # nothing behind the local terminals moves
    skid.cmd_run = True
    rt.run(cycles=100)
    assert skid.v_loc.fault is False
    rt.run(cycles=2)
    assert (skid.v_loc.travel_fault, skid.v_loc.fault, skid.v_loc.comm_ok) == (True, True, True)
    assert not skid.v_mb.fault and not skid.v_sim.fault


# ---------------------------------------------------------------------------
# Injection through FB_init, and its absence
# ---------------------------------------------------------------------------


def test_a_device_gets_its_channel_and_point_through_fb_init() -> None:
    channel = SimChannel()
    pump = Pump(tag="P7", channel=channel, point=3)
    pump.start(25.0)
    for _ in range(10):
        channel.cyclic()
        pump.cyclic()
    assert channel.image.q[3] == 25.0
    assert pump.at_speed and pump.channel == channel


def test_a_device_without_a_channel_faults_with_an_access_violation() -> None:
    pump = Pump(tag="P9")
    message = r"Device\.channel_ref: IChannel\.healthy called through a null interface"
    with pytest.raises(PlcException, match=message) as info:
        pump.cyclic()
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION
    assert pump.comm_ok is False


class Unwired(Program):
    local: LocalIo = VAR()
    valve: Valve = VAR(fb_init={"tag": "V9", "point": 1})

    def body(self) -> None:
        self.valve.open()
        self.valve.cyclic()


def test_a_forgotten_injection_stops_the_task_in_its_first_cycle() -> None:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), Unwired())
    with pytest.raises(PlcException, match=r"cycle 1: .*IChannel\.healthy called through a null interface"):
        rt.run(cycles=3)
    assert rt.fault is not None and rt.fault.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


def test_the_device_abstraction_is_abstract() -> None:
    with pytest.raises(DefinitionError, match="ABSTRACT FUNCTION_BLOCK Device cannot be instantiated"):
        Device(channel=LocalIo())


def test_a_point_outside_the_channel_is_an_array_bounds_fault() -> None:
    local = LocalIo()
    pump = Pump(tag="P5", channel=local, point=5)
    with pytest.raises(PlcException) as info:
        pump.cyclic()
    assert info.value.code == ExceptionCode.RTSEXCPT_ARRAYBOUNDS


@settings(max_examples=100, deadline=None)
@given(value=st.floats(0.0, 100.0, allow_nan=False), latency=st.integers(1, 5))
def test_modbus_round_trip_is_the_value_rounded_to_a_register(value: float, latency: int) -> None:
    channel = ModbusTcp(latency=latency)
    channel.write(2, value)
    for _ in range(latency):
        channel.cyclic()
    remote = adr(channel, "remote").deref  # a loopback behind the coupler, wired through its address
    remote.i[2] = remote.q[2]
    for _ in range(latency):
        channel.cyclic()
    assert channel.healthy
    assert channel.read(2) == round(value * 10.0) / 10.0
    assert abs(channel.read(2) - value) <= 0.05 + 1e-4  # REAL precision on top of the 0.1 % register
