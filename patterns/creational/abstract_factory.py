"""Abstract Factory: fieldbus I/O module families created by one factory per family.

Intent
------

Provide one interface for creating a family of related objects, so that the
client code gets modules that belong together without naming their classes,
and a whole family is swapped by handing over another factory.

The PLC problem
---------------

A tank farm is sold with two remote I/O systems: EtherCAT terminals or a
PROFINET station. Each system has digital input, digital output and 4-20 mA
analog input modules, and each encodes its process image its own way:
EtherCAT words are little-endian and an analog channel is a status word plus
a value of 0..32767, with bit 6 of the status flagging a wire break; PROFINET
words are big-endian (channel 0 of a byte module is bit 8 of the WORD) and an
analog value is 0..27648, with 16#7FFF for a wire break. Reading a PROFINET
module with EtherCAT rules gives wrong bits, so the modules of one tank must
come from one family.

``TankCell`` receives an ``IoFactory`` once, asks it for its level sensor,
its high-level switch and its pump output, and from then on only uses the
``IAnalogInput`` / ``IDigitalInput`` / ``IDigitalOutput`` interfaces. The
concrete module blocks are INTERNAL to the ``patterns`` package: code outside
it can neither instantiate them, nor extend them, nor call their INTERNAL
``bind`` method that ties a module to its process-image address. Only the
family factories create and bind them, from static pools. A factory reports
failures on its ``error`` output (no image attached, pool or image full) and
returns 0; calling through the 0 raises RTSEXCPT_ACCESS_VIOLATION.

Roles
-----

- Abstract factory: ``IoFactory`` (``FB_IoFactory``, ABSTRACT)
- Concrete factories: ``EtherCatFactory`` (``FB_EtherCatFactory``),
  ``ProfinetFactory`` (``FB_ProfinetFactory``), both FINAL
- Abstract products: ``IDigitalInput`` (``I_DigitalInput``),
  ``IDigitalOutput`` (``I_DigitalOutput``), ``IAnalogInput``
  (``I_AnalogInput``), all extending ``IIoModule`` (``I_IoModule``)
- Concrete products (INTERNAL): ``EcDigitalInput``, ``EcDigitalOutput``,
  ``EcAnalogInput``, ``PnDigitalInput``, ``PnDigitalOutput``,
  ``PnAnalogInput`` (``FB_EcDigitalInput`` ...), on the INTERNAL ABSTRACT
  ``IoModule`` (``FB_IoModule``); the analog ones share its extension
  ``AnalogModule`` (``FB_AnalogModule``)
- Client: ``TankCell`` (``FB_TankCell``), wired by ``TankFarmMain``
  (``PROGRAM TankFarmMain``)

IEC 61131-3 mapping
-------------------

::

    TYPE ST_BusImage : STRUCT aInputs : ARRAY[0..3] OF WORD; aOutputs : ARRAY[0..1] OF WORD; END_STRUCT END_TYPE

    INTERFACE I_DigitalInput EXTENDS I_IoModule
        METHOD Read : BOOL  VAR_INPUT nChannel : INT; END_VAR
    INTERFACE I_DigitalOutput EXTENDS I_IoModule
        METHOD Write  VAR_INPUT nChannel : INT; bValue : BOOL; END_VAR
    INTERFACE I_AnalogInput EXTENDS I_IoModule
        PROPERTY Value : REAL
        PROPERTY WireBreak : BOOL

    FUNCTION_BLOCK ABSTRACT FB_IoFactory
        VAR_INPUT  pImage : POINTER TO ST_BusImage; END_VAR
        VAR_OUTPUT eError : E_IoError; END_VAR
        METHOD ABSTRACT CreateDigitalInput : I_DigitalInput
        METHOD ABSTRACT CreateDigitalOutput : I_DigitalOutput
        METHOD ABSTRACT CreateAnalogInput : I_AnalogInput
            VAR_INPUT fLow, fHigh : REAL; END_VAR
        PROPERTY ABSTRACT Family : STRING

    FUNCTION_BLOCK ABSTRACT INTERNAL FB_IoModule
        METHOD INTERNAL Bind  VAR_INPUT pImage : POINTER TO ST_BusImage; nWord : INT; END_VAR
    FUNCTION_BLOCK ABSTRACT INTERNAL FB_AnalogModule EXTENDS FB_IoModule IMPLEMENTS I_AnalogInput
        METHOD INTERNAL SetRange  VAR_INPUT fLow, fHigh : REAL; END_VAR
    FUNCTION_BLOCK INTERNAL FINAL FB_EcAnalogInput EXTENDS FB_AnalogModule

    FUNCTION_BLOCK FINAL FB_EtherCatFactory EXTENDS FB_IoFactory
        VAR aAi : ARRAY[1..2] OF FB_EcAnalogInput; nAi : INT; END_VAR

When not to use it on a PLC
---------------------------

Most machines are built with one I/O system, fixed by the hardware
configuration: then map the channels with ``AT %I*`` variables and let the
I/O configuration do the linking. An abstract factory is worth its weight
in a library sold with several hardware options, or in simulation, where a
simulated family replaces the real one for commissioning tests. A new
module kind means a new method on every factory, so keep the families small.

References
----------

- E. Gamma, R. Helm, R. Johnson, J. Vlissides, *Design Patterns: Elements of
  Reusable Object-Oriented Software*, Addison-Wesley 1994: "Abstract Factory".
- IEC 61131-3:2013, *Programmable controllers - Part 3: Programming
  languages*, 3rd edition: ABSTRACT, FINAL and INTERNAL, interfaces.
- Beckhoff InfoSys, TwinCAT 3 PLC: "ABSTRACT concept", "Object Method"
  (access modifiers, INTERNAL); EL30xx documentation, "Process data"
  (the status word of an analog input terminal).
- CODESYS Online Help: "Object: Method", "Object: Function Block"
  (ABSTRACT, FINAL, INTERNAL).
"""

