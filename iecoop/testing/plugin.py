"""The pytest plugin: registered through the ``pytest11`` entry point when iecoop is installed.

Fixtures:

- ``plc``: a fresh :class:`~iecoop.testing.VirtualPlc` (virtual time, no store
  on disk) for each test. Mark a test ``@pytest.mark.iecoop_profile("codesys")``
  to run it under the CODESYS profile.
- ``plc_runtime``: the same PLC's :class:`~iecoop.runtime.Runtime`.
- ``st_project``: an ST project (``@pytest.mark.st_project("path")``, else the
  first of ``iecoop_projects``) loaded once per session, with fresh instances
  and a fresh runtime for each test: see :class:`StProject`.

TcUnit collection: ``pytest path/Project.plcproj`` runs the project's TcUnit
suites in virtual time and reports one item per test, node id
``Project.plcproj::Suite::Test`` (the suite is its instance path,
``PRG_TEST.fbMath``); a failed assert reports its message, expected and
actual values. The projects listed under the ini key ``iecoop_projects`` are
collected too when pytest runs without explicit paths (as ``testpaths`` are);
``iecoop_tcunit_timeout`` (a TIME literal, default 10s) is the PLC time a test
may stay open; ``iecoop_tcunit = iecoop`` runs a project that carries its own
copy of TcUnit's source with iecoop's TcUnit, the copy's folder left out.
"""

from __future__ import annotations

import os
import pathlib
import sys
from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

import pytest

from iecoop.literals import T
from iecoop.profiles import get_profile
from iecoop.runtime import Runtime
from iecoop.testing import VirtualPlc

if TYPE_CHECKING:  # the TcUnit library is imported when a project is collected, not by every pytest run
    from iecoop.testing.tcunit import RunResult, TestResult

__all__ = [
    "StProject", "TcUnitItem", "TcUnitProject", "TcUnitSuite", "plc", "plc_runtime", "pytest_addoption", "pytest_collect_file",
    "pytest_configure", "st_project",
]

_RESULTS = pytest.StashKey["dict[pathlib.Path, RunResult]"]()
_MODULES = pytest.StashKey[dict[pathlib.Path, Any]]()


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addini("iecoop_projects", "TwinCAT / CODESYS projects (.plcproj) whose TcUnit tests pytest collects",
                  type="paths", default=[])
    parser.addini("iecoop_tcunit_timeout", "PLC time a TcUnit test may stay open (a TIME literal, default 10s)",
                  default="10s")
    parser.addini("iecoop_tcunit", "for a project carrying its own copy of TcUnit's source: iecoop (leave the copy's "
                  "folder out and run the suites with iecoop's TcUnit)", default="")


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line(
        "markers", "iecoop_profile(name): run the test's plc fixture under a vendor profile (twincat, codesys)"
    )
    config.addinivalue_line("markers", "st_project(path): the ST project the st_project fixture loads")
    config.stash[_RESULTS] = {}
    config.stash[_MODULES] = {}
    _tcunit_choice(config)  # a wrong iecoop_tcunit is a usage error before collection
    projects = _ini_projects(config)
    if projects and config.args_source is not pytest.Config.ArgsSource.ARGS:
        config.args = [*config.args, *(str(p) for p in projects)]


def _ini_projects(config: pytest.Config) -> list[pathlib.Path]:
    return [pathlib.Path(p).resolve() for p in config.getini("iecoop_projects")]


def _limit(config: pytest.Config) -> int:
    text = str(config.getini("iecoop_tcunit_timeout") or "").strip() or "10s"
    try:
        return T(text)
    except ValueError as exc:
        raise pytest.UsageError(f"iecoop_tcunit_timeout: {exc}") from None


def _tcunit_choice(config: pytest.Config) -> str | None:
    """The ini key ``iecoop_tcunit`` (empty: none), checked against the choices ``run_project`` takes."""
    text = str(config.getini("iecoop_tcunit") or "").strip()
    if not text:
        return None  # and TcUnit is not imported by a pytest run that names no choice
    from iecoop.testing.tcunit import check_tcunit

    try:
        return check_tcunit(text)
    except ValueError as exc:
        raise pytest.UsageError(f"iecoop_tcunit = {exc}") from None


