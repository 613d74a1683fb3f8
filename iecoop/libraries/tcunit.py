"""TcUnit (and CfUnit, its CODESYS port): unit tests for PLC code, written in ST, run by iecoop.

A test suite is a FUNCTION_BLOCK that ``EXTENDS FB_TestSuite``; its body calls
its tests, and each test opens with ``TEST('Name')``, asserts, and closes with
``TEST_FINISHED()``. A test PROGRAM declares the suites and calls ``RUN()``:
every suite instance registers itself when it is created (its FB_init), and
``RUN()`` calls their bodies each cycle until every test has finished, then
logs TcUnit's summary. Only failed asserts are recorded.

ST::

    FUNCTION_BLOCK FB_Math_Test EXTENDS TcUnit.FB_TestSuite
    TEST('OnePlusOne');
    AssertEquals_INT(Expected := 2, Actual := 1 + 1, Message := 'sum');
    TEST_FINISHED();
    END_FUNCTION_BLOCK

    PROGRAM PRG_TEST
    VAR fbMath : FB_Math_Test; END_VAR
    TcUnit.RUN();
    END_PROGRAM

Python:

>>> from iecoop import INT, Program, VAR
>>> from iecoop.libraries import tcunit
>>> from iecoop.testing import VirtualPlc
>>> class FB_Math_Test(tcunit.FB_TestSuite):
...     def body(self) -> None:
...         tcunit.TEST("OnePlusOne")
...         self.AssertEquals_INT(Expected=2, Actual=1 + 1, Message="sum")
...         tcunit.TEST_FINISHED()
...         tcunit.TEST("Wrong")
...         self.AssertEquals_INT(Expected=3, Actual=1 + 1, Message="sum")
...         tcunit.TEST_FINISHED()
>>> with tcunit.registry() as tests:
...     class PRG_TEST(Program):
...         fbMath: FB_Math_Test = VAR()
...         def body(self) -> None:
...             tcunit.RUN()
...     plc = VirtualPlc()
...     prg = plc.add(PRG_TEST())
...     tests.name_suites(prg)          # instance paths, as TcUnit reports them
...     plc.run_cycles(2)
>>> tests.done, [(t.name, t.status) for t in tests.suites[0].tests]
(True, [('OnePlusOne', 'passed'), ('Wrong', 'failed')])
>>> print(tests.suites[0].tests[1].failures[0].line())
FAILED TEST 'PRG_TEST.fbMath@Wrong', EXP: 3, ACT: 2, MSG: sum

Registration is per registry: the one ``registry()`` makes active (the runner
and the pytest plugin make one per run), else the one of the runtime whose
cycle calls ``RUN()`` (a fresh runtime starts a fresh one). Semantics follow
TcUnit's documentation (https://tcunit.org, "API" and "FAQ"):

- a test stays open over cycles until ``TEST_FINISHED()``; asserts made after
  it are ignored;
- ``TEST_ORDERED`` tests run one after another, in the order of their first
  call: it returns TRUE only for the first one not finished;
- ``RUN_IN_SEQUENCE()`` runs the suites one after another, in declaration
  order, the TIME it is given apart (``RUN_IN_SEQUENCE(T#5S)``; by default
  ``GVL_Param_TcUnit.TimeBetweenTestSuitesExecution``);
- asserts identical in test, values, message and cycle are reported once;
- a test named with the prefix ``disabled_`` is not run and is reported as
  skipped;
- a test that never finishes runs until the registry's per-test limit (PLC
  time; ``limit_ms``, set by the runner) and then fails naming that limit.
"""

from __future__ import annotations

import contextlib
import contextvars
import dataclasses
import os
import sys
from collections.abc import Callable, Iterator
from types import FrameType
from typing import Any, Literal

from iecoop import BOOL, DINT, DWORD, POINTER_TO, STRING, TIME, UDINT, UINT, VAR, GlobalVariables, gvl, method
from iecoop.exceptions import ExceptionCode, PlcException, st_caller
from iecoop.literals import format_time
from iecoop.generics import ANY, AnyType
from iecoop.libraries import _tcunit_asserts as asserts, tc2_system
from iecoop.libraries.tc2_system import T_MaxString
from iecoop.memory import Pointer, adr, memcmp
from iecoop.metadata import iec_class, st_name
from iecoop.pou import FunctionBlock
from iecoop.runtime.clock import Clock, task_clock
from iecoop import types

