"""A project that carries its own copy of TcUnit's source: refused naming the choice, or run with iecoop's TcUnit."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from iecoop.cli import main
from iecoop.testing.tcunit import SOURCE_NOT_RUN, run_project, tcunit_copy_folder, vendored_tcunit

pytest_plugins = ["pytester"]

#: CopiedTcUnit: a valve, its suite (EXTENDS FB_TestSuite, plain TEST / AssertEquals_INT / RUN()) and, in
#: TcUnit/POUs and TcUnit/GVLs, a stand-in copy of the framework that declares FB_TestSuite, TEST, RUN and a GVL.
COPIED = Path(__file__).parent / "data" / "CopiedTcUnit"
PROJECT = COPIED / "CopiedTcUnit.plcproj"


def test_by_default_iecoop_test_refuses_the_copy_naming_the_option_and_why_not_source(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert main(["test", str(PROJECT)]) == 2
    err = capsys.readouterr().err
    assert "TcUnit/POUs/FB_TestSuite.TcPOU: the project carries its own copy of TcUnit" in err
    assert "choose --tcunit iecoop (pytest: the ini key iecoop_tcunit = iecoop; run_project(..., tcunit='iecoop'))" in err
    assert f"copy's folder {COPIED.resolve() / 'TcUnit'} out of the load" in err
    assert "running the copy itself as ST is not offered" in err and "instance-path" in err and "IBaseLibrary" in err
    with pytest.raises(LookupError, match="carries its own copy of TcUnit"):
        run_project(PROJECT)


def test_tcunit_iecoop_leaves_the_copy_out_and_runs_the_suites_with_iecoop_s_tcunit(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert main(["test", str(PROJECT), "--tcunit", "iecoop"]) == 1
    out = capsys.readouterr().out
    assert "PRG_TEST.fbValve_Test::OpensOnCommand PASSED" in out
    assert ("PRG_TEST.fbValve_Test::CountsEverySwitch FAILED - Test/FB_Valve_Test.TcPOU:30: AssertEquals_INT failed in "
            "cycle 1: expected 3, actual 2, message: every switch counted") in out
    assert main(["test", str(PROJECT), "--tcunit", "iecoop", "-k", "OpensOnCommand"]) == 0
    # a folder (no .plcproj) too: everything below it but TcUnit/
    result = run_project(COPIED, tcunit="iecoop")
    assert [(t.nodeid, t.status) for t in result.tests] == [
        ("PRG_TEST.fbValve_Test::OpensOnCommand", "passed"), ("PRG_TEST.fbValve_Test::CountsEverySwitch", "failed")]


def test_tcunit_source_is_not_offered_and_says_what_does_not_run(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["test", str(PROJECT), "--tcunit", "source"]) == 2
    err = capsys.readouterr().err
    assert "'source': running the project's copy of TcUnit as ST is not offered: " + SOURCE_NOT_RUN in err
    with pytest.raises(ValueError, match="'other': not one of iecoop"):
        run_project(PROJECT, tcunit="other")


def test_the_copy_folder_climbs_twincat_s_layout_and_is_refused_in_the_project_s_own_folder(tmp_path: Path) -> None:
    copy = vendored_tcunit(PROJECT)
    assert copy is not None and tcunit_copy_folder(PROJECT, copy) == (COPIED / "TcUnit").resolve()
    flat = tmp_path / "Flat"
    shutil.copytree(COPIED, flat)
    shutil.move(flat / "TcUnit" / "POUs" / "FB_TestSuite.TcPOU", flat / "FB_TestSuite.TcPOU")
    found = vendored_tcunit(flat)
    assert found == flat / "FB_TestSuite.TcPOU"
    with pytest.raises(LookupError, match="lies in the project's own folder .*: leaving it out would leave the project out"):
        run_project(flat, tcunit="iecoop")
    mixed = tmp_path / "Mixed"
    shutil.copytree(COPIED, mixed)
    shutil.move(mixed / "Test" / "FB_Valve_Test.TcPOU", mixed / "TcUnit" / "FB_Valve_Test.TcPOU")
    with pytest.raises(LookupError, match=r"FB_Valve_Test.TcPOU: the folder .*TcUnit that holds the project's copy of TcUnit "
                                          r"holds a suite of the project too"):
        run_project(mixed, tcunit="iecoop")


def test_pytest_runs_the_copy_project_with_the_ini_option_and_refuses_it_without(pytester: pytest.Pytester) -> None:
    shutil.copytree(COPIED, pytester.path / "CopiedTcUnit")
    project = pytester.path / "CopiedTcUnit" / "CopiedTcUnit.plcproj"
    refused = pytester.runpytest(str(project), "-p", "no:cacheprovider")
    refused.stdout.fnmatch_lines(["*carries its own copy of TcUnit*iecoop_tcunit = iecoop*"])
    assert refused.ret == 2
    pytester.makeini("[pytest]\niecoop_tcunit = iecoop\n")
    result = pytester.runpytest(str(project), "-p", "no:cacheprovider")
    result.assert_outcomes(passed=1, failed=1)
    result.stdout.fnmatch_lines(["*expected 3, actual 2, message: every switch counted*"])
    pytester.makeini("[pytest]\niecoop_tcunit = source\n")
    wrong = pytester.runpytest(str(project), "-p", "no:cacheprovider")
    wrong.stderr.fnmatch_lines(["*iecoop_tcunit = 'source': running the project's copy of TcUnit as ST is not offered*"])
    assert wrong.ret == 4  # a usage error