def pytest_collect_file(file_path: pathlib.Path, parent: pytest.Collector) -> TcUnitProject | None:
    """A ``.plcproj`` named on the command line or in ``iecoop_projects`` (never one met in a folder's walk)."""
    if file_path.suffix.lower() != ".plcproj":
        return None
    if parent.session.isinitpath(file_path) or file_path.resolve() in _ini_projects(parent.config):
        return TcUnitProject.from_parent(parent, path=file_path)
    return None


class TcUnitFailure(Exception):
    """A TcUnit test that failed: its report is the failed asserts."""


class TcUnitProject(pytest.File):
    """A project's TcUnit tests: the project runs once, at collection, and each test becomes an item."""

    def collect(self) -> Iterator[pytest.Item | pytest.Collector]:
        """One item per TcUnit test of the project, which runs once (and is kept for the session)."""
        from iecoop.testing.tcunit import TestResult, run_project

        results = self.config.stash[_RESULTS]
        result = results.get(self.path)
        if result is None:
            try:
                result = results[self.path] = run_project(self.path, limit_ms=_limit(self.config), tcunit=_tcunit_choice(self.config))
            except LookupError as exc:
                raise self.CollectError(str(exc.args[0])) from None
        for warning in result.warnings:
            self.warn(pytest.PytestWarning(f"TcUnit: {warning}"))
        suites: dict[str, list[TestResult]] = {}
        for test in result.tests:
            suites.setdefault(test.suite, []).append(test)
        if result.fault or result.errors:
            problem = "\n".join(filter(None, [result.fault, *result.errors]))
            suites.setdefault("TcUnit", []).append(TestResult("TcUnit", "run", "failed", error=problem))
        for suite, tests in suites.items():
            yield TcUnitSuite.from_parent(self, name=suite, tests=tests)