from __future__ import annotations

from iecoop import (
    ABSTRACT,
    ARRAY,
    BOOL,
    INT,
    INTERNAL,
    POINTER_TO,
    PROTECTED,
    REAL,
    STRING,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    VAR_STAT,
    WORD,
    FunctionBlock,
    IecEnum,
    Interface,
    Program,
    Struct,
    T,
    adr,
    method,
    prop,
)
from iecoop.runtime import Runtime, Task
from patterns.showcase.entry import Column, Scenario, Showcase, flag, hex_word

__all__ = [
    "BusImage",
    "CHANNELS",
    "EC_STATUS_ERROR",
    "EtherCatFactory",
    "IAnalogInput",
    "IDigitalInput",
    "IDigitalOutput",
    "IIoModule",
    "IoError",
    "IoFactory",
    "PN_OVERFLOW",
    "ProfinetFactory",
    "TankCell",
    "TankFarmMain",
    "main",
]

#: Channels of a digital module (``0..CHANNELS-1``).
CHANNELS = 8
#: EtherCAT analog status word: bit 6 is the error bit (wire break on 4-20 mA).
EC_STATUS_ERROR = 0x0040
#: PROFINET analog value of a wire break / overflow.
PN_OVERFLOW = 0x7FFF


class BusImage(Struct):
    """``ST_BusImage``: the cyclic process image of one fieldbus (4 input words, 2 output words)."""

    inputs: ARRAY[WORD] = VAR(bounds=(0, 3))
    outputs: ARRAY[WORD] = VAR(bounds=(0, 1))


class IoError(IecEnum):
    """``E_IoError``: why a factory returned 0."""

    NONE = 0
    NO_IMAGE = 1
    POOL_FULL = 2
    IMAGE_FULL = 3


class IIoModule(Interface):
    """``INTERFACE I_IoModule``: what every module tells about itself."""

    @prop
    def address(self) -> INT:
        raise NotImplementedError


class IDigitalInput(IIoModule):
    """``INTERFACE I_DigitalInput EXTENDS I_IoModule``."""

    @method
    def read(self, channel: INT) -> BOOL:
        raise NotImplementedError


