"""Iterator: page through the alarm history ring buffer, newest first, without exposing the array.

Intent
------

Give sequential access to the elements of an aggregate without exposing its
internal representation, so the code that walks it does not depend on how it
is stored.

The PLC problem
---------------

The alarm history of a process cell is a ring buffer of the last
``ALARM_CAPACITY`` alarms: a new alarm overwrites the oldest one. The HMI shows
it as a list of ``PAGE_ROWS`` rows, newest first, with "first", "next" and
"previous" page buttons; a second list shows only the alarms of severity
ALARM and above. Neither list should know that the history is a ring, where
its write index is, or how it wraps; and nothing outside the history may
write into it.

The iterator remembers the sequence number of the newest alarm when it is
reset (its anchor) and walks back from there by sequence number, so:

- indices are always inside the ring's bounds, and each call does a bounded
  amount of work: no allocation, one struct copy per ``next``;
- alarms raised while a client walks the iterator (over several scans, say)
  do not shift what it reads;
- an alarm that the ring overwrote while being paged is never returned:
  ``has_next`` turns FALSE and the iterator reports ``overrun``.

Every page is read from the newest alarm on (reset, then skip), so the HMI
list follows new alarms as an alarm banner does.

Roles
-----

- Iterator → ``IAlarmIterator`` (``I_AlarmIterator``): ``has_next``,
  ``next``, ``reset``.
- Concrete iterators → ``AlarmIterator`` (``FB_AlarmIterator``), walking the
  history newest first, and ``SeverityFilter`` (``FB_SeverityFilter``),
  an iterator over another iterator that skips low-severity alarms.
- Aggregate → ``AlarmHistory`` (``FB_AlarmHistory``): the ring of
  ``AlarmEntry`` (``ST_AlarmEntry``); its only read access is the INTERNAL
  ``copy_out`` the iterators use.
- Client → ``AlarmPager`` (``FB_AlarmPager``), the HMI list, which sees only
  ``IAlarmIterator``; ``AlarmHmi`` (``PRG_AlarmHmi``) wires them.

IEC 61131-3 mapping
-------------------

::

    INTERFACE I_AlarmIterator
        METHOD HasNext : BOOL
        METHOD Next : BOOL   VAR_IN_OUT stEntry : ST_AlarmEntry; END_VAR
                             // FALSE, stEntry untouched, past the last one
        METHOD Reset

    FUNCTION_BLOCK FB_AlarmHistory
        VAR aRing : ARRAY[1..ALARM_CAPACITY] OF ST_AlarmEntry; END_VAR
        VAR_OUTPUT nTotal : UDINT; END_VAR
        METHOD Push : UDINT
        METHOD INTERNAL CopyOut : BOOL
            VAR_INPUT nSequence : UDINT; END_VAR
            VAR_IN_OUT stEntry : ST_AlarmEntry; END_VAR

    FUNCTION_BLOCK FB_AlarmIterator IMPLEMENTS I_AlarmIterator
        VAR rHistory : REFERENCE TO FB_AlarmHistory;
            nAnchor : UDINT; nAvailable, nPosition : INT; END_VAR
        VAR_OUTPUT bOverrun : BOOL; END_VAR
        PROPERTY Bound : BOOL   // __ISVALIDREF(rHistory): unbound, it yields nothing

    FUNCTION_BLOCK FB_SeverityFilter IMPLEMENTS I_AlarmIterator
        VAR iSource : I_AlarmIterator; eMinimum : E_Severity;
            stPending : ST_AlarmEntry; bHasPending : BOOL; END_VAR

    FUNCTION_BLOCK FB_AlarmPager
        VAR_INPUT bFirstPage, bNextPage, bPrevPage : BOOL; END_VAR
        VAR_OUTPUT aRows : ARRAY[1..PAGE_ROWS] OF ST_AlarmEntry;
                   nRows, nPage : INT; bMore : BOOL; END_VAR
        VAR iIterator : I_AlarmIterator; END_VAR

When not to use it on a PLC
---------------------------

Inside the block that owns an array, a plain ``FOR`` loop over its bounds is
shorter and faster than an iterator. An iterator earns its place when the
client must not see the storage (here: the ring's wrap and write index) or
when several storages (a filter, another buffer) must look the same to one
client. On a slow task, read one page per scan, not the whole history.

References
----------

- Gamma, Helm, Johnson, Vlissides: *Design Patterns*, Addison-Wesley 1994,
  "Iterator".
- IEC 61131-3:2013 (3rd edition): interfaces, methods, ``REFERENCE TO``,
  ``VAR_IN_OUT``, the ``INTERNAL`` access specifier, ARRAY bounds.
- Beckhoff InfoSys, TwinCAT 3 PLC: "Interface", "REFERENCE", "Method",
  "Access specifier INTERNAL".
- CODESYS Online Help: "Object: Interface", "Reference", "Object: Method".
- ISA-18.2, *Management of Alarm Systems for the Process Industries*, for the
  alarm history and its presentation.
"""

