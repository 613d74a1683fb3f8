"""ISP: the fat interface's stubs and what they do to its clients; the small interfaces' clients take what they use."""

from __future__ import annotations

from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import BOOL, VAR_OUTPUT, DefinitionError, ExceptionCode, FunctionBlock, PlcException, T, method, prop
from iecoop import query_interface
from iecoop.runtime import Runtime, Task
from patterns.solid.isp import (
    ERR_WIRE_BREAK,
    SLOTS,
    ContactorFan,
    DiagnosticScanner,
    FatContactorFan,
    FatTemperatureTransmitter,
    IDiagnosable,
    IFieldDevice,
    IParameterisable,
    IspCell,
    IStartable,
    ParameterDownload,
    StartSequencer,
    TemperatureTransmitter,
    VfdPump,
)


def _cell() -> tuple[Runtime, IspCell]:
    cell = IspCell()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), cell)
    return rt, cell


# ---------------------------------------------------------------------------
# What goes wrong in the violating design
# ---------------------------------------------------------------------------


def test_the_fat_interface_forces_stubs_that_do_nothing_or_refuse() -> None:
    fan, transmitter = FatContactorFan(), FatTemperatureTransmitter()
    assert fan.write_parameter(1, 20.0) is False
    assert fan.read_parameter(1) == fan.read_parameter(2) == 0.0  # made-up values, whatever was "written"
    assert fan.error_code() == 0  # "healthy", although nothing was checked
    assert transmitter.start() is False
    transmitter.stop()
    assert transmitter.running is False
    # The parts each device can really do work.
    assert fan.start() is True and fan.running is True
    assert transmitter.write_parameter(2, 120.0) is True and transmitter.read_parameter(2) == 120.0


def test_the_fat_start_sequence_aborts_at_the_transmitter_and_never_starts_the_fan() -> None:
    rt, cell = _cell()
    cell.start_request = True
    rt.run(cycles=1)
    assert (cell.fat_pump.q_run, cell.fat_sequencer.started, cell.fat_sequencer.failed_slot) == (True, 1, 0)
    rt.run(cycles=49)  # t = 10 .. 490 ms: waiting for the step delay
    assert cell.fat_sequencer.failed_slot == 0
    rt.run(cycles=1)  # t = 500 ms: the transmitter's stub answers FALSE
    assert (cell.fat_sequencer.failed_slot, cell.fat_sequencer.done) == (2, False)
    rt.run(duration=T("3s"))
    assert (cell.fat_fan.q_contactor, cell.fat_sequencer.started) == (False, 1)
    # The compliant sequence over the same devices started both motors.
    assert (cell.pump.q_run, cell.fan.q_contactor, cell.sequencer.done) == (True, True, True)


def test_the_fat_diagnostic_page_counts_the_fan_stub_as_healthy() -> None:
    rt, cell = _cell()
    rt.run(cycles=1)
    assert (cell.fat_scanner.healthy, cell.fat_scanner.count) == (3, 3)
    cell.fat_transmitter.raw_in = cell.transmitter.raw_in = 32767
    rt.run(cycles=1)
    assert (cell.fat_scanner.healthy, cell.fat_scanner.first_fault_slot) == (2, 2)
    assert (cell.scanner.healthy, cell.scanner.count, cell.scanner.first_fault_code) == (1, 2, ERR_WIRE_BREAK)


def test_a_double_for_a_fat_client_must_implement_all_six_members() -> None:
    missing = r"no implementation for method 'error_code' defined in interface 'IFieldDevice'"
    with pytest.raises(DefinitionError, match=missing):

        class FakeFieldDevice(FunctionBlock, IFieldDevice):
            started: BOOL = VAR_OUTPUT(False)

            @method
            def start(self) -> BOOL:
                self.started = True
                return True

            @method
            def stop(self) -> None:
                self.started = False

            @prop
            def running(self) -> BOOL:
                return self.started


def test_a_double_for_the_small_client_implements_three_members() -> None:
    class FakeStartable(FunctionBlock, IStartable):
        started: BOOL = VAR_OUTPUT(False)

        @method
        def start(self) -> BOOL:
            self.started = True
            return True

        @method
        def stop(self) -> None:
            self.started = False

        @prop
        def running(self) -> BOOL:
            return self.started

    fakes = [FakeStartable(), FakeStartable()]
    sequencer = StartSequencer()
    for fake in fakes:
        sequencer.register(fake)
    for _ in range(3):
        sequencer(request=True, step_delay=T("0ms"))
    assert [f.running for f in fakes] == [True, True] and sequencer.done
    sequencer(request=False)
    assert [f.running for f in fakes] == [False, False]


# ---------------------------------------------------------------------------
# What holds in the compliant design
# ---------------------------------------------------------------------------


