"""Interface segregation: ``IStartable``, ``IDiagnosable`` and ``IParameterisable`` kept apart.

Principle
---------

Clients should not be forced to depend on methods they do not use (Robert C.
Martin). Many small interfaces, each one what a client needs, beat one
general-purpose interface that every implementer must fill in.

The course example
------------------

The course's birds: one ``I_Bird`` with ``Fly``, ``Swim`` and ``Run`` makes
the penguin implement ``Fly`` as an empty method and the eagle ``Swim``.
Split into ``I_Fly``, ``I_Swim`` and ``I_Run``, each bird implements what it
can, and a flight show only takes ``I_Fly``.

The PLC problem
---------------

A cell has a frequency-converter pump (it starts, reports fault codes and has
parameters), a contactor fan (it only starts) and a temperature transmitter
(diagnostics and parameters, nothing to start). One ``I_FieldDevice`` with
all six members forces the fan to answer diagnostics and parameter calls and
the transmitter to answer start and stop. The stubs do nothing or refuse, and
the clients written for ``I_FieldDevice`` cannot tell: the start sequencer
"starts" the transmitter, gets FALSE and aborts before the fan; the
diagnostic page shows the fan green although nothing was checked; a test
double for any client must implement all six members.

Violating design
----------------

- ``IFieldDevice`` (``I_FieldDevice``): start, stop, running, error code,
  parameter write and read, in one interface.
- ``FatVfdPump``, ``FatContactorFan``, ``FatTemperatureTransmitter``
  (``FB_VfdPump``, ``FB_ContactorFan``, ``FB_TemperatureTransmitter``, each
  ``IMPLEMENTS I_FieldDevice``): the last two carry stubs.
- ``FatStartSequencer``, ``FatDiagnosticScanner`` (``FB_StartSequencer``,
  ``FB_DiagnosticScanner``): clients of ``ARRAY[1..8] OF I_FieldDevice``.

Compliant design
----------------

- ``IStartable``, ``IDiagnosable``, ``IParameterisable`` (``I_Startable``,
  ``I_Diagnosable``, ``I_Parameterisable``), all ``EXTENDS
  __SYSTEM.IQueryInterface``.
- ``VfdPump`` (``FB_VfdPump``) implements the three; ``ContactorFan``
  (``FB_ContactorFan``) only ``I_Startable``; ``TemperatureTransmitter``
  (``FB_TemperatureTransmitter``) ``I_Diagnosable`` and ``I_Parameterisable``.
- ``StartSequencer``, ``DiagnosticScanner``, ``ParameterDownload``
  (``FB_StartSequencer`` ...): each holds the one interface it uses, in an
  ``ARRAY[1..8]``; the download writes a table of ``ParameterEntry``
  (``ST_ParameterEntry``) rows. ``IspCell`` (``PRG_IspCell``) registers every device with
  the clients it fits, asking ``__QUERYINTERFACE``.

IEC 61131-3 mapping
-------------------

::

    INTERFACE I_FieldDevice EXTENDS __SYSTEM.IQueryInterface   // violating
        METHOD Start : BOOL
        METHOD Stop
        PROPERTY Running : BOOL
        METHOD ErrorCode : UDINT
        METHOD WriteParameter : BOOL  VAR_INPUT index : INT; value : REAL; END_VAR
        METHOD ReadParameter : REAL   VAR_INPUT index : INT; END_VAR

    INTERFACE I_Startable EXTENDS __SYSTEM.IQueryInterface     // compliant
        METHOD Start : BOOL
        METHOD Stop
        PROPERTY Running : BOOL
    INTERFACE I_Diagnosable EXTENDS __SYSTEM.IQueryInterface
        METHOD ErrorCode : UDINT
    INTERFACE I_Parameterisable EXTENDS __SYSTEM.IQueryInterface
        METHOD WriteParameter : BOOL  VAR_INPUT index : INT; value : REAL; END_VAR
        METHOD ReadParameter : REAL   VAR_INPUT index : INT; END_VAR
    FUNCTION_BLOCK FB_VfdPump IMPLEMENTS I_Startable, I_Diagnosable, I_Parameterisable
    FUNCTION_BLOCK FB_ContactorFan IMPLEMENTS I_Startable
    FUNCTION_BLOCK FB_TemperatureTransmitter IMPLEMENTS I_Diagnosable, I_Parameterisable
    FUNCTION_BLOCK FB_StartSequencer
        VAR aDevices : ARRAY[1..8] OF I_Startable; nCount : INT; tonGap : TON; END_VAR

References
----------

- R. C. Martin, *Agile Software Development: Principles, Patterns, and
  Practices*, Prentice Hall, 2002, chapter 12 "ISP".
- IEC 61131-3:2013, 3rd edition: interfaces, a function block implementing
  several interfaces, arrays of interface references, structures.
- Beckhoff InfoSys, TwinCAT 3 PLC: "Implementing an interface",
  "__QUERYINTERFACE".
- CODESYS online help: "Implementing an interface", "Operator
  __QUERYINTERFACE".
"""