from __future__ import annotations

from iecoop import (
    ARRAY,
    BOOL,
    INT,
    INTERNAL,
    PROTECTED,
    REFERENCE_TO,
    STRING,
    TIME,
    UDINT,
    UINT,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    FunctionBlock,
    IecEnum,
    Interface,
    Program,
    Struct,
    T,
    adr,
    is_valid_ref,
    memcpy,
    method,
    prop,
    ref_assign,
    sizeof,
)
from iecoop.runtime import Runtime, Task, now_ms
from iecoop.stdlib import R_TRIG
from patterns.showcase.entry import Column, Showcase, press, steps

__all__ = [
    "ALARM_CAPACITY",
    "DEMO_ALARMS",
    "DEMO_COUNT",
    "PAGE_ROWS",
    "AlarmEntry",
    "AlarmHistory",
    "AlarmHmi",
    "AlarmIterator",
    "AlarmPager",
    "DemoAlarm",
    "IAlarmIterator",
    "Severity",
    "SeverityFilter",
    "main",
]

#: Alarms the history keeps; the next one overwrites the oldest.
ALARM_CAPACITY = 8
#: Rows of the HMI alarm list.
PAGE_ROWS = 4


class Severity(IecEnum):
    """ST: ``TYPE E_Severity : (INFO := 1, WARNING, ALARM, CRITICAL) INT``."""

    INFO = 1
    WARNING = 2
    ALARM = 3
    CRITICAL = 4


class AlarmEntry(Struct):
    """One alarm of the history. ST: ``TYPE ST_AlarmEntry : STRUCT``."""

    sequence: UDINT = 0
    code: UINT = 0
    severity: Severity = Severity.INFO
    raised_at: TIME = 0
    text: STRING = VAR("", length=32)


class AlarmHistory(FunctionBlock):
    """The aggregate: a ring of the last ``ALARM_CAPACITY`` alarms.

    ST: ``FUNCTION_BLOCK FB_AlarmHistory``. Alarm number ``n`` (its sequence,
    1, 2, 3 ...) lives in slot ``(n - 1) MOD ALARM_CAPACITY + 1``; only the
    INTERNAL ``copy_out`` reads the ring, and only ``push`` writes it.
    """

    ring: ARRAY[AlarmEntry] = VAR(bounds=(1, ALARM_CAPACITY))
    total: UDINT = VAR_OUTPUT(0)

    @method
    def push(self, code: UINT, severity: Severity, text: STRING) -> UDINT:
        """Record an alarm with the task-clock time; return its sequence number."""
        self.total += 1
        entry = self.ring[(self.total - 1) % ALARM_CAPACITY + 1]
        entry.sequence, entry.code, entry.severity = self.total, code, severity
        entry.raised_at, entry.text = now_ms(), text
        return self.total

    @prop
    def count(self) -> INT:
        """How many alarms the ring holds now."""
        return min(self.total, ALARM_CAPACITY)

    @method(INTERNAL)
    def copy_out(self, sequence: UDINT, entry: AlarmEntry) -> BOOL:
        """Copy alarm ``sequence`` into ``entry``; FALSE when it was never raised or was overwritten."""
        if sequence == 0 or sequence > self.total or self.total - sequence >= ALARM_CAPACITY:
            return False
        memcpy(adr(entry), adr(self, "ring", (sequence - 1) % ALARM_CAPACITY + 1), sizeof(AlarmEntry))
        return True