class IDigitalOutput(IIoModule):
    """``INTERFACE I_DigitalOutput EXTENDS I_IoModule``."""

    @method
    def write(self, channel: INT, value: BOOL) -> None: ...


class IAnalogInput(IIoModule):
    """``INTERFACE I_AnalogInput EXTENDS I_IoModule``: a scaled 4-20 mA channel."""

    @prop
    def value(self) -> REAL:
        raise NotImplementedError

    @prop
    def wire_break(self) -> BOOL:
        raise NotImplementedError


# ---------------------------------------------------------------------------
# The concrete modules: INTERNAL to the package
# ---------------------------------------------------------------------------


class IoModule(FunctionBlock, abstract=True, internal=True):
    """``FUNCTION_BLOCK ABSTRACT INTERNAL FB_IoModule``: a module bound to a word of a process image."""

    image: POINTER_TO[BusImage] = VAR()
    word: INT = VAR(-1)
    #: ``aChannelBit : ARRAY[0..CHANNELS - 1] OF WORD``: a channel outside it is the runtime's ARRAYBOUNDS fault.
    CHANNEL_BIT: ARRAY[WORD] = VAR([1 << n for n in range(CHANNELS)], bounds=(0, CHANNELS - 1), constant=True)

    @method(INTERNAL)
    def bind(self, image: POINTER_TO[BusImage], word: INT) -> None:
        """Tie the module to its first word; only the family factories call it."""
        self.image = image
        self.word = word

    @prop
    def address(self) -> INT:
        return self.word

    @method(PROTECTED)
    def mask(self, channel: INT, big_endian: BOOL) -> WORD:
        """The bit of ``channel`` in a WORD of the image (a byte module sits in the low byte, big-endian in the high)."""
        if big_endian:
            return self.CHANNEL_BIT[channel] << 8
        return self.CHANNEL_BIT[channel]

    @method(PROTECTED)
    def set_output(self, bit: WORD, value: BOOL) -> None:
        bus = self.image.deref
        if value:
            bus.outputs[self.word] = bus.outputs[self.word] | bit
        else:
            bus.outputs[self.word] = bus.outputs[self.word] & ~bit & 0xFFFF


class EcDigitalInput(IoModule, IDigitalInput, internal=True, final=True):
    """``FUNCTION_BLOCK INTERNAL FB_EcDigitalInput``: 8 channels, little-endian (bit n = channel n)."""

    @method
    def read(self, channel: INT) -> BOOL:
        return bool(self.image.deref.inputs[self.word] & self.mask(channel, False))


class EcDigitalOutput(IoModule, IDigitalOutput, internal=True, final=True):
    """``FUNCTION_BLOCK INTERNAL FB_EcDigitalOutput``: 8 channels, little-endian."""

    @method
    def write(self, channel: INT, value: BOOL) -> None:
        self.set_output(self.mask(channel, False), value)


class AnalogModule(IoModule, IAnalogInput, abstract=True, internal=True):
    """``FUNCTION_BLOCK ABSTRACT INTERNAL FB_AnalogModule``: the engineering range both families scale to."""

    low: REAL = VAR(0.0)
    high: REAL = VAR(100.0)

    @method(INTERNAL)
    def set_range(self, low: REAL, high: REAL) -> None:
        self.low = low
        self.high = high

    @method(PROTECTED)
    def scaled(self, raw: WORD, full_scale: WORD) -> REAL:
        """``raw`` of ``full_scale`` nominal counts, in ``low``..``high``."""
        return self.low + (self.high - self.low) * raw / full_scale


class EcAnalogInput(AnalogModule, internal=True, final=True):
    """``FUNCTION_BLOCK INTERNAL FB_EcAnalogInput``: status word + value 0..32767 (two words)."""

    @prop
    def value(self) -> REAL:
        return self.scaled(self.image.deref.inputs[self.word + 1], 32767)

    @prop
    def wire_break(self) -> BOOL:
        return bool(self.image.deref.inputs[self.word] & EC_STATUS_ERROR)


