"""Observer: one temperature transmitter, several independent consumers.

Intent
------

Define a one-to-many dependency so that when one object changes, every
dependent is told, without the subject knowing what the dependents are.

The PLC problem
---------------

A reactor jacket has one temperature transmitter, TT101. Three parts of the
program need its value every scan: a high-temperature alarm (limit,
hysteresis and on-delay), the HMI trend and the event logger. Written as
plain code, the transmitter's FB ends up calling each consumer by name, and
every new consumer (an SPC export, a second alarm level) means editing the
transmitter. With Observer the transmitter owns a bounded array of
``I_Observer`` references and calls ``Update(value, quality)`` on each one
once per scan; consumers attach and detach at run time (the trend detaches
when the HMI screen closes) and the transmitter never changes.

Wiring mistakes never stop the PLC: attaching a null reference, an
observer that is already attached, or one more than the array holds is
refused with FALSE and changes nothing, and ``refusal`` (``E_AttachRefusal``)
says which rule was broken; detaching one that is not attached answers
FALSE as well.

Roles
-----

- Subject interface → ``ISubject`` (``I_Subject``)
- Observer interface → ``IObserver`` (``I_Observer``)
- Concrete subject → ``TemperatureTransmitter`` (``FB_TemperatureTransmitter``)
- Concrete observers → ``HighTemperatureAlarm`` (``FB_HighTempAlarm``),
  ``TrendBuffer`` (``FB_TrendBuffer``), ``EventLogger`` (``FB_EventLogger``)
- Client → ``ReactorMain`` (``PRG_ReactorMain``)

IEC 61131-3 mapping
-------------------

::

    TYPE E_Quality : (GOOD := 0, UNCERTAIN := 1, BAD := 2) USINT; END_TYPE

    INTERFACE I_Observer
        METHOD Update
        VAR_INPUT value : REAL; quality : E_Quality; END_VAR

    INTERFACE I_Subject
        METHOD Attach : BOOL   VAR_INPUT observer : I_Observer; END_VAR
        METHOD Detach : BOOL   VAR_INPUT observer : I_Observer; END_VAR
        PROPERTY ObserverCount : INT   (Get only)

    FUNCTION_BLOCK FB_TemperatureTransmitter IMPLEMENTS I_Subject
    VAR_INPUT  rawTemperature : REAL; wireBreak : BOOL; END_VAR
    VAR_OUTPUT value : REAL; quality : E_Quality;
               refusal : E_AttachRefusal; END_VAR  // why the last Attach said FALSE
    VAR        observers : ARRAY[1..MAX_OBSERVERS] OF I_Observer;
               count : INT; END_VAR
        METHOD PRIVATE Notify

    FUNCTION_BLOCK FB_HighTempAlarm IMPLEMENTS I_Observer
    VAR_INPUT  highLimit : REAL := 90.0; hysteresis : REAL := 5.0;
               delay : TIME := T#300MS; END_VAR
    VAR_OUTPUT active : BOOL; sensorFault : BOOL; END_VAR
    VAR        onDelay : TON; END_VAR

    FUNCTION_BLOCK FB_TrendBuffer IMPLEMENTS I_Observer
    VAR        samples : ARRAY[0..TREND_SIZE - 1] OF ST_TrendSample; END_VAR
        METHOD ValueAt : REAL   VAR_INPUT age : INT; END_VAR

    FUNCTION_BLOCK FB_EventLogger IMPLEMENTS I_Observer
    VAR        entries : ARRAY[0..LOG_SIZE - 1] OF ST_LogEntry; END_VAR

When not to use it on a PLC
---------------------------

When every consumer already runs in the same task and just reads
``fbTT101.value`` each scan, a plain output variable is the simplest
observer there is: the scan itself is the notification. Observer pays off
when consumers come and go at run time, or when the subject must stay closed
to edits. Keep the list bounded (the subject's scan time grows with every
observer) and never let an observer detach itself from inside ``Update``:
the subject is walking the array at that moment.

References
----------

- Gamma, Helm, Johnson, Vlissides: *Design Patterns: Elements of Reusable
  Object-Oriented Software*, Addison-Wesley 1994, "Observer".
- IEC 61131-3:2013, 3rd edition: interfaces and methods, properties,
  arrays and enumerated data types, and the standard timer TON.
- Beckhoff InfoSys, TwinCAT 3 PLC: "Interface", "Method", "Property",
  "ARRAY OF", "TON".
- CODESYS Online Help: "Object: Interface", "Object: Method",
  "Implementing interfaces".
"""