class TcUnitSuite(pytest.Collector):
    """A suite instance of the project (``PRG_TEST.fbMath``): its tests are its items."""

    def __init__(self, *, tests: list[TestResult], **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.tests = tests

    def collect(self) -> Iterator[pytest.Item]:
        """One item per test of the suite, in the order the suite declared them."""
        for test in self.tests:
            yield TcUnitItem.from_parent(self, name=test.name, test=test)


class TcUnitItem(pytest.Item):
    """One TcUnit test of a project: passed, failed (its asserts) or skipped (``disabled_``)."""

    def __init__(self, *, test: TestResult, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.test = test

    def runtest(self) -> None:
        """Pass, fail with the test's report, or skip a ``disabled_`` test."""
        if self.test.status == "skipped":
            pytest.skip(f"TcUnit: {self.test.name} is disabled (the disabled_ prefix)")
        if self.test.status != "passed":
            raise TcUnitFailure(self.test.report())

    def repr_failure(self, excinfo: pytest.ExceptionInfo[BaseException], style: Any = None) -> str:
        """The failed asserts, one line each: message, expected and actual values, index and cycle."""
        if isinstance(excinfo.value, TcUnitFailure):
            return f"TcUnit test {self.test.suite}@{self.test.name} failed:\n{excinfo.value}"
        return str(super().repr_failure(excinfo, style))

    def reportinfo(self) -> tuple[os.PathLike[str] | str, int | None, str]:
        """The project file and ``Suite::Test``."""
        return self.path, None, f"{self.test.suite}::{self.test.name}"


@pytest.fixture(autouse=True)
def _iecoop_tcunit_isolation() -> None:
    """Suites a test creates outside a registry are not picked up by the next test's runtime."""
    tcunit = sys.modules.get("iecoop.libraries.tcunit")
    if tcunit is not None:
        tcunit.forget_unscoped()


class StProject:
    """A loaded ST project for one test: fresh instances of its POUs and a fresh virtual PLC.

    ``project.module`` is the loaded module (loaded once per session);
    ``project.new("FB_Valve")`` makes a fresh instance of a FUNCTION_BLOCK or
    PROGRAM, ``project.add("MAIN")`` a fresh program on the test's PLC;
    ``project.write(path, value)`` / ``project.force(path, value)`` set any
    variable by instance path (``"PlcTask.MAIN.bStart"``), as an online write
    or a forced value; ``project.set_inputs(fb, bStart=True)`` sets inputs.
    """

    def __init__(self, module: Any, plc: VirtualPlc) -> None:
        self.module = module
        self.plc = plc

    @property
    def runtime(self) -> Runtime:
        return self.plc.runtime

    def new(self, name: str, **inputs: Any) -> Any:
        """A fresh instance of the POU ``name`` (a PROGRAM's class, not the loaded module's instance)."""
        found = getattr(self.module, name)
        cls = found if isinstance(found, type) else type(found)
        instance = cls()
        self.set_inputs(instance, **inputs)
        return instance

    def add(self, name: str, *, task: str = "PlcTask", interval: int = 10, priority: int = 20) -> Any:
        """A fresh instance of the PROGRAM ``name``, called every ``interval`` ms by the test's PLC."""
        return self.plc.add(self.new(name), task=task, interval=interval, priority=priority)

    @staticmethod
    def set_inputs(instance: Any, **values: Any) -> None:
        """Set variables of ``instance`` by name (its inputs, from the test's side)."""
        for name, value in values.items():
            setattr(instance, name, value)

    def write(self, path: str, value: Any) -> None:
        """Write any variable once, as an online write: ``project.write("PlcTask.MAIN.nSpeed", 50)``."""
        self.runtime.write(path, value)

    def force(self, path: str, value: Any) -> None:
        """Hold any variable at ``value`` until released: ``project.force("PlcTask.MAIN.bSensor", True)``."""
        self.runtime.force(path, value)


@pytest.fixture
def st_project(request: pytest.FixtureRequest, plc: VirtualPlc) -> StProject:
    """The ST project of ``@pytest.mark.st_project(path)`` (else the first ``iecoop_projects``), fresh for this test."""
    marker = request.node.get_closest_marker("st_project")
    if marker is not None:
        if len(marker.args) != 1:
            raise pytest.UsageError("st_project takes one path, e.g. st_project('plc/Project.plcproj')")
        path = pathlib.Path(str(marker.args[0]))
        if not path.is_absolute():
            path = pathlib.Path(str(request.node.path)).parent / path
    else:
        projects = _ini_projects(request.config)
        if not projects:
            raise pytest.UsageError(
                "the st_project fixture needs a project: mark the test @pytest.mark.st_project('path') "
                "or list one under iecoop_projects in the pytest configuration"
            )
        path = projects[0]
    modules = request.config.stash[_MODULES]
    key = path.resolve()
    if key not in modules:
        from iecoop import st

        modules[key] = st.load(key, profile=plc.runtime.profile.name)
    return StProject(modules[key], plc)


@pytest.fixture
def plc(request: pytest.FixtureRequest) -> VirtualPlc:
    """A fresh virtual PLC for this test: ``plc.add(Main())``, ``plc.run_cycles(n)``, ``plc.run_until(...)``."""
    marker = request.node.get_closest_marker("iecoop_profile")
    profile = "twincat"
    if marker is not None:
        if len(marker.args) != 1 or not isinstance(marker.args[0], str):
            raise pytest.UsageError("iecoop_profile takes one profile name, e.g. iecoop_profile('codesys')")
        profile = marker.args[0]
        get_profile(profile)  # an unknown name fails here, naming the known ones
    return VirtualPlc(profile=profile)


@pytest.fixture
def plc_runtime(plc: VirtualPlc) -> Runtime:
    """The :class:`~iecoop.runtime.Runtime` of this test's ``plc``."""
    return plc.runtime