class IAlarmIterator(Interface):
    """Walk alarms newest first. ST: ``INTERFACE I_AlarmIterator``."""

    @method
    def has_next(self) -> BOOL:
        raise NotImplementedError

    @method
    def next(self, entry: AlarmEntry) -> BOOL:
        raise NotImplementedError

    @method
    def reset(self) -> None: ...


class AlarmIterator(FunctionBlock, IAlarmIterator):
    """Newest-first iterator over an ``AlarmHistory``, anchored at the newest alarm by ``reset``.

    ST: ``FUNCTION_BLOCK FB_AlarmIterator IMPLEMENTS I_AlarmIterator``; the
    history is a ``REFERENCE TO`` injected at FB_init (or by ``bind``).
    """

    history: REFERENCE_TO[AlarmHistory] = VAR()
    anchor: UDINT = VAR(0)
    available: INT = VAR(0)
    position: INT = VAR_OUTPUT(0)
    overrun: BOOL = VAR_OUTPUT(False)

    def fb_init(self, init_retains: bool, in_copy_code: bool, history: AlarmHistory | None = None) -> None:
        if history is not None:
            self.bind(history)

    @method
    def bind(self, history: AlarmHistory) -> None:
        ref_assign(self, "history", history)
        self.reset()

    @prop
    def bound(self) -> BOOL:
        """TRUE while the iterator has a live history; without one it yields nothing."""
        return is_valid_ref(self, "history")

    @method
    def reset(self) -> None:
        self.position = 0
        self.overrun = False
        if self.bound:
            self.anchor = self.history.total
            self.available = self.history.count
        else:
            self.anchor, self.available = 0, 0

    @method
    def has_next(self) -> BOOL:
        # A history deleted while walking must not be read: __ISVALIDREF guards every access.
        if not self.bound or self.position >= self.available:
            return False
        if self.history.total - (self.anchor - self.position) >= ALARM_CAPACITY:
            self.overrun = True  # the ring overwrote it while we were paging
            return False
        return True

    @method
    def next(self, entry: AlarmEntry) -> BOOL:
        """Copy the next alarm into ``entry`` and step on; FALSE, ``entry`` untouched, when there is none."""
        if not self.has_next():
            return False
        self.history.copy_out(self.anchor - self.position, entry)
        self.position += 1
        return True


class SeverityFilter(FunctionBlock, IAlarmIterator):
    """An iterator over another iterator that yields only alarms of at least ``minimum`` severity.

    ST: ``FUNCTION_BLOCK FB_SeverityFilter IMPLEMENTS I_AlarmIterator``.
    ``has_next`` looks ahead into ``pending``; over one pass it reads each
    alarm of the source once, so the work stays bounded by the source.
    """

    source: IAlarmIterator = VAR()
    minimum: Severity = VAR(Severity.ALARM)
    pending: AlarmEntry = VAR()
    has_pending: BOOL = VAR(False)

    def fb_init(
        self,
        init_retains: bool,
        in_copy_code: bool,
        source: IAlarmIterator | None = None,
        minimum: Severity = Severity.ALARM,
    ) -> None:
        self.minimum = minimum
        if source is not None:
            self.attach(source)

    @method
    def attach(self, source: IAlarmIterator) -> None:
        self.source = source
        self.has_pending = False

    @method
    def reset(self) -> None:
        self.source.reset()
        self.has_pending = False

    @method
    def has_next(self) -> BOOL:
        while not self.has_pending:
            if not self.source.next(self.pending):
                break
            self.has_pending = self.pending.severity >= self.minimum
        return self.has_pending

    @method
    def next(self, entry: AlarmEntry) -> BOOL:
        """Copy the next alarm of at least ``minimum`` severity into ``entry``; FALSE when there is none."""
        if not self.has_next():
            return False
        memcpy(adr(entry), adr(self, "pending"), sizeof(AlarmEntry))
        self.has_pending = False
        return True


