"""Source maps: a fault, a traceback, pytest's report and a breakpoint in loaded ST point at the ST file and line."""

from __future__ import annotations

import bdb
import json
import linecache
import pathlib
import re
import subprocess
import sys
import traceback
import types
from typing import Any

import pytest

from iecoop import T, st
from iecoop.exceptions import ExceptionCode, PlcException, SourceLocation
from iecoop.runtime import Runtime, Task

pytest_plugins = ["pytester"]

PROJECT = pathlib.Path(__file__).parent / "data" / "sourcemaps"
CALC = str(PROJECT / "FB_Calc.TcPOU")
#: ``Divide := nValue / nDivisor;`` inside the METHOD's CDATA, as a line of the .TcPOU file
DIVIDE_LINE = 23
BODY_LINE = 13


def _innermost_st_frames(tb: types.TracebackType | None) -> list[tuple[str, int, str]]:
    frames = traceback.extract_tb(tb)
    return [(f.filename, f.lineno or 0, f.line or "") for f in frames if f.filename.endswith(".TcPOU")]


def test_traceback_shows_the_tcpou_file_line_and_st_text() -> None:
    plc = st.load(PROJECT)
    calc = plc.FB_Calc()
    with pytest.raises(PlcException) as info:
        calc(nDivisor=0)
    frames = _innermost_st_frames(info.tb)
    assert frames[-1] == (CALC, DIVIDE_LINE, "Divide := nValue / nDivisor;]]></ST>")
    assert frames[-2][:2] == (CALC, BODY_LINE) and "nResult := Divide(100);" in frames[-2][2]
    assert linecache.getline(CALC, DIVIDE_LINE).strip() == "Divide := nValue / nDivisor;]]></ST>"
    # The body is still compiled into the block's call (one frame per call), under the ST file's name.
    assert type(calc).__call__.__code__.co_filename == CALC


def test_readable_python_is_unchanged() -> None:
    plc = st.load(PROJECT)
    assert "Divide = DIV(nValue, self.nDivisor)" in plc.__python__
    assert plc.__python__ == st.to_python(PROJECT)
    assert "Divide := nValue" not in plc.__python__


def test_plc_exception_location() -> None:
    plc = st.load(PROJECT)
    with pytest.raises(PlcException) as info:
        plc.FB_Calc()(nDivisor=0)
    assert info.value.location == SourceLocation(CALC, DIVIDE_LINE, "FB_Calc", "Divide")
    assert str(info.value.location) == f"{CALC}:{DIVIDE_LINE} (FB_Calc.Divide)"


def test_location_of_a_fault_in_a_body_and_outside_st() -> None:
    plc = st.load("PROGRAM MAIN\nVAR a : INT; b : INT; END_VAR\na := a / b;\nEND_PROGRAM\n")
    with pytest.raises(PlcException) as info:
        plc.MAIN()
    location = info.value.location
    assert location is not None and location.file.startswith("<st text #")
    assert (location.line, location.pou, location.member) == (3, "MAIN", None)
    assert linecache.getline(location.file, 3) == "a := a / b;\n"
    assert PlcException(ExceptionCode.RTSEXCPT_DIVIDEBYZERO).location is None


def test_runtime_fault_names_the_st_location() -> None:
    plc = st.load(PROJECT)
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), plc.MAIN)
    with pytest.raises(PlcException, match=rf"stopped in cycle \d+ at {CALC}:{DIVIDE_LINE} \(FB_Calc.Divide\)") as info:
        rt.run(cycles=5)
    assert rt.fault is not None
    assert rt.fault.location == SourceLocation(CALC, DIVIDE_LINE, "FB_Calc", "Divide")
    assert info.value.location == rt.fault.location
    assert f'{CALC}", line {DIVIDE_LINE}, in Divide' in rt.fault.traceback


def test_pytest_report_shows_the_tcpou_line(pytester: pytest.Pytester) -> None:
    pytester.makepyfile(
        test_plc=f"""
        from iecoop import st

        def test_divide():
            plc = st.load({str(PROJECT)!r})
            plc.FB_Calc()(nDivisor=0)
        """
    )
    result = pytester.runpytest("-p", "no:cacheprovider")
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines([
        f"{CALC}:{BODY_LINE}: in body", "*nResult := Divide(100);*",
        f"{CALC}:{DIVIDE_LINE}: in Divide", "    Divide := nValue / nDivisor;]]></ST>",
    ])


class _Stops(bdb.Bdb):
    """A debugger that records where it stopped and goes on to the next breakpoint."""

    def __init__(self) -> None:
        super().__init__()
        self.stops: list[tuple[str, int, str]] = []

    def user_line(self, frame: Any) -> None:
        filename = self.canonic(frame.f_code.co_filename)
        self.stops.append((filename, frame.f_lineno, linecache.getline(filename, frame.f_lineno).strip()))
        self.set_continue()


def breakpoint_stops(project: str, filename: str, line: int) -> tuple[list[tuple[str, int, str]], int]:
    """Load ``project``, break at ``filename:line``, call FB_Calc with nDivisor 5: where it stopped, and nResult."""
    plc = st.load(project)
    calc = plc.FB_Calc()
    debugger = _Stops()
    assert debugger.set_break(filename, line) is None  # None: the line exists and is accepted
    try:
        debugger.runcall(calc, nDivisor=5)
    finally:
        debugger.clear_all_breaks()
    return debugger.stops, calc.nResult