from __future__ import annotations

from typing import Any

from iecoop import (
    ARRAY,
    BOOL,
    INT,
    PRIVATE,
    REAL,
    STRING,
    TIME,
    UDINT,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    FunctionBlock,
    IQueryInterface,
    Program,
    Struct,
    T,
    method,
    prop,
    query_interface,
)
from iecoop.runtime import Runtime, Task
from iecoop.stdlib import TON
from patterns.showcase.entry import Column, Getter, Showcase, hex_word, steps

#: Slots of every client's pool: ``ARRAY[1..SLOTS] OF I_...``.
SLOTS = 8
#: The transmitter's card reports a wire break as a count above this.
WIRE_BREAK_RAW = 32500
#: ``ERR_WIRE_BREAK : UDINT := 16#A001``.
ERR_WIRE_BREAK = 0xA001


# ---------------------------------------------------------------------------
# Violating design: one fat interface for every device
# ---------------------------------------------------------------------------


class IFieldDevice(IQueryInterface):
    """``INTERFACE I_FieldDevice``: everything any device might do, for every device."""

    @method
    def start(self) -> BOOL:
        raise NotImplementedError

    @method
    def stop(self) -> None: ...

    @prop
    def running(self) -> BOOL:
        raise NotImplementedError

    @method
    def error_code(self) -> UDINT:
        raise NotImplementedError

    @method
    def write_parameter(self, index: INT, value: REAL) -> BOOL:
        raise NotImplementedError

    @method
    def read_parameter(self, index: INT) -> REAL:
        raise NotImplementedError


class FatVfdPump(FunctionBlock, IFieldDevice):
    """``FUNCTION_BLOCK FB_VfdPump IMPLEMENTS I_FieldDevice``: the one device that fills it all in."""

    tag: STRING = VAR_INPUT("P101", length=8)
    vfd_fault: UDINT = VAR_INPUT(0)
    q_run: BOOL = VAR_OUTPUT(False)
    params: ARRAY[REAL] = VAR([5.0, 100.0], bounds=(1, 2))

    @method
    def start(self) -> BOOL:
        self.q_run = self.vfd_fault == 0
        return self.q_run

    @method
    def stop(self) -> None:
        self.q_run = False

    @prop
    def running(self) -> BOOL:
        return self.q_run

    @method
    def error_code(self) -> UDINT:
        return self.vfd_fault

    @method
    def write_parameter(self, index: INT, value: REAL) -> BOOL:
        if not 1 <= index <= 2 or value < 0.0:
            return False
        self.params[index] = value
        return True

    @method
    def read_parameter(self, index: INT) -> REAL:
        return self.params[index] if 1 <= index <= 2 else 0.0


class FatContactorFan(FunctionBlock, IFieldDevice):
    """``FUNCTION_BLOCK FB_ContactorFan IMPLEMENTS I_FieldDevice``: three stubs it cannot fill."""

    tag: STRING = VAR_INPUT("F103", length=8)
    q_contactor: BOOL = VAR_OUTPUT(False)

    @method
    def start(self) -> BOOL:
        self.q_contactor = True
        return True

    @method
    def stop(self) -> None:
        self.q_contactor = False

    @prop
    def running(self) -> BOOL:
        return self.q_contactor

    @method
    def error_code(self) -> UDINT:
        return 0  # stub: nothing is checked, yet it reads as healthy

    @method
    def write_parameter(self, index: INT, value: REAL) -> BOOL:
        return False  # stub: no parameters

    @method
    def read_parameter(self, index: INT) -> REAL:
        return 0.0  # stub: a made-up value