class AlarmPager(FunctionBlock):
    """The HMI alarm list: ``PAGE_ROWS`` rows per page, read through ``IAlarmIterator`` only.

    ST: ``FUNCTION_BLOCK FB_AlarmPager``. The page buttons act on their rising
    edge; ``show(page)`` reads at most ``page * PAGE_ROWS`` entries.
    """

    first_page: BOOL = VAR_INPUT(False)
    next_page: BOOL = VAR_INPUT(False)
    prev_page: BOOL = VAR_INPUT(False)
    rows: ARRAY[AlarmEntry] = VAR_OUTPUT(bounds=(1, PAGE_ROWS))
    row_count: INT = VAR_OUTPUT(0)
    page: INT = VAR_OUTPUT(0)
    more: BOOL = VAR_OUTPUT(False)
    iterator: IAlarmIterator = VAR()
    skipped: AlarmEntry = VAR()
    edges: ARRAY[R_TRIG] = VAR(bounds=(1, 3))

    def fb_init(self, init_retains: bool, in_copy_code: bool, iterator: IAlarmIterator | None = None) -> None:
        if iterator is not None:
            self.attach(iterator)

    @method
    def attach(self, iterator: IAlarmIterator) -> None:
        self.iterator = iterator

    def body(self) -> None:
        self.edges[1](CLK=self.first_page)
        self.edges[2](CLK=self.next_page)
        self.edges[3](CLK=self.prev_page)
        if self.edges[1].Q:
            self.show(1)
        if self.edges[2].Q and self.more:
            self.show(self.page + 1)
        if self.edges[3].Q and self.page > 1:
            self.show(self.page - 1)

    @method
    def show(self, page: INT) -> INT:
        """Load page ``page`` (1 = newest alarms) into ``rows``; return the number of rows filled.

        Pages start at 1: a lower number is refused, returns 0 and leaves the list as it was.
        """
        if page < 1:
            return 0
        self.iterator.reset()
        for _ in range((page - 1) * PAGE_ROWS):
            if not self.iterator.next(self.skipped):
                break
        self.row_count = 0
        # ST's AND evaluates both sides: the row is only indexed while there is room for it.
        while self.row_count < PAGE_ROWS:
            if not self.iterator.next(self.rows[self.row_count + 1]):
                break
            self.row_count += 1
        self.page = page
        self.more = self.iterator.has_next()
        return self.row_count


class DemoAlarm(Struct):
    """One alarm of the demo plant. ST: ``TYPE ST_DemoAlarm : STRUCT code : UINT; severity : E_Severity; text : STRING(32);``."""

    code: UINT = 0
    severity: Severity = Severity.INFO
    text: STRING = VAR("", length=32)


#: The demo plant's alarms, raised one per cycle while ``AlarmHmi.simulate`` is TRUE
#: (the initial value of the program's ``VAR CONSTANT demo : ARRAY[1..DEMO_COUNT] OF ST_DemoAlarm``).
DEMO_ALARMS: list[DemoAlarm] = [
    DemoAlarm(code=101, severity=Severity.WARNING, text="TT101 temperature high"),
    DemoAlarm(code=102, severity=Severity.INFO, text="P201 started"),
    DemoAlarm(code=103, severity=Severity.ALARM, text="LS3 tank level high"),
    DemoAlarm(code=104, severity=Severity.INFO, text="XV101 opened"),
    DemoAlarm(code=105, severity=Severity.CRITICAL, text="PT102 pressure high-high"),
    DemoAlarm(code=106, severity=Severity.WARNING, text="M301 motor current high"),
    DemoAlarm(code=107, severity=Severity.INFO, text="P201 stopped"),
    DemoAlarm(code=108, severity=Severity.ALARM, text="FT104 no flow"),
    DemoAlarm(code=109, severity=Severity.INFO, text="operator login"),
    DemoAlarm(code=110, severity=Severity.ALARM, text="TT101 temperature high-high"),
]
DEMO_COUNT = len(DEMO_ALARMS)


