"""The TcUnitDemo project (TwinCAT layout, three ST suites) through ``iecoop test`` and through pytest."""

from __future__ import annotations

import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from iecoop import PlcException
from iecoop.cli import main
from iecoop.libraries import tcunit
from iecoop.testing.tcunit import run_project

pytest_plugins = ["pytester"]

DEMO = Path(__file__).parent / "data" / "TcUnitDemo"
PROJECT = DEMO / "TcUnitDemo.plcproj"

#: Every test of the project and its outcome, worked out by hand from the ST.
EXPECTED = {
    "PRG_TEST.fbStartDelay_Test::RunsAfterTheDelay": "passed",
    "PRG_TEST.fbStartDelay_Test::StopsAtOnce": "passed",
    "PRG_TEST.fbStartDelay_Test::StartsTooLate": "failed",
    "PRG_TEST.fbStartDelay_Test::disabled_WaitsForever": "skipped",
    "PRG_TEST.fbCounter_Test::CountsUp": "passed",
    "PRG_TEST.fbCounter_Test::CountsDown": "passed",
    "PRG_TEST.fbCounter_Test::NeverBelowZero": "failed",
    "PRG_TEST.fbScaler_Test::ScalesEveryValue": "passed",
    "PRG_TEST.fbScaler_Test::SumWithinDelta": "passed",
    "PRG_TEST.fbScaler_Test::GridWithinDelta": "passed",
    "PRG_TEST.fbScaler_Test::WrongExpectation": "failed",
}


def test_the_runner_gives_every_test_its_outcome_and_failure_details() -> None:
    result = run_project(PROJECT)
    assert {t.nodeid: t.status for t in result.tests} == EXPECTED
    by_id = {t.nodeid: t for t in result.tests}
    (late,) = by_id["PRG_TEST.fbStartDelay_Test::StartsTooLate"].failures
    # TON with PT 200 ms starts timing in cycle 1 (t = 0) and is done in the cycle at t = 200 ms
    assert (late.expected, late.actual, late.cycle, late.message) == ("10", "21", 21, "the motor should run after 100 ms")
    (below,) = by_id["PRG_TEST.fbCounter_Test::NeverBelowZero"].failures
    assert (below.expected, below.actual) == ("-1", "0")
    (wrong,) = by_id["PRG_TEST.fbScaler_Test::WrongExpectation"].failures
    assert (wrong.assertion, wrong.index, wrong.expected, wrong.actual) == ("AssertArrayEquals_REAL", "[3]", "2.5", "25.0")
    assert by_id["PRG_TEST.fbStartDelay_Test::RunsAfterTheDelay"].cycles == 51
    assert result.suites == 3 and not result.passed
    assert "Unsuccessful assertions: 3" in result.log