__all__ = [
    "FB_TestSuite", "GVL_Param_TcUnit", "IS_TEST_FINISHED", "RUN", "RUN_IN_SEQUENCE", "TCUNIT_ADSLOGSTR", "TEST",
    "TEST_FINISHED", "TEST_FINISHED_NAMED", "TEST_ORDERED", "WRITE_PROTECTED_BOOL", "WRITE_PROTECTED_BYTE",
    "WRITE_PROTECTED_DATE", "WRITE_PROTECTED_DATE_AND_TIME", "WRITE_PROTECTED_DINT", "WRITE_PROTECTED_DWORD",
    "WRITE_PROTECTED_INT", "WRITE_PROTECTED_LINT", "WRITE_PROTECTED_LREAL", "WRITE_PROTECTED_LWORD",
    "WRITE_PROTECTED_REAL", "WRITE_PROTECTED_SINT", "WRITE_PROTECTED_STRING", "WRITE_PROTECTED_TIME",
    "WRITE_PROTECTED_TIME_OF_DAY", "WRITE_PROTECTED_UDINT", "WRITE_PROTECTED_UINT", "WRITE_PROTECTED_ULINT",
    "WRITE_PROTECTED_USINT", "WRITE_PROTECTED_WORD", "WRITE_PROTECTED_WSTRING",
]

#: The prefix TcUnit reads as "do not run this test", in any case (TcUnit FAQ, "disable a test": ``DISABLED_``).
DISABLED_PREFIX = "disabled_"


@gvl
class GVL_Param_TcUnit(GlobalVariables):
    """TcUnit's library parameters (``VAR_GLOBAL CONSTANT``), with TcUnit's documented defaults.

    ``MaxNumberOfTestsForEachTestSuite`` and ``MaxNumberOfAssertsForEachTestSuite``
    bound what a suite records; a test past the bound fails naming the parameter.
    ``TimeBetweenTestSuitesExecution`` is the pause ``RUN_IN_SEQUENCE`` makes between
    suites. The xUnit and ADS log parameters are there for source compatibility:
    iecoop writes its results through ``iecoop test --junitxml`` and pytest instead.
    """

    MaxNumberOfTestSuites: UINT = VAR(1000, constant=True)
    MaxNumberOfTestsForEachTestSuite: UINT = VAR(100, constant=True)
    MaxNumberOfAssertsForEachTestSuite: UINT = VAR(1000, constant=True)
    TimeBetweenTestSuitesExecution: TIME = VAR(0, constant=True)
    LogExtendedResults: BOOL = VAR(True, constant=True)
    AdsLogMessageFifoRingBufferSize: UINT = VAR(2000, constant=True)
    xUnitEnablePublish: BOOL = VAR(False, constant=True)
    xUnitFilePath: STRING = VAR("C:\\tmp\\xUnitTestResults.xml", length=255, constant=True)
    xUnitBufferSize: UDINT = VAR(65535, constant=True)


# --- results ----------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class AssertFailure:
    """One failed assert: the assert's name, its message, the expected and actual values as ST text.

    ``index`` is where two arrays first differ (``[3]``, ``[1, 2]``; empty for a
    size difference or a scalar); ``cycle`` is the RUN() cycle it was made in (from 1);
    ``file`` and ``lineno`` are where the assert was called: the ST file and line
    for loaded ST, the Python file and line for a suite written in Python.
    """

    test: str
    suite: str
    assertion: str
    message: str
    expected: str
    actual: str
    cycle: int
    index: str = ""
    file: str = ""
    lineno: int = 0

    def line(self) -> str:
        """The line TcUnit logs for it: ``FAILED TEST 'PRG_TEST.fbSuite@Test', EXP: 3, ACT: 2, MSG: sum``."""
        at = f" at index {self.index}" if self.index else ""
        return f"FAILED TEST '{self.suite}@{self.test}', EXP: {self.expected}, ACT: {self.actual}{at}, MSG: {self.message}"


Status = Literal["passed", "failed", "skipped", "open"]


@dataclasses.dataclass(eq=False)
class TestRecord:
    """One test of a suite, as TcUnit records it."""

    __test__ = False  # a record, not a pytest test class

    name: str
    suite: str
    ordered: bool = False
    finished: bool = False
    skipped: bool = False
    #: why the test failed besides its asserts (the limit it hit, a duplicate name)
    error: str = ""
    failures: list[AssertFailure] = dataclasses.field(default_factory=list)
    #: the RUN() cycles (from 1) it started and finished in; 0: not yet
    started_cycle: int = 0
    finished_cycle: int = 0
    started_ns: int = -1
    finished_ns: int = -1
    _seen: set[tuple[Any, ...]] = dataclasses.field(default_factory=set, repr=False)
    #: the RUN() cycle TEST() last declared it in: a second declaration in one cycle is a duplicate
    _declared_cycle: int = dataclasses.field(default=0, repr=False)

    @property
    def status(self) -> Status:
        """``passed``, ``failed``, ``skipped`` or ``open`` (still running)."""
        if self.skipped:
            return "skipped"
        if self.failures or self.error:
            return "failed"
        return "passed" if self.finished else "open"

    @property
    def duration_ns(self) -> int:
        """PLC time from its first to its last cycle (0 before it finished)."""
        return max(0, self.finished_ns - self.started_ns) if self.finished_ns >= 0 and self.started_ns >= 0 else 0


