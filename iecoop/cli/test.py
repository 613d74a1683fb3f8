"""``iecoop test``: run a project's TcUnit (or CfUnit) tests in virtual time, no PLC needed.

::

    iecoop test Project.plcproj                       every suite of the project
    iecoop test tests/ -k "Timer and not Slow"        a folder of ST / TwinCAT files, some tests
    iecoop test Project.plcproj --junitxml out.xml --timeout 30s

Each PATH (a ``.plcproj``, a folder, an ST or TwinCAT file) is loaded, the
PROGRAM calling ``TcUnit.RUN()`` / ``RUN_IN_SEQUENCE()`` runs on the project's
task (the cycle time of its ``.TcTTO``; 10 ms when it has none) until every
test has finished, and one line per test is printed, then
TcUnit's summary. A test still open ``--timeout`` of PLC time after it
started (default 10 s) fails naming the limit. ``-k`` chooses the tests
reported and counted (pytest's syntax, on ``Suite::Test``); every suite still
runs, as on the PLC.

A project that carries its own copy of TcUnit's source (it declares
``FUNCTION_BLOCK FB_TestSuite``) is refused naming the choice:
``--tcunit iecoop`` leaves the copy's folder out of the load and runs the
suites with iecoop's TcUnit.

Exit status: 0 when every chosen test passed, 1 when one failed, the PLC
faulted or a suite broke a ``GVL_Param_TcUnit`` limit, 2 for bad usage or a
project that does not load.
"""

from __future__ import annotations

import argparse
import pathlib
from typing import Any, TextIO

from iecoop import T, st
from iecoop.cli.base import Command, UsageError, usage_errors
from iecoop.cli.st import translated
from iecoop.testing.tcunit import (
    DEFAULT_LIMIT_MS, TCUNIT_CHOICES, KeywordError, RunResult, TestResult, check_tcunit, keyword_matcher,
    run_project, write_junit,
)

__all__ = ["HELP", "add_arguments", "command", "test_command"]

#: The help line of ``iecoop test``.
HELP = "run the TcUnit / CfUnit tests of a .plcproj, folder or ST files in virtual time"

_MARK = {"passed": "PASSED", "failed": "FAILED", "skipped": "SKIPPED"}


def _limit(text: str) -> int:
    try:
        value = T(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be longer than 0 ms, got {text!r}")
    return value


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The arguments of ``iecoop test``."""
    parser.add_argument("paths", nargs="+", metavar="PATH", help="a .plcproj, a folder, or ST / TwinCAT files")
    parser.add_argument("-k", dest="keyword", default="", metavar="EXPR",
                        help="only the tests whose 'Suite::Test' matches EXPR (substrings with and / or / not)")
    parser.add_argument("--junitxml", metavar="FILE", help="also write the results as JUnit XML to FILE")
    parser.add_argument("--timeout", type=_limit, default=DEFAULT_LIMIT_MS, metavar="TIME",
                        help="PLC time a test may stay open, a TIME literal such as 30s (default 10s)")
    parser.add_argument("--program", default=None, help="the test PROGRAM (default: the one calling TcUnit.RUN())")
    parser.add_argument("--profile", choices=("twincat", "codesys"), default="twincat", help="the PLC profile")
    parser.add_argument("--tcunit", type=_tcunit_choice, default=None, metavar="{" + ",".join(TCUNIT_CHOICES) + "}",
                        help="for a project carrying its own copy of TcUnit's source: iecoop leaves the copy's folder out "
                             "and runs the suites with iecoop's TcUnit")


def _tcunit_choice(text: str) -> str:
    try:
        check_tcunit(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    return text


def _load(path: str) -> Any:
    def load(source: Any, **options: Any) -> Any:
        return translated(path, lambda p: st.load(p, **options))

    return load


def _line(test: TestResult) -> str:
    line = f"{test.nodeid} {_MARK.get(test.status, test.status.upper())}"
    if test.status == "failed":
        first = test.report().splitlines()[0] if test.report() else ""
        line += f" - {first}"
    return line


def _summary(results: list[RunResult], chosen: list[TestResult], out: TextIO) -> None:
    failed = [t for t in chosen if t.status == "failed"]
    skipped = [t for t in chosen if t.status == "skipped"]
    asserts = sum(len(t.failures) for t in chosen)
    seconds = sum(r.time_ms for r in results) / 1000
    out.write("==========TESTS FINISHED RUNNING==========\n")
    out.write(f"Test suites: {sum(r.suites for r in results)}\n")
    out.write(f"Tests: {len(chosen)}\n")
    out.write(f"Successful tests: {len(chosen) - len(failed) - len(skipped)}\n")
    out.write(f"Failed tests: {len(failed)}\n")
    out.write(f"Disabled tests: {len(skipped)}\n")
    out.write(f"Unsuccessful assertions: {asserts}\n")
    out.write(f"Duration: {seconds:.3f} s of PLC time\n")
    out.write("==================RESULT==================\n")
    faulted = any(r.fault or r.errors for r in results)
    out.write("SOME TESTS FAILED\n" if failed or faulted else "ALL TESTS SUCCEEDED\n")


@usage_errors("iecoop test")
def test_command(args: argparse.Namespace, out: TextIO, err: TextIO) -> int:
    """Run ``iecoop test`` with parsed arguments."""
    try:
        match = keyword_matcher(args.keyword)
    except KeywordError as exc:
        raise UsageError(str(exc)) from None
    results: list[RunResult] = []
    chosen: list[TestResult] = []
    for path in args.paths:
        if not pathlib.Path(path).exists():
            raise UsageError(f"{path}: does not exist")
        try:
            result = run_project(path, limit_ms=args.timeout, program=args.program, profile=args.profile,
                                 load=_load(path), tcunit=args.tcunit)
        except LookupError as exc:
            raise UsageError(str(exc.args[0])) from None
        results.append(result)
        mine = [t for t in result.tests if match(t.nodeid)]
        chosen += mine
        for test in mine:
            out.write(_line(test) + "\n")
            if test.status == "failed":
                for detail in test.report().splitlines()[1:]:
                    out.write(f"    {detail}\n")
        for warning in result.warnings:
            err.write(f"iecoop test: {path}: warning: {warning}\n")
        for error in result.errors:
            err.write(f"iecoop test: {path}: {error}\n")
        if result.fault:
            err.write(f"iecoop test: {path}: {result.fault}\n")
    if args.junitxml:
        merged = RunResult(", ".join(r.source for r in results), chosen, [], sum(r.suites for r in results),
                           sum(r.time_ms for r in results), "; ".join(r.fault for r in results if r.fault))
        write_junit(merged, args.junitxml)
    _summary(results, chosen, out)
    if args.keyword and not chosen:
        err.write(f"iecoop test: no test matches -k {args.keyword!r}\n")
    failed = any(t.status == "failed" for t in chosen) or any(r.fault or r.errors for r in results)
    return 1 if failed else 0


def command() -> Command:
    """The ``iecoop test`` entry of the command table."""
    return Command(HELP, add_arguments, test_command)