def test_iecoop_test_prints_a_line_per_test_and_the_summary(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    junit = tmp_path / "results.xml"
    status = main(["test", str(PROJECT), "--junitxml", str(junit)])
    out = capsys.readouterr().out
    assert status == 1
    assert "PRG_TEST.fbCounter_Test::CountsUp PASSED" in out
    assert ("PRG_TEST.fbCounter_Test::NeverBelowZero FAILED - Test/FB_Counter_Test.TcPOU:29: AssertEquals_INT "
            "failed in cycle " in out)
    assert "expected -1, actual 0, message: counted below zero" in out
    assert "PRG_TEST.fbStartDelay_Test::disabled_WaitsForever SKIPPED" in out
    for line in ("Test suites: 3", "Tests: 11", "Successful tests: 7", "Failed tests: 3", "Disabled tests: 1",
                 "Unsuccessful assertions: 3", "SOME TESTS FAILED"):
        assert line in out.splitlines(), line
    root = ET.parse(junit).getroot()
    cases = {(c.get("classname"), c.get("name")): c for c in root.iter("testcase")}
    assert len(cases) == 11
    failure = cases[("PRG_TEST.fbScaler_Test", "WrongExpectation")].find("failure")
    assert failure is not None and "expected 2.5, actual 25.0" in (failure.get("message") or "")
    assert cases[("PRG_TEST.fbStartDelay_Test", "disabled_WaitsForever")].find("skipped") is not None


def test_iecoop_test_exits_0_when_the_chosen_tests_pass(capsys: pytest.CaptureFixture[str]) -> None:
    status = main(["test", str(PROJECT), "-k", "Counter and not Zero or SumWithin"])
    out = capsys.readouterr().out
    assert status == 0
    assert "Tests: 3" in out.splitlines() and "ALL TESTS SUCCEEDED" in out
    assert "WrongExpectation" not in out


def test_iecoop_test_names_a_bad_keyword_expression_and_a_missing_path(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["test", str(PROJECT), "-k", "Counter and"]) == 2
    assert "ends too early" in capsys.readouterr().err
    assert main(["test", str(DEMO / "Missing.plcproj")]) == 2
    assert "Missing.plcproj: does not exist" in capsys.readouterr().err


def test_a_test_that_hits_the_timeout_fails_naming_it(capsys: pytest.CaptureFixture[str]) -> None:
    status = main(["test", str(PROJECT), "--timeout", "300ms", "-k", "RunsAfterTheDelay"])
    out = capsys.readouterr().out
    assert status == 1
    assert "did not finish within T#300ms of PLC time" in out


def _copy_demo(pytester: pytest.Pytester) -> Path:
    target = pytester.path / "TcUnitDemo"
    shutil.copytree(DEMO, target)
    return target / "TcUnitDemo.plcproj"


def test_pytest_collects_one_item_per_test_with_the_documented_node_ids(pytester: pytest.Pytester) -> None:
    project = _copy_demo(pytester)
    result = pytester.runpytest(str(project), "--collect-only", "-q", "-p", "no:cacheprovider")
    for nodeid in EXPECTED:
        result.stdout.fnmatch_lines([f"TcUnitDemo/TcUnitDemo.plcproj::{nodeid}"])


def test_pytest_reports_failures_with_message_expected_and_actual(pytester: pytest.Pytester) -> None:
    project = _copy_demo(pytester)
    junit = pytester.path / "junit.xml"
    result = pytester.runpytest(str(project), f"--junitxml={junit}", "-p", "no:cacheprovider")
    result.assert_outcomes(passed=7, failed=3, skipped=1)
    assert result.ret == 1
    result.stdout.fnmatch_lines([
        "*AssertArrayEquals_REAL failed at index [[]3[]] in cycle 1: expected 2.5, actual 25.0, message: a wrong table*",
    ])
    assert len(list(ET.parse(junit).getroot().iter("testcase"))) == 11


def test_pytest_k_x_and_last_failed_work_on_tcunit_items(pytester: pytest.Pytester) -> None:
    project = _copy_demo(pytester)
    chosen = pytester.runpytest(str(project), "-k", "Scaler and not Wrong", "-p", "no:cacheprovider")
    chosen.assert_outcomes(passed=3)
    assert chosen.ret == 0
    first = pytester.runpytest(str(project), "-x", "-p", "cacheprovider")
    first.assert_outcomes(passed=2, failed=1)
    again = pytester.runpytest(str(project), "--lf", "-p", "cacheprovider")
    again.assert_outcomes(failed=1, deselected=10)


def test_projects_listed_in_the_ini_are_collected_and_st_project_loads_one(pytester: pytest.Pytester) -> None:
    _copy_demo(pytester)
    pytester.makeini("[pytest]\niecoop_projects = TcUnitDemo/TcUnitDemo.plcproj\n")
    pytester.makepyfile(test_counter="""
        from iecoop.testing.plugin import StProject

        def test_a_fresh_counter_each_test(st_project: StProject) -> None:
            counter = st_project.new("FB_Counter")
            counter.Up(); counter.Up()
            assert counter.nCount == 2

        def test_the_test_program_on_a_fresh_plc(st_project: StProject) -> None:
            prg = st_project.add("PRG_TEST")
            assert st_project.plc.time_ms == 0
            st_project.plc.run_cycles(51)
            assert prg.fbStartDelay_Test.fbDelay.bRunning
            st_project.force("PlcTask.PRG_TEST.fbCounter_Test.nStep", 7)
            st_project.plc.run_cycles(1)
            assert prg.fbCounter_Test.nStep == 7
    """)
    result = pytester.runpytest("-p", "no:cacheprovider")
    result.assert_outcomes(passed=9, failed=3, skipped=1)


def test_a_folder_without_its_plcproj_gets_tcunit_bound(capsys: pytest.CaptureFixture[str]) -> None:
    status = main(["test", str(DEMO / "Test"), str(DEMO / "POUs"), "-k", "fbCounter_Test"])
    out = capsys.readouterr()
    # the two folders load separately: the tests alone do not find FB_Counter, which lives in POUs
    assert status == 2 and "FB_Counter" in out.err
    status = main(["test", str(DEMO), "-k", "fbCounter_Test"])
    out = capsys.readouterr()
    assert status == 1
    assert "PRG_TEST.fbCounter_Test::CountsDown PASSED" in out.out and "Tests: 3" in out.out.splitlines()


def _tcpou(name: str, declaration: str, implementation: str) -> str:
    return (
        '<?xml version="1.0" encoding="utf-8"?>\n<TcPlcObject Version="1.1.0.1">\n'
        f'  <POU Name="{name}"><Declaration><![CDATA[{declaration}]]></Declaration>\n'
        f'    <Implementation><ST><![CDATA[{implementation}]]></ST></Implementation></POU>\n</TcPlcObject>\n'
    )


def test_a_cfunit_project_binds_the_same_library(tmp_path: Path) -> None:
    (tmp_path / "FB_Cf_Test.TcPOU").write_text(_tcpou(
        "FB_Cf_Test", "FUNCTION_BLOCK FB_Cf_Test EXTENDS CfUnit.FB_TestSuite\nVAR nValue : DINT := 7; END_VAR\n",
        "CfUnit.TEST('Seven');\nAssertEquals_DINT(Expected := 7, Actual := nValue, Message := 'seven');\n"
        "CfUnit.TEST_FINISHED();\nTEST('Eight');\nAssertEquals_DINT(Expected := 8, Actual := nValue, Message := 'eight');\n"
        "TEST_FINISHED();\n"))
    (tmp_path / "PRG_CF.TcPOU").write_text(_tcpou(
        "PRG_CF", "PROGRAM PRG_CF\nVAR fbCf : FB_Cf_Test; END_VAR\n", "CfUnit.RUN_IN_SEQUENCE();\n"))
    (tmp_path / "Cf.plcproj").write_text(
        '<?xml version="1.0" encoding="utf-8"?>\n'
        '<Project xmlns="http://schemas.microsoft.com/developer/msbuild/2003">\n'
        '  <ItemGroup><Compile Include="FB_Cf_Test.TcPOU" /><Compile Include="PRG_CF.TcPOU" /></ItemGroup>\n'
        '  <ItemGroup><PlaceholderReference Include="CfUnit"><DefaultResolution>CfUnit, * (www.cfunit.org)'
        '</DefaultResolution><Namespace>CfUnit</Namespace></PlaceholderReference></ItemGroup>\n</Project>\n')
    result = run_project(tmp_path / "Cf.plcproj")
    assert [(t.nodeid, t.status) for t in result.tests] == [("PRG_CF.fbCf::Seven", "passed"), ("PRG_CF.fbCf::Eight", "failed")]
    assert result.tests[1].failures[0].line() == "FAILED TEST 'PRG_CF.fbCf@Eight', EXP: 8, ACT: 7, MSG: eight"


def test_a_project_without_a_test_program_is_a_usage_error_naming_its_programs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "main.st").write_text("PROGRAM MAIN\nVAR n : INT; END_VAR\nn := n + 1;\nEND_PROGRAM\n")
    assert main(["test", str(tmp_path / "main.st")]) == 2
    err = capsys.readouterr().err
    assert "no PROGRAM calls TcUnit.RUN() or RUN_IN_SEQUENCE() (the project declares: MAIN)" in err
    assert main(["test", str(tmp_path / "main.st"), "--program", "PRG_TEST"]) == 2
    assert "no PROGRAM PRG_TEST (the project declares: MAIN)" in capsys.readouterr().err