def test_devices_join_only_the_clients_whose_interface_they_implement() -> None:
    _rt, cell = _cell()
    assert (cell.sequencer.count, cell.scanner.count, cell.download.count) == (2, 2, 2)
    assert query_interface(cell.fan, IDiagnosable) is None
    assert query_interface(cell.fan, IParameterisable) is None
    assert query_interface(cell.transmitter, IStartable) is None
    assert all(query_interface(cell.pump, i) is not None for i in (IStartable, IDiagnosable, IParameterisable))
    not_startable: Any = cell.transmitter
    with pytest.raises(TypeError, match=r"TemperatureTransmitter does not implement IStartable"):
        StartSequencer().register(not_startable)


def test_the_compliant_sequence_starts_one_device_per_step_and_stops_in_reverse() -> None:
    rt, cell = _cell()
    cell.start_request = True
    rt.run(cycles=50)  # t = 0 .. 490 ms
    assert (cell.pump.q_run, cell.fan.q_contactor) == (True, False)
    rt.run(cycles=1)  # t = 500 ms
    assert (cell.fan.q_contactor, cell.sequencer.done, rt.time_ms) == (True, True, 510)
    cell.start_request = False
    rt.run(cycles=1)
    assert (cell.pump.q_run, cell.fan.q_contactor, cell.sequencer.started) == (False, False, 0)


def test_a_real_refusal_still_aborts_the_compliant_sequence() -> None:
    rt, cell = _cell()
    cell.pump.vfd_fault = 0x2310  # overcurrent
    cell.start_request = True
    rt.run(duration=T("2s"))
    assert (cell.sequencer.failed_slot, cell.sequencer.started, cell.fan.q_contactor) == (1, 0, False)
    assert (cell.scanner.first_fault_slot, cell.scanner.first_fault_code) == (1, 0x2310)


def test_the_parameter_download_writes_rows_and_reports_the_first_refusal() -> None:
    _rt, cell = _cell()
    download = cell.download
    download.add_row(1, 1, 8.0)
    download.add_row(2, 2, 120.0)
    download.add_row(1, 3, 1.0)  # the pump has no parameter 3
    download.add_row(1, 2, -5.0)  # nor negative speeds
    assert download.download() == 2
    assert (download.accepted, download.first_refused) == (2, 3)
    assert (cell.pump.read_parameter(1), cell.transmitter.read_parameter(2)) == (8.0, 120.0)
    assert cell.pump.read_parameter(2) == 100.0
    # A row for a slot with no device, or past the table, is refused with 0 and changes nothing.
    assert (download.add_row(3, 1, 1.0), download.add_row(0, 1, 1.0), download.rows) == (0, 0, 4)
    assert [download.add_row(2, 3, 0.5) for _ in range(SLOTS - download.rows)] == list(range(5, SLOTS + 1))
    assert (download.add_row(2, 3, 0.5), download.rows) == (0, SLOTS)
    assert download.download() == 6 and download.first_refused == 3


def test_every_client_pool_is_bounded() -> None:
    fans = [ContactorFan() for _ in range(SLOTS + 1)]
    sequencer, scanner = StartSequencer(), DiagnosticScanner()
    assert [sequencer.register(f) for f in fans[:SLOTS]] == list(range(1, SLOTS + 1))
    # A ninth device indexes past ARRAY[1..8]: the PLC's own bounds fault, before the count moves.
    with pytest.raises(PlcException, match=r"index 9 outside ARRAY\[1\.\.8\] OF IStartable") as info:
        sequencer.register(fans[SLOTS])
    assert info.value.code == ExceptionCode.RTSEXCPT_ARRAYBOUNDS and sequencer.count == SLOTS
    for _ in range(SLOTS):
        scanner.register(TemperatureTransmitter())
    with pytest.raises(PlcException, match=r"index 9 outside ARRAY\[1\.\.8\] OF IDiagnosable"):
        scanner.register(VfdPump())
    assert scanner.count == SLOTS


KINDS = {"pump": VfdPump, "fan": ContactorFan, "transmitter": TemperatureTransmitter}


@settings(max_examples=60, deadline=None)
@given(st.lists(st.sampled_from(sorted(KINDS)), max_size=SLOTS))
def test_each_client_gets_exactly_the_devices_that_implement_its_interface(kinds: list[str]) -> None:
    devices = [KINDS[k]() for k in kinds]
    sequencer, scanner, download = StartSequencer(), DiagnosticScanner(), ParameterDownload()
    for device in devices:
        startable = query_interface(device, IStartable)
        if startable is not None:
            sequencer.register(startable)
        diagnosable = query_interface(device, IDiagnosable)
        if diagnosable is not None:
            scanner.register(diagnosable)
        parameterisable = query_interface(device, IParameterisable)
        if parameterisable is not None:
            download.register(parameterisable)
    assert sequencer.count == kinds.count("pump") + kinds.count("fan")
    assert scanner.count == download.count == kinds.count("pump") + kinds.count("transmitter")
    for _ in range(sequencer.count + 1):
        sequencer(request=True, step_delay=T("0ms"))
        scanner()
    assert sequencer.done and sequencer.failed_slot == 0
    assert all(d.running for d in devices if isinstance(d, (VfdPump, ContactorFan)))
    assert scanner.healthy == scanner.count