class SuiteState:
    """A registered suite instance: its tests in the order of their first call, and the one running."""

    def __init__(self, instance: FB_TestSuite, key: int, number: int) -> None:
        self.instance = instance
        self.key = key
        #: the instance path TcUnit reports (``PRG_TEST.fbMath``); the runner names it, else the type and its number
        self.path = f"{st_name(type(instance))}#{number}"
        self.tests: list[TestRecord] = []
        self.by_name: dict[str, TestRecord] = {}
        self.current: TestRecord | None = None
        self.errors: list[str] = []
        #: the test names declared twice in one cycle (logged once each)
        self.duplicates: set[str] = set()
        #: the test open is a duplicate declaration: its asserts are not recorded
        self.ignoring = False
        self.asserts = 0

    def reset(self) -> None:
        self.tests.clear()
        self.by_name.clear()
        self.current = None
        self.errors.clear()
        self.duplicates.clear()
        self.asserts = 0

    @property
    def finished(self) -> bool:
        """Every test finished (a suite whose body declares none is finished once called)."""
        return all(t.finished for t in self.tests)

    def rename(self, path: str) -> None:
        self.path = path
        for test in self.tests:
            test.suite = path


class Registry:
    """The test suites of one load / runtime, their results, and where RUN() is.

    ``limit_ms`` (PLC time, None: none, as on the PLC) fails a test still open
    that long after it started; ``log`` collects the lines TcUnit would write
    to the ADS log, ``done`` is set once every test has finished.
    """

    def __init__(self, limit_ms: int | None = None) -> None:
        self.suites: list[SuiteState] = []
        self._by_key: dict[int, SuiteState] = {}
        self.limit_ms = limit_ms
        self.running: SuiteState | None = None
        self.cycle = 0
        self.done = False
        self.log: list[str] = []
        #: what TcUnit logs as an error without failing a test (a test name declared twice in one cycle)
        self.warnings: list[str] = []
        self.clock: Clock | None = None
        self.started_ns = -1
        self.finished_ns = -1
        #: the PLC time of the last RUN() call: what close() dates the end with, outside a cycle
        self.last_ns = 0
        #: RUN_IN_SEQUENCE: the suite running, and when the next may start
        self._sequence = 0
        self._next_start_ns = 0

    def add(self, suite: FB_TestSuite) -> None:
        key = int(adr(suite))
        known = self._by_key.get(key)
        if known is not None:  # FB_init again (a reset): the suite starts over
            known.instance = suite
            known.reset()
            self.done = False
            return
        state = SuiteState(suite, key, len(self.suites) + 1)
        self.suites.append(state)
        self._by_key[key] = state

    def name_suites(self, program: Any, path: str | None = None) -> None:
        """Name the registered suites inside ``program`` by instance path, as TcUnit reports them (``PRG_TEST.fbMath``)."""
        self._name_in(program, st_name(type(program)) if path is None else path, 8)

    def _name_in(self, block: Any, path: str, depth: int) -> None:
        record = iec_class(type(block))
        if record is None or record.layout is None or depth == 0:
            return
        for field in record.layout.fields:
            value = getattr(block, field.name)
            name = f"{path}.{st_name(type(block), field.name)}"
            bounds = getattr(value, "bounds", None)
            if isinstance(value, FunctionBlock):
                state = self._by_key.get(int(adr(value)))
                if state is not None:
                    state.rename(name)
                self._name_in(value, name, depth - 1)
            elif bounds is not None and len(bounds) == 1:
                for i in range(bounds[0][0], bounds[0][1] + 1):
                    element = value[i]
                    if not isinstance(element, FunctionBlock):
                        break
                    state = self._by_key.get(int(adr(element)))
                    if state is not None:
                        state.rename(f"{name}[{i}]")

    def state_of(self, suite: FB_TestSuite) -> SuiteState:
        state = self._by_key.get(int(adr(suite)))
        if state is None:
            raise PlcException(
                ExceptionCode.RTSEXCPT_ACCESS_VIOLATION,
                f"TcUnit: {st_name(type(suite))} is not a registered test suite (it was created outside this registry)",
            )
        return state

    def tests(self) -> list[TestRecord]:
        """Every test of every suite, suite by suite."""
        return [test for suite in self.suites for test in suite.tests]

    def failed_asserts(self) -> int:
        return sum(len(test.failures) for test in self.tests())

    # -- what RUN() does ------------------------------------------------------------------------

    def _now_ns(self) -> int:
        return task_clock.get().now_ns()

    def run(self, in_sequence: bool, pause_ms: int | None = None) -> None:
        """One RUN() cycle; ``pause_ms``: RUN_IN_SEQUENCE's time between suites (default the GVL_Param_TcUnit one)."""
        self.cycle += 1
        now = self.last_ns = self._now_ns()
        if self.started_ns < 0:
            self.started_ns = now
        if self.done:
            return
        if in_sequence:
            self._run_sequence(now, GVL_Param_TcUnit.TimeBetweenTestSuitesExecution if pause_ms is None else pause_ms)
        else:
            for suite in self.suites:
                self._call(suite, now)
        # in sequence, a suite not yet called has declared no test: the run is done once the last one has run
        if self._sequence >= len(self.suites) if in_sequence else all(suite.finished for suite in self.suites):
            self.done = True
            self.finished_ns = now
            self.log.extend(self.summary())

    def _run_sequence(self, now: int, pause_ms: int) -> None:
        while self._sequence < len(self.suites):
            suite = self.suites[self._sequence]
            if now < self._next_start_ns:
                return
            self._call(suite, now)
            if not suite.finished:
                return
            self._sequence += 1
            self._next_start_ns = now + pause_ms * 1_000_000
            if pause_ms:
                return

    def _call(self, suite: SuiteState, now: int) -> None:
        if suite.finished and suite.tests:
            return
        self.running = suite
        suite.current, suite.ignoring = None, False
        try:
            suite.instance()
        finally:
            self.running = None
            suite.current, suite.ignoring = None, False
        self._apply_limit(suite, now)

    def _apply_limit(self, suite: SuiteState, now: int) -> None:
        if self.limit_ms is None:
            return
        for test in suite.tests:
            if not test.finished and test.started_ns >= 0 and now - test.started_ns >= self.limit_ms * 1_000_000:
                test.error = (
                    f"the test did not finish within {format_time(self.limit_ms)} of PLC time "
                    f"(the per-test limit); TEST_FINISHED() was never called"
                )
                self._finish(test, now)

    def _finish(self, test: TestRecord, now: int | None = None) -> None:
        if not test.finished:
            test.finished = True
            test.finished_cycle = self.cycle
            test.finished_ns = self._now_ns() if now is None else now

    def close(self) -> None:
        """End the run where it is: every open test fails as unfinished, and the summary is logged."""
        # After the cycles the task clock is no longer the runtime's: the end is the last RUN() call.
        for test in self.tests():
            if not test.finished:
                test.error = test.error or "the run ended before the test finished (TEST_FINISHED() was never called)"
                self._finish(test, self.last_ns)
        if not self.done:
            self.done = True
            self.finished_ns = self.last_ns
            self.log.extend(self.summary())

    def summary(self) -> list[str]:
        """TcUnit's summary lines, after its FAILED TEST lines."""
        tests = self.tests()
        failed = [t for t in tests if t.status == "failed"]
        skipped = [t for t in tests if t.status == "skipped"]
        lines = [failure.line() for test in tests for failure in test.failures]
        lines += [f"FAILED TEST '{t.suite}@{t.name}', {t.error}" for t in tests if t.error]
        for suite in self.suites:
            lines += [f"ERROR in '{suite.path}': {error}" for error in suite.errors]
        seconds = max(0, self.finished_ns - self.started_ns) / 1e9 if self.started_ns >= 0 else 0.0
        lines += [
            "==========TESTS FINISHED RUNNING==========",
            f"Test suites: {len(self.suites)}",
            f"Tests: {len(tests)}",
            f"Successful tests: {len(tests) - len(failed) - len(skipped)}",
            f"Failed tests: {len(failed)}",
            f"Disabled tests: {len(skipped)}",
            f"Unsuccessful assertions: {self.failed_asserts()}",
            f"Duration: {seconds:.3f} s of PLC time",
            "==================RESULT==================",
            "SOME TESTS FAILED" if failed else "ALL TESTS SUCCEEDED",
        ]
        return lines

    # -- what TEST() and the asserts do ---------------------------------------------------------

    def suite_running(self, what: str) -> SuiteState:
        if self.running is None:
            raise PlcException(
                ExceptionCode.RTSEXCPT_ACCESS_VIOLATION,
                f"TcUnit.{what}: called outside a test suite that RUN() or RUN_IN_SEQUENCE() is running",
            )
        return self.running

    def open_test(self, name: str, ordered: bool) -> TestRecord | None:
        suite = self.suite_running("TEST_ORDERED" if ordered else "TEST")
        name = name.strip()  # TcUnit trims the name it is given
        test = suite.by_name.get(name)
        if test is not None and test._declared_cycle == self.cycle:
            # Declared twice in one cycle: TcUnit logs it once and ignores the second one's asserts
            # (a TEST_FINISHED() after it still finishes the test).
            if name not in suite.duplicates:
                suite.duplicates.add(name)
                warning = f"Test with name '{name}' already exists in test suite '{suite.path}'"
                self.log.append(warning)
                self.warnings.append(warning)
            suite.current, suite.ignoring = test, True
            return None
        suite.ignoring = False
        if test is None:
            if len(suite.tests) >= GVL_Param_TcUnit.MaxNumberOfTestsForEachTestSuite:
                suite.errors.append(
                    f"test {name!r} is one more than GVL_Param_TcUnit.MaxNumberOfTestsForEachTestSuite "
                    f"({GVL_Param_TcUnit.MaxNumberOfTestsForEachTestSuite}) allows; it is not run"
                )
                suite.by_name[name] = test = TestRecord(name, suite.path, ordered, finished=True, skipped=True)
                return None
            test = TestRecord(name, suite.path, ordered)
            suite.tests.append(test)
            suite.by_name[name] = test
            if name.lower().startswith(DISABLED_PREFIX):
                test.skipped = True
                self._finish(test)
        test._declared_cycle = self.cycle
        if test.skipped or test.finished:
            suite.current = test
            return test
        if ordered:
            turn = next((t for t in suite.tests if t.ordered and not t.finished), None)
            if turn is not test:
                suite.current = None
                return None
        if test.started_ns < 0:
            test.started_ns = self._now_ns()
            test.started_cycle = self.cycle
        suite.current = test
        return test

    def finish_current(self) -> bool:
        suite = self.suite_running("TEST_FINISHED")
        if suite.current is None:
            return False
        self._finish(suite.current)
        return True

    def finish_named(self, name: str) -> bool:
        suite = self.suite_running("TEST_FINISHED_NAMED")
        test = suite.by_name.get(name.strip())
        if test is None or test not in suite.tests:
            return False
        self._finish(test)
        return True

    def is_finished(self, name: str) -> bool:
        suite = self.suite_running("IS_TEST_FINISHED")
        test = suite.by_name.get(name.strip())
        return test is not None and test.finished

    def record(self, suite_fb: FB_TestSuite, assertion: str, message: str, expected: str, actual: str,
               index: str = "") -> None:
        """Record a failed assert of the suite's current test (ignored when no test is open)."""
        suite = self.state_of(suite_fb)
        test = suite.current
        if test is None or test.finished or test.skipped or suite.ignoring:
            return
        key = (assertion, message, expected, actual, index, self.cycle)
        if key in test._seen:
            return
        test._seen.add(key)
        suite.asserts += 1
        if suite.asserts > GVL_Param_TcUnit.MaxNumberOfAssertsForEachTestSuite:
            if suite.asserts == GVL_Param_TcUnit.MaxNumberOfAssertsForEachTestSuite + 1:
                suite.errors.append(
                    "more failed asserts than GVL_Param_TcUnit.MaxNumberOfAssertsForEachTestSuite "
                    f"({GVL_Param_TcUnit.MaxNumberOfAssertsForEachTestSuite}); the rest are not recorded"
                )
            test.error = test.error or "failed asserts beyond GVL_Param_TcUnit.MaxNumberOfAssertsForEachTestSuite"
            return
        file, lineno = _assert_site()
        test.failures.append(
            AssertFailure(test.name, suite.path, assertion, message, expected, actual, self.cycle, index, file, lineno))


