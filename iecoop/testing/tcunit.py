"""Run a project's TcUnit (or CfUnit) tests in virtual time: what ``iecoop test`` and pytest both use.

``run_project(path)`` loads the project (``st.load``: a ``.plcproj``, a folder
or ST files), finds the PROGRAM whose body calls ``RUN()`` or
``RUN_IN_SEQUENCE()``, puts it on the project's task (the cycle time of the
``.TcTTO`` beside it; 10 ms when there is none) and runs it until every test
has finished. A test still open ``limit_ms`` of PLC time after it started
(default :data:`DEFAULT_LIMIT_MS`, 10 s) fails naming that limit, so a test
that never calls ``TEST_FINISHED()`` cannot hang the run. The result holds
one :class:`TestResult` per test: suite (instance path), name, status, and
each failed assert with the ST file and line that called it, its message,
expected and actual values, the first differing index of arrays, and the cycle.

>>> from iecoop import Program, VAR
>>> from iecoop.libraries import tcunit
>>> class FB_Flag_Test(tcunit.FB_TestSuite):
...     def body(self) -> None:
...         tcunit.TEST("FlagIsSet")
...         self.AssertTrue(True, "flag")
...         tcunit.TEST_FINISHED()
>>> class PRG_TEST(Program):
...     fbFlag: FB_Flag_Test = VAR()
...     def body(self) -> None:
...         tcunit.RUN()
>>> result = run_programs(PRG_TEST)
>>> [(r.nodeid, r.status) for r in result.tests], result.passed
([('PRG_TEST.fbFlag::FlagIsSet', 'passed')], True)
"""

from __future__ import annotations

import dataclasses
import os
import pathlib
import re
import types
import xml.etree.ElementTree as ET
from collections.abc import Callable, Iterable
from typing import Any

from iecoop.exceptions import PlcException
from iecoop.libraries import tcunit as _tcunit
from iecoop.metadata import Kind, kind_of, st_name
from iecoop.testing import VirtualPlc

__all__ = [
    "DEFAULT_INTERVAL_MS", "DEFAULT_LIMIT_MS", "SOURCE_NOT_RUN", "TCUNIT_CHOICES", "KeywordError", "RunResult", "TestResult",
    "check_tcunit", "find_test_program", "keyword_matcher", "project_interval", "run_programs", "run_project", "tcunit_copy_folder",
    "vendored_tcunit", "write_junit",
]

#: How long a test may stay open, in ms of PLC time, unless told otherwise (``--timeout``).
DEFAULT_LIMIT_MS = 10_000
#: The test program's task cycle (ms) when the project has no task object of its own.
DEFAULT_INTERVAL_MS = 10

#: The names whose call in a PROGRAM's body makes it the test program.
_RUNNERS = ("RUN", "RUN_IN_SEQUENCE")


@dataclasses.dataclass(frozen=True)
class TestResult:
    """One test's outcome: ``status`` is passed, failed or skipped."""

    __test__ = False  # a result, not a pytest test class

    suite: str
    name: str
    status: str
    failures: tuple[_tcunit.AssertFailure, ...] = ()
    error: str = ""
    duration_ms: float = 0.0
    cycles: int = 0

    @property
    def nodeid(self) -> str:
        """``Suite::Test``, the part after the project in a pytest node id."""
        return f"{self.suite}::{self.name}"

    def report(self) -> str:
        """What failed, one line each: where the assert is, its message, expected and actual values, index and cycle."""
        lines = []
        for failure in self.failures:
            at = f" at index {failure.index}" if failure.index else ""
            site = f"{failure.file}:{failure.lineno}: " if failure.file else ""
            lines.append(
                f"{site}{failure.assertion} failed{at} in cycle {failure.cycle}: expected {failure.expected}, "
                f"actual {failure.actual}" + (f", message: {failure.message}" if failure.message else "")
            )
        if self.error:
            lines.append(self.error)
        return "\n".join(lines)


@dataclasses.dataclass
class RunResult:
    """A whole run: the tests, TcUnit's log lines, and the PLC time it took."""

    source: str
    tests: list[TestResult]
    log: list[str]
    suites: int
    time_ms: int
    #: the PLC fault that stopped the run, if one did
    fault: str = ""
    #: what a suite did wrong besides its tests (more tests or asserts than GVL_Param_TcUnit allows)
    errors: list[str] = dataclasses.field(default_factory=list)
    #: what TcUnit logs as an error without failing a test (a test name declared twice in one cycle)
    warnings: list[str] = dataclasses.field(default_factory=list)

    @property
    def passed(self) -> bool:
        return not self.fault and not self.errors and all(t.status != "failed" for t in self.tests)

    def failed_asserts(self) -> int:
        return sum(len(t.failures) for t in self.tests)


