"""Abstract Factory: I/O module families, INTERNAL concrete modules, checked across cycles."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import REAL, AccessError, DefinitionError, ExceptionCode, PlcException, T, adr, method, new
from iecoop.runtime import Runtime, Task
from patterns.creational.abstract_factory import (
    EC_STATUS_ERROR,
    PN_OVERFLOW,
    BusImage,
    EcDigitalInput,
    EtherCatFactory,
    IAnalogInput,
    IoError,
    IoFactory,
    IoModule,
    PnAnalogInput,
    ProfinetFactory,
    TankFarmMain,
)


def running_farm() -> tuple[TankFarmMain, Runtime]:
    farm = TankFarmMain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), farm)
    rt.run(cycles=1)
    assert farm.ready
    return farm, rt


def set_level(farm: TankFarmMain, metres: float) -> None:
    """The field side: each family's analog module reports the level in its own format."""
    farm.ec_bus.inputs[farm.tank_a.level_sensor.address + 1] = round(metres / 4.0 * 32767)
    farm.pn_bus.inputs[farm.tank_b.level_sensor.address] = round(metres / 4.0 * 27648)


def test_each_family_lays_its_modules_out_its_own_way() -> None:
    farm, _rt = running_farm()
    a, b = farm.tank_a, farm.tank_b
    # EtherCAT analog: status + value (2 words), so the DI follows at word 2; PROFINET analog is one word.
    assert (a.level_sensor.address, a.high_switch.address, a.pump.address) == (0, 2, 0)
    assert (b.level_sensor.address, b.high_switch.address, b.pump.address) == (0, 1, 0)
    assert (farm.ethercat.family, farm.profinet.family) == ("EtherCAT", "PROFINET")
    assert type(farm.ethercat.ai[1]).__name__ == "EcAnalogInput"
    assert type(farm.profinet.ai[1]).__name__ == "PnAnalogInput"


def test_the_same_cell_code_fills_both_tanks_with_hysteresis_across_cycles() -> None:
    farm, rt = running_farm()
    seen = []
    for level in (0.5, 2.0, 3.2, 2.0, 0.9, 2.5):
        set_level(farm, level)
        rt.run(cycles=3)
        assert farm.tank_a.level == pytest.approx(level, abs=1e-3)
        assert farm.tank_b.level == pytest.approx(level, abs=1e-3)
        assert farm.tank_a.pump_on == farm.tank_b.pump_on
        seen.append(farm.tank_a.pump_on)
        # The pump bit is channel 0: bit 0 on little-endian EtherCAT, bit 8 on big-endian PROFINET.
        assert farm.ec_bus.outputs[0] == (0x0001 if farm.tank_a.pump_on else 0)
        assert farm.pn_bus.outputs[0] == (0x0100 if farm.tank_b.pump_on else 0)
    assert seen == [True, True, False, False, True, True]


def test_the_high_level_switch_is_read_in_each_familys_bit_order() -> None:
    farm, rt = running_farm()
    set_level(farm, 0.5)
    ec_di, pn_di = farm.tank_a.high_switch.address, farm.tank_b.high_switch.address
    farm.ec_bus.inputs[ec_di] = 0x0001
    farm.pn_bus.inputs[pn_di] = 0x0001  # EtherCAT's encoding is not PROFINET's channel 0
    rt.run(cycles=1)
    assert (farm.tank_a.pump_on, farm.tank_b.pump_on) == (False, True)
    farm.pn_bus.inputs[pn_di] = 0x0100
    rt.run(cycles=1)
    assert (farm.tank_a.pump_on, farm.tank_b.pump_on) == (False, False)


def test_a_wire_break_in_either_format_stops_the_pump() -> None:
    farm, rt = running_farm()
    set_level(farm, 0.5)
    rt.run(cycles=1)
    assert farm.tank_a.pump_on and farm.tank_b.pump_on
    farm.ec_bus.inputs[farm.tank_a.level_sensor.address] = EC_STATUS_ERROR
    farm.pn_bus.inputs[farm.tank_b.level_sensor.address] = PN_OVERFLOW
    rt.run(cycles=1)
    assert (farm.tank_a.fault, farm.tank_b.fault) == (True, True)
    assert (farm.tank_a.pump_on, farm.tank_b.pump_on) == (False, False)
    assert (farm.ec_bus.outputs[0], farm.pn_bus.outputs[0]) == (0, 0)