def _project(folder: Path, pous: dict[str, tuple[str, str]], references: str = "TcUnit") -> Path:
    """A .plcproj in ``folder`` compiling ``pous`` (name: declaration, body) and referencing ``references``."""
    for name, (declaration, body) in pous.items():
        (folder / f"{name}.TcPOU").write_text(_tcpou(name, declaration, body))
    compiles = "".join(f'<Compile Include="{name}.TcPOU" />' for name in pous)
    placeholders = "".join(
        f'<PlaceholderReference Include="{ref}"><DefaultResolution>{ref}, *</DefaultResolution>'
        f"<Namespace>{ref}</Namespace></PlaceholderReference>" for ref in references.split())
    project = folder / "Checks.plcproj"
    project.write_text(
        '<?xml version="1.0" encoding="utf-8"?>\n'
        '<Project xmlns="http://schemas.microsoft.com/developer/msbuild/2003">\n'
        f"  <ItemGroup>{compiles}</ItemGroup>\n  <ItemGroup>{placeholders}</ItemGroup>\n</Project>\n")
    return project


_GUARDED = (
    "FUNCTION_BLOCK FB_Guarded\nVAR_INPUT bSensor : BOOL; END_VAR\nVAR_OUTPUT bAlarm : BOOL; END_VAR\n"
    "VAR nHits : INT; END_VAR\n",
    "IF bSensor THEN nHits := nHits + 1; END_IF\nbAlarm := nHits > 2;\n",
)
_PRG = ("PROGRAM PRG_TEST\nVAR fbChecks : FB_Checks; END_VAR\n", "TcUnit.RUN();\n")