class FatTemperatureTransmitter(FunctionBlock, IFieldDevice):
    """``FUNCTION_BLOCK FB_TemperatureTransmitter IMPLEMENTS I_FieldDevice``: start, stop, running are stubs."""

    tag: STRING = VAR_INPUT("TT102", length=8)
    raw_in: INT = VAR_INPUT(0)
    params: ARRAY[REAL] = VAR([0.0, 150.0, 1.0], bounds=(1, 3))

    @method
    def start(self) -> BOOL:
        return False  # stub: nothing to start

    @method
    def stop(self) -> None: ...  # stub

    @prop
    def running(self) -> BOOL:
        return False  # stub

    @method
    def error_code(self) -> UDINT:
        return ERR_WIRE_BREAK if self.raw_in > WIRE_BREAK_RAW else 0

    @method
    def write_parameter(self, index: INT, value: REAL) -> BOOL:
        if not 1 <= index <= 3:
            return False
        self.params[index] = value
        return True

    @method
    def read_parameter(self, index: INT) -> REAL:
        return self.params[index] if 1 <= index <= 3 else 0.0


class FatStartSequencer(FunctionBlock):
    """``FUNCTION_BLOCK FB_StartSequencer`` over ``I_FieldDevice``: one device per ``step_delay``.

    A device whose ``start`` returns FALSE aborts the sequence: it cannot tell
    a refusal from a stub.
    """

    request: BOOL = VAR_INPUT(False)
    step_delay: TIME = VAR_INPUT(T("500ms"))
    count: INT = VAR_OUTPUT(0)
    started: INT = VAR_OUTPUT(0)
    done: BOOL = VAR_OUTPUT(False)
    failed_slot: INT = VAR_OUTPUT(0)
    devices: ARRAY[IFieldDevice] = VAR(bounds=(1, SLOTS))
    gap: TON = VAR()

    @method
    def register(self, device: IFieldDevice) -> INT:
        """Put ``device`` in the next slot; a device past ``SLOTS`` faults (ARRAYBOUNDS) before the count moves."""
        self.devices[self.count + 1] = device
        self.count += 1
        return self.count

    def body(self) -> None:
        if not self.request:
            for slot in range(self.started, 0, -1):
                self.devices[slot].stop()
            self.started, self.done, self.failed_slot = 0, False, 0
            self.gap(IN=False)
            return
        if self.done or self.failed_slot:
            return
        if self.started < self.count:
            self.gap(IN=self.started > 0, PT=self.step_delay)
            if self.started == 0 or self.gap.Q:
                if not self.devices[self.started + 1].start():
                    self.failed_slot = self.started + 1
                    return
                self.started += 1
                self.gap(IN=False)  # the next gap counts from this start
                self.gap(IN=True, PT=self.step_delay)
        self.done = self.started >= self.count


class FatDiagnosticScanner(FunctionBlock):
    """``FUNCTION_BLOCK FB_DiagnosticScanner`` over ``I_FieldDevice``: counts a stub's 0 as healthy."""

    count: INT = VAR_OUTPUT(0)
    healthy: INT = VAR_OUTPUT(0)
    first_fault_slot: INT = VAR_OUTPUT(0)
    devices: ARRAY[IFieldDevice] = VAR(bounds=(1, SLOTS))

    @method
    def register(self, device: IFieldDevice) -> INT:
        """Put ``device`` in the next slot; a device past ``SLOTS`` faults (ARRAYBOUNDS) before the count moves."""
        self.devices[self.count + 1] = device
        self.count += 1
        return self.count

    def body(self) -> None:
        self.healthy, self.first_fault_slot = 0, 0
        for slot in range(1, self.count + 1):
            if self.devices[slot].error_code() == 0:
                self.healthy += 1
            elif not self.first_fault_slot:
                self.first_fault_slot = slot


# ---------------------------------------------------------------------------
# Compliant design: one small interface per client
# ---------------------------------------------------------------------------


class IStartable(IQueryInterface):
    """``INTERFACE I_Startable``: what a start sequencer needs."""

    @method
    def start(self) -> BOOL:
        raise NotImplementedError

    @method
    def stop(self) -> None: ...

    @prop
    def running(self) -> BOOL:
        raise NotImplementedError