class AlarmHmi(Program):
    """The alarm page of the HMI: all alarms, and alarms of severity ALARM and above.

    ST: ``PROGRAM PRG_AlarmHmi``. FB_init wires the sibling blocks
    (history → iterators → filter → pagers).
    """

    simulate: BOOL = VAR_INPUT(False)
    demo: ARRAY[DemoAlarm] = VAR(DEMO_ALARMS, bounds=(1, DEMO_COUNT), constant=True)
    raised: INT = VAR(0)
    history: AlarmHistory = VAR()
    cursor: AlarmIterator = VAR()
    alarm_cursor: AlarmIterator = VAR()
    alarms_only: SeverityFilter = VAR(fb_init={"minimum": Severity.ALARM})
    all_pager: AlarmPager = VAR()
    alarm_pager: AlarmPager = VAR()

    def fb_init(self, init_retains: bool, in_copy_code: bool) -> None:
        self.cursor.bind(self.history)
        self.alarm_cursor.bind(self.history)
        self.alarms_only.attach(self.alarm_cursor)
        self.all_pager.attach(self.cursor)
        self.alarm_pager.attach(self.alarms_only)

    def body(self) -> None:
        if self.simulate and self.raised < DEMO_COUNT:
            self.raised += 1
            alarm: DemoAlarm = self.demo[self.raised]
            self.history.push(alarm.code, alarm.severity, alarm.text)
        self.all_pager()
        self.alarm_pager()


def _row(entry: AlarmEntry) -> str:
    return f"  #{entry.sequence:<2} t={entry.raised_at:3d} ms  {Severity(entry.severity).name:<8} {entry.text}"


def main() -> None:
    """Raise the ten demo alarms (one per 10 ms cycle) and page through the history on the HMI.

    >>> main()
    10 alarms raised, 8 kept
    page 1 (more: True):
      #10 t= 90 ms  ALARM    TT101 temperature high-high
      #9  t= 80 ms  INFO     operator login
      #8  t= 70 ms  ALARM    FT104 no flow
      #7  t= 60 ms  INFO     P201 stopped
    page 2 (more: False):
      #6  t= 50 ms  WARNING  M301 motor current high
      #5  t= 40 ms  CRITICAL PT102 pressure high-high
      #4  t= 30 ms  INFO     XV101 opened
      #3  t= 20 ms  ALARM    LS3 tank level high
    ALARM and above, page 1: #10, #8, #5, #3
    """
    hmi = AlarmHmi()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), hmi)
    hmi.simulate = True
    rt.run(cycles=len(DEMO_ALARMS))
    hmi.simulate = False
    print(f"{hmi.history.total} alarms raised, {hmi.history.count} kept")
    pager = hmi.all_pager
    for button in ("first_page", "next_page"):
        setattr(pager, button, True)
        rt.run(cycles=1)
        setattr(pager, button, False)
        rt.run(cycles=1)
        print(f"page {pager.page} (more: {pager.more}):")
        for i in range(1, pager.row_count + 1):
            print(_row(pager.rows[i]))
    hmi.alarm_pager.first_page = True
    rt.run(cycles=1)
    shown = [f"#{hmi.alarm_pager.rows[i].sequence}" for i in range(1, hmi.alarm_pager.row_count + 1)]
    print(f"ALARM and above, page 1: {', '.join(shown)}")


SHOWCASE = Showcase(
    use_when="a client walks a storage (a ring buffer, a filtered view) without seeing how it is kept",
    columns=(
        Column("raised", lambda p: p.history.total, watch=False),
        Column("kept", lambda p: p.history.count, watch=False),
        Column("page", lambda p: p.all_pager.page),
        Column("rows", lambda p: p.all_pager.row_count),
        Column("more", lambda p: p.all_pager.more),
        Column("top row", lambda p: p.all_pager.rows[1].text if p.all_pager.row_count else "-"),
    ),
    script=steps((1, "simulate", True), (11, "simulate", False), *press("all_pager.first_page", 12),
                 *press("all_pager.next_page", 14), *press("all_pager.first_page", 16)),
    cycles=18,
    tour_cycles=18,
)