def test_concrete_modules_cannot_be_created_outside_the_package() -> None:
    with pytest.raises(AccessError, match=r"INTERNAL FUNCTION_BLOCK EcDigitalInput cannot be instantiated from .*outside the package 'patterns'"):
        EcDigitalInput()
    with pytest.raises(AccessError, match=r"INTERNAL PnAnalogInput cannot be created from"):
        new(PnAnalogInput)


def test_only_the_factories_bind_a_module_to_an_address() -> None:
    farm, _rt = running_farm()
    module = farm.ethercat.di[1]
    with pytest.raises(AccessError, match=r"INTERNAL METHOD IoModule\.bind cannot be called from .*only inside the package 'patterns'"):
        module.bind(adr(farm, "pn_bus"), 3)
    assert module.address == 2


def test_an_internal_module_cannot_be_extended_outside_the_package() -> None:
    with pytest.raises(DefinitionError, match=r"FUNCTION_BLOCK SpoofedModule cannot EXTEND INTERNAL IoModule outside the package 'patterns'"):

        class SpoofedModule(IoModule):
            pass


def test_the_abstract_factory_cannot_be_instantiated_or_half_implemented() -> None:
    with pytest.raises(DefinitionError, match=r"ABSTRACT FUNCTION_BLOCK IoFactory cannot be instantiated"):
        IoFactory()
    with pytest.raises(DefinitionError, match=r"FUNCTION_BLOCK AnalogOnly must be ABSTRACT or implement PUBLIC METHOD IoFactory\.create_di"):

        class AnalogOnly(IoFactory):
            @method
            def create_ai(self, low: REAL, high: REAL) -> IAnalogInput:
                return self.NO_AI


def test_a_factory_without_an_image_returns_0_and_says_why() -> None:
    factory = EtherCatFactory()
    module = factory.create_di()
    assert not module and factory.error == IoError.NO_IMAGE
    with pytest.raises(PlcException, match=r"IDigitalInput\.read called through a null interface") as info:
        module.read(0)
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION


def test_pool_and_image_exhaustion_are_reported() -> None:
    bus = BusImage()
    factory = ProfinetFactory()
    factory(image=adr(bus))
    assert factory.create_do() and factory.create_do()
    assert not factory.create_do() and factory.error == IoError.POOL_FULL
    ethercat, ec_bus = EtherCatFactory(), BusImage()
    ethercat(image=adr(ec_bus))
    assert ethercat.create_ai(0.0, 1.0) and ethercat.create_ai(0.0, 1.0)  # four of the four input words
    assert not ethercat.create_di() and ethercat.error == IoError.IMAGE_FULL


def test_a_channel_outside_the_module_is_an_array_bounds_fault() -> None:
    farm, _rt = running_farm()
    for channel in (8, -1):
        with pytest.raises(PlcException, match=rf"index {channel} outside ARRAY\[0\.\.7\] OF WORD") as info:
            farm.tank_a.high_switch.read(channel)
        assert info.value.code == ExceptionCode.RTSEXCPT_ARRAYBOUNDS


@settings(max_examples=100, deadline=None)
@given(st.integers(min_value=0, max_value=255))
def test_both_families_decode_and_encode_the_same_channels(pattern: int) -> None:
    ec_bus, pn_bus = BusImage(), BusImage()
    ec, pn = EtherCatFactory(), ProfinetFactory()
    ec(image=adr(ec_bus))
    pn(image=adr(pn_bus))
    ec_in, pn_in, ec_out, pn_out = ec.create_di(), pn.create_di(), ec.create_do(), pn.create_do()
    ec_bus.inputs[0] = pattern  # little-endian: the byte is the low byte of the WORD
    pn_bus.inputs[0] = pattern << 8  # big-endian: the same byte arrives as the high byte
    channels = [bool(pattern >> n & 1) for n in range(8)]
    assert [ec_in.read(n) for n in range(8)] == channels
    assert [pn_in.read(n) for n in range(8)] == channels
    for n, value in enumerate(channels):
        ec_out.write(n, value)
        pn_out.write(n, value)
    assert (ec_bus.outputs[0], pn_bus.outputs[0]) == (pattern, pattern << 8)