class IDiagnosable(IQueryInterface):
    """``INTERFACE I_Diagnosable``: what a diagnostic page needs (0 = healthy)."""

    @method
    def error_code(self) -> UDINT:
        raise NotImplementedError


class IParameterisable(IQueryInterface):
    """``INTERFACE I_Parameterisable``: what a parameter download needs."""

    @method
    def write_parameter(self, index: INT, value: REAL) -> BOOL:
        raise NotImplementedError

    @method
    def read_parameter(self, index: INT) -> REAL:
        raise NotImplementedError


class VfdPump(FunctionBlock, IStartable, IDiagnosable, IParameterisable):
    """``FUNCTION_BLOCK FB_VfdPump IMPLEMENTS I_Startable, I_Diagnosable, I_Parameterisable``."""

    tag: STRING = VAR_INPUT("P101", length=8)
    vfd_fault: UDINT = VAR_INPUT(0)
    q_run: BOOL = VAR_OUTPUT(False)
    params: ARRAY[REAL] = VAR([5.0, 100.0], bounds=(1, 2))

    @method
    def start(self) -> BOOL:
        self.q_run = self.vfd_fault == 0
        return self.q_run

    @method
    def stop(self) -> None:
        self.q_run = False

    @prop
    def running(self) -> BOOL:
        return self.q_run

    @method
    def error_code(self) -> UDINT:
        return self.vfd_fault

    @method
    def write_parameter(self, index: INT, value: REAL) -> BOOL:
        if not 1 <= index <= 2 or value < 0.0:
            return False
        self.params[index] = value
        return True

    @method
    def read_parameter(self, index: INT) -> REAL:
        return self.params[index] if 1 <= index <= 2 else 0.0


class ContactorFan(FunctionBlock, IStartable):
    """``FUNCTION_BLOCK FB_ContactorFan IMPLEMENTS I_Startable``: no stubs."""

    tag: STRING = VAR_INPUT("F103", length=8)
    q_contactor: BOOL = VAR_OUTPUT(False)

    @method
    def start(self) -> BOOL:
        self.q_contactor = True
        return True

    @method
    def stop(self) -> None:
        self.q_contactor = False

    @prop
    def running(self) -> BOOL:
        return self.q_contactor


class TemperatureTransmitter(FunctionBlock, IDiagnosable, IParameterisable):
    """``FUNCTION_BLOCK FB_TemperatureTransmitter IMPLEMENTS I_Diagnosable, I_Parameterisable``.

    Parameters: 1 range low, 2 range high (degC), 3 filter time (s).
    """

    tag: STRING = VAR_INPUT("TT102", length=8)
    raw_in: INT = VAR_INPUT(0)
    params: ARRAY[REAL] = VAR([0.0, 150.0, 1.0], bounds=(1, 3))

    @method
    def error_code(self) -> UDINT:
        return ERR_WIRE_BREAK if self.raw_in > WIRE_BREAK_RAW else 0

    @method
    def write_parameter(self, index: INT, value: REAL) -> BOOL:
        if not 1 <= index <= 3:
            return False
        self.params[index] = value
        return True

    @method
    def read_parameter(self, index: INT) -> REAL:
        return self.params[index] if 1 <= index <= 3 else 0.0


class StartSequencer(FunctionBlock):
    """``FUNCTION_BLOCK FB_StartSequencer`` over ``I_Startable``: the same steps, only startable devices."""

    request: BOOL = VAR_INPUT(False)
    step_delay: TIME = VAR_INPUT(T("500ms"))
    count: INT = VAR_OUTPUT(0)
    started: INT = VAR_OUTPUT(0)
    done: BOOL = VAR_OUTPUT(False)
    failed_slot: INT = VAR_OUTPUT(0)
    devices: ARRAY[IStartable] = VAR(bounds=(1, SLOTS))
    gap: TON = VAR()

    @method
    def register(self, device: IStartable) -> INT:
        """Put ``device`` in the next slot; a device past ``SLOTS`` faults (ARRAYBOUNDS) before the count moves."""
        self.devices[self.count + 1] = device
        self.count += 1
        return self.count

    def body(self) -> None:
        if not self.request:
            for slot in range(self.started, 0, -1):
                self.devices[slot].stop()
            self.started, self.done, self.failed_slot = 0, False, 0
            self.gap(IN=False)
            return
        if self.done or self.failed_slot:
            return
        if self.started < self.count:
            self.gap(IN=self.started > 0, PT=self.step_delay)
            if self.started == 0 or self.gap.Q:
                if not self.devices[self.started + 1].start():
                    self.failed_slot = self.started + 1
                    return
                self.started += 1
                self.gap(IN=False)  # the next gap counts from this start
                self.gap(IN=True, PT=self.step_delay)
        self.done = self.started >= self.count


