"""iecoop.libraries.tcunit: every assert passing and failing, the test life cycle, registration and limits."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import pytest

from iecoop import ARRAY, INT, LREAL, REAL, PlcException, Program, Struct, T, VAR, D, adr
from iecoop.libraries import KNOWN, known, module_of, tcunit
from iecoop.libraries.tcunit import FB_TestSuite, GVL_Param_TcUnit
from iecoop.literals import parse_dt, parse_ltime, parse_tod
from iecoop.testing import VirtualPlc
from iecoop.testing.tcunit import RunResult, TestResult, run_programs

Body = Callable[[Any], None]


def suite_running(*tests: tuple[str, Body]) -> RunResult:
    """Run one suite whose tests each call their body once, then TEST_FINISHED()."""

    class FB_Under_Test(FB_TestSuite):
        def body(self) -> None:
            for name, body in tests:
                tcunit.TEST(name)
                body(self)
                tcunit.TEST_FINISHED()

    class PRG_TEST(Program):
        fbSuite: FB_Under_Test = VAR()

        def body(self) -> None:
            tcunit.RUN()

    return run_programs(PRG_TEST, limit_ms=1000)


def only(result: RunResult) -> TestResult:
    assert len(result.tests) == 1
    return result.tests[0]


class ST_Point(Struct):
    x: INT = 0
    y: INT = 0


# (assert method, arguments that pass, arguments that fail, EXP text, ACT text)
SCALARS: list[tuple[str, tuple[Any, ...], tuple[Any, ...], str, str]] = [
    ("AssertEquals_BOOL", (True, True), (True, False), "TRUE", "FALSE"),
    ("AssertEquals_BYTE", (0x12, 0x112), (0xCD, 0xAB), "16#CD", "16#AB"),
    ("AssertEquals_WORD", (0xBEEF, 0xBEEF), (0xBEEF, 0xBEEE), "16#BEEF", "16#BEEE"),
    ("AssertEquals_DWORD", (1, 1), (0xFFFFFFFF, 0), "16#FFFFFFFF", "16#0"),
    ("AssertEquals_LWORD", (2**63, 2**63), (2**63, 1), "16#8000000000000000", "16#1"),
    ("AssertEquals_SINT", (-128, 128), (-5, 5), "-5", "5"),
    ("AssertEquals_USINT", (255, 255), (200, 201), "200", "201"),
    ("AssertEquals_INT", (-32768, 32768), (1000, -1000), "1000", "-1000"),
    ("AssertEquals_UINT", (65535, -1), (1, 2), "1", "2"),
    ("AssertEquals_DINT", (2**31 - 1, 2**31 - 1), (7, 8), "7", "8"),
    ("AssertEquals_UDINT", (2**32 - 1, 2**32 - 1), (3, 4), "3", "4"),
    ("AssertEquals_LINT", (-(2**63), -(2**63)), (10, 11), "10", "11"),
    ("AssertEquals_ULINT", (2**64 - 1, 2**64 - 1), (0, 1), "0", "1"),
    ("AssertEquals_REAL", (1.0, 1.05, 0.1), (1.0, 1.5, 0.1), "1.0", "1.5"),
    ("AssertEquals_LREAL", (2.5, 2.5, 0.0), (2.5, 2.5000001, 0.0), "2.5", "2.5000001"),
    ("AssertEquals_STRING", ("abc", "abc"), ("abc", "abd"), "abc", "abd"),
    ("AssertEquals_WSTRING", ("Ωmega", "Ωmega"), ("Ω", "ω"), "Ω", "ω"),
    ("AssertEquals_TIME", (T("1s"), T("1000ms")), (T("1s"), T("1s500ms")), "T#1s", "T#1s500ms"),
    ("AssertEquals_LTIME", (parse_ltime("LTIME#1us"), 1000), (parse_ltime("LTIME#1ms"), parse_ltime("LTIME#2ms")), "LTIME#1ms", "LTIME#2ms"),
    ("AssertEquals_DATE", (D("2024-01-28"), D("2024-01-28")), (D("2024-01-28"), D("2024-01-29")),
     "D#2024-01-28", "D#2024-01-29"),
    ("AssertEquals_TIME_OF_DAY", (parse_tod("TOD#12:30:00"), parse_tod("TOD#12:30:00")),
     (parse_tod("TOD#12:30:00"), parse_tod("TOD#12:30:00.5")), "TOD#12:30:00", "TOD#12:30:00.5"),
    ("AssertEquals_DATE_AND_TIME", (parse_dt("DT#2024-01-28-11:05:43"), parse_dt("DT#2024-01-28-11:05:43")),
     (parse_dt("DT#2024-01-28-11:05:43"), parse_dt("DT#2024-01-28-11:05:44")),
     "DT#2024-01-28-11:05:43", "DT#2024-01-28-11:05:44"),
    ("AssertTrue", (True,), (False,), "TRUE", "FALSE"),
    ("AssertFalse", (False,), (True,), "FALSE", "TRUE"),
    ("AssertEquals", (5, 5), (5, 6), "5", "6"),
    ("AssertEquals", ("text", "text"), (1, 1.0), "(DINT) 1", "(LREAL) 1.0"),
    ("AssertEquals", (ST_Point(x=1, y=2), ST_Point(x=1, y=2)), (ST_Point(x=1, y=2), ST_Point(x=1, y=3)),
     "ST_Point (4 bytes)", "ST_Point (4 bytes)"),
]


@pytest.mark.parametrize(("name", "passing", "failing", "expected", "actual"), SCALARS,
                         ids=[f"{row[0]}-{i}" for i, row in enumerate(SCALARS)])
def test_every_scalar_assert_passes_and_fails(name: str, passing: tuple[Any, ...], failing: tuple[Any, ...],
                                              expected: str, actual: str) -> None:
    result = suite_running(
        ("Passes", lambda suite: getattr(suite, name)(*passing, "must not fail")),
        ("Fails", lambda suite: getattr(suite, name)(*failing, "the message")),
    )
    passes, fails = result.tests
    assert (passes.status, passes.failures) == ("passed", ())
    assert fails.status == "failed"
    (failure,) = fails.failures
    assert (failure.assertion, failure.expected, failure.actual, failure.message, failure.cycle) == (
        name, expected, actual, "the message", 1)
    assert failure.line() == f"FAILED TEST 'PRG_TEST.fbSuite@Fails', EXP: {expected}, ACT: {actual}, MSG: the message"


ARRAY_TYPES = ["BOOL", "BYTE", "WORD", "DWORD", "LWORD", "SINT", "USINT", "INT", "UINT", "DINT", "UDINT", "LINT", "ULINT"]


@pytest.mark.parametrize("type_name", ARRAY_TYPES + ["REAL", "LREAL"])
def test_every_array_assert_reports_the_first_differing_index_and_sizes(type_name: str) -> None:
    name = f"AssertArrayEquals_{type_name}"
    delta: tuple[Any, ...] = (0.01,) if type_name in ("REAL", "LREAL") else ()
    one, zero = (True, False) if type_name == "BOOL" else (1, 0)
    same = [one, zero, one]
    result = suite_running(
        ("Passes", lambda s: getattr(s, name)(same, list(same), *delta, "same")),
        ("DiffersInContent", lambda s: getattr(s, name)([one, one, one], [one, one, zero], *delta, "content")),
        ("DiffersInSize", lambda s: getattr(s, name)([one] * 6, [one] * 4, *delta, "size")),
    )
    passes, content, size = result.tests
    assert passes.status == "passed"
    (failure,) = content.failures
    shown = {"BOOL": ("TRUE", "FALSE"), "REAL": ("1.0", "0.0"), "LREAL": ("1.0", "0.0")}.get(
        type_name, ("16#1", "16#0") if type_name.endswith("WORD") or type_name == "BYTE" else ("1", "0"))
    assert (failure.index, failure.expected, failure.actual, failure.message) == ("[2]", *shown, "content")
    (failure,) = size.failures
    assert (failure.index, failure.expected, failure.actual) == ("", "SIZE 6", "SIZE 4")


@pytest.mark.parametrize(("type_", "name"), [(REAL, "REAL"), (LREAL, "LREAL")])
def test_2d_and_3d_arrays_compare_within_delta_and_name_the_index(type_: Any, name: str) -> None:
    grid = [[1.0, 2.0], [3.0, 4.0]]
    cube = [grid, [[5.0, 6.0], [7.0, 8.0]]]
    result = suite_running(
        ("Within", lambda s: getattr(s, f"AssertArray2dEquals_{name}")(grid, [[1.0, 2.0], [3.0, 4.05]], 0.1, "2d")),
        ("Outside", lambda s: getattr(s, f"AssertArray2dEquals_{name}")(grid, [[1.0, 2.0], [3.5, 4.0]], 0.1, "2d")),
        ("Cube", lambda s: getattr(s, f"AssertArray3dEquals_{name}")(cube, [grid, [[5.0, 6.0], [7.0, 9.0]]], 0.5, "3d")),
        ("CubeSame", lambda s: getattr(s, f"AssertArray3dEquals_{name}")(cube, cube, 0.0, "3d")),
        ("Shape", lambda s: getattr(s, f"AssertArray2dEquals_{name}")(grid, [[1.0, 2.0, 0.0]], 0.1, "shape")),
    )
    within, outside, cube_test, cube_same, shape = result.tests
    assert (within.status, cube_same.status) == ("passed", "passed")
    assert (outside.failures[0].index, outside.failures[0].expected, outside.failures[0].actual) == ("[1, 0]", "3.0", "3.5")
    assert cube_test.failures[0].index == "[1, 1, 1]"
    assert (shape.failures[0].expected, shape.failures[0].actual) == ("SIZE 2 x 2", "SIZE 1 x 3")


def test_iecoop_arrays_are_compared_by_their_st_indices() -> None:
    class FB_Arrays(FB_TestSuite):
        a: ARRAY[INT] = VAR([1, 2, 3], bounds=(1, 3))
        b: ARRAY[INT] = VAR([1, 2, 4], bounds=(1, 3))

        def body(self) -> None:
            tcunit.TEST("Differ")
            self.AssertArrayEquals_INT(self.a, self.b, "bounds")
            tcunit.TEST_FINISHED()

    class PRG_TEST(Program):
        fbArrays: FB_Arrays = VAR()

        def body(self) -> None:
            tcunit.RUN()

    failure = only(run_programs(PRG_TEST)).failures[0]
    assert (failure.index, failure.expected, failure.actual) == ("[3]", "3", "4")


def test_a_test_stays_open_over_cycles_until_test_finished() -> None:
    seen: list[int] = []

    class FB_Slow(FB_TestSuite):
        count: INT = VAR()

        def body(self) -> None:
            tcunit.TEST("ThreeCycles")
            self.count += 1
            seen.append(self.count)
            if self.count == 3:
                self.AssertEquals_INT(4, self.count, "at the end")
                tcunit.TEST_FINISHED()
                self.AssertTrue(False, "after TEST_FINISHED: ignored")

    class PRG_TEST(Program):
        fbSlow: FB_Slow = VAR()

        def body(self) -> None:
            tcunit.RUN()

    test = only(run_programs(PRG_TEST))
    assert seen == [1, 2, 3]
    assert (test.status, test.cycles, test.duration_ms) == ("failed", 3, 20.0)
    (failure,) = test.failures
    assert (failure.message, failure.cycle) == ("at the end", 3)


def test_ordered_tests_run_one_after_another() -> None:
    trace: list[str] = []

    class FB_Ordered(FB_TestSuite):
        cycles: INT = VAR()

        def body(self) -> None:
            for name in ("First", "Second", "Third"):
                if tcunit.TEST_ORDERED(name):
                    trace.append(name)
                    self.cycles += 1
                    if self.cycles % 2 == 0:
                        tcunit.TEST_FINISHED()

    class PRG_TEST(Program):
        fbOrdered: FB_Ordered = VAR()

        def body(self) -> None:
            tcunit.RUN()

    result = run_programs(PRG_TEST)
    assert trace == ["First", "First", "Second", "Second", "Third", "Third"]
    assert [t.status for t in result.tests] == ["passed"] * 3


def test_identical_asserts_in_one_cycle_are_reported_once_and_again_in_the_next_cycle() -> None:
    class FB_Twice(FB_TestSuite):
        cycle: INT = VAR()

        def body(self) -> None:
            tcunit.TEST("Twice")
            self.cycle += 1
            for _ in range(3):
                self.AssertEquals_INT(1, 2, "same")
            self.AssertEquals_INT(1, 2, "other message")
            if self.cycle == 2:
                tcunit.TEST_FINISHED()

    class PRG_TEST(Program):
        fbTwice: FB_Twice = VAR()

        def body(self) -> None:
            tcunit.RUN()

    test = only(run_programs(PRG_TEST))
    assert [(f.message, f.cycle) for f in test.failures] == [
        ("same", 1), ("other message", 1), ("same", 2), ("other message", 2)]


def test_disabled_tests_are_skipped_and_their_asserts_ignored() -> None:
    result = suite_running(
        ("disabled_NotYet", lambda s: s.AssertTrue(False, "never counted")),
        ("Runs", lambda s: s.AssertTrue(True, "")),
    )
    skipped, runs = result.tests
    assert (skipped.status, skipped.failures, runs.status) == ("skipped", (), "passed")
    assert "Disabled tests: 1" in result.log
    assert "ALL TESTS SUCCEEDED" in result.log


def test_a_test_that_never_finishes_fails_with_the_limit_it_hit() -> None:
    class FB_Hangs(FB_TestSuite):
        def body(self) -> None:
            tcunit.TEST("Hangs")
            tcunit.TEST("Quick")
            tcunit.TEST_FINISHED()

    class PRG_TEST(Program):
        fbHangs: FB_Hangs = VAR()

        def body(self) -> None:
            tcunit.RUN()

    result = run_programs(PRG_TEST, limit_ms=T("500ms"))
    hangs, quick = result.tests
    assert (hangs.status, quick.status) == ("failed", "passed")
    assert "did not finish within T#500ms of PLC time" in hangs.error
    assert (hangs.duration_ms, hangs.cycles) == (500.0, 51)
    assert result.time_ms == 510 and "Duration: 0.500 s of PLC time" in result.log


def test_finished_named_and_is_test_finished() -> None:
    answers: list[tuple[bool, ...]] = []

    class FB_Named(FB_TestSuite):
        def body(self) -> None:
            tcunit.TEST("A")
            tcunit.TEST("B")
            answers.append((tcunit.IS_TEST_FINISHED("A"), tcunit.TEST_FINISHED_NAMED("A"),
                            tcunit.IS_TEST_FINISHED("A"), tcunit.TEST_FINISHED_NAMED("NoSuchTest")))
            tcunit.TEST_FINISHED_NAMED("B")

    class PRG_TEST(Program):
        fbNamed: FB_Named = VAR()

        def body(self) -> None:
            tcunit.RUN()

    result = run_programs(PRG_TEST)
    assert answers == [(False, True, True, False)]
    assert [t.status for t in result.tests] == ["passed", "passed"]


def test_a_suite_reads_its_counts() -> None:
    counts: list[tuple[int, ...]] = []

    class FB_Counts(FB_TestSuite):
        def body(self) -> None:
            tcunit.TEST("Ok")
            tcunit.TEST_FINISHED()
            tcunit.TEST("Bad")
            self.AssertTrue(False, "bad")
            tcunit.TEST_FINISHED()
            tcunit.TEST("disabled_Later")
            counts.append((self.GetNumberOfTests(), self.GetNumberOfFailedTests(), self.GetNumberOfSuccessfulTests(),
                           self.GetNumberOfSkippedTests(), self.AreAllTestsFinished()))
            assert self.GetInstancePath() == "PRG_TEST.fbCounts"

    class PRG_TEST(Program):
        fbCounts: FB_Counts = VAR()

        def body(self) -> None:
            tcunit.RUN()

    run_programs(PRG_TEST)
    assert counts == [(3, 1, 1, 1, True)]


def _two_step_suite(label: str, trace: list[tuple[str, int]], stamp: Callable[[int], int]) -> type[FB_TestSuite]:
    """A suite of one test that takes two calls; each call appends (label, stamp(its call number)) to ``trace``."""

    class FB_Step(FB_TestSuite):
        n: INT = VAR()

        def body(self) -> None:
            tcunit.TEST("Step")
            self.n += 1
            trace.append((label, stamp(self.n)))
            if self.n == 2:
                tcunit.TEST_FINISHED()

    return FB_Step


def test_run_in_sequence_runs_suites_one_after_another_in_declaration_order() -> None:
    trace: list[tuple[str, int]] = []
    First, Second = (_two_step_suite(label, trace, lambda n: n) for label in ("first", "second"))

    class PRG_TEST(Program):
        fbFirst: First = VAR()  # type: ignore[valid-type]
        fbSecond: Second = VAR()  # type: ignore[valid-type]

        def body(self) -> None:
            tcunit.RUN_IN_SEQUENCE()

    result = run_programs(PRG_TEST)
    assert trace == [("first", 1), ("first", 2), ("second", 1), ("second", 2)]
    assert [t.nodeid for t in result.tests] == ["PRG_TEST.fbFirst::Step", "PRG_TEST.fbSecond::Step"]


def test_run_in_sequence_waits_the_time_it_is_given_between_suites() -> None:
    trace: list[tuple[str, int]] = []
    First, Second, Third = (_two_step_suite(label, trace, lambda n: tcunit.current_registry().cycle)
                            for label in ("first", "second", "third"))

    class PRG_TEST(Program):
        fbFirst: First = VAR()  # type: ignore[valid-type]
        fbSecond: Second = VAR()  # type: ignore[valid-type]
        fbThird: Third = VAR()  # type: ignore[valid-type]

        def body(self) -> None:
            tcunit.RUN_IN_SEQUENCE(T("T#50MS"))

    result = run_programs(PRG_TEST, interval=10)
    # 10 ms cycles: the first suite finishes in cycle 2 (t = 10 ms), the next may start at t = 60 ms, cycle 7
    assert trace == [("first", 1), ("first", 2), ("second", 7), ("second", 8), ("third", 13), ("third", 14)]
    assert [t.status for t in result.tests] == ["passed"] * 3


def test_each_runtime_gets_a_fresh_registry_without_registry_scope() -> None:
    class FB_Once(FB_TestSuite):
        def body(self) -> None:
            tcunit.TEST("Once")
            tcunit.TEST_FINISHED()

    class PRG_TEST(Program):
        fbOnce: FB_Once = VAR()

        def body(self) -> None:
            tcunit.RUN()

    registries: list[tcunit.Registry] = []
    for _ in range(2):
        plc = VirtualPlc()
        plc.add(PRG_TEST())
        plc.run_cycles(2)
        found = tcunit.unscoped_registry()
        assert found is not None
        registries.append(found)
    first, second = registries
    assert first is not second
    assert [len(r.suites) for r in registries] == [1, 1]
    assert second.done and len(second.tests()) == 1


def test_arrays_passed_by_address_are_compared_as_the_arrays_they_point_at() -> None:
    class FB_ByAddress(FB_TestSuite):
        a: ARRAY[INT] = VAR([1, 2], bounds=(0, 1))
        b: ARRAY[INT] = VAR([1, 3], bounds=(0, 1))

        def body(self) -> None:
            tcunit.TEST("InOut")
            self.AssertArrayEquals_INT(adr(self, "a"), adr(self, "b"), "by address")
            tcunit.TEST_FINISHED()

    class PRG_TEST(Program):
        fbByAddress: FB_ByAddress = VAR()

        def body(self) -> None:
            tcunit.RUN()

    failure = only(run_programs(PRG_TEST)).failures[0]
    assert (failure.index, failure.expected, failure.actual) == ("[1]", "2", "3")


def test_a_plc_fault_in_a_suite_ends_the_run_and_is_reported() -> None:
    class FB_Divides(FB_TestSuite):
        zero: INT = VAR(0)
        n: INT = VAR(1)

        def body(self) -> None:
            tcunit.TEST("Divides")
            self.n = self.n // self.zero

    class PRG_TEST(Program):
        fbDivides: FB_Divides = VAR()

        def body(self) -> None:
            tcunit.RUN()

    result = run_programs(PRG_TEST)
    assert "PLC fault in cycle 1" in result.fault and "RTSEXCPT_DIVIDEBYZERO" in result.fault
    assert not result.passed
    assert only(result).error == "the run ended before the test finished (TEST_FINISHED() was never called)"


def test_a_suite_whose_cycle_never_ends_is_stopped_by_the_watchdog(monkeypatch: pytest.MonkeyPatch) -> None:
    class FB_Spins(FB_TestSuite):
        n: INT = VAR(1)

        def body(self) -> None:
            tcunit.TEST("Spins")
            while self.n > 0:  # WHILE n > 0 DO END_WHILE: never ends
                pass

    class PRG_TEST(Program):
        fbSpins: FB_Spins = VAR()

        def body(self) -> None:
            tcunit.RUN()

    monkeypatch.setattr("iecoop.testing.tcunit.WATCHDOG_MS", 50)  # 10 s of the machine's time in a real run
    result = run_programs(PRG_TEST)
    assert "PLC fault in cycle 1" in result.fault and "RTSEXCPT_WATCHDOG" in result.fault and "watchdog 50 ms" in result.fault
    assert not result.passed


def test_test_outside_a_running_suite_is_a_plc_exception() -> None:
    with tcunit.registry(), pytest.raises(PlcException, match="TEST: called outside a test suite"):
        tcunit.TEST("Loose")


def test_more_tests_than_the_parameter_allows_are_an_error_naming_it() -> None:
    result = suite_running(*[(f"T{i}", lambda s: None) for i in range(101)])
    assert len(result.tests) == 100
    assert not result.passed
    assert any("T100" in line and "MaxNumberOfTestsForEachTestSuite (100)" in line for line in result.log)


def test_the_library_is_known_under_both_titles() -> None:
    assert module_of(known("TcUnit")) is tcunit  # type: ignore[arg-type]
    assert module_of(known("cfunit")) is tcunit  # type: ignore[arg-type]
    for name in tcunit.__all__:
        assert hasattr(tcunit, name), name
    assert GVL_Param_TcUnit.MaxNumberOfTestsForEachTestSuite == 100
    assert GVL_Param_TcUnit.TimeBetweenTestSuitesExecution == 0
    assert {lib.name for lib in KNOWN if lib.module == tcunit.__name__} == {"TcUnit", "CfUnit"}


def test_a_failure_of_a_python_suite_names_the_python_line_of_the_assert() -> None:
    import inspect

    line = inspect.currentframe().f_lineno + 2  # type: ignore[union-attr]
    result = suite_running(
        ("Fails", lambda s: s.AssertEquals_DINT(1, 2, "python")),
    )
    (failure,) = only(result).failures
    assert (failure.file, failure.lineno) == (__file__, line)