def _calls_run(program: Any) -> bool:
    body = getattr(type(program), "body", None)
    code = getattr(body, "__code__", None)
    # RUN, or RUN under the namespace prefix the reader gives a name two libraries share (TcUnit_RUN)
    return code is not None and any(
        name == runner or name.endswith("_" + runner) for name in code.co_names for runner in _RUNNERS)


def find_test_program(module: types.ModuleType, name: str | None = None) -> Any:
    """The PROGRAM instance of ``module`` whose body calls ``RUN()`` / ``RUN_IN_SEQUENCE()`` (or the one named ``name``)."""
    programs = {
        key: value for key, value in vars(module).items()
        if not key.startswith("_") and not isinstance(value, type) and kind_of(type(value)) is Kind.PROGRAM
    }
    source = getattr(module, "__file__", module.__name__)
    if name is not None:
        for key, value in programs.items():
            if key.lower() == name.lower() or st_name(type(value)).lower() == name.lower():
                return value
        raise LookupError(f"{source}: no PROGRAM {name} (the project declares: {', '.join(programs) or 'none'})")
    callers = [value for value in programs.values() if _calls_run(value)]
    if len(callers) == 1:
        return callers[0]
    if not callers:
        raise LookupError(
            f"{source}: no PROGRAM calls TcUnit.RUN() or RUN_IN_SEQUENCE() "
            f"(the project declares: {', '.join(programs) or 'no PROGRAM'})"
        )
    names = ", ".join(st_name(type(p)) for p in callers)
    raise LookupError(f"{source}: several PROGRAMs call TcUnit.RUN(): {names}; name the one to run")


def _relative(failure: _tcunit.AssertFailure, base: pathlib.Path | None) -> _tcunit.AssertFailure:
    """The failure with its file relative to ``base`` (the project's folder) when it lies inside it."""
    if base is None or not failure.file:
        return failure
    try:
        inside = pathlib.Path(failure.file).resolve().relative_to(base.resolve())
    except ValueError:
        return failure
    return dataclasses.replace(failure, file=inside.as_posix())


#: The test task's watchdog (ms of the machine's time): a test whose cycle never ends is a PLC fault, not a hung run.
WATCHDOG_MS = 10_000


def _results(registry: _tcunit.Registry, base: pathlib.Path | None = None) -> list[TestResult]:
    return [
        TestResult(
            test.suite, test.name, test.status, tuple(_relative(f, base) for f in test.failures), test.error,
            test.duration_ns / 1e6, max(0, test.finished_cycle - test.started_cycle + 1) if test.started_cycle else 0,
        )
        for test in registry.tests()
    ]


def _drive(registry: _tcunit.Registry, program: Any, limit_ms: int, profile: str, interval: int,
           source: str, base: pathlib.Path | None = None) -> RunResult:
    registry.name_suites(program)
    plc = VirtualPlc(profile=profile)
    plc.add(program, interval=interval, watchdog=WATCHDOG_MS)
    fault = ""
    try:
        while not registry.done:
            # Each test has limit_ms from its start; ordered tests and sequenced suites start one after
            # another, so the whole run is bounded by the limit once per test and suite (and a margin).
            bound = limit_ms * (len(registry.tests()) + len(registry.suites) + 2)
            if plc.time_ms > bound:
                break
            plc.run_cycles(1)
    except PlcException as exc:
        fault = f"PLC fault in cycle {registry.cycle}: {exc}"
    finally:
        registry.close()
    errors = [f"{suite.path}: {error}" for suite in registry.suites for error in suite.errors]
    return RunResult(source, _results(registry, base), list(registry.log), len(registry.suites), plc.time_ms, fault, errors,
                     list(registry.warnings))


def run_programs(program: Callable[[], Any], *, limit_ms: int = DEFAULT_LIMIT_MS, profile: str = "twincat",
                 interval: int = 10) -> RunResult:
    """Run the TcUnit suites of ``program``: a Program class, or a function making the test program.

    It is called here, so that the suites it creates register with this run.
    """
    if kind_of(type(program)) is not None:
        raise TypeError(
            f"run_programs takes the Program class (or a function making it), not the instance {program!r}: "
            "its suites must be created inside the run to register with it"
        )
    with _tcunit.registry(limit_ms) as registry:
        instance = program()
        return _drive(registry, instance, limit_ms, profile, interval, st_name(type(instance)))