from __future__ import annotations

from iecoop import (
    ARRAY,
    BOOL,
    DINT,
    INT,
    NULL,
    PRIVATE,
    REAL,
    TIME,
    USINT,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    FunctionBlock,
    IecEnum,
    Interface,
    Program,
    Struct,
    T,
    method,
    prop,
)
from iecoop.runtime import Runtime, Task, now_ms
from iecoop.stdlib import TON
from patterns.showcase.entry import Column, Showcase

__all__ = [
    "LOG_SIZE",
    "MAX_OBSERVERS",
    "TREND_SIZE",
    "AttachRefusal",
    "EventLogger",
    "HighTemperatureAlarm",
    "IObserver",
    "ISubject",
    "LogEntry",
    "LogReason",
    "Quality",
    "ReactorMain",
    "TemperatureTransmitter",
    "TrendBuffer",
    "TrendSample",
    "main",
]

#: ``MAX_OBSERVERS``, ``TREND_SIZE`` and ``LOG_SIZE``: a GVL's VAR_GLOBAL CONSTANT.
MAX_OBSERVERS = 4
TREND_SIZE = 8
LOG_SIZE = 16


class Quality(IecEnum, base=USINT):
    """``TYPE E_Quality : (GOOD := 0, UNCERTAIN := 1, BAD := 2) USINT; END_TYPE``."""

    GOOD = 0
    UNCERTAIN = 1
    BAD = 2


class LogReason(IecEnum, base=USINT):
    """``TYPE E_LogReason : (FIRST_SAMPLE, QUALITY_CHANGED, DEADBAND) USINT; END_TYPE``."""

    FIRST_SAMPLE = 0
    QUALITY_CHANGED = 1
    DEADBAND = 2


class AttachRefusal(IecEnum, base=USINT):
    """``TYPE E_AttachRefusal : (NONE, NULL_OBSERVER, ALREADY_ATTACHED, LIST_FULL) USINT; END_TYPE``: why ``Attach`` said FALSE."""

    NONE = 0
    NULL_OBSERVER = 1
    ALREADY_ATTACHED = 2
    LIST_FULL = 3


class TrendSample(Struct):
    """``TYPE ST_TrendSample : STRUCT value : REAL; quality : E_Quality; END_STRUCT END_TYPE``."""

    value: REAL = 0.0
    quality: Quality = Quality.GOOD


class LogEntry(Struct):
    """``TYPE ST_LogEntry : STRUCT timeMs : TIME; value : REAL; quality : E_Quality; reason : E_LogReason;``."""

    time_ms: TIME = 0
    value: REAL = 0.0
    quality: Quality = Quality.GOOD
    reason: LogReason = LogReason.FIRST_SAMPLE


class IObserver(Interface):
    """``INTERFACE I_Observer``: told the new value and its quality once per scan."""

    @method
    def update(self, value: REAL, quality: Quality) -> None: ...


class ISubject(Interface):
    """``INTERFACE I_Subject``: keeps a bounded list of observers."""

    @method
    def attach(self, observer: IObserver) -> BOOL:
        raise NotImplementedError

    @method
    def detach(self, observer: IObserver) -> BOOL:
        raise NotImplementedError

    @prop
    def observer_count(self) -> INT:
        raise NotImplementedError