#: The folder of the iecoop package: frames inside it are the library's, not the caller's.
_PACKAGE = os.path.dirname(os.path.dirname(os.path.abspath(__file__))) + os.sep


def _assert_site() -> tuple[str, int]:
    """Where the failing assert was called: the innermost loaded-ST line, else the first frame outside iecoop."""
    found = st_caller()
    if found is not None:
        return found.file, found.line
    frame: FrameType | None = sys._getframe(1)
    while frame is not None and os.path.abspath(frame.f_code.co_filename).startswith(_PACKAGE):
        frame = frame.f_back
    return (frame.f_code.co_filename, frame.f_lineno) if frame is not None else ("", 0)


# --- which registry ---------------------------------------------------------------------------

_active: contextvars.ContextVar[Registry | None] = contextvars.ContextVar("iecoop_tcunit_registry", default=None)
#: Suites created outside ``registry()``: the next runtime whose cycle calls RUN() takes them.
_pending: list[FB_TestSuite] = []
#: The registry the last runtime (by its task clock) runs without ``registry()``.
_unscoped: list[Registry] = []


@contextlib.contextmanager
def registry(limit_ms: int | None = None) -> Iterator[Registry]:
    """Make a fresh :class:`Registry` the one suites register with and RUN() runs, inside the block."""
    fresh = Registry(limit_ms)
    token = _active.set(fresh)
    try:
        yield fresh
    finally:
        _active.reset(token)