class PnDigitalInput(IoModule, IDigitalInput, internal=True, final=True):
    """``FUNCTION_BLOCK INTERNAL FB_PnDigitalInput``: 8 channels, big-endian (channel n = bit n+8)."""

    @method
    def read(self, channel: INT) -> BOOL:
        return bool(self.image.deref.inputs[self.word] & self.mask(channel, True))


class PnDigitalOutput(IoModule, IDigitalOutput, internal=True, final=True):
    """``FUNCTION_BLOCK INTERNAL FB_PnDigitalOutput``: 8 channels, big-endian."""

    @method
    def write(self, channel: INT, value: BOOL) -> None:
        self.set_output(self.mask(channel, True), value)


class PnAnalogInput(AnalogModule, internal=True, final=True):
    """``FUNCTION_BLOCK INTERNAL FB_PnAnalogInput``: one word, 0..27648 nominal, 16#7FFF on wire break."""

    @prop
    def value(self) -> REAL:
        return self.scaled(self.image.deref.inputs[self.word], 27648)

    @prop
    def wire_break(self) -> BOOL:
        return self.image.deref.inputs[self.word] == PN_OVERFLOW


# ---------------------------------------------------------------------------
# The factories
# ---------------------------------------------------------------------------


class IoFactory(FunctionBlock, abstract=True):
    """``FUNCTION_BLOCK ABSTRACT FB_IoFactory``: creates the modules of one family."""

    NO_DI: IDigitalInput = VAR_STAT(constant=True)
    NO_DO: IDigitalOutput = VAR_STAT(constant=True)
    NO_AI: IAnalogInput = VAR_STAT(constant=True)
    image: POINTER_TO[BusImage] = VAR_INPUT()
    error: IoError = VAR_OUTPUT(IoError.NONE)
    next_in: INT = VAR(0)
    next_out: INT = VAR(0)

    @method(ABSTRACT)
    def create_di(self) -> IDigitalInput:
        raise NotImplementedError

    @method(ABSTRACT)
    def create_do(self) -> IDigitalOutput:
        raise NotImplementedError

    @method(ABSTRACT)
    def create_ai(self, low: REAL, high: REAL) -> IAnalogInput:
        raise NotImplementedError

    @prop
    @method(ABSTRACT)
    def family(self) -> STRING:
        raise NotImplementedError

    @method(PROTECTED)
    def reserve(self, used: INT, pool_size: INT, in_words: INT, out_words: INT) -> INT:
        """The first word for a new module, or -1 with ``error`` set."""
        if not self.image:
            self.error = IoError.NO_IMAGE
            return -1
        if used >= pool_size:
            self.error = IoError.POOL_FULL
            return -1
        image = self.image.deref
        if self.next_in + in_words > image.inputs.high + 1 or self.next_out + out_words > image.outputs.high + 1:
            self.error = IoError.IMAGE_FULL
            return -1
        word = self.next_in if in_words else self.next_out
        self.next_in += in_words
        self.next_out += out_words
        return word


class EtherCatFactory(IoFactory, final=True):
    """``FUNCTION_BLOCK FINAL FB_EtherCatFactory EXTENDS FB_IoFactory``: EtherCAT terminals."""

    di: ARRAY[EcDigitalInput] = VAR(bounds=(1, 2))
    do: ARRAY[EcDigitalOutput] = VAR(bounds=(1, 2))
    ai: ARRAY[EcAnalogInput] = VAR(bounds=(1, 2))
    n_di: INT = VAR(0)
    n_do: INT = VAR(0)
    n_ai: INT = VAR(0)

    @method
    def create_di(self) -> IDigitalInput:
        word = self.reserve(self.n_di, self.di.high, 1, 0)
        if word < 0:
            return self.NO_DI
        self.n_di += 1
        module = self.di[self.n_di]
        module.bind(self.image, word)
        return module

    @method
    def create_do(self) -> IDigitalOutput:
        word = self.reserve(self.n_do, self.do.high, 0, 1)
        if word < 0:
            return self.NO_DO
        self.n_do += 1
        module = self.do[self.n_do]
        module.bind(self.image, word)
        return module

    @method
    def create_ai(self, low: REAL, high: REAL) -> IAnalogInput:
        word = self.reserve(self.n_ai, self.ai.high, 2, 0)
        if word < 0:
            return self.NO_AI
        self.n_ai += 1
        module = self.ai[self.n_ai]
        module.bind(self.image, word)
        module.set_range(low, high)
        return module

    @prop
    def family(self) -> STRING:
        return "EtherCAT"