class TemperatureTransmitter(FunctionBlock, ISubject):
    """``FUNCTION_BLOCK FB_TemperatureTransmitter IMPLEMENTS I_Subject``.

    Each call derives the quality (BAD on a wire break, UNCERTAIN outside the
    calibrated range, where the value is clamped) and notifies every attached
    observer in attach order.
    """

    raw_temperature: REAL = VAR_INPUT(0.0)
    wire_break: BOOL = VAR_INPUT(False)
    range_low: REAL = VAR_INPUT(-50.0)
    range_high: REAL = VAR_INPUT(250.0)
    value: REAL = VAR_OUTPUT(0.0)
    quality: Quality = VAR_OUTPUT(Quality.BAD)
    refusal: AttachRefusal = VAR_OUTPUT(AttachRefusal.NONE)
    observers: ARRAY[IObserver] = VAR(bounds=(1, MAX_OBSERVERS))
    count: INT = VAR(0)

    def body(self) -> None:
        if self.wire_break:
            self.quality = Quality.BAD
        elif self.raw_temperature < self.range_low:
            self.value, self.quality = self.range_low, Quality.UNCERTAIN
        elif self.raw_temperature > self.range_high:
            self.value, self.quality = self.range_high, Quality.UNCERTAIN
        else:
            self.value, self.quality = self.raw_temperature, Quality.GOOD
        self.notify()

    @method
    def attach(self, observer: IObserver) -> BOOL:
        """Add ``observer`` at the end; FALSE if refused, ``refusal`` says why."""
        if not observer:
            self.refusal = AttachRefusal.NULL_OBSERVER
            return False
        if self.index_of(observer) > 0:
            self.refusal = AttachRefusal.ALREADY_ATTACHED
            return False
        if self.count >= MAX_OBSERVERS:
            self.refusal = AttachRefusal.LIST_FULL
            return False
        self.refusal = AttachRefusal.NONE
        self.count += 1
        self.observers[self.count] = observer
        return True

    @method
    def detach(self, observer: IObserver) -> BOOL:
        """Remove ``observer`` and close the gap; FALSE if it was not attached."""
        index = self.index_of(observer)
        if index == 0:
            return False
        # Shift the tail down so observers 1..count stay contiguous and in attach order.
        for i in range(index, self.count):
            self.observers[i] = self.observers[i + 1]
        self.observers[self.count] = NULL
        self.count -= 1
        return True

    @prop
    def observer_count(self) -> INT:
        return self.count

    @method(PRIVATE)
    def index_of(self, observer: IObserver) -> INT:
        for i in range(1, self.count + 1):
            if self.observers[i] == observer:
                return i
        return 0

    @method(PRIVATE)
    def notify(self) -> None:
        for i in range(1, self.count + 1):
            self.observers[i].update(self.value, self.quality)


class HighTemperatureAlarm(FunctionBlock, IObserver):
    """``FUNCTION_BLOCK FB_HighTempAlarm IMPLEMENTS I_Observer``.

    ``active`` comes on once the value has stayed above ``high_limit`` for
    ``delay`` (an on-delay TON) and goes off only below
    ``high_limit - hysteresis``. A BAD value sets ``sensor_fault``, stops the
    on-delay and holds ``active`` as it was: a dead sensor neither raises nor
    clears a high alarm.
    """

    high_limit: REAL = VAR_INPUT(90.0)
    hysteresis: REAL = VAR_INPUT(5.0)
    delay: TIME = VAR_INPUT(T("300ms"))
    active: BOOL = VAR_OUTPUT(False)
    sensor_fault: BOOL = VAR_OUTPUT(False)
    on_delay: TON = VAR()

    @method
    def update(self, value: REAL, quality: Quality) -> None:
        if quality == Quality.BAD:
            self.sensor_fault = True
            self.on_delay(IN=False, PT=self.delay)
            return
        self.sensor_fault = False
        self.on_delay(IN=value > self.high_limit, PT=self.delay)
        if self.active:
            if value < self.high_limit - self.hysteresis:
                self.active = False
        elif self.on_delay.Q:
            self.active = True