def test_a_failed_assert_names_its_st_file_and_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    result = run_project(PROJECT)
    by_id = {t.nodeid: t for t in result.tests}
    (late,) = by_id["PRG_TEST.fbStartDelay_Test::StartsTooLate"].failures
    # the call sits in the METHOD StartsTooLate, at line 52 of the .TcPOU; paths are relative to the project
    assert (late.file, late.lineno) == ("Test/FB_StartDelay_Test.TcPOU", 52)
    (wrong,) = by_id["PRG_TEST.fbScaler_Test::WrongExpectation"].failures
    assert (wrong.file, wrong.lineno) == ("Test/FB_Scaler_Test.TcPOU", 33)
    junit = tmp_path / "out.xml"
    assert main(["test", str(PROJECT), "-k", "NeverBelowZero", "--junitxml", str(junit)]) == 1
    assert ("NeverBelowZero FAILED - Test/FB_Counter_Test.TcPOU:29: AssertEquals_INT failed in cycle 3"
            in capsys.readouterr().out)
    failure = next(ET.parse(junit).getroot().iter("failure"))
    assert (failure.get("message") or "").startswith("Test/FB_Counter_Test.TcPOU:29: AssertEquals_INT")


def test_pytest_shows_the_st_line_of_a_failed_assert(pytester: pytest.Pytester) -> None:
    project = _copy_demo(pytester)
    result = pytester.runpytest(str(project), "-k", "WrongExpectation", "-p", "no:cacheprovider")
    result.assert_outcomes(failed=1, deselected=10)
    result.stdout.fnmatch_lines(["Test/FB_Scaler_Test.TcPOU:33: AssertArrayEquals_REAL failed at index*"])