def run_project(
    source: str | os.PathLike[str], *, limit_ms: int = DEFAULT_LIMIT_MS, program: str | None = None,
    profile: str = "twincat", interval: int | None = None, load: Callable[..., types.ModuleType] | None = None,
    tcunit: str | None = None,
) -> RunResult:
    """Load ``source`` and run its TcUnit suites in virtual time (see the module docstring).

    ``interval`` (ms) is the test program's task cycle: by default the cycle
    time of the project's task (the ``.TcTTO`` beside it), else 10 ms.
    ``load`` is how the project is read (default ``iecoop.st.load``); a project
    that does not load raises its ``DefinitionError`` / ``StSyntaxError``. A
    ``.plcproj`` binds the libraries it references; a folder, ST file or PLCopen
    export gets TcUnit bound, under CfUnit too (``TcUnit.RUN()``, ``CfUnit.RUN()``
    and the plain names work).

    A project that carries its own copy of TcUnit's source is refused (a
    LookupError naming the choice) unless ``tcunit="iecoop"``: then the folder
    of the copy is left out of the load and iecoop's TcUnit is bound in its
    place (see :func:`tcunit_copy_folder`).
    """
    check_tcunit(tcunit)
    if load is None:
        from iecoop import st

        load = st.load
    copy = vendored_tcunit(source)
    left_out: list[pathlib.Path] = []
    if copy is not None:
        if tcunit is None:
            try:
                folder = str(tcunit_copy_folder(source, copy))
            except LookupError:
                folder = ""  # --tcunit iecoop says why it cannot leave the copy out
            raise LookupError(f"{copy}: the project carries its own copy of TcUnit (it declares FUNCTION_BLOCK FB_TestSuite): "
                              f"{_choice_text(None, folder)}")
        left_out.append(tcunit_copy_folder(source, copy))
    # A .plcproj says which libraries it uses; a folder, ST file or PLCopen export is TcUnit (or CfUnit, its
    # CODESYS name) tests by being run here, and a project whose copy of TcUnit is left out gets iecoop's in its place.
    bind = pathlib.Path(source).suffix.lower() != ".plcproj" or bool(left_out)
    extra: dict[str, Any] = {"libraries": {"TcUnit": _tcunit, "CfUnit": _tcunit}} if bind else {}
    from iecoop.st.read.parse import leaving_out

    with _tcunit.registry(limit_ms) as registry:
        with leaving_out(*left_out):
            module = load(source, profile=profile, **extra)
        test_program = find_test_program(module, program)
        path = pathlib.Path(source)
        base = path if path.is_dir() else path.parent
        cycle = project_interval(source) if interval is None else interval
        return _drive(registry, test_program, limit_ms, profile, cycle, path.name, base)


def project_interval(source: str | os.PathLike[str]) -> int:
    """The cycle time (ms) of the task of the ``.TcTTO`` beside ``source``; 10 when there is none."""
    from iecoop.cli.base import UsageError
    from iecoop.cli.st_scenario import project_task

    try:
        task = project_task(os.fspath(source))
    except UsageError as exc:
        raise LookupError(str(exc)) from None
    return DEFAULT_INTERVAL_MS if task is None else int(task.interval)


#: What ``tcunit=`` (``iecoop test --tcunit``, the ini key ``iecoop_tcunit``) may choose for a project that
#: carries its own copy of TcUnit's source: ``iecoop`` runs its suites with iecoop's TcUnit.
TCUNIT_CHOICES = ("iecoop",)
#: Why running the copy itself as ST is not offered: what of TcUnit's own source iecoop does not run.
SOURCE_NOT_RUN = (
    "its FB_TestSuite names each suite (and TcUnit finds the suite a test belongs to) by a variable marked "
    "{attribute 'instance-path'}, which iecoop leaves empty; and its asserts read IBaseLibrary.TypeClass, which "
    "iecoop's reader does not know"
)
#: The folders of a TwinCAT project's own layout: a copy's FB_TestSuite in ``TcUnit/POUs`` leaves ``TcUnit/`` out.
_LAYOUT_FOLDERS = frozenset({"pous", "duts", "gvls", "itfs", "functions"})
#: A suite of the project's own: a block that extends FB_TestSuite (left out with the copy, it would not run).
_SUITE_DECLARATION = re.compile(rb"\bEXTENDS\s+(?:\w+\.)?FB_TestSuite\b", re.IGNORECASE)