class TrendBuffer(FunctionBlock, IObserver):
    """``FUNCTION_BLOCK FB_TrendBuffer IMPLEMENTS I_Observer``.

    A ring of the last ``TREND_SIZE`` samples, one kept every ``decimation``
    updates; the oldest is overwritten when the ring is full.
    """

    decimation: INT = VAR_INPUT(1)
    stored: INT = VAR_OUTPUT(0)
    samples: ARRAY[TrendSample] = VAR(bounds=(0, TREND_SIZE - 1))
    head: INT = VAR(0)
    skipped: INT = VAR(0)

    @method
    def update(self, value: REAL, quality: Quality) -> None:
        self.skipped += 1
        if self.skipped < self.decimation:
            return
        self.skipped = 0
        slot = self.samples[self.head]
        slot.value, slot.quality = value, quality
        self.head = (self.head + 1) % TREND_SIZE
        self.stored = min(self.stored + 1, TREND_SIZE)

    @method
    def value_at(self, age: INT) -> REAL:
        """The sample ``age`` updates back (0 = newest); 0.0 past the ``stored`` samples."""
        if not 0 <= age < self.stored:
            return 0.0
        # + TREND_SIZE: ST's MOD keeps the sign of a negative operand, Python's % does not.
        value: REAL = self.samples[(self.head - 1 - age + TREND_SIZE) % TREND_SIZE].value
        return value


class EventLogger(FunctionBlock, IObserver):
    """``FUNCTION_BLOCK FB_EventLogger IMPLEMENTS I_Observer``.

    Records the first sample, every quality change, and every move of more
    than ``deadband`` from the last recorded value, stamped with the task
    time, in a ring of ``LOG_SIZE`` entries.
    """

    deadband: REAL = VAR_INPUT(5.0)
    total: DINT = VAR_OUTPUT(0)
    entries: ARRAY[LogEntry] = VAR(bounds=(0, LOG_SIZE - 1))
    no_entry: LogEntry = VAR({"quality": Quality.BAD})
    last_value: REAL = VAR(0.0)
    last_quality: Quality = VAR(Quality.GOOD)

    @method
    def update(self, value: REAL, quality: Quality) -> None:
        if self.total == 0:
            self.record(value, quality, LogReason.FIRST_SAMPLE)
        elif quality != self.last_quality:
            self.record(value, quality, LogReason.QUALITY_CHANGED)
        elif quality != Quality.BAD and abs(value - self.last_value) >= self.deadband:
            self.record(value, quality, LogReason.DEADBAND)

    @method
    def entry(self, number: DINT) -> LogEntry:
        """Entry ``number`` (1 = the first ever recorded); once out of the ring, an empty entry of quality BAD."""
        if not (self.total - LOG_SIZE < number <= self.total and number >= 1):
            return self.no_entry
        found: LogEntry = self.entries[(number - 1) % LOG_SIZE]
        return found

    @method(PRIVATE)
    def record(self, value: REAL, quality: Quality, reason: LogReason) -> None:
        slot = self.entries[self.total % LOG_SIZE]
        slot.time_ms, slot.value, slot.quality, slot.reason = now_ms(), value, quality, reason
        self.total += 1
        self.last_value, self.last_quality = value, quality