def test_disabled_in_any_case_trimmed_names_and_duplicates_as_tcunit_reads_them(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    project = _project(tmp_path, {
        "FB_Checks": (
            "FUNCTION_BLOCK FB_Checks EXTENDS TcUnit.FB_TestSuite\nVAR nCycle : INT; END_VAR\n",
            "nCycle := nCycle + 1;\n"
            "TEST('DISABLED_AsTheFaqWritesIt');\nAssertTrue(Condition := FALSE, Message := 'never run');\nTEST_FINISHED();\n"
            "TEST('  Padded  ');\nIF nCycle = 2 THEN TEST_FINISHED_NAMED('Padded'); END_IF\n"
            "TEST('Twice');\nAssertEquals_INT(Expected := 1, Actual := 2, Message := 'the first one counts');\n"
            "TEST('Twice');\nAssertEquals_INT(Expected := 1, Actual := 3, Message := 'a duplicate is ignored');\n"
            "TEST_FINISHED();\n",
        ),
        "PRG_TEST": _PRG,
    })
    result = run_project(project)
    assert [(t.name, t.status) for t in result.tests] == [
        ("DISABLED_AsTheFaqWritesIt", "skipped"), ("Padded", "passed"), ("Twice", "failed")]
    assert [f.message for f in result.tests[2].failures] == ["the first one counts"]
    assert result.tests[1].cycles == 2
    assert result.warnings == ["Test with name 'Twice' already exists in test suite 'PRG_TEST.fbChecks'"]
    assert main(["test", str(project)]) == 1
    assert "warning: Test with name 'Twice' already exists" in capsys.readouterr().err


def test_write_protected_sets_what_a_test_may_not_assign_and_tcunit_adslogstr_logs(tmp_path: Path) -> None:
    project = _project(tmp_path, {
        "FB_Guarded": _GUARDED,
        "FB_Checks": (
            "FUNCTION_BLOCK FB_Checks EXTENDS TcUnit.FB_TestSuite\n"
            "VAR fbGuarded : FB_Guarded; sName : STRING; rGain : LREAL; tWait : TIME; END_VAR\n",
            "TEST('AlarmAfterThreeHits');\n"
            "TcUnit.WRITE_PROTECTED_INT(Ptr := ADR(fbGuarded.nHits), Value := 2);\n"
            "TcUnit.WRITE_PROTECTED_BOOL(Ptr := ADR(fbGuarded.bSensor), Value := TRUE);\n"
            "fbGuarded();\n"
            "AssertTrue(Condition := fbGuarded.bAlarm, Message := 'the third hit raises the alarm');\n"
            "WRITE_PROTECTED_STRING(Ptr := ADR(sName), Value := 'pump');\n"
            "WRITE_PROTECTED_LREAL(Ptr := ADR(rGain), Value := 0.5);\n"
            "WRITE_PROTECTED_TIME(Ptr := ADR(tWait), Value := T#2S);\n"
            "AssertEquals_STRING(Expected := 'pump', Actual := sName, Message := 'name');\n"
            "AssertEquals_LREAL(Expected := 0.5, Actual := rGain, Delta := 0.0, Message := 'gain');\n"
            "AssertEquals_TIME(Expected := T#2S, Actual := tWait, Message := 'wait');\n"
            "TCUNIT_ADSLOGSTR(msgCtrlMask := ADSLOG_MSGTYPE_HINT, msgFmtStr := 'hits: %s', strArg := INT_TO_STRING(3));\n"
            "TEST_FINISHED();\n",
        ),
        "PRG_TEST": _PRG,
    }, references="TcUnit Tc2_System")
    result = run_project(project)
    assert [(t.name, t.status, t.report()) for t in result.tests] == [("AlarmAfterThreeHits", "passed", "")]
    assert "hits: 3" in result.log


def test_write_protected_without_an_address_is_an_access_violation() -> None:
    with pytest.raises(PlcException, match="WRITE_PROTECTED_INT: Ptr must be the address of a variable"):
        tcunit.WRITE_PROTECTED_INT(0, 5)


def test_pytest_xdist_workers_collect_the_same_items(pytester: pytest.Pytester) -> None:
    pytest.importorskip("xdist")
    project = _copy_demo(pytester)
    result = pytester.runpytest(str(project), "-n", "2", "-p", "no:cacheprovider")
    result.assert_outcomes(passed=7, failed=3, skipped=1)


def test_a_project_carrying_a_copy_of_tcunit_is_told_its_choice(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], pytester: pytest.Pytester,
) -> None:
    project = _project(tmp_path, {
        "FB_TestSuite": ("{attribute 'call_after_init'}\nFUNCTION_BLOCK PUBLIC FB_TestSuite\nVAR nTests : UINT; END_VAR\n", ""),
        "FB_Checks": ("FUNCTION_BLOCK FB_Checks EXTENDS FB_TestSuite\n",
                      "TEST('One');\nAssertTrue(Condition := TRUE, Message := 'one');\nTEST_FINISHED();\n"),
        "PRG_TEST": _PRG,
    })
    assert main(["test", str(project)]) == 2
    err = capsys.readouterr().err
    assert "FB_TestSuite.TcPOU: the project carries its own copy of TcUnit" in err
    assert "choose --tcunit iecoop" in err and "running the copy itself as ST is not offered" in err
    # here the copy lies in the project's own folder: leaving it out is refused too, saying why
    assert main(["test", str(project), "--tcunit", "iecoop"]) == 2
    assert "lies in the project's own folder" in capsys.readouterr().err
    copied = pytester.path / "Checks"
    shutil.copytree(tmp_path, copied)
    result = pytester.runpytest(str(copied / "Checks.plcproj"), "-p", "no:cacheprovider")
    result.stdout.fnmatch_lines(["*the project carries its own copy of TcUnit*"])
    assert result.ret == 2  # a collection error