class DiagnosticScanner(FunctionBlock):
    """``FUNCTION_BLOCK FB_DiagnosticScanner`` over ``I_Diagnosable``: only devices that really report."""

    count: INT = VAR_OUTPUT(0)
    healthy: INT = VAR_OUTPUT(0)
    first_fault_slot: INT = VAR_OUTPUT(0)
    first_fault_code: UDINT = VAR_OUTPUT(0)
    devices: ARRAY[IDiagnosable] = VAR(bounds=(1, SLOTS))

    @method
    def register(self, device: IDiagnosable) -> INT:
        """Put ``device`` in the next slot; a device past ``SLOTS`` faults (ARRAYBOUNDS) before the count moves."""
        self.devices[self.count + 1] = device
        self.count += 1
        return self.count

    def body(self) -> None:
        self.healthy, self.first_fault_slot, self.first_fault_code = 0, 0, 0
        for slot in range(1, self.count + 1):
            code = self.devices[slot].error_code()
            if code == 0:
                self.healthy += 1
            elif not self.first_fault_slot:
                self.first_fault_slot, self.first_fault_code = slot, code


class ParameterEntry(Struct):
    """``TYPE ST_ParameterEntry : STRUCT slot : INT; index : INT; value : REAL; END_STRUCT``"""

    slot: INT = 0
    index: INT = 0
    value: REAL = 0.0


class ParameterDownload(FunctionBlock):
    """``FUNCTION_BLOCK FB_ParameterDownload`` over ``I_Parameterisable``: writes a table of entries."""

    count: INT = VAR_OUTPUT(0)
    rows: INT = VAR_OUTPUT(0)
    accepted: INT = VAR_OUTPUT(0)
    first_refused: INT = VAR_OUTPUT(0)
    devices: ARRAY[IParameterisable] = VAR(bounds=(1, SLOTS))
    table: ARRAY[ParameterEntry] = VAR(bounds=(1, SLOTS))

    @method
    def register(self, device: IParameterisable) -> INT:
        """Put ``device`` in the next slot; a device past ``SLOTS`` faults (ARRAYBOUNDS) before the count moves."""
        self.devices[self.count + 1] = device
        self.count += 1
        return self.count

    @method
    def add_row(self, slot: INT, index: INT, value: REAL) -> INT:
        """Append a row to the table; return its row number, 0 for a slot with no device or a full table."""
        if slot < 1 or slot > self.count or self.rows >= SLOTS:
            return 0
        self.rows += 1
        self.table[self.rows].slot = slot
        self.table[self.rows].index = index
        self.table[self.rows].value = value
        return self.rows

    @method
    def download(self) -> INT:
        """Write every row to its device; return how many were accepted."""
        self.accepted, self.first_refused = 0, 0
        for row in range(1, self.rows + 1):
            entry = self.table[row]
            if self.devices[entry.slot].write_parameter(entry.index, entry.value):
                self.accepted += 1
            elif not self.first_refused:
                self.first_refused = row
        return self.accepted


class IspCell(Program):
    """``PROGRAM PRG_IspCell``: the same three devices, behind the fat interface and behind the small ones."""

    start_request: BOOL = VAR_INPUT(False)
    fat_pump: FatVfdPump = VAR()
    fat_transmitter: FatTemperatureTransmitter = VAR()
    fat_fan: FatContactorFan = VAR()
    fat_sequencer: FatStartSequencer = VAR()
    fat_scanner: FatDiagnosticScanner = VAR()
    pump: VfdPump = VAR()
    transmitter: TemperatureTransmitter = VAR()
    fan: ContactorFan = VAR()
    sequencer: StartSequencer = VAR()
    scanner: DiagnosticScanner = VAR()
    download: ParameterDownload = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
        self.fat_sequencer.register(self.fat_pump)
        self.fat_sequencer.register(self.fat_transmitter)
        self.fat_sequencer.register(self.fat_fan)
        self.fat_scanner.register(self.fat_pump)
        self.fat_scanner.register(self.fat_transmitter)
        self.fat_scanner.register(self.fat_fan)
        self.connect(self.pump)
        self.connect(self.transmitter)
        self.connect(self.fan)
        return True

    @method(PRIVATE)
    def connect(self, device: IQueryInterface) -> None:
        """Give ``device`` to each client whose interface it implements (``__QUERYINTERFACE``)."""
        startable = query_interface(device, IStartable)
        if startable is not None:
            self.sequencer.register(startable)
        diagnosable = query_interface(device, IDiagnosable)
        if diagnosable is not None:
            self.scanner.register(diagnosable)
        parameterisable = query_interface(device, IParameterisable)
        if parameterisable is not None:
            self.download.register(parameterisable)

    def body(self) -> None:
        self.fat_sequencer(request=self.start_request)
        self.fat_scanner()
        self.sequencer(request=self.start_request)
        self.scanner()