def test_a_breakpoint_on_a_tcpou_line_stops_there() -> None:
    # In a process of its own: a debugger's breakpoints are process-wide (bdb keeps them on its class), and the
    # test must not depend on what tracing or breakpoints earlier tests of the same process left behind.
    script = (
        "import json, sys\n"
        "from tests.iecoop.st.test_source_maps import breakpoint_stops\n"
        "stops, result = breakpoint_stops(sys.argv[1], sys.argv[2], int(sys.argv[3]))\n"
        "print(json.dumps({'stops': stops, 'result': result}))\n"
    )
    root = pathlib.Path(__file__).resolve().parents[3]
    done = subprocess.run([sys.executable, "-c", script, str(PROJECT), CALC, str(DIVIDE_LINE)], cwd=root,
                          capture_output=True, text=True, timeout=600, check=False)
    assert done.returncode == 0, done.stderr
    found = json.loads(done.stdout.splitlines()[-1])
    assert found["result"] == 20
    # The first stop is runcall's own start; then the breakpoint.
    assert [tuple(stop) for stop in found["stops"][1:]] == [(CALC, DIVIDE_LINE, "Divide := nValue / nDivisor;]]></ST>")]


def test_one_cycle_numbering_in_fault_runtime_trace_and_st_run() -> None:
    """MAIN divides by 3 - nCycle: the third cycle of the task faults, and every report calls it cycle 3."""
    import io

    from iecoop.cli.st import st_run

    plc = st.load(PROJECT)
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), plc.MAIN)
    trace = rt.trace(["MAIN.nCycle"])
    with pytest.raises(PlcException, match=r"task PlcTask stopped in cycle 3 at ") as info:
        rt.run(cycles=5)
    assert rt.fault is not None and rt.fault.cycle == 3 and plc.MAIN.nCycle == 3
    assert rt.tasks[0].info.CycleCount == 2  # the failed cycle is not counted: it did not end
    assert trace.rows[-1][0] == 2 and [row[2] for row in trace.rows] == [1, 2]
    assert info.value.location is not None and info.value.location.line == DIVIDE_LINE
    out, err = io.StringIO(), io.StringIO()
    assert st_run([str(PROJECT), "--program", "MAIN", "--cycles", "5"], out, err) == 1
    assert err.getvalue().startswith(f"iecoop st run: PLC fault in cycle 3 at {CALC}:{DIVIDE_LINE} (FB_Calc.Divide): ")
    assert out.getvalue().splitlines()[-1].split()[:3] == ["10", "2", "2"]


COVERED = pathlib.Path(__file__).parent / "data" / "coverage"


def test_coverage_plugin_reports_st_lines_hit_and_missed(tmp_path: pathlib.Path) -> None:
    """coverage.py with ``plugins = iecoop.st.coverage`` reports the .TcPOU's statement lines, hit and missed."""
    import json
    import os
    import shutil
    import subprocess
    import sys

    shutil.copytree(COVERED, tmp_path / "plc")
    pou = tmp_path / "plc" / "FB_Sort.TcPOU"
    lines = pou.read_text().splitlines()

    def line_of(text: str) -> int:
        return next(number for number, line in enumerate(lines, 1) if text in line)

    (tmp_path / ".coveragerc").write_text("[run]\nplugins = iecoop.st.coverage\n")
    (tmp_path / "run_plc.py").write_text(
        "from iecoop import st\nplc = st.load('plc')\nsort = plc.FB_Sort()\nsort(nValue=3)\nassert sort.nBin == 1\n"
    )
    env = {**os.environ, "XDG_CACHE_HOME": str(tmp_path / "user-cache")}
    reports = (["json", "-o", "coverage.json", "--include", "plc/*"], ["html", "-d", "html", "--include", "plc/*"])
    for command in (["run", "run_plc.py"], *reports):
        done = subprocess.run([sys.executable, "-m", "coverage", *command], cwd=tmp_path, env=env,
                              capture_output=True, text=True, timeout=600)
        assert done.returncode == 0, done.stderr
    report = json.loads((tmp_path / "coverage.json").read_text())["files"]["plc/FB_Sort.TcPOU"]
    # A CASE's lines are its labels (their tests run there, the first one reading the selector).
    labels = {number for number, line in enumerate(lines, 1) if line.strip() in ("0:", "1..4:")}
    hit = {line_of(t) for t in ("IF nValue < 0 THEN", "ELSIF nValue < 10", "nBin := Small(nValue);", "Small := 1;")} | labels
    missed = {line_of(t) for t in ("nBin := -1;", "nBin := 99;", "Small := 0;", "Small := 2;")}
    assert set(report["executed_lines"]) == hit
    assert set(report["missing_lines"]) == missed
    # The HTML report shows the ST, each statement line marked run or missed where the JSON report has it.
    [page] = [p for p in (tmp_path / "html").glob("*.html") if "FB_Sort" in p.name]
    html = page.read_text()
    assert "IF nValue &lt; 0 THEN" in html and "nBin := Small(nValue);" in html
    marked = {int(number): kind for kind, number in re.findall(r'<p class="(run|mis)[^"]*">\s*<span class="n"><a id="t(\d+)"', html)}
    assert marked == {**{line: "run" for line in hit}, **{line: "mis" for line in missed}}