def check_tcunit(choice: str | None) -> str | None:
    """``choice`` when it is one of :data:`TCUNIT_CHOICES` (or None); a ValueError saying why not (``source``: what of
    TcUnit's source iecoop does not run)."""
    if choice is not None and choice not in TCUNIT_CHOICES:
        raise ValueError(f"{choice!r}: {_choice_text(choice)}")
    return choice


def _choice_text(given: str | None, folder: str = "") -> str:
    """The choice a project carrying TcUnit's source has, and why running that source is not offered."""
    head = "" if given is None else ("running the project's copy of TcUnit as ST is not offered: " + SOURCE_NOT_RUN + ". "
                                     if given == "source" else f"not one of {', '.join(TCUNIT_CHOICES)}. ")
    return (head + ("choose" if given is None else "Choose") + " --tcunit iecoop (pytest: the ini key iecoop_tcunit = iecoop; "
            "run_project(..., tcunit='iecoop')) to leave the copy's folder" + (f" {folder}" if folder else "")
            + " out of the load and run the suites with iecoop's TcUnit"
            + (f"; running the copy itself as ST is not offered: {SOURCE_NOT_RUN}" if given is None else ""))


def tcunit_copy_folder(source: str | os.PathLike[str], copy: pathlib.Path) -> pathlib.Path:
    """The folder of the copy of TcUnit a project carries (``copy`` declares its FB_TestSuite), left out by ``tcunit="iecoop"``.

    It is the folder that holds ``copy`` (``TcUnit/``; from ``TcUnit/POUs/`` up to
    ``TcUnit/``, TwinCAT's own layout below the copy). A LookupError says why
    when that folder is the project's own folder, or holds suites of the project.
    """
    path = pathlib.Path(source)
    root = (path if path.is_dir() else path.parent).resolve()
    folder = copy.resolve().parent
    while folder.name.lower() in _LAYOUT_FOLDERS and folder.parent != root and folder.parent.is_relative_to(root):
        folder = folder.parent
    if folder == root or not folder.is_relative_to(root):
        raise LookupError(
            f"{copy}: the project's copy of TcUnit (FB_TestSuite) lies in the project's own folder {root}, not in a folder of "
            "its own: leaving it out would leave the project out. Move TcUnit's files into a folder of their own (TcUnit/) "
            "or leave them out of the project and reference the TcUnit library")
    suite = _first_declaring(_source_files(folder), _SUITE_DECLARATION)
    if suite is not None:
        raise LookupError(
            f"{suite}: the folder {folder} that holds the project's copy of TcUnit holds a suite of the project too "
            "(it EXTENDS FB_TestSuite): leaving the folder out would leave the suite out. Move TcUnit's files into a "
            "folder of their own")
    return folder


#: ``FUNCTION_BLOCK FB_TestSuite`` at the start of a line: a declaration of TcUnit's own base block.
_TESTSUITE_DECLARATION = re.compile(rb"^\s*FUNCTION_BLOCK\s+(?:(?:PUBLIC|INTERNAL|ABSTRACT|FINAL)\s+)*FB_TestSuite\b",
                                    re.IGNORECASE | re.MULTILINE)
#: The files looked through for a copy of TcUnit, and how much of each (a POU's declaration comes first).
_SOURCE_SUFFIXES = frozenset({".tcpou", ".st", ".exp"})
_LOOK_FILES, _LOOK_BYTES = 10_000, 64_000


def vendored_tcunit(source: str | os.PathLike[str]) -> pathlib.Path | None:
    """The file of ``source`` (a .plcproj's folder, a folder or a file) declaring TcUnit's FB_TestSuite, or None.

    A project that carries TcUnit's own source (rather than referencing the library) declares it.
    """
    path = pathlib.Path(source)
    folder = path.parent if path.suffix.lower() == ".plcproj" else path
    return _first_declaring([folder] if folder.is_file() else _source_files(folder), _TESTSUITE_DECLARATION)


def _first_declaring(files: Iterable[pathlib.Path], pattern: re.Pattern[bytes]) -> pathlib.Path | None:
    """The first of ``files`` whose head (``_LOOK_BYTES``) ``pattern`` finds, or None."""
    for candidate in files:
        try:
            with candidate.open("rb") as handle:
                head = handle.read(_LOOK_BYTES)
        except OSError:
            continue
        if pattern.search(head):
            return candidate
    return None