class ReactorMain(Program):
    """``PROGRAM PRG_ReactorMain``: simulates TT101 and wires the observers.

    The jacket heats at ``rate`` °C per scan from 80 °C; the scenario steps in
    ``body`` (heat up, cool down, wire break, HMI trend closed) are keyed to
    the scan count so the run is repeatable.
    """

    tt101: TemperatureTransmitter = VAR()
    high_alarm: HighTemperatureAlarm = VAR()
    trend: TrendBuffer = VAR()
    logger: EventLogger = VAR()
    temperature: REAL = VAR(80.0)
    rate: REAL = VAR(0.5)
    wire_break: BOOL = VAR(False)
    scan: DINT = VAR(0)

    def fb_init(self, init_retains: bool, in_copy_code: bool) -> None:
        self.tt101.attach(self.high_alarm)
        self.tt101.attach(self.trend)
        self.tt101.attach(self.logger)

    def body(self) -> None:
        self.scan += 1
        if self.scan == 40:
            self.rate = -0.5        # cooling water valve opens
        elif self.scan == 60:
            self.tt101.detach(self.trend)   # HMI trend screen closed
        elif self.scan == 80:
            self.wire_break = True  # TT101 cable pulled
        elif self.scan == 90:
            self.wire_break = False
        self.temperature += self.rate
        self.tt101(raw_temperature=self.temperature, wire_break=self.wire_break)


def main() -> None:
    """Run the reactor jacket for 1 s of PLC time and print what happened.

    >>> main()
    t=   0 ms  observers attached: 3
    t= 500 ms  alarm ACTIVE at 93.5 C (above 90.0 C for 300 ms)
    t= 590 ms  trend detached, observers: 2
    t= 680 ms  alarm cleared at 84.5 C (below 85.0 C)
    t= 790 ms  sensor fault: quality BAD
    t= 890 ms  quality GOOD again at 74.0 C
    log: 10 entries, the last 4:
      t= 760 ms   80.5 C  GOOD  DEADBAND
      t= 790 ms   79.5 C  BAD   QUALITY_CHANGED
      t= 890 ms   74.0 C  GOOD  QUALITY_CHANGED
      t= 990 ms   69.0 C  GOOD  DEADBAND
    trend: 8 samples, newest 89.5 C
    """
    program = ReactorMain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    print(f"t={rt.time_ms:4d} ms  observers attached: {program.tt101.observer_count}")
    limit, hysteresis, delay = program.high_alarm.high_limit, program.high_alarm.hysteresis, program.high_alarm.delay
    alarm, fault, count = False, False, program.tt101.observer_count
    for _ in range(100):
        now = rt.time_ms
        rt.run(cycles=1)
        value = program.tt101.value
        if program.high_alarm.active != alarm:
            alarm = program.high_alarm.active
            if alarm:
                print(f"t={now:4d} ms  alarm ACTIVE at {value:.1f} C (above {limit:.1f} C for {delay} ms)")
            else:
                print(f"t={now:4d} ms  alarm cleared at {value:.1f} C (below {limit - hysteresis:.1f} C)")
        if program.high_alarm.sensor_fault != fault:
            fault = program.high_alarm.sensor_fault
            if fault:
                print(f"t={now:4d} ms  sensor fault: quality {program.tt101.quality.name}")
            else:
                print(f"t={now:4d} ms  quality GOOD again at {value:.1f} C")
        if program.tt101.observer_count != count:
            count = program.tt101.observer_count
            print(f"t={now:4d} ms  trend detached, observers: {count}")
    print(f"log: {program.logger.total} entries, the last 4:")
    for number in range(program.logger.total - 3, program.logger.total + 1):
        entry = program.logger.entry(number)
        print(f"  t={entry.time_ms:4d} ms  {entry.value:5.1f} C  {entry.quality.name:4}  {entry.reason.name}")
    print(f"trend: {program.trend.stored} samples, newest {program.trend.value_at(0):.1f} C")


SHOWCASE = Showcase(
    use_when="consumers of a value come and go at run time and the producer must stay closed to edits",
    columns=(
        Column("TT101 C", lambda p: p.tt101.value, ".1f", watch=False),
        Column("quality", lambda p: p.tt101.quality),
        Column("observers", lambda p: p.tt101.observer_count),
        Column("alarm", lambda p: p.high_alarm.active),
        Column("sensor fault", lambda p: p.high_alarm.sensor_fault),
        Column("log", lambda p: p.logger.total, watch=False),
    ),
    cycles=100,
    tour_cycles=100,
)