def main() -> None:
    """Start the cell, break the transmitter's wire and download parameters, in both designs.

    >>> main()
    violating  start sequence over I_FieldDevice: aborted at slot 2 (the transmitter's stub); running: P101
    violating  diagnostics over I_FieldDevice: 2 of 3 healthy (the fan's stub says 0)
    violating  fan.WriteParameter(1, 20.0) -> False, fan.ReadParameter(1) -> 0.0
    compliant  start sequence over I_Startable: 2 of 2 started; running: P101, F103
    compliant  diagnostics over I_Diagnosable: 1 of 2 healthy, slot 2 error 16#A001
    compliant  parameter download over I_Parameterisable: 3 of 3 rows accepted
    """
    cell = IspCell()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), cell)
    cell.start_request = True
    cell.fat_transmitter.raw_in = cell.transmitter.raw_in = 32767
    rt.run(duration=T("2s"))
    fat_running = [d.tag for d in (cell.fat_pump, cell.fat_transmitter, cell.fat_fan) if d.running]
    print(
        f"violating  start sequence over I_FieldDevice: aborted at slot {cell.fat_sequencer.failed_slot} "
        f"(the transmitter's stub); running: {', '.join(fat_running)}"
    )
    print(
        f"violating  diagnostics over I_FieldDevice: {cell.fat_scanner.healthy} of {cell.fat_scanner.count} healthy "
        "(the fan's stub says 0)"
    )
    print(
        f"violating  fan.WriteParameter(1, 20.0) -> {cell.fat_fan.write_parameter(1, 20.0)}, "
        f"fan.ReadParameter(1) -> {cell.fat_fan.read_parameter(1)}"
    )
    running = [d.tag for d in (cell.pump, cell.fan) if d.running]
    print(
        f"compliant  start sequence over I_Startable: {cell.sequencer.started} of {cell.sequencer.count} started; "
        f"running: {', '.join(running)}"
    )
    print(
        f"compliant  diagnostics over I_Diagnosable: {cell.scanner.healthy} of {cell.scanner.count} healthy, "
        f"slot {cell.scanner.first_fault_slot} error 16#{cell.scanner.first_fault_code:04X}"
    )
    cell.download.add_row(1, 1, 8.0)
    cell.download.add_row(2, 2, 120.0)
    cell.download.add_row(2, 3, 2.0)
    accepted = cell.download.download()
    print(f"compliant  parameter download over I_Parameterisable: {accepted} of {cell.download.rows} rows accepted")


def _running(*names: str) -> Getter:
    def get(cell: Any) -> object:
        return " ".join(getattr(cell, n).tag for n in names if getattr(cell, n).running) or "-"

    return get


SHOWCASE = Showcase(
    use_when="clients need only part of a device's abilities: give them small interfaces, not one large one",
    columns=(
        Column("fat: running", _running("fat_pump", "fat_transmitter", "fat_fan")),
        Column("failed slot", lambda p: p.fat_sequencer.failed_slot),
        Column("healthy", lambda p: p.fat_scanner.healthy),
        Column("small: running", _running("pump", "fan")),
        Column("healthy ", lambda p: p.scanner.healthy),
        Column("fault code", lambda p: p.scanner.first_fault_code, hex_word),
    ),
    script=steps((1, "start_request", True), (1, "fat_transmitter.raw_in", 32767), (1, "transmitter.raw_in", 32767)),
    cycles=200,
    tour_cycles=200,
)