class ProfinetFactory(IoFactory, final=True):
    """``FUNCTION_BLOCK FINAL FB_ProfinetFactory EXTENDS FB_IoFactory``: a PROFINET I/O station."""

    di: ARRAY[PnDigitalInput] = VAR(bounds=(1, 2))
    do: ARRAY[PnDigitalOutput] = VAR(bounds=(1, 2))
    ai: ARRAY[PnAnalogInput] = VAR(bounds=(1, 2))
    n_di: INT = VAR(0)
    n_do: INT = VAR(0)
    n_ai: INT = VAR(0)

    @method
    def create_di(self) -> IDigitalInput:
        word = self.reserve(self.n_di, self.di.high, 1, 0)
        if word < 0:
            return self.NO_DI
        self.n_di += 1
        module = self.di[self.n_di]
        module.bind(self.image, word)
        return module

    @method
    def create_do(self) -> IDigitalOutput:
        word = self.reserve(self.n_do, self.do.high, 0, 1)
        if word < 0:
            return self.NO_DO
        self.n_do += 1
        module = self.do[self.n_do]
        module.bind(self.image, word)
        return module

    @method
    def create_ai(self, low: REAL, high: REAL) -> IAnalogInput:
        word = self.reserve(self.n_ai, self.ai.high, 1, 0)
        if word < 0:
            return self.NO_AI
        self.n_ai += 1
        module = self.ai[self.n_ai]
        module.bind(self.image, word)
        module.set_range(low, high)
        return module

    @prop
    def family(self) -> STRING:
        return "PROFINET"


# ---------------------------------------------------------------------------
# The client
# ---------------------------------------------------------------------------


class TankCell(FunctionBlock):
    """``FUNCTION_BLOCK FB_TankCell``: fills a tank between 1 m and 3 m; knows only the I/O interfaces."""

    START_LEVEL: REAL = VAR_STAT(1.0, constant=True)
    STOP_LEVEL: REAL = VAR_STAT(3.0, constant=True)
    level_sensor: IAnalogInput = VAR()
    high_switch: IDigitalInput = VAR()
    pump: IDigitalOutput = VAR()
    level: REAL = VAR_OUTPUT(0.0)
    pump_on: BOOL = VAR_OUTPUT(False)
    fault: BOOL = VAR_OUTPUT(False)

    @method
    def setup(self, factory: IoFactory) -> BOOL:
        """Take the tank's modules from ``factory`` (ST: ``VAR_IN_OUT factory : FB_IoFactory``)."""
        self.level_sensor = factory.create_ai(0.0, 4.0)
        self.high_switch = factory.create_di()
        self.pump = factory.create_do()
        return factory.error == IoError.NONE

    def body(self) -> None:
        self.level = self.level_sensor.value
        self.fault = self.level_sensor.wire_break
        if self.fault or self.high_switch.read(0):
            self.pump_on = False
        elif self.level < self.START_LEVEL:
            self.pump_on = True
        elif self.level > self.STOP_LEVEL:
            self.pump_on = False
        self.pump.write(0, self.pump_on)