def forget_unscoped() -> None:
    """Drop the suites and registry kept outside ``registry()`` (the pytest plugin does this between tests)."""
    _pending.clear()
    _unscoped.clear()


def unscoped_registry() -> Registry | None:
    """The registry of the last runtime that called RUN() outside ``registry()`` (None before one did)."""
    return _unscoped[0] if _unscoped else None


def current_registry() -> Registry:
    """The registry RUN() uses here: the active one, else the one of the runtime running this cycle."""
    active = _active.get()
    if active is not None:
        return active
    clock = task_clock.get()
    if _unscoped and _unscoped[0].clock is clock:
        found = _unscoped[0]
    else:  # a fresh runtime: a fresh registry, with the suites created since the last one
        found = Registry()
        found.clock = clock
        _unscoped[:] = [found]
    for suite in _pending:
        found.add(suite)
    _pending.clear()
    return found


def _register(suite: FB_TestSuite) -> None:
    active = _active.get()
    if active is not None:
        active.add(suite)
    elif _unscoped and _unscoped[0].running is not None:  # created during a run (__NEW in a test)
        _unscoped[0].add(suite)
    else:
        _pending.append(suite)


class FB_TestSuite(FunctionBlock):
    """``FUNCTION_BLOCK FB_TestSuite``: the base of a test suite; its asserts are METHODs.

    An instance registers itself when created (FB_init), so ``RUN()`` finds it.
    The body of the derived suite calls its tests; ``RUN()`` calls that body.
    Every assert records only a failure, for the test currently open.
    """

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
        _register(self)
        return True

    def _registry(self) -> Registry:
        return current_registry()

    @method
    def AssertTrue(self, Condition: BOOL, Message: STRING = "") -> None:
        """``AssertTrue(Condition, Message)``: fails when Condition is FALSE."""
        if not Condition:
            self._registry().record(self, "AssertTrue", str(Message), "TRUE", "FALSE")

    @method
    def AssertFalse(self, Condition: BOOL, Message: STRING = "") -> None:
        """``AssertFalse(Condition, Message)``: fails when Condition is TRUE."""
        if Condition:
            self._registry().record(self, "AssertFalse", str(Message), "FALSE", "TRUE")

    @method
    def AssertEquals(self, Expected: ANY, Actual: ANY, Message: STRING = "") -> None:
        """``AssertEquals(Expected, Actual : ANY, Message)``: fails when the types or the values differ.

        Both arrive as ``AnyType``: values of different types (an INT and a DINT, a
        BOOL and an integer) fail with both types shown; strings compare as text,
        other elementary values by value, STRUCTs, blocks and ARRAYs byte by byte.
        From Python, a value's kind gives its type (``int`` is DINT, ``float`` LREAL).
        """
        expected, actual = AnyType.of(Expected), AnyType.of(Actual)
        same_type = expected.TypeClass == actual.TypeClass and (
            expected.TypeClass in asserts.TEXT_CLASSES or expected.diSize == actual.diSize)
        if not same_type:
            self._registry().record(self, "AssertEquals", str(Message), asserts.typed_text(expected), asserts.typed_text(actual))
        elif expected.TypeClass in asserts.ELEMENTARY_CLASSES:
            if expected.value != actual.value:
                self._registry().record(self, "AssertEquals", str(Message), asserts.any_text(expected), asserts.any_text(actual))
        elif memcmp(expected.pValue, actual.pValue, expected.diSize) != 0:
            self._registry().record(self, "AssertEquals", str(Message), asserts.any_text(expected), asserts.any_text(actual))

    AssertEquals_BOOL = asserts.equals("BOOL")
    AssertEquals_BYTE = asserts.equals("BYTE")
    AssertEquals_WORD = asserts.equals("WORD")
    AssertEquals_DWORD = asserts.equals("DWORD")
    AssertEquals_LWORD = asserts.equals("LWORD")
    AssertEquals_SINT = asserts.equals("SINT")
    AssertEquals_USINT = asserts.equals("USINT")
    AssertEquals_INT = asserts.equals("INT")
    AssertEquals_UINT = asserts.equals("UINT")
    AssertEquals_DINT = asserts.equals("DINT")
    AssertEquals_UDINT = asserts.equals("UDINT")
    AssertEquals_LINT = asserts.equals("LINT")
    AssertEquals_ULINT = asserts.equals("ULINT")
    AssertEquals_REAL = asserts.equals("REAL", with_delta=True)
    AssertEquals_LREAL = asserts.equals("LREAL", with_delta=True)
    AssertEquals_STRING = asserts.equals("STRING")
    AssertEquals_WSTRING = asserts.equals("WSTRING")
    AssertEquals_TIME = asserts.equals("TIME")
    AssertEquals_LTIME = asserts.equals("LTIME")
    AssertEquals_DATE = asserts.equals("DATE")
    AssertEquals_TIME_OF_DAY = asserts.equals("TIME_OF_DAY")
    AssertEquals_DATE_AND_TIME = asserts.equals("DATE_AND_TIME")

    AssertArrayEquals_BOOL = asserts.array_equals("BOOL")
    AssertArrayEquals_BYTE = asserts.array_equals("BYTE")
    AssertArrayEquals_WORD = asserts.array_equals("WORD")
    AssertArrayEquals_DWORD = asserts.array_equals("DWORD")
    AssertArrayEquals_LWORD = asserts.array_equals("LWORD")
    AssertArrayEquals_SINT = asserts.array_equals("SINT")
    AssertArrayEquals_USINT = asserts.array_equals("USINT")
    AssertArrayEquals_INT = asserts.array_equals("INT")
    AssertArrayEquals_UINT = asserts.array_equals("UINT")
    AssertArrayEquals_DINT = asserts.array_equals("DINT")
    AssertArrayEquals_UDINT = asserts.array_equals("UDINT")
    AssertArrayEquals_LINT = asserts.array_equals("LINT")
    AssertArrayEquals_ULINT = asserts.array_equals("ULINT")
    AssertArrayEquals_REAL = asserts.array_equals("REAL", with_delta=True)
    AssertArrayEquals_LREAL = asserts.array_equals("LREAL", with_delta=True)
    AssertArray2dEquals_REAL = asserts.array_equals("REAL", 2, with_delta=True)
    AssertArray2dEquals_LREAL = asserts.array_equals("LREAL", 2, with_delta=True)
    AssertArray3dEquals_REAL = asserts.array_equals("REAL", 3, with_delta=True)
    AssertArray3dEquals_LREAL = asserts.array_equals("LREAL", 3, with_delta=True)

    # -- what a suite can read of its tests -----------------------------------------------------

    @method
    def GetNumberOfTests(self) -> UINT:
        """``GetNumberOfTests()``: the tests this suite has declared so far."""
        return len(self._registry().state_of(self).tests)

    @method
    def GetNumberOfFailedTests(self) -> UINT:
        """``GetNumberOfFailedTests()``: its tests with a failed assert (or that hit a limit)."""
        return sum(t.status == "failed" for t in self._registry().state_of(self).tests)

    @method
    def GetNumberOfSuccessfulTests(self) -> UINT:
        """``GetNumberOfSuccessfulTests()``: its finished tests with no failed assert."""
        return sum(t.status == "passed" for t in self._registry().state_of(self).tests)

    @method
    def GetNumberOfSkippedTests(self) -> UINT:
        """``GetNumberOfSkippedTests()``: its ``disabled_`` tests."""
        return sum(t.status == "skipped" for t in self._registry().state_of(self).tests)

    @method
    def AreAllTestsFinished(self) -> BOOL:
        """``AreAllTestsFinished()``: every test of this suite has finished."""
        return self._registry().state_of(self).finished

    @method
    def GetInstancePath(self) -> STRING:
        """``GetInstancePath()``: the suite's instance path (``PRG_TEST.fbMath``)."""
        return self._registry().state_of(self).path