def _source_files(folder: pathlib.Path) -> list[pathlib.Path]:
    """The ST / TwinCAT files under ``folder``, in name order, at most _LOOK_FILES; links are not followed."""
    found: list[pathlib.Path] = []
    for root, folders, files in os.walk(folder):
        folders[:] = sorted(f for f in folders if f != "__iecoop_cache__")
        found += [pathlib.Path(root, f) for f in sorted(files) if pathlib.Path(f).suffix.lower() in _SOURCE_SUFFIXES]
        if len(found) >= _LOOK_FILES:
            break
    return found[:_LOOK_FILES]


# --- -k expressions ---------------------------------------------------------------------------


class KeywordError(ValueError):
    """A ``-k`` expression that does not parse."""


_TOKEN = re.compile(r"\s*(?:(\()|(\))|(\S[^\s()]*))")


def keyword_matcher(expression: str) -> Callable[[str], bool]:
    """A test of ``-k EXPR`` as pytest reads it: substrings (case-insensitive) joined by ``and`` / ``or`` / ``not``.

    >>> match = keyword_matcher("Timer and not Slow")
    >>> match("PRG_TEST.fbTimer::Elapses"), match("PRG_TEST.fbTimer::SlowStart")
    (True, False)
    """
    tokens: list[str] = []
    position = 0
    text = expression.strip()
    while position < len(text):
        found = _TOKEN.match(text, position)
        if found is None:
            break
        tokens.append(found.group(0).strip())
        position = found.end()
    if not tokens:
        return lambda _: True
    index = 0

    def peek() -> str | None:
        return tokens[index] if index < len(tokens) else None

    def take() -> str:
        nonlocal index
        if index >= len(tokens):
            raise KeywordError(f"-k {expression!r}: the expression ends too early")
        index += 1
        return tokens[index - 1]

    def disjunction() -> Callable[[str], bool]:
        terms = [conjunction()]
        while peek() == "or":
            take()
            terms.append(conjunction())
        return lambda name: any(term(name) for term in terms)

    def conjunction() -> Callable[[str], bool]:
        factors = [negation()]
        while peek() == "and":
            take()
            factors.append(negation())
        return lambda name: all(factor(name) for factor in factors)

    def negation() -> Callable[[str], bool]:
        if peek() == "not":
            take()
            inner = negation()
            return lambda name: not inner(name)
        token = take()
        if token == "(":
            inner = disjunction()
            if take() != ")":
                raise KeywordError(f"-k {expression!r}: a '(' is not closed")
            return inner
        if token in (")", "and", "or"):
            raise KeywordError(f"-k {expression!r}: unexpected {token!r}")
        word = token.lower()
        return lambda name: word in name.lower()

    matcher = disjunction()
    if index != len(tokens):
        raise KeywordError(f"-k {expression!r}: unexpected {tokens[index]!r}")
    return matcher


# --- JUnit XML --------------------------------------------------------------------------------


def write_junit(result: RunResult, path: str | os.PathLike[str], tests: Iterable[TestResult] | None = None) -> None:
    """Write ``result`` as JUnit XML (one ``testsuite`` per suite), as CI servers read it."""
    chosen = list(result.tests if tests is None else tests)
    root = ET.Element("testsuites", name=result.source)
    by_suite: dict[str, list[TestResult]] = {}
    for test in chosen:
        by_suite.setdefault(test.suite, []).append(test)
    for suite, members in by_suite.items():
        element = ET.SubElement(
            root, "testsuite", name=suite, tests=str(len(members)),
            failures=str(sum(t.status == "failed" for t in members)),
            skipped=str(sum(t.status == "skipped" for t in members)),
            time=f"{sum(t.duration_ms for t in members) / 1000:.3f}",
        )
        for test in members:
            case = ET.SubElement(element, "testcase", classname=suite, name=test.name, time=f"{test.duration_ms / 1000:.3f}")
            if test.status == "failed":
                first = test.failures[0] if test.failures else None
                site = f"{first.file}:{first.lineno}: " if first is not None and first.file else ""
                message = (f"{site}{first.assertion}: expected {first.expected}, actual {first.actual}; {first.message}"
                           if first is not None else test.error)
                failure = ET.SubElement(case, "failure", message=message, type="AssertionError")
                failure.text = test.report()
            elif test.status == "skipped":
                ET.SubElement(case, "skipped", message="disabled_ test")
    if result.fault:
        ET.SubElement(root, "error", message=result.fault)
    ET.ElementTree(root).write(os.fspath(path), encoding="utf-8", xml_declaration=True)