def test_the_test_program_runs_at_the_cycle_time_of_the_project_s_task(tmp_path: Path) -> None:
    project = tmp_path / "TcUnitDemo"
    shutil.copytree(DEMO, project)
    (project / "PlcTask.TcTTO").write_text(
        '<?xml version="1.0" encoding="utf-8"?>\n<TcPlcObject Version="1.1.0.1">\n'
        '  <Task Name="PlcTask" Id="{7c1e2a90-0000-4000-8000-0000000000ff}">\n'
        "    <!--CycleTime in micro seconds.-->\n    <CycleTime>2000</CycleTime>\n    <Priority>20</Priority>\n  </Task>\n</TcPlcObject>\n")
    result = run_project(project / "TcUnitDemo.plcproj")
    by_id = {t.nodeid: t for t in result.tests}
    # a 2 ms task: the 500 ms TON is done in the cycle at t = 500 ms, the 251st
    assert by_id["PRG_TEST.fbStartDelay_Test::RunsAfterTheDelay"].cycles == 251
    (late,) = by_id["PRG_TEST.fbStartDelay_Test::StartsTooLate"].failures
    assert (late.expected, late.actual) == ("10", "101")
    assert run_project(project / "TcUnitDemo.plcproj", interval=10).tests[0].cycles == 51  # told otherwise
    (project / "PlcTask.TcTTO").write_text("<TcPlcObject><Task><CycleTime>5</CycleTime></Task></TcPlcObject>")
    with pytest.raises(LookupError, match="not a whole number of ms"):
        run_project(project / "TcUnitDemo.plcproj")


def test_projects_listed_in_pyproject_toml_are_collected(pytester: pytest.Pytester) -> None:
    _copy_demo(pytester)
    pytester.makepyprojecttoml(
        '[tool.pytest.ini_options]\niecoop_projects = ["TcUnitDemo/TcUnitDemo.plcproj"]\niecoop_tcunit_timeout = "300ms"\n')
    result = pytester.runpytest("-p", "no:cacheprovider", "-k", "RunsAfterTheDelay or CountsUp")
    result.assert_outcomes(passed=1, failed=1, deselected=9)  # the 500 ms test hits the 300 ms limit
    result.stdout.fnmatch_lines(["*did not finish within T#300ms of PLC time*"])


def test_a_project_referencing_tc3_module_runs_and_one_using_its_names_is_refused_naming_them(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    checks = ("FUNCTION_BLOCK FB_Checks EXTENDS TcUnit.FB_TestSuite\n",
              "TEST('Template');\nAssertEquals_INT(Expected := 3, Actual := 1 + 2, Message := 'sum');\nTEST_FINISHED();\n")
    project = _project(tmp_path, {"FB_Checks": checks, "PRG_TEST": _PRG}, references="Tc2_Standard Tc2_System Tc3_Module TcUnit")
    assert [(t.name, t.status) for t in run_project(project).tests] == [("Template", "passed")]
    using = ("FUNCTION_BLOCK FB_Checks EXTENDS TcUnit.FB_TestSuite\nVAR ipObject : Tc3_Module.ITComObject; END_VAR\n", checks[1])
    project = _project(tmp_path, {"FB_Checks": using, "PRG_TEST": _PRG}, references="Tc3_Module TcUnit")
    assert main(["test", str(project)]) == 2
    assert "FB_Checks.TcPOU:4: unknown type 'Tc3_Module.ITComObject': library Tc3_Module declares no ITComObject" in capsys.readouterr().err