# --- the global functions ---------------------------------------------------------------------


def TEST(TestName: STRING) -> BOOL:
    """``TEST('Name')``: open (or continue) the test ``Name`` of the suite running; its asserts follow."""
    current_registry().open_test(str(TestName), ordered=False)
    return True


def TEST_ORDERED(TestName: STRING) -> BOOL:
    """``TEST_ORDERED('Name')``: TRUE when it is this test's turn (the first not finished, in call order)."""
    test = current_registry().open_test(str(TestName), ordered=True)
    return test is not None and not test.finished


def TEST_FINISHED() -> BOOL:
    """``TEST_FINISHED()``: the test opened last in this suite has finished; later asserts of it are ignored."""
    return current_registry().finish_current()


def TEST_FINISHED_NAMED(TestName: STRING) -> BOOL:
    """``TEST_FINISHED_NAMED('Name')``: the named test of this suite has finished (FALSE: no such test)."""
    return current_registry().finish_named(str(TestName))


def IS_TEST_FINISHED(TestName: STRING) -> BOOL:
    """``IS_TEST_FINISHED('Name')``: whether the named test of this suite has finished."""
    return current_registry().is_finished(str(TestName))


def RUN() -> None:
    """``TcUnit.RUN()``: call every registered suite each cycle until all tests finish, then log the results."""
    current_registry().run(in_sequence=False)