class TankFarmMain(Program):
    """``PROGRAM TankFarmMain``: tank A on EtherCAT, tank B on PROFINET, the same cell code."""

    ec_bus: BusImage = VAR_INPUT()
    pn_bus: BusImage = VAR_INPUT()
    ethercat: EtherCatFactory = VAR()
    profinet: ProfinetFactory = VAR()
    tank_a: TankCell = VAR()
    tank_b: TankCell = VAR()
    ready: BOOL = VAR_OUTPUT(False)
    first_scan: BOOL = VAR(True)

    def body(self) -> None:
        if self.first_scan:
            self.first_scan = False
            self.ethercat(image=adr(self, "ec_bus"))
            self.profinet(image=adr(self, "pn_bus"))
            self.ready = self.tank_a.setup(self.ethercat) and self.tank_b.setup(self.profinet)
        if self.ready:
            self.tank_a()
            self.tank_b()


def main() -> None:
    """Feed both tanks the same levels in their own wire formats and show what the cells do.

    >>> main()
    level   EtherCAT AI  PROFINET AI  pumps  EtherCAT QW0  PROFINET QW0
    0.50 m         4096         3456  ON/ON  16#0001       16#0100
    2.00 m        16384        13824  ON/ON  16#0001       16#0100
    3.50 m        28671        24192  -/-    16#0000       16#0000
    2.00 m        16384        13824  -/-    16#0000       16#0000
    0.80 m         6553         5530  ON/ON  16#0001       16#0100
    broken   status 16#0040   16#7FFF  -/-    16#0000       16#0000
    """
    farm = TankFarmMain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), farm)
    rt.run(cycles=1)
    ec_ai = farm.tank_a.level_sensor.address
    pn_ai = farm.tank_b.level_sensor.address
    print("level   EtherCAT AI  PROFINET AI  pumps  EtherCAT QW0  PROFINET QW0")

    def show(first: str) -> None:
        rt.run(cycles=1)
        pumps = "/".join("ON" if tank.pump_on else "-" for tank in (farm.tank_a, farm.tank_b))
        print(f"{first}  {pumps:<5}  16#{farm.ec_bus.outputs[0]:04X}       16#{farm.pn_bus.outputs[0]:04X}")

    for level in (0.5, 2.0, 3.5, 2.0, 0.8):
        ec_raw, pn_raw = round(level / 4.0 * 32767), round(level / 4.0 * 27648)
        farm.ec_bus.inputs[ec_ai + 1] = ec_raw
        farm.pn_bus.inputs[pn_ai] = pn_raw
        show(f"{level:.2f} m  {ec_raw:11d}  {pn_raw:11d}")
    farm.ec_bus.inputs[ec_ai] = EC_STATUS_ERROR
    farm.pn_bus.inputs[pn_ai] = PN_OVERFLOW
    show(f"broken   status 16#{EC_STATUS_ERROR:04X}   16#{PN_OVERFLOW:04X}")


def _tanks(scenario: Scenario, cycle: int) -> None:
    farm = scenario.program
    if cycle == 1:
        scenario.sim.update(a=0.5, b=0.8)
        return  # the factories bind the modules in the first scan
    for key, tank, bus, full_scale in (("a", farm.tank_a, farm.ec_bus, 32767), ("b", farm.tank_b, farm.pn_bus, 27648)):
        level = scenario.sim[key] + (0.1 if tank.pump_on else -0.04)
        scenario.sim[key] = level = min(max(level, 0.0), 4.0)
        address = tank.level_sensor.address
        raw = round(level / 4.0 * full_scale)
        if key == "a":
            bus.inputs[address] = EC_STATUS_ERROR if 71 <= cycle < 81 else 0
            bus.inputs[address + 1] = raw
        else:
            bus.inputs[address] = raw


SHOWCASE = Showcase(
    use_when="a library sold with several I/O hardware options, or a simulated family swapped in for commissioning",
    columns=(
        Column("A level m", lambda p: p.tank_a.level, ".2f", watch=False),
        Column("A pump", lambda p: p.tank_a.pump_on, flag),
        Column("A fault", lambda p: p.tank_a.fault),
        Column("EC QW0", lambda p: p.ec_bus.outputs[0], hex_word),
        Column("B level m", lambda p: p.tank_b.level, ".2f", watch=False),
        Column("PN QW0", lambda p: p.pn_bus.outputs[0], hex_word),
    ),
    script=_tanks,
    cycles=120,
    tour_cycles=90,
)