def RUN_IN_SEQUENCE(TimeBetweenTestSuitesExecution: TIME | None = None) -> None:
    """``TcUnit.RUN_IN_SEQUENCE(T#5S)``: as RUN(), one suite after another in declaration order.

    The time between suites is the input, else ``GVL_Param_TcUnit.TimeBetweenTestSuitesExecution``.
    """
    current_registry().run(in_sequence=True, pause_ms=TimeBetweenTestSuitesExecution)


def TCUNIT_ADSLOGSTR(msgCtrlMask: DWORD, msgFmtStr: T_MaxString, strArg: T_MaxString) -> DINT:
    """``TCUNIT_ADSLOGSTR(msgCtrlMask, msgFmtStr, strArg)``: ``Tc2_System.ADSLOGSTR`` into TcUnit's own log too.

    TcUnit buffers its log; a message written through this function keeps its
    place among TcUnit's lines (TcUnit FAQ, "ADSLOGSTR ... correct sequence").
    """
    result = tc2_system.ADSLOGSTR(msgCtrlMask, msgFmtStr, strArg)
    current_registry().log.append(tc2_system.adslog_messages()[-1].text)
    return result


def _write_protected(type_name: str) -> Callable[..., None]:
    """``FUNCTION WRITE_PROTECTED_<type>(Ptr : POINTER TO <type>, Value : <type>)``: write past the access rules."""
    element = getattr(types, asserts.ELEMENTARY.get(type_name, type_name))
    name = f"WRITE_PROTECTED_{type_name}"

    def write_protected(Ptr: Any, Value: Any) -> None:
        if not isinstance(Ptr, Pointer) or Ptr.is_null:
            raise PlcException(ExceptionCode.RTSEXCPT_ACCESS_VIOLATION,
                               f"TcUnit.{name}: Ptr must be the address of a variable (ADR(...)), got {Ptr!r}")
        try:
            Ptr.deref = Value
        except TypeError:  # an untyped address (PVOID): write it as the function's type
            Ptr.typed(element).deref = Value

    write_protected.__name__ = write_protected.__qualname__ = name
    write_protected.__doc__ = (
        f"``{name}(Ptr := ADR(x), Value := v)``: set the {type_name} at Ptr, even an input, an ``AT %I*`` "
        "variable or another block's VAR a test may not assign (TcUnit FAQ, \"test %I* or %Q* variables\")."
    )
    pointer: Any = POINTER_TO  # POINTER TO <type>: the type is only known here
    write_protected.__annotations__ = {"Ptr": pointer[element], "Value": element, "return": None}
    return write_protected


WRITE_PROTECTED_BOOL = _write_protected("BOOL")
WRITE_PROTECTED_BYTE = _write_protected("BYTE")
WRITE_PROTECTED_WORD = _write_protected("WORD")
WRITE_PROTECTED_DWORD = _write_protected("DWORD")
WRITE_PROTECTED_LWORD = _write_protected("LWORD")
WRITE_PROTECTED_SINT = _write_protected("SINT")
WRITE_PROTECTED_USINT = _write_protected("USINT")
WRITE_PROTECTED_INT = _write_protected("INT")
WRITE_PROTECTED_UINT = _write_protected("UINT")
WRITE_PROTECTED_DINT = _write_protected("DINT")
WRITE_PROTECTED_UDINT = _write_protected("UDINT")
WRITE_PROTECTED_LINT = _write_protected("LINT")
WRITE_PROTECTED_ULINT = _write_protected("ULINT")
WRITE_PROTECTED_REAL = _write_protected("REAL")
WRITE_PROTECTED_LREAL = _write_protected("LREAL")
WRITE_PROTECTED_STRING = _write_protected("STRING")
WRITE_PROTECTED_WSTRING = _write_protected("WSTRING")
WRITE_PROTECTED_TIME = _write_protected("TIME")
WRITE_PROTECTED_DATE = _write_protected("DATE")
WRITE_PROTECTED_TIME_OF_DAY = _write_protected("TIME_OF_DAY")
WRITE_PROTECTED_DATE_AND_TIME = _write_protected("DATE_AND_TIME")
